"""Force of the unit along one experiment: base physics plus whatever the mechanisms changed.

A mechanism never computes the whole force. It edits an :class:`ExperimentMods` record of each
experiment (a charge factor, a damping factor, the actual valve angle, an added force or friction
term, a throttle law, a sensor offset...) and :func:`simulate_experiment` composes them in the
order the physics acts:

1. kinematics — piston position ``x_p`` = crosshead position (+ a zero offset); frame compliance
   is solved last, as the piston then lags the crosshead;
2. gas — eq. 5 (isothermal) with the charge factors, or the chamber energy balance;
3. throttle — laminar ``L ẋ`` (+ turbulent orifice, + relief valve), then the oil column's
   compressibility (a lag), then the cavitation floor;
4. friction — Coulomb (times its factors) + added friction terms (+ Stribeck), times sign(ẋ);
5. added forces (membrane, contact, start transient);
6. the load cell: offset, then the campaign adds the noise.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np
from scipy.optimize import brentq

from .motion import ExperimentPlan, Motion
from .unit import BaseUnit

__all__ = ["ExperimentMods", "State", "simulate_experiment", "throttle_static_N", "RHO_OIL_KG_MM3"]

#: Oil density, kg/mm³ (mineral hydraulic oil, 870 kg/m³).
RHO_OIL_KG_MM3 = 870e-9
#: Gas constant ratio of air, cp/cv.
GAMMA_AIR = 1.4


@dataclass
class ExperimentMods:
    """What the active mechanisms changed in one experiment (defaults: the base physics)."""

    valve_deg: float  #: actual valve angle, degree (the command unless a mechanism moves it)
    charge2: list = field(default_factory=list)  #: callables t -> factor on chamber 2's charge
    charge1: list = field(default_factory=list)  #: callables t -> factor on chamber 1's charge
    damping: list = field(default_factory=list)  #: callables t -> factor on the laminar damping
    x_offset_mm: float = 0.0  #: piston position minus crosshead position, mm
    force_terms: list = field(default_factory=list)  #: callables State -> added force, N
    friction_terms: list = field(default_factory=list)  #: callables State -> added friction magnitude, N
    friction_factors: list = field(default_factory=list)  #: callables State -> factor on Coulomb C
    stribeck: dict | None = None  #: {"Fs_over_C", "v_s_mm_s", "delta"}: Stribeck breakaway
    turbulent_K_N_s2_mm2: float = 0.0  #: orifice term K ẋ|ẋ| of the throttle, N s²/mm²
    relief: dict | None = None  #: spring-ball relief valve parameters
    oil_stiffness_N_per_mm: float | None = None  #: A2²/C_h of a compressible oil column, N/mm
    cavitation_p_MPa: float | None = None  #: absolute pressure at which the oil side cavitates, MPa
    thermal: dict | None = None  #: {"tau2_s", "tau1_s"}: chamber energy balance
    frame_K_N_per_mm: float | None = None  #: stiffness in series with the unit, N/mm
    sensor_offset_N: float = 0.0  #: load-cell offset, N
    owners: dict = field(default_factory=dict)  #: field name -> mechanism that set it

    def claim(self, field_name: str, mechanism: str) -> None:
        """Record that ``mechanism`` sets ``field_name``; two mechanisms may not set the same one.

        Parameters
        ----------
        field_name : str
            Name of the exclusive field (e.g. ``"relief"``).
        mechanism : str
            Name of the mechanism setting it.

        Raises
        ------
        ValueError
            If another mechanism already set that field.
        """
        prev = self.owners.get(field_name)
        if prev is not None and prev != mechanism:
            raise ValueError(f"mechanisms {prev!r} and {mechanism!r} both set {field_name!r}: not combinable")
        self.owners[field_name] = mechanism


@dataclass(frozen=True)
class State:
    """Everything a force or friction term may depend on, per sample of one experiment."""

    t: np.ndarray  #: time since the start, s
    x: np.ndarray  #: piston position, mm
    v: np.ndarray  #: piston velocity, mm/s
    P2: np.ndarray  #: chamber-2 absolute pressure, MPa
    F_gas: np.ndarray  #: gas force, N
    F_thr: np.ndarray  #: throttle force, N
    plan: ExperimentPlan  #: the experiment's settings and campaign time
    base: BaseUnit  #: the unit
    valve_deg: float  #: actual valve angle, degree
    turn_index: int  #: index of the turning point


def _factor(funcs, t) -> np.ndarray:
    out = np.ones_like(t)
    for f in funcs:
        out = out * np.asarray(f(t), dtype=float)
    return out


def _turbulent_velocity(F, L, K):
    """Equivalent piston velocity through a laminar+orifice throttle at force F (inverse law)."""
    F = np.asarray(F, dtype=float)
    if K <= 0:
        return F / L
    a = np.abs(F)
    return np.sign(F) * (-L + np.sqrt(L * L + 4.0 * K * a)) / (2.0 * K)


def _relief_velocity(F, A2, r):
    """Equivalent piston velocity of the relief valve's flow at throttle force F >= 0, mm/s."""
    dp = np.asarray(F, dtype=float) / A2  # MPa
    a_seat = math.pi / 4.0 * r["d_seat_mm"] ** 2
    lift = np.clip((dp - r["F_crack_N"] / A2) * a_seat / r["k_spring_N_per_mm"], 0.0, r["lift_max_mm"])
    area = math.pi * r["d_seat_mm"] * lift  # curtain area, mm²
    jet = np.sqrt(2.0 * np.maximum(dp, 0.0) * 1e6 / 870.0) * 1e3  # mm/s
    return r["Cd"] * area * jet / A2


