"""The CAD part table: one entry per part drives build, export, labels,
colours, closed-form checks, renders, the 3-D view, the drawings and the bill
of materials.

A part owns its data: its entry carries its builder, material, colour,
closed-form volume, files, its **drawing hook** (the sheet's section plane,
dimensions and notes, :mod:`~vvea_design.cad.sheets`), its section hatch and
its **BOM hook** (its line(s) of the bill, :mod:`~vvea_design.cad.bill`) or
the reason it is not on the bill. Adding a part = one :class:`Part` entry in
:data:`PARTS` (its builder and hooks may be written here or in a part module).
:func:`~vvea_design.cad.assembly.build_cad` builds every entry once, names and
colours it; ``write_cad`` writes the files each entry lists (the file count
follows from the table); the renders and the GLB take the parts of their
group; :mod:`vvea_design.report.drawing` draws a sheet per entry with a drawing
hook and :mod:`vvea_design.report.bom` asks every entry for its lines; the tests
check every closed-form volume and that every STEP file carries the part's name.

Groups:

* ``assembly`` -- the unit as it is assembled (``assembly.step``, the
  interference check, the cut-away, the unit's section, ``assembly.glb``);
* ``machined`` -- the housing's machined pieces (slices of the united
  housing; drawings and bill of materials);
* ``mould`` -- the bladder mould (mould frame; ``mould.glb``, mould render;
  tooling lines of the bill);
* ``gas`` -- the gas domains (STL only; cut-away, unit's section, 3-D view).
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass
from functools import cached_property

from build123d import Solid

from ..materials.structural import DENSITY_SILICONE_g_per_mm3, get_material
from ..spring.design import Design
from .bill import BomContext, BomLine
from .bladder import bladder, bladder_volume_mm3, support_ring, support_ring_volume_mm3
from .drafting import SheetContent
from .features import (Feature, base_features, inner_tube_features, outer_tube_features, piston_features,
                       top_cap_features)
from .gas import gas_chamber_1, gas_chamber_2
from .housing_joints import outer_tube_profile
from .layout import Layout
from .mould import Mould, mould, mould_core_volume_mm3
from .parts import housing, housing_pieces, lead_in_ring_mm3, piston, piston_volume_mm3, tube_bottom_lead_in
from .sheets import housing_base_sheet, inner_tube_sheet, outer_tube_sheet, piston_sheet, top_cap_sheet

__all__ = ["Part", "PartContext", "PartMaterial", "PARTS", "GROUPS", "HATCHES", "all_parts", "get_part", "parts_in",
           "SILICONE", "MOULD_MATERIAL", "FLUID_COLOUR", "BomHook", "DrawingHook", "made_part", "cast_part",
           "tooling_part", "structural_material", "fixed_material"]

#: Material of the cast bladder when no silicone is named (the BOM names the chosen one).
SILICONE = "silicone (platinum-cure casting compound)"
#: Structural-material key of the printed mould.
MOULD_MATERIAL = "pla"
#: Colour of the fluid column in the renders (RGB 0..1).
FLUID_COLOUR = (0.25, 0.75, 0.35)
#: The part groups, in drawing order.
GROUPS = ("assembly", "machined", "mould", "gas")
#: Section hatches of the drawings by part kind (None: a gas domain, drawn as a translucent fill).
HATCHES = ("metal", "steel", "plastic", "rubber", None)


@dataclass(frozen=True)
class PartMaterial:
    """What a part is made of: display name, density (g/mm³; None for gas) and how it is made."""

    name: str
    density_g_per_mm3: float | None
    process: str  #: "machined", "turned", "printed", "cast", "gas"

    def to_dict(self) -> dict:
        """JSON-ready content.

        Returns
        -------
        dict
            ``name``, ``density_g_per_mm3`` (g/mm³, None for gas) and ``process``.
        """
        return {"name": self.name, "density_g_per_mm3": self.density_g_per_mm3, "process": self.process}


class PartContext:
    """One layout at one piston displacement, with the shared solids built lazily
    (the united housing, its slices, the mould) so each builder is a one-liner and
    each expensive solid is built once.

    Parameters
    ----------
    lay : Layout
        Radii and axial levels of the design, mm.
    x_mm : float
        Piston displacement the moving parts are built at, mm (x > 0 extends).
    """

    def __init__(self, lay: Layout, x_mm: float = 0.0) -> None:
        self.lay = lay
        self.x_mm = float(x_mm)

    @cached_property
    def housing(self) -> Solid:
        """The united housing (:func:`~vvea_design.cad.parts.housing`), mm."""
        return housing(self.lay)

    @cached_property
    def housing_pieces(self) -> dict[str, Solid]:
        """The housing's machined pieces by part name (:func:`~vvea_design.cad.parts.housing_pieces`), mm."""
        return housing_pieces(self.lay, self.housing)

    @cached_property
    def mould(self) -> Mould:
        """The bladder mould (:func:`~vvea_design.cad.mould.mould`), mould frame, mm."""
        return mould(self.lay)


