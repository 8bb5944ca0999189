"""Housing and working piston (with rod) as solids of one :class:`Layout`.

The housing is drawn as **one united solid** (outer tube, inner tube, top
cap with the top bladder clamp, base) -- the parts a designer machines are
its slices at ``z = fixed.base_mm`` and ``z = fixed.base_mm + inner_length``
(base / tubes / top cap); the tubes are separate bar stock. Bores are drawn
at nominal size (line-to-line with the piston and rod; tolerances go on the
drawing), so the CAD areas are exactly the design's A1 and A2.
"""

from __future__ import annotations

import math

from build123d import Axis, Solid

from ._shapes import bar, cut, cylinder, fuse, revolved, ring
from .layout import Layout
from .seals import LeadIn
from .bladder import bladder as _bladder

__all__ = ["housing", "housing_pieces", "piston", "piston_head", "piston_volume_mm3", "piston_faces_mm2",
           "base_spigot_profile", "lead_in_ring_mm3", "tube_bottom_lead_in", "seat_regions"]


def base_spigot_profile(lay: Layout) -> list[tuple[float, float]]:
    """Meridian outline (r, z) of the base's spigot: the ring that rises into the outer tube from the base top to
    the top of the support ring, carries the base's static seal on its outside and is the outer wall of the
    bladder's lower cuff groove: its bore is the cuff's outer face, with an internal groove the cuff's outer bead
    snaps into (metal on the gas side); the support ring, no wider than that bore, passes it on assembly, mm.

    Parameters
    ----------
    lay : Layout
        Radii and axial levels of the design, mm (z = 0 under the base).

    Returns
    -------
    list of tuple of float
        The corners ``(r, z)`` in order, mm (the groove is cut later).
    """
    ro, e, za = lay.r_bladder_out, lay.bead_mm, lay.z_bladder0
    zb = za + lay.bead_length
    return [(ro, lay.z_base_top), (lay.r_bore, lay.z_base_top), (lay.r_bore, lay.z_free0), (ro, lay.z_free0),
            (ro, zb), (ro + e, zb), (ro + e, za), (ro, za)]


def _lead_in_tool(r: float, z: float, depth: float, length: float, outward: bool, upward: bool) -> Solid:
    """The ring removed by a lead-in chamfer on the circular edge at radius ``r``, level ``z``: a revolved
    triangle reaching ``depth`` radially (outwards for a bore, inwards for a shaft) and ``length`` along the
    axis (upwards or downwards), mm."""
    rr = r + depth if outward else r - depth
    zz = z + length if upward else z - length
    return revolved([(r, z), (rr, z), (r, zz)])


def lead_in_ring_mm3(r: float, depth: float, length: float, outward: bool) -> float:
    """Volume of a lead-in chamfer's ring (Pappus): triangle ``depth`` x ``length`` / 2 at its centroid, mm³.

    Parameters
    ----------
    r : float
        Radius of the chamfered edge (bore or shaft), mm.
    depth, length : float
        Radial depth and axial length of the chamfer, mm.
    outward : bool
        True for a bore (the chamfer reaches outwards), False for a shaft.

    Returns
    -------
    float
        Volume of material the chamfer removes, mm³.
    """
    rc = r + depth / 3 if outward else r - depth / 3
    return 2 * math.pi * rc * 0.5 * depth * length


