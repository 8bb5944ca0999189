"""Identification: the paper's eq. 14 and its extensions, fitted to recordings.

The paper (section 4) fits ::

    f = g p2 x + L(γ) ẋ + C sign(ẋ)                      (eq. 14)

by least squares (eq. 15) and lists g, C (its "B") and one L per valve in
Table 3. The model is linear in its parameters, so here it is solved exactly
by bounded linear least squares (g, C, L >= 0). The same engine fits the
extended models of :mod:`vvea_design.identification.diagnose` (eq. 14 plus effects from
:mod:`vvea_design.identification.effects`): amplitudes are linear, each effect's one shape
parameter is searched on a grid and refined.

Samples within one run are not independent (correlated noise), so the
parameter uncertainties are cluster-robust (sandwich) standard errors with
whole experiments as clusters, not the naive i.i.d. ones.

Everything is computed from per-experiment normal-equation blocks
``G_e = X_eᵀX_e``, ``b_e = X_eᵀy_e``, so refitting without some experiments
(grouped cross-validation) costs a ``p x p`` solve.
"""

from __future__ import annotations

import inspect
import json
from dataclasses import asdict, dataclass, field
from pathlib import Path

import numpy as np
import pandas as pd
from scipy.linalg import cho_factor, cho_solve, solve_triangular
from scipy.linalg.lapack import dpotrf as _dpotrf, dpotrs as _dpotrs
from scipy.optimize import lsq_linear, minimize_scalar

from ..figure_layout import tight_layout_once
from .effects import REGISTRY, FitData, baseline_params, effect_columns, fill_baseline
from .recordings import Recordings

__all__ = [
    "PAPER_TABLE3",
    "PAPER_ERROR_BAND_PCT",
    "Blocks",
    "ModelFit",
    "assemble",
    "blocks",
    "extend_blocks",
    "solve_bounded",
    "auto_context",
    "fit_model",
    "relief_context",
    "fit_eq14",
    "table3",
    "error_band_pct",
    "format_table3",
    "write_identification",
    "Identifiability",
    "identifiability",
    "plot_fig10",
    "plot_fig11",
]

#: Table 3 of the paper (value per parameter name).
PAPER_TABLE3: dict[str, float] = {
    "g": 23.31,
    "C": 125.5,
    "L(50)": 0.4,
    "L(80)": 0.5,
    "L(100)": 7.1,
    "L(104)": 15.1,
    "L(106)": 25.3,
    "L(108)": 40.6,
    "L(109)": 52.7,
    "L(110)": 85.2,
    "L(120)": 1024.7,
}
#: The paper's error band of eq. 14 against its measurements (% of nominal force).
PAPER_ERROR_BAND_PCT = (-9.5, 12.0)


# ------------------------------------------------------------------ engine
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
    params, groups = _layout(D, effects)
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


def _layout(D: FitData, effects) -> tuple[list, dict]:
    """Parameters and column groups of the design of eq. 14 plus ``effects`` (see :func:`assemble`), without building it."""
    params = baseline_params(D)
    groups = {"eq14": slice(0, len(params))}
    p = len(params)
    for eid in effects:
        q = list(REGISTRY[eid].params(D))
        params = params + q
        groups[eid] = slice(p, p + len(q))
        p += len(q)
    return params, groups


@dataclass(frozen=True)
class Blocks:
    """Per-experiment normal-equation blocks of a design."""

    G: np.ndarray  #: (n_exp, p, p)
    b: np.ndarray  #: (n_exp, p)
    yy: np.ndarray  #: (n_exp,)
    n: np.ndarray  #: samples per experiment
    lower: np.ndarray
    upper: np.ndarray

    def sse(self, theta: np.ndarray, rows: np.ndarray | None = None) -> np.ndarray:
        """Sum of squared residuals per experiment for parameters ``theta``.

        Computed from the blocks alone: ``yy - 2 b·θ + θᵀ G θ`` per experiment, no pass over the samples.

        Parameters
        ----------
        theta : numpy.ndarray
            Shape (p,): amplitudes in the units of the design's parameters (one per column).
        rows : numpy.ndarray, optional
            Experiments to evaluate: integer indices or a boolean mask over the experiments
            (dimensionless); default all.

        Returns
        -------
        numpy.ndarray
            Shape (n_exp,) or (len(rows),): the sum of squared force residuals of each experiment, N^2.
        """
        G, b, yy = (self.G, self.b, self.yy) if rows is None else (self.G[rows], self.b[rows], self.yy[rows])
        return yy - 2 * b @ theta + np.einsum("i,eij,j->e", theta, G, theta)


def _equal_runs(bounds: np.ndarray) -> list:
    """``(e0, e1)``: runs of consecutive experiments with the same number of samples (a campaign's are usually all equal)."""
    n = np.diff(bounds)
    if len(n) == 0:
        return []
    cuts = np.flatnonzero(np.diff(n) != 0) + 1
    return list(zip(np.r_[0, cuts].tolist(), np.r_[cuts, len(n)].tolist()))


