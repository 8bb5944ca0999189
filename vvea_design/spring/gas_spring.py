"""Antagonistic gas spring: paper eqs 3-7, generalised to a polytropic law.

Two gas chambers act on one piston. Chamber 2 (area ``A2``, volume ``V2``,
charge ``p2``) is compressed as the displacement ``x`` grows; chamber 1
(``A1``, ``V1``, ``p1``) expands::

    F(x) = A2 p2 (V2 / (V2 - A2 x))**n  -  A1 p1 (V1 / (V1 + A1 x))**n

Units: mm, mm², mm³, MPa (= N/mm²), N. ``x > 0`` extends the pull spring and
compresses chamber 2; ``F > 0`` is tension. ``n = 1`` is the paper's
isothermal law, ``n = 1.4`` adiabatic air.

Every function broadcasts with numpy: pass ``x`` as shape ``(m,)`` and the
parameters as shape ``(k, 1)`` to evaluate ``k`` designs at once.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike

from ..messages import show

__all__ = [
    "ChamberBottomedOut",
    "GasSpring",
    "force_N",
    "chamber_pressures_MPa",
    "local_stiffness_N_per_mm",
    "setpoint_p1_MPa",
    "linearity_error",
    "least_squares_line",
    "mean_stiffness_N_per_mm",
    "PAPER_FIG5",
]


class ChamberBottomedOut(ValueError):
    """Raised when a chamber's gas volume would reach zero inside the stroke."""


def _check_volumes(x, A1, A2, V1, V2) -> None:
    x = np.asarray(x, dtype=float)
    v2 = np.asarray(V2, dtype=float) - np.asarray(A2, dtype=float) * x
    v1 = np.asarray(V1, dtype=float) + np.asarray(A1, dtype=float) * x
    if np.any(v2 <= 0):
        xmax = float(np.min(np.asarray(V2, float) / np.asarray(A2, float)))
        raise ChamberBottomedOut(
            f"chamber 2 bottoms out: V2 - A2*x <= 0 for x up to {float(np.max(x)):.4g} mm "
            f"(chamber 2 is empty at x = V2/A2 = {xmax:.4g} mm)"
        )
    if np.any(v1 <= 0):
        xmin = float(np.max(-np.asarray(V1, float) / np.asarray(A1, float)))
        raise ChamberBottomedOut(
            f"chamber 1 bottoms out: V1 + A1*x <= 0 for x down to {float(np.min(x)):.4g} mm "
            f"(chamber 1 is empty at x = -V1/A1 = {xmin:.4g} mm)"
        )


def chamber_pressures_MPa(x: ArrayLike, A1, A2, V1, V2, p1, p2, n: float = 1.0):
    """Absolute-law chamber pressures ``(P1, P2)`` in MPa at displacement ``x`` (mm).

    Raises
    ------
    ChamberBottomedOut
        If a chamber volume is non-positive anywhere in ``x``.
    """
    _check_volumes(x, A1, A2, V1, V2)
    x = np.asarray(x, dtype=float)
    P2 = p2 * (V2 / (V2 - A2 * x)) ** n
    P1 = p1 * (V1 / (V1 + A1 * x)) ** n
    return P1, P2


def force_N(x: ArrayLike, A1, A2, V1, V2, p1, p2, n: float = 1.0) -> np.ndarray:
    """Spring force F(x) in N (paper eq. 5; polytropic exponent ``n``)."""
    P1, P2 = chamber_pressures_MPa(x, A1, A2, V1, V2, p1, p2, n)
    return A2 * P2 - A1 * P1


def local_stiffness_N_per_mm(x: ArrayLike, A1, A2, V1, V2, p1, p2, n: float = 1.0) -> np.ndarray:
    """Analytical dF/dx in N/mm."""
    P1, P2 = chamber_pressures_MPa(x, A1, A2, V1, V2, p1, p2, n)
    x = np.asarray(x, dtype=float)
    return n * A2**2 * P2 / (V2 - A2 * x) + n * A1**2 * P1 / (V1 + A1 * x)


def setpoint_p1_MPa(p2, A1, A2, V1, V2, x0: float = 0.0, n: float = 1.0):
    """Charge pressure p1 that puts the zero-force point at ``x0`` (paper eqs 6/7).

    With ``x0 = 0`` this is ``p1 = A2/A1 * p2`` (eq. 7).
    """
    _check_volumes(x0, A1, A2, V1, V2)
    return (A2 / A1) * p2 * (V2 / (V2 - A2 * x0)) ** n * ((V1 + A1 * x0) / V1) ** n


def least_squares_line(x: ArrayLike, F: ArrayLike):
    """Slope and intercept of the least-squares line of ``F`` over ``x`` (last axis)."""
    x = np.asarray(x, dtype=float)
    F = np.asarray(F, dtype=float)
    xm = x.mean()
    dx = x - xm
    slope = ((F - F.mean(axis=-1, keepdims=True)) * dx).sum(axis=-1) / (dx * dx).sum()
    intercept = F.mean(axis=-1) - slope * xm
    return slope, intercept


