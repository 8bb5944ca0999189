"""Actuator model (eqs 8-13), Table 4 settings and the design -> actuator mapping."""

from __future__ import annotations

import json
import math
import types

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from vvea_design.actuator.model import (
    PAPER_PULLEY_RADIUS_M,
    PAPER_SETTINGS,
    TABLE3_L_NS_PER_MM,
    Actuator,
    actuator_from_spring,
    dynamics,
    from_design_json,
    link_torque_Nm,
    paper_mapping_check,
    pulley_radius_for_stiffness_m,
    throttle_damping_Ns_per_mm,
)
from vvea_design.spring.gas_spring import PAPER_FIG5, GasSpring


def test_table4_settings_structure():
    s = PAPER_SETTINGS
    assert set(s) == {"VVEA", "iVVEA", "SEA", "LWR"}
    assert s["VVEA"].variable_damping and s["iVVEA"].variable_damping
    assert not s["SEA"].variable_damping and not s["LWR"].variable_damping
    # SEA is the special case of iVVEA with D held at its lower bound
    assert s["SEA"].D_min_Nms_per_rad == s["iVVEA"].D_min_Nms_per_rad
    assert s["SEA"].K_Nm_per_rad == s["iVVEA"].K_Nm_per_rad == s["VVEA"].K_Nm_per_rad


def test_eigenfrequency_matches_section_5():
    # paper: omega = sqrt(K/M)/(2 pi) ~ 3.03 Hz with K = 362, M = 1
    assert PAPER_SETTINGS["SEA"].eigenfrequency_Hz == pytest.approx(3.03, abs=0.005)


@pytest.mark.parametrize(
    "field, value",
    [("K_Nm_per_rad", 0.0), ("K_Nm_per_rad", float("nan")), ("D_min_Nms_per_rad", -1.0), ("B_kgm2", -0.5),
     ("tau_m_max_Nm", 0.0)],
)
def test_bad_actuator_names_the_field(field, value):
    kw = dict(name="x", K_Nm_per_rad=362.0, D_min_Nms_per_rad=0.0, D_max_Nms_per_rad=200.0)
    kw[field] = value
    with pytest.raises(ValueError, match=field):
        Actuator(**kw)


def test_dmax_below_dmin_rejected():
    with pytest.raises(ValueError, match="D_max_Nms_per_rad"):
        Actuator("x", 362.0, 50.0, 10.0)


@given(
    th=st.floats(-1, 1), q=st.floats(-1, 1), dth=st.floats(-10, 10), dq=st.floats(-10, 10),
    D=st.floats(0, 500), tau_m=st.floats(-100, 100),
)
@settings(max_examples=50, deadline=None)
def test_dynamics_momentum_balance(th, q, dth, dq, D, tau_m):
    """Eqs 8 + 9: B θ'' + M q'' = τ_m (the spring-damper torque is internal)."""
    K, B, M = 362.0, 0.598, 1.0
    f = dynamics([th, q, dth, dq, D], [tau_m, 7.0], K, B=B, M=M)
    assert f[0] == dth and f[1] == dq and f[4] == 7.0
    assert B * f[2] + M * f[3] == pytest.approx(tau_m, abs=1e-9 * (1 + abs(tau_m) + 500 * 20))
    tau = link_torque_Nm(th, q, dth, dq, D, K)
    assert M * f[3] == pytest.approx(tau, rel=1e-12, abs=1e-9)


def test_throttle_table_and_interpolation():
    for g, L in TABLE3_L_NS_PER_MM.items():
        assert throttle_damping_Ns_per_mm(g) == pytest.approx(L)
    gg = np.linspace(50, 120, 141)
    L = throttle_damping_Ns_per_mm(gg)
    assert np.all(np.diff(L) >= 0)  # the table is monotone, so is the interpolation
    with pytest.raises(ValueError, match="gamma_deg"):
        throttle_damping_Ns_per_mm(130.0)


