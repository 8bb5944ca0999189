"""Catalogue effect ``relief_valve``: the blow-off valve caps the throttle force above its opening force (soft knee).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .base import Check, Effect, Param, fmt_estimate, register

__all__: list[str] = []  # its effects are reached through the registry

#: Place of this module's effects among the candidates (see :mod:`vvea_design.identification.effects`).
RANK = 40


@dataclass(frozen=True)
class ReliefValve(Effect):
    depends_on = ("velocity", "valve")  #: the states its force depends on (names from evidence)

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
            f"{self.physics} Opens at F_open = {fmt_estimate(F_open, se, 'N')}; above it the throttle force is "
            f"F_r = {fmt_estimate(values['c'] * F_open, errors.get('c', np.nan) * F_open, 'N')} plus r = {fmt_estimate(values['r'], errors.get('r'))} of the further rise."
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
