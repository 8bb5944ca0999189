"""Registry of effects that the paper's eq. 14 leaves out: one object per effect.

The baseline is the paper's identification model (eq. 14)::

    f = g p2 x + L(γ) ẋ + C sign(ẋ)

An :class:`Effect` is everything the tool knows about one piece of physics:
its fit columns (linear amplitudes with physical bounds, at most one *shape*
parameter searched on a grid), the context it needs from the current model,
its equation and an engineer's sentence, its physical signature checks and,
for the unit-test bench :mod:`~vvea_design.identification.testbench`, the
force it adds to a simulated bench. Every effect is registered once, in
:data:`REGISTRY`; identification, diagnosis and the unit-test bench only
call its methods, so adding an effect touches this file only.

Two kinds of effects live in the registry:

- **catalogue** effects (``catalogue=True``): named physics of the unit
  (``shared/specs/diagnosis-report.md``). Each fits a *family* of physical
  forms, not one formula, so that the real form of the effect is followed:

  ===================  ======================================================
  id                   added force (N)
  ===================  ======================================================
  gas_nonlinearity     p2 (a2 r2(x; V2) + a1 r1(x)): eq. 5's two chamber
                       forces of the unit's geometry, each minus its straight
                       line; V2 free (an effective, polytropic volume)
  thermal              p2 (k_i f_i h_i + s_i f_i h_i² + k h),  ḣ_i = u̇_i - h_i/τ  (wall heat
                       exchange per chamber, chamber 1 at τ/2, τ, 2τ; second order)
  quadratic_damping    K(γ) ẋ|ẋ|^(m-1)   (orifice flow, exponent m fitted)
  relief_valve         soft knee: above F_open the throttle force follows
                       c F_open + r (L ẋ - F_open), c near 1
  stiction             sign(ẋ) (S1 e^(-|ẋ|/v_s) + S2 e^(-(|ẋ|/v_s)²))  (Stribeck
                       shape between exponential and Gaussian)
  pressure_friction    c_p p2 sign(ẋ)
  leakage              -p2 t_c (q0 + q x + curvature) + p2 t_c² (c0 + c x)
                       (the charge, and all it carries, decays over campaign time)
  ===================  ======================================================

- **discovery operators** (``catalogue=False``): interpretable operators on the
  measured signals for physics nobody listed (memory: first-order lags of
  the model force, of the damping force and of the motion; play/stop
  hysteresis operators; Fourier terms in displacement and in time, pitch or
  frequency found by a periodogram of the residual; direction-dependent
  stiffness; state polynomials; campaign-time trends). Each translates its
  fitted parameters into a physical signature and a sentence.

Residual sign convention everywhere: residual = measurement − model (N).
"""

from __future__ import annotations

import functools
import re
from dataclasses import dataclass, field

import numpy as np
from scipy.signal import lfilter

from ..spring import gas_spring
from ..spring.gas_spring import GasSpring
from ..spring.paper import PAPER_FIG5
from .recordings import Recordings

__all__ = [
    "FitData",
    "Param",
    "Check",
    "Effect",
    "REGISTRY",
    "CATALOGUE",
    "DISCOVERY",
    "EFFECT_IDS",
    "DISCOVERY_IDS",
    "register",
    "is_effect_id",
    "filter_id",
    "fitted_filter",
    "baseline_columns",
    "baseline_params",
    "fill_baseline",
    "effect_columns",
    "chamber_remainders",
    "thermal_state",
    "lowpass",
    "stop_operator",
    "REFERENCE_NOTE",
]

#: What the tool assumes when no design file is given.
REFERENCE_NOTE = (
    "no --design given: the gas terms use the paper's Fig. 5 unit (vvea_design.spring.paper.PAPER_FIG5: "
    f"A1 = {PAPER_FIG5.A1_mm2:.0f} mm^2, A2 = {PAPER_FIG5.A2_mm2:.0f} mm^2, V1 = {PAPER_FIG5.V1_mm3:.3g} mm^3, "
    f"V2 = {PAPER_FIG5.V2_mm3:.3g} mm^3, travel {PAPER_FIG5.travel_mm:g} mm)"
)


@dataclass(frozen=True)
class FitData:
    """Numeric arrays of a campaign, ready for fitting (one entry per sample).

    Attributes (units): ``x`` mm, ``v`` mm/s (estimated), ``p2`` MPa,
    ``valve`` degree, ``valve_idx`` index into ``valves``, ``t`` s within the
    experiment, ``tsr`` s since last reversal, ``ctime`` s of campaign time,
    ``exp`` experiment index (0..n_exp-1, run order), ``y`` measured force N,
    ``bounds`` row offsets of the experiments, ``reference`` the unit's gas
    spring (areas, V1, V2 and travel used by the gas terms; the design
    file's, or the paper's Fig. 5 unit).
    """

    x: np.ndarray
    v: np.ndarray
    p2: np.ndarray
    valve: np.ndarray
    valve_idx: np.ndarray
    valves: tuple
    t: np.ndarray
    tsr: np.ndarray
    ctime: np.ndarray
    exp: np.ndarray
    y: np.ndarray
    bounds: np.ndarray
    reference: GasSpring = PAPER_FIG5
    rows_left_out: int = 0
    speed: np.ndarray | None = None  #: nominal speed label per sample (mm/s)
    _cache: dict = field(default_factory=dict, compare=False, repr=False)
    _cache_nbytes: dict = field(default_factory=dict, compare=False, repr=False)  #: (entry, its bytes) per _cache key

    @property
    def n(self) -> int:
        return len(self.y)

    @property
    def n_exp(self) -> int:
        return len(self.bounds) - 1

    @property
    def n_per_exp(self) -> np.ndarray:
        """Samples per experiment."""
        return np.diff(self.bounds)

    @property
    def s(self) -> np.ndarray:
        """sign(ẋ)."""
        return np.sign(self.v)

    @property
    def travel_mm(self) -> float:
        """The unit's travel (from the reference design)."""
        return float(self.reference.travel_mm)

    @classmethod
    def from_recordings(cls, rec: Recordings, reference: GasSpring = PAPER_FIG5, drop_rest: bool = True) -> "FitData":
        """Arrays of a :class:`~vvea_design.identification.recordings.Recordings` campaign.

        With ``drop_rest`` the samples at rest (start, turning point, end:
        ``at_rest``) are left out, because friction is set-valued there;
        :attr:`rows_left_out` counts them. ``reference`` is the unit's gas
        spring (its chamber areas, V1, V2 and travel shape the gas terms).

        Parameters
        ----------
        rec : Recordings
            The campaign as read (mm, mm/s, N, MPa, deg, s columns).
        reference : GasSpring
            The unit the gas terms are shaped with (default: the paper's Fig. 5 unit).
        drop_rest : bool
            Leave out the samples at rest.

        Returns
        -------
        FitData
            Samples in run order, experiments renumbered 0..n-1 (``bounds`` are their row ranges).
        """
        d = rec.data[~rec.data["at_rest"].to_numpy()] if drop_rest else rec.data
        valve = d["valve_deg"].to_numpy(float)
        valves = tuple(np.unique(valve))
        exp = d["exp_index"].to_numpy(int)
        # renumber experiments 0..n-1 in run order (an experiment can lose all rows only if it never moves)
        _, exp = np.unique(exp, return_inverse=True)
        starts = np.flatnonzero(np.r_[True, exp[1:] != exp[:-1]])
        return cls(
            x=d["displacement_mm"].to_numpy(float),
            v=d["velocity_mm_s"].to_numpy(float),
            p2=d["p2_MPa"].to_numpy(float),
            valve=valve,
            valve_idx=np.searchsorted(np.array(valves), valve),
            valves=valves,
            t=d["time_s"].to_numpy(float),
            tsr=d["time_since_reversal_s"].to_numpy(float),
            ctime=d["campaign_time_s"].to_numpy(float),
            exp=exp,
            y=d["force_N"].to_numpy(float),
            bounds=np.r_[starts, len(d)],
            reference=reference,
            rows_left_out=int(len(rec.data) - len(d)) + rec.rows_left_out,
            speed=d["speed_mm_s"].to_numpy(float),
        )

    def per_exp_dt(self) -> np.ndarray:
        """Median sample spacing of each experiment (cached).

        Returns
        -------
        numpy.ndarray
            ``(n_exp,)`` spacing in s (1 s for an experiment with a single sample).
        """
        key = ("dt",)
        if key not in self._cache:
            dt = np.ones(self.n_exp)
            for e in range(self.n_exp):
                t = self.t[self.bounds[e] : self.bounds[e + 1]]
                if len(t) > 1:
                    dt[e] = float(np.median(np.diff(t)))
            self._cache[key] = dt
        return self._cache[key]


@dataclass(frozen=True)
class Param:
    """A model parameter: name, unit, physical bounds, meaning."""

    name: str
    unit: str
    lower: float
    upper: float
    meaning: str = ""


@dataclass(frozen=True)
class Check:
    """One physical signature check of a fitted effect."""

    name: str
    passed: bool
    detail: str

    def to_dict(self) -> dict:
        """The check as JSON.

        Returns
        -------
        dict
            ``name``, ``passed`` (bool) and ``detail`` (the numbers behind the verdict, as text).
        """
        return dict(name=self.name, passed=bool(self.passed), detail=self.detail)


#: The column cache of a FitData holds at most this many arrays of its length, and at most
#: CACHE_BYTES in all, every entry counted (columns, filter grids, velocity gaps). 40 MB is just above
#: what the column limit gives a 135-experiment campaign (~40,000 rows: 120 columns, 39 MB), so a
#: campaign of that size caches as before, and a larger one holds no more than that (a campaign ten
#: times the size: ~12 columns; at 64 MB the cache was the largest resident item of its diagnosis).
CACHE_COLUMNS = 120
CACHE_BYTES = 40e6


def _nbytes(v) -> int:
    if isinstance(v, np.ndarray):
        return v.nbytes
    if isinstance(v, (tuple, list)):
        return sum(_nbytes(q) for q in v)
    return 0


