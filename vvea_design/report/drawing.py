"""Dimensioned workshop drawings (SVG per sheet, one multi-page PDF) from the
build123d model: the unit's section and a sheet per machined piece.

Geometry: every outline is the section of the part's build123d solid by a
meridian half-plane (``Solid.intersect`` with a planar face), so the drawing
shows what the STEP files hold. The unit's section is an *aligned* section
A-A: the left half lies in the valve plane (y = 0, x < 0: relief valve,
channels), the right half in the fill-port plane (x = 0, y > 0). Dimensions
come from the :class:`~vvea_design.cad.layout.Layout` the solids were built
from, and each dimension's anchor points are checked against the drawn
outline (:func:`check_anchors`, used by the tests).

Sheets are ISO A3 landscape at a true scale (1:1, 2:1, ... stated in the
title block), all dimensions in mm, text 2.5-3.5 mm. Drawn with matplotlib
(``Figure`` objects, no pyplot, no backend switch); SVG and PDF carry no date,
so the files are byte-stable.

Tolerances: general tolerances ISO 2768-m; the sliding fits are
ISO 286 H8/f7 (piston in its bore, rod in the base), their deviations
computed from the ISO 286 tables below; seal grooves from the O-ring's gland
(:mod:`vvea_design.cad.seals`).
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from ..cad.assembly import CadModel
from ..cad.registry import get_part

__all__ = ["Dim", "Leader", "Detail", "SheetSpec", "DrawingSet", "fit_deviations_um", "sheet_specs", "sheet_figure",
           "write_drawings", "check_anchors", "section_loops", "SHEET_MM"]

#: ISO A3 landscape, mm.
SHEET_MM = (420.0, 297.0)
_PT_PER_MM = 72.0 / 25.4
_TEXT_PT = 9.0  # ~3.2 mm font size, ~2.3 mm cap height
_SMALL_PT = 7.5
_TIER_MM = 6.5  # spacing of stacked dimension lines on paper
_GAP_MM = 6.0  # first dimension line from the outline
_SCALES = (5.0, 2.0, 1.0, 0.5)  # ISO 5455
_DETAIL_W = 150.0  # width of the detail area at the right of the sheet, mm

# ISO 286-1 standard tolerance grades (µm) and the fundamental deviation of shafts "f" (µm) by nominal size
# range (over, up to] in mm.
_ISO286 = (  # (over, up to, IT7, IT8, es of f)
    (3, 6, 12, 18, -10), (6, 10, 15, 22, -13), (10, 18, 18, 27, -16), (18, 30, 21, 33, -20),
    (30, 50, 25, 39, -25), (50, 80, 30, 46, -30), (80, 120, 35, 54, -36),
)


def fit_deviations_um(nominal_mm: float, fit: str) -> tuple[float, float]:
    """ISO 286 deviations of an H8 hole or an f7 shaft.

    Parameters
    ----------
    nominal_mm : float
        Nominal size, mm (3 ... 120).
    fit : str
        ``"H8"`` or ``"f7"``.

    Returns
    -------
    (float, float)
        Upper and lower deviation, µm.

    Raises
    ------
    ValueError
        For another fit or a size outside the table.
    """
    for lo, hi, it7, it8, es_f in _ISO286:
        if lo < nominal_mm <= hi:
            if fit == "H8":
                return float(it8), 0.0
            if fit == "f7":
                return float(es_f), float(es_f - it7)
            raise ValueError(f"fit must be 'H8' or 'f7', got {fit!r}")
    raise ValueError(f"nominal size {nominal_mm:g} mm outside the ISO 286 table (3-120 mm)")


def _fit_text(d_mm: float, fit: str) -> str:
    up, lo = fit_deviations_um(d_mm, fit)
    return f"Ø{d_mm:.2f} {fit} ({up / 1000:+.3f}/{lo / 1000:+.3f})".replace("+0.000", "0")


# --------------------------------------------------------------------------- geometry
def section_loops(solid, plane: str, u_min: float, u_max: float) -> list[np.ndarray]:
    """Closed outlines of a solid cut by a meridian plane.

    Straight edges give their end points, curved ones 24 points; the loops are
    sorted and canonicalised (start vertex, counter-clockwise) so the output
    does not depend on OCCT's result order.

    Parameters
    ----------
    solid : build123d.Solid
        Solid in the assembly frame, mm.
    plane : str
        ``"xz"`` (u = x, at y = 0) or ``"yz"`` (u = y, at x = 0).
    u_min, u_max : float
        Part of the plane kept, mm.

    Returns
    -------
    list of ndarray
        Closed loops of (u, z) points, mm.
    """
    from build123d import Face, Wire

    bb = solid.bounding_box()
    z0, z1 = bb.min.Z - 1.0, bb.max.Z + 1.0
    if plane == "xz":
        pts = [(u_min, 0, z0), (u_max, 0, z0), (u_max, 0, z1), (u_min, 0, z1)]
    elif plane == "yz":
        pts = [(0, u_min, z0), (0, u_max, z0), (0, u_max, z1), (0, u_min, z1)]
    else:
        raise ValueError(f"plane must be 'xz' or 'yz', got {plane!r}")
    cutter = Face(Wire.make_polygon(pts, close=True))
    sec = solid.intersect(cutter)
    loops = []
    if sec is None:
        return loops
    k = 0 if plane == "xz" else 1
    for face in sec.faces():
        for wire in [face.outer_wire(), *face.inner_wires()]:
            pts_uz: list[tuple[float, float]] = []
            for edge in wire.order_edges():
                n = 2 if edge.geom_type.name == "LINE" else 24
                ps = [edge.position_at(t) for t in np.linspace(0.0, 1.0, n)]
                seg = [((p.X, p.Y)[k], p.Z) for p in ps]
                if pts_uz and math.dist(pts_uz[-1], seg[-1]) < math.dist(pts_uz[-1], seg[0]):
                    seg = seg[::-1]
                pts_uz.extend(seg if not pts_uz else seg[1:])
            loops.append(_canonical(np.asarray(pts_uz, dtype=float)))
    # OCCT's boolean result order is not stable between calls: sort (and canonicalise) for byte-stable files
    return sorted(loops, key=lambda lp: (round(float(lp[:, 1].min()), 6), round(float(lp[:, 0].min()), 6),
                                         len(lp), round(float(lp.sum()), 6)))


def _canonical(loop: np.ndarray) -> np.ndarray:
    """A closed loop started at its lowest-leftmost vertex, counter-clockwise, closed."""
    pts = loop[:-1] if len(loop) > 1 and np.allclose(loop[0], loop[-1]) else loop
    area2 = float(np.sum(pts[:, 0] * np.roll(pts[:, 1], -1) - np.roll(pts[:, 0], -1) * pts[:, 1]))
    if area2 < 0:
        pts = pts[::-1]
    r = np.round(pts, 9)
    k = min(range(len(r)), key=lambda i: (r[i, 1], r[i, 0]))
    pts = np.roll(pts, -k, axis=0)
    return np.vstack([pts, pts[:1]])


# --------------------------------------------------------------------------- specs
@dataclass(frozen=True)
class Dim:
    """A linear dimension between two anchor points on the outline (model mm).

    ``axis`` "z": vertical (measures z1 - z0, line on ``side`` "left"/"right");
    ``axis`` "u": horizontal (measures u1 - u0, line on ``side`` "top"/"bottom").
    """

    axis: str
    a: tuple[float, float]  #: first anchor (u, z)
    b: tuple[float, float]  #: second anchor (u, z)
    side: str  #: left/right (axis z), top/bottom (axis u), or "inside": the line at the anchors' u, no extension
    text: str = ""  #: label; default the measured length with two decimals
    on_axis: bool = False  #: an anchor is a feature's axis (bore, channel), not a point of the outline

    @property
    def value_mm(self) -> float:
        return abs(self.b[1] - self.a[1]) if self.axis == "z" else abs(self.b[0] - self.a[0])

    def label(self) -> str:
        """The text written on the dimension line.

        Returns
        -------
        str
            :attr:`text` when set, else the measured length :attr:`value_mm` in mm with two decimals.
        """
        return self.text or f"{self.value_mm:.2f}"


@dataclass(frozen=True)
class Leader:
    """A note with a line to a point of the drawing (model mm)."""

    at: tuple[float, float]
    text: str
    side: str = "right"


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
class Detail:
    """An enlarged view of a window of the sheet's regions (model mm) with its own dimensions."""

    window: tuple[float, float, float, float]  #: u0, u1, z0, z1
    scale: float
    dims: list[Dim]
    leaders: list[Leader] = field(default_factory=list)
    label: str = "A"


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


