"""The design's joint as the CAD draws it (issue 23): levels of the threaded spigots, the ring's plug and groove
and the tie rods' circle; the joint's items in the bill with their standards; the pieces' volumes against the
design's closed form with the joint (one mass)."""

from __future__ import annotations

import pytest

from tests.cad.cases import BULKHEAD, JOINTS
from vvea_design.cad.bill import BomContext, housing_joint
from vvea_design.cad.layout import Layout
from vvea_design.materials.structural import get_material


@pytest.mark.parametrize("name", list(JOINTS))
def test_joint_levels_follow_the_design(name):
    d = JOINTS[name]
    lay = Layout(d)
    j = lay.joint
    assert j.kind == d.joint and lay.has_joint
    assert j.z_tube_bottom == pytest.approx(float(d.derived.section.base_own_mm))
    assert 0.0 < j.z_tube_bottom < lay.z_base_top < lay.z_cap < j.z_tube_top <= lay.z_top
    for t in (j.base_thread, j.cap_thread):
        if t is None:
            continue
        zones = sorted([t.runout, t.thread, t.relief, t.seal])
        assert all(a[1] == pytest.approx(b[0]) for a, b in zip(zones, zones[1:]))  # contiguous
        assert t.relief[1] - t.relief[0] == pytest.approx(t.pitch_mm)  # the internal run-out, DIN 76-1 short
        assert t.external_minor_mm < t.pitch_diameter_mm < t.major_mm
        assert t.pitch_diameter_mm / 2 > lay.r_bore  # the O-ring passes the thread into the bore
        # ... clear of the internal thread's crests (ISO 3601-2): its free ring and the bore's lead-in inside D1
        for g in (lay.base_seal, lay.cap_seal):
            assert g.free_sealing_radius_mm < t.internal_minor_mm / 2
        assert lay.r_bore + lay.lead_in_outer_bottom.depth_mm <= t.internal_minor_mm / 2
    g0, g1 = lay.z_base_seal
    assert j.base_seal[0] <= g0 < g1 <= j.base_seal[1]
    g0, g1 = lay.z_cap_seal
    assert j.cap_seal[0] <= g0 < g1 <= j.cap_seal[1]
    if j.ring is not None:
        assert j.ring.plug[1] == pytest.approx(j.ring.groove[0]) and j.ring.groove[1] < lay.z_top
        # the cap's O-ring seals in the bore below the counterbore and passes the ring's groove clear of it
        assert lay.cap_seal.sliding_diameter_mm == pytest.approx(2 * lay.r_bore)
        assert lay.cap_seal.free_sealing_radius_mm < j.ring.bore_mm / 2
        assert lay.z_cap_face == pytest.approx(j.ring.plug[1])
    if j.rods is not None:
        r = j.rods
        assert r.circle_radius_mm + r.hole_mm / 2 < lay.r_outer
        assert r.circle_radius_mm - r.hole_mm / 2 > j.tube_outer_radius_mm
        assert min(min(abs((a - b + 180) % 360 - 180) for b in (0, 90, 180)) for a in r.angles_deg) > 10.0


def test_a_gas_only_design_has_no_joint():
    lay = Layout(BULKHEAD)
    assert not lay.has_joint and lay.joint.kind == "none"
    assert housing_joint(BomContext(lay, {}, None)) == ()


