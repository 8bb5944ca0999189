"""Discrepancy diagnosis: where eq. 14 and the bench disagree, and why.

Answers the four questions of ``shared/specs/diagnosis-report.md``:

1. **Where** — residuals of the baseline (eq. 14) organised by displacement,
   speed, direction, time since reversal, pressure, valve and campaign time,
   against the measurement-noise level (:func:`residual_map`).
2. **What was left out** — forward selection over the catalogue of
   :mod:`vvea_design.identification.effects`. Samples within one run are correlated, so a
   sample-wise AIC/BIC would accept false terms; instead a candidate is
   accepted only if, in *grouped* cross-validation (whole experiments held
   out), it lowers the held-out error
   (a) by at least ``min_gain`` of the mean square,
   (b) consistently: a paired t statistic over held-out experiments of at
   least ``min_t`` -- or, for an effect confined to a few experiments (a
   relief valve that opens only at the highest damping forces), at least
   ``min_halved`` badly fit held-out experiments (RMS above twice the
   noise) whose squared error it halves,
   (c) by a physically meaningful amount: its fitted force contribution has
   an RMS of at least ``min_snr`` times the residual RMS,
   with every amplitude constrained to its physical sign.
3. **Its model** — the fitted parameters with cluster-robust standard errors
   (experiments as clusters) and, for shape parameters, a fold jackknife.
4. **Did it improve** — RMS error on an outer set of experiments that took no
   part in the selection or the fit, before and after. A flexible learner
   (gradient-boosted trees, grouped CV) is then trained on the final
   residuals; where it still predicts them beyond the noise,
   ``unexplained_structure`` is set and the place is named.
"""

from __future__ import annotations

import json
import time
from dataclasses import asdict, dataclass, field
from pathlib import Path

import numpy as np

from .effects import CATALOGUE, EFFECT_IDS, FitData
from .identify import ModelFit, assemble, blocks, fit_model, relief_context, solve_bounded
from .recordings import Recordings

__all__ = [
    "DiagnoseSettings",
    "Diagnosis",
    "diagnose",
    "residual_map",
    "noise_level_N",
    "write_diagnosis",
    "format_summary",
]


@dataclass(frozen=True)
class DiagnoseSettings:
    """Settings of :func:`diagnose` (the defaults are the benchmarked ones)."""

    n_folds: int = 5  #: grouped-CV folds (whole experiments)
    test_fraction: float = 0.2  #: experiments held out of selection and fit
    min_gain: float = 0.02  #: minimum relative reduction of the CV mean square
    min_t: float = 3.0  #: minimum paired t over held-out experiments
    min_halved: int = 1  #: ... or at least this many badly fit (RMS > 2 x noise) held-out experiments with their squared error halved
    min_snr: float = 0.25  #: minimum effect RMS / residual RMS
    max_effects: int = 4  #: at most this many accepted effects
    seed: int = 0  #: seed of the experiment splits
    learner: bool = True  #: run the flexible-learner check
    learner_min_gain: float = 0.10  #: learner must explain this share of residual variance ...
    learner_min_ratio: float = 1.0  #: ... and an RMS of at least this times the noise
    learner_rows: int = 12000  #: rows sub-sampled for the learner
    candidates: tuple = EFFECT_IDS  #: effect ids to test


@dataclass(frozen=True)
class Diagnosis:
    """Result of :func:`diagnose`: the report plus the fitted models."""

    report: dict
    baseline: ModelFit  #: eq. 14 fitted on all experiments
    final: ModelFit  #: eq. 14 + accepted effects fitted on all experiments
    data: FitData = field(repr=False)


# ------------------------------------------------------------------ noise & maps
def noise_level_N(D: FitData, residual_N: np.ndarray) -> float:
    """High-frequency noise level (N): robust std of sample-to-sample residual differences / √2.

    Model misfit is smooth within an experiment and cancels in the
    differences; white measurement noise does not. (For positively
    correlated noise this is a lower bound of the noise RMS.)
    """
    d = []
    for e in range(D.n_exp):
        r = residual_N[D.bounds[e] : D.bounds[e + 1]]
        d.append(np.diff(r))
    d = np.concatenate(d)
    return float(1.4826 * np.median(np.abs(d - np.median(d))) / np.sqrt(2.0))


