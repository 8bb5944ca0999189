"""Selection: which terms eq. 14 lacks, by grouped cross-validation over whole experiments.

1. **Plan** (:func:`plan_split`) -- experiments held out of everything
   (stratified by valve) and grouped-CV folds over the rest; with few
   experiments the plan says what cannot be assessed instead of failing.
2. **Forward selection** (:func:`select_effects`) -- over the registry of
   :mod:`~vvea_design.identification.effects`: catalogue effects and
   discovery operators compete in grouped cross-validation (whole
   experiments held out). A term is accepted when it lowers the held-out
   error (a) by at least ``min_gain`` of the mean square, (b) consistently
   (paired t over held-out experiments >= ``min_t``, or at least
   ``min_halved`` badly fit experiments with their error halved), (c) stably
   (improves at least ``min_folds`` of the folds), (d) by a meaningful force
   (its RMS >= ``min_snr`` x the residual RMS). **Naming discipline**: a
   catalogue effect is accepted only if it passes its physical signature
   checks and the best passing discovery operator is not significantly
   better on held-out experiments (paired t <= ``name_t``); otherwise the
   discovery operator is accepted and reported with ``catalogue: false``.
   The accepted second-order sensor filter gets its damping ratio fitted
   (:func:`refine_filter_damping`). Each round also offers the state
   library's candidate (:func:`~vvea_design.identification.effects.library.select_terms`:
   a sparse sum of terms in the measured states, STLSQ with a grouped-CV
   threshold); after the first round only the candidates that showed some
   structure are tested again (:func:`_settles`).
3. **Backward step** (:func:`_backward_step`): at the end every accepted
   term is re-tested beside all the other accepted terms and
   dropped when they explain it away (its force or its held-out gain below
   ``keep_noise`` x the noise floor, or the gain, t and fold tests failed).
4. **Final fits** (:func:`final_fits`) -- all experiments, cluster-robust
   errors, fold jackknife for shape parameters (their stability), held-out
   RMS after each accepted term (fitted without the held-out experiments).

Residual sign: residual = measurement − model (N).
"""

from __future__ import annotations

import inspect
from dataclasses import asdict, dataclass

import numpy as np

from .design import assemble
from .effects import REGISTRY, Effect, effect_columns
from .effects.force_lag import ZETA_RANGE, ForceFilter, filter_id
from .effects.library import select_terms, states_id
from .fit_data import FitData
from .fitting import ModelFit, fit_model, relief_context
from .general import fold_residuals, general_sse, name_evidence
from .last_stage import FEATURES
from .least_squares import blocks, extend_blocks, solve_bounded
from .noise import noise_floor_N
from .report import Evidence, HeldOutStep
from .settings import DiagnoseSettings

__all__ = ["Plan", "plan_split", "select_effects", "refine_filter_damping", "final_fits", "BLOWUP"]

#: A candidate whose cross-validated squared error exceeds this many times the current model's has blown up numerically.
BLOWUP = 100.0


# ------------------------------------------------------------------ plan
@dataclass(frozen=True)
class Plan:
    """Which experiments train, which are held out, the CV folds, and what cannot be assessed."""

    train: np.ndarray
    test: np.ndarray
    folds: np.ndarray  #: fold per experiment (-1: test)
    n_folds: int
    can_select: bool
    notes: tuple


