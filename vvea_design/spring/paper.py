"""The paper's gas-spring figures (section 3.2, Figs 3–5) as data.

The paper prints V1 = 1.22e5 mm³, V2 = 7.34e4 mm³, a 30 mm piston, a 59.5 mm
housing and "1.86 % (33.98 N at 1827 N)". Its numbers do not pin down the
chamber areas: with A1 = A2 = the 30 mm piston the curve deviates 6.3 %. The
interpretation adopted here (``docs/paper-interpretation.md``): chamber 2
acts through the fluid on the 30 mm working piston and chamber 1 on the bore
of the 59.5 mm outer tube (1.2 mm wall, 57.1 mm bore) — "only the overall
outer diameter had to be hand optimized to obtain good linearity". That is
:data:`~vvea_design.spring.gas_spring.PAPER_FIG5`; it gives 1.85–1.87 % (depending on
how finely the stroke is sampled) and F(40 mm) = 1827 N at p2 = 2.387 MPa.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .gas_spring import PAPER_FIG5, GasSpring, linearity_error, mean_stiffness_N_per_mm
from .records import Record

__all__ = ["PAPER_FIG5", "PAPER_LINEARITY", "fig3_setpoints", "fig4_pressures", "fig5_volumes",
           "reference_summary", "ReferenceSummary", "equal_area_variant"]

#: What the paper prints for Fig. 5's V2 = 7.34e4 mm³ curve.
PAPER_LINEARITY = {"linearity_error": 0.0186, "deviation_N": 33.98, "max_force_N": 1827.0}


def _curve_rows(label: str, value: float, spring: GasSpring, x: np.ndarray) -> list[dict]:
    F = spring.force_N(x)
    return [{"series": label, "value": value, "x_mm": float(xi), "force_N": float(fi)} for xi, fi in zip(x, F)]


def fig3_setpoints(x0_values_mm=(-5.0, 0.0, 5.0), base: GasSpring = PAPER_FIG5, num: int = 91):
    """Fig. 3: p1 from eq. 6 moves the zero crossing (setpoint) within ±5 mm.

    Each spring keeps the reference geometry and p2 and takes p1 from eq. 6 so that
    F(x0) = 0.

    Parameters
    ----------
    x0_values_mm : sequence of float
        Set points, the displacements where the force is to be zero.
    base : GasSpring
        Reference spring (geometry mm² / mm³, charge MPa, travel mm); default the paper's Fig. 5
        configuration :data:`PAPER_FIG5`.
    num : int
        Samples per curve over x from -5 mm to the travel.

    Returns
    -------
    springs : dict of float to GasSpring
        One recharged spring per set point (key: x0, mm).
    rows : list of dict
        Tidy curve rows, one per sample and spring: ``series`` (the swept quantity's name with its
        unit), ``value`` (its value), ``x_mm`` (displacement) and ``force_N`` (force, tension > 0).
    """
    x = np.linspace(-5.0, base.travel_mm, num)
    springs = {float(x0): base.with_pressures(base.p2_MPa, x0_mm=float(x0)) for x0 in x0_values_mm}
    rows = [r for x0, s in springs.items() for r in _curve_rows("x0_mm", x0, s, x)]
    return springs, rows


def fig4_pressures(p2_values_MPa=(1.0, 2.0, 3.0, 4.0), base: GasSpring = PAPER_FIG5, num: int = 81):
    """Fig. 4: raising p2 at a fixed p1/p2 ratio scales the whole curve (stiffness ∝ p2).

    Parameters
    ----------
    p2_values_MPa : sequence of float
        Chamber-2 charges to draw; p1 keeps the reference's ratio p1/p2.
    base : GasSpring
        Reference spring (geometry mm² / mm³, charge MPa, travel mm); default the paper's Fig. 5
        configuration :data:`PAPER_FIG5`.
    num : int
        Samples per curve over x from 0 to the travel.

    Returns
    -------
    springs : dict of float to GasSpring
        One spring per charge (key: p2, MPa).
    rows : list of dict
        Tidy curve rows, one per sample and spring: ``series`` (the swept quantity's name with its
        unit), ``value`` (its value), ``x_mm`` (displacement) and ``force_N`` (force, tension > 0).
    """
    x = base.x_mm(num)
    ratio = base.p1_MPa / base.p2_MPa
    springs = {float(p2): GasSpring(base.A1_mm2, base.A2_mm2, base.V1_mm3, base.V2_mm3, ratio * p2, p2,
                                    base.travel_mm, base.n_polytropic) for p2 in p2_values_MPa}
    rows = [r for p2, s in springs.items() for r in _curve_rows("p2_MPa", p2, s, x)]
    return springs, rows


def fig5_volumes(V2_values_mm3=(4.5e4, 5.5e4, 7.34e4, 9.0e4, 1.1e5), base: GasSpring = PAPER_FIG5, num: int = 81):
    """Fig. 5: smaller V2 makes the curve progressive; 7.34e4 mm³ is the near-linear setting.

    Each curve keeps F(0) = 0 (p1 from eq. 7) and the charge of the reference.

    Parameters
    ----------
    V2_values_mm3 : sequence of float
        Chamber-2 gas volumes at x = 0 to draw.
    base : GasSpring
        Reference spring (geometry mm² / mm³, charge MPa, travel mm); default the paper's Fig. 5
        configuration :data:`PAPER_FIG5`.
    num : int
        Samples per curve over x from 0 to the travel.

    Returns
    -------
    springs : dict of float to GasSpring
        One spring per volume (key: V2, mm³).
    rows : list of dict
        Tidy curve rows, one per sample and spring: ``series`` (the swept quantity's name with its
        unit), ``value`` (its value), ``x_mm`` (displacement) and ``force_N`` (force, tension > 0).
    """
    x = base.x_mm(num)
    springs = {}
    for V2 in V2_values_mm3:
        s = GasSpring(base.A1_mm2, base.A2_mm2, base.V1_mm3, float(V2), base.p1_MPa, base.p2_MPa,
                      base.travel_mm, base.n_polytropic).with_pressures(base.p2_MPa)
        springs[float(V2)] = s
    rows = [r for V2, s in springs.items() for r in _curve_rows("V2_mm3", V2, s, x)]
    return springs, rows


@dataclass(frozen=True)
class ReferenceSummary(Record):
    """A spring's linearity, deviation and force span next to the paper's printed numbers."""

    linearity_error: float  #: fraction
    deviation_N: float  #: largest deviation from the least-squares line
    max_force_N: float
    mean_stiffness_N_per_mm: float
    stiffness_per_MPa_N_per_mm_per_MPa: float  #: mean stiffness per MPa of p2
    samples: str | int  #: "exact (continuous)" or the number of samples
    paper: dict  #: the paper's printed numbers (:data:`PAPER_LINEARITY`)


def reference_summary(spring: GasSpring = PAPER_FIG5, num: int | None = None) -> ReferenceSummary:
    """Linearity, deviation and force span of a spring next to the paper's printed numbers.

    Parameters
    ----------
    spring : GasSpring
        The spring to measure (mm², mm³, MPa, travel mm); default the paper's Fig. 5 reference.
    num : int or None
        None (default): the exact metric over the continuous travel; an int: the metric on that
        many equally spaced samples (to compare with sampled data).

    Returns
    -------
    ReferenceSummary
        ``linearity_error`` (fraction), ``deviation_N`` (largest deviation from the least-squares
        line, N), ``max_force_N`` (N), ``mean_stiffness_N_per_mm`` (N/mm),
        ``stiffness_per_MPa_N_per_mm_per_MPa`` (mean stiffness per MPa of p2), ``samples`` (the
        sampling used) and ``paper`` (the paper's printed numbers, :data:`PAPER_LINEARITY`).
    """
    if num is None:
        r = spring.linearity()
        lin, span, k = float(r.linearity_error), float(r.force_span_N), float(r.mean_stiffness_N_per_mm)
        fmax = float(max(spring.force_N(0.0), spring.force_N(spring.travel_mm)))
    else:
        x = spring.x_mm(num)
        F = spring.force_N(x)
        lin, span, k = float(linearity_error(x, F)), float(F.max() - F.min()), float(mean_stiffness_N_per_mm(x, F))
        fmax = float(F.max())
    return ReferenceSummary(lin, lin * span, fmax, k, k / spring.p2_MPa, "exact (continuous)" if num is None else num,
                            dict(PAPER_LINEARITY))


def equal_area_variant(base: GasSpring = PAPER_FIG5) -> GasSpring:
    """The reading the paper's numbers rule out: A1 = A2 = the 30 mm piston (≈ 6.3 %).

    Parameters
    ----------
    base : GasSpring
        Spring whose chamber-2 area, volumes, p2 and travel are kept; default :data:`PAPER_FIG5`.

    Returns
    -------
    GasSpring
        Both chambers on ``base``'s chamber-2 area (mm²), both charged to its p2 (MPa), so F(0) = 0.
    """
    return GasSpring(base.A2_mm2, base.A2_mm2, base.V1_mm3, base.V2_mm3, base.p2_MPa, base.p2_MPa,
                     base.travel_mm, base.n_polytropic)
