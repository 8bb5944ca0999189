"""The machined parts' features, from the layout the solids are built from:
every cylinder, face, groove, hole, thread, chamfer and slot of a part with
its size, its tolerance, how its sheet gives it, and where it is in the solid.

A :class:`Feature` is the part's definition as a workshop reads it: the
drawing hooks (:mod:`vvea_design.cad.sheets`) put each feature's
annotation (:attr:`Feature.show`) on the part's sheet, and the tests check
the list against the solid both ways -- each feature is in the solid (its
``probe`` point lies in removed material; its section edges lie on the
drawn outline) and every edge of the part's section belongs to a feature
(:attr:`Feature.u_edges`, :attr:`Feature.z_edges`, :attr:`Feature.slants`),
so a feature the builder cuts but the list (and so the sheet) forgets is
found.

Coordinates as on the sheets: ``u`` across the axis in the sheet's section
plane (x in the valve plane, y in the port plane), ``z`` along it, model mm.
Tolerances: an ISO 286 fit, an explicit deviation, a thread class (ISO 965-1)
or :data:`GENERAL` (ISO 2768-m, in the sheet's notes).
"""

from __future__ import annotations

import math

from .drafting import Dim, Leader, fit_tolerance
from .feature_base import (DETAIL_KEYS, FEATURE_KINDS, GENERAL, GROOVE_WIDTH_TOL, SEAL_BORE_FIT, SPIGOT_FIT,
                           THREAD_CLASS, TUBE_OD_FIT, Feature, feature_texts, sheet_plane)
from .feature_base import fit_text as _fit
from .feature_base import groove_feature as _groove_feature
from .feature_base import lead_in_feature as _lead_in_feature
from .feature_base import symmetric as _sym
from .joint_features import base_joint_features, outer_tube_joint_features, top_cap_joint_features
from .layout import Layout
from .parts import tube_bottom_lead_in
from .seat_features import seat_features, tube_end_features

__all__ = ["Feature", "FEATURE_KINDS", "DETAIL_KEYS", "GENERAL", "GROOVE_WIDTH_TOL", "THREAD_CLASS", "outer_tube_features",
           "inner_tube_features", "top_cap_features", "base_features", "piston_features", "sheet_plane",
           "feature_texts", "unexplained_edges", "missing_edges"]

def _cuff_groove(lay: Layout, z_open: float, side: str, key: str) -> Feature:
    """The groove that holds the bladder's upper cuff, opening downwards at ``z_open``: inner/outer walls at the
    bead and above it, depth and bead length."""
    ri, ro, e, lb, cuff = lay.r_bladder_in, lay.r_bladder_out, lay.bead_mm, lay.bead_length, lay.cuff
    sgn = 1.0
    z_bead, z_end = z_open + sgn * lb, z_open + sgn * cuff
    size = f"Ø{2 * (ri - e):.2f}/Ø{2 * ri:.2f}/Ø{2 * ro:.2f}/Ø{2 * (ro + e):.2f}"
    txt = (f"bladder cuff groove {size} (bead/wall/wall/bead) x {cuff:.2f} deep, beads {lb:.2f} long; "
           "±0.05, Ra 1.6")
    return Feature(key, "groove", "bladder cuff groove", size, "±0.05", Leader((-(ro + 0.5 * e), z_open + sgn * 0.5 * lb),
                   txt, side), u_edges=_sym(ri - e, ri, ro, ro + e), z_edges=(z_bead, z_end),
                   probe=(-(0.5 * (ri + ro)), 0.0, z_open + sgn * 0.5 * cuff), finish="Ra 1.6")


def _tapped(key: str, y: float, z_face: float, depth: float, tap_d: float, lay: Layout, side: str, what: str,
            down: bool = True) -> Feature:
    """A charging valve's M5 tapped hole on a face at +y, with its spot face."""
    c = lay.cad
    z_bot = z_face - depth if down else z_face + depth
    txt = (f"{what}: M5x0.8-{THREAD_CLASS} x {depth:g} deep (tap drill Ø{tap_d:g}), spot face Ø{c.valve_spot_face_mm:g} "
           "flat, Ra 1.6")
    return Feature(key, "thread", what, "M5x0.8", THREAD_CLASS, Leader((y, z_face - (0.5 if down else -0.5)), txt, side),
                   u_edges=(y - tap_d / 2, y + tap_d / 2), z_edges=(z_bot,),
                   probe=(0.0, y, 0.5 * (z_face + z_bot)), finish="Ra 1.6", standard="ISO 261, ISO 965-1")