#: A BOM hook: ``hook(part, ctx)`` -> the part's lines of the bill (unnumbered), mm³, g.
BomHook = Callable[["Part", BomContext], tuple[BomLine, ...]]
#: A drawing hook: ``hook(lay, solid)`` -> what the part's sheet shows (section plane, dimensions, notes), mm.
DrawingHook = Callable[[Layout, Solid], SheetContent]
#: A feature hook: ``hook(lay)`` -> the part's machined features, each with its size, tolerance and annotation.
FeatureHook = Callable[[Layout], tuple[Feature, ...]]


def made_part(part: "Part", ctx: BomContext) -> tuple[BomLine, ...]:
    """BOM hook of a made part (machined, turned, printed): one line, mass = CAD volume x density.

    Parameters
    ----------
    part : Part
        The table entry (name, title, material).
    ctx : BomContext
        The built solids (mm) and the design (its materials).

    Returns
    -------
    tuple of BomLine
        One line in the unit: category = the material's process, volume (mm³) and mass (g), its STEP file.
    """
    mat = part.material(ctx.design)
    vol = float(ctx.solids[part.name].volume)
    return (BomLine(part=part.name, description=part.title, category=mat.process, material=mat.name, standard="",
                    size="", quantity=1, unit_volume_mm3=vol, unit_mass_g=vol * mat.density_g_per_mm3, in_unit=True,
                    file=f"{part.name}.step", note=f"{mat.process}; mass = CAD volume x {mat.density_g_per_mm3:g} g/mm³"),)


def cast_part(part: "Part", ctx: BomContext) -> tuple[BomLine, ...]:
    """BOM hook of the cast bladder: one line in the bill's casting silicone (``ctx.silicone``).

    Parameters
    ----------
    part : Part
        The table entry (name, title, material: its density).
    ctx : BomContext
        The built solids (mm) and the casting silicone.

    Returns
    -------
    tuple of BomLine
        One line in the unit: the silicone's name and hardness, volume (mm³) and mass (g), its STEP file.
    """
    mat = part.material(ctx.design)
    vol = float(ctx.solids[part.name].volume)
    sil = ctx.silicone
    return (BomLine(part=part.name, description=part.title, category=mat.process,
                    material=f"{sil.name} ({sil.hardness})", standard="", size="", quantity=1, unit_volume_mm3=vol,
                    unit_mass_g=vol * mat.density_g_per_mm3, in_unit=True, file=f"{part.name}.step",
                    note=f"cast in the printed mould; mass = CAD volume x {DENSITY_SILICONE_g_per_mm3:g} g/mm³"),)


def tooling_part(part: "Part", ctx: BomContext) -> tuple[BomLine, ...]:
    """BOM hook of a mould part: one tooling line, not in the unit (mass at 100 % infill).

    Parameters
    ----------
    part : Part
        The table entry (name, title, material).
    ctx : BomContext
        The built solids (mm) and the design.

    Returns
    -------
    tuple of BomLine
        One ``tooling`` line: volume (mm³), mass (g), its STEP file.
    """
    mat = part.material(ctx.design)
    vol = float(ctx.solids[part.name].volume)
    return (BomLine(part=part.name, description=part.title, category="tooling", material=mat.name, standard="",
                    size="", quantity=1, unit_volume_mm3=vol, unit_mass_g=vol * mat.density_g_per_mm3, in_unit=False,
                    file=f"{part.name}.step", note="bladder mould (not part of the unit); mass at 100 % infill"),)


