"""The diagnosis report: typed results of every stage, the final model file, the summary an engineer reads.

The classes here are what :func:`~vvea_design.identification.diagnose.diagnose`
returns (:class:`Diagnosis`, its :class:`DiagnosisReport`); ``to_dict()`` of
the report is the JSON of ``shared/specs/diagnosis-report.md``,
:class:`FinalModel` is ``final_model.json`` (:func:`load_final_model` reads it
back and evaluates it on new motions), :func:`format_summary` the Markdown
summary. The builders (:func:`param_estimates`, :func:`make_final_model`,
:func:`effect_reports`, :func:`worst_experiments`, :func:`where_sentences`)
turn the fits of the stages into report entries.

Residual sign: residual = measurement − model (N), on every axis and in
every table.
"""

from __future__ import annotations

import json
from dataclasses import asdict, dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

from ..spring.gas_spring import GasSpring
from .design import assemble
from .dependence import dependence_profile, describe_dependence
from .effects import REGISTRY, is_effect_id
from .effects.force_lag import ForceFilter
from .fit_data import FitData
from .fitting import ModelFit
from .last_stage import RESIDUAL_ID, ResidualModel

if TYPE_CHECKING:
    from .settings import DiagnoseSettings

__all__ = [
    "RESIDUAL_SIGN",
    "ParamEstimate",
    "Evidence",
    "EffectReport",
    "ResidualBin",
    "ResidualFeature",
    "ExperimentError",
    "HeldOutStep",
    "HeldOut",
    "StructureWhere",
    "LearnerCheck",
    "FinalModel",
    "DiagnosisReport",
    "Diagnosis",
    "load_final_model",
    "param_estimates",
    "make_final_model",
    "effect_reports",
    "worst_experiments",
    "where_sentences",
    "format_summary",
]

RESIDUAL_SIGN = "residual = measurement − model"


@dataclass(frozen=True)
class ParamEstimate:
    """A fitted parameter in physical units."""

    name: str
    value: float
    std_error: float
    unit: str
    meaning: str = ""

    def to_dict(self) -> dict:
        """The estimate as JSON.

        Returns
        -------
        dict
            ``value`` and ``std_error`` in ``unit`` (None where not finite), ``unit``, ``meaning``.
        """
        return dict(value=_f(self.value), std_error=_f(self.std_error), unit=self.unit, meaning=self.meaning)


@dataclass(frozen=True)
class Evidence:
    """Why a term was (not) accepted: grouped-CV statistics over held-out experiments."""

    round: int
    cv_gain: float  #: relative reduction of the held-out mean square
    paired_t: float  #: paired t of the per-experiment squared-error reduction
    folds_improved: int
    n_folds: int
    experiments_halved: int
    snr: float  #: effect RMS / residual RMS
    effect_rms_N: float
    residual_rms_N: float
    signature_ok: bool
    vs_best_discovered_t: float | None  #: paired t by which the best discovery operator beats this catalogue effect
    passes: bool
    reasons: tuple = ()
    #: catalogue names from evidence (:mod:`.general`): share of the all-states trees' held-out gain that trees on the formula's states reach
    states_share: float | None = None
    #: ... and share of the same-states trees' held-out gain that the formula reaches
    general_share: float | None = None

    def to_dict(self) -> dict:
        """The evidence as JSON.

        Returns
        -------
        dict
            Every field (RMS values in N, gains and t statistics dimensionless; None where not finite),
            ``reasons`` as a list of sentences.
        """
        d = {k: _j(v) for k, v in asdict(self).items()}
        d["reasons"] = list(self.reasons)
        return d


