"""Sweep drivers: coarse grid, multi-start guarantee, Dask path, resume, failures, CLI."""

from __future__ import annotations

import dataclasses
import json

import numpy as np
import pandas as pd
import pytest
from tests.helpers import make_app
from typer.testing import CliRunner

import vvea_design.actuator.multistart as ms
import vvea_design.actuator.rest_to_rest as sa
from vvea_design.actuator.model import PAPER_SETTINGS
from vvea_design.cli.study import register
from vvea_design.actuator.ocp import Mesh
from vvea_design.actuator.multistart import RESULT_COLUMNS, CaseRow, RestToRestCase, solve_case
from vvea_design.actuator.rest_to_rest import GRIDS, Grid, RestToRestSummary, SweepRun, run_rest_to_rest
from vvea_design.actuator.safety import run_safety
from vvea_design.actuator.statistics import Table5Statistics, table5_statistics
from tests.helpers import REPO

SMALL_MESH = Mesh(16, 3)
TINY = Grid((0.3, 0.9), (0.4, 1.2))
SETTINGS = tuple(PAPER_SETTINGS.values())


def _app():
    return make_app(register)


ONE = Grid((0.4,), (0.8,))


@pytest.fixture(scope="module")
def one_case_run(tmp_path_factory):
    """One finished single-case sweep (small mesh, no figures): (folder, summary); tests work on copies."""
    out = tmp_path_factory.mktemp("one_case")
    summary = run_rest_to_rest(out, grid=ONE, mesh=SMALL_MESH, workers=1, progress=False, figures=False)
    return out, summary


def _copy_run(run, dest):
    import shutil

    shutil.copytree(run[0], dest, dirs_exist_ok=True)
    return run[1]


@pytest.fixture(scope="module")
def coarse_run(tmp_path_factory):
    """The coarse grid through the CLI on two local processes (small mesh: 16 intervals, as the other sweeps
    here; the guarantee and the 95 % rule cover the same cases as at 24, at half the solver time)."""
    out = tmp_path_factory.mktemp("coarse")
    res = CliRunner().invoke(_app(), ["study", "rest-to-rest", "--grid", "coarse", "--mesh-n", "16",
                                      "--workers", "2", "--out", str(out), "--no-progress"])
    assert res.exit_code == 0, res.output + str(res.exception)
    return out


def test_coarse_grid_files_and_columns(coarse_run):
    df = pd.read_csv(coarse_run / "results.csv")
    assert len(df) == len(GRIDS["coarse"].cases()) * len(SETTINGS)
    for col in ("setting", "A_rad", "T_s", "rmse", "valid", "status", "seconds"):
        assert col in df.columns
    assert set(df.setting) == set(PAPER_SETTINGS)
    assert df.groupby("case_id").size().eq(len(SETTINGS)).all()
    summary = json.loads((coarse_run / "summary.json").read_text())
    assert summary["n_cases"] == len(GRIDS["coarse"].cases())
    assert summary["paper_table5"]["VVEA_beats_SEA"] == pytest.approx(0.291)
    for png in ("best_map.png", "trajectory.png"):
        assert (coarse_run / png).stat().st_size > 10_000


def test_ivvea_never_worse_than_sea_on_coarse_grid(coarse_run):
    df = pd.read_csv(coarse_run / "results.csv")
    piv = df.pivot(index="case_id", columns="setting", values="rmse")
    assert piv[["iVVEA", "SEA"]].notna().all().all()
    assert (piv["iVVEA"] <= piv["SEA"]).all()
    s = json.loads((coarse_run / "summary.json").read_text())
    assert s["ivvea_vs_sea_guarantee"]["iVVEA_worse_than_SEA_cases"] == 0


def test_validity_follows_the_95_percent_rule(coarse_run):
    df = pd.read_csv(coarse_run / "results.csv")
    ok = df[df.success]
    expect = (np.minimum(ok.peak_q_up1_rad, ok.peak_q_up2_rad) >= 0.95 * ok.A_rad)
    assert (ok.valid == expect).all()


