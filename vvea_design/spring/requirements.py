"""Requirements (a TOML file): what the designer asks of the unit.

The defaults are the paper's unit: 40 mm travel with F(0) = 0, 59.5 mm ×
132.5 mm envelope, charges <= 4 MPa, mean stiffness >= 93.2 N/mm at the
highest charge (the identified 23.31 N/mm/MPa × 4 MPa), walls with a safety
factor >= 2 on yield (6061-T6), at least 20 % of the chamber-2 gas left at
full stroke, and a bladder that has room to move at both stroke ends.

A requirements file holds any of the top-level keys of :class:`Requirements`,
plus optional tables ``[bounds]`` (search range of each decision variable,
``name = [low, high]``) and ``[fixed]`` (any field of
:class:`~vvea_design.spring.design.FixedParameters`)::

    max_outer_diameter_mm = 59.5
    max_housing_length_mm = 132.5
    min_mean_stiffness_N_per_mm = 93.2

    [bounds]
    piston_diameter_mm = [12, 50]

    [fixed]
    housing_material = "al-7075-t6"

The evaluation of a design against them (margins, feasibility) is the optimisation problem,
:mod:`vvea_design.spring.problem`.
"""

from __future__ import annotations

import math
import re
import tomllib
from dataclasses import asdict, dataclass, field, fields, replace
from pathlib import Path
from typing import Any

from .layouts import COMMON_BOUNDS, LAYOUTS, get_layout, layout_variables
from .parameters import DesignError, FixedParameters
from ..materials.silicones import allowable_strain, get_silicone
from ..inputs import decode_text, read_input_bytes
from ..messages import show
from ..plausibility import FIELD_LIMITS, LIMITS, check_field

__all__ = [
    "Requirements",
    "SpecError",
    "load_requirements",
    "default_bounds",
    "DEFAULT_BOUNDS",
    "BOUNDS_FOLLOW",
    "FIXED_FOLLOW",
    "follow_flow_path",
    "REQUIREMENT_LIMITS",
    "envelope_room",
    "OBJECTIVES",
    "REPORTED_N",
]

#: Search range of the bladder's cast fill (a stroke fraction): the strain surrogate is poor below 0.1
#: (docs/layout.md).
CAST_FILL_BOUNDS = (0.1, 1.0)


def default_bounds(req: "Requirements | None" = None) -> dict[str, tuple[float, float]]:
    """Default search range of each decision variable of every registered layout, following ``req``.

    Parameters
    ----------
    req : Requirements or None
        The requirements the search serves; None: the ranges of the paper's unit (the layouts' own).

    Returns
    -------
    dict of str to tuple of float
        Variable name -> ``(low, high)`` in its unit (mm, mm³; ``bladder_cast_fill`` a fraction): the
        shared four, each layout's own (:mod:`vvea_design.spring.layouts`), then the cast fill. With
        ``req`` the ranges follow its envelope and never fall below the paper's
        (:data:`BOUNDS_FOLLOW`): the outer diameter runs up to ``max_outer_diameter_mm``, the piston up to what fits inside the envelope's walls and bladder, every
        gas volume (mm³) up to the gas the envelope's bore holds between the end caps.
    """
    own = {name: var.bounds for name, (_, var) in layout_variables().items()}
    base = {**COMMON_BOUNDS, **own, "bladder_cast_fill": CAST_FILL_BOUNDS}
    if req is None:
        return base
    return {name: _follow(name, lo, hi, req) for name, (lo, hi) in base.items()}


def envelope_room(max_outer_diameter_mm: float, max_housing_length_mm: float,
                  fixed: FixedParameters) -> tuple[float, float]:
    """What an envelope can hold at most: the widest piston and the most gas.

    Parameters
    ----------
    max_outer_diameter_mm, max_housing_length_mm : float
        The envelope (mm).
    fixed : FixedParameters
        Its thinnest walls and end caps, the bladder's thickness and gaps (mm).

    Returns
    -------
    piston_mm, gas_mm3 : float
        The largest piston diameter inside the thinnest outer and inner walls, the bladder and its two
        gaps (mm); the volume of the outer bore between the thinnest end caps (mm³).
    """
    f = fixed
    piston = max_outer_diameter_mm - 2 * (f.min_outer_wall_mm + f.min_inner_tube_wall_mm + f.bladder_thickness_mm
                                          + 2 * f.bladder_min_gap_mm)
    bore = max_outer_diameter_mm - 2 * f.min_outer_wall_mm
    gas = math.pi / 4 * bore**2 * max(max_housing_length_mm - f.min_top_cap_mm - f.min_base_mm, 0.0)
    return piston, gas


