"""The pressure-bearing pieces of a unit as FE models: which CAD solid, which walls of the design it holds,
where its joint bears, and the stress-classification lines its nominal stress is read on.

Pieces (CAD part -> the design's walls in it): ``housing_outer_tube`` -> ``outer_tube``; ``housing_inner_tube``
-> ``inner_tube`` (and ``bulkhead`` with its fill tube in the bulkhead layout, ``collar`` in annulus_top);
``housing_top_cap`` -> ``top_cap``; ``housing_base`` -> ``base``; ``piston`` -> ``piston_floor`` (a cupped
piston) or ``piston``, with a stub of its rod.

How the axial end load reaches the joint (the design's joint, :meth:`~vvea_design.spring.design.Design.joints`):

* ``thread`` (ISO 261 fine thread): the end piece's load goes through its spigot's thread into the outer
  tube's, smeared over the engaged length next to the tube's end, clear of the run-out at the spigot's
  shoulder (DIN 76-1: no full thread there) (an axial traction on the cylindrical faces
  of the thread zone); the outer tube carries the top cap's load (plus the tendon's pull on the cap's eye) from
  its top thread to its bottom one: a closed-ended tube.
* ``ring_top`` (DIN 472): the top cap bears on the ring over the ring's seat on its top face at the bore; the
  tube takes it at the ring's groove.
* ``tie_rods`` (ISO 898-1 rods, ISO 4032 nuts): each nut's load is smeared over an annulus of the rod circle
  (a nut's width across flats) on the cap's top face and the base's underside; the tubes carry no pressure end
  load but the rods' clamp force (the largest preload, VDI 2230-1).

A joint face the drawn section does not have (the CAD does not draw the thread yet) is replaced by the next
one listed: for the end pieces their rim over the tube wall (as if tie rods held them: a plate supported at
the outer bore, the sizing's model), for the tube its end faces. The result names the face each case used.
The inner tube only bears (seats) on the base and under the cap: its net axial load (its bulkhead's or
collar's pressure difference) goes to the end that can push back. The piston's goes into its rod: the rod
stub is cut 1.5 rod diameters below the piston and its section takes the reaction.

Lengths mm, pressures MPa.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from functools import partial

import numpy as np
from matplotlib.path import Path as _Path

from ..cad.assembly import CadModel
from ..cad.layout import Layout
from ..materials.structural import get_material
from ..spring.derive import piston_floor_moment
from .closed_form import lame, plate_simply_supported
from .evaluate import Region, StressLine
from .meshing import MeshSpec, mesh_section
from .model import Bearing, PieceModel
from .section import MeridianSection, outline_polygon, section_of_solid, with_corner_radii
from .surroundings import Surroundings

__all__ = ["PieceSpec", "piece_specs", "build_piece", "thread_zones"]

#: Rod stub kept below the piston, in rod diameters (its cut section takes the piston's load).
ROD_STUB_DIAMETERS = 1.5


@dataclass(frozen=True)
class PieceSpec:
    """One piece before meshing: its section, material key, joint faces and walls."""

    part: str
    title: str
    material_key: str
    section: MeridianSection
    bearings: tuple[Bearing, ...]
    regions: tuple[Region, ...]
    joint: str  #: how the axial load reaches the joint (for the report)
    #: forces other pieces put on it through a joint face: (faces, source), the first of the faces the section has,
    #: source ``"top_cap"`` (the top cap's joint reaction plus the tendon's pull) or a force in N (a clamp force),
    #: > 0 up
    applied: tuple = ()


def _chord(poly: np.ndarray, fixed: float, lo: float, hi: float, vertical: bool, hint: float) -> tuple[float, float]:
    """The interval of a line (r = fixed if vertical, else z = fixed) inside a polygon, containing ``hint``
    (or the longest), sampled at 0.01 mm."""
    s = np.arange(lo, hi + 1e-9, 0.01)
    pts = np.column_stack([np.full_like(s, fixed), s]) if vertical else np.column_stack([s, np.full_like(s, fixed)])
    inside = _Path(poly).contains_points(pts)
    if not inside.any():
        return math.nan, math.nan
    edges = np.flatnonzero(np.diff(np.concatenate([[0], inside.astype(int), [0]])))
    runs = [(s[a], s[b - 1]) for a, b in zip(edges[::2], edges[1::2])]
    for a, b in runs:
        if a <= hint <= b:
            return a, b
    return max(runs, key=lambda ab: ab[1] - ab[0])


def _full_chord_r(poly, r_from: float, r_to: float, z0: float, z1: float) -> float:
    """The first radius from ``r_from`` at which a vertical line crosses the section from z0 to z1 whole."""
    for r in np.arange(r_from, r_to, 0.1):
        a, b = _chord(poly, r, z0 - 0.5, z1 + 0.5, True, 0.5 * (z0 + z1))
        if a <= z0 + 0.02 and b >= z1 - 0.02:
            return float(r)
    return 0.5 * (r_from + r_to)


def _plate_line(poly, what: str, r_c: float, z0: float, z1: float, a_mm: float, t_mm: float, nu: float,
                pressure) -> StressLine:
    zl, zh = _chord(poly, r_c, z0 - 0.5, z1 + 0.5, True, 0.5 * (z0 + z1))

    def cf(p, x_mm):
        return float(abs(plate_simply_supported(r_c, a_mm, t_mm, pressure(p), nu)["s_rr"]))

    return StressLine(what, (r_c, zl), (r_c, zh), cf,
                      f"simply supported plate a = {a_mm:.2f} mm, t = {t_mm:.2f} mm: radial stress at r = {r_c:.2f} mm")


def _joints(design) -> dict:
    """The design's joint record holding each end piece (``top_cap``, ``base``; None: no joint records)."""
    out: dict = {}
    try:
        records = design.joints()
    except AttributeError:  # a design without joints (before the buildability rules)
        return out
    for j in records:
        if j.kind in ("thread", "ring_top"):
            out[j.joint] = j
        elif j.kind == "tie_rods":
            out["top_cap"] = out["base"] = j
    return out


