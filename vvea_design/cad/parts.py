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
from .bladder import bladder as _bladder

__all__ = ["housing", "housing_pieces", "piston", "piston_head", "piston_volume_mm3", "piston_faces_mm2"]


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
    body = fuse(
        ring(lay.r_bore, lay.r_outer, z0, z1),  # outer tube
        ring(lay.r_piston, lay.r_inner_tube, z0, z1),  # inner tube
        cylinder(lay.r_outer, z1, zt),  # top cap
        ring(lay.r_inner_tube, lay.r_bore, lay.z_free1, lay.z_collar1),  # top bladder clamp (annulus_top: collar)
        cylinder(lay.r_outer, 0.0, z0),  # base
    )
    if lay.has_bulkhead:  # bulkhead web and the chamber-1 fill tube (part of the inner tube)
        body = fuse(body, cylinder(lay.r_piston + 0.01, lay.z_bulkhead0, lay.z_bulkhead1),
                    ring(lay.r_fill_tube_bore, lay.r_fill_tube_out, lay.z_bulkhead1 - 0.01, z1 + 0.01))
    return cut(body, *_top_tools(lay), *_base_tools(lay))


def _top_tools(lay: Layout) -> list[Solid]:
    """What is cut from the housing's top: the bladder's upper cuff (the clamp's groove), the fill ports with
    their counterbores, and per layout the fill tube's bore and cross port (bulkhead) or the slots, the collar's
    seal groove and the chamber-2 port through the base (annulus_top), mm. In cutting order."""
    c = lay.cad
    z0, z1, zt = lay.z_base_top, lay.z_cap, lay.z_top
    tools: list[Solid] = []
    # top clamp groove = the bladder's upper cuff (exact fit)
    tools.append(_bladder(lay))
    ports = [(lay.r_port1, z1 - 0.01), (lay.r_port2, lay.z_free1 - 0.01)]
    if lay.has_bulkhead:
        # chamber 1 is charged through the fill tube's bore (on the axis, through bulkhead, tube and cap);
        # the space above the bulkhead reaches the chamber-2 port through a riser and a cross port in the cap
        # (drilled from the outside and plugged; the plug is not drawn)
        ports = [(lay.r_port2, lay.z_free1 - 0.01)]
        tools.append(cylinder(lay.r_fill_tube_bore, lay.z_bulkhead0 - 0.01, zt + 1))
        tools.append(cylinder(c.fill_port_counterbore_mm / 2, zt - c.fill_port_counterbore_depth_mm, zt + 1))
        rc = lay.cross_port_d / 2
        tools.append(cylinder(rc, z1 - 0.01, lay.z_cross_port, y=lay.y_cross_riser))
        tools.append(bar(rc, (0, lay.y_cross_riser, lay.z_cross_port), (0, 1, 0), lay.r_port2 - lay.y_cross_riser))
    if lay.has_top_annulus:
        # chamber 1 only through the top cap; chamber 2 through the base (see below); the slots join the annulus
        ports = [(lay.r_port1, z1 - 0.01)]
        tools.extend(cross_slots(lay, lay.r_piston - 0.01, lay.r_inner_tube + 0.01, 0.01))
        # the collar's static O-ring groove in its rim (chamber 1's annulus above, chamber 2 below)
        tools.append(ring(lay.collar_seal.groove_diameter_mm / 2, lay.r_bore, *lay.z_collar_seal))
        tools.append(cylinder(lay.fill_port_d / 2, -1.0, z0 + 0.01, y=lay.r_port2))
        cb = c.fill_port_counterbore_mm / 2
        if lay.r_port2 + cb < lay.r_outer - 0.8:
            tools.append(cylinder(cb, -1.0, c.fill_port_counterbore_depth_mm, y=lay.r_port2))
    # fill ports (chamber 1 at +y over the piston or on the axis, chamber 2 at +y outside the bladder)
    for r_port, z_start in ports:
        tools.append(cylinder(lay.fill_port_d / 2, z_start, zt + 1, y=r_port))
        cb = c.fill_port_counterbore_mm / 2
        if r_port + cb < lay.r_outer - 0.8 and (r_port - cb > lay.r_piston + 0.8 or r_port + cb < lay.r_piston - 0.8) \
                and not (lay.has_bulkhead and r_port > 0 and abs(r_port - lay.y_cross_riser) < cb + 0.8):
            tools.append(cylinder(cb, zt - c.fill_port_counterbore_depth_mm, zt + 1, y=r_port))
    return tools


def _base_tools(lay: Layout) -> list[Solid]:
    """What is cut from the base: rod bore and seal groove, the throttle and relief valve bores, the servo's
    screw holes and the fluid channels, mm. In cutting order."""
    c = lay.cad
    z0 = lay.z_base_top
    tools: list[Solid] = []
    # rod bore and rod seal groove
    tools.append(cylinder(lay.r_rod, -1.0, z0 + 0.01))
    tools.append(ring(0.0, lay.rod_seal.groove_diameter_mm / 2, *lay.z_rod_seal))
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
    tools.append(bar(min(c.relief_seat_mm, lay.relief_d) / 2, (-x_b - 0.01, 0, zv), (1, 0, 0),
                     x_b - lay.x_valve_inner + 0.01))
    # vertical channels: fluid column <-> valves <-> support ring, both valves
    ch = lay.base_channel_d / 2
    for sgn in (1, -1):
        tools.append(cylinder(ch, zv, z0 + 0.01, x=sgn * lay.r_channel_a))
        tools.append(cylinder(min(ch, lay.ring_channel_d / 2), zv, z0 + 0.01, x=sgn * lay.r_ring_channel))
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
    regions = {
        "housing_base": cylinder(big, -1.0, z0),
        "housing_outer_tube": ring(lay.r_bore, big, z0, z1),
        "housing_inner_tube": cylinder(lay.r_inner_tube, z0, z1),
        "housing_top_cap": fuse(cylinder(big, z1, zt + 1.0), ring(lay.r_inner_tube, lay.r_bore, lay.z_free1, z1)),
    }
    if lay.has_top_annulus:  # the collar is part of the inner tube; the top cap is a plain cap
        regions["housing_inner_tube"] = fuse(cylinder(lay.r_inner_tube, z0, z1),
                                             ring(lay.r_inner_tube, lay.r_bore, lay.z_free1, lay.z_collar1))
        regions["housing_top_cap"] = cylinder(big, z1, zt + 1.0)
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
    """Closed-form volume of :func:`piston` (piston + rod - grooves - tapped hole - pocket).

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
