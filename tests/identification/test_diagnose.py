"""Tests of the diagnosis end to end: effects recovered, discovery, typed report and its files, the final model,
small campaigns, the CLI.

The registry is tested in test_effects.py, the noise floor in test_noise.py; the small benchmark is in
test_diagnose_bench.py, the shared campaigns in test_diagnose_shared.py (their own modules so that pytest-xdist
can run them beside this one)."""

from __future__ import annotations

import json
from dataclasses import replace

import numpy as np
import pytest
from tests.helpers import REPO, SHARED_RECORDINGS, make_app
from scipy.signal import lfilter, lfilter_zi
from typer.testing import CliRunner

from vvea_benches.testbench import BenchmarkCase, case_spec, simulate, small_spec
from vvea_design.cli.identify import register
from vvea_design.identification.diagnose import DiagnoseSettings, diagnose, write_diagnosis
from vvea_design.identification.effects import EFFECT_IDS, REGISTRY
from vvea_design.identification.fit_data import FitData
from vvea_design.identification.recordings import recordings_from_frame
from vvea_design.identification.report import DiagnosisReport, load_final_model
from vvea_design.spring.design_file import spring_from_json

SHARED = SHARED_RECORDINGS

CONTRACT = {"baseline", "heldout_rmse_N", "effects", "unexplained_structure", "final_model", "noise_floor_N"}


def test_fitted_effect_parameters_match_truth():
    """A linear-in-amplitude effect is recovered in physical units with a sensible uncertainty."""
    spec = case_spec(BenchmarkCase("single", ("pressure_friction",), (6.0,), 31, "small"))
    d = diagnose(recordings_from_frame(simulate(spec).frame, "pf"), DiagnoseSettings(learner=False))
    eff = next(e for e in d.report.effects if e.id == "pressure_friction")
    assert eff.accepted and eff.catalogue
    cp = next(p for p in eff.parameters if p.name == "c_p")
    true = spec.effects[0].params["c_p_N_per_MPa"]
    assert abs(cp.value - true) < 5 * cp.std_error + 0.05 * true
    assert cp.unit == "N/MPa"


# -- discovery: structure outside the catalogue is modelled and described, never named ---------------------
@pytest.fixture(scope="module")
def ripple_diag():
    frame = simulate(small_spec(seed=21)).frame.copy()
    frame["force_N"] += 25 * np.sin(2 * np.pi * frame["displacement_mm"] / 6.0)  # a 6 mm ripple: no catalogue term
    return diagnose(recordings_from_frame(frame, "ripple"), DiagnoseSettings())


def test_position_ripple_is_discovered_with_its_pitch(ripple_diag):
    r = ripple_diag.report
    assert r.accepted_catalogue_ids == ()
    (rip,) = [e for e in r.accepted if e.id == "position_ripple"]
    assert rip.catalogue is False
    pitch = next(p for p in rip.parameters if p.name == "P")
    assert pitch.value == pytest.approx(6.0, rel=0.01)
    assert "6 " in rip.explanation or "6.0" in rip.explanation
    assert "ripple" in rip.explanation
    assert r.heldout.final_N < 2.0 * r.noise_floor_N < r.heldout.baseline_N
    assert rip.heldout_rmse_removed_N > 5.0


def test_force_lag_is_discovered_with_its_time_constant():
    spec = case_spec(BenchmarkCase("null", (), (), 44, "small"))
    frame = simulate(spec).frame.copy()
    tau = 0.05
    for _, g in frame.groupby("experiment", sort=False):
        t = g["time_s"].to_numpy()
        dt = np.median(np.diff(t))
        q = np.exp(-dt / tau)
        f = g["force_true_N"].to_numpy()
        # a continuous-time first-order sensor, exact for the force linear between samples
        b = [1 - tau * (1 - q) / dt, tau * (1 - q) / dt - q]
        lag = lfilter(b, [1, -q], f, zi=lfilter_zi(b, [1, -q]) * f[0])[0]
        frame.loc[g.index, "force_N"] += lag - f
    d = diagnose(recordings_from_frame(frame, "lag"), DiagnoseSettings(learner=False))
    r = d.report
    assert r.accepted_catalogue_ids == ()
    lag = next(e for e in r.accepted if e.id == "force_lag")
    t_fit = next(p for p in lag.parameters if p.name == "tau")
    assert t_fit.value == pytest.approx(tau, rel=0.15)
    assert "sensor or amplifier" in lag.explanation


# -- typed report, contract, files, final model -------------------------------------------------------------
def test_report_contract_and_files(tmp_path, ripple_diag):
    r = ripple_diag.report
    assert isinstance(r, DiagnosisReport)
    d = r.to_dict()
    assert CONTRACT <= set(d)
    assert {e["id"] for e in d["effects"] if e["catalogue"]} == set(EFFECT_IDS)  # every catalogue candidate listed
    for e in d["effects"]:
        assert {"id", "catalogue", "accepted", "explanation", "parameters", "evidence", "equation"} <= set(e)
    assert set(d["heldout_rmse_N"]) >= {"baseline", "final"}
    assert d["rows_left_out"] == 3 * d["n_experiments"]
    assert "measurement − model" in d["residual_sign"]
    files = write_diagnosis(ripple_diag, tmp_path)
    for f in files:
        assert (tmp_path / f).stat().st_size > 0
    assert json.loads((tmp_path / "report.json").read_text())["final_model"]["effects"] == list(r.final_model.effects)
    assert "position_ripple" in (tmp_path / "summary.md").read_text()