# ----------------------------------------------------------------------------------------------- parts
def outer_tube_features(lay: Layout) -> tuple[Feature, ...]:
    """The outer tube's features: length, outside diameter, the sealing bore, the lead-in chamfers at its ends.

    Parameters
    ----------
    lay : Layout
        Radii and levels of the design, mm.

    Returns
    -------
    tuple of Feature
        In sheet order.
    """
    if lay.has_joint:  # threaded or counterbored ends (the design's joint)
        return outer_tube_joint_features(lay)
    R, rb, z0, z1 = lay.r_outer, lay.r_bore, lay.z_base_top, lay.z_cap
    lo, hi = lay.lead_in_outer_bottom, lay.lead_in_outer_top
    od, od_tol = _fit(2 * R, TUBE_OD_FIT)
    bd, bd_tol = _fit(2 * rb, SEAL_BORE_FIT)
    zb = z1 - hi.length_mm if hi is not None else z1
    f = [Feature("length", "length", "length", f"{z1 - z0:.2f}", GENERAL, Dim("z", (-R, z0), (-R, z1), "left"),
                 z_edges=(z0, z1)),
         Feature("outside", "diameter", "outside diameter", od, od_tol, Dim("u", (-R, z1), (R, z1), "top", f"{od} {od_tol}"),
                 u_edges=_sym(R)),
         Feature("bore", "diameter", "bore (O-ring counter-surface)", bd, bd_tol,
                 Dim("u", (-rb, zb), (rb, zb), "top", f"{bd} {bd_tol}"), u_edges=_sym(rb), finish="Ra 0.8",
                 standard="ISO 3601-2"),
         _lead_in_feature("lead_in_bottom", "bore, bottom end", lo, rb, z0, True, True, "right", lay.base_seal)]
    if hi is not None:
        f.append(_lead_in_feature("lead_in_top", "bore, top end", hi, rb, z1, True, False, "right", lay.cap_seal))
    return tuple(f)


def inner_tube_features(lay: Layout) -> tuple[Feature, ...]:
    """The inner tube's features: length, diameters, the piston's bore with its lead-in; with a bulkhead the web,
    the blind bore's depth and the fill tube; with the ``annulus_top`` collar its rim, seal groove, cuff groove and
    the slots.

    Parameters
    ----------
    lay : Layout
        Radii and levels of the design, mm.

    Returns
    -------
    tuple of Feature
        In sheet order.
    """
    d = lay.design
    ri, rp, z1 = lay.r_inner_tube, lay.r_piston, lay.z_cap
    li, z0 = tube_bottom_lead_in(lay)  # the tube's ends: in the end pieces' seats with a joint
    seats = lay.seats
    zt = seats.z_top_end if seats is not None and seats.top is not None else z1
    od, od_tol = _fit(2 * ri, TUBE_OD_FIT)
    bd, bd_tol = _fit(2 * rp, "H8")
    f = [Feature("length", "length", "length", f"{zt - z0:.2f}", GENERAL, Dim("z", (-ri, z0), (-ri, zt), "left"),
                 z_edges=(z0, zt)),
         Feature("outside", "diameter", "outside diameter", od, od_tol,
                 Dim("u", (-ri, zt), (ri, zt), "top", f"{od} {od_tol}"), u_edges=_sym(ri)),
         Feature("bore", "diameter", "piston bore", bd, bd_tol,
                 Dim("u", (-rp, z0 + li.length_mm), (rp, z0 + li.length_mm), "bottom", f"{bd} {bd_tol}"),
                 u_edges=_sym(rp), finish="Ra 0.4 (honed)", standard="ISO 286, ISO 3601-2"),
         _lead_in_feature("lead_in_bottom", "piston bore, bottom end", li, rp, z0, True, True, "right",
                          seats.base if seats is not None else lay.piston_seal),
         *tube_end_features(lay)]
    if lay.has_bulkhead:
        zb0, zb1 = lay.z_bulkhead0, lay.z_bulkhead1
        rf, rfb = lay.r_fill_tube_out, lay.r_fill_tube_bore
        f += [Feature("bore_depth", "length", "blind bore depth (to the bulkhead)", f"{zb0 - z0:.2f}", GENERAL,
                      Dim("z", (ri, z0), (rp, zb0), "right"), z_edges=(zb0,)),
              Feature("bulkhead", "length", "bulkhead web", f"{d.bulkhead_mm:.2f}", "±0.05",
                      Leader((0.5 * (rf + rp), zb1), f"bulkhead web {d.bulkhead_mm:.2f} ±0.05 thick (its underside "
                             f"{zb0 - z0:.2f} from the bottom end)"), z_edges=(zb1,)),
              Feature("fill_tube", "diameter", "fill tube outside", f"Ø{2 * rf:.2f}", "±0.05",
                      Dim("u", (-rf, z1), (rf, z1), "top", f"Ø{2 * rf:.2f} ±0.05 (fill tube)"), u_edges=_sym(rf)),
              Feature("fill_tube_bore", "hole", "fill tube bore (chamber 1), through bulkhead and tube", f"Ø{2 * rfb:.2f}",
                      GENERAL, Leader((rfb, 0.5 * (zb0 + z1)), f"Ø{2 * rfb:.2f} through (chamber 1: fill tube and bulkhead)"),
                      u_edges=_sym(rfb), probe=(0.0, 0.0, 0.5 * (zb0 + zb1))),
              Feature("top_space", "length", "depth of the chamber-2 space above the bulkhead", f"{z1 - zb1:.2f}",
                      GENERAL, Dim("z", (-rf, zb1), (-rf, z1), "inside"), probe=(0.5 * (rf + rp), 0.0, 0.5 * (zb1 + z1)))]
    if lay.has_top_annulus:
        f += _collar_features(lay)
    return tuple(f)


