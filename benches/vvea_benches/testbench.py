"""A test-bench simulator: tension-test campaigns with concealed effects.

Generates campaigns in the exchange format of ``shared/specs/recordings.md``
(the paper's p2 x valve x speed grid, 0 -> 40 -> 0 mm, shuffled run order)
from eq. 14 plus any of the catalogue's effects, with randomised parameters,
correlated force noise (AR(1) within each experiment) and white
displacement noise. The diagnosis tool is told nothing but the recordings;
the simulator also returns the truth (noise-free force, effect parameters,
signal-to-noise ratio of each effect) so a benchmark can score it.

The truth here is deliberately *not* identical to the candidate terms of
:mod:`vvea_design.identification.effects`: the gas spring uses random V1 *and* V2, stiction
a random Stribeck exponent, leakage an exponential decay, the relief valve
a hard cap on the true (not estimated) velocity, the thermal state is
integrated from the true velocity.

Signal-to-noise ratio of an effect (the benchmark's x axis)::

    SNR = RMS over the campaign of the part of the effect's force that eq. 14
          cannot represent (its least-squares residual against the eq.-14
          columns p2 x, sign(ẋ), ẋ·1{γ}) / RMS of the force noise
"""

from __future__ import annotations

from dataclasses import dataclass, field, replace

import numpy as np
import pandas as pd

from vvea_design.identification.effects import REGISTRY
from vvea_design.identification.recordings import trapezoid_profile
from vvea_design.spring.gas_spring import GasSpring
from vvea_design.spring.paper import PAPER_FIG5

__all__ = [
    "TABLE3_L",
    "TruthEffect",
    "CampaignSpec",
    "Campaign",
    "simulate",
    "random_effect",
    "effect_force_N",
    "snr",
    "BenchmarkCase",
    "small_spec",
    "make_cases",
    "case_spec",
    "run_case",
    "summarise_benchmark",
]

#: Table 3's damping per valve position (N s/mm).
TABLE3_L: dict[float, float] = {50: 0.4, 80: 0.5, 100: 7.1, 104: 15.1, 106: 25.3, 108: 40.6, 109: 52.7, 110: 85.2, 120: 1024.7}


@dataclass(frozen=True)
class TruthEffect:
    """An effect present in the simulated bench.

    ``params`` (physical units) per id:

    - ``gas_nonlinearity``: ``V1_mm3``, ``V2_mm3``, ``amp`` (1 = reference areas)
    - ``thermal``: ``k_N_per_mm_MPa``, ``tau_s``
    - ``quadratic_damping``: ``K_N_s2_per_mm2`` (dict valve -> K)
    - ``relief_valve``: ``F_r_N``
    - ``stiction``: ``S_N``, ``v_s_mm_s``, ``delta``
    - ``pressure_friction``: ``c_p_N_per_MPa``
    - ``leakage``: ``rate_per_h``
    """

    id: str
    params: dict


@dataclass(frozen=True)
class CampaignSpec:
    """What the simulated bench runs and how it is built."""

    pressures_MPa: tuple = (1.0, 2.0, 4.0)
    valves_deg: tuple = (50.0, 80.0, 100.0, 104.0, 106.0, 108.0, 109.0, 110.0, 120.0)
    speeds_mm_s: tuple = (0.1, 1.0, 4.0, 8.0, 12.0)
    travel_mm: float = PAPER_FIG5.travel_mm
    samples: int = 301  #: samples per experiment
    accel_time_s: float = 0.2  #: time to reach the cruise speed
    g_N_per_mm_MPa: float = 23.31
    C_N: float = 125.5
    L_N_s_per_mm: dict = field(default_factory=lambda: dict(TABLE3_L))
    noise_N: float = 4.0  #: marginal RMS of the force noise
    noise_rho: float = 0.7  #: AR(1) coefficient of the force noise between samples
    displacement_noise_mm: float = 0.002
    effects: tuple = ()  #: TruthEffect entries
    reference: GasSpring = PAPER_FIG5  #: areas used by the gas law
    seed: int = 0
    shuffle: bool = True

    @property
    def n_experiments(self) -> int:
        return len(self.pressures_MPa) * len(self.valves_deg) * len(self.speeds_mm_s)


