"""Equal stiffness (the charge for a target K inside the pressure limits), the unit's own damping range, every case counted."""

from __future__ import annotations

import math
import warnings

import matplotlib
import numpy as np
import pandas as pd
import pytest

from tests.helpers import REPO
from vvea_design.actuator.damping import TABLE4_SOURCE, UNIT_SOURCE, DampingRange, unit_damping_range
from vvea_design.actuator.design_study import FULL_CHARGE, EQUAL_STIFFNESS, study_actuators
from vvea_design.actuator.figures import plot_design_vs_sea
from vvea_design.actuator.model import PAPER_PULLEY_RADIUS_M, PAPER_SETTINGS
from vvea_design.actuator.statistics import counted_pair, table5_statistics
from vvea_design.actuator.stiffness import ATMOSPHERE_MPA, charge_for_stiffness
from vvea_design.spring.gas_spring import PAPER_FIG5


@pytest.fixture(scope="module")
def design():
    from vvea_design.spring.design_file import load_design

    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # an old design file: loaded with its own (gas-only) rules
        return load_design(REPO / "cad" / "design.json")


def test_charge_for_the_paper_stiffness_is_inside_the_range(design):
    ch = charge_for_stiffness(design.gas_spring, 362.0, pulley_radius_m=PAPER_PULLEY_RADIUS_M)
    assert ch.in_range and ch.binding_limit is None
    assert ch.K_Nm_per_rad == pytest.approx(362.0, rel=1e-9)
    # K is proportional to the charge: the full charge (4 MPa) gives K_full, half the K needs half the charge
    assert ch.p2_MPa == pytest.approx(ch.p2_full_MPa * 362.0 / ch.K_full_Nm_per_rad, rel=1e-9)
    assert ch.p2_full_MPa == pytest.approx(design.p2_MPa) and ch.max_charge_MPa == pytest.approx(design.p2_MPa)
    half = design.gas_spring.with_pressures(ch.p2_MPa)
    assert ch.p1_MPa == pytest.approx(half.p1_MPa) and ch.k_N_per_mm == pytest.approx(half.mean_stiffness_N_per_mm())
    assert ch.to_dict()["in_range"] is True and "target 362" in ch.describe()


def test_an_out_of_range_target_names_the_limit_that_binds(design):
    s = design.gas_spring
    hi = charge_for_stiffness(s, 5000.0, pulley_radius_m=PAPER_PULLEY_RADIUS_M)
    assert not hi.in_range and "highest charge" in hi.binding_limit and "chamber 2" in hi.binding_limit
    assert hi.K_Nm_per_rad == pytest.approx(hi.K_full_Nm_per_rad) and hi.p2_MPa == pytest.approx(hi.p2_full_MPa)
    assert "out of range" in hi.describe()
    lo = charge_for_stiffness(s, 1.0, pulley_radius_m=PAPER_PULLEY_RADIUS_M)
    assert not lo.in_range and "lowest pressure" in lo.binding_limit
    P1, P2 = s.with_pressures(lo.p2_MPa).pressures_MPa(np.linspace(0, s.travel_mm, 401))
    assert min(P1.min(), P2.min()) == pytest.approx(ATMOSPHERE_MPA, rel=1e-6)
    # a lower max charge lowers the top of the range
    capped = charge_for_stiffness(s, 362.0, pulley_radius_m=PAPER_PULLEY_RADIUS_M, max_charge_MPa=1.0)
    assert not capped.in_range and capped.p2_MPa == pytest.approx(1.0 / max(1.0, s.p1_MPa / s.p2_MPa))


@pytest.mark.parametrize("kwargs, name", [
    (dict(target_K_Nm_per_rad=-1.0), "target_K_Nm_per_rad"),
    (dict(pulley_radius_m=0.0), "pulley_radius_m"),
    (dict(max_charge_MPa=float("nan")), "max_charge_MPa"),
    (dict(min_pressure_MPa=9.0), "no charge fits"),
])
def test_charge_bad_input_is_named(kwargs, name):
    args = dict(target_K_Nm_per_rad=362.0, pulley_radius_m=PAPER_PULLEY_RADIUS_M) | kwargs
    with pytest.raises(ValueError, match=name):
        charge_for_stiffness(PAPER_FIG5, **args)


def test_the_units_own_damping_range_through_the_pulley(design):
    r = 0.06388
    rng = unit_damping_range(design, pulley_radius_m=r)
    L_min, L_max = design.damping_range_N_s_per_mm()
    assert rng.source == UNIT_SOURCE and rng.from_unit
    assert rng.D_min_Nms_per_rad == pytest.approx(2 * r**2 * 1e3 * L_min)
    assert rng.D_max_Nms_per_rad == pytest.approx(2 * r**2 * 1e3 * L_max)
    assert rng.relief_torque_Nm == pytest.approx(2 * r * design.fixed.relief_force_N)
    paper = unit_damping_range(PAPER_FIG5, pulley_radius_m=r)  # a bare gas spring has no valve: Table 4, said so
    assert paper.source == TABLE4_SOURCE and not paper.from_unit and "GasSpring" in paper.why
    assert (paper.D_min_Nms_per_rad, paper.D_max_Nms_per_rad) == (12.1, 200.0)
    with pytest.raises(ValueError, match="D_max_Nms_per_rad"):
        DampingRange(5.0, 1.0, "x", "y")


