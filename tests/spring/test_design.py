"""Design geometry: every volume has a place, areas and lengths are consistent, errors are clear."""

import math
from dataclasses import replace

import pytest

from tests.spring.rules import GAS_ONLY, gas_only_defaults

from vvea_design.spring.design import Design, DesignError, FixedParameters

REF = Design(35.18, 59.5, 47107.0, 99735.0, fixed=GAS_ONLY)


@pytest.fixture(scope="module", autouse=True)
def _gas_only_rules():
    """These tests are the gas-only rules' (tests/spring/rules.py): every FixedParameters() here defaults to them."""
    with gas_only_defaults():
        yield


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
    assert d.housing_length_mm == pytest.approx(d.inner_length_mm + d.top_cap_mm + d.base_mm)
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
    d = REF.with_charge(2.0)  # low charge: the walls stay at their minimums whatever V2 is
    cap = d.V2_capacity_mm3
    at_cap = Design(d.piston_diameter_mm, d.outer_diameter_mm, d.V1_mm3, cap, p2_MPa=2.0)
    assert at_cap.walls_mm() == d.walls_mm()
    assert at_cap.bladder_clearance_mm()["compressed"] == pytest.approx(0.0, abs=1e-6)
    over = Design(d.piston_diameter_mm, d.outer_diameter_mm, d.V1_mm3, cap * 1.05, p2_MPa=2.0)
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


def test_walls_are_sized_for_the_adiabatic_peak_pressure_with_a_minimum():
    sf = REF.wall_safety_factors()
    assert set(sf) == {"outer_tube", "inner_tube", "top_cap", "base"}
    assert all(v >= 2.0 - 1e-9 for v in sf.values())
    walls, f = REF.walls_mm(), REF.fixed
    # a wall is either at its manufacturable minimum or sized to exactly the safety factor
    for wall, fmin in (("outer_tube", f.min_outer_wall_mm), ("inner_tube", f.min_inner_tube_wall_mm),
                       ("top_cap", f.min_top_cap_mm), ("base", f.min_base_mm)):
        assert walls[wall] >= fmin - 1e-12
        assert walls[wall] == pytest.approx(fmin) or sf[wall] == pytest.approx(2.0, rel=1e-9)
    # the outer tube is sized by Lamé at the adiabatic (n = 1.4) peak of chamber 2
    p = REF.gas_spring.p2_MPa * (REF.V2_mm3 / (REF.V2_mm3 - REF.displaced_volume_mm3)) ** 1.4
    assert REF.peak_pressures_MPa()["chamber_2"] == pytest.approx(p)
    ro, rb = REF.outer_diameter_mm / 2, REF.outer_bore_radius_mm
    assert p * (ro**2 + rb**2) / (ro**2 - rb**2) == pytest.approx(276.0 / 2.0, rel=1e-9)
    # the inner tube carries the peak as Lamé and does not buckle under the net pressure
    g = REF.derived
    assert g.inner_tube_buckling_MPa >= 2.0 * g.inner_tube_net_pressure_MPa * (1 - 1e-9)
    # a higher safety factor thickens the walls and costs mass; a thicker minimum is respected
    stiff = Design(35.18, 59.5, 47107.0, 99735.0, fixed=FixedParameters(wall_safety_factor=3.0))
    assert stiff.outer_wall_mm > REF.outer_wall_mm and stiff.mass_g > REF.mass_g
    thick = Design(35.18, 59.5, 47107.0, 99735.0, fixed=FixedParameters(min_outer_wall_mm=2.5))
    assert thick.outer_wall_mm == 2.5
    assert REF.minimum_walls_mm()["outer_tube"] == pytest.approx(REF.outer_wall_mm)  # sized, not at the minimum
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
        (dict(fill_tube_bore_mm=5.0), "fill_tube_bore_mm"),
    ],
)
def test_invalid_fixed_parameters(kwargs, match):
    with pytest.raises(DesignError, match=match):
        FixedParameters(**kwargs)


def test_legacy_fixed_wall_keys_become_minimums():
    f = FixedParameters.from_dict({"outer_wall_mm": 2.0, "base_mm": 15.0})
    assert f.min_outer_wall_mm == 2.0 and f.min_base_mm == 15.0