def _thread_levels(lay: Layout, joint, top: bool) -> tuple[float, float]:
    """z range of a thread's engaged flanks: the CAD's thread zone, or where the CAD draws no joint (a design of the
    gas-only rules with its what-if thread records) the engagement next to the tube's end, mm."""
    t = lay.joint.cap_thread if top else lay.joint.base_thread
    if t is not None:
        return t.thread
    zone, ro = joint.runout_mm + joint.engagement_length_mm, joint.runout_mm
    return (lay.z_cap - zone, lay.z_cap - ro) if top else (lay.z_base_top + ro, lay.z_base_top + zone)


def _thread_band(lay: Layout, joint, top: bool) -> tuple[float, float]:
    """Radii a thread's smeared flanks are found between: around its minor and major diameters, or where the CAD
    draws no joint from the outer bore (the plain tube's wall stands in for the thread), mm."""
    drawn = (lay.joint.cap_thread if top else lay.joint.base_thread) is not None
    lo = joint.minor_diameter_mm / 2 if drawn else min(joint.minor_diameter_mm / 2, lay.outer_bore_radius_mm)
    return lo - 0.5, joint.major_diameter_mm / 2 + 0.5


def _end_bearings(lay: Layout, joint, end: str) -> tuple[Bearing, ...]:
    """Where an end piece (``top_cap`` or ``base``) takes its reaction, in order of preference."""
    rb, R = lay.outer_bore_radius_mm, lay.outer_radius_mm
    top = end == "top_cap"
    z_face = lay.z_top if top else 0.0
    push = -1 if top else +1
    out = []
    if joint is not None and joint.kind == "thread":
        # the engaged flanks, clear of the run-outs (DIN 76-1: no full thread there): the CAD's levels
        zr = _thread_levels(lay, joint, top)
        out.append(Bearing(f"{joint.designation} thread on its spigot, smeared over {joint.engagement_length_mm:.1f} "
                           "mm of engagement", _thread_band(lay, joint, top),
                           zr, push, faces="radial"))
    elif joint is not None and joint.kind == "ring_top" and top:
        seat = joint.groove_diameter_mm - joint.bore_mm  # the ring's seat: about twice the groove's depth
        out.append(Bearing(f"{joint.designation} retaining ring on its top face at the bore",
                           (joint.bore_mm / 2 - seat, joint.bore_mm / 2), (z_face, z_face), push))
    elif joint is not None and joint.kind == "tie_rods":
        rc, s = joint.rod_circle_radius_mm, joint.nut_width_across_flats_mm
        out.append(Bearing(f"{joint.designation}: the nuts on the rod circle r = {rc:.1f} mm (smeared ring)",
                           (rc - s / 2, min(rc + s / 2, R)), (z_face, z_face), push))
    out.append(Bearing(("its top face" if top else "its underside") + " over the tube wall (a plate held at the outer "
                       "bore: the joint's own face is not drawn)", (rb, R), (z_face, z_face), push))
    return tuple(out)


