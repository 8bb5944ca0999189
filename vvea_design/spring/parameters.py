"""The parameters the optimiser does not change (:class:`FixedParameters`) and the error of a design that
cannot be built (:class:`DesignError`): the bottom of the spring wing, read by the layouts, the derivation
and the design. All lengths in mm, volumes mm³, masses g.
"""

from __future__ import annotations

import math
from dataclasses import asdict, dataclass, fields

from ..messages import show
from ..plausibility import LIMITS, check_field
from ..materials.structural import get_material

__all__ = ["FixedParameters", "DesignError", "CHANNEL_GAP_MM", "SIZING_RULES"]

#: Radial room the cast bladder must leave to the inner tube for the support ring's fluid channels, mm: the CAD
#: draws them (>= 0.5 mm) beside the cuff's sealing bead when the gap is >= 10/9 mm (``cad.layout``); with a margin.
CHANNEL_GAP_MM = 1.15

#: Old names of the wall fields (design files written before the walls were sized): now the minimums.
_LEGACY_FIXED = {"outer_wall_mm": "min_outer_wall_mm", "inner_tube_wall_mm": "min_inner_tube_wall_mm",
                 "top_cap_mm": "min_top_cap_mm", "base_mm": "min_base_mm"}

_NONNEGATIVE = {"dead_volume_1_mm3", "dead_volume_2_mm3", "servo_and_valve_mass_g", "bladder_min_gap_mm"}
#: Fields that may take any finite value.
_ANY_SIGN = {"oil_temperature_C"}
#: The values of ``sizing_rules``.
SIZING_RULES = ("buildable", "gas_only")


class DesignError(ValueError):
    """A design that cannot be built (names the field and what is wrong)."""