def _bins(D: FitData):
    """(feature name, unit, labels per sample) for the residual map."""
    out = []
    xb = np.clip(np.digitize(D.x, np.linspace(0, 40, 9)[1:-1]), 0, 7)
    edges = np.linspace(0, 40, 9)
    out.append(("displacement", "mm", np.array([f"{edges[i]:.0f}-{edges[i + 1]:.0f}" for i in range(8)])[xb]))
    sp = D.speed if D.speed is not None else np.round(np.abs(D.v), 1)
    out.append(("speed", "mm/s", np.array([f"{s:g}" for s in sp])))
    out.append(("direction", "", np.where(D.v > 0, "extending", "retracting")))
    te = np.array([0, 0.5, 2, 10, 50, np.inf])
    tl = ["0-0.5", "0.5-2", "2-10", "10-50", "50+"]
    out.append(("time_since_reversal", "s", np.array(tl)[np.clip(np.digitize(D.tsr, te[1:-1]), 0, 4)]))
    out.append(("p2", "MPa", np.array([f"{p:g}" for p in D.p2])))
    out.append(("valve", "deg", np.array([f"{v:g}" for v in D.valve])))
    q = np.quantile(D.ctime, [0.2, 0.4, 0.6, 0.8])
    out.append(("campaign_time", "quintile", np.array(["Q1", "Q2", "Q3", "Q4", "Q5"])[np.digitize(D.ctime, q)]))
    return out


def residual_map(D: FitData, residual_N: np.ndarray, noise_N: float) -> dict:
    """Residuals organised by where they occur.

    Returns ``{feature: [{"bin", "n", "mean_N", "rms_N", "rms_over_noise"}]}``
    for displacement, speed, direction, time since reversal, pressure, valve
    and campaign time.
    """
    out = {}
    for name, unit, lab in _bins(D):
        rows = []
        for b in _ordered(np.unique(lab)):
            m = lab == b
            r = residual_N[m]
            rms = float(np.sqrt(np.mean(r**2)))
            # signed by direction of motion so friction-like residuals do not cancel
            rows.append(
                dict(
                    bin=str(b),
                    n=int(m.sum()),
                    mean_N=float(np.mean(r)),
                    mean_along_motion_N=float(np.mean(r * np.sign(D.v[m]))),
                    rms_N=rms,
                    rms_over_noise=rms / noise_N if noise_N > 0 else float("inf"),
                )
            )
        out[name] = dict(unit=unit, bins=rows)
    return out


def _ordered(labels):
    def key(s):
        try:
            return (0, float(str(s).split("-")[0].rstrip("+").lstrip("Q")))
        except ValueError:
            return (1, str(s))

    return sorted(labels, key=key)


# ------------------------------------------------------------------ CV machinery
def _cv_sse(D, effects, shapes, ctx, new_effect, train, folds, fallback=None):
    """Held-out SSE per experiment (grouped CV over ``train``) for eq.14 + effects (+ new_effect).

    Shapes of ``effects`` are fixed; the new effect's shape is chosen on each
    fold's training part from the effect's grid.
    """
    effs = tuple(effects) + ((new_effect,) if new_effect else ())
    grid = [np.nan]
    if new_effect and CATALOGUE[new_effect].shape is not None:
        grid = list(CATALOGUE[new_effect].grid(D, ctx))
        if not grid:
            return None
    blks = []
    for gval in grid:
        sh = dict(shapes)
        if new_effect:
            sh[new_effect] = float(gval)
        X, params, groups = assemble(D, effs, sh, ctx)
        blks.append((blocks(X, D.y, D.bounds, params), groups.get(new_effect)))
    if new_effect and CATALOGUE[new_effect].damping_mask is not None:
        # the relief valve replaces damping columns, so "no valve" is not nested in
        # its grid: offer it explicitly, each fold keeps whichever trains better
        X, params, _ = assemble(D, tuple(effects), shapes, ctx)
        blks.append((blocks(X, D.y, D.bounds, params), None))
    sse = np.full(D.n_exp, np.nan)
    for f in np.unique(folds[train]):
        tr = train[folds[train] != f]
        te = train[folds[train] == f]
        best = None
        for Bk, sl in blks:
            Gtr = Bk.G[tr].sum(0)
            if sl is not None and not np.all(np.diag(Gtr)[sl] > 0):
                continue  # the effect leaves no trace in this fold's training part
            th = solve_bounded(Gtr, Bk.b[tr].sum(0), Bk.lower, Bk.upper)
            c = Bk.sse(th, tr).sum()
            if best is None or c < best[0]:
                best = (c, th, Bk)
        if best is None:
            sse[te] = fallback[te]  # not identifiable here: predict as without the effect
        else:
            sse[te] = best[2].sse(best[1], te)
    return sse


