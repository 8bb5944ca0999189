"""Gas-spring physics (paper eqs 3-7) and the linearity metric."""

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from vvea_design.spring.gas_spring import (
    PAPER_FIG5,
    ChamberBottomedOut,
    GasSpring,
    force_N,
    linearity_error,
    local_stiffness_N_per_mm,
    mean_stiffness_N_per_mm,
    setpoint_p1_MPa,
)

A1, A2, V1, V2 = 2560.0, 706.9, 1.22e5, 7.34e4
x = np.linspace(0, 40, 401)

geometry = st.tuples(
    st.floats(300, 3000), st.floats(300, 3000), st.floats(3e4, 3e5), st.floats(3e4, 3e5)
).filter(lambda g: g[3] - g[1] * 40 > 0.05 * g[3])


@settings(max_examples=60, deadline=None)
@given(geometry, st.floats(0.2, 6.0), st.floats(0.1, 5.0))
def test_force_scales_linearly_with_pressure_at_fixed_ratio(g, p2, scale):
    a1, a2, v1, v2 = g
    p1 = a2 / a1 * p2
    f = force_N(x, a1, a2, v1, v2, p1, p2)
    fs = force_N(x, a1, a2, v1, v2, scale * p1, scale * p2)
    np.testing.assert_allclose(fs, scale * f, rtol=1e-12, atol=1e-9)
    # the shape - and so the linearity metric - does not depend on the charge
    assert linearity_error(x, fs) == pytest.approx(float(linearity_error(x, f)), rel=1e-9)


@settings(max_examples=60, deadline=None)
@given(geometry, st.floats(0.2, 6.0), st.floats(-5.0, 5.0), st.sampled_from([1.0, 1.2, 1.4]))
def test_eq6_puts_zero_force_at_the_setpoint(g, p2, x0, n):
    a1, a2, v1, v2 = g
    p1 = setpoint_p1_MPa(p2, a1, a2, v1, v2, x0, n)
    assert force_N(x0, a1, a2, v1, v2, p1, p2, n) == pytest.approx(0.0, abs=1e-8 * a2 * p2)


def test_eq7_is_eq6_at_zero():
    assert setpoint_p1_MPa(3.0, A1, A2, V1, V2, 0.0) == pytest.approx(A2 / A1 * 3.0, rel=1e-14)


def test_n1_is_the_isothermal_law_of_eq5():
    p2 = 2.0
    p1 = A2 / A1 * p2
    eq5 = A2 * p2 * V2 / (V2 - A2 * x) - A1 * p1 * V1 / (V1 + A1 * x)
    np.testing.assert_allclose(force_N(x, A1, A2, V1, V2, p1, p2, n=1.0), eq5, rtol=1e-13)


def test_adiabatic_is_stiffer_than_isothermal():
    p1 = A2 / A1 * 2.0
    k1 = mean_stiffness_N_per_mm(x, force_N(x, A1, A2, V1, V2, p1, 2.0, n=1.0))
    k14 = mean_stiffness_N_per_mm(x, force_N(x, A1, A2, V1, V2, p1, 2.0, n=1.4))
    assert k14 > 1.3 * k1


@pytest.mark.parametrize("n", [1.0, 1.25, 1.4])
def test_local_stiffness_is_the_derivative(n):
    p1 = A2 / A1 * 2.0
    h = 1e-4
    xs = np.linspace(0.5, 39.5, 20)
    num = (force_N(xs + h, A1, A2, V1, V2, p1, 2.0, n) - force_N(xs - h, A1, A2, V1, V2, p1, 2.0, n)) / (2 * h)
    np.testing.assert_allclose(local_stiffness_N_per_mm(xs, A1, A2, V1, V2, p1, 2.0, n), num, rtol=1e-6)


def test_bottoming_out_raises_with_a_clear_message():
    with pytest.raises(ChamberBottomedOut, match="chamber 2 bottoms out"):
        force_N(np.array([0.0, 40.0]), A1, A2, V1, 20_000.0, 1.0, 1.0)
    with pytest.raises(ChamberBottomedOut, match="chamber 1 bottoms out"):
        force_N(np.array([-60.0, 0.0]), A1, A2, 1.0e5, V2, 1.0, 1.0)
    with pytest.raises(ValueError, match="bottoms out"):
        GasSpring(A1, 1000.0, V1, 30_000.0, 1.0, 1.0)


def test_vectorised_over_many_designs():
    V2s = np.array([[6e4], [7.34e4], [9e4]])
    F = force_N(x, A1, A2, V1, V2s, A2 / A1, 1.0)
    assert F.shape == (3, x.size)
    lin = linearity_error(x, F)
    for i, v2 in enumerate(V2s[:, 0]):
        single = linearity_error(x, force_N(x, A1, A2, V1, v2, A2 / A1, 1.0))
        assert lin[i] == pytest.approx(float(single), rel=1e-12)


