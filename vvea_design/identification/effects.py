"""Catalogue of candidate effects that the paper's eq. 14 leaves out.

The baseline is the paper's identification model (eq. 14)::

    f = g p2 x + L(γ) ẋ + C sign(ẋ)

Each candidate effect adds physically grounded terms. Every term is linear
in its amplitude parameters once at most one *shape* parameter is fixed
(a chamber volume, a time constant, a Stribeck velocity, a relief force);
the shape parameter is searched on a grid and refined, the amplitudes are
found by bounded linear least squares. Bounds carry the physical sign: a
friction cannot pull with the motion, a leak cannot raise the pressure.

===================  ==========================================================
id                   added force (N)
===================  ==========================================================
gas_nonlinearity     p2 (a2 r2(x; V2) + a1 r1(x)): the two chamber forces of the
                     isothermal antagonistic law (eq. 5) per MPa of p2, each
                     minus its least-squares line through the origin
thermal              k p2 h_τ(t),  ḣ = ẋ - h/τ   (heat exchange, polytropic gas)
quadratic_damping    K(γ) ẋ|ẋ|   (turbulent orifice flow)
relief_valve         damping force L(γ)ẋ capped at ±F_r (blow-off valve)
stiction             S sign(ẋ) exp(-(|ẋ|/v_s)²)   (Stribeck breakaway)
pressure_friction    c_p p2 sign(ẋ)   (seal friction grows with charge)
leakage              -q p2 x t_c   (charge drifts down with campaign time t_c)
===================  ==========================================================
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Callable

import numpy as np
from scipy.signal import lfilter

from ..spring import gas_spring
from ..spring.gas_spring import GasSpring, PAPER_FIG5
from .recordings import Recordings

__all__ = [
    "FitData",
    "Param",
    "Effect",
    "CATALOGUE",
    "EFFECT_IDS",
    "baseline_columns",
    "effect_params",
    "gas_remainder",
    "chamber_remainders",
    "thermal_state",
]


@dataclass(frozen=True)
class FitData:
    """Numeric arrays of a campaign, ready for fitting (one entry per sample).

    Attributes (units): ``x`` mm, ``v`` mm/s (estimated), ``p2`` MPa,
    ``valve`` degree, ``valve_idx`` index into ``valves``, ``t`` s within the
    experiment, ``tsr`` s since last reversal, ``ctime`` s of campaign time,
    ``exp`` experiment index (0..n_exp-1, run order), ``y`` measured force N,
    ``bounds`` row offsets of the experiments, ``reference`` the unit's gas
    spring geometry (areas and V1 used by ``gas_nonlinearity``).
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

    @classmethod
    def from_recordings(cls, rec: Recordings, reference: GasSpring = PAPER_FIG5, drop_rest: bool = True) -> "FitData":
        """Arrays of a :class:`~vvea_design.identification.recordings.Recordings` campaign.

        With ``drop_rest`` the samples at rest (start, turning point, end:
        ``at_rest``) are left out, because friction is set-valued there;
        :attr:`rows_left_out` counts them.
        """
        d = rec.data[~rec.data["at_rest"].to_numpy()] if drop_rest else rec.data
        valve = d["valve_deg"].to_numpy(float)
        valves = tuple(np.unique(valve))
        exp = d["exp_index"].to_numpy(int)
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


@dataclass(frozen=True)
class Param:
    """A model parameter: name, unit, physical bounds, meaning."""

    name: str
    unit: str
    lower: float
    upper: float
    meaning: str = ""


def baseline_columns(D: FitData) -> tuple[np.ndarray, list[Param]]:
    """Design matrix of eq. 14: ``[p2 x, sign(ẋ), ẋ·1{γ=γ_j} ...]``."""
    cols = [D.p2 * D.x, D.s]
    params = [
        Param("g", "N/mm/MPa", 0.0, np.inf, "spring stiffness per MPa of p2"),
        Param("C", "N", 0.0, np.inf, "Coulomb friction (Table 3's B)"),
    ]
    for j, val in enumerate(D.valves):
        cols.append(D.v * (D.valve_idx == j))
        params.append(Param(f"L({val:g})", "N s/mm", 0.0, np.inf, f"linear damping at valve {val:g} deg"))
    return np.column_stack(cols), params


# ------------------------------------------------------------------ physics
_XX = np.linspace(0.0, 40.0, 401)


def gas_remainder(x: np.ndarray, V2_mm3: float, reference: GasSpring = PAPER_FIG5, travel_mm: float = 40.0) -> np.ndarray:
    """Nonlinear part of the antagonistic isothermal law per MPa of p2 (N/MPa).

    Paper eq. 5 with the reference areas and V1, chamber volume ``V2`` and
    p1 from eq. 7 (zero force at x = 0), minus its least-squares line through
    the origin over ``0..travel``; what a straight ``g p2 x`` cannot follow.
    """
    A1, A2, V1 = reference.A1_mm2, reference.A2_mm2, reference.V1_mm3
    p1 = A2 / A1

    def F(z):
        return gas_spring.force_N(z, A1, A2, V1, V2_mm3, p1, 1.0)

    xx = np.linspace(0.0, travel_mm, 401)
    k = float((F(xx) * xx).sum() / (xx * xx).sum())
    xc = np.clip(x, None, 0.999 * V2_mm3 / A2)
    return F(xc) - k * xc