def _collar_features(lay: Layout) -> list[Feature]:
    """The ``annulus_top`` collar on the inner tube: rim, levels, seal groove, cuff groove, slots."""
    c = lay.cad
    R, rb, zc1, zf1, z1 = lay.r_bore, lay.r_bore, lay.z_collar1, lay.z_free1, lay.z_cap
    seal = lay.collar_seal
    rim, rim_tol = _fit(2 * rb, SPIGOT_FIT)
    f = [Feature("collar_rim", "diameter", "collar rim (in the outer-tube bore)", rim, rim_tol,
                 Dim("u", (-R, zc1), (R, zc1), "top", f"{rim} {rim_tol}"), u_edges=_sym(rb)),
         Feature("collar_height", "length", "collar (clamp + plate)", f"{zc1 - zf1:.2f}", GENERAL,
                 Dim("z", (-R, zf1), (-R, zc1), "left", f"{zc1 - zf1:.2f} (collar)"), z_edges=(zf1,)),
         Feature("collar_level", "length", "collar top below the tube's top", f"{z1 - zc1:.2f}", GENERAL,
                 Dim("z", (-lay.r_inner_tube, zc1), (-lay.r_inner_tube, z1), "left"), z_edges=(zc1,)),
         *_groove_feature("collar_seal", seal, *lay.z_collar_seal, zc1, "the collar's top", "right"),
         _cuff_groove(lay, zf1, "left", "cuff_groove"),
         Feature("slots", "slot", "slots in the top end", f"{c.cross_slots}x {math.degrees(lay.slot_angle_rad):.1f}°",
                 GENERAL, f"Top end: {c.cross_slots}x {math.degrees(lay.slot_angle_rad):.1f}° slots (wide) x "
                 f"{lay.slot_height:.2f} deep, centred at 45° + k·{360 / c.cross_slots:g}° (chamber 1: bore to annulus); "
                 f"{GENERAL}.",
                 probe=(0.5 * (lay.r_piston + lay.r_inner_tube) * math.cos(math.pi / 4),
                        0.5 * (lay.r_piston + lay.r_inner_tube) * math.sin(math.pi / 4), z1 - 0.5 * lay.slot_height))]
    return f


def top_cap_features(lay: Layout) -> tuple[Feature, ...]:
    """The top cap's features: thickness, diameter, the charging valves' tapped holes and ports; with the top
    bladder clamp (its spigot in the outer tube) the spigot's diameters and length, its seal groove, the cuff
    groove, the chamber-2 port, cross port (riser in ``bulkhead``) and the cross port's plug bore.

    Parameters
    ----------
    lay : Layout
        Radii and levels of the design, mm.

    Returns
    -------
    tuple of Feature
        In sheet order (section in the port plane x = 0, u = y).
    """
    c = lay.cad
    R, z1, zt = lay.r_outer, lay.z_cap, lay.z_cap_face
    tap, tap_d = c.fill_port_counterbore_mm, c.fill_port_counterbore_depth_mm
    f = [Feature("thickness", "length", "thickness", f"{zt - z1:.2f}", GENERAL, Dim("z", (-R, z1), (-R, zt), "left"),
                 z_edges=(z1, zt)),
         Feature("outside", "diameter", "outside diameter", f"Ø{2 * R:.2f}", GENERAL,
                 Dim("u", (-R, zt), (R, zt), "top", f"Ø{2 * R:.2f}"), u_edges=_sym(R))]
    # chamber 1: the fill tube's bore on the axis (bulkhead) or a port over the piston
    if lay.has_bulkhead:
        rb = lay.r_fill_tube_bore
        f.append(Feature("port1", "hole", "chamber-1 port (fill tube's bore)", f"Ø{2 * rb:.2f}", GENERAL,
                         Leader((rb, z1 + 0.5), f"chamber 1: Ø{2 * rb:.2f} through on the axis (to the fill tube)"),
                         u_edges=_sym(rb), probe=(0.0, 0.0, z1 + 0.5)))
    else:
        rp1, dp = lay.r_port1, lay.fill_port_d
        f += [Feature("port1", "hole", "chamber-1 port", f"Ø{dp:.2f}", GENERAL,
                      Leader((rp1 - dp / 2, z1 + 0.5), f"chamber 1: Ø{dp:.2f} through"),
                      u_edges=(rp1 - dp / 2, rp1 + dp / 2), probe=(0.0, rp1, z1 + 0.5)),
              Feature("port1_position", "length", "chamber-1 port position", f"{rp1:.2f}", GENERAL,
                      Dim("u", (0.0, zt), (rp1, zt), "top", f"{rp1:.2f} (port 1 axis)", on_axis=True))]
    f.append(_tapped("valve1_thread", lay.y_port1, zt, tap_d, tap, lay, "right", "chamber-1 charging valve"))
    if not lay.has_top_annulus:
        f += _clamp_features(lay)
        f += _chamber2_features(lay, "right")
    f += seat_features(lay, "housing_top_cap")
    if lay.has_joint:  # the shoulder above the tube, the spigot's thread (or the ring's plug), the rods' holes
        return top_cap_joint_features(lay, tuple(f))
    return tuple(f)


