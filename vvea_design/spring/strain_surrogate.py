"""A cheap surrogate of the bladder's FE strain bound, for the optimiser's global search.

The FE check (:func:`vvea_design.bladder.check.strain_bound`, ~0.1 s per
design) is too slow for a population search. Its value depends on the cast
sleeve and the fluid it takes and gives up only through four dimensionless
groups (a neo-Hookean membrane at a prescribed volume: the shear modulus
scales the pressure, not the shape):

* ``e_exp = dV_expanded / (2 pi R^2 L)`` and ``e_com = |dV_compressed| / (2 pi R^2 L)``:
  the mean hoop strains of the two stroke ends,
* ``L / R``: slenderness, ``H / R``: wall thickness,

with ``R`` the cast mid radius, ``L`` the free length, ``H`` the wall. The
surrogate is a polynomial in the logarithms of these groups for the logarithm
of the strain bound, fitted by least squares to FE runs over the design space
of the ``inner_tube`` and ``bulkhead`` layouts (not yet refitted with ``annulus_top`` designs;
``python studies/bladder_surrogate.py``, which writes the
coefficients to ``strain_surrogate.json`` beside this module and states the
held-out error). The optimiser uses it in the global search and corrects it
with the FE itself before the final check (:func:`vvea_design.spring.optimise.optimise`).
"""

from __future__ import annotations

import json
import math
from functools import lru_cache
from itertools import combinations_with_replacement
from pathlib import Path

import numpy as np

__all__ = ["features", "population_strain", "design_strain", "load_coefficients", "poly_terms", "COEFFICIENTS_FILE"]

COEFFICIENTS_FILE = Path(__file__).with_name("strain_surrogate.json")
_FLOOR = 1e-4  #: added to the hoop strains before the logarithm (a bladder cast at an end has one of them 0)


def features(R, L, H, dv_expanded, dv_compressed) -> np.ndarray:
    """The four log-groups of the surrogate.

    Parameters
    ----------
    R, L, H : float or array
        Cast mid radius, free length and wall of the sleeve, mm.
    dv_expanded, dv_compressed : float or array
        Fluid volume relative to the cast shape at full stroke (>= 0) and at x = 0 (<= 0), mm³.

    Returns
    -------
    ndarray
        Shape ``(S, 4)``: log e_exp, log e_com, log L/R, log H/R (dimensionless).
    """
    R, L, H = (np.asarray(v, dtype=float) for v in (R, L, H))
    base = 2 * math.pi * R**2 * L
    e_e = np.abs(np.asarray(dv_expanded, dtype=float)) / base
    e_c = np.abs(np.asarray(dv_compressed, dtype=float)) / base
    return np.stack([np.log(e_e + _FLOOR), np.log(e_c + _FLOOR), np.log(L / R), np.log(H / R)], axis=-1)


def poly_terms(Z: np.ndarray, degree: int) -> np.ndarray:
    """All monomials of the columns of ``Z`` up to ``degree``, with the constant.

    Parameters
    ----------
    Z : ndarray
        Shape ``(S, F)``, dimensionless features.
    degree : int
        Highest total degree.

    Returns
    -------
    ndarray
        Shape ``(S, P)``, dimensionless.
    """
    Z = np.atleast_2d(Z)
    cols = [np.ones(Z.shape[0])]
    # each monomial is the one of degree d - 1 times one more column, in the order np.prod multiplies them
    # (left to right): the same values as np.prod(Z[:, idx], axis=1), with one multiplication each
    zc = [Z[:, j] for j in range(Z.shape[1])]
    prev: dict[tuple, np.ndarray] = {(): None}
    for d in range(1, degree + 1):
        cur: dict[tuple, np.ndarray] = {}
        for idx in combinations_with_replacement(range(Z.shape[1]), d):
            lower = prev[idx[:-1]]
            cur[idx] = zc[idx[-1]].copy() if lower is None else lower * zc[idx[-1]]
            cols.append(cur[idx])
        prev = cur
    return np.stack(cols, axis=1)


@lru_cache(maxsize=1)
def load_coefficients() -> dict:
    """The fitted surrogate (degree, feature centre/scale, coefficients, validation numbers)."""
    if not COEFFICIENTS_FILE.is_file():
        raise FileNotFoundError(f"{COEFFICIENTS_FILE} is missing: run python studies/bladder_surrogate.py")
    return json.loads(COEFFICIENTS_FILE.read_text(encoding="utf-8"))


def _predict(Z: np.ndarray) -> np.ndarray:
    c = load_coefficients()
    Zs = (Z - np.asarray(c["center"])) / np.asarray(c["scale"])
    return np.exp(poly_terms(Zs, int(c["degree"])) @ np.asarray(c["coefficients"]))


def population_strain(g, cols: dict | None = None) -> np.ndarray:
    """Surrogate strain bound of every design in a :func:`~vvea_design.spring.derive.derive` result.

    Parameters
    ----------
    g : Derived
        The derived quantities (mm, mm³) of ``S`` designs (:class:`~vvea_design.spring.derive.Derived`).
    cols : dict, optional
        Their decision variables (unused; the optimiser passes them to every strain function).

    Returns
    -------
    ndarray
        Shape ``(S,)``, strain as a fraction; ``inf`` where the bladder cannot be drawn.
    """
    R = np.asarray(g.bladder_mid_radius_mm, dtype=float)
    L = np.asarray(g.bladder_free_length_mm, dtype=float)
    H = np.asarray(g.bladder_outer_radius_mm, dtype=float) - np.asarray(g.bladder_inner_radius_mm, dtype=float)
    disp = np.asarray(g.displaced_volume_mm3, dtype=float)
    f = np.asarray(g.bladder_cast_fill, dtype=float)
    ok = (R > H) & (L > 0) & np.isfinite(R) & np.isfinite(L)
    Rs = np.where(ok, R, 10.0)
    Ls = np.where(ok, L, 10.0)
    Z = features(Rs, Ls, H, disp * (1 - f), disp * f)
    with np.errstate(over="ignore", invalid="ignore"):
        s = _predict(Z)
    return np.where(ok & np.isfinite(s), s, np.inf)


population_strain.reads_bladder_geometry_only = True  # evaluate_population may leave out the walls' stresses


def design_strain(design) -> float:
    """Surrogate strain bound of one design.

    Parameters
    ----------
    design : vvea_design.spring.design.Design
        The frozen design (mm, mm³).

    Returns
    -------
    float
        Strain bound as a fraction (``inf`` if the bladder cannot be drawn).
    """
    return float(np.asarray(population_strain(design.derived)).ravel()[0])