def test_every_start_is_recorded_and_the_winner_is_the_best(one_case_run):
    # solve_case's rows as the sweep wrote them (one case, 16 intervals, the default starts: a lone case has no
    # neighbour) and solve_case's rows with the issue-13 multi-start (cold and cross starts as well)
    swept = pd.read_csv(one_case_run[0] / "results.csv").to_dict("records")
    every = [r.to_dict() for r in solve_case(RestToRestCase(0.4, 0.8, SETTINGS, SMALL_MESH,
                                                            ("const-Dmin", "ramp", "cold", "cross")))]
    for rows, starts in ((swept, {"const-Dmin (adopted)", "const-Dmin", "ramp"}),
                         (every, {"const-Dmin (adopted)", "const-Dmin", "ramp", "cold"})):
        _check_starts(rows, starts)


def _check_starts(rows, starts):
    assert len(rows) == len(SETTINGS)
    for r in rows:
        objs = json.loads(r["start_objectives"])
        if r["setting"] in ("VVEA", "iVVEA"):
            assert starts <= set(objs)
            best = min(v for v in objs.values() if v is not None)
            assert r["objective"] == pytest.approx(best, rel=1e-8)
            assert objs[r["start"]] == pytest.approx(best, rel=1e-5)


def test_the_summary_is_typed_and_is_what_summary_json_holds(one_case_run):
    out, summary = one_case_run
    assert isinstance(summary, RestToRestSummary) and isinstance(summary.statistics, Table5Statistics)
    assert isinstance(summary.run, SweepRun) and summary.out_dir == out
    assert json.loads((out / "summary.json").read_text()) == json.loads(json.dumps(summary.to_dict()))
    assert list(summary.to_dict())[-1] == "run" and summary.to_dict()["run"]["mesh"]["n_intervals"] == 16
    with pytest.raises(dataclasses.FrozenInstanceError):
        summary.run = None
    rows = pd.read_csv(out / "results.csv")
    assert list(rows.columns) == RESULT_COLUMNS == [f.name for f in dataclasses.fields(CaseRow)]


def test_dask_cluster_gives_the_local_numbers(tmp_path):
    distributed = pytest.importorskip("distributed")
    grid = Grid((0.5,), (0.6, 1.0))
    local = run_rest_to_rest(tmp_path / "local", grid=grid, mesh=SMALL_MESH, workers=1, progress=False,
                             figures=False)
    # one worker process: the cases still go through the scheduler, pickling and a separate process
    with distributed.LocalCluster(n_workers=1, processes=True, threads_per_worker=1,
                                  dashboard_address=None) as cluster:
        dask = run_rest_to_rest(tmp_path / "dask", grid=grid, mesh=SMALL_MESH, scheduler=cluster.scheduler_address,
                                progress=False, figures=False)
    a = pd.read_csv(tmp_path / "local" / "results.csv").sort_values(["case_id", "setting"]).reset_index(drop=True)
    b = pd.read_csv(tmp_path / "dask" / "results.csv").sort_values(["case_id", "setting"]).reset_index(drop=True)
    for col in ("rmse", "objective"):
        np.testing.assert_allclose(a[col].to_numpy(), b[col].to_numpy(), rtol=1e-9)
    assert (a.valid == b.valid).all() and (a.status == b.status).all()
    assert local.statistics.pairs == dask.statistics.pairs


def test_resume_after_an_interrupted_sweep(tmp_path, monkeypatch):
    # the sweep's work item is a chain (one amplitude, its periods in order, each from its neighbour's optima):
    # a finished chain is saved, an interrupted one solved again on resume
    grid = Grid((0.4, 0.6), (0.4, 0.8))
    calls = {"n": 0}
    real = sa.solve_chain

    def flaky(cases, keep=None):
        calls["n"] += 1
        if calls["n"] == 2:
            raise KeyboardInterrupt  # the user hits Ctrl-C during the second chain
        return real(cases, keep)

    monkeypatch.setattr(sa, "solve_chain", flaky)
    with pytest.raises(KeyboardInterrupt):
        run_rest_to_rest(tmp_path, grid=grid, mesh=SMALL_MESH, workers=1, progress=False, figures=False)
    first = pd.read_csv(tmp_path / "results.csv")
    assert first.case_id.nunique() == 2 and len(first) == 2 * len(SETTINGS) and set(first.A_rad) == {0.4}
    # a torn half-written line, as after a kill -9, is dropped on resume
    with (tmp_path / "results.csv").open("a") as fh:
        fh.write("A0.6_T0.4,VVEA,0.6,0.4,0.01")
    monkeypatch.setattr(sa, "solve_chain", real)
    calls["n"] = 0
    run_rest_to_rest(tmp_path, grid=grid, mesh=SMALL_MESH, workers=1, progress=False, figures=False)
    df = pd.read_csv(tmp_path / "results.csv")
    assert df.case_id.nunique() == 4 and len(df) == 4 * len(SETTINGS)
    kept = df[df.case_id.isin(first.case_id)].reset_index(drop=True)
    pd.testing.assert_frame_equal(kept[RESULT_COLUMNS], first[RESULT_COLUMNS])  # not recomputed


