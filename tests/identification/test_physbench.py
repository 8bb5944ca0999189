"""Physics checks of the independent bench simulator (independent of the diagnosis)."""

import ast
import json
import subprocess
import sys
from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest

from vvea_benches import physbench as pb
from vvea_benches import physics
from vvea_design.identification.recordings import read_recordings
from vvea_design.spring.gas_spring import force_N as eq5_force_N
from vvea_design.spring.paper import PAPER_FIG5

SMALL = pb.CampaignGrid(pressures_MPa=(2.0,), valves_deg=(100.0,), speeds_mm_s=(1.0,), samples=81, substeps=20)


def _quiet(effects, **kw):
    """A bench with nothing but the given effects, no friction/damping/noise unless asked."""
    base = dict(effects=tuple(effects), grid=SMALL, coulomb_N=0.0, L_N_s_per_mm={g: 0.0 for g in pb.TABLE3_L},
                noise_N=0.0, displacement_noise_mm=0.0)
    base.update(kw)
    return pb.BenchParameters(**base)


def test_does_not_import_the_catalogue():
    imported = set()
    for node in (n for f in (pb.__file__, physics.__file__) for n in ast.walk(ast.parse(Path(f).read_text()))):
        if isinstance(node, ast.ImportFrom):
            imported.add(node.module or "")
            imported.update(a.name for a in node.names)
        elif isinstance(node, ast.Import):
            imported.update(a.name for a in node.names)
    for bad in ("effects", "identify", "diagnose", "testbench"):
        assert not any(m == bad or m.endswith("." + bad) for m in imported), bad
    assert not any(m.startswith("vvea_design.identification") or m in ("identification", "testbench") for m in imported)
    code = (
        "import sys; import vvea_benches.physbench as m; m.simulate_campaign(m.random_parameters(('thermal',),"
        " seed=1, grid=m.CampaignGrid(pressures_MPa=(1.0,), valves_deg=(50.0,), speeds_mm_s=(4.0,), samples=21)));"
        "bad=[k for k in sys.modules if (k.split('.')[-1] in ('effects','identify','diagnose','testbench') and 'vvea' in k)"
        " or k.startswith('vvea_design.identification')];"
        "print(bad); sys.exit(1 if bad else 0)"
    )
    r = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True)
    assert r.returncode == 0, r.stdout + r.stderr


def test_isothermal_limit_is_eq5():
    c = pb.simulate_campaign(_quiet(["gas_nonlinearity"]))
    fr = c.frame
    x = c.truth.displacement_true_mm
    assert np.max(np.abs(fr["displacement_mm"].to_numpy() - x)) < 1e-4  # recorded to 0.1 µm
    g = PAPER_FIG5
    F = eq5_force_N(x, g.A1_mm2, g.A2_mm2, g.V1_mm3, g.V2_mm3, g.A2_mm2 / g.A1_mm2 * 2.0, 2.0)
    assert np.max(np.abs(c.truth.force_true_N - F)) < 1e-6 * np.max(np.abs(F)) + 1e-9
    # and with the curvature switched off, it is the straight line through the origin
    lin = pb.simulate_campaign(_quiet([])).truth.force_true_N
    s = (F * x).sum() / (x * x).sum()
    xr = np.linspace(0, 40, 201)
    Fr = eq5_force_N(xr, g.A1_mm2, g.A2_mm2, g.V1_mm3, g.V2_mm3, g.A2_mm2 / g.A1_mm2 * 2.0, 2.0)
    s = (Fr * xr).sum() / (xr * xr).sum()
    np.testing.assert_allclose(lin, s * x, atol=1e-6)


