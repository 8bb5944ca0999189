"""Axisymmetric hyperelastic membrane FE (vvea_design.bladder.membrane): verification against closed forms."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from vvea_design.bladder.membrane import (
    SLACK,
    TAUT,
    WRINKLED,
    MembraneError,
    MooneyRivlin,
    element_stretches,
    enclosed_volume_mm3,
    relaxed_energy_density,
    sleeve_meridian,
    solve_volume,
    solve_volume_path,
    sphere_meridian,
)

R0, H0 = 10.0, 0.1


def balloon_pressure_MPa(lam, mat: MooneyRivlin, R=R0, H=H0):
    """Thin incompressible Mooney-Rivlin sphere: p = (2H/R)(1/l - 1/l^7)(2 C10 + 2 C01 l^2)."""
    return 2 * H / R * (1 / lam - lam**-7) * (2 * mat.C10_MPa + 2 * mat.C01_MPa * lam**2)


def _balloon_path(mat, lams, n=48):
    ref = sphere_meridian(R0, H0, n)
    V0 = ref.volume_mm3
    sols = solve_volume_path(ref, mat, [V0 * (lam**3 - 1) for lam in lams])
    # the stretch is what the FE volume says, measured against the same polygon
    lam_fe = np.array([((V0 + s.volume_change_mm3) / V0) ** (1 / 3) for s in sols])
    return lam_fe, np.array([s.pressure_MPa for s in sols]), sols


@pytest.mark.parametrize("mat", [MooneyRivlin.neo_hookean(0.6), MooneyRivlin(0.25, 0.05)], ids=["neo-Hookean", "Mooney-Rivlin"])
def test_balloon_through_and_past_the_pressure_maximum(mat):
    lams = [1.1, 1.3, 7 ** (1 / 6), 1.5, 2.0, 2.5]
    lam_fe, p, sols = _balloon_path(mat, lams)
    exact = balloon_pressure_MPa(lam_fe, mat)
    assert np.max(np.abs(p / exact - 1)) <= 1e-3
    if mat.C01_MPa == 0:  # neo-Hookean: the path rises, peaks near 7^(1/6), then falls (volume control passes it)
        assert p[1] < p[2] and p[3] > p[4] > p[5]
    for s in sols:
        assert np.all(s.state == TAUT)
        # equibiaxial: both stretches equal to the volume stretch away from the poles
        mid = slice(len(s.state) // 4, 3 * len(s.state) // 4)
        assert np.allclose(s.fields["l1"][mid], s.fields["l2"][mid], rtol=2e-3)


def test_pressure_is_the_energy_derivative():
    """The Lagrange multiplier equals dPi/dV (independent of any closed form)."""
    mat = MooneyRivlin(0.3, 0.1)
    ref = sleeve_meridian(20.0, 60.0, 1.0, 24)
    dv, d = 4000.0, 20.0
    lo, mid, hi = solve_volume_path(ref, mat, [dv - d, dv, dv + d])
    dPi_dV = (hi.energy_N_mm - lo.energy_N_mm) / (hi.volume_change_mm3 - lo.volume_change_mm3)
    assert mid.pressure_MPa == pytest.approx(dPi_dV, rel=1e-4)
    assert mid.volume_change_mm3 == pytest.approx(dv, rel=1e-8)


def test_long_clamped_tube_follows_laplace_at_small_strain():
    mu, R, H, L = 0.5, 10.0, 0.1, 400.0
    mat = MooneyRivlin.neo_hookean(mu)
    ref = sleeve_meridian(R, L, H, 60, grading=0.0)
    eps = 1e-3
    s = solve_volume(ref, mat, 2 * math.pi * R * L * R * eps)
    f = s.fields
    i = ref.n_elements // 2
    l1, l2 = f["l1"][i], f["l2"][i]
    sigma_hoop = mu * (l2**2 - (l1 * l2) ** -2)  # Cauchy hoop stress
    p_laplace = sigma_hoop * (H / (l1 * l2)) / (l2 * R)
    assert s.pressure_MPa == pytest.approx(p_laplace, rel=1e-3)
    # small strain, axially held: the plane-strain thin-cylinder law p = 4 mu H eps / R
    assert s.pressure_MPa == pytest.approx(4 * mu * H * (l2 - 1) / R, rel=5e-3)


def test_balloon_error_converges_with_the_mesh():
    mat = MooneyRivlin.neo_hookean(1.0)
    errs = []
    ns = (8, 16, 32)
    for n in ns:
        lam_fe, p, _ = _balloon_path(mat, [1.5], n=n)
        errs.append(abs(p[0] / balloon_pressure_MPa(lam_fe[0], mat) - 1))
    orders = [math.log(errs[k] / errs[k + 1], 2) for k in range(len(ns) - 1)]
    assert errs[0] > errs[1] > errs[2]
    assert min(orders) > 1.5  # two-node elements with midpoint quadrature: O(h^2)


def test_deflated_sleeve_wrinkles_and_carries_almost_no_pressure():
    mat = MooneyRivlin.neo_hookean(0.2)
    ref = sleeve_meridian(20.0, 80.0, 1.5, 32)
    dv = 0.15 * math.pi * 20.0**2 * 80.0
    up = solve_volume(ref, mat, dv)
    down = solve_volume(ref, mat, -dv)
    stiff = solve_volume(ref, mat, -dv, relaxed=False)
    assert np.all(up.state == TAUT)
    assert np.all(down.state != TAUT) and down.wrinkled_fraction == 1.0
    assert abs(down.pressure_MPa) < 0.01 * up.pressure_MPa
    # the wrinkles take up the hoop contraction: the material is barely strained ...
    assert down.max_principal_strain < 0.1 * up.max_principal_strain
    assert np.all(np.abs(down.principal_strains[:, 1]) < 0.01)
    # ... whereas the geometric hoop contraction is large, and an unrelaxed membrane would be compressed by it
    assert down.fields["l2"].min() < 0.95
    assert stiff.principal_strains.min() < -0.04 and stiff.pressure_MPa < 0


@settings(max_examples=200, deadline=None)
@given(st.floats(0.5, 2.0), st.floats(0.5, 2.0))
def test_relaxed_energy_is_nonnegative_below_the_full_energy_and_zero_when_slack(l1, l2):
    mat = MooneyRivlin(0.3, 0.05)
    w = float(relaxed_energy_density(l1, l2, mat))
    w_full = float(relaxed_energy_density(l1, l2, mat, relaxed=False))
    assert -1e-12 <= w <= w_full + 1e-12
    if l1 <= 1 and l2 <= 1:
        assert w == 0.0


def test_relaxed_energy_is_continuous_across_the_wrinkling_boundary():
    mat = MooneyRivlin(0.3, 0.05)
    for l1 in (1.05, 1.3, 1.8):
        l2b = l1**-0.5  # natural width: the boundary taut / wrinkled
        w = relaxed_energy_density([l1, l1], [l2b * (1 - 1e-7), l2b * (1 + 1e-7)], mat)
        assert w[0] == pytest.approx(w[1], rel=1e-5)


def test_element_states_and_volume_of_a_cylinder():
    ref = sleeve_meridian(10.0, 20.0, 1.0, 4, grading=0.0)
    assert enclosed_volume_mm3(ref.r_mm, ref.z_mm) == pytest.approx(math.pi * 100 * 20)
    # stretch the meridian, shrink the hoop a lot -> wrinkled; shrink everything -> slack
    f = element_stretches(ref, ref.r_mm * 0.8, ref.z_mm * 1.2)
    inner = f["state"][1:-1]
    assert np.all(inner == WRINKLED)
    assert np.allclose(f["l2_eff"][1:-1], f["l1"][1:-1] ** -0.5)
    g = element_stretches(ref, ref.r_mm * 0.9, ref.z_mm * 0.9)
    assert np.all(g["state"][1:-1] == SLACK)


def test_bad_membrane_input_is_named():
    with pytest.raises(MembraneError, match="radius_mm"):
        sleeve_meridian(-1.0, 10.0, 1.0)
    with pytest.raises(MembraneError, match="thickness_mm"):
        sleeve_meridian(10.0, 10.0, 0.0)
    with pytest.raises(MembraneError, match="C10_MPa"):
        MooneyRivlin(0.0)
    with pytest.raises(MembraneError, match="no enclosed volume"):
        ref = sphere_meridian(5.0, 0.1, 8)
        solve_volume(ref, MooneyRivlin.neo_hookean(1.0), -2 * ref.volume_mm3)


def test_every_public_name_is_documented():
    import inspect

    import vvea_design.bladder.check as bladder
    import vvea_design.cli.bladder as cli_bladder
    import vvea_design.bladder.membrane as membrane
    import vvea_design.materials.silicones as silicones

    for mod in (membrane, bladder, silicones, cli_bladder):
        assert mod.__doc__
        for name in mod.__all__:
            obj = getattr(mod, name)
            if inspect.isfunction(obj) or inspect.isclass(obj):
                assert inspect.getdoc(obj), f"{mod.__name__}.{name} has no docstring"
