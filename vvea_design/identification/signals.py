"""Signal operators on a campaign's samples, experiment by experiment: the building blocks of the effects' columns.

- :func:`lowpass` -- first-order low-pass ``τ ẏ = u - y`` (started in steady state);
- :func:`thermal_state` -- the relaxing state ``ḣ = u̇ - h/τ`` (started at 0);
- :func:`stop_operator` -- Prandtl stop operator of width r on x (pre-sliding memory);
- :func:`travel_since_reversal`, :func:`first_ramp` -- where each sample sits on its ramp;
- :func:`periodogram_peaks` -- periods of the highest lines of a signal against another;
- :func:`filter_design` -- a design matrix through a causal sensor filter, run on a time grid finer than
  the sampling (the samples left out at rest still pass the sensor; the motion's velocity between
  samples is followed where a ramp starts, ends or reverses).

Experiments of the same sample spacing (and length) are filtered together, bit for bit as one by one.
Everything that is a function of the campaign alone is cached on it
(:func:`~vvea_design.identification.fit_data.cached`).
"""

from __future__ import annotations

import functools

import numpy as np
from scipy.signal import lfilter

from .fit_data import FitData, cached

__all__ = ["lowpass", "thermal_state", "stop_operator", "travel_since_reversal", "first_ramp", "periodogram_peaks",
           "filter_design"]


def lowpass(D: FitData, u: np.ndarray, tau_s: float) -> np.ndarray:
    """First-order low-pass ``τ ẏ = u - y`` per experiment, started in steady state (y = u at the first sample).

    Parameters
    ----------
    D : FitData
        The campaign: its experiment bounds and sample spacing (s) are used.
    u : numpy.ndarray, shape (D.n,)
        Signal per sample, in any unit (e.g. a force in N or a displacement
        in mm); the output keeps its unit.
    tau_s : float
        Time constant τ, s.

    Returns
    -------
    numpy.ndarray, shape (D.n,)
        The filtered signal, same unit as ``u``.
    """
    out = np.empty_like(u, dtype=float)
    u = np.asarray(u, dtype=float)
    for dt, idx, valid in _same_dt_blocks(D):  # experiments of one spacing filtered together (bit for bit the same)
        q = np.exp(-dt / tau_s)
        seg = u[idx]
        out[idx[valid]] = lfilter([1.0 - q], [1.0, -q], seg, axis=1, zi=q * seg[:, :1])[0][valid]
    return out


def _same_dt_blocks(D: FitData):
    """Experiments grouped by their sample spacing, as padded row-index blocks (cached).

    Each block: ``(dt, idx, valid)``: ``dt`` the spacing (s) of its
    experiments, ``idx`` (n_e, longest) the rows of D per experiment (padded
    with its last row), ``valid`` where ``idx`` is a real sample. A causal
    filter run along axis 1 of ``u[idx]`` gives, on the valid samples, what
    it gives experiment by experiment (padding only follows the end).
    """
    return cached(D, ("same_dt_blocks",), lambda: _make_same_dt_blocks(D))


def _make_same_dt_blocks(D: FitData):
    dts = D.per_exp_dt()
    groups: dict = {}
    for e in range(D.n_exp):
        if D.bounds[e + 1] > D.bounds[e]:
            groups.setdefault(float(dts[e]), []).append(e)
    out = []
    for dt, exps in groups.items():
        n_e = np.array([D.bounds[e + 1] - D.bounds[e] for e in exps])
        j = np.arange(n_e.max())
        valid = j[None, :] < n_e[:, None]
        idx = np.array([D.bounds[e] for e in exps])[:, None] + np.minimum(j[None, :], n_e[:, None] - 1)
        out.append((dt, idx, valid))
    return out


def thermal_state(D: FitData, tau_s: float, u: np.ndarray | None = None, name: str = "x") -> np.ndarray:
    """Thermal state h: ḣ = u̇ - h/τ per experiment, h = 0 at start (``u`` = x by default, mm; ``name`` keys the cache).

    Exact for piecewise-linear u between samples. ``k p2 h`` is the excess
    gas force that heat exchange with the walls relaxes with time constant τ.

    Parameters
    ----------
    D : FitData
        The campaign: its experiment bounds, sample spacing (s) and x (mm).
    tau_s : float
        Time constant τ of the heat exchange, s.
    u : numpy.ndarray, shape (D.n,), optional
        Driving signal, in any unit (default: the displacement x, mm); h has
        the same unit.
    name : str
        Cache key of ``u``: give each different ``u`` its own name.

    Returns
    -------
    numpy.ndarray, shape (D.n,)
        The state h per sample, unit of ``u`` (mm by default). Cached: do not
        modify it in place.
    """
    return cached(D, ("thermal", float(tau_s), name), lambda: _thermal_state(D, tau_s, D.x if u is None else u))