BULK = Design(35.4, 59.5, 48800.0, 102000.0, layout="bulkhead", V2_top_mm3=3800.0, fixed=GAS_ONLY)


def test_bulkhead_layout_places_every_volume():
    d, f = BULK, BULK.fixed
    a_fo = math.pi / 4 * f.fill_tube_outer_mm**2
    a_fb = math.pi / 4 * f.fill_tube_bore_mm**2
    # V2_top is the inner-tube bore above the bulkhead minus the fill tube; V1 the column below plus the tube's bore
    assert (d.A1_mm2 - a_fo) * d.top_space_length_mm == pytest.approx(d.V2_top_mm3)
    assert d.A1_mm2 * d.chamber1_length_mm + a_fb * (d.bulkhead_mm + d.top_space_length_mm) == pytest.approx(d.V1_mm3)
    assert d.inner_length_mm == pytest.approx(d.chamber1_length_mm + d.bulkhead_mm + d.top_space_length_mm
                                              + f.piston_height_mm + f.travel_mm + f.fluid_clearance_mm)
    # the annulus holds the rest of chamber 2, over the whole inner length
    rw, L = d.outer_bore_radius_mm, d.bladder_free_length_mm
    r0 = d.bladder_equivalent_outer_radius_mm(0.0)
    assert math.pi * (rw**2 - r0**2) * L + d.V2_top_mm3 == pytest.approx(d.V2_mm3, rel=1e-12)
    assert L == pytest.approx(d.inner_length_mm - 2 * f.bladder_clamp_mm)
    assert "bulkhead" in d.walls_mm() and d.bulkhead_mm >= f.min_bulkhead_mm
    assert d.wall_safety_factors()["bulkhead"] >= 2.0 - 1e-9
    assert d.mass_breakdown_g()["bulkhead"] > 0
    # the same gas in today's layout needs a longer housing (V1 sets its length)
    today = Design(35.4, 59.5, 48800.0, 102000.0)
    assert d.V2_capacity_mm3 > today.V2_capacity_mm3 - 1.0 or d.housing_length_mm < today.housing_length_mm + 30


ANN = Design(34.0, 59.5, 52000.0, 80000.0, layout="annulus_top", V1_annulus_mm3=9000.0, fixed=GAS_ONLY)


def test_annulus_top_layout_places_every_volume():
    """Issue 12: chamber 1 = the bore above the piston + the annulus above the collar; the collar is sized."""
    d, f = ANN, ANN.fixed
    a_ann = math.pi * (d.outer_bore_radius_mm**2 - d.inner_tube_outer_radius_mm**2)
    assert a_ann * d.top_annulus_length_mm == pytest.approx(d.V1_annulus_mm3, rel=1e-12)
    # the slots through the inner tube's top end join the two; their gas is chamber 1's too
    slots = f.cross_slot_fraction * math.pi * (d.inner_tube_outer_radius_mm**2 - (d.piston_diameter_mm / 2) ** 2) \
        * f.cross_slot_mm
    assert d.A1_mm2 * d.chamber1_length_mm + d.V1_annulus_mm3 + slots == pytest.approx(d.V1_mm3, rel=1e-12)
    # the housing length follows the bore column only (as in inner_tube); the annulus takes bladder length
    assert d.inner_length_mm == pytest.approx(d.chamber1_length_mm + f.piston_height_mm + f.travel_mm
                                              + f.fluid_clearance_mm)
    L = d.bladder_free_length_mm
    assert L == pytest.approx(d.inner_length_mm - 2 * f.bladder_clamp_mm - d.collar_mm - d.top_annulus_length_mm)
    r0 = d.bladder_equivalent_outer_radius_mm(0.0)
    assert math.pi * (d.outer_bore_radius_mm**2 - r0**2) * L == pytest.approx(d.V2_mm3, rel=1e-12)
    # collar: a ring cantilevered from the inner tube, sized for chamber 2 minus chamber 1 at the safety factor
    assert "collar" in d.walls_mm() and "bulkhead" not in d.walls_mm()
    rb, rio = d.outer_bore_radius_mm, d.inner_tube_outer_radius_mm
    p = d.derived.chamber_difference_MPa  # the pressure on the walls between the chambers (the collar)
    peaks = d.peak_pressures_MPa()
    assert p >= peaks["chamber_2"] - d.p1_MPa  # at least the peak chamber-2 pressure over the charge of chamber 1
    m = p / rio * ((rb**3 - rio**3) / 3 - rio * (rb**2 - rio**2) / 2)  # moment per unit root circumference
    assert d.wall_stresses_MPa()["collar"] == pytest.approx(6 * m / d.collar_mm**2, rel=1e-12)
    assert d.wall_safety_factors()["collar"] >= f.wall_safety_factor - 1e-9
    assert d.minimum_walls_mm()["collar"] <= d.collar_mm + 1e-9
    assert d.mass_breakdown_g()["collar"] == pytest.approx(a_ann * d.collar_mm * 2.7e-3, rel=0.02)
    assert d.cross_slot_room_mm == pytest.approx(min(d.top_annulus_length_mm, d.chamber1_length_mm)
                                                 - f.cross_slot_mm - 1.0)
    # a thicker minimum collar shortens the bladder by exactly the difference
    thick = replace(d, fixed=replace(f, min_collar_mm=d.collar_mm + 2.0))
    assert thick.bladder_free_length_mm == pytest.approx(L - 2.0)
    assert d.geometry_summary()["V1_annulus_mm3"] == d.V1_annulus_mm3