def test_adiabatic_limit_gives_n_1p4():
    p = _quiet(["gas_nonlinearity", "thermal"], thermal_tau_s=np.inf, thermal_tau1_s=np.inf)
    c = pb.simulate_campaign(p)
    x = c.truth.displacement_true_mm
    g = PAPER_FIG5
    F14 = eq5_force_N(x, g.A1_mm2, g.A2_mm2, g.V1_mm3, g.V2_mm3, g.A2_mm2 / g.A1_mm2 * 2.0, 2.0, n=1.4)
    F10 = eq5_force_N(x, g.A1_mm2, g.A2_mm2, g.V1_mm3, g.V2_mm3, g.A2_mm2 / g.A1_mm2 * 2.0, 2.0, n=1.0)
    err = np.max(np.abs(c.truth.force_true_N - F14))
    assert err < 2e-3 * np.max(np.abs(F14))
    assert np.max(np.abs(F14 - F10)) > 50 * err  # the test separates the two laws
    # stiffness at the start is n times the isothermal one (both chambers at their charge)
    k_sim = np.polyfit(x[1:6], c.truth.force_true_N[1:6], 1)[0]
    k_iso = np.polyfit(x[1:6], F10[1:6], 1)[0]
    assert k_sim / k_iso == pytest.approx(1.4, rel=0.02)


def test_speed_dependent_stiffness_and_hysteresis():
    grid = replace(SMALL, speeds_mm_s=(0.1, 12.0), shuffle=False)
    c = pb.simulate_campaign(_quiet(["gas_nonlinearity", "thermal"], grid=grid, thermal_tau_s=3.0, thermal_tau1_s=3.0))
    fr = c.frame.assign(f=c.truth.force_true_N)
    areas = {}
    for e, d in fr.groupby("experiment"):
        x, f = d["displacement_mm"].to_numpy(), d["f"].to_numpy()
        areas[d["speed_mm_s"].iloc[0]] = np.trapezoid(f, x)  # loop area: energy dissipated (N mm)
    assert 0 < areas[0.1] and areas[12.0] > 10 * areas[0.1]  # work dissipated over the loop grows with speed
    assert areas[12.0] > 1000.0


def test_energy_balance_closes():
    t = np.linspace(0, 20, 4001)[None, :]
    x, v, _ = pb.motion_profile(t[0], 4.0, 40.0, 40.0)
    A, V0, tau, P0 = 707.0, 7.34e4, 2.0, 2.0
    V = (V0 - A * x)[None, :]
    dV = (-A * v)[None, :]
    th, mu = pb.chamber_states(t, V, dV, tau)
    P = P0 * th * V0 / V  # MPa; P V in N mm = mJ
    mcvTw = P0 * V0 / 0.4  # m cv T_w = P0 V0 / (κ - 1)
    U = mcvTw * th
    Q = np.concatenate([[0.0], np.cumsum(0.5 * np.diff(t[0]) * (mcvTw * (1 - th[0, 1:]) / tau + mcvTw * (1 - th[0, :-1]) / tau))])
    W = np.concatenate([[0.0], np.cumsum(0.5 * (P[0, 1:] + P[0, :-1]) * np.diff(V[0]))])
    resid = (U[0] - U[0, 0]) - (Q - W)
    assert np.max(np.abs(resid)) < 2e-3 * np.max(np.abs(W))
    assert np.max(np.abs(W)) > 1e4  # a real amount of work (10 J)


def test_integrator_matches_solve_ivp():
    from scipy.integrate import solve_ivp

    t = np.linspace(0, 10.2, 6001)
    x, v, _ = pb.motion_profile(t, 8.0, 40.0, 40.0)
    A, V0, tau = 2561.0, 1.22e5, 0.8
    th, _ = pb.chamber_states(t[None], (V0 + A * x)[None], (A * v)[None], tau)

    def rhs(tt, y):
        xx, vv, _ = pb.motion_profile(tt, 8.0, 40.0, 40.0)
        VV = V0 + A * xx
        return [(1 - y[0]) / tau - 0.4 * y[0] * A * vv / VV]

    ref = solve_ivp(rhs, (0, 10.2), [1.0], method="Radau", t_eval=t, rtol=1e-9, atol=1e-11, max_step=0.01)
    assert np.max(np.abs(th[0] - ref.y[0])) < 1e-4


