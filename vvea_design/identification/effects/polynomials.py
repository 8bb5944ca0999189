"""Discovered family: state polynomials -- direction-dependent stiffness, spring curvature beyond the gas law,
pressure-dependent damping, friction along the stroke.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .base import FREE, Effect, Param, fmt_estimate, register

__all__: list[str] = []  # its effects are reached through the registry

#: Place of this module's effects among the candidates (see :mod:`vvea_design.identification.effects`).
RANK = 150


@dataclass(frozen=True)
class DirectionStiffness(Effect):
    def columns(self, D, _, ctx):
        up = D.s > 0
        return np.column_stack([D.x * up, D.x * ~up, D.p2 * D.x * D.s])

    def describe(self, values, errors, _, __):
        ke, kr, dk = values["k_ext"], values["k_ret"], values["dk_p"]
        se = float(np.hypot(errors.get("k_ext", np.nan), errors.get("k_ret", np.nan)))
        same = abs(ke - kr) <= max(0.1 * max(abs(ke), abs(kr)), 2.0 * se if np.isfinite(se) else 0.0) and abs(dk) * 4.0 < 0.1 * max(abs(ke), abs(kr), 1e-12)
        if same:  # fitted with direction columns, but it does not depend on the direction: say what it depends on
            return (
                f"An extra stiffness, the same in both directions and at every charge: {fmt_estimate(ke, errors.get('k_ext'), 'N/mm')} extending, "
                f"{fmt_estimate(kr, errors.get('k_ret'), 'N/mm')} retracting: a spring in parallel with the gas (bladder, end stop, load "
                "train) or a stiffness the gas law misses -- not a direction-dependent effect."
            )
        return (
            f"The stiffness differs between extension and retraction: {fmt_estimate(values['k_ext'], errors.get('k_ext'), 'N/mm')} extra while "
            f"extending, {fmt_estimate(values['k_ret'], errors.get('k_ret'), 'N/mm')} while retracting (+ {fmt_estimate(values['dk_p'], errors.get('dk_p'), 'N/mm/MPa')} "
            "p2 x sign(xdot)): a spring that engages in one direction only (one-sided contact, a check valve, friction "
            "growing with load) -- not a gas law, not plain friction."
        )


@dataclass(frozen=True)
class SpringPolynomial(Effect):
    """A spring curvature the same at every charge (outside the gas chambers).

    The charge-proportional curvature is not bundled here: it is the gas law's own family, which
    ``gas_nonlinearity`` fits with the unit's geometry and ``charge_curvature`` with a free polynomial
    (a bundle of both would out-score, and so out-name, the catalogue effect whenever a second spring is there).
    """

    def columns(self, D, _, ctx):
        u = D.x / D.travel_mm
        return np.column_stack([u**2 - u, u**3 - u])

    def describe(self, values, errors, _, __):
        return (
            "The force-displacement curve bends the same way at every charge, which no gas law does: a polynomial in x "
            f"({values['b2']:.3g} N u^2 {values['b3']:+.3g} N u^3, u = x/travel): a spring element outside the gas chambers "
            "(bladder, end stop, load train)."
        )


@dataclass(frozen=True)
class ChargeCurvature(Effect):
    """A spring curvature proportional to the charge, as a free polynomial (the general alternative to the gas law's form)."""

    def columns(self, D, _, ctx):
        u = D.x / D.travel_mm
        return np.column_stack([D.p2 * (u**2 - u), D.p2 * (u**3 - u)])

    def describe(self, values, errors, _, __):
        return (
            "The force-displacement curve bends in proportion to the charge, in a shape the unit's gas law does not follow "
            f"(per MPa: {values['b2p']:.3g} N u^2 {values['b3p']:+.3g} N u^3, u = x/travel): chambers of another geometry "
            "than the design's, or a gas that departs from the polytropic law."
        )


@dataclass(frozen=True)
class PressureDamping(Effect):
    def columns(self, D, _, ctx):
        return (ctx["damping_force_N"] * (D.p2 - np.mean(D.p2)))[:, None]

    def describe(self, values, errors, _, __):
        return f"The throttle force changes by {fmt_estimate(100 * values['c'], 100 * errors.get('c', np.nan), '%')} per MPa of charge: fluid properties or valve behaviour that depend on pressure."


@dataclass(frozen=True)
class FrictionAlongStroke(Effect):
    def columns(self, D, _, ctx):
        u = D.x / D.travel_mm
        return np.column_stack([D.s * u, D.s * u**2])

    def describe(self, values, errors, _, __):
        return (
            f"Friction changes along the stroke by {values['c1'] + values['c2']:.3g} N from x = 0 to full travel: a tapered or "
            "misaligned bore, or seal load growing with the stroke."
        )


register(DirectionStiffness("direction_stiffness", "direction-dependent stiffness", "The stiffness differs between the two directions.",
                            "f += k_ext x 1{xdot > 0} + k_ret x 1{xdot < 0} + dk_p p2 x sign(xdot)",
                            (Param("k_ext", "N/mm", *FREE, "extra stiffness while extending"), Param("k_ret", "N/mm", *FREE, "extra stiffness while retracting"),
                             Param("dk_p", "N/mm/MPa", *FREE, "direction-dependent stiffness per MPa")),
                            catalogue=False))


register(SpringPolynomial("spring_polynomial", "non-gas spring curvature", "The spring curve bends beyond the gas law, the same at every charge.",
                          "f += b2 (u^2-u) + b3 (u^3-u),  u = x/travel",
                          (Param("b2", "N", *FREE), Param("b3", "N", *FREE)),
                          catalogue=False))


register(ChargeCurvature("charge_curvature", "charge-proportional spring curvature", "The spring curve bends with the charge, not as the gas law says.",
                         "f += p2 (b2p (u^2-u) + b3p (u^3-u)),  u = x/travel",
                         (Param("b2p", "N/MPa", *FREE), Param("b3p", "N/MPa", *FREE)),
                         catalogue=False))


register(PressureDamping("pressure_damping", "pressure-dependent damping", "The throttle force depends on the charge.",
                         "f += c (p2 - mean p2) L(gamma) xdot", (Param("c", "1/MPa", *FREE, "relative change of damping per MPa"),),
                         catalogue=False, needs=("damping_force_N",)))


register(FrictionAlongStroke("friction_along_stroke", "friction varying along the stroke", "Friction changes with x.",
                             "f += sign(xdot) (c1 u + c2 u^2),  u = x/travel",
                             (Param("c1", "N", *FREE), Param("c2", "N", *FREE)), catalogue=False))