@given(r=st.floats(0.01, 0.3), p2=st.floats(0.5, 4.0), n=st.integers(1, 4))
@settings(max_examples=30, deadline=None)
def test_mapping_scales_with_radius_squared(r, p2, n):
    act = actuator_from_spring(PAPER_FIG5, pulley_radius_m=r, p2_MPa=p2, n_units=n)
    k = PAPER_FIG5.with_pressures(p2).mean_stiffness_N_per_mm()
    assert act.K_Nm_per_rad == pytest.approx(n * r**2 * k * 1e3, rel=1e-12)
    # K/D = k/L does not depend on the transmission
    assert act.K_Nm_per_rad / act.D_min_Nms_per_rad == pytest.approx(k / TABLE3_L_NS_PER_MM[50.0] * 1e-0, rel=1e-9)


def test_paper_mapping_reproduces_K_and_Dmax():
    """With the inferred radius, K = 362 and L(106°) gives ≈ the paper's D_max = 200."""
    chk = paper_mapping_check()
    assert chk.K_Nm_per_rad == pytest.approx(362.0, rel=1e-9)
    assert chk.D_of_gamma_Nms_per_rad[106.0] == pytest.approx(200.0, rel=0.05)
    # D_min = 12.1 would need an L that Table 3 does not hold (between L(80) and L(100))
    assert TABLE3_L_NS_PER_MM[80.0] < chk.L_needed_for_D12p1_Ns_per_mm < TABLE3_L_NS_PER_MM[100.0]
    act = actuator_from_spring(PAPER_FIG5, gamma_min_deg=50, gamma_max_deg=106)
    assert act.K_Nm_per_rad == pytest.approx(362.0)
    assert act.D_max_Nms_per_rad == pytest.approx(chk.D_of_gamma_Nms_per_rad[106.0])
    assert chk.to_dict()["K_Nm_per_rad"] == chk.K_Nm_per_rad and chk.to_dict()["n_units"] == 2


def test_pulley_radius_roundtrip():
    r = pulley_radius_for_stiffness_m(PAPER_FIG5.mean_stiffness_N_per_mm(), 362.0)
    assert r == pytest.approx(PAPER_PULLEY_RADIUS_M)
    with pytest.raises(ValueError, match="k_N_per_mm"):
        pulley_radius_for_stiffness_m(0.0, 362.0)


def test_mapping_bad_input_names_field():
    with pytest.raises(ValueError, match="pulley_radius_m"):
        actuator_from_spring(PAPER_FIG5, pulley_radius_m=-0.1)
    with pytest.raises(ValueError, match="p2_MPa"):
        actuator_from_spring(PAPER_FIG5, p2_MPa=0.0)
    with pytest.raises(ValueError, match="gamma_max_deg"):
        actuator_from_spring(PAPER_FIG5, gamma_min_deg=110, gamma_max_deg=100)


def test_cap_limits_dmax():
    act = actuator_from_spring(PAPER_FIG5, D_max_cap_Nms_per_rad=200.0)
    assert act.D_max_Nms_per_rad == 200.0 and act.D_min_Nms_per_rad < 200.0


def test_from_design_json(tmp_path, monkeypatch):
    """from_design_json goes through design_io.load_design and its .gas_spring."""
    params = {"A1_mm2": PAPER_FIG5.A1_mm2, "A2_mm2": PAPER_FIG5.A2_mm2, "V1_mm3": PAPER_FIG5.V1_mm3,
              "V2_mm3": PAPER_FIG5.V2_mm3, "p1_MPa": PAPER_FIG5.p1_MPa, "p2_MPa": PAPER_FIG5.p2_MPa,
              "travel_mm": 40.0, "n_polytropic": 1.0}
    path = tmp_path / "design.json"
    path.write_text(json.dumps({"format_version": 1, "parameters": params}))
    # the contract used: design_io.load_design(path).gas_spring (the loader itself is tested by its owner)
    import vvea_design.spring.design_file as dio

    def load_design(p):
        d = json.loads(open(p).read())["parameters"]
        return types.SimpleNamespace(gas_spring=GasSpring(**d))

    monkeypatch.setattr(dio, "load_design", load_design)
    act = from_design_json(path, pulley_radius_m=PAPER_PULLEY_RADIUS_M)
    assert act.K_Nm_per_rad == pytest.approx(362.0, rel=1e-6)
    assert act.name == "design"
    assert math.isclose(act.K_Nm_per_rad / act.D_min_Nms_per_rad,
                        PAPER_FIG5.mean_stiffness_N_per_mm() / TABLE3_L_NS_PER_MM[50.0], rel_tol=1e-9)
