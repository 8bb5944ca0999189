"""The parameters the optimiser does not change (:class:`FixedParameters`) and the error of a design that
cannot be built (:class:`DesignError`): the bottom of the spring wing, read by the layouts, the derivation
and the design. All lengths in mm, volumes mm³, masses g.
"""

from __future__ import annotations

import math
from dataclasses import asdict, dataclass, fields

from ..messages import show
from ..plausibility import LIMITS
from ..materials.structural import get_material

__all__ = ["FixedParameters", "DesignError", "CHANNEL_GAP_MM"]

#: Radial room the cast bladder must leave to the inner tube for the support ring's fluid channels, mm: the CAD
#: draws them (>= 0.5 mm) beside the cuff's sealing bead when the gap is >= 10/9 mm (``cad.layout``); with a margin.
CHANNEL_GAP_MM = 1.15

#: Old names of the wall fields (design files written before the walls were sized): now the minimums.
_LEGACY_FIXED = {"outer_wall_mm": "min_outer_wall_mm", "inner_tube_wall_mm": "min_inner_tube_wall_mm",
                 "top_cap_mm": "min_top_cap_mm", "base_mm": "min_base_mm"}

_NONNEGATIVE = {"dead_volume_1_mm3", "dead_volume_2_mm3", "servo_and_valve_mass_g", "bladder_min_gap_mm"}


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

    def __post_init__(self) -> None:
        for f in fields(self):
            v = getattr(self, f.name)
            if f.type in ("bool", bool) and not isinstance(v, bool):
                raise DesignError(f"fixed.{f.name} must be true or false, got {show(v)}")
            if f.type in ("float", float):
                if isinstance(v, bool) or not isinstance(v, (int, float)) or not math.isfinite(v):
                    raise DesignError(f"fixed.{f.name} must be a finite number, got {show(v)}")
                if f.name in _NONNEGATIVE:
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
        for key in ("housing_material", "rod_material", "support_ring_material"):
            try:
                get_material(getattr(self, key))
            except ValueError as exc:
                raise DesignError(f"fixed.{key}: {exc}") from None

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
        try:
            return cls(**{**data, **override})
        except TypeError as exc:  # pragma: no cover - guarded by the key check
            raise DesignError(str(exc)) from None