def test_annulus_top_constraints_are_reported():
    """The layout's own constraints (cross-hole room, collar strength) are reported and can fail."""
    from vvea_design.spring.problem import constraint_names, evaluate_design
    from vvea_design.spring.requirements import Requirements

    req = Requirements(layouts=("inner_tube", "annulus_top"))
    names = constraint_names(req, "annulus_top")
    assert "cross_slot_room" in names and "wall_safety_collar" in names
    assert "cross_slot_room" in constraint_names(req, "annulus_top", search=True)
    assert "cross_slot_room" not in constraint_names(req, "bulkhead")
    short = replace(ANN, V1_annulus_mm3=100.0, V1_mm3=ANN.V1_mm3 - 8900.0)  # 100 mm³: a sliver of annulus
    assert evaluate_design(short, req).margins["cross_slot_room"] < 0


def test_layout_errors_are_clear():
    with pytest.raises(DesignError, match="unknown layout"):
        Design(35.4, 59.5, 48800.0, 102000.0, layout="sideways")
    with pytest.raises(DesignError, match="only the 'bulkhead' layout"):
        Design(35.4, 59.5, 48800.0, 102000.0, V2_top_mm3=100.0)
    with pytest.raises(DesignError, match="V2_top_mm3"):
        Design(35.4, 59.5, 48800.0, 102000.0, layout="bulkhead", V2_top_mm3=1.5e5)
    with pytest.raises(DesignError, match="only the 'annulus_top' layout"):
        Design(35.4, 59.5, 48800.0, 102000.0, V1_annulus_mm3=100.0)
    with pytest.raises(DesignError, match="plus V1_annulus_mm3"):
        Design(35.4, 59.5, 48800.0, 102000.0, layout="annulus_top", V1_annulus_mm3=48800.0)
    with pytest.raises(DesignError, match="V1_annulus_mm3 must be"):
        Design(35.4, 59.5, 48800.0, 102000.0, layout="annulus_top", V1_annulus_mm3=-1.0)


def test_population_formulas_are_the_designs():
    import numpy as np

    from vvea_design.spring.problem import constraint_names, evaluate_design, evaluate_population
    from vvea_design.spring.requirements import Requirements

    req = Requirements()
    rng = np.random.default_rng(3)
    for layout, base in (("inner_tube", REF), ("bulkhead", BULK), ("annulus_top", ANN)):
        X = base.decision_vector() * rng.uniform(0.93, 1.07, (12, base.decision_vector().size))
        obj, mar, ok = evaluate_population(X, req, layout)
        assert ok.any()
        for k in np.flatnonzero(ok):
            kw = dict(zip(base.variant.decision_variables, X[k]))
            ev = evaluate_design(Design(**kw, p2_MPa=4.0, layout=layout), req)
            assert obj[k] == pytest.approx(ev.objective, rel=1e-12)
            np.testing.assert_allclose(mar[:, k], [ev.margins[n] for n in constraint_names(req, layout, search=True)],
                                       rtol=1e-10, atol=1e-12)


