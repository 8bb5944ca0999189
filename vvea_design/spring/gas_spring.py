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

from dataclasses import dataclass, replace

import numpy as np
from numpy.typing import ArrayLike

from ..messages import show
from ..plausibility import LIMITS

__all__ = [
    "ChamberBottomedOut",
    "GasSpring",
    "force_N",
    "chamber_pressures_MPa",
    "local_stiffness_N_per_mm",
    "setpoint_p1_MPa",
    "linearity_error",
    "linearity_error_exact",
    "linearity_exact",
    "LinearityResult",
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
    """Chamber pressures ``(P1, P2)`` at displacement ``x`` by the polytropic law ``p V**n = const``.

    ``P2 = p2 (V2 / (V2 - A2 x))**n`` and ``P1 = p1 (V1 / (V1 + A1 x))**n`` (paper eqs 3-4 for n = 1).
    All arguments broadcast with numpy.

    Parameters
    ----------
    x : array_like
        Displacement, mm; x > 0 extends the pull spring and compresses chamber 2.
    A1, A2 : float or array_like
        Effective areas of chamber 1 (expands as x grows) and chamber 2 (compressed as x grows), mm².
    V1, V2 : float or array_like
        Gas volumes of chambers 1 and 2 at x = 0, mm³.
    p1, p2 : float or array_like
        Absolute charge pressures of chambers 1 and 2 at x = 0, MPa.
    n : float
        Polytropic exponent, dimensionless: 1 isothermal (the paper's law), 1.4 adiabatic air.

    Returns
    -------
    P1, P2 : numpy.ndarray
        Absolute pressures of chamber 1 and chamber 2, MPa, broadcast over the inputs.

    Raises
    ------
    ChamberBottomedOut
        If a chamber's gas volume (``V2 - A2 x`` or ``V1 + A1 x``) is zero or negative anywhere in ``x``.
    """
    _check_volumes(x, A1, A2, V1, V2)
    x = np.asarray(x, dtype=float)
    P2 = p2 * (V2 / (V2 - A2 * x)) ** n
    P1 = p1 * (V1 / (V1 + A1 * x)) ** n
    return P1, P2


def force_N(x: ArrayLike, A1, A2, V1, V2, p1, p2, n: float = 1.0) -> np.ndarray:
    """Spring force ``F(x) = A2 P2 - A1 P1`` (paper eq. 5, generalised to the polytropic exponent ``n``).

    Parameters
    ----------
    x : array_like
        Displacement, mm; x > 0 extends the pull spring and compresses chamber 2.
    A1, A2 : float or array_like
        Effective areas of chamber 1 (expands as x grows) and chamber 2 (compressed as x grows), mm².
    V1, V2 : float or array_like
        Gas volumes of chambers 1 and 2 at x = 0, mm³.
    p1, p2 : float or array_like
        Absolute charge pressures of chambers 1 and 2 at x = 0, MPa.
    n : float
        Polytropic exponent, dimensionless: 1 isothermal (the paper's law), 1.4 adiabatic air.

    Returns
    -------
    numpy.ndarray
        Force, N (tension > 0), broadcast over the inputs.

    Raises
    ------
    ChamberBottomedOut
        If a chamber's gas volume (``V2 - A2 x`` or ``V1 + A1 x``) is zero or negative anywhere in ``x``.
    """
    P1, P2 = chamber_pressures_MPa(x, A1, A2, V1, V2, p1, p2, n)
    return A2 * P2 - A1 * P1


def local_stiffness_N_per_mm(x: ArrayLike, A1, A2, V1, V2, p1, p2, n: float = 1.0) -> np.ndarray:
    """Local stiffness: the analytic derivative ``dF/dx = n (A2² P2 / (V2 - A2 x) + A1² P1 / (V1 + A1 x))``.

    Parameters
    ----------
    x : array_like
        Displacement, mm; x > 0 extends the pull spring and compresses chamber 2.
    A1, A2 : float or array_like
        Effective areas of chamber 1 (expands as x grows) and chamber 2 (compressed as x grows), mm².
    V1, V2 : float or array_like
        Gas volumes of chambers 1 and 2 at x = 0, mm³.
    p1, p2 : float or array_like
        Absolute charge pressures of chambers 1 and 2 at x = 0, MPa.
    n : float
        Polytropic exponent, dimensionless: 1 isothermal (the paper's law), 1.4 adiabatic air.

    Returns
    -------
    numpy.ndarray
        Stiffness dF/dx, N/mm, broadcast over the inputs (positive for positive charges).

    Raises
    ------
    ChamberBottomedOut
        If a chamber's gas volume (``V2 - A2 x`` or ``V1 + A1 x``) is zero or negative anywhere in ``x``.
    """
    P1, P2 = chamber_pressures_MPa(x, A1, A2, V1, V2, p1, p2, n)
    x = np.asarray(x, dtype=float)
    return n * A2**2 * P2 / (V2 - A2 * x) + n * A1**2 * P1 / (V1 + A1 * x)


def setpoint_p1_MPa(p2, A1, A2, V1, V2, x0: float = 0.0, n: float = 1.0):
    """Charge pressure p1 that puts the zero-force point at ``x0`` (paper eqs 6/7).

    With ``x0 = 0`` this is ``p1 = A2/A1 * p2`` (eq. 7).

    Parameters
    ----------
    p2 : float or array_like
        Absolute charge pressure of chamber 2 at x = 0, MPa.
    A1, A2 : float or array_like
        Effective areas of chamber 1 (expands as x grows) and chamber 2 (compressed as x grows), mm².
    V1, V2 : float or array_like
        Gas volumes of chambers 1 and 2 at x = 0, mm³.
    x0 : float
        Displacement at which the force is to be zero, mm (the set point).
    n : float
        Polytropic exponent, dimensionless: 1 isothermal (the paper's law), 1.4 adiabatic air.

    Returns
    -------
    float or numpy.ndarray
        Absolute charge pressure of chamber 1 at x = 0, MPa.

    Raises
    ------
    ChamberBottomedOut
        If a chamber's gas volume is zero or negative at ``x0``.
    """
    _check_volumes(x0, A1, A2, V1, V2)
    return (A2 / A1) * p2 * (V2 / (V2 - A2 * x0)) ** n * ((V1 + A1 * x0) / V1) ** n


def least_squares_line(x: ArrayLike, F: ArrayLike):
    """Slope and intercept of the least-squares line of sampled ``F`` over ``x`` (along the last axis).

    Parameters
    ----------
    x : array_like
        Sample positions, shape ``(m,)``, mm.
    F : array_like
        Forces at ``x``, N; shape ``(..., m)`` to fit many curves at once.

    Returns
    -------
    slope : numpy.ndarray
        Slope of each line, N/mm, shape ``F.shape[:-1]``.
    intercept : numpy.ndarray
        Value of each line at x = 0, N, shape ``F.shape[:-1]``.
    """
    x = np.asarray(x, dtype=float)
    F = np.asarray(F, dtype=float)
    xm = x.mean()
    dx = x - xm
    slope = ((F - F.mean(axis=-1, keepdims=True)) * dx).sum(axis=-1) / (dx * dx).sum()
    intercept = F.mean(axis=-1) - slope * xm
    return slope, intercept


def linearity_error(x: ArrayLike, F: ArrayLike) -> np.ndarray:
    """The project's linearity metric on sampled data (a fraction).

    Largest deviation of ``F`` from its least-squares line over ``x``,
    divided by the force span ``max F - min F`` over ``x``. Works along the
    last axis, so ``F`` may hold many curves. :func:`linearity_exact` is the
    same metric over the continuous travel.

    Parameters
    ----------
    x : array_like
        Sample positions, shape ``(m,)``, mm.
    F : array_like
        Forces at ``x``, N; shape ``(..., m)``.

    Returns
    -------
    numpy.ndarray
        Linearity error as a fraction (0.0186 = 1.86 %), shape ``F.shape[:-1]``.
    """
    x = np.asarray(x, dtype=float)
    F = np.asarray(F, dtype=float)
    slope, intercept = least_squares_line(x, F)
    fit = slope[..., None] * x + np.asarray(intercept)[..., None]
    dev = np.abs(F - fit).max(axis=-1)
    span = F.max(axis=-1) - F.min(axis=-1)
    return dev / span


def mean_stiffness_N_per_mm(x: ArrayLike, F: ArrayLike) -> np.ndarray:
    """Mean stiffness: the least-squares slope of sampled ``F`` over ``x``.

    Parameters
    ----------
    x : array_like
        Sample positions, shape ``(m,)``, mm.
    F : array_like
        Forces at ``x``, N; shape ``(..., m)``.

    Returns
    -------
    numpy.ndarray
        Slope, N/mm, shape ``F.shape[:-1]``.
    """
    return least_squares_line(x, F)[0]


# ---------------------------------------------------------------------------
# The exact (continuous) metric
# ---------------------------------------------------------------------------

_GL_U, _GL_W = np.polynomial.legendre.leggauss(48)  # Gauss-Legendre on [-1, 1]
_GRID = np.linspace(0.0, 1.0, 33)  # bracketing grid for the extrema of the deviation
_NEWTON_STEPS = 6


@dataclass(frozen=True)
class LinearityResult:
    """The continuous linearity metric of one or many springs (arrays broadcast like the inputs)."""

    linearity_error: np.ndarray  #: max |F - line| / (F(T) - F(0)), fraction
    mean_stiffness_N_per_mm: np.ndarray  #: slope of the continuous least-squares line, N/mm
    intercept_N: np.ndarray  #: its value at x = 0, N
    max_deviation_N: np.ndarray  #: max over [0, T] of |F - line|, N
    x_max_deviation_mm: np.ndarray  #: where that maximum is, mm
    force_span_N: np.ndarray  #: F(T) - F(0) (F is monotonic: dF/dx > 0), N
    signed_extremes_N: np.ndarray | None = None  #: F - line at x = 0, at x = T, interior max, interior min, N (..., 4)

    def to_dict(self) -> dict:
        """JSON-ready content.

        Returns
        -------
        dict
            Every field that is set, as (nested) lists of floats; units in the keys (N, mm, N/mm;
            ``linearity_error`` a fraction).
        """
        return {k: np.asarray(v).tolist() for k, v in self.__dict__.items() if v is not None}


def _pow(r, n):
    # linearity_exact passes the float 1.0 when every exponent is 1, else the exponents (pow(r, 1) = r exactly)
    if type(n) is float:
        return r if n == 1.0 else r**n
    return r if np.all(n == 1.0) else r**n


def _terms(x, A1, A2, V1, V2, p1, p2, n):
    """Chamber pressures and the volumes they act through (no checks: the caller masks)."""
    v2 = V2 - A2 * x
    v1 = V1 + A1 * x
    return p1 * _pow(V1 / v1, n), p2 * _pow(V2 / v2, n), v1, v2


def linearity_exact(A1, A2, V1, V2, p1, p2, travel_mm, n=1.0) -> LinearityResult:
    """The project's linearity metric over the continuous travel ``[0, travel_mm]``.

    * The least-squares line minimises the integral of ``(F - a - k x)^2``
      over the travel (48-point Gauss-Legendre quadrature: eq. 5 is analytic
      on the travel, so the integrals are exact to rounding).
    * The largest deviation is the maximum of ``|F - line|`` at the two ends
      and at every interior root of ``dF/dx = k`` (bracketed on a 33-point
      grid, refined by safeguarded Newton steps with the analytic ``F''``):
      exact to rounding, far inside the 1e-5 asked for.
    * The span is ``F(T) - F(0)``: ``dF/dx > 0`` for positive charges.

    All parameters broadcast (pass arrays of shape ``(k,)`` to evaluate ``k``
    springs at once). A spring that bottoms out gives ``nan``.

    Parameters
    ----------
    A1, A2 : float or array_like
        Effective areas of chamber 1 (expands as x grows) and chamber 2 (compressed as x grows), mm².
    V1, V2 : float or array_like
        Gas volumes of chambers 1 and 2 at x = 0, mm³.
    p1, p2 : float or array_like
        Absolute charge pressures of chambers 1 and 2 at x = 0, MPa.
    travel_mm : float or array_like
        Stroke T: the metric is taken over x in [0, T], mm.
    n : float
        Polytropic exponent, dimensionless: 1 isothermal (the paper's law), 1.4 adiabatic air.

    Returns
    -------
    LinearityResult
        Linearity error (fraction), mean stiffness (N/mm), intercept (N), largest deviation (N) and
        where it lies (mm), force span (N), signed deviations at the ends and interior extrema (N);
        each of the broadcast shape of the inputs, ``nan`` where a chamber bottoms out or T <= 0.
    """
    arrs = [np.asarray(v, dtype=float) for v in (A1, A2, V1, V2, p1, p2, travel_mm, n)]
    shape = np.broadcast_shapes(*(v.shape for v in arrs))
    arrs = [v if v.shape == shape else np.broadcast_to(v, shape) for v in arrs]  # np.broadcast_arrays' views
    A1, A2, V1, V2, p1, p2, T, n = (v.reshape(-1, 1) for v in arrs)
    ok = (V2 - A2 * T > 0) & (V1 > 0) & (T > 0) & np.isfinite(p1) & np.isfinite(p2)
    V2 = np.where(ok, V2, A2 * T * 2 + 1.0)  # keep the arithmetic finite; masked to nan below
    p1 = np.where(ok, p1, 0.0)
    p2 = np.where(ok, p2, 1.0)
    nn = n if np.any(n != 1.0) else 1.0

    xq = 0.5 * T * (_GL_U + 1.0)
    w = 0.5 * T * _GL_W
    xg = T * _GRID
    # F = A2 P2 - A1 P1 at the quadrature points, the grid, T and 0, and F' on the grid, from one evaluation of
    # the chamber terms (elementwise: the same values as one evaluation per set of points)
    nq, ng = xq.shape[1], xg.shape[1]
    P1a, P2a, v1a, v2a = _terms(np.concatenate([xq, xg, T, np.zeros_like(T)], axis=1), A1, A2, V1, V2, p1, p2, nn)
    Fall = A2 * P2a - A1 * P1a
    Fq, Fg = Fall[:, :nq], Fall[:, nq:nq + ng]
    gs = slice(nq, nq + ng)
    dFg = nn * (A2 * A2 * P2a[:, gs] / v2a[:, gs] + A1 * A1 * P1a[:, gs] / v1a[:, gs])
    xm = 0.5 * T
    k = (w * (xq - xm) * Fq).sum(axis=-1, keepdims=True) / (T**3 / 12.0)
    b = (w * Fq).sum(axis=-1, keepdims=True) / T - k * xm
    sdev = Fg - (k * xg + b)
    int_max = sdev[:, 1:-1].max(axis=-1)
    int_min = sdev[:, 1:-1].min(axis=-1)
    dev = np.abs(sdev)
    i = dev.argmax(axis=-1)
    rows = np.arange(dev.shape[0])
    devmax, xmax = dev[rows, i], xg[rows, i]
    # refine every bracketed root of F' = k (the interior extrema of the deviation)
    g = dFg - k
    di, ii = np.nonzero(np.sign(g[:, :-1]) * np.sign(g[:, 1:]) < 0)
    if di.size:
        sel = [v[di, 0] if v.shape[0] > 1 else np.broadcast_to(v[0, 0], di.shape) for v in
               (A1, A2, V1, V2, p1, p2, np.broadcast_to(n, A1.shape), k, b)]
        a1, a2, v1_, v2_, q1, q2, ns, kk, bb = sel
        ns = ns if np.any(ns != 1.0) else 1.0
        a, c = xg[di, ii], xg[di, ii + 1]
        ga, gc = g[di, ii], g[di, ii + 1]
        x = a - ga * (c - a) / (gc - ga)
        # loop invariants hoisted (the same operations on the same values: bit-identical)
        a2a2, a1a1, a2c, a1c, nn1, sga = a2 * a2, a1 * a1, a2**3, a1**3, ns * (ns + 1), np.sign(ga)
        with np.errstate(divide="ignore", invalid="ignore"):
            for _ in range(_NEWTON_STEPS):
                P1, P2, w1, w2 = _terms(x, a1, a2, v1_, v2_, q1, q2, ns)
                gx = ns * (a2a2 * P2 / w2 + a1a1 * P1 / w1) - kk
                d2 = nn1 * (a2c * P2 / w2**2 - a1c * P1 / w1**2)
                left = np.sign(gx) == sga
                a = np.where(left, x, a)
                c = np.where(left, c, x)
                xn = x - gx / d2
                bad = ~np.isfinite(xn) | (xn <= a) | (xn >= c)
                x = np.where(bad, 0.5 * (a + c), xn)
        P1, P2, _, _ = _terms(x, a1, a2, v1_, v2_, q1, q2, ns)
        sr = a2 * P2 - a1 * P1 - (kk * x + bb)
        np.maximum.at(int_max, di, sr)
        np.minimum.at(int_min, di, sr)
        dr = np.abs(sr)
        better = np.zeros_like(devmax)
        np.maximum.at(better, di, dr)
        xr = np.zeros_like(devmax)
        pick = dr >= better[di]
        xr[di[pick]] = x[pick]
        upd = better > devmax
        devmax = np.where(upd, better, devmax)
        xmax = np.where(upd, xr, xmax)
    span = Fall[:, -2] - Fall[:, -1]  # F(T) - F(0)
    with np.errstate(divide="ignore", invalid="ignore"):
        lin = devmax / span
    bad = ~ok[:, 0]
    out = [lin, k[:, 0], b[:, 0], devmax, xmax, span]
    out = [np.where(bad, np.nan, v).reshape(shape) for v in out]
    ext = np.stack([sdev[:, 0], sdev[:, -1], int_max, int_min], axis=-1)
    ext = np.where(bad[:, None], np.nan, ext).reshape(shape + (4,))
    return LinearityResult(*out, signed_extremes_N=ext)


def linearity_error_exact(A1, A2, V1, V2, p1, p2, travel_mm, n=1.0) -> np.ndarray:
    """Just the continuous linearity error of :func:`linearity_exact`.

    Parameters
    ----------
    A1, A2 : float or array_like
        Effective areas of chamber 1 (expands as x grows) and chamber 2 (compressed as x grows), mm².
    V1, V2 : float or array_like
        Gas volumes of chambers 1 and 2 at x = 0, mm³.
    p1, p2 : float or array_like
        Absolute charge pressures of chambers 1 and 2 at x = 0, MPa.
    travel_mm : float or array_like
        Stroke T: the metric is taken over x in [0, T], mm.
    n : float
        Polytropic exponent, dimensionless: 1 isothermal (the paper's law), 1.4 adiabatic air.

    Returns
    -------
    numpy.ndarray
        Linearity error as a fraction, of the broadcast shape of the inputs (``nan`` where a chamber
        bottoms out).
    """
    return linearity_exact(A1, A2, V1, V2, p1, p2, travel_mm, n).linearity_error


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
        """Evenly spaced displacements over the travel.

        Parameters
        ----------
        num : int
            Number of samples, ends included.

        Returns
        -------
        numpy.ndarray
            ``num`` displacements from 0 to ``travel_mm``, mm.
        """
        return np.linspace(0.0, self.travel_mm, num)

    def force_N(self, x: ArrayLike) -> np.ndarray:
        """Spring force at ``x`` (:func:`force_N` with this spring's parameters).

        Parameters
        ----------
        x : array_like
            Displacement, mm (x > 0 extends).

        Returns
        -------
        numpy.ndarray
            Force, N (tension > 0).

        Raises
        ------
        ChamberBottomedOut
            If ``x`` reaches a displacement where a chamber's gas volume is zero.
        """
        return force_N(x, *self._args())

    def stiffness_N_per_mm(self, x: ArrayLike) -> np.ndarray:
        """Local stiffness dF/dx at ``x`` (:func:`local_stiffness_N_per_mm`).

        Parameters
        ----------
        x : array_like
            Displacement, mm.

        Returns
        -------
        numpy.ndarray
            Stiffness, N/mm.

        Raises
        ------
        ChamberBottomedOut
            If ``x`` reaches a displacement where a chamber's gas volume is zero.
        """
        return local_stiffness_N_per_mm(x, *self._args())

    def pressures_MPa(self, x: ArrayLike):
        """Chamber pressures at ``x`` (:func:`chamber_pressures_MPa`).

        Parameters
        ----------
        x : array_like
            Displacement, mm.

        Returns
        -------
        P1, P2 : numpy.ndarray
            Absolute pressures of chamber 1 and chamber 2, MPa.

        Raises
        ------
        ChamberBottomedOut
            If ``x`` reaches a displacement where a chamber's gas volume is zero.
        """
        return chamber_pressures_MPa(x, *self._args())

    def with_pressures(self, p2_MPa: float, x0_mm: float = 0.0) -> "GasSpring":
        """Same geometry charged to ``p2`` with p1 from eq. 6 (zero force at ``x0``).

        Parameters
        ----------
        p2_MPa : float
            New absolute charge of chamber 2 at x = 0.
        x0_mm : float
            Displacement where the force is to be zero.

        Returns
        -------
        GasSpring
            The recharged spring (travel and polytropic exponent unchanged).

        Raises
        ------
        vvea_design.plausibility.PlausibilityError
            ``p2_MPa`` is not a charge a real unit can have (:data:`vvea_design.plausibility.LIMITS`
            ``charge_MPa``: 0.01 ... 20 MPa).
        """
        LIMITS["charge_MPa"].check(p2_MPa, "p2_MPa")
        p1 = float(setpoint_p1_MPa(p2_MPa, self.A1_mm2, self.A2_mm2, self.V1_mm3, self.V2_mm3, x0_mm, self.n_polytropic))
        return GasSpring(self.A1_mm2, self.A2_mm2, self.V1_mm3, self.V2_mm3, p1, p2_MPa, self.travel_mm, self.n_polytropic)

    def linearity(self) -> LinearityResult:
        """The exact (continuous) linearity metric, its line and its largest deviation.

        Returns
        -------
        LinearityResult
            :func:`linearity_exact` of this spring over ``[0, travel_mm]``: linearity error
            (fraction), mean stiffness (N/mm), intercept (N), largest deviation (N) and where (mm).
        """
        return linearity_exact(self.A1_mm2, self.A2_mm2, self.V1_mm3, self.V2_mm3, self.p1_MPa, self.p2_MPa,
                               self.travel_mm, self.n_polytropic)

    def linearity_error(self, num: int | None = None) -> float:
        """The linearity error: exact over the continuous travel by default, or on samples.

        Parameters
        ----------
        num : int or None
            None: the exact continuous metric. A number: the metric on ``num`` equally spaced
            samples of the travel (only to compare with sampled data).

        Returns
        -------
        float
            Linearity error as a fraction.
        """
        if num is None:
            return float(self.linearity().linearity_error)
        x = self.x_mm(num)
        return float(linearity_error(x, self.force_N(x)))

    def mean_stiffness_N_per_mm(self, num: int | None = None) -> float:
        """Slope of the least-squares line: continuous by default, or over samples.

        Parameters
        ----------
        num : int or None
            None: the continuous least-squares line. A number: the line through ``num`` equally
            spaced samples of the travel.

        Returns
        -------
        float
            Mean stiffness, N/mm.
        """
        if num is None:
            return float(self.linearity().mean_stiffness_N_per_mm)
        x = self.x_mm(num)
        return float(mean_stiffness_N_per_mm(x, self.force_N(x)))

    def with_polytropic(self, n: float) -> "GasSpring":
        """The same charged spring compressed with polytropic exponent ``n`` (charges unchanged).

        Parameters
        ----------
        n : float
            Polytropic exponent, dimensionless, in [1, 1.4].

        Returns
        -------
        GasSpring
            A copy with ``n_polytropic = n``.

        Raises
        ------
        ValueError
            If ``n`` is outside [1, 1.4].
        """
        return replace(self, n_polytropic=float(n))

    def peak_pressure_MPa(self) -> float:
        """Highest chamber pressure over the stroke (chamber 2 at full travel or p1 at x=0).

        Returns
        -------
        float
            Absolute pressure, MPa.
        """
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