_HATCH = {"metal": "////", "steel": "\\\\\\\\", "plastic": "xx", "rubber": None}


def _region(model: CadModel, name: str, plane: str, u_min: float, u_max: float, solid=None, hatch="metal",
            alpha=1.0, dashed=False) -> Region:
    part = get_part(name) if name in {p for p in model.solids} else None
    s = solid if solid is not None else model.solids[name]
    colour = part.colour if part else (0.8, 0.8, 0.8)
    return Region(name, tuple(section_loops(s, plane, u_min, u_max)), colour,
                  _HATCH.get(hatch, hatch), alpha, True, dashed)


def _general_notes(model: CadModel) -> list[str]:
    lay = model.layout
    ps, rs = lay.piston_seal, lay.rod_seal
    return [
        "All dimensions in mm. General tolerances ISO 2768-m. Break sharp edges 0.2 x 45°.",
        f"Sliding fits ISO 286 H8/f7: piston bore {_fit_text(2 * lay.r_piston, 'H8')}, "
        f"piston {_fit_text(2 * lay.r_piston, 'f7')};",
        f"rod bore {_fit_text(2 * lay.r_rod, 'H8')}, rod {_fit_text(2 * lay.r_rod, 'f7')}. "
        "Seal running surfaces Ra 0.4.",
        f"Piston seals: 2x O-ring {ps.oring.name}; groove Ø{ps.groove_diameter_mm:.2f} h9 x {ps.width_mm:.2f} +0.1 "
        f"(stretch {100 * ps.stretch:.1f} %, squeeze {100 * ps.squeeze:.0f} %).",
        f"Rod seal: O-ring {rs.oring.name}; groove Ø{rs.groove_diameter_mm:.2f} H9 x {rs.width_mm:.2f} +0.1 "
        f"(stretch {100 * rs.stretch:.1f} %, squeeze {100 * rs.squeeze:.0f} %).",
    ]