def linearity_error(x: ArrayLike, F: ArrayLike) -> np.ndarray:
    """The project's one linearity metric (a fraction).

    Largest deviation of ``F`` from its least-squares line over ``x``,
    divided by the force span ``max F - min F`` over ``x``. Works along the
    last axis, so ``F`` may hold many curves.
    """
    x = np.asarray(x, dtype=float)
    F = np.asarray(F, dtype=float)
    slope, intercept = least_squares_line(x, F)
    fit = slope[..., None] * x + np.asarray(intercept)[..., None]
    dev = np.abs(F - fit).max(axis=-1)
    span = F.max(axis=-1) - F.min(axis=-1)
    return dev / span


def mean_stiffness_N_per_mm(x: ArrayLike, F: ArrayLike) -> np.ndarray:
    """Mean stiffness: the least-squares slope of ``F`` over ``x`` (N/mm)."""
    return least_squares_line(x, F)[0]


@dataclass(frozen=True)
class GasSpring:
    """The spring's physics parameters (what the design JSON's ``parameters`` hold).

    Attributes are in mm, mm², mm³, MPa.
    """

    A1_mm2: float  #: effective area of chamber 1 (expands with x)
    A2_mm2: float  #: effective area of chamber 2 (compressed with x)
    V1_mm3: float  #: chamber-1 gas volume at x = 0
    V2_mm3: float  #: chamber-2 gas volume at x = 0
    p1_MPa: float  #: chamber-1 charge pressure (at x = 0)
    p2_MPa: float  #: chamber-2 charge pressure (at x = 0)
    travel_mm: float = 40.0  #: stroke, x from 0 to travel
    n_polytropic: float = 1.0  #: 1 isothermal ... 1.4 adiabatic

    def __post_init__(self) -> None:
        for name in ("A1_mm2", "A2_mm2", "V1_mm3", "V2_mm3", "travel_mm"):
            v = getattr(self, name)
            if not np.isfinite(v) or v <= 0:
                raise ValueError(f"GasSpring.{name} must be a positive number, got {show(v)}")
        for name in ("p1_MPa", "p2_MPa"):
            v = getattr(self, name)
            if not np.isfinite(v) or v < 0:
                raise ValueError(f"GasSpring.{name} must be >= 0, got {show(v)}")
        if not 1.0 <= self.n_polytropic <= 1.4:
            raise ValueError(f"GasSpring.n_polytropic must be in [1, 1.4], got {show(self.n_polytropic)}")
        _check_volumes(self.travel_mm, self.A1_mm2, self.A2_mm2, self.V1_mm3, self.V2_mm3)

    # -- convenience -----------------------------------------------------
    def _args(self):
        return (self.A1_mm2, self.A2_mm2, self.V1_mm3, self.V2_mm3, self.p1_MPa, self.p2_MPa, self.n_polytropic)

    def x_mm(self, num: int = 401) -> np.ndarray:
        """Displacement grid over the travel."""
        return np.linspace(0.0, self.travel_mm, num)

    def force_N(self, x: ArrayLike) -> np.ndarray:
        return force_N(x, *self._args())

    def stiffness_N_per_mm(self, x: ArrayLike) -> np.ndarray:
        return local_stiffness_N_per_mm(x, *self._args())

    def pressures_MPa(self, x: ArrayLike):
        return chamber_pressures_MPa(x, *self._args())

    def with_pressures(self, p2_MPa: float, x0_mm: float = 0.0) -> "GasSpring":
        """Same geometry charged to ``p2`` with p1 from eq. 6 (zero force at ``x0``)."""
        p1 = float(setpoint_p1_MPa(p2_MPa, self.A1_mm2, self.A2_mm2, self.V1_mm3, self.V2_mm3, x0_mm, self.n_polytropic))
        return GasSpring(self.A1_mm2, self.A2_mm2, self.V1_mm3, self.V2_mm3, p1, p2_MPa, self.travel_mm, self.n_polytropic)

    def linearity_error(self, num: int = 401) -> float:
        x = self.x_mm(num)
        return float(linearity_error(x, self.force_N(x)))

    def mean_stiffness_N_per_mm(self, num: int = 401) -> float:
        x = self.x_mm(num)
        return float(mean_stiffness_N_per_mm(x, self.force_N(x)))

    def peak_pressure_MPa(self) -> float:
        """Highest chamber pressure over the stroke (chamber 2 at full travel or p1 at x=0)."""
        P1, P2 = self.pressures_MPa(np.array([0.0, self.travel_mm]))
        return float(max(P1.max(), P2.max()))


#: Paper Fig. 5 reference (see docs/paper-interpretation.md): chamber 2 acts
#: through the fluid on the 30 mm working piston, chamber 1 on the bore of the
#: 59.5 mm outer tube with a 1.2 mm wall (57.1 mm); V1 = 1.22e5 mm³,
#: V2 = 7.34e4 mm³, F(0) = 0. The charge p2 = 2.3866 MPa makes F(40) = 1827 N.
PAPER_FIG5 = GasSpring(
    A1_mm2=float(np.pi / 4 * 57.1**2),
    A2_mm2=float(np.pi / 4 * 30.0**2),
    V1_mm3=1.22e5,
    V2_mm3=7.34e4,
    p1_MPa=float(30.0**2 / 57.1**2 * 2.3866),
    p2_MPa=2.3866,
)
