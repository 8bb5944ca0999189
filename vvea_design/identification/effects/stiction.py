"""Catalogue effect ``stiction``: Stribeck breakaway friction, between exponential and Gaussian in shape.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .base import Check, Effect, Param, fmt_estimate, register

__all__: list[str] = []  # its effects are reached through the registry

#: Place of this module's effects among the candidates (see :mod:`vvea_design.identification.effects`).
RANK = 50


@dataclass(frozen=True)
class Stiction(Effect):
    depends_on = ("velocity",)  #: the states its force depends on (names from evidence)

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
        return f"{self.physics} Breakaway {S:.3g} N above Coulomb (S1 = {fmt_estimate(values['S1'], errors.get('S1'), 'N')}, S2 = {fmt_estimate(values['S2'], errors.get('S2'), 'N')}), Stribeck velocity v_s = {fmt_estimate(vs, se, 'mm/s')}."

    bench_strength: str = "S_N"

    def bench_random(self, rng, spec):
        return dict(S_N=1.0, v_s_mm_s=float(np.exp(rng.uniform(np.log(0.05), np.log(1.5)))), delta=float(rng.uniform(1.5, 2.5)))

    def bench_force(self, P, cols, spec):
        v = cols["v"]
        return P["S_N"] * np.sign(v) * np.exp(-((np.abs(v) / P["v_s_mm_s"]) ** P["delta"]))


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
