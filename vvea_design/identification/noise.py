"""What the residuals hold: the noise floor, where they sit, and whether a flexible learner still finds structure.

- :func:`noise_floor_N` -- what no smooth model of the cycle can explain: per
  ramp, the periodogram of the residual with spectral lines removed by a
  running median and the lowest bins (slow misfit) excluded, fitted by an
  AR(1) spectrum whose integral is the noise variance. Periodic (lines) and
  slow structure cannot inflate it.
- :func:`residual_map` -- residual statistics per bin of displacement,
  speed, direction, time since reversal, pressure, valve and campaign time.
- :func:`learner_check` -- gradient-boosted trees on the final residuals
  (grouped CV by experiment): structure is left when they predict the
  residuals beyond the noise floor; where, by permutation importance.

Residual sign: residual = measurement − model (N).
"""

from __future__ import annotations

import functools

import numpy as np

from .fit_data import FitData, cached
from .report import LearnerCheck, ResidualBin, ResidualFeature, StructureWhere
from .settings import DiagnoseSettings

__all__ = ["NOISE_METHOD", "noise_floor_N", "residual_map", "learner_check"]


# ------------------------------------------------------------------ noise floor
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


# ------------------------------------------------------------------ residual map
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


# ------------------------------------------------------------------ flexible-learner check
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
    feats = np.column_stack([D.x, D.v, np.abs(D.v), np.sign(D.v), np.log10(D.tsr + 1e-3), D.p2, D.valve, D.ctime, D.t])
    names = ["displacement", "velocity", "speed", "direction", "time_since_reversal", "p2", "valve", "campaign_time", "time_in_experiment"]
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