def test_orifice_laminar_and_turbulent_limits():
    A, D, Re_c = 0.2e-6, 0.5e-3, 5.0
    dp = np.logspace(-7, 1, 200)
    Q = pb.throttle_flow_mm3_s(dp, A, D, Re_c)
    np.testing.assert_allclose(pb.throttle_dp_MPa(Q, A, D, Re_c), dp, rtol=1e-8)
    # Cd of the computed flow is the regime law at the flow's Reynolds number
    u = Q * 1e-9 / A
    Re = u * D / 3.0e-5
    cd = Q * 1e-9 / (A * np.sqrt(2 * dp * 1e6 / 870.0))
    np.testing.assert_allclose(cd, pb.discharge_coefficient(Re, Re_c), rtol=1e-6)
    lam, turb = Re < 0.01 * Re_c, Re > 100 * Re_c
    assert lam.sum() > 5 and turb.sum() > 5
    assert np.ptp(Q[lam] / dp[lam]) < 0.02 * np.mean(Q[lam] / dp[lam])  # Q ∝ Δp
    r = Q[turb] / np.sqrt(dp[turb])
    assert np.ptp(r) < 0.12 * np.mean(r)  # Q ∝ sqrt(Δp)
    assert cd[turb].min() > 0.99 * 0.7 * np.sqrt(100 / 101)


def test_lugre_breakaway_presliding_and_coulomb():
    t = np.linspace(0, 400, 40001)[None, :]
    v = np.full_like(t, 0.02)  # mm/s, far below the Stribeck speed
    F, z = pb.lugre_friction(t, v, Fc=100.0, Fs=180.0, vs=1.0, delta=2.0, sigma0=200.0)
    assert F[0, -1] == pytest.approx(180.0 * 1.0, rel=0.01)  # sticks up to the breakaway force g(v) ≈ F_s
    x = 0.02 * t[0]
    k = np.polyfit(x[:3], F[0, :3], 1)[0]  # first 4 µm: the bristle stiffness
    assert k == pytest.approx(200.0, rel=0.03)
    t2 = np.linspace(0, 5, 20001)[None, :]
    F2, _ = pb.lugre_friction(t2, np.full_like(t2, 10.0), Fc=100.0, Fs=180.0, vs=1.0, delta=2.0, sigma0=200.0)
    assert F2[0, -1] == pytest.approx(100.0, rel=1e-3)  # Coulomb level at speed
    assert F2[0].max() < 181.0


def test_relief_valve_caps_the_pressure_drop():
    A2 = PAPER_FIG5.A2_mm2
    b, a = pb.throttle_coefficients(np.array([1024.7]), np.array([8.0]), A2)
    v = np.linspace(0, 12, 61)
    relief = dict(cracking_MPa=2500.0 / A2, spring_N_per_mm=8.0)
    dp0 = pb.damping_dp_MPa(A2 * v, b, a, None)
    dp = pb.damping_dp_MPa(A2 * v, b, a, relief)
    assert dp0.max() * A2 > 10000.0
    assert dp.max() * A2 < 2500.0 * 1.1
    assert np.all(np.diff(dp) >= -1e-12)
    m = dp0 < relief["cracking_MPa"]
    np.testing.assert_allclose(dp[m], dp0[m])
    # flows balance where the valve is open
    q_t = (-b + np.sqrt(b * b + 4 * a * dp)) / (2 * a)
    np.testing.assert_allclose(q_t + pb.relief_flow_mm3_s(dp, **relief), A2 * v, rtol=1e-6, atol=1e-6)


