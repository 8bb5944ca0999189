"""Closed-form stresses the FE is verified against (and compared with, piece by piece).

* Lamé's thick cylinder under internal and external pressure (Timoshenko & Goodier, *Theory of Elasticity*,
  §33): ``s_r = A - B / r^2``, ``s_t = A + B / r^2`` with ``A = (p_i a^2 - p_o b^2) / (b^2 - a^2)`` and
  ``B = (p_i - p_o) a^2 b^2 / (b^2 - a^2)``; the axial stress of a closed cylinder is ``A``.
* Thin circular plates under uniform pressure (Timoshenko & Woinowsky-Krieger, *Theory of Plates and Shells*,
  §15-16; Roark's *Formulas for Stress and Strain*, table 11.2, cases 10a/10b): simply supported,
  ``s_r(r) = 3 (3 + nu) q (a^2 - r^2) / (8 t^2)`` and ``s_t(r) = 3 q ((3 + nu) a^2 - (1 + 3 nu) r^2) / (8 t^2)``;
  clamped, ``s_r(r) = 3 q ((1 + nu) a^2 - (3 + nu) r^2) / (8 t^2)``, ``s_t(r) = 3 q ((1 + nu) a^2 - (1 + 3 nu)
  r^2) / (8 t^2)`` (surface stresses, tension on the side away from the pressure at the centre).
* The annular plate of the piston pocket's floor is the spring side's
  (:func:`~vvea_design.spring.derive.piston_floor_moment`), verified there against the plate equation.

Pressures and stresses MPa, lengths mm.
"""

from __future__ import annotations

import numpy as np

__all__ = ["lame", "plate_simply_supported", "plate_clamped", "annular_plate_moment"]


def lame(r_mm, inner_radius_mm: float, outer_radius_mm: float, p_inner_MPa: float,
         p_outer_MPa: float = 0.0) -> dict[str, np.ndarray]:
    """Lamé's stresses in a thick cylinder.

    Parameters
    ----------
    r_mm : array_like
        Radii in the wall, mm.
    inner_radius_mm, outer_radius_mm : float
        Bore and outer radius, mm.
    p_inner_MPa, p_outer_MPa : float
        Pressure inside and outside, MPa.

    Returns
    -------
    dict of str to ndarray
        ``s_rr``, ``s_tt`` (hoop) and ``s_zz_closed`` (axial stress of a closed-ended cylinder), MPa.
    """
    a, b = inner_radius_mm, outer_radius_mm
    r = np.asarray(r_mm, dtype=float)
    A = (p_inner_MPa * a**2 - p_outer_MPa * b**2) / (b**2 - a**2)
    B = (p_inner_MPa - p_outer_MPa) * a**2 * b**2 / (b**2 - a**2)
    return {"s_rr": A - B / r**2, "s_tt": A + B / r**2, "s_zz_closed": np.full_like(r, A)}


def plate_simply_supported(r_mm, radius_mm: float, thickness_mm: float, pressure_MPa: float,
                           poisson: float) -> dict[str, np.ndarray]:
    """Surface bending stresses of a simply supported circular plate under uniform pressure.

    Parameters
    ----------
    r_mm : array_like
        Radii, mm (0 .. radius).
    radius_mm, thickness_mm : float
        Support radius and thickness, mm.
    pressure_MPa : float
        Uniform pressure, MPa.
    poisson : float
        Poisson's ratio.

    Returns
    -------
    dict of str to ndarray
        ``s_rr`` and ``s_tt`` at the surface away from the pressure, MPa (the loaded surface has them with
        the opposite sign).
    """
    a, t, q, nu = radius_mm, thickness_mm, pressure_MPa, poisson
    r = np.asarray(r_mm, dtype=float)
    k = 3 * q / (8 * t**2)
    return {"s_rr": k * (3 + nu) * (a**2 - r**2), "s_tt": k * ((3 + nu) * a**2 - (1 + 3 * nu) * r**2)}


