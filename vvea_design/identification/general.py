"""Names from evidence: a catalogue name must beat a general function of the same states.

A catalogue formula (``thermal``, ``leakage``, ...) fitted to a residual always explains *some* of it.
Whether the name is earned is a question about the residual, not about the formula: the force the
formula describes depends on a few measured states (:attr:`~vvea_design.identification.effects.base.Effect.depends_on`),
and a flexible learner on exactly those states -- the most general term on the same states -- tells
how much of the residual those states can carry at all. In each selection round, over the same
grouped-CV folds as the candidates (whole experiments out; the current model refitted on each fold's
training part, :func:`fold_residuals`), :func:`general_sse` gives the held-out squared error per
experiment of

- the current model + gradient-boosted trees on the catalogue effect's own states, and
- the current model + trees on all the states and their simple histories
  (:data:`~vvea_design.identification.last_stage.FEATURES`).

:func:`name_evidence` then asks two questions of a catalogue candidate that passed its own tests:

1. **Does the residual depend on the formula's states?** The trees on the formula's states must
   predict at least ``settings.name_states_share`` of what the trees on all states predict (a drift over
   the campaign fitted by a velocity law fails: its structure lies along the campaign order);
2. **Does the formula beat the general term on those states?** It must remove at least
   ``settings.name_general_share`` of what the general term on its states removes, unless the
   general term's advantage is not significant (paired t over held-out experiments <= ``settings.name_t``).

A candidate that fails is not named: the round's discovered explanation (or, failing one, the last
stage on the states) describes the structure by what it depends on.

Residual sign: residual = measurement − model (N).
"""

from __future__ import annotations

import numpy as np

from .fit_data import FitData, cached
from .last_stage import FEATURES, state_matrix
from .least_squares import solve_bounded

__all__ = ["fold_residuals", "general_sse", "name_evidence", "NameEvidence", "noise_upper_bound"]

#: Trees of the general term: small and quick (it is fitted once per fold and state set in a round).
_HGB = dict(max_iter=60, learning_rate=0.2, max_leaf_nodes=15, min_samples_leaf=40, l2_regularization=1.0)
#: Rows each fold's trees are fitted on (sub-sampled from the fold's training experiments).
GENERAL_ROWS = 5000


def fold_residuals(D: FitData, X0: np.ndarray, base_blk, plan) -> dict:
    """The current model's residual, refitted on each CV fold's training experiments.

    Parameters
    ----------
    D : FitData
        The campaign.
    X0 : numpy.ndarray
        ``(D.n, p)`` the current model's design (N per unit amplitude).
    base_blk : Blocks
        Its per-experiment Gram blocks (:func:`~vvea_design.identification.least_squares.blocks`).
    plan : Plan
        Training experiments and their folds.

    Returns
    -------
    dict
        Fold id -> ``(D.n,)`` residual (measurement − model fitted without that fold), N.
    """
    out = {}
    for f in np.unique(plan.folds[plan.train]):
        tr = plan.train[plan.folds[plan.train] != f]
        th = solve_bounded(base_blk.G[tr].sum(0), base_blk.b[tr].sum(0), base_blk.lower, base_blk.upper)
        r = D.y - X0 @ th
        out[int(f)] = np.where(np.isfinite(r), r, 0.0)
    return out


def _features(D: FitData, states) -> np.ndarray:
    names = tuple(states)
    return cached(D, ("general_features", names), lambda: state_matrix(D, names))


def general_sse(D: FitData, plan, residuals: dict, states, seed: int = 0) -> np.ndarray:
    """Held-out squared error per experiment of the current model + trees on ``states`` (grouped CV).

    Parameters
    ----------
    D : FitData
        The campaign.
    plan : Plan
        Training experiments and their folds.
    residuals : dict
        Per fold the current model's residual (:func:`fold_residuals`), N.
    states : sequence of str
        :data:`~vvea_design.identification.last_stage.FEATURES` names the trees read.
    seed : int
        Seed of the row sub-sample and the trees.

    Returns
    -------
    numpy.ndarray
        ``(D.n_exp,)`` squared error summed over each held-out experiment's samples (N²); nan outside
        the training experiments.
    """
    from sklearn.ensemble import HistGradientBoostingRegressor
    from threadpoolctl import threadpool_limits

    # one OpenMP thread, set after sklearn is imported (a limit set before its runtime loads does not reach it, and
    # idle OpenMP threads spinning on a loaded machine cost many times the fit's CPU)
    with threadpool_limits(limits=1):
        return _general_sse(D, plan, residuals, states, seed, HistGradientBoostingRegressor)


def _general_sse(D, plan, residuals, states, seed, HistGradientBoostingRegressor) -> np.ndarray:
    X = _features(D, states)
    sse = np.full(D.n_exp, np.nan)
    rng = np.random.default_rng(seed + 31)
    for f, r in residuals.items():
        tr_e = plan.train[plan.folds[plan.train] != f]
        te_e = plan.train[plan.folds[plan.train] == f]
        rows = np.flatnonzero(np.isin(D.exp, tr_e))
        if len(rows) > GENERAL_ROWS:
            rows = np.sort(rng.choice(rows, GENERAL_ROWS, replace=False))
        te = np.isin(D.exp, te_e)
        m = HistGradientBoostingRegressor(random_state=seed, **_HGB).fit(X[rows], r[rows])
        pred = np.asarray(m.predict(X[te]), float)
        err = r[te] - np.where(np.isfinite(pred), pred, 0.0)
        sse[te_e] = np.bincount(D.exp[te], weights=err**2, minlength=D.n_exp)[te_e]
    return sse


