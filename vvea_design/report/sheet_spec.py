"""The sheets of a CAD model before layout: each drawn part's section cut
from its build123d solid, with what its drawing hook says (dimensions,
leaders, notes, detail), and the unit's section A-A.

Geometry: every outline is the section of the part's build123d solid by a
meridian half-plane (``Solid.intersect`` with a planar face), so the drawing
shows what the STEP files hold. The unit's section is an *aligned* section
A-A: the left half lies in the valve plane (y = 0, x < 0: relief valve,
channels), the right half in the fill-port plane (x = 0, y > 0). What each
sheet dimensions comes from the part table
(:attr:`~vvea_design.cad.registry.Part.drawing`, :mod:`vvea_design.cad.sheets`);
each dimension's anchor points are checked against the drawn outline
(:func:`check_anchors`, used by the tests).
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass, field

import numpy as np

from ..cad.assembly import CadModel
from ..cad.drafting import Detail, Dim, Leader, SheetContent, radial_extent_mm
from ..cad.gas import fluid_column
from ..cad.parts import piston_head
from ..cad.registry import FLUID_COLOUR, Part, all_parts, parts_in
from ..cad.section import section_loops
from ..cad.sheets import unit_section_sheet

__all__ = ["Region", "SheetSpec", "section_loops", "sheet_specs", "check_anchors", "HATCH_PATTERNS", "PART_HATCHES",
           "hatch_pattern", "unit_parts"]

#: matplotlib hatch of each part hatch (:data:`~vvea_design.cad.registry.HATCHES`).
HATCH_PATTERNS = {"metal": "////", "steel": "\\\\\\\\", "plastic": "xx", "rubber": None, None: None}
#: The housing's pieces hatched differently (ISO 128-50: adjacent parts differ in direction or spacing), so the
#: joints show on the section: base 45° dense, outer tube 135° dense, inner tube 135° wide, top cap 45° wide.
PART_HATCHES = {"housing_base": "////", "housing_outer_tube": "\\\\\\\\", "housing_inner_tube": "\\\\",
                "housing_top_cap": "//"}


def hatch_pattern(part: Part) -> str | None:
    """The matplotlib hatch a part's section is drawn with: its own (:data:`PART_HATCHES`) or its kind's.

    Parameters
    ----------
    part : Part
        The table entry.

    Returns
    -------
    str or None
        A matplotlib hatch pattern (None: a plain fill).
    """
    return PART_HATCHES.get(part.name, HATCH_PATTERNS[part.hatch])
_FILL_ALPHA = 0.18  # gas and fluid: translucent fills without outline
_GHOST_COLOUR = (0.3, 0.3, 0.3)  # the piston at full stroke, dashed


def _aligned_loops(solid, margin_mm: float) -> tuple[np.ndarray, ...]:
    """Section A-A of ``solid``: the valve plane for u < 0, the fill-port plane for u > 0, |u| <= margin_mm."""
    return tuple(section_loops(solid, "xz", -margin_mm, 0.0) + section_loops(solid, "yz", 0.0, margin_mm))


# --------------------------------------------------------------------------- specs
@dataclass(frozen=True, eq=False)
class Region:
    """One filled section region: loops (model mm) and how it is drawn."""

    name: str
    loops: tuple[np.ndarray, ...]
    colour: tuple[float, float, float]
    hatch: str | None
    alpha: float = 1.0
    outline: bool = True
    dashed: bool = False


@dataclass
class SheetSpec:
    """Everything on one sheet before layout (model mm)."""

    name: str
    title: str
    regions: list[Region]
    dims: list[Dim]
    leaders: list[Leader]
    notes: list[str]
    material: str
    mass_g: float | None = None
    view_note: str = ""
    extent: tuple[float, float, float, float] = (0, 0, 0, 0)  #: u0, u1, z0, z1 of the view
    anchor_loops: list[np.ndarray] = field(default_factory=list)  #: outlines the anchors must lie on
    detail: Detail | None = None
    finish: str = ""  #: surface treatment for the title block


def _unit_spec(model: CadModel) -> SheetSpec:
    """The unit's section A-A: the assembly's parts hatched, the gas domains and the fluid column as
    translucent fills under them, the piston at full stroke dashed; the content from
    :func:`~vvea_design.cad.sheets.unit_section_sheet`."""
    lay, d = model.layout, model.design
    content: SheetContent = unit_section_sheet(lay)
    R = content.extent[1]
    parts, anchors = [], []
    for p in unit_parts():
        loops = _aligned_loops(model.solids[p.name], R + 5)
        parts.append(Region(p.name, loops, p.colour, hatch_pattern(p)))
        anchors.extend(loops)
    # fills first (under the outlines): the fluid, then the gas domains from the last to the first
    fills = [Region("fluid", _aligned_loops(fluid_column(lay, 0.0), R), FLUID_COLOUR, None, _FILL_ALPHA,
                    outline=False)]
    fills += [Region(p.name, _aligned_loops(model.solids[p.name], R + 5), p.colour, None, _FILL_ALPHA, outline=False)
              for p in reversed(parts_in("gas"))]
    ghost = Region("piston_at_travel", _aligned_loops(piston_head(lay, d.fixed.travel_mm), R), _GHOST_COLOUR, None,
                   0.0, True, dashed=True)
    return SheetSpec("unit_section", content.title, fills + parts + [ghost], list(content.dims),
                     list(content.leaders), list(content.notes), material=content.material,
                     view_note=content.view_note, extent=content.extent, anchor_loops=anchors)


def unit_parts() -> tuple[Part, ...]:
    """The parts the unit's section draws: the housing as its machined pieces (each hatched its own way), then
    the other assembly parts (piston, bladder, support ring).

    Returns
    -------
    tuple of Part
        In drawing order.
    """
    return tuple(p for p in parts_in("machined", "assembly") if p.name != "housing")


def _part_spec(model: CadModel, part: Part) -> SheetSpec:
    """The sheet of one part with a drawing hook: its section, what the hook says, its material and mass."""
    solid = model.solids[part.name]
    content: SheetContent = part.drawing(model.layout, solid)
    R, z0, z1 = radial_extent_mm(solid)
    plane = content.plane
    if plane == "aligned":
        loops = _aligned_loops(solid, R + 5)
    else:
        loops = tuple(section_loops(solid, plane, -R - 5, R + 5))
    reg = Region(part.name, loops, part.colour, hatch_pattern(part))
    mat = part.material(model.design)
    view = {"xz": "Section in the valve plane (y = 0)", "yz": "Section in the fill-port plane (x = 0)",
            "aligned": "Section A-A, aligned"}[plane]
    return SheetSpec(part.name, content.title or part.title[:1].upper() + part.title[1:], [reg], list(content.dims),
                     list(content.leaders), list(content.notes), material=content.material or mat.name,
                     mass_g=float(solid.volume) * mat.density_g_per_mm3, view_note=content.view_note or view,
                     extent=content.extent or (-R, R, z0, z1), anchor_loops=list(reg.loops), detail=content.detail,
                     finish=part.finish)


def sheet_specs(model: CadModel, names: Sequence[str] | None = None) -> list[SheetSpec]:
    """The sheets of a CAD model, before layout.

    Parameters
    ----------
    model : CadModel
        The built CAD set.
    names : sequence of str, optional
        Only these sheets (``"unit_section"`` or part names), in the usual order; default all.

    Returns
    -------
    list of SheetSpec
        The unit's section A-A, then every part of the table with a drawing hook, in table order (model mm).

    Raises
    ------
    ValueError
        If a name in ``names`` is not a sheet.
    """
    pieces = [p for p in all_parts() if p.drawing is not None]
    if names is None:
        return [_unit_spec(model)] + [_part_spec(model, p) for p in pieces]
    unknown = set(names) - {"unit_section", *(p.name for p in pieces)}
    if unknown:
        raise ValueError(f"no sheet named {sorted(unknown)}; sheets: unit_section, {', '.join(p.name for p in pieces)}")
    return ([_unit_spec(model)] if "unit_section" in names else []) + [_part_spec(model, p) for p in pieces
                                                                      if p.name in names]


def _dist_to_loops(p: tuple[float, float], loops: Sequence[np.ndarray]) -> float:
    best = math.inf
    q = np.asarray(p, dtype=float)
    for loop in loops:
        a, b = loop[:-1], loop[1:]
        ab = b - a
        t = np.clip(np.einsum("ij,ij->i", q - a, ab) / np.maximum(np.einsum("ij,ij->i", ab, ab), 1e-300), 0, 1)
        d = np.linalg.norm(a + t[:, None] * ab - q, axis=1)
        best = min(best, float(d.min()))
    return best


def check_anchors(spec: SheetSpec, tol_mm: float = 1e-6) -> list[str]:
    """Dimension anchors that do not lie on a drawn outline.

    Parameters
    ----------
    spec : SheetSpec
        The sheet (its detail view included).
    tol_mm : float
        Distance to the outline accepted, mm.

    Returns
    -------
    list of str
        One message per stray anchor (empty: every anchor lies on the outline; feature axes skipped).
    """
    bad = []
    for dim in [*spec.dims, *(spec.detail.dims if spec.detail else [])]:
        if dim.on_axis:
            continue
        for p in (dim.a, dim.b):
            if _dist_to_loops(p, spec.anchor_loops) > tol_mm:
                bad.append(f"{spec.name}: {dim.label()} anchor {p}")
    return bad