def plate_clamped(r_mm, radius_mm: float, thickness_mm: float, pressure_MPa: float,
                  poisson: float) -> dict[str, np.ndarray]:
    """Surface bending stresses of a clamped circular plate under uniform pressure.

    Parameters
    ----------
    r_mm : array_like
        Radii, mm (0 .. radius).
    radius_mm, thickness_mm : float
        Clamped radius and thickness, mm.
    pressure_MPa : float
        Uniform pressure, MPa.
    poisson : float
        Poisson's ratio.

    Returns
    -------
    dict of str to ndarray
        ``s_rr`` and ``s_tt`` at the surface away from the pressure, MPa (at the edge ``s_rr = -3 q a^2 /
        (4 t^2)``: compression there, tension on the loaded side).
    """
    a, t, q, nu = radius_mm, thickness_mm, pressure_MPa, poisson
    r = np.asarray(r_mm, dtype=float)
    k = 3 * q / (8 * t**2)
    return {"s_rr": k * ((1 + nu) * a**2 - (3 + nu) * r**2), "s_tt": k * ((1 + nu) * a**2 - (1 + 3 * nu) * r**2)}


def annular_plate_moment(r_mm, piston_radius_mm: float, pocket_radius_mm: float, rod_radius_mm: float,
                         pressure_MPa: float, poisson: float) -> np.ndarray:
    """Radial bending moment of the piston pocket's floor as the sizing idealises it, at any radius.

    The annular thin plate from the rod (``b``, clamped: ``w' = 0``) to the pocket's wall (``a``, free to rotate:
    ``M_r = 0``) carries the pressure ``q`` on ``b .. a`` and the rim's share ``q (rp^2 - a^2) / (2 a)`` at ``a``,
    so its shear is ``Q = q (rp^2 - r^2) / (2 r)``. Integrating ``d/dr[(1/r) d/dr(r w')] = Q / D`` twice gives
    ``w' = (q / 2D) (rp^2 (r ln r / 2 - r / 4) - r^3 / 8) + C1 r / 2 + C2 / r`` and
    ``M_r = -D (w'' + nu w' / r)``; ``C1``, ``C2`` from the two edge conditions. At ``r = b`` it is ``q K`` of
    :func:`~vvea_design.spring.derive.piston_floor_moment`.

    Parameters
    ----------
    r_mm : array_like
        Radii, mm (b .. a).
    piston_radius_mm, pocket_radius_mm, rod_radius_mm : float
        ``rp``, ``a``, ``b``, mm.
    pressure_MPa : float
        ``q``, MPa.
    poisson : float
        Poisson's ratio.

    Returns
    -------
    ndarray
        ``|M_r(r)|``, N·mm/mm (the bending stress is ``6 M / t^2``).
    """
    rp, a, b, q, nu = piston_radius_mm, pocket_radius_mm, rod_radius_mm, pressure_MPa, poisson
    # with D = 1 (M scales with D, the constants with 1/D): phi = P(r) + C1 r/2 + C2/r
    def P(r):
        return 0.5 * q * (rp**2 * (0.5 * r * np.log(r) - 0.25 * r) - r**3 / 8)

    def dP(r):
        return 0.5 * q * (rp**2 * (0.5 * np.log(r) + 0.25) - 3 * r**2 / 8)

    def m(r, c1, c2):  # -(phi' + nu phi / r)
        return -(dP(r) + c1 / 2 - c2 / r**2 + nu * (P(r) / r + c1 / 2 + c2 / r**2))

    # phi(b) = 0 ; M(a) = 0 -> linear in (c1, c2)
    A = np.array([[b / 2, 1 / b],
                  [-(1 + nu) / 2, (1 - nu) / a**2]])
    rhs = np.array([-P(b), dP(a) + nu * P(a) / a])
    c1, c2 = np.linalg.solve(A, rhs)
    return np.abs(m(np.asarray(r_mm, dtype=float), c1, c2))