def _params_json(fit: ModelFit, effect_id: str | None, jack: dict | None = None) -> dict:
    sl = fit.groups["eq14" if effect_id is None else effect_id]
    out = {}
    for q, v, s in zip(fit.params[sl], fit.theta[sl], fit.se[sl]):
        out[q.name] = dict(value=float(v), std_error=float(s), unit=q.unit, meaning=q.meaning)
    if effect_id is not None:
        eff = CATALOGUE[effect_id]
        if eff.shape is not None:
            sv = fit.shapes.get(effect_id, np.nan)
            se = (jack or {}).get(effect_id, np.nan)
            out[eff.shape.name] = dict(
                value=float(sv), std_error=float(se), unit=eff.shape.unit, meaning=eff.shape.meaning + " (fold jackknife s.e.)"
            )
    return out


def _split(D: FitData, settings: DiagnoseSettings):
    """Held-out test experiments and CV folds, stratified by valve position.

    Every valve keeps about ``1 - test_fraction`` of its experiments for
    training and each CV fold's training part holds ``(k-1)/k`` of them, so
    no fold has to predict a valve whose damping it never saw.
    """
    rng = np.random.default_rng(settings.seed)
    valve_of = D.valve[D.bounds[:-1]]
    test, folds = [], np.full(D.n_exp, -1)
    for v in np.unique(valve_of):
        exps = rng.permutation(np.flatnonzero(valve_of == v))
        n_test = int(np.floor(settings.test_fraction * len(exps) + rng.uniform()))
        n_test = min(n_test, max(len(exps) - settings.n_folds, 0))
        test += list(exps[:n_test])
        rest = exps[n_test:]
        folds[rest] = (rng.integers(settings.n_folds) + np.arange(len(rest))) % settings.n_folds
    test = np.sort(np.array(test, dtype=int))
    train = np.sort(np.setdiff1d(np.arange(D.n_exp), test))
    return train, test, folds


def _rmse(D, fit, exps) -> float:
    pred = fit.predict(D)
    m = np.isin(D.exp, exps)
    return float(np.sqrt(np.mean((D.y[m] - pred[m]) ** 2)))


# ------------------------------------------------------------------ learner check
def _learner_check(D: FitData, residual: np.ndarray, noise_N: float, settings: DiagnoseSettings) -> dict:
    from sklearn.ensemble import HistGradientBoostingRegressor
    from sklearn.model_selection import GroupKFold
    from threadpoolctl import threadpool_limits

    with threadpool_limits(limits=1):  # one thread: predictable on a shared 2-core machine and inside parallel_map
        return _learner_check_inner(D, residual, noise_N, settings, HistGradientBoostingRegressor, GroupKFold)


