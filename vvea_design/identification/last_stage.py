"""The last stage: a flexible, regularised function of the states for what the sparse library leaves.

When the accepted model (eq. 14 + named and discovered terms) still leaves a held-out error above
the noise, the structure left may be physics no catalogue formula and no state-library column
describes. :func:`fit_last_stage` then

1. measures, in grouped cross-validation over the TRAINING experiments only (group = experiment),
   how much of the residual gradient-boosted trees can predict from the measured states and their
   simple histories (:data:`FEATURES`: position, velocity, speed, direction, charge, valve, time in
   the experiment, time and distance since the last reversal, a low-pass filtered velocity,
   campaign order), and which states carry it (permutation importance on the held-out folds);
2. fits the trees on exactly those states, on the training experiments, and keeps the stage only
   when it lowers the error on the experiments held out of everything (the held-out guard) by a
   clear margin;
3. refits on all experiments for the final model, and describes the stage by what it depends on
   and how (rises / falls with a state, odd in the velocity, only in part of each experiment) --
   never with a catalogue name: the trees model a force, they do not say what causes it.

Residual sign: residual = measurement − model (N).
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from .fit_data import FitData

__all__ = ["FEATURES", "RESIDUAL_ID", "ResidualModel", "LastStage", "state_features", "state_matrix", "fit_last_stage", "describe_shape"]

#: Id of the last stage in the report's ``effects`` (never a catalogue id).
RESIDUAL_ID = "residual_model"

#: Low-pass time constant of the filtered velocity, s (a general "recent motion" history, not a fitted lag).
FILTER_TAU_S = 0.2
#: Shorter and longer low-pass histories of the velocity, s (a decade around :data:`FILTER_TAU_S`'s order).
FILTER_SHORT_S, FILTER_LONG_S = 0.05, 1.0

#: Feature name -> (meaning, unit).
FEATURES: dict = {
    "position": ("the position x", "mm"),
    "velocity": ("the velocity xdot", "mm/s"),
    "speed": ("the speed |xdot|", "mm/s"),
    "direction": ("the direction of motion", "-"),
    "charge": ("the charge p2", "MPa"),
    "valve": ("the valve opening", "deg"),
    "time_in_experiment": ("the time within each experiment", "s"),
    "since_reversal": ("the time since the last reversal", "s"),
    "distance_since_reversal": ("the distance travelled since the last reversal", "mm"),
    "filtered_velocity": (f"the velocity low-pass filtered over {FILTER_TAU_S:g} s", "mm/s"),
    "filtered_velocity_short": (f"the velocity low-pass filtered over {FILTER_SHORT_S:g} s", "mm/s"),
    "filtered_velocity_long": (f"the velocity low-pass filtered over {FILTER_LONG_S:g} s", "mm/s"),
    "campaign_order": ("the campaign order (campaign time)", "s"),
}

_HGB = dict(max_iter=150, learning_rate=0.1, max_leaf_nodes=15, min_samples_leaf=40, l2_regularization=1.0)


def _segments(D: FitData) -> np.ndarray:
    """Start index of each contiguous run of samples of one experiment (time not decreasing)."""
    new = np.ones(D.n, bool)
    if D.n > 1:
        new[1:] = (np.diff(D.exp) != 0) | (np.diff(D.t) < 0)
    return np.flatnonzero(new)


def state_features(D: FitData) -> dict:
    """The states and their simple histories, one array per :data:`FEATURES` name.

    Parameters
    ----------
    D : FitData
        The campaign (x in mm, ẋ in mm/s, p2 in MPa, valve in deg, times in s).

    Returns
    -------
    dict
        Feature name -> ``(D.n,)`` array in the unit of :data:`FEATURES` (``since_reversal`` in s).
    """
    from scipy.signal import lfilter

    starts = _segments(D)
    ends = np.append(starts[1:], D.n)
    s = np.sign(D.v)
    # distance since the last reversal: |x − x at the last sign change of the velocity (or the start)|
    anchor = np.zeros(D.n, bool)
    anchor[starts] = True
    if D.n > 1:
        anchor[1:] |= (s[1:] != s[:-1]) & (s[1:] != 0)
    idx = np.maximum.accumulate(np.where(anchor, np.arange(D.n), 0))
    dist = np.abs(D.x - D.x[idx])
    vf = {tau: np.empty(D.n) for tau in (FILTER_TAU_S, FILTER_SHORT_S, FILTER_LONG_S)}
    for a, b in zip(starts, ends):
        dt = float(np.median(np.diff(D.t[a:b]))) if b - a > 1 else 0.0
        for tau, out in vf.items():
            if not np.isfinite(dt) or dt <= 0:
                out[a:b] = D.v[a:b]
                continue
            k = dt / (tau + dt)
            out[a:b] = lfilter([k], [1.0, k - 1.0], D.v[a:b], zi=[(1.0 - k) * D.v[a]])[0]
    return {
        "position": D.x, "velocity": D.v, "speed": np.abs(D.v), "direction": s, "charge": D.p2,
        "valve": D.valve, "time_in_experiment": D.t, "since_reversal": D.tsr, "distance_since_reversal": dist,
        "filtered_velocity": vf[FILTER_TAU_S], "filtered_velocity_short": vf[FILTER_SHORT_S],
        "filtered_velocity_long": vf[FILTER_LONG_S], "campaign_order": D.ctime,
    }


def state_matrix(D: FitData, names) -> np.ndarray:
    """The states ``names`` as the columns of one matrix (the time since reversal as log10 of s + 1 ms).

    Parameters
    ----------
    D : FitData
        The campaign.
    names : sequence of str
        :data:`FEATURES` names.

    Returns
    -------
    numpy.ndarray
        ``(D.n, len(names))`` in the units of :data:`FEATURES` (``since_reversal`` as log10 s).
    """
    f = state_features(D)
    cols = [np.log10(np.asarray(f[k], float) + 1e-3) if k == "since_reversal" else np.asarray(f[k], float) for k in names]
    return np.column_stack(cols)


@dataclass(frozen=True)
class ResidualModel:
    """A fitted last stage: gradient-boosted trees on exactly ``states``; ``predict`` gives its force (N).

    Attributes
    ----------
    states : tuple of str
        :data:`FEATURES` names it reads.
    description : str
        What its force depends on and how, in plain words.
    model : object
        The fitted ``HistGradientBoostingRegressor``.
    """

    states: tuple
    description: str
    model: object = field(repr=False, compare=False)

    def predict(self, D: FitData) -> np.ndarray:
        """Force of the last stage at the samples of ``D``.

        Parameters
        ----------
        D : FitData
            The motions (x in mm, ẋ in mm/s, p2 in MPa, valve in deg, times in s).

        Returns
        -------
        numpy.ndarray
            ``(D.n,)`` force, N (added to the parametric model's force).
        """
        out = np.asarray(self.model.predict(state_matrix(D, self.states)), float)
        return np.where(np.isfinite(out), out, 0.0)

    def to_dict(self) -> dict:
        """The stage as JSON (the trees themselves are written to ``last_stage.pkl``).

        Returns
        -------
        dict
            ``kind``, ``states`` (with their units), ``description`` and the model file name.
        """
        return dict(kind="gradient-boosted trees on the residual of the parametric model", states=list(self.states),
                    units={k: FEATURES[k][1] for k in self.states}, description=self.description, file="last_stage.pkl")


@dataclass(frozen=True)
class LastStage:
    """Outcome of :func:`fit_last_stage`.

    Attributes
    ----------
    tried : bool
        The stage was fitted (the held-out error was above the gate and the trees found structure in CV).
    accepted : bool
        It lowered the held-out error by the required margin.
    states : tuple of str
        The states it depends on (largest permutation importance first).
    cv_gain : float or None
        Share of the training residual variance the trees predict in grouped CV (dimensionless).
    heldout_before_N, heldout_after_N : float or None
        Held-out RMS without and with the stage, N.
    description : str
        What its force depends on and how (plain words), or why it was not kept.
    model : ResidualModel or None
        Fitted on all experiments (only when accepted).
    """

    tried: bool
    accepted: bool
    states: tuple = ()
    cv_gain: float | None = None
    heldout_before_N: float | None = None
    heldout_after_N: float | None = None
    description: str = ""
    model: ResidualModel | None = field(default=None, repr=False, compare=False)


def _hgb(seed: int):
    from sklearn.ensemble import HistGradientBoostingRegressor

    return HistGradientBoostingRegressor(random_state=seed, **_HGB)


def _rows(rows: np.ndarray, cap: int, seed: int) -> np.ndarray:
    if len(rows) <= cap:
        return rows
    return np.sort(np.random.default_rng(seed).choice(rows, cap, replace=False))


def _rms(a: np.ndarray) -> float:
    v = float(np.sqrt(np.mean(a**2))) if len(a) else float("nan")
    return v if np.isfinite(v) else float("inf")


#: Leftover-learner feature name (:func:`~vvea_design.identification.noise.learner_check`) -> :data:`FEATURES` name.
LEARNER_NAMES = {"displacement": "position", "velocity": "velocity", "speed": "speed", "direction": "direction",
                 "time_since_reversal": "since_reversal", "p2": "charge", "valve": "valve",
                 "campaign_time": "campaign_order", "time_in_experiment": "time_in_experiment"}


def fit_last_stage(D: FitData, plan, train_fit, final_fit, noise_N: float, settings, learner=None) -> LastStage:
    """Fit, guard and describe the last stage (see the module docstring).

    Parameters
    ----------
    D : FitData
        The campaign.
    plan : Plan
        ``train`` and ``test`` experiments (:func:`~vvea_design.identification.selection.plan_split`).
    train_fit : ModelFit
        The accepted model fitted on the training experiments.
    final_fit : ModelFit
        The accepted model fitted on all experiments.
    noise_N : float
        Noise floor, N RMS.
    settings : DiagnoseSettings
        ``last_stage``, ``last_stage_gate`` (x noise), ``last_stage_learner_gain``,
        ``last_stage_min_drop``, ``last_stage_rows``, ``seed``.
    learner : LearnerCheck, optional
        The leftover learner's check on the final residual: its grouped-CV share of explained variance
        opens the stage (at least ``last_stage_learner_gain`` opens it even when the held-out RMS is within
        ``last_stage_gate`` x the noise floor -- a sharp structure the noise-floor estimate took for noise),
        and its permutation importances name the states. Whether the stage is kept is decided by the
        held-out experiments only.

    Returns
    -------
    LastStage
        Whether it was tried and kept, the states it depends on, the held-out RMS without and with it (N).
    """
    if not getattr(settings, "last_stage", True) or len(plan.test) == 0 or len(plan.train) < 4:
        return LastStage(False, False, description="not tried: no held-out experiments or too few training experiments")
    from threadpoolctl import threadpool_limits

    with threadpool_limits(limits=1):
        return _fit(D, plan, train_fit, final_fit, noise_N, settings, learner)


def _main_states(learner) -> tuple:
    """The states the leftover learner found the structure in (largest permutation importance first)."""
    where = getattr(learner, "where", ()) or ()
    return tuple(dict.fromkeys(LEARNER_NAMES.get(w.feature, w.feature) for w in where if w.feature in LEARNER_NAMES))


def _fit(D, plan, train_fit, final_fit, noise_N, settings, learner) -> LastStage:
    seed = int(settings.seed)
    tr_mask = np.isin(D.exp, plan.train)
    te_mask = np.isin(D.exp, plan.test)
    res = D.y - train_fit.predict(D)
    before = _rms(res[te_mask])
    gain = None if learner is None or not learner.ran else learner.heldout_variance_explained
    predictable = gain is not None and gain >= settings.last_stage_learner_gain
    if not np.isfinite(before) or (before <= settings.last_stage_gate * noise_N and not predictable):
        return LastStage(False, False, heldout_before_N=before, cv_gain=gain, description=(
            f"not tried: the held-out RMS {before:.3g} N is within {settings.last_stage_gate:g} x the noise floor {noise_N:.3g} N "
            f"and the leftover learner predicts little of the residual"))
    names = list(FEATURES)
    X = state_matrix(D, names)
    fit_rows = _rows(np.flatnonzero(tr_mask), settings.last_stage_rows, seed + 12)
    m = _hgb(seed).fit(X[fit_rows], res[fit_rows])
    pred_te = np.asarray(m.predict(X[te_mask]), float)
    after = _rms(res[te_mask] - pred_te) if np.all(np.isfinite(pred_te)) else float("inf")
    states = _main_states(learner) or tuple(names)
    if not (after < before * (1.0 - settings.last_stage_min_drop) and before - after > 0.05 * min(noise_N, before)):
        return LastStage(True, False, states, gain, before, after, (
            f"not kept: trees on the states and their histories do not lower the held-out RMS enough ({before:.3g} N without, {after:.3g} N with)"))
    res_all = D.y - final_fit.predict(D)
    all_rows = _rows(np.arange(D.n), settings.last_stage_rows, seed + 13)
    m_all = _hgb(seed).fit(X[all_rows], res_all[all_rows])
    shown = [k for k in states if k in names][:3]
    desc = describe_shape(D, shown, m_all, X, seed, columns=[names.index(k) for k in shown])
    desc = (f"A flexible correction (gradient-boosted trees on the residual, fitted on the states and their histories) "
            f"whose structure sits mainly along {desc}; held-out RMS {before:.3g} N -> {after:.3g} N. "
            f"Not named: the trees model the force, not its cause.")
    return LastStage(True, True, states, gain, before, after, desc, ResidualModel(tuple(names), desc, m_all))


def describe_shape(D: FitData, states, model, X: np.ndarray, seed: int = 0, n_rows: int = 400, columns=None) -> str:
    """How a fitted function depends on each of its states, from its partial dependence, in words.

    Parameters
    ----------
    D : FitData
        The campaign (only its size is used).
    states : sequence of str
        :data:`FEATURES` names, the columns of ``X``.
    model : object
        Fitted regressor with ``predict``.
    X : numpy.ndarray
        ``(D.n, k)`` its inputs (``since_reversal`` as log10 s).
    seed : int
        Seed of the rows averaged over.
    n_rows : int
        Rows averaged over per grid point.
    columns : sequence of int, optional
        Column of ``X`` of each state (default: 0, 1, ...).

    Returns
    -------
    str
        E.g. "the charge p2 (rises with it, 12.3 N over its range), the velocity xdot (odd in it, 4.1 N)".
    """
    rows = _rows(np.arange(len(X)), n_rows, seed + 21)
    Xs = X[rows]
    parts = []
    cols = list(range(len(states))) if columns is None else list(columns)
    for j, name in zip(cols, states):
        col = X[:, j]
        grid = np.unique(np.quantile(col, np.linspace(0.02, 0.98, 13)))
        if name == "velocity":
            a = float(np.quantile(np.abs(col), 0.95))
            grid = np.linspace(-a, a, 13)
        pd_ = []
        for z in grid:
            Xz = Xs.copy()
            Xz[:, j] = z
            pd_.append(float(np.mean(model.predict(Xz))))
        pd_ = np.asarray(pd_)
        span = float(pd_.max() - pd_.min())
        how = []
        d = np.diff(pd_)
        tol = 0.05 * span
        if span > 0 and np.all(d >= -tol) and len(grid) > 2:
            how.append("rises with it")
        elif span > 0 and np.all(d <= tol) and len(grid) > 2:
            how.append("falls with it")
        elif len(grid) > 2:
            how.append("not monotone in it")
        if name == "velocity" and span > 0:
            mid = pd_[len(pd_) // 2]
            odd, even = pd_ - pd_[::-1], pd_ + pd_[::-1] - 2 * mid
            how.append("odd in it" if np.abs(odd).max() > 2 * np.abs(even).max() else
                       "even in it" if np.abs(even).max() > 2 * np.abs(odd).max() else "neither odd nor even in it")
        if name in ("time_in_experiment", "since_reversal", "distance_since_reversal") and span > 0 and len(grid) > 3:
            ch = np.abs(d)
            first = int(np.searchsorted(np.cumsum(ch) / ch.sum(), 0.8)) + 1
            if first <= len(grid) // 3:
                z = grid[min(first, len(grid) - 1)]
                z = 10**z - 1e-3 if name == "since_reversal" else z
                how.append(f"it changes mostly below {z:.3g} {FEATURES[name][1]} (only in part of each experiment)")
        parts.append(f"{FEATURES[name][0]} ({', '.join(how + [f'{span:.3g} N over its range'])})")
    return ", ".join(parts)