def housing(lay: Layout) -> Solid:
    """The housing: tubes, top cap (fill ports, top bladder clamp), base (valves, channels, rod seal).

    Features (radii/levels from :class:`Layout`):

    * top cap ``z_cap .. z_top`` with two fill ports: chamber 1 (over the
      piston, ``r_port1``) and chamber 2 (through the top clamp, outside
      the bladder, ``r_port2``), each with an M5 counterbore where it fits;
    * top bladder clamp ``z_free1 .. z_cap`` filling the annulus, with the
      bladder's upper cuff and bead as its groove;
    * base ``0 .. z_base_top``: rod bore with a seal groove; the radial
      rotary-throttle bore (+x) with two servo-mount screw holes; the
      spring-ball relief bore (-x, stepped seat); vertical fluid channels
      from the fluid column (``r_channel_a``) and from the support ring
      (``r_ring_channel``) into both valve bores.

    In the ``annulus_top`` layout the top clamp is a **collar** on the inner
    tube (``z_free1 .. z_collar1``: the clamp with the cuff's groove, then the
    collar plate), the annulus above it is chamber-1 gas, joined to the bore
    by ``cad.cross_slots`` slots cut into the inner tube's top end
    (:func:`cross_slots`); the top cap has only the chamber-1 port, and
    chamber 2 is charged through an axial port in the base (``+y``,
    ``r_port2``) that continues through the support ring outside the
    bladder's bead.

    Parameters
    ----------
    lay : Layout
        Radii and axial levels of the design, mm (z = 0 under the base).

    Returns
    -------
    Solid
        The united housing in the assembly frame, mm.
    """
    z0, z1, zt = lay.z_base_top, lay.z_cap, lay.z_top
    inner = [ring(lay.r_piston, lay.r_inner_tube, z0, z1),  # inner tube
             ring(lay.r_inner_tube, lay.r_bore, lay.z_free1, lay.z_collar1),  # top bladder clamp (annulus_top: collar)
             revolved(base_spigot_profile(lay))]  # base spigot (outer wall of the lower cuff groove)
    if lay.has_joint:  # the design's joint: threaded or counterbored tube ends, the end pieces' spigots
        from .housing_joints import joint_bodies, joint_tools

        body = fuse(*joint_bodies(lay), *inner)
    else:  # the gas-only rules: the tubes butt on the base and the cap
        joint_tools = None
        body = fuse(ring(lay.r_bore, lay.r_outer, z0, z1), cylinder(lay.r_outer, z1, zt), cylinder(lay.r_outer, 0.0, z0),
                    *inner)
    if lay.has_bulkhead:  # bulkhead web and the chamber-1 fill tube (part of the inner tube)
        body = fuse(body, cylinder(lay.r_piston + 0.01, lay.z_bulkhead0, lay.z_bulkhead1),
                    ring(lay.r_fill_tube_bore, lay.r_fill_tube_out, lay.z_bulkhead1 - 0.01, z1 + 0.01))
    return cut(body, *_top_tools(lay), *_base_tools(lay), *(joint_tools(lay) if joint_tools else ()))


def _top_tools(lay: Layout) -> list[Solid]:
    """What is cut from the housing's top: the bladder's upper cuff (the clamp's groove), the cap's static seal
    groove and the outer tube's top lead-in chamfer, the charging ports with the valves' tapped holes, and per
    layout the fill tube's bore (bulkhead), the chamber-2 riser, cross port and plug bore, or the slots and the
    collar's seal groove (annulus_top), mm. In cutting order."""
    c = lay.cad
    z1, zt = lay.z_cap, lay.z_cap_face
    tools: list[Solid] = [_bladder(lay)]  # top clamp groove = the bladder's upper cuff (exact fit)
    tap = c.fill_port_counterbore_mm / 2  # the valves' M5 tap drill
    tap_z = zt - c.fill_port_counterbore_depth_mm
    if lay.cap_seal is not None:  # the cap's static seal to the outer bore, and the tube's lead-in above it
        tools.append(ring(lay.cap_seal.groove_diameter_mm / 2, lay.cap_seal_bore_mm / 2, *lay.z_cap_seal))
        if lay.lead_in_counterbore is not None:  # ring_top: the chamfer at the counterbore's mouth
            li = lay.lead_in_counterbore
            tools.append(_lead_in_tool(lay.joint.ring.bore_mm / 2, lay.z_top, li.depth_mm, li.length_mm,
                                       outward=True, upward=False))
        li = lay.lead_in_outer_top  # where the ring enters the bore (behind a thread or the counterbore)
        tools.append(_lead_in_tool(lay.r_bore, lay.z_lead_in_top, li.depth_mm, li.length_mm, outward=True,
                                   upward=False))
    tools += _seat_tools(lay)
    # chamber 1: the fill tube's bore on the axis (bulkhead) or a port over the piston; its valve's tapped hole
    if lay.has_bulkhead:
        tools.append(cylinder(lay.r_fill_tube_bore, lay.z_bulkhead0 - 0.01, zt + 1))
    else:
        tools.append(cylinder(lay.fill_port_d / 2, z1 - 0.01, zt + 1, y=lay.r_port1))
    tools.append(cylinder(tap, tap_z, zt + 1, y=lay.y_port1))
    if lay.has_top_annulus:  # chamber 2 is charged through the base; the slots join the chamber-1 annulus
        tools.extend(cross_slots(lay, lay.r_piston - 0.01, lay.r_inner_tube + 0.01, 0.01))
        tools.append(ring(lay.collar_seal.groove_diameter_mm / 2, lay.r_bore, *lay.z_collar_seal))
        return tools
    tools.extend(_chamber2_tools(lay, lay.z_free1 - 0.01, z1 - 0.01 if lay.has_bulkhead else None, tap_z, zt, +1))
    return tools