def throttle_static_N(v, L, K=0.0, relief=None, A2=None) -> np.ndarray:
    """Throttle force of an incompressible oil column: laminar + orifice, bypassed by a relief valve.

    Parameters
    ----------
    v : array_like
        Piston velocity, mm/s.
    L : float or array_like
        Laminar damping, N s/mm.
    K : float
        Orifice coefficient (force = K ẋ|ẋ|), N s²/mm².
    relief : dict or None
        Relief valve (``F_crack_N``, ``d_seat_mm``, ``k_spring_N_per_mm``, ``lift_max_mm``, ``Cd``,
        ``bidirectional``); None: no relief valve.
    A2 : float or None
        Chamber-2 (working piston) area, mm²; needed with a relief valve.

    Returns
    -------
    numpy.ndarray
        Throttle force, N, with the sign of ``v`` (it opposes the motion).
    """
    v = np.asarray(v, dtype=float)
    L = np.broadcast_to(np.asarray(L, dtype=float), v.shape)
    F = L * v + K * v * np.abs(v)
    if relief is None:
        return F
    s = np.sign(v)
    a = np.abs(v)
    lo, hi = np.zeros_like(a), np.abs(F)
    if not relief.get("bidirectional", True):
        hi = np.where(v < 0, 0.0, hi)
    for _ in range(60):  # total flow u(F) + u_r(F) is increasing in F: bisection
        mid = 0.5 * (lo + hi)
        u = _turbulent_velocity(mid, L, K) + _relief_velocity(mid, A2, relief)
        lo, hi = np.where(u < a, mid, lo), np.where(u < a, hi, mid)
    Fr = s * 0.5 * (lo + hi)
    if not relief.get("bidirectional", True):
        Fr = np.where(v < 0, F, Fr)
    return Fr


def _thermal_pressures(base, plan, motion, t, x_off, f2, f1, th):
    """Chamber pressures from each chamber's energy balance (ideal gas, wall at the charge temperature).

    Over each sub-step the balance ``dθ/dt = -(γ-1) θ V̇/V + (1 - θ)/τ`` (θ = T/T_wall) is linear
    with coefficients frozen at the sub-step's middle, and is advanced exactly.
    """
    gm1 = GAMMA_AIR - 1.0
    n_sub = np.maximum(1, np.ceil(np.diff(t) / 0.25).astype(int))
    fine = np.concatenate([[t[0]]] + [np.linspace(t[k], t[k + 1], n + 1)[1:] for k, n in enumerate(n_sub)])
    ends = np.cumsum(n_sub)  # index in `fine` of each sample after the first
    xs = motion.position_mm(fine) + x_off
    h = np.diff(fine).tolist()
    theta = np.ones((len(t), 2))
    chambers = ((base.V2_mm3, -base.A2_mm2, th["tau2_s"]), (base.V1_mm3, base.A1_mm2, th["tau1_s"]))
    for c, (V0, dV, tau) in enumerate(chambers):
        logV = np.log(V0 + dV * xs).tolist()
        th_c, out, k = 1.0, [1.0], 0
        for j, hj in enumerate(h):
            a = gm1 * (logV[j] - logV[j + 1]) / hj - 1.0 / tau  # -(γ-1) V̇/V - 1/τ
            if abs(a) < 1e-12:  # heating and exchange balance: θ moves linearly
                th_c += hj / tau
            else:
                star = -(1.0 / tau) / a
                th_c = star + (th_c - star) * math.exp(a * hj)
            if j + 1 == ends[k]:
                out.append(th_c)
                k += 1
        theta[:, c] = out
    x = motion.position_mm(t) + x_off
    P1, P2 = base.chamber_pressures_MPa(x, plan.p2_MPa, f2, f1)
    return P1 * theta[:, 1], P2 * theta[:, 0]


