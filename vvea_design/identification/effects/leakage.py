"""Catalogue effect ``leakage``: the charge, and every part of the spring force it carries, decays over campaign time.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..fit_data import cached
from ..dependence import per_charge_share
from .base import Check, Effect, Param, fmt_estimate, register
from .gas_nonlinearity import chamber_remainders

__all__: list[str] = []  # its effects are reached through the registry

#: Place of this module's effects among the candidates (see :mod:`vvea_design.identification.effects`).
RANK = 70


@dataclass(frozen=True)
class Leakage(Effect):
    depends_on = ("charge", "campaign_order", "position")  #: the states its force depends on (names from evidence)

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
        # the name needs the dependence of a leak: a charge that FALLS over campaign time (never rises back), and a
        # force that changes with campaign order, not a constant per charge level
        xm = 0.5 * D.travel_mm
        rate0 = values.get("q0", 0.0) + values.get("q", 0.0) * xm
        rate_end = rate0 - 2.0 * th * (values.get("c0", 0.0) + values.get("c", 0.0) * xm)
        falls = bool(rate0 > 0 and rate_end >= -0.1 * rate0)
        share = per_charge_share(D, contribution) if D.n else 0.0
        return [
            Check("grows over the campaign", drift > 0, f"RMS of the leak force in the last fifth of the campaign minus the first fifth: {drift:.3g} N (> 0; campaign {th:.2g} h)"),
            Check("the charge falls throughout the campaign", falls,
                  f"loss rate at mid-stroke {rate0:.3g} N/MPa/h at the start and {rate_end:.3g} N/MPa/h at the end of the campaign "
                  "(a leak never gives the charge back: the end rate must not be below -0.1 x the start rate)"),
            Check("changes with campaign order, not with the charge alone", share < 0.8,
                  f"a constant per charge level explains {100 * share:.0f} % of its force (< 80 %: otherwise it is an offset that "
                  "follows the charge, not a loss over time)"),
        ]

    def describe(self, values, errors, _, __):
        return (
            f"{self.physics} Preload loss {fmt_estimate(values['q0'], errors.get('q0'), 'N/MPa/h')}, stiffness loss "
            f"{fmt_estimate(values['q'], errors.get('q'), 'N/mm/MPa/h')}, curvature loss q2 = {fmt_estimate(values['q2'], errors.get('q2'), '1/h')} (chamber 2), "
            f"q1 = {fmt_estimate(values['q1'], errors.get('q1'), '1/h')} (chamber 1); the loss slows by {values['c0']:.3g} N/MPa/h^2 "
            f"(preload) and {values['c']:.3g} N/mm/MPa/h^2 (stiffness)."
        )

    bench_strength: str = "rate_per_h"
    bench_linear: bool = False

    def bench_random(self, rng, spec):
        return dict(rate_per_h=1.0)

    def bench_force(self, P, cols, spec):
        return spec.g_N_per_mm_MPa * cols["p2"] * cols["x"] * (np.exp(-P["rate_per_h"] * cols["ctime_h"]) - 1.0)


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
