"""JSON Schemas of the two files a designer writes or keeps, generated from the dataclasses.

* the requirements file (TOML, read as a mapping):
  :class:`~vvea_design.spring.requirements.Requirements` with its ``[bounds]``
  and ``[fixed]`` (:class:`~vvea_design.spring.design.FixedParameters`);
* the design file (JSON, :mod:`vvea_design.spring.design_file`).

The shipped copies are ``vvea_design/schemas/*.schema.json`` (package data);
``python -m vvea_design.schema`` regenerates them and a test checks the
shipped ones equal what this module makes, so they cannot drift from the
dataclasses.
"""

from __future__ import annotations

import inspect
import json
import re
import sys
import types
import typing
from dataclasses import MISSING, fields
from importlib import resources
from pathlib import Path
from typing import Any

from .materials.silicones import SILICONES
from .materials.structural import STRUCTURAL
from .spring.layouts import LAYOUTS
from .spring.parameters import FixedParameters
from .spring.design_file import (DESIGN_PARAMETER_KEYS, FORMAT, FORMAT_VERSION, OPTIONAL_FIXED_KEYS,
                                 OPTIONAL_PARAMETER_KEYS)
from .spring.gas_spring import GasSpring
from .spring.hydraulics import OILS
from .spring.joints import JOINTS, PROPERTY_CLASSES
from .spring.parameters import SIZING_RULES
from .spring.tolerances import GENERAL_CLASSES, IT_GRADES
from .spring.requirements import DEFAULT_BOUNDS, Requirements

__all__ = ["requirements_schema", "design_schema", "SCHEMAS", "shipped_schema", "write_schemas"]

_DIALECT = "https://json-schema.org/draft/2020-12/schema"
_MATERIAL_FIELDS = {"housing_material", "rod_material", "support_ring_material"}


def _comments(cls: type) -> dict[str, str]:
    """The ``#:`` comment of each field of a dataclass (its description)."""
    out = {}
    for line in inspect.getsource(cls).splitlines():
        m = re.match(r"\s+(\w+)\s*:[^=]*(?:=.*?)?#:\s*(.+)$", line)
        if m:
            out[m.group(1)] = m.group(2).strip()
    return out


def _type_schema(tp: Any) -> dict[str, Any]:
    if tp is float:
        return {"type": "number"}
    if tp is int:
        return {"type": "integer"}
    if tp is str:
        return {"type": "string"}
    if tp is bool:
        return {"type": "boolean"}
    origin = typing.get_origin(tp)
    if origin is tuple:  # tuple[X, ...]: a list of X
        return {"type": "array", "items": _type_schema(typing.get_args(tp)[0])}
    if origin in (types.UnionType, typing.Union):
        args = [a for a in typing.get_args(tp) if a is not type(None)]
        if len(args) == 1:
            inner = _type_schema(args[0])
            return {**inner, "type": [inner["type"], "null"]}
    raise TypeError(f"no JSON Schema for the field type {tp!r}")  # pragma: no cover - a new field type


def _dataclass_properties(cls: type, skip: set[str] = frozenset()) -> dict[str, Any]:
    hints = typing.get_type_hints(cls)
    notes = _comments(cls)
    props: dict[str, Any] = {}
    for f in fields(cls):
        if f.name in skip:
            continue
        s = _type_schema(hints[f.name])
        if f.name in notes:
            s["description"] = notes[f.name]
        if f.default is not MISSING:
            s["default"] = json.loads(json.dumps(f.default))  # tuples as lists, as JSON has them
        props[f.name] = s
    return props


def fixed_schema(all_required: bool = False) -> dict[str, Any]:
    """Schema of the ``[fixed]`` table / the design file's ``fixed`` object.

    Parameters
    ----------
    all_required : bool
        Every field required (a design file is self-contained) or every field optional (requirements).

    Returns
    -------
    dict
        JSON Schema (object, the :class:`FixedParameters` fields, no other key).
    """
    props = _dataclass_properties(FixedParameters)
    for name in _MATERIAL_FIELDS:
        props[name]["enum"] = sorted(STRUCTURAL)
    props["sizing_rules"]["enum"] = list(SIZING_RULES)
    props["oil"]["enum"] = sorted(OILS)
    props["tie_rod_property_class"]["enum"] = sorted(PROPERTY_CLASSES)
    props["thickness_tolerance_class"]["enum"] = list(GENERAL_CLASSES)
    for name in ("bore_tolerance_grade", "outside_tolerance_grade"):
        props[name]["enum"] = list(IT_GRADES)
    out = {"type": "object", "description": FixedParameters.__doc__.strip(), "properties": props,
           "additionalProperties": False}
    if all_required:
        out["required"] = [f.name for f in fields(FixedParameters) if f.name not in OPTIONAL_FIXED_KEYS]
    return out