def _compressible_throttle(t, v, k_oil, L, K):
    """Throttle force through a compressible oil column (Maxwell: oil stiffness in series with the throttle).

    ``dF/dt = k (ẋ - u(F))`` with ``u`` the throttle's velocity at force ``F``; each sub-step is
    advanced exactly for the throttle linearised at its current force (exponential update).
    """
    F = np.zeros_like(v)
    v_list, L_list, t_list = v.tolist(), np.broadcast_to(L, v.shape).tolist(), t.tolist()
    f = 0.0
    for i in range(1, len(t_list)):
        h_tot = t_list[i] - t_list[i - 1]
        n = max(1, min(20, int(math.ceil(h_tot / 0.01))))
        h = h_tot / n
        Li = L_list[i]
        for j in range(n):
            vv = v_list[i - 1] + (v_list[i] - v_list[i - 1]) * (j + 1) / n  # end of the sub-step
            target = Li * vv + K * vv * abs(vv)
            u = f / Li if K <= 0 else math.copysign((-Li + math.sqrt(Li * Li + 4.0 * K * abs(f))) / (2.0 * K), f)
            R = Li + 2.0 * K * abs(u)
            f = target + (f - target) * math.exp(-k_oil * h / R)
        F[i] = f
    return F


def _smooth_max(a, floor, width=5.0):
    z = (a - floor) / width
    return floor + width * np.logaddexp(0.0, z)


def simulate_experiment(base: BaseUnit, plan: ExperimentPlan, mods: ExperimentMods, motion: Motion) -> dict:
    """Noise-free force of the unit over one experiment.

    Parameters
    ----------
    base : BaseUnit
        The unit's base physics.
    plan : ExperimentPlan
        The experiment's preset, valve command, speed and campaign time.
    mods : ExperimentMods
        What the active mechanisms changed.
    motion : Motion
        The crosshead motion (its sample times are the experiment's samples).

    Returns
    -------
    dict of numpy.ndarray
        ``t_s``, ``x_cross_mm`` (crosshead, what the displacement channel reads), ``x_mm`` and
        ``v_mm_s`` (piston), ``P2_MPa``, ``F_gas_N``, ``F_thr_N``, ``F_fric_N``, ``F_extra_N``,
        ``f_unit_N`` (force the unit transmits) and ``f_meas_N`` (what a noise-free load cell
        reads: ``f_unit_N`` + offset).
    """
    t = motion.t_s
    xc = motion.position_mm(t)
    v = motion.velocity_mm_s(t)
    x = xc + mods.x_offset_mm
    f2, f1 = _factor(mods.charge2, t), _factor(mods.charge1, t)
    L = float(base.damping_N_s_per_mm(mods.valve_deg)) * _factor(mods.damping, t)
    if mods.frame_K_N_per_mm is not None:
        return _simulate_with_frame(base, plan, mods, motion, t, xc, f2, f1, L)

    if mods.thermal is not None:
        P1, P2 = _thermal_pressures(base, plan, motion, t, mods.x_offset_mm, f2, f1, mods.thermal)
        F_gas = base.A2_mm2 * P2 - base.A1_mm2 * P1
    else:
        F_gas = base.gas_force_N(x, plan.p2_MPa, f2, f1)
        P2 = base.chamber_pressures_MPa(x, plan.p2_MPa, f2, f1)[1]

    K = mods.turbulent_K_N_s2_mm2
    F_thr = throttle_static_N(v, L, K, mods.relief, base.A2_mm2)
    if mods.oil_stiffness_N_per_mm is not None:
        if mods.relief is not None:
            raise ValueError("a compressible oil column is not combinable with the relief valve")
        F_thr = _compressible_throttle(t, v, mods.oil_stiffness_N_per_mm, L, K)
    if mods.cavitation_p_MPa is not None:  # the oil side cannot fall below the gas-release pressure
        F_thr = _smooth_max(F_thr, -base.A2_mm2 * (P2 - mods.cavitation_p_MPa))

    state = State(t, x, v, P2, F_gas, F_thr, plan, base, mods.valve_deg, motion.turn_index)
    mag = base.C_N * np.ones_like(t)
    for f in mods.friction_factors:
        mag = mag * f(state)
    if mods.stribeck is not None:
        s = mods.stribeck
        mag = mag + base.C_N * (s["Fs_over_C"] - 1.0) * np.exp(-((np.abs(v) / s["v_s_mm_s"]) ** s["delta"]))
    for f in mods.friction_terms:
        mag = mag + f(state)
    F_fric = mag * base.friction_sign(v)
    F_extra = np.zeros_like(t)
    for f in mods.force_terms:
        F_extra = F_extra + f(state)
    f_unit = F_gas + F_thr + F_fric + F_extra
    return dict(t_s=t, x_cross_mm=xc, x_mm=x, v_mm_s=v, P2_MPa=P2, F_gas_N=F_gas, F_thr_N=F_thr,
                F_fric_N=F_fric, F_extra_N=F_extra, f_unit_N=f_unit, f_meas_N=f_unit + mods.sensor_offset_N)