def _clamp_features(lay: Layout) -> list[Feature]:
    """The top bladder clamp (the cap's spigot): diameters, length, seal groove, cuff groove."""
    rb, rin, zf1, z1 = lay.r_bore, lay.r_inner_tube, lay.z_free1, lay.z_cap
    so, so_tol = _fit(2 * rb, SPIGOT_FIT)
    si, si_tol = _fit(2 * rin, "H9")
    return [Feature("spigot_outside", "diameter", "spigot outside (in the outer-tube bore)", so, so_tol,
                    Dim("u", (-rb, zf1), (rb, zf1), "bottom", f"{so} {so_tol}"), u_edges=_sym(rb)),
            Feature("spigot_inside", "diameter", "spigot bore (over the inner tube)", si, si_tol,
                    Dim("u", (-rin, zf1), (rin, zf1), "bottom", f"{si} {si_tol}"), u_edges=_sym(rin)),
            Feature("spigot_length", "length", "spigot length", f"{z1 - zf1:.2f}", GENERAL,
                    Dim("z", (-rb, zf1), (-rb, z1), "left", f"{z1 - zf1:.2f} (clamp)"), z_edges=(zf1,)),
            *_groove_feature("cap_seal", lay.cap_seal, *lay.z_cap_seal, zf1, "the spigot's end", "left", -1.0),
            _cuff_groove(lay, zf1, "left", "cuff_groove")]


def _chamber2_features(lay: Layout, side: str) -> list[Feature]:
    """The chamber-2 port through the top clamp, its valve's hole (the riser in ``bulkhead``), the cross port from
    the outside and its plug bore; or a straight port under the valve."""
    c = lay.cad
    R, z1, zt, zf1 = lay.r_outer, lay.z_cap, lay.z_cap_face, lay.z_free1
    dp, rp2, tap, tap_d = lay.fill_port_d, lay.r_port2, c.fill_port_counterbore_mm, c.fill_port_counterbore_depth_mm
    f = [Feature("port2_position", "length", "chamber-2 port position", f"{rp2:.2f}", GENERAL,
                 Dim("u", (0.0, zf1), (rp2, zf1), "bottom", f"{rp2:.2f} (port 2 axis)", on_axis=True))]
    if not lay.has_cross_port:
        f += [Feature("port2", "hole", "chamber-2 port", f"Ø{dp:.2f}", GENERAL,
                      Leader((rp2 - dp / 2, 0.5 * (zf1 + z1)), f"chamber 2: Ø{dp:.2f} through cap and clamp", side),
                      u_edges=(rp2 - dp / 2, rp2 + dp / 2), probe=(0.0, rp2, z1)),
              _tapped("valve2_thread", rp2, zt, tap_d, tap, lay, side, "chamber-2 charging valve")]
        return f
    zc, rc, yv = lay.z_cross_port, lay.cross_port_d / 2, lay.y_valve2
    riser = "riser: " if lay.has_bulkhead else ""
    to = "through to the cap's underside (chamber 2 above the bulkhead)" if lay.has_bulkhead else "to the cross port"
    f += [Feature("port2", "hole", "chamber-2 port", f"Ø{dp:.2f}", GENERAL,
                  Leader((rp2 - dp / 2, 0.5 * (zf1 + z1)), f"chamber 2: Ø{dp:.2f} from the clamp's end to the cross "
                         f"port ({zc - zf1:.2f} deep)", side), u_edges=(rp2 - dp / 2, rp2 + dp / 2),
                  probe=(0.0, rp2, z1)),
          Feature("valve2_hole", "hole", "chamber-2 valve hole", f"Ø{2 * rc:.2f}", GENERAL,
                  Leader((yv - rc, 0.5 * (zc + zt - tap_d) + (0.0 if not lay.has_bulkhead else -1.0)),
                         f"{riser}Ø{2 * rc:.2f} from the valve's thread {to}", side),
                  u_edges=(yv - rc, yv + rc), probe=(0.0, yv, zc + rc + 0.2)),
          Feature("valve2_position", "length", "chamber-2 valve position", f"{yv:.2f}", GENERAL,
                  Dim("u", (0.0, zt), (yv, zt), "top", f"{yv:.2f} (valve 2 axis)", on_axis=True)),
          _tapped("valve2_thread", yv, zt, tap_d, tap, lay, side, "chamber-2 charging valve"),
          Feature("cross_port", "hole", "cross port (drilled from the outside)", f"Ø{2 * rc:.2f}", GENERAL,
                  Leader((0.5 * (yv + rp2), zc - rc), f"cross port Ø{2 * rc:.2f} from the outside to the valve hole, "
                         f"axis {zc - z1:.2f} above the underside", side), z_edges=(zc - rc, zc + rc),
                  probe=(0.0, 0.5 * (yv + rp2), zc)),
          Feature("cross_port_level", "length", "cross port axis", f"{zc - z1:.2f}", GENERAL,
                  Dim("z", (R, z1), (R, zc), "right", on_axis=True)),
          Feature("plug_bore", "hole", "plug bore of the cross port", f"Ø{c.plug_bore_mm:.2f}",
                  fit_tolerance(c.plug_bore_mm, "H11"),
                  Leader((R - 0.5 * c.plug_depth_mm, zc + 0.5 * c.plug_bore_mm),
                         f"Ø{c.plug_bore_mm:.2f} {fit_tolerance(c.plug_bore_mm, 'H11')} x {c.plug_depth_mm:g} deep, "
                         "Ra 1.6: expander plug (see parts list)", side),
                  u_edges=(R - c.plug_depth_mm,), z_edges=(zc - c.plug_bore_mm / 2, zc + c.plug_bore_mm / 2),
                  probe=(0.0, R - 0.5 * c.plug_depth_mm, zc), finish="Ra 1.6")]
    return f


