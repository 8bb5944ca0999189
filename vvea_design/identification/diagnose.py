"""Discrepancy diagnosis: where eq. 14 and the bench disagree, what was left out, its model, the held-out gain.

Answers the four questions of ``shared/specs/diagnosis-report.md`` in named
stages (:func:`diagnose` only chains them):

1. **Plan** (:func:`plan_split`) -- experiments held out of everything
   (stratified by valve) and grouped-CV folds over the rest; with few
   experiments the plan says what cannot be assessed instead of failing.
2. **Noise floor** (:func:`noise_floor_N`) -- what no smooth model of the
   cycle can explain: per ramp, the periodogram of the residual with spectral
   lines removed by a running median and the lowest bins (slow misfit)
   excluded, fitted by an AR(1) spectrum whose integral is the noise
   variance. Periodic (lines) and slow structure cannot inflate it.
3. **Selection** (:func:`select_effects`) -- forward selection over the
   registry of :mod:`~vvea_design.identification.effects`: catalogue effects
   and discovery operators compete in grouped cross-validation (whole
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
   **Backward step** (:func:`_backward_step`): at the end every accepted
   term is re-tested beside all the other accepted terms and
   dropped when they explain it away (its force or its held-out gain below
   ``keep_noise`` x the noise floor, or the gain, t and fold tests failed).
4. **Final fits** (:func:`final_fits`) -- all experiments, cluster-robust
   errors, fold jackknife for shape parameters, held-out RMS after each
   accepted term (fitted without the held-out experiments).
5. **Leftover check** (:func:`learner_check`) -- gradient-boosted trees on the
   final residuals (grouped CV); ``unexplained_structure`` when they still
   predict them beyond the noise floor, or the held-out error stays above
   twice the floor; the report then says where.

Residual sign: residual = measurement − model (N), on every axis and in
every table.
"""

from __future__ import annotations

import functools
import inspect
import json
import time
from dataclasses import asdict, dataclass, field
from pathlib import Path

import numpy as np

from ..figure_layout import set_margins_in, text_width_in, tick_labels_in_view, tight_layout_once, ytick_label_width_in
from ..spring.gas_spring import GasSpring
from ..spring.paper import PAPER_FIG5
from .effects import (
    DISCOVERY_IDS,
    EFFECT_IDS,
    REFERENCE_NOTE,
    REGISTRY,
    ZETA_RANGE,
    Effect,
    FitData,
    ForceFilter,
    cached,
    effect_columns,
    filter_id,
    is_effect_id,
)
from .identify import ModelFit, assemble, blocks, extend_blocks, fit_model, relief_context, solve_bounded
from .recordings import Recordings

__all__ = [
    "DiagnoseSettings",
    "ParamEstimate",
    "Evidence",
    "EffectReport",
    "ResidualBin",
    "ResidualFeature",
    "ExperimentError",
    "HeldOutStep",
    "HeldOut",
    "LearnerCheck",
    "FinalModel",
    "DiagnosisReport",
    "Diagnosis",
    "Plan",
    "diagnose",
    "plan_split",
    "noise_floor_N",
    "select_effects",
    "final_fits",
    "learner_check",
    "residual_map",
    "write_diagnosis",
    "format_summary",
    "load_final_model",
]

RESIDUAL_SIGN = "residual = measurement − model"


@dataclass(frozen=True)
class DiagnoseSettings:
    """Settings of :func:`diagnose` (the defaults are the benchmarked ones)."""

    n_folds: int = 5  #: grouped-CV folds (whole experiments)
    test_fraction: float = 0.2  #: experiments held out of selection and fit
    min_gain: float = 0.02  #: minimum relative reduction of the CV mean square
    min_t: float = 3.0  #: minimum paired t over held-out experiments
    min_halved: int = 1  #: ... or at least this many badly fit (RMS > 2 x noise) held-out experiments with their squared error halved
    min_folds: int = 4  #: stability: the term improves at least this many folds (of n_folds)
    min_snr: float = 0.25  #: minimum effect RMS / residual RMS
    name_t: float = 2.0  #: a catalogue effect loses its name when a discovery operator is better by this paired t
    keep_noise: float = 0.5  #: backward step: an accepted term stays only if its force RMS is at least keep_noise x the noise floor and, beside all other accepted terms, it lowers the held-out mean square by at least (keep_noise x noise floor)^2 and still passes the gain, consistency and fold tests
    max_effects: int = 6  #: at most this many accepted terms
    seed: int = 0  #: seed of the experiment splits
    learner: bool = True  #: run the flexible-learner check
    learner_min_gain: float = 0.10  #: learner must explain this share of residual variance ...
    learner_min_ratio: float = 1.0  #: ... and an RMS of at least this times the noise
    learner_rows: int = 12000  #: rows sub-sampled for the learner
    candidates: tuple = EFFECT_IDS  #: catalogue effect ids to test
    discovery: tuple = DISCOVERY_IDS  #: discovery operators to test (empty: catalogue only)
    min_experiments_cv: int = 6  #: fewer experiments than this: no selection (nothing can be cross-validated)