def test_resume_refuses_a_different_sweep(tmp_path, one_case_run):
    _copy_run(one_case_run, tmp_path)  # the finished sweep of ONE on SMALL_MESH
    with pytest.raises(ValueError, match="different sweep"):
        run_rest_to_rest(tmp_path, grid=ONE, mesh=Mesh(20, 3), workers=1, progress=False, figures=False)


def test_solver_failure_is_recorded_not_counted(tmp_path):
    grid = Grid((0.5,), (0.8,))
    summary = run_rest_to_rest(tmp_path, grid=grid, mesh=SMALL_MESH, workers=1, progress=False, figures=False,
                               ipopt_options={"ipopt.max_iter": 2})
    df = pd.read_csv(tmp_path / "results.csv")
    assert len(df) == len(SETTINGS)
    assert (~df.success).all() and df.rmse.isna().all() and (~df.valid).all()
    assert df.status.str.contains("Maximum_Iterations").all()
    assert summary.statistics.solver_failures["count"] == len(SETTINGS)
    assert summary.statistics.pairs["VVEA_vs_SEA_all"].n_cases == 0


def test_unexpected_error_becomes_rows():
    bad = RestToRestCase(0.5, 0.8, SETTINGS, Mesh(18, 3))  # not a multiple of 4
    rows = solve_case(bad)
    assert len(rows) == len(SETTINGS)
    assert all(r.status.startswith("error: ValueError") and not r.success for r in rows)


def test_table5_statistics_on_constructed_data():
    rows = []
    rm = {"c1": dict(VVEA=1.0, iVVEA=0.8, SEA=0.9, LWR=2.0), "c2": dict(VVEA=0.5, iVVEA=0.5, SEA=1.0, LWR=0.4)}
    for cid, d in rm.items():
        for s, v in d.items():
            a = PAPER_SETTINGS[s]
            rows.append(dict(case_id=cid, setting=s, A_rad=1.0, T_s=1.0, rmse=v, valid=True, status="ok",
                             seconds=0.1, success=True, start="x", D_min_Nms_per_rad=a.D_min_Nms_per_rad,
                             D_max_Nms_per_rad=a.D_max_Nms_per_rad))
    st = table5_statistics(pd.DataFrame(rows))
    p = st.pairs
    assert p["VVEA_vs_SEA_all"].fraction_X_beats_Y == 0.5
    assert p["VVEA_vs_LWR_all"].fraction_X_beats_Y == 0.5
    assert p["iVVEA_vs_SEA_all"].fraction_X_beats_Y == 1.0
    assert p["VVEA_vs_SEA_all"].meanrmse_Y_over_X == pytest.approx(1.9 / 1.5)
    assert st.ivvea_vs_sea_guarantee["iVVEA_worse_than_SEA_cases"] == 0
    assert st.pair("VVEA", "SEA", "all") is p["VVEA_vs_SEA_all"] and st.pair("SEA", "VVEA") is None
    d = st.to_dict()  # the JSON of summary.json: plain dicts, the pairs included
    assert d["pairs"]["VVEA_vs_SEA_all"]["fraction_X_beats_Y"] == 0.5 and list(d)[:3] == [
        "outperform_rtol", "n_cases", "n_cases_any_valid"]


def test_cli_bad_grid_is_a_clear_error(tmp_path):
    res = CliRunner().invoke(_app(), ["study", "rest-to-rest", "--grid", "huge", "--out", str(tmp_path)])
    assert res.exit_code != 0
    assert "--grid" in res.output


