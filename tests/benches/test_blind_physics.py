"""Physics of each mechanism: signs (x > 0 extends, force > 0 is tension), limits, energy."""

import numpy as np
import pytest

from vvea_benches.blind.catalogue.quadratic_damping import orifice_K_N_s2_per_mm2
from vvea_benches.blind.mechanisms.bladder_membrane import loss_state
from vvea_benches.blind.mechanisms.gas_dissolution import _evolve
from vvea_benches.blind.mechanisms.seal_heating import lip_temperature_K
from vvea_benches.blind.mechanisms.valve_backlash import actual_angles_deg
from vvea_benches.blind.registry import lookup
from vvea_benches.blind.simulate import throttle_static_N


def delta(bench, ctx, name, params, idx):
    base, _ = bench.simulate(ctx, (), idx)
    on, mods = bench.simulate(ctx, [(lookup(name), params)], idx)
    return base, on, mods


def loop_work(s):
    """Work the crosshead puts in over the cycle, N mm (> 0: the unit dissipates)."""
    return float(np.trapezoid(s["f_unit_N"], s["x_mm"]))


def test_charge_zero_offset_is_k_p2_everywhere(bench, ctx):
    i = bench.find(ctx, 4.0, 108.0, 4.0)
    base, on, _ = delta(bench, ctx, "charge_zero_offset", {"k_N_per_MPa": 10.0, "sign": -1.0}, [i])
    np.testing.assert_allclose(on[i]["f_meas_N"] - base[i]["f_meas_N"], -40.0)
    np.testing.assert_allclose(on[i]["f_unit_N"], base[i]["f_unit_N"])  # the unit itself is unchanged


def test_room_warming_raises_the_charge_over_the_campaign(bench, ctx):
    first, last = 0, len(ctx.plans) - 1
    base, on, _ = delta(bench, ctx, "room_warming", {"dT_K": 6.0, "tau_h": 2.0}, [first, last])
    ratio = on[last]["F_gas_N"][10:-10] / base[last]["F_gas_N"][10:-10]
    assert 1.0 < ratio.min() <= ratio.max() <= (293.15 + 6.0) / 293.15 + 1e-12
    assert abs(on[first]["F_gas_N"] - base[first]["F_gas_N"]).max() < 0.05 * abs(on[last]["F_gas_N"] - base[last]["F_gas_N"]).max()


def test_oil_warming_lowers_damping_not_spring(bench, ctx):
    i = len(ctx.plans) - 1
    params = {"b_per_K": 0.04, "dT_room_K": 5.0, "tau_room_h": 1.0, "C_th_J_per_K": 600.0, "R_th_K_per_W": 4.0}
    base, on, _ = delta(bench, ctx, "oil_warming", params, [i])
    np.testing.assert_allclose(on[i]["F_gas_N"], base[i]["F_gas_N"])
    r = on[i]["F_thr_N"][5:-5] / base[i]["F_thr_N"][5:-5]
    assert np.all(r < 1.0) and np.all(r > np.exp(-0.04 * 30))


def test_sticky_band_opposes_motion_inside_the_band_only(bench, ctx):
    i = bench.find(ctx, 2.0, 104.0, 4.0)
    base, on, _ = delta(bench, ctx, "sticky_band", {"x_start_mm": 10.0, "width_mm": 6.0, "dC_N": 50.0}, [i])
    d, x, v = on[i]["f_meas_N"] - base[i]["f_meas_N"], on[i]["x_mm"], on[i]["v_mm_s"]
    inside = (x > 11) & (x < 15)
    outside = (x < 8) | (x > 18)
    np.testing.assert_allclose(d[inside], 50.0 * np.sign(v[inside]), atol=0.5)
    assert np.abs(d[outside]).max() < 0.5


