"""The design JSON: the file a designer keeps and feeds to every later step.

Layout (``format_version`` 1)::

    {
      "format": "vvea-design",
      "format_version": 1,
      "parameters": {piston_diameter_mm, outer_diameter_mm, V1_mm3, V2_mm3,
                     A1_mm2, A2_mm2, p1_MPa, p2_MPa, travel_mm, n_polytropic,
                     setpoint_x0_mm, layout, V2_top_mm3, V1_annulus_mm3},
      (layout: a key of spring.layouts.LAYOUTS; V2_top_mm3: chamber-2 gas above
       the bulkhead, 0 outside the bulkhead layout; V1_annulus_mm3: chamber-1
       gas in the annulus above the collar, 0 outside the annulus_top layout,
       optional in files written before that layout existed)
      "fixed":       {every FixedParameters field},
      "geometry":    {derived lengths/radii/volumes, for reading},
      "performance": {linearity_error, linearity_error_isothermal (n = 1),
                      linearity_error_adiabatic (n = 1.4), objective,
                      mean_stiffness_N_per_mm, max_force_N, mass_g,
                      peak_pressure_MPa, walls_mm, ...},
      "constraints": {name: margin (positive = satisfied)},
      "constraint_details": {name: {value, limit, unit, kind}},
      "spec":        {the requirements used},
      "optimiser":   {seed, evaluations, seconds, ...}       (optional)
      "structure":   {sizing_rules, joint, load_cases, pieces, tolerances},
      "joints":      [the joint records: thread / ring / tie rods, the seats],
      "hydraulics":  {oil, restrictions, D_min_N_s_per_mm, D_max_N_s_per_mm, ...}
    }

(``parameters.joint``: the joint choice, ``thread`` when absent; ``structure``, ``joints`` and ``hydraulics``
are derived from the decision variables and ``fixed`` on load, like ``geometry``: written for reading.)

The force curve is reproducible from ``parameters`` alone with paper eq. 5.
Every reader (:func:`load_design`, :func:`spring_from_json`, and so every
command) rebuilds the frozen :class:`~vvea_design.spring.design.Design` from
its decision variables and ``fixed`` and rejects the file where a stored
derived value of ``parameters`` (the areas and p1 of eq. 5) disagrees with
it. The numbers of ``geometry`` and ``performance`` are for reading: where
they disagree with the rebuilt design (an edited wall, a volume changed by
hand) they are ignored with a :class:`StaleDerivedValues` warning naming
them (the commands print it as a note), so an edited file never silently
disagrees with itself: edit the decision variables, never the derived
values. Numbers a real unit cannot have (a
1e9 MPa charge, a 1e-300 mm travel) are refused by the design itself
(:mod:`vvea_design.plausibility`). The file is read through
:mod:`vvea_design.inputs` (a folder, a device, a FIFO, a file over 16 MiB,
UTF-16 text or JSON nested absurdly deep are errors naming the file).

A design file is self-contained: :func:`load_design` takes nothing from a
default. ``parameters`` (with ``setpoint_x0_mm``) and every field of
``fixed`` are required, ``fixed.travel_mm`` / ``fixed.n_polytropic`` must
equal ``parameters.travel_mm`` / ``parameters.n_polytropic``, and an unknown
key at the top level or in ``parameters`` is an error naming it (the known
keys are :data:`TOP_LEVEL_KEYS` and :data:`DESIGN_PARAMETER_KEYS`). ``spec``
is required by :func:`load_requirements_from_design`.
"""

from __future__ import annotations

import json
import math
import warnings
from dataclasses import fields as dataclass_fields
from pathlib import Path
from typing import Any

from .design import Design, DesignError, FixedParameters
from .gas_spring import GasSpring
from .layouts import DECISION_VARIABLES, LAYOUTS
from .problem import Evaluation, evaluate_design
from .requirements import Requirements, SpecError
from ..inputs import decode_text, parse_json, read_input_bytes
from ..messages import show
from ..plausibility import check_field

