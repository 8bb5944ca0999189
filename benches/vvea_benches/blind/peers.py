"""Peer methods on the same campaigns and the same held-out experiments as ``vvea diagnose``.

Two generic peers a reviewer would reach for, both fitted on the training experiments only and
scored on the experiments the diagnosis held out (``heldout.test_experiments`` of its report):

- **SINDy** — sparse regression (pysindy's STLSQ) of the force on a library of the states:
  polynomials up to degree 3 of x, ẋ, p2 and the campaign time, sign(ẋ) times 1, p2, x and the
  campaign time, and one damping column ẋ per valve. Columns are standardised; the threshold is
  chosen by 5-fold cross-validation grouped by experiment on the training experiments.
- **eq. 14 + trees** — eq. 14 by least squares, then a gradient-boosted tree model
  (scikit-learn's HistGradientBoostingRegressor) on its residual from x, ẋ, p2, the valve, the time
  in the experiment, the time since the reversal, the direction and the campaign time.

Velocity: ``np.gradient`` of the displacement over time (what a generic peer does), or the
velocity of a trapezoidal ramp (constant acceleration, cruise, deceleration) fitted to each ramp's
displacement by least squares (a fitted velocity, so the comparison is fair).
Samples at rest (start, turning point, end) are left out as the diagnosis leaves them out.
"""

from __future__ import annotations

import numpy as np
import pandas as pd

__all__ = ["load_recordings", "add_states", "fit_sindy", "fit_eq14_trees", "fit_eq14", "peer_heldout_rmse",
           "THRESHOLDS_N"]

#: Candidate STLSQ thresholds on standardised columns (N per standard deviation of a column).
THRESHOLDS_N = (0.3, 1.0, 3.0, 10.0, 30.0)


def load_recordings(csv_path) -> pd.DataFrame:
    """Read an exchange-format CSV and number the experiments in campaign order.

    Parameters
    ----------
    csv_path : path-like
        The recordings.

    Returns
    -------
    pandas.DataFrame
        The columns plus ``exp`` (0-based index in campaign order).
    """
    df = pd.read_csv(csv_path)
    order = pd.unique(df["experiment"])
    df["exp"] = df["experiment"].map({e: i for i, e in enumerate(order)}).astype(int)
    return df


def _trapezoid(t, t0, T, D, v):
    """Displacement along a trapezoidal ramp of duration T, distance D and cruise speed v, from t0."""
    a = v * v / max(v * T - D, 1e-12)
    ta = v / a
    tau = np.clip(t - t0, 0.0, T)
    s = np.where(tau < ta, 0.5 * a * tau**2, v * tau - 0.5 * v * ta)
    s = np.where(tau > T - ta, D - 0.5 * a * (T - tau) ** 2, s)
    ds = np.where(tau < ta, a * tau, v)
    return s, np.where(tau > T - ta, a * (T - tau), ds)


def _fitted_ramp_velocity(t, x):
    """Velocity of the trapezoid (constant acceleration, cruise, constant deceleration) fitting one ramp.

    The ramp runs from its first to its last sample; the cruise speed is the one free parameter
    (the acceleration follows from the duration and the distance), found by least squares.
    """
    from scipy.optimize import minimize_scalar

    T, D = t[-1] - t[0], x[-1] - x[0]
    sgn = 1.0 if D >= 0 else -1.0
    D = abs(D)
    if T <= 0 or D <= 0:
        return np.gradient(x, t)
    y = sgn * (x - x[0])

    def sse(v):
        return float(np.sum((_trapezoid(t, t[0], T, D, v)[0] - y) ** 2))

    res = minimize_scalar(sse, bounds=(D / T * (1 + 1e-9), 2.0 * D / T), method="bounded",
                          options={"xatol": 1e-10 * D / T})
    return sgn * _trapezoid(t, t[0], T, D, float(res.x))[1]


def _velocity(t, x, method):
    if method == "gradient":
        return np.gradient(x, t)
    if method != "fitted":
        raise ValueError(f"velocity method must be 'gradient' or 'fitted', got {method!r}")
    v = np.empty_like(x)
    k = int(np.argmax(x))
    for sl in (slice(0, k + 1), slice(k, len(x))):
        v[sl] = _fitted_ramp_velocity(t[sl], x[sl]) if len(x[sl]) >= 5 else np.gradient(x[sl], t[sl])
    return v