@dataclass(frozen=True)
class Part:
    """One CAD part: how it is built, what it is made of, where it goes, how it is drawn and billed."""

    name: str  #: file stem, STEP product name, label
    title: str  #: human name (drawings, BOM, legends)
    group: str  #: one of :data:`GROUPS`
    build: Callable[[PartContext], Solid]  #: the solid (assembly or mould frame), mm
    material: Callable[[Design], PartMaterial]  #: resolved from the design's fixed materials
    colour: tuple[float, float, float]  #: RGB 0..1 (STEP colour, renders, GLB, drawings)
    volume_mm3: Callable[[Layout], float] | None = None  #: closed-form volume, mm³ (None: measured only)
    files: tuple[str, ...] = ("step", "stl")  #: exported formats
    moves: bool = False  #: depends on the piston displacement x
    bom: BomHook | None = made_part  #: its lines of the bill of materials (None: give ``not_on_bom``)
    not_on_bom: str = ""  #: why the part has no line of its own (required when ``bom`` is None)
    drawing: DrawingHook | None = None  #: its dimensioned sheet (None: no sheet of its own)
    hatch: str | None = "metal"  #: section hatch on the drawings, one of :data:`HATCHES`
    features: FeatureHook | None = None  #: its machined features (cylinders, grooves, holes, threads, chamfers)
    finish: str = ""  #: surface treatment and finish, for the title block

    def __post_init__(self) -> None:
        if self.group not in GROUPS:
            raise ValueError(f"part {self.name!r}: group must be one of {GROUPS}, got {self.group!r}")
        bad = set(self.files) - {"step", "stl"}
        if bad:
            raise ValueError(f"part {self.name!r}: unknown file formats {sorted(bad)}")
        if (self.bom is None) == (not self.not_on_bom):
            raise ValueError(f"part {self.name!r}: give either a BOM hook or the reason it is not on the bill "
                             f"(not_on_bom), not {'neither' if self.bom is None else 'both'}")
        if self.hatch not in HATCHES:
            raise ValueError(f"part {self.name!r}: hatch must be one of {HATCHES}, got {self.hatch!r}")


def structural_material(field: str, process: str) -> Callable[[Design], PartMaterial]:
    """A part's material: the structural material the design names in ``fixed.<field>``.

    Parameters
    ----------
    field : str
        Field of :class:`~vvea_design.spring.design.FixedParameters` holding a structural-material key
        (``"housing_material"``, ``"rod_material"``, ``"support_ring_material"``).
    process : str
        How the part is made (``"machined"``, ``"turned"``, ``"printed"``).

    Returns
    -------
    callable
        ``resolve(design) -> PartMaterial`` (name, density in g/mm³, process).
    """
    def resolve(d: Design) -> PartMaterial:
        m = get_material(getattr(d.fixed, field))
        return PartMaterial(m.name, m.density_g_per_mm3, process)

    return resolve


def fixed_material(key: str, process: str) -> Callable[[Design], PartMaterial]:
    """A part's material: one structural material whatever the design.

    Parameters
    ----------
    key : str
        Key of :data:`~vvea_design.materials.structural.MATERIALS` (e.g. ``"pla"``).
    process : str
        How the part is made (``"machined"``, ``"turned"``, ``"printed"``).

    Returns
    -------
    callable
        ``resolve(design) -> PartMaterial`` (name, density in g/mm³, process).
    """
    def resolve(d: Design) -> PartMaterial:
        m = get_material(key)
        return PartMaterial(m.name, m.density_g_per_mm3, process)

    return resolve


def _const(name: str, density: float | None, process: str) -> Callable[[Design], PartMaterial]:
    return lambda d: PartMaterial(name, density, process)


def revolved_volume_mm3(pts) -> float:
    """Volume of a closed meridian polygon (r, z) revolved about the axis (a sum of frusta), mm³.

    Parameters
    ----------
    pts : sequence of (float, float)
        The corners (r >= 0, z), mm, in order.

    Returns
    -------
    float
        Volume, mm³.
    """
    v = 0.0
    for (r0, z0), (r1, z1) in zip(pts, [*pts[1:], pts[0]]):
        v += (z1 - z0) * (r0 * r0 + r0 * r1 + r1 * r1)
    return abs(v) * math.pi / 3


def _outer_tube_mm3(lay: Layout) -> float:
    """The outer tube as drawn: its meridian outline (the ends over the joint's threads at the pitch cylinder, the
    ring's counterbore; the plain tube between the base and the cap without a joint), less the bore's lead-in
    chamfers and the retaining ring's groove, mm³."""
    v = revolved_volume_mm3(outer_tube_profile(lay))
    j = lay.joint
    li = lay.lead_in_outer_bottom  # the bore's lead-in chamfers at both ends (behind a thread: at the step)
    v -= lead_in_ring_mm3(lay.r_bore, li.depth_mm, li.length_mm, outward=True)
    if lay.lead_in_counterbore is not None:  # ring_top: at the counterbore's mouth, where the plug enters
        li = lay.lead_in_counterbore
        v -= lead_in_ring_mm3(j.ring.bore_mm / 2, li.depth_mm, li.length_mm, outward=True)
    if lay.lead_in_outer_top is not None:  # where the cap's ring enters the bore (ring_top: the counterbore's step)
        li = lay.lead_in_outer_top
        v -= lead_in_ring_mm3(lay.r_bore, li.depth_mm, li.length_mm, outward=True)
    if j.ring is not None:  # the retaining ring's groove in the counterbore
        v -= math.pi * ((j.ring.groove_diameter_mm / 2) ** 2 - (j.ring.bore_mm / 2) ** 2) * (j.ring.groove[1]
                                                                                              - j.ring.groove[0])
    return v