def base_features(lay: Layout) -> tuple[Feature, ...]:
    """The base's features: height, diameter, the spigot with its seal groove and the cuff's outer wall, the rod
    bore and seal groove, the valve bores, the fluid channels, the servo screws; in ``annulus_top`` the chamber-2
    port and its valve.

    Parameters
    ----------
    lay : Layout
        Radii and levels of the design, mm.

    Returns
    -------
    tuple of Feature
        In sheet order (section in the valve plane y = 0, u = x).
    """
    R, z0, zf0 = lay.r_outer, lay.z_base_top, lay.z_free0
    rb, ro, e = lay.r_bore, lay.r_bladder_out, lay.bead_mm
    rs, rr = lay.rod_seal, lay.r_rod
    so, so_tol = _fit(2 * rb, SPIGOT_FIT)
    rod, rod_tol = _fit(2 * rr, "H8")
    f = [Feature("height", "length", "height", f"{z0:.2f}", GENERAL, Dim("z", (-R, 0.0), (-R, z0), "left"),
                 z_edges=(0.0, z0)),
         Feature("outside", "diameter", "outside diameter", f"Ø{2 * R:.2f}", GENERAL,
                 Dim("u", (-R, z0), (R, z0), "top", f"Ø{2 * R:.2f}"), u_edges=_sym(R)),
         Feature("spigot_outside", "diameter", "spigot outside (in the outer-tube bore)", so, so_tol,
                 Dim("u", (-rb, zf0), (rb, zf0), "top", f"{so} {so_tol}"), u_edges=_sym(rb)),
         Feature("spigot_height", "length", "spigot height", f"{zf0 - z0:.2f}", GENERAL,
                 Dim("z", (rb, z0), (rb, zf0), "right", f"{zf0 - z0:.2f} (spigot)"), z_edges=(zf0,)),
         Feature("spigot_inside", "diameter", "spigot bore (the lower cuff's outer wall) and the bead's groove",
                 f"Ø{2 * ro:.2f}/Ø{2 * (ro + e):.2f}", "±0.05",
                 Leader((-ro, 0.5 * (lay.z_bladder0 + lay.bead_length + zf0)),
                        f"bore / bead groove Ø{2 * ro:.2f}/Ø{2 * (ro + e):.2f} ±0.05 (the cuff's outer wall), "
                        f"groove {lay.bead_length:.2f} wide, {lay.z_bladder0 - z0:.2f} above the base top, Ra 1.6",
                        "left"),
                 u_edges=_sym(ro, ro + e), z_edges=(lay.z_bladder0, lay.z_bladder0 + lay.bead_length),
                 probe=(-(ro + 0.5 * e), 0.0, lay.z_bladder0 + 0.5 * lay.bead_length), finish="Ra 1.6"),
         *_groove_feature("base_seal", lay.base_seal, *lay.z_base_seal, zf0, "the spigot's top", "right"),
         Feature("rod_bore", "diameter", "rod bore", rod, rod_tol,
                 Dim("u", (-rr, 0.0), (rr, 0.0), "bottom", f"{rod} {rod_tol}"), u_edges=_sym(rr),
                 finish="Ra 0.4"),
         *_groove_feature("rod_seal", rs, *lay.z_rod_seal, 0.0, "the underside", "right"),
         Feature("rod_seal_position", "length", "rod seal groove from the underside", f"{lay.z_rod_seal[0]:.2f}",
                 GENERAL, Dim("z", (0.5 * rr, 0.0), (0.5 * rr, lay.z_rod_seal[0]), "inside", on_axis=True))]
    f += _valve_features(lay)
    f += seat_features(lay, "housing_base")
    if lay.has_top_annulus:
        f += _base_port_notes(lay)
    if lay.has_joint:  # the own part's shoulder, the spigot's thread and run-out, the rods' holes
        return base_joint_features(lay, tuple(f))
    return tuple(f)