def test_linearity_metric_divides_by_span_not_by_max_force():
    # a straight line plus a large offset is perfectly linear: offsets cannot fake or hide curvature
    F = 5.0 * x + 1e4
    assert linearity_error(x, F) == pytest.approx(0.0, abs=1e-12)
    curved = 5.0 * x + 0.01 * x**2
    assert linearity_error(x, curved + 1e4) == pytest.approx(float(linearity_error(x, curved)), rel=1e-9)
    # a known case: a parabola over [0, 1] deviates 1/6 of its span from its least-squares line
    u = np.linspace(0, 1, 20001)
    assert linearity_error(u, u**2) == pytest.approx(1 / 6, rel=1e-3)


def test_gasspring_rejects_bad_values():
    with pytest.raises(ValueError, match="A1_mm2"):
        GasSpring(-1.0, A2, V1, V2, 1.0, 1.0)
    with pytest.raises(ValueError, match="n_polytropic"):
        GasSpring(A1, A2, V1, V2, 1.0, 1.0, n_polytropic=1.6)
    with pytest.raises(ValueError, match="p2_MPa"):
        GasSpring(A1, A2, V1, V2, 1.0, float("nan"))


def test_peak_pressure_is_chamber2_at_full_stroke():
    g = PAPER_FIG5
    assert g.peak_pressure_MPa() == pytest.approx(g.p2_MPa * g.V2_mm3 / (g.V2_mm3 - g.A2_mm2 * 40.0))


def _independent_metric(g: GasSpring) -> float:
    """The metric by a different route: scipy quad for the least-squares line, bounded scalar search
    for the largest deviation (on a fine bracket grid), span from the two ends."""
    from scipy.integrate import quad
    from scipy.optimize import minimize_scalar

    T = g.travel_mm
    f = lambda t: float(g.force_N(t))  # noqa: E731
    m0 = quad(f, 0, T, epsabs=0, epsrel=1e-13)[0] / T
    m1 = quad(lambda t: (t - T / 2) * f(t), 0, T, epsabs=0, epsrel=1e-13)[0]
    k = m1 / (T**3 / 12)
    b = m0 - k * T / 2
    dev = lambda t: -abs(f(t) - (k * t + b))  # noqa: E731
    grid = np.linspace(0, T, 201)
    best = max(-dev(t) for t in grid)
    for a, c in zip(grid[:-1], grid[1:]):
        r = minimize_scalar(dev, bounds=(a, c), method="bounded", options={"xatol": 1e-10})
        best = max(best, -r.fun)
    return best / (f(T) - f(0.0))


@pytest.mark.parametrize("n", [1.0, 1.4])
@pytest.mark.parametrize("spring", [PAPER_FIG5, GasSpring(1010.0, 960.0, 48800.0, 102000.0, 3.8, 4.0)])
def test_exact_metric_agrees_with_an_independent_computation(spring, n):
    g = spring.with_polytropic(n)
    assert g.linearity_error() == pytest.approx(_independent_metric(g), abs=1e-9)
    # sampled metrics converge to it from below as the grid refines (the sampled max misses the peak)
    assert abs(g.linearity_error(200001) - g.linearity_error()) < 1e-5
    assert abs(g.linearity_error(401) - g.linearity_error()) > abs(g.linearity_error(200001) - g.linearity_error())


def test_exact_metric_is_vectorised_and_reports_its_line():
    from vvea_design.spring.gas_spring import linearity_exact

    V2s = np.array([6e4, 7.34e4, 9e4])
    r = linearity_exact(A1, A2, V1, V2s, A2 / A1 * 2.0, 2.0, 40.0)
    assert r.linearity_error.shape == (3,)
    for i, v2 in enumerate(V2s):
        g = GasSpring(A1, A2, V1, v2, A2 / A1 * 2.0, 2.0)
        one = g.linearity()
        assert r.linearity_error[i] == pytest.approx(float(one.linearity_error), rel=1e-12)
        assert r.max_deviation_N[i] == pytest.approx(abs(float(g.force_N(r.x_max_deviation_mm[i]))
                                                         - (r.mean_stiffness_N_per_mm[i] * r.x_max_deviation_mm[i]
                                                            + r.intercept_N[i])), rel=1e-9)
    bad = linearity_exact(A1, A2, V1, 20_000.0, 1.0, 1.0, 40.0)  # chamber 2 bottoms out: nan, no exception
    assert np.isnan(bad.linearity_error)