# ================================================================== typed report
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

    @property
    def model(self) -> str:
        return "eq14" + "".join(f" + {e}" for e in self.effects)

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
        return fit.predict(D)

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
                   tuple(d["valves_deg"]), GasSpring(**d["reference"]), float(d["rmse_N"] or np.nan))


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
        If the file is not a vvea final-model file or names unknown effects.
    """
    return FinalModel.from_dict(json.loads(Path(path).read_text()))


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
        return tuple(acc[i] for i in self.final_model.effects if i in acc)

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


# ================================================================== stage: noise floor
def _ar1_rho(segs) -> float:
    """rho of the AR(1) spectrum shape 1/(1+ρ²-2ρ cos 2πf) best fitting segment spectra in log space (levels free per segment)."""
    f = np.concatenate([q[0] for q in segs])
    lp = np.log(np.concatenate([q[1] for q in segs]))
    sid = np.repeat(np.arange(len(segs)), [len(q[0]) for q in segs])
    cnt = np.bincount(sid)
    c = np.cos(2 * np.pi * f)
    best = (np.inf, 0.0)
    for rho in np.linspace(-0.6, 0.985, 64):
        z = lp + np.log(1 + rho**2 - 2 * rho * c)
        zm = np.bincount(sid, weights=z) / cnt
        cost = float(np.sum((z - zm[sid]) ** 2))
        if cost < best[0]:
            best = (cost, float(rho))
    return best[1]


#: E[9-bin running median of a Hann-windowed periodogram of white noise] / variance
#: (neighbouring Hann bins are correlated, so it lies between ln 2 and the
#: order-statistic value 0.746; calibrated by simulation of white noise).
_MEDIAN_GAIN = 0.80


def noise_floor_N(D: FitData, residual_N: np.ndarray, min_bin: int = 4, med_bins: int = 9) -> float:
    """Measurement noise (N RMS) from what no smooth model of the cycle explains.

    Per ramp (monotone half of an experiment, without its first sixth where
    transients after start and reversal live) the residual's Hann-windowed
    periodogram is taken; a running median over ``med_bins`` frequency bins
    removes spectral lines (periodic structure in time or position), the
    lowest ``min_bin`` bins (slow structure, model misfit) are left out. An
    AR(1) spectrum shape (correlated sensor noise) is fitted per group of
    similar sample spacing, its level per ramp (noise may differ between
    experiments); the integral, the marginal variance, averaged over samples,
    is the noise floor. White noise gives its RMS, AR(1) noise its marginal
    RMS; a ripple or a slow misfit does not raise it.

    Parameters
    ----------
    D : FitData
        The campaign (experiment bounds, direction of motion, sample spacing in s).
    residual_N : numpy.ndarray, shape (D.n,)
        Residual per sample (measurement − model), N.
    min_bin : int
        Number of lowest periodogram bins left out of the level fit.
    med_bins : int
        Width of the running median over frequency, a number of bins.

    Returns
    -------
    float
        Noise floor, N RMS; NaN if there are fewer than 3 samples. When no
        ramp is long enough, the RMS of the sample-to-sample differences / √2.
    """
    from scipy.ndimage import median_filter

    segs = cached(D, ("noise_ramps", int(min_bin)), lambda: _noise_ramps(D, int(min_bin)))
    if not len(segs):
        return float(np.std(np.diff(residual_N)) / np.sqrt(2)) if len(residual_N) > 2 else float("nan")
    # per ramp: quadratic trend out (np.polyfit's own least-squares problem, its matrix built once per
    # length), Hann periodogram; the running medians of ramps of one length in one call (a median moves no bit)
    spectra = []
    for a0, n, _ in segs.tolist():
        k, w, sw2, _, lhs, scale, rcond = _ramp_basis(n)
        r = residual_N[a0 : a0 + n]
        c, _, rank, _ = np.linalg.lstsq(lhs, r + 0.0, rcond)
        c = c / scale if rank == 3 else np.polyfit(k, r, 2)  # np.polyfit(k, r, 2), computed as it computes it
        r = r - np.polyval(c, k)
        spectra.append(np.abs(np.fft.rfft(r * w)) ** 2 / sw2)
    lengths = segs[:, 1]
    med: list = [None] * len(segs)
    for n in np.unique(lengths).tolist():
        idx = np.flatnonzero(lengths == n)
        M = median_filter(np.stack([spectra[i] for i in idx]), size=(1, med_bins), mode="nearest") / _MEDIAN_GAIN
        for j, i in enumerate(idx.tolist()):
            med[i] = M[j]
    groups: dict[int, list] = {}
    sel = slice(min_bin, None)
    for (_, n, g), Pm in zip(segs.tolist(), med):
        if np.all(Pm[sel] > 0):
            groups.setdefault(g, []).append((_ramp_basis(n)[3], Pm, n))
    if not groups:
        return float(np.std(np.diff(residual_N)) / np.sqrt(2)) if len(residual_N) > 2 else float("nan")
    var, wsum = 0.0, 0
    for segs_g in groups.values():
        rho = _ar1_rho([(f[min_bin:], P[min_bin:]) for f, P, _ in segs_g])
        for f, P, n in segs_g:
            shape = 1.0 / (1 + rho**2 - 2 * rho * np.cos(2 * np.pi * f))
            sw = float(np.mean(P[min_bin:] / shape[min_bin:]))
            S = np.concatenate((sw * shape[:min_bin], P[min_bin:]))  # measured spectrum; the AR(1) model fills the slow bins only
            wk = np.full(len(S), 2.0)
            wk[0] = 1.0
            if n % 2 == 0:
                wk[-1] = 1.0
            var += n * float(np.sum(wk * S) / n)
            wsum += n
    return float(np.sqrt(var / wsum))


def _noise_ramps(D: FitData, min_bin: int) -> np.ndarray:
    """The ramps :func:`noise_floor_N` reads (a function of the campaign alone, cached on it): rows ``(first row, samples, spacing group)``."""
    dts = D.per_exp_dt()
    out = []
    s_all = D.s  # sign(xdot) of every sample, once (the property computes it over the whole campaign at each call)
    for e in range(D.n_exp):
        a, b = D.bounds[e], D.bounds[e + 1]
        s = s_all[a:b]
        cuts = np.flatnonzero(np.diff(s) != 0) + 1
        for lo, hi in zip(np.r_[0, cuts].tolist(), np.r_[cuts, b - a].tolist()):
            lo = lo + (hi - lo) // 6  # transients after start and reversal are misfit, not noise: skip a sixth of the ramp
            n = hi - lo
            if n < 4 * min_bin + 8:
                continue
            out.append((int(a + lo), int(n), int(np.round(4 * np.log10(dts[e])))))
    return np.array(out, dtype=np.int64).reshape(-1, 3)


@functools.lru_cache(maxsize=512)
def _ramp_basis(n: int):
    """Per ramp length ``n``: sample index, Hann window, its sum of squares, rfft frequencies, and the scaled
    Vandermonde matrix, column scales and rcond of ``np.polyfit(k, r, 2)`` (its own computation, so its bits)."""
    k = np.arange(n)
    w = np.hanning(n)
    x = k + 0.0
    lhs = np.vander(x, 3)
    scale = np.sqrt((lhs * lhs).sum(axis=0))
    lhs /= scale
    for v in (k, w, lhs, scale):
        v.flags.writeable = False
    return k, w, np.sum(w**2), np.fft.rfftfreq(n), lhs, scale, len(x) * np.finfo(x.dtype).eps


NOISE_METHOD = (
    "per ramp (first sixth after start/reversal skipped): Hann periodogram of the residual, spectral lines removed by a 9-bin running median, the 4 lowest bins "
    "(slow misfit) left out, AR(1) spectrum shape fitted per sample-spacing group, its level per ramp; noise floor = sample-weighted RMS of those AR(1) processes"
)


# ================================================================== stage: residual map
def _bins(D: FitData):
    """(feature name, unit, labels per sample) for the residual map."""
    out = []
    xmax = float(max(np.max(D.x), 1e-9)) if D.n else 1.0
    edges = np.linspace(0, xmax, 9)
    xb = np.clip(np.digitize(D.x, edges[1:-1]), 0, 7)
    out.append(("displacement", "mm", np.array([f"{edges[i]:.0f}-{edges[i + 1]:.0f}" for i in range(8)])[xb]))
    sp = D.speed if D.speed is not None else np.round(np.abs(D.v), 1)
    out.append(("speed", "mm/s", np.array([f"{s:g}" for s in sp])))
    out.append(("direction", "", np.where(D.v > 0, "extending", "retracting")))
    te = np.array([0, 0.5, 2, 10, 50, np.inf])
    tl = ["0-0.5", "0.5-2", "2-10", "10-50", "50+"]
    out.append(("time_since_reversal", "s", np.array(tl)[np.clip(np.digitize(D.tsr, te[1:-1]), 0, 4)]))
    out.append(("p2", "MPa", np.array([f"{p:g}" for p in D.p2])))
    out.append(("valve", "deg", np.array([f"{v:g}" for v in D.valve])))
    q = np.quantile(D.ctime, [0.2, 0.4, 0.6, 0.8]) if D.n else np.zeros(4)
    out.append(("campaign_time", "quintile", np.array(["Q1", "Q2", "Q3", "Q4", "Q5"])[np.digitize(D.ctime, q)]))
    return out


def _ordered(labels):
    def key(s):
        try:
            return (0, float(str(s).split("-")[0].rstrip("+").lstrip("Q")))
        except ValueError:
            return (1, str(s))

    return sorted(labels, key=key)


def residual_map(D: FitData, residual_N: np.ndarray, noise_N: float) -> tuple:
    """Residuals (measurement − model) organised by where they occur.

    Returns a tuple of :class:`ResidualFeature` (displacement, speed,
    direction, time since reversal, pressure, valve, campaign time), each
    with one :class:`ResidualBin` per bin: samples, mean, mean along the
    motion (so friction-like residuals do not cancel), RMS and RMS / noise.

    Parameters
    ----------
    D : FitData
        The campaign (x in mm, speeds in mm/s, p2 in MPa, valve in deg, times in s).
    residual_N : numpy.ndarray, shape (D.n,)
        Residual per sample (measurement − model), N.
    noise_N : float
        Noise floor, N RMS (see :func:`noise_floor_N`).

    Returns
    -------
    tuple of ResidualFeature
        One per feature, bins in ascending order; means and RMS in N, RMS /
        noise dimensionless (``inf`` when ``noise_N`` is not positive).
    """
    out = []
    for name, unit, lab in _bins(D):
        rows = []
        for b in _ordered(np.unique(lab)):
            m = lab == b
            r = residual_N[m]
            rms = float(np.sqrt(np.mean(r**2)))
            rows.append(ResidualBin(str(b), int(m.sum()), float(np.mean(r)), float(np.mean(r * np.sign(D.v[m]))), rms,
                                    rms / noise_N if noise_N > 0 else float("inf")))
        out.append(ResidualFeature(name, unit, tuple(rows)))
    return tuple(out)


# ================================================================== stage: plan
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


# ================================================================== stage: selection
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


def _score(D, cur, cand, ctx, plan, base_sse, base_blk, X0, noise, settings, rnd) -> _Trial:
    eff = REGISTRY[cand]
    ctx_c = relief_context(D, cur.effects + (cand,), plan.train, cur.shapes, start=ctx) if eff.replaces_damping else ctx
    new_sse, shape = _cv_sse(D, cur, base_blk, X0, ctx_c, cand, plan, base_sse)
    if new_sse is None:
        return _Trial(cand, None, np.nan, None, None)
    tr = plan.train
    if eff.nuisance_per_experiment:  # parameters fitted on the held-out experiment itself: charge their expected gain on noise
        new_sse = new_sse + eff.nuisance_per_experiment * noise**2
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
    for rnd in range(1, settings.max_effects + 1):
        ctx, X0, base_blk, base_sse = _cv_current(D, cur, plan)
        round_trials = []
        for c in cands:
            if c in sel:
                continue
            say(f"round {rnd}: testing {c}")
            tri = _score(D, cur, c, ctx, plan, base_sse, base_blk, X0, noise, settings, rnd)
            trials[c] = tri
            round_trials.append(tri)
        del ctx, X0, base_blk  # the round's design is not alive beside the refit and the next round's design
        passing = [t for t in round_trials if t.evidence is not None and t.evidence.passes]
        disc = [t for t in passing if not REGISTRY[t.id].catalogue]
        cat = [t for t in passing if REGISTRY[t.id].catalogue]
        best_disc = max(disc, key=lambda t: t.evidence.cv_gain) if disc else None
        named = []
        for t in cat:
            vt = _paired_t(t.sse[plan.train], best_disc.sse[plan.train]) if best_disc is not None else None
            ok = vt is None or vt <= settings.name_t
            ev = t.evidence
            reasons = ev.reasons + (() if ok else (f"a discovered explanation ({best_disc.id}) fits held-out experiments better (paired t {vt:.1f} > {settings.name_t:g})",))
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
        if isinstance(REGISTRY[best.id], ForceFilter):  # a sensor filter of a standard type: fit its damping ratio too
            fid, cur = refine_filter_damping(D, cur, best.id, plan.train)
            if fid != best.id:
                sel[-1] = fid
                trials[fid] = trials.pop(best.id)
                cands = [c for c in cands if c != best.id]  # the standard type it grew from is not tested again beside it
    sel, cur = _backward_step(D, plan, sel, cur, noise, settings, trials)
    return sel, dict(cur.shapes), trials


def refine_filter_damping(D: FitData, cur: ModelFit, eid: str, rows: np.ndarray, xtol: float = 0.002):
    """Fit the damping ratio of the sensor filter ``eid`` of ``cur`` (and its lag again), on the experiments ``rows``.

    The standard filter types (Butterworth ... critical) are tested in the
    selection; the accepted one's damping ratio shapes the response at every
    start and reversal of the motion, where a stiff valve's force changes
    fastest, so it is fitted within :data:`ZETA_RANGE` (bounded scalar
    search on the training SSE, lag fixed), then the lag at that ratio, then
    the ratio again near its value. The result is the filter of that ratio
    (id :func:`~vvea_design.identification.effects.filter_id`) when it
    lowers the training SSE, else ``eid`` unchanged.

    Parameters
    ----------
    D : FitData
        The campaign.
    cur : ModelFit
        The current model; ``eid`` among its effects, its lag (s) in ``cur.shapes``.
    eid : str
        Id of the accepted second-order filter (a :class:`~vvea_design.identification.effects.ForceFilter`).
    rows : numpy.ndarray of int
        Training experiments (indices 0 .. n_exp-1).
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
    while True:
        cat = list(sel)
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
                worst = (c, dmse, why, fr)
        if worst is None:
            return sel, cur
        c, _, why, fr = worst
        sel = [e for e in sel if e != c]
        cur = fr
        t0 = trials.get(c)
        if t0 is not None and t0.evidence is not None:
            ev = t0.evidence
            reasons = ev.reasons + ("explained away by the other accepted terms: " + "; ".join(why),)
            trials[c] = _Trial(c, t0.sse, t0.shape, Evidence(**{**asdict(ev), "passes": False, "reasons": reasons}), t0.fit, t0.signature)