@dataclass(frozen=True)
class FixedParameters:
    """Parameters the optimiser does not change (mm, mm³, g)."""

    travel_mm: float = 40.0  #: stroke, x from 0 to travel
    rod_diameter_mm: float = 8.0  #: piston rod (crosses the fluid, leaves through the base)
    min_outer_wall_mm: float = 1.5  #: thinnest outer tube wall made (sized up for chamber-2 pressure)
    min_inner_tube_wall_mm: float = 1.5  #: thinnest inner tube wall made (sized up for external chamber-2 pressure)
    min_top_cap_mm: float = 8.0  #: thinnest top end cap (fill ports, top eye)
    min_base_mm: float = 14.0  #: thinnest base (valve bores, channels, rod seal)
    min_bulkhead_mm: float = 4.0  #: thinnest bulkhead web (``bulkhead`` layout: a web left when boring the inner tube)
    fill_tube_outer_mm: float = 4.0  #: chamber-1 fill tube through the upper chamber-2 space (``bulkhead`` layout)
    fill_tube_bore_mm: float = 1.5  #: its bore (counted in V1)
    #: thinnest collar plate above the top bladder clamp (``annulus_top`` layout): it holds the static O-ring
    #: groove to the outer bore (1.78 mm series: 2.41 mm wide, 0.75 mm lands; the CAD checks it)
    min_collar_mm: float = 4.0
    cross_slot_mm: float = 2.0  #: axial height of the slots in the inner tube's top end joining the chamber-1 annulus to the bore (``annulus_top``)
    cross_slot_fraction: float = 1 / 3  #: share of the inner tube's circumference the slots take (their gas is in V1)
    wall_safety_factor: float = 2.0  #: walls are sized to this safety factor on yield (the requirements set it)
    wall_sizing_n: float = 1.4  #: walls carry the peak pressure of this polytropic exponent (1.4: a fast, adiabatic stroke)
    piston_height_mm: float = 10.0  #: working piston incl. seal grooves
    piston_pocket: bool = False  #: a coaxial pocket bored into the piston crown holds chamber-1 gas (a cupped piston)
    piston_pocket_wall_mm: float = 3.0  #: radial wall from the piston's sliding diameter to the pocket (seal groove depth + the wall under its root)
    min_piston_floor_mm: float = 3.0  #: thinnest pocket floor made (sized up: a plate carrying the chamber-1 / fluid differential to the rod)
    fluid_clearance_mm: float = 2.0  #: fluid column left under the piston at full stroke
    bladder_thickness_mm: float = 1.5  #: silicone sleeve wall as cast
    bladder_clamp_mm: float = 5.0  #: axial length of each clamped end (support ring / top clamp)
    bladder_cast_fill: float = 0.5  #: stroke fraction at which the bladder has its cast shape
    bladder_min_gap_mm: float = 0.5  #: radial clearance the bladder keeps at both stroke ends
    bladder_bulge_factor: float = 1.5  #: peak / mean radial shift between the clamps (1.5 = parabolic, as the FE check finds)
    dead_volume_1_mm3: float = 0.0  #: chamber-1 gas outside the inner-tube column (ports)
    dead_volume_2_mm3: float = 0.0  #: chamber-2 gas outside the bladder annulus (ports)
    housing_material: str = "al-6061-t6"
    rod_material: str = "steel-42crmo4"
    support_ring_material: str = "pa12-sls"
    servo_and_valve_mass_g: float = 40.0  #: servo (BMS-390DMH class), valve core, fittings
    n_polytropic: float = 1.0  #: 1 isothermal (paper) ... 1.4 adiabatic
    #: "buildable": every piece sized for its load cases (gas, damper, proof) at the least-material condition of
    #: its drawn tolerance, the joints and their room, the damper's hydraulics, one mass (docs/layout.md);
    #: "gas_only": the rules before (walls at nominal for the gas peak, no joints, no damper loads)
    sizing_rules: str = "buildable"
    #: the relief (blow-off) valve opens at this damping force on the piston, N: its pressure drop is this over A2
    relief_force_N: float = 2500.0
    max_motor_torque_Nm: float = 100.0  #: |tau_m| limit of the actuator's motor (paper eq. 13), N m
    #: tendon-pulley radius of the actuator mapping (the actuator's PAPER_PULLEY_RADIUS_M), mm
    pulley_radius_mm: float = 63.88
    proof_pressure_factor: float = 1.5  #: proof test at this multiple of each face's highest working pressure (ISO 10100)
    proof_safety_factor: float = 1.05  #: on yield at the proof pressure (EN 13445-3 test condition: f_test = R_p0.2/1.05)
    bore_tolerance_grade: int = 8  #: ISO 286-1 IT grade of the tube bores (H): their least-material size is nominal + IT
    outside_tolerance_grade: int = 9  #: ISO 286-1 IT grade of the tubes' outside diameters (h)
    thickness_tolerance_class: str = "f"  #: ISO 2768-1 class of the sized axial thicknesses (caps, base, bulkhead, collar, floor)
    tie_rod_property_class: str = "10.9"  #: ISO 898-1 property class of the tie rods (``tie_rods`` joint)
    joint_seal_cross_section_mm: float = 1.78  #: ISO 3601-1 cross-section of the joints' static O-rings
    seal_land_mm: float = 0.75  #: axial land each side of a static O-ring groove
    throttle_bore_mm: float = 6.0  #: rotary throttle valve bore in the base (largest; shrinks to fit the base)
    relief_bore_mm: float = 5.0  #: spring-ball relief valve bore (largest; at most the throttle bore)
    relief_seat_mm: float = 2.5  #: relief valve seat drilling
    fluid_channel_mm: float = 3.0  #: the base's vertical fluid channels (largest; shrinks to fit beside the rod)
    ring_channel_mm: float = 2.0  #: the support ring's axial fluid channels (largest; shrinks to fit inside the bladder)
    ring_channels: int = 6  #: number of support-ring channels
    oil: str = "iso-vg-32"  #: the hydraulic oil (a key of ``spring.hydraulics.OILS``)
    oil_temperature_C: float = 20.0  #: temperature the damping is evaluated at (the oil's viscosity), °C

    def __post_init__(self) -> None:
        for f in fields(self):
            v = getattr(self, f.name)
            if f.type in ("bool", bool) and not isinstance(v, bool):
                raise DesignError(f"fixed.{f.name} must be true or false, got {show(v)}")
            if f.type in ("str", str) and not isinstance(v, str):
                raise DesignError(f"fixed.{f.name} must be a string, got {show(v)}")
            if f.type in ("int", int) and (isinstance(v, bool) or not isinstance(v, int) or v < 1):
                raise DesignError(f"fixed.{f.name} must be a whole number >= 1, got {show(v)}")
            if f.type in ("float", float):
                if isinstance(v, bool) or not isinstance(v, (int, float)) or not math.isfinite(v):
                    raise DesignError(f"fixed.{f.name} must be a finite number, got {show(v)}")
                if f.name in _ANY_SIGN:
                    pass
                elif f.name in _NONNEGATIVE:
                    if v < 0:
                        raise DesignError(f"fixed.{f.name} must be >= 0, got {show(v)}")
                elif v <= 0 and f.name != "bladder_cast_fill":
                    raise DesignError(f"fixed.{f.name} must be > 0, got {show(v)}")
        LIMITS["travel_mm"].check(self.travel_mm, "fixed.travel_mm", DesignError)
        if not 0.0 <= self.bladder_cast_fill <= 1.0:
            raise DesignError(f"fixed.bladder_cast_fill must be in [0, 1], got {show(self.bladder_cast_fill)}")
        if not 1.0 <= self.n_polytropic <= 1.4:
            raise DesignError(f"fixed.n_polytropic must be in [1, 1.4], got {show(self.n_polytropic)}")
        if not 1.0 <= self.wall_sizing_n <= 1.67:
            raise DesignError(f"fixed.wall_sizing_n must be in [1, 1.67], got {show(self.wall_sizing_n)}")
        if not self.cross_slot_fraction < 1.0:
            raise DesignError(f"fixed.cross_slot_fraction must be in (0, 1), got {show(self.cross_slot_fraction)}")
        if self.fill_tube_bore_mm >= self.fill_tube_outer_mm:
            raise DesignError("fixed.fill_tube_bore_mm must be smaller than fixed.fill_tube_outer_mm")
        self._check_buildability_fields()
        for key in ("housing_material", "rod_material", "support_ring_material"):
            try:
                get_material(getattr(self, key))
            except ValueError as exc:
                raise DesignError(f"fixed.{key}: {exc}") from None

    def _check_buildability_fields(self) -> None:
        """The choices of the buildability rules name known standards' classes and grades."""
        from .tolerances import GENERAL_CLASSES, IT_GRADES

        if self.sizing_rules not in SIZING_RULES:
            raise DesignError(f"fixed.sizing_rules must be one of {list(SIZING_RULES)}, got {show(self.sizing_rules)}")
        for key in ("bore_tolerance_grade", "outside_tolerance_grade"):
            if getattr(self, key) not in IT_GRADES:
                raise DesignError(f"fixed.{key} must be an ISO 286-1 IT grade in {list(IT_GRADES)}, "
                                  f"got {show(getattr(self, key))}")
        if self.thickness_tolerance_class not in GENERAL_CLASSES:
            raise DesignError(f"fixed.thickness_tolerance_class must be an ISO 2768-1 class in {list(GENERAL_CLASSES)}, "
                              f"got {show(self.thickness_tolerance_class)}")
        if self.proof_safety_factor < 1.0 or self.proof_pressure_factor < 1.0:
            raise DesignError("fixed.proof_pressure_factor and fixed.proof_safety_factor must be >= 1")
        if not -20.0 <= self.oil_temperature_C <= 100.0:
            raise DesignError(f"fixed.oil_temperature_C must be in [-20, 100] °C, got {show(self.oil_temperature_C)}")
        if self.relief_seat_mm >= self.relief_bore_mm:
            raise DesignError("fixed.relief_seat_mm must be smaller than fixed.relief_bore_mm")
        from .hydraulics import OILS
        from .joints import PROPERTY_CLASSES

        if self.oil not in OILS:
            raise DesignError(f"fixed.oil must be one of {sorted(OILS)}, got {show(self.oil)}")
        if self.tie_rod_property_class not in PROPERTY_CLASSES:
            raise DesignError(f"fixed.tie_rod_property_class must be an ISO 898-1 class in {sorted(PROPERTY_CLASSES)}, "
                              f"got {show(self.tie_rod_property_class)}")

    def to_dict(self) -> dict:
        """JSON-ready content.

        Returns
        -------
        dict
            Every field by name (lengths mm, volumes mm³, masses g, fractions, material keys).
        """
        return asdict(self)

    @classmethod
    def from_dict(cls, data, **override) -> "FixedParameters":
        """Build from a mapping (a TOML table or the design JSON's ``fixed``); unknown keys are an error.

        Parameters
        ----------
        data : dict
            Field name -> value (mm, mm³, g, fractions, material keys); the old wall names
            (``outer_wall_mm`` ...) are read as the minimums.
        **override
            Fields that replace those of ``data``.

        Returns
        -------
        FixedParameters
            The validated parameters.

        Raises
        ------
        DesignError
            If ``data`` is not a mapping, names an unknown field or holds a bad value.
        """
        if not isinstance(data, dict):
            raise DesignError(f"fixed parameters must be a table/object, got {type(data).__name__}")
        # files written before the walls were sized: their fixed walls become the minimums
        data = {_LEGACY_FIXED.get(k, k): v for k, v in data.items()}
        known = {f.name for f in fields(cls)}
        bad = set(data) - known
        if bad:
            raise DesignError(f"unknown fixed parameter(s) {sorted(bad)}; known: {sorted(known)}")
        merged = {**data, **override}
        for name, value in merged.items():  # what a user typed: in the range a real unit has, before the rest
            if name in FLOAT_FIELDS and isinstance(value, (int, float)) and not isinstance(value, bool):
                check_field(name, value, f"fixed.{name}", DesignError)
        try:
            out = cls(**merged)
        except TypeError as exc:  # pragma: no cover - guarded by the key check
            raise DesignError(str(exc)) from None
        out.check_plausible()
        return out

    def check_plausible(self) -> None:
        """Raise :class:`DesignError` unless every number is one a real unit can have (what a user typed).

        Every length, volume, mass and factor lies in its range of
        :data:`vvea_design.plausibility.FIELD_LIMITS` (a value whose scale points to another unit, a rod of
        0.008 "mm", names that unit), and the walls are sized for at least the spring's own exponent
        (``wall_sizing_n >= n_polytropic``). Applied by :meth:`from_dict` (a ``[fixed]`` table, a design file's
        ``fixed``); the toolkit's own variants (walls at their bare minimum for a sizing study) are not checked.

        Raises
        ------
        DesignError
            The first implausible field (names it, its range, why, and the likely unit).
        """
        for f in fields(self):
            if f.type in ("float", float):
                check_field(f.name, getattr(self, f.name), f"fixed.{f.name}", DesignError)
        if self.wall_sizing_n < self.n_polytropic:
            raise DesignError(f"fixed.wall_sizing_n ({show(self.wall_sizing_n)}) is below the spring's polytropic "
                              f"exponent n_polytropic ({show(self.n_polytropic)}): the walls would be sized for a "
                              "lower peak pressure than the spring itself makes; set wall_sizing_n >= n_polytropic")


#: The numeric (float) fields of :class:`FixedParameters`: each has its range in
#: :data:`vvea_design.plausibility.FIELD_LIMITS`.
FLOAT_FIELDS = frozenset(f.name for f in fields(FixedParameters) if f.type in ("float", float))
