"""Every mechanism of the blind bench: description, ranges, switched off = base, and its physics."""

import importlib

import numpy as np
import pytest

from vvea_benches.blind.registry import ALL, BLIND, CATALOGUE, DEV, MECHANISMS, lookup
from vvea_benches.blind.spec import DOMAINS, STATES, Choice, Range

#: Parameters that switch each mechanism off (its force vanishes or its lag goes to zero).
OFF = {
    "charge_zero_offset": {"k_N_per_MPa": 0.0, "sign": 1.0},
    "room_warming": {"dT_K": 0.0, "tau_h": 2.0},
    "oil_warming": {"b_per_K": 0.0, "dT_room_K": 4.0, "tau_room_h": 2.0, "C_th_J_per_K": 700.0, "R_th_K_per_W": 4.0},
    "sticky_band": {"x_start_mm": 10.0, "width_mm": 5.0, "dC_N": 0.0},
    "bladder_membrane": {"p_b_MPa": 0.0, "x_n_mm": 20.0, "a": 0.5, "eta": 0.2, "x_h_mm": 2.0},
    "start_transient": {"A_N": 0.0, "tau_s": 0.1},
    "entrained_air": {"alpha_at_1MPa": 0.0, "V_in_mm3": 1.0, "K_oil_MPa": 1e9},
    "zero_position_scatter": {"sigma_mm": 0.0},
    "seal_heating": {"R_K_per_W": 30.0, "tau_s": 5.0, "kappa_per_K": 0.0},
    "misalignment_friction": {"mu_eff": 0.0},
    "bladder_contact": {"x_c_mm": 34.0, "F_end_N": 0.0, "mu_c": 0.4},
    "frame_compliance": {"K_N_per_mm": 1e12},
    "gas_dissolution": {"ostwald": 0.0, "V_oil_mm3": 4e4, "tau_s": 300.0},
    "cavitation": {"p_cav_MPa": -1e6},
    "valve_backlash": {"backlash_deg": 0.0},
    "gas_nonlinearity": {},
    "thermal": {"tau2_s": 1e-6, "tau1_ratio": 1.0},
    "quadratic_damping": {"A_w_mm2": 1e6, "A_b_mm2": 1e6, "gamma_c_deg": 112.0, "Cd": 0.7},
    "relief_valve": {"F_crack_N": 1e9, "d_seat_mm": 2.0, "k_spring_N_per_mm": 30.0},
    "stiction": {"Fs_over_C": 1.0, "v_s_mm_s": 0.2, "delta": 1.0},
    "pressure_friction": {"c_p_N_per_MPa": 0.0},
    "leakage": {"tau_dome_h": 1e12, "tau_seal_h": 1e12},
}


def test_the_split_and_the_count():
    assert len(MECHANISMS) >= 10 and set(CATALOGUE) == {"gas_nonlinearity", "thermal", "quadratic_damping",
                                                         "relief_valve", "stiction", "pressure_friction", "leakage"}
    assert not set(DEV) & set(BLIND) and set(DEV) | set(BLIND) == set(MECHANISMS)
    assert abs(len(DEV) - len(BLIND)) <= 1
    assert len({MECHANISMS[n].domain for n in MECHANISMS}) >= 5  # several domains
    assert set(OFF) == set(ALL)


@pytest.mark.parametrize("name", sorted(ALL))
def test_spec_is_described(name):
    spec = lookup(name)
    assert spec.domain in DOMAINS and spec.description and set(spec.states) <= set(STATES) and spec.states
    module = importlib.import_module(spec.apply.__module__)
    assert "Physics" in module.__doc__ and (not spec.ranges or "Ranges" in module.__doc__)
    for k, r in spec.ranges.items():
        assert r.why and r.unit, k
        assert k in module.__doc__, f"{name}: the docstring gives no reason for the range of {k}"
        if isinstance(r, Range):
            assert r.lo < r.hi
    draws = [spec.sample(np.random.default_rng(s)) for s in range(20)]
    for d in draws:
        for k, r in spec.ranges.items():
            assert (r.lo <= d[k] <= r.hi) if isinstance(r, Range) else d[k] in r.options
    assert (spec.catalogue_id is None) == (name in MECHANISMS)


@pytest.mark.parametrize("name", sorted(ALL))
def test_switched_off_is_the_base(name, bench, ctx):
    idx = [bench.find(ctx, 1.0, 120.0, 8.0), bench.find(ctx, 4.0, 109.0, 12.0), bench.find(ctx, 2.0, 50.0, 0.1)]
    base, _ = bench.simulate(ctx, (), idx)
    off, _ = bench.simulate(ctx, [(lookup(name), OFF[name])], idx)
    for i in idx:
        np.testing.assert_allclose(off[i]["f_meas_N"], base[i]["f_meas_N"], atol=0.05, rtol=1e-6)


@pytest.mark.parametrize("name", sorted(ALL))
def test_drawn_parameters_change_the_force_and_repeat(name, bench, ctx):
    spec = lookup(name)
    params = spec.sample(np.random.default_rng(7))
    idx = [bench.find(ctx, 1.0, 120.0, 8.0), bench.find(ctx, 4.0, 110.0, 12.0), bench.find(ctx, 2.0, 108.0, 0.1)]
    base, _ = bench.simulate(ctx, (), idx)
    a, _ = bench.simulate(ctx, [(spec, params)], idx)
    b, _ = bench.simulate(ctx, [(spec, params)], idx)
    for i in idx:
        np.testing.assert_array_equal(a[i]["f_meas_N"], b[i]["f_meas_N"])  # deterministic
        assert np.all(np.isfinite(a[i]["f_meas_N"]))
    if name not in ("gas_nonlinearity", "zero_position_scatter", "valve_backlash", "gas_dissolution", "leakage",
                    "room_warming", "oil_warming"):  # these need the campaign's history or the base law
        assert max(np.abs(a[i]["f_meas_N"] - base[i]["f_meas_N"]).max() for i in idx) > 1.0