@dataclass(frozen=True)
class EffectReport:
    """One tested term (catalogue effect or discovery operator)."""

    id: str
    catalogue: bool
    accepted: bool
    title: str
    explanation: str
    physics: str
    equation: str
    parameters: tuple = ()  #: ParamEstimate entries (amplitudes and the shape parameter)
    evidence: Evidence | None = None
    signature: tuple = ()  #: Check entries
    heldout_rmse_removed_N: float | None = None  #: held-out RMS before minus after adding this term

    def to_dict(self) -> dict:
        """The tested term as JSON (one entry of the report's ``effects``).

        Returns
        -------
        dict
            ``id``, ``catalogue``, ``accepted``, texts, ``parameters`` by name (values in their units),
            ``evidence``, ``signature`` checks and ``heldout_rmse_removed_N`` (N).
        """
        return dict(
            id=self.id,
            catalogue=self.catalogue,
            accepted=self.accepted,
            title=self.title,
            explanation=self.explanation,
            physics=self.physics,
            equation=self.equation,
            parameters={p.name: p.to_dict() for p in self.parameters},
            evidence=self.evidence.to_dict() if self.evidence else {},
            signature=[c.to_dict() for c in self.signature],
            heldout_rmse_removed_N=_f(self.heldout_rmse_removed_N),
        )


@dataclass(frozen=True)
class ResidualBin:
    bin: str
    n: int
    mean_N: float
    mean_along_motion_N: float
    rms_N: float
    rms_over_noise: float


@dataclass(frozen=True)
class ResidualFeature:
    """Residual statistics along one feature (displacement, speed, ...)."""

    name: str
    unit: str
    bins: tuple

    def worst(self) -> ResidualBin:
        """The bin with the largest residual RMS.

        Returns
        -------
        ResidualBin
            Its range, sample count and residual statistics (N).
        """
        return max(self.bins, key=lambda b: b.rms_N)


@dataclass(frozen=True)
class ExperimentError:
    exp_index: int
    experiment: str
    p2_MPa: float
    valve_deg: float
    speed_mm_s: float
    rms_baseline_N: float
    rms_final_N: float


@dataclass(frozen=True)
class HeldOutStep:
    """Held-out RMS after adding one more term (fitted without the held-out experiments)."""

    label: str
    effects: tuple
    rmse_N: float | None


@dataclass(frozen=True)
class HeldOut:
    assessable: bool
    baseline_N: float | None
    final_N: float | None
    steps: tuple
    test_experiments: tuple
    method: str


@dataclass(frozen=True)
class StructureWhere:
    feature: str
    importance_share: float
    largest_structure_rms_N: float
    range: tuple


@dataclass(frozen=True)
class LearnerCheck:
    ran: bool
    flag: bool
    heldout_variance_explained: float | None = None
    explained_rms_N: float | None = None
    rows: int = 0
    where: tuple = ()
    note: str = ""