def test_safety_study_cli(tmp_path):
    # 30 intervals (graded): the variable-damping and fixed-D steps keep every asserted property
    res = CliRunner().invoke(_app(), ["study", "safety", "--out", str(tmp_path), "--mesh-n", "30"])
    assert res.exit_code == 0, res.output + str(res.exception)
    s = json.loads((tmp_path / "safety.json").read_text())
    cases = s["cases"]
    var = cases[s["variable_case"]]
    f31, f200 = cases["fixed D 31"], cases["fixed D 200"]
    assert f31["mean_D_Nms_per_rad"] == pytest.approx(31.0) and f200["mean_D_Nms_per_rad"] == pytest.approx(200.0)
    assert 12.1 - 1e-6 <= var["mean_D_Nms_per_rad"] <= 200.0
    # the optimiser may always fall back to the fixed-D trajectories' shape, so variable damping
    # is never worse than fixed D = 31 in its own cost with the same reference
    assert all(c["success"] for c in cases.values())
    assert f200["t95_s"] < f31["t95_s"]
    assert (tmp_path / "safety.png").stat().st_size > 10_000
    traj = pd.read_csv(tmp_path / "safety_trajectories.csv")
    assert set(traj["case"]) == set(cases)


def test_safety_bad_input(tmp_path):
    with pytest.raises(ValueError, match="M_kgm2"):
        run_safety(tmp_path, M_kgm2=-1.0, figures=False)


@pytest.mark.slow
def test_paper_grid_guarantee(tmp_path):
    """The full paper grid (600 OCPs): no failures, iVVEA <= SEA on every case."""
    summary = run_rest_to_rest(tmp_path, grid="paper", progress=False, figures=False).statistics
    assert summary.solver_failures["count"] == 0
    assert summary.ivvea_vs_sea_guarantee["iVVEA_worse_than_SEA_cases"] == 0
    assert summary.n_cases == 150


FINE = Mesh(32, 3)
#: two cases (both amplitudes of TINY at its longer period): every row property below holds on each
TWO_LEVEL = Grid((0.3, 0.9), (1.2,))


@pytest.fixture(scope="module")
def two_level_run(tmp_path_factory):
    out = tmp_path_factory.mktemp("two_level")
    # in this process (the pool is covered by the coarse grid and the Dask test): the solvers of both
    # meshes stay in this process's cache for the tests below
    summary = run_rest_to_rest(out, grid=TWO_LEVEL, mesh=SMALL_MESH, fine_mesh=FINE, workers=1, progress=False,
                               figures=False)
    return out, summary


def test_two_level_rows_come_from_the_fine_mesh(two_level_run):
    out, summary = two_level_run
    df = pd.read_csv(out / "results.csv")
    assert len(df) == len(TWO_LEVEL.cases()) * len(SETTINGS) and df.success.all()
    assert (df.mesh_N == FINE.n_intervals).all() and (df.coarse_mesh_N == SMALL_MESH.n_intervals).all()
    assert summary.run.fine_mesh.n_intervals == FINE.n_intervals
    # constant damping: the fine-mesh QP; variable damping: the fine QP at D_min or the polish
    assert set(df[df.setting.isin(["SEA", "LWR"])].start) == {"qp"}
    var = df[df.setting.isin(["VVEA", "iVVEA"])]
    assert var.start.str.match(r"^(polish:|const-Dmin \(adopted\))").all()
    for so in var.start_objectives:
        keys = json.loads(so)
        assert any(k.startswith("N16 ") for k in keys) and "const-Dmin (adopted)" in keys


def test_two_level_ivvea_never_worse_than_sea_on_the_fine_mesh(two_level_run):
    out, summary = two_level_run
    df = pd.read_csv(out / "results.csv")
    p = df.pivot(index="case_id", columns="setting", values="objective")
    assert (p["iVVEA"] <= p["SEA"] * (1 + 1e-12)).all()
    assert summary.statistics.ivvea_vs_sea_guarantee["iVVEA_worse_than_SEA_cases"] == 0
    # the fine SEA objective is the direct fine-mesh QP (the sweep's per-process solver of that mesh)
    s = ms._solver(FINE, ())
    row = df[(df.setting == "SEA")].iloc[0]
    r = s.solve(PAPER_SETTINGS["SEA"], float(row.A_rad), float(row.T_s), regularisation=ms.DEFAULT_REGULARISATION)
    assert r.objective == pytest.approx(float(row.objective), rel=1e-6)


