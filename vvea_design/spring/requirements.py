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

from .design import DECISION_VARIABLES, Design, DesignError, FixedParameters
from .gas_spring import linearity_error, mean_stiffness_N_per_mm
from ..materials.silicones import get_silicone
from ..messages import show

__all__ = [
    "Requirements",
    "SpecError",
    "load_requirements",
    "Evaluation",
    "evaluate_design",
    "constraint_margins",
    "constraint_names",
]

#: Default search range of each decision variable.
DEFAULT_BOUNDS: dict[str, tuple[float, float]] = {
    "piston_diameter_mm": (12.0, 50.0),
    "outer_diameter_mm": (25.0, 59.5),
    "V1_mm3": (5.0e3, 3.0e5),
    "V2_mm3": (5.0e3, 3.0e5),
}


#: Requirements that may be absent (``None``: no limit).
_OPTIONAL = ("max_mass_g", "max_bladder_strain")
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
    n_polytropic: float = 1.0  #: 1 isothermal ... 1.4 adiabatic
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
        if self.max_bladder_strain is not None and not (0 < self.max_bladder_strain < 10):
            raise SpecError(f"max_bladder_strain must be a fraction in (0, 10), got {show(self.max_bladder_strain)}")
        if not (abs(self.setpoint_x0_mm) < self.travel_mm):
            raise SpecError(f"setpoint_x0_mm ({show(self.setpoint_x0_mm)}) must lie inside the travel "
                            f"(|x0| < {show(self.travel_mm)})")
        unknown = set(self.bounds) - set(DECISION_VARIABLES)
        if unknown:
            raise SpecError(f"[bounds] has unknown variable(s) {sorted(unknown)}; known: {list(DECISION_VARIABLES)}")
        for name, (lo, hi) in self.bounds.items():
            if not (math.isfinite(lo) and math.isfinite(hi)) or lo <= 0 or hi <= lo:
                raise SpecError(f"[bounds] {name} = {show([lo, hi])} must satisfy 0 < low < high")
        lo_D = self.bounds.get("outer_diameter_mm", DEFAULT_BOUNDS["outer_diameter_mm"])[0]
        if lo_D >= self.max_outer_diameter_mm:
            raise SpecError(
                f"contradictory envelope: max_outer_diameter_mm ({show(self.max_outer_diameter_mm)}) is not above the "
                f"lower search bound of outer_diameter_mm ({show(lo_D)})"
            )
        if self.fixed.travel_mm != self.travel_mm or self.fixed.n_polytropic != self.n_polytropic:
            object.__setattr__(self, "fixed", replace(self.fixed, travel_mm=self.travel_mm, n_polytropic=self.n_polytropic))
        min_len = self.fixed.top_cap_mm + self.fixed.base_mm + self.fixed.piston_height_mm + self.travel_mm + self.fixed.fluid_clearance_mm
        if self.max_housing_length_mm <= min_len:
            raise SpecError(
                f"max_housing_length_mm ({show(self.max_housing_length_mm)}) leaves no room for chamber 1: end caps + piston "
                f"+ travel + fluid clearance already take {min_len:.1f} mm"
            )

    def search_bounds(self) -> list[tuple[float, float]]:
        """Bounds per decision variable, clipped to the envelope."""
        out = []
        for name in DECISION_VARIABLES:
            lo, hi = self.bounds.get(name, DEFAULT_BOUNDS[name])
            if name == "outer_diameter_mm":
                hi = min(hi, self.max_outer_diameter_mm)
            out.append((float(lo), float(hi)))
        return out

    def to_dict(self) -> dict[str, Any]:
        d = asdict(self)
        d["bounds"] = {k: list(v) for k, v in self.bounds.items()}
        return d

    @classmethod
    def from_dict(cls, data: dict[str, Any], source: str = "requirements") -> "Requirements":
        """Build from a parsed TOML/JSON mapping; every error names ``source`` and the key."""
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
            elif key in ("bladder_material",):
                if not isinstance(value, str):
                    raise SpecError(f"{source}: {key} must be a string, got {show(value)}")
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
    """Read a requirements TOML file (``None`` = the built-in defaults)."""
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

#: Displacement samples used for linearity and stiffness everywhere.
N_SAMPLES = 401


@dataclass(frozen=True)
class Evaluation:
    """A design's performance and its constraint margins (positive = satisfied)."""

    design: Design
    linearity_error: float  #: fraction (see gas_spring.linearity_error)
    mean_stiffness_N_per_mm: float
    max_force_N: float
    peak_pressure_MPa: float
    mass_g: float
    margins: dict[str, float]  #: dimensionless, positive = satisfied
    details: dict[str, dict[str, float | str]]  #: value, limit and unit of each constraint

    @property
    def feasible(self) -> bool:
        return all(m >= -1e-9 for m in self.margins.values())

    def binding(self, tol: float = 1e-3) -> list[str]:
        """Constraints at (or beyond) their limit."""
        return [k for k, m in self.margins.items() if m < tol]

    def performance(self) -> dict[str, float]:
        return {
            "linearity_error": self.linearity_error,
            "mean_stiffness_N_per_mm": self.mean_stiffness_N_per_mm,
            "stiffness_per_charge_N_per_mm_per_MPa": self.mean_stiffness_N_per_mm / self.design.p2_MPa,
            "max_force_N": self.max_force_N,
            "mass_g": self.mass_g,
            "peak_pressure_MPa": self.peak_pressure_MPa,
            "p1_MPa": self.design.p1_MPa,
            "housing_length_mm": self.design.housing_length_mm,
        }