@dataclass(frozen=True)
class FinalModel:
    """The fitted final model (eq. 14 + accepted terms), evaluable on new motions.

    ``predict(D)`` rebuilds the design of the same terms on any
    :class:`FitData` whose valve positions were in the fit (``reference``
    is the unit the gas terms were shaped with).
    """

    effects: tuple
    shapes: dict
    parameters: tuple  #: ParamEstimate in column order (eq. 14 first)
    valves: tuple
    reference: GasSpring
    rmse_N: float
    last_stage: ResidualModel | None = None  #: the flexible last stage on the residual (identification.last_stage)
    last_stage_info: dict | None = None  #: its JSON (kept when read back without the trees)

    @property
    def model(self) -> str:
        return "eq14" + "".join(f" + {e}" for e in self.effects) + (f" + {RESIDUAL_ID}" if self.has_last_stage else "")

    @property
    def has_last_stage(self) -> bool:
        """Whether the model ends with a last stage (fitted trees on the residual)."""
        return self.last_stage is not None or bool(self.last_stage_info)

    def predict(self, D: FitData) -> np.ndarray:
        """Force of the final model at the samples of ``D`` (new motions of the same unit).

        Parameters
        ----------
        D : FitData
            The new motions (their valve positions must have been in the fit).

        Returns
        -------
        numpy.ndarray
            ``(D.n,)`` predicted force reading (N).

        Raises
        ------
        ValueError
            A valve position of ``D`` was not in the fitted campaign (named, in deg).
        """
        missing = sorted(set(D.valves) - set(self.valves))
        if missing:
            raise ValueError(f"valve position(s) {missing} deg were not in the fitted campaign (fitted: {list(self.valves)})")
        byname = {p.name: p.value for p in self.parameters}
        _, params, groups = assemble(D, self.effects, self.shapes, {"damping_force_N": np.zeros(D.n)})
        theta = np.zeros(len(params))
        for gname, sl in groups.items():
            prefix = "" if gname == "eq14" else f"{gname}."
            for i in range(sl.start, sl.stop):
                theta[i] = byname[prefix + params[i].name]
        fit = ModelFit(self.effects, dict(self.shapes), params, theta, np.zeros_like(theta), 0.0, 0, groups)
        out = fit.predict(D)
        if self.has_last_stage:
            if self.last_stage is None:
                raise ValueError("the final model ends with a last stage whose trees were not loaded (last_stage.pkl missing)")
            out = out + self.last_stage.predict(D)
        return out

    def to_dict(self) -> dict:
        """The final model as JSON (``final_model.json``; :meth:`from_dict` reads it back).

        Returns
        -------
        dict
            ``format``, ``version``, the model string, effect ids, shape values and parameters (in their
            units), valve positions (deg), the reference unit (mm², mm³, MPa, mm), ``rmse_N`` (N), the
            residual sign convention and each term's equation.
        """
        return dict(
            format="vvea-final-model",
            version=1,
            model=self.model,
            effects=list(self.effects),
            shapes={k: _f(v) for k, v in self.shapes.items()},
            parameters={p.name: p.to_dict() for p in self.parameters},
            valves_deg=[float(v) for v in self.valves],
            reference={k: float(getattr(self.reference, k)) for k in ("A1_mm2", "A2_mm2", "V1_mm3", "V2_mm3", "p1_MPa", "p2_MPa", "travel_mm", "n_polytropic")},
            rmse_N=_f(self.rmse_N),
            residual_sign=RESIDUAL_SIGN,
            equations={e: REGISTRY[e].equation for e in self.effects},
            last_stage=(self.last_stage.to_dict() if self.last_stage is not None else self.last_stage_info),
        )

    @classmethod
    def from_dict(cls, d: dict) -> "FinalModel":
        """The final model from its JSON (:meth:`to_dict`).

        Parameters
        ----------
        d : dict
            The parsed ``final_model.json``.

        Returns
        -------
        FinalModel
            Ready to :meth:`predict` new motions.

        Raises
        ------
        ValueError
            Not a final-model file, or it names an effect this version does not know.
        """
        if d.get("format") != "vvea-final-model":
            raise ValueError("not a vvea final-model file (format must be 'vvea-final-model')")
        unknown = [e for e in d["effects"] if not is_effect_id(e)]
        if unknown:
            raise ValueError(f"final model names unknown effect(s) {unknown}")
        params = tuple(
            ParamEstimate(k, float(v["value"]), float(v["std_error"]) if v["std_error"] is not None else float("nan"), v["unit"], v.get("meaning", ""))
            for k, v in d["parameters"].items()
        )
        return cls(tuple(d["effects"]), {k: (np.nan if v is None else float(v)) for k, v in d["shapes"].items()}, params,
                   tuple(d["valves_deg"]), GasSpring(**d["reference"]), float(d["rmse_N"] or np.nan),
                   last_stage_info=d.get("last_stage") or None)