def _section(model: CadModel, part: str, corner_radius_mm: float | None, z_range=None) -> MeridianSection:
    """A part's meridian section, its internal corners rounded: with the drawing's root radii
    (:meth:`~vvea_design.cad.layout.Layout.corner_radius_mm`) or, given ``corner_radius_mm``, that one."""
    at = None if corner_radius_mm is not None else partial(model.layout.corner_radius_mm, part)
    return with_corner_radii(section_of_solid(model.solids[part], part, z_range_mm=z_range),
                             0.0 if corner_radius_mm is None else corner_radius_mm, at)


def thread_zones(lay: Layout) -> tuple[tuple[float, float, float, float], ...]:
    """The boxes ``(r0, r1, z0, z1)`` round the drawn threads' flanks (a pitch beyond their engaged length), mm.

    The CAD draws a thread as its pitch cylinder (ISO 6410-1) and the FE smears the joint's load over it: the
    stress at the ends of that band is the model's, not the thread roots'. The thread is checked by its standard
    (ISO 965-1 stripping and the tube's wall under the root, the joint's safety factors); the FE peak of the
    pieces is taken outside these boxes, the wall under the thread kept (the box stops at the thread's major
    radius plus half a millimetre).

    Parameters
    ----------
    lay : Layout
        The CAD's levels and its joint as drawn (mm).

    Returns
    -------
    tuple of tuple of float
        One box per drawn thread, ``(r0, r1, z0, z1)`` in mm; empty without a threaded joint.
    """
    out = []
    for t in (lay.joint.base_thread, lay.joint.cap_thread) if lay.has_joint else ():
        if t is not None:
            out.append((t.internal_minor_mm / 2 - 0.5, t.major_mm / 2 + 0.5, t.thread[0] - t.pitch_mm,
                        t.thread[1] + t.pitch_mm))
    return tuple(out)


