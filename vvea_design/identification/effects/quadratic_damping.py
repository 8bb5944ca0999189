"""Catalogue effect ``quadratic_damping``: turbulent throttle flow, ``K(γ) ẋ |ẋ|^(m-1)``.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .base import Check, Effect, Param, fmt_estimate, register

__all__: list[str] = []  # its effects are reached through the registry

#: Place of this module's effects among the candidates (see :mod:`vvea_design.identification.effects`).
RANK = 30


@dataclass(frozen=True)
class QuadraticDamping(Effect):
    depends_on = ("velocity", "valve")  #: the states its force depends on (names from evidence)

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
        return f"{self.physics} Exponent m = {fmt_estimate(m, m_se)}; largest coefficients " + ", ".join(f"{k} = {v:.3g}" for k, v in big) + " N s^m/mm^m."

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