__all__ = ["FORMAT", "FORMAT_VERSION", "DesignFileError", "design_to_dict", "save_design", "load_design",
           "load_design_dict", "spring_from_json", "read_design_json", "load_requirements_from_design", "reevaluate",
           "CHECKED_PERFORMANCE", "LegacyDesignFile", "StaleDerivedValues", "stale_derived_values"]

FORMAT = "vvea-design"
FORMAT_VERSION = 1

PARAMETER_KEYS = ("piston_diameter_mm", "outer_diameter_mm", "V1_mm3", "V2_mm3", "A1_mm2", "A2_mm2",
                  "p1_MPa", "p2_MPa", "travel_mm", "n_polytropic")
#: Parameters that shape the geometry beyond eq. 5: required by :func:`load_design_dict`.
DESIGN_PARAMETER_KEYS = PARAMETER_KEYS + ("setpoint_x0_mm", "layout", "V2_top_mm3")
#: Parameters and fixed fields added after format_version 1 was first written: optional (their defaults are
#: the layouts that do not use them), so older files still load.
OPTIONAL_PARAMETER_KEYS = ("V1_annulus_mm3", "joint")
#: Fixed fields added with the buildability rules: a file without ``sizing_rules`` predates them and loads under
#: ``sizing_rules = "gas_only"`` (the rules it was made with, so its design is unchanged), with a notice.
BUILDABILITY_FIXED_KEYS = ("sizing_rules", "relief_force_N", "max_motor_torque_Nm", "pulley_radius_mm",
                           "proof_pressure_factor", "proof_safety_factor", "bore_tolerance_grade",
                           "outside_tolerance_grade", "thickness_tolerance_class", "tie_rod_property_class",
                           "joint_seal_cross_section_mm", "seal_land_mm", "throttle_bore_mm", "relief_bore_mm",
                           "relief_seat_mm", "fluid_channel_mm", "ring_channel_mm", "ring_channels", "oil",
                           "oil_temperature_C")
OPTIONAL_FIXED_KEYS = ("min_collar_mm", "cross_slot_mm", "cross_slot_fraction", "piston_pocket", "piston_pocket_wall_mm",
                       "min_piston_floor_mm") + BUILDABILITY_FIXED_KEYS
#: Every top-level key a design JSON may hold; anything else is an error (a typo or a foreign file).
TOP_LEVEL_KEYS = ("format", "format_version", "parameters", "fixed", "geometry", "performance", "constraints",
                  "constraint_details", "spec", "optimiser", "structure", "joints", "hydraulics")


class DesignFileError(ValueError):
    """A design JSON that is malformed, foreign or inconsistent (names file and key)."""


def _clean(v: Any) -> Any:
    """Plain-JSON values (numpy scalars to Python; non-finite floats to null)."""
    if isinstance(v, dict):
        return {str(k): _clean(x) for k, x in v.items()}
    if isinstance(v, (list, tuple)):
        return [_clean(x) for x in v]
    if hasattr(v, "item") and not isinstance(v, (str, bytes)):
        v = v.item()
    if isinstance(v, float):
        return v if math.isfinite(v) else None
    return v