#: How a default search bound follows the requirements (table-driven: a new decision variable slots in by its
#: name, a gas volume ``*_mm3`` scales like V1 and V2): variable (or suffix) -> rule.
BOUNDS_FOLLOW: dict[str, str] = {
    "outer_diameter_mm": "high end at the envelope's max_outer_diameter_mm",
    "piston_diameter_mm": "high end scaled up to the widest piston the envelope holds",
    "*_mm3": "high end scaled up to the gas the envelope's bore holds between the end caps",
}


#: The envelope diameter of the paper's unit (mm), the size the default flow path was drawn for.
PAPER_OUTER_DIAMETER_MM = 59.5

#: The open flow path's largest sizes (``[fixed]``, mm) that follow the envelope under the buildability rules: a
#: field left at its default (the paper's valve) grows in proportion to ``max_outer_diameter_mm / 59.5`` (rounded
#: down to 0.5 mm; never below the default). The open-valve damping grows as A2^3 / port^4, so a larger unit with
#: the paper's 3 mm port cannot meet ``max_parasitic_damping_N_s_per_mm``: a bookkeeping limit, not a physical one.
FIXED_FOLLOW: tuple[str, ...] = ("throttle_bore_mm", "fluid_channel_mm", "ring_channel_mm")


def follow_flow_path(fixed: FixedParameters, max_outer_diameter_mm: float) -> FixedParameters:
    """The fixed parameters with the flow path's default sizes scaled to the envelope (:data:`FIXED_FOLLOW`).

    Parameters
    ----------
    fixed : FixedParameters
        The fixed parameters; a field of :data:`FIXED_FOLLOW` that differs from its default is the user's and kept.
    max_outer_diameter_mm : float
        The envelope's diameter (mm).

    Returns
    -------
    FixedParameters
        ``fixed`` itself at or below the paper's envelope (59.5 mm) or under the gas-only rules; else with each
        default flow-path size times ``max_outer_diameter_mm / 59.5``, rounded down to 0.5 mm (mm).
    """
    scale = max_outer_diameter_mm / PAPER_OUTER_DIAMETER_MM
    if scale <= 1.0 or fixed.sizing_rules != "buildable":
        return fixed
    default = FixedParameters()
    grown = {name: max(getattr(default, name), math.floor(2 * getattr(default, name) * scale) / 2)
             for name in FIXED_FOLLOW if getattr(fixed, name) == getattr(default, name)}
    return replace(fixed, **grown) if grown else fixed


def _follow(name: str, lo: float, hi: float, req: "Requirements") -> tuple[float, float]:
    piston, gas = envelope_room(req.max_outer_diameter_mm, req.max_housing_length_mm, req.fixed)
    if name == "outer_diameter_mm":
        return (lo, req.max_outer_diameter_mm)
    if name == "piston_diameter_mm":
        return (lo, hi * max(1.0, piston / COMMON_BOUNDS["piston_diameter_mm"][1]))
    if name.endswith("_mm3"):
        return (lo, hi * max(1.0, gas / COMMON_BOUNDS["V2_mm3"][1]))
    return (lo, hi)


def _zero_low() -> set[str]:
    """Bounds whose low end may be 0 (the layouts' own volumes, the cast fill); the others must be > 0."""
    return set(layout_variables()) | {"bladder_cast_fill"}


#: Default search range of each decision variable (of the layouts registered at import; :func:`default_bounds`).
DEFAULT_BOUNDS: dict[str, tuple[float, float]] = default_bounds()

#: Polytropic exponents whose worst linearity each objective minimises (``nominal``: the design's n_polytropic).
OBJECTIVES: dict[str, tuple[float, ...] | None] = {
    "nominal": None,
    "isothermal": (1.0,),
    "adiabatic": (1.4,),
    "worst": (1.0, 1.4),
}

#: Exponents whose linearity every design file and report shows.
REPORTED_N = {"isothermal": 1.0, "adiabatic": 1.4}


#: Requirements that may be absent (``None``: no limit).
_OPTIONAL = ("max_mass_g", "max_bladder_strain", "max_linearity_adiabatic", "max_parasitic_damping_N_s_per_mm")
#: Top-level requirements that FixedParameters also carries (kept equal to the top level).
_TOP_LEVEL_IN_FIXED = ("travel_mm", "n_polytropic")