def _inner_tube_mm3(lay: Layout) -> float:
    v = math.pi * (lay.r_inner_tube**2 - lay.r_piston**2) * (lay.z_cap - lay.z_base_top)
    li, _ = tube_bottom_lead_in(lay)  # the bore's lead-in for the piston's rings (and the seat's) at the bottom end
    v -= lead_in_ring_mm3(lay.r_piston, li.depth_mm, li.length_mm, outward=True)
    s = lay.seats
    if s is not None:  # the tube's ends in the end pieces' seats, the top end's lead-in, the fill tube's neck
        ends = (lay.z_base_top - s.z_base_floor) + (s.z_top_end - lay.z_cap if s.top is not None else 0.0)
        v += math.pi * (lay.r_inner_tube**2 - lay.r_piston**2) * ends
        if s.top is not None:
            v -= lead_in_ring_mm3(lay.r_piston, s.lead_in_top.depth_mm, s.lead_in_top.length_mm, outward=True)
        if s.fill is not None:
            v += math.pi * (s.neck_radius_mm**2 - lay.r_fill_tube_bore**2) * (s.z_neck_top - lay.z_cap)
            v -= lead_in_ring_mm3(s.neck_radius_mm, s.lead_in_neck.depth_mm, s.lead_in_neck.length_mm, outward=False)
    if lay.has_bulkhead:  # + the bulkhead web and the fill tube, minus the tube's bore through the web
        d = lay.design
        v += math.pi * (lay.r_piston**2 - lay.r_fill_tube_bore**2) * d.bulkhead_mm
        v += math.pi * (lay.r_fill_tube_out**2 - lay.r_fill_tube_bore**2) * d.top_space_length_mm
    if lay.has_top_annulus:  # + the collar, minus the bladder's upper cuff (its groove) and the slots
        ri, ro, e, lb = lay.r_bladder_in, lay.r_bladder_out, lay.bead_mm, lay.bead_length
        v += math.pi * (lay.r_bore**2 - lay.r_inner_tube**2) * (lay.z_collar1 - lay.z_free1)
        v -= math.pi * (ro**2 - ri**2) * (lay.z_bladder1 - lay.z_free1)
        v -= math.pi * ((ro + e) ** 2 - ro**2 + ri**2 - (ri - e) ** 2) * lb
        v -= lay.design.cross_slot_volume_mm3
        v -= math.pi * (lay.r_bore**2 - (lay.collar_seal.groove_diameter_mm / 2) ** 2) * lay.collar_seal.width_mm
    return v


_HOUSING = structural_material("housing_material", "machined")
_ANODISED = "clear anodised ISO 7599, 10 µm; dimensions after anodising"
_GREY = (0.72, 0.74, 0.78)
_MOULD = (0.55, 0.75, 0.95)

_MOULD_PLA = fixed_material(MOULD_MATERIAL, "printed")
_GAS = "gas domain (nitrogen charged through the fill valves), not an item"