def _learner_check_inner(D, residual, noise_N, settings, HistGradientBoostingRegressor, GroupKFold) -> dict:
    feats = np.column_stack([D.x, D.v, np.abs(D.v), np.sign(D.v), np.log10(D.tsr + 1e-3), D.p2, D.valve, D.ctime])
    names = ["displacement", "velocity", "speed", "direction", "time_since_reversal", "p2", "valve", "campaign_time"]
    rng = np.random.default_rng(settings.seed + 1)
    idx = np.arange(D.n)
    if D.n > settings.learner_rows:
        idx = np.sort(rng.choice(D.n, settings.learner_rows, replace=False))
    Xf, r, g = feats[idx], residual[idx], D.exp[idx]
    pred = np.zeros(len(idx))
    importance = np.zeros(len(names))
    prng = np.random.default_rng(settings.seed + 2)
    for tr, te in GroupKFold(n_splits=min(5, len(np.unique(g)))).split(Xf, r, g):
        m = HistGradientBoostingRegressor(max_iter=100, learning_rate=0.15, max_leaf_nodes=15, min_samples_leaf=40, random_state=settings.seed)
        m.fit(Xf[tr], r[tr])
        pred[te] = m.predict(Xf[te])
        base = np.mean((r[te] - pred[te]) ** 2)
        for j in range(len(names)):  # permutation importance on the held-out fold
            Xp = Xf[te].copy()
            Xp[:, j] = prng.permutation(Xp[:, j])
            importance[j] += (np.mean((r[te] - m.predict(Xp)) ** 2) - base) * len(te)
    importance /= len(idx)
    mse0 = float(np.mean(r**2))
    mse1 = float(np.mean((r - pred) ** 2))
    gain = 1.0 - mse1 / mse0 if mse0 > 0 else 0.0
    explained_rms = float(np.sqrt(max(mse0 - mse1, 0.0)))
    flag = bool(gain >= settings.learner_min_gain and explained_rms >= settings.learner_min_ratio * noise_N)
    # where: the features the learner relies on (permutation importance) and,
    # along each, the bin where its held-out prediction is largest (RMS)
    where = []
    for j in np.argsort(-importance):
        col = Xf[:, j]
        uq = np.unique(col)
        lab = col if len(uq) <= 12 else np.digitize(col, np.quantile(col, np.linspace(0, 1, 9)[1:-1]))
        best = (0.0, None)
        for b in np.unique(lab):
            mm = lab == b
            rms = float(np.sqrt(np.mean(pred[mm] ** 2)))
            if rms > best[0]:
                lo, hi = float(col[mm].min()), float(col[mm].max())
                if names[j] == "time_since_reversal":
                    lo, hi = 10**lo - 1e-3, 10**hi - 1e-3
                best = (rms, (lo, hi))
        where.append(
            dict(
                feature=names[j],
                importance_share=float(importance[j] / mse0) if mse0 > 0 else 0.0,
                largest_structure_rms_N=best[0],
                range=best[1],
            )
        )
    return dict(
        model="HistGradientBoostingRegressor on residuals, 5-fold GroupKFold by experiment",
        rows=int(len(idx)),
        heldout_variance_explained=gain,
        explained_rms_N=explained_rms,
        noise_N=noise_N,
        flag=flag,
        where=[w for k, w in enumerate(where) if k == 0 or w["importance_share"] >= 0.05][:3],
    )