#: Which range of :data:`vvea_design.plausibility.LIMITS` each numeric requirement must lie in: the entries of
#: :data:`vvea_design.plausibility.FIELD_LIMITS` (the one table) for the top-level requirements (``None`` values
#: of optional ones are not checked). A value out of range whose scale points to another unit (metres, bar,
#: percent) names that unit. A target no design can reach (a stiffness of 1e9 N/mm) within the range is no bad
#: input: the optimiser reports it infeasible (exit 3).
REQUIREMENT_LIMITS: dict[str, str] = {
    name: FIELD_LIMITS[name] for name in (
        "travel_mm", "max_outer_diameter_mm", "max_housing_length_mm", "max_charge_MPa",
        "min_mean_stiffness_N_per_mm", "min_wall_safety_factor", "min_gas_fraction_at_full_stroke", "max_mass_g",
        "max_bladder_strain", "n_polytropic", "max_linearity_adiabatic", "max_parasitic_damping_N_s_per_mm")
}


#: A travel below this share of the housing length whose value in inches would fit the housing is refused as
#: inches (the paper's unit strokes 30 % of its length).
TRAVEL_SHARE_MIN = 0.02


def _inch_hint(name: str, value: float) -> str:
    """``"; it looks like inches: 1.575 in is 40 mm"`` when ``value`` x 25.4 is a plausible ``name``, else ""."""
    mm = value * 25.4
    if LIMITS[FIELD_LIMITS[name]].problem(mm) is None:
        return f"; it looks like inches: {show(value)} in is {show(mm)} mm; give it in mm"
    return ""


def _hint(name: str, req: "Requirements") -> str:
    """``"; it looks like a percentage: ..."`` when the field's value fits its range in another unit, else ""."""
    hint = LIMITS[FIELD_LIMITS[name]].unit_hint(getattr(req, name))
    return f"; {hint}" if hint else ""


class SpecError(ValueError):
    """A requirements file or value that is wrong (names the file, key and problem)."""