def _unit_spec(model: CadModel) -> SheetSpec:
    lay, d = model.layout, model.design
    c = lay.cad
    R = lay.r_outer
    regions: list[Region] = []
    anchors: list[np.ndarray] = []
    from ..cad._shapes import ring

    styles = {"housing": "metal", "piston": "steel", "bladder": "rubber", "support_ring": "plastic"}
    for name, hatch in styles.items():
        left = _region(model, name, "xz", -R - 5, 0.0, hatch=hatch)
        right = _region(model, name, "yz", 0.0, R + 5, hatch=hatch)
        regions.append(Region(name, left.loops + right.loops, left.colour, left.hatch))
        anchors.extend(left.loops + right.loops)
    for name in ("gas_chamber_1", "gas_chamber_2"):
        gl = _region(model, name, "xz", -R - 5, 0.0)
        gr = _region(model, name, "yz", 0.0, R + 5)
        regions.insert(0, Region(name, gl.loops + gr.loops, gl.colour, None, 0.18, outline=False))
    fluid = ring(lay.r_rod, lay.r_piston, lay.z_base_top, lay.z_piston_bottom(0.0))
    fl = section_loops(fluid, "xz", -R, 0.0) + section_loops(fluid, "yz", 0.0, R)
    regions.insert(0, Region("fluid", tuple(fl), (0.25, 0.75, 0.35), None, 0.18, outline=False))
    from ..cad._shapes import cylinder

    zgt = lay.z_piston_top(d.fixed.travel_mm)
    ghost = cylinder(lay.r_piston, lay.z_piston_bottom(d.fixed.travel_mm), zgt)  # piston head at full stroke
    gl = section_loops(ghost, "xz", -R, 0.0) + section_loops(ghost, "yz", 0.0, R)
    regions.append(Region("piston_at_travel", tuple(gl), (0.3, 0.3, 0.3), None, 0.0, True, dashed=True))

    zr = lay.z_piston_bottom(0.0) - d.rod_length_mm
    zt, zb0, zc = lay.z_top, lay.z_base_top, lay.z_cap
    dims = [
        Dim("z", (-R, 0.0), (-R, zt), "left", f"{zt:.2f} (housing)"),
        Dim("z", (-R, 0.0), (-R, zb0), "left"),
        Dim("z", (-R, zc), (-R, zt), "left"),
        Dim("z", (-lay.r_bore, lay.z_free0), (-lay.r_bore, lay.z_free1), "left",
            f"{lay.z_free1 - lay.z_free0:.2f} (bladder free)"),
        Dim("z", (-lay.r_rod, zr), (-lay.r_rod, 0.0), "left", f"{-zr:.2f} (rod at x = 0)"),
        Dim("z", (-0.45 * lay.r_piston, lay.z_piston_top(d.fixed.travel_mm)),
            (-0.45 * lay.r_piston, lay.z_piston_top(0.0)), "inside", f"stroke {d.fixed.travel_mm:.2f}", on_axis=True),
        Dim("z", (0.5 * (lay.r_rod + lay.r_piston), zb0), (0.5 * (lay.r_rod + lay.r_piston), lay.z_piston_bottom(0.0)),
            "inside", f"{lay.z_piston_bottom(0.0) - zb0:.2f} (fluid)", on_axis=True),
        Dim("z", (0.45 * lay.r_piston, lay.z_piston_top(0.0)), (0.45 * lay.r_piston, lay.z_bulkhead0), "inside",
            f"{lay.z_bulkhead0 - lay.z_piston_top(0.0):.2f} (chamber 1)", on_axis=True),
        Dim("u", (-R, zt), (R, zt), "top", f"Ø{2 * R:.2f}"),
        Dim("u", (-lay.r_bore, lay.z_free1), (lay.r_bore, lay.z_free1), "top", f"Ø{2 * lay.r_bore:.2f}"),
        Dim("u", (-lay.r_inner_tube, lay.z_free1), (lay.r_inner_tube, lay.z_free1), "top",
            f"Ø{2 * lay.r_inner_tube:.2f}"),
        Dim("u", (-lay.r_piston, zc), (lay.r_piston, zc), "top", _fit_text(2 * lay.r_piston, "H8")),
        Dim("u", (-lay.r_rod, zr), (lay.r_rod, zr), "bottom", _fit_text(2 * lay.r_rod, "f7")),
    ]
    zm = 0.5 * (lay.z_free0 + lay.z_free1)
    ps, rs = lay.piston_seal, lay.rod_seal
    g_z = lay.z_piston_bottom(0.0) + 0.73 * d.fixed.piston_height_mm
    leaders = [
        Leader((-lay.r_bore - 0.5 * d.outer_wall_mm, zm + 20), f"outer tube wall {d.outer_wall_mm:.2f}",
               "left"),
        Leader((-lay.r_inner_tube + 0.5 * d.inner_tube_wall_mm, zm - 20),
               f"inner tube wall {d.inner_tube_wall_mm:.2f}", "left"),
        Leader((-(lay.r_outer - 1.0), lay.z_valve), f"relief valve bore Ø{lay.relief_d:g}, seat Ø{c.relief_seat_mm:g}",
               "left"),
        Leader((-lay.r_ring_channel, zb0 - 1.0), f"fluid channels Ø{lay.ring_channel_d:.2f} / "
                                                 f"Ø{lay.base_channel_d:.2f}", "left"),
        Leader((0.0 if lay.has_bulkhead else lay.r_port1, zt - 1.0),
               f"chamber 1 fill port Ø{(2 * lay.r_fill_tube_bore) if lay.has_bulkhead else lay.fill_port_d:.2f}"
               + (" (fill tube through the bulkhead)" if lay.has_bulkhead else "") + ", M5 counterbore", "right"),
        Leader((lay.r_port2, 1.0), f"chamber 2 fill port Ø{lay.fill_port_d:.2f} through base and support ring",
               "right") if lay.has_top_annulus else
        Leader((lay.r_port2, zt - 2.0), f"chamber 2 fill port Ø{lay.fill_port_d:.2f}", "right"),
        Leader((0.5 * (ps.groove_diameter_mm / 2 + lay.r_piston), g_z),
               f"2x O-ring {ps.oring.code}: {ps.oring.inner_diameter_mm:.2f} x {ps.oring.cross_section_mm:.2f}",
               "right"),
        Leader((0.5 * (lay.r_rod + rs.groove_diameter_mm / 2), 0.5 * sum(lay.z_rod_seal)),
               f"O-ring {rs.oring.code}: {rs.oring.inner_diameter_mm:.2f} x {rs.oring.cross_section_mm:.2f}", "right"),
        Leader((0.5 * (lay.r_bladder_in + lay.r_bladder_out), zm), "bladder (cast silicone)", "right"),
        Leader((0.5 * (lay.r_inner_tube + lay.r_bore), zb0 + 0.5 * lay.clamp), "support ring", "right"),
        Leader((0.5 * lay.r_piston, 0.5 * (lay.z_piston_top(0.0) + lay.z_bulkhead0)), "gas chamber 1", "right"),
        Leader((lay.r_bore - 0.5, zm - 12.0), "gas chamber 2", "right"),
        Leader((0.5 * (lay.r_rod + lay.r_piston), 0.5 * (zb0 + lay.z_piston_bottom(0.0))), "fluid column",
               "right"),
        Leader((lay.r_piston - 0.5, zgt), "piston at full stroke (dashed)", "right"),
    ]
    if lay.has_top_annulus:  # the collar (top bladder clamp + plate) and the chamber-1 annulus above it
        zcol = lay.z_collar1
        dims.append(Dim("z", (-lay.r_bore, lay.z_free1), (-lay.r_bore, zcol), "left",
                        f"{zcol - lay.z_free1:.2f} (collar)"))
        leaders += [
            Leader((-0.5 * (lay.r_inner_tube + lay.r_bore), 0.5 * (lay.z_free1 + zcol)),
                   f"collar on the inner tube: top bladder clamp + plate {d.collar_mm:.2f}", "left"),
            Leader((0.5 * (lay.r_inner_tube + lay.r_bore), 0.5 * (zcol + zc)),
                   f"gas chamber 1 (annulus, joined to the bore by {c.cross_slots} slots at 45°)", "right"),
        ]
    return SheetSpec(
        "unit_section", "Spring-damper unit: section A-A", regions, dims, leaders, _general_notes(model),
        material="see parts list (bom.csv)", view_note="Section A-A, aligned: left half in the valve plane (y = 0), "
                                                     "right half in the fill-port plane (x = 0); x = 0 (piston up)",
        extent=(-R, R, zr, zt), anchor_loops=anchors)