def plan_split(D: FitData, settings: DiagnoseSettings) -> Plan:
    """Held-out test experiments and CV folds, stratified by valve position.

    Every valve keeps about ``1 - test_fraction`` of its experiments for
    training and each CV fold's training part holds ``(k-1)/k`` of them, so
    no fold has to predict a valve whose damping it never saw. Small
    campaigns: fewer folds; no held-out set when a valve cannot spare an
    experiment; no selection below ``min_experiments_cv`` experiments.

    Parameters
    ----------
    D : FitData
        The campaign (its experiments and their valve angles).
    settings : DiagnoseSettings
        ``n_folds``, ``test_fraction`` (fraction of experiments held out),
        ``min_experiments_cv`` and the ``seed`` of the split.

    Returns
    -------
    Plan
        Training and held-out experiment indices, the fold of each
        experiment (-1 for held out), the number of folds, whether selection
        is possible and notes on what cannot be assessed.
    """
    rng = np.random.default_rng(settings.seed)
    valve_of = D.valve[D.bounds[:-1]]
    notes = []
    k = int(min(settings.n_folds, max(2, D.n_exp // 2)))
    test, folds = [], np.full(D.n_exp, -1)
    for v in np.unique(valve_of):
        exps = rng.permutation(np.flatnonzero(valve_of == v))
        n_test = int(np.floor(settings.test_fraction * len(exps) + rng.uniform()))
        n_test = min(n_test, max(len(exps) - k, 0))
        test += list(exps[:n_test])
        rest = exps[n_test:]
        folds[rest] = (rng.integers(k) + np.arange(len(rest))) % k
    test = np.sort(np.array(test, dtype=int))
    train = np.sort(np.setdiff1d(np.arange(D.n_exp), test))
    can_select = D.n_exp >= settings.min_experiments_cv and len(np.unique(folds[train])) >= 2
    if len(test) == 0:
        notes.append(
            f"held-out error cannot be assessed: {D.n_exp} experiment(s) over {len(np.unique(valve_of))} valve position(s) "
            "leave none to hold out (each valve keeps enough experiments to fit its damping)"
        )
    if not can_select:
        notes.append(
            f"no effect can be tested: {D.n_exp} experiment(s) < {settings.min_experiments_cv} needed for a cross-validated "
            "selection over whole experiments; the report gives eq. 14 and the residual map only"
        )
    elif k < settings.n_folds:
        notes.append(f"small campaign: {k} cross-validation folds instead of {settings.n_folds}")
    return Plan(train, test, folds, k, bool(can_select), tuple(notes))


# ------------------------------------------------------------------ forward and backward selection
@dataclass(frozen=True)
class _Trial:
    """One candidate's cross-validated score in one round."""

    id: str
    sse: np.ndarray | None
    shape: float
    evidence: Evidence | None
    fit: ModelFit | None
    signature: tuple = ()


def _has_mask(eff: Effect) -> bool:
    return not eff.nested


def _filtered_design(D: FitData, eff: Effect, X0: np.ndarray, shape: float, ctx: dict) -> np.ndarray:
    """A copy of the design ``X0`` (a whole design, eq. 14's columns first) through the design filter of ``eff``, called as :func:`assemble` calls it."""
    X = X0.copy()
    sig = inspect.signature(eff.transform).parameters
    kw = dict(({"out": X} if "out" in sig else {}), **({"eq14_first": True} if "eq14_first" in sig else {}))
    return eff.transform(D, X, shape, ctx, **kw)


def _cv_sse(D, cur: ModelFit, base_blk, X0, ctx, cand, plan, fallback):
    """Held-out SSE per experiment (grouped CV over the training experiments) with ``cand`` added.

    The candidate's shape is chosen on each fold's training part from its
    grid. Returns (sse per experiment, shape value best on all training experiments).
    """
    eff = REGISTRY[cand]
    grid = np.asarray(eff.grid(D, ctx), float) if eff.shape is not None else np.array([np.nan])
    if len(grid) == 0:
        return None, np.nan
    train, folds = plan.train, plan.folds
    # each grid value's blocks are scored on every fold as soon as they are built, so only one set of
    # per-experiment blocks is alive at a time (memory on large campaigns); same order of comparisons
    parts = [(train[folds[train] != f], train[folds[train] == f]) for f in np.unique(folds[train])]
    best = [None] * len(parts)  # per fold: (training SSE, held-out SSE per experiment) of the best grid value so far
    costs = []  # training SSE over all training experiments per grid value (shape for the trial fit)

    def score(Bk, sl, on_grid):
        for i, (tr, te) in enumerate(parts):
            Gtr = Bk.G[tr].sum(0)
            if sl is not None and not np.all(np.diag(Gtr)[sl] > 0):
                continue  # the term leaves no trace in this fold's training part
            th = solve_bounded(Gtr, Bk.b[tr].sum(0), Bk.lower, Bk.upper)
            c = Bk.sse(th, tr).sum()
            if best[i] is None or c < best[i][0]:
                best[i] = (c, Bk.sse(th, te))
        if on_grid:
            th = solve_bounded(Bk.G[train].sum(0), Bk.b[train].sum(0), Bk.lower, Bk.upper)
            costs.append(Bk.sse(th, train).sum())

    # a candidate that only filters the design (sensor dynamics, no columns of its own) over a model without
    # such filters: its design is the current one, X0, filtered (what assemble would rebuild and filter)
    only_filter = (_has_mask(eff) and eff.transforms_design and not eff.params(D) and eff.damping_mask(D, float(grid[0]), ctx) is None
                   and not any(REGISTRY[o].transforms_design for o in cur.effects) and X0.shape[1] == len(cur.params))
    for gval in grid:
        sh = dict(cur.shapes)
        sh[cand] = float(gval)
        if only_filter:
            X = _filtered_design(D, eff, X0, float(gval), ctx)
            Bk = blocks(X, D.y, D.bounds, cur.params)
            del X
            sl = slice(X0.shape[1], X0.shape[1])
        elif _has_mask(eff):
            X, params, groups = assemble(D, cur.effects + (cand,), sh, ctx)
            Bk = blocks(X, D.y, D.bounds, params)
            del X  # not alive while the next grid value's design is built
            sl = groups[cand]
        else:
            Xn = effect_columns(D, eff, float(gval), ctx)
            for o in cur.effects:  # sensor dynamics already in the model act on the new columns too
                if REGISTRY[o].transforms_design:
                    Xn = REGISTRY[o].transform(D, Xn, cur.shapes.get(o, np.nan), ctx)
            Bk = extend_blocks(base_blk, X0, Xn, D.y, D.bounds, eff.params(D))
            sl = slice(X0.shape[1], X0.shape[1] + Xn.shape[1])
            del Xn
        score(Bk, sl, True)
        del Bk
    if _has_mask(eff):
        score(base_blk, None, False)  # "valve closed" is not nested in the relief grid: offer it
    sse = np.full(D.n_exp, np.nan)
    for (tr, te), b in zip(parts, best):
        sse[te] = fallback[te] if b is None else b[1]
    return sse, float(grid[int(np.argmin(costs))])


def _round_context(D, cur: ModelFit, plan: Plan) -> dict:
    ctx = cur.context(D)
    pred = cur.predict(D)
    ctx["model_force_N"] = pred
    mtrain = np.isin(D.exp, plan.train)
    ctx["residual_N"] = np.where(mtrain, D.y - pred, 0.0)  # for grids: training experiments only
    ctx.setdefault("residual_all_N", D.y - pred)  # for per-experiment nuisance parameters (kept once a nuisance term is in)
    return ctx


def _blown(cand: str, rnd: int, n_folds: int, why: str, shape: float = np.nan) -> _Trial:
    """A rejected trial for a candidate whose fit blows up or fails numerically: no gain is reported for it."""
    ev = Evidence(rnd, float("nan"), float("nan"), 0, n_folds, 0, 0.0, 0.0, 0.0, False, None, False, (why,))
    return _Trial(cand, None, shape, ev, None)


def _score_safely(D, cur, cand, ctx, plan, base_sse, base_blk, X0, noise, settings, rnd) -> _Trial:
    """:func:`_score`, with a candidate whose fit fails numerically (singular, overflowing, non-finite) rejected, with its reason."""
    n_folds = len(np.unique(plan.folds[plan.train]))
    try:
        return _score(D, cur, cand, ctx, plan, base_sse, base_blk, X0, noise, settings, rnd)
    except (np.linalg.LinAlgError, ValueError, FloatingPointError, OverflowError, ZeroDivisionError) as exc:
        return _blown(cand, rnd, n_folds, f"its fit fails numerically ({type(exc).__name__}: {str(exc)[:120]}): rejected, no gain reported")


def _score(D, cur, cand, ctx, plan, base_sse, base_blk, X0, noise, settings, rnd) -> _Trial:
    eff = REGISTRY[cand]
    ctx_c = relief_context(D, cur.effects + (cand,), plan.train, cur.shapes, start=ctx) if eff.replaces_damping else ctx
    new_sse, shape = _cv_sse(D, cur, base_blk, X0, ctx_c, cand, plan, base_sse)
    if new_sse is None:
        return _Trial(cand, None, np.nan, None, None)
    tr = plan.train
    if eff.nuisance_per_experiment:  # parameters fitted on the held-out experiment itself: charge their expected gain on noise
        new_sse = new_sse + eff.nuisance_per_experiment * noise**2
    blown = not np.all(np.isfinite(new_sse[tr])) or float(np.sum(new_sse[tr])) > BLOWUP * max(float(np.sum(base_sse[tr])), 1e-300)
    if blown:  # a candidate fit that blows up numerically is rejected with its reason, never scored by its gain
        why = (f"its cross-validated fit blows up numerically (held-out mean square {np.nansum(new_sse[tr]) / max(D.n_per_exp[tr].sum(), 1):.3g} N^2 "
               f"against {np.sum(base_sse[tr]) / max(D.n_per_exp[tr].sum(), 1):.3g} N^2 without it): rejected")
        return _blown(cand, rnd, len(np.unique(plan.folds[tr])), why, shape)
    d = base_sse[tr] - new_sse[tr]
    gain = float(d.sum() / max(base_sse[tr].sum(), 1e-300))
    sd = float(np.std(d, ddof=1)) if len(d) > 1 else 0.0
    t = float(np.mean(d) / sd * np.sqrt(len(d))) if sd > 0 else 0.0
    fold_ids = np.unique(plan.folds[tr])
    fold_gain = [float(d[plan.folds[tr] == f].sum()) for f in fold_ids]
    n_improved = int(sum(g > 0 for g in fold_gain))
    ratio = new_sse[tr] / np.maximum(base_sse[tr], 1e-300)
    badly = base_sse[tr] / D.n_per_exp[tr] > (2.0 * noise) ** 2
    n_halved = int(np.sum((ratio < 0.5) & badly))
    consistent = t >= settings.min_t or n_halved >= settings.min_halved
    need_folds = min(settings.min_folds, len(fold_ids))
    stable = n_improved >= need_folds
    fit_c, snr, eff_rms, res_rms, sig = None, 0.0, 0.0, float(np.sqrt(np.nansum(base_sse[tr]) / max(D.n_per_exp[tr].sum(), 1))), ()
    if gain >= settings.min_gain and consistent:
        sh = dict(cur.shapes)
        if eff.shape is not None:
            sh[cand] = shape
        fit_c = fit_model(D, cur.effects + (cand,), experiments=tr, shapes=sh, ctx=ctx_c)
        contrib = fit_c.contribution(D, cand)
        mtr = np.isin(D.exp, tr)
        res_all = D.y - fit_c.predict(D)  # one design built for the residual of both checks below
        res_c = res_all[mtr]
        eff_rms = float(np.sqrt(np.mean(contrib[mtr] ** 2)))
        res_rms = float(np.sqrt(np.mean(res_c**2)))
        snr = eff_rms / max(res_rms, 1e-300)
        if eff.catalogue:
            sig = tuple(eff.signature(D, fit_c.effect_values(cand), fit_c.shapes.get(cand, np.nan), contrib))
        # the backward step's force test, already here: a term below keep_noise x the floor of the model with it
        # would be dropped there anyway, after a selection round spent beside it
        floor_c = noise_floor_N(D, res_all)
        del res_all
        floor_c = min(noise, floor_c) if np.isfinite(floor_c) else noise
        small = eff_rms < settings.keep_noise * floor_c
    else:
        small, floor_c = False, noise
    sig_ok = all(c.passed for c in sig)
    reasons = []
    if gain < settings.min_gain:
        reasons.append(f"held-out error falls by {100 * gain:.2f} % < {100 * settings.min_gain:.1f} %")
    if not consistent:
        reasons.append(f"paired t over held-out experiments {t:.1f} < {settings.min_t:g} and {n_halved} badly fit experiments halved (< {settings.min_halved})")
    if not stable:
        reasons.append(f"improves only {n_improved} of {len(fold_ids)} folds (< {need_folds}): not stable across folds")
    if fit_c is not None and snr < settings.min_snr:
        reasons.append(f"effect RMS {snr:.2f} x residual < {settings.min_snr:g}")
    if fit_c is not None and not sig_ok:
        reasons.append("fails its physical signature: " + "; ".join(c.detail for c in sig if not c.passed))
    if small:
        reasons.append(f"its force ({eff_rms:.3g} N RMS) is below {settings.keep_noise:g} x the noise floor ({floor_c:.3g} N)")
    passes = gain >= settings.min_gain and consistent and stable and fit_c is not None and snr >= settings.min_snr and sig_ok and not small
    ev = Evidence(rnd, gain, t, n_improved, len(fold_ids), n_halved, snr, eff_rms, res_rms, sig_ok, None, bool(passes), tuple(reasons))
    return _Trial(cand, new_sse, shape, ev, fit_c, sig)


def _library_candidate(D: FitData, ctx: dict, plan: Plan, X0: np.ndarray) -> str | None:
    """This round's candidate from the state library: the terms STLSQ keeps beside the current model's design ``X0`` (None: no term)."""
    terms = select_terms(D, ctx, plan.folds, X0)
    return states_id(terms) if terms else None


def _settles(t: _Trial) -> bool:
    """A candidate that lowered the cross-validated error by nothing at all (or could not be fitted) is not tested again.

    A term added later takes its own share of the residual; a candidate whose columns explained nothing
    of the residual beside the current model (cross-validated gain <= 0, paired t <= 0) does not start
    to explain it then, short of a term that masked it, so later rounds keep its last score (its
    evidence says which round) instead of refitting it: the rounds after the first test only the
    candidates that showed some structure (the time of a diagnosis is mostly the candidates' fits).
    """
    ev = t.evidence
    if t.sse is None or ev is None:
        return True
    return bool(ev.cv_gain <= 0.0 and ev.paired_t <= 0.0)


def _paired_t(a: np.ndarray, b: np.ndarray) -> float:
    """Paired t by which ``b`` has smaller squared error than ``a``."""
    d = a - b
    sd = float(np.std(d, ddof=1)) if len(d) > 1 else 0.0
    return float(np.mean(d) / sd * np.sqrt(len(d))) if sd > 0 else 0.0


def select_effects(D: FitData, plan: Plan, noise: float, settings: DiagnoseSettings, say=lambda m: None):
    """Forward selection over catalogue effects and discovery operators (grouped CV, naming discipline).

    Each round tests every candidate not yet selected against the current
    model over the CV folds of ``plan``; of the candidates that pass
    (``settings``' gain, t, fold and SNR thresholds), a catalogue effect is
    preferred unless a discovery operator fits held-out experiments better by
    a paired t above ``settings.name_t``. Stops when nothing passes or after
    ``settings.max_effects`` terms.

    Parameters
    ----------
    D : FitData
        The campaign.
    plan : Plan
        Training experiments and CV folds (:func:`plan_split`).
    noise : float
        Noise floor, N RMS (:func:`noise_floor_N`).
    settings : DiagnoseSettings
        Candidates and acceptance thresholds.
    say : callable
        Called with a progress message (str) before each candidate is tested.

    Returns
    -------
    selected : list of str
        Accepted effect ids, in the order accepted.
    shapes : dict
        Shape parameter per effect id of the last accepted model, in each
        effect's shape unit (empty when ``plan`` allows no selection).
    trials : dict
        Per candidate id its score in the last round it was tested
        (cross-validated SSE per experiment in N², shape, evidence, fit).
    """
    cands = [c for c in settings.candidates if c in REGISTRY] + [c for c in settings.discovery if c in REGISTRY]
    sel: list[str] = []
    trials: dict[str, _Trial] = {}
    cur = fit_model(D, (), experiments=plan.train)
    if not plan.can_select:
        return sel, {}, trials
    settled: set = set()  # candidates that explained nothing in a round: not tested again (see _settles)
    for rnd in range(1, settings.max_effects + 1):
        ctx, X0, base_blk, base_sse = _cv_current(D, cur, plan)
        round_trials = []
        lib = _library_candidate(D, ctx, plan, X0) if settings.library else None
        for c in cands + ([lib] if lib is not None else []):
            if c in sel or c in settled:
                continue
            say(f"round {rnd}: testing {c}")
            tri = _score_safely(D, cur, c, ctx, plan, base_sse, base_blk, X0, noise, settings, rnd)
            trials[c] = tri
            round_trials.append(tri)
        settled |= {t.id for t in round_trials if _settles(t)}
        passing = [t for t in round_trials if t.evidence is not None and t.evidence.passes]
        if settings.name_evidence:  # names from evidence: a catalogue name must beat general terms on the states
            passing = _name_from_evidence(D, plan, passing, X0, base_blk, base_sse, settings, trials)
        del ctx, X0, base_blk  # the round's design is not alive beside the refit and the next round's design
        disc = [t for t in passing if not REGISTRY[t.id].catalogue]
        cat = [t for t in passing if REGISTRY[t.id].catalogue]
        best_disc = max(disc, key=lambda t: t.evidence.cv_gain) if disc else None
        named = []
        for t in cat:
            vt = _paired_t(t.sse[plan.train], best_disc.sse[plan.train]) if best_disc is not None else None
            # the name needs the catalogue form to explain at least half of what the best discovered explanation explains
            small = best_disc is not None and t.evidence.cv_gain < 0.5 * best_disc.evidence.cv_gain
            ok = vt is None or (vt <= settings.name_t and not small)
            ev = t.evidence
            why = (f"a discovered explanation ({best_disc.id}) fits held-out experiments better (paired t {vt:.1f} > {settings.name_t:g})"
                   if vt is not None and vt > settings.name_t else
                   f"it removes less than half the held-out error a discovered explanation ({best_disc.id}) removes "
                   f"({100 * ev.cv_gain:.1f} % against {100 * best_disc.evidence.cv_gain:.1f} %)" if small else "")
            reasons = ev.reasons + (() if ok else (why,))
            trials[t.id] = _Trial(t.id, t.sse, t.shape, Evidence(**{**asdict(ev), "vs_best_discovered_t": vt, "passes": ok, "reasons": reasons}), t.fit, t.signature)
            if ok:
                named.append(trials[t.id])
        if named:
            best = max(named, key=lambda t: t.evidence.cv_gain)
        elif best_disc is not None:
            best = best_disc
        else:
            break
        sel.append(best.id)
        cur = best.fit
        if REGISTRY[best.id].shape is not None:  # the CV chose the shape on a coarse grid: refine it on the training experiments
            cur = fit_model(D, cur.effects, experiments=plan.train, shapes={k: v for k, v in cur.shapes.items() if k != best.id}, ctx=cur.ctx)
        if isinstance(REGISTRY[best.id], ForceFilter):  # the second-order sensor filter: fit its damping ratio too
            fid, cur = refine_filter_damping(D, cur, best.id, plan.train)
            if fid != best.id:
                sel[-1] = fid
                trials[fid] = trials.pop(best.id)
                cands = [c for c in cands if c != best.id]  # the filter it grew from is not tested again beside it
    sel, cur = _backward_step(D, plan, sel, cur, noise, settings, trials)
    return sel, dict(cur.shapes), trials


def _name_from_evidence(D: FitData, plan: Plan, passing: list, X0, base_blk, base_sse, settings: DiagnoseSettings, trials: dict) -> list:
    """The passing candidates, less the catalogue ones whose name general terms on the states refute (:mod:`.general`).

    A refused catalogue candidate's evidence gets ``passes`` False and the reason; the others get the shares.
    """
    cat = [t for t in passing if REGISTRY[t.id].catalogue and REGISTRY[t.id].depends_on]
    if not cat:
        return passing
    res = fold_residuals(D, X0, base_blk, plan)
    seed = int(settings.seed)
    memo: dict = {}

    def sse(states):
        key = tuple(states)
        if key not in memo:
            memo[key] = general_sse(D, plan, res, key, seed)
        return memo[key]

    all_sse = sse(tuple(FEATURES))
    refused = set()
    for t in cat:
        states = tuple(REGISTRY[t.id].depends_on)
        ne = name_evidence(base_sse, t.sse, sse(states), all_sse, plan.train, states, settings)
        ev = t.evidence
        new_ev = Evidence(**{**asdict(ev), "states_share": ne.states_share, "general_share": ne.general_share,
                             "passes": bool(ev.passes and ne.ok), "reasons": ev.reasons + ((ne.reason,) if not ne.ok else ())})
        trials[t.id] = _Trial(t.id, t.sse, t.shape, new_ev, t.fit, t.signature)
        if not ne.ok:
            refused.add(t.id)
    return [trials[t.id] if t.id in trials and REGISTRY[t.id].catalogue else t for t in passing if t.id not in refused]


def refine_filter_damping(D: FitData, cur: ModelFit, eid: str, rows: np.ndarray, xtol: float = 0.002):
    """Fit the damping ratio of the sensor filter ``eid`` of ``cur`` (and its lag again), on the experiments ``rows``.

    One second-order filter (damping ratio 0.707 to start) is tested in the
    selection; the accepted one's damping ratio shapes the response at every
    start and reversal of the motion, where a stiff valve's force changes
    fastest, so it is fitted within :data:`ZETA_RANGE` (bounded scalar
    search on the training SSE, lag fixed), then the lag at that ratio, then
    the ratio again near its value. The result is the filter of that ratio
    (id :func:`~vvea_design.identification.effects.force_lag.filter_id`) when it
    lowers the training SSE, else ``eid`` unchanged.

    Parameters
    ----------
    D : FitData
        The campaign.
    cur : ModelFit
        The current model; ``eid`` among its effects, its lag (s) in ``cur.shapes``.
    eid : str
        Id of the accepted second-order filter (a :class:`~vvea_design.identification.effects.force_lag.ForceFilter`).
    rows : numpy.ndarray of int
        Training experiments (indices 0 .. n_exp-1, dimensionless).
    xtol : float
        Tolerance of the damping-ratio search (dimensionless).

    Returns
    -------
    fid : str
        Id of the filter with the fitted damping ratio (or ``eid``).
    fit : ModelFit
        ``cur`` with that filter, its lag (s) refitted, on ``rows``.
    """
    from scipy.optimize import minimize_scalar

    others = {k: v for k, v in cur.shapes.items() if k != eid}
    at = cur.effects.index(eid)

    def effects_with(fid):
        return cur.effects[:at] + (fid,) + cur.effects[at + 1 :]

    def fit_at(zeta, lag):
        fid = filter_id(zeta)
        return fid, fit_model(D, effects_with(fid), experiments=rows, shapes=dict(others, **{fid: lag}), ctx=cur.ctx, refine=False)

    memo: dict = {}

    def cost(zeta, lag):
        key = (filter_id(zeta), round(float(np.log(lag)), 6))
        if key not in memo:
            memo[key] = fit_at(zeta, lag)[1].rmse_N
        return memo[key]

    lag = float(cur.shapes[eid])
    z0 = float(REGISTRY[eid].zeta)
    lo, hi = ZETA_RANGE
    z = float(minimize_scalar(lambda q: cost(q, lag), bounds=(lo, hi), method="bounded", options={"xatol": xtol}).x)
    z = z if cost(z, lag) < cost(z0, lag) else z0
    r = minimize_scalar(lambda u: cost(z, np.exp(u)), bounds=(np.log(lag / 1.25), np.log(lag * 1.25)), method="bounded",
                        options={"xatol": 1e-3})
    lag = float(np.exp(r.x)) if r.fun < cost(z, lag) else lag
    r = minimize_scalar(lambda q: cost(q, lag), bounds=(max(lo, z - 0.1), min(hi, z + 0.1)), method="bounded", options={"xatol": xtol})
    z = float(r.x) if r.fun < cost(z, lag) else z
    if cost(z, lag) >= cur.rmse_N:
        return eid, cur
    return fit_at(z, lag)


def _cv_current(D: FitData, cur: ModelFit, plan: Plan):
    """Context, design, blocks and grouped-CV SSE per experiment (N², shapes fixed) of the model ``cur``."""
    ctx = _round_context(D, cur, plan)
    X0, params0, _ = assemble(D, cur.effects, cur.shapes, ctx)
    base_blk = blocks(X0, D.y, D.bounds, params0)
    base_sse = np.full(D.n_exp, np.nan)
    for f in np.unique(plan.folds[plan.train]):
        tr = plan.train[plan.folds[plan.train] != f]
        te = plan.train[plan.folds[plan.train] == f]
        th = solve_bounded(base_blk.G[tr].sum(0), base_blk.b[tr].sum(0), base_blk.lower, base_blk.upper)
        base_sse[te] = base_blk.sse(th, te)
    return ctx, X0, base_blk, base_sse


def _backward_step(D: FitData, plan: Plan, sel: list, cur: ModelFit, noise: float, settings: DiagnoseSettings, trials: dict):
    """Re-test every accepted term beside all the other accepted terms; drop those explained away.

    Forward selection accepts a term against the model of its round; a term
    accepted later (a more complete explanation of the same structure) can
    explain its improvement away. A term (a catalogue effect keeps its name,
    a discovered term its place) stays only if its force is at least ``keep_noise`` x the noise floor (RMS over the
    training samples) and removing it from the final model raises the
    grouped-CV error by at least
    ``(keep_noise x noise)^2`` per sample, by ``min_gain`` of the mean square,
    consistently (paired t or halved experiments) and in ``min_folds`` folds.
    The weakest failing effect is dropped and the test repeated.
    """
    tr = plan.train
    n_tr = max(float(D.n_per_exp[tr].sum()), 1.0)
    protected: set = set()  # catalogue terms that explain most of what the discovered corrections after them explain
    while True:
        cat = [e for e in sel if e not in protected]
        if not cat:
            return sel, cur
        full_sse = _cv_current(D, cur, plan)[3]
        # the floor of the model as it now stands: structure the selection explained (a ripple the
        # periodogram could not separate) no longer inflates the thresholds
        floor = noise_floor_N(D, D.y - cur.predict(D))
        noise = min(noise, floor) if np.isfinite(floor) else noise
        worst = None
        for c in cat:
            rest = tuple(e for e in sel if e != c)
            fr = fit_model(D, rest, experiments=tr, shapes={e: cur.shapes[e] for e in rest if e in cur.shapes})
            sse_wo = _cv_current(D, fr, plan)[3]
            d = sse_wo[tr] - full_sse[tr]
            dmse = float(d.sum() / n_tr)
            gain = float(d.sum() / max(sse_wo[tr].sum(), 1e-300))
            t = _paired_t(sse_wo[tr], full_sse[tr])
            ratio = full_sse[tr] / np.maximum(sse_wo[tr], 1e-300)
            badly = sse_wo[tr] / D.n_per_exp[tr] > (2.0 * noise) ** 2
            n_halved = int(np.sum((ratio < 0.5) & badly))
            fold_ids = np.unique(plan.folds[tr])
            n_improved = int(sum(d[plan.folds[tr] == f].sum() > 0 for f in fold_ids))
            mtr = np.isin(D.exp, tr)
            eff_rms = float(np.sqrt(np.mean(cur.contribution(D, c)[mtr] ** 2))) if mtr.any() else 0.0
            why = []
            if eff_rms < settings.keep_noise * noise:
                why.append(f"its force ({eff_rms:.3g} N RMS) is below {settings.keep_noise:g} x the noise floor ({noise:.3g} N)")
            if dmse < (settings.keep_noise * noise) ** 2:
                why.append(f"beside {', '.join(rest) or 'eq. 14'} it lowers the held-out mean square by {dmse:.3g} N^2 < ({settings.keep_noise:g} x noise floor)^2 = {(settings.keep_noise * noise) ** 2:.3g} N^2")
            if gain < settings.min_gain:
                why.append(f"beside {', '.join(rest) or 'eq. 14'} it lowers the held-out error by {100 * gain:.2f} % < {100 * settings.min_gain:.1f} %")
            if not (t >= settings.min_t or n_halved >= settings.min_halved):
                why.append(f"beside {', '.join(rest) or 'eq. 14'} its paired t is {t:.1f} < {settings.min_t:g}")
            if n_improved < min(settings.min_folds, len(fold_ids)):
                why.append(f"beside {', '.join(rest) or 'eq. 14'} it improves only {n_improved} of {len(fold_ids)} folds")
            if why and (worst is None or dmse < worst[1]):
                worst = (c, dmse, why, fr, sse_wo)
        if worst is None:
            return sel, cur
        c, _, why, fr, sse_c = worst
        if REGISTRY[c].catalogue:  # naming discipline here too: a discovered term does not explain a catalogue name away
            alt = _drop_discovered_instead(D, plan, sel, cur, c, sse_c, settings)
            if alt is not None:
                c, fr = alt
                why = [f"it covers the same structure as the catalogue effect {worst[0]}, which explains the held-out experiments "
                       f"as well (paired t <= {settings.name_t:g}): the catalogue name is kept"]
            elif _catalogue_explains_most(D, plan, sel, cur, c, sse_c, settings):
                protected.add(c)  # the discovered terms after it are corrections of its form, not a different cause
                continue
        sel = [e for e in sel if e != c]
        cur = fr
        t0 = trials.get(c)
        if t0 is not None and t0.evidence is not None:
            ev = t0.evidence
            reasons = ev.reasons + ("explained away by the other accepted terms: " + "; ".join(why),)
            trials[c] = _Trial(c, t0.sse, t0.shape, Evidence(**{**asdict(ev), "passes": False, "reasons": reasons}), t0.fit, t0.signature)


def _drop_discovered_instead(D: FitData, plan: Plan, sel, cur: ModelFit, c: str, sse_c: np.ndarray, settings: DiagnoseSettings):
    """A discovered term accepted after the catalogue term ``c`` to drop instead of ``c`` (its fit), or None.

    The model without the discovered term must explain the held-out experiments as well as the model
    without ``c`` (paired t of the per-experiment CV error <= ``settings.name_t``, and its CV error at
    most ``settings.min_gain`` larger); of those, the one whose removal costs least.
    """
    tr = plan.train
    best = None
    for d in sel[sel.index(c) + 1:]:
        if REGISTRY[d].catalogue:
            continue
        rest = tuple(e for e in sel if e != d)
        fd = fit_model(D, rest, experiments=tr, shapes={e: cur.shapes[e] for e in rest if e in cur.shapes})
        sse_d = _cv_current(D, fd, plan)[3]
        t = _paired_t(sse_d[tr], sse_c[tr])  # > 0: dropping d costs more than dropping c
        extra = float((sse_d[tr].sum() - sse_c[tr].sum()) / max(sse_c[tr].sum(), 1e-300))  # and by this share of the error
        if t <= settings.name_t and extra < settings.min_gain and (best is None or t < best[0]):
            best = (t, d, fd)
    return None if best is None else (best[1], best[2])


def _catalogue_explains_most(D: FitData, plan: Plan, sel, cur: ModelFit, c: str, sse_c: np.ndarray, settings: DiagnoseSettings) -> bool:
    """Whether the catalogue term ``c``, explained away by a discovered term accepted after it, is the main explanation.

    For a discovered term ``d`` accepted after ``c``: without ``d``, ``c`` must remove at least
    ``settings.keep_catalogue_share`` of the grouped-CV error that ``d`` removes without ``c`` (the catalogue
    form explains most of the structure, ``d`` is a correction of its form: a gas curvature with a small
    spring-polynomial correction); then ``c`` keeps its name beside ``d``. A ``d`` that covers other structure
    leaves ``c``'s gain without it near zero and protects nothing.
    """
    later = [d for d in sel[sel.index(c) + 1:] if not REGISTRY[d].catalogue]
    if not later or settings.keep_catalogue_share <= 0:
        return False
    tr = plan.train

    def cv(effects):
        f = fit_model(D, effects, experiments=tr, shapes={e: cur.shapes[e] for e in effects if e in cur.shapes})
        return float(np.nansum(_cv_current(D, f, plan)[3][tr]))

    wo_c = float(np.nansum(sse_c[tr]))
    for d in later:
        neither = cv(tuple(e for e in sel if e not in (c, d)))
        by_c, by_d = neither - cv(tuple(e for e in sel if e != d)), neither - wo_c
        if by_d > 0 and np.isfinite(by_c) and by_c >= settings.keep_catalogue_share * by_d:
            return True
    return False


# ------------------------------------------------------------------ final fits
def _rmse(D, fit: ModelFit, exps) -> float | None:
    if len(exps) == 0:
        return None
    pred = fit.predict(D)
    m = np.isin(D.exp, exps)
    return float(np.sqrt(np.mean((D.y[m] - pred[m]) ** 2)))


def _damping_context(D: FitData, effects, rows, shapes: dict) -> dict | None:
    """The unbiased damping force for models with a term that replaces damping columns (as in selection); else None (automatic)."""
    if any(REGISTRY[e].replaces_damping for e in effects):
        return relief_context(D, tuple(effects), rows, shapes, iters=4)
    return None


def final_fits(D: FitData, plan: Plan, sel, shapes: dict, settings: DiagnoseSettings):
    """Baseline and final model on all experiments; held-out RMS after each accepted term; fold jackknife of shapes.

    Parameters
    ----------
    D : FitData
        The campaign.
    plan : Plan
        Training / held-out experiments and CV folds (:func:`plan_split`).
    sel : sequence of str
        Accepted effect ids, in the order accepted.
    shapes : dict
        Shape parameter per effect id (each in its effect's shape unit).
    settings : DiagnoseSettings
        The diagnosis settings (kept for a uniform stage signature).

    Returns
    -------
    baseline : ModelFit
        Eq. 14 fitted on all experiments.
    final : ModelFit
        Eq. 14 + ``sel`` fitted on all experiments.
    steps : tuple of ModelFit
        Fits on the training experiments after 0, 1, ... accepted terms.
    heldout_steps : tuple of HeldOutStep
        Held-out RMS error (N; None without held-out experiments) after each step.
    shape_se : dict
        Fold-jackknife standard error of each fitted shape parameter, in its unit.
    """
    sel = tuple(sel)
    steps, hsteps = [], []
    for k in range(len(sel) + 1):
        eff = sel[:k]
        sh = {e: shapes[e] for e in eff if e in shapes}
        f = fit_model(D, eff, experiments=plan.train, shapes=sh, ctx=_damping_context(D, eff, plan.train, sh))
        steps.append(f)
        hsteps.append(HeldOutStep("eq. 14" if k == 0 else f"+ {sel[k - 1]}", eff, _rmse(D, f, plan.test)))
    baseline = fit_model(D, ())
    sh = {e: shapes[e] for e in sel if e in shapes}
    final = fit_model(D, sel, shapes=sh, ctx=_damping_context(D, sel, np.arange(D.n_exp), sh)) if sel else baseline
    shape_se: dict[str, float] = {}
    shaped = [e for e in sel if REGISTRY[e].shape is not None]
    if shaped and plan.can_select:
        allx = np.arange(D.n_exp)
        fold_ids = np.unique(plan.folds[plan.folds >= 0])
        vals = {e: [] for e in shaped}
        memo: dict = {}  # the folds' shape searches share their Gram blocks, summed per fold (leave-one-fold-out by summing)
        for f in fold_ids:
            ff = fit_model(D, sel, experiments=np.setdiff1d(allx, allx[plan.folds == f]), ctx=final.ctx, memo=memo, memo_groups=plan.folds)
            for e in shaped:
                vals[e].append(ff.shapes[e])
        k = len(fold_ids)
        for e in shaped:
            z = np.asarray(vals[e], float)
            if REGISTRY[e].log_shape:
                z = np.log(np.clip(z, 1e-300, None))
                shape_se[e] = float(final.shapes[e] * np.sqrt((k - 1) / k * np.sum((z - z.mean()) ** 2)))
            else:
                shape_se[e] = float(np.sqrt((k - 1) / k * np.sum((z - z.mean()) ** 2)))
    return baseline, final, tuple(steps), tuple(hsteps), shape_se