def _remainder(f, travel_mm: float = 40.0):
    xx = np.linspace(0.0, travel_mm, 401)
    f0 = float(f(np.array(0.0)))
    k = float(((f(xx) - f0) * xx).sum() / (xx * xx).sum())
    return lambda z: f(z) - f0 - k * z


def chamber_remainders(x: np.ndarray, V2_mm3: float, reference: GasSpring = PAPER_FIG5, travel_mm: float = 40.0):
    """Nonlinear parts (N per MPa of p2) of the two chamber forces of eq. 5.

    Returns ``(r2, r1)``: chamber 2 ``A2 V2/(V2 - A2 x)`` (progressive) and
    chamber 1 ``-A2 V1/(V1 + A1 x)`` (p1 = A2/A1 p2, eq. 7; regressive),
    each minus its value at x = 0 and its least-squares line through the
    origin over the travel.
    Their sum is :func:`gas_remainder`.
    """
    A1, A2, V1 = reference.A1_mm2, reference.A2_mm2, reference.V1_mm3
    xc = np.clip(x, None, 0.999 * V2_mm3 / A2)
    r2 = _remainder(lambda z: A2 * V2_mm3 / (V2_mm3 - A2 * np.clip(z, None, 0.999 * V2_mm3 / A2)), travel_mm)(xc)
    r1 = _remainder(lambda z: -A2 * V1 / (V1 + A1 * z), travel_mm)(x)
    return r2, r1


def thermal_state(D: FitData, tau_s: float) -> np.ndarray:
    """Thermal state h (mm): ḣ = ẋ - h/τ per experiment, h = 0 at start.

    Exact for piecewise-linear x between samples. ``k p2 h`` is the excess
    gas force that heat exchange with the walls relaxes with time constant τ.
    """
    key = ("thermal", float(tau_s))
    if key in D._cache:
        return D._cache[key]
    h = np.zeros(D.n)
    for e in range(D.n_exp):
        a, b = D.bounds[e], D.bounds[e + 1]
        t = D.t[a:b]
        dx = np.diff(D.x[a:b], prepend=D.x[a])
        dt = float(np.median(np.diff(t))) if b - a > 1 else 1.0
        q = np.exp(-dt / tau_s)
        gain = tau_s * (1 - q) / dt
        h[a:b] = lfilter([gain], [1.0, -q], dx)
    D._cache[key] = h
    return h


# ------------------------------------------------------------------ effects
@dataclass(frozen=True)
class Effect:
    """One candidate effect of the catalogue.

    Attributes
    ----------
    id : str
        Identifier (``shared/specs/diagnosis-report.md``).
    title : str
        Short name.
    physics : str
        A sentence a mechanical engineer would accept.
    equation : str
        The added term.
    params : tuple[Param]
        Amplitude parameters (linear, bounded).
    shape : Param or None
        The one shape parameter searched on ``grid`` (None: purely linear).
    grid : callable
        ``grid(D, context) -> array`` of shape-parameter values to search.
    columns : callable
        ``columns(D, shape_value, context) -> (n, k)`` design columns.
    damping_mask : callable or None
        ``mask(D, shape_value, context) -> bool (n,)`` samples whose linear
        damping column is replaced (relief valve only).
    """

    id: str
    title: str
    physics: str
    equation: str
    params: tuple
    shape: Param | None
    grid: Callable
    columns: Callable
    damping_mask: Callable | None = None
    log_shape: bool = True


def _gas_grid(D, ctx):
    A2 = D.reference.A2_mm2
    return A2 * np.geomspace(42.0, 400.0, 14)


def _gas_cols(D, V2, ctx):
    key = ("gas", float(V2))
    if key not in D._cache:
        c2, c1 = chamber_remainders(D.x, V2, D.reference)
        D._cache[key] = np.column_stack([D.p2 * c2, D.p2 * c1])
    return D._cache[key]


def _thermal_cols(D, tau, ctx):
    return (D.p2 * thermal_state(D, tau))[:, None]


def _quad_cols(D, _, ctx):
    q = D.v * np.abs(D.v)
    return np.column_stack([q * (D.valve_idx == j) for j in range(len(D.valves))])


def _relief_grid(D, ctx):
    damp = ctx.get("damping_force_N")
    if damp is None:
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
    grid = np.r_[mids[-11:], 0.97 * groups[-1][0]]
    return np.unique(grid)


def _relief_mask(D, F_r, ctx):
    damp = ctx.get("damping_force_N")
    return np.abs(damp) > F_r


def _relief_cols(D, F_r, ctx):
    return (D.s * _relief_mask(D, F_r, ctx))[:, None]


def _stiction_cols(D, vs, ctx):
    return (D.s * np.exp(-((np.abs(D.v) / vs) ** 2)))[:, None]


def _pfric_cols(D, _, ctx):
    return (D.p2 * D.s)[:, None]