def _thermal_state(D: FitData, tau_s: float, u: np.ndarray) -> np.ndarray:
    h = np.zeros(D.n)
    u = np.asarray(u, dtype=float)
    dx = np.diff(u, prepend=u[:1]) if D.n else u.copy()
    dx[D.bounds[:-1][D.bounds[:-1] < D.n]] = 0.0  # each experiment starts at rest: no step into its first sample
    for dt, idx, valid in _same_dt_blocks(D):  # experiments of one spacing filtered together (bit for bit the same)
        q = np.exp(-dt / tau_s)
        gain = tau_s * (1 - q) / dt
        h[idx[valid]] = lfilter([gain], [1.0, -q], dx[idx], axis=1)[valid]
    return h


def stop_operator(D: FitData, r_mm: float) -> np.ndarray:
    """Prandtl stop operator of width ``r`` on x (mm, in [-r, r]), relaxed (0) at each experiment's start.

    ``x - play_r(x)``: follows x for the first ``r`` after a reversal, then
    saturates at ±r -- elastic-plastic (pre-sliding) memory of the motion.
    Each ramp is monotone, so the play operator is a running max/min.

    Parameters
    ----------
    D : FitData
        The campaign: x (mm), direction of motion and experiment bounds.
    r_mm : float
        Width r of the operator, mm.

    Returns
    -------
    numpy.ndarray, shape (D.n,)
        Stop operator output per sample, mm, in [-r, r]. Cached: do not
        modify it in place.
    """
    return cached(D, ("stop", float(r_mm)), lambda: _stop_operator(D, r_mm))


def _stop_operator(D: FitData, r_mm: float) -> np.ndarray:
    z = np.zeros(D.n)
    x_all = D.x
    for a, b, runs in _monotone_runs(D):
        p = x_all[a:b][0]
        for lo, hi, up in runs:
            xs = x_all[lo:hi]
            if up:
                pp = np.maximum(p, np.maximum.accumulate(xs - r_mm))
            else:
                pp = np.minimum(p, np.minimum.accumulate(xs + r_mm))
            z[lo:hi] = xs - pp
            p = pp[-1]
    return z


def _monotone_runs(D: FitData) -> list:
    """Per experiment ``(a, b, runs)``: its rows ``a:b`` and its runs of one direction of motion, ``(first row, end row, sign(ẋ) >= 0)``
    (rows of the campaign; cached: a function of the campaign alone, read by every stop operator)."""
    def make():
        out = []
        s = D.s
        for e in range(D.n_exp):
            a, b = int(D.bounds[e]), int(D.bounds[e + 1])
            ss = s[a:b]
            cuts = np.flatnonzero(np.diff(ss) != 0) + 1
            out.append((a, b, [(a + lo, a + hi, bool(ss[lo] >= 0)) for lo, hi in zip(np.r_[0, cuts].tolist(), np.r_[cuts, b - a].tolist())]))
        return out

    return cached(D, ("monotone_runs",), make)


def travel_since_reversal(D: FitData) -> np.ndarray:
    """|x - x at the last start or reversal| (mm), per experiment (cached).

    Parameters
    ----------
    D : FitData
        The campaign: x (mm), direction of motion and experiment bounds.

    Returns
    -------
    numpy.ndarray, shape (D.n,)
        Travel since the start of the experiment or its last reversal, mm. Cached: do not modify it in place.
    """
    def make():
        d = np.zeros(D.n)
        s = D.s
        for e in range(D.n_exp):
            a, b = D.bounds[e], D.bounds[e + 1]
            x = D.x[a:b]
            cuts = np.flatnonzero(np.diff(s[a:b]) != 0) + 1
            for lo, hi in zip(np.r_[0, cuts], np.r_[cuts, b - a]):
                x0 = x[0] if lo == 0 else x[lo - 1]
                d[a + lo : a + hi] = np.abs(x[lo:hi] - x0)
        return d

    return cached(D, ("travel_since_rev",), make)


