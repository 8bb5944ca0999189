"""Trajectory verification, regularisation, invalid-case exclusion and the design's own actuator study."""

from __future__ import annotations

import dataclasses
import json

import matplotlib
import numpy as np
import pandas as pd
import pytest
from scipy.integrate import solve_ivp
from scipy.linalg import expm

from vvea_design.actuator.design_study import (
    DesignStudy,
    design_actuator,
    run_design_study,
)
from vvea_design.actuator.figures import plot_best_map, plot_design_map, plot_trajectory
from vvea_design.actuator.model import PAPER_SETTINGS
from vvea_design.actuator.model import actuator_from_spring, dynamics
from vvea_design.actuator.multistart import DEFAULT_REGULARISATION
from vvea_design.actuator.ocp import Mesh, Regularisation, RestToRestSolver
from vvea_design.actuator.rest_to_rest import Grid
from vvea_design.actuator.statistics import table5_statistics
from vvea_design.actuator.verify import expm_stack, simulate_inputs, verify_rest_to_rest
from vvea_design.spring.gas_spring import PAPER_FIG5

MESH = Mesh(32, 3)


@pytest.fixture(scope="module")
def solver():
    return RestToRestSolver(MESH)


def test_expm_stack_matches_scipy():
    rng = np.random.default_rng(1)
    A = rng.normal(size=(50, 5, 5)) * rng.uniform(0.01, 40, size=(50, 1, 1))
    A = A - np.eye(5) * 60 * (A.max() > 0)  # keep the exponentials finite
    E = expm_stack(A)
    R = np.stack([expm(a) for a in A])
    assert np.max(np.abs(E - R) / np.abs(R).max(axis=(1, 2), keepdims=True)) < 1e-10


def test_simulation_agrees_with_an_adaptive_ode_solver():
    """Independent check of the exponential integrator with a varying damping (scipy Radau)."""
    act = PAPER_SETTINGS["VVEA"]
    edges = np.linspace(0, 0.4, 9)
    tau = np.array([100, 100, -50, -100, 0, 30, 60, -20], float)
    ud = np.array([1e4, 5e3, 0, -1e4, -5e3, 0, 2e3, 0], float)
    t, X = simulate_inputs(act, edges, tau, ud, substeps=32)
    x = np.array([0, 0, 0, 0, act.D_min_Nms_per_rad], float)
    for k in range(8):
        sol = solve_ivp(lambda _t, y: dynamics(y, [tau[k], ud[k]], act.K_Nm_per_rad, act.B_kgm2, act.M_kgm2),
                        (edges[k], edges[k + 1]), x, method="Radau", rtol=1e-10, atol=1e-12)
        x = sol.y[:, -1]
    np.testing.assert_allclose(X[-1], x, rtol=1e-4, atol=1e-6)


@pytest.mark.parametrize("name", ["SEA", "VVEA", "LWR"])
def test_optimal_trajectories_verify(solver, name):
    act = PAPER_SETTINGS[name]
    r = solver.solve(act, 0.5, 0.8, regularisation=DEFAULT_REGULARISATION)
    v = verify_rest_to_rest(r, act, 0.5, 0.8)
    assert v.verified, v.reason
    assert v.rmse_rel_error < 0.02 and v.max_bound_violation <= 1e-6
    assert json.loads(json.dumps(v.to_dict()))["verified"] is True


def test_a_trajectory_the_model_does_not_follow_is_caught(solver):
    act = PAPER_SETTINGS["SEA"]
    r = solver.solve(act, 0.5, 0.8)
    bad = dataclasses.replace(r, tau_m_Nm=0.5 * r.tau_m_Nm)  # inputs that do not produce the states
    v = verify_rest_to_rest(bad, act, 0.5, 0.8)
    assert not v.verified and "re-simulated rmse" in v.reason
    over = dataclasses.replace(r, tau_m_Nm=np.where(np.arange(len(r.tau_m_Nm)) == 3, 150.0, r.tau_m_Nm))
    v = verify_rest_to_rest(over, act, 0.5, 0.8)
    assert not v.verified and "bounds exceeded" in v.reason
    failed = dataclasses.replace(r, success=False, status="Maximum_Iterations_Exceeded")
    assert verify_rest_to_rest(failed, act, 0.5, 0.8).reason.startswith("solver: Maximum_Iterations")


def _switches(x):
    return int(np.sum(np.abs(np.diff(x)) > 0.5 * (np.max(x) - np.min(x) + 1e-12)))