def _valve_features(lay: Layout) -> list[Feature]:
    """The base's valve bores (throttle +x, relief -x with seat and adjusting thread), channels, servo screws."""
    c = lay.cad
    R, z0, zv = lay.r_outer, lay.z_base_top, lay.z_valve
    td, rd, seat = lay.throttle_d, lay.relief_d, lay.relief_seat_d
    x_in = lay.x_valve_inner
    x_b = lay.r_ring_channel - lay.ring_channel_d / 2 - 0.5
    thread = relief_thread(lay)
    ch, rch = lay.base_channel_d, min(lay.base_channel_d, lay.ring_channel_d)
    ys = td / 2 + 3.5
    return [
        Feature("valve_axis", "length", "valve bores' axis from the underside", f"{zv:.2f}", GENERAL,
                Dim("z", (-R, 0.0), (-R, zv), "left", f"{zv:.2f}", on_axis=True)),
        Feature("throttle_bore", "hole", "rotary throttle bore (+x)", f"Ø{td:g}", fit_tolerance(td, "H8"),
                Leader((R - 1.0, zv), f"throttle bore Ø{td:g} {fit_tolerance(td, 'H8')} Ra 0.8 from the outside to "
                       f"{x_in:.2f} from the axis"),
                u_edges=(x_in,), z_edges=(zv - td / 2, zv + td / 2), probe=(0.5 * (x_in + R), 0.0, zv),
                finish="Ra 0.8"),
        Feature("relief_bore", "hole", "relief valve bore (-x)", f"Ø{rd:g}", GENERAL,
                Leader((-R + 1.0, zv), f"relief bore Ø{rd:g} to {x_b:.2f} from the axis, thread {thread} x "
                       f"{relief_thread_depth(lay):.1f} from the outside", "left"),
                u_edges=(-x_b,), z_edges=(zv - rd / 2, zv + rd / 2), probe=(-0.5 * (x_b + R), 0.0, zv)),
        Feature("relief_thread", "thread", "relief adjusting thread", thread.split("-")[0], THREAD_CLASS,
                f"Relief bore: thread {thread} (ISO 261/965-1), {relief_thread_depth(lay):.1f} deep from the outside, "
                "for the adjusting set screw (parts list).",
                probe=(-(R - 0.5), 0.0, zv), standard="ISO 261, ISO 965-1"),
        Feature("relief_seat", "hole", "relief seat drilling", f"Ø{seat:g}", "±0.02",
                Leader((-(x_in + 0.5), zv), f"seat Ø{seat:g} ±0.02, sharp seat edge for the ball, to {x_in:.2f}",
                       "left"),
                u_edges=(-x_in,), z_edges=(zv - seat / 2, zv + seat / 2), probe=(-(x_in + 0.3), 0.0, zv)),
        Feature("channels", "hole", "fluid-column channels", f"Ø{ch:.2f}", GENERAL,
                Leader((lay.r_channel_a, z0 - 1.0), f"2x channel Ø{ch:.2f} from the top to the valve axis"),
                u_edges=_sym(lay.r_channel_a - ch / 2, lay.r_channel_a + ch / 2),
                probe=(lay.r_channel_a, 0.0, z0 - 0.5)),
        Feature("channel_positions", "length", "fluid-column channel axes", f"{2 * lay.r_channel_a:.2f}", GENERAL,
                Dim("u", (-lay.r_channel_a, z0), (lay.r_channel_a, z0), "top", f"{2 * lay.r_channel_a:.2f} (channel axes)",
                    on_axis=True)),
        Feature("ring_channels", "hole", "support-ring channels", f"Ø{rch:.2f}", GENERAL,
                Leader((-lay.r_ring_channel, z0 - 1.0), f"2x channel Ø{rch:.2f} from the top to the valve axis", "left"),
                u_edges=_sym(lay.r_ring_channel - rch / 2, lay.r_ring_channel + rch / 2),
                probe=(lay.r_ring_channel, 0.0, z0 - 0.5)),
        Feature("ring_channel_positions", "length", "support-ring channel axes", f"{2 * lay.r_ring_channel:.2f}",
                GENERAL, Dim("u", (-lay.r_ring_channel, z0), (lay.r_ring_channel, z0), "top",
                             f"{2 * lay.r_ring_channel:.2f} (channel axes)", on_axis=True)),
        Feature("servo_screws", "thread", "servo mount screw holes", "M3x0.5", THREAD_CLASS,
                f"Servo mount: 2x M3x0.5-{THREAD_CLASS} x {c.servo_screw_depth_mm:g} deep (tap drill "
                f"Ø{c.servo_screw_core_mm:g}) from the +x face, at y = ±{ys:.2f}, axis {zv:.2f} from the underside.",
                probe=(math.sqrt(R**2 - ys**2) - 0.5 * c.servo_screw_depth_mm, ys, zv), standard="ISO 261, ISO 965-1"),
    ]


def relief_thread(lay: Layout) -> str:
    """The relief bore's adjusting thread: the ISO 261 thread whose tap drill (bd_warehouse's table, aluminium) is
    the relief bore, coarse pitch first, e.g. ``M6x1``.

    Parameters
    ----------
    lay : Layout
        The design's layout (its relief bore, mm).

    Returns
    -------
    str
        Thread designation with its class, e.g. ``M6x1-6H``.
    """
    from bd_warehouse.fastener import Screw

    best = None
    for size, holes in Screw.tap_hole_data.items():
        if not size.startswith("M") or "-" not in size:
            continue
        drill = holes.get("Soft")
        major = float(size[1:].split("-")[0])
        if drill is not None and drill <= lay.relief_d + 1e-9 and major <= lay.relief_d + 1.5:
            key = (drill, major, -float(size.split("-")[1]))
            if best is None or key > best[0]:
                best = (key, size)
    if best is None:
        raise ValueError(f"no ISO 261 thread taps a Ø{lay.relief_d:g} mm relief bore")
    major, pitch = best[1][1:].split("-")
    return f"M{major}x{pitch}-{THREAD_CLASS}"


def relief_thread_depth(lay: Layout) -> float:
    """Depth of the relief bore's adjusting thread from the outside: 1.5 x the thread's diameter, mm.

    Parameters
    ----------
    lay : Layout
        The design's layout.

    Returns
    -------
    float
        Thread depth, mm.
    """
    return 1.5 * float(relief_thread(lay)[1:].split("x")[0])


