"""Tests of what the residuals hold: the noise floor (not inflated by ripple or slow structure) and the residual map."""

from __future__ import annotations

import numpy as np
import pytest
from scipy.signal import lfilter

from vvea_benches.testbench import simulate, small_spec
from vvea_design.identification.fit_data import FitData
from vvea_design.identification.fitting import fit_model
from vvea_design.identification.noise import noise_floor_N, residual_map
from vvea_design.identification.recordings import recordings_from_frame


def test_noise_floor_is_not_inflated_by_ripple_or_slow_structure():
    D = FitData.from_recordings(recordings_from_frame(simulate(small_spec(seed=3)).frame, "n"))
    rng = np.random.default_rng(0)
    white = rng.standard_normal(D.n) * 4.0
    assert noise_floor_N(D, white) == pytest.approx(4.0, rel=0.1)
    ar = lfilter([1.0], [1.0, -0.8], rng.standard_normal(D.n)) * 4.0 * np.sqrt(1 - 0.64)
    assert noise_floor_N(D, ar) == pytest.approx(4.0, rel=0.15)
    # a 20 N time ripple, a 15 N position ripple and a 30 N slow bow on 4 N noise (RMS 19 N in all): the
    # floor rises by < 40 % (Hann side lobes of the strong lines), where the RMS rises 4.8-fold
    ripple = 20 * np.sin(2 * np.pi * D.t / 0.5) + 15 * np.sin(2 * np.pi * D.x / 5.0) + 30 * (D.x / 40.0) ** 2
    assert noise_floor_N(D, white + ripple) < 1.4 * noise_floor_N(D, white)


def test_residual_map_bins_account_for_every_sample():
    frame = simulate(small_spec(seed=21)).frame.copy()
    frame["force_N"] += 25 * np.sin(2 * np.pi * frame["displacement_mm"] / 6.0)  # the ripple campaign of test_diagnose.py
    D = FitData.from_recordings(recordings_from_frame(frame, "ripple"))
    baseline = fit_model(D, ())  # the diagnosis's eq.-14 fit on all experiments
    m = residual_map(D, D.y - baseline.predict(D), 1.0)
    assert {f.name for f in m} == {"displacement", "speed", "direction", "time_since_reversal", "p2", "valve", "campaign_time"}
    for feat in m:
        assert sum(b.n for b in feat.bins) == D.n