# ------------------------------------------------------------------ main entry
def diagnose(rec: Recordings | FitData, settings: DiagnoseSettings = DiagnoseSettings(), progress=None) -> Diagnosis:
    """Diagnose the discrepancy between eq. 14 and a campaign.

    Parameters
    ----------
    rec : Recordings or FitData
        The campaign (a :class:`FitData` skips the reader).
    settings : DiagnoseSettings
    progress : callable, optional
        ``progress(message)`` called at each step (e.g. to update a spinner).

    Returns
    -------
    Diagnosis
        ``report`` holds the contract keys of the spec (``baseline``,
        ``heldout_rmse_N``, ``effects``, ``unexplained_structure``) and the
        evidence behind them.
    """
    t0 = time.perf_counter()
    say = progress or (lambda msg: None)
    D = rec if isinstance(rec, FitData) else FitData.from_recordings(rec)
    train, test, folds = _split(D, settings)
    cands = [c for c in settings.candidates if c in CATALOGUE]

    say("baseline eq. 14")
    base_train = fit_model(D, (), experiments=train)
    sel: list[str] = []
    cur = base_train
    evidence: dict[str, dict] = {}
    trial_fits: dict[str, ModelFit] = {}
    rounds = []
    for rnd in range(settings.max_effects):
        ctx = cur._ctx_for(D) if "relief_valve" in cur.effects else {"damping_force_N": cur.damping_force(D)}
        base_sse = _cv_sse(D, cur.effects, cur.shapes, ctx, None, train, folds)
        noise_round = noise_level_N(D, D.y - cur.predict(D))
        resid_rms = float(np.sqrt(np.nansum(base_sse) / D.bounds[-1]))
        cand_rows = []
        for c in cands:
            if c in sel:
                continue
            say(f"round {rnd + 1}: testing {c}")
            ctx_c = relief_context(D, cur.effects + (c,), train, cur.shapes, start=ctx) if c == "relief_valve" else ctx
            new_sse = _cv_sse(D, cur.effects, cur.shapes, ctx_c, c, train, folds, fallback=base_sse)
            if new_sse is None:
                ev = dict(cv_gain=0.0, paired_t=0.0, folds_improved=0, snr=0.0, note="not applicable to this campaign")
                evidence[c] = dict(ev, round=rnd + 1)
                continue
            d = base_sse[train] - new_sse[train]
            gain = float(d.sum() / base_sse[train].sum())
            sd = float(np.std(d, ddof=1))
            t = float(np.mean(d) / sd * np.sqrt(len(d))) if sd > 0 else 0.0
            fold_gain = [float((base_sse[train][folds[train] == f] - new_sse[train][folds[train] == f]).sum()) for f in range(settings.n_folds)]
            fit_c = fit_model(D, cur.effects + (c,), experiments=train, shapes=cur.shapes, ctx=ctx_c)
            contrib = fit_c.contribution(D, c)
            mtr = np.isin(D.exp, train)
            res_c = D.y[mtr] - fit_c.predict(D)[mtr]
            snr = float(np.sqrt(np.mean(contrib[mtr] ** 2)) / np.sqrt(np.mean(res_c**2)))
            ratio = new_sse[train] / np.maximum(base_sse[train], 1e-300)
            badly_fit = base_sse[train] / D.n_per_exp[train] > (2.0 * noise_round) ** 2
            n_halved = int(np.sum((ratio < 0.5) & badly_fit))
            ev = dict(
                cv_gain=gain,
                paired_t=t,
                experiments_halved=n_halved,
                folds_improved=int(sum(g > 0 for g in fold_gain)),
                snr=snr,
                effect_rms_N=float(np.sqrt(np.mean(contrib[mtr] ** 2))),
                residual_rms_N=float(np.sqrt(np.mean(res_c**2))),
            )
            consistent = t >= settings.min_t or n_halved >= settings.min_halved
            ok = gain >= settings.min_gain and consistent and snr >= settings.min_snr
            reasons = []
            if gain < settings.min_gain:
                reasons.append(f"held-out error falls by {100 * gain:.2f} % < {100 * settings.min_gain:.1f} %")
            if not consistent:
                reasons.append(
                    f"paired t over held-out experiments {t:.1f} < {settings.min_t:g} and only {n_halved} "
                    f"badly fit held-out experiments have their error halved (< {settings.min_halved})"
                )
            if snr < settings.min_snr:
                reasons.append(f"effect RMS {snr:.2f} x residual < {settings.min_snr:g}")
            ev["passes"] = bool(ok)
            ev["reasons"] = reasons
            evidence[c] = dict(ev, round=rnd + 1)
            trial_fits[c] = fit_c
            cand_rows.append((c, ok, gain))
        passing = [(c, g) for c, ok, g in cand_rows if ok]
        rounds.append(dict(round=rnd + 1, selected=list(sel), cv_rmse_N=resid_rms, candidates={c: evidence[c] for c, _, _ in cand_rows}))
        if not passing:
            break
        best = max(passing, key=lambda z: z[1])[0]
        sel.append(best)
        evidence[best]["accepted_in_round"] = rnd + 1
        cur = fit_model(D, tuple(sel), experiments=train)
        rounds[-1]["accepted"] = best

    say("final fits")
    final_train = fit_model(D, tuple(sel), experiments=train) if sel else base_train
    heldout = dict(baseline=_rmse(D, base_train, test), final=_rmse(D, final_train, test))
    allx = np.arange(D.n_exp)
    baseline = fit_model(D, ())
    final = fit_model(D, tuple(sel)) if sel else baseline
    # fold jackknife for shape parameters
    jack: dict[str, float] = {}
    shaped = [e for e in sel if CATALOGUE[e].shape is not None]
    if shaped:
        vals = {e: [] for e in shaped}
        for f in range(settings.n_folds):
            ff = fit_model(D, tuple(sel), experiments=np.setdiff1d(allx, allx[folds == f]))
            for e in shaped:
                vals[e].append(ff.shapes[e])
        k = settings.n_folds
        for e in shaped:
            z = np.log(vals[e])
            jack[e] = float(final.shapes[e] * np.sqrt((k - 1) / k * np.sum((z - z.mean()) ** 2)))
    res_b = D.y - baseline.predict(D)
    res_f = D.y - final.predict(D)
    noise = noise_level_N(D, res_f)
    say("flexible-learner check")
    learner = _learner_check(D, res_f, noise, settings) if settings.learner else dict(flag=False, note="skipped")

    # worst experiments (baseline) and their state after
    per_exp = []
    for e in range(D.n_exp):
        a, b = D.bounds[e], D.bounds[e + 1]
        per_exp.append(
            dict(
                exp_index=e,
                p2_MPa=float(D.p2[a]),
                valve_deg=float(D.valve[a]),
                speed_mm_s=float(D.speed[a]) if D.speed is not None else float(np.max(np.abs(D.v[a:b]))),
                rms_baseline_N=float(np.sqrt(np.mean(res_b[a:b] ** 2))),
                rms_final_N=float(np.sqrt(np.mean(res_f[a:b] ** 2))),
            )
        )
    names = getattr(rec, "experiments", None)
    if names is not None:
        for row, nm in zip(per_exp, names["experiment"]):
            row["experiment"] = str(nm)
    worst = sorted(per_exp, key=lambda r: -r["rms_baseline_N"])[:8]

    effects = []
    for c in cands:
        eff = CATALOGUE[c]
        acc = c in sel
        fitc = final if acc else trial_fits.get(c)
        ev = evidence.get(c, {})
        if acc:
            expl = f"Accepted: {eff.physics}"
        else:
            expl = "Not accepted: " + ("; ".join(ev.get("reasons", [])) or ev.get("note", "not tested")) + "."
        effects.append(
            dict(
                id=c,
                accepted=acc,
                title=eff.title,
                explanation=expl,
                physics=eff.physics,
                equation=eff.equation,
                parameters=_params_json(fitc, c, jack if acc else None) if fitc is not None and c in fitc.groups else {},
                evidence=ev,
            )
        )
    report = dict(
        source=getattr(rec, "source", "<data>"),
        rows_read=int(D.n + D.rows_left_out),
        rows_used=int(D.n),
        rows_left_out=int(D.rows_left_out),
        rows_left_out_reason="samples at rest (start, turning point, end): friction is set-valued there",
        n_experiments=int(D.n_exp),
        noise_N=dict(value=noise, method="robust std of sample-to-sample differences of the final residuals / sqrt(2)"),
        baseline=dict(
            model="eq14: f = g p2 x + L(gamma) xdot + C sign(xdot)",
            parameters=_params_json(baseline, None),
            rmse_N=baseline.rmse_N,
        ),
        final_model=dict(
            model="eq14 + " + " + ".join(sel) if sel else "eq14",
            effects=list(sel),
            parameters={k: v for e in ("eq14",) + tuple(sel) for k, v in _params_json(final, None if e == "eq14" else e, jack).items()},
            rmse_N=final.rmse_N,
        ),
        heldout_rmse_N=heldout,
        heldout=dict(
            method=f"{len(test)} experiments (~{100 * settings.test_fraction:.0f} % of each valve, seed {settings.seed}) held out of selection and fitting",
            test_experiments=[int(e) for e in test],
        ),
        effects=effects,
        unexplained_structure=bool(learner.get("flag", False)),
        unexplained_where=learner.get("where", []) if learner.get("flag", False) else [],
        learner=learner,
        where=dict(baseline=residual_map(D, res_b, noise), final=residual_map(D, res_f, noise), worst_experiments=worst),
        selection=dict(settings=asdict(settings), rounds=rounds),
        runtime_s=time.perf_counter() - t0,
    )
    return Diagnosis(report=_jsonable(report), baseline=baseline, final=final, data=D)