def test_study_actuators_equal_stiffness_and_full_charge(design):
    runs, rng = study_actuators(design)
    (l1, d1, s1, c1), (l2, d2, s2, c2) = runs
    assert (l1, l2) == (EQUAL_STIFFNESS, FULL_CHARGE)
    assert d1.K_Nm_per_rad == pytest.approx(362.0) and s1.K_Nm_per_rad == d1.K_Nm_per_rad and not s1.variable_damping
    assert d2.K_Nm_per_rad == pytest.approx(c2.K_full_Nm_per_rad) and s2.K_Nm_per_rad == d2.K_Nm_per_rad
    assert d2.K_Nm_per_rad > 2 * d1.K_Nm_per_rad  # the reference design at 4 MPa: 761 N m/rad
    assert (d1.D_min_Nms_per_rad, d1.D_max_Nms_per_rad) == (rng.D_min_Nms_per_rad, rng.D_max_Nms_per_rad)
    assert c2.p2_MPa == pytest.approx(design.p2_MPa)
    # the paper's spring at the paper's pulley: both runs at 362, Table 4's range -> the design *is* VVEA
    runs, rng = study_actuators(PAPER_FIG5)
    assert rng.source == TABLE4_SOURCE
    assert runs[0][1].with_(name="VVEA") == PAPER_SETTINGS["VVEA"]
    with pytest.raises(ValueError, match="mapping options"):
        study_actuators(design, mapping={"p2_MPa": 2.0})


def test_counted_pair_counts_every_case():
    # c1 both valid, X better; c2 X invalid, Y valid (a loss); c3 X valid, Y unsolved (a win); c4 neither; c5 tie
    x = [1.0, 1.0, 1.0, 1.0, 2.0]
    y = [2.0, 2.0, float("nan"), 3.0, 2.0]
    ux = [True, False, True, False, True]
    uy = [True, True, False, False, True]
    c = counted_pair(x, y, ux, uy)
    assert (c.n_cases, c.X_beats_Y, c.X_worse_than_Y, c.ties, c.neither_usable) == (5, 2, 1, 1, 1)
    assert (c.only_X_usable, c.only_Y_usable, c.n_both_usable) == (1, 1, 2)
    assert c.X_beats_Y + c.X_worse_than_Y + c.ties + c.neither_usable == c.n_cases
    assert c.fraction_X_beats_Y == pytest.approx(2 / 5) and c.meanrmse_Y_over_X == pytest.approx(2.0 / 1.5)


def test_table5_statistics_carry_the_counted_pairs():
    rows = []
    for cid, d in {"c1": dict(VVEA=1.0, SEA=2.0), "c2": dict(VVEA=1.0, SEA=2.0)}.items():
        for s, v in d.items():
            a = PAPER_SETTINGS[s]
            rows.append(dict(case_id=cid, setting=s, A_rad=1.0, T_s=1.0, rmse=v, success=True, start="x",
                             valid=not (cid == "c2" and s == "VVEA"), verified=True, status="ok", seconds=0.1,
                             D_min_Nms_per_rad=a.D_min_Nms_per_rad, D_max_Nms_per_rad=a.D_max_Nms_per_rad))
    st = table5_statistics(pd.DataFrame(rows))
    c = st.counted_pair("VVEA", "SEA")
    assert (c.X_beats_Y, c.X_worse_than_Y, c.only_Y_usable) == (1, 1, 1)
    assert st.pair("VVEA", "SEA", "valid").n_cases == 1  # the "valid" scope still leaves c2 out
    assert st.to_dict()["counted"]["VVEA_vs_SEA"]["fraction_X_beats_Y"] == 0.5


def test_designer_figure_marks_every_case():
    rows = []
    for (A, T), d in {(0.2, 0.3): dict(design=(1.0, True), SEA=(2.0, True)),
                      (0.2, 1.0): dict(design=(1.0, False), SEA=(2.0, True)),
                      (0.7, 0.3): dict(design=(1.0, True), SEA=(1.0, False)),
                      (0.7, 1.0): dict(design=(1.0, False), SEA=(1.0, False))}.items():
        for s, (v, ok) in d.items():
            rows.append(dict(setting=s, A_rad=A, T_s=T, rmse=v, valid=ok, success=True, verified=True))
    before = matplotlib.get_backend()
    fig = plot_design_vs_sea(pd.DataFrame(rows), [(EQUAL_STIFFNESS, "design", "SEA", 362.0)], damping="D 12-200")
    texts = [t.get_text() for t in fig.axes[0].texts]
    assert sorted(texts) == sorted(["-50.0 %", "design not valid\n(a loss)", "SEA not valid\n(a win)",
                                    "neither\nvalid"])
    assert "better in 2, worse in 1 of 4" in fig.axes[0].get_title()
    assert len(fig.axes) == 2 and matplotlib.get_backend() == before  # the panel and its colour bar
    assert math.isclose(fig.get_size_inches()[1], 4.6)