def cached(D: FitData, key, make):
    """``D._cache[key]``, computed by ``make()`` when missing; the least recently used entries go when over :data:`CACHE_COLUMNS`."""
    c = D._cache
    if key in c:
        c[key] = c.pop(key)  # most recently used last
        return c[key]
    val = make()
    c[key] = val
    limit = min(CACHE_COLUMNS * max(D.n, 1) * 8, CACHE_BYTES)
    total = sum(_entry_nbytes(D, k, v) for k, v in c.items())
    while total > limit:
        k0 = next(iter(c))
        if k0 == key:
            break
        total -= _entry_nbytes(D, k0, c.pop(k0))
        D._cache_nbytes.pop(k0, None)  # (it holds the entry: let the evicted arrays go)
    return val


def _entry_nbytes(D: FitData, key, val) -> int:
    """``_nbytes(val)``, remembered per cache entry (walking every cached array on each miss was ~1 % of a
    diagnosis). The size is tied to the object it was measured on, so an entry written into ``_cache``
    directly, or a size left by a copy of ``D`` that shares the dict, is measured afresh."""
    sizes = D._cache_nbytes
    got = sizes.get(key)
    if got is None or got[0] is not val:
        got = sizes[key] = (val, _nbytes(val))
    return got[1]


def effect_columns(D: FitData, eff: "Effect", shape: float, ctx: dict) -> np.ndarray:
    """``eff.columns(D, shape, ctx)``, cached per effect and shape value when the effect needs no context.

    The columns of an effect without ``needs`` are a function of the campaign
    and the shape alone (the same forces are rebuilt by every fold, round and
    refit); those that read the context are always rebuilt.

    Parameters
    ----------
    D : FitData
        The campaign (x in mm, ẋ in mm/s, p2 in MPa, t in s, ...).
    eff : Effect
        The effect whose columns are wanted.
    shape : float
        Its shape parameter, in the unit of ``eff.shape`` (e.g. s for a time
        constant, mm for a pitch); NaN for an effect without one.
    ctx : dict
        Context arrays per sample (``damping_force_N`` etc., N), read only by
        effects that declare them in ``needs``.

    Returns
    -------
    numpy.ndarray, shape (D.n, number of the effect's amplitudes)
        The effect's columns, each in the unit its amplitude multiplies (N per
        amplitude unit). Cached: do not modify it in place.
    """
    if eff.needs:
        return eff.columns(D, shape, ctx)
    sv = float(shape)
    return cached(D, ("columns", eff.id, sv if np.isfinite(sv) else None), lambda: eff.columns(D, shape, ctx))


def baseline_columns(D: FitData) -> tuple[np.ndarray, list[Param]]:
    """Design matrix of eq. 14: ``[p2 x, sign(ẋ), ẋ·1{γ=γ_j} ...]`` (cached: do not modify it in place).

    Parameters
    ----------
    D : FitData
        The campaign's arrays (x in mm, ẋ in mm/s, p2 in MPa, valve angles in deg).

    Returns
    -------
    X : numpy.ndarray, shape (D.n, 2 + len(D.valves))
        Columns ``p2 x`` (MPa mm), ``sign(ẋ)`` (dimensionless) and one column
        ``ẋ`` (mm/s) per valve angle, zero at samples of the other angles.
    params : list of Param
        One per column: ``g`` (N/mm/MPa), ``C`` (N), ``L(γ)`` (N s/mm), all
        bounded below by 0.
    """
    return cached(D, ("eq14",), lambda: _baseline_columns(D))


def baseline_params(D: FitData) -> list[Param]:
    """The parameters of eq. 14's columns (see :func:`baseline_columns`), without building the columns.

    Parameters
    ----------
    D : FitData
        The campaign (its valve angles, deg, give one damping parameter each).

    Returns
    -------
    list of Param
        ``g`` (N/mm/MPa), ``C`` (N) and one ``L(γ)`` (N s/mm) per valve angle, all bounded below by 0.
    """
    params = [
        Param("g", "N/mm/MPa", 0.0, np.inf, "spring stiffness per MPa of p2"),
        Param("C", "N", 0.0, np.inf, "Coulomb friction (Table 3's B)"),
    ]
    for val in D.valves:
        params.append(Param(f"L({val:g})", "N s/mm", 0.0, np.inf, f"linear damping at valve {val:g} deg"))
    return params


def fill_baseline(D: FitData, out: np.ndarray, zeroed: bool = False) -> None:
    """Write eq. 14's columns (the values of :func:`baseline_columns`) into ``out[:, :2 + len(D.valves)]``.

    Lets a design be built in one array, without a cached ``(n, 2 + valves)`` copy of the mostly-zero
    per-valve damping columns (memory on large campaigns).

    Parameters
    ----------
    D : FitData
        The campaign's arrays (x in mm, ẋ in mm/s, p2 in MPa, valve angles in deg).
    out : numpy.ndarray, shape (D.n, p) with p >= 2 + len(D.valves)
        Filled in place: ``p2 x`` (MPa mm), ``sign(ẋ)`` (dimensionless) and one ``ẋ`` column (mm/s) per
        valve angle, zero at samples of the other angles; columns beyond are left untouched.
    zeroed : bool
        ``out``'s valve columns are already zero (``numpy.zeros``: its pages need no writing), so only
        each sample's own valve column is written.

    Returns
    -------
    None
    """
    out[:, 0] = D.p2 * D.x
    out[:, 1] = D.s
    if not zeroed:
        out[:, 2 : 2 + len(D.valves)] = 0.0
    out[np.arange(D.n), 2 + D.valve_idx] = D.v  # one pass instead of a masked product per valve


def _baseline_columns(D: FitData):
    cols = [D.p2 * D.x, D.s]
    params = [
        Param("g", "N/mm/MPa", 0.0, np.inf, "spring stiffness per MPa of p2"),
        Param("C", "N", 0.0, np.inf, "Coulomb friction (Table 3's B)"),
    ]
    for j, val in enumerate(D.valves):
        cols.append(D.v * (D.valve_idx == j))
        params.append(Param(f"L({val:g})", "N s/mm", 0.0, np.inf, f"linear damping at valve {val:g} deg"))
    return np.column_stack(cols), params


# ------------------------------------------------------------------ signal operators
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


def _chamber_logs(D: FitData):
    """Log volume changes and isothermal force factors of the two chambers (per MPa of p2), unit geometry.

    Returns ``u2 = -ln(1 - A2 x/V2)``, ``u1 = ln(1 + A1 x/V1)``,
    ``f2 = A2 V2/(V2 - A2 x)``, ``f1 = (p1/p2) A1 V1/(V1 + A1 x)``.
    """
    def make():
        ref = D.reference
        A1, A2, V1, V2 = ref.A1_mm2, ref.A2_mm2, ref.V1_mm3, ref.V2_mm3
        ratio = ref.p1_MPa / ref.p2_MPa if ref.p2_MPa > 0 else A2 / A1
        c2 = np.clip(1 - A2 * D.x / V2, 0.05, None)
        c1 = np.clip(1 + A1 * D.x / V1, 0.05, None)
        return (-np.log(c2), np.log(c1), A2 / c2, ratio * A1 / c1)

    return cached(D, ("chambers",), make)


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


def _travel_since_reversal(D: FitData) -> np.ndarray:
    """|x - x at the last start or reversal| (mm), per experiment."""
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


def _first_ramp(D: FitData) -> np.ndarray:
    """True on the samples before the first reversal of each experiment (the ramp that starts from rest)."""
    def make():
        m = np.zeros(D.n, bool)
        s = D.s
        for e in range(D.n_exp):
            a, b = D.bounds[e], D.bounds[e + 1]
            cuts = np.flatnonzero(np.diff(s[a:b]) != 0) + 1
            m[a : a + (cuts[0] if len(cuts) else b - a)] = True
        return m

    return cached(D, ("first_ramp",), make)