def _outer_tube(model: CadModel, lay: Layout, sec: MeridianSection) -> PieceSpec:
    rb, R, z0, zc = lay.outer_bore_radius_mm, lay.outer_radius_mm, lay.z_base_top, lay.z_cap
    zm = 0.5 * (lay.z_free0 + lay.z_free1)
    line = StressLine("mid-length, through the wall", (rb, zm), (R, zm),
                      lambda p, x: float(lame(rb, rb, R, p["chamber_2"])["s_tt"]),
                      "Lamé, chamber-2 pressure in the bore: hoop stress at the bore")
    joints = _joints(model.design)
    top, base = joints.get("top_cap"), joints.get("base")
    if lay.has_joint:  # the tube's ends as drawn (threaded ends reach over the end pieces' spigots)
        z0, zc = lay.joint.z_tube_bottom, lay.joint.z_tube_top
    top_end = Bearing("its top end", (rb, R), (zc, zc), 0)
    bottom_end = Bearing("its bottom end on the base", (rb, R), (z0, z0), 0)
    bearings, applied, how = [], (), "its ends bear on base and top cap"
    if top is not None and top.kind in ("thread", "ring_top"):
        if top.kind == "thread":
            band = _thread_band(lay, top, True)
            applied = (((Bearing(f"the top cap's {top.designation} thread", band, _thread_levels(lay, top, True),
                                 0, faces="radial"),
                         top_end), "top_cap"),)
        else:
            applied = (((Bearing(f"the {top.designation} ring's groove", (rb, 0.5 * top.groove_diameter_mm + 0.1),
                                 (zc, zc + 10.0), 0), top_end), "top_cap"),)
        how = "closed-ended: it carries the top cap's load (and the tendon's pull) to the base's joint"
    if base is not None and base.kind == "thread":
        band = _thread_band(lay, base, False)
        bearings.append(Bearing(f"the base's {base.designation} thread", band, _thread_levels(lay, base, False), 0,
                                faces="radial"))
    bearings.append(bottom_end)
    if top is not None and top.kind == "tie_rods":
        applied = (((top_end,), -float(top.preload_max_N)),)
        how = f"clamped by the tie rods' preload ({top.preload_max_N:.0f} N, VDI 2230-1 F_Mzul), no pressure end load"
    return PieceSpec("housing_outer_tube", "outer tube", model.design.fixed.housing_material, sec, tuple(bearings),
                     (Region("outer_tube", ((0, R + 1, -1e9, 1e9),), (line,), thread_zones(lay)),), how, applied)


def _inner_tube(model: CadModel, lay: Layout, sec: MeridianSection, poly) -> PieceSpec:
    d = model.design
    rp, rio, z0, zc = lay.piston_radius_mm, lay.inner_tube_outer_radius_mm, lay.z_base_top, lay.z_cap
    t_i = rio - rp
    z_hi = min(lay.z_free1, lay.z_bulkhead0 if lay.has_bulkhead else lay.z_free1)
    z_lo = max(lay.z_free0, lay.z_piston_top(0.0))
    zm = 0.5 * (z_lo + z_hi) if z_hi - z_lo > 2 * t_i else 0.5 * (lay.z_free0 + lay.z_free1)

    def inner_cf(p, x_mm):
        inside = Surroundings(lay, x_mm).pressures(Surroundings(lay, x_mm).medium(rp - 0.05, zm), p)[0]
        return float(abs(lame(rp, rp, rio, inside, p["chamber_2"])["s_tt"]))

    regions = []
    excl = []
    if lay.has_bulkhead:
        zb0, zb1 = lay.z_bulkhead0, lay.z_bulkhead1
        box = (0.0, rio + 1, zb0 - 2 * t_i, zc + 1)
        excl.append(box)
        r_c = _full_chord_r(poly, lay.fill_tube_outer_radius_mm + 0.3, rp, zb0, zb1)
        kp_nu = get_material(d.fixed.housing_material).poisson
        line = _plate_line(poly, "bulkhead, through the web", r_c, zb0, zb1, rp, d.bulkhead_mm, kp_nu,
                           lambda p: abs(p["chamber_2"] - p["chamber_1"]))
        regions.append(Region("bulkhead", (box,), (line,)))
    if lay.has_top_annulus:
        rb = lay.outer_bore_radius_mm
        box = (rio - 0.5 * t_i, rb + 1, lay.z_free1 - 2 * t_i, lay.z_collar1 + 2 * t_i)
        excl.append(box)
        r_c = rio + 0.3
        zl, zh = _chord(poly, r_c, lay.z_free1 - 1, lay.z_collar1 + 1, True, lay.z_collar1 - 0.5 * d.collar_mm)

        def collar_cf(p, x_mm):
            dp = abs(p["chamber_2"] - p["chamber_1"])
            m = dp / rio * ((rb**3 - rio**3) / 3 - rio * (rb**2 - rio**2) / 2)
            return float(6 * m / d.collar_mm**2)

        regions.append(Region("collar", (box,), (StressLine("collar root, through clamp and plate", (r_c, zl), (r_c, zh),
                                                             collar_cf, "ring cantilevered from the inner tube: 6 M / t^2 at the root"),)))
    line = StressLine("bladder zone, through the wall", (rp, zm), (rio, zm), inner_cf,
                      "Lamé, chamber 2 outside, the bore's medium inside: hoop stress at the bore")
    regions.insert(0, Region("inner_tube", ((0, rio + 1, -1e9, 1e9),), (line,), tuple(excl)))
    seats = lay.seats  # the tube's ends sit in the end pieces' seats (the buildability rules)
    zb = z0 if seats is None else seats.z_base_floor
    zt = zc if seats is None or seats.top is None else seats.z_top_end
    bearings = (Bearing("its bottom end on the base" + ("" if seats is None else "'s seat floor"), (rp, rio), (zb, zb), +1),
                Bearing("its top end under the top cap" + ("" if zt == zc else " (in its seat)"), (0.0, rio), (zt, zt), -1))
    return PieceSpec("housing_inner_tube", "inner tube", d.fixed.housing_material, sec, bearings, tuple(regions),
                     "clamped between base and top cap: its net axial load bears on the end that pushes back")


