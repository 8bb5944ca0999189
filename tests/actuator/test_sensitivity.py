"""The designer's question as a study: the design against an SEA of the same K while D_min, D_max and K move
(the sensitivity job), the design study's target stiffness and the lines `vvea design` prints."""

from __future__ import annotations

import json
import warnings

import pandas as pd
import pytest

from tests.helpers import REPO
from vvea_design.actuator.sensitivity import PARAMETERS, DesignSensitivity
from vvea_design.jobs.common import OptionError
from vvea_design.jobs.studies import run_design_sensitivity, target_stiffness

ONE = "0.4:0.8"  # one case: A = 0.4 rad, T = 0.8 s


@pytest.fixture(scope="module")
def design():
    from vvea_design.spring.design_file import load_design

    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # an old design file: loaded with its own (gas-only) rules
        return load_design(REPO / "cad" / "design.json")


@pytest.fixture(scope="module")
def sensitivity(design, tmp_path_factory):
    out = tmp_path_factory.mktemp("sens") / "sensitivity"
    s = run_design_sensitivity(design, out=out, grid=ONE, mesh_n=16, D_min_values=(0.0,), D_max_values=(100.0,),
                               K_factors=(0.75, 1.0), workers=1, progress=False)
    return s, out


def test_every_point_counts_every_case_and_the_base_is_marked(sensitivity):
    s, _ = sensitivity
    assert isinstance(s, DesignSensitivity)
    assert {p.parameter for p in s.points} == set(PARAMETERS)
    for p in s.points:
        assert p.n_cases == 1
        assert p.design_beats + p.design_worse <= p.n_cases and p.only_sea_valid <= p.design_worse
        assert p.n_both_valid <= p.n_cases
        if p.mean_rmse_ratio_design_over_sea is not None:
            assert p.n_both_valid >= 1 and p.mean_rmse_ratio_design_over_sea > 0
    # the K points: the design and its SEA at the same K, the base at the target (the paper's 362 N m/rad)
    ks = s.of("K")
    assert [round(p.K_Nm_per_rad, 6) for p in ks] == [round(0.75 * 362.0, 6), 362.0]
    assert [p.is_base for p in ks] == [False, True]
    # D_min and D_max move one at a time, the rest stays the base design's
    (dmin,), (dmax,) = s.of("D_min"), s.of("D_max")
    assert dmin.D_min_Nms_per_rad == 0.0 and dmin.D_max_Nms_per_rad == pytest.approx(s.base.D_max_Nms_per_rad)
    assert dmax.D_max_Nms_per_rad == 100.0 and dmax.D_min_Nms_per_rad == pytest.approx(s.base.D_min_Nms_per_rad)
    assert s.base.K_Nm_per_rad == pytest.approx(362.0) and s.damping.source


def test_files_hold_every_ocp_and_the_answer(sensitivity):
    s, out = sensitivity
    rows = pd.read_csv(out / "sensitivity.csv")
    names = {p.setting for p in s.points}
    assert names <= set(rows.setting)  # every design variant solved (and the SEAs of every K)
    assert {"SEA K=271.5", "SEA K=362"} <= set(rows.setting)
    d = json.loads((out / "sensitivity.json").read_text())
    assert d["answer"] == s.answer() and len(d["points"]) == len(s.points)
    assert (out / "sensitivity.png").stat().st_size > 10_000
    for par in PARAMETERS:
        assert par in s.answer() or sum(p.mean_rmse_ratio_design_over_sea is not None for p in s.of(par)) < 2


@pytest.mark.parametrize("kw, option", [
    ({"target_K_Nm_per_rad": -1.0}, "target_K_Nm_per_rad"),
    ({"D_min_values": (float("nan"),)}, "D_min_values"),
    ({"K_factors": (0.0,)}, "K_factors"),
    ({"grid": "0.4:x"}, "grid"),
])
def test_bad_options_are_named_before_any_solve(design, tmp_path, kw, option):
    with pytest.raises(OptionError) as exc:
        run_design_sensitivity(design, out=tmp_path / "o", progress=False, **kw)
    assert exc.value.option == option
    assert not (tmp_path / "o").exists()


def test_target_stiffness_defaults_to_the_paper_and_rejects_nonsense():
    assert target_stiffness(None) == 362.0 and target_stiffness(500) == 500.0
    for bad in (0.0, -3.0, float("inf"), float("nan")):
        with pytest.raises(OptionError, match="positive joint stiffness"):
            target_stiffness(bad, "study_target_K_Nm_per_rad")


def test_design_unit_checks_the_target_stiffness_before_any_work(tmp_path):
    from vvea_design.pipeline import design_unit

    with pytest.raises(OptionError) as exc:
        design_unit(None, tmp_path / "unit", study_target_K_Nm_per_rad=-5.0)
    assert exc.value.option == "study_target_K_Nm_per_rad"
    assert not (tmp_path / "unit").exists()
