"""Typed intermediate results of :func:`~vvea_design.spring.derive.derive`, read by the layouts' hooks.

Each is a frozen dataclass whose numeric fields are numpy arrays broadcast over a population (or 0-d arrays
for one design): :class:`Pressures` (the charge and the peaks the walls are sized for) and :class:`Section`
(the radii and the sized walls of the cross-section: the typed geometry the wall stresses are computed
from). Lengths in mm, areas mm², volumes mm³, pressures and stresses MPa.
"""

from __future__ import annotations

from dataclasses import dataclass, fields
from typing import Any

import numpy as np

__all__ = ["Pressures", "Section", "Array"]

#: A float, or a numpy array of floats broadcast over a population.
Array = Any


@dataclass(frozen=True)
class Pressures:
    """Charges and the pressures the walls carry, MPa (arrays broadcast over a population).

    The peaks are those of a stroke at ``max(n_polytropic, fixed.wall_sizing_n)`` (adiabatic by default).
    """

    p1_MPa: Array  #: chamber-1 charge that puts zero force at the set point (paper eq. 6)
    peak_chamber_2_MPa: Array  #: chamber 2 at full stroke (its highest)
    min_chamber_1_MPa: Array  #: chamber 1 at full stroke (its lowest)
    chamber_difference_MPa: Array  #: largest chamber-2 minus chamber-1 pressure (or p1 - p2), >= 0: on the walls between the chambers
    inner_tube_net_pressure_MPa: Array  #: chamber 2 outside minus chamber 1 inside the inner tube at full stroke, >= 0

    def to_dict(self) -> dict[str, Array]:
        """Every field by name.

        Returns
        -------
        dict of str to ndarray
            Pressures, MPa.
        """
        return {f.name: getattr(self, f.name) for f in fields(self)}


@dataclass(frozen=True)
class Section:
    """The unit's cross-section with its sized walls: what the wall stresses and the axial stack read.

    Radii and thicknesses in mm, areas mm², stresses MPa (arrays broadcast over a population).
    """

    A1_mm2: Array  #: chamber-1 area, the full piston face
    A2_mm2: Array  #: chamber-2 area, piston minus rod
    outer_radius_mm: Array  #: outer tube outer radius (half the outer diameter)
    outer_bore_radius_mm: Array  #: outer tube bore
    piston_radius_mm: Array  #: inner tube bore = piston radius
    inner_tube_outer_radius_mm: Array  #: inner tube outer radius
    walls_mm: dict[str, Array]  #: sized walls: outer_tube, inner_tube, top_cap, base and the layout's own
    allowable_MPa: float  #: housing material's yield over the wall safety factor
    plate_factor: float  #: ``3 (3 + nu) / 8`` of the housing material (plate stress ``k p a^2 / t^2``)
    piston_floor_mm: Array  #: floor of the piston pocket (the piston height without a pocket)
    piston_pocket_radius_mm: Array  #: radius of the pocket (0 without one)
    piston_pocket_volume_mm3: Array  #: chamber-1 gas in the pocket (0 without one)
    has_piston_pocket: Array  #: bool: a pocket is bored (``fixed.piston_pocket`` and room beside the rod)
    #: the buildability rules (``fixed.sizing_rules = "buildable"``; None under ``"gas_only"``): the ISO 2768-1
    #: class of the sized thicknesses, the ISO 286-1 grades of the bores (H) and outsides (h)
    thickness_tolerance_class: str | None = None
    bore_grade: int | None = None
    outside_grade: int | None = None
    outer_tube_outer_radius_mm: Array = None  #: the outer tube's outside radius (inside the rod circle for tie rods)
    joint: Any = None  #: the joint's sizing (:class:`~vvea_design.spring.joints.JointSizing`), None under gas_only
    base_own_mm: Array = None  #: the base below its joint zone (valves, channels, rod seal), mm
    piston_floor_room_mm: Array = None  #: piston height less the floor its load needs (< 0: the floor is capped), mm

    def sized_thickness_mm(self, required_mm: Array) -> Array:
        """A sized thickness's nominal: what its load needs at the least-material condition plus the tolerance, mm.

        Parameters
        ----------
        required_mm : float or array
            Thickness the load needs, mm.

        Returns
        -------
        ndarray
            ``required + allowance`` (ISO 2768-1, :func:`~vvea_design.spring.tolerances.thickness_allowance_mm`);
            ``required`` itself under the gas-only rules, mm.
        """
        if self.thickness_tolerance_class is None:
            return required_mm
        from .tolerances import thickness_allowance_mm

        return required_mm + thickness_allowance_mm(required_mm, self.thickness_tolerance_class)

    def least_material_thickness_mm(self, nominal_mm: Array) -> Array:
        """A drawn thickness at its least-material condition (nominal less its ISO 2768-1 deviation), mm.

        Parameters
        ----------
        nominal_mm : float or array
            Nominal thickness, mm.

        Returns
        -------
        ndarray
            ``nominal - deviation``; ``nominal`` under the gas-only rules, mm.
        """
        if self.thickness_tolerance_class is None:
            return nominal_mm
        from .tolerances import general_tolerance_mm

        return nominal_mm - general_tolerance_mm(nominal_mm, self.thickness_tolerance_class)

    @property
    def piston_bore_lmc_radius_mm(self) -> Array:
        """Inner-tube bore radius at its least-material condition (H tolerance), mm (nominal under gas-only)."""
        if self.bore_grade is None:
            return self.piston_radius_mm
        from .tolerances import it_tolerance_mm

        return self.piston_radius_mm + it_tolerance_mm(2 * self.piston_radius_mm, self.bore_grade) / 2

    @property
    def outer_bore_lmc_radius_mm(self) -> Array:
        """Outer-tube bore radius at its least-material condition (H tolerance), mm (nominal under gas-only)."""
        if self.bore_grade is None:
            return self.outer_bore_radius_mm
        from .tolerances import it_tolerance_mm

        return self.outer_bore_radius_mm + it_tolerance_mm(2 * self.outer_bore_radius_mm, self.bore_grade) / 2

    @property
    def inner_tube_outer_lmc_radius_mm(self) -> Array:
        """Inner tube's outside radius at its least-material condition (h tolerance), mm (nominal under gas-only)."""
        if self.outside_grade is None:
            return self.inner_tube_outer_radius_mm
        from .tolerances import it_tolerance_mm

        return self.inner_tube_outer_radius_mm - it_tolerance_mm(2 * self.inner_tube_outer_radius_mm,
                                                                 self.outside_grade) / 2

    @property
    def annulus_area_mm2(self) -> Array:
        """Area of the annulus between the inner tube and the outer bore, mm²."""
        return np.pi * (self.outer_bore_radius_mm**2 - self.inner_tube_outer_radius_mm**2)

    def to_dict(self) -> dict[str, Any]:
        """Every field by name.

        Returns
        -------
        dict
            Radii and walls (mm), areas (mm²), stresses (MPa), volume (mm³), the pocket flag.
        """
        return {f.name: getattr(self, f.name) for f in fields(self)}