# ================================================================== stage: final fits
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


def _param_estimates(fit: ModelFit, group: str, shape_se: dict | None = None, prefix: str = "") -> tuple:
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


def _final_model(final: ModelFit, D: FitData, shape_se: dict) -> FinalModel:
    params = list(_param_estimates(final, "eq14"))
    for e in final.effects:
        sl = final.groups[e]
        params += [ParamEstimate(f"{e}.{q.name}", float(v), float(s), q.unit, q.meaning) for q, v, s in zip(final.params[sl], final.theta[sl], final.se[sl])]
    shapes = {e: float(final.shapes.get(e, np.nan)) for e in final.effects}
    return FinalModel(tuple(final.effects), shapes, tuple(params), tuple(D.valves), D.reference, final.rmse_N)


# ================================================================== stage: learner check
def learner_check(D: FitData, residual: np.ndarray, noise_N: float, settings: DiagnoseSettings) -> LearnerCheck:
    """Gradient-boosted trees (grouped CV by experiment) on the final residuals: is structure left, and where?

    Parameters
    ----------
    D : FitData
        The campaign (the learner's features: x in mm, ẋ in mm/s, p2 in MPa,
        valve in deg, times in s).
    residual : numpy.ndarray, shape (D.n,)
        Residual of the final model per sample (measurement − model), N.
    noise_N : float
        Noise floor, N RMS.
    settings : DiagnoseSettings
        ``learner_rows``, ``learner_min_gain`` (fraction) and ``learner_min_ratio``.

    Returns
    -------
    LearnerCheck
        Whether it ran and flags structure, the held-out share of residual
        variance it explains (fraction), the RMS it explains (N) and where.
    """
    if D.n_exp < 2:
        return LearnerCheck(False, False, note=f"skipped: {D.n_exp} experiment(s) cannot be split into groups")
    from sklearn.ensemble import HistGradientBoostingRegressor
    from sklearn.model_selection import GroupKFold
    from threadpoolctl import threadpool_limits

    with threadpool_limits(limits=1):  # one thread: predictable on a shared 2-core machine and inside parallel_map
        return _learner_inner(D, residual, noise_N, settings, HistGradientBoostingRegressor, GroupKFold)


