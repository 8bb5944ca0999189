"""Discovered family: general terms in the measured states, named by what they depend on.

Not look-alikes of any simulator's effects: each is a low-order function of the states a bench
records (charge, position, direction, campaign order) times eq. 14's own forces, so that physics
outside the catalogue that shifts, drifts or bands the force has a term that follows it, and the
report describes it by its dependence instead of borrowing a catalogue name:

- ``charge_offset``: a force proportional to the charge, plus a constant, independent of motion;
- ``charge_drift``: the charge-borne spring force rising with campaign order (a falling one is the
  catalogue's ``leakage``, whose checks decide its name);
- ``damping_drift``: the throttle force changing with campaign order;
- ``friction_map``: friction as a piecewise-linear function of the position (a band of the stroke);
- ``start_pulse``: a force fading over the first moments of each experiment (time within the experiment).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .base import FREE, Effect, Param, fmt_estimate, register

__all__: list[str] = []  # its effects are reached through the registry

#: Place of this module's effects among the candidates (see :mod:`vvea_design.identification.effects`).
RANK = 165

#: Knots of the friction map over the stroke (fractions of travel).
KNOTS = np.linspace(0.0, 1.0, 9)


@dataclass(frozen=True)
class ChargeOffset(Effect):
    def columns(self, D, _, ctx):
        return np.column_stack([D.p2, np.ones(D.n)])

    def describe(self, values, errors, _, __):
        return (
            f"A force proportional to the charge, independent of motion and position: {fmt_estimate(values['a'], errors.get('a'), 'N/MPa')} "
            f"per MPa plus {fmt_estimate(values['b'], errors.get('b'), 'N')} (a load-train or sensor offset that follows the charge, "
            "a pressurised line on the load cell -- not a loss over time)."
        )


@dataclass(frozen=True)
class ChargeDrift(Effect):
    def columns(self, D, _, ctx):
        th = D.ctime / 3600.0
        return np.column_stack([D.p2 * D.x * th, D.p2 * th, D.p2 * D.x * th**2, D.p2 * th**2])

    def describe(self, values, errors, _, __):
        k, k2 = values["k"], values["k2"]
        way = "rises" if k >= 0 else "falls"
        return (
            f"The charge-borne spring force {way} with campaign order: stiffness {fmt_estimate(k, errors.get('k'), 'N/mm/MPa/h')} "
            f"({k2:+.3g} N/mm/MPa/h^2) and offset {fmt_estimate(values['a'], errors.get('a'), 'N/MPa/h')} per hour of campaign "
            f"(the charge {way} over the campaign: temperature of the room or the gas, regulator drift" + (", or a leak" if k < 0 else "") + ")."
        )


@dataclass(frozen=True)
class DampingDrift(Effect):
    def columns(self, D, _, ctx):
        th = D.ctime / 3600.0
        return np.column_stack([ctx["damping_force_N"] * th, ctx["damping_force_N"] * th**2])

    def describe(self, values, errors, _, __):
        return (
            f"The throttle force changes with campaign order: {fmt_estimate(100 * values['d1'], 100 * errors.get('d1', np.nan), '%/h')} "
            f"and {100 * values['d2']:.3g} %/h^2 (oil viscosity changing as it warms, or a valve setting drifting)."
        )


@dataclass(frozen=True)
class FrictionMap(Effect):
    def params(self, D):
        return tuple(Param(f"f{i}", "N", *FREE, f"extra friction at x = {k * D.travel_mm:.3g} mm") for i, k in enumerate(KNOTS))

    def columns(self, D, _, ctx):
        u = np.clip(D.x / D.travel_mm, 0.0, 1.0)
        h = KNOTS[1] - KNOTS[0]
        hats = np.clip(1.0 - np.abs(u[:, None] - KNOTS[None, :]) / h, 0.0, None)
        return D.s[:, None] * hats

    def describe(self, values, errors, _, __):
        f = np.array([values[f"f{i}"] for i in range(len(KNOTS))])
        i = int(np.argmax(np.abs(f)))
        return (
            f"Friction changes along the stroke, in both directions: extra friction from {f.min():.3g} N to {f.max():.3g} N, largest "
            f"({f[i]:.3g} N) at {100 * KNOTS[i]:.0f} % of travel (a band of the bore: a score, a dry patch, a seal load that follows position)."
        )


register(ChargeOffset("charge_offset", "offset following the charge", "A force offset proportional to the charge, whatever the motion.",
                      "f += a p2 + b", (Param("a", "N/MPa", *FREE, "offset per MPa of charge"), Param("b", "N", *FREE, "constant offset")),
                      catalogue=False, log_shape=False))

register(ChargeDrift("charge_drift", "charge drifting with campaign order", "The charge-borne spring force drifts over the campaign.",
                     "f += p2 t_c (k x + a) + p2 t_c^2 (k2 x + a2)   (t_c campaign time in h)",
                     (Param("k", "N/mm/MPa/h", 0.0, np.inf, "stiffness gained per MPa per hour (a falling charge is the catalogue's leakage)"),
                      Param("a", "N/MPa/h", *FREE, "offset change per MPa per hour"),
                      Param("k2", "N/mm/MPa/h^2", -np.inf, 0.0, "slowing of the stiffness gain per hour"),
                      Param("a2", "N/MPa/h^2", *FREE, "change of the offset drift per hour")),
                     catalogue=False, log_shape=False))

register(DampingDrift("damping_drift", "damping drifting with campaign order", "The throttle force drifts over the campaign.",
                      "f += L(gamma) xdot (d1 t_c + d2 t_c^2)   (t_c campaign time in h)",
                      (Param("d1", "1/h", *FREE, "relative damping change per hour"), Param("d2", "1/h^2", *FREE, "its change per hour")),
                      catalogue=False, needs=("damping_force_N",), log_shape=False))

register(FrictionMap("friction_map", "friction varying over bands of the stroke", "Friction follows the position, in both directions.",
                     "f += sign(xdot) sum_i f_i hat_i(x/travel)   (piecewise-linear over 9 knots, 12.5 % of travel apart)", (), catalogue=False, log_shape=False))


@dataclass(frozen=True)
class StartPulse(Effect):
    def grid(self, D, ctx):
        return np.array([0.05, 0.1, 0.2, 0.3, 0.5, 1.0, 2.0])

    def columns(self, D, tau, ctx):
        return np.exp(-D.t / tau)[:, None]

    def describe(self, values, errors, tau, tau_se):
        return (
            f"A force at the start of every experiment, whatever the motion: {fmt_estimate(values['a'], errors.get('a'), 'N')} "
            f"fading with time constant {fmt_estimate(tau, tau_se, 's')} (a force in the first {3 * tau:.2g} s of each experiment: "
            "the load train seating, a clamp settling, a sensor's start-up)."
        )


register(StartPulse("start_pulse", "a force at the start of each experiment", "A force that fades over the first moments of each experiment.",
                    "f += a exp(-t/tau)   (t time within the experiment, s)", (Param("a", "N", *FREE, "force at the start"),),
                    Param("tau", "s", 0.0, np.inf, "time over which it fades"), catalogue=False))
