"""The whole CAD set of one design, its named assembly and the geometric checks.

:func:`build_cad` is the one entry point: it validates the design and the
CAD parameters (:class:`~vvea_design.cad.layout.Layout` raises
:class:`~vvea_design.cad.layout.CadError` naming the field) *before* any
solid is built, then draws every part once.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from itertools import combinations

from build123d import Color, Compound, Solid

from ..spring.design import Design
from ..materials.structural import get_material
from ._shapes import cylinder, single_solid
from .bladder import bladder, bladder_volume_mm3, support_ring
from .gas import gas_chamber_1, gas_chamber_2
from .layout import CadParameters, Layout
from .mould import Mould, box, mould
from .parts import housing, housing_pieces, piston, piston_faces_mm2, piston_volume_mm3

__all__ = ["CadModel", "build_cad", "assembly", "interference_mm3", "mould_void", "part_materials",
           "SILICONE", "MOULD_MATERIAL"]

#: Material of the cast bladder (not a structural material).
SILICONE = "silicone (platinum-cure casting compound)"
#: Material of the printed mould.
MOULD_MATERIAL = "pla"

#: Part colours (RGB 0..1) in the assembly and renders.
COLOURS = {
    "housing": (0.72, 0.74, 0.78),
    "piston": (0.45, 0.47, 0.52),
    "bladder": (0.95, 0.75, 0.20),
    "support_ring": (0.15, 0.15, 0.15),
    "gas_chamber_1": (0.20, 0.40, 0.95),  # negative chamber: blue (paper Fig. 2)
    "gas_chamber_2": (0.95, 0.25, 0.20),  # positive chamber: red
}


def part_materials(design: Design) -> dict[str, str]:
    """Material name of every exported part (design's fixed materials)."""
    f = design.fixed
    mould_name = get_material(MOULD_MATERIAL).name
    return {
        "housing": get_material(f.housing_material).name,
        **{f"housing_{k}": get_material(f.housing_material).name for k in ("base", "outer_tube", "inner_tube", "top_cap")},
        "piston": get_material(f.rod_material).name,
        "bladder": SILICONE,
        "support_ring": get_material(f.support_ring_material).name,
        "mould_half_a": mould_name,
        "mould_half_b": mould_name,
        "mould_core": mould_name,
        "gas_chamber_1": "gas (nitrogen), chamber 1",
        "gas_chamber_2": "gas (nitrogen), chamber 2",
    }


@dataclass
class CadModel:
    """Every solid of one design (assembly frame unless noted), mm.

    ``parts`` holds housing, piston (x = 0), bladder, support_ring;
    ``housing_pieces`` the housing's machined parts (base, tubes, top cap);
    ``piston_at_travel`` the piston at x = travel; ``gas`` the two gas
    domains at x = 0; ``mould`` the mould (mould frame).
    """

    design: Design
    layout: Layout
    parts: dict[str, Solid]
    piston_at_travel: Solid
    gas: dict[str, Solid]
    mould: Mould
    housing_pieces: dict[str, Solid] = field(default_factory=dict)
    closed_form_mm3: dict[str, float] = field(default_factory=dict)

    def parts_at(self, x_mm: float) -> dict[str, Solid]:
        """The four assembly parts with the piston at ``x_mm`` (0 or travel, else rebuilt)."""
        out = dict(self.parts)
        if x_mm == 0:
            return out
        if math.isclose(x_mm, self.design.fixed.travel_mm):
            out["piston"] = self.piston_at_travel
        else:
            out["piston"] = piston(self.layout, x_mm)
        return out

    def export_solids(self) -> dict[str, Solid]:
        """Every solid written as its own STEP + STL, by file stem."""
        return {**self.parts, **self.housing_pieces, **self.mould.parts()}

    def measured(self) -> dict[str, float]:
        """CAD-measured chamber volumes (mm³) and piston areas (mm²)."""
        areas = piston_faces_mm2(self.parts["piston"], self.layout, 0.0)
        return {
            "chamber_1_volume_mm3": self.gas["gas_chamber_1"].volume,
            "chamber_2_volume_mm3": self.gas["gas_chamber_2"].volume,
            "piston_area_A1_mm2": areas["A1_mm2"],
            "piston_area_A2_mm2": areas["A2_mm2"],
        }


def build_cad(design: Design, cad: CadParameters | None = None, progress=None) -> CadModel:
    """Validate, then draw every part of ``design``.

    Parameters
    ----------
    design : Design
        The frozen design (mm, mm³).
    cad : CadParameters, optional
        Feature sizes; defaults to ``CadParameters()``.
    progress : callable, optional
        ``advance()`` called once per part built (7 calls).

    Raises
    ------
    CadError
        Before any geometry is built, naming the field that does not fit.
    """
    lay = Layout(design, cad or CadParameters())
    step = progress or (lambda n=1: None)
    parts: dict[str, Solid] = {}
    parts["housing"] = housing(lay); step()
    parts["piston"] = piston(lay, 0.0)
    at_travel = piston(lay, design.fixed.travel_mm); step()
    parts["bladder"] = bladder(lay); step()
    parts["support_ring"] = support_ring(lay); step()
    gas = {"gas_chamber_1": gas_chamber_1(lay), "gas_chamber_2": gas_chamber_2(lay)}; step()
    m = mould(lay); step()
    for name, s in parts.items():
        s.label = name
        s.color = Color(*COLOURS[name])
    closed = {
        "piston": piston_volume_mm3(lay),
        "bladder": bladder_volume_mm3(lay),
        "gas_chamber_1": design.V1_mm3 - design.fixed.dead_volume_1_mm3,
        "gas_chamber_2": design.V2_mm3 - design.fixed.dead_volume_2_mm3,
        "mould_cavity": bladder_volume_mm3(lay) * (1 + lay.cad.mould_shrinkage) ** 3,
    }
    pieces = housing_pieces(lay, parts["housing"])
    model = CadModel(design, lay, parts, at_travel, gas, m, housing_pieces=pieces, closed_form_mm3=closed)
    step()
    return model


def assembly(model: CadModel, x_mm: float = 0.0) -> Compound:
    """Named assembly (``housing``, ``piston``, ``bladder``, ``support_ring``) at ``x_mm``.

    The children carry names but no colours, so the STEP bytes are stable
    (OCCT orders assembly colour styles by memory address)."""
    children = []
    for name, s in model.parts_at(x_mm).items():
        c = Solid(s.wrapped)  # no colour: OCCT writes assembly styles in a run-dependent order
        c.label = name
        children.append(c)
    asm = Compound(children=children)
    asm.label = "vvea_unit"
    return asm


def _volume(shape) -> float:
    """Volume of a boolean result (None, a shape or a list of shapes), mm³."""
    if shape is None:
        return 0.0
    if isinstance(shape, (list, tuple)):
        return float(sum(_volume(s) for s in shape))
    return float(shape.volume)


def interference_mm3(parts: dict[str, Solid]) -> dict[str, float]:
    """Boolean intersection volume of every pair of parts, mm³ (``"a/b"`` keys)."""
    out = {}
    for (na, a), (nb, b) in combinations(parts.items(), 2):
        bb_a, bb_b = a.bounding_box(), b.bounding_box()
        if (bb_a.min.X > bb_b.max.X or bb_b.min.X > bb_a.max.X or bb_a.min.Z > bb_b.max.Z or bb_b.min.Z > bb_a.max.Z):
            out[f"{na}/{nb}"] = 0.0
            continue
        out[f"{na}/{nb}"] = _volume(a.intersect(b))
    return out


def mould_void(m: Mould) -> dict:
    """The empty space of the closed mould that holds the cavity, measured.

    Returns a dict with ``cavity_volume_mm3`` (void clipped to the cavity's
    envelope), ``void_volume_mm3`` (cavity + sprue + runner + vents),
    ``sprue_open`` / ``vents_open`` (the void reaches each opening in the
    top face) and ``void`` (the solid).
    """
    x0, x1, y0, y1, z0, z1 = m.block_mm
    space = box(x0, x1, y0, y1, z0, z1)
    rest = space.cut(m.half_a, m.half_b, m.core)
    bb = m.cavity.bounding_box()
    r_max = bb.max.X
    # a point inside the cavity wall: mid-sleeve at z = 0 on +y
    probe = None
    for s in rest.solids():
        sb = s.bounding_box()
        if sb.min.Z <= bb.min.Z + 1e-6 and sb.max.Z >= z1 - 1e-6 and sb.max.X >= r_max - 1e-3:
            if probe is None or s.volume > probe.volume:
                probe = s
    if probe is None:
        raise RuntimeError("no void component holds the mould cavity")
    void = single_solid(probe)
    clip = cylinder(r_max, bb.min.Z, bb.max.Z)
    cav = void.intersect(clip)
    eps = 0.3
    sx, sy, sz = m.sprue_top_mm
    return {
        "cavity_volume_mm3": _volume(cav),
        "void_volume_mm3": float(void.volume),
        "sprue_open": bool(void.is_inside((sx, sy, sz - eps))),
        "vents_open": [bool(void.is_inside((vx, vy, vz - eps))) for vx, vy, vz in m.vent_tops_mm],
        "void": void,
    }