def _leak_cols(D, _, ctx):
    return (-D.p2 * D.x * D.ctime / 3600.0)[:, None]


_NOGRID = lambda D, ctx: np.array([np.nan])  # noqa: E731


def _catalogue() -> dict[str, Effect]:
    effs = [
        Effect(
            "gas_nonlinearity",
            "antagonistic isothermal gas spring",
            "The two gas chambers follow Boyle's law (paper eq. 5): the compressed chamber stiffens as its volume "
            "shrinks, so the spring is progressive, not the straight line g p2 x.",
            "f += p2 * (a2 * r2(x; V2) + a1 * r1(x)),  r2 = A2 V2/(V2 - A2 x) - k2 x,  r1 = -A2 V1/(V1 + A1 x) - k1 x "
            "(eq. 5 per MPa of p2, p1 = A2/A1 p2, each chamber minus its straight line)",
            (
                Param("a2", "1", 0.0, 5.0, "chamber-2 (compressed, progressive) amplitude; 1 = reference area A2"),
                Param("a1", "1", 0.0, 5.0, "chamber-1 (expanding, regressive) amplitude; 1 = reference V1, A1"),
            ),
            Param("V2", "mm^3", 0.0, np.inf, "chamber-2 gas volume at x = 0"),
            _gas_grid,
            _gas_cols,
        ),
        Effect(
            "thermal",
            "non-isothermal gas (heat exchange)",
            "Fast compression heats the gas, which then cools through the walls with a time constant tau: "
            "the spring is stiffer while moving and relaxes at rest, a speed-dependent force proportional to p2.",
            "f += k * p2 * h,  dh/dt = xdot - h/tau",
            (Param("k", "N/mm/MPa", 0.0, np.inf, "excess (adiabatic minus isothermal) stiffness per MPa"),),
            Param("tau", "s", 0.0, np.inf, "thermal time constant"),
            lambda D, ctx: np.geomspace(0.1, 50.0, 10),
            _thermal_cols,
        ),
        Effect(
            "quadratic_damping",
            "turbulent throttle flow",
            "Flow through a sharp-edged orifice is turbulent: the pressure drop, and hence the throttle force, "
            "grows with the square of the flow rate, i.e. with xdot|xdot|.",
            "f += K(gamma) * xdot * |xdot|",
            None,  # filled below (one per valve)
            None,
            _NOGRID,
            _quad_cols,
        ),
        Effect(
            "relief_valve",
            "pressure relief valve",
            "The blow-off valve opens at a set pressure difference and caps the throttle force at +-F_r, "
            "however fast the piston is pushed.",
            "f = g p2 x + sat(L(gamma) xdot, F_r) + C sign(xdot)",
            (Param("F_r", "N", 0.0, np.inf, "relief (cap) force of the throttle"),),
            Param("F_open", "N", 0.0, np.inf, "damping force above which the valve is open"),
            _relief_grid,
            _relief_cols,
            _relief_mask,
        ),
        Effect(
            "stiction",
            "Stribeck breakaway friction",
            "Seals stick at rest: breaking away at start and at reversal needs more force than the Coulomb level, "
            "which decays as the sliding speed rises (Stribeck curve).",
            "f += S * sign(xdot) * exp(-(|xdot|/v_s)^2)",
            (Param("S", "N", 0.0, np.inf, "breakaway force above Coulomb"),),
            Param("v_s", "mm/s", 0.0, np.inf, "Stribeck velocity"),
            lambda D, ctx: np.geomspace(0.02, 3.0, 9),
            _stiction_cols,
        ),
        Effect(
            "pressure_friction",
            "pressure-loaded seal friction",
            "Seal lips are pressed onto the rod by the gas charge, so seal friction grows in proportion to p2.",
            "f += c_p * p2 * sign(xdot)",
            (Param("c_p", "N/MPa", 0.0, np.inf, "seal friction per MPa of charge"),),
            None,
            _NOGRID,
            _pfric_cols,
        ),
        Effect(
            "leakage",
            "charge leakage",
            "Gas leaks past the seals, so the charge pressure, and with it the stiffness, drifts down over the campaign.",
            "f += -q * p2 * x * t_c   (t_c in h: g p2(t_c) = g p2 (1 - q t_c / g))",
            (Param("q", "N/mm/MPa/h", 0.0, np.inf, "stiffness loss per MPa per hour of campaign"),),
            None,
            _NOGRID,
            _leak_cols,
        ),
    ]
    out = {e.id: e for e in effs}
    return out


CATALOGUE: dict[str, Effect] = _catalogue()
#: The effect ids, in catalogue order.
EFFECT_IDS: tuple[str, ...] = tuple(CATALOGUE)


def effect_params(effect: Effect, D: FitData) -> tuple:
    """Amplitude parameters of ``effect`` for campaign ``D`` (per-valve for quadratic damping)."""
    if effect.id == "quadratic_damping":
        return tuple(
            Param(f"K({v:g})", "N s^2/mm^2", 0.0, np.inf, f"quadratic damping at valve {v:g} deg") for v in D.valves
        )
    return effect.params