def _piece_spec(model: CadModel, name: str) -> SheetSpec:
    lay, d = model.layout, model.design
    c = lay.cad
    part = get_part(name)
    solid = model.solids[name]
    bb = solid.bounding_box()
    R = max(abs(bb.min.X), abs(bb.max.X), abs(bb.min.Y), abs(bb.max.Y))
    plane = "yz" if name == "housing_top_cap" else "xz"
    hatch = "steel" if name == "piston" else "metal"
    reg = _region(model, name, plane, -R - 5, R + 5, hatch=hatch)
    z0, z1 = bb.min.Z, bb.max.Z
    mat = part.material(d)
    dims: list[Dim] = []
    leaders: list[Leader] = []
    detail: Detail | None = None
    notes = [_general_notes(model)[0]]
    zb0, zc, zt = lay.z_base_top, lay.z_cap, lay.z_top
    if name == "housing_outer_tube":
        dims = [Dim("z", (-R, z0), (-R, z1), "left"),
                Dim("u", (-R, z1), (R, z1), "top", f"Ø{2 * R:.2f}"),
                Dim("u", (-lay.r_bore, z1), (lay.r_bore, z1), "top", f"Ø{2 * lay.r_bore:.2f}")]
        leaders = [Leader((R - 0.5 * d.outer_wall_mm, 0.5 * (z0 + z1)), f"wall {d.outer_wall_mm:.2f}")]
    elif name == "housing_inner_tube" and lay.has_top_annulus:
        ri, zcol = lay.r_inner_tube, lay.z_collar1
        dims = [Dim("z", (-ri, z0), (-ri, z1), "left"),
                Dim("z", (-R, lay.z_free1), (-R, zcol), "left", f"{zcol - lay.z_free1:.2f} (collar)"),
                Dim("z", (-ri, zcol), (-ri, z1), "left"),
                Dim("u", (-ri, z1), (ri, z1), "top", f"Ø{2 * ri:.2f}"),
                Dim("u", (-R, zcol), (R, zcol), "top", f"Ø{2 * R:.2f}"),
                Dim("u", (-lay.r_piston, z0), (lay.r_piston, z0), "bottom", _fit_text(2 * lay.r_piston, "H8"))]
        leaders = [Leader((ri - 0.5 * d.inner_tube_wall_mm, 0.5 * (z0 + lay.z_free1)),
                          f"wall {d.inner_tube_wall_mm:.2f}; bore Ra 0.4"),
                   Leader((0.5 * (ri + R), zcol - 0.5), f"collar plate {d.collar_mm:.2f} over the bladder clamp"),
                   Leader((lay.collar_seal.groove_diameter_mm / 2 - 0.2, 0.5 * sum(lay.z_collar_seal)),
                          f"groove root Ø{lay.collar_seal.groove_diameter_mm:.2f} h9 "
                          f"(O-ring {lay.collar_seal.oring.code})"),
                   Leader((-(lay.r_bladder_out + 0.1), lay.z_free1 + 0.5 * lay.cuff),
                          "bladder cuff groove (fits the cast bladder)", "left")]
        notes += [_general_notes(model)[1],
                  f"Top end: {c.cross_slots} slots {math.degrees(lay.slot_angle_rad):.1f}° wide x "
                  f"{lay.slot_height:.2f} deep, centred at 45° + k·{360 / c.cross_slots:g}° (chamber 1: bore to annulus).",
                  f"Collar to outer-tube bore: static seal, O-ring {lay.collar_seal.oring.name}; groove "
                  f"Ø{lay.collar_seal.groove_diameter_mm:.2f} h9 x {lay.collar_seal.width_mm:.2f} +0.1 "
                  f"(squeeze {100 * lay.collar_seal.squeeze:.0f} %)."]
    elif name == "housing_inner_tube":
        dims = [Dim("z", (-R, z0), (-R, z1), "left"),
                Dim("u", (-R, z1), (R, z1), "top", f"Ø{2 * R:.2f}"),
                Dim("u", (-lay.r_piston, z0), (lay.r_piston, z0), "bottom", _fit_text(2 * lay.r_piston, "H8"))]
        leaders = [Leader((R - 0.5 * d.inner_tube_wall_mm, 0.5 * (z0 + z1)),
                          f"wall {d.inner_tube_wall_mm:.2f}; bore Ra 0.4")]
        notes.append(_general_notes(model)[1])
    elif name == "housing_base":
        zv = lay.z_valve
        dims = [Dim("z", (-R, 0.0), (-R, zb0), "left"),
                Dim("z", (-R, 0.0), (-R, zv), "left", f"{zv:.2f}", on_axis=True),
                Dim("z", (0.5 * lay.r_rod, 0.0), (0.5 * lay.r_rod, lay.z_rod_seal[0]), "inside", on_axis=True),
                Dim("u", (-R, zb0), (R, zb0), "top", f"Ø{2 * R:.2f}"),
                Dim("u", (-lay.r_ring_channel, zb0), (lay.r_ring_channel, zb0), "top",
                    f"{2 * lay.r_ring_channel:.2f} (channel axes)", on_axis=True),
                Dim("u", (-lay.r_channel_a, zb0), (lay.r_channel_a, zb0), "top",
                    f"{2 * lay.r_channel_a:.2f} (channel axes)", on_axis=True),
                Dim("u", (-lay.r_rod, 0.0), (lay.r_rod, 0.0), "bottom", _fit_text(2 * lay.r_rod, "H8"))]
        rs = lay.rod_seal
        leaders = [
            Leader((R - 1.0, zv), f"throttle valve bore Ø{lay.throttle_d:g} to x = {lay.x_valve_inner:.2f}, "
                                  f"axis {zv:.2f} from underside"),
            Leader((-R + 1.0, zv), f"relief bore Ø{lay.relief_d:g}, seat Ø{min(c.relief_seat_mm, lay.relief_d):g}",
                   "left"),
            Leader((rs.groove_diameter_mm / 2 - 0.2, 0.5 * sum(lay.z_rod_seal)),
                   f"rod seal groove Ø{rs.groove_diameter_mm:.2f} H9 x {rs.width_mm:.2f} +0.1 "
                   f"(O-ring {rs.oring.code})"),
            Leader((lay.r_channel_a, zb0 - 1.0), f"2x channel Ø{lay.base_channel_d:.2f} to the valve bores"),
            Leader((-lay.r_ring_channel, zb0 - 1.0), f"2x channel Ø{min(lay.base_channel_d, lay.ring_channel_d):.2f}",
                   "left"),
        ]
        notes += [_general_notes(model)[2], _general_notes(model)[4],
                  f"Servo mount: 2x M3 (tap drill Ø{c.servo_screw_core_mm:g}) x {c.servo_screw_depth_mm:g} deep, "
                  f"±{lay.throttle_d / 2 + 3.5:.2f} either side of the throttle bore."]
        if lay.has_top_annulus:
            notes.append(f"Chamber-2 fill port: Ø{lay.fill_port_d:.2f} through at y = +{lay.r_port2:.2f}"
                         + (f", M5 counterbore Ø{c.fill_port_counterbore_mm:g} x {c.fill_port_counterbore_depth_mm:g}"
                            if lay.r_port2 + c.fill_port_counterbore_mm / 2 < lay.r_outer - 0.8 else "")
                         + "; continues through the support ring.")
    elif name == "housing_top_cap" and lay.has_top_annulus:
        dims = [Dim("z", (-R, zc), (-R, zt), "left"),
                Dim("u", (-R, zt), (R, zt), "top", f"Ø{2 * R:.2f}"),
                Dim("u", (0.0, zt), (lay.r_port1, zt), "top", f"{lay.r_port1:.2f} (port 1 axis)", on_axis=True)]
        leaders = [Leader((lay.r_port1, zt - 1.0), f"Ø{lay.fill_port_d:.2f} through (chamber 1), M5 counterbore "
                                                   f"Ø{c.fill_port_counterbore_mm:g} x {c.fill_port_counterbore_depth_mm:g}")]
        notes.append("Plain cap: the top bladder clamp is the inner tube's collar; chamber 2 is charged through the base.")
    elif name == "housing_top_cap":
        dims = [Dim("z", (-R, zc), (-R, zt), "left"),
                Dim("z", (-lay.r_bore, lay.z_free1), (-lay.r_bore, zc), "left", f"{zc - lay.z_free1:.2f} (clamp)"),
                Dim("u", (-R, zt), (R, zt), "top", f"Ø{2 * R:.2f}"),
                Dim("u", (-lay.r_bore, lay.z_free1), (lay.r_bore, lay.z_free1), "bottom", f"Ø{2 * lay.r_bore:.2f}"),
                Dim("u", (-lay.r_inner_tube, lay.z_free1), (lay.r_inner_tube, lay.z_free1), "bottom",
                    f"Ø{2 * lay.r_inner_tube:.2f}"),
                Dim("u", (0.0, zt), (lay.r_port2, zt), "top", f"{lay.r_port2:.2f} (port 2 axis)", on_axis=True),
                Dim("u", (0.0, zt), (lay.r_port1, zt), "top", f"{lay.r_port1:.2f} (port 1 axis)", on_axis=True)]
        leaders = [Leader((lay.r_port1, zt - 1.0), f"Ø{lay.fill_port_d:.2f} through, M5 counterbore "
                                                   f"Ø{c.fill_port_counterbore_mm:g} x {c.fill_port_counterbore_depth_mm:g}"),
                   Leader((lay.r_port2, lay.z_free1 + 1.0), f"Ø{lay.fill_port_d:.2f} through (chamber 2)"),
                   Leader((-(lay.r_bladder_out + 0.1), lay.z_free1 + 0.5 * lay.cuff),
                          "bladder cuff groove (fits the cast bladder)", "left")]
    elif name == "piston":
        ps = lay.piston_seal
        zpb, zpt = lay.z_piston_bottom(0.0), lay.z_piston_top(0.0)
        zend = zpb - d.rod_length_mm
        (g0a, g0b), (g1a, g1b) = [(zpb + d.fixed.piston_height_mm * q - ps.width_mm / 2,
                                   zpb + d.fixed.piston_height_mm * q + ps.width_mm / 2) for q in (0.27, 0.73)]
        rp, rg = lay.r_piston, ps.groove_diameter_mm / 2
        dims = [Dim("z", (-rp, zpb), (-rp, zpt), "left"),
                Dim("z", (-lay.r_rod, zend), (-lay.r_rod, zpb), "left", f"{d.rod_length_mm:.2f} (rod)"),
                Dim("u", (-rp, zpt), (rp, zpt), "top", _fit_text(2 * rp, "f7")),
                Dim("u", (-lay.r_rod, zend), (lay.r_rod, zend), "bottom", _fit_text(2 * lay.r_rod, "f7"))]
        leaders = [Leader((0.0, zend + c.rod_thread_depth_mm * 0.5),
                          f"M5 x {c.rod_thread_depth_mm:g} (tap drill Ø{c.rod_thread_core_mm:g})")]
        if lay.has_piston_pocket:  # the chamber-1 pocket in the crown (fixed.piston_pocket)
            a, zf = lay.r_pocket, zpt - d.piston_pocket_depth_mm
            dims += [Dim("u", (-a, zpt), (a, zpt), "top", f"Ø{2 * a:.2f} (pocket)"),
                     Dim("z", (-0.5 * a, zf), (-0.5 * a, zpt), "inside", f"{d.piston_pocket_depth_mm:.2f}",
                         on_axis=True)]
            leaders.append(Leader((0.5 * a, zf), f"pocket (chamber-1 gas), floor {d.piston_floor_mm:.2f}"))
        win = (rp - 6.0, rp + 1.0, zpb - 1.0, zpt + 1.0)
        detail = Detail(win, 5.0, [
            Dim("z", (rp, zpb), (rp, g0a), "right"),
            Dim("z", (rp, g0a), (rp, g0b), "right", f"{ps.width_mm:.2f} +0.1"),
            Dim("z", (rp, zpb), (rp, g1a), "right"),
            Dim("z", (rp, g1a), (rp, g1b), "right", f"{ps.width_mm:.2f} +0.1"),
            Dim("z", (rp, zpb), (rp, zpt), "right"),
            Dim("u", (rg, g1b), (rp, g1b), "top", f"{rp - rg:.3f} (groove depth)"),
        ], [Leader((rg, 0.5 * (g0a + g0b)), f"groove root Ø{2 * rg:.2f} h9; 2x O-ring {ps.oring.name}")])
        notes += [_general_notes(model)[1], _general_notes(model)[2], _general_notes(model)[3]]
    return SheetSpec(name, part.title[:1].upper() + part.title[1:], [reg], dims, leaders, notes,
                     material=mat.name, mass_g=float(solid.volume) * mat.density_g_per_mm3,
                     view_note=f"Section in the {'fill-port plane (x = 0)' if plane == 'yz' else 'valve plane (y = 0)'}",
                     extent=(-R, R, z0, z1), anchor_loops=list(reg.loops), detail=detail)


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
        The unit's section A-A, then every part the table marks ``drawing=True`` (model mm).

    Raises
    ------
    ValueError
        If a name in ``names`` is not a sheet.
    """
    from ..cad.registry import all_parts

    pieces = [p.name for p in all_parts() if p.drawing]
    if names is None:
        return [_unit_spec(model)] + [_piece_spec(model, name) for name in pieces]
    unknown = set(names) - {"unit_section", *pieces}
    if unknown:
        raise ValueError(f"no sheet named {sorted(unknown)}; sheets: unit_section, {', '.join(pieces)}")
    return ([_unit_spec(model)] if "unit_section" in names else []) + [_piece_spec(model, n) for n in pieces
                                                                      if n in names]


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


# --------------------------------------------------------------------------- layout
class _Paper:
    """Model mm -> paper mm at a scale, view placed in a box."""

    def __init__(self, scale: float, u0: float, z0: float, x0: float, y0: float) -> None:
        self.s, self.u0, self.z0, self.x0, self.y0 = scale, u0, z0, x0, y0

    def __call__(self, u, z):
        return self.x0 + self.s * (np.asarray(u) - self.u0), self.y0 + self.s * (np.asarray(z) - self.z0)


def _text_mm(text: str, pt: float = _TEXT_PT) -> float:
    """Approximate rendered width of ``text`` (DejaVu Sans), mm."""
    return 0.6 * len(text) * pt / _PT_PER_MM


def _tiers(items: list[tuple[float, float]]) -> list[int]:
    """Interval scheduling: tier index per (lo, hi) so intervals of one tier do not overlap (wider first)."""
    order = sorted(range(len(items)), key=lambda i: items[i][1] - items[i][0])
    tiers: list[list[tuple[float, float]]] = []
    out = [0] * len(items)
    for i in order:
        lo, hi = items[i]
        for k, tier in enumerate(tiers):
            if all(hi < a - 1.0 or lo > b + 1.0 for a, b in tier):
                tier.append((lo, hi))
                out[i] = k
                break
        else:
            tiers.append([(lo, hi)])
            out[i] = len(tiers) - 1
    return out


def sheet_figure(spec: SheetSpec, sheet_no: int = 1, n_sheets: int = 1, design_id: str = ""):
    """The A3 sheet of ``spec`` as a matplotlib Figure (paper mm coordinates; true scale).

    Parameters
    ----------
    spec : SheetSpec
        Regions, dimensions, leaders and notes (model mm).
    sheet_no, n_sheets : int
        For the title block.
    design_id : str
        Short design identifier for the title block.

    Returns
    -------
    matplotlib.figure.Figure
        Not saved; the caller writes SVG/PDF.
    """
    from matplotlib.figure import Figure
    from matplotlib.patches import PathPatch, Rectangle
    from matplotlib.path import Path as MPath

    W, H = SHEET_MM
    fig = Figure(figsize=(W / 25.4, H / 25.4))
    ax = fig.add_axes((0, 0, 1, 1))
    ax.set_xlim(0, W)
    ax.set_ylim(0, H)
    ax.set_aspect("equal")
    ax.axis("off")
    ax.add_patch(Rectangle((10, 10), W - 20, H - 20, fill=False, lw=0.7, color="black"))

    u0, u1, z0, z1 = spec.extent
    band = 40.0  # notes and title block at the bottom
    n_top = len([d for d in spec.dims if d.axis == "u" and d.side == "top"])
    n_bot = len([d for d in spec.dims if d.axis == "u" and d.side == "bottom"])
    top = (_GAP_MM + n_top * _TIER_MM + 4) if n_top else 8.0
    bot = (_GAP_MM + n_bot * _TIER_MM + 4) if n_bot else 8.0

    def side_room(side: str) -> float:
        n = len([d for d in spec.dims if d.axis == "z" and d.side == side])
        texts = [lead.text for lead in spec.leaders if lead.side == side]
        return (_GAP_MM + n * _TIER_MM if n else 4.0) + (max(_text_mm(t, _SMALL_PT) for t in texts) + 14 if texts else 6)

    left, right = side_room("left"), side_room("right") + (_DETAIL_W + 6 if spec.detail else 0)
    avail_w, avail_h = W - 20 - left - right, H - 20 - band - top - bot
    scale = next((s for s in _SCALES if s * (u1 - u0) <= avail_w and s * (z1 - z0) <= avail_h), _SCALES[-1])
    vx0 = 10 + left + 0.5 * (avail_w - scale * (u1 - u0))
    vy0 = 10 + band + bot + 0.5 * (avail_h - scale * (z1 - z0))
    P = _Paper(scale, u0, z0, vx0, vy0)
    fig._vvea_paper = P

    # regions
    for reg in spec.regions:
        for loop in reg.loops:
            x, y = P(loop[:, 0], loop[:, 1])
            path = MPath(np.column_stack([x, y]))
            if reg.dashed:
                ax.plot(x, y, color="0.25", lw=0.6, ls=(0, (4, 2)))
                continue
            face = (*reg.colour, reg.alpha) if reg.alpha > 0 else "none"
            ax.add_patch(PathPatch(path, facecolor=face, edgecolor="black" if reg.outline else "none",
                                   lw=0.7 if reg.outline else 0, hatch=reg.hatch))
    # centre line
    cx, _ = P(0.0, 0.0)
    _, yb = P(0.0, z0)
    _, yt = P(0.0, z1)
    ax.plot([cx, cx], [yb - 6, yt + 6], color="0.2", lw=0.4, ls=(0, (12, 3, 2, 3)))

    _draw_dims(ax, spec.dims, P, spec.extent)
    if spec.detail is not None:
        _draw_detail(ax, spec, fig)

    # leaders: text columns outside the dimension tiers, spread vertically
    n_left_tiers = 1 + max([0] + _tiers_count(spec, "left", P))
    n_right_tiers = 1 + max([0] + _tiers_count(spec, "right", P))
    for side in ("left", "right"):
        items = [lead for lead in spec.leaders if lead.side == side]
        if not items:
            continue
        items.sort(key=lambda lead: -lead.at[1])
        if side == "left":
            xt = P(u0, 0)[0] - _GAP_MM - n_left_tiers * _TIER_MM - 4
        else:
            xt = P(u1, 0)[0] + _GAP_MM + n_right_tiers * _TIER_MM + 4
        ys = [P(*lead.at)[1] for lead in items]
        step = 5.0
        top = H - 16.0
        bottom = 10 + band + 6.0
        placed = []
        for y in ys:
            y = min(y, top) if not placed else min(y, placed[-1] - step)
            placed.append(y)
        if placed and placed[-1] < bottom:  # push up if the column runs into the notes
            shift = bottom - placed[-1]
            placed = [min(p + shift, top - i * step) for i, p in enumerate(placed)]
        for lead, yt in zip(items, placed):
            xa, ya = P(*lead.at)
            ax.plot([xa], [ya], marker="o", ms=1.6, color="black")
            ax.plot([xa, xt], [ya, yt], color="black", lw=0.35)
            ha = "right" if side == "left" else "left"
            ax.plot([xt, xt + (-3 if side == "left" else 3)], [yt, yt], color="black", lw=0.35)
            ax.text(xt + (-4 if side == "left" else 4), yt, lead.text, ha=ha, va="center", fontsize=_SMALL_PT,
                    family="DejaVu Sans")
    # notes (bottom left) and title block (bottom right)
    y = 10 + band - 2.0
    ax.text(14, y, "Notes", fontsize=_TEXT_PT, weight="bold", va="top", family="DejaVu Sans")
    for i, n in enumerate(spec.notes):
        ax.text(14, y - 5.0 - 4.2 * i, f"{i + 1}. {n}", fontsize=_SMALL_PT, va="top", family="DejaVu Sans")
    bx, by, bw, bh = W - 10 - 170, 10, 170, 34
    ax.add_patch(Rectangle((bx, by), bw, bh, fill=False, lw=0.7, color="black"))
    rows = [
        (spec.title, 11.0, "bold"),
        (f"Material: {spec.material}" + (f" | Mass: {spec.mass_g:.1f} g" if spec.mass_g else ""), _SMALL_PT, "normal"),
        (f"Scale {_scale_text(scale)} | Sheet {sheet_no}/{n_sheets} | A3 | Dimensions in mm | ISO 2768-m",
         _SMALL_PT, "normal"),
        (spec.view_note, _SMALL_PT, "normal"),
        (f"vvea_design, design {design_id} | section views", _SMALL_PT, "normal"),
    ]
    for i, (t, pt, wgt) in enumerate(rows):
        ax.text(bx + 3, by + bh - 5 - 6.5 * i, t, fontsize=pt, weight=wgt, va="center", family="DejaVu Sans")
    fig._vvea_scale = scale  # for the tests
    return fig


def _draw_dims(ax, all_dims: Sequence[Dim], P: _Paper, extent: tuple[float, float, float, float]) -> None:
    """Draw ``dims`` of a view mapped by ``P`` (view extent ``u0, u1, z0, z1`` in model mm)."""
    u0, u1, z0, z1 = extent
    # labels on a white ground above every line, so a crossing leader is interrupted, never drawn through text
    kw = dict(fontsize=_TEXT_PT, color="black", family="DejaVu Sans", zorder=6,
              bbox=dict(facecolor="white", edgecolor="none", pad=0.4))
    arrow = dict(arrowstyle="<|-|>", lw=0.5, color="black", shrinkA=0, shrinkB=0, mutation_scale=7)

    # vertical dimensions
    for side in ("left", "right"):
        dims = [d for d in all_dims if d.axis == "z" and d.side == side]
        if not dims:
            continue
        spans = [(min(d.a[1], d.b[1]), max(d.a[1], d.b[1])) for d in dims]
        paper_spans = []
        for (lo, hi), d in zip(spans, dims):
            ylo, yhi = P(0, lo)[1], P(0, hi)[1]
            need = _text_mm(d.label()) + 4
            if yhi - ylo < need:  # text does not fit: reserve room above the top end
                yhi = yhi + need
            paper_spans.append((ylo, yhi))
        tiers = _tiers(paper_spans)
        edge = P(u0 if side == "left" else u1, 0)[0]
        sgn = -1 if side == "left" else 1
        for d, (lo, hi), k in zip(dims, spans, tiers):
            xl = edge + sgn * (_GAP_MM + k * _TIER_MM)
            for (u, z) in (d.a, d.b):
                xa, ya = P(u, z)
                ax.plot([xa + sgn * 1.0, xl + sgn * 1.5], [ya, ya], color="black", lw=0.35)
            ylo, yhi = P(0, lo)[1], P(0, hi)[1]
            ax.annotate("", (xl, yhi), (xl, ylo), arrowprops=arrow)
            t = d.label()
            if yhi - ylo >= _text_mm(t) + 4:
                ax.text(xl - 1.0, 0.5 * (ylo + yhi), t, rotation=90, ha="center", va="bottom", **kw)
            else:
                ax.text(xl - 1.0, yhi + 1.5, t, rotation=90, ha="center", va="bottom", **kw)
    # horizontal dimensions
    for side in ("top", "bottom"):
        dims = [d for d in all_dims if d.axis == "u" and d.side == side]
        if not dims:
            continue
        paper = []
        for d in dims:
            xa, xb = sorted((P(d.a[0], 0)[0], P(d.b[0], 0)[0]))
            need = _text_mm(d.label()) + 4
            if xb - xa < need:
                xb = xb + need
            paper.append((xa, xb))
        tiers = _tiers(paper)
        edge = P(0, z1 if side == "top" else z0)[1]
        sgn = 1 if side == "top" else -1
        for d, k in zip(dims, tiers):
            yl = edge + sgn * (_GAP_MM + k * _TIER_MM)
            for (u, z) in (d.a, d.b):
                xa, ya = P(u, z)
                ax.plot([xa, xa], [ya + sgn * 1.0, yl + sgn * 1.5], color="black", lw=0.35)
            xa, xb = sorted((P(d.a[0], 0)[0], P(d.b[0], 0)[0]))
            ax.annotate("", (xb, yl), (xa, yl), arrowprops=arrow)
            t = d.label()
            if xb - xa >= _text_mm(t) + 4:
                ax.text(0.5 * (xa + xb), yl + 0.8, t, ha="center", va="bottom", **kw)
            else:
                ax.text(xb + 2.0, yl + 0.8, t, ha="left", va="bottom", **kw)
    # inside dimensions: the line at the anchors' u, text to its right
    for d in all_dims:
        if d.side != "inside":
            continue
        xl, ylo = P(d.a[0], min(d.a[1], d.b[1]))
        _, yhi = P(d.a[0], max(d.a[1], d.b[1]))
        ax.annotate("", (xl, yhi), (xl, ylo), arrowprops=arrow)
        t = d.label()
        ymid = 0.5 * (ylo + yhi)  # beside the line, so it may be longer than the span
        left_of = d.a[0] < 0  # text on the side away from the axis
        ax.text(xl + (-0.8 if left_of else 0.8), ymid, t, rotation=90, ha="right" if left_of else "left",
                va="center", **kw)


def _draw_detail(ax, spec: SheetSpec, fig) -> None:
    """The enlarged detail view at the right of the sheet, its window marked on the main view."""
    from matplotlib.patches import PathPatch, Rectangle
    from matplotlib.path import Path as MPath

    det = spec.detail
    W, H = SHEET_MM
    u0, u1, z0, z1 = det.window
    s = det.scale
    x_area0, x_area1 = W - 10 - _DETAIL_W, W - 14
    y_area0, y_area1 = 10 + 40 + 20, H - 16
    x0 = 0.5 * (x_area0 + x_area1) - 0.5 * s * (u1 - u0)
    y0 = 0.5 * (y_area0 + y_area1) - 0.5 * s * (z1 - z0)
    P2 = _Paper(s, u0, z0, x0, y0)
    from matplotlib.transforms import Bbox

    box = Bbox.from_extents(x0, y0, x0 + s * (u1 - u0), y0 + s * (z1 - z0))
    for reg in spec.regions:
        for loop in reg.loops:
            x, y = P2(loop[:, 0], loop[:, 1])
            path = MPath(np.column_stack([x, y])).clip_to_bbox(box, inside=True)
            if len(path.vertices) < 3:
                continue
            face = (*reg.colour, reg.alpha) if reg.alpha > 0 else "none"
            ax.add_patch(PathPatch(path, facecolor=face, edgecolor="black" if reg.outline else "none",
                                   lw=0.7 if reg.outline else 0, hatch=reg.hatch))
    ax.add_patch(Rectangle((x0, y0), s * (u1 - u0), s * (z1 - z0), fill=False, lw=0.5, ls="-.", color="0.2"))
    ax.text(x0, y0 + s * (z1 - z0) + 2 + _GAP_MM + _TIER_MM * len([d for d in det.dims if d.side == "top"]),
            f"Detail {det.label} ({_scale_text(s)})", fontsize=_TEXT_PT, weight="bold", family="DejaVu Sans")
    _draw_dims(ax, det.dims, P2, det.window)
    for lead in det.leaders:
        xa, ya = P2(*lead.at)
        ax.plot([xa], [ya], marker="o", ms=1.6, color="black")
        xt, yt = x0 + 8, y0 - 12
        ax.plot([xa, xt], [ya, yt], color="black", lw=0.35)
        ax.text(xt, yt - 1.0, lead.text.replace("; ", ";\n"), ha="left", va="top", fontsize=_SMALL_PT,
                family="DejaVu Sans")
    # window on the main view
    P = fig._vvea_paper
    (wx0, wy0), (wx1, wy1) = [tuple(map(float, P(u, z))) for u, z in ((u0, z0), (u1, z1))]
    ax.add_patch(Rectangle((wx0, wy0), wx1 - wx0, wy1 - wy0, fill=False, lw=0.5, ls="-.", color="0.2"))
    ax.text(wx1 + 1.0, wy1 + 1.0, det.label, fontsize=_TEXT_PT, weight="bold", family="DejaVu Sans")


def _tiers_count(spec: SheetSpec, side: str, P) -> list[int]:
    dims = [d for d in spec.dims if d.axis == "z" and d.side == side]
    spans = []
    for d in dims:
        lo, hi = sorted((d.a[1], d.b[1]))
        ylo, yhi = P(0, lo)[1], P(0, hi)[1]
        need = _text_mm(d.label()) + 4
        spans.append((ylo, yhi + (need if yhi - ylo < need else 0.0)))
    return _tiers(spans) if spans else []


def _scale_text(s: float) -> str:
    return f"{s:g}:1" if s >= 1 else f"1:{1 / s:g}"


# --------------------------------------------------------------------------- files
@dataclass(frozen=True)
class DrawingSet:
    """The drawing files written (paths) and each sheet's scale."""

    sheets: tuple[str, ...]  #: sheet names, in page order
    svg: tuple[Path, ...]
    pdf: Path  #: all sheets, one page each
    scales: tuple[float, ...]

    def to_dict(self) -> dict:
        """Plain-JSON dictionary of the files and scales.

        Returns
        -------
        dict
            JSON-ready: ``sheets`` (names in page order), ``svg`` (one path per sheet, as text), ``pdf``
            (path of the multi-page PDF) and ``scales`` (per sheet, drawing length per model length,
            dimensionless; 2.0 is 2:1).
        """
        return {"sheets": list(self.sheets), "svg": [str(p) for p in self.svg], "pdf": str(self.pdf),
                "scales": list(self.scales)}


