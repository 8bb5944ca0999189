"""Tests of the numerical machinery under ``diagnose``: bounded solver, design assembly, Gram blocks and their
per-fold reuse, the discretised sensor filter and the bounded column cache (small sizes, exact references)."""

from __future__ import annotations

import numpy as np
import pytest
from scipy.optimize import lsq_linear
from scipy.signal import bilinear

from vvea_design.identification import effects as fx
from vvea_design.identification.effects import REGISTRY, FitData, baseline_columns
from vvea_design.identification.identify import assemble, blocks, extend_blocks, fit_model, solve_bounded
from vvea_design.identification.recordings import recordings_from_frame
from vvea_design.identification.testbench import simulate, small_spec


@pytest.fixture(scope="module")
def D():
    spec = small_spec(seed=5, g_N_per_mm_MPa=21.0, C_N=140.0, noise_N=4.0, noise_rho=0.8)
    return FitData.from_recordings(recordings_from_frame(simulate(spec).frame, "sim"))


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


def test_assemble_equals_the_stacked_columns(D):
    """One preallocated design equals eq. 14's columns, masked, with each effect's columns stacked and transformed."""
    base = fit_model(D, ())
    ctx = base.context(D)
    ctx["model_force_N"] = base.predict(D)
    ctx["residual_N"] = ctx["residual_all_N"] = D.y - ctx["model_force_N"]
    cases = [
        ((), {}),
        (("gas_nonlinearity", "stiction"), {"gas_nonlinearity": 3e5, "stiction": 0.3}),
        (("relief_valve", "thermal"), {"relief_valve": 400.0, "thermal": 2.0}),
        (("stiction", "force_lag"), {"stiction": 0.3, "force_lag": 0.05}),
    ]
    for effects, shapes in cases:
        X, params, groups = assemble(D, effects, shapes, ctx)
        X0 = baseline_columns(D)[0].copy()
        cols = [X0]
        for e in effects:
            m = REGISTRY[e].damping_mask(D, shapes[e], ctx)
            if m is not None:
                X0[m, 2:] = 0.0
            cols.append(REGISTRY[e].columns(D, shapes[e], ctx))
        ref = np.column_stack(cols)
        for e in effects:
            if REGISTRY[e].transforms_design:
                ref = REGISTRY[e].transform(D, ref, shapes[e], ctx, eq14_first=True)  # the whole design, eq. 14 first
        assert X.shape == ref.shape == (D.n, len(params))
        np.testing.assert_array_equal(X, ref)
        assert groups["eq14"] == slice(0, X0.shape[1])


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


def test_second_order_filter_coefficients_equal_scipy_bilinear():
    for lag in (0.003, 0.05, 0.7, 3.0):
        for dt in (0.001, 0.02, 0.5):
            wn = 2 * 0.7071 / lag
            b, a = fx._bilinear_2nd_order(wn, 0.7071, 1.0 / dt)
            br, ar = bilinear([wn**2], [1.0, 2 * 0.7071 * wn, wn**2], fs=1.0 / dt)
            np.testing.assert_allclose(b, br, rtol=1e-13)
            np.testing.assert_allclose(a, ar, rtol=1e-13, atol=1e-15)


@pytest.mark.parametrize("eid", [e.id for e in REGISTRY.values() if e.transforms_design])
def test_sensor_transforms_in_place_equal_the_copying_ones(D, eid):
    """``transform(..., out=X)`` (assemble filters the design in place) equals the transform into a new array."""
    eff = REGISTRY[eid]
    X = np.column_stack([D.x, np.sin(3 * D.t), np.ones(D.n)])
    shape = float(np.median(eff.grid(D, {})))
    ref = eff.transform(D, X.copy(), shape, {})
    Xi = X.copy()
    got = eff.transform(D, Xi, shape, {}, out=Xi)
    assert got is Xi
    np.testing.assert_allclose(got, ref, rtol=0, atol=1e-12 * np.abs(ref).max())


