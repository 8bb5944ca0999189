"""Tests of eq. 14 identification, Table 3, uncertainties and the identify command."""

from __future__ import annotations

import json

import numpy as np
import pytest
from tests.helpers import SHARED_RECORDINGS, make_app
from typer.testing import CliRunner

from vvea_benches.testbench import simulate, small_spec
from vvea_design.cli.identify import register
from vvea_design.identification.fit_data import FitData
from vvea_design.identification.identify import (
    PAPER_ERROR_BAND_PCT,
    PAPER_TABLE3,
    Identification,
    error_band_pct,
    fit_eq14,
    table3,
    write_identification,
)
from vvea_design.identification.recordings import read_recordings, recordings_from_frame

SHARED = SHARED_RECORDINGS


@pytest.fixture(scope="module")
def sim():
    spec = small_spec(seed=11, g_N_per_mm_MPa=21.0, C_N=140.0, noise_N=4.0, noise_rho=0.8)
    camp = simulate(spec)
    return spec, recordings_from_frame(camp.frame, "sim")


def test_eq14_recovers_the_bench(sim):
    spec, rec = sim
    fit = fit_eq14(rec)
    v = fit.values
    se = fit.errors
    truth = {"g": spec.g_N_per_mm_MPa, "C": spec.C_N}
    truth.update({f"L({g:g})": L for g, L in spec.L_N_s_per_mm.items() if g in spec.valves_deg})
    for k, true in truth.items():
        # within 5 cluster-robust standard errors, and the errors are not absurdly small or large
        assert abs(v[k] - true) < 5 * se[k] + 1e-6 * abs(true), (k, v[k], true, se[k])
    assert 0 < se["g"] < 0.05 * spec.g_N_per_mm_MPa
    # residual is the noise: in-sample RMSE close to the noise RMS
    assert fit.rmse_N == pytest.approx(spec.noise_N, rel=0.25)


def test_cluster_errors_exceed_iid_errors_for_correlated_noise(sim):
    """With AR(1) noise the per-experiment sandwich must be wider than the naive i.i.d. error."""
    _, rec = sim
    D = FitData.from_recordings(rec)
    fit = fit_eq14(D)
    X = fit.design(D)
    r = D.y - X @ fit.theta
    iid = np.sqrt(np.diag(np.linalg.inv(X.T @ X)) * np.mean(r**2))
    assert fit.se[1] > 1.3 * iid[1]  # Coulomb friction: sign(ẋ) is constant over half runs


def test_table3_layout(sim):
    _, rec = sim
    tab = table3(fit_eq14(rec))
    assert list(tab.columns) == ["parameter", "unit", "value", "std_error", "paper"]
    assert tab["parameter"].iloc[0] == "g" and tab["parameter"].iloc[1] == "B (=C)"
    assert len(tab) == 2 + rec.experiments["valve_deg"].nunique()
    assert tab.loc[tab["parameter"] == "g", "paper"].item() == PAPER_TABLE3["g"]


def test_shared_campaign_a_table3_and_error_band():
    """campaign_a holds eq. 14 + noise: the error band must be far inside the paper's."""
    rec = read_recordings(SHARED / "campaign_a.csv")
    D = FitData.from_recordings(rec)
    fit = fit_eq14(D)
    lo, hi = error_band_pct(D, fit.predict(D))
    assert PAPER_ERROR_BAND_PCT[0] < lo < 0 < hi < PAPER_ERROR_BAND_PCT[1]
    # L grows with the valve angle (the throttle closes)
    L = [fit.values[f"L({g:g})"] for g in D.valves]
    assert np.all(np.diff(L) > 0)
    assert D.rows_left_out == 3 * rec.n_experiments


def test_write_identification(tmp_path, sim):
    _, rec = sim
    s = write_identification(rec, tmp_path, figures=False)
    assert isinstance(s, Identification)
    for f in s.files:
        assert (tmp_path / f).stat().st_size > 0
    j = json.loads((tmp_path / "identification.json").read_text())
    assert j["rows_left_out"] == 3 * rec.n_experiments
    assert set(j["parameters"]) >= {"g", "B (=C)"}
    # the typed result is the file: same keys in the same order, same numbers
    assert json.dumps(s.to_dict(), indent=2) == (tmp_path / "identification.json").read_text()
    assert list(j) == ["source", "model", "rows_read", "rows_left_out", "rows_left_out_reason", "n_experiments",
                       "velocity_fallback_experiments", "parameters", "rmse_N", "error_band_pct", "identifiability", "notes",
                       "residual_sign", "fig11", "files"]
    assert s.rows_left_out == j["rows_left_out"] and s.parameters["g"].value == j["parameters"]["g"]["value"]
    with pytest.raises(AttributeError):
        s.rmse_N = 0.0  # frozen


