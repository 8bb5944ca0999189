"""Bounded linear least squares from per-experiment normal-equation blocks.

Every fit is computed from the blocks ``G_e = X_eᵀX_e``, ``b_e = X_eᵀy_e`` of
each experiment (:func:`blocks`), so refitting without some experiments
(grouped cross-validation) costs a ``p x p`` solve, and adding columns
(:func:`extend_blocks`) computes only their products. The parameters carry
physical bounds (``g, C, L >= 0``): :func:`solve_bounded` solves exactly on
the box (an active-set method, BVLS as the fallback).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy.linalg import cho_factor, cho_solve, solve_triangular
from scipy.linalg.lapack import dpotrf as _dpotrf, dpotrs as _dpotrs
from scipy.optimize import lsq_linear

__all__ = ["Blocks", "blocks", "extend_blocks", "solve_bounded", "cluster_se"]


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


def cluster_se(Bk: Blocks, theta: np.ndarray, rows: np.ndarray) -> np.ndarray:
    """Cluster-robust (sandwich) standard errors of ``theta``, experiments as clusters.

    Samples within one run are not independent (correlated noise), so the
    naive i.i.d. errors are too small: the score of each experiment is one
    cluster of the sandwich ``G⁻¹ (Σ s_e s_eᵀ) G⁻¹``, with the small-sample
    factor ``n_e/(n_e - 1)``.

    Parameters
    ----------
    Bk : Blocks
        The design's per-experiment blocks (:func:`blocks`).
    theta : numpy.ndarray, shape (p,)
        The fitted parameters, each in its unit (N per column unit).
    rows : numpy.ndarray of int
        The experiments fitted (indices 0 .. n_exp-1, dimensionless).

    Returns
    -------
    numpy.ndarray, shape (p,)
        Standard error of each parameter, in its unit (N per column unit).
    """
    G = Bk.G[rows].sum(0)
    scores = Bk.b[rows] - np.einsum("eij,j->ei", Bk.G[rows], theta)
    meat = scores.T @ scores
    ne = len(rows)
    d = np.sqrt(np.clip(np.diag(G), 1e-300, None))
    Gi = np.linalg.pinv(G / np.outer(d, d)) / np.outer(d, d)
    cov = Gi @ meat @ Gi * (ne / max(ne - 1, 1))
    return np.sqrt(np.clip(np.diag(cov), 0, None))
