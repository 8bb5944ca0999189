"""Design geometry: every volume has a place, areas and lengths are consistent, errors are clear."""

import math

import pytest

from vvea_design.spring.design import Design, DesignError, FixedParameters

REF = Design(35.18, 59.5, 47107.0, 99735.0)


def test_areas_follow_the_layout():
    d = REF
    assert d.A1_mm2 == pytest.approx(math.pi / 4 * 35.18**2)
    assert d.A2_mm2 == pytest.approx(math.pi / 4 * (35.18**2 - 8.0**2))
    assert d.A1_mm2 > d.A2_mm2  # so p1 = A2/A1 p2 stays below p2


def test_V1_sets_the_length_and_fits_in_the_inner_tube():
    d = REF
    assert d.A1_mm2 * d.chamber1_length_mm == pytest.approx(d.V1_mm3)
    f = d.fixed
    assert d.inner_length_mm == pytest.approx(d.chamber1_length_mm + f.piston_height_mm + f.travel_mm + f.fluid_clearance_mm)
    assert d.housing_length_mm == pytest.approx(d.inner_length_mm + f.top_cap_mm + f.base_mm)
    longer = Design(35.18, 59.5, 60000.0, 99735.0)
    assert longer.housing_length_mm - d.housing_length_mm == pytest.approx(12893.0 / d.A1_mm2)


def test_V2_is_the_gas_around_the_bladder():
    d = REF
    rw, L = d.outer_bore_radius_mm, d.bladder_free_length_mm
    cast_gas = math.pi * (rw**2 - d.bladder_outer_radius_mm**2) * L
    assert cast_gas == pytest.approx(d.V2_mm3 - 0.5 * d.displaced_volume_mm3, rel=1e-9)
    r0 = d.bladder_equivalent_outer_radius_mm(0.0)
    assert math.pi * (rw**2 - r0**2) * L == pytest.approx(d.V2_mm3, rel=1e-12)
    rT = d.bladder_equivalent_outer_radius_mm(d.fixed.travel_mm)
    assert math.pi * (rw**2 - rT**2) * L == pytest.approx(d.V2_mm3 - d.displaced_volume_mm3, rel=1e-12)
    assert d.inner_tube_outer_radius_mm < d.bladder_inner_radius_mm < d.bladder_outer_radius_mm < rw


def test_capacity_and_room_agree():
    d = REF
    cap = d.V2_capacity_mm3
    at_cap = Design(d.piston_diameter_mm, d.outer_diameter_mm, d.V1_mm3, cap)
    assert at_cap.bladder_clearance_mm()["compressed"] == pytest.approx(0.0, abs=1e-6)
    over = Design(d.piston_diameter_mm, d.outer_diameter_mm, d.V1_mm3, cap * 1.05)
    assert over.bladder_clearance_mm()["compressed"] < 0


def test_volume_changes_add_up_to_the_displaced_fluid():
    dv = REF.bladder_volume_change_mm3
    assert dv["expanded"] - dv["compressed"] == pytest.approx(REF.displaced_volume_mm3)
    assert dv["compressed"] < 0 < dv["expanded"]


def test_gas_spring_matches_design_and_has_zero_force_at_setpoint():
    gs = REF.gas_spring
    assert gs.A1_mm2 == REF.A1_mm2 and gs.V2_mm3 == REF.V2_mm3
    assert abs(float(gs.force_N(0.0))) < 1e-9
    shifted = REF.with_charge(4.0, setpoint_x0_mm=3.0)
    assert abs(float(shifted.gas_spring.force_N(3.0))) < 1e-8


def test_strength_and_mass_are_physical():
    sf = REF.wall_safety_factors()
    assert set(sf) == {"outer_tube", "inner_tube", "top_cap", "base"}
    assert all(v > 1 for v in sf.values())
    tmin = REF.minimum_walls_mm(2.0)
    assert tmin["outer_tube"] < REF.fixed.outer_wall_mm  # SF 2.25 > 2: the wall is thicker than needed
    # same bore, thinner wall: exactly the safety factor asked for
    D = 2 * (REF.outer_bore_radius_mm + tmin["outer_tube"])
    thin = Design(35.18, D, 47107.0, 99735.0, fixed=FixedParameters(outer_wall_mm=tmin["outer_tube"]))
    assert thin.wall_safety_factors()["outer_tube"] == pytest.approx(2.0, rel=1e-6)
    m = REF.mass_breakdown_g()
    assert 300 < REF.mass_g < 800 and m["servo_and_valve"] == 40.0
    assert sum(m.values()) == pytest.approx(REF.mass_g)


@pytest.mark.parametrize(
    "kwargs, match",
    [
        (dict(piston_diameter_mm=-1.0), "piston_diameter_mm must be a positive number"),
        (dict(V1_mm3=float("nan")), "V1_mm3 must be a positive number"),
        (dict(piston_diameter_mm=6.0), "must exceed the rod diameter"),
        (dict(piston_diameter_mm=50.0), "no room for the bladder"),
        (dict(V2_mm3=30000.0), "chamber 2 bottoms out"),
        (dict(p2_MPa=0.0), "p2_MPa must be > 0"),
    ],
)
def test_invalid_designs_name_the_field(kwargs, match):
    base = dict(piston_diameter_mm=35.18, outer_diameter_mm=59.5, V1_mm3=47107.0, V2_mm3=99735.0)
    base.update(kwargs)
    with pytest.raises(DesignError, match=match):
        Design(**base)


@pytest.mark.parametrize(
    "kwargs, match",
    [
        (dict(travel_mm=0.0), "fixed.travel_mm must be > 0"),
        (dict(bladder_cast_fill=1.5), "bladder_cast_fill"),
        (dict(housing_material="unobtainium"), "unknown material"),
        (dict(n_polytropic=2.0), "n_polytropic"),
    ],
)
def test_invalid_fixed_parameters(kwargs, match):
    with pytest.raises(DesignError, match=match):
        FixedParameters(**kwargs)