@dataclass(frozen=True)
class Campaign:
    """A simulated campaign and its truth."""

    frame: pd.DataFrame  #: the recordings (exchange format + ``force_true_N``)
    spec: CampaignSpec
    snr: dict  #: effect id -> SNR (see module doc)
    effect_rms_N: dict  #: effect id -> RMS of its non-eq.-14 part (N)


# ------------------------------------------------------------------ physics of the bench
def effect_force_N(eff: TruthEffect, cols: dict, spec: CampaignSpec) -> np.ndarray:
    """Force (N) the effect adds to eq. 14 at the samples in ``cols`` (the registry's bench force).

    ``cols`` holds arrays ``x, v, p2, valve, ctime_h, exp, t`` (true kinematics).

    Parameters
    ----------
    eff : TruthEffect
        The effect and its parameters (physical units, see :class:`TruthEffect`).
    cols : dict of str to numpy.ndarray
        True kinematics per sample: ``x`` (mm), ``v`` (mm/s), ``p2`` (MPa),
        ``valve`` (deg), ``ctime_h`` (campaign time, h), ``exp`` (experiment
        index), ``t`` (s within the experiment).
    spec : CampaignSpec
        The simulated bench (reference unit, valve angles, travel in mm).

    Returns
    -------
    numpy.ndarray
        Added force per sample, N (force > 0 is tension).

    Raises
    ------
    ValueError
        If ``eff.id`` is not in the effect registry.
    """
    if eff.id not in REGISTRY:
        raise ValueError(f"unknown effect id {eff.id!r}")
    return REGISTRY[eff.id].bench_force(eff.params, cols, spec)


def _eq14_columns(cols, valves):
    X = [cols["p2"] * cols["x"], np.sign(cols["v"])]
    X += [cols["v"] * (cols["valve"] == g) for g in valves]
    return np.column_stack(X)


def snr(force_N: np.ndarray, cols: dict, valves, noise_N: float) -> tuple[float, float]:
    """(SNR, RMS in N) of the part of ``force_N`` eq. 14 cannot represent.

    Parameters
    ----------
    force_N : numpy.ndarray
        Force of one effect per sample, N.
    cols : dict of str to numpy.ndarray
        Kinematics per sample; ``x`` (mm), ``v`` (mm/s), ``p2`` (MPa) and
        ``valve`` (deg) are used.
    valves : sequence of float
        Valve angles of the campaign, deg (one damping column each).
    noise_N : float
        RMS of the force noise, N.

    Returns
    -------
    snr : float
        RMS of the least-squares residual of ``force_N`` against the eq.-14
        columns divided by ``noise_N``, dimensionless.
    rms : float
        That residual RMS, N.
    """
    X = _eq14_columns(cols, valves)
    th, *_ = np.linalg.lstsq(X, force_N, rcond=None)
    r = force_N - X @ th
    rms = float(np.sqrt(np.mean(r**2)))
    return rms / noise_N, rms


# ------------------------------------------------------------------ campaign
def _kinematics(spec: CampaignSpec, rng: np.random.Generator):
    grid = [(p, g, s) for p in spec.pressures_MPa for g in spec.valves_deg for s in spec.speeds_mm_s]
    order = rng.permutation(len(grid)) if spec.shuffle else np.arange(len(grid))
    parts = []
    t_off = 0.0
    for k, i in enumerate(order):
        p, g, s = grid[i]
        ta = min(spec.accel_time_s, 0.25 * spec.travel_mm / s)
        a = s / ta
        t_rev = spec.travel_mm / s + ta
        t = np.linspace(0.0, 2 * t_rev, spec.samples)
        x, v = trapezoid_profile(t, s, a, t_rev)
        parts.append(
            dict(exp=np.full(len(t), k), t=t, x=x, v=v, p2=np.full(len(t), p), valve=np.full(len(t), float(g)), speed=np.full(len(t), s), ctime_h=(t_off + t) / 3600.0)
        )
        t_off += t[-1] + 60.0  # a minute between experiments
    cols = {key: np.concatenate([q[key] for q in parts]) for key in parts[0]}
    return cols


