"""The peers: fitted velocity, eq. 14 least squares, SINDy's STLSQ on a known sparse law."""

import numpy as np
import pandas as pd
import pysindy
import pytest

from vvea_benches.blind.motion import Motion
from vvea_benches.blind.peers import add_states, fit_eq14, fit_eq14_trees, fit_sindy


def _campaign(noise=0.0, seed=0):
    rng = np.random.default_rng(seed)
    rows = []
    for e, (p2, valve, speed) in enumerate([(p, g, s) for p in (1.0, 4.0) for g in (50.0, 110.0) for s in (1.0, 8.0)] * 2):
        m = Motion(speed, n_per_ramp=30)
        t = m.t_s
        x, v = m.position_mm(t), m.velocity_mm_s(t)
        L = 0.5 if valve == 50.0 else 80.0
        f = 23.0 * p2 * x + L * v + 120.0 * np.sign(v) + rng.normal(0, noise, len(t))
        rows.append(pd.DataFrame({"experiment": f"E{e:02d}", "time_s": t, "displacement_mm": x, "force_N": f,
                                  "p2_MPa": p2, "valve_deg": valve, "speed_mm_s": speed, "exp": e, "v_true": v}))
    return pd.concat(rows, ignore_index=True)


def test_fitted_velocity_is_the_trapezoid():
    df = add_states(_campaign(), "fitted")
    np.testing.assert_allclose(df["v"], df["v_true"], atol=1e-3)
    g = add_states(_campaign(), "gradient")
    assert not g["used"].all() and (~g["used"]).sum() == 3 * g["exp"].nunique()  # start, turn, end left out


def test_eq14_and_sindy_recover_a_law_they_contain():
    df = add_states(_campaign(noise=1.0), "fitted")
    df = df[df["used"]]
    train, test = df[df["exp"] < 8], df[df["exp"] >= 8]
    _, p = fit_eq14(train, test)
    assert np.sqrt(np.mean((test["force_N"] - p) ** 2)) < 1.5
    s = fit_sindy(train, test, n_folds=4, cv_stride=1)
    assert np.sqrt(np.mean((test["force_N"] - s["pred"]) ** 2)) < 2.0
    assert "x p" in s["terms"] and "sgn" in s["terms"]
    t = fit_eq14_trees(train, test, max_rows=2000)
    assert np.sqrt(np.mean((test["force_N"] - t["pred"]) ** 2)) < 3.0
    assert pysindy.STLSQ  # the peer is pysindy's optimiser


def test_unknown_velocity_method_raises():
    with pytest.raises(ValueError, match="velocity method"):
        add_states(_campaign(), "spline")