#: The part table (order = build, file, legend, sheet and bill order).
PARTS: tuple[Part, ...] = (
    Part("housing", "housing (united)", "assembly", lambda c: c.housing, _HOUSING, _GREY, bom=None,
         not_on_bom="made as its four machined pieces, each on the bill"),
    Part("housing_base", "base (valves, channels, rod seal)", "machined", lambda c: c.housing_pieces["housing_base"],
         _HOUSING, (0.66, 0.68, 0.72), drawing=housing_base_sheet, features=base_features, finish=_ANODISED),
    Part("housing_outer_tube", "outer tube", "machined", lambda c: c.housing_pieces["housing_outer_tube"], _HOUSING,
         (0.78, 0.80, 0.84), volume_mm3=_outer_tube_mm3, drawing=outer_tube_sheet, features=outer_tube_features,
         finish=_ANODISED),
    Part("housing_inner_tube", "inner tube (piston bore)", "machined",
         lambda c: c.housing_pieces["housing_inner_tube"], _HOUSING, (0.60, 0.62, 0.66),
         volume_mm3=_inner_tube_mm3, drawing=inner_tube_sheet, features=inner_tube_features,
         finish="hard anodised ISO 10074, 25 µm; bore honed after anodising"),
    Part("housing_top_cap", "top cap (charging ports, bladder clamp)", "machined",
         lambda c: c.housing_pieces["housing_top_cap"], _HOUSING, (0.70, 0.72, 0.76), drawing=top_cap_sheet,
         features=top_cap_features, finish=_ANODISED),
    Part("piston", "piston with rod", "assembly", lambda c: piston(c.lay, c.x_mm),
         structural_material("rod_material", "turned"), (0.45, 0.47, 0.52), volume_mm3=piston_volume_mm3, moves=True,
         drawing=piston_sheet, hatch="steel", features=piston_features,
         finish="quenched and tempered (ISO 683-2); rod hard-chromed ISO 6158, 20 µm, ground after plating"),
    Part("bladder", "bladder (cast silicone sleeve)", "assembly", lambda c: bladder(c.lay),
         _const(SILICONE, DENSITY_SILICONE_g_per_mm3, "cast"), (0.95, 0.75, 0.20), volume_mm3=bladder_volume_mm3,
         bom=cast_part, hatch="rubber"),
    Part("support_ring", "support ring", "assembly", lambda c: support_ring(c.lay),
         structural_material("support_ring_material", "printed"), (0.15, 0.15, 0.15),
         volume_mm3=support_ring_volume_mm3, hatch="plastic"),
    Part("mould_half_a", "mould half A (pins)", "mould", lambda c: c.mould.half_a, _MOULD_PLA, _MOULD,
         bom=tooling_part, hatch="plastic"),
    Part("mould_half_b", "mould half B (pin holes)", "mould", lambda c: c.mould.half_b, _MOULD_PLA, _MOULD,
         bom=tooling_part, hatch="plastic"),
    Part("mould_core", "mould core", "mould", lambda c: c.mould.core, _MOULD_PLA, (0.85, 0.85, 0.85),
         volume_mm3=mould_core_volume_mm3, bom=tooling_part, hatch="plastic"),
    # negative chamber blue, positive chamber red (paper Fig. 2)
    Part("gas_chamber_1", "gas, chamber 1", "gas", lambda c: gas_chamber_1(c.lay, c.x_mm),
         _const("gas (nitrogen), chamber 1", None, "gas"), (0.20, 0.40, 0.95),
         volume_mm3=lambda lay: lay.design.V1_mm3 - lay.design.fixed.dead_volume_1_mm3,
         files=("stl",), moves=True, bom=None, not_on_bom=_GAS, hatch=None),
    Part("gas_chamber_2", "gas, chamber 2", "gas", lambda c: gas_chamber_2(c.lay, c.x_mm),
         _const("gas (nitrogen), chamber 2", None, "gas"), (0.95, 0.25, 0.20),
         volume_mm3=lambda lay: lay.design.V2_mm3 - lay.design.fixed.dead_volume_2_mm3,
         files=("stl",), moves=True, bom=None, not_on_bom=_GAS, hatch=None),
)

if len({p.name for p in PARTS}) != len(PARTS):  # pragma: no cover - table integrity
    raise RuntimeError("duplicate part names in vvea_design.cad.registry.PARTS")


def all_parts() -> tuple[Part, ...]:
    """The part table, looked up at call time (every consumer goes through this or :func:`parts_in`).

    Returns
    -------
    tuple of Part
        Every entry of :data:`PARTS`, in table (build, file and legend) order.
    """
    return PARTS


def get_part(name: str) -> Part:
    """The table entry of part ``name``.

    Parameters
    ----------
    name : str
        Part name (file stem, STEP product name), e.g. ``"piston"``.

    Returns
    -------
    Part
        Its builder, material, colour, closed-form volume (mm³) and file formats.

    Raises
    ------
    KeyError
        If no part is called ``name`` (the message lists the known parts).
    """
    for p in PARTS:
        if p.name == name:
            return p
    raise KeyError(f"unknown CAD part {name!r}; known: {', '.join(p.name for p in PARTS)}")


def parts_in(*groups: str) -> tuple[Part, ...]:
    """The table entries of the given groups, in table order.

    Parameters
    ----------
    *groups : str
        Names from :data:`GROUPS` (``"assembly"``, ``"machined"``, ``"mould"``, ``"gas"``).

    Returns
    -------
    tuple of Part
        The entries whose group is one of ``groups``, in table order.

    Raises
    ------
    ValueError
        If a group is not one of :data:`GROUPS`.
    """
    for g in groups:
        if g not in GROUPS:
            raise ValueError(f"unknown part group {g!r}; known: {GROUPS}")
    return tuple(p for p in PARTS if p.group in groups)
