"""Direct-collocation OCPs: rest-to-rest (eq. 16) and torque step (section 6)."""

from __future__ import annotations

import numpy as np
import pytest
from scipy.integrate import solve_ivp

from vvea_design.actuator.model import PAPER_SETTINGS, dynamics
from vvea_design.actuator.ocp import (
    Mesh,
    RestToRestSolver,
    TorqueStepSolver,
    ramp_u_d_profile,
    rest_to_rest_reference,
)

MESH = Mesh(32, 3)


@pytest.fixture(scope="module")
def solver():
    return RestToRestSolver(MESH)


def _simulate(act, r, t_eval):
    """Integrate eqs 8-10 interval by interval with the solution's piecewise-constant inputs."""
    x = np.array([0, 0, 0, 0, act.D_min_Nms_per_rad], dtype=float)
    t_eval = np.asarray(t_eval)
    out = np.full((5, len(t_eval)), np.nan)
    out[:, t_eval <= 0] = x[:, None]
    for k in range(len(r.tau_m_Nm)):
        t0, t1 = r.t_s[k], r.t_s[k + 1]
        u = [r.tau_m_Nm[k], r.u_d[k]]
        sel = (t_eval > t0) & (t_eval < t1)
        sol = solve_ivp(lambda t, y: dynamics(y, u, act.K_Nm_per_rad, B=act.B_kgm2, M=act.M_kgm2),
                        (t0, t1), x, method="DOP853", rtol=1e-10, atol=1e-12, t_eval=np.append(t_eval[sel], t1))
        out[:, sel] = sol.y[:, :-1]
        x = sol.y[:, -1]
        out[:, np.abs(t_eval - t1) <= 1e-12 * max(1.0, t1)] = x[:, None]
    return out


@pytest.fixture(scope="module")
def fine_solver():
    return RestToRestSolver(Mesh(48, 3))


@pytest.mark.parametrize("name", ["SEA", "iVVEA"])
def test_solution_is_a_trajectory_of_the_model(fine_solver, name):
    """Re-simulating the optimal inputs reproduces the collocation states and the rmse.

    The mesh resolves the relative mode (ω ≈ 31 rad/s, ω h ≈ 0.5).
    """
    act = PAPER_SETTINGS[name]
    A, T = 0.5, 0.4
    r = fine_solver.solve(act, A, T)
    assert r.success, r.status
    y = _simulate(act, r, r.t_s)
    assert np.max(np.abs(y[1] - r.q_rad)) < 2e-3 * A
    assert np.max(np.abs(y[4] - r.D_Nms_per_rad)) < 1e-6 * max(1.0, act.D_max_Nms_per_rad)
    # rmse from a dense simulation vs the exact polynomial integral used as the objective
    td = np.linspace(0, 2 * T, 8001)
    yd = _simulate(act, r, td)
    e = yd[1] - rest_to_rest_reference(td, A, T)
    rmse_sim = np.sqrt(np.trapezoid(e**2, td) / (2 * T))
    assert rmse_sim == pytest.approx(r.extra["rmse_rad"], rel=0.02)


def test_constraints_hold(solver):
    act = PAPER_SETTINGS["VVEA"]
    r = solver.solve(act, 0.8, 0.6)
    assert r.success
    tol = 1e-6
    assert np.all(np.abs(r.tau_m_Nm) <= act.tau_m_max_Nm * (1 + tol))
    assert np.all(np.abs(r.u_d) <= act.u_d_max * (1 + tol))
    D = r.Z[..., 4]
    assert D.min() >= act.D_min_Nms_per_rad * (1 - tol) - tol and D.max() <= act.D_max_Nms_per_rad * (1 + tol)
    assert r.D_Nms_per_rad[0] == pytest.approx(act.D_min_Nms_per_rad)
    assert r.q_rad[0] == 0 and r.theta_rad[0] == 0 and r.dq_rad_s[0] == 0


@pytest.fixture(scope="module")
def sea_then_ivvea(solver):
    """At A = 0.6 rad, T = 0.8 s: the SEA optimum and the iVVEA optimum started from it (two tests use both)."""
    A, T = 0.6, 0.8
    sea = solver.solve(PAPER_SETTINGS["SEA"], A, T)
    return sea, solver.solve(PAPER_SETTINGS["iVVEA"], A, T, w0=solver.guess_from(sea, PAPER_SETTINGS["iVVEA"], A, T))


def test_sea_solution_is_exactly_an_ivvea_candidate(solver, sea_then_ivvea):
    """SEA ⊂ iVVEA: the SEA optimum evaluated as iVVEA has the same objective on the same mesh."""
    A, T = 0.6, 0.8
    sea, r = sea_then_ivvea
    cand = solver.evaluate_as(sea, PAPER_SETTINGS["iVVEA"], A, T)
    assert cand.objective == pytest.approx(sea.objective, rel=1e-12)
    assert r.success
    assert min(r.objective, cand.objective) <= sea.objective


def test_ramp_profile_is_feasible_and_fast():
    act = PAPER_SETTINGS["VVEA"]
    dt = np.full(20, 0.01)
    u = ramp_u_d_profile(act, dt, act.D_max_Nms_per_rad)
    assert np.all(np.abs(u) <= act.u_d_max + 1e-9)
    D = act.D_min_Nms_per_rad + np.concatenate([[0], np.cumsum(u * dt)])
    assert D.max() == pytest.approx(act.D_max_Nms_per_rad)
    assert D.min() >= act.D_min_Nms_per_rad - 1e-9