def test_two_level_resume_checks_the_fine_mesh(tmp_path, two_level_run):
    out, _ = two_level_run
    meta = json.loads((out / "meta.json").read_text())
    assert meta["fine_mesh"]["n_intervals"] == FINE.n_intervals
    before = pd.read_csv(out / "results.csv")
    # the same command resumes (nothing to solve, rows unchanged)
    s2 = run_rest_to_rest(out, grid=TWO_LEVEL, mesh=SMALL_MESH, fine_mesh=FINE, workers=1, progress=False, figures=False)
    assert s2.run.cases_solved_this_run == 0
    pd.testing.assert_frame_equal(pd.read_csv(out / "results.csv")[RESULT_COLUMNS], before[RESULT_COLUMNS])
    # another fine mesh, or none, is a different sweep
    for fm in (Mesh(24, 3), None):
        with pytest.raises(ValueError, match="different sweep"):
            run_rest_to_rest(out, grid=TWO_LEVEL, mesh=SMALL_MESH, fine_mesh=fm, workers=1, progress=False,
                             figures=False)


def test_default_fine_mesh_only_with_the_default_mesh(tmp_path, one_case_run):
    s = one_case_run[1]  # run_rest_to_rest(grid=ONE, mesh=SMALL_MESH), fine_mesh left at "auto"
    assert s.run.fine_mesh is None
    assert ms.DEFAULT_FINE_MESH.n_intervals == 192 and ms.DEFAULT_MESH.n_intervals == 64
    with pytest.raises(ValueError, match="multiple of 4"):
        run_rest_to_rest(tmp_path / "x", grid=ONE, mesh=SMALL_MESH, fine_mesh=Mesh(30, 3), workers=1,
                         progress=False, figures=False)


def test_cli_fine_mesh_option(tmp_path):
    res = CliRunner().invoke(_app(), ["study", "rest-to-rest", "--grid", "0.5:0.8", "--mesh-n", "16",
                                      "--fine-mesh-n", "24", "--workers", "1", "--out", str(tmp_path),
                                      "--no-progress"])
    assert res.exit_code == 0, res.output + str(res.exception)
    df = pd.read_csv(tmp_path / "results.csv")
    assert (df.mesh_N == 24).all() and (df.coarse_mesh_N == 16).all()


# -- reliability of the sweep (issue 11 items 6, 7, 9, 11) ---------------------------------------------------
@pytest.mark.parametrize("args, option", [
    (["--mesh-n", "5"], "--mesh-n"),
    (["--mesh-n", "-4"], "--mesh-n"),
    (["--fine-mesh-n", "6"], "--fine-mesh-n"),
    (["--workers", "0"], "--workers"),
    (["--p2-mpa", "3"], "--design only"),
    (["--grid", "0.2,x:0.4"], "--grid"),
    (["--grid", "0.2,-1:0.4"], "--grid"),
])
def test_cli_bad_options_are_rejected_before_the_sweep(tmp_path, monkeypatch, args, option):
    def never(cases, keep=None):  # pragma: no cover - must not be reached
        raise AssertionError("a case was solved")

    monkeypatch.setattr(sa, "solve_chain", never)
    res = CliRunner().invoke(_app(), ["study", "rest-to-rest", "--out", str(tmp_path / "o"), "--no-progress", *args])
    assert res.exit_code == 2, res.output
    assert option in res.output
    assert not (tmp_path / "o" / "results.csv").exists()


def test_library_rejects_a_bad_mesh_before_touching_files(tmp_path):
    with pytest.raises(ValueError, match="multiple of 4"):
        run_rest_to_rest(tmp_path / "o", grid=TINY, mesh=Mesh(18, 3), workers=1, progress=False, figures=False)
    with pytest.raises(ValueError, match="starts"):
        run_rest_to_rest(tmp_path / "o", grid=TINY, mesh=SMALL_MESH, starts=("warm",), workers=1, progress=False)
    assert not (tmp_path / "o").exists()