@dataclass(frozen=True)
class Requirements:
    """What the designer asks for. Units in the names."""

    travel_mm: float = 40.0  #: stroke
    setpoint_x0_mm: float = 0.0  #: zero-force displacement (F(x0) = 0)
    max_outer_diameter_mm: float = 59.5  #: envelope diameter
    max_housing_length_mm: float = 132.5  #: envelope length
    max_charge_MPa: float = 4.0  #: highest charge pressure of either chamber
    min_mean_stiffness_N_per_mm: float = 93.2  #: least-squares slope at the highest charge
    min_wall_safety_factor: float = 2.0  #: on yield, every pressure wall
    min_gas_fraction_at_full_stroke: float = 0.2  #: (V2 - A2 travel) / V2
    max_mass_g: float | None = None  #: optional mass limit (Pareto fronts use it)
    max_bladder_strain: float | None = None  #: optional FE strain-bound constraint (fraction)
    bladder_material: str = "dragon-skin-20"  #: bladder silicone: checked by `vvea design` and by the optional strain constraint
    n_polytropic: float = 1.0  #: 1 isothermal ... 1.4 adiabatic (the design's nominal law: stiffness, setpoint)
    objective: str = "nominal"  #: nominal | isothermal | adiabatic | worst (of n = 1 and 1.4)
    objective_n: tuple[float, ...] | None = None  #: or: minimise the worst linearity over these exponents
    layouts: tuple[str, ...] = ("inner_tube", "bulkhead", "annulus_top")  #: layout variants the optimiser chooses between
    optimise_cast_fill: bool = False  #: the bladder's cast fill is a decision variable too (max_bladder_strain then defaults to the silicone's cyclic allowable)
    max_linearity_adiabatic: float | None = None  #: optional: linearity error at n = 1.4 <= this (fraction)
    #: joints the optimiser chooses between (thread: both ends screwed into the outer tube; ring_top: a DIN 472
    #: ring holds the top cap; tie_rods: rods outside the tube clamp both ends); with fixed.sizing_rules = "buildable"
    joints: tuple[str, ...] = ("thread", "ring_top", "tie_rods")
    #: the damping of the fully open throttle (the flow path's parasitic damping, the paper's identification) may
    #: not exceed this, N s/mm: 1.5 is the paper's actuator study's D_min = 12.1 N m s/rad through the mapping
    #: D = 2 r^2 L with its pulley radius 63.9 mm (null: no limit; with fixed.sizing_rules = "buildable")
    max_parasitic_damping_N_s_per_mm: float | None = 1.5
    #: search ranges given explicitly (``[bounds]``); every other variable's range follows the requirements
    #: (:func:`default_bounds`, :attr:`resolved_bounds`)
    bounds: dict[str, tuple[float, float]] = field(default_factory=dict)
    fixed: FixedParameters = field(default_factory=FixedParameters)

    def __post_init__(self) -> None:
        positive = ("travel_mm", "max_outer_diameter_mm", "max_housing_length_mm", "max_charge_MPa",
                    "min_mean_stiffness_N_per_mm", "min_wall_safety_factor")
        for name in positive:
            v = getattr(self, name)
            if isinstance(v, bool) or not isinstance(v, (int, float)) or not math.isfinite(v) or v <= 0:
                raise SpecError(f"{name} must be a positive number, got {show(v)}")
        late = ("min_gas_fraction_at_full_stroke", "n_polytropic", "max_mass_g", "max_linearity_adiabatic",
                "max_bladder_strain")  # their own checks first (their messages), then the plausible range
        for name in REQUIREMENT_LIMITS:
            if name not in late:
                check_field(name, getattr(self, name), name, SpecError)
        if not 0.0 <= self.min_gas_fraction_at_full_stroke < 1.0:
            raise SpecError(f"min_gas_fraction_at_full_stroke must be in [0, 1), got "
                            f"{show(self.min_gas_fraction_at_full_stroke)}{_hint('min_gas_fraction_at_full_stroke', self)}")
        if not 1.0 <= self.n_polytropic <= 1.4:
            raise SpecError(f"n_polytropic must be in [1, 1.4], got {show(self.n_polytropic)}")
        try:
            get_silicone(self.bladder_material)
        except ValueError as exc:
            raise SpecError(f"bladder_material: {exc}") from None
        if self.max_mass_g is not None and not (self.max_mass_g > 0):
            raise SpecError(f"max_mass_g must be > 0, got {show(self.max_mass_g)}")
        if self.max_linearity_adiabatic is not None and not (0 < self.max_linearity_adiabatic < 1):
            raise SpecError(f"max_linearity_adiabatic must be a fraction in (0, 1), got "
                            f"{show(self.max_linearity_adiabatic)}{_hint('max_linearity_adiabatic', self)}")
        if self.max_bladder_strain is not None and not (0 < self.max_bladder_strain < 10):
            raise SpecError(f"max_bladder_strain must be a fraction in (0, 10), got {show(self.max_bladder_strain)}"
                            f"{_hint('max_bladder_strain', self)}")
        for name in late:
            check_field(name, getattr(self, name), name, SpecError)
        self._check_strain_limit()
        if not (abs(self.setpoint_x0_mm) < self.travel_mm):
            raise SpecError(f"setpoint_x0_mm ({show(self.setpoint_x0_mm)}) must lie inside the travel "
                            f"(|x0| < {show(self.travel_mm)})")
        if self.objective not in OBJECTIVES:
            raise SpecError(f"objective must be one of {list(OBJECTIVES)}, got {show(self.objective)}")
        if self.objective_n is not None:
            ns = tuple(self.objective_n) if isinstance(self.objective_n, (list, tuple)) else None
            if (not ns or not all(isinstance(v, (int, float)) and not isinstance(v, bool) and 1.0 <= v <= 1.4
                                  for v in ns)):
                raise SpecError(f"objective_n must be a non-empty list of exponents in [1, 1.4], got {show(self.objective_n)}")
            object.__setattr__(self, "objective_n", tuple(float(v) for v in ns))
        lays = tuple(self.layouts) if isinstance(self.layouts, (list, tuple)) else ()
        if not lays or any(not isinstance(v, str) or v not in LAYOUTS for v in lays):
            raise SpecError(f"layouts must be a non-empty list of {list(LAYOUTS)}, got {show(self.layouts)}")
        object.__setattr__(self, "layouts", lays)
        from .joints import JOINTS

        js = tuple(self.joints) if isinstance(self.joints, (list, tuple)) else ()
        if not js or any(not isinstance(v, str) or v not in JOINTS for v in js):
            raise SpecError(f"joints must be a non-empty list of {list(JOINTS)}, got {show(self.joints)}")
        object.__setattr__(self, "joints", js)
        if self.max_parasitic_damping_N_s_per_mm is not None and not (self.max_parasitic_damping_N_s_per_mm > 0):
            raise SpecError(f"max_parasitic_damping_N_s_per_mm must be > 0, got {show(self.max_parasitic_damping_N_s_per_mm)}")
        defaults, zero_low = default_bounds(), _zero_low()
        object.__setattr__(self, "bounds", {k: (v[0], v[1]) if isinstance(v, (list, tuple)) and len(v) == 2 else v
                                            for k, v in dict(self.bounds).items()})
        known_vars = set(defaults)
        unknown = set(self.bounds) - known_vars
        if unknown:
            raise SpecError(f"[bounds] has unknown variable(s) {sorted(unknown)}; known: {sorted(known_vars)}")
        for name, pair in self.bounds.items():
            if (not isinstance(pair, tuple) or not all(isinstance(p, (int, float)) and not isinstance(p, bool)
                                                       for p in pair)):
                raise SpecError(f"[bounds] {name} must be [low, high] numbers, got {show(pair)}")
            lo, hi = pair
            low_ok = lo >= 0 if name in zero_low else lo > 0
            if not (math.isfinite(lo) and math.isfinite(hi)) or not low_ok or hi <= lo:
                raise SpecError(f"[bounds] {name} = {show([lo, hi])} must satisfy 0 < low < high"
                                + (" (low may be 0)" if name in zero_low else ""))
            for end, v in (("low", lo), ("high", hi)):
                if not (end == "low" and v == 0 and name in zero_low):
                    check_field(name, v, f"[bounds] {name} ({end} end)", SpecError)
        if self.bounds:  # a range equal to the one that follows the requirements is no override
            derived = default_bounds(self)
            object.__setattr__(self, "bounds", {k: v for k, v in self.bounds.items()
                                                if (float(v[0]), float(v[1])) != tuple(map(float, derived[k]))})
        if self.bounds.get("bladder_cast_fill", (0.0, 1.0))[1] > 1.0:
            raise SpecError(f"[bounds] bladder_cast_fill = {show(list(self.bounds['bladder_cast_fill']))}: a stroke "
                            "fraction, the high end must be <= 1")
        if not isinstance(self.optimise_cast_fill, bool):
            raise SpecError(f"optimise_cast_fill must be true or false, got {show(self.optimise_cast_fill)}")
        if self.optimise_cast_fill and self.max_bladder_strain is None:
            # a free cast fill trades gas room for bladder strain: it needs a strain limit, by default the
            # one the bladder check applies (the silicone's cyclic allowable)
            object.__setattr__(self, "max_bladder_strain", allowable_strain(self.bladder_material))
        lo_D = self.bounds.get("outer_diameter_mm", defaults["outer_diameter_mm"])[0]
        if lo_D >= self.max_outer_diameter_mm:
            raise SpecError(
                f"contradictory envelope: max_outer_diameter_mm ({show(self.max_outer_diameter_mm)}) is not above the "
                f"lower search bound of outer_diameter_mm ({show(lo_D)}); "
                + ("set [bounds] outer_diameter_mm = [low, high] to search units that small"
                   if "outer_diameter_mm" not in self.bounds else "lower that bound or widen the envelope")
                + _inch_hint("max_outer_diameter_mm", self.max_outer_diameter_mm))
        if (self.fixed.travel_mm != self.travel_mm or self.fixed.n_polytropic != self.n_polytropic
                or self.fixed.wall_safety_factor != self.min_wall_safety_factor):
            try:
                object.__setattr__(self, "fixed", replace(self.fixed, travel_mm=self.travel_mm,
                                                          n_polytropic=self.n_polytropic,
                                                          wall_safety_factor=self.min_wall_safety_factor))
            except DesignError as exc:  # e.g. fixed.wall_sizing_n below the top-level n_polytropic
                raise SpecError(f"[fixed] {exc}") from None
        object.__setattr__(self, "fixed", follow_flow_path(self.fixed, self.max_outer_diameter_mm))
        if max(self.objective_exponents) > self.fixed.wall_sizing_n:
            raise SpecError(f"[fixed] wall_sizing_n ({show(self.fixed.wall_sizing_n)}) is below the exponent "
                            f"{show(max(self.objective_exponents))} the objective evaluates the spring at: the walls "
                            "would be sized for a lower peak pressure than the spring is designed for")
        self._check_room()
        from .contradictions import check_values

        check_values(self, SpecError)

    def _check_room(self) -> None:
        """The envelope leaves room for the servo's mass and the stroke; a travel that short reads as inches."""
        if self.max_mass_g is not None and self.max_mass_g <= self.fixed.servo_and_valve_mass_g:
            raise SpecError(f"max_mass_g ({show(self.max_mass_g)} g) leaves nothing for the unit: the servo, valve and "
                            f"fittings alone weigh fixed.servo_and_valve_mass_g = "
                            f"{show(self.fixed.servo_and_valve_mass_g)} g")
        min_len = (self.fixed.min_top_cap_mm + self.fixed.min_base_mm + self.fixed.piston_height_mm + self.travel_mm
                   + self.fixed.fluid_clearance_mm)
        if self.max_housing_length_mm <= min_len:
            f = self.fixed
            parts = " + ".join(f"{k} {show(v)}" for k, v in (
                ("[fixed] min_top_cap_mm", f.min_top_cap_mm), ("[fixed] min_base_mm", f.min_base_mm),
                ("[fixed] piston_height_mm", f.piston_height_mm), ("travel_mm", self.travel_mm),
                ("[fixed] fluid_clearance_mm", f.fluid_clearance_mm)))
            raise SpecError(
                f"max_housing_length_mm ({show(self.max_housing_length_mm)}) leaves no room for chamber 1: end caps + piston "
                f"+ travel + fluid clearance already take {min_len:.1f} mm ({parts}); accepted: max_housing_length_mm "
                f"> {min_len:.1f}, or travel_mm < {show(round(self.max_housing_length_mm - (min_len - self.travel_mm), 3))}"
                " (or thinner [fixed] parts), and chamber 1 needs room beyond that"
                + _inch_hint("max_housing_length_mm", self.max_housing_length_mm)
            )
        room = self.max_housing_length_mm - (min_len - self.travel_mm)  # what the stroke may take at most
        if (self.travel_mm < TRAVEL_SHARE_MIN * self.max_housing_length_mm and 25.4 * self.travel_mm <= room
                and _inch_hint("travel_mm", self.travel_mm)):
            raise SpecError(  # a stroke that short in that envelope, and the same number in inches fits it
                f"travel_mm = {show(self.travel_mm)} is {100 * self.travel_mm / self.max_housing_length_mm:.2g} % of "
                f"max_housing_length_mm ({show(self.max_housing_length_mm)}), where a spring-damper unit strokes "
                f"a good share of its length" + _inch_hint("travel_mm", self.travel_mm)
                + " (or narrow the envelope to the short-stroke unit you mean)")

    def _check_strain_limit(self) -> None:
        """A bladder strain limit beyond what its silicone survives even once (a third of its elongation at break)."""
        if self.max_bladder_strain is None:
            return
        from ..materials.silicones import allowable_strain

        static = allowable_strain(self.bladder_material, "static")
        if self.max_bladder_strain > static:
            pct = (f"; it looks like a percentage: {show(self.max_bladder_strain)} % is "
                   f"{show(self.max_bladder_strain / 100)} (give a fraction)" if self.max_bladder_strain >= 1 else "")
            raise SpecError(f"max_bladder_strain = {show(self.max_bladder_strain)} is beyond what "
                            f"{self.bladder_material} survives even once (its static allowable, a third of its "
                            f"elongation at break, is {show(round(static, 4))}){pct}")

    @property
    def buildable(self) -> bool:
        """True when the buildability rules apply (``fixed.sizing_rules = "buildable"``): joints, damper loads,
        tolerances, the hydraulics' constraint."""
        return self.fixed.sizing_rules == "buildable"

    @property
    def joint_choices(self) -> tuple[str, ...]:
        """The joints the optimiser tries: :attr:`joints` under the buildability rules; the gas-only rules have none
        (``("thread",)``, which they ignore)."""
        return self.joints if self.buildable else ("thread",)

    @property
    def objective_exponents(self) -> tuple[float, ...]:
        """The polytropic exponents whose worst linearity is the objective."""
        if self.objective_n is not None:
            return tuple(self.objective_n)
        ns = OBJECTIVES[self.objective]
        return (float(self.n_polytropic),) if ns is None else ns

    def decision_variables(self, layout: str = "inner_tube") -> tuple[str, ...]:
        """The decision variables of ``layout``, plus ``bladder_cast_fill`` when ``optimise_cast_fill``.

        Parameters
        ----------
        layout : str
            Layout variant, a name of :data:`vvea_design.spring.layouts.LAYOUTS` (``"inner_tube"``,
            ``"bulkhead"`` or ``"annulus_top"``).

        Returns
        -------
        tuple of str
            Variable names in the optimiser's order, each with its unit in the name (mm, mm³;
            ``bladder_cast_fill`` a fraction of the stroke).

        Raises
        ------
        DesignError
            If ``layout`` is unknown.
        """
        names = get_layout(layout).decision_variables
        return names + ("bladder_cast_fill",) if self.optimise_cast_fill else names

    def search_bounds(self, layout: str = "inner_tube") -> list[tuple[float, float]]:
        """Bounds per decision variable of ``layout``, clipped to the envelope.

        Parameters
        ----------
        layout : str
            Layout variant, a name of :data:`vvea_design.spring.layouts.LAYOUTS` (``"inner_tube"``,
            ``"bulkhead"`` or ``"annulus_top"``).

        Returns
        -------
        list of tuple of float
            ``(low, high)`` per variable of :meth:`decision_variables`, in its order and unit
            (mm, mm³, fraction); the outer diameter's high end is at most ``max_outer_diameter_mm``.

        Raises
        ------
        DesignError
            If ``layout`` is unknown.
        """
        out, resolved = [], self.resolved_bounds
        for name in self.decision_variables(layout):
            lo, hi = resolved[name]
            if name == "outer_diameter_mm":
                hi = min(hi, self.max_outer_diameter_mm)
            out.append((float(lo), float(hi)))
        return out

    @property
    def resolved_bounds(self) -> dict[str, tuple[float, float]]:
        """The search range of every decision variable: the explicit :attr:`bounds`, the rest following these
        requirements (:func:`default_bounds`), in mm, mm³ and fractions."""
        return {**default_bounds(self), **self.bounds}

    def to_dict(self) -> dict[str, Any]:
        """JSON/TOML-ready content (what a design file's ``spec`` holds).

        Returns
        -------
        dict
            Every field (units in the names), ``bounds`` as ``name -> [low, high]`` (every variable's range
            the search used, :attr:`resolved_bounds`), ``layouts``
            and ``objective_n`` as lists, ``fixed`` as a nested dict.
        """
        d = asdict(self)
        d["bounds"] = {k: list(v) for k, v in self.resolved_bounds.items()}
        d["layouts"] = list(self.layouts)
        d["joints"] = list(self.joints)
        if self.objective_n is not None:
            d["objective_n"] = list(self.objective_n)
        return d

    @classmethod
    def from_dict(cls, data: dict[str, Any], source: str = "requirements") -> "Requirements":
        """Build from a parsed TOML/JSON mapping; every error names ``source`` and the key.

        Parameters
        ----------
        data : dict
            Top-level keys of :class:`Requirements` (units in the names) with optional ``bounds``
            (``name -> [low, high]``) and ``fixed`` (fields of ``FixedParameters``) tables.
        source : str
            Name of where ``data`` came from (a file path), put in front of every error.

        Returns
        -------
        Requirements
            The validated requirements; keys not given keep their defaults.

        Raises
        ------
        SpecError
            For an unknown key, a value of the wrong type or out of range, a malformed table, or a
            ``[fixed]`` copy of travel / polytropic exponent / safety factor that disagrees with the
            top level.
        """
        if not isinstance(data, dict):
            raise SpecError(f"{source}: expected a table of requirements, got {type(data).__name__}")
        known = {f.name for f in fields(cls)}
        unknown = set(data) - known
        if unknown:
            raise SpecError(f"{source}: unknown key(s) {sorted(unknown)}; known keys: {sorted(known)}")
        kwargs: dict[str, Any] = {}
        for key, value in data.items():
            if key == "bounds":
                if not isinstance(value, dict):
                    raise SpecError(f"{source}: [bounds] must be a table")
                b = {}
                for name, pair in value.items():
                    if (not isinstance(pair, (list, tuple)) or len(pair) != 2
                            or not all(isinstance(p, (int, float)) and not isinstance(p, bool) for p in pair)):
                        raise SpecError(f"{source}: [bounds] {name} must be [low, high] numbers, got {show(pair)}")
                    b[name] = (float(pair[0]), float(pair[1]))
                kwargs["bounds"] = b
            elif key == "fixed":
                try:
                    kwargs["fixed"] = FixedParameters.from_dict(value)
                except DesignError as exc:
                    raise SpecError(f"{source}: [fixed] {exc}") from None
                # travel and polytropic index are one quantity each: set at the top level; a copy in
                # [fixed] (as a design file's spec holds) must agree with it, never silently lose
                for dup in _TOP_LEVEL_IN_FIXED:
                    if dup in value:
                        top = data.get(dup, getattr(cls, dup))
                        if not isinstance(top, (int, float)) or isinstance(top, bool) or value[dup] != top:
                            raise SpecError(
                                f"{source}: [fixed] {dup} = {show(value[dup])} disagrees with the top-level {dup} = "
                                f"{show(top)}{'' if dup in data else ' (the default)'}; set {dup} once, at the top "
                                "level (above any [table])")
                wsf = value.get("wall_safety_factor")
                top_sf = data.get("min_wall_safety_factor", getattr(cls, "min_wall_safety_factor"))
                if wsf is not None and wsf != top_sf:
                    raise SpecError(f"{source}: [fixed] wall_safety_factor = {show(wsf)} disagrees with the top-level "
                                    f"min_wall_safety_factor = {show(top_sf)}; set it once, at the top level")
            elif key == "optimise_cast_fill":
                if not isinstance(value, bool):
                    raise SpecError(f"{source}: optimise_cast_fill must be true or false, got {show(value)}")
                kwargs[key] = value
            elif key in ("bladder_material", "objective"):
                if not isinstance(value, str):
                    raise SpecError(f"{source}: {key} must be a string, got {show(value)}")
                kwargs[key] = value
            elif key in ("layouts", "objective_n", "joints"):
                if value is not None and not isinstance(value, (list, tuple)):
                    raise SpecError(f"{source}: {key} must be a list, got {show(value)}")
                kwargs[key] = value
            else:
                if value is None and key in _OPTIONAL:
                    pass
                elif isinstance(value, bool) or not isinstance(value, (int, float)):
                    raise SpecError(f"{source}: {key} must be a number, got {show(value)}")
                kwargs[key] = value
        try:
            req = cls(**kwargs)
        except SpecError as exc:
            raise SpecError(f"{source}: {exc}") from None
        written = {k: float(v) for k, v in (data.get("fixed") or {}).items() if k in FIXED_FOLLOW}
        if written and any(getattr(req.fixed, k) != v for k, v in written.items()):  # the user's own size stays
            object.__setattr__(req, "fixed", replace(req.fixed, **written))
        return req


