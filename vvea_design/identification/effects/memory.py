"""Discovered family: relaxing memory -- a first-order lag of the damping force, a relaxing memory of the motion.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..signals import lowpass, thermal_state
from .base import Effect, Param, fmt_estimate, register

__all__: list[str] = []  # its effects are reached through the registry

#: Place of this module's effects among the candidates (see :mod:`vvea_design.identification.effects`).
RANK = 120


@dataclass(frozen=True)
class DampingLag(Effect):
    def grid(self, D, ctx):
        return np.geomspace(0.003, 3.0, 13)

    def columns(self, D, tau, ctx):
        f = ctx["damping_force_N"]
        return (lowpass(D, f, tau) - f)[:, None]

    def describe(self, values, errors, tau, se):
        return (
            f"The throttle force builds up with a time constant tau = {fmt_estimate(tau, se, 's')} (gain {values['a']:.2f}): compliance "
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
            f"A force of {fmt_estimate(values['k'], errors.get('k'), 'N/mm')} per mm of recent motion that relaxes with tau = {fmt_estimate(tau, se, 's')}, "
            "independent of the charge pressure: viscoelastic relaxation of elastomer parts (bladder, seals)."
        )


register(DampingLag("damping_lag", "lagging throttle force", "The throttle force builds up with a time constant.",
                    "f += a (lowpass_tau(L xdot) - L xdot)", (Param("a", "1", 0.0, 1.5, "share of a first-order lag of the damping force"),),
                    Param("tau", "s", 0.0, np.inf, "time constant"), catalogue=False, needs=("damping_force_N",)))


register(MotionMemory("motion_memory", "relaxing memory of the motion", "A force proportional to recent motion that relaxes.",
                      "f += k h,  dh/dt = xdot - h/tau", (Param("k", "N/mm", 0.0, np.inf, "relaxing stiffness"),),
                      Param("tau", "s", 0.0, np.inf, "relaxation time constant"), catalogue=False))