def design_from_vector(v, req: Requirements) -> Design:
    """A design from the decision vector, charged to the highest allowed pressure."""
    kw = {name: float(val) for name, val in zip(DECISION_VARIABLES, v)}
    return Design(**kw, p2_MPa=req.max_charge_MPa, setpoint_x0_mm=req.setpoint_x0_mm, fixed=req.fixed)


def evaluate_design(design: Design, req: Requirements, bladder_strain: float | None = None) -> Evaluation:
    """Performance and margins of ``design`` against ``req``.

    The design is evaluated as charged (``design.p2_MPa``); the stiffness
    requirement is checked at the highest allowed charge, where p2 is
    ``req.max_charge_MPa`` unless p1 would exceed it (then p1 is the
    limiting chamber).
    """
    gs = design.gas_spring
    x = gs.x_mm(N_SAMPLES)
    F = gs.force_N(x)
    lin = float(linearity_error(x, F))
    # stiffness at the highest charge both chambers allow (force scales with pressure)
    scale_to_max = req.max_charge_MPa / max(design.p2_MPa, design.p1_MPa)
    k = float(mean_stiffness_N_per_mm(x, F)) * scale_to_max
    peaks = design.peak_pressures_MPa()
    sf = design.wall_safety_factors()
    clear = design.bladder_clearance_mm()
    gas_left = (design.V2_mm3 - design.displaced_volume_mm3) / design.V2_mm3
    t_bl = design.fixed.bladder_thickness_mm
    details: dict[str, dict[str, float | str]] = {
        "outer_diameter": {"value": design.outer_diameter_mm, "limit": req.max_outer_diameter_mm, "unit": "mm", "kind": "max"},
        "housing_length": {"value": design.housing_length_mm, "limit": req.max_housing_length_mm, "unit": "mm", "kind": "max"},
        "charge_p1": {"value": design.p1_MPa, "limit": req.max_charge_MPa, "unit": "MPa", "kind": "max"},
        "charge_p2": {"value": design.p2_MPa, "limit": req.max_charge_MPa, "unit": "MPa", "kind": "max"},
        "mean_stiffness": {"value": k, "limit": req.min_mean_stiffness_N_per_mm, "unit": "N/mm", "kind": "min"},
        "gas_left_at_full_stroke": {"value": gas_left, "limit": req.min_gas_fraction_at_full_stroke, "unit": "-", "kind": "min"},
        "bladder_room_compressed": {"value": clear["compressed"], "limit": 0.0, "unit": "mm", "kind": "min", "scale": t_bl},
        "bladder_room_expanded": {"value": clear["expanded"], "limit": 0.0, "unit": "mm", "kind": "min", "scale": t_bl},
    }
    for wall in WALLS:
        s = sf[wall]
        details[f"wall_safety_{wall}"] = {"value": s, "limit": req.min_wall_safety_factor, "unit": "-", "kind": "min"}
    if req.max_mass_g is not None:
        details["mass"] = {"value": design.mass_g, "limit": req.max_mass_g, "unit": "g", "kind": "max"}
    if req.max_bladder_strain is not None:
        if bladder_strain is None:
            raise ValueError("req.max_bladder_strain is set: pass the design's bladder_strain to evaluate_design")
        details["bladder_strain"] = {"value": bladder_strain, "limit": req.max_bladder_strain, "unit": "-", "kind": "max"}
    margins = {name: _margin(d) for name, d in details.items()}
    return Evaluation(
        design=design,
        linearity_error=lin,
        mean_stiffness_N_per_mm=float(mean_stiffness_N_per_mm(x, F)),
        max_force_N=float(np.abs(F).max()),
        peak_pressure_MPa=max(peaks.values()),
        mass_g=design.mass_g,
        margins=margins,
        details=details,
    )


WALLS = ("outer_tube", "inner_tube", "top_cap", "base")


def constraint_names(req: Requirements) -> list[str]:
    """Names of the constraints :func:`evaluate_design` reports for ``req``, in its order."""
    names = ["outer_diameter", "housing_length", "charge_p1", "charge_p2", "mean_stiffness",
             "gas_left_at_full_stroke", "bladder_room_compressed", "bladder_room_expanded"]
    names += [f"wall_safety_{w}" for w in WALLS]
    if req.max_mass_g is not None:
        names.append("mass")
    if req.max_bladder_strain is not None:
        names.append("bladder_strain")
    return names


def _margin(d: dict) -> float:
    v, lim = float(d["value"]), float(d["limit"])
    scale = float(d.get("scale", abs(lim) if lim != 0 else 1.0))
    if d["kind"] == "max":
        return (lim - v) / scale
    return (v - lim) / scale


def constraint_margins(design: Design, req: Requirements) -> dict[str, float]:
    """Just the margins (positive = satisfied) of ``design`` against ``req``."""
    return evaluate_design(design, req).margins
