"""``bulkhead``: a bulkhead closes chamber 1 inside the inner tube; the bore above it is chamber-2 gas
(``V2_top_mm3``), so the housing length is free of V1 (``docs/layout.md``).

The bulkhead is a web left when the inner tube is bored from both ends: a simply supported circular plate
over the piston bore carrying the largest chamber-2 minus chamber-1 pressure. A fill tube
(``fixed.fill_tube_outer_mm``, bore ``fixed.fill_tube_bore_mm``, counted in V1) charges chamber 1 through the
space above it. Lengths mm, volumes mm³, pressures MPa, masses g.
"""

from __future__ import annotations

import math

import numpy as np

from ..geometry import Array, Pressures, Section
from ..parameters import FixedParameters
from .base import BudgetShare, LayoutStack, LayoutVariable, LayoutVariant, register

__all__ = ["Bulkhead"]


def _fill_tube_areas(fixed: FixedParameters) -> tuple[float, float]:
    """Outer and bore cross-section of the fill tube, mm²."""
    return math.pi / 4 * fixed.fill_tube_outer_mm**2, math.pi / 4 * fixed.fill_tube_bore_mm**2


@register
class Bulkhead(LayoutVariant):
    """Chamber 1 below a bulkhead in the inner tube; chamber-2 gas above it and in the annulus."""

    name = "bulkhead"
    summary = ("a bulkhead closes chamber 1 inside the inner tube; the inner-tube space above it (V2_top) is "
               "chamber-2 gas, ported to the annulus through the top cap, so the housing length is free of V1")
    order = 1
    own_variables = (LayoutVariable("V2_top_mm3", (0.0, 1.5e5), "chamber-2 gas above chamber 1"),)
    own_walls = ("bulkhead",)
    budget_items = BudgetShare(walls={"wall_bulkhead": 0.0, "wall_fill_tube": 0.0},
                               chamber_2={"gas_chamber_2_above_bulkhead": 0.0})
    has_bulkhead = True
    chamber1_note = " plus the fill tube's bore"
    chamber2_note = " and V2_top_mm3"

    def size_walls(self, section: Section, pressures: Pressures, fixed: FixedParameters) -> dict[str, Array]:
        """The bulkhead: a simply supported plate over the bore, ``t = sqrt(k p r^2 / s_allow)`` (the bore and the
        thickness at their least-material condition under the buildability rules).

        Parameters
        ----------
        section : Section
            The cross-section with the shared walls sized (mm).
        pressures : Pressures or Loads
            Its pressure is the largest chamber-2 minus chamber-1 pressure (``chamber_difference_MPa``), MPa.
        fixed : FixedParameters
            ``min_bulkhead_mm`` is its least thickness.

        Returns
        -------
        dict of str to ndarray
            ``bulkhead`` -> thickness, mm.
        """
        s = section
        t = np.sqrt(s.plate_factor * pressures.chamber_difference_MPa * s.piston_bore_lmc_radius_mm**2 / s.allowable_MPa)
        return {"bulkhead": np.fmax(fixed.min_bulkhead_mm, s.sized_thickness_mm(t))}

    def stack(self, section: Section, variables: dict[str, Array], fixed: FixedParameters) -> LayoutStack:
        """The bulkhead and the chamber-2 space above it lengthen the inner tube; the fill tube's bore is V1.

        Parameters
        ----------
        section : Section
            The cross-section with every wall sized (mm, mm²).
        variables : dict of str to ndarray
            ``V2_top_mm3`` among them, mm³.
        fixed : FixedParameters
            The fill tube's sizes (mm).

        Returns
        -------
        LayoutStack
            The fill tube's gas (chamber 1), the web and the space above it (inner length), ``V2_top``
            (chamber 2); quantities ``V2_top_mm3``, ``top_space_length_mm``, ``fill_tube_volume_mm3``.
        """
        Vt = np.asarray(variables["V2_top_mm3"], dtype=float)
        a_fo, a_fb = _fill_tube_areas(fixed)
        t_bh = section.walls_mm["bulkhead"]
        L_top = Vt / (section.A1_mm2 - a_fo)
        fill = a_fb * (t_bh + L_top)
        return LayoutStack(chamber1_elsewhere_mm3=(fill,), inner_length_extra_mm=(t_bh, L_top),
                           chamber2_elsewhere_mm3=Vt, buildable=Vt >= 0,
                           quantities={"V2_top_mm3": Vt, "top_space_length_mm": L_top, "fill_tube_volume_mm3": fill})

    def wall_stresses(self, section: Section, pressures: Pressures, fixed: FixedParameters) -> dict[str, Array]:
        """The bulkhead plate's peak stress, ``3 (3 + nu) p r^2 / (8 t^2)``.

        Parameters
        ----------
        section : Section
            The cross-section with every wall sized (mm).
        pressures : Pressures
            The largest chamber-2 minus chamber-1 pressure, MPa.
        fixed : FixedParameters
            Unused (the plate is the housing's material).

        Returns
        -------
        dict of str to ndarray
            ``bulkhead`` -> peak stress, MPa.
        """
        s = section
        return {"bulkhead": s.plate_factor * pressures.chamber_difference_MPa * s.piston_bore_lmc_radius_mm**2
                / s.least_material_thickness_mm(s.walls_mm["bulkhead"])**2}

    def part_masses(self, section: Section, quantities: dict[str, Array], fixed: FixedParameters,
                    density_g_per_mm3: float) -> dict[str, Array]:
        """The bulkhead web and the fill tube's wall over the space above it.

        Parameters
        ----------
        section : Section
            The cross-section with every wall sized (mm).
        quantities : dict of str to ndarray
            ``top_space_length_mm`` among them, mm.
        fixed : FixedParameters
            The fill tube's sizes (mm).
        density_g_per_mm3 : float
            Density of the housing material, g/mm³.

        Returns
        -------
        dict of str to ndarray
            ``bulkhead`` -> mass, g.
        """
        a_fo, a_fb = _fill_tube_areas(fixed)
        ri = section.piston_radius_mm
        return {"bulkhead": (math.pi * ri**2 * section.walls_mm["bulkhead"]
                             + (a_fo - a_fb) * quantities["top_space_length_mm"]) * density_g_per_mm3}

    def geometry_summary(self, design) -> dict[str, float]:
        """``V2_top_mm3``, ``top_space_length_mm`` and ``fill_tube_volume_mm3`` of the design file.

        Parameters
        ----------
        design : Design
            A design of this layout.

        Returns
        -------
        dict of str to float
            Volumes (mm³) and the length of the space above the bulkhead (mm).
        """
        return {"V2_top_mm3": design.V2_top_mm3, "top_space_length_mm": design.top_space_length_mm,
                "fill_tube_volume_mm3": design.fill_tube_volume_mm3}

    def budget(self, design) -> BudgetShare:
        """The bulkhead web, the fill tube's wall and the chamber-2 gas above the bulkhead.

        Parameters
        ----------
        design : Design
            A design of this layout.

        Returns
        -------
        BudgetShare
            Volumes at x = 0, mm³.
        """
        a_fo, a_fb = _fill_tube_areas(design.fixed)
        return BudgetShare(walls={"wall_bulkhead": (design.A1_mm2 - a_fb) * design.bulkhead_mm,
                                  "wall_fill_tube": (a_fo - a_fb) * design.top_space_length_mm},
                           chamber_2={"gas_chamber_2_above_bulkhead": design.V2_top_mm3})