def design_to_dict(evaluation: Evaluation, req: Requirements, optimiser: dict | None = None) -> dict:
    """The design JSON content of an evaluated design (the layout in this module's docstring).

    Parameters
    ----------
    evaluation : Evaluation
        The evaluated design (:func:`~vvea_design.spring.problem.evaluate_design`): its design,
        performance and constraint margins.
    req : Requirements
        The requirements it was evaluated against (stored as ``spec``; the minimum walls use its
        safety factor).
    optimiser : dict or None
        The optimiser's summary (:meth:`OptimisationResult.summary`), stored as ``optimiser``;
        None or empty: no such block.

    Returns
    -------
    dict
        Plain JSON data (numpy scalars as Python numbers, non-finite floats as None); units in the
        keys (mm, mm², mm³, MPa, N, g).
    """
    d = evaluation.design
    gs = d.gas_spring
    out = {
        "format": FORMAT,
        "format_version": FORMAT_VERSION,
        "parameters": {
            "piston_diameter_mm": d.piston_diameter_mm,
            "outer_diameter_mm": d.outer_diameter_mm,
            "V1_mm3": d.V1_mm3,
            "V2_mm3": d.V2_mm3,
            "A1_mm2": gs.A1_mm2,
            "A2_mm2": gs.A2_mm2,
            "p1_MPa": gs.p1_MPa,
            "p2_MPa": gs.p2_MPa,
            "travel_mm": gs.travel_mm,
            "n_polytropic": gs.n_polytropic,
            "setpoint_x0_mm": d.setpoint_x0_mm,
            "layout": d.layout,
            "V2_top_mm3": d.V2_top_mm3,
            "V1_annulus_mm3": d.V1_annulus_mm3,
            "joint": d.joint,
        },
        "fixed": d.fixed.to_dict(),
        "geometry": d.geometry_summary(),
        "performance": {
            **evaluation.performance(),
            "wall_safety_factors": d.wall_safety_factors(),
            "walls_mm": d.walls_mm(),
            "minimum_walls_mm": d.minimum_walls_mm(req.min_wall_safety_factor),
            "mass_breakdown_g": d.mass_breakdown_g(),
        },
        "constraints": evaluation.margins,
        "constraint_details": evaluation.details,
        "spec": req.to_dict(),
        **d.buildability.to_dict(),
    }
    if optimiser:
        out["optimiser"] = optimiser
    return _clean(out)


def save_design(path: str | Path, evaluation: Evaluation, req: Requirements, optimiser: dict | None = None) -> Path:
    """Write the design JSON (sorted keys, 2-space indent, trailing newline: byte-stable).

    Parameters
    ----------
    path : str or Path
        File to write (parent folders created, an existing file replaced).
    evaluation : Evaluation
        The evaluated design (:func:`~vvea_design.spring.problem.evaluate_design`): its design,
        performance and constraint margins.
    req : Requirements
        The requirements it was evaluated against (stored as ``spec``; the minimum walls use its
        safety factor).
    optimiser : dict or None
        The optimiser's summary (:meth:`OptimisationResult.summary`), stored as ``optimiser``;
        None or empty: no such block.

    Returns
    -------
    Path
        ``path``.
    """
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text(json.dumps(design_to_dict(evaluation, req, optimiser), indent=2, sort_keys=True) + "\n",
                    encoding="utf-8")
    return path


def read_design_json(path: str | Path) -> dict:
    """Parse and validate the envelope of a design JSON (format, version, parameters).

    Parameters
    ----------
    path : str or Path
        The design JSON file.

    Returns
    -------
    dict
        The parsed file; its ``parameters`` of eq. 5 are finite numbers (mm, mm², mm³, MPa).

    Raises
    ------
    DesignFileError
        If the file does not exist, is not a regular file (a folder, a device, a FIFO), is larger than
        16 MiB, is not UTF-8 (UTF-16 is named), is not valid JSON or nested absurdly deep, is not a vvea
        design file, has an unsupported ``format_version``, an unknown top-level or parameter key, or a
        parameter of eq. 5 that is missing or not a finite number (each message names the file and key).
    """
    path = Path(path)
    raw = read_input_bytes(path, "design file", DesignFileError)
    data = parse_json(decode_text(raw, path, "design file", DesignFileError, "JSON"), path, "design file",
                      DesignFileError)
    _check_envelope(data, str(path))
    return data


