"""Discovered family: hysteresis with memory of the motion -- pre-sliding (stop operator and bristle approach).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..signals import first_ramp, stop_operator, travel_since_reversal
from .base import Effect, Param, fmt_estimate, register

__all__: list[str] = []  # its effects are reached through the registry

#: Place of this module's effects among the candidates (see :mod:`vvea_design.identification.effects`).
RANK = 130


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
        e = np.exp(-travel_since_reversal(D) / r)
        first = first_ramp(D)
        ex = -D.s * e
        return np.column_stack([z / r - D.s, D.p2 * (z / r - D.s), ex * first, ex * ~first, D.p2 * ex * ~first, -D.v * e])

    def describe(self, values, errors, r, se):
        F = values["F_h"] + values["F_e"]
        return (
            f"Hysteresis with memory of the motion: after each start or reversal the force needs about {fmt_estimate(r, se, 'mm')} of travel to reach "
            f"its sliding level (loop width {2 * F:.3g} N + {2 * (values['F_hp'] + values['F_ep']):.3g} N per MPa across the loop; "
            f"deficit {values['F_s']:.3g} N after a start from rest): pre-sliding "
            "(elastic seal/bladder deformation before gross sliding), not a speed effect."
        )


register(PreSliding("presliding_hysteresis", "pre-sliding hysteresis (stop operator)", "Friction builds up over a travel after reversal.",
                    "f += (F_h + F_hp p2) (stop_r(x)/r - sign(xdot)) - (F_s 1{first ramp} + (F_e + F_ep p2) 1{after reversal}) sign(xdot) exp(-d/r) "
                    "- b xdot exp(-d/r)   (d: travel since the start or last reversal)",
                    (Param("F_h", "N", 0.0, np.inf, "friction deficit right after reversal (elastic-plastic)"), Param("F_hp", "N/MPa", 0.0, np.inf, "its growth per MPa"),
                     Param("F_s", "N", 0.0, np.inf, "friction deficit at the start from rest (exponential approach)"),
                     Param("F_e", "N", 0.0, np.inf, "friction deficit right after reversal (exponential approach)"), Param("F_ep", "N/MPa", 0.0, np.inf, "its growth per MPa"),
                     Param("b", "N s/mm", -np.inf, np.inf, "damping of the pre-sliding deformation (bristle damping)")),
                    Param("r", "mm", 0.0, np.inf, "pre-sliding travel (half loop width in x)"), catalogue=False))
