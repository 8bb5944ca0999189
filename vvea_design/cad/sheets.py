"""What each drawing sheet dimensions and notes: the unit's section A-A and one
sheet per drawn part (the drawing hooks of :data:`~vvea_design.cad.registry.PARTS`).

Every hook is ``hook(lay, solid) -> SheetContent`` with the part's solid in
the assembly frame (mm); its dimensions are anchored on the outline of the
solid's section (:func:`vvea_design.report.drawing.check_anchors` checks it)
or marked ``on_axis`` when they end on a feature's axis. The numbers come
from the :class:`~vvea_design.cad.layout.Layout` the solids were built from.
"""

from __future__ import annotations

from dataclasses import replace

from build123d import Solid

from .drafting import Detail, Dim, Leader, SheetContent, fit_text, general_notes, part_notes, radial_extent_mm
from .features import (DETAIL_KEYS, GROOVE_WIDTH_TOL, base_features, inner_tube_features, outer_tube_features, piston_features,
                       top_cap_features)
from .layout import Layout

__all__ = ["unit_section_sheet", "housing_base_sheet", "outer_tube_sheet", "inner_tube_sheet", "top_cap_sheet",
           "piston_sheet"]


def _unit_dims(lay: Layout) -> list[Dim]:
    """The unit section's dimensions (model mm; u < 0 the valve plane, u > 0 the fill-port plane)."""
    d = lay.design
    R = lay.r_outer
    zr = lay.z_piston_bottom(0.0) - d.rod_length_mm
    zt, zb0, zc = lay.z_top, lay.z_base_top, lay.z_cap
    dims = [
        Dim("z", (-R, 0.0), (-R, zt), "left", f"{zt:.2f} (housing)"),
        Dim("z", (-R, 0.0), (-R, zb0), "left"),
        Dim("z", (-R, zc), (-R, zt), "left"),
        Dim("z", (-lay.r_bore, lay.z_free0), (-lay.r_bore, lay.z_free1), "left",
            f"{lay.z_free1 - lay.z_free0:.2f} (bladder free)"),
        Dim("z", (-(lay.r_rod - lay.lead_in_rod.depth_mm), zr), (-lay.r_rod, 0.0), "left", f"{-zr:.2f} (rod at x = 0)"),
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
        Dim("u", (-lay.r_piston, zc), (lay.r_piston, zc), "top", fit_text(2 * lay.r_piston, "H8")),
        Dim("u", (-lay.r_rod, zr + lay.lead_in_rod.length_mm), (lay.r_rod, zr + lay.lead_in_rod.length_mm), "bottom",
            fit_text(2 * lay.r_rod, "f7")),
    ]
    if lay.has_top_annulus:  # the collar (top bladder clamp + plate)
        dims.append(Dim("z", (-lay.r_bore, lay.z_free1), (-lay.r_bore, lay.z_collar1), "left",
                        f"{lay.z_collar1 - lay.z_free1:.2f} (collar)"))
    return dims


def _chamber2_leader(lay: Layout) -> Leader:
    """The unit section's note on chamber 2's charging port."""
    if lay.has_top_annulus:
        return Leader((lay.r_port2, 1.0), f"chamber 2 fill port: valve M5 under the base, port Ø{lay.fill_port_d:.2f} "
                                           "through base and spigot", "right")
    if not lay.has_cross_port:
        return Leader((lay.r_port2, lay.z_top - 1.0), f"chamber 2 fill port: valve M5 over its port "
                                                      f"Ø{lay.fill_port_d:.2f}", "right")
    via = "riser and " if lay.has_bulkhead else ""
    return Leader((lay.y_valve2, lay.z_top - 1.0), f"chamber 2 fill port: valve M5, {via}cross port "
                                                   f"Ø{lay.cross_port_d:.2f} (plugged) to the port Ø{lay.fill_port_d:.2f}",
                  "right")