def _simulate_with_frame(base, plan, mods, motion, t, xc, f2, f1, L):
    """Unit in series with a compliant frame: implicit Euler on the transmitted force ``q``.

    The piston is at ``x_p = x_cross - q/K`` and moves at ``v_p = v_cross - q̇/K``; each step solves
    ``q = gas(x_p) + L v_p + C tanh(v_p/ε)`` for ``q`` (monotone: bracketed root). Where a sample step
    is comparable to the Maxwell time ``L/K`` it is split into sub-steps of at most a fifth of it (at
    most 20); where it is over 50 Maxwell times the force is quasi-static and one implicit step is exact
    enough.
    """
    busy = [n for n in ("force_terms", "friction_terms", "friction_factors") if getattr(mods, n)]
    if busy or mods.thermal or mods.relief or mods.oil_stiffness_N_per_mm or mods.stribeck \
            or mods.cavitation_p_MPa is not None or mods.turbulent_K_N_s2_mm2:
        raise ValueError("frame compliance combines only with charge, damping, valve, offset and sensor mechanisms")
    Kf, p2, C, eps = mods.frame_K_N_per_mm, plan.p2_MPa, base.C_N, base.friction_eps_mm_s
    A1, A2, V1, V2 = base.A1_mm2, base.A2_mm2, base.V1_mm3, base.V2_mm3
    p1, g = float(base.p1_MPa(p2)), base.g_N_per_mm_MPa
    x0 = mods.x_offset_mm
    lin = base.gas_law == "linear"
    n = len(t)
    q = np.zeros(n)
    vp = np.zeros(n)
    q[0] = float(base.gas_force_N(xc[0] + x0, p2, f2[0], f1[0]))
    qk = q[0]
    for k in range(1, n):
        a2, a1, Lk = f2[k], f1[k], L[k]
        r = (t[k] - t[k - 1]) / max(Lk / Kf, 1e-12)  # step over the Maxwell time
        m = 1 if r > 50.0 else max(1, min(20, int(math.ceil(5.0 * r))))
        ts = np.linspace(t[k - 1], t[k], m + 1)[1:]
        xs, vs = (motion.position_mm(ts) + x0).tolist(), motion.velocity_mm_s(ts).tolist()
        h = (t[k] - t[k - 1]) / m
        for j in range(m):
            xm, vm, q_old = xs[j], vs[j], qk

            def resid(qq, xm=xm, vm=vm, q_old=q_old):
                xx = xm - qq / Kf
                vv = vm - (qq - q_old) / (Kf * h)
                if lin:
                    gas = 0.5 * (a1 + a2) * g * p2 * xx
                else:
                    gas = A2 * a2 * p2 * V2 / (V2 - A2 * xx) - A1 * a1 * p1 * V1 / (V1 + A1 * xx)
                return qq - gas - Lk * vv - C * math.tanh(vv / eps)

            span = 2e3 + abs(q_old) * 0.5
            lo, hi = q_old - span, q_old + span
            while resid(lo) > 0:
                lo -= span
            while resid(hi) < 0:
                hi += span
            qk = brentq(resid, lo, hi, xtol=1e-7)
            vp[k] = vm - (qk - q_old) / (Kf * h)
        q[k] = qk
    xp = xc + x0 - q / Kf
    F_gas = base.gas_force_N(xp, p2, f2, f1)
    P2 = base.chamber_pressures_MPa(xp, p2, f2, f1)[1]
    F_thr = L * vp
    F_fric = C * np.tanh(vp / eps)
    return dict(t_s=t, x_cross_mm=xc, x_mm=xp, v_mm_s=vp, P2_MPa=P2, F_gas_N=F_gas, F_thr_N=F_thr,
                F_fric_N=F_fric, F_extra_N=q - F_gas - F_thr - F_fric, f_unit_N=q,
                f_meas_N=q + mods.sensor_offset_N)