def noise_upper_bound(D: FitData, plan, seed: int = 0) -> float:
    """An upper bound on the noise: the held-out RMS of eq. 14 + trees on all the states (grouped CV), N.

    The periodogram floor (:func:`~vvea_design.identification.noise.noise_floor_N`) takes sharp structure
    (friction that steps over a band of the stroke) for noise; what a general function of the states
    leaves on experiments it was not fitted to is noise plus what no such function predicts, so it
    bounds the noise from above.

    Parameters
    ----------
    D : FitData
        The campaign.
    plan : Plan
        Training experiments and their folds.
    seed : int
        Seed of the trees and their rows.

    Returns
    -------
    float
        RMS over the training experiments' samples, N (inf when it cannot be formed).
    """
    from .fitting import fit_model

    folds = np.unique(plan.folds[plan.train])
    if len(folds) < 2:
        return float("inf")
    res = {}
    for f in folds:
        tr = plan.train[plan.folds[plan.train] != f]
        r = D.y - fit_model(D, (), experiments=tr).predict(D)
        res[int(f)] = np.where(np.isfinite(r), r, 0.0)
    sse = general_sse(D, plan, res, tuple(FEATURES), seed)[plan.train]
    n = float(D.n_per_exp[plan.train].sum())
    v = float(np.sqrt(np.nansum(sse) / max(n, 1.0)))
    return v if np.isfinite(v) and v > 0 else float("inf")


class NameEvidence:
    """Outcome of :func:`name_evidence` for one catalogue candidate.

    Attributes
    ----------
    ok : bool
        The name is earned (both questions answered yes).
    reason : str
        Why not (empty when ``ok``).
    states_share : float
        Share of the all-states trees' held-out gain that the trees on the formula's states reach (dimensionless).
    general_share : float
        Share of the same-states trees' held-out gain that the formula reaches (dimensionless).
    general_t : float
        Paired t by which the same-states trees beat the formula on held-out experiments.
    """

    def __init__(self, ok: bool, reason: str, states_share: float, general_share: float, general_t: float):
        self.ok, self.reason = bool(ok), reason
        self.states_share, self.general_share, self.general_t = float(states_share), float(general_share), float(general_t)


def _paired_t(a: np.ndarray, b: np.ndarray) -> float:
    d = a - b
    sd = float(np.std(d, ddof=1)) if len(d) > 1 else 0.0
    return float(np.mean(d) / sd * np.sqrt(len(d))) if sd > 0 else 0.0


def name_evidence(base_sse: np.ndarray, cat_sse: np.ndarray, same_sse: np.ndarray, all_sse: np.ndarray, train,
                  states, settings) -> NameEvidence:
    """Does a catalogue candidate earn its name against general terms (see the module docstring)?

    Parameters
    ----------
    base_sse, cat_sse, same_sse, all_sse : numpy.ndarray
        ``(n_exp,)`` grouped-CV squared error per experiment (N²) of the current model, with the
        catalogue term, with trees on the term's states, with trees on all states.
    train : numpy.ndarray of int
        Training experiments (the CV's held-out experiments).
    states : sequence of str
        The catalogue term's states (:data:`~vvea_design.identification.last_stage.FEATURES` names).
    settings : DiagnoseSettings
        ``name_states_share``, ``name_general_share``, ``name_t``.

    Returns
    -------
    NameEvidence
    """
    b, c, s, a = (np.asarray(z, float)[train] for z in (base_sse, cat_sse, same_sse, all_sse))
    if not all(np.all(np.isfinite(z)) for z in (b, c, s, a)):
        return NameEvidence(True, "", float("nan"), float("nan"), 0.0)
    g_cat, g_same, g_all = (float(b.sum() - z.sum()) for z in (c, s, a))
    words = ", ".join(FEATURES[k][0] for k in states)
    # the formula is itself a function of its states: what it removes is a lower bound on what they carry
    # (trees on few states can fail in CV where the formula does not: stiction at the low speeds of a reversal)
    states_share = max(g_same, g_cat) / g_all if g_all > 0 else 1.0
    general_share = g_cat / g_same if g_same > 0 else 1.0
    t = _paired_t(c, s)
    if g_all > 0 and states_share < settings.name_states_share:
        return NameEvidence(False, (
            f"not named: the residual does not depend on the states its formula follows ({words}): a general function of "
            f"them predicts {100 * states_share:.0f} % of what one of all the states predicts on held-out experiments "
            f"(< {100 * settings.name_states_share:.0f} %)"), states_share, general_share, t)
    if g_same > 0 and general_share < settings.name_general_share and t > settings.name_t:
        return NameEvidence(False, (
            f"not named: a general function of the same states ({words}) explains the held-out experiments better "
            f"(the formula removes {100 * general_share:.0f} % of what it removes, < {100 * settings.name_general_share:.0f} %; "
            f"paired t {t:.1f} > {settings.name_t:g})"), states_share, general_share, t)
    return NameEvidence(True, "", states_share, general_share, t)