def write_drawings(model: CadModel, out_dir) -> DrawingSet:
    """Write ``drawing_<sheet>.svg`` per sheet and ``drawings.pdf`` (all sheets) into ``out_dir``.

    Parameters
    ----------
    model : CadModel
        The built CAD set (:func:`~vvea_design.cad.build_cad`).
    out_dir : path-like
        Output folder (created).

    Returns
    -------
    DrawingSet
        Paths and scales; the files carry no date (byte-stable).
    """
    import hashlib
    import json

    import matplotlib as mpl
    from matplotlib.backends.backend_pdf import PdfPages

    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    from dataclasses import asdict

    design_id = hashlib.sha256(json.dumps(asdict(model.design), sort_keys=True).encode()).hexdigest()[:10]
    specs = sheet_specs(model)
    svgs, scales = [], []
    with mpl.rc_context({"svg.hashsalt": "vvea", "svg.fonttype": "none", "pdf.fonttype": 42,
                         "hatch.linewidth": 0.3, "path.simplify": False}):
        with PdfPages(out / "drawings.pdf", metadata={"CreationDate": None, "ModDate": None,
                                                       "Creator": "vvea_design", "Producer": "matplotlib"}) as pdf:
            for i, spec in enumerate(specs):
                fig = sheet_figure(spec, i + 1, len(specs), design_id)
                path = out / f"drawing_{spec.name}.svg"
                fig.savefig(path, format="svg", metadata={"Date": None})
                pdf.savefig(fig)
                svgs.append(path)
                scales.append(fig._vvea_scale)
    return DrawingSet(tuple(s.name for s in specs), tuple(svgs), out / "drawings.pdf", tuple(scales))