def first_ramp(D: FitData) -> np.ndarray:
    """True on the samples before the first reversal of each experiment (the ramp that starts from rest; cached).

    Parameters
    ----------
    D : FitData
        The campaign: direction of motion and experiment bounds.

    Returns
    -------
    numpy.ndarray of bool, shape (D.n,)
        True on the first ramp of each experiment (dimensionless flags). Cached: do not modify it in place.
    """
    def make():
        m = np.zeros(D.n, bool)
        s = D.s
        for e in range(D.n_exp):
            a, b = D.bounds[e], D.bounds[e + 1]
            cuts = np.flatnonzero(np.diff(s[a:b]) != 0) + 1
            m[a : a + (cuts[0] if len(cuts) else b - a)] = True
        return m

    return cached(D, ("first_ramp",), make)


def periodogram_peaks(u: np.ndarray, y: np.ndarray, periods: np.ndarray, n_peaks: int = 3) -> np.ndarray:
    """Periods (units of ``u``) of the highest periodogram peaks of ``y`` against ``u``.

    ``y`` is averaged on a uniform grid of ``u`` (a fifth of the shortest
    period; empty cells count as zero after the mean is removed) and
    Fourier-transformed; the power is read at ``periods``.

    Parameters
    ----------
    u : numpy.ndarray
        The abscissa per sample, in any unit (e.g. displacement, mm).
    y : numpy.ndarray
        The signal per sample, in any unit (e.g. a residual force, N).
    periods : numpy.ndarray
        Candidate periods, in the same unit as ``u`` (e.g. mm).
    n_peaks : int
        Number of peaks to return (count).

    Returns
    -------
    numpy.ndarray
        Up to ``n_peaks`` of ``periods`` (same unit as ``u``, e.g. mm), ascending; the middle period when ``y`` is
        constant.
    """
    y = y - (y.mean() if len(y) else 0.0)
    if not np.any(y):
        return periods[[len(periods) // 2]]
    h = float(periods.min()) / 5.0
    k = np.floor((u - u.min()) / h).astype(int)
    m = int(k.max()) + 1
    cnt = np.bincount(k, minlength=m)
    avg = np.bincount(k, weights=y, minlength=m) / np.maximum(cnt, 1)
    nfft = int(2 ** np.ceil(np.log2(max(4 * m, 64))))
    spec = np.abs(np.fft.rfft(avg, nfft)) ** 2
    freqs = np.fft.rfftfreq(nfft, d=h)
    pw = np.interp(1.0 / periods, freqs, spec)
    loc = np.flatnonzero((pw[1:-1] >= pw[:-2]) & (pw[1:-1] >= pw[2:])) + 1
    if len(loc) == 0:
        loc = np.array([int(np.argmax(pw))])
    best = loc[np.argsort(-pw[loc])][:n_peaks]
    return np.sort(periods[best])



# ------------------------------------------------------------------ filters on a finer time grid
def _fine_grid(D: FitData, m: int):
    """Index arrays of :func:`_on_sample_grid` (cached): groups of experiments with the same spacing and lengths.

    Each group: ``(dt_fine, exps, src0, src1, w, read)`` with ``src0/src1``
    (n_e, n_fine) rows of D to interpolate between (``D.n``: a zero row),
    ``w`` their weights and ``read`` (n_e, n_kept) the fine-grid positions
    of the kept samples; experiments with irregular timing are in the group
    ``dt_fine = None`` (filtered on their kept samples).
    """
    return cached(D, ("finegrid", m), lambda: _make_fine_grid(D, m))


def _make_fine_grid(D: FitData, m: int):
    dts = D.per_exp_dt()
    groups: dict = {}
    irregular = []
    for e in range(D.n_exp):
        a, b = D.bounds[e], D.bounds[e + 1]
        k = np.round((D.t[a:b] - min(D.t[a], 0.0)) / dts[e]).astype(int)
        if not (len(k) > 1 and np.all(np.diff(k) > 0) and k[-1] <= 20 * len(k)):
            irregular.append(e)
            continue
        rows = np.arange(a, b)
        lead = k[0] > 0
        if lead:  # the unit at rest at x = 0 before the first kept sample: a zero row at t = 0
            k = np.r_[0, k]
            rows = np.r_[D.n, rows]
        tf = np.arange(k[-1] * m + 1) / m
        i = np.clip(np.searchsorted(k, tf, side="right") - 1, 0, len(k) - 2)
        w = (tf - k[i]) / (k[i + 1] - k[i])
        read = k * m
        if lead:
            read = read[1:]
        groups.setdefault((round(float(dts[e]), 12), len(tf), b - a), []).append((e, rows[i], rows[i + 1], w, read))
    out = []
    for (dt, _, _), items in groups.items():
        out.append((dt / m, np.array([q[0] for q in items]), np.array([q[1] for q in items]), np.array([q[2] for q in items]),
                    np.array([q[3] for q in items]), np.array([q[4] for q in items])))
    if irregular:
        out.append((None, np.array(irregular), None, None, None, None))
    return out


#: memory for one chunk of the fine time grid of :func:`_on_sample_grid` (bytes, its three arrays)
_FINE_GRID_BYTES = 8 * 2**20


def _on_sample_grid(D: FitData, X: np.ndarray, op, substeps: int = 4, out: np.ndarray | None = None) -> np.ndarray:
    """Apply the causal filter ``op(X_fine, dt_fine)`` (along axis 1) per experiment on its full, uniform time grid.

    The samples left out at rest (start, turning point) still pass the
    sensor: a filter run over the kept samples only would shift the time
    base by a sample at every gap. The columns are filled in linearly on a
    grid of ``substeps`` steps per sample interval from ``t = 0`` (from zero,
    the unit at rest at x = 0, before the first kept sample), filtered there
    (a discretisation finer than the sampling, which may be as coarse as the
    sensor's lag) and read back at the kept samples. Experiments of the same
    spacing and length are filtered together. ``out`` may be ``X`` itself (filtered in place: each
    chunk of experiments reads its own rows before it writes them, so no copy of ``X`` is made).
    """
    out = np.empty_like(X) if out is None else out
    n = X.shape[0]
    dts = D.per_exp_dt()

    def rows(src):  # rows of X, the zero row (index n: the unit at rest before the motion) as zeros
        r = X[np.minimum(src, n - 1)]
        r[src == n] = 0.0
        return r

    for dtf, exps, src0, src1, w, read in _fine_grid(D, int(substeps)):
        if dtf is None:
            for e in exps:
                a, b = D.bounds[e], D.bounds[e + 1]
                out[a:b] = op(X[a:b][None], dts[e])[0]
            continue
        # in chunks of experiments: the fine grid of a whole group (substeps x its rows x every column)
        # would be several times the design itself on large campaigns; each experiment is filtered
        # alone along its time axis, so chunking changes no bit of the result
        step = max(1, _FINE_GRID_BYTES // (3 * 8 * src0.shape[1] * max(1, X.shape[1])))
        for c0 in range(0, len(exps), step):
            sl = slice(c0, c0 + step)
            # a chunk reads only its own experiments' rows, and writes them after: safe in place, no copy of X
            full = rows(src0[sl]) * (1.0 - w[sl])[..., None] + rows(src1[sl]) * w[sl][..., None]
            res = op(full, dtf)
            kept = np.take_along_axis(res, read[sl][..., None], axis=1)
            for j, e in enumerate(exps[sl]):
                out[D.bounds[e] : D.bounds[e + 1]] = kept[j]
    return out


def _substep_filter(b, a, m: int):
    """:func:`_substep_filter_cached` for array coefficients (the same few filters recur across candidates and folds)."""
    return _substep_filter_cached(tuple(np.atleast_1d(np.asarray(b, float))), tuple(np.atleast_1d(np.asarray(a, float))), int(m))


@functools.lru_cache(maxsize=4096)
def _substep_filter_cached(b: tuple, a: tuple, m: int):
    """The digital filter ``(b, a)`` run on ``m`` substeps per sample of a linearly interpolated input, as one filter on the samples.

    A causal filter (``lfilter`` convention, zero state before the first
    input) applied to the fine grid of :func:`_on_sample_grid` -- the input
    interpolated linearly between samples, ``m`` steps per sample interval --
    and read at every ``m``-th step is, exactly (up to rounding), a filter of
    the same order on the samples themselves: with the state-space form
    ``s' = A s + B x, y = C s + D x`` of ``(b, a)``, one sample interval maps
    ``S_{k+1} = A^m S_k + G0 u_k + G1 u_{k+1}`` (``G0, G1`` the sums of
    ``A^(m-1-i) B`` weighted by ``1 - i/m`` and ``i/m``), and ``W_k = S_k -
    G1 u_k`` gives the standard form ``W' = A^m W + (A^m G1 + G0) u, Y = C W
    + (C G1 + D) u``. Its transfer function is built from its Markov
    parameters (no subtraction of nearly equal polynomials).

    Returns ``(bc, ac, br)``: the filter on the samples, and the numerator of
    ``r_k = C A^(mk) G1`` (``W_0 = -G1 u_0``: the fine filter starts at rest
    before ``u_0``, so ``y_k`` gets ``- u_0 r_k`` when ``u_0 != 0``).
    """
    from scipy.signal import tf2ss

    b = np.atleast_1d(np.asarray(b, float)) / float(a[0])
    a = np.atleast_1d(np.asarray(a, float)) / float(a[0])
    N = max(len(a), len(b)) - 1
    if N == 0:
        return b, a, np.zeros(1)
    A, B, C, Dd = tf2ss(np.r_[b, np.zeros(N + 1 - len(b))], np.r_[a, np.zeros(N + 1 - len(a))])
    P = [np.eye(N)]
    for _ in range(m):
        P.append(A @ P[-1])
    G0 = sum(P[m - 1 - i] @ B * (1.0 - i / m) for i in range(m))
    G1 = sum(P[m - 1 - i] @ B * (i / m) for i in range(m))
    Am = P[m]
    ac = np.real(np.poly(Am)) if N > 1 else np.array([1.0, -Am[0, 0]])

    def numerator(d0, v):  # transfer-function numerator of the Markov parameters d0, C v, C Am v, ...
        h = [d0]
        for _ in range(N):
            h.append((C @ v).item())
            v = Am @ v
        return np.convolve(ac, h)[: N + 1]

    bc = numerator((C @ G1 + Dd).item(), Am @ G1 + G0)
    br = numerator((C @ G1).item(), Am @ G1)
    return bc, ac, br


def _filter_on_sample_grid(D: FitData, X: np.ndarray, ba, substeps: int = 4, out: np.ndarray | None = None) -> np.ndarray:
    """:func:`_on_sample_grid` for a linear filter ``ba(dt) -> (b, a)``, computed on the samples (4 x less work, the same result).

    The same filter as ``_on_sample_grid(D, X, lambda seg, dt: lfilter(*ba(dt), seg, axis=1), substeps)``:
    the fine grid's input is linear between kept samples, so the fine filter
    read at the samples is the exact filter :func:`_substep_filter` on the
    uniform sample grid (the samples left out at rest filled in linearly,
    from a zero row before the motion); equal to rounding (~1e-15 relative).
    Columns never nonzero in the same experiment (eq. 14's one damping
    column per valve) are filtered as one: the filter acts per experiment, so
    this moves no bit. ``out`` may be ``X`` itself (in place, chunk by chunk,
    as :func:`_on_sample_grid`).
    """
    from scipy.signal import lfilter

    out = np.empty_like(X) if out is None else out
    n, p = X.shape
    dts = D.per_exp_dt()
    m = int(substeps)
    # slots: per experiment, the column of X each filtered slot carries (columns dead in an experiment
    # share a slot with the one alive there; a slot whose columns are all dead carries one of them: zeros)
    live = np.logical_or.reduceat(X != 0.0, D.bounds[:-1], axis=0) if n and D.n_exp else np.ones((D.n_exp, p), bool)
    merged: list = []  # [(experiments covered, [columns])]
    for j in range(p):
        for sup, cols in merged:
            if not np.any(sup & live[:, j]):
                sup |= live[:, j]
                cols.append(j)
                break
        else:
            merged.append((live[:, j].copy(), [j]))
    slot = np.empty((D.n_exp, len(merged)), int)
    for g, (_, cols) in enumerate(merged):
        slot[:, g] = cols[0]
        for j in cols[1:]:
            slot[live[:, j], g] = j
    for gi, (dtc, exps, src0, src1, w, read) in enumerate(_fine_grid(D, 1)):
        if dtc is None:
            for e in exps:
                a, b = D.bounds[e], D.bounds[e + 1]
                out[a:b] = lfilter(*ba(dts[e]), X[a:b], axis=0)
            continue
        bf, af = ba(dtc / m)
        bc, ac, br = _substep_filter(bf, af, m)
        L = src0.shape[1]
        r = None
        if np.any(src0[:, 0] != n):  # an experiment starts at t = 0 with a kept sample: the fine filter's start
            r = lfilter(br, ac, np.r_[1.0, np.zeros(L - 1)])
        nk = read.shape[1]
        k = slot.shape[1]
        step = max(1, _FINE_GRID_BYTES // (8 * L * max(1, k)))
        for c0, (e_sl, s0c, zero, interp, rows, ar_e) in zip(range(0, len(exps), step), _sample_grid_chunks(D, gi, step)):
            cs = slot[e_sl]  # (n_e, k)
            # (n_e, slots, time): each experiment's slot filtered along the contiguous last axis
            full = X[s0c[:, None, :], cs[:, :, None]]
            if zero is not None:
                full.transpose(0, 2, 1)[zero] = 0.0
            if interp is not None:
                ei, li, wi, wi1, s1c, s1z = interp
                r1 = X[s1c, cs[ei]]
                if s1z is not None:
                    r1[s1z] = 0.0
                full[ei, :, li] = full[ei, :, li] * wi1 + r1 * wi
            u0 = full[:, :, 0].copy() if r is not None else None
            res = lfilter(bc, ac, full, axis=-1)
            if r is not None:
                res -= u0[:, :, None] * r[None, None, :]
            kept = res[ar_e[:, None, None], np.arange(k)[None, :, None], read[c0 : c0 + step][:, None, :]]  # (n_e, k, nk)
            if k < p:
                out[rows.ravel()] = 0.0  # the dead columns (their rows of X are read above: safe in place)
            out[rows[:, None, :], cs[:, :, None]] = kept
    return out


def _sample_grid_chunks(D: FitData, gi: int, step: int) -> list:
    """Index arrays of :func:`_filter_on_sample_grid` for group ``gi`` of ``_fine_grid(D, 1)`` in chunks of ``step`` experiments (cached:
    a function of the campaign alone, rebuilt by every filter call before). Per chunk ``(experiments, source rows clipped to the
    campaign, zero-row mask or None, interpolation or None, rows written, arange)``; the interpolation
    ``(experiment, time, weight, 1 - weight, second source rows clipped, their zero-row mask or None)``."""
    def make():
        n = D.n
        _, exps, src0, src1, w, read = _fine_grid(D, 1)[gi]
        nk = read.shape[1]
        out = []
        for c0 in range(0, len(exps), step):
            sl = slice(c0, c0 + step)
            e_sl = exps[sl]
            s0 = src0[sl]
            zero = s0 == n
            ii = w[sl] != 0.0
            interp = None
            if ii.any():
                ei, li = np.nonzero(ii)
                wi = w[sl][ii][:, None]
                s1 = src1[sl][ii]
                s1z = s1 == n
                interp = (ei, li, wi, 1.0 - wi, np.minimum(s1, n - 1)[:, None], s1z if s1z.any() else None)
            rows = D.bounds[e_sl][:, None] + np.arange(nk)  # every row of these experiments (the kept samples)
            out.append((e_sl, np.minimum(s0, n - 1), zero if zero.any() else None, interp, rows, np.arange(len(e_sl))))
        return out

    return cached(D, ("samplegrid_chunks", int(gi), int(step)), make)


def _velocity_gaps(D: FitData, m: int):
    """Per regular experiment (cached): the motion's velocity between samples minus its linear fill, on the fine grid of :func:`_on_sample_grid`.

    The test machine moves with constant acceleration to a cruise speed and
    back (``recordings``' motion profile), so between two samples the
    velocity is not linear where a ramp starts or ends: it follows the ramp
    at the acceleration ``a`` (the largest velocity change per second between
    samples of the experiment, from rest before the first sample) up to the
    neighbouring sample's speed, and crosses zero at a reversal at ``a``
    (the time of the crossing from the sample on the ramp); where an
    experiment's ramps fall between samples, ``a`` is the machine's (the
    upper tenth of the experiments' values). Returns a list of groups of
    experiments with the same spacing and lengths,
    ``(exps, dt_fine, (n_e, n_fine), nz, vals, reads)``: the gaps (n_e,
    n_fine, 2), the direction sign(ẋ) and the velocity (mm/s) minus their
    linear fill, are nonzero only in the intervals with a kink, a start or a
    reversal (friction turns with the motion at once, not along the straight
    line from the sample before), so only their nonzero fine-grid rows are
    kept: ``vals`` (len(nz), 2) at the flat rows ``nz`` of the (n_e * n_fine,
    2) array (:func:`_dense_gaps` restores it); ``reads`` the fine-grid
    positions of the kept samples; experiments without a gap are left out.
    """
    return cached(D, ("velocity_gaps", m), lambda: _make_velocity_gaps(D, m))


def _make_velocity_gaps(D: FitData, m: int):
    dts = D.per_exp_dt()
    knots = {}
    acc_e = np.zeros(D.n_exp)  # mm/s^2: each experiment's largest velocity change per second (a lower bound of the acceleration)
    for e in range(D.n_exp):
        a, b = D.bounds[e], D.bounds[e + 1]
        k = np.round((D.t[a:b] - min(D.t[a], 0.0)) / dts[e]).astype(int)
        if not (len(k) > 1 and np.all(np.diff(k) > 0) and k[-1] <= 20 * len(k)):
            continue
        vk = D.v[a:b].astype(float)
        lead = k[0] > 0
        if lead:
            k, vk = np.r_[0, k], np.r_[0.0, vk]
        knots[e] = (k, vk, lead)
        acc_e[e] = float(np.max(np.abs(np.diff(vk)) / np.diff(k))) / dts[e]
    # one test machine: where the ramps are shorter than a sample interval (slow runs), the acceleration is
    # the one the experiments that resolve their ramps show (the upper tenth of the campaign's values)
    acc_machine = float(np.quantile(acc_e[acc_e > 0], 0.9)) if np.any(acc_e > 0) else 0.0
    # experiments of the same fine spacing and lengths are filtered together. Group by group, one
    # (n_e, n_fine, 2) array is filled experiment by experiment and kept compact: the gaps are zero
    # outside the few intervals with a kink, a start or a reversal, so only the nonzero fine-grid rows
    # are stored (:func:`_velocity_correction` restores the dense group; memory on large campaigns)
    members: dict = {}  # (fine spacing, fine length, kept samples) -> experiments
    for e, (k, vk, lead) in knots.items():
        acc = max(acc_e[e], acc_machine) * dts[e]  # per sample interval
        if acc > 0 and np.isfinite(acc):
            members.setdefault((round(float(dts[e] / m), 15), int(k[-1] * m + 1), len(k) - int(lead)), []).append(e)
    out = []
    for (_, n_fine, n_kept), exps_g in members.items():
        exps, reads, gaps = np.empty(len(exps_g), int), np.empty((len(exps_g), n_kept), int), np.empty((len(exps_g), n_fine, 2))
        j, dtf = 0, None
        for e in exps_g:
            k, vk, lead = knots[e]
            acc = max(acc_e[e], acc_machine) * dts[e]  # per sample interval
            tau = np.arange(k[-1] * m + 1) / m
            i = np.clip(np.searchsorted(k, tau, side="right") - 1, 0, len(k) - 2)
            k0, k1, v0, v1 = k[i], k[i + 1], vk[i], vk[i + 1]
            vlin = v0 + (v1 - v0) * (tau - k0) / (k1 - k0)
            s0, s1 = np.abs(v0), np.abs(v1)
            same = v0 * v1 >= 0.0
            sig = np.sign(v0 + v1)
            v_same = sig * np.where(s1 >= s0, np.minimum(s0 + acc * (tau - k0), s1), np.minimum(s0, s1 + acc * (k1 - tau)))
            # a reversal inside the interval: the zero crossing follows the sample on the ramp (the slower one)
            tA, tB = k0 + s0 / acc, k1 - s1 / acc
            t_rev = np.where(s0 > s1 * (1 + 1e-9), tB, np.where(s1 > s0 * (1 + 1e-9), tA, 0.5 * (tA + tB)))
            v_rev = np.sign(v0) * np.clip(acc * (t_rev - tau), -s1, s0)
            vf = np.where(same, v_same, v_rev)
            sk = np.sign(vk)
            slin = sk[i] + (sk[i + 1] - sk[i]) * (tau - k0) / (k1 - k0)
            gap = gaps[j]
            gap[:, 0] = np.sign(vf) - slin
            gap[:, 1] = vf - vlin
            if not np.any(np.abs(gap) > 1e-12 * max(float(np.max(np.abs(vk))), 1.0)):
                continue  # experiments without a gap are left out
            read = k * m
            exps[j], reads[j] = e, read[1:] if lead else read
            if dtf is None:
                dtf = dts[e] / m
            j += 1
        if j:
            flat = gaps[:j].reshape(-1, 2)
            nz = np.flatnonzero(np.any(flat.view(np.int64) != 0, axis=1))  # every bit kept (a -0.0 too)
            out.append((exps[:j].copy(), dtf, (j, n_fine), nz, flat[nz], reads[:j].copy()))
        del gaps
    return out


def _dense_gaps(shape: tuple, nz: np.ndarray, vals: np.ndarray) -> np.ndarray:
    """The (n_e, n_fine, 2) gaps of one group of :func:`_velocity_gaps` from its nonzero fine-grid rows."""
    g = np.zeros((shape[0] * shape[1], 2))
    g[nz] = vals
    return g.reshape(shape + (2,))


def _velocity_correction(D: FitData, op, substeps: int = 4) -> np.ndarray:
    """``op`` (a causal filter ``op(seg, dt_fine)`` along axis 1) of :func:`_velocity_gaps`, read at the kept samples: (n, 2), sign and mm/s."""
    corr = np.zeros((D.n, 2))
    for exps, dtf, shape, nz, vals, reads in _velocity_gaps(D, int(substeps)):
        res = np.take_along_axis(op(_dense_gaps(shape, nz, vals), dtf), reads[..., None], axis=1)
        for j, e in enumerate(exps):
            corr[D.bounds[e] : D.bounds[e + 1]] = res[j]
    return corr


def filter_design(D: FitData, X: np.ndarray, ba, out, eq14_first: bool) -> np.ndarray:
    """The design ``X`` through the sensor filter ``ba(dt_fine) -> (b, a)`` (:func:`_on_sample_grid`), eq. 14's damping columns with the motion's velocity between samples.

    With ``eq14_first`` (``X`` is a whole design, eq. 14's columns first),
    each damping column ``L(gamma) xdot`` is filtered as the velocity really
    runs between samples (:func:`_velocity_gaps`: a ramp's end or a reversal
    between two samples, where a stiff valve's force bends), and the
    friction column ``sign(xdot)`` turns at the start and the reversal
    itself, not along the straight line between samples: linear filtering
    lets the corrections add.

    Parameters
    ----------
    D : FitData
        The campaign (times in s, velocity in mm/s, valve positions).
    X : numpy.ndarray, shape (D.n, p)
        Design columns, each in its own unit (N per unit amplitude once multiplied).
    ba : callable
        ``ba(dt_s) -> (b, a)``: the digital filter for a time step ``dt_s`` (s), ``lfilter`` convention.
    out : numpy.ndarray or None
        Where to write the result, in the same unit as ``X`` (may be ``X`` itself: filtered in place); a new
        array when None.
    eq14_first : bool
        ``X`` is a whole design with eq. 14's columns first (its friction and damping columns get the
        motion's velocity between samples).

    Returns
    -------
    numpy.ndarray, shape (D.n, p)
        The filtered design, each column in the same unit as in ``X``.
    """
    share = None
    if eq14_first and X.shape[1] >= 2 + len(D.valves):
        # eq. 14's sign column, and each sample's own valve column (the others are zero), over sign and velocity:
        # 1, or 0 where a term masked the damping column (relief valve open)
        rows, vcol = np.arange(D.n), 2 + D.valve_idx
        share = np.column_stack([np.where(D.s != 0, X[:, 1] * D.s, 0.0),
                                 np.where(D.v != 0, X[rows, vcol] / np.where(D.v != 0, D.v, 1.0), 0.0)])

    def op(seg, dt):
        return lfilter(*ba(dt), seg, axis=1)  # from rest (see ForceLag)

    res = _filter_on_sample_grid(D, X, ba, out=out)  # the same filter as _on_sample_grid with op, on the samples
    if share is not None:
        c = _velocity_correction(D, op)
        c *= share  # in place: no third (n, 2) array
        res[:, 1] += c[:, 0]
        res[rows, vcol] += c[:, 1]
    return res