def load_final_model(path: str | Path) -> FinalModel:
    """Read ``final_model.json`` written by :func:`write_diagnosis`.

    Parameters
    ----------
    path : str or pathlib.Path
        The JSON file.

    Returns
    -------
    FinalModel
        The model; :meth:`FinalModel.predict` gives its force (N) on new motions.

    Raises
    ------
    ValueError
        If the file is not a vvea final-model file, names unknown effects, or ends with a last stage
        whose trees file (``last_stage.pkl`` beside it, a pickle: read only files you wrote) is missing.
    """
    import pickle
    from dataclasses import replace

    fm = FinalModel.from_dict(json.loads(Path(path).read_text()))
    if fm.last_stage_info:
        pkl = Path(path).parent / fm.last_stage_info.get("file", "last_stage.pkl")
        if not pkl.exists():
            raise ValueError(f"{path} ends with a last stage but its trees file {pkl} is missing")
        model = pickle.loads(pkl.read_bytes())
        if not isinstance(model, ResidualModel):
            raise ValueError(f"{pkl} does not hold a last stage (ResidualModel)")
        fm = replace(fm, last_stage=model)
    return fm


@dataclass(frozen=True)
class DiagnosisReport:
    """Everything :func:`diagnose` found; :meth:`to_dict` is the JSON report of the spec."""

    source: str
    reference: str
    n_experiments: int
    rows_read: int
    rows_used: int
    rows_left_out: int
    rows_left_out_reason: str
    noise_floor_N: float
    noise_method: str
    baseline_parameters: tuple
    baseline_rmse_N: float
    final_model: FinalModel
    heldout: HeldOut
    effects: tuple  #: EffectReport, every tested term
    unexplained_structure: bool
    unexplained_where: tuple  #: sentences
    learner: LearnerCheck
    where_baseline: tuple  #: ResidualFeature
    where_final: tuple
    worst_experiments: tuple  #: ExperimentError
    notes: tuple  #: what could not be assessed, and other caveats
    settings: DiagnoseSettings
    runtime_s: float

    @property
    def accepted(self) -> tuple:
        """The accepted terms, in the order they were accepted."""
        acc = {e.id: e for e in self.effects if e.accepted}
        order = tuple(self.final_model.effects) + ((RESIDUAL_ID,) if self.final_model.has_last_stage else ())
        return tuple(acc[i] for i in order if i in acc)

    @property
    def accepted_catalogue_ids(self) -> tuple:
        return tuple(e.id for e in self.accepted if e.catalogue)

    def to_dict(self) -> dict:
        """The JSON report (contract keys of ``shared/specs/diagnosis-report.md`` plus the evidence).

        Returns
        -------
        dict
            The source, the reference unit and row counts, ``noise_floor_N`` (N), ``baseline`` (eq. 14 fit),
            ``final_model``, ``heldout_rmse_N`` (N, baseline and final), ``effects``,
            ``unexplained_structure`` with where it sits, the leftover learner's check, the worst experiments,
            notes, the settings and ``runtime_s`` (s).
        """
        fm = self.final_model
        return dict(
            source=self.source,
            reference=self.reference,
            residual_sign=RESIDUAL_SIGN,
            n_experiments=self.n_experiments,
            rows_read=self.rows_read,
            rows_used=self.rows_used,
            rows_left_out=self.rows_left_out,
            rows_left_out_reason=self.rows_left_out_reason,
            noise_floor_N=_f(self.noise_floor_N),
            noise_method=self.noise_method,
            baseline=dict(
                model="eq14: f = g p2 x + L(gamma) xdot + C sign(xdot)",
                parameters={p.name: p.to_dict() for p in self.baseline_parameters},
                rmse_N=_f(self.baseline_rmse_N),
            ),
            final_model=dict(fm.to_dict(), file="final_model.json"),
            heldout_rmse_N=dict(baseline=_f(self.heldout.baseline_N), final=_f(self.heldout.final_N)),
            heldout=dict(
                assessable=self.heldout.assessable,
                method=self.heldout.method,
                test_experiments=list(self.heldout.test_experiments),
                steps=[dict(label=s.label, effects=list(s.effects), rmse_N=_f(s.rmse_N)) for s in self.heldout.steps],
            ),
            effects=[e.to_dict() for e in self.effects],
            unexplained_structure=self.unexplained_structure,
            unexplained_where=list(self.unexplained_where),
            learner=_j(asdict(self.learner)),
            where=dict(
                baseline=_map_dict(self.where_baseline),
                final=_map_dict(self.where_final),
                worst_experiments=[_j(asdict(w)) for w in self.worst_experiments],
            ),
            notes=list(self.notes),
            settings=_j(asdict(self.settings)),
            runtime_s=self.runtime_s,
        )