def _check_envelope(data: Any, src: str) -> None:
    if not isinstance(data, dict):
        raise DesignFileError(f"{src}: expected a JSON object, got {type(data).__name__}")
    if data.get("format") != FORMAT:
        raise DesignFileError(f"{src}: not a vvea design file (key 'format' is {data.get('format')!r}, expected {FORMAT!r})")
    ver = data.get("format_version")
    if ver != FORMAT_VERSION:
        raise DesignFileError(f"{src}: unsupported format_version {ver!r} (this version reads {FORMAT_VERSION})")
    unknown = sorted(set(data) - set(TOP_LEVEL_KEYS))
    if unknown:
        raise DesignFileError(f"{src}: unknown top-level key(s) {unknown}; a design file holds only "
                              f"{', '.join(TOP_LEVEL_KEYS)}")
    params = data.get("parameters")
    if not isinstance(params, dict):
        raise DesignFileError(f"{src}: missing object 'parameters'")
    unknown = sorted(set(params) - set(DESIGN_PARAMETER_KEYS) - set(OPTIONAL_PARAMETER_KEYS))
    if unknown:
        raise DesignFileError(f"{src}: unknown key(s) {unknown} in 'parameters'; known: {', '.join(DESIGN_PARAMETER_KEYS)}")
    for key in PARAMETER_KEYS:
        if key not in params:
            raise DesignFileError(f"{src}: parameters.{key} is missing")
        v = params[key]
        if isinstance(v, bool) or not isinstance(v, (int, float)) or not math.isfinite(v):
            raise DesignFileError(f"{src}: parameters.{key} must be a finite number, got {v!r}")
    for key in ("piston_diameter_mm", "outer_diameter_mm", "V1_mm3", "V2_mm3", "p2_MPa", "travel_mm",
                "V2_top_mm3", "V1_annulus_mm3"):  # a value in another unit names it (plausibility.FIELD_LIMITS)
        v = params.get(key)
        if isinstance(v, (int, float)) and not isinstance(v, bool) and v > 0:  # <= 0: the design names it
            check_field(key, params[key], f"{src}: parameters.{key}", DesignFileError)


def spring_from_json(path_or_data: str | Path | dict) -> GasSpring:
    """The gas spring of a design JSON (paper eq. 5): what `vvea check` and `vvea spring` evaluate.

    The design is rebuilt from its decision variables and checked like :func:`load_design_dict` does
    (a stored area, p1, geometry or performance figure that disagrees is an error), so the spring is
    the file's design, never a stale copy of it.

    Parameters
    ----------
    path_or_data : str or Path or dict
        A design JSON file, or its parsed content.

    Returns
    -------
    GasSpring
        Areas (mm²), volumes (mm³), charges (MPa), travel (mm) and polytropic exponent of the design.

    Raises
    ------
    DesignFileError
        As :func:`read_design_json` and :func:`load_design_dict` (each message names the file and key).
    """
    if isinstance(path_or_data, dict):
        return load_design_dict(path_or_data).gas_spring
    return load_design(path_or_data).gas_spring