def _jsonable(o):
    if isinstance(o, dict):
        return {str(k): _jsonable(v) for k, v in o.items()}
    if isinstance(o, (list, tuple)):
        return [_jsonable(v) for v in o]
    if isinstance(o, (np.floating, float)):
        v = float(o)
        return v if np.isfinite(v) else None
    if isinstance(o, (np.integer,)):
        return int(o)
    if isinstance(o, np.bool_):
        return bool(o)
    if isinstance(o, np.ndarray):
        return _jsonable(o.tolist())
    return o


# ------------------------------------------------------------------ output
def format_summary(report: dict) -> str:
    """A summary an engineer can read (Markdown)."""
    L = []
    noise = report["noise_N"]["value"] or 0.0
    L.append(f"# Diagnosis of {report['source']}")
    L.append("")
    L.append(
        f"{report['n_experiments']} experiments, {report['rows_used']} samples used, "
        f"{report['rows_left_out']} left out ({report['rows_left_out_reason']}). Noise level {noise:.1f} N."
    )
    L.append("")
    L.append("## Where eq. 14 and the bench disagree")
    wm = report["where"]["baseline"]
    L.append(f"Baseline RMS residual {report['baseline']['rmse_N']:.1f} N = {report['baseline']['rmse_N'] / max(noise, 1e-9):.1f} x noise.")
    for feat, block in wm.items():
        bins = block["bins"]
        worst = max(bins, key=lambda b: b["rms_N"])
        L.append(f"- by {feat}: largest in {worst['bin']} {block['unit']} (RMS {worst['rms_N']:.1f} N, mean along motion {worst['mean_along_motion_N']:+.1f} N)")
    w = report["where"]["worst_experiments"][:3]
    L.append("- worst experiments: " + "; ".join(
        f"{r.get('experiment', r['exp_index'])} (p2 {r['p2_MPa']:g} MPa, valve {r['valve_deg']:g} deg, {r['speed_mm_s']:g} mm/s): "
        f"{r['rms_baseline_N']:.0f} -> {r['rms_final_N']:.0f} N" for r in w))
    L.append("")
    L.append("## What was left out")
    acc = [e for e in report["effects"] if e["accepted"]]
    if not acc:
        L.append("No candidate effect passed grouped cross-validation: eq. 14 explains the recordings to within the noise it can resolve.")
    for e in acc:
        ev = e["evidence"]
        L.append(f"### {e['id']} — {e['title']}")
        L.append(e["physics"])
        L.append(f"Model: `{e['equation']}`")
        for k, v in e["parameters"].items():
            L.append(f"- {k} = {v['value']:.4g} ± {v['std_error'] if v['std_error'] is not None else float('nan'):.2g} {v['unit']}")
        L.append(
            f"Evidence: held-out mean square -{100 * ev['cv_gain']:.1f} %, paired t = {ev['paired_t']:.1f}, "
            f"improves {ev['folds_improved']} of {report['selection']['settings']['n_folds']} folds, effect RMS = {ev['snr']:.2f} x residual."
        )
    rej = [e for e in report["effects"] if not e["accepted"]]
    if rej:
        L.append("")
        L.append("Tested and rejected: " + "; ".join(f"{e['id']} ({e['explanation'][len('Not accepted: '):].rstrip('.')})" for e in rej))
    L.append("")
    L.append("## Did the fit improve where it was not trained?")
    h = report["heldout_rmse_N"]
    L.append(f"Held-out RMS error: {h['baseline']:.1f} N (eq. 14) -> {h['final']:.1f} N ({report['heldout']['method']}).")
    if report["unexplained_structure"]:
        w = report["unexplained_where"]
        L.append(
            "**Structure remains** that no candidate explains: a flexible learner predicts "
            f"{100 * report['learner']['heldout_variance_explained']:.0f} % of the held-out residual variance, mostly along "
            + ", ".join(
                f"{x['feature']} ({100 * x['importance_share']:.0f} % of residual variance; largest at "
                f"{x['range'][0]:.3g}..{x['range'][1]:.3g}: {x['largest_structure_rms_N']:.1f} N RMS)"
                for x in w
            )
            + ".\n  Eq. 14 with the accepted effects is not the whole story there: add physics before trusting the model in that region."
        )
    else:
        lv = report["learner"].get("heldout_variance_explained")
        L.append(
            "No structure remains beyond noise"
            + (f" (a flexible learner explains {100 * lv:.1f} % of held-out residual variance)." if lv is not None else ".")
        )
    return "\n".join(L) + "\n"