def simulate(spec: CampaignSpec) -> Campaign:
    """Simulate a campaign.

    Parameters
    ----------
    spec : CampaignSpec
        The bench: grid of pressures (MPa), valve angles (deg) and speeds
        (mm/s), eq.-14 parameters (N/mm/MPa, N, N s/mm), noise (N, mm), the
        concealed effects and the seed.

    Returns
    -------
    Campaign
        ``frame`` has the exchange-format columns plus ``force_true_N`` (the
        noise-free force, ignored by the reader).
    """
    rng = np.random.default_rng(spec.seed)
    cols = _kinematics(spec, rng)
    L = np.array([spec.L_N_s_per_mm[float(g)] for g in cols["valve"]])
    f = spec.g_N_per_mm_MPa * cols["p2"] * cols["x"] + L * cols["v"] + spec.C_N * np.sign(cols["v"])
    snrs, rmss = {}, {}
    for eff in spec.effects:
        fe = effect_force_N(eff, cols, spec)
        snrs[eff.id], rmss[eff.id] = snr(fe, cols, spec.valves_deg, spec.noise_N)
        f = f + fe
    # AR(1) force noise within each experiment, marginal RMS noise_N
    n = len(f)
    w = rng.standard_normal(n) * spec.noise_N * np.sqrt(1 - spec.noise_rho**2)
    from scipy.signal import lfilter

    noise = np.empty(n)
    for e in np.unique(cols["exp"]):
        m = np.flatnonzero(cols["exp"] == e)
        w0 = w[m].copy()
        w0[0] = rng.standard_normal() * spec.noise_N
        noise[m] = lfilter([1.0], [1.0, -spec.noise_rho], w0)
    xm = cols["x"] + rng.standard_normal(n) * spec.displacement_noise_mm
    frame = pd.DataFrame(
        dict(
            experiment=[f"S{int(e):03d}" for e in cols["exp"]],
            time_s=np.round(cols["t"], 6),
            displacement_mm=np.round(xm, 5),
            force_N=np.round(f + noise, 3),
            p2_MPa=cols["p2"],
            valve_deg=cols["valve"],
            speed_mm_s=cols["speed"],
            force_true_N=f,
        )
    )
    return Campaign(frame, spec, snrs, rmss)


# ------------------------------------------------------------------ random effects
def random_effect(eid: str, target_snr: float, spec: CampaignSpec, rng: np.random.Generator) -> TruthEffect:
    """A random instance of effect ``eid`` whose SNR in ``spec``'s campaign is ``target_snr``.

    Shape parameters are drawn at random (the registry's ``bench_random``);
    the strength (amplitude, or the relief force / leak rate) is set by
    bisection on the SNR.

    Parameters
    ----------
    eid : str
        Effect id, a key of the effect registry.
    target_snr : float
        Signal-to-noise ratio to reach (see the module doc), dimensionless.
    spec : CampaignSpec
        The bench the effect will be simulated in (its effects are ignored).
    rng : numpy.random.Generator
        Source of the random shape parameters.

    Returns
    -------
    TruthEffect
        The effect with its parameters in physical units.

    Raises
    ------
    ValueError
        If ``eid`` is not in the effect registry.
    """
    if eid not in REGISTRY:
        raise ValueError(f"unknown effect id {eid!r}")
    eff = REGISTRY[eid]
    base = eff.bench_random(rng, spec)
    cols = _kinematics(replace(spec, effects=()), np.random.default_rng(spec.seed))

    def snr_of(s):
        return snr(eff.bench_force(eff.bench_with_strength(base, s), cols, spec), cols, spec.valves_deg, spec.noise_N)[0]

    def make(s):
        return TruthEffect(eid, eff.bench_with_strength(base, float(s)))

    if eff.bench_linear:
        return make(target_snr / snr_of(1.0))
    lo, hi = np.log(np.array(eff.bench_strength_range(cols, spec)))
    if not eff.bench_snr_rises and snr_of(np.exp(lo)) < target_snr:
        return make(np.exp(lo))
    for _ in range(50):
        mid = 0.5 * (lo + hi)
        above = snr_of(np.exp(mid)) > target_snr
        if eff.bench_snr_rises:
            lo, hi = (lo, mid) if above else (mid, hi)
        else:
            lo, hi = (mid, hi) if above else (lo, mid)
    return make(np.exp(0.5 * (lo + hi)))