def _app():
    return make_app(register)


def test_cli_identify(tmp_path, sim):
    _, rec = sim
    f = tmp_path / "rec.csv"
    rec.data[["experiment", "time_s", "displacement_mm", "force_N", "p2_MPa", "valve_deg", "speed_mm_s"]].to_csv(f, index=False)
    res = CliRunner().invoke(_app(), ["identify", str(f), "--out", str(tmp_path / "out")])
    assert res.exit_code == 0, res.output
    assert "Table 3" in res.output and "paper" in res.output.lower()
    for p2 in ("1", "4"):
        assert (tmp_path / "out" / f"fig10_model_vs_measurement_p2_{p2}MPa.png").exists()
    assert (tmp_path / "out" / "fig11_force_displacement.png").exists()


def test_cli_identify_bad_file(tmp_path):
    f = tmp_path / "bad.csv"
    f.write_text("experiment,time_s,force_N\nA,0,1\n")
    res = CliRunner().invoke(_app(), ["identify", str(f), "--out", str(tmp_path / "out")])
    assert res.exit_code == 2
    assert "missing required column" in res.output


# ---------------------------------------------------------------- issue 11 items 1, 10, 12 and issue 13 (fig. 10)
def _repeat(rec, copies=2):
    import pandas as pd

    cols = ["experiment", "time_s", "displacement_mm", "force_N", "p2_MPa", "valve_deg", "speed_mm_s"]
    f = rec.data[cols]
    return recordings_from_frame(pd.concat([f.assign(experiment=f["experiment"] + f"_r{k}") for k in range(copies)]), "rep")


def test_repeated_test_conditions_with_figures(tmp_path, sim):
    _, rec = sim
    rep = _repeat(rec)
    (tmp_path / "fig10_model_vs_measurement.png").write_bytes(b"stale")  # from an older version
    s = write_identification(rep, tmp_path, figures=True)
    assert not (tmp_path / "fig10_model_vs_measurement.png").exists()
    figs = sorted(p.name for p in tmp_path.glob("fig10_*.png"))
    assert figs == ["fig10_model_vs_measurement_p2_1MPa.png", "fig10_model_vs_measurement_p2_4MPa.png"]
    assert s.fig11.experiment.endswith("_r0")
    assert s.identifiability.inseparable == [] and s.notes == ()
    assert json.loads((tmp_path / "identification.json").read_text())["fig11"] == s.fig11.to_dict()
    from PIL import Image

    w, h = Image.open(tmp_path / figs[0]).size
    assert w >= 280 * 3 and h >= 170 * 5  # legible: ~290 x 175 px per panel (3 speeds x 5 valves) at 100 dpi


def test_one_experiment_says_what_cannot_be_separated(tmp_path, sim):
    _, rec = sim
    ex = rec.experiments
    one = ex[(ex["speed_mm_s"] == 4.0) & (ex["valve_deg"] == 100.0) & (ex["p2_MPa"] == 4.0)]["experiment"]
    sub = rec.subset(one)
    s = write_identification(sub, tmp_path, figures=False)
    groups = s.identifiability.inseparable
    assert any({"C", "L(100)"} <= set(g) for g in groups)
    assert not s.identifiability.errors_reliable
    assert all(p.std_error is None for p in s.parameters.values())
    assert any("cannot separate C and L(100)" in n for n in s.notes)
    assert any("only 1 experiment" in n for n in s.notes)
    # two experiments, one valve, one pressure, two speeds: C and L separable, but too few experiments for errors
    two = ex[(ex["valve_deg"] == 100.0) & (ex["p2_MPa"] == 4.0)]["experiment"].iloc[:2]
    s2 = write_identification(rec.subset(two), tmp_path / "two", figures=False)
    assert s2.identifiability.inseparable == []
    assert s2.parameters["g"].std_error is None


def test_cli_identify_prints_notes(tmp_path, sim):
    _, rec = sim
    ex = rec.experiments
    one = ex[(ex["speed_mm_s"] == 4.0) & (ex["valve_deg"] == 100.0) & (ex["p2_MPa"] == 4.0)]["experiment"]
    f = tmp_path / "one.csv"
    cols = ["experiment", "time_s", "displacement_mm", "force_N", "p2_MPa", "valve_deg", "speed_mm_s"]
    rec.subset(one).data[cols].to_csv(f, index=False, sep=";", decimal=",")
    res = CliRunner().invoke(_app(), ["identify", str(f), "--out", str(tmp_path / "out")])
    assert res.exit_code == 0, res.output
    assert "not determined" in res.output
    assert "cannot separate C and L(100)" in res.output.replace("\n", " ")
    assert "semicolon" in res.output
    json.loads((tmp_path / "out" / "identification.json").read_text())  # strict JSON (no NaN)
