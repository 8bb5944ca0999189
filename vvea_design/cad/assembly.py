"""The whole CAD set of one design, its named assembly and the geometric checks.

:func:`build_cad` is the one entry point: it validates the design and the
CAD parameters (:class:`~vvea_design.cad.layout.Layout` raises
:class:`~vvea_design.cad.layout.CadError` naming the field) *before* any
solid is built, then draws every part once.
"""

from __future__ import annotations

import math
from collections import OrderedDict
from dataclasses import dataclass, field
from itertools import combinations

from build123d import Color, Compound, Solid

from ..spring.design import Design
from ._shapes import cylinder, single_solid
from .bladder import bladder_volume_mm3
from .layout import CadParameters, Layout
from .mould import Mould, box
from .parts import piston_faces_mm2
from .registry import MOULD_MATERIAL, PARTS, SILICONE, PartContext, all_parts, get_part, parts_in
from .sequence import AssemblyCheck, check_assembly

__all__ = ["CadModel", "MouldVoid", "build_cad", "assembly", "interference_mm3", "mould_void", "part_materials",
           "SILICONE", "MOULD_MATERIAL", "COLOURS"]

#: Part colours (RGB 0..1) by part name, from the part table.
COLOURS = {p.name: p.colour for p in PARTS}


def part_materials(design: Design) -> dict[str, str]:
    """Material name of every part in the table (design's fixed materials).

    Parameters
    ----------
    design : Design
        The design whose ``fixed`` materials (housing, rod, support ring) resolve the parts'.

    Returns
    -------
    dict of str to str
        Part name -> material display name, in table order.
    """
    return {p.name: p.material(design).name for p in all_parts()}


@dataclass
class CadModel:
    """Every solid of one design, by part name (assembly frame; mould parts in the mould frame), mm.

    ``solids`` holds every entry of :data:`~vvea_design.cad.registry.PARTS` at
    x = 0; ``at_travel`` the moving ones at x = travel; ``mould`` the mould
    with its cavity and openings; ``closed_form_mm3`` the closed-form volume
    of every part that has one (plus ``mould_cavity``).
    """

    design: Design
    layout: Layout
    solids: dict[str, Solid]
    at_travel: dict[str, Solid]
    mould: Mould
    closed_form_mm3: dict[str, float] = field(default_factory=dict)
    _assembly: AssemblyCheck | None = field(default=None, repr=False, compare=False)

    def group(self, *groups: str) -> dict[str, Solid]:
        """The solids of the given part groups (x = 0), in table order.

        Parameters
        ----------
        *groups : str
            Part groups (``"assembly"``, ``"machined"``, ``"mould"``, ``"gas"``).

        Returns
        -------
        dict of str to Solid
            Part name -> solid, mm.

        Raises
        ------
        ValueError
            If a group is unknown.
        """
        return {p.name: self.solids[p.name] for p in parts_in(*groups)}

    @property
    def parts(self) -> dict[str, Solid]:
        """The assembled unit at x = 0 (group ``assembly``)."""
        return self.group("assembly")

    @property
    def housing_pieces(self) -> dict[str, Solid]:
        """The housing's machined pieces (group ``machined``)."""
        return self.group("machined")

    @property
    def gas(self) -> dict[str, Solid]:
        """The gas domains at x = 0 (group ``gas``)."""
        return self.group("gas")

    @property
    def piston_at_travel(self) -> Solid:
        """The piston with rod at x = travel (full extension), assembly frame, mm."""
        return self.at_travel["piston"]

    def solids_at(self, x_mm: float, *groups: str) -> dict[str, Solid]:
        """The solids of ``groups`` with the piston at ``x_mm`` (moving parts rebuilt unless x = 0 or travel).

        Parameters
        ----------
        x_mm : float
            Piston displacement, mm (x > 0 extends; 0 and the travel reuse the built solids).
        *groups : str
            Part groups (``"assembly"``, ``"machined"``, ``"mould"``, ``"gas"``).

        Returns
        -------
        dict of str to Solid
            Part name -> solid at ``x_mm``, named and coloured, mm.

        Raises
        ------
        ValueError
            If a group is unknown.
        """
        out = self.group(*groups)
        if x_mm == 0:
            return out
        travel = math.isclose(x_mm, self.design.fixed.travel_mm)
        ctx = None if travel else PartContext(self.layout, x_mm)
        for name in out:
            part = get_part(name)
            if part.moves:
                out[name] = self.at_travel[name] if travel else _named(part, part.build(ctx))
        return out

    def parts_at(self, x_mm: float) -> dict[str, Solid]:
        """The assembly parts with the piston at ``x_mm``.

        Parameters
        ----------
        x_mm : float
            Piston displacement, mm (x > 0 extends; 0 and the travel reuse the built solids).

        Returns
        -------
        dict of str to Solid
            Housing, piston, bladder and support ring by part name, mm.
        """
        return self.solids_at(x_mm, "assembly")

    def export_solids(self) -> dict[str, Solid]:
        """Every solid written as its own STEP, by file stem.

        Returns
        -------
        dict of str to Solid
            The table's parts whose ``files`` include ``"step"`` (x = 0), mm.
        """
        return {p.name: self.solids[p.name] for p in all_parts() if "step" in p.files}

    def assembly_check(self) -> AssemblyCheck:
        """The assembly order checked on this model's parts (:func:`~vvea_design.cad.sequence.check_assembly`),
        computed once per model.

        Returns
        -------
        AssemblyCheck
            Per step: the swept overlap (mm) and the O-rings' crossings.
        """
        if self._assembly is None:
            self._assembly = check_assembly(self.solids, self.layout)
        return self._assembly

    def measured(self) -> dict[str, float]:
        """CAD-measured chamber volumes and piston areas at x = 0.

        Returns
        -------
        dict of str to float
            ``chamber_1_volume_mm3``, ``chamber_2_volume_mm3`` (mm³), ``piston_area_A1_mm2`` and
            ``piston_area_A2_mm2`` (mm²), measured on the solids.
        """
        areas = piston_faces_mm2(self.solids["piston"], self.layout, 0.0)
        return {
            "chamber_1_volume_mm3": self.solids["gas_chamber_1"].volume,
            "chamber_2_volume_mm3": self.solids["gas_chamber_2"].volume,
            "piston_area_A1_mm2": areas["A1_mm2"],
            "piston_area_A2_mm2": areas["A2_mm2"],
        }


