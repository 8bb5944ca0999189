"""Settings of the diagnosis (:func:`~vvea_design.identification.diagnose.diagnose`): the benchmarked defaults."""

from __future__ import annotations

from dataclasses import dataclass

from .effects import DISCOVERY_IDS, EFFECT_IDS

__all__ = ["DiagnoseSettings"]


@dataclass(frozen=True)
class DiagnoseSettings:
    """Settings of :func:`~vvea_design.identification.diagnose.diagnose` (the defaults are the benchmarked ones)."""

    n_folds: int = 5  #: grouped-CV folds (whole experiments)
    test_fraction: float = 0.2  #: experiments held out of selection and fit
    min_gain: float = 0.02  #: minimum relative reduction of the CV mean square
    min_t: float = 3.0  #: minimum paired t over held-out experiments
    min_halved: int = 1  #: ... or at least this many badly fit (RMS > 2 x noise) held-out experiments with their squared error halved
    min_folds: int = 4  #: stability: the term improves at least this many folds (of n_folds)
    min_snr: float = 0.25  #: minimum effect RMS / residual RMS
    name_t: float = 2.0  #: a catalogue effect loses its name when a discovery operator is better by this paired t
    noise_bound: bool = True  #: the noise floor is at most the grouped-CV RMS of eq. 14 + trees on the states (identification.general)
    name_evidence: bool = True  #: a catalogue name must beat general terms on the states (identification.general)
    name_states_share: float = 0.2  #: ... trees on the formula's states reach this share of what trees on all states reach
    name_general_share: float = 0.75  #: ... and the formula this share of what trees on its states reach (unless not significant, paired t <= name_t)
    keep_catalogue_share: float = 0.8  #: backward step: a catalogue term explained away by discovered terms after it stays when, without them, it removes this share of what they remove without it
    keep_noise: float = 0.5  #: backward step: an accepted term stays only if its force RMS is at least keep_noise x the noise floor and, beside all other accepted terms, it lowers the held-out mean square by at least (keep_noise x noise floor)^2 and still passes the gain, consistency and fold tests
    guard_min_drop_N: float = 0.0  #: held-out guard: a kept term lowers the held-out RMS by more than this (N)
    max_effects: int = 6  #: at most this many accepted terms
    seed: int = 0  #: seed of the experiment splits
    learner: bool = True  #: run the flexible-learner check
    learner_min_gain: float = 0.10  #: learner must explain this share of residual variance ...
    learner_min_ratio: float = 1.0  #: ... and an RMS of at least this times the noise
    learner_rows: int = 8000  #: rows sub-sampled for the learner
    candidates: tuple = EFFECT_IDS  #: catalogue effect ids to test
    discovery: tuple = DISCOVERY_IDS  #: discovery operators to test (empty: catalogue only)
    library: bool = True  #: each selection round also tests the sparse state-library candidate (effects.library)
    last_stage: bool = True  #: fit the last stage (gradient-boosted trees on the states the residual depends on; identification.last_stage)
    last_stage_gate: float = 1.1  #: ... only when the held-out RMS exceeds this x the noise floor
    last_stage_learner_gain: float = 0.3  #: ... or when the leftover learner predicts this share of the residual variance
    last_stage_min_drop: float = 0.02  #: ... kept only when it lowers the held-out RMS by this fraction (and by 0.05 x noise)
    last_stage_rows: int = 20000  #: rows sub-sampled to fit the last stage
    min_experiments_cv: int = 6  #: fewer experiments than this: no selection (nothing can be cross-validated)
