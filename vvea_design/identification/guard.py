"""The held-out guard: a term stays accepted only if it lowers the error on experiments held out of everything.

Forward selection (:mod:`.selection`) judges terms by grouped cross-validation over the training
experiments. The guard then replays the accepted terms, in the order accepted, on the experiments
held out of selection and fitting (``plan.test``):

- each term is fitted beside the terms kept before it, on the training experiments only, and kept
  only if the held-out RMS falls (by at least ``settings.guard_min_drop_N``, and the new RMS is finite);
- a catalogue term is kept only if its own physical signature checks pass on that fit (a check that
  fails un-accepts the term instead of only being printed);

so the final model is never worse on the held-out experiments than eq. 14 alone. Every term the
guard removes gets its reason appended to its evidence (``passes`` set to False).

Residual sign: residual = measurement − model (N).
"""

from __future__ import annotations

from dataclasses import asdict

import numpy as np

from .effects import REGISTRY
from .fit_data import FitData
from .fitting import ModelFit, fit_model, relief_context
from .report import Evidence

__all__ = ["heldout_rmse", "heldout_guard", "unaccept"]


def heldout_rmse(D: FitData, fit: ModelFit, exps) -> float | None:
    """RMS error (N) of ``fit`` on the experiments ``exps`` (None when there are none; inf when not finite).

    Parameters
    ----------
    D : FitData
        The campaign.
    fit : ModelFit
        A fitted model.
    exps : array_like of int
        Experiment indices (0 .. n_exp-1, dimensionless).

    Returns
    -------
    float or None
        Root mean square of measurement − model over those experiments' samples, N.
    """
    if len(exps) == 0:
        return None
    m = np.isin(D.exp, exps)
    r = D.y[m] - fit.predict(D)[m]
    v = float(np.sqrt(np.mean(r**2)))
    return v if np.isfinite(v) else float("inf")


def unaccept(trials: dict, eid: str, reason: str) -> None:
    """Mark the trial of ``eid`` as not passing, with ``reason`` appended to its evidence (in place).

    Parameters
    ----------
    trials : dict
        Per candidate id its last trial (``selection._Trial``).
    eid : str
        Effect id.
    reason : str
        Sentence saying why the term is no longer accepted.
    """
    t0 = trials.get(eid)
    if t0 is None or t0.evidence is None:
        return
    ev = t0.evidence
    trials[eid] = type(t0)(t0.id, t0.sse, t0.shape, Evidence(**{**asdict(ev), "passes": False, "reasons": ev.reasons + (reason,)}),
                           t0.fit, t0.signature)


def _fit_train(D: FitData, effects: tuple, shapes: dict, train) -> ModelFit:
    sh = {e: shapes[e] for e in effects if e in shapes}
    ctx = relief_context(D, effects, train, sh, iters=4) if any(REGISTRY[e].replaces_damping for e in effects) else None
    return fit_model(D, effects, experiments=train, shapes=sh, ctx=ctx)


def failed_checks(D: FitData, fit: ModelFit, eid: str) -> list:
    """The physical signature checks of the catalogue term ``eid`` that fail on ``fit`` (empty for discovery terms).

    Parameters
    ----------
    D : FitData
        The campaign.
    fit : ModelFit
        A model holding ``eid``.
    eid : str
        Effect id.

    Returns
    -------
    list of Check
        The failing checks.
    """
    eff = REGISTRY[eid]
    if not eff.catalogue:
        return []
    sig = eff.signature(D, fit.effect_values(eid), fit.shapes.get(eid, np.nan), fit.contribution(D, eid))
    return [c for c in sig if not c.passed]


def heldout_guard(D: FitData, plan, sel, shapes: dict, trials: dict, min_drop_N: float = 0.0):
    """Replay the accepted terms on the held-out experiments; keep those that lower the held-out RMS and pass their checks.

    Parameters
    ----------
    D : FitData
        The campaign.
    plan : Plan
        ``train`` and ``test`` experiments (:func:`~vvea_design.identification.selection.plan_split`).
    sel : sequence of str
        Accepted effect ids, in the order accepted.
    shapes : dict
        Shape parameter per effect id, in each effect's shape unit.
    trials : dict
        Per candidate id its last trial; a removed term's evidence gets the reason (in place).
    min_drop_N : float
        A term must lower the held-out RMS by more than this, N.

    Returns
    -------
    kept : list of str
        The terms kept, in order.
    removed : dict
        Removed id -> reason (sentence).
    """
    sel = list(sel)
    if not sel or len(plan.test) == 0:
        return sel, {}
    kept: list[str] = []
    removed: dict[str, str] = {}
    cur = heldout_rmse(D, fit_model(D, (), experiments=plan.train), plan.test)
    for eid in sel:
        cand = tuple(kept) + (eid,)
        try:
            fit = _fit_train(D, cand, shapes, plan.train)
            new = heldout_rmse(D, fit, plan.test)
        except (np.linalg.LinAlgError, ValueError, FloatingPointError) as exc:  # a fit that fails numerically is no evidence
            removed[eid] = f"held-out guard: its fit beside {', '.join(kept) or 'eq. 14'} failed numerically ({type(exc).__name__})"
            continue
        if not np.isfinite(new) or new > 1e6 * max(cur, 1e-9):
            removed[eid] = f"held-out guard: its fit beside {', '.join(kept) or 'eq. 14'} blows up numerically (held-out RMS {new:.3g} N)"
            continue
        if not new < cur - min_drop_N:
            removed[eid] = (f"held-out guard: beside {', '.join(kept) or 'eq. 14'} it does not lower the error on the held-out experiments "
                            f"({cur:.3g} N without it, {new:.3g} N with it)")
            continue
        bad = failed_checks(D, fit, eid)
        if bad:
            removed[eid] = "its own physical signature check fails beside the other kept terms: " + "; ".join(c.detail for c in bad)
            continue
        kept.append(eid)
        cur = new
    for eid, why in removed.items():
        unaccept(trials, eid, why)
    return kept, removed