def _learner_inner(D, residual, noise_N, settings, HistGradientBoostingRegressor, GroupKFold) -> LearnerCheck:
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
    where = []
    for j in np.argsort(-importance):
        col = Xf[:, j]
        uq = np.unique(col)
        lab = col if len(uq) <= 12 else np.digitize(col, np.quantile(col, np.linspace(0, 1, 9)[1:-1]))
        best = (0.0, (float("nan"), float("nan")))
        for b in np.unique(lab):
            mm = lab == b
            rms = float(np.sqrt(np.mean(pred[mm] ** 2)))
            if rms > best[0]:
                lo, hi = float(col[mm].min()), float(col[mm].max())
                if names[j] == "time_since_reversal":
                    lo, hi = 10**lo - 1e-3, 10**hi - 1e-3
                best = (rms, (lo, hi))
        share = float(importance[j] / mse0) if mse0 > 0 else 0.0
        where.append(StructureWhere(names[j], share, best[0], best[1]))
    where = tuple(w for k, w in enumerate(where) if k == 0 or w.importance_share >= 0.05)[:3]
    return LearnerCheck(True, flag, gain, explained_rms, int(len(idx)), where,
                        "HistGradientBoostingRegressor on residuals, GroupKFold by experiment")


# ================================================================== stage: assemble the report
def _experiment_errors(D, rec, res_b, res_f) -> tuple:
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