def _check_geometry_complete(data: dict, src: str) -> None:
    """Every parameter that shapes the geometry is in the file: nothing is silently taken from a default.

    ``parameters.setpoint_x0_mm`` and the whole ``fixed`` object (every
    :class:`~vvea_design.spring.design.FixedParameters` field) are required;
    ``fixed.travel_mm`` / ``fixed.n_polytropic`` must equal their copies in
    ``parameters``.
    """
    p = data["parameters"]
    v = p.get("setpoint_x0_mm")
    if "setpoint_x0_mm" not in p:
        raise DesignFileError(f"{src}: parameters.setpoint_x0_mm is missing (the zero-force displacement, "
                              "0 for the paper's unit); every parameter that shapes the design must be in the file")
    if isinstance(v, bool) or not isinstance(v, (int, float)) or not math.isfinite(v):
        raise DesignFileError(f"{src}: parameters.setpoint_x0_mm must be a finite number, got {v!r}")
    lay = p.get("layout")
    if lay not in LAYOUTS:
        raise DesignFileError(f"{src}: parameters.layout is {'missing' if lay is None else repr(lay)}; "
                              f"one of {', '.join(map(repr, LAYOUTS))} (docs/layout.md)")
    vt = p.get("V2_top_mm3")
    if isinstance(vt, bool) or not isinstance(vt, (int, float)) or not math.isfinite(vt):
        raise DesignFileError(f"{src}: parameters.V2_top_mm3 must be a finite number (0 in the inner_tube layout), "
                              f"got {vt!r}")
    va = p.get("V1_annulus_mm3", 0.0)
    if isinstance(va, bool) or not isinstance(va, (int, float)) or not math.isfinite(va):
        raise DesignFileError(f"{src}: parameters.V1_annulus_mm3 must be a finite number (0 outside the annulus_top "
                              f"layout), got {va!r}")
    fixed = data.get("fixed")
    hint = ("; a design file must hold every fixed parameter (write it with `vvea optimise`, or copy the "
            "missing ones from the defaults: " + ", ".join(f"{k} = {v!r}" for k, v in FixedParameters().to_dict().items())
            + ")")
    if fixed is None:
        raise DesignFileError(f"{src}: missing object 'fixed' (wall thicknesses, end caps, materials, ...){hint}")
    if not isinstance(fixed, dict):
        raise DesignFileError(f"{src}: 'fixed' must be an object, got {type(fixed).__name__}")
    missing = [f.name for f in dataclass_fields(FixedParameters) if f.name not in fixed and f.name not in OPTIONAL_FIXED_KEYS]
    if missing:
        raise DesignFileError(f"{src}: fixed.{', fixed.'.join(missing)} missing{hint}")
    for key in ("travel_mm", "n_polytropic"):
        a, b = fixed[key], p[key]
        if isinstance(a, (int, float)) and not isinstance(a, bool) and not math.isclose(a, b, rel_tol=1e-12, abs_tol=0):
            raise DesignFileError(f"{src}: fixed.{key} = {a:g} disagrees with parameters.{key} = {b:g}; "
                                  "they are one quantity, make them equal")


def load_design_dict(data: dict, src: str = "design") -> Design:
    """Rebuild the frozen design from a parsed design JSON, checking that it is complete and consistent.

    Parameters
    ----------
    data : dict
        Parsed design JSON.
    src : str
        Name of where ``data`` came from (a file path), put in front of every error.

    Returns
    -------
    Design
        The frozen design (geometry in mm, mm³; charge in MPa) whose derived areas and p1 agree with
        the stored ones to 1e-6 relative.

    Raises
    ------
    DesignFileError
        If the envelope is wrong (see :func:`read_design_json`), ``setpoint_x0_mm``, ``layout``,
        ``V2_top_mm3`` or a ``fixed`` field is missing or invalid, ``fixed`` disagrees with
        ``parameters`` on travel or exponent, the geometry cannot be built, or a stored area or p1
        disagrees with the geometry.
    """
    _check_envelope(data, src)
    _check_geometry_complete(data, src)
    p = data["parameters"]
    try:
        fixed_data = dict(data["fixed"])
        if "sizing_rules" not in fixed_data:  # written before the buildability rules: re-derived under its own rules
            fixed_data["sizing_rules"] = "gas_only"
            warnings.warn(f"{src}: written before the buildability rules (no fixed.sizing_rules): loaded with "
                          "sizing_rules = 'gas_only', the rules it was made with (walls for the gas peak at nominal "
                          "size, no joints, no damper loads); re-optimise it for a unit a workshop can build",
                          LegacyDesignFile, stacklevel=3)
        fixed = FixedParameters.from_dict(fixed_data)
        design = Design(
            **{k: p[k] for k in DECISION_VARIABLES},
            p2_MPa=p["p2_MPa"],
            setpoint_x0_mm=p["setpoint_x0_mm"],
            fixed=fixed,
            layout=p["layout"],
            V2_top_mm3=p["V2_top_mm3"],
            V1_annulus_mm3=p.get("V1_annulus_mm3", 0.0),
            joint=p.get("joint", "thread"),
        )
    except (DesignError, TypeError) as exc:
        raise DesignFileError(f"{src}: {exc}{_walls_hint(data, str(exc))}") from None
    for key, value in (("A1_mm2", design.A1_mm2), ("A2_mm2", design.A2_mm2), ("p1_MPa", design.p1_MPa)):
        stored = float(p[key])
        if not math.isclose(stored, value, rel_tol=1e-6, abs_tol=1e-9):
            raise DesignFileError(
                f"{src}: parameters.{key} = {stored:.6g} disagrees with the design rebuilt from its decision "
                f"variables and fixed ({value:.6g}): either {key} was edited (edit the decision variables "
                "piston_diameter_mm, outer_diameter_mm, V1_mm3, V2_mm3, p2_MPa instead) or a decision variable was "
                f"edited without it (set {key} to {value:.6g}, or re-run `vvea optimise`)"
            )
    _check_stored_derived(data, design, src)
    return design