@pytest.mark.parametrize("name", ["thread_inner_tube", "ring_top_inner_tube", "tie_rods_inner_tube"])
def test_the_joint_is_in_the_bill_with_its_standard(name):
    d = JOINTS[name]
    lines = {ln.part: ln for ln in housing_joint(BomContext(Layout(d), {}, None))}
    recs = {(r.joint, r.kind): r for r in d.joints()}
    if d.joint in ("thread", "ring_top"):
        base = lines["thread_base"]
        assert "ISO 965-1" in base.standard and recs[("base", "thread")].designation in base.size
    if d.joint == "thread":
        assert recs[("top_cap", "thread")].designation in lines["thread_top_cap"].size
    if d.joint == "ring_top":
        ring = lines["retaining_ring"]
        rec = recs[("top_cap", "ring_top")]
        assert "DIN 472" in ring.standard and ring.size == rec.designation
        assert ring.unit_mass_g == pytest.approx(rec.mass_g) and ring.in_unit
        # the design's mass breakdown weighs the same ring
        assert d.mass_breakdown_g()["retaining_ring"] == pytest.approx(ring.unit_mass_g)
    if d.joint == "tie_rods":
        rec = recs[("top_cap_and_base", "tie_rods")]
        rods, nuts = lines["tie_rods"], lines["tie_rod_nuts"]
        assert "DIN 976-1" in rods.standard and "ISO 898-1" in rods.standard and rec.property_class in rods.material
        assert rods.quantity == rec.count and nuts.quantity == 2 * rec.count and "ISO 4032" in nuts.standard
        assert rods.torque_Nm == pytest.approx(rec.tightening_torque_Nm) and rods.torque_Nm > 0
        # the design's mass breakdown weighs the same rods and nuts
        total = rods.unit_mass_g * rods.quantity + nuts.unit_mass_g * nuts.quantity
        assert d.mass_breakdown_g()["tie_rods"] == pytest.approx(total, rel=1e-6)


def test_the_joint_pieces_are_the_designs_closed_form():
    """One mass with the joint drawn: every housing piece agrees with the design's closed form within 0.5 % (the
    base with its spigot around the lower cuff, its outer bead's groove and its seal gland; tests/spring/test_masses.py
    checks every part of every layout and joint)."""
    from vvea_design.cad import build_cad

    d = JOINTS["thread_inner_tube"]
    model = build_cad(d)
    rho = get_material(d.fixed.housing_material).density_g_per_mm3
    closed = {k: v / rho for k, v in d.mass_breakdown_g().items() if k.startswith("housing_")}
    cad = {k: float(s.volume) for k, s in model.housing_pieces.items()}
    assert set(cad) == set(closed)
    for part in ("housing_base", "housing_outer_tube", "housing_inner_tube", "housing_top_cap"):
        assert cad[part] == pytest.approx(closed[part], rel=5e-3), part


@pytest.mark.parametrize("name", list(JOINTS))
def test_the_joints_seal_zones_hold_the_bores_lead_ins(name):
    """The design reserves, between the step where a joint's O-ring enters the outer tube's bore and its groove,
    the bore's lead-in chamfer (ISO 3601-2: 15 ... 20 deg, radial depth over the ring's protrusion) and the
    clearance to the groove: the CAD draws the chamfer there, never over the ring."""
    from vvea_design.cad.layout import LEAD_IN_GAP_MM
    from vvea_design.spring.joints import LEAD_IN_MIN_LENGTH_MM, seal_lead_in_land_mm

    d = JOINTS[name]
    lay = Layout(d)
    f = d.fixed
    land = seal_lead_in_land_mm(f.joint_seal_cross_section_mm, f.seal_land_mm)
    assert land == pytest.approx(LEAD_IN_MIN_LENGTH_MM[f.joint_seal_cross_section_mm] + LEAD_IN_GAP_MM)
    assert float(d.derived.section.joint.seal_zone_mm) == pytest.approx(land + lay.base_seal.width_mm
                                                                         + f.seal_land_mm)
    ends = [(lay.lead_in_outer_bottom, lay.z_base_seal[0] - lay.z_lead_in_bottom, lay.base_seal)]
    if lay.lead_in_outer_top is not None:
        ends.append((lay.lead_in_outer_top, lay.z_lead_in_top - lay.z_cap_seal[1], lay.cap_seal))
    for li, room, gland in ends:
        assert 15.0 <= li.angle_deg <= 20.0
        assert li.depth_mm > gland.protrusion_mm + gland.oring.cross_section_tolerance_mm
        assert li.length_mm + LEAD_IN_GAP_MM <= room + 1e-9


