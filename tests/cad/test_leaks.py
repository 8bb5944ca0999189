"""Every joint and port sealed (issue 23, item 2): the leak audit finds every path sealed, with its ring and standard,
for every buildable layout x joint pair; the inner tube's ends sit in seats of the base and the top cap, each with a
static O-ring on the end piece's spigot in the tube's bore (ISO 3601-2), and the bulkhead's fill tube has a Ø3.8 neck
with O-ring 007 in the cap. The seats are drawn (the grooves are in the solids), in the bill of materials and on the
assembly check; a design sized by the gas-only rules keeps its open paths listed.

One design per layout runs by default (the audit needs the layout only; the solids of the default optimum), every
other pair in the slow run.
"""

from __future__ import annotations

import pytest
from build123d import Vector

from tests.cad.cases import BULKHEAD, JOINTS
from tests.cad.test_assembly_check import DEFAULT_OPTIMUM, SLOW_CASES
import vvea_design.cad.tube_seats as seats_module
from vvea_design.cad import build_cad
from vvea_design.cad.bill import glands
from vvea_design.cad.errors import CadError
from vvea_design.cad.layout import Layout
from vvea_design.cad.leaks import leak_paths
from vvea_design.cad.seals import get_oring
from vvea_design.cad.tube_seats import FILL_NECK_MM, SEAT_FLOOR_WALL_MM
from vvea_design.spring.design import Design
from vvea_design.spring.joints import LEAD_IN_GAP_MM, seal_zone_mm
from vvea_design.spring.sizing import tube_seat_mm

#: One buildable design per layout (threaded joints, near the default optimum's sizes).
PER_LAYOUT = {"inner_tube": DEFAULT_OPTIMUM,
              "bulkhead": Design(33.0, 59.3, 33000.0, 75000.0, layout="bulkhead", V2_top_mm3=3000.0),
              "annulus_top": JOINTS["thread_annulus_top"]}
#: The other buildable layout x joint pairs (bulkhead with ring_top is not built: spring.joints.EXCLUDED_PAIRS).
OTHER_PAIRS = {**{k: v for k, v in JOINTS.items() if k != "thread_annulus_top"},
               **{k: v for k, v in SLOW_CASES.items() if k not in ("thread_annulus_top", "thread_inner_tube")}}


def _assert_all_sealed(design: Design) -> Layout:
    lay = Layout(design)
    paths = leak_paths(lay)
    open_ = [(p.where, p.note) for p in paths if not p.is_sealed]
    assert not open_, open_
    for p in paths:
        assert p.standard, p.where  # every seal names its standard
    wheres = {p.where for p in paths}
    assert "inner tube on the base" in wheres
    assert ("inner tube's top end at the top cap" in wheres) == (not lay.has_top_annulus)
    assert ("fill tube's top end at the top cap" in wheres) == lay.has_bulkhead
    for p in paths:
        if p.where.startswith(("inner tube", "fill tube")):
            assert "O-ring" in p.sealed_by and p.standard.startswith("ISO 3601-1"), p
    return lay


@pytest.mark.parametrize("name", list(PER_LAYOUT))
def test_every_path_is_sealed_per_layout(name):
    lay = _assert_all_sealed(PER_LAYOUT[name])
    assert lay.seats is not None
    s = lay.seats
    # the seats' rings are on the bill of materials, with the ISO 3601-1 size the grooves were sized for
    listed = {g.kind: (g, q) for g, q, _ in glands(lay)}
    assert listed["tube_base"] == (s.base, 1)
    assert ("tube_top" in listed) == (not lay.has_top_annulus)
    if lay.has_bulkhead:
        assert listed["fill_tube"][0].oring == get_oring("007")
        assert s.fill.stretch == pytest.approx(FILL_NECK_MM / 3.68 - 1) and 0 <= s.fill.stretch <= 0.05


@pytest.mark.slow
@pytest.mark.parametrize("name", list(OTHER_PAIRS))
def test_every_path_is_sealed_for_every_pair(name):
    _assert_all_sealed(OTHER_PAIRS[name])


def test_a_gas_only_unit_lists_its_open_paths():
    """The gas-only rules draw no seats: the audit says so instead of calling the butt joints sealed."""
    lay = Layout(BULKHEAD)
    assert lay.seats is None
    open_ = {p.where for p in leak_paths(lay) if not p.is_sealed}
    assert open_ == {"inner tube on the base", "inner tube's top end at the top cap",
                     "fill tube's top end at the top cap"}