def _periodogram_peaks(u: np.ndarray, y: np.ndarray, periods: np.ndarray, n_peaks: int = 3) -> np.ndarray:
    """Periods (units of ``u``) of the highest periodogram peaks of ``y`` against ``u``.

    ``y`` is averaged on a uniform grid of ``u`` (a fifth of the shortest
    period; empty cells count as zero after the mean is removed) and
    Fourier-transformed; the power is read at ``periods``.
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


# ------------------------------------------------------------------ the Effect object
_NAN = np.array([np.nan])


@dataclass(frozen=True)
class Effect:
    """One effect: fit columns, context, equation and sentence, signature checks, bench force.

    Subclasses override :meth:`columns` (always), and where needed
    :meth:`params`, :meth:`grid`, :meth:`damping_mask`, :meth:`signature`,
    :meth:`describe` and the ``bench_*`` methods.

    Attributes
    ----------
    id : str
        Identifier (``shared/specs/diagnosis-report.md``; discovery operators
        name what they are, e.g. ``force_lag``).
    title, physics, equation : str
        Short name; a sentence a mechanical engineer would accept; the added term.
    amplitudes : tuple[Param]
        Linear amplitude parameters (bounds carry the physical sign).
    shape : Param or None
        The one shape parameter searched on :meth:`grid` and refined.
    catalogue : bool
        Named physics of the unit (True) or a discovery operator (False).
    needs : tuple[str]
        Context keys the columns need from the current model:
        ``damping_force_N`` (L(γ)ẋ), ``model_force_N`` (the current model's
        force), ``residual_N`` (measurement − current model).
    log_shape : bool
        Refine the shape in log space.
    """

    id: str
    title: str
    physics: str
    equation: str
    amplitudes: tuple = ()
    shape: Param | None = None
    catalogue: bool = True
    needs: tuple = ()
    log_shape: bool = True
    shape_xtol: float = 1e-3  #: tolerance of the shape refinement (log units when log_shape)
    #: parameters fitted per experiment on that experiment's own data (held-out error is charged for them)
    nuisance_per_experiment: int = 0

    # -- fitting ---------------------------------------------------------
    def params(self, D: FitData) -> tuple:
        """Amplitude parameters for campaign ``D`` (per valve for some effects).

        Parameters
        ----------
        D : FitData
            The campaign.

        Returns
        -------
        tuple of Param
            One per design column of :meth:`columns`, in that order (units in ``Param.unit``).
        """
        return self.amplitudes

    def grid(self, D: FitData, ctx: dict) -> np.ndarray:
        """Shape-parameter values to search (``[nan]`` without a shape).

        Parameters
        ----------
        D : FitData
            The campaign.
        ctx : dict
            The context of the current model (keys in :attr:`needs`: forces in N).

        Returns
        -------
        numpy.ndarray
            Values of the shape parameter in its own unit, ``shape.unit`` (e.g. s for a time constant, mm for
            a pitch).
        """
        return _NAN

    def columns(self, D: FitData, shape: float, ctx: dict) -> np.ndarray:
        """Design columns ``(n, k)`` of the amplitudes at shape value ``shape``.

        Parameters
        ----------
        D : FitData
            The campaign.
        shape : float
            The shape parameter in its own unit, ``shape.unit`` (e.g. s for a time constant, mm for a pitch;
            nan without one).
        ctx : dict
            The context of the current model (keys in :attr:`needs`: forces in N).

        Returns
        -------
        numpy.ndarray
            ``(D.n, k)``: force in N per unit of each amplitude (the amplitudes' units cancel), one column per
            :meth:`params` entry.
        """
        raise NotImplementedError

    def damping_mask(self, D: FitData, shape: float, ctx: dict) -> np.ndarray | None:
        """Samples whose linear damping column this effect replaces (None: none).

        Parameters
        ----------
        D : FitData
            The campaign.
        shape : float
            The shape parameter in its own unit, ``shape.unit`` (e.g. s for a time constant, mm for a pitch;
            nan without one).
        ctx : dict
            The context of the current model (forces in N).

        Returns
        -------
        numpy.ndarray or None
            ``(D.n,)`` bool, True where eq. 14's ``L(γ)ẋ`` column is zeroed (e.g. the relief valve open).
        """
        return None

    def transform(self, D: FitData, X: np.ndarray, shape: float, ctx: dict, out: np.ndarray | None = None) -> np.ndarray:
        """The whole design matrix as the effect changes it (sensor dynamics); identity by default.

        Parameters
        ----------
        D : FitData
            The campaign.
        X : numpy.ndarray
            ``(D.n, p)`` design columns (N per unit amplitude).
        shape : float
            The shape parameter, in ``shape.unit`` (e.g. a lag in s).
        ctx : dict
            The context of the current model (forces in N).
        out : numpy.ndarray, optional
            Where to write the result, N per unit amplitude (may be ``X`` itself: the design is then transformed in place,
            without a second copy); a new array when None.

        Returns
        -------
        numpy.ndarray
            ``(D.n, p)`` transformed design (N per unit amplitude); ``X`` itself for the identity.
        """
        return X

    @property
    def replaces_damping(self) -> bool:
        """True when the effect replaces linear damping columns (not nested in eq. 14)."""
        return type(self).damping_mask is not Effect.damping_mask

    @property
    def transforms_design(self) -> bool:
        """True when the effect acts on the whole design (e.g. a lag of the force reading)."""
        return type(self).transform is not Effect.transform

    @property
    def nested(self) -> bool:
        """True when the effect only adds columns (eq. 14 + others is the effect at zero amplitude)."""
        return not (self.replaces_damping or self.transforms_design)

    # -- meaning -----------------------------------------------------------
    def signature(self, D: FitData, values: dict, shape: float, contribution: np.ndarray) -> list[Check]:
        """Physical signature checks of a fitted instance (catalogue effects).

        Parameters
        ----------
        D : FitData
            The campaign.
        values : dict
            Fitted amplitudes by parameter name (their units in :meth:`params`).
        shape : float
            The fitted shape parameter in its own unit, ``shape.unit`` (e.g. s for a time constant).
        contribution : numpy.ndarray
            ``(D.n,)`` the effect's fitted force at the samples (N).

        Returns
        -------
        list of Check
            Empty for effects without checks (discovery operators).
        """
        return []

    def describe(self, values: dict, errors: dict, shape: float, shape_se: float) -> str:
        """The fitted effect in one sentence with its numbers.

        Parameters
        ----------
        values, errors : dict
            Fitted amplitudes and their standard errors by parameter name (units in :meth:`params`).
        shape, shape_se : float
            The fitted shape parameter and its standard error in its own unit, ``shape.unit`` (e.g. s for a
            time constant, mm for a pitch).

        Returns
        -------
        str
            The sentence an engineer reads in the report (units written out).
        """
        return self.physics

    # -- unit-test bench ---------------------------------------------------
    #: key of the strength parameter in :meth:`bench_random`'s params, and how SNR follows it
    bench_strength: str = ""
    bench_snr_rises: bool = True
    bench_linear: bool = True

    def bench_force(self, P: dict, cols: dict, spec) -> np.ndarray:
        """Force this effect adds to eq. 14 on the unit-test bench (``testbench``, not the proof's simulator).

        Parameters
        ----------
        P : dict
            The effect's bench parameters (:meth:`bench_random`, units in their keys).
        cols : dict
            Bench signals: ``x`` (mm), ``v`` (mm/s), ``p2`` (MPa), ``valve`` (deg), ``ctime_h`` (h), ``exp``
            (index), ``t`` (s).
        spec : CampaignSpec
            The bench campaign (its reference unit and grid).

        Returns
        -------
        numpy.ndarray
            The added force per sample (N).
        """
        raise NotImplementedError(f"{self.id} has no bench force")

    def bench_random(self, rng: np.random.Generator, spec) -> dict:
        """Random bench parameters of strength 1.

        Parameters
        ----------
        rng : numpy.random.Generator
            The seeded generator of the case.
        spec : CampaignSpec
            The bench campaign.

        Returns
        -------
        dict
            Parameters for :meth:`bench_force`, units in their keys; ``bench_strength`` names the one scaled
            to reach a target SNR.
        """
        raise NotImplementedError(f"{self.id} has no bench force")

    def bench_strength_range(self, cols: dict, spec) -> tuple[float, float]:
        """Bisection range of the strength (effects not linear in strength).

        Parameters
        ----------
        cols : dict
            Bench signals (see :meth:`bench_force`).
        spec : CampaignSpec
            The bench campaign.

        Returns
        -------
        tuple of float
            Lowest and highest strength searched, in the unit of the ``bench_strength`` parameter (e.g. N, MPa
            or s: its key names it).
        """
        return (1e-6, 10.0)

    def bench_with_strength(self, P: dict, s: float) -> dict:
        """Bench parameters with the strength set.

        Parameters
        ----------
        P : dict
            Bench parameters (:meth:`bench_random`).
        s : float
            The strength, in the unit of the ``bench_strength`` parameter (e.g. N, MPa or s: its key names it).

        Returns
        -------
        dict
            A copy of ``P`` with ``P[bench_strength] = s``.
        """
        P = dict(P)
        P[self.bench_strength] = s
        return P


class _Registry(dict):
    """The effect registry: a dict by id, plus effects created from their id on first use.

    A sensor filter whose damping ratio was fitted is named by it
    (``force_filter_lag_z0733``: zeta = 0.733, see :func:`filter_id`); such an
    id is made on lookup (``REGISTRY[id]``) without being listed, so the
    registry's listing stays the set of candidates.
    """

    def __missing__(self, key):
        eff = _made_effect(key)
        if eff is None:
            raise KeyError(key)
        return eff


def _made_effect(key):
    m = _FILTER_ID.fullmatch(str(key))
    if m is None:
        return None
    eff = _MADE.get(key)
    if eff is None:
        eff = _MADE[key] = fitted_filter(int(m.group(1)) / 1000.0)
    return eff


def is_effect_id(key) -> bool:
    """True when ``key`` names a registered effect or one made from its id (a fitted sensor filter).

    Parameters
    ----------
    key : str
        An effect id (e.g. ``"thermal"`` or ``"force_filter_lag_z0733"``).

    Returns
    -------
    bool
        Whether ``REGISTRY[key]`` gives an effect.
    """
    return key in REGISTRY or _made_effect(key) is not None


#: Every effect (catalogue and discovery operators), by id.
REGISTRY: dict[str, Effect] = _Registry()


def register(effect: Effect) -> Effect:
    """Add ``effect`` to :data:`REGISTRY` (ids are unique).

    Parameters
    ----------
    effect : Effect
        The effect to register; its ``id`` must not be registered yet.

    Returns
    -------
    Effect
        ``effect`` itself (so it can be used as ``X = register(X(...))``).

    Raises
    ------
    ValueError
        If an effect with the same id is already registered.
    """
    if effect.id in REGISTRY:
        raise ValueError(f"effect id {effect.id!r} registered twice")
    REGISTRY[effect.id] = effect
    return effect


def _fmt(v: float, se: float | None = None, unit: str = "") -> str:
    s = f"{v:.3g}"
    if se is not None and np.isfinite(se):
        s += f" ± {se:.2g}"
    return s + (f" {unit}" if unit else "")


# ================================================================== catalogue
def _remainder(f, travel_mm: float):
    xx = np.linspace(0.0, travel_mm, 401)
    f0 = float(f(np.array(0.0)))
    k = float(((f(xx) - f0) * xx).sum() / (xx * xx).sum())
    return lambda z: f(z) - f0 - k * z


def chamber_remainders(x: np.ndarray, V2_mm3: float, reference: GasSpring = PAPER_FIG5):
    """Nonlinear parts (N per MPa of p2) of the two chamber forces of eq. 5 for the unit ``reference``.

    Returns ``(r2, r1)``: chamber 2 ``A2 V2/(V2 - A2 x)`` (progressive) and
    chamber 1 ``-(p1/p2) A1 V1/(V1 + A1 x)`` (regressive; p1/p2 of the
    design, A2/A1 for eq. 7's zero force at x = 0), each minus its value at
    x = 0 and its least-squares line through the origin over the unit's travel.

    Parameters
    ----------
    x : numpy.ndarray
        Displacement, mm (x > 0 extends the spring).
    V2_mm3 : float
        Chamber-2 volume at x = 0, mm³ (an effective, polytropic volume when fitted).
    reference : GasSpring
        The unit whose chamber areas (mm²), V1 (mm³), pressures (MPa) and
        travel (mm) are used; default the paper's Fig. 5 unit.

    Returns
    -------
    r2, r1 : numpy.ndarray
        Nonlinear remainders of the chamber-2 and chamber-1 forces at ``x``,
        N per MPa of p2 (mm²).
    """
    A1, A2, V1 = reference.A1_mm2, reference.A2_mm2, reference.V1_mm3
    ratio = reference.p1_MPa / reference.p2_MPa if reference.p2_MPa > 0 else A2 / A1
    travel = reference.travel_mm
    xmax = 0.999 * V2_mm3 / A2
    r2 = _remainder(lambda z: A2 * V2_mm3 / (V2_mm3 - A2 * np.clip(z, None, xmax)), travel)(np.clip(x, None, xmax))
    r1 = _remainder(lambda z: -ratio * A1 * V1 / (V1 + A1 * np.clip(z, -0.999 * V1 / A1, None)), travel)(x)
    return r2, r1


@dataclass(frozen=True)
class GasNonlinearity(Effect):
    def grid(self, D, ctx):
        # effective chamber-2 volume: from just above the swept volume to 10 x it
        A2, travel = D.reference.A2_mm2, D.travel_mm
        return A2 * travel * np.geomspace(1.08, 10.0, 14)

    def columns(self, D, V2, ctx):
        c2, c1 = chamber_remainders(D.x, V2, D.reference)
        return np.column_stack([D.p2 * c2, D.p2 * c1])

    def signature(self, D, values, V2, contribution):
        ref = D.reference
        ratio = V2 / ref.V2_mm3
        swept = ref.A2_mm2 * D.travel_mm
        return [
            Check("progressive", values.get("a2", 0.0) > 0.0, f"chamber-2 amplitude a2 = {values.get('a2', 0.0):.3g} (> 0: the compressed chamber stiffens)"),
            Check(
                "chamber volume near the design",
                0.25 <= ratio <= 4.0,
                f"effective V2 = {V2:.3g} mm^3 = {ratio:.2f} x the design's {ref.V2_mm3:.3g} mm^3 (must lie within 0.25..4 x)",
            ),
            Check(
                "a compression a gas spring survives",
                V2 >= 1.25 * swept,
                f"compression ratio at full travel V2/(V2 - A2 travel) = {V2 / max(V2 - swept, 1e-9):.2g} (<= 5: the chamber does not bottom out)",
            ),
        ]

    def describe(self, values, errors, V2, V2_se):
        return (
            f"{self.physics} Effective chamber-2 volume V2 = {_fmt(V2, V2_se, 'mm^3')}, chamber amplitudes "
            f"a2 = {_fmt(values['a2'], errors.get('a2'))}, a1 = {_fmt(values['a1'], errors.get('a1'))} (1 = the unit's areas)."
        )

    bench_strength: str = "amp"

    def bench_random(self, rng, spec):
        A2 = spec.reference.A2_mm2
        return dict(V1_mm3=float(rng.uniform(0.8e5, 3e5)), V2_mm3=float(A2 * spec.travel_mm * rng.uniform(1.4, 4.0)), amp=1.0)

    def bench_force(self, P, cols, spec):
        ref = spec.reference
        A1, A2 = ref.A1_mm2, ref.A2_mm2
        F = lambda z: gas_spring.force_N(z, A1, A2, P["V1_mm3"], P["V2_mm3"], A2 / A1, 1.0)  # noqa: E731
        xx = np.linspace(0, spec.travel_mm, 401)
        k = float((F(xx) * xx).sum() / (xx * xx).sum())
        return P["amp"] * cols["p2"] * (F(cols["x"]) - k * cols["x"])


@dataclass(frozen=True)
class Thermal(Effect):
    def grid(self, D, ctx):
        return np.geomspace(0.1, 50.0, 10)

    def columns(self, D, tau, ctx):
        # per chamber: isothermal pressure x (kappa - 1) x the log volume change, relaxed with tau
        # (linearised p V^kappa = const with heat exchange); plus a geometry-free p2 h term
        # Each chamber exchanges heat through its own walls: chamber 1's time constant may differ from
        # chamber 2's (tau), so chamber 1 is relaxed at tau/2, tau and 2 tau (non-negative weights span
        # the time constants between). Second order in the temperature excess (p ~ exp of the relaxed
        # log-volume change at large, fast compressions): the squared states, amplitudes free.
        u2, u1, f2, f1 = _chamber_logs(D)
        h2 = thermal_state(D, tau, u2, "u2")
        h1 = thermal_state(D, tau, u1, "u1")
        h1s = thermal_state(D, 0.5 * tau, u1, "u1")
        h1l = thermal_state(D, 2.0 * tau, u1, "u1")
        h = thermal_state(D, tau)
        return np.column_stack([D.p2 * f2 * h2, D.p2 * f1 * h1, D.p2 * f1 * h1s, D.p2 * f1 * h1l, D.p2 * h,
                                D.p2 * f2 * h2**2, -D.p2 * f1 * h1**2])

    def signature(self, D, values, tau, contribution):
        spd = np.abs(D.v)
        slow = spd < np.quantile(spd, 0.3)
        fast = spd > np.quantile(spd, 0.7)
        r_slow = float(np.sqrt(np.mean(contribution[slow] ** 2))) if slow.any() else 0.0
        r_fast = float(np.sqrt(np.mean(contribution[fast] ** 2))) if fast.any() else 0.0
        dur = float(np.median(np.diff(D.t[D.bounds[:-1]], prepend=0))) if D.n_exp else 0.0
        tmax = float(np.max(D.t)) if D.n else 0.0
        return [
            Check("speed-dependent", r_fast > 1.5 * r_slow, f"thermal force RMS {r_fast:.3g} N in the fastest 30 % of samples vs {r_slow:.3g} N in the slowest 30 % (must be > 1.5 x)"),
            Check("time constant inside the campaign's time scales", 0.05 <= tau <= 2.0 * max(tmax, dur), f"tau = {tau:.3g} s (longest experiment {tmax:.3g} s)"),
        ]

    def describe(self, values, errors, tau, tau_se):
        return (
            f"{self.physics} Effective kappa - 1 = {_fmt(values['k2'], errors.get('k2'))} (chamber 2), "
            f"{values['k1'] + values['k1s'] + values['k1l']:.3g} (chamber 1, {values['k1s']:.2g} of it at tau/2, {values['k1l']:.2g} at 2 tau), geometry-free part {_fmt(values['k'], errors.get('k'), 'N/mm/MPa')}; heat exchange time constant tau = {_fmt(tau, tau_se, 's')}."
        )

    bench_strength: str = "k_N_per_mm_MPa"

    def bench_random(self, rng, spec):
        return dict(k_N_per_mm_MPa=1.0, tau_s=float(np.exp(rng.uniform(np.log(0.3), np.log(20)))))

    def bench_force(self, P, cols, spec):
        x, v = cols["x"], cols["v"]
        h = np.zeros_like(x)
        for e in np.unique(cols["exp"]):
            m = cols["exp"] == e
            t, ve = cols["t"][m], v[m]
            n_sub = 20
            tf = np.linspace(t[0], t[-1], (len(t) - 1) * n_sub + 1)
            vf = np.interp(tf, t, ve)
            q = np.exp(-(tf[1] - tf[0]) / P["tau_s"])
            h[m] = lfilter([P["tau_s"] * (1 - q)], [1.0, -q], vf)[::n_sub]
        return P["k_N_per_mm_MPa"] * cols["p2"] * h


@dataclass(frozen=True)
class QuadraticDamping(Effect):
    def params(self, D):
        return tuple(Param(f"K({v:g})", "N s^m/mm^m", 0.0, np.inf, f"orifice damping at valve {v:g} deg") for v in D.valves)

    def grid(self, D, ctx):
        return np.array([1.4, 1.6, 1.8, 2.0, 2.25])

    def columns(self, D, m, ctx):
        q = D.v * np.abs(D.v) ** (m - 1.0)
        out = np.empty((D.n, len(D.valves)))  # q 1{valve j} filled in place: no per-valve copies of q to stack (memory on large campaigns)
        for j in range(len(D.valves)):
            np.multiply(q, D.valve_idx == j, out=out[:, j])
        return out

    def signature(self, D, values, m, contribution):
        spd = np.abs(D.v)
        fast = spd >= np.quantile(spd, 0.8)
        grows = float(np.mean(contribution[fast] * D.s[fast])) if fast.any() else 0.0
        return [
            Check("exponent of orifice flow", 1.3 <= m <= 2.3, f"force ~ |xdot|^{m:.2f} (turbulent 2, transitional 1.3-2)"),
            Check("adds force along the motion at speed", grows > 0, f"mean added force along the motion in the fastest 20 % of samples {grows:.3g} N (> 0)"),
        ]

    def describe(self, values, errors, m, m_se):
        big = sorted(values.items(), key=lambda kv: -kv[1])[:2]
        return f"{self.physics} Exponent m = {_fmt(m, m_se)}; largest coefficients " + ", ".join(f"{k} = {v:.3g}" for k, v in big) + " N s^m/mm^m."

    bench_strength: str = "scale"

    def bench_random(self, rng, spec):
        w = np.exp(rng.normal(0, 0.3, len(spec.valves_deg)))
        return dict(K_N_s2_per_mm2={float(g): float(spec.L_N_s_per_mm[float(g)] * wi + 1.0) for g, wi in zip(spec.valves_deg, w)}, scale=1.0)

    def bench_with_strength(self, P, s):
        P = dict(P)
        P["K_N_s2_per_mm2"] = {g: K * s / P["scale"] for g, K in P["K_N_s2_per_mm2"].items()}
        P["scale"] = s
        return P

    def bench_force(self, P, cols, spec):
        K = np.array([P["K_N_s2_per_mm2"][float(g)] for g in cols["valve"]])
        return K * cols["v"] * np.abs(cols["v"])


@dataclass(frozen=True)
class ReliefValve(Effect):
    def grid(self, D, ctx):
        damp = ctx.get("damping_force_N")
        if damp is None or D.n_exp == 0:
            return np.array([])
        # the damping force plateaus of the experiments: the valve opens either
        # between two plateaus or just below the highest one
        peaks = np.array([np.max(np.abs(damp[D.bounds[e] : D.bounds[e + 1]])) for e in range(D.n_exp)])
        levels = np.sort(peaks[peaks > 50.0])
        if len(levels) == 0:
            return np.array([])
        # plateaus within 3 % of each other are one level (same valve and speed, other pressure)
        groups = np.split(levels, np.flatnonzero(levels[1:] > 1.03 * levels[:-1]) + 1)
        mids = [np.sqrt(lo[-1] * hi[0]) for lo, hi in zip(groups[:-1], groups[1:])]
        return np.unique(np.r_[mids[-11:], 0.97 * groups[-1][0]])

    def damping_mask(self, D, F_open, ctx):
        return np.abs(ctx["damping_force_N"]) > F_open

    def columns(self, D, F_open, ctx):
        # the force is continuous through the opening up to a soft knee: the level reached at opening is
        # c F_open with c near 1 (bounded), then r of the further rise
        m = self.damping_mask(D, F_open, ctx)
        damp = ctx["damping_force_N"]
        s = D.s
        # [s m F_open, m (damp - s F_open)], the same operations filled in place (memory on large campaigns)
        out = np.empty((D.n, 2))
        np.multiply(s, m, out=out[:, 0])
        out[:, 0] *= F_open
        np.multiply(s, F_open, out=out[:, 1])
        np.subtract(damp, out[:, 1], out=out[:, 1])
        np.multiply(m, out[:, 1], out=out[:, 1])
        return out

    def signature(self, D, values, F_open, contribution):
        return [
            Check("opens far above friction", F_open > 300.0, f"opening force {F_open:.3g} N (a relief valve opens at kN level, not at friction level)"),
            Check("caps the force", values.get("r", 1.0) < 0.7, f"force slope above opening r = {values.get('r', 1.0):.2f} of the throttle's (< 0.7: the valve relieves)"),
        ]

    def describe(self, values, errors, F_open, se):
        return (
            f"{self.physics} Opens at F_open = {_fmt(F_open, se, 'N')}; above it the throttle force is "
            f"F_r = {_fmt(values['c'] * F_open, errors.get('c', np.nan) * F_open, 'N')} plus r = {_fmt(values['r'], errors.get('r'))} of the further rise."
        )

    bench_strength: str = "F_r_N"
    bench_snr_rises: bool = False
    bench_linear: bool = False

    def bench_random(self, rng, spec):
        return dict(F_r_N=1.0)

    def bench_strength_range(self, cols, spec):
        L = np.array([spec.L_N_s_per_mm[float(g)] for g in cols["valve"]])
        # a blow-off valve protects the unit: it opens above 1 kN, never at friction level
        return (1000.0, float(np.max(np.abs(L * cols["v"]))))

    def bench_force(self, P, cols, spec):
        L = np.array([spec.L_N_s_per_mm[float(g)] for g in cols["valve"]])
        damp = L * cols["v"]
        return np.clip(damp, -P["F_r_N"], P["F_r_N"]) - damp


@dataclass(frozen=True)
class Stiction(Effect):
    def grid(self, D, ctx):
        return np.geomspace(0.02, 3.0, 9)

    def columns(self, D, vs, ctx):
        a = np.abs(D.v) / vs
        return np.column_stack([D.s * np.exp(-a), D.s * np.exp(-(a**2))])

    def signature(self, D, values, vs, contribution):
        spd = np.abs(D.v)
        vmax = float(np.max(spd)) if D.n else 0.0
        slow = spd <= np.quantile(spd, 0.2)
        fast = spd >= np.quantile(spd, 0.5)
        a_slow = float(np.mean(np.abs(contribution[slow]))) if slow.any() else 0.0
        a_fast = float(np.mean(np.abs(contribution[fast]))) if fast.any() else 0.0
        return [
            Check("breakaway at low speed", vs < 0.5 * vmax, f"Stribeck velocity {vs:.3g} mm/s < half the top speed {vmax:.3g} mm/s"),
            Check("decays with sliding speed", a_slow > 2.0 * a_fast, f"mean |force| {a_slow:.3g} N in the slowest 20 % of samples vs {a_fast:.3g} N in the fastest half (must be > 2 x)"),
        ]

    def describe(self, values, errors, vs, se):
        S = values["S1"] + values["S2"]
        return f"{self.physics} Breakaway {S:.3g} N above Coulomb (S1 = {_fmt(values['S1'], errors.get('S1'), 'N')}, S2 = {_fmt(values['S2'], errors.get('S2'), 'N')}), Stribeck velocity v_s = {_fmt(vs, se, 'mm/s')}."

    bench_strength: str = "S_N"

    def bench_random(self, rng, spec):
        return dict(S_N=1.0, v_s_mm_s=float(np.exp(rng.uniform(np.log(0.05), np.log(1.5)))), delta=float(rng.uniform(1.5, 2.5)))

    def bench_force(self, P, cols, spec):
        v = cols["v"]
        return P["S_N"] * np.sign(v) * np.exp(-((np.abs(v) / P["v_s_mm_s"]) ** P["delta"]))


@dataclass(frozen=True)
class PressureFriction(Effect):
    def columns(self, D, _, ctx):
        return (D.p2 * D.s)[:, None]

    def signature(self, D, values, _, contribution):
        ps = np.unique(D.p2)
        return [Check("several charge pressures", len(ps) >= 2, f"{len(ps)} pressure preset(s) in the campaign (needs >= 2 to tell pressure from Coulomb friction)")]

    def describe(self, values, errors, _, __):
        return f"{self.physics} c_p = {_fmt(values['c_p'], errors.get('c_p'), 'N/MPa')}."

    bench_strength: str = "c_p_N_per_MPa"

    def bench_random(self, rng, spec):
        return dict(c_p_N_per_MPa=1.0)

    def bench_force(self, P, cols, spec):
        return P["c_p_N_per_MPa"] * cols["p2"] * np.sign(cols["v"])


@dataclass(frozen=True)
class Leakage(Effect):
    def columns(self, D, _, ctx):
        # the charge falls over campaign time t_c: every part of the spring force that scales with the
        # charge falls with it -- the chamber-2 preload (offset), the stiffness, and each chamber's
        # curvature (present only if the spring is curved) -- at a rate that may itself change (t_c^2)
        th = D.ctime / 3600.0
        r2, r1 = cached(D, ("leak_remainders",), lambda: chamber_remainders(D.x, D.reference.V2_mm3, D.reference))
        return np.column_stack([-D.p2 * th, -D.p2 * D.x * th, -D.p2 * th * r2, D.p2 * th * r1, D.p2 * th**2, D.p2 * D.x * th**2])

    def signature(self, D, values, _, contribution):
        th = float(np.max(D.ctime) / 3600.0) if D.n else 0.0
        late = D.ctime >= np.quantile(D.ctime, 0.8) if D.n else np.zeros(0, bool)
        early = D.ctime <= np.quantile(D.ctime, 0.2) if D.n else np.zeros(0, bool)
        drift = float(np.sqrt(np.mean(contribution[late] ** 2)) - np.sqrt(np.mean(contribution[early] ** 2))) if D.n else 0.0
        return [Check("grows over the campaign", drift > 0, f"RMS of the leak force in the last fifth of the campaign minus the first fifth: {drift:.3g} N (> 0; campaign {th:.2g} h)")]

    def describe(self, values, errors, _, __):
        return (
            f"{self.physics} Preload loss {_fmt(values['q0'], errors.get('q0'), 'N/MPa/h')}, stiffness loss "
            f"{_fmt(values['q'], errors.get('q'), 'N/mm/MPa/h')}, curvature loss q2 = {_fmt(values['q2'], errors.get('q2'), '1/h')} (chamber 2), "
            f"q1 = {_fmt(values['q1'], errors.get('q1'), '1/h')} (chamber 1); the loss slows by {values['c0']:.3g} N/MPa/h^2 "
            f"(preload) and {values['c']:.3g} N/mm/MPa/h^2 (stiffness)."
        )

    bench_strength: str = "rate_per_h"
    bench_linear: bool = False

    def bench_random(self, rng, spec):
        return dict(rate_per_h=1.0)

    def bench_force(self, P, cols, spec):
        return spec.g_N_per_mm_MPa * cols["p2"] * cols["x"] * (np.exp(-P["rate_per_h"] * cols["ctime_h"]) - 1.0)


register(GasNonlinearity(
    "gas_nonlinearity",
    "antagonistic gas spring (eq. 5)",
    "The two gas chambers follow the gas law of paper eq. 5 with the unit's own areas and volumes: the compressed "
    "chamber stiffens as its volume shrinks, so the spring is progressive, not the straight line g p2 x.",
    "f += p2 (a2 r2(x; V2) + a1 r1(x)),  r2 = A2 V2/(V2 - A2 x) - line,  r1 = -(p1/p2) A1 V1/(V1 + A1 x) - line "
    "(eq. 5 per MPa of p2 with the design's A1, A2, V1 and travel; each chamber minus its straight line)",
    (
        Param("a2", "1", 0.0, 5.0, "chamber-2 (compressed, progressive) amplitude; 1 = the unit's area A2"),
        Param("a1", "1", 0.0, 5.0, "chamber-1 (expanding, regressive) amplitude; 1 = the unit's V1, A1"),
    ),
    Param("V2", "mm^3", 0.0, np.inf, "effective chamber-2 gas volume at x = 0 (isothermal: the real one; polytropic: smaller)"),
))
register(Thermal(
    "thermal",
    "non-isothermal gas (heat exchange)",
    "Fast compression heats the gas, which then cools through the walls with a time constant tau: "
    "the spring is stiffer while moving and relaxes at rest, a speed-dependent force proportional to p2.",
    "f += p2 (f2 (k2 h2 + s2 h2^2) + f1 (k1 h1 + k1s h1[tau/2] + k1l h1[2 tau] - s1 h1^2) + k h),  f2 = A2 V2/(V2 - A2 x), "
    "f1 = (p1/p2) A1 V1/(V1 + A1 x),  dh_i/dt = du_i/dt - h_i/tau, u2 = -ln(1 - A2 x/V2), u1 = ln(1 + A1 x/V1), u = x  "
    "(p V^kappa with wall heat exchange, to second order; chamber 1 with its own time constant)",
    (
        Param("k2", "1", 0.0, 1.0, "chamber 2: effective kappa - 1 of the fast compression (0.4 adiabatic air)"),
        Param("k1", "1", 0.0, 1.0, "chamber 1: effective kappa - 1 of the fast expansion (relaxing with tau)"),
        Param("k1s", "1", 0.0, 1.0, "chamber 1: part relaxing with tau/2"),
        Param("k1l", "1", 0.0, 1.0, "chamber 1: part relaxing with 2 tau"),
        Param("k", "N/mm/MPa", 0.0, np.inf, "geometry-free excess stiffness per MPa"),
        Param("s2", "1", 0.0, np.inf, "chamber 2: second-order coefficient ((kappa - 1)^2/2 adiabatic: p ~ exp of the relaxed log-compression)"),
        Param("s1", "1", 0.0, np.inf, "chamber 1: second-order coefficient (the expanding chamber's pressure falls less than linearly)"),
    ),
    Param("tau", "s", 0.0, np.inf, "thermal time constant"),
))
register(QuadraticDamping(
    "quadratic_damping",
    "turbulent throttle flow",
    "Flow through a sharp-edged orifice is turbulent: the pressure drop, and hence the throttle force, "
    "grows with the square of the flow rate (exponent m between 1.3 and 2 in the transition), not linearly.",
    "f += K(gamma) xdot |xdot|^(m-1)",
    (),
    Param("m", "1", 1.0, 3.0, "velocity exponent of the orifice force (2 = fully turbulent)"),
    log_shape=False,
))
register(ReliefValve(
    "relief_valve",
    "pressure relief valve",
    "The blow-off valve opens at a set pressure difference and caps the throttle force, "
    "however fast the piston is pushed (soft knee: the valve spring lets the force rise a little further).",
    "f = g p2 x + d(L(gamma) xdot) + C sign(xdot),  d(F) = F for |F| <= F_open, else sign(F) c F_open + r (F - sign(F) F_open)  "
    "(c near 1: the force is continuous through the opening up to a soft knee)",
    (
        Param("c", "1", 0.85, 1.15, "force at opening relative to the opening level (1: continuous; a soft knee rounds it)"),
        Param("r", "1", 0.0, 1.0, "slope of the throttle force above opening, relative to the closed valve"),
    ),
    Param("F_open", "N", 0.0, np.inf, "damping force above which the valve is open"),
    needs=("damping_force_N",),
))
register(Stiction(
    "stiction",
    "Stribeck breakaway friction",
    "Seals stick at rest: breaking away at start and at reversal needs more force than the Coulomb level, "
    "which decays as the sliding speed rises (Stribeck curve).",
    "f += sign(xdot) (S1 exp(-|xdot|/v_s) + S2 exp(-(|xdot|/v_s)^2))",
    (
        Param("S1", "N", 0.0, np.inf, "breakaway above Coulomb, exponential Stribeck part"),
        Param("S2", "N", 0.0, np.inf, "breakaway above Coulomb, Gaussian Stribeck part"),
    ),
    Param("v_s", "mm/s", 0.0, np.inf, "Stribeck velocity"),
))
register(PressureFriction(
    "pressure_friction",
    "pressure-loaded seal friction",
    "Seal lips are pressed onto the rod by the gas charge, so seal friction grows in proportion to p2.",
    "f += c_p p2 sign(xdot)",
    (Param("c_p", "N/MPa", 0.0, np.inf, "seal friction per MPa of charge"),),
))
register(Leakage(
    "leakage",
    "charge leakage",
    "Gas leaks past the seals, so the charge pressure, and with it the stiffness, drifts down over the campaign.",
    "f += -p2 t_c (q0 + q x + q2 r2(x) - q1 r1(x)) + p2 t_c^2 (c0 + c x)   (t_c campaign time in h; r2, r1 the chambers' "
    "curvature of eq. 5, zero for a straight spring)",
    (
        Param("q0", "N/MPa/h", 0.0, np.inf, "chamber-2 preload (force at x = 0) lost per MPa per hour"),
        Param("q", "N/mm/MPa/h", 0.0, np.inf, "stiffness lost per MPa per hour"),
        Param("q2", "1/h", 0.0, np.inf, "chamber-2 curvature lost per hour"),
        Param("q1", "1/h", 0.0, np.inf, "chamber-1 curvature lost per hour"),
        Param("c0", "N/MPa/h^2", 0.0, np.inf, "slowing of the preload loss over the campaign (the leak flow falls with the charge)"),
        Param("c", "N/mm/MPa/h^2", 0.0, np.inf, "slowing of the stiffness loss over the campaign"),
    ),
))


# ================================================================== discovery operators
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


def _filter_design(D: FitData, X: np.ndarray, ba, out, eq14_first: bool) -> np.ndarray:
    """The design ``X`` through the sensor filter ``ba(dt_fine) -> (b, a)`` (:func:`_on_sample_grid`), eq. 14's damping columns with the motion's velocity between samples.

    With ``eq14_first`` (``X`` is a whole design, eq. 14's columns first),
    each damping column ``L(gamma) xdot`` is filtered as the velocity really
    runs between samples (:func:`_velocity_gaps`: a ramp's end or a reversal
    between two samples, where a stiff valve's force bends), and the
    friction column ``sign(xdot)`` turns at the start and the reversal
    itself, not along the straight line between samples: linear filtering
    lets the corrections add.
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


@dataclass(frozen=True)
class ForceLag(Effect):
    def grid(self, D, ctx):
        return np.geomspace(0.003, 3.0, 13)

    def columns(self, D, tau, ctx):
        return np.zeros((D.n, 0))

    def transform(self, D, X, tau, ctx, out=None, eq14_first=False):
        # the reading is the unit's force through a first-order lag: every column of the model is lagged
        # (exact and still linear in the amplitudes); the sensor starts from the unit at rest before the
        # motion (zero force state: every column of the model vanishes at rest at x = 0)
        def ba(dt):
            q = np.exp(-dt / tau)
            return [1.0 - q], [1.0, -q]

        return _filter_design(D, X, ba, out, eq14_first)

    def describe(self, values, errors, tau, se):
        return (
            f"The force reading lags the motion by tau = {_fmt(tau, se, 's')} (first-order lag of the whole force): "
            "sensor or amplifier dynamics, not the spring or damper."
        )


def _bilinear_2nd_order(wn: float, zeta: float, fs: float):
    """``scipy.signal.bilinear([wn²], [1, 2 ζ wn, wn²], fs)`` in closed form (the same digital filter, without its polynomial overhead).

    Parameters: natural frequency ``wn`` (rad/s), damping ratio ``zeta`` (-), sampling rate ``fs`` (Hz).
    Returns the numerator and denominator coefficients (descending powers of z, ``a[0] = 1``).
    """
    K = 2.0 * fs
    a0 = K * K + 2.0 * zeta * wn * K + wn * wn
    b = (wn * wn / a0) * np.array([1.0, 2.0, 1.0])
    a = np.array([1.0, 2.0 * (wn * wn - K * K) / a0, (K * K - 2.0 * zeta * wn * K + wn * wn) / a0])
    return b, a


@dataclass(frozen=True)
class ForceFilter(ForceLag):
    """Second-order low-pass of the force reading (damping ratio ``zeta`` of a standard filter type); shape = its lag 2 zeta / omega_n."""

    zeta: float = 0.7071
    kind: str = "Butterworth"

    def grid(self, D, ctx):
        # the filter types compete on this grid, so it is fine around the lag the residual shows: a lag
        # tau leaves residual ~ -tau df/dt of the model force f (first order in tau)
        r, f = ctx.get("residual_N"), ctx.get("model_force_N")
        coarse = np.geomspace(0.003, 3.0, 13)
        if r is None or f is None or D.n_exp == 0:
            return coarse
        fd = np.zeros(D.n)
        for e in range(D.n_exp):
            a, b = D.bounds[e], D.bounds[e + 1]
            if b - a > 2:
                fd[a:b] = np.gradient(f[a:b], D.t[a:b])
        m = (r != 0) & np.isfinite(fd)
        den = float(np.sum(fd[m] ** 2))
        tau = -float(np.sum(r[m] * fd[m])) / den if den > 0 else np.nan
        if not np.isfinite(tau) or tau <= 0.003:
            return coarse
        return np.clip(tau, 0.003, 3.0) * np.geomspace(0.6, 2.5, 9)

    def transform(self, D, X, lag, ctx, out=None, eq14_first=False):
        wn = 2 * self.zeta / lag

        def ba(dt):
            # bilinear (Tustin) discretisation of wn^2/(s^2 + 2 zeta wn s + wn^2), in closed form; from rest (see ForceLag)
            return _bilinear_2nd_order(wn, self.zeta, 1.0 / dt)

        return _filter_design(D, X, ba, out, eq14_first)

    def describe(self, values, errors, lag, se):
        fn = 2 * self.zeta / lag / (2 * np.pi)
        kind = f"damping ratio {self.zeta:.3g}, fitted" if self.kind.startswith("fitted") else f"{self.kind}, damping ratio {self.zeta:.3g}"
        return (
            f"The force reading passes a second-order filter ({kind}, natural frequency {fn:.3g} Hz, "
            f"lag {_fmt(lag, se, 's')}): sensor or amplifier dynamics, not the spring or damper."
        )


#: id of a second-order force filter with a fitted damping ratio: ``force_filter_lag_z`` + 1000 zeta (4 digits)
_FILTER_ID = re.compile(r"force_filter_lag_z(\d{4})")
_MADE: dict = {}  #: fitted sensor filters made from their id
ZETA_RANGE = (0.4, 1.6)  #: damping ratios a fitted sensor filter may take (underdamped amplifier .. nearly first order)


def filter_id(zeta: float) -> str:
    """Effect id of the second-order force filter with damping ratio ``zeta`` (rounded to 0.001).

    Parameters
    ----------
    zeta : float
        Damping ratio (dimensionless), within :data:`ZETA_RANGE`.

    Returns
    -------
    str
        ``force_filter_lag_z`` + 1000 zeta on 4 digits (``force_filter_lag_z0733`` for 0.733).

    Raises
    ------
    ValueError
        If ``zeta`` lies outside :data:`ZETA_RANGE`.
    """
    z = float(zeta)
    if not (ZETA_RANGE[0] - 1e-9 <= z <= ZETA_RANGE[1] + 1e-9):
        raise ValueError(f"filter damping ratio zeta = {z:g} outside {ZETA_RANGE}")
    return f"force_filter_lag_z{int(round(1000 * z)):04d}"


def fitted_filter(zeta: float) -> "ForceFilter":
    """The second-order force-reading filter with a fitted damping ratio (not registered: made from its id).

    Parameters
    ----------
    zeta : float
        Damping ratio (dimensionless), within :data:`ZETA_RANGE`; rounded to 0.001.

    Returns
    -------
    ForceFilter
        The filter effect, id :func:`filter_id` (``zeta``), its shape the lag 2 zeta/omega_n in s.
    """
    z = round(float(zeta), 3)
    return ForceFilter(filter_id(z), "second-order force-reading filter (fitted damping ratio)",
                       "The measured force is the unit's force through a second-order filter.",
                       f"f_meas = H(s) f,  H = wn^2/(s^2 + 2 zeta wn s + wn^2),  zeta = {z:.3f} (fitted),  lag = 2 zeta/wn", (),
                       Param("lag", "s", 0.0, np.inf, "filter lag 2 zeta/omega_n"), catalogue=False, zeta=z,
                       kind="fitted damping ratio")


@dataclass(frozen=True)
class DampingLag(Effect):
    def grid(self, D, ctx):
        return np.geomspace(0.003, 3.0, 13)

    def columns(self, D, tau, ctx):
        f = ctx["damping_force_N"]
        return (lowpass(D, f, tau) - f)[:, None]

    def describe(self, values, errors, tau, se):
        return (
            f"The throttle force builds up with a time constant tau = {_fmt(tau, se, 's')} (gain {values['a']:.2f}): compliance "
            "in the hydraulic path (bladder, trapped gas) or fluid inertia delays the damping force."
        )


@dataclass(frozen=True)
class MotionMemory(Effect):
    def grid(self, D, ctx):
        return np.geomspace(0.03, 100.0, 12)

    def columns(self, D, tau, ctx):
        return thermal_state(D, tau)[:, None]

    def describe(self, values, errors, tau, se):
        return (
            f"A force of {_fmt(values['k'], errors.get('k'), 'N/mm')} per mm of recent motion that relaxes with tau = {_fmt(tau, se, 's')}, "
            "independent of the charge pressure: viscoelastic relaxation of elastomer parts (bladder, seals)."
        )


@dataclass(frozen=True)
class PreSliding(Effect):
    def grid(self, D, ctx):
        return np.geomspace(0.01, 4.0, 12)

    def columns(self, D, r, ctx):
        # friction builds up over a travel r after each start and reversal. Bristle (Dahl/LuGre-like)
        # approach: the deficit decays as exp(-d/r) with the travel d since the start or reversal; it is
        # Coulomb at a start from rest, twice Coulomb at a reversal (the seal swings from -F_c to +F_c),
        # so the two carry their own amplitudes; its rate shows as a damping (bristle damping) that
        # decays alike; the elastic-plastic (stop-operator) approach is the alternative shape.
        z = stop_operator(D, r)
        e = np.exp(-_travel_since_reversal(D) / r)
        first = _first_ramp(D)
        ex = -D.s * e
        return np.column_stack([z / r - D.s, D.p2 * (z / r - D.s), ex * first, ex * ~first, D.p2 * ex * ~first, -D.v * e])

    def describe(self, values, errors, r, se):
        F = values["F_h"] + values["F_e"]
        return (
            f"Hysteresis with memory of the motion: after each start or reversal the force needs about {_fmt(r, se, 'mm')} of travel to reach "
            f"its sliding level (loop width {2 * F:.3g} N + {2 * (values['F_hp'] + values['F_ep']):.3g} N per MPa across the loop; "
            f"deficit {values['F_s']:.3g} N after a start from rest): pre-sliding "
            "(elastic seal/bladder deformation before gross sliding), not a speed effect."
        )


@dataclass(frozen=True)
class PositionRipple(Effect):
    def grid(self, D, ctx):
        periods = np.geomspace(0.3, max(D.travel_mm / 2.5, 0.6), 400)
        return _periodogram_peaks(D.x, ctx["residual_N"], periods)

    def columns(self, D, pitch, ctx):
        w = 2 * np.pi * D.x / pitch
        return np.column_stack([np.sin(w), np.cos(w)])

    def describe(self, values, errors, pitch, se):
        A = float(np.hypot(values["a_s"], values["a_c"]))
        return (
            f"A {A:.3g} N periodic force with {_fmt(pitch, se, 'mm')} pitch in displacement, the same in every experiment: "
            "spindle or lead-screw ripple of the drive (or a periodic bore/seal track), not the gas spring."
        )


@dataclass(frozen=True)
class TimeRipple(Effect):
    """A force periodic in time whose phase is not tied to the motion: the phase is fitted per experiment.

    The period and the amplitude are shared by all experiments; each
    experiment's phase is a nuisance parameter set from its own residual
    (``residual_all_N``), so the term cannot be predicted for a new motion
    without measuring it (:meth:`columns` gives zeros without a residual).
    """

    nuisance_per_experiment: int = 2
    shape_xtol: float = 1e-7

    def _fast_rows(self, D):
        dts = D.per_exp_dt()
        keep = dts <= np.median(dts) + 1e-12
        return np.repeat(keep, D.n_per_exp), float(np.max(dts[keep])) if keep.any() else 1.0

    def _power(self, D, r, periods, rows):
        """Per-experiment-phase periodogram: sum over experiments of the power at each period."""
        pw = np.zeros(len(periods))
        w = 2 * np.pi / periods
        trig, kept = {}, 0  # cos and sin of the phases per distinct sampling (experiments share a few), up to 32 MB
        for e in range(D.n_exp):
            a, b = D.bounds[e], D.bounds[e + 1]
            if not rows[a]:
                continue
            key = D.t[a:b].tobytes()
            cs = trig.get(key)
            if cs is None:
                ph = np.outer(D.t[a:b], w)
                cs = (np.cos(ph), np.sin(ph))
                if kept + 2 * ph.nbytes <= 32e6:
                    trig[key] = cs
                    kept += 2 * ph.nbytes
            re = r[a:b] - r[a:b].mean()
            pw += (re @ cs[0]) ** 2 + (re @ cs[1]) ** 2
        return pw

    def grid(self, D, ctx):
        rows, dt = self._fast_rows(D)
        r = ctx["residual_N"]
        periods = np.geomspace(3 * dt, 40.0, 330)
        pw = self._power(D, r, periods, rows & (r != 0))
        if not np.any(pw):
            return np.array([])
        k = int(np.argmax(pw))
        if pw[k] < 5.0 * np.median(pw):  # no line stands out of the noise: nothing periodic to test
            return np.array([])
        best = float(periods[k])
        # the fast experiments are short against a slow ripple: the frequency is resolved by every experiment
        # sampled at least 2.5 times per period (no aliasing), the longest ones most finely: scanned over the
        # coarse estimate's uncertainty (+-15 %) at an eighth of their resolution; then over +-3 of those
        # steps by all experiments (aliasing puts no other line that close) at an eighth of theirs
        dts = D.per_exp_dt()
        live = r != 0
        ok = np.repeat(dts <= best / 2.5, D.n_per_exp) & live
        if ok.any():
            span = max(float(np.max(D.t[ok]) - np.min(D.t[ok])), best)
            f0, df = 1.0 / best, 1.0 / (8.0 * span)
            half = min(0.15 * f0, 400 * df)
            freqs = f0 + np.arange(-half, half + 0.5 * df, df)
            freqs = freqs[freqs > 0]
            best = float(1.0 / freqs[int(np.argmax(self._power(D, r, 1.0 / freqs, ok)))])
        else:
            df = 0.05 / best
        span_all = max(float(np.max(D.t[live]) - np.min(D.t[live])), best) if live.any() else best
        f0, df2 = 1.0 / best, min(1.0 / (8.0 * span_all), df)
        freqs = f0 + np.arange(-3 * df, 3 * df + 0.5 * df2, df2)
        freqs = freqs[freqs > 0]
        best = float(1.0 / freqs[int(np.argmax(self._power(D, r, 1.0 / freqs, live)))])
        step = best * best * df2
        return np.array([best - step, best, best + step])

    def columns(self, D, period, ctx):
        r = ctx.get("residual_all_N")
        if r is None:
            return np.zeros((D.n, 1))
        w = 2 * np.pi / period
        sn, cs = np.sin(w * D.t), np.cos(w * D.t)
        # the phase from a least-squares fit of sine, cosine and an offset to each experiment's residual
        # (an experiment shorter than the period leaves sine and cosine far from orthogonal): the 3 x 3
        # normal equations of all experiments at once
        B = [sn, cs, np.ones(D.n)]
        starts = D.bounds[:-1]
        G = np.empty((D.n_exp, 3, 3))
        rhs = np.empty((D.n_exp, 3))
        for i in range(3):
            rhs[:, i] = np.add.reduceat(B[i] * r, starts) if D.n else 0.0
            for j in range(i, 3):
                G[:, i, j] = G[:, j, i] = np.add.reduceat(B[i] * B[j], starts) if D.n else 0.0
        ok = D.n_per_exp >= 3
        coef = np.zeros((D.n_exp, 3))
        if ok.any():
            G[ok] += 1e-12 * np.trace(G[ok], axis1=1, axis2=2)[:, None, None] * np.eye(3)  # a period much longer than an experiment
            coef[ok] = np.linalg.solve(G[ok], rhs[ok][..., None])[..., 0]
        phi = np.repeat(np.arctan2(coef[:, 1], coef[:, 0]), D.n_per_exp)
        col = np.sin(w * D.t + phi)
        return col[:, None]

    def describe(self, values, errors, period, se):
        return (
            f"A {_fmt(values['A'], errors.get('A'), 'N')} periodic force at {1 / period:.4g} Hz (period {_fmt(period, se, 's')}), "
            "independent of position and speed, its phase not tied to the start of the motion: vibration of the "
            "test machine or a periodic disturbance in the force chain (phase fitted per experiment)."
        )


@dataclass(frozen=True)
class DirectionStiffness(Effect):
    def columns(self, D, _, ctx):
        up = D.s > 0
        return np.column_stack([D.x * up, D.x * ~up, D.p2 * D.x * D.s])

    def describe(self, values, errors, _, __):
        return (
            f"The stiffness differs between extension and retraction: {_fmt(values['k_ext'], errors.get('k_ext'), 'N/mm')} extra while "
            f"extending, {_fmt(values['k_ret'], errors.get('k_ret'), 'N/mm')} while retracting (+ {_fmt(values['dk_p'], errors.get('dk_p'), 'N/mm/MPa')} "
            "p2 x sign(xdot)): a spring that engages in one direction only (one-sided contact, a check valve, friction "
            "growing with load) -- not a gas law, not plain friction."
        )


@dataclass(frozen=True)
class SpringPolynomial(Effect):
    def columns(self, D, _, ctx):
        u = D.x / D.travel_mm
        return np.column_stack([D.p2 * (u**2 - u), D.p2 * (u**3 - u), u**2 - u, u**3 - u])

    def describe(self, values, errors, _, __):
        return (
            "The force-displacement curve bends in a way the unit's gas law does not explain: a polynomial in x "
            f"(per MPa: {values['b2p']:.3g} N u^2 {values['b3p']:+.3g} N u^3; charge-independent {values['b2']:.3g} N u^2 {values['b3']:+.3g} N u^3, "
            "u = x/travel): a spring element outside the gas chambers (bladder, end stop) or a geometry other than the design's."
        )


@dataclass(frozen=True)
class PressureDamping(Effect):
    def columns(self, D, _, ctx):
        return (ctx["damping_force_N"] * (D.p2 - np.mean(D.p2)))[:, None]

    def describe(self, values, errors, _, __):
        return f"The throttle force changes by {_fmt(100 * values['c'], 100 * errors.get('c', np.nan), '%')} per MPa of charge: fluid properties or valve behaviour that depend on pressure."


@dataclass(frozen=True)
class FrictionAlongStroke(Effect):
    def columns(self, D, _, ctx):
        u = D.x / D.travel_mm
        return np.column_stack([D.s * u, D.s * u**2])

    def describe(self, values, errors, _, __):
        return (
            f"Friction changes along the stroke by {values['c1'] + values['c2']:.3g} N from x = 0 to full travel: a tapered or "
            "misaligned bore, or seal load growing with the stroke."
        )


@dataclass(frozen=True)
class CampaignTrend(Effect):
    def columns(self, D, _, ctx):
        th = D.ctime / 3600.0
        return np.column_stack([th, D.s * th])

    def describe(self, values, errors, _, __):
        return (
            f"A drift over the campaign: force offset {_fmt(values['d0'], errors.get('d0'), 'N/h')} and friction "
            f"{_fmt(values['d1'], errors.get('d1'), 'N/h')}: sensor zero drift, warming up or seal wear."
        )


_FREE = (-np.inf, np.inf)
register(ForceLag("force_lag", "force-reading lag", "The measured force is a lagged copy of the force the unit makes.",
                  "f_meas = lowpass_tau(f),  tau df_meas/dt = f - f_meas   (the whole model lagged)", (),
                  Param("tau", "s", 0.0, np.inf, "lag time constant"), catalogue=False))
for _zeta, _kind, _id in ((0.7071, "Butterworth", "force_filter_lag"), (0.78, "between Butterworth and Bessel", "force_filter_lag_z078"),
                          (0.8660, "Bessel", "force_bessel_lag"), (0.93, "between Bessel and critical", "force_filter_lag_z093"),
                          (1.0, "critically damped", "force_critical_lag")):
    register(ForceFilter(_id, f"second-order force-reading filter ({_kind})", "The measured force is the unit's force through a second-order filter.",
                         f"f_meas = H(s) f,  H = wn^2/(s^2 + 2 zeta wn s + wn^2),  zeta = {_zeta:.4g} ({_kind}),  lag = 2 zeta/wn", (),
                         Param("lag", "s", 0.0, np.inf, "filter lag 2 zeta/omega_n"), catalogue=False, zeta=_zeta, kind=_kind))
register(DampingLag("damping_lag", "lagging throttle force", "The throttle force builds up with a time constant.",
                    "f += a (lowpass_tau(L xdot) - L xdot)", (Param("a", "1", 0.0, 1.5, "share of a first-order lag of the damping force"),),
                    Param("tau", "s", 0.0, np.inf, "time constant"), catalogue=False, needs=("damping_force_N",)))
register(MotionMemory("motion_memory", "relaxing memory of the motion", "A force proportional to recent motion that relaxes.",
                      "f += k h,  dh/dt = xdot - h/tau", (Param("k", "N/mm", 0.0, np.inf, "relaxing stiffness"),),
                      Param("tau", "s", 0.0, np.inf, "relaxation time constant"), catalogue=False))
register(PreSliding("presliding_hysteresis", "pre-sliding hysteresis (stop operator)", "Friction builds up over a travel after reversal.",
                    "f += (F_h + F_hp p2) (stop_r(x)/r - sign(xdot)) - (F_s 1{first ramp} + (F_e + F_ep p2) 1{after reversal}) sign(xdot) exp(-d/r) "
                    "- b xdot exp(-d/r)   (d: travel since the start or last reversal)",
                    (Param("F_h", "N", 0.0, np.inf, "friction deficit right after reversal (elastic-plastic)"), Param("F_hp", "N/MPa", 0.0, np.inf, "its growth per MPa"),
                     Param("F_s", "N", 0.0, np.inf, "friction deficit at the start from rest (exponential approach)"),
                     Param("F_e", "N", 0.0, np.inf, "friction deficit right after reversal (exponential approach)"), Param("F_ep", "N/MPa", 0.0, np.inf, "its growth per MPa"),
                     Param("b", "N s/mm", -np.inf, np.inf, "damping of the pre-sliding deformation (bristle damping)")),
                    Param("r", "mm", 0.0, np.inf, "pre-sliding travel (half loop width in x)"), catalogue=False))
register(PositionRipple("position_ripple", "periodic force in displacement", "A force periodic in x.",
                        "f += a_s sin(2 pi x/P) + a_c cos(2 pi x/P)",
                        (Param("a_s", "N", *_FREE, "sine amplitude"), Param("a_c", "N", *_FREE, "cosine amplitude")),
                        Param("P", "mm", 0.0, np.inf, "pitch"), catalogue=False, needs=("residual_N",)))
register(TimeRipple("time_ripple", "periodic force in time", "A force periodic in time.",
                    "f += A sin(2 pi t/T + phi_e)   (phi_e fitted per experiment from its residual)",
                    (Param("A", "N", 0.0, np.inf, "amplitude"),),
                    Param("T", "s", 0.0, np.inf, "period"), catalogue=False, needs=("residual_N",)))
register(DirectionStiffness("direction_stiffness", "direction-dependent stiffness", "The stiffness differs between the two directions.",
                            "f += k_ext x 1{xdot > 0} + k_ret x 1{xdot < 0} + dk_p p2 x sign(xdot)",
                            (Param("k_ext", "N/mm", *_FREE, "extra stiffness while extending"), Param("k_ret", "N/mm", *_FREE, "extra stiffness while retracting"),
                             Param("dk_p", "N/mm/MPa", *_FREE, "direction-dependent stiffness per MPa")),
                            catalogue=False))
register(SpringPolynomial("spring_polynomial", "non-gas spring curvature", "The spring curve bends beyond the gas law.",
                          "f += p2 (b2p (u^2-u) + b3p (u^3-u)) + b2 (u^2-u) + b3 (u^3-u),  u = x/travel",
                          (Param("b2p", "N/MPa", *_FREE), Param("b3p", "N/MPa", *_FREE), Param("b2", "N", *_FREE), Param("b3", "N", *_FREE)),
                          catalogue=False))
register(PressureDamping("pressure_damping", "pressure-dependent damping", "The throttle force depends on the charge.",
                         "f += c (p2 - mean p2) L(gamma) xdot", (Param("c", "1/MPa", *_FREE, "relative change of damping per MPa"),),
                         catalogue=False, needs=("damping_force_N",)))
register(FrictionAlongStroke("friction_along_stroke", "friction varying along the stroke", "Friction changes with x.",
                             "f += sign(xdot) (c1 u + c2 u^2),  u = x/travel",
                             (Param("c1", "N", *_FREE), Param("c2", "N", *_FREE)), catalogue=False))
register(CampaignTrend("campaign_trend", "drift over the campaign", "Offset and friction drift over campaign time.",
                       "f += d0 t_c + d1 t_c sign(xdot)   (t_c in h)",
                       (Param("d0", "N/h", *_FREE, "offset drift"), Param("d1", "N/h", *_FREE, "friction drift")), catalogue=False))

#: Catalogue effects (named physics of the unit), in registry order.
CATALOGUE: dict[str, Effect] = {k: e for k, e in REGISTRY.items() if e.catalogue}
#: Discovery operators, in registry order.
DISCOVERY: dict[str, Effect] = {k: e for k, e in REGISTRY.items() if not e.catalogue}
#: The catalogue's effect ids.
EFFECT_IDS: tuple[str, ...] = tuple(CATALOGUE)
#: The discovery operators' ids.
DISCOVERY_IDS: tuple[str, ...] = tuple(DISCOVERY)