def _base_port_notes(lay: Layout) -> list[Feature]:
    """``annulus_top``: the chamber-2 port through the base and its spigot, its valve on the underside."""
    c = lay.cad
    dp, rp2, zf0 = lay.fill_port_d, lay.r_port2, lay.z_free0
    tap, tap_d = c.fill_port_counterbore_mm, c.fill_port_counterbore_depth_mm
    f = [Feature("port2", "hole", "chamber-2 port", f"Ø{dp:.2f}", GENERAL,
                 f"Chamber-2 fill port: Ø{dp:.2f} at y = +{rp2:.2f}, from the underside through the base and its spigot; "
                 f"{GENERAL}.", probe=(0.0, rp2, 0.5 * (lay.z_base_top + zf0)))]
    if lay.has_cross_port:
        raise NotImplementedError("annulus_top chamber-2 valve inboard of its port: cross port in the base not drawn")
    f.append(Feature("valve2_thread", "thread", "chamber-2 charging valve", "M5x0.8", THREAD_CLASS,
                     f"Chamber-2 charging valve: M5x0.8-{THREAD_CLASS} x {tap_d:g} deep (tap drill Ø{tap:g}) at "
                     f"y = +{rp2:.2f} from the underside, spot face Ø{c.valve_spot_face_mm:g} flat, Ra 1.6.",
                     probe=(0.0, rp2 + 0.5 * (tap - dp) - 0.05, 0.5), finish="Ra 1.6", standard="ISO 261, ISO 965-1"))
    return f


def piston_features(lay: Layout) -> tuple[Feature, ...]:
    """The piston's features: height and diameter (f7), the two seal grooves and their positions, the rod (f7),
    its length, tapped end and lead-in chamfer, the pocket (``fixed.piston_pocket``).

    Parameters
    ----------
    lay : Layout
        Radii and levels of the design, mm.

    Returns
    -------
    tuple of Feature
        In sheet order (section in the valve plane at x = 0).
    """
    d, c = lay.design, lay.cad
    ps = lay.piston_seal
    rp, rr = lay.r_piston, lay.r_rod
    zpb, zpt = lay.z_piston_bottom(0.0), lay.z_piston_top(0.0)
    zend = zpb - d.rod_length_mm
    li = lay.lead_in_rod
    (g0a, g0b), (g1a, g1b) = [(zpb + d.fixed.piston_height_mm * q - ps.width_mm / 2,
                               zpb + d.fixed.piston_height_mm * q + ps.width_mm / 2) for q in (0.27, 0.73)]
    pd, pd_tol = _fit(2 * rp, "f7")
    rd, rd_tol = _fit(2 * rr, "f7")
    rg = ps.groove_diameter_mm / 2
    gd, g_tol = _fit(2 * rg, "h9")
    rad = ps.radius_range_mm
    f = [Feature("height", "length", "piston height", f"{zpt - zpb:.2f}", GENERAL,
                 Dim("z", (-rp, zpb), (-rp, zpt), "left"), z_edges=(zpb, zpt)),
         Feature("outside", "diameter", "piston", pd, pd_tol, Dim("u", (-rp, zpt), (rp, zpt), "top", f"{pd} {pd_tol}"),
                 u_edges=_sym(rp), finish="Ra 0.8"),
         Feature("rod", "diameter", "rod", rd, rd_tol,
                 Dim("u", (-rr, zend + li.length_mm), (rr, zend + li.length_mm), "bottom", f"{rd} {rd_tol}"),
                 u_edges=_sym(rr), finish="Ra 0.2", standard="ISO 3601-2 (dynamic counter-surface)"),
         Feature("rod_length", "length", "rod length", f"{d.rod_length_mm:.2f}", GENERAL,
                 Dim("z", (-(rr - li.depth_mm), zend), (-rr, zpb), "left", f"{d.rod_length_mm:.2f} (rod)"),
                 z_edges=(zend,)),
         Feature("rod_thread", "thread", "tapped rod end", "M5x0.8", THREAD_CLASS,
                 Leader((0.0, zend + c.rod_thread_depth_mm * 0.5),
                        f"M5x0.8-{THREAD_CLASS} x {c.rod_thread_depth_mm:g} (tap drill Ø{c.rod_thread_core_mm:g})"),
                 u_edges=_sym(c.rod_thread_core_mm / 2), z_edges=(zend + c.rod_thread_depth_mm,),
                 probe=(0.0, 0.0, zend + 0.5 * c.rod_thread_depth_mm), standard="ISO 261, ISO 965-1"),
         _lead_in_feature("rod_lead_in", "rod end", li, rr, zend, False, True, "left", lay.rod_seal),
         Feature("grooves", "groove", "piston seal grooves", gd, g_tol,
                 Leader((rg, 0.5 * (g0a + g0b)), f"2x groove root {gd} {g_tol}, R{ps.radius_mm:.2f} (R{rad[0]:.2f}..."
                        f"{rad[1]:.2f}); 2x O-ring {ps.oring.name}; {ps.finish_text}"),
                 u_edges=_sym(rg), z_edges=(g0a, g0b, g1a, g1b), probe=(0.5 * (rg + rp), 0.0, 0.5 * (g0a + g0b)),
                 finish=ps.finish_text, standard="ISO 3601-2 (bd_warehouse gland data)"),
         Feature("groove_width", "groove", "piston seal groove width (detail A)", f"{ps.width_mm:.2f}", GROOVE_WIDTH_TOL,
                 Dim("z", (rp, g0a), (rp, g0b), "right", f"{ps.width_mm:.2f} {GROOVE_WIDTH_TOL}")),
         Feature("groove_radius", "radius", "groove root radius", f"R{ps.radius_mm:.2f}", f"R{rad[0]:.2f}...{rad[1]:.2f}",
                 f"Seal grooves: root radius R{ps.radius_mm:.2f} (R{rad[0]:.2f}...{rad[1]:.2f}), groove edges "
                 "0.1...0.2 rounded, burr-free (ISO 3601-2).", standard="ISO 3601-2")]
    if lay.has_piston_pocket:
        a, zf = lay.r_pocket, zpt - d.piston_pocket_depth_mm
        f += [Feature("pocket", "diameter", "pocket", f"Ø{2 * a:.2f}", GENERAL,
                      Dim("u", (-a, zpt), (a, zpt), "top", f"Ø{2 * a:.2f} (pocket)"), u_edges=_sym(a),
                      probe=(0.0, 0.0, zpt - 0.5)),
              Feature("pocket_depth", "length", "pocket depth", f"{d.piston_pocket_depth_mm:.2f}", GENERAL,
                      Dim("z", (-0.5 * a, zf), (-0.5 * a, zpt), "inside", f"{d.piston_pocket_depth_mm:.2f}",
                          on_axis=True), z_edges=(zf,))]
    return tuple(f)