#: Figures of ``performance`` that follow from the design alone (not from its requirements) and are
#: compared with the design rebuilt from the file: key -> how to compute it.
CHECKED_PERFORMANCE = {
    "walls_mm": lambda d: d.walls_mm(),
    "mass_g": lambda d: d.mass_g,
    "mass_breakdown_g": lambda d: d.mass_breakdown_g(),
    "wall_safety_factors": lambda d: d.wall_safety_factors(),
    "linearity_error_isothermal": lambda d: d.gas_spring.with_polytropic(1.0).linearity_error(),
    "linearity_error_adiabatic": lambda d: d.gas_spring.with_polytropic(1.4).linearity_error(),
    "housing_length_mm": lambda d: d.housing_length_mm,
}

def _disagreements(stored: Any, derived: Any, where: str) -> list[str]:
    """Every number of ``stored`` that disagrees with ``derived`` (1e-6 relative), named by its path."""
    if isinstance(stored, dict) and isinstance(derived, dict):
        return [bad for k, v in stored.items() if k in derived for bad in _disagreements(v, derived[k], f"{where}.{k}")]
    if (isinstance(stored, bool) or not isinstance(stored, (int, float)) or isinstance(derived, bool)
            or not isinstance(derived, (int, float)) or not math.isfinite(float(derived))):
        return []
    if not math.isfinite(stored) or not math.isclose(stored, derived, rel_tol=1e-6, abs_tol=1e-9):
        return [f"{where} = {stored:.6g} (rebuilt: {float(derived):.6g})"]
    return []


class LegacyDesignFile(UserWarning):
    """A design file written before the buildability rules: re-derived under the gas-only rules it was made with."""


class StaleDerivedValues(UserWarning):
    """Formerly warned for stale derived values; a design file whose ``geometry`` or ``performance`` holds numbers
    of another design is now refused (:class:`DesignFileError`). Kept so that filters naming it still import."""


def stale_derived_values(data: dict, design: Design) -> list[str]:
    """The numbers of ``geometry`` and ``performance`` that disagree with the design rebuilt from the file.

    Parameters
    ----------
    data : dict
        Parsed design JSON.
    design : Design
        The design rebuilt from its decision variables and ``fixed`` (:func:`load_design_dict`).

    Returns
    -------
    list of str
        ``"geometry.walls_mm.outer_tube = 3 (rebuilt: 1.58972)"`` per disagreeing number (mm, mm³, g,
        fractions as stored); empty when the file agrees with itself.
    """
    out: list[str] = []
    if isinstance(data.get("geometry"), dict):
        out += _disagreements(data["geometry"], design.geometry_summary(), "geometry")
    perf = data.get("performance")
    if isinstance(perf, dict):
        for key, fn in CHECKED_PERFORMANCE.items():
            if key in perf:
                out += _disagreements(perf[key], _clean(fn(design)), f"performance.{key}")
    ev = _evaluation_against_spec(data, design)
    if ev is not None:  # every other figure and every margin, re-evaluated against the file's own spec
        if isinstance(perf, dict):
            fresh = _clean(ev.performance())
            out += _disagreements({k: v for k, v in perf.items() if k not in CHECKED_PERFORMANCE},
                                  fresh, "performance")
        if isinstance(data.get("constraints"), dict):
            margins = {k: v for k, v in _clean(dict(ev.margins)).items() if "strain" not in k}
            out += _disagreements(data["constraints"], margins, "constraints")
    return out