def tube_bottom_lead_in(lay: Layout) -> tuple[LeadIn, float]:
    """The lead-in chamfer of the inner tube's bore at its bottom end and the level of that end: in the base's seat
    with a joint (the seat's ring and the piston's rings pass it), else on the base's top, mm.

    Parameters
    ----------
    lay : Layout
        Radii and axial levels of the design, mm (z = 0 under the base).

    Returns
    -------
    (LeadIn, float)
        The chamfer (angle deg, length and depth mm) and the tube's bottom end, mm.
    """
    s = lay.seats
    return (s.lead_in_bottom, s.z_base_floor) if s is not None else (lay.lead_in_piston, lay.z_base_top)


def _seat_tools(lay: Layout) -> list[Solid]:
    """The top cap's side of the seats: the static seal's groove in the cap's spigot inside the tube's bore and the
    lead-in of the tube's top end; the fill tube's neck: the cap's groove around it and the neck's chamfer, mm."""
    s, tools = lay.seats, []
    if s is not None and s.top is not None:
        tools.append(ring(s.top.groove_diameter_mm / 2, lay.r_piston, *s.z_top_groove))
        li = s.lead_in_top
        tools.append(_lead_in_tool(lay.r_piston, s.z_top_end, li.depth_mm, li.length_mm, outward=True, upward=False))
    if s is not None and s.fill is not None:
        rn, li = s.neck_radius_mm, s.lead_in_neck
        tools.append(ring(rn, s.fill.groove_diameter_mm / 2, *s.z_neck_groove))
        tools.append(_lead_in_tool(rn, s.z_neck_top, li.depth_mm, li.length_mm, outward=False, upward=False))
    return tools


def seat_regions(lay: Layout) -> list[Solid]:
    """The inner tube's material inside the end pieces' seats (its ends, the fill tube's neck): the regions the
    tube takes from the base and the top cap when the united housing is cut into pieces, mm.

    Parameters
    ----------
    lay : Layout
        Radii and axial levels of the design, mm (z = 0 under the base).

    Returns
    -------
    list of Solid
        Empty without seats (the gas-only rules).
    """
    s = lay.seats
    if s is None:
        return []
    out = [ring(lay.r_piston, lay.r_inner_tube, s.z_base_floor, lay.z_base_top)]
    if s.top is not None:
        out.append(ring(lay.r_piston, lay.r_inner_tube, lay.z_cap, s.z_top_end))
    if s.fill is not None:
        out.append(cylinder(s.neck_radius_mm, lay.z_cap, s.z_neck_top))
    return out


def _chamber2_tools(lay: Layout, z_port: float, z_riser: float | None, tap_z: float, z_face: float,
                    sgn: int) -> list[Solid]:
    """The chamber-2 port and its valve, mm: straight through to the valve's tapped hole, or a port up (or down)
    from the gas side to a cross port drilled from the outside along +y, joined to the valve's hole (which in
    ``bulkhead`` continues to the cap's underside as the riser), the cross port closed by a plug in its bore.
    ``sgn`` = +1: the valve on the top face ``z_face``; -1: on the base's underside."""
    c = lay.cad
    tap, rp = c.fill_port_counterbore_mm / 2, lay.fill_port_d / 2
    tools: list[Solid] = []
    if not lay.has_cross_port:  # valve over the port: a straight hole
        lo, hi = sorted((z_port, z_face + sgn))
        tools.append(cylinder(rp, lo, hi, y=lay.r_port2))
        tools.append(cylinder(tap, *sorted((tap_z, z_face + sgn)), y=lay.r_port2))
        return tools
    zc, rc = lay.z_cross_port, lay.cross_port_d / 2
    tools.append(cylinder(rp, *sorted((z_port, zc)), y=lay.r_port2))  # the port, blind to the cross port
    valve_lo = z_riser if z_riser is not None else zc - sgn * rc  # down to the cross port's far side
    tools.append(cylinder(rc, *sorted((valve_lo, z_face + sgn)), y=lay.y_valve2))  # the valve's hole (riser)
    tools.append(cylinder(tap, *sorted((tap_z, z_face + sgn)), y=lay.y_valve2))
    R = lay.r_outer
    tools.append(bar(rc, (0, lay.y_valve2 - rc, zc), (0, 1, 0), R + 1 - lay.y_valve2 + rc))  # from the outside
    tools.append(bar(c.plug_bore_mm / 2, (0, R - c.plug_depth_mm, zc), (0, 1, 0), c.plug_depth_mm + 1))
    return tools