@pytest.mark.parametrize("layout", ["inner_tube", "bulkhead", "annulus_top"])
def test_volume_budget_accounts_for_every_mm3_of_the_envelope(layout):
    """Issue 12: walls, piston, rod, fluid, bladder, clamps and gas add up to the envelope cylinder."""
    top = 4735.0 if layout == "bulkhead" else 0.0
    ann = 6000.0 if layout == "annulus_top" else 0.0
    dp = 32.0 if layout == "annulus_top" else 35.42  # the shorter bladder holds the larger piston's stroke

    def at_capacity(fixed):  # V2 = its capacity (the walls follow V2's peak pressure: a fixed point)
        v2 = 90000.0
        for _ in range(30):
            v2 = Design(dp, 59.5, 48820.0 + ann, v2, layout=layout, V2_top_mm3=top, V1_annulus_mm3=ann,
                        fixed=fixed).V2_capacity_mm3
        return Design(dp, 59.5, 48820.0 + ann, v2, layout=layout, V2_top_mm3=top, V1_annulus_mm3=ann, fixed=fixed)

    d = at_capacity(FixedParameters())
    assert d.bladder_clearance_mm()["compressed"] == pytest.approx(0.0, abs=1e-4)
    for H in (None, d.housing_length_mm + 7.5):
        b = d.volume_budget_mm3(H)
        envelope = math.pi / 4 * d.outer_diameter_mm**2 * (d.housing_length_mm if H is None else H)
        assert sum(b.values()) == pytest.approx(envelope, rel=1e-12)
        assert min(b.values()) >= -1e-9
        assert b["unused_length"] == pytest.approx(math.pi / 4 * d.outer_diameter_mm**2 * (0 if H is None else 7.5))
    gas = b["gas_chamber_1"] + b["gas_chamber_1_annulus"] + b["gas_chamber_2_above_bulkhead"] + b["gas_chamber_2_annulus"]
    assert b["gas_chamber_1_annulus"] == ann and (b["wall_collar"] > 0) == (layout == "annulus_top")
    assert gas == pytest.approx(d.V1_mm3 + d.V2_mm3, rel=1e-12)
    fluid = (b["fluid_swept_by_stroke"] + b["fluid_clearance_under_piston"] + b["bladder_fluid_min_gap"]
             + b["bladder_fluid_bulge_room"])
    assert fluid == pytest.approx(d.fluid_volume_mm3, rel=1e-12)
    assert b["fluid_swept_by_stroke"] == pytest.approx(d.displaced_volume_mm3)
    assert (b["wall_bulkhead"] > 0) == (layout == "bulkhead")
    # the bladder cast at mid-stroke needs room for its inward bulge at x = 0 (about (k - 1)/2 of the half
    # stroke's fluid, k = bladder_bulge_factor); cast at x = 0 it needs none, and that room is gas
    assert b["bladder_fluid_bulge_room"] == pytest.approx(0.5 * 0.5 * d.displaced_volume_mm3, rel=0.15)
    e = at_capacity(FixedParameters(bladder_cast_fill=0.0))
    early = e.volume_budget_mm3()
    assert early["bladder_fluid_bulge_room"] == pytest.approx(0.0, abs=1.0)
    assert early["bladder_fluid_min_gap"] == pytest.approx(b["bladder_fluid_min_gap"], rel=1e-2)
    assert e.V2_mm3 > d.V2_mm3 + 0.8 * b["bladder_fluid_bulge_room"]


# ------------------------------------------------------------------ piston pocket (issue 12)
POCKET = FixedParameters(piston_pocket=True, sizing_rules="gas_only")