def test_regularisation_removes_chatter_at_a_small_rmse_cost():
    """The VVEA optimum at A = 1 rad, T = 1.6 s chatters while the link rests; the study default does not."""
    s = RestToRestSolver(Mesh(96, 3))
    act = PAPER_SETTINGS["VVEA"]
    A, T = 1.0, 1.6
    runs = {}
    for label, reg in (("none", Regularisation()), ("default", DEFAULT_REGULARISATION)):
        sea = s.solve(PAPER_SETTINGS["SEA"], A, T, regularisation=reg)
        runs[label] = s.solve(act, A, T, w0=s.guess_from(sea, act, A, T), regularisation=reg)
        assert runs[label].success
    plain, smooth = runs["none"], runs["default"]
    assert smooth.extra["rmse_rad"] == pytest.approx(plain.extra["rmse_rad"], rel=5e-3)
    assert smooth.extra["rmse_rad"] >= plain.extra["rmse_rad"] * (1 - 1e-6)  # objective = pure tracking cost
    assert _switches(smooth.D_Nms_per_rad) < _switches(plain.D_Nms_per_rad)
    assert np.sum(np.abs(np.diff(smooth.tau_m_Nm))) < np.sum(np.abs(np.diff(plain.tau_m_Nm)))


@pytest.mark.parametrize("field", ["u_d", "tau_rate"])
def test_bad_regularisation_names_the_field(field):
    with pytest.raises(ValueError, match=field):
        Regularisation(**{field: -1.0})


def _rows(table, verified=None, valid=None):
    rows = []
    for cid, d in table.items():
        for s, v in d.items():
            a = PAPER_SETTINGS.get(s, PAPER_SETTINGS["VVEA"])
            rows.append(dict(case_id=cid, setting=s, A_rad=1.0, T_s=1.0, rmse=v, success=True, start="x",
                             valid=(valid or {}).get((cid, s), True), verified=(verified or {}).get((cid, s), True),
                             status="ok", seconds=0.1, D_min_Nms_per_rad=a.D_min_Nms_per_rad,
                             D_max_Nms_per_rad=a.D_max_Nms_per_rad))
    return pd.DataFrame(rows)


def test_invalid_and_unverified_cases_are_left_out_and_counted():
    table = {"c1": dict(VVEA=1.0, SEA=2.0), "c2": dict(VVEA=1.0, SEA=2.0), "c3": dict(VVEA=3.0, SEA=2.0)}
    st = table5_statistics(_rows(table))
    assert st.pairs["VVEA_vs_SEA_valid"].X_beats_Y == 2 and st.pairs["VVEA_vs_SEA_valid"].n_cases == 3
    # c1: VVEA's trajectory is not valid (95 % rule) -> out of the "valid" statistic only
    st = table5_statistics(_rows(table, valid={("c1", "VVEA"): False}))
    p = st.pairs["VVEA_vs_SEA_valid"]
    assert (p.n_cases, p.X_beats_Y, p.n_excluded) == (2, 1, 1)
    assert st.pairs["VVEA_vs_SEA_all"].n_cases == 3
    # c2: VVEA's trajectory does not verify -> out of every statistic, and reported
    st = table5_statistics(_rows(table, verified={("c2", "VVEA"): False}))
    assert st.pairs["VVEA_vs_SEA_all"].n_cases == 2 and st.pairs["VVEA_vs_SEA_all"].X_beats_Y == 1
    assert st.unverified["count"] == 1 and st.unverified["cases"] == ["c2 VVEA"]


def test_figures_return_figures_and_leave_the_backend_alone(solver):
    before = matplotlib.get_backend()
    best = {n: solver.solve(PAPER_SETTINGS[n], 0.5, 0.8) for n in ("SEA", "VVEA")}
    fig = plot_trajectory(best, 0.5, 0.8, highlight="VVEA")
    assert isinstance(fig, matplotlib.figure.Figure) and len(fig.axes) == 3
    df = _rows({"c1": dict(VVEA=1.0, SEA=2.0, design=0.9)})
    assert isinstance(plot_best_map(df), matplotlib.figure.Figure)
    fig = plot_design_map(df, "design", ["VVEA", "SEA"])
    assert len(fig.axes) == 3  # map, colour bar, bars
    assert matplotlib.get_backend() == before


def test_design_actuator_accepts_design_spring_or_actuator():
    act = design_actuator(PAPER_FIG5)
    assert act.name == "design" and act == actuator_from_spring(PAPER_FIG5, name="design")

    class D:
        gas_spring = PAPER_FIG5

    assert design_actuator(D()) == act
    assert design_actuator(PAPER_SETTINGS["SEA"]).name == "design"
    with pytest.raises(ValueError, match="gas_spring"):
        design_actuator(42)
    with pytest.raises(ValueError, match="mapping"):
        design_actuator(PAPER_SETTINGS["SEA"], pulley_radius_m=0.05)