def _named(part, solid: Solid) -> Solid:
    solid.label = part.name
    solid.color = Color(*part.colour)
    return solid


def build_cad(design: Design, cad: CadParameters | None = None, progress=None) -> CadModel:
    """Validate, then draw every part of the table for ``design``.

    Parameters
    ----------
    design : Design
        The frozen design (mm, mm³).
    cad : CadParameters, optional
        Feature sizes; defaults to ``CadParameters()``.
    progress : callable, optional
        ``advance()`` called once per part built and once at the end
        (``len(PARTS) + 1`` calls).

    Returns
    -------
    CadModel
        Every part, named (``label``) and coloured from the table.

    Raises
    ------
    CadError
        Before any geometry is built, naming the field that does not fit.
    """
    lay = Layout(design, cad or CadParameters())
    step = progress or (lambda n=1: None)
    ctx = PartContext(lay, 0.0)
    ctx_travel = PartContext(lay, design.fixed.travel_mm)
    solids: dict[str, Solid] = {}
    at_travel: dict[str, Solid] = {}
    closed: dict[str, float] = {}
    for part in all_parts():
        solids[part.name] = _named(part, part.build(ctx))
        if part.moves:
            at_travel[part.name] = _named(part, part.build(ctx_travel))
        if part.volume_mm3 is not None:
            closed[part.name] = float(part.volume_mm3(lay))
        step()
    closed["mould_cavity"] = bladder_volume_mm3(lay) * (1 + lay.cad.mould_shrinkage) ** 3
    model = CadModel(design, lay, solids, at_travel, ctx.mould, closed_form_mm3=closed)
    step()
    return model


