"""The CAD's fit checks of a :class:`~vvea_design.cad.layout.Layout`: every feature has room (valve bores and rod
seal in the base, seal grooves with their lands, lead-ins, charging valves, cross port and plug, channels,
bladder cuffs); each failure raises :class:`~vvea_design.cad.layout.CadError` naming the field to change."""

from __future__ import annotations

from ..spring.ports import MIN_FILL_PORT_MM, chamber2_port_fit_mm, valve_bore_reach_mm
from .errors import CadError

# ``Layout`` (vvea_design.cad.layout, which imports this module) appears in the annotations only, unevaluated.

__all__ = ["check_layout", "COLLAR_SEAL_LAND_MM", "SPIGOT_LAND_MM"]

#: Axial land on each side of the collar's seal groove (annulus_top), mm.
COLLAR_SEAL_LAND_MM = 0.75
#: Shortest axial land between a static seal groove and the end of its spigot, mm.
SPIGOT_LAND_MM = 0.5


def check_layout(lay: Layout) -> None:
    """Raise :class:`CadError` if a feature of ``lay`` does not fit (names the field to change).

    Parameters
    ----------
    lay : Layout
        The design's layout.

    Raises
    ------
    CadError
        A feature (valve bores, seal grooves, ports, channels, bladder, cuffs) has no room.
    """
    f, c = lay.design.fixed, lay.cad
    if lay.base_own_mm < 11.0:
        raise CadError(f"the base ({lay.design.base_mm:g} mm; fixed.min_base_mm = {f.min_base_mm:g}) is too thin "
                       f"for the valve bores and rod seal; needs >= 11 mm")
    if lay.design.top_cap_mm <= c.fill_port_counterbore_depth_mm:
        raise CadError(f"the top cap ({lay.design.top_cap_mm:g} mm; fixed.min_top_cap_mm = {f.min_top_cap_mm:g}) "
                       f"must exceed cad.fill_port_counterbore_depth_mm")
    ps = lay.piston_seal
    if f.piston_height_mm < 2.5 * ps.width_mm:
        raise CadError(f"fixed.piston_height_mm = {f.piston_height_mm:g} mm cannot hold two seal grooves of "
                       f"{ps.width_mm:g} mm ({ps.oring.name}); use >= {2.5 * ps.width_mm:g} mm or a smaller "
                       f"cad.oring_cross_section_mm")
    if ps.depth_mm >= 0.5 * (lay.piston_radius_mm - lay.rod_radius_mm):
        raise CadError(f"the piston seal groove ({ps.depth_mm:g} mm deep, cad.oring_cross_section_mm) is deeper "
                       f"than half the piston's radial land")
    if lay.z_rod_seal[1] > lay.base_own_mm - 4.0 - lay.throttle_d:
        raise CadError(f"the base ({lay.design.base_mm:g} mm; fixed.min_base_mm = {f.min_base_mm:g}) has no room "
                       f"for the rod seal groove below the valve bores")
    if lay.has_top_annulus:
        need = lay.collar_seal.width_mm + 2 * COLLAR_SEAL_LAND_MM
        if lay.design.collar_mm < need - 1e-9:
            raise CadError(f"the collar plate ({lay.design.collar_mm:g} mm; fixed.min_collar_mm = "
                           f"{f.min_collar_mm:g}) cannot hold its static seal to the outer bore: the groove "
                           f"for O-ring {lay.collar_seal.oring.name} is {lay.collar_seal.width_mm:g} mm wide "
                           f"and needs {COLLAR_SEAL_LAND_MM:g} mm lands, so >= {need:g} mm")
    if c.rod_thread_core_mm >= f.rod_diameter_mm - 2.0:
        raise CadError(f"cad.rod_thread_core_mm = {c.rod_thread_core_mm:g} mm leaves < 1 mm wall in the rod "
                       f"(fixed.rod_diameter_mm = {f.rod_diameter_mm:g})")
    if lay.bladder_inner_radius_mm - lay.inner_tube_outer_radius_mm <= 0.2:
        raise CadError(f"the cast bladder (inner radius {lay.bladder_inner_radius_mm:.2f} mm) touches the inner tube "
                       f"(outer radius {lay.inner_tube_outer_radius_mm:.2f} mm): V2_mm3 too large for outer_diameter_mm")
    if lay.outer_bore_radius_mm - lay.bladder_outer_radius_mm <= 0.2:
        raise CadError(f"the cast bladder (outer radius {lay.bladder_outer_radius_mm:.2f} mm) touches the outer tube bore "
                       f"({lay.outer_bore_radius_mm:.2f} mm): V2_mm3 too small")
    if lay.ring_channel_d < 0.5:
        raise CadError("no room for the support-ring fluid channels inside the bladder (< 0.5 mm)")
    if lay.fill_port_d < MIN_FILL_PORT_MM:
        raise CadError(f"no room for the chamber-2 fill port outside the bladder ({lay.fill_port_d:.2f} mm < "
                       f"{MIN_FILL_PORT_MM:g} mm: the design's chamber2_port_room)")
    if valve_bore_reach_mm(lay.design.piston_diameter_mm, f.rod_diameter_mm, f.fluid_channel_mm) <= 0:
        raise CadError("the valve bores cannot reach the fluid channel: piston_diameter_mm too small for the rod")
    if lay.has_piston_pocket:
        root_wall = ps.groove_diameter_mm / 2 - lay.piston_pocket_radius_mm
        if root_wall < c.min_pocket_root_wall_mm - 1e-9:
            raise CadError(f"fixed.piston_pocket_wall_mm = {f.piston_pocket_wall_mm:g} mm leaves {root_wall:.2f} mm "
                           f"between the piston pocket and the seal groove's root ({ps.depth_mm:g} mm deep, "
                           f"{ps.oring.name}); needs >= cad.min_pocket_root_wall_mm = {c.min_pocket_root_wall_mm:g} "
                           f"mm: use fixed.piston_pocket_wall_mm >= {ps.depth_mm + c.min_pocket_root_wall_mm:g}")
    if lay.design.fluid_column_mm - f.travel_mm < 0.5:
        raise CadError("fixed.fluid_clearance_mm must leave >= 0.5 mm under the piston at full stroke")
    if lay.has_bulkhead:
        if lay.y_cross_riser - lay.cross_port_d / 2 < lay.fill_tube_outer_radius_mm + 0.5 \
                or lay.y_cross_riser + lay.cross_port_d / 2 > lay.piston_radius_mm - 0.5:
            raise CadError("no room for the chamber-2 riser between the fill tube and the piston bore "
                           "(fixed.fill_tube_outer_mm too large for piston_diameter_mm)")
        if lay.fill_tube_outer_radius_mm >= 0.5 * lay.piston_radius_mm:
            raise CadError("fixed.fill_tube_outer_mm must be below half the piston diameter")
    if lay.has_top_annulus:
        d = lay.design
        if d.cross_slot_room_mm < 0:
            raise CadError(f"no room for the cross slots ({f.cross_slot_mm:g} mm, fixed.cross_slot_mm) below the top "
                           f"cap: the chamber-1 annulus is {d.top_annulus_length_mm:.2f} mm and the column above the "
                           f"piston {d.chamber1_length_mm:.2f} mm long; each needs >= {f.cross_slot_mm + 1:g} mm "
                           f"(increase V1_annulus_mm3 or V1_mm3)")
        if lay.z_free1 - lay.cuff < lay.z_free0 + lay.cuff:
            raise CadError("the collar and the chamber-1 annulus leave the bladder no free length")
    if lay.z_free1 - lay.z_free0 <= 4 * lay.bead_length:
        raise CadError("bladder free length too short for its cuffs")
    _check_seals_and_ports(lay)