def test_final_model_file_evaluates_new_motions(tmp_path, ripple_diag):
    write_diagnosis(ripple_diag, tmp_path)
    fm = load_final_model(tmp_path / "final_model.json")
    D = ripple_diag.data
    np.testing.assert_allclose(fm.predict(D), ripple_diag.final.predict(D), rtol=1e-9, atol=1e-6)
    # a new motion of the same unit: another campaign's kinematics
    D2 = FitData.from_recordings(recordings_from_frame(simulate(small_spec(seed=99, speeds_mm_s=(2.0,))).frame, "new"))
    f2 = fm.predict(D2)
    assert f2.shape == (D2.n,) and np.all(np.isfinite(f2))


# -- small campaigns degrade gracefully ---------------------------------------------------------------------
@pytest.mark.parametrize("n_exp", [1, 3, 8])
def test_small_campaigns_do_not_crash(tmp_path, n_exp):
    frame = simulate(small_spec(seed=8)).frame
    keep = frame["experiment"].drop_duplicates().iloc[:n_exp]
    rec = recordings_from_frame(frame[frame["experiment"].isin(keep)].reset_index(drop=True), "small")
    d = diagnose(rec, DiagnoseSettings())
    r = d.report
    assert r.n_experiments == n_exp
    if n_exp < 6:
        assert any("no effect can be tested" in n for n in r.notes)
        assert r.accepted == ()
    if not r.heldout.assessable:
        assert any("held-out error cannot be assessed" in n for n in r.notes)
        assert r.to_dict()["heldout_rmse_N"]["final"] is None
    write_diagnosis(d, tmp_path)
    assert "Note" in (tmp_path / "summary.md").read_text()


# -- CLI ----------------------------------------------------------------------------------------------------
def _app():
    return make_app(register)


def test_cli_diagnose(tmp_path):
    spec = case_spec(BenchmarkCase("single", ("stiction",), (5.0,), 5, "small"))
    f = tmp_path / "rec.parquet"
    simulate(spec).frame.drop(columns=["force_true_N"]).to_parquet(f)
    res = CliRunner().invoke(_app(), ["diagnose", str(f), "--out", str(tmp_path / "d"), "--no-learner"])
    assert res.exit_code == 0, res.output
    rep = json.loads((tmp_path / "d" / "report.json").read_text())
    assert [e["id"] for e in rep["effects"] if e["accepted"]] == ["stiction"]
    assert "stiction" in res.output and "Held-out RMS error" in res.output
    assert "paper's Fig. 5 unit" in res.output  # says which reference it assumes
    for png in ("residual_maps.png", "worst_experiments.png", "heldout_per_effect.png"):
        assert (tmp_path / "d" / png).exists()


def test_cli_diagnose_uses_the_design_geometry(tmp_path):
    """`vvea diagnose --design d.json`: d's areas, V1, V2 and travel shape the gas terms."""
    design = REPO / "cad" / "design.json"
    unit = spring_from_json(design)
    spec = replace(small_spec(seed=12), reference=unit)
    gas = REGISTRY["gas_nonlinearity"]
    truth = dict(V1_mm3=unit.V1_mm3, V2_mm3=unit.V2_mm3, amp=1.0)
    frame = simulate(spec).frame.copy()
    cols = dict(x=frame["displacement_mm"].to_numpy(), p2=frame["p2_MPa"].to_numpy())
    frame["force_N"] += gas.bench_force(truth, cols, spec)
    f = tmp_path / "rec.csv"
    frame.drop(columns=["force_true_N"]).to_csv(f, index=False)
    res = CliRunner().invoke(_app(), ["diagnose", str(f), "--out", str(tmp_path / "d"), "--no-learner", "--design", str(design)])
    assert res.exit_code == 0, res.output
    assert f"V2 = {unit.V2_mm3:.4g}" in res.output
    rep = json.loads((tmp_path / "d" / "report.json").read_text())
    assert rep["final_model"]["reference"]["A2_mm2"] == pytest.approx(unit.A2_mm2)
    g = next(e for e in rep["effects"] if e["id"] == "gas_nonlinearity")
    assert g["accepted"]
    assert g["parameters"]["V2"]["value"] == pytest.approx(unit.V2_mm3, rel=0.1)
    # the bench charges chamber 1 at A2/A1 p2 (eq. 7), the design at its own p1/p2: amplitudes near 1, not exactly
    assert 0.5 < g["parameters"]["a2"]["value"] < 1.5


def test_cli_diagnose_bad_file(tmp_path):
    f = tmp_path / "bad.csv"
    f.write_text("experiment,time_s,displacement_mm,force_N,p2_MPa,valve_deg\nA,0,0,0,2,x\n")
    res = CliRunner().invoke(_app(), ["diagnose", str(f), "--out", str(tmp_path / "d")])
    assert res.exit_code == 2
    assert "valve_deg" in res.output and "non-numeric" in res.output


def test_cli_diagnose_bad_design(tmp_path):
    f = tmp_path / "d.json"
    f.write_text("{}")
    res = CliRunner().invoke(_app(), ["diagnose", str(SHARED / "campaign_a.csv"), "--out", str(tmp_path / "d"), "--design", str(f)])
    assert res.exit_code == 2
    assert "d.json" in res.output