# ------------------------------------------------------------------ benchmark
@dataclass(frozen=True)
class BenchmarkCase:
    """One benchmark campaign: which effects at which target SNR, and the seed."""

    kind: str  #: "null", "single" or "combined"
    effects: tuple  #: effect ids present
    target_snr: tuple  #: target SNR per effect
    seed: int
    n_experiments_scale: str = "full"  #: "full" (135 experiments) or "small" (CI)
    learner: bool = False  #: run the flexible-learner check


def small_spec(**kw) -> CampaignSpec:
    """A reduced campaign for CI: 2 pressures x 5 valves x 3 speeds, 151 samples.

    Parameters
    ----------
    **kw
        Further :class:`CampaignSpec` fields (units in their names), which
        override the reduced grid too.

    Returns
    -------
    CampaignSpec
        The reduced bench: p2 1 and 4 MPa, valves 50, 100, 108, 110, 120 deg,
        speeds 0.1, 4 and 12 mm/s.
    """
    base = dict(
        pressures_MPa=(1.0, 4.0),
        valves_deg=(50.0, 100.0, 108.0, 110.0, 120.0),
        speeds_mm_s=(0.1, 4.0, 12.0),
        samples=151,
    )
    base.update(kw)
    return CampaignSpec(**base)


def make_cases(
    n_single: int = 16,
    n_null: int = 20,
    n_combined: int = 14,
    snr_range: tuple = (0.05, 8.0),
    seed: int = 0,
    effects: tuple | None = None,
    scale: str = "full",
    learner: bool = False,
) -> list[BenchmarkCase]:
    """The benchmark's campaigns: every effect alone at log-uniform SNRs, null campaigns, random pairs.

    Parameters
    ----------
    n_single : int
        Number of single-effect campaigns per effect, stratified in log SNR over ``snr_range``.
    n_null : int
        Number of campaigns without any effect (for the false-positive rate).
    n_combined : int
        Number of campaigns with a random pair of effects, each at an SNR
        drawn log-uniformly between 2 and ``snr_range[1]``.
    snr_range : tuple of float
        (lowest, highest) target SNR, dimensionless.
    seed : int
        Seed of the draws; case seeds are ``seed * 100000 + k``.
    effects : tuple of str, optional
        Effect ids to test (default: every catalogue effect).
    scale : str
        ``"full"`` (the paper's 135-experiment grid) or ``"small"`` (:func:`small_spec`).
    learner : bool
        Run the flexible-learner check in the diagnosis of each case.

    Returns
    -------
    list of BenchmarkCase
        Single-effect cases first, then the null and the combined ones.
    """
    from vvea_design.identification.effects import EFFECT_IDS

    effects = tuple(effects or EFFECT_IDS)
    rng = np.random.default_rng(seed)
    lo, hi = np.log(snr_range[0]), np.log(snr_range[1])
    cases = []
    k = 0
    for eid in effects:
        for i in range(n_single):
            # stratified in log SNR so each effect covers the whole range
            u = (i + rng.uniform()) / n_single
            cases.append(BenchmarkCase("single", (eid,), (float(np.exp(lo + u * (hi - lo))),), seed * 100000 + k, scale, learner))
            k += 1
    for i in range(n_null):
        cases.append(BenchmarkCase("null", (), (), seed * 100000 + k, scale, learner))
        k += 1
    for i in range(n_combined):
        pair = tuple(rng.choice(len(effects), 2, replace=False))
        cases.append(
            BenchmarkCase(
                "combined",
                tuple(effects[j] for j in pair),
                tuple(float(np.exp(rng.uniform(np.log(2.0), hi))) for _ in pair),
                seed * 100000 + k,
                scale,
                learner,
            )
        )
        k += 1
    return cases


