"""What each drawing sheet dimensions and notes: the unit's section A-A and one
sheet per drawn part (the drawing hooks of :data:`~vvea_design.cad.registry.PARTS`).

Every hook is ``hook(lay, solid) -> SheetContent`` with the part's solid in
the assembly frame (mm); its dimensions are anchored on the outline of the
solid's section (:func:`vvea_design.report.drawing.check_anchors` checks it)
or marked ``on_axis`` when they end on a feature's axis. The numbers come
from the :class:`~vvea_design.cad.layout.Layout` the solids were built from.
"""

from __future__ import annotations

import math

from build123d import Solid

from .drafting import Detail, Dim, Leader, SheetContent, fit_text, general_notes, radial_extent_mm
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
        Dim("u", (-lay.r_piston, zc), (lay.r_piston, zc), "top", fit_text(2 * lay.r_piston, "H8")),
        Dim("u", (-lay.r_rod, zr), (lay.r_rod, zr), "bottom", fit_text(2 * lay.r_rod, "f7")),
    ]
    if lay.has_top_annulus:  # the collar (top bladder clamp + plate)
        dims.append(Dim("z", (-lay.r_bore, lay.z_free1), (-lay.r_bore, lay.z_collar1), "left",
                        f"{lay.z_collar1 - lay.z_free1:.2f} (collar)"))
    return dims


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