def add_states(df: pd.DataFrame, velocity: str = "gradient") -> pd.DataFrame:
    """Add the states the peers use.

    Parameters
    ----------
    df : pandas.DataFrame
        From :func:`load_recordings`.
    velocity : str
        "gradient" (``np.gradient``) or "fitted" (a trapezoidal ramp fitted to each ramp).

    Returns
    -------
    pandas.DataFrame
        A copy with ``v`` (mm/s), ``t_rev`` (s since the reversal, 0 before it), ``dirn`` (±1),
        ``tc`` (campaign time, h: the experiments' durations summed in run order) and ``used``
        (False for the samples at rest: start, turning point, end).
    """
    out = df.copy()
    v = np.empty(len(df))
    t_rev = np.zeros(len(df))
    used = np.ones(len(df), dtype=bool)
    tc = np.empty(len(df))
    clock = 0.0
    for _, idx in df.groupby("exp", sort=True).indices.items():
        t, x = df["time_s"].to_numpy()[idx], df["displacement_mm"].to_numpy()[idx]
        v[idx] = _velocity(t, x, velocity)
        k = int(np.argmax(x))
        t_rev[idx] = np.where(np.arange(len(idx)) > k, t - t[k], 0.0)
        used[idx[[0, k, len(idx) - 1]]] = False
        tc[idx] = (clock + t) / 3600.0
        clock += t[-1]
    out["v"], out["t_rev"], out["used"], out["tc"] = v, t_rev, used, tc
    out["dirn"] = np.sign(v)
    return out


def _eq14_columns(df, valves):
    cols = [df["p2_MPa"].to_numpy() * df["displacement_mm"].to_numpy()]
    for g in valves:
        cols.append(df["v"].to_numpy() * (df["valve_deg"].to_numpy() == g))
    cols.append(np.sign(df["v"].to_numpy()))
    return np.column_stack(cols)


def fit_eq14(train: pd.DataFrame, test: pd.DataFrame) -> tuple[np.ndarray, np.ndarray]:
    """Eq. 14 (g p2 x + L(γ) ẋ + C sign ẋ) by least squares.

    Parameters
    ----------
    train, test : pandas.DataFrame
        Rows from :func:`add_states`.

    Returns
    -------
    pred_train, pred_test : numpy.ndarray
        Force predictions, N.
    """
    valves = sorted(train["valve_deg"].unique())
    A = _eq14_columns(train, valves)
    coef, *_ = np.linalg.lstsq(A, train["force_N"].to_numpy(), rcond=None)
    return A @ coef, _eq14_columns(test, valves) @ coef


def _sindy_library(df, valves):
    import pysindy as ps

    z = np.column_stack([df["displacement_mm"].to_numpy() / 40.0, df["v"].to_numpy() / 12.0,
                         df["p2_MPa"].to_numpy() / 4.0, df["tc"].to_numpy() / 10.0])
    lib = ps.PolynomialLibrary(degree=3, include_bias=True)
    lib.fit(z)
    P = np.asarray(lib.transform(z))
    names = list(lib.get_feature_names(["x", "v", "p", "tc"]))
    s = np.sign(df["v"].to_numpy())
    extra = [s, s * z[:, 2], s * z[:, 0], s * z[:, 3]]
    names += ["sgn", "p sgn", "x sgn", "tc sgn"]
    for g in valves:
        extra.append(z[:, 1] * (df["valve_deg"].to_numpy() == g))
        names.append(f"v@{g:g}")
    return np.column_stack([P] + extra), names


def _stlsq(Th, y, thr):
    import pysindy as ps

    opt = ps.STLSQ(threshold=thr, alpha=1e-6, max_iter=30, normalize_columns=False)
    opt.fit(Th, y.reshape(-1, 1))
    return np.asarray(opt.coef_).ravel()