def test_time_ripple_scan_reuses_the_phases_of_shared_samplings_exactly(D):
    """Experiments sampled alike share one cos/sin table: the periodogram is the direct one, bit for bit."""
    r = np.random.default_rng(0).normal(size=D.n)
    periods = np.geomspace(0.05, 20.0, 50)
    rows = np.ones(D.n, bool)
    w = 2 * np.pi / periods
    ref = np.zeros(len(periods))
    for e in range(D.n_exp):
        a, b = D.bounds[e], D.bounds[e + 1]
        ph = np.outer(D.t[a:b], w)
        re = r[a:b] - r[a:b].mean()
        ref += (re @ np.cos(ph)) ** 2 + (re @ np.sin(ph)) ** 2
    assert len({D.t[D.bounds[e] : D.bounds[e + 1]].tobytes() for e in range(D.n_exp)}) < D.n_exp  # shared samplings exist
    np.testing.assert_array_equal(REGISTRY["time_ripple"]._power(D, r, periods, rows), ref)


def test_sensor_filter_in_chunks_of_experiments_is_bit_identical(D, monkeypatch):
    """The fine time grid is filtered in bounded chunks of experiments (memory): no bit of the result moves."""
    eff = REGISTRY["force_filter_lag"]
    X = np.column_stack([D.x, np.sin(3 * D.t), np.ones(D.n)])
    whole = eff.transform(D, X.copy(), 0.05, {})
    monkeypatch.setattr(fx, "_FINE_GRID_BYTES", 1)  # one experiment per chunk
    np.testing.assert_array_equal(eff.transform(D, X.copy(), 0.05, {}), whole)


def _shifted_starts(D):
    """D with every experiment starting at t = 0 on a kept sample (no rest row before the motion) and one irregular experiment."""
    import dataclasses

    t = D.t.copy()
    for e in range(D.n_exp):
        a = D.bounds[e]
        t[a : D.bounds[e + 1]] -= t[a] if e % 2 else t[a] + 0.3 * D.per_exp_dt()[e]
    a = D.bounds[1]
    t[a + 5] = t[a + 4]  # two samples at one time: filtered on its kept samples
    return dataclasses.replace(D, t=t, _cache={})


@pytest.mark.parametrize("shift", [False, True])
def test_sensor_filter_on_the_samples_equals_the_fine_grid_filter(D, shift):
    """The sensor filters run on the samples (:func:`_substep_filter`) give what the filter on the fine, linearly
    interpolated time grid gives (the direct reference), for first- and second-order filters and any start."""
    from scipy.signal import lfilter

    Dx = _shifted_starts(D) if shift else D
    if shift:
        assert any(g[0] is None for g in fx._fine_grid(Dx, 1))
    X = np.column_stack([Dx.x + 1.0, np.sin(3 * Dx.t), np.ones(Dx.n), np.sign(Dx.v)])
    for tau in (0.003, 0.05, 0.7, 3.0):
        q = lambda dt: np.exp(-dt / tau)  # noqa: E731
        first = lambda dt: ([1.0 - q(dt)], [1.0, -q(dt)])  # noqa: E731
        second = lambda dt: fx._bilinear_2nd_order(2 * 0.5 / tau, 0.5, 1.0 / dt)  # noqa: E731
        for ba in (first, second):
            ref = fx._on_sample_grid(Dx, X, lambda seg, dt: lfilter(*ba(dt), seg, axis=1))
            got = fx._filter_on_sample_grid(Dx, X, ba)
            np.testing.assert_allclose(got, ref, rtol=0, atol=1e-9 * np.abs(ref).max())


def test_thermal_state_and_lowpass_of_grouped_experiments_are_bit_identical(D):
    """Experiments of one spacing are filtered together: the per-experiment filters' result, bit for bit."""
    from scipy.signal import lfilter

    dts = D.per_exp_dt()
    for tau in (0.05, 1.0, 30.0):
        h = np.zeros(D.n)
        lp = np.zeros(D.n)
        for e in range(D.n_exp):
            a, b = D.bounds[e], D.bounds[e + 1]
            q = np.exp(-dts[e] / tau)
            h[a:b] = lfilter([tau * (1 - q) / dts[e]], [1.0, -q], np.diff(D.x[a:b], prepend=D.x[a]))
            lp[a:b] = lfilter([1.0 - q], [1.0, -q], D.y[a:b], zi=np.array([q * D.y[a]]))[0]
        np.testing.assert_array_equal(fx._thermal_state(D, tau, D.x), h)
        np.testing.assert_array_equal(fx.lowpass(D, D.y, tau), lp)