def test_a_joint_ring_is_of_the_series_the_design_sized():
    """A 70 mm envelope's tie-rod tube bore would take no 1.78 mm ring: the design lowers the bore to one a
    standard ring of its series seals (``spring.joints.standard_seal_bore_radius_mm``), so the CAD never falls back
    to the 2.62 mm series, whose gland and lead-in the seal zone was not sized for; a ring of another series would
    be a CadError naming the field."""
    from dataclasses import replace

    from vvea_design.spring.joints import standard_seal_bore_radius_mm

    d = JOINTS["tie_rods_inner_tube"]
    for w in (1.78, 2.62):
        lay = Layout(replace(d, fixed=replace(d.fixed, joint_seal_cross_section_mm=w)))
        assert lay.base_seal.oring.cross_section_mm == w and lay.cap_seal.oring.cross_section_mm == w
        assert standard_seal_bore_radius_mm(lay.r_bore, w) == pytest.approx(lay.r_bore)


def test_a_gas_only_spigot_gets_a_standard_lead_in_or_an_error():
    """Under the gas-only rules the spigot is the bladder clamp: a 15 ... 20 deg lead-in, ending at the seal groove
    at the latest (the CAD's own clearance may be used, the standard's angle and depth not); a clamp too short for
    even that is a CadError naming fixed.bladder_clamp_mm."""
    from dataclasses import replace

    from vvea_design.cad.errors import CadError
    from vvea_design.spring.design import Design, FixedParameters

    d = Design(35.18, 59.5, 47107.0, 99735.0, fixed=FixedParameters(sizing_rules="gas_only"))  # ring 034
    lay = Layout(d)
    li, g = lay.lead_in_outer_bottom, lay.base_seal
    assert 15.0 <= li.angle_deg <= 20.0 and li.depth_mm > g.protrusion_mm + g.oring.cross_section_tolerance_mm
    assert lay.z_base_top + li.length_mm <= lay.z_base_seal[0] + 1e-9
    with pytest.raises(CadError, match="fixed.bladder_clamp_mm"):
        Layout(replace(d, fixed=replace(d.fixed, bladder_clamp_mm=4.0)))


def test_a_cross_port_drilled_through_the_joint_is_an_open_leak_path(monkeypatch):
    """The bulkhead layout's chamber-2 cross port lies in the top cap above the outer tube's end (the design reserves
    the cap's shoulder), closed by its plug; drilled lower it would pass through the tube inside the joint, above
    the cap's seal: the leak audit says so (open, not an expander plug's seal)."""
    from vvea_design.cad.layout_checks import SPIGOT_LAND_MM
    from vvea_design.cad.leaks import leak_paths
    from vvea_design.spring.design import Design

    d = Design(33.155, 59.33, 33650.0, 80180.0, layout="bulkhead", V2_top_mm3=658.0)
    lay = Layout(d)
    assert lay.has_cross_port and lay.z_cross_port - 0.5 * lay.cad.plug_bore_mm >= lay.joint.z_tube_top
    cross = [p for p in leak_paths(lay) if p.where == "port: chamber-2 cross port"]
    assert len(cross) == 1 and cross[0].is_sealed
    monkeypatch.setattr(Layout, "z_cross_port_floor", property(lambda self: self.z_cap + SPIGOT_LAND_MM))
    low = Layout(d)
    assert low.z_cross_port < low.joint.z_tube_top
    cross = [p for p in leak_paths(low) if p.where == "port: chamber-2 cross port"]
    assert len(cross) == 1 and not cross[0].is_sealed and "OPEN" in cross[0].note
    plain = [p for p in leak_paths(Layout(BULKHEAD)) if p.where == "port: chamber-2 cross port"]
    assert len(plain) == 1 and plain[0].is_sealed  # the gas-only cap: the port in the cap, closed by its plug