def outer_tube_sheet(lay: Layout, solid: Solid) -> SheetContent:
    """Sheet of the outer tube: length, outside and bore diameters, wall.

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
    dims = (Dim("z", (-R, z0), (-R, z1), "left"),
            Dim("u", (-R, z1), (R, z1), "top", f"Ø{2 * R:.2f}"),
            Dim("u", (-lay.r_bore, z1), (lay.r_bore, z1), "top", f"Ø{2 * lay.r_bore:.2f}"))
    leaders = (Leader((R - 0.5 * d.outer_wall_mm, 0.5 * (z0 + z1)), f"wall {d.outer_wall_mm:.2f}"),)
    return SheetContent(dims, leaders, general_notes(lay)[:1])


def inner_tube_sheet(lay: Layout, solid: Solid) -> SheetContent:
    """Sheet of the inner tube (the piston's bore): length, diameters, the H8 bore; in the ``annulus_top``
    layout also its collar, the collar's seal groove and the slots of its top end.

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
    d, c = lay.design, lay.cad
    R, z0, z1 = radial_extent_mm(solid)
    notes = general_notes(lay)
    if not lay.has_top_annulus:
        dims = (Dim("z", (-R, z0), (-R, z1), "left"),
                Dim("u", (-R, z1), (R, z1), "top", f"Ø{2 * R:.2f}"),
                Dim("u", (-lay.r_piston, z0), (lay.r_piston, z0), "bottom", fit_text(2 * lay.r_piston, "H8")))
        leaders = (Leader((R - 0.5 * d.inner_tube_wall_mm, 0.5 * (z0 + z1)),
                          f"wall {d.inner_tube_wall_mm:.2f}; bore Ra 0.4"),)
        return SheetContent(dims, leaders, notes[:2])
    ri, zcol, seal = lay.r_inner_tube, lay.z_collar1, lay.collar_seal
    dims = (Dim("z", (-ri, z0), (-ri, z1), "left"),
            Dim("z", (-R, lay.z_free1), (-R, zcol), "left", f"{zcol - lay.z_free1:.2f} (collar)"),
            Dim("z", (-ri, zcol), (-ri, z1), "left"),
            Dim("u", (-ri, z1), (ri, z1), "top", f"Ø{2 * ri:.2f}"),
            Dim("u", (-R, zcol), (R, zcol), "top", f"Ø{2 * R:.2f}"),
            Dim("u", (-lay.r_piston, z0), (lay.r_piston, z0), "bottom", fit_text(2 * lay.r_piston, "H8")))
    leaders = (Leader((ri - 0.5 * d.inner_tube_wall_mm, 0.5 * (z0 + lay.z_free1)),
                      f"wall {d.inner_tube_wall_mm:.2f}; bore Ra 0.4"),
               Leader((0.5 * (ri + R), zcol - 0.5), f"collar plate {d.collar_mm:.2f} over the bladder clamp"),
               Leader((seal.groove_diameter_mm / 2 - 0.2, 0.5 * sum(lay.z_collar_seal)),
                      f"groove root Ø{seal.groove_diameter_mm:.2f} h9 (O-ring {seal.oring.code})"),
               Leader((-(lay.r_bladder_out + 0.1), lay.z_free1 + 0.5 * lay.cuff),
                      "bladder cuff groove (fits the cast bladder)", "left"))
    notes = (*notes[:2],
             f"Top end: {c.cross_slots} slots {math.degrees(lay.slot_angle_rad):.1f}° wide x "
             f"{lay.slot_height:.2f} deep, centred at 45° + k·{360 / c.cross_slots:g}° (chamber 1: bore to annulus).",
             f"Collar to outer-tube bore: static seal, O-ring {seal.oring.name}; groove "
             f"Ø{seal.groove_diameter_mm:.2f} h9 x {seal.width_mm:.2f} +0.1 (squeeze {100 * seal.squeeze:.0f} %).")
    return SheetContent(dims, leaders, notes)


def housing_base_sheet(lay: Layout, solid: Solid) -> SheetContent:
    """Sheet of the base: height, valve axis, rod bore and seal groove, channels, valve bores, servo mount
    (and in the ``annulus_top`` layout the chamber-2 fill port).

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
    c = lay.cad
    R, _, _ = radial_extent_mm(solid)
    zb0, zv, rs = lay.z_base_top, lay.z_valve, lay.rod_seal
    dims = (Dim("z", (-R, 0.0), (-R, zb0), "left"),
            Dim("z", (-R, 0.0), (-R, zv), "left", f"{zv:.2f}", on_axis=True),
            Dim("z", (0.5 * lay.r_rod, 0.0), (0.5 * lay.r_rod, lay.z_rod_seal[0]), "inside", on_axis=True),
            Dim("u", (-R, zb0), (R, zb0), "top", f"Ø{2 * R:.2f}"),
            Dim("u", (-lay.r_ring_channel, zb0), (lay.r_ring_channel, zb0), "top",
                f"{2 * lay.r_ring_channel:.2f} (channel axes)", on_axis=True),
            Dim("u", (-lay.r_channel_a, zb0), (lay.r_channel_a, zb0), "top",
                f"{2 * lay.r_channel_a:.2f} (channel axes)", on_axis=True),
            Dim("u", (-lay.r_rod, 0.0), (lay.r_rod, 0.0), "bottom", fit_text(2 * lay.r_rod, "H8")))
    leaders = (
        Leader((R - 1.0, zv), f"throttle valve bore Ø{lay.throttle_d:g} to x = {lay.x_valve_inner:.2f}, "
                              f"axis {zv:.2f} from underside"),
        Leader((-R + 1.0, zv), f"relief bore Ø{lay.relief_d:g}, seat Ø{min(c.relief_seat_mm, lay.relief_d):g}",
               "left"),
        Leader((rs.groove_diameter_mm / 2 - 0.2, 0.5 * sum(lay.z_rod_seal)),
               f"rod seal groove Ø{rs.groove_diameter_mm:.2f} H9 x {rs.width_mm:.2f} +0.1 (O-ring {rs.oring.code})"),
        Leader((lay.r_channel_a, zb0 - 1.0), f"2x channel Ø{lay.base_channel_d:.2f} to the valve bores"),
        Leader((-lay.r_ring_channel, zb0 - 1.0), f"2x channel Ø{min(lay.base_channel_d, lay.ring_channel_d):.2f}",
               "left"),
    )
    gn = general_notes(lay)
    notes = [gn[0], gn[2], gn[4],
             f"Servo mount: 2x M3 (tap drill Ø{c.servo_screw_core_mm:g}) x {c.servo_screw_depth_mm:g} deep, "
             f"±{lay.throttle_d / 2 + 3.5:.2f} either side of the throttle bore."]
    if lay.has_top_annulus:
        notes.append(f"Chamber-2 fill port: Ø{lay.fill_port_d:.2f} through at y = +{lay.r_port2:.2f}"
                     + (f", M5 counterbore Ø{c.fill_port_counterbore_mm:g} x {c.fill_port_counterbore_depth_mm:g}"
                        if lay.r_port2 + c.fill_port_counterbore_mm / 2 < lay.r_outer - 0.8 else "")
                     + "; continues through the support ring.")
    return SheetContent(dims, leaders, tuple(notes))


def top_cap_sheet(lay: Layout, solid: Solid) -> SheetContent:
    """Sheet of the top cap: height, diameter, fill ports; with the top bladder clamp (not in the
    ``annulus_top`` layout, whose clamp is the inner tube's collar) its spigot and the cuff's groove.

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
    c = lay.cad
    R, _, _ = radial_extent_mm(solid)
    zc, zt = lay.z_cap, lay.z_top
    counterbore = f"M5 counterbore Ø{c.fill_port_counterbore_mm:g} x {c.fill_port_counterbore_depth_mm:g}"
    if lay.has_top_annulus:
        dims = (Dim("z", (-R, zc), (-R, zt), "left"),
                Dim("u", (-R, zt), (R, zt), "top", f"Ø{2 * R:.2f}"),
                Dim("u", (0.0, zt), (lay.r_port1, zt), "top", f"{lay.r_port1:.2f} (port 1 axis)", on_axis=True))
        leaders = (Leader((lay.r_port1, zt - 1.0), f"Ø{lay.fill_port_d:.2f} through (chamber 1), {counterbore}"),)
        notes = (general_notes(lay)[0],
                 "Plain cap: the top bladder clamp is the inner tube's collar; chamber 2 is charged through the base.")
        return SheetContent(dims, leaders, notes, plane="yz")
    dims = (Dim("z", (-R, zc), (-R, zt), "left"),
            Dim("z", (-lay.r_bore, lay.z_free1), (-lay.r_bore, zc), "left", f"{zc - lay.z_free1:.2f} (clamp)"),
            Dim("u", (-R, zt), (R, zt), "top", f"Ø{2 * R:.2f}"),
            Dim("u", (-lay.r_bore, lay.z_free1), (lay.r_bore, lay.z_free1), "bottom", f"Ø{2 * lay.r_bore:.2f}"),
            Dim("u", (-lay.r_inner_tube, lay.z_free1), (lay.r_inner_tube, lay.z_free1), "bottom",
                f"Ø{2 * lay.r_inner_tube:.2f}"),
            Dim("u", (0.0, zt), (lay.r_port2, zt), "top", f"{lay.r_port2:.2f} (port 2 axis)", on_axis=True),
            Dim("u", (0.0, zt), (lay.r_port1, zt), "top", f"{lay.r_port1:.2f} (port 1 axis)", on_axis=True))
    leaders = (Leader((lay.r_port1, zt - 1.0), f"Ø{lay.fill_port_d:.2f} through, {counterbore}"),
               Leader((lay.r_port2, lay.z_free1 + 1.0), f"Ø{lay.fill_port_d:.2f} through (chamber 2)"),
               Leader((-(lay.r_bladder_out + 0.1), lay.z_free1 + 0.5 * lay.cuff),
                      "bladder cuff groove (fits the cast bladder)", "left"))
    return SheetContent(dims, leaders, general_notes(lay)[:1], plane="yz")


def piston_sheet(lay: Layout, solid: Solid) -> SheetContent:
    """Sheet of the piston with its rod: heights, the f7 diameters, the tapped rod end, the pocket (if any)
    and a 5:1 detail of the two seal grooves.

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
    d, c = lay.design, lay.cad
    ps = lay.piston_seal
    zpb, zpt = lay.z_piston_bottom(0.0), lay.z_piston_top(0.0)
    zend = zpb - d.rod_length_mm
    (g0a, g0b), (g1a, g1b) = [(zpb + d.fixed.piston_height_mm * q - ps.width_mm / 2,
                               zpb + d.fixed.piston_height_mm * q + ps.width_mm / 2) for q in (0.27, 0.73)]
    rp, rg = lay.r_piston, ps.groove_diameter_mm / 2
    dims = [Dim("z", (-rp, zpb), (-rp, zpt), "left"),
            Dim("z", (-lay.r_rod, zend), (-lay.r_rod, zpb), "left", f"{d.rod_length_mm:.2f} (rod)"),
            Dim("u", (-rp, zpt), (rp, zpt), "top", fit_text(2 * rp, "f7")),
            Dim("u", (-lay.r_rod, zend), (lay.r_rod, zend), "bottom", fit_text(2 * lay.r_rod, "f7"))]
    leaders = [Leader((0.0, zend + c.rod_thread_depth_mm * 0.5),
                      f"M5 x {c.rod_thread_depth_mm:g} (tap drill Ø{c.rod_thread_core_mm:g})")]
    if lay.has_piston_pocket:  # the chamber-1 pocket in the crown (fixed.piston_pocket)
        a, zf = lay.r_pocket, zpt - d.piston_pocket_depth_mm
        dims += [Dim("u", (-a, zpt), (a, zpt), "top", f"Ø{2 * a:.2f} (pocket)"),
                 Dim("z", (-0.5 * a, zf), (-0.5 * a, zpt), "inside", f"{d.piston_pocket_depth_mm:.2f}", on_axis=True)]
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
    gn = general_notes(lay)
    return SheetContent(tuple(dims), tuple(leaders), (gn[0], gn[1], gn[2], gn[3]), detail=detail)