def assembly(model: CadModel, x_mm: float = 0.0) -> Compound:
    """Named assembly (``housing``, ``piston``, ``bladder``, ``support_ring``) at ``x_mm``.

    The children carry names but no colours, so the STEP bytes are stable
    (OCCT orders assembly colour styles by memory address).

    Parameters
    ----------
    model : CadModel
        The built CAD set.
    x_mm : float
        Piston displacement, mm (x > 0 extends).

    Returns
    -------
    Compound
        Labelled ``vvea_unit``, one labelled child per assembly part, assembly frame, mm.
    """
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
    """Boolean intersection volume of every pair of parts.

    Parameters
    ----------
    parts : dict of str to Solid
        Solids by name, in one frame, mm.

    Returns
    -------
    dict of str to float
        ``"a/b"`` -> intersection volume, mm³ (0 for pairs whose bounding boxes do not overlap in x or z).
        A pair already measured (the same two solids, not moved since) is not intersected again.
    """
    out = {}
    for (na, a), (nb, b) in combinations(parts.items(), 2):
        bb_a, bb_b = a.bounding_box(), b.bounding_box()
        if (bb_a.min.X > bb_b.max.X or bb_b.min.X > bb_a.max.X or bb_a.min.Z > bb_b.max.Z or bb_b.min.Z > bb_a.max.Z):
            out[f"{na}/{nb}"] = 0.0
            continue
        out[f"{na}/{nb}"] = _MEMO.get("intersection", (a, b), (), lambda a=a, b=b: _volume(a.intersect(b)))
    return out


class _ShapeMemo:
    """Results of pure functions of solids, by the solids' OCCT identity (same TShape, location and orientation:
    the same solid), least recently used dropped first. The manifest's interference and mould checks are measured
    once per model: a caller asking again about the same solids (the BOM, a test) gets the number without
    the booleans. A solid moved in place has another location, so it is measured afresh."""

    def __init__(self, size: int):
        self.size = size
        self._entries: OrderedDict = OrderedDict()

    def get(self, kind: str, shapes: tuple, extra: tuple, compute):
        ws = tuple(s.wrapped for s in shapes)
        key = (kind, tuple(hash(w) for w in ws), extra)
        hit = self._entries.get(key)
        if hit is not None and all(a.IsEqual(b) for a, b in zip(hit[0], ws)):
            self._entries.move_to_end(key)
            return hit[1]
        value = compute()
        # own handles on the shapes (a later in-place move of the caller's solid does not move these)
        self._entries[key] = (tuple(w.Located(w.Location()) for w in ws), value)
        while len(self._entries) > self.size:
            self._entries.popitem(last=False)
        return value


_MEMO = _ShapeMemo(64)


@dataclass(frozen=True, eq=False)
class MouldVoid:
    """The empty space of the closed mould that holds the cavity, measured (mould frame)."""

    cavity_volume_mm3: float  #: the void clipped to the cavity's envelope, mm³
    void_volume_mm3: float  #: cavity + sprue + runner + vents, mm³
    sprue_open: bool  #: the void reaches the sprue's opening in the top face
    vents_open: tuple[bool, ...]  #: the void reaches each vent's opening in the top face
    void: Solid  #: the void itself, mm

    def to_dict(self) -> dict:
        """The measured numbers (the solid left out).

        Returns
        -------
        dict
            ``cavity_volume_mm3`` and ``void_volume_mm3`` (mm³), ``sprue_open`` and ``vents_open`` (list of bool).
        """
        return {"cavity_volume_mm3": self.cavity_volume_mm3, "void_volume_mm3": self.void_volume_mm3,
                "sprue_open": self.sprue_open, "vents_open": list(self.vents_open)}


def mould_void(m: Mould) -> MouldVoid:
    """The empty space of the closed mould that holds the cavity, measured.

    Parameters
    ----------
    m : Mould
        The mould (:func:`~vvea_design.cad.mould.mould`), mould frame, mm.

    Returns
    -------
    MouldVoid
        Cavity and void volumes (mm³), whether the void reaches the sprue and each vent, the void solid (mm).
        Measured once per mould (asked again about the same solids, the same record comes back).

    Raises
    ------
    RuntimeError
        If no connected void of the closed mould holds the cavity (the mould is broken).
    """
    return _MEMO.get("mould_void", (m.half_a, m.half_b, m.core, m.cavity), (m.block_mm, m.sprue_top_mm, m.vent_tops_mm),
                     lambda: _mould_void(m))


def _mould_void(m: Mould) -> MouldVoid:
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
    return MouldVoid(
        cavity_volume_mm3=_volume(cav),
        void_volume_mm3=float(void.volume),
        sprue_open=bool(void.is_inside((sx, sy, sz - eps))),
        vents_open=tuple(bool(void.is_inside((vx, vy, vz - eps))) for vx, vy, vz in m.vent_tops_mm),
        void=void,
    )
