"""Requirements (a TOML file) and the constraint margins of a design against them.

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
"""

from __future__ import annotations

import math
import tomllib
from dataclasses import asdict, dataclass, field, fields, replace
from pathlib import Path
from typing import Any

import numpy as np

from .design import (CHANNEL_GAP_MM, LAYOUTS, WALLS, Design, DesignError, FixedParameters, derive,
                     get_layout)
from .gas_spring import linearity_exact
from ..materials.silicones import allowable_strain, get_silicone
from ..messages import show

__all__ = [
    "Requirements",
    "SpecError",
    "load_requirements",
    "Evaluation",
    "evaluate_design",
    "constraint_margins",
    "constraint_names",
    "evaluate_population",
    "design_from_vector",
    "OBJECTIVES",
]

#: Default search range of each decision variable.
DEFAULT_BOUNDS: dict[str, tuple[float, float]] = {
    "piston_diameter_mm": (12.0, 50.0),
    "outer_diameter_mm": (25.0, 59.5),
    "V1_mm3": (5.0e3, 3.0e5),
    "V2_mm3": (5.0e3, 3.0e5),
    "V2_top_mm3": (0.0, 1.5e5),
    "V1_annulus_mm3": (0.0, 1.5e5),
    "bladder_cast_fill": (0.1, 1.0),  # the strain surrogate is poor below 0.1 (docs/layout.md)
}

