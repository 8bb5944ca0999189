"""Tests of the bounded least squares: the solver against BVLS, physical signs, and grouped cross-validation from
per-experiment Gram blocks (and their extension by new columns)."""

from __future__ import annotations

import numpy as np
import pytest
from scipy.optimize import lsq_linear

from vvea_design.identification.design import assemble
from vvea_design.identification.effects import REGISTRY
from vvea_design.identification.least_squares import blocks, extend_blocks, solve_bounded


def _objective(G, b, th):
    return float(th @ G @ th - 2 * b @ th)


def test_bounded_solver_equals_bvls_on_random_problems():
    rng = np.random.default_rng(3)
    n_bounded = 0
    for _ in range(300):
        p = int(rng.integers(2, 22))
        X = rng.normal(size=(120, p)) * rng.uniform(0.01, 100.0, p)
        if rng.uniform() < 0.3:
            X[:, int(rng.integers(p))] = 0.0  # a column absent from this training part
        y = X @ rng.normal(size=p) + 10 * rng.normal(size=120)
        lo = np.where(rng.uniform(size=p) < 0.6, 0.0, -np.inf)
        hi = np.where(rng.uniform(size=p) < 0.2, rng.uniform(0.1, 2.0, p), np.inf)
        G, b = X.T @ X, X.T @ y
        th = solve_bounded(G, b, lo, hi)
        assert np.all(th >= lo - 1e-12) and np.all(th <= hi + 1e-12)
        d = np.sqrt(np.diag(G))
        d[d == 0] = 1.0
        ref = lsq_linear(X / d, y, bounds=(lo * d, hi * d), method="bvls", tol=1e-14).x / d
        n_bounded += not np.allclose(np.clip(th, lo, hi), np.linalg.lstsq(X, y, rcond=None)[0])
        f, fr = _objective(G, b, th), _objective(G, b, ref)
        assert f <= fr + 1e-9 * abs(fr)
        live = np.diag(G) > 0
        assert np.allclose((th * d)[live], (ref * d)[live], rtol=1e-7, atol=1e-7 * np.max(np.abs(ref * d)))
    assert n_bounded > 100  # the active-set path was exercised, not only the unconstrained solve


def test_solve_bounded_respects_physical_signs():
    rng = np.random.default_rng(0)
    X = rng.normal(size=(200, 4))
    y = X @ np.array([1.0, -2.0, 0.5, 3.0]) + rng.normal(size=200) * 0.1
    lo = np.array([0.0, 0.0, -np.inf, 0.0])
    hi = np.full(4, np.inf)
    th = solve_bounded(X.T @ X, X.T @ y, lo, hi)
    assert np.all(th >= lo - 1e-12)
    assert th[1] == pytest.approx(0.0, abs=1e-9)  # the negative one is clamped
    assert th[3] == pytest.approx(3.0, abs=0.3)


def test_grouped_cv_from_gram_blocks_equals_refitting_without_the_fold(D):
    """Leave-experiments-out: the fold's solve from summed per-experiment blocks equals a least-squares refit without it."""
    X, params, _ = assemble(D, ("friction_along_stroke",), {})
    B = blocks(X, D.y, D.bounds, params)
    free = np.full(len(params), -np.inf), np.full(len(params), np.inf)
    folds = np.arange(D.n_exp) % 3
    for f in range(3):
        tr = np.flatnonzero(folds != f)
        rows = np.isin(D.exp, tr)
        th = solve_bounded(B.G[tr].sum(0), B.b[tr].sum(0), *free)
        ref = np.linalg.lstsq(X[rows], D.y[rows], rcond=None)[0]
        assert np.allclose(th, ref, rtol=1e-9, atol=1e-9 * np.max(np.abs(ref)))
        te = np.flatnonzero(folds == f)
        sse = B.sse(th, te)
        for k, e in enumerate(te):
            a, b = D.bounds[e], D.bounds[e + 1]
            ref_sse = float(np.sum((D.y[a:b] - X[a:b] @ th) ** 2))
            assert abs(sse[k] - ref_sse) <= 1e-9 * ref_sse + 1e-13 * B.yy[e]  # yy - 2 b.th + th.G.th cancels down from yy
    # and extending the blocks by new columns equals the blocks of the wider design
    Xn = REGISTRY["pressure_friction"].columns(D, np.nan, {})
    Bx = extend_blocks(B, X, Xn, D.y, D.bounds, REGISTRY["pressure_friction"].params(D))
    Bf = blocks(np.column_stack([X, Xn]), D.y, D.bounds, list(params) + list(REGISTRY["pressure_friction"].params(D)))
    np.testing.assert_allclose(Bx.G, Bf.G, rtol=1e-12, atol=1e-9)