def case_spec(case: BenchmarkCase) -> CampaignSpec:
    """The randomised bench of a case (parameters, noise and effects drawn from its seed).

    Parameters
    ----------
    case : BenchmarkCase
        The case: its effects, target SNRs, seed and scale.

    Returns
    -------
    CampaignSpec
        The bench with g within ±10 % of 23.31 N/mm/MPa, C within ±20 % of
        125.5 N, Table 3's damping scattered by about 10 %, force noise
        2-6 N RMS, and the case's effects at their target SNRs.
    """
    rng = np.random.default_rng(case.seed)
    L = {g: float(v * np.exp(rng.normal(0, 0.1))) for g, v in TABLE3_L.items()}
    kw = dict(
        g_N_per_mm_MPa=float(23.31 * rng.uniform(0.9, 1.1)),
        C_N=float(125.5 * rng.uniform(0.8, 1.2)),
        L_N_s_per_mm=L,
        noise_N=float(rng.uniform(2.0, 6.0)),
        noise_rho=float(rng.uniform(0.3, 0.9)),
        seed=case.seed,
    )
    spec = small_spec(**kw) if case.n_experiments_scale == "small" else CampaignSpec(**kw)
    effs = tuple(random_effect(e, s, spec, rng) for e, s in zip(case.effects, case.target_snr))
    return replace(spec, effects=effs)


def run_case(case: BenchmarkCase) -> dict:
    """Simulate a case, diagnose it blind, and score the result (picklable, for ``parallel_map``).

    Parameters
    ----------
    case : BenchmarkCase
        The case to run.

    Returns
    -------
    dict
        The score: ``snr`` per effect (dimensionless), ``accepted``,
        ``discovered``, ``detected`` and ``false_positives`` effect ids,
        held-out RMS errors of the baseline, the final and the true model
        (``heldout_*_N``, N), ``noise_floor_N`` and ``noise_N`` (N),
        ``noise_rho``, ``unexplained_structure`` and the times taken
        (``simulate_read_s``, ``diagnose_s``, s).
    """
    import time

    from vvea_design.identification.diagnose import diagnose
    from vvea_design.identification.recordings import recordings_from_frame
    from vvea_design.identification.settings import DiagnoseSettings

    t0 = time.perf_counter()
    spec = case_spec(case)
    camp = simulate(spec)
    rec = recordings_from_frame(camp.frame.drop(columns=["force_true_N"]), source=f"bench-{case.seed}")
    t1 = time.perf_counter()
    diag = diagnose(rec, DiagnoseSettings(learner=case.learner))
    t2 = time.perf_counter()
    rep = diag.report
    accepted = list(rep.accepted_catalogue_ids)
    # the true model's held-out error: measured minus the noise-free force on the same samples
    D = diag.data
    keep = ~rec.data["at_rest"].to_numpy()
    ftrue = camp.frame["force_true_N"].to_numpy()[keep]
    m = np.isin(D.exp, rep.heldout.test_experiments)
    true_rmse = float(np.sqrt(np.mean((D.y[m] - ftrue[m]) ** 2)))
    return dict(
        kind=case.kind,
        seed=case.seed,
        effects=list(case.effects),
        snr={k: float(v) for k, v in camp.snr.items()},
        accepted=accepted,
        discovered=[e.id for e in rep.accepted if not e.catalogue],
        detected={e: (e in accepted) for e in case.effects},
        false_positives=[e for e in accepted if e not in case.effects],
        heldout_baseline_N=rep.heldout.baseline_N,
        heldout_final_N=rep.heldout.final_N,
        heldout_true_N=true_rmse,
        noise_floor_N=rep.noise_floor_N,
        noise_N=spec.noise_N,
        noise_rho=spec.noise_rho,
        unexplained_structure=rep.unexplained_structure,
        simulate_read_s=t1 - t0,
        diagnose_s=t2 - t1,
    )