def _plot_maps(report: dict, path: Path) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    mb, mf = report["where"]["baseline"], report["where"]["final"]
    noise = report["noise_N"]["value"] or 0.0
    feats = list(mb)
    fig, axes = plt.subplots(2, 4, figsize=(15, 6.5))
    for ax, feat in zip(axes.flat, feats):
        bb, bf = mb[feat]["bins"], mf[feat]["bins"]
        lab = [b["bin"] for b in bb]
        xi = np.arange(len(lab))
        ax.bar(xi - 0.2, [b["rms_N"] for b in bb], 0.4, label="eq. 14", color="C3")
        ax.bar(xi + 0.2, [b["rms_N"] for b in bf], 0.4, label="final", color="C2")
        ax.axhline(noise, color="k", ls="--", lw=0.8, label="noise")
        ax.set_xticks(xi, lab, rotation=45, fontsize=7)
        ax.set_title(f"{feat} [{mb[feat]['unit']}]", fontsize=9)
        ax.set_ylabel("RMS residual [N]", fontsize=8)
        ax.set_yscale("log")
    axes.flat[0].legend(fontsize=7)
    ax = axes.flat[-1]
    ax.axis("off")
    acc = [e["id"] for e in report["effects"] if e["accepted"]]
    h = report["heldout_rmse_N"]
    ax.text(0, 0.9, "accepted: " + (", ".join(acc) or "none"), fontsize=9, transform=ax.transAxes)
    ax.text(0, 0.75, f"held-out RMS: {h['baseline']:.1f} N -> {h['final']:.1f} N", fontsize=9, transform=ax.transAxes)
    ax.text(0, 0.6, f"unexplained structure: {report['unexplained_structure']}", fontsize=9, transform=ax.transAxes)
    fig.suptitle("Where the model and the recordings disagree: residual RMS before (eq. 14) and after")
    fig.tight_layout()
    fig.savefig(path, dpi=80)
    plt.close(fig)


