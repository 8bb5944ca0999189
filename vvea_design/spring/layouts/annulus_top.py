"""``annulus_top``: chamber 1 also fills the annulus between the tubes above a collar on the inner tube
(``V1_annulus_mm3``), joined to the bore by slots through the inner tube's top end (``docs/layout.md``).

The collar is the top bladder clamp and the pressure wall between the chambers: a plate ``clamp + t`` long,
``t`` sized as a ring cantilevered from the inner tube (its seal on the outer bore carries no axial load)
under the largest chamber-2 minus chamber-1 pressure: root moment per unit circumference
``M = p/rio ((rb^3 - rio^3)/3 - rio (rb^2 - rio^2)/2)``, ``sigma = 6 M / t^2`` (the hoop stiffening of the
ring is neglected: conservative). The bladder's free length loses ``t + L_annulus``. Lengths mm, volumes mm³,
pressures MPa, masses g.
"""

from __future__ import annotations

import math

import numpy as np

from ..geometry import Array, Pressures, Section
from ..parameters import FixedParameters
from .base import BudgetShare, LayoutStack, LayoutVariable, LayoutVariant, register

__all__ = ["AnnulusTop"]


def _collar_moment(section: Section, pressures: Pressures) -> Array:
    """Root moment per unit circumference of the collar ring, N·mm/mm."""
    rb, rio = section.outer_bore_lmc_radius_mm, section.inner_tube_outer_lmc_radius_mm
    return pressures.chamber_difference_MPa / rio * ((rb**3 - rio**3) / 3 - rio * (rb**2 - rio**2) / 2)