def _evaluation_against_spec(data: dict, design: Design) -> Evaluation | None:
    """The design evaluated against the requirements stored with it (None without a valid ``spec``)."""
    spec = data.get("spec")
    if not isinstance(spec, dict):
        return None
    try:
        req = Requirements.from_dict(spec, source="spec")
        if req.fixed.sizing_rules != design.fixed.sizing_rules:  # a file older than its rules: re-derived otherwise
            return None
        return evaluate_design(design, req, bladder_strain=0.0 if req.max_bladder_strain is not None else None)
    except (SpecError, DesignError, ValueError, TypeError, KeyError):
        return None


def _decision_values(data: dict) -> str:
    """The decision variables a design is rebuilt from, with their values, those outside the range the file's own
    search used (``spec.bounds``) first: where an edited or mistyped value is to be looked for."""
    p = data.get("parameters") if isinstance(data.get("parameters"), dict) else {}
    bounds = (data.get("spec") or {}).get("bounds") if isinstance(data.get("spec"), dict) else None
    bounds = bounds if isinstance(bounds, dict) else {}
    names = ["travel_mm", *DECISION_VARIABLES, "V2_top_mm3", "V1_annulus_mm3", "p2_MPa"]
    shown, outside = [], []
    for k in dict.fromkeys(names):
        v = p.get(k)
        if isinstance(v, bool) or not isinstance(v, (int, float)) or (v == 0 and k in ("V2_top_mm3", "V1_annulus_mm3")):
            continue  # a layout's own volume it does not have (0) says nothing
        rng = bounds.get(k)
        if (isinstance(rng, (list, tuple)) and len(rng) == 2 and all(isinstance(x, (int, float)) for x in rng)
                and not rng[0] * (1 - 1e-9) <= v <= rng[1] * (1 + 1e-9)):
            outside.append(f"parameters.{k} = {v:.6g} (outside spec.bounds.{k} = {show(list(rng))}, the range "
                           "its search used)")
        else:
            shown.append(f"{k} = {v:.6g}")
    geometry = data.get("geometry") if isinstance(data.get("geometry"), dict) else {}
    layout, written = p.get("layout"), geometry.get("layout")
    if isinstance(written, str) and written != layout:
        outside.insert(0, f"parameters.layout = {show(layout)} but the file's geometry was written for layout = "
                          f"{show(written)}")
    kinds = ", ".join(f"{k} = {show(p[k])}" for k in ("layout", "joint") if isinstance(p.get(k), str))
    return "; ".join([*outside, "rebuilt from parameters " + ", ".join(filter(None, [kinds, *shown]))])


def _walls_hint(data: dict, message: str) -> str:
    """For a design that has no room left: the walls are re-sized from ``fixed`` on reading, so name what sizes them
    and the walls the file was written with (an edited material or safety factor makes them thicker)."""
    if "no room" not in message:
        return ""
    f = data.get("fixed") if isinstance(data.get("fixed"), dict) else {}
    stored = ((data.get("performance") or {}).get("walls_mm") if isinstance(data.get("performance"), dict) else None)
    sizing = ", ".join(f"fixed.{k} = {show(f[k])}" for k in ("housing_material", "wall_safety_factor", "sizing_rules")
                       if k in f)
    was = (f"; the file was written with walls {', '.join(f'{k} {v:.4g} mm' for k, v in stored.items())}"
           if isinstance(stored, dict) and all(isinstance(v, (int, float)) for v in stored.values()) else "")
    return (f" ({_decision_values(data)}; every reader re-sizes the walls from {sizing}{was}: an edited material "
            "or safety factor changes them)")