def _plot_worst(diag: Diagnosis, path: Path) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    D = diag.data
    fb, ff = diag.baseline.predict(D), diag.final.predict(D)
    worst = diag.report["where"]["worst_experiments"][:4]
    fig, axes = plt.subplots(2, len(worst), figsize=(4 * len(worst), 6), squeeze=False, gridspec_kw={"height_ratios": [2, 1]})
    for j, w in enumerate(worst):
        e = w["exp_index"]
        a, b = D.bounds[e], D.bounds[e + 1]
        ax, axr = axes[0, j], axes[1, j]
        ax.plot(D.x[a:b], D.y[a:b], ".", ms=2, color="0.4", label="measured")
        ax.plot(D.x[a:b], fb[a:b], "-", color="C3", lw=1, label="eq. 14")
        ax.plot(D.x[a:b], ff[a:b], "-", color="C2", lw=1, label="final")
        ax.set_title(f"{w.get('experiment', e)}: p2 {w['p2_MPa']:g} MPa, γ {w['valve_deg']:g}°, {w['speed_mm_s']:g} mm/s", fontsize=8)
        axr.plot(D.x[a:b], D.y[a:b] - fb[a:b], color="C3", lw=0.8)
        axr.plot(D.x[a:b], D.y[a:b] - ff[a:b], color="C2", lw=0.8)
        axr.set_xlabel("x [mm]")
        if j == 0:
            ax.set_ylabel("force [N]")
            axr.set_ylabel("residual [N]")
            ax.legend(fontsize=7)
    fig.suptitle("Worst experiments of eq. 14, before and after the accepted effects")
    fig.tight_layout()
    fig.savefig(path, dpi=80)
    plt.close(fig)


def write_diagnosis(diag: Diagnosis, out_dir: str | Path) -> list[str]:
    """Write ``report.json``, ``summary.md``, ``residual_maps.png``, ``worst_experiments.png``.

    Returns the list of file names written.
    """
    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    (out / "report.json").write_text(json.dumps(diag.report, indent=1))
    (out / "summary.md").write_text(format_summary(diag.report))
    _plot_maps(diag.report, out / "residual_maps.png")
    _plot_worst(diag, out / "worst_experiments.png")
    return ["report.json", "summary.md", "residual_maps.png", "worst_experiments.png"]