@pytest.mark.parametrize("name", list(PER_LAYOUT))
def test_the_seats_leave_room_for_their_glands(name):
    """Seat depth = the seal zone (entry land with the tube's lead-in, ISO 3601-2 gland, land), the lead-in ends
    before the groove, the seat's floor stays over the valve bores, the cap's cross port stays above its seat."""
    lay = Layout(PER_LAYOUT[name])
    s, f = lay.seats, lay.design.fixed
    cs = s.base.oring.cross_section_mm
    h = seal_zone_mm(cs, f.seal_land_mm)
    assert s.depth_mm == pytest.approx(h) == pytest.approx(float(tube_seat_mm(lay.r_piston, f)))
    assert s.z_base_floor == pytest.approx(lay.z_base_top - h)
    assert s.z_base_floor >= lay.z_valve + 0.5 * lay.throttle_d + SEAT_FLOOR_WALL_MM
    g0, g1 = s.z_base_groove
    assert g1 - g0 == pytest.approx(s.base.width_mm) and g1 <= lay.z_base_top - f.seal_land_mm + 1e-9
    assert s.z_base_floor + s.lead_in_bottom.length_mm + LEAD_IN_GAP_MM <= g0 + 1e-9
    assert 15.0 <= s.lead_in_bottom.angle_deg <= 20.0
    # the bottom lead-in covers the seat's ring and the piston's rings (the deeper protrusion)
    for g in (s.base, lay.piston_seal):
        assert s.lead_in_bottom.depth_mm >= g.protrusion_mm + g.oring.cross_section_tolerance_mm
    if s.top is not None:
        g0, g1 = s.z_top_groove
        assert g0 >= lay.z_cap + f.seal_land_mm - 1e-9
        assert g1 + s.lead_in_top.length_mm + LEAD_IN_GAP_MM <= s.z_top_end + 1e-9
        if lay.has_cross_port:
            assert lay.z_cross_port - 0.5 * lay.cad.plug_bore_mm > s.z_top_end


def test_the_seats_are_in_the_solids():
    """The grooves are cut where the layout says (a point in each groove is outside its part, the spigot's metal
    beside it inside), the tube's ends fill the seats, and the assembly check runs each seat's ring over the
    tube's lead-in."""
    from vvea_design.cad.sequence import check_assembly

    model = build_cad(DEFAULT_OPTIMUM)
    lay, s = model.layout, model.layout.seats
    base, cap, tube = (model.housing_pieces[k] for k in ("housing_base", "housing_top_cap", "housing_inner_tube"))
    r_mid = 0.5 * (s.base.groove_diameter_mm / 2 + lay.r_piston)
    for solid, (g0, g1) in ((base, s.z_base_groove), (cap, s.z_top_groove)):
        assert not solid.is_inside(Vector(r_mid, 0.0, 0.5 * (g0 + g1)))
        assert solid.is_inside(Vector(s.base.groove_diameter_mm / 2 - 0.3, 0.0, 0.5 * (g0 + g1)))
    r_wall = 0.5 * (lay.r_piston + lay.r_inner_tube)
    assert tube.is_inside(Vector(0.0, r_wall, s.z_base_floor + 0.5 * s.depth_mm))
    assert not base.is_inside(Vector(0.0, r_wall, s.z_base_floor + 0.5 * s.depth_mm))
    assert tube.is_inside(Vector(0.0, r_wall, s.z_top_end - 0.5 * s.depth_mm))
    assert not cap.is_inside(Vector(0.0, r_wall, s.z_top_end - 0.5 * s.depth_mm))
    check = check_assembly(model.solids, lay)
    assert check.passes
    crossings = {c.ring: c for st in check.steps for c in st.crossings}
    for ring in ("tube_base", "tube_top"):
        assert crossings[ring].ok and crossings[ring].part == "housing_inner_tube"
        assert any(e.startswith("lead-in") for e in crossings[ring].edges), crossings[ring].edges


def test_a_seat_over_the_valve_bores_is_refused(monkeypatch):
    """A seat whose floor would come within the least wall of the valve bores is a CadError naming the field."""
    monkeypatch.setattr(seats_module, "SEAT_FLOOR_WALL_MM", 50.0)
    with pytest.raises(CadError, match="fixed.min_base_mm"):
        Layout(DEFAULT_OPTIMUM)