def _base_tools(lay: Layout) -> list[Solid]:
    """What is cut from the base: rod bore and seal groove, the base spigot's seal groove, the lead-in chamfers
    of the tubes' bottom bore ends, the throttle and relief valve bores, the servo's screw holes, the fluid
    channels and (annulus_top) the chamber-2 port, mm. In cutting order."""
    c = lay.cad
    z0 = lay.z_base_top
    tools: list[Solid] = []
    # rod bore and rod seal groove
    tools.append(cylinder(lay.r_rod, -1.0, z0 + 0.01))
    tools.append(ring(0.0, lay.rod_seal.groove_diameter_mm / 2, *lay.z_rod_seal))
    # the base spigot's static seal; the outer tube's lead-in over it and the inner tube's for the piston's rings
    tools.append(ring(lay.base_seal.groove_diameter_mm / 2, lay.r_bore, *lay.z_base_seal))
    li = lay.lead_in_outer_bottom
    tools.append(_lead_in_tool(lay.r_bore, lay.z_lead_in_bottom, li.depth_mm, li.length_mm, outward=True,
                               upward=True))
    li, zb = tube_bottom_lead_in(lay)  # at the tube's bottom end (in the base's seat with a joint)
    tools.append(_lead_in_tool(lay.r_piston, zb, li.depth_mm, li.length_mm, outward=True, upward=True))
    if lay.seats is not None:  # the base's spigot in the tube's bore: its static seal
        tools.append(ring(lay.seats.base.groove_diameter_mm / 2, lay.r_piston, *lay.seats.z_base_groove))
    zv = lay.z_valve
    # rotary throttle: radial bore along +x, channels up from it
    tools.append(bar(lay.throttle_d / 2, (lay.x_valve_inner, 0, zv), (1, 0, 0), lay.r_outer + 1 - lay.x_valve_inner))
    # servo mount: two screw holes flanking the throttle bore
    ys = lay.throttle_d / 2 + 3.5
    xs = math.sqrt(lay.r_outer**2 - ys**2)
    for sgn in (1, -1):
        tools.append(bar(c.servo_screw_core_mm / 2, (xs - c.servo_screw_depth_mm, sgn * ys, zv), (1, 0, 0),
                         c.servo_screw_depth_mm + 1.0))
    # relief valve: stepped radial bore along -x (seat drilling reaches the fluid-column channel)
    x_b = lay.r_ring_channel - lay.ring_channel_d / 2 - 0.5
    tools.append(bar(lay.relief_d / 2, (-(lay.r_outer + 1), 0, zv), (1, 0, 0), lay.r_outer + 1 - x_b))
    tools.append(bar(lay.relief_seat_d / 2, (-x_b - 0.01, 0, zv), (1, 0, 0),
                     x_b - lay.x_valve_inner + 0.01))
    # vertical channels: fluid column <-> valves <-> support ring, both valves
    ch = lay.base_channel_d / 2
    for sgn in (1, -1):
        tools.append(cylinder(ch, zv, z0 + 0.01, x=sgn * lay.r_channel_a))
        tools.append(cylinder(min(ch, lay.ring_channel_d / 2), zv, z0 + 0.01, x=sgn * lay.r_ring_channel))
    if lay.has_top_annulus:  # chamber 2 through the base and its spigot, the valve on the underside
        tools.extend(_chamber2_tools(lay, lay.z_free0 + 0.01, None, c.fill_port_counterbore_depth_mm, 0.0, -1))
    return tools


def cross_slots(lay: Layout, r_in: float, r_out: float, above: float = 0.0) -> list[Solid]:
    """The ``annulus_top`` layout's slots through the inner tube's top end: ``cad.cross_slots`` annular
    sectors from ``r_in`` to ``r_out``, from ``slot_height`` below the top cap's underside to ``above`` over it, mm."""
    z1 = lay.z_cap
    out = []
    for k in range(lay.cad.cross_slots):
        a0 = math.degrees(lay.slot_start_rad(k))
        s = revolved([(r_in, z1 - lay.slot_height), (r_out, z1 - lay.slot_height), (r_out, z1 + above),
                      (r_in, z1 + above)], angle_deg=math.degrees(lay.slot_angle_rad))
        out.append(s.rotate(Axis.Z, a0))
    return out


