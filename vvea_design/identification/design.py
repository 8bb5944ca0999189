"""The design matrix: eq. 14's columns, plus the columns of any effects, in one array.

The paper's identification model (eq. 14)::

    f = g p2 x + L(γ) ẋ + C sign(ẋ)

is linear in its parameters: its design has the columns ``p2 x``, ``sign(ẋ)``
and one ``ẋ`` column per valve angle (zero at the other angles' samples).
:func:`assemble` appends each effect's columns (:func:`~vvea_design.identification.effects.effect_columns`),
zeroes the damping columns an effect replaces and passes the whole design
through the effects that act on it (sensor dynamics).
"""

from __future__ import annotations

import inspect

import numpy as np

from .effects import REGISTRY, Param, effect_columns
from .fit_data import FitData, cached

__all__ = ["baseline_columns", "baseline_params", "fill_baseline", "assemble", "layout"]


def baseline_columns(D: FitData) -> tuple[np.ndarray, list[Param]]:
    """Design matrix of eq. 14: ``[p2 x, sign(ẋ), ẋ·1{γ=γ_j} ...]`` (cached: do not modify it in place).

    Parameters
    ----------
    D : FitData
        The campaign's arrays (x in mm, ẋ in mm/s, p2 in MPa, valve angles in deg).

    Returns
    -------
    X : numpy.ndarray, shape (D.n, 2 + len(D.valves))
        Columns ``p2 x`` (MPa mm), ``sign(ẋ)`` (dimensionless) and one column
        ``ẋ`` (mm/s) per valve angle, zero at samples of the other angles.
    params : list of Param
        One per column: ``g`` (N/mm/MPa), ``C`` (N), ``L(γ)`` (N s/mm), all
        bounded below by 0.
    """
    return cached(D, ("eq14",), lambda: _baseline_columns(D))


def baseline_params(D: FitData) -> list[Param]:
    """The parameters of eq. 14's columns (see :func:`baseline_columns`), without building the columns.

    Parameters
    ----------
    D : FitData
        The campaign (its valve angles, deg, give one damping parameter each).

    Returns
    -------
    list of Param
        ``g`` (N/mm/MPa), ``C`` (N) and one ``L(γ)`` (N s/mm) per valve angle, all bounded below by 0.
    """
    params = [
        Param("g", "N/mm/MPa", 0.0, np.inf, "spring stiffness per MPa of p2"),
        Param("C", "N", 0.0, np.inf, "Coulomb friction (Table 3's B)"),
    ]
    for val in D.valves:
        params.append(Param(f"L({val:g})", "N s/mm", 0.0, np.inf, f"linear damping at valve {val:g} deg"))
    return params


def fill_baseline(D: FitData, out: np.ndarray, zeroed: bool = False) -> None:
    """Write eq. 14's columns (the values of :func:`baseline_columns`) into ``out[:, :2 + len(D.valves)]``.

    Lets a design be built in one array, without a cached ``(n, 2 + valves)`` copy of the mostly-zero
    per-valve damping columns (memory on large campaigns).

    Parameters
    ----------
    D : FitData
        The campaign's arrays (x in mm, ẋ in mm/s, p2 in MPa, valve angles in deg).
    out : numpy.ndarray, shape (D.n, p) with p >= 2 + len(D.valves)
        Filled in place: ``p2 x`` (MPa mm), ``sign(ẋ)`` (dimensionless) and one ``ẋ`` column (mm/s) per
        valve angle, zero at samples of the other angles; columns beyond are left untouched.
    zeroed : bool
        ``out``'s valve columns are already zero (``numpy.zeros``: its pages need no writing), so only
        each sample's own valve column is written.

    Returns
    -------
    None
    """
    out[:, 0] = D.p2 * D.x
    out[:, 1] = D.s
    if not zeroed:
        out[:, 2 : 2 + len(D.valves)] = 0.0
    out[np.arange(D.n), 2 + D.valve_idx] = D.v  # one pass instead of a masked product per valve


def _baseline_columns(D: FitData):
    cols = [D.p2 * D.x, D.s]
    for j in range(len(D.valves)):
        cols.append(D.v * (D.valve_idx == j))
    return np.column_stack(cols), baseline_params(D)


def assemble(D: FitData, effects=(), shapes: dict | None = None, ctx: dict | None = None):
    """Design matrix of eq. 14 plus ``effects``.

    Parameters
    ----------
    D : FitData
    effects : sequence of str
        Effect ids from :data:`vvea_design.identification.effects.REGISTRY`.
    shapes : dict
        Shape-parameter value per effect id (ignored for effects without one).
    ctx : dict
        Context for effects that need the current model (``damping_force_N``,
        ``model_force_N``, ``residual_N``; see :class:`~vvea_design.identification.effects.Effect`).

    Returns
    -------
    X : (n, p) array
    params : list[Param]
    groups : dict[str, slice]
        Columns of the baseline (``"eq14"``) and of each effect.
    """
    shapes = shapes or {}
    ctx = ctx or {}
    params, groups = layout(D, effects)
    p0, p = groups["eq14"].stop, len(params)
    # one (n, p) array filled in place, column block by column block: no copies of the baseline or of
    # all the stacked columns at once (memory on large campaigns)
    X = np.zeros((D.n, p))  # zeroed pages come free from the kernel; only nonzeros are written
    fill_baseline(D, X, zeroed=True)
    for eid in effects:
        eff = REGISTRY[eid]
        sv = shapes.get(eid, np.nan)
        m = eff.damping_mask(D, sv, ctx)
        if m is not None:
            X[m, 2:p0] = 0.0
        c = effect_columns(D, eff, sv, ctx)
        if c.shape[1] != groups[eid].stop - groups[eid].start:
            raise ValueError(f"effect {eid!r} gives {c.shape[1]} columns for {groups[eid].stop - groups[eid].start} parameters")
        X[:, groups[eid]] = c
        del c
    for eid in effects:
        eff = REGISTRY[eid]
        if eff.transforms_design:
            sig = inspect.signature(eff.transform).parameters
            if "eq14_first" in sig:  # the whole design, eq. 14's columns first (sensor filters treat its damping columns)
                X = eff.transform(D, X, shapes.get(eid, np.nan), ctx, out=X, eq14_first=True)
            elif "out" in sig:
                X = eff.transform(D, X, shapes.get(eid, np.nan), ctx, out=X)  # X is ours: transformed in place
            else:
                X = eff.transform(D, X, shapes.get(eid, np.nan), ctx)
    return X, params, groups


def layout(D: FitData, effects) -> tuple[list, dict]:
    """Parameters and column groups of the design of eq. 14 plus ``effects`` (see :func:`assemble`), without building it.

    Parameters
    ----------
    D : FitData
        The campaign (its valve angles, deg, give eq. 14 one damping parameter each).
    effects : sequence of str
        Effect ids from :data:`vvea_design.identification.effects.REGISTRY`.

    Returns
    -------
    params : list of Param
        One per column, eq. 14's first (units in ``Param.unit``).
    groups : dict of str to slice
        Columns of the baseline (``"eq14"``) and of each effect.
    """
    params = baseline_params(D)
    groups = {"eq14": slice(0, len(params))}
    p = len(params)
    for eid in effects:
        q = list(REGISTRY[eid].params(D))
        params = params + q
        groups[eid] = slice(p, p + len(q))
        p += len(q)
    return params, groups