def fit_sindy(train: pd.DataFrame, test: pd.DataFrame, n_folds: int = 5, thresholds=THRESHOLDS_N,
              cv_stride: int = 4) -> dict:
    """Sparse regression (STLSQ) of the force on the state library, threshold by grouped CV.

    Parameters
    ----------
    train, test : pandas.DataFrame
        Rows from :func:`add_states` (training and held-out experiments).
    n_folds : int
        Folds of the cross-validation grouped by experiment.
    thresholds : sequence of float
        Candidate thresholds, N per standard deviation of a column.
    cv_stride : int
        The cross-validation uses every ``cv_stride``-th training row (the final fit uses all).

    Returns
    -------
    dict
        ``pred`` (held-out predictions, N), ``threshold`` (chosen), ``cv_rmse_N`` (per threshold),
        ``terms`` (names of the non-zero terms).
    """
    from sklearn.model_selection import GroupKFold

    valves = sorted(train["valve_deg"].unique())
    Th, names = _sindy_library(train, valves)
    mu, sd = Th.mean(axis=0), Th.std(axis=0)
    mu[0], sd[0] = 0.0, 1.0  # the bias column stays a column of ones
    sd[sd == 0] = 1.0
    Z = (Th - mu) / sd
    Z[:, 0] = 1.0
    y = train["force_N"].to_numpy()
    groups = train["exp"].to_numpy()
    cv = {}
    Zc, yc, gc = Z[::cv_stride], y[::cv_stride], groups[::cv_stride]
    for thr in thresholds:
        err = []
        for tr, va in GroupKFold(n_splits=n_folds).split(Zc, yc, gc):
            c = _stlsq(Zc[tr], yc[tr], thr)
            err.append((yc[va] - Zc[va] @ c) ** 2)
        cv[thr] = float(np.sqrt(np.mean(np.concatenate(err))))
    best = min(cv, key=cv.get)
    coef = _stlsq(Z, y, best)
    Tt, _ = _sindy_library(test, valves)
    Zt = (Tt - mu) / sd
    Zt[:, 0] = 1.0
    return {"pred": Zt @ coef, "threshold": best, "cv_rmse_N": {str(k): v for k, v in cv.items()},
            "terms": [n for n, c in zip(names, coef) if c != 0]}


TREE_FEATURES = ("displacement_mm", "v", "p2_MPa", "valve_deg", "time_s", "t_rev", "dirn", "tc")


def fit_eq14_trees(train: pd.DataFrame, test: pd.DataFrame, seed: int = 0, max_rows: int = 30000) -> dict:
    """Eq. 14 by least squares plus gradient-boosted trees on its residual.

    Parameters
    ----------
    train, test : pandas.DataFrame
        Rows from :func:`add_states`.
    seed : int
        Seed of the row subsample and the trees.
    max_rows : int
        Training rows given to the trees (a random subsample).

    Returns
    -------
    dict
        ``pred`` (held-out predictions, N) and ``eq14_pred`` (eq. 14 alone, N).
    """
    from sklearn.ensemble import HistGradientBoostingRegressor

    p_tr, p_te = fit_eq14(train, test)
    r = train["force_N"].to_numpy() - p_tr
    X = train[list(TREE_FEATURES)].to_numpy()
    rng = np.random.default_rng(seed)
    sel = rng.choice(len(X), size=min(max_rows, len(X)), replace=False)
    hgb = HistGradientBoostingRegressor(max_iter=300, learning_rate=0.1, max_leaf_nodes=31,
                                        l2_regularization=1.0, random_state=seed)
    hgb.fit(X[sel], r[sel])
    return {"pred": p_te + hgb.predict(test[list(TREE_FEATURES)].to_numpy()), "eq14_pred": p_te}


def peer_heldout_rmse(csv_path, test_experiments, seed: int = 0) -> dict:
    """Held-out RMS of every peer on one campaign.

    Parameters
    ----------
    csv_path : path-like
        The campaign's recordings.
    test_experiments : sequence of int
        Indices (campaign order) of the held-out experiments, from the diagnosis report.
    seed : int
        Seed of the trees.

    Returns
    -------
    dict
        ``<peer>_<velocity>_N`` for peers ``eq14``, ``sindy``, ``trees`` and velocities
        ``gradient``, ``fitted`` (held-out RMS, N, over the samples not at rest), plus the SINDy
        thresholds and term counts.
    """
    from threadpoolctl import threadpool_limits

    with threadpool_limits(limits=1):  # the sweep runs campaigns in parallel processes
        return _peer_heldout_rmse(csv_path, test_experiments, seed)


def _peer_heldout_rmse(csv_path, test_experiments, seed):
    raw = load_recordings(csv_path)
    test_set = set(int(i) for i in test_experiments)
    if not test_set:
        raise ValueError(f"{csv_path}: no held-out experiments given")
    out = {}
    for vel in ("gradient", "fitted"):
        df = add_states(raw, vel)
        df = df[df["used"]]
        is_test = df["exp"].isin(test_set).to_numpy()
        train, test = df[~is_test], df[is_test]
        y = test["force_N"].to_numpy()

        def rms(p):
            return float(np.sqrt(np.mean((y - p) ** 2)))

        s = fit_sindy(train, test)
        t = fit_eq14_trees(train, test, seed)
        out[f"eq14_{vel}_N"] = rms(t["eq14_pred"])
        out[f"sindy_{vel}_N"] = rms(s["pred"])
        out[f"trees_{vel}_N"] = rms(t["pred"])
        out[f"sindy_{vel}_threshold"] = s["threshold"]
        out[f"sindy_{vel}_terms"] = len(s["terms"])
    return out