def test_bladder_membrane_is_charge_free_and_dissipates(bench, ctx):
    prm = {"p_b_MPa": 0.03, "x_n_mm": 20.0, "a": 0.6, "eta": 0.2, "x_h_mm": 2.0}
    i1, i4 = bench.find(ctx, 1.0, 50.0, 1.0), bench.find(ctx, 4.0, 50.0, 1.0)
    base, on, _ = delta(bench, ctx, "bladder_membrane", prm, [i1, i4])
    d1, d4 = (on[i]["F_extra_N"] for i in (i1, i4))
    np.testing.assert_allclose(d1, d4, atol=1e-9)  # the same force at every charge
    assert np.abs(d1).max() <= ctx.base.A2_mm2 * 0.03 * 1.2 + 1e-9
    work = float(np.trapezoid(d1, on[i1]["x_mm"]))
    assert work > 0  # loading branch above unloading: the loop dissipates
    h = loss_state(np.array([0.0, 5.0, 10.0, 5.0]), np.array([1.0, 1.0, -1.0, -1.0]), 0.2, 2.0)
    assert h[1] > 0 > h[3]


def test_start_transient_peaks_at_tau_and_dies_out(bench, ctx):
    i = bench.find(ctx, 2.0, 80.0, 12.0)
    base, on, _ = delta(bench, ctx, "start_transient", {"A_N": 50.0, "tau_s": 0.05}, [i])
    d, t = on[i]["f_meas_N"] - base[i]["f_meas_N"], on[i]["t_s"]
    assert d.max() <= 50.0 + 1e-9 and d.max() > 40.0 and np.all(d >= 0)
    assert np.abs(d[t > 1.0]).max() < 1e-3


def test_entrained_air_lags_the_damping_force(bench, ctx):
    i = bench.find(ctx, 1.0, 120.0, 8.0)
    prm = {"alpha_at_1MPa": 0.01, "V_in_mm3": 3e4, "K_oil_MPa": 1500.0}
    base, on, mods = delta(bench, ctx, "entrained_air", prm, [i])
    F, Fb, t = on[i]["F_thr_N"], base[i]["F_thr_N"], on[i]["t_s"]
    tau = ctx.base.damping_N_s_per_mm(120.0) / mods[i].oil_stiffness_N_per_mm
    early = (t > 0.3) & (t < 0.3 + 0.5 * tau)
    assert np.all(np.abs(F[early]) < np.abs(Fb[early]))  # builds up slowly
    k = ctx.motions[i].turn_index
    assert F[k] > 0.5 * Fb[k - 20]  # and still carries force at the reversal (a lag, not a loss)
    assert loop_work(on[i]) > 0


def test_zero_position_scatter_is_random_per_experiment_and_repeatable(bench, ctx):
    idx = list(range(40))
    _, on, mods = delta(bench, ctx, "zero_position_scatter", {"sigma_mm": 0.2}, idx)
    off = np.array([m.x_offset_mm for m in mods])
    assert 0.1 < off.std() < 0.3 and len(set(np.round(off, 9))) == len(off)
    _, again, mods2 = delta(bench, ctx, "zero_position_scatter", {"sigma_mm": 0.2}, idx[:2])
    assert [m.x_offset_mm for m in mods2] == list(off)


def test_seal_heating_friction_sinks_in_fast_runs_only(bench, ctx):
    fast, slow = bench.find(ctx, 2.0, 50.0, 12.0), bench.find(ctx, 2.0, 50.0, 0.1)
    prm = {"R_K_per_W": 40.0, "tau_s": 5.0, "kappa_per_K": 0.006}
    base, on, _ = delta(bench, ctx, "seal_heating", prm, [fast, slow])
    ratio_fast = np.abs(on[fast]["F_fric_N"][-5]) / np.abs(base[fast]["F_fric_N"][-5])
    ratio_slow = np.abs(on[slow]["F_fric_N"][-5]) / np.abs(base[slow]["F_fric_N"][-5])
    assert ratio_fast < 0.9 and ratio_slow > 0.99
    dT = lip_temperature_K(np.linspace(0, 100, 1001), np.full(1001, 10.0), 100.0, 40.0, 5.0)
    assert dT[-1] == pytest.approx(40.0 * 100.0 * 10.0 * 1e-3, rel=1e-3)  # steady rise R C v