@dataclass(frozen=True)
class Diagnosis:
    """Result of :func:`diagnose`: the typed report plus the fitted models."""

    report: DiagnosisReport
    baseline: ModelFit  #: eq. 14 fitted on all experiments
    final: ModelFit  #: eq. 14 + accepted terms fitted on all experiments
    data: FitData = field(repr=False)
    steps: tuple = field(default=(), repr=False)  #: ModelFit after each accepted term, fitted on the training experiments


def _f(v):
    if v is None:
        return None
    v = float(v)
    return v if np.isfinite(v) else None


def _j(o):
    if isinstance(o, dict):
        return {str(k): _j(v) for k, v in o.items()}
    if isinstance(o, (list, tuple)):
        return [_j(v) for v in o]
    if isinstance(o, (np.floating, float)):
        return _f(o)
    if isinstance(o, np.integer):
        return int(o)
    if isinstance(o, np.bool_):
        return bool(o)
    if isinstance(o, np.ndarray):
        return _j(o.tolist())
    return o


def _map_dict(feats) -> dict:
    return {f.name: dict(unit=f.unit, bins=[_j(asdict(b)) for b in f.bins]) for f in feats}


# ------------------------------------------------------------------ building the report
def param_estimates(fit: ModelFit, group: str, shape_se: dict | None = None, prefix: str = "") -> tuple:
    """The fitted parameters of one column group of ``fit`` as report entries (amplitudes, then the shape).

    Parameters
    ----------
    fit : ModelFit
        The fitted model.
    group : str
        ``"eq14"`` or an effect id of ``fit``.
    shape_se : dict, optional
        Standard error of each effect's shape parameter, in its unit (e.g. s, mm); NaN where missing.
    prefix : str
        Prepended to each parameter name (``"thermal."`` in the final model).

    Returns
    -------
    tuple of ParamEstimate
        Values and standard errors in each parameter's unit; a fitted sensor filter adds its damping ratio
        (dimensionless, no standard error).
    """
    sl = fit.groups[group]
    out = [ParamEstimate(prefix + q.name, float(v), float(s), q.unit, q.meaning) for q, v, s in zip(fit.params[sl], fit.theta[sl], fit.se[sl])]
    if group != "eq14":
        eff = REGISTRY[group]
        if eff.shape is not None:
            out.append(ParamEstimate(prefix + eff.shape.name, float(fit.shapes.get(group, np.nan)), float((shape_se or {}).get(group, np.nan)),
                                     eff.shape.unit, eff.shape.meaning + " (fold-jackknife s.e.)"))
        if isinstance(eff, ForceFilter) and eff.kind.startswith("fitted"):
            out.append(ParamEstimate(prefix + "zeta", float(eff.zeta), float("nan"), "1",
                                     "damping ratio of the filter (fitted on the training experiments, lag fixed; no s.e.)"))
    return tuple(out)