def test_fixed_u_d_is_respected(solver):
    act = PAPER_SETTINGS["iVVEA"]
    A, T = 0.4, 1.0
    prof = ramp_u_d_profile(act, solver.interval_seconds(T), act.D_max_Nms_per_rad)
    r = solver.solve(act, A, T, u_d_fixed=prof)
    assert r.success
    np.testing.assert_allclose(r.u_d, prof, rtol=1e-9, atol=1e-6)


def test_one_solver_serves_every_period(solver):
    """Time scaling: the same solver gives a longer settling for a slower-period case, no rebuild."""
    r1 = solver.solve(PAPER_SETTINGS["SEA"], 0.5, 0.4)
    r2 = solver.solve(PAPER_SETTINGS["SEA"], 0.5, 1.6)
    assert r1.t_s[-1] == pytest.approx(0.8) and r2.t_s[-1] == pytest.approx(3.2)
    assert r2.extra["rmse_rad"] < r1.extra["rmse_rad"]  # more time per step, smaller mean error


def test_bad_input_named():
    with pytest.raises(ValueError, match="multiple of 4"):
        RestToRestSolver(Mesh(18, 3))
    with pytest.raises(ValueError, match="n_intervals"):
        Mesh(2, 3)
    s = RestToRestSolver(Mesh(8, 2))
    with pytest.raises(ValueError, match="A_rad"):
        s.solve(PAPER_SETTINGS["SEA"], -1.0, 1.0)
    with pytest.raises(ValueError, match="T_s"):
        s.solve(PAPER_SETTINGS["SEA"], 0.5, 0.0)
    with pytest.raises(ValueError, match="u_d_fixed"):
        s.solve(PAPER_SETTINGS["SEA"], 0.5, 1.0, u_d_fixed=np.zeros(8))


def test_solver_failure_is_a_status_not_an_exception():
    s = RestToRestSolver(Mesh(16, 3), {"ipopt.max_iter": 1})
    r = s.solve(PAPER_SETTINGS["VVEA"], 0.5, 1.0)
    assert not r.success and "Maximum" in r.status


def test_torque_step_properties():
    # 30 intervals clustered at both ends (as the design study's small safety mesh): every property below
    # holds with margin (final torques within 0.41 and 0.11 N m of 50 N m)
    ts = TorqueStepSolver(Mesh(30, 3, grading=0.8))
    base = PAPER_SETTINGS["VVEA"].with_(M_kgm2=1e4)
    fixed = base.with_(D_min_Nms_per_rad=50.0, D_max_Nms_per_rad=50.0)
    rf = ts.solve(fixed, 50.0)
    assert rf.success
    assert rf.extra["mean_D_Nms_per_rad"] == pytest.approx(50.0)
    assert 0 < rf.extra["t95_s"] < 0.5
    rv = ts.solve(base, 50.0)
    assert rv.success
    assert rv.D_Nms_per_rad[0] == pytest.approx(base.D_min_Nms_per_rad)
    assert base.D_min_Nms_per_rad - 1e-6 <= rv.extra["mean_D_Nms_per_rad"] <= base.D_max_Nms_per_rad
    assert np.all(np.abs(rv.tau_m_Nm) <= 100 + 1e-6)
    # the link torque ends near the reference in both cases
    assert abs(rv.tau_Nm[-1] - 50.0) < 2.5 and abs(rf.tau_Nm[-1] - 50.0) < 2.5
    # higher fixed damping -> faster torque rise
    rhi = ts.solve(base.with_(D_min_Nms_per_rad=200.0, D_max_Nms_per_rad=200.0), 50.0)
    assert rhi.extra["t95_s"] < rf.extra["t95_s"]


def test_interpolation_onto_a_finer_mesh_reproduces_the_trajectory(solver, fine_solver, sea_then_ivvea):
    """A coarse (N = 32) optimum carried onto N = 48 keeps its trajectory and objective."""
    act, A, T = PAPER_SETTINGS["iVVEA"], 0.6, 0.8
    r = sea_then_ivvea[1]  # iVVEA on N = 32, started from the SEA optimum
    assert r.success
    w = fine_solver.guess_from_other_mesh(r, act, A, T)
    rf = fine_solver.evaluate_as(r, act, A, T)  # same path (resampling), as an OcpResult
    col = fine_solver.cols[True]
    pv = col.params(act, A, T)
    np.testing.assert_allclose(w, col.from_phys(rf.Z, rf.U, pv), rtol=1e-12, atol=1e-12)
    # link angle at the fine collocation points = the coarse trajectory there (within 2 % of A)
    t_old = np.concatenate([[0.0], r.t_points_s[:, 1:].ravel()])
    q_old = np.concatenate([r.Z[:1, 0, 1], r.Z[:, 1:, 1].ravel()])
    q_new = rf.Z[:, 1:, 1].ravel()
    assert np.max(np.abs(q_new - np.interp(rf.t_points_s[:, 1:].ravel(), t_old, q_old))) < 1e-12
    # D stays in range; the fine-mesh objective of the carried solution is close to the coarse one
    assert rf.Z[..., 4].min() >= act.D_min_Nms_per_rad - 1e-12
    assert rf.objective == pytest.approx(r.objective, rel=0.05)
    # one polish from it on the fine mesh converges and does not lose
    p = fine_solver.solve(act, A, T, w0=w)
    assert p.success and p.objective <= rf.objective * (1 + 1e-9)
    assert np.max(np.abs(np.interp(r.t_s, p.t_s, p.q_rad) - r.q_rad)) < 0.1 * A


def test_interpolation_to_the_same_mesh_is_the_identity(solver):
    act, A, T = PAPER_SETTINGS["VVEA"], 0.5, 1.0
    r = solver.solve(act, A, T)
    w = solver.guess_from_other_mesh(r, act, A, T)
    np.testing.assert_allclose(w, solver.guess_from(r, act, A, T), rtol=1e-9, atol=1e-9)