@register
class AnnulusTop(LayoutVariant):
    """Chamber 1 in the bore and in the annulus above the collar; chamber 2 around the bladder below it."""

    name = "annulus_top"
    summary = ("chamber 1 fills the inner tube from the piston to the top cap and, through cross slots below the top "
               "cap, the annulus above a collar on the inner tube (V1_annulus); the collar is the top bladder clamp "
               "and the pressure wall between the chambers, chamber 2 is charged through the base")
    order = 2
    own_variables = (LayoutVariable("V1_annulus_mm3", (0.0, 1.5e5), "chamber-1 gas in the annulus"),)
    own_walls = ("collar",)
    own_constraints = ("cross_slot_room",)
    budget_items = BudgetShare(walls={"wall_collar": 0.0}, chamber_1={"gas_chamber_1_annulus": 0.0})
    has_top_annulus = True
    chamber1_note = " plus V1_annulus_mm3"
    bladder_note = ", the collar and the chamber-1 annulus"

    def size_walls(self, section: Section, pressures: Pressures, fixed: FixedParameters) -> dict[str, Array]:
        """The collar plate: ``t = sqrt(6 M / s_allow)``, never below ``fixed.min_collar_mm``.

        Parameters
        ----------
        section : Section
            The cross-section with the shared walls sized (mm).
        pressures : Pressures
            The largest chamber-2 minus chamber-1 pressure, MPa.
        fixed : FixedParameters
            ``min_collar_mm`` is its least thickness.

        Returns
        -------
        dict of str to ndarray
            ``collar`` -> thickness, mm.
        """
        m = _collar_moment(section, pressures)
        return {"collar": np.fmax(fixed.min_collar_mm, section.sized_thickness_mm(np.sqrt(6 * m / section.allowable_MPa)))}

    def stack(self, section: Section, variables: dict[str, Array], fixed: FixedParameters) -> LayoutStack:
        """The annulus above the collar and the slots hold chamber-1 gas; collar and annulus take bladder length.

        Parameters
        ----------
        section : Section
            The cross-section with every wall sized (mm, mm²).
        variables : dict of str to ndarray
            ``V1_annulus_mm3`` among them, mm³.
        fixed : FixedParameters
            The slots' height and share of the circumference.

        Returns
        -------
        LayoutStack
            ``V1_annulus`` and the slots' gas (chamber 1), the collar plate and the annulus's length (taken
            from the bladder), the slots (cut from the inner tube); quantities ``V1_annulus_mm3``,
            ``top_annulus_length_mm``, ``cross_slot_volume_mm3``.
        """
        Va = np.asarray(variables["V1_annulus_mm3"], dtype=float)
        rio, ri = section.inner_tube_outer_radius_mm, section.piston_radius_mm
        L_a = Va / section.annulus_area_mm2
        v_slots = fixed.cross_slot_fraction * math.pi * (rio**2 - ri**2) * fixed.cross_slot_mm
        return LayoutStack(chamber1_elsewhere_mm3=(Va, v_slots),
                           bladder_length_taken_mm=(section.walls_mm["collar"], L_a),
                           inner_tube_cut_mm3=v_slots, buildable=Va >= 0,
                           quantities={"V1_annulus_mm3": Va * np.ones_like(L_a), "top_annulus_length_mm": L_a,
                                       "cross_slot_volume_mm3": v_slots * np.ones_like(L_a)})

    def rooms(self, stack, fixed: FixedParameters) -> dict[str, Array]:
        """Room left for the cross slots below the top cap, in the annulus and above the piston at x = 0.

        Parameters
        ----------
        stack : Stack
            The finished axial stack (``chamber1_length_mm`` and the quantity ``top_annulus_length_mm``, mm).
        fixed : FixedParameters
            ``cross_slot_mm``, the slots' height.

        Returns
        -------
        dict of str to ndarray
            ``cross_slot_room_mm``: ``min(L_annulus, chamber1_length) - cross_slot_mm - 1``, mm.
        """
        L_a = stack.layout.quantities["top_annulus_length_mm"]
        return {"cross_slot_room_mm": np.fmin(L_a, stack.chamber1_length_mm) - (fixed.cross_slot_mm + 1.0)}

    def wall_stresses(self, section: Section, pressures: Pressures, fixed: FixedParameters) -> dict[str, Array]:
        """The collar's root bending stress ``6 M / t^2``.

        Parameters
        ----------
        section : Section
            The cross-section with every wall sized (mm).
        pressures : Pressures
            The largest chamber-2 minus chamber-1 pressure, MPa.
        fixed : FixedParameters
            Unused (the collar is the housing's material).

        Returns
        -------
        dict of str to ndarray
            ``collar`` -> peak stress, MPa.
        """
        t = section.least_material_thickness_mm(section.walls_mm["collar"])
        return {"collar": 6 * _collar_moment(section, pressures) / t**2}

    def part_masses(self, section: Section, quantities: dict[str, Array], fixed: FixedParameters,
                    density_g_per_mm3: float) -> dict[str, Array]:
        """The collar plate above the top clamp (the clamp itself is counted nowhere, as for the others).

        Parameters
        ----------
        section : Section
            The cross-section with every wall sized (mm).
        quantities : dict of str to ndarray
            The layout's quantities (unused).
        fixed : FixedParameters
            Unused.
        density_g_per_mm3 : float
            Density of the housing material, g/mm³.

        Returns
        -------
        dict of str to ndarray
            ``collar`` -> mass, g.
        """
        return {"collar": section.annulus_area_mm2 * section.walls_mm["collar"] * density_g_per_mm3}

    def constraint_details(self, derived) -> dict[str, dict]:
        """``cross_slot_room``: the slots fit below the top cap (room >= 0 mm).

        Parameters
        ----------
        derived : Derived
            The derived quantities (``cross_slot_room_mm``, mm).

        Returns
        -------
        dict of str to dict
            ``cross_slot_room`` -> value (mm), limit 0 mm, kind ``min``, scale 1 mm.
        """
        return {"cross_slot_room": {"value": derived.layout_quantities["cross_slot_room_mm"], "limit": 0.0,
                                    "unit": "mm", "kind": "min", "scale": 1.0}}

    def geometry_summary(self, design) -> dict[str, float]:
        """``V1_annulus_mm3``, ``top_annulus_length_mm`` and ``collar_mm`` of the design file.

        Parameters
        ----------
        design : Design
            A design of this layout.

        Returns
        -------
        dict of str to float
            The annulus's gas (mm³), its length and the collar plate (mm).
        """
        return {"V1_annulus_mm3": design.V1_annulus_mm3, "top_annulus_length_mm": design.top_annulus_length_mm,
                "collar_mm": design.collar_mm}

    def budget(self, design) -> BudgetShare:
        """The collar plate and the chamber-1 gas in the annulus above it.

        Parameters
        ----------
        design : Design
            A design of this layout.

        Returns
        -------
        BudgetShare
            Volumes at x = 0, mm³.
        """
        rb, rio = design.outer_bore_radius_mm, design.inner_tube_outer_radius_mm
        return BudgetShare(walls={"wall_collar": math.pi * (rb**2 - rio**2) * design.collar_mm},
                           chamber_1={"gas_chamber_1_annulus": design.V1_annulus_mm3})