def make_final_model(final: ModelFit, D: FitData, shape_se: dict, last_stage: ResidualModel | None = None) -> FinalModel:
    """The final model of the report (every parameter, eq. 14's first, named ``effect.parameter``).

    Parameters
    ----------
    final : ModelFit
        Eq. 14 + the accepted terms, fitted on all experiments.
    D : FitData
        The campaign (its valve positions in deg and reference unit are kept).
    shape_se : dict
        Fold-jackknife standard error of each shape parameter, in its unit (e.g. s, mm).
    last_stage : ResidualModel, optional
        The accepted last stage (its force in N is added to the prediction).

    Returns
    -------
    FinalModel
        Ready to write (``final_model.json``) and to predict new motions (force in N).
    """
    params = list(param_estimates(final, "eq14"))
    for e in final.effects:
        sl = final.groups[e]
        params += [ParamEstimate(f"{e}.{q.name}", float(v), float(s), q.unit, q.meaning) for q, v, s in zip(final.params[sl], final.theta[sl], final.se[sl])]
    shapes = {e: float(final.shapes.get(e, np.nan)) for e in final.effects}
    return FinalModel(tuple(final.effects), shapes, tuple(params), tuple(D.valves), D.reference, final.rmse_N, last_stage)


def worst_experiments(D: FitData, rec, res_b: np.ndarray, res_f: np.ndarray) -> tuple:
    """The eight experiments eq. 14 fits worst, with their error before and after the accepted terms.

    Parameters
    ----------
    D : FitData
        The campaign (p2 in MPa, valve in deg, speed in mm/s per sample).
    rec : Recordings or FitData
        The campaign as given to the diagnosis (its ``experiments`` table names the experiments).
    res_b, res_f : numpy.ndarray
        Residual (measurement − model) of eq. 14 and of the final model per sample, N.

    Returns
    -------
    tuple of ExperimentError
        Largest eq.-14 RMS error (N) first.
    """
    names = getattr(rec, "experiments", None)
    labels = [str(n) for n in names["experiment"]] if names is not None and len(names) == D.n_exp else [str(e) for e in range(D.n_exp)]
    rows = []
    for e in range(D.n_exp):
        a, b = D.bounds[e], D.bounds[e + 1]
        rows.append(ExperimentError(
            e, labels[e], float(D.p2[a]), float(D.valve[a]),
            float(D.speed[a]) if D.speed is not None else float(np.max(np.abs(D.v[a:b]))),
            float(np.sqrt(np.mean(res_b[a:b] ** 2))), float(np.sqrt(np.mean(res_f[a:b] ** 2))),
        ))
    return tuple(sorted(rows, key=lambda r: -r.rms_baseline_N)[:8])


def effect_reports(D: FitData, sel, trials: dict, final: ModelFit, shape_se: dict, hsteps, plan, settings: DiagnoseSettings) -> tuple:
    """One report entry per tested term: the accepted ones with their fit on all experiments, the others with why not.

    Parameters
    ----------
    D : FitData
        The campaign.
    sel : sequence of str
        Accepted effect ids, in the order accepted.
    trials : dict
        Per candidate id its score in the last round it was tested (``evidence``, ``fit``, ``signature``).
    final : ModelFit
        Eq. 14 + ``sel`` fitted on all experiments.
    shape_se : dict
        Fold-jackknife standard error of each shape parameter, in its unit (e.g. s, mm).
    hsteps : sequence of HeldOutStep
        Held-out RMS error (N) after 0, 1, ... accepted terms.
    plan : Plan
        The experiment split (whether selection was possible).
    settings : DiagnoseSettings
        The candidates and discovery operators tested.

    Returns
    -------
    tuple of EffectReport
        The catalogue candidates first, then the discovery operators tested, then fitted sensor filters.
    """
    out = []
    removed = {}
    for k, eid in enumerate(sel):
        a, b = hsteps[k].rmse_N, hsteps[k + 1].rmse_N
        removed[eid] = None if a is None or b is None else a - b
    listed = list(settings.candidates) + [d for d in settings.discovery if d in sel or d in trials]
    made = [d for d in dict.fromkeys(list(sel) + list(trials)) if d not in listed]  # fitted sensor filters (ids made from their ratio)
    for eid in listed + made:
        if not is_effect_id(eid):
            continue
        eff = REGISTRY[eid]
        acc = eid in sel
        tri = trials.get(eid)
        ev = tri.evidence if tri else None
        if acc:
            vals, errs = final.effect_values(eid), final.effect_errors(eid)
            sh = final.shapes.get(eid, np.nan)
            contrib = final.contribution(D, eid)
            expl = "Accepted: " + eff.describe(vals, errs, sh, shape_se.get(eid, np.nan)) + " " + describe_dependence(dependence_profile(D, contrib))
            params = param_estimates(final, eid, shape_se)
            sig = tuple(eff.signature(D, vals, sh, contrib)) if eff.catalogue else ()
        else:
            if ev is None:
                why = "not tested: " + ("too few experiments for a cross-validated test" if not plan.can_select else "not applicable to this campaign")
            else:
                why = "; ".join(ev.reasons) or "a better term was accepted for the same structure"
            expl = f"Not accepted: {why}."
            fitc = tri.fit if tri else None
            params = param_estimates(fitc, eid) if fitc is not None and eid in fitc.groups else ()
            sig = tri.signature if tri else ()
        out.append(EffectReport(eid, eff.catalogue, acc, eff.title, expl, eff.physics, eff.equation, params, ev, sig, removed.get(eid)))
    return tuple(out)