@pytest.mark.parametrize("eid", [e.id for e in REGISTRY.values() if not e.needs])
def test_columns_of_effects_without_needs_do_not_read_the_context(D, eid):
    """``effect_columns`` caches the columns of effects without ``needs`` per shape: they must not depend on the context."""
    eff = REGISTRY[eid]
    rng = np.random.default_rng(1)
    ctx = {k: rng.normal(size=D.n) * 50 for k in ("damping_force_N", "model_force_N", "residual_N", "residual_all_N")}
    grid = np.asarray(eff.grid(D, ctx), float) if eff.shape is not None else np.array([np.nan])
    if len(grid) == 0:
        pytest.skip("no grid on this campaign")
    shape = float(grid[len(grid) // 2])
    ref = eff.columns(D, shape, ctx)
    np.testing.assert_array_equal(eff.columns(D, shape, {}), ref)
    got = fx.effect_columns(D, eff, shape, ctx)
    np.testing.assert_array_equal(got, ref)
    assert fx.effect_columns(D, eff, shape, {}) is got  # the second call is the cached array


@pytest.mark.parametrize("eid", [e.id for e in REGISTRY.values() if e.transforms_design and not e.params(None)])
def test_filter_only_candidate_design_equals_the_assembled_one(D, eid):
    """The CV of a filter-only candidate filters the current design instead of rebuilding it: the same design, bit for bit."""
    from vvea_design.identification import diagnose as dg

    base = ("stiction", "thermal")
    shapes = {"stiction": 8.0, "thermal": 1.5, eid: 0.05}
    X0, _, _ = assemble(D, base, shapes, {})
    X, _, _ = assemble(D, base + (eid,), shapes, {})
    np.testing.assert_array_equal(dg._filtered_design(D, REGISTRY[eid], X0, 0.05, {}), X)


def test_cache_budget_counts_every_entry_and_eviction_moves_no_bit(D, monkeypatch):
    """Every entry of a FitData's cache (columns, fine grids, velocity gaps, ...) counts against its byte budget, and
    what an evicted entry is rebuilt into is bit for bit what the roomy cache held (memory on large campaigns)."""
    import dataclasses

    from scipy.signal import lfilter

    def run(Dc):
        op = lambda seg, dt: lfilter([1.0 - np.exp(-dt / 0.05)], [1.0, -np.exp(-dt / 0.05)], seg, axis=1)  # noqa: E731
        out = []
        for _ in range(2):  # the second pass reads what survived in the cache (or rebuilds it)
            out.append(fx._velocity_correction(Dc, op))
            out.append(REGISTRY["force_filter_lag"].transform(Dc, np.column_stack([Dc.x, np.ones(Dc.n)]), 0.05, {}))
            out += [fx.effect_columns(Dc, REGISTRY[e], s, {}) for e, s in (("stiction", 2.0), ("quadratic_damping", 1.6), ("thermal", 3.0))]
            out.append(fx._travel_since_reversal(Dc))
            sizes = [fx._nbytes(v) for v in Dc._cache.values()]
            assert sum(sizes) <= fx.CACHE_BYTES or len(sizes) == 1
        return out

    roomy = run(dataclasses.replace(D, _cache={}))
    monkeypatch.setattr(fx, "CACHE_BYTES", 3 * 8 * D.n)  # three columns' worth: most entries are evicted and rebuilt
    tight = run(dataclasses.replace(D, _cache={}))
    for a, b in zip(roomy, tight):
        np.testing.assert_array_equal(a.view(np.int64), b.view(np.int64))


def test_quadratic_damping_columns_put_each_sample_on_its_valve(D):
    """K(gamma) columns: xdot |xdot|^(m-1) in the column of the sample's valve, zero in the others."""
    m = 1.7
    X = REGISTRY["quadratic_damping"].columns(D, m, {})
    assert X.shape == (D.n, len(D.valves))
    q = D.v * np.abs(D.v) ** (m - 1.0)
    for j, g in enumerate(D.valves):
        on = D.valve == g
        np.testing.assert_array_equal(X[on, j], q[on])
        assert not np.any(X[~on, j])
