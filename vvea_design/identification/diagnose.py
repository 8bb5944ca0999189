"""Discrepancy diagnosis: where eq. 14 and the bench disagree, what was left out, its model, the held-out gain.

Answers the four questions of ``shared/specs/diagnosis-report.md`` in named
stages; :func:`diagnose` only chains them, :func:`write_diagnosis` writes
the files:

1. **Plan** (:func:`~vvea_design.identification.selection.plan_split`) --
   experiments held out of everything and grouped-CV folds over the rest.
2. **Noise floor** (:func:`~vvea_design.identification.noise.noise_floor_N`)
   -- what no smooth model of the cycle can explain.
3. **Selection** (:func:`~vvea_design.identification.selection.select_effects`)
   -- forward selection over the effect registry
   (:mod:`~vvea_design.identification.effects`) in grouped
   cross-validation, naming discipline, backward step.
4. **Final fits** (:func:`~vvea_design.identification.selection.final_fits`)
   -- all experiments, cluster-robust errors, fold jackknife for shape
   parameters, held-out RMS after each accepted term.
5. **Held-out guard** (:func:`~vvea_design.identification.guard.heldout_guard`)
   -- each accepted term is kept only if it lowers the error on the
   held-out experiments and (catalogue terms) passes its own signature
   checks; the final model is never worse there than eq. 14.
6. **Leftover check** (:func:`~vvea_design.identification.noise.learner_check`)
   -- gradient-boosted trees on the final residuals; ``unexplained_structure``
   when they still predict them beyond the noise floor, or the held-out error
   stays above twice the floor; the report then says where.

The report (:mod:`~vvea_design.identification.report`) is typed;
:func:`load_final_model` reads the final model back. Residual sign:
residual = measurement − model (N), on every axis and in every table.
"""

from __future__ import annotations

import json
import time
from pathlib import Path

from ..spring.gas_spring import GasSpring
from ..spring.paper import PAPER_FIG5
from .fit_data import REFERENCE_NOTE, REST_REASON, FitData
from .fitting import fit_model
from .general import noise_upper_bound
from .guard import failed_checks, heldout_guard, unaccept
from .last_stage import RESIDUAL_ID, fit_last_stage
from .noise import NOISE_METHOD, learner_check, noise_floor_N, residual_map
from .plots import plot_heldout_steps, plot_residual_maps, plot_worst
from .recordings import Recordings
from .report import (
    Diagnosis,
    DiagnosisReport,
    EffectReport,
    HeldOut,
    HeldOutStep,
    LearnerCheck,
    effect_reports,
    format_summary,
    load_final_model,
    make_final_model,
    param_estimates,
    where_sentences,
    worst_experiments,
)
from .selection import final_fits, plan_split, select_effects
from .settings import DiagnoseSettings

#: The diagnosis's public face: its entry points, and the settings, results and readers they use (defined in
#: :mod:`.settings` and :mod:`.report`).
__all__ = ["DiagnoseSettings", "Diagnosis", "DiagnosisReport", "diagnose", "write_diagnosis", "format_summary",
           "load_final_model"]


def diagnose(
    rec: Recordings | FitData,
    settings: DiagnoseSettings = DiagnoseSettings(),
    progress=None,
    reference: GasSpring | None = None,
) -> Diagnosis:
    """Diagnose the discrepancy between eq. 14 and a campaign.

    Parameters
    ----------
    rec : Recordings or FitData
        The campaign (a :class:`FitData` skips the reader and carries its own reference).
    settings : DiagnoseSettings
    progress : callable, optional
        ``progress(message)`` called at each step (e.g. to update a spinner).
    reference : GasSpring, optional
        The unit's gas spring (from its design file): its areas, V1, V2 and
        travel shape the gas terms. Default: the paper's Fig. 5 unit.

    Returns
    -------
    Diagnosis
        ``report`` is a :class:`DiagnosisReport` (``to_dict()`` is the JSON of
        the spec); ``baseline`` and ``final`` the fitted models.
    """
    from threadpoolctl import threadpool_limits

    # one BLAS thread: the fits are many small solves and stacked products, which threads only make contend
    # (on a shared 2-core machine two threads cost ~20 % more CPU for the same wall time)
    with threadpool_limits(limits=1):
        return _diagnose(rec, settings, progress, reference)