def where_sentences(learner: LearnerCheck, where_final, noise: float, held: HeldOut) -> tuple:
    """Where structure remains after the final model, in sentences.

    Parameters
    ----------
    learner : LearnerCheck
        The flexible learner's check on the final residuals.
    where_final : sequence of ResidualFeature
        The final model's residual map.
    noise : float
        Noise floor, N RMS.
    held : HeldOut
        The held-out errors (N).

    Returns
    -------
    tuple of str
        One sentence per place: features the learner found, bins above twice the noise, a held-out error
        above twice the noise floor.
    """
    out = []
    for w in learner.where if learner.flag else ():
        out.append(f"along {w.feature} ({100 * w.importance_share:.0f} % of residual variance; largest at "
                   f"{w.range[0]:.3g}..{w.range[1]:.3g}: {w.largest_structure_rms_N:.1f} N RMS)")
    # when the learner flags, it has measured which states carry the structure (permutation importance): the
    # residual map then names only those (a large residual is above twice the noise in the bins of every state)
    carried = {w.feature for w in learner.where} if learner.flag else None
    for f in where_final:
        b = f.worst()
        if carried is not None and f.name not in carried:
            continue
        if b.rms_over_noise > 2.0 and b.n >= 0.05 * sum(x.n for x in f.bins):
            out.append(f"{f.name} {b.bin} {f.unit}: residual RMS {b.rms_N:.1f} N = {b.rms_over_noise:.1f} x noise (mean {b.mean_N:+.1f} N, measurement − model)")
    if held.assessable and held.final_N is not None and held.final_N > 2.0 * noise:
        out.append(f"held-out RMS after the fit {held.final_N:.1f} N > 2 x noise floor {noise:.1f} N")
    return tuple(out)


