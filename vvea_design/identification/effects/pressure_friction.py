"""Catalogue effect ``pressure_friction``: seal friction that grows with the charge, ``c_p p2 sign(ẋ)``.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .base import Check, Effect, Param, fmt_estimate, register

__all__: list[str] = []  # its effects are reached through the registry

#: Place of this module's effects among the candidates (see :mod:`vvea_design.identification.effects`).
RANK = 60


@dataclass(frozen=True)
class PressureFriction(Effect):
    depends_on = ("charge", "direction")  #: the states its force depends on (names from evidence)

    def columns(self, D, _, ctx):
        return (D.p2 * D.s)[:, None]

    def signature(self, D, values, _, contribution):
        ps = np.unique(D.p2)
        return [Check("several charge pressures", len(ps) >= 2, f"{len(ps)} pressure preset(s) in the campaign (needs >= 2 to tell pressure from Coulomb friction)")]

    def describe(self, values, errors, _, __):
        return f"{self.physics} c_p = {fmt_estimate(values['c_p'], errors.get('c_p'), 'N/MPa')}."

    bench_strength: str = "c_p_N_per_MPa"

    def bench_random(self, rng, spec):
        return dict(c_p_N_per_MPa=1.0)

    def bench_force(self, P, cols, spec):
        return P["c_p_N_per_MPa"] * cols["p2"] * np.sign(cols["v"])


register(PressureFriction(
    "pressure_friction",
    "pressure-loaded seal friction",
    "Seal lips are pressed onto the rod by the gas charge, so seal friction grows in proportion to p2.",
    "f += c_p p2 sign(xdot)",
    (Param("c_p", "N/MPa", 0.0, np.inf, "seal friction per MPa of charge"),),
))