def _diagnose(rec, settings, progress, reference) -> Diagnosis:
    t0 = time.perf_counter()
    say = progress or (lambda msg: None)
    if isinstance(rec, FitData):
        D = rec
    else:
        D = FitData.from_recordings(rec, reference=reference or PAPER_FIG5)
    ref_note = REFERENCE_NOTE if (reference is None and D.reference == PAPER_FIG5) else (
        f"the unit's design: A1 = {D.reference.A1_mm2:.0f} mm^2, A2 = {D.reference.A2_mm2:.0f} mm^2, V1 = {D.reference.V1_mm3:.4g} mm^3, "
        f"V2 = {D.reference.V2_mm3:.4g} mm^3, travel {D.reference.travel_mm:g} mm")
    plan = plan_split(D, settings)
    say("baseline eq. 14 and noise floor")
    base_train = fit_model(D, (), experiments=plan.train)
    noise0 = noise_floor_N(D, D.y - base_train.predict(D))
    # sharp structure must not pass for noise: eq. 14 + trees on the states bound it (held-out RMS)
    bound = noise_upper_bound(D, plan, int(settings.seed)) if settings.noise_bound and plan.can_select else float("inf")
    noise0 = min(noise0, bound)
    say("selection")
    sel, shapes, trials = select_effects(D, plan, noise0, settings, say)
    say("held-out guard and final fits")
    for _ in range(len(sel) + 1):
        sel, _removed = heldout_guard(D, plan, sel, shapes, trials, settings.guard_min_drop_N)
        baseline, final, steps, hsteps, shape_se = final_fits(D, plan, sel, shapes, settings)
        # a catalogue term whose own signature check fails on the final fit is not accepted
        bad = {e: c for e in sel if (c := failed_checks(D, final, e))}
        for e, checks in bad.items():
            unaccept(trials, e, "its own physical signature check fails on the final fit: " + "; ".join(c.detail for c in checks))
        if not bad:
            break
        sel = [e for e in sel if e not in bad]
    res_b = D.y - baseline.predict(D)
    res_f = D.y - final.predict(D)
    noise = min(noise_floor_N(D, res_f), bound)
    held = HeldOut(
        len(plan.test) > 0, hsteps[0].rmse_N, hsteps[-1].rmse_N, hsteps, tuple(int(e) for e in plan.test),
        f"{len(plan.test)} experiments (~{100 * settings.test_fraction:.0f} % of each valve, seed {settings.seed}) held out of selection and fitting"
        if len(plan.test) else "no experiment could be held out",
    )
    say("flexible-learner check")
    learner = learner_check(D, res_f, noise, settings) if settings.learner else LearnerCheck(False, False, note="skipped (--no-learner)")
    say("last stage")
    last = fit_last_stage(D, plan, steps[-1], final, noise, settings, learner)
    if last.accepted:
        # what the stage leaves on held-out experiments bounds the noise too (a floor inflated by sharp structure is revised)
        noise = min(noise, last.heldout_after_N) if last.heldout_after_N is not None and last.heldout_after_N > 0 else noise
        hsteps = hsteps + (HeldOutStep(f"+ {RESIDUAL_ID}", tuple(sel) + (RESIDUAL_ID,), last.heldout_after_N),)
        held = HeldOut(held.assessable, held.baseline_N, last.heldout_after_N, hsteps, held.test_experiments, held.method)
    where_b, where_f = residual_map(D, res_b, noise), residual_map(D, res_f, noise)
    effects = effect_reports(D, sel, trials, final, shape_se, hsteps, plan, settings) + _last_stage_report(last)
    where_txt = where_sentences(learner, where_f, noise, held)
    above = bool(held.assessable and held.final_N is not None and held.final_N > 2.0 * noise)
    # the learner looks at the parametric residual: once a last stage models it, only the held-out error tells what is left
    unexplained = above if last.accepted else bool(learner.flag or above)
    report = DiagnosisReport(
        source=getattr(rec, "source", "<data>"),
        reference=ref_note,
        n_experiments=int(D.n_exp),
        rows_read=int(D.n + D.rows_left_out),
        rows_used=int(D.n),
        rows_left_out=int(D.rows_left_out),
        rows_left_out_reason=REST_REASON,
        noise_floor_N=noise,
        noise_method=NOISE_METHOD,
        baseline_parameters=param_estimates(baseline, "eq14"),
        baseline_rmse_N=baseline.rmse_N,
        final_model=make_final_model(final, D, shape_se, last.model if last.accepted else None),
        heldout=held,
        effects=effects,
        unexplained_structure=unexplained,
        unexplained_where=where_txt if unexplained else (),
        learner=learner,
        where_baseline=where_b,
        where_final=where_f,
        worst_experiments=worst_experiments(D, rec, res_b, res_f),
        notes=plan.notes + (_clock_note(rec),),
        settings=settings,
        runtime_s=time.perf_counter() - t0,
    )
    return Diagnosis(report, baseline, final, D, steps)