def summarise_benchmark(results: list[dict], snr_bins=(0.0, 0.1, 0.25, 0.5, 1.0, 2.0, 4.0, np.inf)) -> dict:
    """Detection rate per effect against SNR, false-positive rate, held-out gap closure.

    Parameters
    ----------
    results : list of dict
        Outputs of :func:`run_case`.
    snr_bins : sequence of float
        Edges of the SNR bins for the detection rates, dimensionless.

    Returns
    -------
    dict
        ``per_effect`` (detection rate per SNR bin and at SNR >= 2, fraction),
        ``null`` (false-positive rate, fraction), ``spurious_rate_with_effects``
        (fraction), ``gap_closure_snr_ge_2`` (share of the gap between the
        baseline's and the true model's held-out RMS error that the final
        model closes, fraction; mean held-out RMS errors in N), ``diagnose_s``
        (median and max time per diagnosis, s) and ``n_campaigns``.
    """
    from vvea_design.identification.effects import EFFECT_IDS

    out: dict = {"per_effect": {}, "n_campaigns": len(results)}
    for eid in EFFECT_IDS:
        rows = [(r["snr"][eid], r["detected"][eid]) for r in results if eid in r["effects"]]
        if not rows:
            continue
        s = np.array([a for a, _ in rows])
        d = np.array([b for _, b in rows], bool)
        bins = []
        for lo, hi in zip(snr_bins[:-1], snr_bins[1:]):
            m = (s >= lo) & (s < hi)
            bins.append(dict(snr_lo=lo, snr_hi=None if not np.isfinite(hi) else hi, n=int(m.sum()), rate=float(d[m].mean()) if m.any() else None))
        hi_m = s >= 2.0
        out["per_effect"][eid] = dict(
            n=int(len(s)),
            n_snr_ge_2=int(hi_m.sum()),
            detection_rate_snr_ge_2=float(d[hi_m].mean()) if hi_m.any() else None,
            bins=bins,
        )
    nulls = [r for r in results if r["kind"] == "null"]
    out["null"] = dict(
        n=len(nulls),
        false_positive_rate=float(np.mean([bool(r["accepted"]) for r in nulls])) if nulls else None,
        accepted=[r["accepted"] for r in nulls if r["accepted"]],
    )
    withfx = [r for r in results if r["effects"]]
    out["spurious_rate_with_effects"] = float(np.mean([bool(r["false_positives"]) for r in withfx])) if withfx else None
    strong = [r for r in withfx if min(r["snr"].values()) >= 2.0]
    if strong:
        base = np.array([r["heldout_baseline_N"] for r in strong])
        fin = np.array([r["heldout_final_N"] for r in strong])
        tru = np.array([r["heldout_true_N"] for r in strong])
        clos = (base - fin) / np.maximum(base - tru, 1e-9)
        out["gap_closure_snr_ge_2"] = dict(
            n=len(strong),
            aggregate=float((base - fin).sum() / (base - tru).sum()),
            median=float(np.median(clos)),
            fraction_at_least_half=float(np.mean(clos >= 0.5)),
            heldout_rmse_mean_N=dict(baseline=float(base.mean()), final=float(fin.mean()), true=float(tru.mean())),
        )
    out["diagnose_s"] = dict(
        median=float(np.median([r["diagnose_s"] for r in results])), max=float(np.max([r["diagnose_s"] for r in results]))
    )
    return out