def _effect_reports(D, sel, trials, final, shape_se, hsteps, plan, settings) -> tuple:
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
            expl = "Accepted: " + eff.describe(vals, errs, sh, shape_se.get(eid, np.nan))
            params = _param_estimates(final, eid, shape_se)
            sig = tuple(eff.signature(D, vals, sh, final.contribution(D, eid))) if eff.catalogue else ()
        else:
            if ev is None:
                why = "not tested: " + ("too few experiments for a cross-validated test" if not plan.can_select else "not applicable to this campaign")
            else:
                why = "; ".join(ev.reasons) or "a better term was accepted for the same structure"
            expl = f"Not accepted: {why}."
            fitc = tri.fit if tri else None
            params = _param_estimates(fitc, eid) if fitc is not None and eid in fitc.groups else ()
            sig = tri.signature if tri else ()
        out.append(EffectReport(eid, eff.catalogue, acc, eff.title, expl, eff.physics, eff.equation, params, ev, sig, removed.get(eid)))
    return tuple(out)


def _where_sentences(learner: LearnerCheck, where_final, noise: float, held: HeldOut) -> tuple:
    out = []
    for w in learner.where if learner.flag else ():
        out.append(f"along {w.feature} ({100 * w.importance_share:.0f} % of residual variance; largest at "
                   f"{w.range[0]:.3g}..{w.range[1]:.3g}: {w.largest_structure_rms_N:.1f} N RMS)")
    for f in where_final:
        b = f.worst()
        if b.rms_over_noise > 2.0 and b.n >= 0.05 * sum(x.n for x in f.bins):
            out.append(f"{f.name} {b.bin} {f.unit}: residual RMS {b.rms_N:.1f} N = {b.rms_over_noise:.1f} x noise (mean {b.mean_N:+.1f} N, measurement − model)")
    if held.assessable and held.final_N is not None and held.final_N > 2.0 * noise:
        out.append(f"held-out RMS after the fit {held.final_N:.1f} N > 2 x noise floor {noise:.1f} N")
    return tuple(out)


