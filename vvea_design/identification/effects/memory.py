"""Discovered family: relaxing memory -- a first-order lag of the damping force, a relaxing memory of the motion.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from scipy.signal import lfilter

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


def _throttle_per_experiment(D, f: np.ndarray) -> np.ndarray:
    """The throttle coefficient L of each experiment (N s/mm): the median of damping force / velocity where it moves."""
    L = np.zeros(D.n_exp)
    for e in range(D.n_exp):
        a, b = D.bounds[e], D.bounds[e + 1]
        v, fe = D.v[a:b], f[a:b]
        m = np.abs(v) > 1e-9
        if m.any():
            L[e] = float(np.median(fe[m] / v[m]))
    return np.clip(L, 0.0, None)


@dataclass(frozen=True)
class SeriesCompliance(Effect):
    """The throttle in series with a compliance (a Maxwell element): its force builds up with tau = L(gamma)/k.

    One stiffness k for the campaign; the lag of each experiment follows its throttle (the stiffer the valve,
    the longer the lag), which a single time constant (``damping_lag``) cannot follow.
    """

    def grid(self, D, ctx):
        L = _throttle_per_experiment(D, ctx["damping_force_N"])
        top = float(np.max(L)) if len(L) else 0.0
        if not np.isfinite(top) or top <= 0:
            return np.array([])
        return top / np.geomspace(0.003, 3.0, 13)  # the stiffest valve's lag from 3 ms to 3 s

    def columns(self, D, k, ctx):
        f = ctx["damping_force_N"]
        L = _throttle_per_experiment(D, f)
        out = np.zeros(D.n)
        for e in range(D.n_exp):
            a, b = D.bounds[e], D.bounds[e + 1]
            tau = L[e] / k if k > 0 else 0.0
            if tau <= 0 or b - a < 2:
                continue
            dt = float(np.median(np.diff(D.t[a:b])))
            q = np.exp(-dt / tau) if dt > 0 else 0.0
            seg = f[a:b]
            out[a:b] = lfilter([1.0 - q], [1.0, -q], seg, zi=[q * seg[0]])[0] - seg
        return out[:, None]

    def describe(self, values, errors, k, se):
        return (
            f"The throttle force builds up with a lag that grows with the throttle's resistance: a compliance of "
            f"k = {fmt_estimate(k, se, 'N/mm')} in series with the throttle, tau = L(gamma)/k (gain {values['a']:.2f}): "
            "a compressible oil column, trapped gas or a soft hydraulic path between the piston and the valve."
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


register(SeriesCompliance("series_compliance", "throttle in series with a compliance", "The throttle force lags by L(gamma)/k.",
                          "f += a (lowpass_{L(gamma)/k}(L xdot) - L xdot)", (Param("a", "1", 0.0, 1.5, "share of the lag"),),
                          Param("k", "N/mm", 0.0, np.inf, "stiffness in series with the throttle"), catalogue=False, needs=("damping_force_N",)))


register(MotionMemory("motion_memory", "relaxing memory of the motion", "A force proportional to recent motion that relaxes.",
                      "f += k h,  dh/dt = xdot - h/tau", (Param("k", "N/mm", 0.0, np.inf, "relaxing stiffness"),),
                      Param("tau", "s", 0.0, np.inf, "relaxation time constant"), catalogue=False))