def requirements_schema() -> dict[str, Any]:
    """Schema of a requirements file (TOML read as a mapping), from :class:`Requirements`.

    Returns
    -------
    dict
        JSON Schema (draft 2020-12); every key optional, no unknown key.
    """
    props = _dataclass_properties(Requirements, skip={"bounds", "fixed"})
    props["bladder_material"]["enum"] = sorted(SILICONES)
    props["bounds"] = {
        "type": "object",
        "description": "search range [low, high] of each decision variable (mm, mm³)",
        "properties": {name: {"type": "array", "items": {"type": "number"}, "minItems": 2, "maxItems": 2,
                              "default": list(DEFAULT_BOUNDS[name])} for name in DEFAULT_BOUNDS},
        "additionalProperties": False,
    }
    props["fixed"] = fixed_schema()
    return {"$schema": _DIALECT, "$id": "vvea-design/requirements.schema.json", "title": "vvea-design requirements",
            "description": Requirements.__doc__.strip(), "type": "object", "properties": props,
            "additionalProperties": False}


def design_schema() -> dict[str, Any]:
    """Schema of a design file (``design.json``), from the design-file keys and the dataclasses.

    Returns
    -------
    dict
        JSON Schema (draft 2020-12).
    """
    gs_notes = _comments(GasSpring)
    params = {k: {"type": "number", **({"description": gs_notes[k]} if k in gs_notes else {})}
              for k in DESIGN_PARAMETER_KEYS + OPTIONAL_PARAMETER_KEYS}
    params["layout"] = {"type": "string", "enum": list(LAYOUTS), "description": "layout variant (docs/layout.md)"}
    params["joint"] = {"type": "string", "enum": list(JOINTS),
                       "description": "what holds the end pieces to the outer tube (docs/layout.md)"}
    spec = requirements_schema()
    spec = {k: v for k, v in spec.items() if k not in ("$schema", "$id", "title")}
    number_map = {"type": "object", "additionalProperties": {"type": ["number", "null"]}}
    return {
        "$schema": _DIALECT, "$id": "vvea-design/design.schema.json", "title": "vvea-design design file",
        "type": "object",
        "required": ["format", "format_version", "parameters", "fixed"],
        "properties": {
            "format": {"const": FORMAT},
            "format_version": {"const": FORMAT_VERSION},
            "parameters": {"type": "object", "properties": params, "required": list(DESIGN_PARAMETER_KEYS),
                           "additionalProperties": False,
                           "description": "the spring's physics (mm, mm², mm³, MPa): eq. 5 needs nothing else"},
            "fixed": fixed_schema(all_required=True),
            "geometry": {"type": "object", "description": "derived lengths, radii, volumes (for reading)"},
            "performance": {"type": "object", "description": "linearity (fraction), stiffness (N/mm), force (N), "
                                                             "mass (g), pressures (MPa), ..."},
            "constraints": {**number_map, "description": "margin of each constraint (positive = met)"},
            "constraint_details": {"type": "object", "additionalProperties": {
                "type": "object", "required": ["value", "limit", "unit", "kind"],
                "properties": {"kind": {"enum": ["min", "max"]}, "unit": {"type": "string"}}}},
            "spec": spec,
            "optimiser": {"type": "object", "description": "seed, evaluations, seconds, binding constraints"},
            "structure": {"type": "object", "required": ["sizing_rules", "joint", "load_cases", "pieces", "tolerances"],
                          "description": "load cases (MPa, N), every pressure-bearing piece's governing case and "
                                         "safety factor, the drawn tolerances (mm); derived, for reading"},
            "joints": {"type": "array", "items": {"type": "object", "required": ["joint", "kind"]},
                       "description": "the joints (thread, ring, tie rods) and seats with their sizes (mm), loads (N) "
                                      "and safety factors; derived, for reading"},
            "hydraulics": {"type": "object", "required": ["D_min_N_s_per_mm", "D_max_N_s_per_mm"],
                           "description": "the damper: oil, restrictions, damping range (N s/mm); derived, for reading"},
        },
        "additionalProperties": False,
    }


#: File name -> generator of every shipped schema.
SCHEMAS = {"requirements.schema.json": requirements_schema, "design.schema.json": design_schema}


def _dump(schema: dict) -> str:
    return json.dumps(schema, indent=2, sort_keys=True, ensure_ascii=False) + "\n"


def shipped_schema(name: str) -> dict[str, Any]:
    """A schema as shipped in the package data.

    Parameters
    ----------
    name : str
        ``"requirements.schema.json"`` or ``"design.schema.json"``.

    Returns
    -------
    dict
        The parsed schema.
    """
    return json.loads(resources.files("vvea_design").joinpath("schemas", name).read_text(encoding="utf-8"))


def write_schemas(folder: str | Path | None = None) -> list[Path]:
    """Regenerate the shipped schema files.

    Parameters
    ----------
    folder : path-like, optional
        Where to write (default: the package's ``schemas/`` folder).

    Returns
    -------
    list of Path
        The files written.
    """
    out = Path(folder) if folder is not None else Path(__file__).parent / "schemas"
    out.mkdir(parents=True, exist_ok=True)
    written = []
    for name, make in SCHEMAS.items():
        (out / name).write_text(_dump(make()), encoding="utf-8")
        written.append(out / name)
    return written


if __name__ == "__main__":  # pragma: no cover
    for p in write_schemas(sys.argv[1] if len(sys.argv) > 1 else None):
        print(p)