#: a coarse torque-step mesh (the default has 100 intervals): the variable damping still beats D = 31
SMALL_SAFETY_MESH = Mesh(30, 3, grading=0.8)


@pytest.fixture(scope="module")
def small_study(tmp_path_factory):
    out = tmp_path_factory.mktemp("design_study")
    calls = []
    # 16 intervals: the same cases verify (one left out, SEA at T = 1 s) and compare as at 24
    study = run_design_study(PAPER_FIG5, out_dir=out, workers=1, grid=Grid((0.3,), (0.6, 1.0)),
                             mesh=Mesh(16, 3), safety_mesh=SMALL_SAFETY_MESH,
                             progress=lambda i, n, m: calls.append((i, n, m)))
    return study, out, calls


def test_design_study_typed_result_and_files(small_study):
    study, out, calls = small_study
    assert isinstance(study, DesignStudy)
    names = ["design", "VVEA", "SEA", "LWR", "design, full charge", "SEA, full charge"]
    assert [s.name for s in study.settings] == names
    assert len(study.cases) == 2 * 6 and {c.setting for c in study.cases} == set(names)
    for c in study.comparisons:  # every case counted: wins, losses, ties and the cases neither has
        assert c.n_cases == 2
        assert c.design_beats + c.design_worse + c.ties + c.neither_valid == c.n_cases
        assert c.only_other_valid <= c.design_worse and c.only_design_valid <= c.design_beats
    assert study.comparison("SEA").paper_vvea_beats == pytest.approx(0.291)
    assert study.safety_design.variable.success and study.safety_reference.variable.success
    assert study.safety_design.variable.t95_s < study.safety_design.case("fixed D 31").t95_s
    d = json.loads((out / "design_study.json").read_text())
    assert d == json.loads(json.dumps(study.to_dict()))
    assert d["timing"]["total_s"] > 0 and d["n_left_out_unverified"] == study.n_left_out
    for f in (study.files.map_png, study.files.trajectory_png, study.files.safety_png):
        assert f is not None and f.stat().st_size > 20_000
    df = pd.read_csv(study.files.results_csv)
    assert len(df) == 12
    # at 16 intervals some trajectories do not verify (the mesh is coarse); they are counted as not usable
    assert study.n_left_out == int((df.success & ~df.verified).sum())
    for c in study.comparisons:
        both = [T for T in (0.6, 1.0)
                if all(x.usable for x in study.cases if x.T_s == T and x.setting in (c.design, c.other))]
        assert c.n_both_valid == len(both)
    # progress: every work item (the torque steps, one item + 2 cases, each its own item without the neighbour start)
    # and the files, counting up to the total
    assert [c[0] for c in calls] == list(range(1, 5)) and all(c[1] == 4 for c in calls)


def test_design_study_counts_a_case_the_design_loses_by_being_invalid(small_study):
    """A case where the design is not usable and the other is, is a loss in every comparison (nothing dropped)."""
    study, _, _ = small_study
    for c in study.comparisons:
        lost = sum(1 for T in (0.6, 1.0)
                   if not next(x for x in study.cases if x.T_s == T and x.setting == c.design).usable
                   and next(x for x in study.cases if x.T_s == T and x.setting == c.other).usable)
        assert c.only_other_valid == lost
        assert c.fraction_design_beats == pytest.approx(c.design_beats / c.n_cases)


def test_design_study_rejects_unknown_reference():
    with pytest.raises(ValueError, match="references"):
        run_design_study(PAPER_FIG5, references=("SEA", "XYZ"), workers=1)


def test_design_study_report_tables_and_files_iterate(small_study):
    study, out, _ = small_study
    tables = study.report_tables()
    assert len(tables) == 4
    for title, header, rows in tables:
        assert title and rows and all(len(r) == len(header) for r in rows)
    assert [r[1] for r in tables[0][2]] == ["design vs SEA", "design vs VVEA", "design vs LWR",
                                            "design, full charge vs SEA, full charge"]
    assert [r[0] for r in tables[2][2]] == ["equal stiffness", "full charge"]
    assert {p.name for p in study.files} == {"results.csv", "design_study.json", "design_map.png",
                                            "design_trajectory.png", "design_safety.png"}


def test_pipeline_calling_convention():
    """pipeline.design_unit calls ``vvea_design.actuator.run_design_study(actuator, out_dir)``."""
    import inspect

    import vvea_design.actuator as actuator

    params = list(inspect.signature(actuator.run_design_study).parameters.values())
    assert [p.name for p in params[:2]] == ["design", "out_dir"]
    assert all(p.kind is p.KEYWORD_ONLY for p in params[2:])