@pytest.mark.parametrize("base", [REF, BULK, ANN], ids=["inner_tube", "bulkhead", "annulus_top"])
def test_piston_pocket_holds_chamber_1_gas_in_every_layout(base):
    """The pocket's gas is part of V1: the bore column shrinks by pocket/A1, the spring is unchanged."""
    d = replace(base, fixed=replace(base.fixed, piston_pocket=True))
    f = d.fixed
    a, depth = d.piston_pocket_radius_mm, d.piston_pocket_depth_mm
    assert a == pytest.approx(d.piston_diameter_mm / 2 - f.piston_pocket_wall_mm)
    assert depth == pytest.approx(f.piston_height_mm - d.piston_floor_mm) and depth > 0
    assert d.piston_pocket_volume_mm3 == pytest.approx(math.pi * a**2 * depth, rel=1e-12)
    assert d.chamber1_length_mm == pytest.approx(base.chamber1_length_mm - d.piston_pocket_volume_mm3 / d.A1_mm2)
    assert d.housing_length_mm == pytest.approx(base.housing_length_mm - d.piston_pocket_volume_mm3 / d.A1_mm2)
    # gas-spring physics unchanged: V1 is still the chamber-1 gas at x = 0
    assert d.p1_MPa == base.p1_MPa and d.gas_spring.V1_mm3 == base.V1_mm3
    # the floor is a wall: sized, reported, in the summary; the budget still adds up to the envelope
    assert d.walls_mm()["piston_floor"] == d.piston_floor_mm and "piston_floor" not in base.walls_mm()
    assert d.wall_safety_factors()["piston_floor"] >= f.wall_safety_factor - 1e-9
    assert d.geometry_summary()["piston_pocket_volume_mm3"] == d.piston_pocket_volume_mm3
    assert "piston_pocket_volume_mm3" not in base.geometry_summary()
    b = d.volume_budget_mm3()
    assert sum(b.values()) == pytest.approx(math.pi / 4 * d.outer_diameter_mm**2 * d.housing_length_mm, rel=1e-12)
    assert b["gas_chamber_1_piston_pocket"] == d.piston_pocket_volume_mm3
    assert b["piston"] == pytest.approx(d.A1_mm2 * f.piston_height_mm - d.piston_pocket_volume_mm3)
    gas = sum(v for k, v in b.items() if k.startswith("gas_"))
    assert gas == pytest.approx(d.V1_mm3 + d.V2_mm3, rel=1e-12)
    # mass: the cupped piston in the rod's material (one turned part with the rod)
    rho = 7.85e-3
    assert d.mass_breakdown_g()["piston"] == pytest.approx((d.A1_mm2 * f.piston_height_mm
                                                            - d.piston_pocket_volume_mm3) * rho, rel=1e-12)


def test_piston_floor_moment_solves_the_plate_equation():
    """The closed form against an independent numerical solution of the axisymmetric plate (scipy solve_bvp):
    annular plate b..a clamped at the rod, free to rotate at the pocket wall, uniform pressure on b..a plus the
    rim's load as a line load at a."""
    import numpy as np
    from scipy.integrate import solve_bvp

    from vvea_design.spring.derive import piston_floor_moment

    nu = 0.29
    for rp, a, b in ((18.1, 15.1, 4.0), (12.0, 8.5, 4.0), (25.0, 22.0, 3.0)):
        # unknowns: slope th = w' and Mr (per unit pressure, D = 1); equilibrium d(r Mr)/dr - Mt = r Q,
        # Mr = -(th' + nu th / r), Mt = -(th / r + nu th'), Q = (rp^2 - r^2) / (2 r)
        def rhs(r, y):
            th, mr = y
            dth = -mr - nu * th / r
            mt = -(th / r + nu * dth)
            return np.vstack([dth, (mt + r * (rp**2 - r**2) / (2 * r) - mr) / r])

        r = np.linspace(b, a, 200)
        sol = solve_bvp(rhs, lambda ya, yb: np.array([ya[0], yb[1]]), r, np.zeros((2, r.size)), tol=1e-10,
                        max_nodes=100000)
        assert sol.success
        mr = sol.sol(np.linspace(b, a, 400))[1]
        assert np.abs(mr).max() == pytest.approx(abs(mr[0]), rel=1e-9)  # the largest moment is at the rod
        assert float(piston_floor_moment(rp, a, b, nu)) == pytest.approx(abs(mr[0]), rel=1e-6)