def test_repeated_grid_values_are_solved_once_and_resume(tmp_path):
    out = tmp_path / "rep"
    args = ["study", "rest-to-rest", "--grid", "0.2,0.2:0.4,0.4000000001", "--mesh-n", "16", "--workers", "1",
            "--out", str(out), "--no-progress"]
    res = CliRunner().invoke(_app(), args)
    assert res.exit_code == 0, res.output + str(res.exception)
    assert "repeats" in res.output and "solved once" in " ".join(res.output.split())
    df = pd.read_csv(out / "results.csv")
    assert len(df) == len(SETTINGS) and df.case_id.nunique() == 1
    s = json.loads((out / "summary.json").read_text())
    assert s["n_cases"] == 1 and s["run"]["cases"] == 1
    res = CliRunner().invoke(_app(), args)  # the same command again: nothing left to solve
    assert res.exit_code == 0, res.output
    assert json.loads((out / "summary.json").read_text())["run"]["cases_solved_this_run"] == 0
    assert len(pd.read_csv(out / "results.csv")) == len(SETTINGS)


def test_grid_repeated_and_unique():
    g = Grid((0.2, 0.4, 0.2), (1.0, 1.0))
    assert g.repeated() == {"A_rad": [0.2], "T_s": [1.0]}
    assert g.unique() == Grid((0.2, 0.4), (1.0,))
    assert Grid((0.2,), (1.0,)).repeated() == {}


def test_resume_hint_names_the_cli_flag(tmp_path, one_case_run):
    _copy_run(one_case_run, tmp_path)  # the finished sweep of ONE (0.4:0.8) on 16 intervals
    res = CliRunner().invoke(_app(), ["study", "rest-to-rest", "--grid", "0.4:0.8", "--mesh-n", "20", "--workers", "1",
                                      "--out", str(tmp_path), "--no-progress"])
    assert res.exit_code == 2
    text = " ".join(res.output.replace("│", " ").split())  # rich's error box wraps at the terminal width
    assert "--restart" in text and "restart=True" not in text.replace("(restart=True in Python)", "")


def test_ctrl_c_says_how_to_resume(tmp_path, monkeypatch):
    calls = {"n": 0}
    real = sa.solve_chain

    def interrupted_second(cases, keep=None):  # the second chain (amplitude) of the sweep
        calls["n"] += 1
        if calls["n"] == 2:
            raise KeyboardInterrupt
        return real(cases, keep)

    monkeypatch.setattr(sa, "solve_chain", interrupted_second)
    res = CliRunner().invoke(_app(), ["study", "rest-to-rest", "--grid", "0.4,0.6:0.4", "--mesh-n", "16",
                                      "--workers", "1", "--out", str(tmp_path), "--no-progress"])
    assert res.exit_code == 130, res.output
    text = " ".join(res.output.split())
    assert "1 finished case(s) are saved" in text
    assert "Run the same command again to resume" in text and "--restart" in text


@pytest.mark.skipif(not __import__("sys").platform.startswith("linux"), reason="reads /proc")
def test_sigterm_to_vvea_study_ends_workers_and_says_how_to_resume(tmp_path):
    """A real `vvea study rest-to-rest` process, its two workers, SIGTERM to the parent."""
    import os
    import signal
    import subprocess
    import sys

    from tests.helpers import alive as _alive, children as _children, wait_until as _wait

    env = dict(os.environ, COLUMNS="200")
    proc = subprocess.Popen([sys.executable, "-c", "from vvea_design.cli.main import main; main()", "study", "rest-to-rest", "--grid", "paper",
                             "--workers", "2", "--out", str(tmp_path), "--no-progress"],
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, env=env,
                            cwd=str(REPO))
    try:
        assert _wait(lambda: len(_children(proc.pid)) >= 2, 120), "workers did not start"
        workers = _children(proc.pid)
        os.kill(proc.pid, signal.SIGTERM)
        _, err = proc.communicate(timeout=60)
        assert proc.returncode == 143, err.decode()
        assert _wait(lambda: not any(_alive(w) for w in workers), 15)
        assert b"Run the same command again to resume" in err
    finally:
        if proc.poll() is None:
            proc.kill()
