"""Catalogue effect ``gas_nonlinearity``: the antagonistic gas spring of the paper's eq. 5.

Eq. 14's straight spring ``g p2 x`` against the two chambers of the unit's own
geometry: each chamber's force minus its straight line
(:func:`chamber_remainders`), the chamber-2 volume free (an effective,
polytropic volume).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ...spring import gas_spring
from ...spring.gas_spring import GasSpring
from ...spring.paper import PAPER_FIG5
from .base import Check, Effect, Param, fmt_estimate, register

__all__ = ["chamber_remainders"]

#: Place of this module's effects among the candidates (see :mod:`vvea_design.identification.effects`).
RANK = 10


def _remainder(f, travel_mm: float):
    xx = np.linspace(0.0, travel_mm, 401)
    f0 = float(f(np.array(0.0)))
    k = float(((f(xx) - f0) * xx).sum() / (xx * xx).sum())
    return lambda z: f(z) - f0 - k * z


def chamber_remainders(x: np.ndarray, V2_mm3: float, reference: GasSpring = PAPER_FIG5):
    """Nonlinear parts (N per MPa of p2) of the two chamber forces of eq. 5 for the unit ``reference``.

    Returns ``(r2, r1)``: chamber 2 ``A2 V2/(V2 - A2 x)`` (progressive) and
    chamber 1 ``-(p1/p2) A1 V1/(V1 + A1 x)`` (regressive; p1/p2 of the
    design, A2/A1 for eq. 7's zero force at x = 0), each minus its value at
    x = 0 and its least-squares line through the origin over the unit's travel.

    Parameters
    ----------
    x : numpy.ndarray
        Displacement, mm (x > 0 extends the spring).
    V2_mm3 : float
        Chamber-2 volume at x = 0, mm³ (an effective, polytropic volume when fitted).
    reference : GasSpring
        The unit whose chamber areas (mm²), V1 (mm³), pressures (MPa) and
        travel (mm) are used; default the paper's Fig. 5 unit.

    Returns
    -------
    r2, r1 : numpy.ndarray
        Nonlinear remainders of the chamber-2 and chamber-1 forces at ``x``,
        N per MPa of p2 (mm²).
    """
    A1, A2, V1 = reference.A1_mm2, reference.A2_mm2, reference.V1_mm3
    ratio = reference.p1_MPa / reference.p2_MPa if reference.p2_MPa > 0 else A2 / A1
    travel = reference.travel_mm
    xmax = 0.999 * V2_mm3 / A2
    r2 = _remainder(lambda z: A2 * V2_mm3 / (V2_mm3 - A2 * np.clip(z, None, xmax)), travel)(np.clip(x, None, xmax))
    r1 = _remainder(lambda z: -ratio * A1 * V1 / (V1 + A1 * np.clip(z, -0.999 * V1 / A1, None)), travel)(x)
    return r2, r1


@dataclass(frozen=True)
class GasNonlinearity(Effect):
    depends_on = ("position", "charge")  #: the states its force depends on (names from evidence)

    def grid(self, D, ctx):
        # effective chamber-2 volume: from just above the swept volume to 10 x it
        A2, travel = D.reference.A2_mm2, D.travel_mm
        return A2 * travel * np.geomspace(1.08, 10.0, 14)

    def columns(self, D, V2, ctx):
        c2, c1 = chamber_remainders(D.x, V2, D.reference)
        return np.column_stack([D.p2 * c2, D.p2 * c1])

    def signature(self, D, values, V2, contribution):
        ref = D.reference
        ratio = V2 / ref.V2_mm3
        swept = ref.A2_mm2 * D.travel_mm
        return [
            Check("progressive", values.get("a2", 0.0) > 0.0, f"chamber-2 amplitude a2 = {values.get('a2', 0.0):.3g} (> 0: the compressed chamber stiffens)"),
            Check(
                "chamber volume near the design",
                0.25 <= ratio <= 4.0,
                f"effective V2 = {V2:.3g} mm^3 = {ratio:.2f} x the design's {ref.V2_mm3:.3g} mm^3 (must lie within 0.25..4 x)",
            ),
            Check(
                "a compression a gas spring survives",
                V2 >= 1.25 * swept,
                f"compression ratio at full travel V2/(V2 - A2 travel) = {V2 / max(V2 - swept, 1e-9):.2g} (<= 5: the chamber does not bottom out)",
            ),
        ]

    def describe(self, values, errors, V2, V2_se):
        return (
            f"{self.physics} Effective chamber-2 volume V2 = {fmt_estimate(V2, V2_se, 'mm^3')}, chamber amplitudes "
            f"a2 = {fmt_estimate(values['a2'], errors.get('a2'))}, a1 = {fmt_estimate(values['a1'], errors.get('a1'))} (1 = the unit's areas)."
        )

    bench_strength: str = "amp"

    def bench_random(self, rng, spec):
        A2 = spec.reference.A2_mm2
        return dict(V1_mm3=float(rng.uniform(0.8e5, 3e5)), V2_mm3=float(A2 * spec.travel_mm * rng.uniform(1.4, 4.0)), amp=1.0)

    def bench_force(self, P, cols, spec):
        ref = spec.reference
        A1, A2 = ref.A1_mm2, ref.A2_mm2
        F = lambda z: gas_spring.force_N(z, A1, A2, P["V1_mm3"], P["V2_mm3"], A2 / A1, 1.0)  # noqa: E731
        xx = np.linspace(0, spec.travel_mm, 401)
        k = float((F(xx) * xx).sum() / (xx * xx).sum())
        return P["amp"] * cols["p2"] * (F(cols["x"]) - k * cols["x"])


register(GasNonlinearity(
    "gas_nonlinearity",
    "antagonistic gas spring (eq. 5)",
    "The two gas chambers follow the gas law of paper eq. 5 with the unit's own areas and volumes: the compressed "
    "chamber stiffens as its volume shrinks, so the spring is progressive, not the straight line g p2 x.",
    "f += p2 (a2 r2(x; V2) + a1 r1(x)),  r2 = A2 V2/(V2 - A2 x) - line,  r1 = -(p1/p2) A1 V1/(V1 + A1 x) - line "
    "(eq. 5 per MPa of p2 with the design's A1, A2, V1 and travel; each chamber minus its straight line)",
    (
        Param("a2", "1", 0.0, 5.0, "chamber-2 (compressed, progressive) amplitude; 1 = the unit's area A2"),
        Param("a1", "1", 0.0, 5.0, "chamber-1 (expanding, regressive) amplitude; 1 = the unit's V1, A1"),
    ),
    Param("V2", "mm^3", 0.0, np.inf, "effective chamber-2 gas volume at x = 0 (isothermal: the real one; polytropic: smaller)"),
))