def _stacked(A: np.ndarray, bounds: np.ndarray, e0: int, e1: int) -> np.ndarray:
    """Rows of experiments ``e0 .. e1-1`` (equal lengths) of ``A`` as a (experiments, samples, ...) stack (a view when ``A`` is contiguous)."""
    k = e1 - e0
    return A[bounds[e0] : bounds[e1]].reshape((k, (bounds[e1] - bounds[e0]) // k) + A.shape[1:])


def blocks(X: np.ndarray, y: np.ndarray, bounds: np.ndarray, params) -> Blocks:
    """Normal-equation blocks per experiment (``bounds`` = row offsets).

    Parameters
    ----------
    X : numpy.ndarray, shape (n, p)
        Design matrix; each column in its own unit (e.g. MPa mm for ``p2 x``,
        mm/s for ``ẋ``, dimensionless for ``sign(ẋ)``), see :func:`assemble`.
    y : numpy.ndarray, shape (n,)
        Measured force, N.
    bounds : numpy.ndarray, shape (n_exp + 1,)
        Row offsets of the experiments (a count of samples; ``bounds[-1] == n``).
    params : sequence of Param
        One per column of ``X``; their ``lower`` / ``upper`` bounds are kept.

    Returns
    -------
    Blocks
        ``G[e] = Xeᵀ Xe``, ``b[e] = Xeᵀ ye`` and ``yy[e] = yeᵀ ye`` (N²) per
        experiment ``e``, the samples per experiment and the parameter bounds.
    """
    ne = len(bounds) - 1
    p = X.shape[1]
    G = np.empty((ne, p, p))
    b = np.empty((ne, p))
    yy = np.empty(ne)
    for e0, e1 in _equal_runs(bounds):  # experiments of equal length side by side: one stacked product each
        X3, y3 = _stacked(X, bounds, e0, e1), _stacked(y, bounds, e0, e1)
        X3t = X3.transpose(0, 2, 1)
        np.matmul(X3t, X3, out=G[e0:e1])
        b[e0:e1] = np.matmul(X3t, y3[..., None])[..., 0]
        yy[e0:e1] = np.matmul(y3[:, None, :], y3[..., None])[:, 0, 0]
    lo = np.array([q.lower for q in params], float)
    hi = np.array([q.upper for q in params], float)
    return Blocks(G, b, yy, np.diff(bounds), lo, hi)


def extend_blocks(base: Blocks, X0: np.ndarray, Xn: np.ndarray, y: np.ndarray, bounds: np.ndarray, params_new) -> Blocks:
    """Blocks of ``[X0, Xn]`` from the blocks of ``X0``: only the new columns' products are computed.

    Parameters
    ----------
    base : Blocks
        Blocks of ``X0`` (from :func:`blocks` with the same ``y`` and ``bounds``).
    X0 : numpy.ndarray, shape (n, p0)
        The design ``base`` was built from; columns in their own units (e.g.
        MPa mm, mm/s, dimensionless; see :func:`blocks`).
    Xn : numpy.ndarray, shape (n, k)
        New columns, each in its own unit (e.g. mm for a stop operator,
        dimensionless for a sign), as the effect defines them.
    y : numpy.ndarray, shape (n,)
        Measured force, N.
    bounds : numpy.ndarray, shape (n_exp + 1,)
        Row offsets of the experiments (a count of samples).
    params_new : sequence of Param
        One per column of ``Xn`` (their bounds are appended).

    Returns
    -------
    Blocks
        The blocks of ``[X0, Xn]``, equal to ``blocks(np.column_stack([X0, Xn]), y, bounds, ...)``.
    """
    ne, p0, k = len(bounds) - 1, X0.shape[1], Xn.shape[1]
    G = np.empty((ne, p0 + k, p0 + k))
    G[:, :p0, :p0] = base.G
    b = np.empty((ne, p0 + k))
    b[:, :p0] = base.b
    for e0, e1 in _equal_runs(bounds):
        Xn3, X03, y3 = _stacked(Xn, bounds, e0, e1), _stacked(X0, bounds, e0, e1), _stacked(y, bounds, e0, e1)
        Xn3t = Xn3.transpose(0, 2, 1)
        c = np.matmul(X03.transpose(0, 2, 1), Xn3)
        G[e0:e1, :p0, p0:] = c
        G[e0:e1, p0:, :p0] = c.transpose(0, 2, 1)
        G[e0:e1, p0:, p0:] = np.matmul(Xn3t, Xn3)
        b[e0:e1, p0:] = np.matmul(Xn3t, y3[..., None])[..., 0]
    lo = np.r_[base.lower, [q.lower for q in params_new]]
    hi = np.r_[base.upper, [q.upper for q in params_new]]
    return Blocks(G, b, base.yy, base.n, lo, hi)


def solve_bounded(G: np.ndarray, b: np.ndarray, lower: np.ndarray, upper: np.ndarray) -> np.ndarray:
    """Minimise ``θᵀGθ - 2bᵀθ`` subject to ``lower <= θ <= upper``.

    Columns are scaled to unit diagonal; a tiny ridge keeps parameters of
    absent columns (a valve missing from a training fold) at zero.

    Parameters
    ----------
    G : numpy.ndarray, shape (p, p)
        Gram matrix ``XᵀX``; entry (i, j) in the product of the units of
        columns i and j (e.g. mm²/s² for two ẋ columns in mm/s).
    b : numpy.ndarray, shape (p,)
        ``Xᵀy`` (column unit times N).
    lower, upper : numpy.ndarray, shape (p,)
        Bounds on each parameter, in its unit (N per column unit, e.g.
        N/mm/MPa, N, N s/mm); ``±inf`` for none.

    Returns
    -------
    numpy.ndarray, shape (p,)
        The bounded least-squares parameters θ, each in its unit (N per column unit).
    """
    p = len(b)
    d = np.sqrt(np.maximum(np.diag(G), 0))  # = np.clip(diag, 0, None): the same ufunc
    d[d == 0] = 1.0
    Gs = G / (d[:, None] * d) + _ridge(p)  # np.outer(d, d) is this product
    bs = b / d
    th = _chol_solve(Gs, bs) if p else None
    if th is None or not np.isfinite(th).all():  # non-finite input or not positive definite: scipy's checks and errors
        cf = cho_factor(Gs)
        th = cho_solve(cf, bs)
    th = th / d
    if (th >= lower - 1e-12).all() and (th <= upper + 1e-12).all():
        return th
    xs = _box_active_set(Gs, bs, lower * d, upper * d, th * d)
    if xs is not None:
        return xs / d
    cf = cho_factor(Gs)
    R = np.triu(cf[0]) if not cf[1] else np.triu(cf[0].T)
    c = solve_triangular(R.T, bs, lower=True)
    sol = lsq_linear(R, c, bounds=(lower * d, upper * d), method="bvls")
    return sol.x / d


_RIDGES: dict = {}


def _ridge(p: int) -> np.ndarray:
    """``1e-10 * np.eye(p)`` (read-only, cached per size: solve_bounded runs thousands of times per diagnosis)."""
    r = _RIDGES.get(p)
    if r is None:
        r = 1e-10 * np.eye(p)
        r.flags.writeable = False
        _RIDGES[p] = r
    return r


def _chol_solve(A: np.ndarray, rhs: np.ndarray) -> np.ndarray | None:
    """``cho_solve(cho_factor(A), rhs)`` for a finite float matrix, or None where ``cho_factor`` would raise.

    Calls the LAPACK routines ``dpotrf`` / ``dpotrs`` that :func:`scipy.linalg.cho_factor` and
    :func:`scipy.linalg.cho_solve` call, with the same arguments (upper factor, unclean, no
    overwrite), so the result is the same to the bit; only scipy's per-call checks and wrappers
    are skipped (they cost more than the solve on the few dozen parameters of a diagnosis).
    """
    c, info = _dpotrf(A, lower=0, clean=0, overwrite_a=0)
    if info != 0:
        return None
    x, info = _dpotrs(c, rhs, lower=0, overwrite_b=0)
    return x if info == 0 else None


def _box_active_set(Gs: np.ndarray, bs: np.ndarray, lo: np.ndarray, hi: np.ndarray, x0: np.ndarray) -> np.ndarray | None:
    """Exact minimiser of ``xᵀGs x - 2 bsᵀx`` on the box ``lo <= x <= hi`` (Gs positive definite), or None.

    Primal active-set method (Lawson-Hanson generalised to two-sided bounds),
    started from the clipped unconstrained minimiser ``x0``: solve on the free
    variables with the others held at their bounds; step back to the first
    bound crossed while infeasible, else release the bound variable whose
    multiplier has the wrong sign, until none has. Each step is a Cholesky
    solve of the free block: the same optimum as BVLS, far cheaper for the
    few dozen parameters of a diagnosis model. None after ``10 p + 10``
    steps (the caller falls back to BVLS).
    """
    p = len(bs)
    x = np.clip(x0, lo, hi)
    act = (x == lo) | (x == hi)
    tol = 1e-12 * max(1.0, float(np.abs(bs).max()))
    with np.errstate(divide="ignore", invalid="ignore"):  # the step ratios below divide by zero where x does not move
        for _ in range(10 * p + 10):
            F = ~act
            z = x.copy()
            fi = F.nonzero()[0]
            if len(fi):
                ai = act.nonzero()[0]
                rhs = bs[fi] - Gs[fi[:, None], ai] @ x[ai]  # the rows/columns np.ix_(F, act) selects, C-ordered like it
                GF = Gs[fi[:, None], fi]
                zF = _chol_solve(GF, rhs)
                if zF is None:
                    zF = cho_solve(cho_factor(GF), rhs)  # raises as before
                z[fi] = zF
            else:
                zF = z[fi]
            if (zF >= lo[fi]).all() and (zF <= hi[fi]).all():
                x = z
                w = bs - Gs @ x  # minus half the gradient: <= 0 at an optimal lower bound, >= 0 at an optimal upper one
                viol = np.where(act & (x == lo), w, 0.0) - np.where(act & (x == hi), w, 0.0)
                k = int(viol.argmax())
                if viol[k] <= tol:
                    return x
                act[k] = False
            else:
                dz = z - x
                step = np.minimum(np.where(F & (dz < 0), (lo - x) / dz, np.inf), np.where(F & (dz > 0), (hi - x) / dz, np.inf))
                k = int(step.argmin())
                x = x + min(max(float(step[k]), 0.0), 1.0) * dz
                x[k] = lo[k] if dz[k] < 0 else hi[k]
                act |= F & ((x <= lo) | (x >= hi))
                act[k] = True
                x = x.clip(lo, hi)
    return None


@dataclass(frozen=True)
class ModelFit:
    """A fitted model: eq. 14 plus zero or more effects.

    Attributes
    ----------
    effects : tuple[str]
        Effect ids included (keys of :data:`~vvea_design.identification.effects.REGISTRY`).
    shapes : dict
        Fitted shape parameter per effect id (NaN when the effect has none).
    params : list[Param]
        Amplitude parameters in column order.
    theta : array
        Fitted amplitudes (units of ``params``).
    se : array
        Cluster-robust standard errors (experiments as clusters).
    rmse_N : float
        In-sample RMS residual (N).
    n_rows : int
        Samples used.
    groups : dict
        Column slice per effect (``"eq14"`` for the baseline).
    ctx : dict
        Context the model was fitted with.
    """

    effects: tuple
    shapes: dict
    params: list
    theta: np.ndarray
    se: np.ndarray
    rmse_N: float
    n_rows: int
    groups: dict
    ctx: dict = field(default_factory=dict)
    shape_se: dict = field(default_factory=dict)

    @property
    def values(self) -> dict[str, float]:
        """Parameter name -> value."""
        return {q.name: float(v) for q, v in zip(self.params, self.theta)}

    @property
    def errors(self) -> dict[str, float]:
        """Parameter name -> standard error."""
        return {q.name: float(v) for q, v in zip(self.params, self.se)}

    def effect_values(self, effect_id: str) -> dict[str, float]:
        """Amplitude name -> value of one effect (``"eq14"`` for the baseline).

        Parameters
        ----------
        effect_id : str
            An effect id of this model (a key of :attr:`groups`), or ``"eq14"`` for the baseline.

        Returns
        -------
        dict of str to float
            Parameter name to fitted value, each in its parameter's own unit (see ``params``).

        Raises
        ------
        KeyError
            When ``effect_id`` is not part of this model.
        """
        sl = self.groups[effect_id]
        return {q.name: float(v) for q, v in zip(self.params[sl], self.theta[sl])}

    def effect_errors(self, effect_id: str) -> dict[str, float]:
        """Amplitude name -> cluster-robust standard error of one effect.

        Parameters
        ----------
        effect_id : str
            An effect id of this model (a key of :attr:`groups`), or ``"eq14"`` for the baseline.

        Returns
        -------
        dict of str to float
            Parameter name to standard error (experiments as clusters), in the parameter's own unit.

        Raises
        ------
        KeyError
            When ``effect_id`` is not part of this model.
        """
        sl = self.groups[effect_id]
        return {q.name: float(v) for q, v in zip(self.params[sl], self.se[sl])}

    def _ctx_for(self, D: FitData) -> dict:
        """The context the model was fitted with, when it belongs to ``D``; else rebuilt from this fit."""
        if self.ctx and all(len(v) == D.n for v in self.ctx.values() if isinstance(v, np.ndarray)):
            return self.ctx
        return self.context(D)

    def context(self, D: FitData) -> dict:
        """Context rebuilt from this fit on ``D``: its damping force and its force without model-force terms.

        Parameters
        ----------
        D : FitData
            The campaign's samples (x in mm, ẋ in mm/s, p2 in MPa, valve in deg, times in s, force in N).

        Returns
        -------
        dict of str to numpy.ndarray
            Arrays of shape (n,) over the samples of ``D``, in N: ``"damping_force_N"`` (the baseline's
            L(γ)ẋ, see :meth:`damping_force`); ``"residual_all_N"`` when the fit context has one of the same
            length (kept as fitted); ``"model_force_N"`` when an effect of the model needs it (the model's
            force with its model-force terms left at zero).

        Raises
        ------
        ValueError
            When ``D`` has another number of valve positions than the model (see :meth:`damping_force`).
        """
        ctx = {"damping_force_N": self.damping_force(D)}
        keep = self.ctx.get("residual_all_N")  # per-experiment nuisance terms keep the residual they were fitted with
        if keep is not None and len(keep) == D.n:
            ctx["residual_all_N"] = keep
        if any("model_force_N" in REGISTRY[e].needs for e in self.effects):
            X = assemble(D, self.effects, self.shapes, ctx)[0]  # model-force terms give zero columns here
            ctx["model_force_N"] = X @ self.theta
        return ctx

    def design(self, D: FitData) -> np.ndarray:
        """Design matrix of this model on ``D``.

        Parameters
        ----------
        D : FitData
            The campaign's samples (x in mm, ẋ in mm/s, p2 in MPa, valve in deg, times in s, force in N).

        Returns
        -------
        numpy.ndarray
            Shape (n, p): one row per sample, one column per parameter, each column in its own unit
            (e.g. MPa mm for ``p2 x``, mm/s for ``ẋ``, dimensionless for ``sign(ẋ)``), such that
            ``design(D) @ theta`` is a force in N.
        """
        return assemble(D, self.effects, self.shapes, self._ctx_for(D))[0]

    def predict(self, D: FitData) -> np.ndarray:
        """Model force (N) at the samples of ``D``.

        Parameters
        ----------
        D : FitData
            The campaign's samples (x in mm, ẋ in mm/s, p2 in MPa, valve in deg, times in s, force in N).

        Returns
        -------
        numpy.ndarray
            Shape (n,): the fitted model's force at every sample, N (tension positive).
        """
        return self.design(D) @ self.theta

    def contribution(self, D: FitData, effect_id: str) -> np.ndarray:
        """Force (N) the effect adds relative to the same model (same amplitudes) without it.

        Parameters
        ----------
        D : FitData
            The campaign's samples (x in mm, ẋ in mm/s, p2 in MPa, valve in deg, times in s, force in N).
        effect_id : str
            An effect id of this model.

        Returns
        -------
        numpy.ndarray
            Shape (n,): model force minus the force of the model without ``effect_id`` (its other
            amplitudes unchanged), N, per sample.

        Raises
        ------
        KeyError
            When ``effect_id`` is not part of this model.
        """
        ctx = self._ctx_for(D)
        f = assemble(D, self.effects, self.shapes, ctx)[0] @ self.theta  # one design alive at a time
        others = tuple(e for e in self.effects if e != effect_id)
        Xo, _, go = assemble(D, others, self.shapes, ctx)
        keep = np.ones(len(self.theta), bool)
        keep[self.groups[effect_id]] = False
        return f - Xo @ self.theta[keep]

    def damping_force(self, D: FitData) -> np.ndarray:
        """Linear damping force L(γ)ẋ of the fitted baseline (N).

        Parameters
        ----------
        D : FitData
            The campaign's samples (x in mm, ẋ in mm/s, p2 in MPa, valve in deg, times in s, force in N).

        Returns
        -------
        numpy.ndarray
            Shape (n,): each sample's velocity times the fitted damping coefficient (N s/mm) of its valve
            position, N.

        Raises
        ------
        ValueError
            When ``D`` has another number of valve positions than the model has damping parameters.
        """
        L = self.theta[2 : self.groups["eq14"].stop]  # one damping column per valve, zero at the other valves' samples
        if len(L) != len(D.valves):
            raise ValueError(f"the model has {len(L)} valve damping parameters, the data {len(D.valves)} valve positions")
        return D.v * L[D.valve_idx]


def _cluster_se(Bk: Blocks, theta: np.ndarray, rows: np.ndarray) -> np.ndarray:
    G = Bk.G[rows].sum(0)
    scores = Bk.b[rows] - np.einsum("eij,j->ei", Bk.G[rows], theta)
    meat = scores.T @ scores
    ne = len(rows)
    d = np.sqrt(np.clip(np.diag(G), 1e-300, None))
    Gi = np.linalg.pinv(G / np.outer(d, d)) / np.outer(d, d)
    cov = Gi @ meat @ Gi * (ne / max(ne - 1, 1))
    return np.sqrt(np.clip(np.diag(cov), 0, None))


def _needs(effects, key: str) -> bool:
    return any(key in REGISTRY[e].needs for e in effects)


def fit_model(
    D: FitData,
    effects=(),
    *,
    experiments: np.ndarray | None = None,
    shapes: dict | None = None,
    ctx: dict | None = None,
    refine: bool = True,
    memo: dict | None = None,
    memo_groups: np.ndarray | None = None,
) -> ModelFit:
    """Fit eq. 14 plus ``effects`` to the experiments ``experiments`` of ``D``.

    Shape parameters not given in ``shapes`` are searched on the effect's
    grid one effect at a time (two sweeps), then refined by a bounded scalar
    search (in log space for ``log_shape`` effects) when ``refine``.

    Parameters
    ----------
    D : FitData
    effects : sequence of str
        Effect ids from :data:`vvea_design.identification.effects.REGISTRY`.
    experiments : int array, optional
        Experiment indices to fit, 0 .. n_exp-1 in run order (dimensionless;
        default all).
    shapes : dict, optional
        Fixed shape values per effect id.
    ctx : dict, optional
        Context (damping force, model force, residual); built from simpler
        fits when needed and not given.
    refine : bool
        Refine grid-searched shape parameters.
    memo, memo_groups : dict and int array (one label per experiment), optional
        Share the shape search's Gram blocks between fits of the same ``D``,
        ``effects`` and ``ctx`` on different unions of groups of experiments
        (the fold refits of a jackknife): ``memo`` keeps, per shape values
        tried, the blocks summed per group; a fit whose ``experiments`` are
        whole groups reuses them (leave-groups-out by summing the other
        groups' Gram matrices) instead of rebuilding the design. Pass the
        same empty dict to each of those fits; ignored when the experiments
        are not whole groups.

    Returns
    -------
    ModelFit
    """
    effects = tuple(effects)
    rows = np.arange(D.n_exp) if experiments is None else np.asarray(experiments, int)
    shapes = dict(shapes or {})
    if ctx is None:
        ctx = auto_context(D, effects, rows, shapes)
    free = [e for e in effects if REGISTRY[e].shape is not None and e not in shapes]
    grids = {e: np.asarray(REGISTRY[e].grid(D, ctx), float) for e in free}
    for e in free:  # start values: the middle of each grid
        g = grids[e]
        shapes[e] = float(g[len(g) // 2]) if len(g) else np.nan

    best_fit: dict = {}  # the best shape values a full fit was made at, and that fit (the final fit is often one of them)

    def train_sse(sh):
        X, params, _ = assemble(D, effects, sh, ctx)
        Bk = blocks(X, D.y, D.bounds, params)
        del X
        th = solve_bounded(Bk.G[rows].sum(0), Bk.b[rows].sum(0), Bk.lower, Bk.upper)
        res = (float(Bk.sse(th, rows).sum()), th, Bk, params)
        if not best_fit or res[0] < best_fit["fit"][0]:
            best_fit.update(key=tuple(sorted(sh.items())), fit=res)
        return res

    grouped = None
    if memo is not None and memo_groups is not None:
        labels, gi = np.unique(np.asarray(memo_groups), return_inverse=True)
        in_rows = np.zeros(len(labels), bool)
        in_rows[np.unique(gi[rows])] = True
        if np.array_equal(np.sort(rows), np.flatnonzero(in_rows[gi])):  # the experiments are whole groups
            grouped = (len(labels), gi, in_rows)

    def memo_cost(key, make_blocks):
        """Training SSE from the per-group sums of the blocks of shape values ``key`` (built once by ``make_blocks``)."""
        nl, gi, in_rows = grouped
        ent = memo.get(key)
        if ent is None:
            Bk = make_blocks()
            ent = (np.stack([Bk.G[gi == j].sum(0) for j in range(nl)]), np.stack([Bk.b[gi == j].sum(0) for j in range(nl)]),
                   np.array([Bk.yy[gi == j].sum() for j in range(nl)]), Bk.lower, Bk.upper)
            memo[key] = ent
        Gg, bg, yyg, lo, hi = ent
        G, b = Gg[in_rows].sum(0), bg[in_rows].sum(0)
        th = solve_bounded(G, b, lo, hi)
        return float(yyg[in_rows].sum() - 2 * b @ th + th @ G @ th)

    def full_cost(sh):
        if grouped is None:
            return train_sse(sh)[0]
        return memo_cost(("design",) + tuple(sorted(sh.items())), lambda: train_sse(sh)[2])

    def cost_fn(e):
        """SSE as a function of effect e's shape, others fixed (blocks of the rest computed once)."""
        eff = REGISTRY[e]
        if not all(REGISTRY[o].nested for o in effects):
            return lambda val: full_cost(dict(shapes, **{e: float(val)}))
        rest = tuple(o for o in effects if o != e)
        rest_key = tuple(sorted((k, v) for k, v in shapes.items() if k != e))
        base = []  # blocks of the rest, built at the first evaluation that needs them

        def extended(val):
            if not base:
                X0, p0, _ = assemble(D, rest, shapes, ctx)
                base.extend([X0, blocks(X0, D.y, D.bounds, p0)])
            X0, B0 = base
            return extend_blocks(B0, X0, effect_columns(D, eff, float(val), ctx), D.y, D.bounds, pe)

        pe = eff.params(D)

        def cost(val):
            if grouped is not None:
                return memo_cost(("extend", e, float(val)) + rest_key, lambda: extended(val))
            Bk = extended(val)
            th = solve_bounded(Bk.G[rows].sum(0), Bk.b[rows].sum(0), Bk.lower, Bk.upper)
            return float(Bk.sse(th, rows).sum())

        return cost

    n_sweeps = 2 if len(free) > 1 else 1
    for sweep in range(n_sweeps):
        for e in free:
            g = grids[e]
            if len(g) == 0:
                continue
            cost = cost_fn(e)
            costs = [cost(val) for val in g]
            k = int(np.argmin(costs))
            shapes[e] = float(g[k])
            if refine and len(g) > 1 and sweep == n_sweeps - 1:
                lo, hi = g[max(k - 1, 0)], g[min(k + 1, len(g) - 1)]
                if hi > lo:
                    lg = REGISTRY[e].log_shape
                    fwd, back = (np.log, np.exp) if lg else (float, float)
                    r = minimize_scalar(lambda z, back=back, cost=cost: cost(back(z)), bounds=(fwd(lo), fwd(hi)), method="bounded", options={"xatol": REGISTRY[e].shape_xtol})
                    if r.fun <= costs[k]:
                        shapes[e] = float(back(r.x))
    same = best_fit and best_fit["key"] == tuple(sorted(shapes.items()))
    sse, th, Bk, params = best_fit["fit"] if same else train_sse(shapes)
    params, groups = _layout(D, effects)
    se = _cluster_se(Bk, th, rows)
    n_rows = int(Bk.n[rows].sum())
    return ModelFit(effects, shapes, params, th, se, float(np.sqrt(sse / max(n_rows, 1))), n_rows, groups, ctx)


def auto_context(D: FitData, effects, experiments, shapes: dict | None = None, iters: int = 2) -> dict:
    """Context for ``effects`` built from simpler fits on ``experiments``.

    ``damping_force_N``: the linear damping of eq. 14 with the other effects
    (refitted ``iters`` times with the effects that replace damping columns,
    whose eq.-14 estimate is biased low where the relief valve caps the
    force); ``model_force_N``: the force of the model without the terms
    that need it (refitted ``iters`` times); ``residual_N``: measurement −
    that model.

    Parameters
    ----------
    D : FitData
        The campaign.
    effects : sequence of str
        Effect ids of the model the context is for.
    experiments : array_like of int
        Indices of the experiments to fit, 0 .. n_exp-1 in run order (dimensionless).
    shapes : dict, optional
        Fixed shape values per effect id (in each effect's shape unit).
    iters : int
        Refits of the damping and model force with all the effects.

    Returns
    -------
    dict
        ``damping_force_N``, ``model_force_N``, ``residual_N`` and
        ``residual_all_N``, arrays per sample, N; empty when no effect needs context.
    """
    effects = tuple(effects)
    rows = np.asarray(experiments, int)
    if not effects or not any(REGISTRY[e].needs for e in effects):
        return {}
    shapes = dict(shapes or {})
    plain = tuple(e for e in effects if not REGISTRY[e].needs)
    fit = fit_model(D, plain, experiments=rows, shapes={k: v for k, v in shapes.items() if k in plain}, ctx={})
    ctx = fit.context(D)
    ctx["model_force_N"] = fit.predict(D)
    ctx["residual_N"] = D.y - ctx["model_force_N"]
    ctx["residual_all_N"] = ctx["residual_N"]
    needy = tuple(e for e in effects if REGISTRY[e].needs)
    if _needs(needy, "damping_force_N") or _needs(needy, "model_force_N"):
        for _ in range(iters):
            sh = {k: v for k, v in shapes.items()}
            f = fit_model(D, effects, experiments=rows, shapes=sh, ctx=ctx, refine=False)
            new = f.context(D)
            ctx = dict(ctx, damping_force_N=new["damping_force_N"])
            if "model_force_N" in new:
                ctx["model_force_N"] = new["model_force_N"]
    return ctx


def relief_context(D: FitData, effects, experiments, shapes: dict | None = None, start: dict | None = None, iters: int = 3) -> dict:
    """Context of effects that replace damping columns (the relief valve): the unbiased damping force.

    Starting from ``start`` (or eq. 14 with the other effects, whose L is
    biased low where the valve caps the force), the model is refitted
    ``iters`` times, each time with the damping force of the previous fit,
    so that the samples deemed capped follow from an unbiased L.

    Parameters
    ----------
    D : FitData
        The campaign.
    effects : sequence of str
        Effect ids of the model (including the one that replaces damping columns).
    experiments : array_like of int
        Indices of the experiments to fit, 0 .. n_exp-1 in run order (dimensionless).
    shapes : dict, optional
        Fixed shape values per effect id (in each effect's shape unit).
    start : dict, optional
        Starting context (see :func:`auto_context`); default built by :func:`auto_context`.
    iters : int
        Number of refits.

    Returns
    -------
    dict
        The context, with ``damping_force_N`` (per sample, N) from the last refit.
    """
    rows = np.asarray(experiments, int)
    ctx0 = dict(start) if start is not None else auto_context(D, effects, rows, shapes, iters=0)
    # The iteration has a wrong fixed point: from an L biased low, fast experiments look closed and
    # keep L low. So it also starts from the L of the slow experiments (which the valve cannot cap),
    # and the start whose converged fit has the smaller training error wins.
    starts = [ctx0]
    peak = np.array([np.max(np.abs(D.v[D.bounds[e] : D.bounds[e + 1]])) if D.bounds[e + 1] > D.bounds[e] else 0.0 for e in rows])
    slow = rows[peak <= np.quantile(peak, 0.4)] if len(rows) else rows
    if len(np.unique(D.valve_idx[np.isin(D.exp, slow)])) == len(D.valves) and len(slow) < len(rows):
        f_slow = fit_model(D, (), experiments=slow, ctx={})
        starts.append(dict(ctx0, damping_force_N=f_slow.damping_force(D)))
    best = None
    for ctx in starts:
        for _ in range(iters):
            f = fit_model(D, effects, experiments=rows, shapes=dict(shapes or {}), ctx=ctx, refine=False)
            ctx = dict(ctx, damping_force_N=f.damping_force(D))
        cost = fit_model(D, effects, experiments=rows, shapes=dict(shapes or {}), ctx=ctx, refine=False).rmse_N if len(starts) > 1 else 0.0
        if best is None or cost < best[0]:
            best = (cost, ctx)
    return best[1]


# ------------------------------------------------------------------ eq. 14
def fit_eq14(rec: Recordings | FitData) -> ModelFit:
    """Fit the paper's eq. 14 (g, C, one L per valve) to a campaign.

    Parameters
    ----------
    rec : Recordings or FitData

    Returns
    -------
    ModelFit
        Parameters ``g`` (N/mm/MPa), ``C`` (N), ``L(γ)`` (N s/mm) with
        cluster-robust standard errors.
    """
    D = rec if isinstance(rec, FitData) else FitData.from_recordings(rec)
    return fit_model(D, ())


def table3(fit: ModelFit) -> pd.DataFrame:
    """Table 3's layout: parameter, unit, value, standard error, paper value.

    The paper calls the Coulomb friction ``B`` in Table 3 and ``C`` in eq. 14.

    Parameters
    ----------
    fit : ModelFit
        A fit with the eq.-14 group (e.g. from :func:`fit_eq14`).

    Returns
    -------
    pandas.DataFrame
        Columns ``parameter``, ``unit`` (N/mm/MPa, N, N s/mm), ``value``,
        ``std_error`` (same unit) and ``paper`` (Table 3's value, NaN if none).
    """
    rows = []
    sl = fit.groups["eq14"]
    for q, v, s in zip(fit.params[sl], fit.theta[sl], fit.se[sl]):
        name = "B (=C)" if q.name == "C" else q.name
        rows.append(
            dict(parameter=name, unit=q.unit, value=float(v), std_error=float(s), paper=PAPER_TABLE3.get(q.name, np.nan))
        )
    return pd.DataFrame(rows)


def format_table3(df: pd.DataFrame) -> str:
    """Plain-text rendering of :func:`table3` (Parameter / Unit / Value ± se / Paper).

    Parameters
    ----------
    df : pandas.DataFrame
        Output of :func:`table3`.

    Returns
    -------
    str
        One header line and one line per parameter, values with 2 decimals in their units.
    """
    lines = [f"{'Parameter':<10} {'Unit':<10} {'Value':>22} {'Paper':>9}"]
    for r in df.itertuples():
        val = f"{r.value:10.2f} ± {r.std_error:<8.2f}"
        pap = "" if not np.isfinite(r.paper) else f"{r.paper:9.2f}"
        lines.append(f"{r.parameter:<10} {r.unit:<10} {val:>22} {pap:>9}")
    return "\n".join(lines)


def error_band_pct(D: FitData, force_model_N: np.ndarray) -> tuple[float, float]:
    """Model error (model - measured) in % of the nominal force, min and max.

    The nominal force of an experiment is its largest measured |force|; the
    paper's band for eq. 14 is -9.5 % ... +12 %.

    Parameters
    ----------
    D : FitData
        The campaign (measured force in N, experiment bounds).
    force_model_N : numpy.ndarray, shape (D.n,)
        Model force per sample, N.

    Returns
    -------
    lowest, highest : float
        Smallest and largest model error, % of the experiment's nominal force.
    """
    nom = np.zeros(D.n)
    for e in range(D.n_exp):
        a, b = D.bounds[e], D.bounds[e + 1]
        nom[a:b] = np.max(np.abs(D.y[a:b]))
    err = 100.0 * (force_model_N - D.y) / nom
    return float(err.min()), float(err.max())


# ------------------------------------------------------------------ identifiability
@dataclass(frozen=True)
class Identifiability:
    """Whether the recordings can separate the fitted parameters.

    Attributes
    ----------
    n_parameters, n_experiments : int
    condition_number : float
        Of the column-scaled design matrix (ratio of its extreme singular values).
    inseparable : list[list[str]]
        Groups of parameters the data cannot tell apart: a combination of
        their columns has less than ``tolerance`` of a column's norm.
    no_data : list[str]
        Parameters whose column is zero (e.g. a valve with no moving samples).
    errors_reliable : bool
        Cluster-robust standard errors need more experiments than parameters.
    messages : list[str]
        What to tell the user.
    """

    n_parameters: int
    n_experiments: int
    condition_number: float
    inseparable: list
    no_data: list
    errors_reliable: bool
    messages: list

    @property
    def unreliable_parameters(self) -> set:
        """Parameters whose value or uncertainty the data do not determine."""
        if not self.errors_reliable:
            return set()  # every error is unreliable; the values may still be fine
        return {n for grp in self.inseparable for n in grp} | set(self.no_data)

    def to_dict(self) -> dict:
        """Plain-JSON dictionary of the fields.

        Returns
        -------
        dict
            JSON-ready: ``n_parameters`` and ``n_experiments`` (counts), ``condition_number``
            (dimensionless), ``inseparable`` (groups of parameter names), ``no_data`` (parameter names),
            ``errors_reliable`` and ``messages``.
        """
        return asdict(self)


def identifiability(fit: ModelFit, D: FitData, tolerance: float = 0.1) -> Identifiability:
    """Check rank and conditioning of the fit's design on ``D`` (issue 11 item 10).

    The design's columns are scaled to unit norm; an eigenvector of the
    scaled normal matrix with eigenvalue below ``tolerance²`` is a
    combination of parameters the data cannot determine (its columns
    combine to less than ``tolerance`` = 10 % of a column's norm: the
    variance of that combination is inflated more than 100-fold against
    independent columns, the usual "severe collinearity" mark), and the
    parameters with a large share in it (|component| > 0.3) are reported
    together. With no more experiments than parameters the
    cluster-robust (experiments as clusters) standard errors are not
    available.

    Parameters
    ----------
    fit : ModelFit
        The fitted model.
    D : FitData
        The data it was fitted to.
    tolerance : float
        Smallest norm of a column combination, as a fraction of a column's norm.

    Returns
    -------
    Identifiability
        Condition number, inseparable groups, whether errors are reliable, messages.
    """
    X = fit.design(D)
    names = [q.name for q in fit.params]
    G = X.T @ X
    d = np.sqrt(np.clip(np.diag(G), 0, None))
    no_data = [names[j] for j in np.flatnonzero(d <= 1e-12 * max(d.max(), 1e-300))]
    keep = np.flatnonzero(d > 1e-12 * max(d.max(), 1e-300))
    Gs = G[np.ix_(keep, keep)] / np.outer(d[keep], d[keep])
    lam, V = np.linalg.eigh(Gs)
    lam = np.clip(lam, 0, None)
    cond = float(np.sqrt(lam.max() / lam.min())) if lam.min() > 0 else float("inf")
    groups = []
    for i in np.flatnonzero(lam < tolerance**2):
        grp = [names[keep[j]] for j in np.flatnonzero(np.abs(V[:, i]) > 0.3)]
        if grp and grp not in groups:
            groups.append(grp)
    ne = int(D.n_exp)
    reliable = ne > len(names)
    msgs = []
    for grp in groups:
        msgs.append(
            f"the recordings cannot separate {' and '.join(grp)}: a combination of them hardly changes the force "
            "(e.g. one speed per valve makes C sign(ẋ) and L ẋ alike; one pressure leaves g p2 x alone); "
            "their values are not determined and no uncertainty is given for them -- record more speeds, valves or pressures"
        )
    for n in no_data:
        msgs.append(f"no moving samples inform {n}: it is not identified")
    if not reliable:
        msgs.append(
            f"only {ne} experiment(s) for {len(names)} parameters: cluster-robust standard errors (experiments as "
            "clusters) need more experiments than parameters, so no uncertainties are given"
        )
    return Identifiability(len(names), ne, cond, groups, no_data, reliable, msgs)


# ------------------------------------------------------------------ figures & files
def plot_fig10(rec: Recordings, D: FitData, fmod: np.ndarray, p2_MPa: float, fig=None):
    """Fig. 10 for one charge pressure: measurement, model and error per valve (rows) and speed (columns).

    Error is measurement − model. Repeated test conditions are drawn in the
    same panel.

    Parameters
    ----------
    rec : Recordings
        The campaign (its ``experiments`` table, run order).
    D : FitData
        The fitted samples (force N, displacement mm).
    fmod : array
        Model force per sample of ``D`` (N).
    p2_MPa : float
        Charge pressure whose experiments are drawn (MPa).
    fig : matplotlib Figure, optional
        Figure to draw into (default: a new one sized to the grid).

    Returns
    -------
    matplotlib.figure.Figure
    """
    import matplotlib.pyplot as plt

    ex = rec.experiments.reset_index(drop=True)
    speeds = sorted(ex["speed_mm_s"].unique())
    valves = sorted(ex["valve_deg"].unique())
    sel = ex.index[ex["p2_MPa"] == p2_MPa]
    nr, nc = len(valves), len(speeds)
    if fig is None:
        fig = plt.figure(figsize=(2.9 * nc + 1.2, 1.75 * nr + 1.3))
    # Margins in inches, set once: the labels' sizes are fixed (7-9 pt), and the automatic
    # layout engines measure every tick label of the ~90 axes (it was ~80 % of the figure's time).
    W, H = fig.get_figwidth(), fig.get_figheight()
    fig.subplots_adjust(left=0.8 / W, right=1.0 - 0.62 / W, bottom=0.5 / H, top=1.0 - 1.0 / H,
                        wspace=0.5 / ((W - 1.42 - 0.5 * (nc - 1)) / nc), hspace=0.12 / ((H - 1.5 - 0.12 * (nr - 1)) / nr))
    # one x range for every panel, set rather than shared: a 90-axes shared group makes every
    # limit look-up walk the whole group
    axes = fig.subplots(nr, nc, squeeze=False)
    cell = {k: (valves.index(ex.loc[k, "valve_deg"]), speeds.index(ex.loc[k, "speed_mm_s"])) for k in sel}
    # the right-hand (error) axes, made before any data is drawn: a twin made after the shared x
    # axes hold data re-scales the whole shared group
    twins = {ij: axes[ij].twinx() for ij in sorted(set(cell.values()))}
    err_lim = 1.0
    for k in sel:
        a, b = D.bounds[k], D.bounds[k + 1]
        err_lim = max(err_lim, float(np.max(np.abs(D.y[a:b] - fmod[a:b]))) if b > a else 0.0)
    for k in sel:
        i, j = cell[k]
        a, b = D.bounds[k], D.bounds[k + 1]
        ax = axes[i, j]
        ax.plot(D.x[a:b], D.y[a:b], ".", ms=1.5, color="C0")
        ax.plot(D.x[a:b], fmod[a:b], "-", lw=0.9, color="k")
        twins[(i, j)].plot(D.x[a:b], D.y[a:b] - fmod[a:b], "-", lw=0.7, color="C3")
    for (i, j), tw in twins.items():
        tw.set_ylim(-1.1 * err_lim, 1.1 * err_lim)
        tw.tick_params(labelsize=7, colors="C3")
        if j != nc - 1:
            tw.set_yticklabels([])
        else:
            tw.set_ylabel("meas. − model [N]", fontsize=7, color="C3")
    for i, v in enumerate(valves):
        axes[i, 0].set_ylabel(f"γ = {v:g}°\nforce [N]", fontsize=8)
    for j, sp in enumerate(speeds):
        axes[0, j].set_title(f"ẋ = {sp:g} mm/s", fontsize=9)
        axes[-1, j].set_xlabel("displacement x [mm]", fontsize=8)
    xs = [D.x[D.bounds[k]:D.bounds[k + 1]] for k in sel if D.bounds[k + 1] > D.bounds[k]]
    if xs:
        lo, hi = min(float(v.min()) for v in xs), max(float(v.max()) for v in xs)
        pad = 0.05 * (hi - lo) or 0.5
        for ax in axes.flat:
            ax.set_xlim(lo - pad, hi + pad)
    for ax in axes[:-1].flat:
        ax.tick_params(labelbottom=False)
    for ax in axes.flat:
        ax.tick_params(labelsize=7)
        if not ax.lines:
            ax.text(0.5, 0.5, "not recorded", ha="center", va="center", transform=ax.transAxes, fontsize=7, color="0.5")
    handles = [
        plt.Line2D([], [], color="C0", marker=".", ls="", label="measurement"),
        plt.Line2D([], [], color="k", label="model eq. 14"),
        plt.Line2D([], [], color="C3", label="error = measurement − model (right axis)"),
    ]
    fig.suptitle(f"Fig. 10 — eq. 14 against the recordings at p2 = {p2_MPa:g} MPa ({len(sel)} experiments)",
                 fontsize=11, y=1.0 - 0.08 / H, va="top")
    fig.legend(handles=handles, loc="upper center", bbox_to_anchor=(0.5, 1.0 - 0.35 / H), ncol=3,
               fontsize=8, frameon=False)
    return fig


def _fig10_name(p2: float) -> str:
    """File name of Fig. 10 for one pressure (``2.5`` -> ``..._p2_2p5MPa.png``)."""
    return f"fig10_model_vs_measurement_p2_{float(p2):g}MPa.png".replace(".", "p", 1) if "." in f"{float(p2):g}" else \
        f"fig10_model_vs_measurement_p2_{float(p2):g}MPa.png"


def plot_fig11(rec: Recordings, D: FitData, fmod: np.ndarray, fig=None):
    """Fig. 11: force over displacement of one slow experiment (lowest speed, middle pressure and valve).

    Repeated test conditions are fine (the first in run order is drawn).

    Parameters
    ----------
    rec : Recordings
        The campaign.
    D : FitData
        The fitted samples (force N, displacement mm).
    fmod : array
        Model force per sample of ``D`` (N).
    fig : matplotlib Figure, optional
        Figure to draw into.

    Returns
    -------
    fig : matplotlib.figure.Figure
    info : dict
        ``experiment``, ``max_abs_error_N``, ``max_force_N``.
    """
    import matplotlib.pyplot as plt

    ex = rec.experiments.reset_index(drop=True)
    sel = ex[ex["speed_mm_s"] == ex["speed_mm_s"].min()]
    ps = sorted(sel["p2_MPa"].unique())
    sel = sel[sel["p2_MPa"] == ps[len(ps) // 2]]
    vs = sorted(sel["valve_deg"].unique())
    k = int(sel.index[sel["valve_deg"] == vs[len(vs) // 2]][0])
    r = ex.loc[k]
    a, b = D.bounds[k], D.bounds[k + 1]
    err = D.y[a:b] - fmod[a:b]
    if fig is None:
        fig = plt.figure(figsize=(6.5, 5.5))
    ax, axe = fig.subplots(2, 1, sharex=True, gridspec_kw={"height_ratios": [3, 1]})
    ax.plot(D.x[a:b], D.y[a:b], ".", ms=3, label="measurement")
    ax.plot(D.x[a:b], fmod[a:b], "-", color="k", label="model eq. 14")
    ax.set_ylabel("force [N] (+ = tension)")
    ax.set_title(f"{r['experiment']}: ẋ = {r['speed_mm_s']:g} mm/s, p2 = {r['p2_MPa']:g} MPa, γ = {r['valve_deg']:g}°",
                 fontsize=10)
    ax.legend()
    axe.plot(D.x[a:b], err, "-", color="C3")
    axe.axhline(0, color="0.6", lw=0.6)
    axe.set_ylabel("meas. − model [N]")
    axe.set_xlabel("displacement x [mm]")
    tight_layout_once(fig)
    info = dict(
        experiment=str(r["experiment"]),
        max_abs_error_N=float(np.abs(err).max()) if len(err) else None,
        max_force_N=float(np.abs(D.y[a:b]).max()) if len(err) else None,
    )
    return fig, info


def write_identification(rec: Recordings, out_dir: str | Path, fit: ModelFit | None = None, figures: bool = True) -> dict:
    """Fit eq. 14 and write Table 3 (CSV), a JSON summary and Figs 10/11 (PNG).

    Parameters
    ----------
    rec : Recordings
    out_dir : path
        Created if missing. Files: ``table3.csv``, ``identification.json``,
        one ``fig10_model_vs_measurement_p2_<p>MPa.png`` per charge pressure,
        ``fig11_force_displacement.png``.
    fit : ModelFit, optional
        A precomputed eq.-14 fit.
    figures : bool
        Draw Figs 10 and 11 (skip for speed when only numbers are needed).

    Returns
    -------
    dict
        The JSON summary. ``identifiability`` says which parameters the data
        cannot separate (their ``std_error`` is ``null``); ``notes`` collects
        what the user must be told (how the file was read, identifiability).
    """
    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    D = FitData.from_recordings(rec)
    fit = fit or fit_model(D, ())
    ident = identifiability(fit, D)
    tab = table3(fit)
    bad = ident.unreliable_parameters
    unrel = (not ident.errors_reliable) | tab["parameter"].map(lambda n: ("C" if n == "B (=C)" else n) in bad)
    tab.loc[unrel, "std_error"] = np.nan
    tab.to_csv(out / "table3.csv", index=False)
    fmod = fit.predict(D)
    band = error_band_pct(D, fmod)
    f11 = None
    files = ["table3.csv", "identification.json"]
    for old in out.glob("fig10_model_vs_measurement*.png"):  # never leave a figure of an earlier run beside the new ones
        old.unlink()
    if figures:
        import matplotlib.pyplot as plt

        for p2 in sorted(rec.experiments["p2_MPa"].unique()):
            fig = plot_fig10(rec, D, fmod, float(p2))
            name = _fig10_name(float(p2))
            fig.savefig(out / name, dpi=100)
            plt.close(fig)
            files.append(name)
        fig, f11 = plot_fig11(rec, D, fmod)
        fig.savefig(out / "fig11_force_displacement.png", dpi=100)
        plt.close(fig)
        files.append("fig11_force_displacement.png")

    def _num(v):
        return None if v is None or not np.isfinite(v) else float(v)

    summary = dict(
        source=rec.source,
        model="eq14: f = g p2 x + L(gamma) xdot + C sign(xdot)",
        rows_read=rec.rows_read,
        rows_left_out=D.rows_left_out,
        rows_left_out_reason="samples at rest (start, turning point, end): friction is set-valued there",
        n_experiments=rec.n_experiments,
        velocity_fallback_experiments=rec.n_savgol,
        parameters={r.parameter: dict(value=float(r.value), std_error=_num(r.std_error), unit=r.unit, paper=_num(r.paper)) for r in tab.itertuples()},
        rmse_N=fit.rmse_N,
        error_band_pct=dict(ours=list(band), paper=list(PAPER_ERROR_BAND_PCT)),
        identifiability=ident.to_dict(),
        notes=list(rec.notes) + list(ident.messages),
        residual_sign="figures plot measurement - model",
        fig11=f11,
        files=files,
    )
    (out / "identification.json").write_text(json.dumps(summary, indent=2, allow_nan=False, default=_num))
    return summary