def _unit_leaders(lay: Layout) -> list[Leader]:
    """The unit section's notes with leader lines: walls, valves, ports, seals, chambers (model mm)."""
    d, c = lay.design, lay.cad
    zt, zb0, zc = lay.z_top, lay.z_base_top, lay.z_cap
    zm = 0.5 * (lay.z_free0 + lay.z_free1)
    ps, rs = lay.piston_seal, lay.rod_seal
    g_z = lay.z_piston_bottom(0.0) + 0.73 * d.fixed.piston_height_mm
    zgt = lay.z_piston_top(d.fixed.travel_mm)
    leaders = [
        Leader((-lay.r_bore - 0.5 * d.outer_wall_mm, zm + 20), f"outer tube wall {d.outer_wall_mm:.2f}",
               "left"),
        Leader((-lay.r_inner_tube + 0.5 * d.inner_tube_wall_mm, zm - 20),
               f"inner tube wall {d.inner_tube_wall_mm:.2f}", "left"),
        Leader((-(lay.r_outer - 1.0), lay.z_valve), f"relief valve bore Ø{lay.relief_d:g}, seat Ø{lay.relief_seat_d:g}",
               "left"),
        Leader((-lay.r_ring_channel, zb0 - 1.0), f"fluid channels Ø{lay.ring_channel_d:.2f} / "
                                                 f"Ø{lay.base_channel_d:.2f}", "left"),
        Leader((lay.y_port1, zt - 1.0),
               f"chamber 1 fill port: charging valve M5 over "
               + (f"the fill tube's bore Ø{2 * lay.r_fill_tube_bore:.2f}" if lay.has_bulkhead else
                  f"its port Ø{lay.fill_port_d:.2f}"), "right"),
        _chamber2_leader(lay),
        Leader((-(lay.r_bore - 0.5 * lay.base_seal.depth_mm), 0.5 * sum(lay.z_base_seal)),
               f"O-ring {lay.base_seal.oring.code} (base spigot to outer tube, static)", "left"),
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
    if lay.cap_seal is not None:
        leaders.append(Leader((-(lay.r_bore - 0.5 * lay.cap_seal.depth_mm), 0.5 * sum(lay.z_cap_seal)),
                              f"O-ring {lay.cap_seal.oring.code} (top cap to outer tube, static)", "left"))
    if lay.has_top_annulus:  # the collar (top bladder clamp + plate) and the chamber-1 annulus above it
        zcol = lay.z_collar1
        leaders += [
            Leader((-0.5 * (lay.r_inner_tube + lay.r_bore), 0.5 * (lay.z_free1 + zcol)),
                   f"collar on the inner tube: top bladder clamp + plate {d.collar_mm:.2f}", "left"),
            Leader((0.5 * (lay.r_inner_tube + lay.r_bore), 0.5 * (zcol + zc)),
                   f"gas chamber 1 (annulus, joined to the bore by {c.cross_slots} slots at 45°)", "right"),
        ]
    return leaders


def unit_section_sheet(lay: Layout) -> SheetContent:
    """The unit's section A-A: overall and internal dimensions, walls, valves, ports, seals, chambers.

    Parameters
    ----------
    lay : Layout
        Radii and levels of the design, mm (z = 0 under the base).

    Returns
    -------
    SheetContent
        Aligned section (left half in the valve plane y = 0, right half in the fill-port plane x = 0) at
        x = 0, from the rod's end to the top of the housing; dimensions and leaders in model mm.
    """
    R = lay.r_outer
    zr = lay.z_piston_bottom(0.0) - lay.design.rod_length_mm
    return SheetContent(
        tuple(_unit_dims(lay)), tuple(_unit_leaders(lay)), general_notes(lay), plane="aligned",
        title="Spring-damper unit: section A-A", material="see parts list (bom.csv)",
        view_note="Section A-A, aligned: left half in the valve plane (y = 0), right half in the fill-port plane "
                  "(x = 0); x = 0 (piston up)",
        extent=(-R, R, zr, lay.z_top))


def _part_sheet(lay: Layout, features, plane: str = "xz", detail: Detail | None = None,
                notes: tuple[str, ...] = ()) -> SheetContent:
    """A part's sheet from its features: each feature's dimension (in the detail view for :data:`DETAIL_KEYS`),
    leader or note; the general notes first, then a note with the surface roughness of the features whose
    annotation does not give it."""
    dims = tuple(f.show for f in features if isinstance(f.show, Dim) and f.key not in DETAIL_KEYS)
    if detail is not None:
        detail = replace(detail, dims=[*detail.dims, *(f.show for f in features if f.key in DETAIL_KEYS)])
    leaders = tuple(f.show for f in features if isinstance(f.show, Leader))
    own = tuple(dict.fromkeys(f.show for f in features if isinstance(f.show, str)))  # one note for equal grooves
    rough = [f"{f.title} {f.finish}" for f in features if f.finish and f.finish not in f.text]
    finish = (f"Surface roughness: {'; '.join(rough)}.",) if rough else ()
    return SheetContent(dims, leaders, (*part_notes(), *finish, *own, *notes), plane=plane, detail=detail)


def outer_tube_sheet(lay: Layout, solid: Solid) -> SheetContent:
    """Sheet of the outer tube: its features (:func:`~vvea_design.cad.features.outer_tube_features`) and the wall.

    Parameters
    ----------
    lay : Layout
        Radii and levels of the design, mm.
    solid : build123d.Solid
        The outer tube, assembly frame, mm.

    Returns
    -------
    SheetContent
        Section in the valve plane; dimensions in model mm.
    """
    d = lay.design
    R, z0, z1 = radial_extent_mm(solid)
    wall = Leader((-(R - 0.5 * d.outer_wall_mm), 0.5 * (z0 + z1)), f"wall {d.outer_wall_mm:.2f}", "left")
    c = _part_sheet(lay, outer_tube_features(lay))
    return replace(c, leaders=(*c.leaders, wall))


def inner_tube_sheet(lay: Layout, solid: Solid) -> SheetContent:
    """Sheet of the inner tube (the piston's bore): its features
    (:func:`~vvea_design.cad.features.inner_tube_features`: with a bulkhead the web and the fill tube, in the
    ``annulus_top`` layout the collar, its seal groove, the cuff groove and the slots) and the wall.

    Parameters
    ----------
    lay : Layout
        Radii and levels of the design, mm.
    solid : build123d.Solid
        The inner tube, assembly frame, mm.

    Returns
    -------
    SheetContent
        Section in the valve plane; dimensions in model mm.
    """
    d = lay.design
    _, z0, z1 = radial_extent_mm(solid)
    ri = lay.r_inner_tube
    z_w = 0.5 * (z0 + (lay.z_free1 if lay.has_top_annulus else z1))
    wall = Leader((-(ri - 0.5 * d.inner_tube_wall_mm), z_w), f"wall {d.inner_tube_wall_mm:.2f}", "left")
    notes = ()
    if lay.has_top_annulus:
        g = lay.collar_seal
        notes = (f"Collar to outer-tube bore: static seal, O-ring {g.oring.name} (squeeze {100 * g.squeeze:.0f} %, "
                 f"stretch {100 * g.stretch:.1f} %).",)
    c = _part_sheet(lay, inner_tube_features(lay), notes=notes)
    return replace(c, leaders=(*c.leaders, wall))


def housing_base_sheet(lay: Layout, solid: Solid) -> SheetContent:
    """Sheet of the base: its features (:func:`~vvea_design.cad.features.base_features`: height, spigot with its
    seal and the cuff's outer wall, rod bore and seal, valve bores, channels, servo mount; in ``annulus_top`` the
    chamber-2 port and valve).

    Parameters
    ----------
    lay : Layout
        Radii and levels of the design, mm.
    solid : build123d.Solid
        The base, assembly frame, mm.

    Returns
    -------
    SheetContent
        Section in the valve plane; dimensions in model mm.
    """
    return _part_sheet(lay, base_features(lay))


def top_cap_sheet(lay: Layout, solid: Solid) -> SheetContent:
    """Sheet of the top cap: its features (:func:`~vvea_design.cad.features.top_cap_features`: the charging valves'
    tapped holes and ports -- chamber 1 on the axis in ``bulkhead`` --, with the top bladder clamp its spigot, seal
    groove, cuff groove, the chamber-2 port, cross port (and riser) and plug bore).

    Parameters
    ----------
    lay : Layout
        Radii and levels of the design, mm.
    solid : build123d.Solid
        The top cap, assembly frame, mm.

    Returns
    -------
    SheetContent
        Section in the fill-port plane (x = 0); dimensions in model mm.
    """
    extra = () if not lay.has_top_annulus else (
        "Plain cap: the top bladder clamp is the inner tube's collar; chamber 2 is charged through the base.",)
    return _part_sheet(lay, top_cap_features(lay), plane="yz", notes=extra)


def piston_sheet(lay: Layout, solid: Solid) -> SheetContent:
    """Sheet of the piston with its rod: its features (:func:`~vvea_design.cad.features.piston_features`) and a 5:1
    detail of the two seal grooves.

    Parameters
    ----------
    lay : Layout
        Radii and levels of the design, mm.
    solid : build123d.Solid
        The piston with rod at x = 0, assembly frame, mm.

    Returns
    -------
    SheetContent
        Section in the valve plane with detail A; dimensions in model mm.
    """
    d = lay.design
    ps = lay.piston_seal
    zpb, zpt = lay.z_piston_bottom(0.0), lay.z_piston_top(0.0)
    (g0a, g0b), (g1a, g1b) = [(zpb + d.fixed.piston_height_mm * q - ps.width_mm / 2,
                               zpb + d.fixed.piston_height_mm * q + ps.width_mm / 2) for q in (0.27, 0.73)]
    rp, rg = lay.r_piston, ps.groove_diameter_mm / 2
    feats = piston_features(lay)
    win = (rp - 6.0, rp + 1.0, zpb - 1.0, zpt + 1.0)
    detail = Detail(win, 5.0, [
        Dim("z", (rp, zpb), (rp, g0a), "right"),
        Dim("z", (rp, g1a), (rp, g1b), "right", f"{ps.width_mm:.2f} {GROOVE_WIDTH_TOL}"),
        Dim("z", (rp, zpb), (rp, g1a), "right"),
        Dim("z", (rp, zpb), (rp, zpt), "right"),
        Dim("u", (rg, g1b), (rp, g1b), "top", f"{rp - rg:.3f} (groove depth)"),
    ], [])
    return _part_sheet(lay, feats, detail=detail)