def _last_stage_report(last) -> tuple:
    """The last stage as a report entry (none when it was not tried)."""
    if not last.tried:
        return ()
    gain = (None if last.heldout_before_N is None or last.heldout_after_N is None
            else last.heldout_before_N - last.heldout_after_N)
    expl = ("Accepted: " if last.accepted else "Not accepted: ") + last.description
    return (EffectReport(RESIDUAL_ID, False, last.accepted, "a flexible function of the states (not named)", expl,
                         "not named: structure no catalogue formula or state-library column describes, modelled by what it depends on",
                         "f_res = trees(" + ", ".join(last.states) + ")", (), None, (), gain if last.accepted else None),)


def _clock_note(rec) -> str:
    """What the campaign time is made of: the tester's clock (``clock_s``) or the runs back to back."""
    data = getattr(rec, "data", None)
    if data is not None and "clock_s" in data.columns:
        return "campaign time from the clock_s column: the pauses between runs are included"
    return ("no absolute time column (clock_s): campaign time counts the runs back to back, the pauses between runs left out; "
            "a drift that goes on during the pauses (warming, leakage) is compressed in time, so its rate per hour is over-estimated "
            "and a drift over long pauses shows as steps between runs")


def write_diagnosis(diag: Diagnosis, out_dir: str | Path) -> list[str]:
    """Write ``report.json``, ``final_model.json``, ``summary.md`` and the figures.

    Figures: ``residual_maps.png``, ``heldout_per_effect.png``,
    ``worst_experiments.png``. Returns the list of file names written.

    Parameters
    ----------
    diag : Diagnosis
        Output of :func:`diagnose`.
    out_dir : str or pathlib.Path
        Directory to write into (created if missing; files are overwritten).

    Returns
    -------
    list of str
        Names of the files written, relative to ``out_dir``.
    """
    import matplotlib.pyplot as plt

    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    r = diag.report
    (out / "report.json").write_text(json.dumps(r.to_dict(), indent=1))
    (out / "final_model.json").write_text(json.dumps(r.final_model.to_dict(), indent=1))
    (out / "summary.md").write_text(format_summary(r))
    names = []
    if r.final_model.last_stage is not None:
        import pickle

        (out / "last_stage.pkl").write_bytes(pickle.dumps(r.final_model.last_stage))
        names = ["last_stage.pkl"]
    for name, fig in (("residual_maps.png", plot_residual_maps(r)), ("heldout_per_effect.png", plot_heldout_steps(r)), ("worst_experiments.png", plot_worst(diag))):
        fig.savefig(out / name, dpi=80)
        plt.close(fig)
    return ["report.json", "final_model.json", "summary.md", "residual_maps.png", "heldout_per_effect.png", "worst_experiments.png"] + names