#: Bounds whose low end may be 0 (the others must be > 0).
_ZERO_LOW = ("V2_top_mm3", "V1_annulus_mm3", "bladder_cast_fill")

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
_OPTIONAL = ("max_mass_g", "max_bladder_strain", "max_linearity_adiabatic")
#: Top-level requirements that FixedParameters also carries (kept equal to the top level).
_TOP_LEVEL_IN_FIXED = ("travel_mm", "n_polytropic")


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
    bounds: dict[str, tuple[float, float]] = field(default_factory=lambda: dict(DEFAULT_BOUNDS))
    fixed: FixedParameters = field(default_factory=FixedParameters)

    def __post_init__(self) -> None:
        positive = ("travel_mm", "max_outer_diameter_mm", "max_housing_length_mm", "max_charge_MPa",
                    "min_mean_stiffness_N_per_mm", "min_wall_safety_factor")
        for name in positive:
            v = getattr(self, name)
            if isinstance(v, bool) or not isinstance(v, (int, float)) or not math.isfinite(v) or v <= 0:
                raise SpecError(f"{name} must be a positive number, got {show(v)}")
        if not 0.0 <= self.min_gas_fraction_at_full_stroke < 1.0:
            raise SpecError(f"min_gas_fraction_at_full_stroke must be in [0, 1), got {show(self.min_gas_fraction_at_full_stroke)}")
        if not 1.0 <= self.n_polytropic <= 1.4:
            raise SpecError(f"n_polytropic must be in [1, 1.4], got {show(self.n_polytropic)}")
        try:
            get_silicone(self.bladder_material)
        except ValueError as exc:
            raise SpecError(f"bladder_material: {exc}") from None
        if self.max_mass_g is not None and not (self.max_mass_g > 0):
            raise SpecError(f"max_mass_g must be > 0, got {show(self.max_mass_g)}")
        if self.max_linearity_adiabatic is not None and not (0 < self.max_linearity_adiabatic < 1):
            raise SpecError(f"max_linearity_adiabatic must be a fraction in (0, 1), got {show(self.max_linearity_adiabatic)}")
        if self.max_bladder_strain is not None and not (0 < self.max_bladder_strain < 10):
            raise SpecError(f"max_bladder_strain must be a fraction in (0, 10), got {show(self.max_bladder_strain)}")
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
        known_vars = set(DEFAULT_BOUNDS)
        unknown = set(self.bounds) - known_vars
        if unknown:
            raise SpecError(f"[bounds] has unknown variable(s) {sorted(unknown)}; known: {sorted(known_vars)}")
        for name, (lo, hi) in self.bounds.items():
            low_ok = lo >= 0 if name in _ZERO_LOW else lo > 0
            if not (math.isfinite(lo) and math.isfinite(hi)) or not low_ok or hi <= lo:
                raise SpecError(f"[bounds] {name} = {show([lo, hi])} must satisfy 0 < low < high"
                                + (" (low may be 0)" if name in _ZERO_LOW else ""))
        if self.bounds.get("bladder_cast_fill", (0.0, 1.0))[1] > 1.0:
            raise SpecError(f"[bounds] bladder_cast_fill = {show(list(self.bounds['bladder_cast_fill']))}: a stroke "
                            "fraction, the high end must be <= 1")
        if not isinstance(self.optimise_cast_fill, bool):
            raise SpecError(f"optimise_cast_fill must be true or false, got {show(self.optimise_cast_fill)}")
        if self.optimise_cast_fill and self.max_bladder_strain is None:
            # a free cast fill trades gas room for bladder strain: it needs a strain limit, by default the
            # one the bladder check applies (the silicone's cyclic allowable)
            object.__setattr__(self, "max_bladder_strain", allowable_strain(self.bladder_material))
        lo_D = self.bounds.get("outer_diameter_mm", DEFAULT_BOUNDS["outer_diameter_mm"])[0]
        if lo_D >= self.max_outer_diameter_mm:
            raise SpecError(
                f"contradictory envelope: max_outer_diameter_mm ({show(self.max_outer_diameter_mm)}) is not above the "
                f"lower search bound of outer_diameter_mm ({show(lo_D)})"
            )
        if (self.fixed.travel_mm != self.travel_mm or self.fixed.n_polytropic != self.n_polytropic
                or self.fixed.wall_safety_factor != self.min_wall_safety_factor):
            object.__setattr__(self, "fixed", replace(self.fixed, travel_mm=self.travel_mm, n_polytropic=self.n_polytropic,
                                                      wall_safety_factor=self.min_wall_safety_factor))
        min_len = (self.fixed.min_top_cap_mm + self.fixed.min_base_mm + self.fixed.piston_height_mm + self.travel_mm
                   + self.fixed.fluid_clearance_mm)
        if self.max_housing_length_mm <= min_len:
            raise SpecError(
                f"max_housing_length_mm ({show(self.max_housing_length_mm)}) leaves no room for chamber 1: end caps + piston "
                f"+ travel + fluid clearance already take {min_len:.1f} mm"
            )

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
            Layout variant, a name of :data:`vvea_design.spring.design.LAYOUTS` (``"inner_tube"``,
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
            Layout variant, a name of :data:`vvea_design.spring.design.LAYOUTS` (``"inner_tube"``,
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
        out = []
        for name in self.decision_variables(layout):
            lo, hi = self.bounds.get(name, DEFAULT_BOUNDS[name])
            if name == "outer_diameter_mm":
                hi = min(hi, self.max_outer_diameter_mm)
            out.append((float(lo), float(hi)))
        return out

    def to_dict(self) -> dict[str, Any]:
        """JSON/TOML-ready content (what a design file's ``spec`` holds).

        Returns
        -------
        dict
            Every field (units in the names), ``bounds`` as ``name -> [low, high]``, ``layouts``
            and ``objective_n`` as lists, ``fixed`` as a nested dict.
        """
        d = asdict(self)
        d["bounds"] = {k: list(v) for k, v in self.bounds.items()}
        d["layouts"] = list(self.layouts)
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
                b = dict(DEFAULT_BOUNDS)
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
            elif key in ("layouts", "objective_n"):
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
            return cls(**kwargs)
        except SpecError as exc:
            raise SpecError(f"{source}: {exc}") from None


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
        If the file does not exist, cannot be read, is not UTF-8 (names line and column) or not
        valid TOML, or a value is wrong (:meth:`Requirements.from_dict`).
    """
    if path is None:
        return Requirements()
    path = Path(path)
    if not path.is_file():
        raise SpecError(f"requirements file {str(path)!r} does not exist")
    try:
        raw = path.read_bytes()
    except OSError as exc:
        raise SpecError(f"{path}: cannot be read ({exc.strerror})") from None
    try:
        text = raw.decode("utf-8-sig")  # a byte-order mark (some Windows editors) is not an error
    except UnicodeDecodeError as exc:
        line = raw[:exc.start].count(b"\n") + 1
        col = exc.start - (raw.rfind(b"\n", 0, exc.start) + 1) + 1
        raise SpecError(
            f"{path}: not UTF-8 text: byte 0x{raw[exc.start]:02x} at line {line}, column {col} (byte offset "
            f"{exc.start}) cannot be decoded; TOML files are UTF-8 — save it as UTF-8 (e.g. `iconv -f latin1 -t utf-8`)"
        ) from None
    try:
        data = tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        raise SpecError(f"{path}: not valid TOML: {exc}") from None
    return Requirements.from_dict(data, source=str(path))


# ---------------------------------------------------------------------------
# Evaluation of one design against the requirements
# ---------------------------------------------------------------------------

#: Displacement samples of the curves that are drawn and written (the metric itself is exact, continuous).
N_SAMPLES = 401


@dataclass(frozen=True)
class Evaluation:
    """A design's performance and its constraint margins (positive = satisfied)."""

    design: Design
    linearity_error: float  #: fraction, exact (continuous) metric at the nominal n_polytropic
    mean_stiffness_N_per_mm: float  #: continuous least-squares slope at the design's charge (nominal n)
    max_force_N: float
    peak_pressure_MPa: float  #: highest chamber pressure the walls are sized for
    mass_g: float
    margins: dict[str, float]  #: dimensionless, positive = satisfied
    details: dict[str, dict[str, float | str]]  #: value, limit and unit of each constraint
    linearity_isothermal: float = float("nan")  #: n = 1, fraction
    linearity_adiabatic: float = float("nan")  #: n = 1.4, fraction
    mean_stiffness_adiabatic_N_per_mm: float = float("nan")  #: n = 1.4, at the design's charge
    objective: float = float("nan")  #: what the optimiser minimised (worst linearity over its exponents)
    objective_exponents: tuple[float, ...] = (1.0,)

    @property
    def feasible(self) -> bool:
        """Every margin >= 0 (to 1e-9)."""
        return all(m >= -1e-9 for m in self.margins.values())

    def binding(self, tol: float = 1e-3) -> list[str]:
        """Constraints at (or beyond) their limit.

        Parameters
        ----------
        tol : float
            A constraint binds when its margin (scaled, dimensionless) is below this.

        Returns
        -------
        list of str
            Names of the binding or violated constraints, in the order of :attr:`margins`.
        """
        return [k for k, m in self.margins.items() if m < tol]

    def performance(self) -> dict[str, float]:
        """The design's performance figures (the ``performance`` block of the design JSON).

        Returns
        -------
        dict
            Linearity errors (fraction: nominal, n = 1, n = 1.4, objective) with the objective's
            exponents, mean stiffness (N/mm, nominal and n = 1.4), stiffness per MPa of charge,
            ``max_force_N``, ``mass_g``, ``peak_pressure_MPa``, ``p1_MPa``, ``housing_length_mm``,
            ``total_gas_mm3`` and ``layout``.
        """
        return {
            "linearity_error": self.linearity_error,
            "linearity_error_isothermal": self.linearity_isothermal,
            "linearity_error_adiabatic": self.linearity_adiabatic,
            "objective": self.objective,
            "objective_exponents": list(self.objective_exponents),
            "mean_stiffness_N_per_mm": self.mean_stiffness_N_per_mm,
            "mean_stiffness_adiabatic_N_per_mm": self.mean_stiffness_adiabatic_N_per_mm,
            "stiffness_per_charge_N_per_mm_per_MPa": self.mean_stiffness_N_per_mm / self.design.p2_MPa,
            "max_force_N": self.max_force_N,
            "mass_g": self.mass_g,
            "peak_pressure_MPa": self.peak_pressure_MPa,
            "p1_MPa": self.design.p1_MPa,
            "housing_length_mm": self.design.housing_length_mm,
            "total_gas_mm3": self.design.V1_mm3 + self.design.V2_mm3,
            "layout": self.design.layout,
        }

    def to_dict(self) -> dict:
        """JSON-ready content.

        Returns
        -------
        dict
            ``performance`` (:meth:`performance`), ``constraints`` (name -> scaled margin,
            dimensionless, > 0 met) and ``constraint_details`` (name -> value, limit, unit, kind).
        """
        return {"performance": self.performance(), "constraints": dict(self.margins),
                "constraint_details": {k: dict(v) for k, v in self.details.items()}}


def design_from_vector(v, req: Requirements, layout: str = "inner_tube") -> Design:
    """A design of ``layout`` from its decision vector, charged to the highest allowed pressure.

    Parameters
    ----------
    v : array_like
        Values of :meth:`Requirements.decision_variables` of the layout in their order and units
        (mm, mm³; ``bladder_cast_fill`` a fraction, clipped to [0, 1]).
    req : Requirements
        Gives the charge p2 (``max_charge_MPa``), the set point (mm) and the fixed parameters.
    layout : str
        Layout variant, a name of :data:`vvea_design.spring.design.LAYOUTS` (``"inner_tube"``,
        ``"bulkhead"`` or ``"annulus_top"``).

    Returns
    -------
    Design
        The design, charged to p2 = ``req.max_charge_MPa`` with p1 from the set point.

    Raises
    ------
    DesignError
        If the layout is unknown or the geometry cannot be drawn.
    """
    kw = {name: float(val) for name, val in zip(req.decision_variables(layout), v)}
    fixed = req.fixed
    if "bladder_cast_fill" in kw:
        fixed = replace(fixed, bladder_cast_fill=min(max(kw.pop("bladder_cast_fill"), 0.0), 1.0))
    return Design(**kw, p2_MPa=req.max_charge_MPa, setpoint_x0_mm=req.setpoint_x0_mm, fixed=fixed, layout=layout)


def _exponents(req: Requirements, report: bool = True) -> list[float]:
    extra = REPORTED_N.values() if report else ()
    cap = (REPORTED_N["adiabatic"],) if req.max_linearity_adiabatic is not None else ()
    return sorted({float(req.n_polytropic), *extra, *cap, *req.objective_exponents})


def _performance(g: dict, req: Requirements, p2, report: bool = True) -> dict[str, np.ndarray]:
    """Linearity (exact metric) at every exponent needed, stiffness, force; arrays like ``g``."""
    T = req.fixed.travel_mm
    out: dict[str, np.ndarray] = {}
    for n in _exponents(req, report):
        r = linearity_exact(g["A1_mm2"], g["A2_mm2"], g["V1_mm3"], g["V2_mm3"], g["p1_MPa"], p2, T, n)
        out[f"lin_{n:g}"] = r.linearity_error
        out[f"k_{n:g}"] = r.mean_stiffness_N_per_mm
        if n in req.objective_exponents or (n == REPORTED_N["adiabatic"] and req.max_linearity_adiabatic is not None):
            with np.errstate(divide="ignore", invalid="ignore"):
                out[f"ext_{n:g}"] = r.signed_extremes_N / r.force_span_N[..., None]
        if n == req.n_polytropic:
            A1, A2, V1, V2, p1 = g["A1_mm2"], g["A2_mm2"], g["V1_mm3"], g["V2_mm3"], g["p1_MPa"]
            with np.errstate(divide="ignore", invalid="ignore"):
                F0 = A2 * p2 - A1 * p1
                FT = A2 * p2 * (V2 / (V2 - A2 * T)) ** n - A1 * p1 * (V1 / (V1 + A1 * T)) ** n
            out["max_force_N"] = np.maximum(np.abs(F0), np.abs(FT))
    with np.errstate(invalid="ignore"):
        out["objective"] = np.max([out[f"lin_{n:g}"] for n in req.objective_exponents], axis=0)
    return out


def _details(g: dict, perf: dict, req: Requirements, design_values: dict, layout: str,
             strain=None, search: bool = False) -> dict[str, dict]:
    """Every constraint's value, limit, unit and kind (values are arrays or floats like ``g``); with ``search``
    not the wall safety factors (not searched: the sized walls meet them whenever ``wall_capacity`` does)."""
    p1, p2 = g["p1_MPa"], design_values["p2_MPa"]
    with np.errstate(divide="ignore", invalid="ignore"):
        scale_to_max = req.max_charge_MPa / np.maximum(p2, p1)
        k = perf[f"k_{req.n_polytropic:g}"] * scale_to_max
        gas_left = (g["V2_mm3"] - g["displaced_volume_mm3"]) / g["V2_mm3"]
    t_bl = req.fixed.bladder_thickness_mm
    d: dict[str, dict] = {
        "outer_diameter": {"value": design_values["outer_diameter_mm"], "limit": req.max_outer_diameter_mm, "unit": "mm", "kind": "max"},
        "housing_length": {"value": g["housing_length_mm"], "limit": req.max_housing_length_mm, "unit": "mm", "kind": "max"},
        "charge_p1": {"value": p1, "limit": req.max_charge_MPa, "unit": "MPa", "kind": "max"},
        "charge_p2": {"value": p2, "limit": req.max_charge_MPa, "unit": "MPa", "kind": "max"},
        "mean_stiffness": {"value": k, "limit": req.min_mean_stiffness_N_per_mm, "unit": "N/mm", "kind": "min"},
        "gas_left_at_full_stroke": {"value": gas_left, "limit": req.min_gas_fraction_at_full_stroke, "unit": "-", "kind": "min"},
        "bladder_room_compressed": {"value": g["bladder_clearance_compressed_mm"], "limit": 0.0, "unit": "mm", "kind": "min", "scale": t_bl},
        "bladder_room_expanded": {"value": g["bladder_clearance_expanded_mm"], "limit": 0.0, "unit": "mm", "kind": "min", "scale": t_bl},
        "bladder_channel_room": {"value": g["bladder_cast_gap_mm"], "limit": CHANNEL_GAP_MM, "unit": "mm", "kind": "min",
                                 "scale": t_bl},
        "wall_capacity": {"value": g["wall_capacity_value_MPa"], "limit": g["wall_capacity_limit_MPa"], "unit": "MPa", "kind": "max"},
    }
    if get_layout(layout).has_top_annulus:
        d["cross_slot_room"] = {"value": g["cross_slot_room_mm"], "limit": 0.0, "unit": "mm", "kind": "min", "scale": 1.0}
    for wall in () if search else _walls(layout, req.fixed):
        d[f"wall_safety_{wall}"] = {"value": g[f"safety_{wall}"], "limit": req.min_wall_safety_factor, "unit": "-", "kind": "min"}
    if req.max_mass_g is not None:
        d["mass"] = {"value": g["mass_g"], "limit": req.max_mass_g, "unit": "g", "kind": "max"}
    if req.max_linearity_adiabatic is not None:
        d["linearity_adiabatic"] = {"value": perf[f"lin_{REPORTED_N['adiabatic']:g}"],
                                    "limit": req.max_linearity_adiabatic, "unit": "-", "kind": "max"}
    if req.max_bladder_strain is not None:
        if strain is None:
            raise ValueError("req.max_bladder_strain is set: pass the design's bladder_strain to evaluate_design")
        d["bladder_strain"] = {"value": strain, "limit": req.max_bladder_strain, "unit": "-", "kind": "max"}
    return d


def _walls(layout: str, fixed=None) -> tuple[str, ...]:
    """The pressure walls of a layout, plus the piston pocket's floor when ``fixed.piston_pocket``."""
    return get_layout(layout).walls + (("piston_floor",) if fixed is not None and fixed.piston_pocket else ())


def evaluate_design(design: Design, req: Requirements, bladder_strain: float | None = None) -> Evaluation:
    """Performance and margins of ``design`` against ``req``.

    The design is evaluated as charged (``design.p2_MPa``); the stiffness
    requirement is checked at the highest allowed charge, where p2 is
    ``req.max_charge_MPa`` unless p1 would exceed it (then p1 is the
    limiting chamber). Linearity is the exact (continuous) metric, at the
    nominal exponent and at n = 1 and n = 1.4.

    Parameters
    ----------
    design : Design
        The design as charged (geometry in mm, mm³; p1, p2 in MPa).
    req : Requirements
        The limits to check against.
    bladder_strain : float or None
        The design's bladder strain bound (fraction), required when ``req.max_bladder_strain``
        is set.

    Returns
    -------
    Evaluation
        Linearity (fraction), stiffness (N/mm), force (N), peak pressure (MPa), mass (g) and every
        constraint's margin (scaled, dimensionless, > 0 met) with its value, limit and unit.

    Raises
    ------
    ValueError
        If ``req.max_bladder_strain`` is set and ``bladder_strain`` is None.
    """
    g = dict(design._g)
    g["V1_mm3"], g["V2_mm3"] = design.V1_mm3, design.V2_mm3
    g["p1_MPa"] = design.p1_MPa
    perf = {k: float(v) for k, v in _performance(g, req, design.p2_MPa).items() if not k.startswith("ext_")}
    values = {"p2_MPa": design.p2_MPa, "outer_diameter_mm": design.outer_diameter_mm}
    details = _details(g, perf, req, values, design.layout, bladder_strain)
    details = {k: {kk: (float(vv) if not isinstance(vv, str) else vv) for kk, vv in v.items()} for k, v in details.items()}
    margins = {name: float(_margin(d)) for name, d in details.items()}
    n = req.n_polytropic
    return Evaluation(
        design=design,
        linearity_error=perf[f"lin_{n:g}"],
        mean_stiffness_N_per_mm=perf[f"k_{n:g}"],
        max_force_N=perf["max_force_N"],
        peak_pressure_MPa=max(design.peak_pressures_MPa().values()),
        mass_g=design.mass_g,
        margins=margins,
        details=details,
        linearity_isothermal=perf["lin_1"],
        linearity_adiabatic=perf["lin_1.4"],
        mean_stiffness_adiabatic_N_per_mm=perf["k_1.4"],
        objective=perf["objective"],
        objective_exponents=tuple(req.objective_exponents),
    )


def evaluate_population(X, req: Requirements, layout: str = "inner_tube", strain_fn=None, extremes: bool = False):
    """Objective and constraint margins of many designs at once (what the optimiser calls).

    ``X`` has shape ``(S, N)``: ``S`` decision vectors of ``layout`` (its
    ``decision_variables``), each charged to ``req.max_charge_MPa``. Returns
    ``(objective (S,), margins (M, S), buildable (S,))`` with the margins in
    the order of ``constraint_names(req, layout, search=True)`` (the
    constraints a search can violate: not the p2 charge, which is the limit,
    nor the wall safety factors, which the sized walls meet whenever
    ``wall_capacity`` does); the same formulas as
    :func:`evaluate_design` (:func:`~vvea_design.spring.design.derive`).
    ``strain_fn(g, cols) -> (S,)`` gives the bladder strain when
    ``req.max_bladder_strain`` is set (the optimiser's surrogate). With
    ``extremes`` a fourth array ``(4 E, S)`` holds the signed deviations
    over the force span (at both ends, interior max and min) for each of the
    ``E`` objective exponents: the objective is their largest magnitude, and
    they are smooth where the objective has kinks (the polish's epigraph).

    Parameters
    ----------
    X : array_like
        Decision vectors, shape ``(S, N)``, each in the order and units of
        ``req.decision_variables(layout)`` (mm, mm³; the cast fill a fraction).
    req : Requirements
        The limits; the charge is ``req.max_charge_MPa``.
    layout : str
        Layout variant, a name of :data:`vvea_design.spring.design.LAYOUTS` (``"inner_tube"``,
        ``"bulkhead"`` or ``"annulus_top"``).
    strain_fn : callable or None
        ``strain_fn(g, cols)``: bladder strain bound (fraction) of each design from the derived
        geometry ``g`` and the decision columns ``cols`` (name -> array); used only when
        ``req.max_bladder_strain`` is set (None then counts as zero strain).
    extremes : bool
        Also return the signed deviations.

    Returns
    -------
    objective : numpy.ndarray
        Shape ``(S,)``: worst linearity error over the objective exponents (fraction); 1.0 for an
        unbuildable design.
    margins : numpy.ndarray
        Shape ``(M, S)``: scaled, dimensionless margins (> 0 met); -1 for an unbuildable design.
    buildable : numpy.ndarray
        Shape ``(S,)``, bool: the geometry can be drawn and every value is finite.
    extremes : numpy.ndarray
        Only with ``extremes``: shape ``(4 E, S)``, signed deviations over the force span
        (fraction).

    Raises
    ------
    DesignError
        If ``layout`` is unknown.
    """
    X = np.atleast_2d(np.asarray(X, dtype=float))
    lay = get_layout(layout)
    cols = {name: X[:, i] for i, name in enumerate(req.decision_variables(layout))}
    S = X.shape[0]
    p2 = np.full(S, req.max_charge_MPa)
    # the walls' stresses (and the masses without a mass limit) are not searched: not derived, unless a strain
    # function that may read them is used (the surrogate declares it reads only the bladder's geometry)
    strained = strain_fn is not None and req.max_bladder_strain is not None
    lean = not strained or getattr(strain_fn, "reads_bladder_geometry_only", False)
    with np.errstate(all="ignore"):
        g = derive(cols["piston_diameter_mm"], cols["outer_diameter_mm"], cols["V1_mm3"], cols["V2_mm3"],
                   cols.get("V2_top_mm3", np.zeros(S)), p2, req.setpoint_x0_mm, req.fixed, lay.has_bulkhead,
                   cast_fill=cols.get("bladder_cast_fill"), V1_annulus_mm3=cols.get("V1_annulus_mm3", np.zeros(S)),
                   top_annulus=lay.has_top_annulus, stresses=not lean, masses=not lean or req.max_mass_g is not None)
        g["V1_mm3"], g["V2_mm3"] = cols["V1_mm3"], cols["V2_mm3"]
        perf = _performance(g, req, p2, report=False)
        strain = strain_fn(g, cols) if strained else None
        details = _details(g, perf, req, {"p2_MPa": p2, "outer_diameter_mm": cols["outer_diameter_mm"]}, layout,
                           strain if req.max_bladder_strain is None else (strain if strain is not None else np.zeros(S)),
                           search=lean)
        rows = []
        for k in constraint_names(req, layout, search=True):
            if k.startswith("linearity_adiabatic["):  # smooth pieces of max |deviation| <= limit (no kinks)
                i = int(k[len("linearity_adiabatic["):-1])
                e = perf[f"ext_{REPORTED_N['adiabatic']:g}"][:, i % 4]
                lim = req.max_linearity_adiabatic
                rows.append((lim - e) / lim if i < 4 else (lim + e) / lim)
            else:
                m = _margin(details[k])
                rows.append(m if np.shape(m) == (S,) else np.broadcast_to(m, (S,)))
        margins = np.array(rows, dtype=float)
    ok = g["buildable"] & np.all(np.isfinite(margins), axis=0) & np.isfinite(perf["objective"])
    obj = np.where(ok, perf["objective"], 1.0)
    margins = np.where(ok[None, :], margins, -1.0)
    if extremes:
        ext = np.concatenate([perf[f"ext_{n:g}"].T for n in req.objective_exponents], axis=0)
        ext = np.where(ok[None, :], ext, 1.0)
        return obj, margins, ok, ext
    return obj, margins, ok


def constraint_names(req: Requirements, layout: str = "inner_tube", search: bool = False) -> list[str]:
    """Names of the constraints :func:`evaluate_design` reports for ``req`` and ``layout``, in its order.

    Parameters
    ----------
    req : Requirements
        Optional limits (mass, adiabatic linearity, bladder strain) add their constraints.
    layout : str
        Layout variant, a name of :data:`vvea_design.spring.design.LAYOUTS` (``"inner_tube"``,
        ``"bulkhead"`` or ``"annulus_top"``).
    search : bool
        Only the constraints :func:`evaluate_population` returns (no p2 charge, no wall safety
        factors; the adiabatic linearity as its 8 smooth pieces).

    Returns
    -------
    list of str
        Constraint names in order.

    Raises
    ------
    DesignError
        If ``layout`` is unknown (only when ``search`` is false).
    """
    names = ["outer_diameter", "housing_length", "charge_p1", "charge_p2", "mean_stiffness",
             "gas_left_at_full_stroke", "bladder_room_compressed", "bladder_room_expanded", "bladder_channel_room",
             "wall_capacity"]
    if get_layout(layout).has_top_annulus:
        names.append("cross_slot_room")
    if search:
        names.remove("charge_p2")
    else:
        names += [f"wall_safety_{w}" for w in _walls(layout, req.fixed)]
    if req.max_mass_g is not None:
        names.append("mass")
    if req.max_linearity_adiabatic is not None:
        names += [f"linearity_adiabatic[{i}]" for i in range(8)] if search else ["linearity_adiabatic"]
    if req.max_bladder_strain is not None:
        names.append("bladder_strain")
    return names


def _margin(d: dict):
    v, lim = d["value"], d["limit"]
    scale = d.get("scale")
    if scale is None:
        if isinstance(lim, (float, int)):  # a scalar limit (float64 arithmetic either way: the same values)
            scale = float(abs(lim)) if lim != 0 else 1.0
        else:
            scale = np.where(np.asarray(lim) != 0, np.abs(lim), 1.0)
    if d["kind"] == "max":
        return (lim - v) / scale
    return (v - lim) / scale


def constraint_margins(design: Design, req: Requirements) -> dict[str, float]:
    """Just the margins (positive = satisfied) of ``design`` against ``req``.

    Parameters
    ----------
    design : Design
        The design as charged.
    req : Requirements
        The limits (without ``max_bladder_strain``: this passes no strain).

    Returns
    -------
    dict of str to float
        Constraint name -> scaled margin, dimensionless (> 0 met).

    Raises
    ------
    ValueError
        If ``req.max_bladder_strain`` is set (use :func:`evaluate_design` with the strain).
    """
    return evaluate_design(design, req).margins