# ================================================================== main entry
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
    say("selection")
    sel, shapes, trials = select_effects(D, plan, noise0, settings, say)
    say("final fits")
    baseline, final, steps, hsteps, shape_se = final_fits(D, plan, sel, shapes, settings)
    res_b = D.y - baseline.predict(D)
    res_f = D.y - final.predict(D)
    noise = noise_floor_N(D, res_f)
    held = HeldOut(
        len(plan.test) > 0, hsteps[0].rmse_N, hsteps[-1].rmse_N, hsteps, tuple(int(e) for e in plan.test),
        f"{len(plan.test)} experiments (~{100 * settings.test_fraction:.0f} % of each valve, seed {settings.seed}) held out of selection and fitting"
        if len(plan.test) else "no experiment could be held out",
    )
    say("flexible-learner check")
    learner = learner_check(D, res_f, noise, settings) if settings.learner else LearnerCheck(False, False, note="skipped (--no-learner)")
    where_b, where_f = residual_map(D, res_b, noise), residual_map(D, res_f, noise)
    effects = _effect_reports(D, sel, trials, final, shape_se, hsteps, plan, settings)
    where_txt = _where_sentences(learner, where_f, noise, held)
    unexplained = bool(learner.flag or (held.assessable and held.final_N is not None and held.final_N > 2.0 * noise))
    report = DiagnosisReport(
        source=getattr(rec, "source", "<data>"),
        reference=ref_note,
        n_experiments=int(D.n_exp),
        rows_read=int(D.n + D.rows_left_out),
        rows_used=int(D.n),
        rows_left_out=int(D.rows_left_out),
        rows_left_out_reason="samples at rest (start, turning point, end): friction is set-valued there",
        noise_floor_N=noise,
        noise_method=NOISE_METHOD,
        baseline_parameters=_param_estimates(baseline, "eq14"),
        baseline_rmse_N=baseline.rmse_N,
        final_model=_final_model(final, D, shape_se),
        heldout=held,
        effects=effects,
        unexplained_structure=unexplained,
        unexplained_where=where_txt if unexplained else (),
        learner=learner,
        where_baseline=where_b,
        where_final=where_f,
        worst_experiments=_experiment_errors(D, rec, res_b, res_f),
        notes=plan.notes,
        settings=settings,
        runtime_s=time.perf_counter() - t0,
    )
    return Diagnosis(report, baseline, final, D, steps)


# ================================================================== output
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
                 if not r.notes else "No effect accepted (see the notes above).")
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


def _in_view_log_locator(subs):
    """A log-axis LogLocator that returns only the ticks inside the view.

    matplotlib makes a Tick (two lines, two texts) for every location a locator returns and then draws only
    those in view; a plain LogLocator returns whole decades beyond both ends, about half of them never drawn.
    """
    from matplotlib.ticker import LogLocator

    class InView(LogLocator):
        def __call__(self):
            lo, hi = sorted(self.axis.get_view_interval())
            if not (lo > 0 and np.isfinite(hi)):
                return super().__call__()
            tol = 1e-9 * max(np.log10(hi / lo), 1e-12)  # matplotlib keeps ticks within ~1e-10 of the ends
            a, b = np.log10(lo) - tol, np.log10(hi) + tol
            return [v for v in super().__call__() if v > 0 and a <= np.log10(v) <= b]

    return InView(10.0, subs)


def _plain_log_ticks(ax) -> None:
    """Log axis with plain numbers (4, 6, 10, 20 rather than 4x10^0); ticks made only where drawn."""
    from matplotlib.ticker import FuncFormatter

    ax.yaxis.set_major_locator(_in_view_log_locator((1.0,)))
    ax.yaxis.set_minor_locator(_in_view_log_locator(None))
    fmt = FuncFormatter(lambda v, _: f"{v:g}")
    ax.yaxis.set_major_formatter(fmt)
    ax.yaxis.set_minor_formatter(FuncFormatter(lambda v, _: f"{v:g}" if f"{v:.1e}"[0] in "2468" or f"{v:.1e}"[0] == "5" else ""))


# Figure margins are set in inches from the fonts instead of by fig.tight_layout(): tight_layout draws every
# tick of every panel to measure it, and leaves a layout engine on the figure that makes savefig draw it twice.
# Only the strings that decide the margins are measured (tick labels in view, rotated bin labels), with the
# same paddings tight_layout uses (1.08 x the 10 pt font between a label and the figure edge or the next panel).
_PAD_PT = 10.8  # tight_layout's default pad
_TICK_PT = 3.5 + 3.5  # major tick length + tick-label pad
_LABELPAD_PT = 4.0
_TITLEPAD_PT = 6.0
_LINE = 1.07  # height of one line of text / font size (DejaVu Sans as matplotlib lays it out: 1.0 to 1.07)
_TITLE = 0.8  # a title's rise above its baseline (which sits _TITLEPAD_PT above the axes) / font size


def _text_w_pt(s: str, size: float) -> float:
    """Width in points of one line of text at font size ``size`` (no drawing)."""
    return 72.0 * text_width_in(s, size)


