"""Catalogue effect ``thermal``: non-isothermal gas (heat exchange with the walls).

Per chamber, the isothermal pressure times (κ - 1) times the log volume
change, relaxed with the time constant τ (linearised ``p V^κ = const`` with
heat exchange), chamber 1 at τ/2, τ and 2τ, to second order.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy.signal import lfilter

from ..fit_data import FitData, cached
from ..signals import thermal_state
from .base import Check, Effect, Param, fmt_estimate, register

__all__: list[str] = []  # its effects are reached through the registry

#: Place of this module's effects among the candidates (see :mod:`vvea_design.identification.effects`).
RANK = 20


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


@dataclass(frozen=True)
class Thermal(Effect):
    depends_on = ("position", "velocity", "charge", "since_reversal", "distance_since_reversal", "filtered_velocity")  #: the states its force depends on (names from evidence)

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
            f"{self.physics} Effective kappa - 1 = {fmt_estimate(values['k2'], errors.get('k2'))} (chamber 2), "
            f"{values['k1'] + values['k1s'] + values['k1l']:.3g} (chamber 1, {values['k1s']:.2g} of it at tau/2, {values['k1l']:.2g} at 2 tau), geometry-free part {fmt_estimate(values['k'], errors.get('k'), 'N/mm/MPa')}; heat exchange time constant tau = {fmt_estimate(tau, tau_se, 's')}."
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