def housing_pieces(lay: Layout, united: Solid | None = None) -> dict[str, Solid]:
    """The housing's machined parts: slices of the united :func:`housing`, mm.

    ``housing_base`` (z < base top), ``housing_outer_tube`` and
    ``housing_inner_tube`` (between base and top cap), ``housing_top_cap``
    (the cap with the top bladder clamp spigot). Their volumes add up to the
    united housing's; they touch on faces only.

    Parameters
    ----------
    lay : Layout
        Radii and axial levels of the design, mm (z = 0 under the base).
    united : Solid or None
        The united housing if already built (saves rebuilding it); None: built here.

    Returns
    -------
    dict of str to Solid
        The four pieces by part name, assembly frame, mm.
    """
    h = united if united is not None else housing(lay)
    big = lay.r_outer + 1.0
    z0, z1, zt = lay.z_base_top, lay.z_cap, lay.z_top
    if lay.has_joint:  # cut along the joint: the tube over the end pieces' spigots
        from .housing_joints import joint_regions

        regions = joint_regions(lay, big)
    else:
        regions = {
            "housing_base": fuse(cylinder(big, -1.0, z0), ring(lay.r_bladder_out - 1e-3, lay.r_bore, z0, lay.z_free0)),
            "housing_outer_tube": ring(lay.r_bore, big, z0, z1),
            "housing_top_cap": fuse(cylinder(big, z1, zt + 1.0), ring(lay.r_inner_tube, lay.r_bore, lay.z_free1, z1)),
        }
        if lay.has_top_annulus:  # the top cap is a plain cap
            regions["housing_top_cap"] = cylinder(big, z1, zt + 1.0)
    regions["housing_inner_tube"] = cylinder(lay.r_inner_tube, z0, z1)
    if lay.has_top_annulus:  # the collar is part of the inner tube
        regions["housing_inner_tube"] = fuse(cylinder(lay.r_inner_tube, z0, z1),
                                             ring(lay.r_inner_tube, lay.r_bore, lay.z_free1, lay.z_collar1))
    seats = seat_regions(lay)
    if seats:  # the tube's ends (and the fill tube's neck) in the end pieces' seats
        regions["housing_inner_tube"] = fuse(regions["housing_inner_tube"], *seats)
        for k in ("housing_base", "housing_top_cap"):
            regions[k] = cut(regions[k], *seats)
    regions = {k: regions[k] for k in ("housing_base", "housing_outer_tube", "housing_inner_tube", "housing_top_cap")}
    from ._shapes import single_solid

    return {name: single_solid(h.intersect(region)) for name, region in regions.items()}


def _groove_levels(lay: Layout, x_mm: float) -> list[tuple[float, float]]:
    hp = lay.design.fixed.piston_height_mm
    w = lay.piston_seal.width_mm
    zb = lay.z_piston_bottom(x_mm)
    return [(zb + hp * q - w / 2, zb + hp * q + w / 2) for q in (0.27, 0.73)]


def piston(lay: Layout, x_mm: float = 0.0) -> Solid:
    """Working piston with two seal grooves and its rod (tapped end), at displacement ``x_mm``.

    The top face is the full bore (area A1); the underside is the annulus
    between bore and rod (area A2). With ``fixed.piston_pocket`` a coaxial
    pocket (radius ``design.piston_pocket_radius_mm``, depth
    ``design.piston_pocket_depth_mm``) is bored from the top face: chamber-1
    gas; the rod ends in its floor (the top face is then the rim and the
    pocket floor, together still A1 projected).

    Parameters
    ----------
    lay : Layout
        Radii and axial levels of the design, mm (z = 0 under the base).
    x_mm : float
        Piston displacement, mm (x > 0 extends the spring and moves the piston down, towards the base).

    Returns
    -------
    Solid
        Piston and rod in the assembly frame, mm.
    """
    d, c = lay.design, lay.cad
    zb, ztp = lay.z_piston_bottom(x_mm), lay.z_piston_top(x_mm)
    z_end = zb - d.rod_length_mm
    boss = min(0.5 * d.fixed.piston_height_mm, d.piston_floor_mm)  # the rod reaches into the piston, never its pocket
    body = fuse(cylinder(lay.r_piston, zb, ztp), cylinder(lay.r_rod, z_end, zb + boss))
    r_root = lay.piston_seal.groove_diameter_mm / 2
    tools = [ring(r_root, lay.r_piston + 1, g0, g1) for g0, g1 in _groove_levels(lay, x_mm)]
    tools.append(cylinder(c.rod_thread_core_mm / 2, z_end - 1, z_end + c.rod_thread_depth_mm))
    li = lay.lead_in_rod  # the rod's end passes the rod seal in the base on assembly
    tools.append(_lead_in_tool(lay.r_rod, z_end, li.depth_mm, li.length_mm, outward=False, upward=True))
    if lay.has_piston_pocket:
        tools.append(cylinder(lay.r_pocket, ztp - d.piston_pocket_depth_mm, ztp + 1))
    return cut(body, *tools)


