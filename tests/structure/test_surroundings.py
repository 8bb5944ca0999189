"""What each boundary of a piece touches, from the CAD's levels, and the default load cases."""

import numpy as np
import pytest

from tests.cad.cases import BULKHEAD, OTHERS, REFERENCE
from vvea_design.cad.layout import Layout
from vvea_design.structure.loads import CASE_POSITION, default_load_cases
from vvea_design.structure.surroundings import Surroundings


@pytest.fixture(scope="module")
def bulkhead():
    return Layout(BULKHEAD)  # the gas-only bulkhead optimum (the default optimum is now an inner_tube unit)


def test_the_spaces_of_a_bulkhead_unit(bulkhead):
    lay = bulkhead
    sur = Surroundings(lay, 0.0)
    rp, rio, rb = lay.piston_radius_mm, lay.inner_tube_outer_radius_mm, lay.outer_bore_radius_mm
    zmid = 0.5 * (lay.z_free0 + lay.z_free1)
    pts = {
        "outside the housing": ((lay.outer_radius_mm + 1, zmid), "air"),
        "under the base": ((5.0, -1.0), "air"),
        "over the piston": ((0.5 * rp, lay.z_piston_top(0) + 1), "chamber_1"),
        "under the piston": ((0.5 * (rp + lay.rod_radius_mm), lay.z_piston_bottom(0) - 1), "fluid"),
        "between the piston's seals": ((rp, 0.5 * (lay.z_piston_bottom(0) + lay.z_piston_top(0))), "air"),
        "the annulus": ((0.5 * (rio + rb), zmid), "chamber_2"),
        "above the bulkhead": ((0.5 * (lay.fill_tube_outer_radius_mm + rp), lay.z_bulkhead1 + 1), "chamber_2"),
        "in the fill tube": ((0.5 * lay.fill_tube_bore_radius_mm, lay.z_bulkhead1 + 1), "chamber_1"),
        "the rod's bore above its seal": ((lay.rod_radius_mm + 0.01, lay.z_rod_seal[1] + 0.5), "fluid"),
        "the rod's bore below its seal": ((lay.rod_radius_mm + 0.01, lay.z_rod_seal[0] - 0.5), "air"),
        "a gap in the base's joint": ((rio + 0.2, lay.z_base_top - 0.1), "gap:chamber_2|fluid"),
        "a gap in the top joint": ((rb + 0.2, lay.z_cap - 0.1), "gap:chamber_1|chamber_2"),
    }
    got = sur.medium([p[0][0] for p in pts.values()], [p[0][1] for p in pts.values()])
    assert dict(zip(pts, got)) == {k: v[1] for k, v in pts.items()}
    # the piston moved to full stroke: the bore it left is chamber 1
    z = lay.z_piston_bottom(0) - 1
    assert Surroundings(lay, lay.design.fixed.travel_mm).medium(0.5 * rp, z)[0] == "chamber_1"
    # another piece's outline makes a contact face
    square = np.array([[0, 0], [100, 0], [100, 1], [0, 1]], dtype=float)
    assert Surroundings(lay, 0.0, (square,)).medium(5.0, 0.5)[0] == "contact"
    assert sur.pressures(np.array(["air", "contact", "chamber_1", "gap:chamber_1|fluid"]),
                         {"chamber_1": 2.0, "chamber_2": 3.0, "fluid": 5.0}).tolist() == [0, 0, 2, 5]


def test_the_collar_of_annulus_top():
    lay = Layout(OTHERS["annulus_top_short"])
    sur = Surroundings(lay, 0.0)
    rio, rb = lay.inner_tube_outer_radius_mm, lay.outer_bore_radius_mm
    assert sur.medium(0.5 * (rio + rb), lay.z_collar1 + 0.5)[0] == "chamber_1"  # the annulus above the collar
    assert sur.medium(0.5 * (rio + rb), lay.z_free1 - 0.5)[0] == "chamber_2"  # below it


def test_default_load_cases_are_the_spring_sides_at_their_positions(bulkhead):
    d = REFERENCE
    cases = {c.name: c for c in default_load_cases(d)}
    spring = {c.name: c for c in d.load_cases.cases}
    assert list(cases) == list(spring)
    for name, c in cases.items():
        s = spring[name]
        assert (c.chamber_1_MPa, c.chamber_2_MPa, c.fluid_MPa) == pytest.approx(
            (float(s.chamber_1_MPa), float(s.chamber_2_MPa), float(s.fluid_MPa)))
        assert c.required_safety == s.required_safety_factor and c.external_force_N == pytest.approx(float(s.external_force_N))
        assert c.x_mm == (0.0 if CASE_POSITION[name] == "rest" else d.fixed.travel_mm)
        assert c.gauge_MPa()["fluid"] == c.fluid_MPa and c.to_dict()["name"] == name
    assert cases["gas_full_stroke"].chamber_2_MPa == pytest.approx(d.peak_pressures_MPa()["chamber_2"])
