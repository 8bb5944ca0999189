"""Tests of the signal operators: the grouped low-pass and thermal state, and the sensor filters on a time grid finer
than the sampling (run on the samples, in chunks, across the samples left out at rest, with the motion's velocity
between samples)."""

from __future__ import annotations

import numpy as np
import pytest

from vvea_design.identification import signals
from vvea_design.identification.effects import REGISTRY
from vvea_design.identification.effects.force_lag import _bilinear_2nd_order, filter_id
from vvea_design.identification.fit_data import FitData


def test_sensor_filter_in_chunks_of_experiments_is_bit_identical(D, monkeypatch):
    """The fine time grid is filtered in bounded chunks of experiments (memory): no bit of the result moves."""
    eff = REGISTRY["force_filter_lag"]
    X = np.column_stack([D.x, np.sin(3 * D.t), np.ones(D.n)])
    whole = eff.transform(D, X.copy(), 0.05, {})
    monkeypatch.setattr(signals, "_FINE_GRID_BYTES", 1)  # one experiment per chunk
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
        assert any(g[0] is None for g in signals._fine_grid(Dx, 1))
    X = np.column_stack([Dx.x + 1.0, np.sin(3 * Dx.t), np.ones(Dx.n), np.sign(Dx.v)])
    for tau in (0.003, 0.05, 0.7, 3.0):
        q = lambda dt: np.exp(-dt / tau)  # noqa: E731
        first = lambda dt: ([1.0 - q(dt)], [1.0, -q(dt)])  # noqa: E731
        second = lambda dt: _bilinear_2nd_order(2 * 0.5 / tau, 0.5, 1.0 / dt)  # noqa: E731
        for ba in (first, second):
            ref = signals._on_sample_grid(Dx, X, lambda seg, dt: lfilter(*ba(dt), seg, axis=1))
            got = signals._filter_on_sample_grid(Dx, X, ba)
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
        np.testing.assert_array_equal(signals._thermal_state(D, tau, D.x), h)
        np.testing.assert_array_equal(signals.lowpass(D, D.y, tau), lp)


def test_force_filter_runs_over_the_samples_left_out_at_rest():
    # one experiment sampled at dt = 0.1 s, its force a ramp in time; the samples at rest (t = 0, and one
    # in the middle) are left out. The lag must keep the time base across the gap: the first-order
    # response of a ramp from rest is t - tau (1 - exp(-t/tau)).
    dt, n, tau = 0.1, 41, 0.25
    t = np.arange(n) * dt
    keep = np.ones(n, bool)
    keep[[0, 20]] = False
    x = np.minimum(t, 4.0 - t) * 10.0
    D = FitData(x=x[keep], v=np.gradient(x, t)[keep], p2=np.ones(keep.sum()), valve=np.zeros(keep.sum()),
                valve_idx=np.zeros(keep.sum(), int), valves=(0.0,), t=t[keep], tsr=t[keep], ctime=t[keep],
                exp=np.zeros(keep.sum(), int), y=np.zeros(keep.sum()), bounds=np.array([0, keep.sum()]))
    got = REGISTRY["force_lag"].transform(D, t[keep][:, None], tau, {})[:, 0]
    want = t[keep] - tau * (1 - np.exp(-t[keep] / tau))
    assert np.max(np.abs(got - want)) < 0.15 * dt  # the discretisation's half step (dt/8), not a sample's shift (dt)


def _ramp_experiment(dt, speed, accel, travel=4.0, t_end=None):
    """One out-and-back experiment of the machine's motion profile, sampled every ``dt``; samples at rest dropped."""
    from vvea_design.identification.recordings import trapezoid_profile

    t_rev = travel / speed + speed / accel
    t = np.arange(0.0, 2 * t_rev + 1e-9, dt)
    x, v = trapezoid_profile(t, speed, accel, t_rev)
    keep = np.abs(v) > 0
    n = int(keep.sum())
    D = FitData(x=x[keep], v=v[keep], p2=np.ones(n), valve=np.zeros(n), valve_idx=np.zeros(n, int), valves=(0.0,),
                t=t[keep], tsr=t[keep], ctime=t[keep], exp=np.zeros(n, int), y=np.zeros(n), bounds=np.array([0, n]))
    return D, t_rev


def test_sensor_filter_runs_the_damping_columns_with_the_velocity_between_samples():
    # a stiff valve's damping force follows the velocity, whose ramps end between samples when the
    # sampling is as coarse as the ramp: filtered as the straight line between samples, the reading
    # at the next sample is wrong by a share of the force; with the motion profile's velocity it is
    # the filter of the true velocity
    from scipy.signal import lfilter

    from vvea_design.identification.recordings import trapezoid_profile

    dt, speed, accel, lag = 0.067, 4.0, 40.0, 0.026
    D, t_rev = _ramp_experiment(dt, speed, accel)
    eff = REGISTRY[filter_id(1.0)]  # a critically damped sensor filter (made from its id)
    X = np.column_stack([D.p2 * D.x, D.s, D.v])  # eq. 14's columns (one valve)
    got = eff.transform(D, X.copy(), lag, {}, eq14_first=True)[:, 2]
    lin = eff.transform(D, X.copy(), lag, {})[:, 2]
    # reference: the velocity on a grid 400 x finer than the sampling, through the same filter
    m = 400
    tf = np.arange(0, D.t[-1] * m / dt + 0.5) * dt / m
    vf = trapezoid_profile(tf, speed, accel, t_rev)[1]
    wn = 2 * eff.zeta / lag
    ref_f = lfilter(*_bilinear_2nd_order(wn, eff.zeta, m / dt), vf)
    ref = np.interp(D.t, tf, ref_f)
    err, err_lin = np.max(np.abs(got - ref)), np.max(np.abs(lin - ref))
    assert err < 0.01 * speed  # 1 % of the cruise speed (the fine grid's own discretisation)
    assert err_lin > 5 * err  # the straight line between samples is off by several times that