def _top_cap(model: CadModel, lay: Layout, sec: MeridianSection, poly) -> PieceSpec:
    d = model.design
    rb, R, zc, zt = lay.outer_bore_radius_mm, lay.outer_radius_mm, lay.z_cap, lay.z_top
    nu = get_material(d.fixed.housing_material).poisson
    r_c = _full_chord_r(poly, 0.3, rb, zc, zt)
    line = _plate_line(poly, "centre, through the cap", r_c, zc, zt, rb, d.top_cap_mm, nu,
                       lambda p: max(p["chamber_1"], p["chamber_2"]))
    joint = _joints(d).get("top_cap")
    bearings = _end_bearings(lay, joint, "top_cap")
    return PieceSpec("housing_top_cap", "top cap", d.fixed.housing_material, sec, bearings,
                     (Region("top_cap", ((0, R + 1, -1e9, 1e9),), (line,), thread_zones(lay)),),
                     f"{'no joint record' if joint is None else joint.designation}: {bearings[0].what}")


def _base(model: CadModel, lay: Layout, sec: MeridianSection, poly) -> PieceSpec:
    d = model.design
    rb, R, z0 = lay.outer_bore_radius_mm, lay.outer_radius_mm, lay.z_base_top
    nu = get_material(d.fixed.housing_material).poisson
    r_c = _full_chord_r(poly, lay.rod_radius_mm + lay.rod_seal.depth_mm + 0.3, rb, 0.0, z0)
    line = _plate_line(poly, "near the rod bore, through the base", r_c, 0.0, z0, rb, d.base_mm, nu,
                       lambda p: max(p["chamber_2"], p["fluid"]))
    joint = _joints(d).get("base")
    bearings = _end_bearings(lay, joint, "base")
    return PieceSpec("housing_base", "base", d.fixed.housing_material, sec, bearings,
                     (Region("base", ((0, R + 1, -1e9, 1e9),), (line,), thread_zones(lay)),),
                     f"{'no joint record' if joint is None else joint.designation}: {bearings[0].what}")


