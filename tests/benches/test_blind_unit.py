"""Base physics and motion of the blind bench."""

import numpy as np
import pytest

from vvea_benches.blind.motion import Motion, plan_campaign
from vvea_benches.blind.simulate import ExperimentMods, simulate_experiment, throttle_static_N
from vvea_benches.blind.unit import TABLE3_L, VALVES_DEG, BaseUnit, sample_base
from vvea_design.spring.gas_spring import PAPER_FIG5


@pytest.fixture(scope="module")
def base():
    return sample_base(np.random.default_rng(0))


def test_chambers_follow_eq5_zero_at_rest_tension_when_extended(base):
    x = np.linspace(0, 40, 81)
    F = base.gas_force_N(x, 2.0)
    assert abs(F[0]) < 1e-9  # eq. 7: zero force at x = 0
    assert np.all(np.diff(F) > 0) and F[-1] > 0  # x > 0 extends the pull spring: tension grows
    k = np.polyfit(x, F, 1)[0] / 2.0
    assert 15 < k < 28  # per MPa: the design gives about 19 (1827 N at 40 mm and 2.39 MPa), Table 3 23.3
    P1, P2 = base.chamber_pressures_MPa(40.0, 2.0)
    assert P2 > 2.0 > 0 and P1 < base.p1_MPa(2.0)  # chamber 2 compressed, chamber 1 expanded
    F4 = base.gas_force_N(x, 4.0)
    np.testing.assert_allclose(F4, 2 * F, rtol=1e-12)  # force scales with the charge


def test_paper_geometry_and_near_linear_spring(base):
    assert base.A2_mm2 == pytest.approx(PAPER_FIG5.A2_mm2) and base.A1_mm2 == pytest.approx(PAPER_FIG5.A1_mm2)
    assert 0.9 * PAPER_FIG5.V2_mm3 <= base.V2_mm3 <= 1.1 * PAPER_FIG5.V2_mm3
    x = np.linspace(0, 40, 401)
    F = base.gas_force_N(x, 2.0)
    dev = np.abs(F - np.polyval(np.polyfit(x, F, 1), x)).max() / (F.max() - F.min())
    assert 0.005 < dev < 0.05  # paper section 3.2.4: 1.86 % linearity deviation at the design's V2
    d2 = np.diff(F, 2)
    assert d2[0] < 0 < d2[-1]  # chamber 1 softens first, chamber 2 stiffens at the end


def test_linear_law_is_eq14_spring():
    b = sample_base(np.random.default_rng(1), "linear")
    np.testing.assert_allclose(b.gas_force_N(np.array([0.0, 10.0, 40.0]), 2.0),
                               b.g_N_per_mm_MPa * 2.0 * np.array([0.0, 10.0, 40.0]))


def test_damping_table_and_continuity(base):
    L = base.damping_N_s_per_mm(np.array(VALVES_DEG))
    np.testing.assert_allclose(L, base.L_N_s_per_mm, rtol=1e-12)
    ratio = np.array(base.L_N_s_per_mm) / np.array(TABLE3_L)
    assert np.all((ratio >= 0.9) & (ratio <= 1.1))
    g = np.linspace(100, 120, 201)
    assert np.all(np.diff(base.damping_N_s_per_mm(g)) > 0)  # closing the valve raises the damping


def test_bad_base_raises():
    with pytest.raises(ValueError, match="gas_law"):
        BaseUnit("adiabatic", 1, 1, 1e5, 1e5, 20, tuple(TABLE3_L), 120)
    with pytest.raises(ValueError, match="V2_mm3"):
        BaseUnit("chambers", 2561, 707, 1.22e5, 2.0e4, 20, tuple(TABLE3_L), 120)


def test_motion_out_and_back():
    m = Motion(12.0, n_per_ramp=200)
    t = m.t_s
    x, v = m.position_mm(t), m.velocity_mm_s(t)
    assert x[0] == pytest.approx(0) and x[-1] == pytest.approx(0, abs=1e-9)
    assert x[m.turn_index] == pytest.approx(40.0) and t[m.turn_index] == pytest.approx(m.ramp_s)
    assert v.max() == pytest.approx(12.0) and v.min() == pytest.approx(-12.0)
    assert np.all(v[: m.turn_index] >= 0) and np.all(v[m.turn_index + 1:] <= 0)
    np.testing.assert_allclose(np.gradient(x, t)[20:180], v[20:180], atol=1e-6)  # velocity is x's derivative
    with pytest.raises(ValueError, match="speed"):
        Motion(0.0)


def test_plan_is_the_papers_campaign_shuffled():
    plans = plan_campaign(np.random.default_rng(0), 20)
    combos = {(p.p2_MPa, p.valve_deg, p.speed_mm_s) for p in plans}
    assert len(plans) == 135 and len(combos) == 135
    starts = np.array([p.t_start_s for p in plans])
    assert np.all(np.diff(starts) > 0)
    assert plans != plan_campaign(np.random.default_rng(1), 20)  # the order depends on the seed


def test_base_experiment_is_eq14_plus_chambers(base):
    m = Motion(4.0, n_per_ramp=50)
    from vvea_benches.blind.motion import ExperimentPlan

    plan = ExperimentPlan(0, "E000", 2.0, 108.0, 4.0, 0.0, 0.0, m.duration_s)
    s = simulate_experiment(base, plan, ExperimentMods(valve_deg=108.0), m)
    L = float(base.damping_N_s_per_mm(108.0))
    expect = base.gas_force_N(s["x_mm"], 2.0) + L * s["v_mm_s"] + base.C_N * np.tanh(s["v_mm_s"] / 0.01)
    np.testing.assert_allclose(s["f_unit_N"], expect, atol=1e-9)
    assert np.all(s["F_thr_N"][1:50] > 0) and np.all(s["F_thr_N"][51:-1] < 0)  # damping opposes the motion


def test_throttle_static_linear_and_odd():
    v = np.linspace(-12, 12, 25)
    np.testing.assert_allclose(throttle_static_N(v, 40.0), 40.0 * v)
    F = throttle_static_N(v, 40.0, 0.5)
    np.testing.assert_allclose(F, -F[::-1])
