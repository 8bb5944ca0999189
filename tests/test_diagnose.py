"""Tests of the diagnosis: catalogue, selection honesty, report contract, CLI, shared campaigns."""

from __future__ import annotations

import json

import numpy as np
import pytest
from conftest import SHARED_RECORDINGS, make_app
from typer.testing import CliRunner

from vvea_design.cli.identify import register
from vvea_design.identification.diagnose import DiagnoseSettings, diagnose, residual_map, write_diagnosis
from vvea_design.identification.effects import CATALOGUE, EFFECT_IDS
from vvea_design.identification.recordings import read_recordings, recordings_from_frame
from vvea_design.identification.testbench import BenchmarkCase, case_spec, run_case, simulate, small_spec, summarise_benchmark

SHARED = SHARED_RECORDINGS
SPEC_IDS = {"gas_nonlinearity", "thermal", "quadratic_damping", "relief_valve", "stiction", "pressure_friction", "leakage"}
CONTRACT = {"baseline", "heldout_rmse_N", "effects", "unexplained_structure"}


def test_catalogue_covers_the_spec_and_is_signed():
    assert SPEC_IDS <= set(EFFECT_IDS)
    for e in CATALOGUE.values():
        assert e.physics and e.equation
        for p in e.params or ():
            assert p.lower >= 0.0, f"{e.id}.{p.name} must carry its physical sign"


# -- a small benchmark: every effect at a clear SNR, and null campaigns --------------------------
SMALL_CASES = [BenchmarkCase("single", (eid,), (5.0,), 1000 + k, "small") for k, eid in enumerate(EFFECT_IDS)]
SMALL_CASES[EFFECT_IDS.index("relief_valve")] = BenchmarkCase("single", ("relief_valve",), (4.0,), 123, "small")
NULL_CASES = [BenchmarkCase("null", (), (), 2000 + k, "small") for k in range(3)]


@pytest.fixture(scope="module")
def small_bench():
    return [run_case(c) for c in SMALL_CASES + NULL_CASES]


def test_small_benchmark_detects_each_effect(small_bench):
    for r in small_bench[: len(SMALL_CASES)]:
        (eid,) = r["effects"]
        assert r["snr"][eid] == pytest.approx(5.0 if eid != "relief_valve" else 4.0, rel=0.05)
        assert r["detected"][eid], f"{eid} not detected: accepted {r['accepted']}"
        assert not r["false_positives"], f"{eid}: spurious {r['false_positives']}"
        # held-out error closes at least half of the gap to the true model
        gap = r["heldout_baseline_N"] - r["heldout_true_N"]
        if gap > 0.2:
            assert r["heldout_baseline_N"] - r["heldout_final_N"] >= 0.5 * gap, eid


def test_small_benchmark_null_campaigns_accept_nothing(small_bench):
    nulls = small_bench[len(SMALL_CASES) :]
    assert all(r["accepted"] == [] for r in nulls)
    assert all(r["heldout_final_N"] == r["heldout_baseline_N"] for r in nulls)
    s = summarise_benchmark(small_bench)
    assert s["null"]["false_positive_rate"] == 0.0
    assert set(s["per_effect"]) == set(EFFECT_IDS)


def test_case_spec_is_deterministic():
    c = BenchmarkCase("single", ("stiction",), (3.0,), 77, "small")
    a, b = case_spec(c), case_spec(c)
    assert a == b
    f1, f2 = simulate(a).frame, simulate(b).frame
    np.testing.assert_array_equal(f1["force_N"], f2["force_N"])


def test_fitted_effect_parameters_match_truth():
    """A linear-in-amplitude effect is recovered in physical units with a sensible uncertainty."""
    c = BenchmarkCase("single", ("pressure_friction",), (6.0,), 31, "small")
    spec = case_spec(c)
    rec = recordings_from_frame(simulate(spec).frame, "pf")
    d = diagnose(rec, DiagnoseSettings(learner=False))
    eff = next(e for e in d.report["effects"] if e["id"] == "pressure_friction")
    assert eff["accepted"]
    cp = eff["parameters"]["c_p"]
    true = spec.effects[0].params["c_p_N_per_MPa"]
    assert abs(cp["value"] - true) < 5 * cp["std_error"] + 0.05 * true
    assert cp["unit"] == "N/MPa"


# -- honesty: structure outside the catalogue is flagged, not named --------------------------------
@pytest.fixture(scope="module")
def ripple_diag():
    frame = simulate(small_spec(seed=21)).frame.copy()
    frame["force_N"] += 25 * np.sin(2 * np.pi * frame["displacement_mm"] / 6.0)  # a 6 mm ripple: no catalogue term
    return diagnose(recordings_from_frame(frame, "ripple"), DiagnoseSettings())


def test_unexplained_structure_is_flagged_and_located(ripple_diag):
    r = ripple_diag.report
    assert r["unexplained_structure"] is True
    assert [e["id"] for e in r["effects"] if e["accepted"]] == []
    assert r["unexplained_where"][0]["feature"] == "displacement"


def test_report_contract_and_files(tmp_path, ripple_diag):
    r = ripple_diag.report
    assert CONTRACT <= set(r)
    assert {e["id"] for e in r["effects"]} == set(EFFECT_IDS)  # every candidate listed
    for e in r["effects"]:
        assert {"id", "accepted", "explanation", "parameters", "evidence"} <= set(e)
    assert set(r["heldout_rmse_N"]) >= {"baseline", "final"}
    assert r["rows_left_out"] == 3 * r["n_experiments"]
    files = write_diagnosis(ripple_diag, tmp_path)
    for f in files:
        assert (tmp_path / f).stat().st_size > 0
    json.loads((tmp_path / "report.json").read_text())
    assert "Structure remains" in (tmp_path / "summary.md").read_text()


def test_residual_map_bins_account_for_every_sample(ripple_diag):
    D = ripple_diag.data
    res = D.y - ripple_diag.baseline.predict(D)
    m = residual_map(D, res, 1.0)
    assert set(m) == {"displacement", "speed", "direction", "time_since_reversal", "p2", "valve", "campaign_time"}
    for feat in m.values():
        assert sum(b["n"] for b in feat["bins"]) == D.n


# -- the shared campaigns ----------------------------------------------------------------------------
@pytest.mark.parametrize(
    "name, expected",
    [("campaign_a", set()), ("campaign_b", {"quadratic_damping"}), ("campaign_c", {"gas_nonlinearity", "stiction"})],
)
def test_shared_campaigns_accept_exactly_the_readme_effects(name, expected):
    rec = read_recordings(SHARED / f"{name}.csv")
    d = diagnose(rec, DiagnoseSettings(learner=False))
    r = d.report
    assert {e["id"] for e in r["effects"] if e["accepted"]} == expected
    h = r["heldout_rmse_N"]
    if expected:
        assert h["final"] < 0.5 * h["baseline"]
    else:
        assert h["final"] == h["baseline"]


# -- CLI ---------------------------------------------------------------------------------------------
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
    assert (tmp_path / "d" / "residual_maps.png").exists() and (tmp_path / "d" / "worst_experiments.png").exists()


def test_cli_diagnose_bad_file(tmp_path):
    f = tmp_path / "bad.csv"
    f.write_text("experiment,time_s,displacement_mm,force_N,p2_MPa,valve_deg\nA,0,0,0,2,x\n")
    res = CliRunner().invoke(_app(), ["diagnose", str(f), "--out", str(tmp_path / "d")])
    assert res.exit_code == 2
    assert "valve_deg" in res.output and "non-numeric" in res.output