def _check_seals_and_ports(lay: Layout) -> None:
    """Raise :class:`CadError` if a static seal, a lead-in chamfer, a charging valve, the cross port or its
    plug does not fit (names the field to change)."""
    f, c = lay.design.fixed, lay.cad
    wall = 0.4  # least metal between two features, mm
    j = lay.joint
    if lay.has_joint:  # the joint's seal zones (the design sized them: fixed.seal_land_mm, the gland's width)
        seals = [(lay.base_seal, lay.z_base_seal, *j.base_seal, "base's joint seal zone")]
        seals.append((lay.cap_seal, lay.z_cap_seal, *j.cap_seal, "top cap's joint seal zone"))
        land, field = 0.0, "fixed.seal_land_mm"
    else:
        seals = [(lay.base_seal, lay.z_base_seal, lay.z_base_top, lay.z_free0, "base spigot")]
        if lay.cap_seal is not None:
            seals.append((lay.cap_seal, lay.z_cap_seal, lay.z_free1, lay.z_cap, "top cap's spigot"))
        land, field = SPIGOT_LAND_MM, "fixed.bladder_clamp_mm"
    for g, (g0, g1), lo, hi, name in seals:
        if lay.has_joint and abs(g.oring.cross_section_mm - f.joint_seal_cross_section_mm) > 1e-9:
            field = "fixed.joint_seal_cross_section_mm"  # the zone was sized for the design's ring, not this one
        if g0 < lo + land - 1e-9 or g1 > hi - land + 1e-9:
            raise CadError(f"{field} = {getattr(f, field.split('.')[1]):g} mm: the {name} ({hi - lo:.2f} mm) "
                           f"cannot hold the {g.width_mm:g} mm groove of O-ring {g.oring.code} with "
                           f"{land:g} mm lands")
        if chamber2_port_fit_mm(g.groove_diameter_mm / 2, lay.bladder_outer_radius_mm, lay.bead_mm) < MIN_FILL_PORT_MM:
            raise CadError(f"outer_diameter_mm: the {name}'s seal groove (root Ø{g.groove_diameter_mm:.2f}) leaves no "
                           f"room for the chamber-2 port beside the bladder's bead (Ø{2 * lay.r_base_spigot:.2f}): "
                           f"the design's chamber2_port_room")
    _ = lay.lead_in_piston, lay.lead_in_rod, lay.lead_in_outer_bottom, lay.lead_in_outer_top, lay.seats
    s = lay.seats
    if s is not None and s.top is not None and lay.has_cross_port and not lay.has_top_annulus:
        if lay.z_cross_port - 0.5 * c.plug_bore_mm < s.z_top_end + wall - 1e-9:
            raise CadError(f"fixed.min_top_cap_mm = {f.min_top_cap_mm:g} mm: the chamber-2 cross port runs through "
                           f"the inner tube's seat in the top cap ({s.depth_mm:.2f} mm deep)")
    R, spot = lay.outer_radius_mm, 0.5 * c.valve_spot_face_mm
    if not lay.has_top_annulus:
        # the two valves on the top face (+y): chamber 1 (axis or r_port1) and chamber 2 (y_valve2)
        if lay.y_valve2 - spot < lay.y_port1 + spot + 0.5 - 1e-9:
            raise CadError(f"cad.valve_spot_face_mm = {c.valve_spot_face_mm:g} mm: the two charging valves' seats "
                           f"overlap on the top face (at y = {lay.y_port1:.2f} and {lay.y_valve2:.2f} mm)")
    if lay.has_cross_port:
        if lay.r_port2 - lay.fill_port_d / 2 < lay.y_valve2 - lay.cross_port_d / 2 - 1e-9:
            raise CadError(f"cad.valve_spot_face_mm = {c.valve_spot_face_mm:g} mm: the chamber-2 valve "
                           f"(y = {lay.y_valve2:.2f}) and its port (r = {lay.r_port2:.2f}) overlap")
        plug_in = R - c.plug_depth_mm
        if plug_in < lay.r_port2 + lay.fill_port_d / 2 + wall - 1e-9:
            raise CadError(f"cad.plug_depth_mm = {c.plug_depth_mm:g} mm: the cross port's plug bore reaches the "
                           f"chamber-2 port (at r = {lay.r_port2:.2f} mm)")
        zc, rp = lay.z_cross_port, 0.5 * c.plug_bore_mm
        if lay.has_top_annulus:
            lo_ok, hi_ok = zc - rp >= c.fill_port_counterbore_depth_mm, zc + rp <= lay.z_base_top - 1.0
            where = f"the base ({lay.design.base_mm:g} mm; fixed.min_base_mm)"
        else:
            lo_ok = zc - rp >= lay.z_cross_port_floor - 1e-9
            hi_ok = zc + rp <= lay.z_cap_face - c.fill_port_counterbore_depth_mm - 0.3 + 1e-9
            where = f"the top cap ({lay.design.top_cap_mm:g} mm; fixed.min_top_cap_mm = {f.min_top_cap_mm:g})"
        if not (lo_ok and hi_ok):
            raise CadError(f"{where} is too thin for the chamber-2 cross port's plug (Ø{c.plug_bore_mm:g}, "
                           f"cad.plug_bore_mm) beside the valves' tapped holes")