def _piston(model: CadModel, lay: Layout, corner_radius_mm: float | None) -> PieceSpec:
    d = model.design
    rr, rp = lay.rod_radius_mm, lay.piston_radius_mm
    zpb, zpt = lay.z_piston_bottom(0.0), lay.z_piston_top(0.0)
    z_cut = zpb - ROD_STUB_DIAMETERS * 2 * rr
    sec = _section(model, "piston", corner_radius_mm, (z_cut, zpt + 1.0))
    poly = outline_polygon(sec.face)
    mat = get_material(d.fixed.rod_material)
    lines = ()
    wall = "piston"
    if lay.has_piston_pocket:
        wall = "piston_floor"
        r_c = rr + 0.3
        zl, zh = _chord(poly, r_c, zpb - 0.5, zpt + 0.5, True, zpb + 0.5 * d.piston_floor_mm)
        a = lay.piston_pocket_radius_mm
        k = float(piston_floor_moment(rp, a, rr, mat.poisson))

        def floor_cf(p, x_mm):
            dp = abs(p["fluid"] - p["chamber_1"])
            t = d.piston_floor_mm
            return float(max(6 * k * dp / t**2, 3 * dp * (rp**2 - rr**2) / (2 * rr * t)))

        lines = (StressLine("pocket floor at the rod, through the floor", (r_c, zl), (r_c, zh), floor_cf,
                            "annular plate clamped at the rod: 6 M / t^2 (or Tresca on the root shear)"),)
    bearings = (Bearing(f"the rod's section {ROD_STUB_DIAMETERS:g} rod diameters below the piston", (0.0, rr),
                        (z_cut, z_cut), 0, cut=True),)
    return PieceSpec("piston", "piston with rod stub", d.fixed.rod_material, sec, bearings,
                     (Region(wall, ((0, rp + 1, zpb - 1.0, zpt + 1.0),), lines),),
                     "its load goes into the rod (the stub's section takes the reaction)")


def piece_specs(model: CadModel, corner_radius_mm: float | None = None) -> tuple[PieceSpec, ...]:
    """The pressure-bearing pieces of a CAD model, with their sections cut from the CAD solids.

    Parameters
    ----------
    model : CadModel
        The built CAD set (the machined pieces and the piston at x = 0), mm.
    corner_radius_mm : float, optional
        Radius given to every internal corner the CAD draws sharp, mm; None (default): the drawing's root radii
        (:meth:`~vvea_design.cad.layout.Layout.corner_radius_mm`).

    Returns
    -------
    tuple of PieceSpec
        Outer tube, inner tube, top cap, base, piston (in this order).
    """
    lay = model.layout
    secs = {p: _section(model, p, corner_radius_mm) for p in
            ("housing_outer_tube", "housing_inner_tube", "housing_top_cap", "housing_base")}
    polys = {p: outline_polygon(s.face) for p, s in secs.items()}
    return (_outer_tube(model, lay, secs["housing_outer_tube"]),
            _inner_tube(model, lay, secs["housing_inner_tube"], polys["housing_inner_tube"]),
            _top_cap(model, lay, secs["housing_top_cap"], polys["housing_top_cap"]),
            _base(model, lay, secs["housing_base"], polys["housing_base"]),
            _piston(model, lay, corner_radius_mm))


def build_piece(spec: PieceSpec, model: CadModel, others: dict[str, np.ndarray], mesh: MeshSpec = MeshSpec()) -> PieceModel:
    """Mesh a piece and set what surrounds it.

    Parameters
    ----------
    spec : PieceSpec
        The piece.
    model : CadModel
        The CAD set (its layout gives the spaces round the piece).
    others : dict of str to ndarray
        Outlines of the machined pieces (``(n, 2)`` r, z, mm): the piece's neighbours are its contact faces.
    mesh : MeshSpec
        Mesh sizes.

    Returns
    -------
    PieceModel
        Meshed, labelled, factorised.
    """
    if spec.part == "piston":  # drawn at x = 0; what surrounds it moves with it
        sur = partial(_surroundings, model.layout, (), fixed_x_mm=0.0)
    else:
        sur = partial(_surroundings, model.layout, tuple(v for k, v in others.items() if k != spec.part))
    return PieceModel(spec.part, spec.section, mesh_section(spec.section, mesh), get_material(spec.material_key),
                      spec.bearings, sur)


def _surroundings(lay: Layout, solids: tuple, x_mm: float, fixed_x_mm: float | None = None) -> Surroundings:
    return Surroundings(lay, x_mm if fixed_x_mm is None else fixed_x_mm, solids)