def _rotated_h_pt(s: str, size: float, deg: float) -> float:
    """Vertical extent in points of a label rotated by ``deg`` degrees."""
    a = np.radians(deg)
    return _text_w_pt(s, size) * abs(np.sin(a)) + _LINE * size * abs(np.cos(a))


def _has_offset_text(ax) -> bool:
    """True if either axis of ``ax`` will draw an offset or scientific-notation text (margins then need tight_layout)."""
    for axis in (ax.xaxis, ax.yaxis):
        for which in ("major", "minor"):
            tick_labels_in_view(axis, which)  # formatting the ticks in view sets the formatter's offset
            fmt = axis.get_major_formatter() if which == "major" else axis.get_minor_formatter()
            if hasattr(fmt, "get_offset") and fmt.get_offset():
                return True
    return False


def _ytick_w_pt(ax) -> float:
    """Room in points left of the spine for the y tick labels (tick, pad, widest major or minor label)."""
    return _TICK_PT + 72.0 * ytick_label_width_in(ax, minor=True)


def plot_residual_maps(r: DiagnosisReport, fig=None):
    """Residual RMS per bin of each feature, eq. 14 against the final model, with the noise floor. Returns the Figure."""
    import matplotlib.pyplot as plt

    noise = r.noise_floor_N
    fig = fig or plt.figure(figsize=(15, 7.5))
    axes = fig.subplots(2, 4)
    for ax, fb, ff in zip(axes.flat, r.where_baseline, r.where_final):
        lab = [b.bin for b in fb.bins]
        xi = np.arange(len(lab))
        ax.bar(xi - 0.2, [b.rms_N for b in fb.bins], 0.4, color="C3")
        ax.bar(xi + 0.2, [b.rms_N for b in ff.bins], 0.4, color="C2")
        ax.axhline(noise, color="k", ls="--", lw=0.8)
        ax.set_xticks(xi, lab, rotation=45, fontsize=7)
        ax.set_title(f"{fb.name}" + (f" [{fb.unit}]" if fb.unit else ""), fontsize=9, y=1.0)  # fixed: ticks are below
        ax.set_ylabel("RMS of measurement − model [N]", fontsize=7)
        ax.set_yscale("log")
        _plain_log_ticks(ax)
        ax.tick_params(labelsize=7, which="both")
    ax = axes.flat[-1]
    ax.axis("off")
    from matplotlib.patches import Patch
    from matplotlib.lines import Line2D

    ax.legend(handles=[Patch(color="C3", label="eq. 14"), Patch(color="C2", label="final model"),
                       Line2D([], [], color="k", ls="--", lw=0.8, label=f"noise floor {noise:.1f} N")],
              loc="upper left", fontsize=8, frameon=False)
    acc = [e.id for e in r.accepted]
    h = r.heldout
    ax.text(0, 0.55, "accepted: " + (", ".join(acc) or "none"), fontsize=8, transform=ax.transAxes, wrap=True)
    if h.assessable:
        ax.text(0, 0.42, f"held-out RMS: {h.baseline_N:.1f} N -> {h.final_N:.1f} N", fontsize=8, transform=ax.transAxes)
    ax.text(0, 0.30, f"unexplained structure: {r.unexplained_structure}", fontsize=8, transform=ax.transAxes)
    fig.suptitle("Where the model and the recordings disagree: RMS of (measurement − model) per bin, before (eq. 14) and after")
    # margins in points (what tight_layout found, without drawing every tick): y tick labels + the 7 pt y label
    # left of each panel, the 45 degree bin labels below each row, the 9 pt titles and the 12 pt suptitle above
    ylab = _LINE * 7 + _LABELPAD_PT
    ywid = [_ytick_w_pt(ax) + ylab for ax in axes.flat[:-1]]
    xlab = [max((_rotated_h_pt(b.bin, 7, 45) for fb in r.where_baseline[4 * i:4 * i + 4] for b in fb.bins), default=0.0) + _TICK_PT
            for i in range(2)]
    title = _TITLEPAD_PT + _TITLE * 9
    pt = 1 / 72  # inches per point
    set_margins_in(fig, left=pt * (_PAD_PT + max(ywid[0], ywid[4] if len(ywid) > 4 else 0.0)), right=pt * _PAD_PT,
                   top=pt * (_PAD_PT + title + _PAD_PT + _LINE * 12), bottom=pt * (_PAD_PT + xlab[1]),
                   wspace=pt * (_PAD_PT + max(ywid[1:4] + ywid[5:])), hspace=pt * (_PAD_PT + xlab[0] + title))
    return fig