def test_misalignment_friction_follows_the_load(bench, ctx):
    i = bench.find(ctx, 4.0, 100.0, 4.0)
    base, on, _ = delta(bench, ctx, "misalignment_friction", {"mu_eff": 0.02}, [i])
    d = on[i]["f_meas_N"] - base[i]["f_meas_N"]
    expect = 0.02 * np.abs(base[i]["F_gas_N"] + base[i]["F_thr_N"]) * np.tanh(on[i]["v_mm_s"] / 0.01)
    np.testing.assert_allclose(d, expect, atol=1e-9)


def test_bladder_contact_only_near_full_stroke(bench, ctx):
    i = bench.find(ctx, 2.0, 50.0, 4.0)
    base, on, _ = delta(bench, ctx, "bladder_contact", {"x_c_mm": 35.0, "F_end_N": 80.0, "mu_c": 0.5}, [i])
    d, x = on[i]["f_meas_N"] - base[i]["f_meas_N"], on[i]["x_mm"]
    assert np.abs(d[x < 34.9]).max() < 1e-9
    k = ctx.motions[i].turn_index
    assert d[k - 1] > 80.0 * 0.9  # near the end: elastic force plus rubbing while extending
    assert d[k + 1] < d[k - 1]  # rubbing changes sign on the way back


def test_frame_compliance_softens_and_lags(bench, ctx):
    slow, stiff = bench.find(ctx, 4.0, 50.0, 0.1), bench.find(ctx, 2.0, 120.0, 4.0)
    K = 5000.0
    base, on, _ = delta(bench, ctx, "frame_compliance", {"K_N_per_mm": K}, [slow, stiff])
    s = on[slow]
    np.testing.assert_allclose(s["x_mm"], s["x_cross_mm"] - s["f_unit_N"] / K, atol=1e-9)
    assert np.all(s["x_mm"][5:-5] <= s["x_cross_mm"][5:-5] + 1e-9) or np.all(s["f_unit_N"][5:-5] < 0)
    k = ctx.motions[slow].turn_index
    assert on[slow]["f_unit_N"][k - 2] < base[slow]["f_unit_N"][k - 2]  # the spring looks softer
    m = ctx.motions[stiff]
    early = (m.t_s > 0.1) & (m.t_s < 0.15)
    assert np.all(on[stiff]["f_unit_N"][early] < base[stiff]["f_unit_N"][early])  # Maxwell lag at the closed valve


def test_gas_dissolution_conserves_gas_and_follows_the_previous_charge():
    P, D = _evolve(4.0, 1.0, 0.05, 200.0, np.array([0.0, 100.0, 1e5]))
    np.testing.assert_allclose(P + 0.05 * D, 4.0 + 0.05 * 1.0)  # the gas leaves the chamber into the oil
    assert P[0] == 4.0 and P[1] < 4.0 and P[2] == pytest.approx(D[2])
    P, _ = _evolve(1.0, 4.0, 0.05, 200.0, 100.0)
    assert P > 1.0  # after a step down the oil gives gas back


def test_cavitation_caps_the_retracting_damping_only(bench, ctx):
    i = bench.find(ctx, 1.0, 120.0, 8.0)
    base, on, _ = delta(bench, ctx, "cavitation", {"p_cav_MPa": 0.1}, [i])
    v, F, P2 = on[i]["v_mm_s"], on[i]["F_thr_N"], on[i]["P2_MPa"]
    ext = v > 1
    np.testing.assert_allclose(F[ext], base[i]["F_thr_N"][ext], atol=1e-6)
    ret = v < -1
    assert np.all(F[ret] >= -ctx.base.A2_mm2 * (P2[ret] - 0.1) - 1e-6)
    assert np.all(F[ret] > base[i]["F_thr_N"][ret])


def test_valve_backlash_side_of_approach():
    a = actual_angles_deg([108.0, 108.0, 110.0, 104.0, 104.0, 108.0], 1.0)
    assert a == [107.5, 107.5, 109.5, 104.5, 104.5, 107.5]