def _check_stored_derived(data: dict, design: Design, src: str) -> None:
    """Refuse a file that leaves its own envelope, or whose geometry or performance hold numbers of another design."""
    _check_own_envelope(data, design, src)
    stale = stale_derived_values(data, design)
    if stale:
        more = f" and {len(stale) - 3} more" if len(stale) > 3 else ""
        raise DesignFileError(
            f"{src}: {len(stale)} stored derived value(s) disagree with the design rebuilt from its parameters and "
            f"fixed: {'; '.join(stale[:3])}{more} ({_decision_values(data)}). A design file must agree with itself: "
            "edit the decision "
            "variables (parameters) or fixed, never a derived value; after such an edit delete the blocks "
            "geometry, performance, constraints and constraint_details (every command recomputes them) or re-run "
            "`vvea optimise`")


def _check_own_envelope(data: dict, design: Design, src: str) -> None:
    """The design lies inside the envelope of its own ``spec`` (where the file claims it does)."""
    spec = data.get("spec")
    if not isinstance(spec, dict):
        return
    margins = data.get("constraints") if isinstance(data.get("constraints"), dict) else {}
    for key, value, claim in (("max_outer_diameter_mm", design.outer_diameter_mm, "outer_diameter"),
                              ("max_housing_length_mm", design.housing_length_mm, "housing_length")):
        limit = spec.get(key)
        if isinstance(limit, bool) or not isinstance(limit, (int, float)) or not math.isfinite(limit):
            continue
        stored = margins.get(claim)
        claims_fit = claim == "outer_diameter" or (isinstance(stored, (int, float)) and stored >= 0)
        if claims_fit and value > limit * (1 + 1e-9) + 1e-9:
            raise DesignFileError(
                f"{src}: the design's {claim.replace('_', ' ')} ({value:.6g} mm) lies outside its own envelope "
                f"(spec.{key} = {show(limit)} mm) although the file says it fits ({_decision_values(data)}); a value "
                "of parameters, fixed or spec was edited: edit the decision variables within the envelope, or re-run "
                "`vvea optimise`")


def load_design(path: str | Path) -> Design:
    """Read a design JSON file into the frozen :class:`~vvea_design.spring.design.Design`.

    Parameters
    ----------
    path : str or Path
        The design JSON file.

    Returns
    -------
    Design
        The frozen design (see :func:`load_design_dict`).

    Raises
    ------
    DesignFileError
        If the file cannot be read or is incomplete or inconsistent (the message names file and key).
    """
    return load_design_dict(read_design_json(path), str(path))


def load_requirements_from_design(path: str | Path) -> Requirements:
    """The requirements stored in a design JSON (its ``spec``).

    Parameters
    ----------
    path : str or Path
        The design JSON file.

    Returns
    -------
    Requirements
        The validated requirements the design was optimised for.

    Raises
    ------
    DesignFileError
        If the file cannot be read, has no ``spec`` object, or its ``spec`` is not valid
        requirements (the message names the key).
    """
    data = read_design_json(path)
    spec = data.get("spec")
    if not isinstance(spec, dict):
        raise DesignFileError(f"{path}: missing object 'spec' (the requirements the design was optimised for; "
                              "`vvea optimise` writes it)")
    try:
        return Requirements.from_dict(spec, source=f"{path}: spec")
    except SpecError as exc:
        raise DesignFileError(str(exc)) from None


def reevaluate(path: str | Path) -> Evaluation:
    """Load a design and evaluate it against the requirements stored with it.

    Parameters
    ----------
    path : str or Path
        The design JSON file (with its ``spec``).

    Returns
    -------
    Evaluation
        Linearity (fraction), stiffness (N/mm), force (N), mass (g) and constraint margins
        (dimensionless, > 0 met), recomputed from the file's design.

    Raises
    ------
    DesignFileError
        If the file cannot be read or is incomplete or inconsistent.
    ValueError
        If the stored requirements set ``max_bladder_strain`` (the FE strain is not recomputed here).
    """
    return evaluate_design(load_design(path), load_requirements_from_design(path))