def piston_head(lay: Layout, x_mm: float = 0.0) -> Solid:
    """The piston's envelope at displacement ``x_mm``: a plain cylinder of the bore's radius from the piston's
    underside to its top (no grooves, rod or pocket), e.g. for the piston drawn dashed at full stroke.

    Parameters
    ----------
    lay : Layout
        Radii and axial levels of the design, mm (z = 0 under the base).
    x_mm : float
        Piston displacement, mm (x > 0 extends the spring and moves the piston down, towards the base).

    Returns
    -------
    Solid
        The cylinder in the assembly frame, mm.
    """
    return cylinder(lay.r_piston, lay.z_piston_bottom(x_mm), lay.z_piston_top(x_mm))


def piston_volume_mm3(lay: Layout) -> float:
    """Closed-form volume of :func:`piston` (piston + rod - grooves - tapped hole - rod-end lead-in - pocket).

    Parameters
    ----------
    lay : Layout
        Radii and axial levels of the design, mm (z = 0 under the base).

    Returns
    -------
    float
        Volume, mm³ (the same at every displacement).
    """
    d, c = lay.design, lay.cad
    rp, rr = lay.r_piston, lay.r_rod
    v = math.pi * rp**2 * d.fixed.piston_height_mm + math.pi * rr**2 * d.rod_length_mm
    g = lay.piston_seal
    v -= 2 * math.pi * (rp**2 - (g.groove_diameter_mm / 2) ** 2) * g.width_mm
    v -= math.pi * (c.rod_thread_core_mm / 2) ** 2 * c.rod_thread_depth_mm
    li = lay.lead_in_rod
    v -= lead_in_ring_mm3(rr, li.depth_mm, li.length_mm, outward=False)
    if lay.has_piston_pocket:
        v -= math.pi * lay.r_pocket**2 * d.piston_pocket_depth_mm
    return v


def piston_faces_mm2(solid: Solid, lay: Layout, x_mm: float = 0.0) -> dict[str, float]:
    """Measure the drawn piston areas: the planar faces at the piston top (A1: the top face, and with a
    pocket its rim plus the pocket's floor, the projected area chamber 1 pushes on) and the
    planar faces at its underside (A2 = bore minus rod).

    Parameters
    ----------
    solid : Solid
        A piston as :func:`piston` draws it, mm.
    lay : Layout
        Radii and axial levels of the design, mm (z = 0 under the base).
    x_mm : float
        Displacement the piston was drawn at, mm (locates its top and underside).

    Returns
    -------
    dict of str to float
        ``A1_mm2`` and ``A2_mm2``: summed areas of the horizontal faces at the top and the underside, mm².
    """
    zt, zb = lay.z_piston_top(x_mm), lay.z_piston_bottom(x_mm)
    zf = zt - lay.design.piston_pocket_depth_mm if lay.has_piston_pocket else math.nan  # the pocket's floor
    a1 = a2 = 0.0
    for face in solid.faces():
        bb = face.bounding_box()
        if bb.max.Z - bb.min.Z > 1e-6:
            continue
        in_pocket = max(abs(bb.min.X), abs(bb.max.X), abs(bb.min.Y), abs(bb.max.Y)) < lay.r_pocket + 1e-6
        if abs(bb.min.Z - zt) < 1e-6 or (abs(bb.min.Z - zf) < 1e-6 and in_pocket):
            a1 += face.area
        elif abs(bb.min.Z - zb) < 1e-6:
            a2 += face.area
    return {"A1_mm2": a1, "A2_mm2": a2}