# ----------------------------------------------------------------------------------------------- checks
def unexplained_edges(loops, features, tol_mm: float = 1e-5) -> list[str]:
    """Edges of a part's section that no feature makes: the features the list (and so the sheet) forgets.

    Every straight edge of the section is explained by a feature: a vertical one by a feature's
    :attr:`Feature.u_edges`, a horizontal one by its :attr:`Feature.z_edges`, a slanted one by its
    :attr:`Feature.slants`.

    Parameters
    ----------
    loops : sequence of ndarray
        The part's section in its sheet's plane (:func:`~vvea_design.cad.section.section_loops`), (u, z) mm.
    features : iterable of Feature
        The part's features.
    tol_mm : float
        Distance accepted, mm.

    Returns
    -------
    list of str
        One message per unexplained edge (empty: the list covers the section).
    """
    import numpy as np

    feats = list(features)
    us = np.array([u for f in feats for u in f.u_edges] or [np.inf])
    zs = np.array([z for f in feats for z in f.z_edges] or [np.inf])
    slants = [(np.asarray(p), np.asarray(q)) for f in feats for p, q in f.slants]
    bad = []
    for lp in loops:
        for a, b in zip(lp[:-1], lp[1:]):
            if np.allclose(a, b, atol=1e-9):
                continue
            if abs(a[0] - b[0]) < tol_mm:
                if np.abs(us - a[0]).min() > tol_mm:
                    bad.append(f"vertical edge at u = {a[0]:.4f}, z = {min(a[1], b[1]):.3f}...{max(a[1], b[1]):.3f}")
            elif abs(a[1] - b[1]) < tol_mm:
                if np.abs(zs - a[1]).min() > tol_mm:
                    bad.append(f"horizontal edge at z = {a[1]:.4f}, u = {min(a[0], b[0]):.3f}...{max(a[0], b[0]):.3f}")
            elif not any((np.allclose(a, p, atol=tol_mm) and np.allclose(b, q, atol=tol_mm))
                         or (np.allclose(a, q, atol=tol_mm) and np.allclose(b, p, atol=tol_mm)) for p, q in slants):
                bad.append(f"slanted edge ({a[0]:.3f}, {a[1]:.3f})-({b[0]:.3f}, {b[1]:.3f})")
    return bad


def missing_edges(loops, features, tol_mm: float = 1e-5) -> list[str]:
    """Edges a feature says it makes that the section does not have: a feature the solid lacks.

    Parameters
    ----------
    loops : sequence of ndarray
        The part's section in its sheet's plane, (u, z) mm.
    features : iterable of Feature
        The part's features.
    tol_mm : float
        Distance accepted, mm.

    Returns
    -------
    list of str
        One message per declared edge not found (empty: every feature's edges are in the section).
    """
    import numpy as np

    segs = [(a, b) for lp in loops for a, b in zip(lp[:-1], lp[1:]) if not np.allclose(a, b, atol=1e-9)]
    vert = np.array([a[0] for a, b in segs if abs(a[0] - b[0]) < tol_mm] or [np.inf])
    hor = np.array([a[1] for a, b in segs if abs(a[1] - b[1]) < tol_mm] or [np.inf])
    bad = []
    for f in features:
        bad += [f"{f.key}: no vertical edge at u = {u:.4f}" for u in f.u_edges if np.abs(vert - u).min() > tol_mm]
        bad += [f"{f.key}: no horizontal edge at z = {z:.4f}" for z in f.z_edges if np.abs(hor - z).min() > tol_mm]
        for p, q in f.slants:
            if not any((np.allclose(a, p, atol=tol_mm) and np.allclose(b, q, atol=tol_mm))
                       or (np.allclose(a, q, atol=tol_mm) and np.allclose(b, p, atol=tol_mm)) for a, b in segs):
                bad.append(f"{f.key}: no slanted edge {p}-{q}")
    return bad