# ------------------------------------------------------------------ summary
def format_summary(r: DiagnosisReport) -> str:
    """A summary an engineer can read (Markdown).

    Parameters
    ----------
    r : DiagnosisReport
        The report of :func:`diagnose`.

    Returns
    -------
    str
        Markdown text: campaign, noise floor (N), accepted and rejected
        effects with their parameters and evidence, held-out errors (N) and
        what is left unexplained.
    """
    L = []
    noise = r.noise_floor_N if np.isfinite(r.noise_floor_N) else 0.0
    L.append(f"# Diagnosis of {r.source}")
    L.append("")
    L.append(
        f"{r.n_experiments} experiments, {r.rows_used} samples used, {r.rows_left_out} left out ({r.rows_left_out_reason}). "
        f"Noise floor {noise:.1f} N. Gas terms shaped by {r.reference}. Residual sign: {RESIDUAL_SIGN}."
    )
    for n in r.notes:
        L.append(f"- **Note:** {n}.")
    L.append("")
    L.append("## Where eq. 14 and the bench disagree")
    L.append(f"Baseline RMS residual {r.baseline_rmse_N:.1f} N = {r.baseline_rmse_N / max(noise, 1e-9):.1f} x noise floor.")
    for f in r.where_baseline:
        w = f.worst()
        L.append(f"- by {f.name}: largest in {w.bin} {f.unit} (RMS {w.rms_N:.1f} N, mean along motion {w.mean_along_motion_N:+.1f} N)")
    if r.worst_experiments:
        L.append("- worst experiments: " + "; ".join(
            f"{w.experiment} (p2 {w.p2_MPa:g} MPa, valve {w.valve_deg:g} deg, {w.speed_mm_s:g} mm/s): {w.rms_baseline_N:.0f} -> {w.rms_final_N:.0f} N"
            for w in r.worst_experiments[:3]))
    L.append("")
    L.append("## What was left out")
    acc = r.accepted
    if not acc:
        L.append("No candidate passed grouped cross-validation: eq. 14 explains the recordings to within the noise it can resolve."
                 if not any("cannot" in n for n in r.notes) else "No effect accepted (see the notes above).")
    for e in acc:
        ev = e.evidence
        kind = "catalogue effect" if e.catalogue else "found beyond the catalogue"
        L.append(f"### {e.id} — {e.title} ({kind})")
        L.append(e.explanation[len("Accepted: "):])
        L.append(f"Model: `{e.equation}`")
        for p in e.parameters:
            L.append(f"- {p.name} = {p.value:.4g} ± {p.std_error:.2g}" + ("" if p.unit == "1" else f" {p.unit}"))
        if ev is not None:
            L.append(
                f"Evidence: held-out mean square -{100 * ev.cv_gain:.1f} %, paired t = {ev.paired_t:.1f}, improves {ev.folds_improved} of "
                f"{ev.n_folds} folds, effect RMS = {ev.snr:.2f} x residual"
                + (f"; held-out RMS -{e.heldout_rmse_removed_N:.1f} N." if e.heldout_rmse_removed_N is not None else ".")
            )
        for c in e.signature:
            L.append(f"- signature {c.name}: {'ok' if c.passed else 'FAILED'} ({c.detail})")
    rej = [e for e in r.effects if not e.accepted and e.catalogue]
    if rej:
        L.append("")
        L.append("Catalogue effects tested and rejected: " + "; ".join(f"{e.id} ({e.explanation[len('Not accepted: '):].rstrip('.')})" for e in rej))
    L.append("")
    L.append("## Did the fit improve where it was not trained?")
    h = r.heldout
    if h.assessable:
        L.append(f"Held-out RMS error: {h.baseline_N:.1f} N (eq. 14) -> {h.final_N:.1f} N ({h.method}); noise floor {noise:.1f} N.")
        if len(h.steps) > 1:
            L.append("Per accepted term: " + " -> ".join(f"{s.label} {s.rmse_N:.1f} N" for s in h.steps) + ".")
    else:
        L.append(f"Not assessable: {h.method}.")
    if r.unexplained_structure:
        L.append("**Structure remains** that no accepted term explains: " + "; ".join(r.unexplained_where) + ".")
        L.append("  Eq. 14 with the accepted terms is not the whole story there: add physics before trusting the model in that region.")
    else:
        lv = r.learner.heldout_variance_explained
        L.append("No structure remains beyond noise" + (f" (a flexible learner explains {100 * lv:.1f} % of held-out residual variance)." if lv is not None else "."))
    L.append("")
    L.append(f"The final model ({r.final_model.model}) is in `final_model.json`; `vvea_design.identification.diagnose.load_final_model` evaluates it on new motions.")
    return "\n".join(L) + "\n"