def plot_heldout_steps(r: DiagnosisReport, fig=None):
    """Held-out RMS after each accepted term (fitted without those experiments), against the noise floor. Returns the Figure."""
    import matplotlib.pyplot as plt

    fig = fig or plt.figure(figsize=(7, 4.2))
    ax = fig.subplots()
    steps = [s for s in r.heldout.steps if s.rmse_N is not None]
    if steps:
        xi = np.arange(len(steps))
        cols = ["C3"] + ["C0" if REGISTRY[s.effects[-1]].catalogue else "C1" for s in steps[1:]]
        ax.bar(xi, [s.rmse_N for s in steps], color=cols)
        for x, s in zip(xi, steps):
            ax.text(x, s.rmse_N, f"{s.rmse_N:.1f}", ha="center", va="bottom", fontsize=8)
        ax.set_xticks(xi, [s.label for s in steps], rotation=20, ha="right", fontsize=8)
        ax.set_yscale("log")
        _plain_log_ticks(ax)
        top = max(s.rmse_N for s in steps)
        ax.set_ylim(min(min(s.rmse_N for s in steps), r.noise_floor_N) * 0.6, top * 2.2)
    else:
        ax.text(0.5, 0.5, "held-out error not assessable\n(too few experiments)", ha="center", va="center", transform=ax.transAxes)
    ax.axhline(r.noise_floor_N, color="k", ls="--", lw=0.8)
    ax.axhline(2 * r.noise_floor_N, color="k", ls=":", lw=0.8)
    from matplotlib.patches import Patch
    from matplotlib.lines import Line2D

    ax.legend(handles=[Patch(color="C3", label="eq. 14"), Patch(color="C0", label="+ catalogue effect"), Patch(color="C1", label="+ discovered term"),
                       Line2D([], [], color="k", ls="--", lw=0.8, label="noise floor"), Line2D([], [], color="k", ls=":", lw=0.8, label="2 x noise floor")],
              fontsize=7, loc="upper right", ncol=2)
    ax.set_ylabel("held-out RMS of measurement − model [N]")
    ax.set_title("Held-out error as terms are added (experiments not used in selection or fit)", fontsize=9)
    tight_layout_once(fig)  # the rotated step names may reach into the left margin: let tight_layout measure them
    return fig


def plot_worst(diag: Diagnosis, fig=None):
    """The worst experiments of eq. 14: force and residual (measurement − model) against x. Returns the Figure."""
    import matplotlib.pyplot as plt

    D = diag.data
    fb, ff = diag.baseline.predict(D), diag.final.predict(D)
    worst = diag.report.worst_experiments[:4]
    fig = fig or plt.figure(figsize=(4 * max(len(worst), 1), 6))
    axes = fig.subplots(2, max(len(worst), 1), squeeze=False, gridspec_kw={"height_ratios": [2, 1]})
    titles = []
    for j, w in enumerate(worst):
        e = w.exp_index
        a, b = D.bounds[e], D.bounds[e + 1]
        ax, axr = axes[0, j], axes[1, j]
        ax.plot(D.x[a:b], D.y[a:b], ".", ms=2, color="0.4", label="measured")
        ax.plot(D.x[a:b], fb[a:b], "-", color="C3", lw=1, label="eq. 14")
        ax.plot(D.x[a:b], ff[a:b], "-", color="C2", lw=1, label="final model")
        titles.append((ax, f"{w.experiment}: p2 {w.p2_MPa:g} MPa, γ {w.valve_deg:g}°, {w.speed_mm_s:g} mm/s"))
        axr.plot(D.x[a:b], D.y[a:b] - fb[a:b], color="C3", lw=0.8)
        axr.plot(D.x[a:b], D.y[a:b] - ff[a:b], color="C2", lw=0.8)
        axr.axhline(0, color="k", lw=0.5)
        axr.set_xlabel("displacement x [mm]")
        if j == 0:
            ax.set_ylabel("force (+ = tension) [N]")
            axr.set_ylabel("measurement − model [N]")
            ax.legend(fontsize=7)
    fig.suptitle("Worst experiments of eq. 14, before and after the accepted terms")
    if any(_has_offset_text(a) for a in axes.flat):  # an offset text above a panel: let tight_layout place it
        for ax, t in titles:
            ax.set_title(t, fontsize=8)
        tight_layout_once(fig)
        return fig
    for ax, t in titles:
        ax.set_title(t, fontsize=8, y=1.0)  # fixed: ticks are below and there is no offset text
    # margins in points (what tight_layout found, without drawing every tick): the 10 pt y tick labels of each
    # column (+ the y labels left of the first), 10 pt x tick labels below each row (+ the x label under the
    # second), the 8 pt titles and the 12 pt suptitle above
    line = _LINE * 10
    yw = [max(_ytick_w_pt(axes[0, j]), _ytick_w_pt(axes[1, j])) for j in range(axes.shape[1])]
    left = _PAD_PT + yw[0] + _LABELPAD_PT + line
    top = _PAD_PT + (_TITLEPAD_PT + _TITLE * 8 if titles else 0.0) + _PAD_PT + _LINE * 12
    hgap = _PAD_PT + _TICK_PT + line
    bottom = _PAD_PT + _TICK_PT + line + _LABELPAD_PT + line
    pt = 1 / 72  # inches per point
    set_margins_in(fig, left=pt * left, right=pt * _PAD_PT, top=pt * top, bottom=pt * bottom,
                   wspace=pt * (_PAD_PT + max(yw[1:], default=0.0)), hspace=pt * hgap)
    return fig


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
    for name, fig in (("residual_maps.png", plot_residual_maps(r)), ("heldout_per_effect.png", plot_heldout_steps(r)), ("worst_experiments.png", plot_worst(diag))):
        fig.savefig(out / name, dpi=80)
        plt.close(fig)
    return ["report.json", "final_model.json", "summary.md", "residual_maps.png", "heldout_per_effect.png", "worst_experiments.png"]