def test_piston_floor_is_pressure_sized_never_below_its_minimum():
    lo, hi = (replace(BULK, fixed=POCKET).with_charge(p) for p in (1.0, 4.0))
    assert lo.piston_floor_mm == POCKET.min_piston_floor_mm  # a low charge: the manufacturable minimum
    assert hi.piston_floor_mm > POCKET.min_piston_floor_mm  # the paper's charge: sized up, to the safety factor
    assert hi.wall_safety_factors()["piston_floor"] == pytest.approx(POCKET.wall_safety_factor, rel=1e-9)
    assert hi.piston_pocket_volume_mm3 < lo.piston_pocket_volume_mm3
    assert hi.minimum_walls_mm()["piston_floor"] == pytest.approx(hi.piston_floor_mm)
    # the floor carries the bulkhead's differential (chamber 2 = the fluid below, minus chamber 1): both walls'
    # stresses follow from the one pressure between the chambers
    from vvea_design.materials.structural import get_material
    from vvea_design.spring.derive import piston_floor_moment

    p, f = hi.derived.chamber_difference_MPa, hi.fixed
    assert p >= hi.peak_pressures_MPa()["chamber_2"] - hi.p1_MPa
    rp, b, t = hi.piston_diameter_mm / 2, f.rod_diameter_mm / 2, hi.piston_floor_mm
    k = piston_floor_moment(rp, hi.piston_pocket_radius_mm, b, get_material(f.rod_material).poisson)
    floor = max(6 * k * p / t**2, 3 * p * (rp**2 - b**2) / (2 * b * t))
    assert hi.wall_stresses_MPa()["piston_floor"] == pytest.approx(floor, rel=1e-12)
    nu = get_material(f.housing_material).poisson
    assert hi.wall_stresses_MPa()["bulkhead"] == pytest.approx(3 * (3 + nu) / 8 * p * rp**2 / hi.bulkhead_mm**2,
                                                               rel=1e-12)
    # a weaker piston material needs a thicker floor; a floor the height of the piston leaves no pocket
    alu = replace(BULK, fixed=replace(POCKET, rod_material="al-6061-t6"))
    assert alu.piston_floor_mm > hi.piston_floor_mm
    solid = replace(BULK, fixed=replace(POCKET, min_piston_floor_mm=12.0))
    assert solid.piston_floor_mm == POCKET.piston_height_mm and solid.piston_pocket_volume_mm3 == 0.0
    # no pocket where its radius would not exceed the rod's
    thin = Design(14.0, 40.0, 9000.0, 20000.0, fixed=replace(POCKET, piston_pocket_wall_mm=3.5))
    assert thin.piston_pocket_volume_mm3 == 0.0 and thin.piston_pocket_radius_mm == 0.0
    with pytest.raises(DesignError, match="fixed.piston_pocket must be true or false"):
        FixedParameters(piston_pocket="yes")


def test_piston_pocket_population_formulas_are_the_designs():
    import numpy as np

    from vvea_design.spring.problem import constraint_names, evaluate_design, evaluate_population
    from vvea_design.spring.requirements import Requirements

    req = Requirements(fixed=POCKET)
    assert "wall_safety_piston_floor" in constraint_names(req, "bulkhead")
    rng = np.random.default_rng(5)
    X = BULK.decision_vector() * rng.uniform(0.95, 1.05, (8, 5))
    obj, mar, ok = evaluate_population(X, req, "bulkhead")
    for k in np.flatnonzero(ok):
        d = Design(**dict(zip(BULK.variant.decision_variables, X[k])), layout="bulkhead", fixed=POCKET)
        ev = evaluate_design(d, req)
        assert obj[k] == pytest.approx(ev.objective, rel=1e-12)
        np.testing.assert_allclose(mar[:, k], [ev.margins[n] for n in constraint_names(req, "bulkhead", search=True)],
                                   rtol=1e-10, atol=1e-12)
        assert ev.margins["wall_safety_piston_floor"] >= -1e-9