def load_requirements(path: str | Path | None) -> Requirements:
    """Read a requirements TOML file (``None`` = the built-in defaults).

    Parameters
    ----------
    path : str or Path or None
        The TOML file (UTF-8, a byte-order mark allowed); None: the paper's unit.

    Returns
    -------
    Requirements
        The validated requirements.

    Raises
    ------
    SpecError
        If the file does not exist, is not a regular file (a folder, a FIFO, a device), is larger
        than 1 MiB, cannot be read, is not UTF-8 (UTF-16 is named; otherwise line and column) or not
        valid TOML, holds a number of hundreds of digits, or a value is wrong
        (:meth:`Requirements.from_dict`).
    """
    if path is None:
        return Requirements()
    path = Path(path)
    raw = read_input_bytes(path, "requirements file", SpecError)
    text = decode_text(raw, path, "requirements file", SpecError, "TOML")
    long = re.search(r"[0-9_]{400,}", text)
    if long:  # Python refuses to convert integers of more than 4300 digits (a ValueError inside tomllib)
        line = text.count("\n", 0, long.start()) + 1
        key = re.match(r"\s*([A-Za-z0-9_.\"-]+)\s*=", text.splitlines()[line - 1])
        raise SpecError(f"{path}: line {line}: {key.group(1) + ': ' if key else ''}a number of {len(long.group())} "
                        "digits; no requirement needs more than a handful")
    try:
        data = tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        raise SpecError(f"{path}: not valid TOML: {exc}") from None
    except (ValueError, RecursionError) as exc:  # an absurd literal tomllib cannot convert
        raise SpecError(f"{path}: not valid TOML: {exc}") from None
    req = Requirements.from_dict(data, source=str(path))
    from .contradictions import check_written

    check_written(req, data, str(path), SpecError)  # settings the file wrote that contradict each other
    return req