def test_thermal_stiffer_when_fast_isothermal_when_slow_and_dissipative(bench, ctx):
    fast, slow = bench.find(ctx, 4.0, 50.0, 12.0), bench.find(ctx, 4.0, 50.0, 0.1)
    base, on, _ = delta(bench, ctx, "thermal", {"tau2_s": 1.0, "tau1_ratio": 1.2}, [fast, slow])
    k = ctx.motions[fast].turn_index
    assert on[fast]["F_gas_N"][k] > base[fast]["F_gas_N"][k] + 50
    assert np.abs(on[slow]["F_gas_N"] - base[slow]["F_gas_N"]).max() < 0.05 * 0.01 * base[slow]["F_gas_N"].max() + 5
    gas_loop = float(np.trapezoid(on[fast]["F_gas_N"], on[fast]["x_mm"]))
    assert gas_loop > 0  # heat exchange makes the gas cycle dissipate


def test_quadratic_damping_orifice_law():
    p = {"A_w_mm2": 2.0, "A_b_mm2": 0.2, "gamma_c_deg": 112.0, "Cd": 0.7}
    K = orifice_K_N_s2_per_mm2(120.0, p, 706.86)
    assert K == pytest.approx(1e-3 * 870e-9 * 706.86**3 / (2 * 0.49 * 0.04), rel=1e-6)
    assert orifice_K_N_s2_per_mm2(50.0, p, 706.86) < orifice_K_N_s2_per_mm2(108.0, p, 706.86) < K
    v = np.array([-8.0, -1.0, 1.0, 8.0])
    F = throttle_static_N(v, 10.0, K)
    np.testing.assert_allclose(F, 10.0 * v + K * v * np.abs(v))


def test_relief_valve_caps_the_force_and_is_transparent_below(bench, ctx):
    prm = {"F_crack_N": 2000.0, "d_seat_mm": 2.0, "k_spring_N_per_mm": 30.0}
    r = dict(prm, Cd=0.65, lift_max_mm=1.0, bidirectional=True)
    v = np.array([0.5, 1.0, 4.0, 12.0, -12.0])
    F = throttle_static_N(v, 1000.0, 0.0, r, 706.86)
    np.testing.assert_allclose(F[:2], 1000.0 * v[:2])  # below cracking: the throttle alone
    assert 2000.0 < F[3] < 2600.0 and F[4] == pytest.approx(-F[3])  # capped a little above cracking


def test_stiction_breakaway_and_coulomb_limit(bench, ctx):
    i = bench.find(ctx, 2.0, 50.0, 0.1)
    base, on, _ = delta(bench, ctx, "stiction", {"Fs_over_C": 1.5, "v_s_mm_s": 0.05, "delta": 2.0}, [i])
    f = on[i]["F_fric_N"]
    v = on[i]["v_mm_s"]
    C = ctx.base.C_N
    assert np.all(np.abs(f[np.abs(v) > 0.09]) < C * (1 + 0.5 * np.exp(-(0.09 / 0.05) ** 2)) + 1e-6)
    j = bench.find(ctx, 2.0, 50.0, 12.0)
    base, on, _ = delta(bench, ctx, "stiction", {"Fs_over_C": 1.5, "v_s_mm_s": 0.05, "delta": 2.0}, [j])
    cruise = np.abs(on[j]["v_mm_s"]) > 11.9
    np.testing.assert_allclose(np.abs(on[j]["F_fric_N"][cruise]), C, rtol=1e-6)


def test_pressure_friction_grows_with_chamber_pressure(bench, ctx):
    i = bench.find(ctx, 4.0, 80.0, 4.0)
    base, on, _ = delta(bench, ctx, "pressure_friction", {"c_p_N_per_MPa": 15.0}, [i])
    d = on[i]["f_meas_N"] - base[i]["f_meas_N"]
    np.testing.assert_allclose(d, 15.0 * on[i]["P2_MPa"] * np.tanh(on[i]["v_mm_s"] / 0.01), atol=1e-9)


def test_leakage_lowers_the_charge_over_the_campaign(bench, ctx):
    last = len(ctx.plans) - 1
    base, on, _ = delta(bench, ctx, "leakage", {"tau_dome_h": 100.0, "tau_seal_h": 50.0}, [last])
    r = on[last]["F_gas_N"][10:-10] / base[last]["F_gas_N"][10:-10]
    assert np.all(r < 1.0) and np.all(r > np.exp(-(ctx.plans[last].t_start_s + 900) / 3600 / 50))