def test_leak_lowers_p2_monotonically():
    grid = pb.CampaignGrid(pressures_MPa=(1.0, 4.0), valves_deg=(50.0, 110.0), speeds_mm_s=(0.1, 12.0), samples=41)
    p = pb.random_parameters(("leakage",), seed=4, grid=grid)
    c = pb.simulate_campaign(p)
    ratio = c.truth.p2_start_MPa / c.truth.run_order["p2_MPa"].to_numpy()
    assert ratio[0] == 1.0
    assert np.all(np.diff(ratio) < 0)
    hours = (c.truth.campaign_start_s[-1]) / 3600
    assert 1 - ratio[-1] == pytest.approx(p.leak_rate_per_h * hours, rel=0.5)


def test_deterministic_with_a_seed(tmp_path):
    grid = pb.CampaignGrid(pressures_MPa=(1.0, 4.0), valves_deg=(50.0, 120.0), speeds_mm_s=(1.0, 12.0), samples=41)
    a = pb.simulate_campaign(pb.random_parameters(pb.EFFECTS, seed=7, grid=grid))
    b = pb.simulate_campaign(pb.random_parameters(pb.EFFECTS, seed=7, grid=grid))
    c = pb.simulate_campaign(pb.random_parameters(pb.EFFECTS, seed=8, grid=grid))
    assert a.frame.equals(b.frame)
    assert not a.frame["force_N"].equals(c.frame["force_N"])
    path = pb.write_campaign(a, tmp_path / "camp.csv")
    rec = read_recordings(path)
    assert rec.n_experiments == 8 and rec.rows_read == 8 * 41
    truth = json.loads((tmp_path / "camp.truth.json").read_text())
    assert set(truth["effects"]) == set(pb.EFFECTS)
    assert truth["noise_N"] == a.truth.noise_N


def test_null_bench_is_eq14_plus_noise():
    """With every effect off the unit obeys f = g p2 x + L ẋ + C sign(ẋ) (up to the ramps' transients)."""
    grid = pb.CampaignGrid(pressures_MPa=(1.0, 4.0), valves_deg=(50.0, 108.0), speeds_mm_s=(1.0, 8.0), samples=61)
    p = pb.random_parameters((), seed=2, grid=grid)
    c = pb.simulate_campaign(p)
    fr = c.frame
    x = fr["displacement_mm"].to_numpy()
    t = fr["time_s"].to_numpy()
    _, v, _ = pb.motion_profile(t, 1.0, 40.0, 40.0)
    vel = np.concatenate([pb.motion_profile(d["time_s"].to_numpy(), d["speed_mm_s"].iloc[0], 40.0, 40.0)[1]
                          for _, d in fr.groupby("experiment", sort=False)])
    X = np.column_stack([fr["p2_MPa"] * x, np.sign(vel)] + [vel * (fr["valve_deg"] == g) for g in grid.valves_deg])
    moving = np.abs(vel) > 0.05
    th, *_ = np.linalg.lstsq(X[moving], c.truth.force_true_N[moving], rcond=None)
    r = c.truth.force_true_N[moving] - X[moving] @ th
    assert np.sqrt(np.mean(r**2)) < 0.5
    assert th[1] == pytest.approx(p.coulomb_N, rel=0.01)
    noise = fr["force_N"].to_numpy() - c.truth.force_true_N
    assert np.std(noise) == pytest.approx(p.noise_N, rel=0.2)


def test_any_design_can_be_simulated():
    from vvea_design.spring.design import Design

    d = Design(piston_diameter_mm=30.0, outer_diameter_mm=60.0, V1_mm3=1.2e5, V2_mm3=7.3e4)
    geo = pb.unit_geometry(d)
    assert geo.travel_mm == d.fixed.travel_mm and geo.A2_mm2 == d.A2_mm2
    grid = pb.CampaignGrid(pressures_MPa=(2.0,), valves_deg=(100.0,), speeds_mm_s=(4.0,), samples=31)
    c = pb.simulate_campaign(pb.random_parameters(("gas_nonlinearity", "thermal"), seed=1, unit=d, grid=grid))
    assert c.frame["displacement_mm"].max() == pytest.approx(d.fixed.travel_mm, abs=0.02)
    with pytest.raises(TypeError, match="Design"):
        pb.unit_geometry("paper")
