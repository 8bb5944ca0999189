"""The design's joint as the CAD draws it (issue 23): levels of the threaded spigots, the ring's plug and groove
and the tie rods' circle; the joint's items in the bill with their standards; the pieces' volumes against the
design's closed form with the joint (one mass)."""

from __future__ import annotations

import pytest

from tests.cad.cases import JOINTS, REFERENCE
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
    lay = Layout(REFERENCE)
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
    thread's run-outs, the seal zone with its lead-in, the static gland)."""
    from vvea_design.cad import build_cad

    d = JOINTS["thread_inner_tube"]
    model = build_cad(d)
    rho = get_material(d.fixed.housing_material).density_g_per_mm3
    closed = {k: v / rho for k, v in d.mass_breakdown_g().items() if k.startswith("housing_")}
    cad = {k: float(s.volume) for k, s in model.housing_pieces.items()}
    for part in ("housing_outer_tube", "housing_inner_tube", "housing_top_cap", "housing_base"):
        assert cad[part] == pytest.approx(closed[part], rel=5e-3), part
