"""Tests of the last stage: trees on the states for what the sparse library leaves, kept only when the held-out error falls."""

from __future__ import annotations

import json
from dataclasses import dataclass, replace

import numpy as np
import pytest

from vvea_benches.testbench import simulate, small_spec
from vvea_design.identification.effects import REGISTRY
from vvea_design.identification.fit_data import FitData
from vvea_design.identification.fitting import fit_model
from vvea_design.identification.last_stage import (
    FEATURES,
    RESIDUAL_ID,
    describe_shape,
    fit_last_stage,
    state_features,
)
from vvea_design.identification.noise import noise_floor_N
from vvea_design.identification.recordings import recordings_from_frame
from vvea_design.identification.report import load_final_model, make_final_model
from vvea_design.identification.selection import plan_split
from vvea_design.identification.settings import DiagnoseSettings


def _data(frame):
    return FitData.from_recordings(recordings_from_frame(frame, "last-stage"))


@pytest.fixture(scope="module")
def band():
    """A friction that acts only over one band of the stroke (no catalogue formula, no library column): 60 N there."""
    frame = simulate(small_spec(seed=3, noise_N=2.0)).frame.copy()
    x = frame["displacement_mm"].to_numpy()
    v = frame.groupby("experiment")["displacement_mm"].diff().fillna(0.0).to_numpy()
    lo, hi = np.quantile(x, [0.55, 0.75])
    frame["force_N"] = frame["force_N"].to_numpy() + 60.0 * np.sign(v) * ((x > lo) & (x < hi))
    return _data(frame)


@dataclass(frozen=True)
class _Learner:
    ran: bool = True
    heldout_variance_explained: float = 0.9
    where: tuple = ()


def _stage(D, settings=DiagnoseSettings(), learner=None):
    plan = plan_split(D, settings)
    tr = fit_model(D, (), experiments=plan.train)
    final = fit_model(D, ())
    noise = noise_floor_N(D, D.y - final.predict(D))
    return plan, final, fit_last_stage(D, plan, tr, final, noise, settings, learner)


def test_state_features_histories(D):
    f = state_features(D)
    assert set(f) == set(FEATURES)
    assert all(np.all(np.isfinite(v)) and len(v) == D.n for v in f.values())
    d = f["distance_since_reversal"]
    assert np.all(d >= 0)
    # zero at each experiment's first sample, and it grows while the direction holds
    first = np.flatnonzero(np.r_[True, np.diff(D.exp) != 0])
    assert np.allclose(d[first], 0.0)
    # the filtered velocity lags the velocity: smaller in magnitude right after a reversal
    assert np.max(np.abs(f["filtered_velocity"])) <= np.max(np.abs(D.v)) + 1e-9


def test_last_stage_models_a_band_the_library_cannot_name(band):
    plan, _, last = _stage(band)
    assert last.tried and last.accepted
    assert last.heldout_after_N < 0.5 * last.heldout_before_N
    assert np.all(np.isfinite(last.model.predict(band)))
    assert "Not named" in last.description
    assert not any(e in last.description for e in REGISTRY if REGISTRY[e].catalogue)


def test_last_stage_not_kept_on_a_clean_campaign(D):
    _, _, last = _stage(D, learner=_Learner(heldout_variance_explained=0.0))
    assert not last.accepted
    assert last.model is None
    assert last.description.startswith("not")


def test_last_stage_off_by_setting(band):
    _, _, last = _stage(band, settings=replace(DiagnoseSettings(), last_stage=False))
    assert not last.tried and not last.accepted


def test_final_model_with_last_stage_round_trip(band, tmp_path):
    import pickle

    plan, final, last = _stage(band)
    fm = make_final_model(final, band, {}, last.model)
    assert fm.model.endswith(RESIDUAL_ID)
    (tmp_path / "final_model.json").write_text(json.dumps(fm.to_dict()))
    with pytest.raises(ValueError, match="last_stage.pkl"):
        load_final_model(tmp_path / "final_model.json")
    (tmp_path / "last_stage.pkl").write_bytes(pickle.dumps(fm.last_stage))
    back = load_final_model(tmp_path / "final_model.json")
    assert np.allclose(back.predict(band), final.predict(band) + last.model.predict(band))
    assert back.to_dict()["last_stage"]["states"] == list(FEATURES)


class _Lin:
    """A known function of two columns: rises with column 0, odd in column 1."""

    def predict(self, X):
        return 3.0 * X[:, 0] + 2.0 * X[:, 1]


def test_describe_shape_words(D):
    X = np.column_stack([D.p2, D.v])
    txt = describe_shape(D, ["charge", "velocity"], _Lin(), X)
    assert "the charge p2 (rises with it" in txt
    assert "odd in it" in txt


def test_diagnose_reports_the_last_stage(band, tmp_path):
    from vvea_design.identification.diagnose import diagnose, write_diagnosis

    d = diagnose(band)
    r = d.report
    stage = [e for e in r.effects if e.id == RESIDUAL_ID]
    assert len(stage) == 1 and stage[0].accepted and not stage[0].catalogue
    assert RESIDUAL_ID in [e.id for e in r.accepted]
    assert r.heldout.final_N < 0.6 * r.heldout.baseline_N
    assert r.heldout.steps[-1].effects[-1] == RESIDUAL_ID
    assert r.heldout.steps[-1].rmse_N < 0.98 * r.heldout.steps[-2].rmse_N  # the stage itself lowers the held-out error
    files = write_diagnosis(d, tmp_path)
    assert "last_stage.pkl" in files
    back = load_final_model(tmp_path / "final_model.json")
    assert back.model.endswith(RESIDUAL_ID)
    assert np.all(np.isfinite(back.predict(band)))
    rep = json.loads((tmp_path / "report.json").read_text())
    assert rep["heldout_rmse_N"]["final"] == pytest.approx(r.heldout.final_N)
