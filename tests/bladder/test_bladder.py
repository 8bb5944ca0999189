"""The bladder check (vvea_design.bladder.check, silicones, cli_bladder)."""

from __future__ import annotations

import json
import math

import numpy as np
import pytest
from tests.helpers import make_app
from typer.testing import CliRunner

from vvea_design.bladder.check import (
    PAPER_BLADDER,
    SURROGATE_FACTOR,
    BladderError,
    check_bladder,
    check_membrane,
    strain_bound,
    write_bladder_report,
)
from vvea_design.cli.bladder import register
from vvea_design.spring.design import Design, FixedParameters
from vvea_design.bladder.membrane import TAUT
from vvea_design.materials.silicones import CRITERIA, SILICONES, StrainCriterion, allowable_strain, get_silicone
from tests.helpers import REPO

#: The hand example: the old gas-only optimum, under the gas-only rules it was sized by (the membrane-physics tests
#: below pin its numbers). Under the default buildable rules the same parameters leave no room for the bladder
#: (test_the_old_optimum_does_not_fit_under_the_buildable_rules).
GAS_ONLY = FixedParameters(sizing_rules="gas_only")
EXAMPLE = Design(35.18, 59.5, 47107.0, 99735.0, fixed=GAS_ONLY)
#: A unit the optimiser built: the default optimum under the first buildability rules (`vvea optimise`, seed 0:
#: bulkhead, thread joint; with the joints' seals clear of the threads the default optimum is the inner_tube unit of
#: cad/design.json).
OPTIMUM = Design(32.590048463374174, 59.00923543940918, 30391.70736111289, 75289.11744253983, layout="bulkhead",
                 V2_top_mm3=0.0)
N = 48  # elements in the default tests (the study runs the fine meshes)

REQUIRED_KEYS = {"membrane", "volume_change_mm3", "max_principal_strain", "pressure_MPa", "strain_bound",
                 "allowable_strain", "passes"}


@pytest.fixture(scope="module")
def example():
    return check_bladder(EXAMPLE, n_elements=N)


@pytest.fixture(scope="module")
def optimum():
    return check_bladder(OPTIMUM, n_elements=N)


def test_result_is_consistent_with_the_design(example):
    r = example
    dv = r.volume_change_mm3
    assert dv["expanded"] - dv["compressed"] == pytest.approx(EXAMPLE.displaced_volume_mm3)
    for k in ("expanded", "compressed"):
        assert r.ends[k].solution.volume_change_mm3 == pytest.approx(dv[k], rel=1e-6)
    assert r.mid_radius_mm == pytest.approx(EXAMPLE.bladder_mid_radius_mm)
    assert r.free_length_mm == pytest.approx(EXAMPLE.bladder_free_length_mm)
    e, c = r.ends["expanded"], r.ends["compressed"]
    assert e.pressure_MPa > 0 and abs(c.pressure_MPa) < 0.01 * e.pressure_MPa
    assert np.all(e.solution.state == TAUT) and c.wrinkled_fraction > 0.9
    for end in r.ends.values():
        assert end.strain_bound >= end.max_principal_strain
        assert end.strain_bound >= end.clamp_strain >= end.bending_strain > 0
        assert end.touches["inner_tube"] == (end.gap_inner_tube_mm < 0)
        assert end.touches["outer_bore"] == (end.gap_outer_bore_mm < 0)
    # the expanded sleeve bulges outward, the compressed one inward, never past the cast radius the other way
    assert e.solution.r_mm.max() > r.mid_radius_mm > c.solution.r_mm.min()
    assert r.strain_bound == max(e.strain_bound, c.strain_bound)
    assert r.passes == (r.strain_bound <= r.allowable_strain and r.passes_room)


def test_bladder_json_has_the_required_keys_and_is_plain_json(example):
    d = example.to_dict()
    assert REQUIRED_KEYS <= set(d)
    assert set(d["membrane"]) >= {"mid_radius_mm", "free_length_mm", "thickness_mm", "shear_modulus_MPa"}
    for key in ("volume_change_mm3", "max_principal_strain", "pressure_MPa", "touches", "gap_inner_tube_mm"):
        assert set(d[key]) == {"expanded", "compressed"}
    assert json.loads(json.dumps(d)) == d


def test_membrane_reference_in_json_reproduces_the_result(example):
    """bladder.json's membrane block is enough to recompute the strains."""
    d = example.to_dict()
    m = d["membrane"]
    again = check_membrane(m["mid_radius_mm"], m["free_length_mm"], m["thickness_mm"], d["volume_change_mm3"],
                           n_elements=m["n_elements"])
    assert again.to_dict()["max_principal_strain"] == pytest.approx(d["max_principal_strain"], rel=1e-6)


def test_neo_hookean_strains_do_not_depend_on_the_modulus(example):
    """Volume-controlled neo-Hookean membrane: the shape is modulus-free, the pressure scales with mu."""
    soft = check_bladder(EXAMPLE, "ecoflex-00-30", n_elements=N)
    ratio = SILICONES["ecoflex-00-30"].shear_modulus_MPa / SILICONES["dragon-skin-20"].shear_modulus_MPa
    e0, e1 = example.ends["expanded"], soft.ends["expanded"]
    assert e1.max_principal_strain == pytest.approx(e0.max_principal_strain, rel=1e-5)
    assert e1.strain_bound == pytest.approx(e0.strain_bound, rel=1e-4)
    assert e1.pressure_MPa == pytest.approx(e0.pressure_MPa * ratio, rel=1e-5)


def test_strains_grow_with_the_stroke(example):
    d = example.to_dict()
    m = d["membrane"]
    half = {k: v / 2 for k, v in d["volume_change_mm3"].items()}
    small = check_membrane(m["mid_radius_mm"], m["free_length_mm"], m["thickness_mm"], half, n_elements=N)
    assert small.ends["expanded"].max_principal_strain < example.ends["expanded"].max_principal_strain
    assert 0 < small.ends["expanded"].pressure_MPa < example.ends["expanded"].pressure_MPa
    assert small.strain_bound < example.strain_bound


@pytest.mark.parametrize("design", [
    EXAMPLE,
    Design(30.0, 59.5, 60000.0, 80000.0, fixed=GAS_ONLY),
    Design(25.0, 50.0, 30000.0, 40000.0, fixed=GAS_ONLY),
    Design(35.18, 59.5, 47107.0, 99735.0, fixed=FixedParameters(bladder_cast_fill=0.2, sizing_rules="gas_only")),
    Design(30.0, 59.5, 60000.0, 80000.0),
    OPTIMUM,
], ids=["example", "long", "small", "cast-early", "long-buildable", "optimum"])
def test_fast_strain_bound_is_conservative_against_the_fine_check(design):
    fast = strain_bound(design)
    fine = check_bladder(design, n_elements=192).strain_bound
    assert fine <= fast <= SURROGATE_FACTOR * 1.05 * fine


def test_strain_bound_is_infinite_for_a_bladder_that_does_not_fit():
    d = Design(35.18, 59.5, 47107.0, 400000.0, fixed=GAS_ONLY)  # V2 beyond the annulus capacity
    assert math.isinf(strain_bound(d))
    with pytest.raises(BladderError, match="V2_mm3"):
        check_bladder(d)


def test_the_old_optimum_does_not_fit_under_the_buildable_rules():
    """The gas-only optimum's parameters under the default (buildable) rules: the joints' zones and the thicker
    walls take the room its bladder was cast in. The optimiser rejects it (bladder_room_compressed < 0), the
    bladder check names the field, the fast bound is infinite."""
    from vvea_design.spring.problem import evaluate_design
    from vvea_design.spring.requirements import Requirements

    d = Design(35.18, 59.5, 47107.0, 99735.0)
    assert d.fixed.sizing_rules == "buildable"
    ev = evaluate_design(d, Requirements())
    assert not ev.feasible and ev.margins["bladder_room_compressed"] < 0
    assert math.isinf(strain_bound(d))
    with pytest.raises(BladderError, match="V2_mm3|cannot give up"):
        check_bladder(d)


def test_a_unit_the_optimiser_accepts_has_a_bladder_that_takes_the_stroke():
    """No missing constraint: every buildable design of a random sample that meets the optimiser's bladder-room
    constraints (bladder_room_compressed, bladder_room_expanded: the sleeve's equal-volume radius clears the inner
    tube and the outer bore at both stroke ends) has a sleeve that can give up and take the stroke's volume change
    (a finite strain bound: the membrane check's volume limits hold); and the default optimum passes the fine
    check at its stroke ends."""
    from vvea_design.spring.parameters import DesignError
    from vvea_design.spring.problem import evaluate_design
    from vvea_design.spring.requirements import Requirements

    req = Requirements()
    rng = np.random.default_rng(0)
    checked = 0
    for _ in range(120):
        layout = str(rng.choice(["inner_tube", "bulkhead"]))
        extra = {"V2_top_mm3": float(rng.uniform(0, 3000))} if layout == "bulkhead" else {}
        p = (rng.uniform(28, 38), rng.uniform(56, 62), rng.uniform(20000, 60000), rng.uniform(50000, 110000))
        try:
            d = Design(*p, layout=layout, **extra)
            ev = evaluate_design(d, req)
        except (ValueError, DesignError):  # parameters with no geometry (the optimiser's bounds exclude them)
            continue
        if min(ev.margins["bladder_room_compressed"], ev.margins["bladder_room_expanded"]) < 0:
            continue
        checked += 1
        assert math.isfinite(strain_bound(d)), d
    assert checked >= 10
    from tests.cad.cases import REFERENCE  # the default optimum (cad/design.json: inner_tube, threaded joints)

    ev = evaluate_design(REFERENCE, req)
    assert ev.feasible and min(ev.margins["bladder_room_compressed"], ev.margins["bladder_room_expanded"]) >= 0


def test_silicone_library_and_criteria():
    for key, s in SILICONES.items():
        assert s.shear_modulus_MPa > 0 and s.elongation_at_break > 0 and s.source and s.hardness
        assert allowable_strain(key, "cyclic") == pytest.approx(min(s.elongation_at_break / 10, 0.25))
        assert allowable_strain(key, "static") == pytest.approx(s.elongation_at_break / 3)
    assert allowable_strain("dragon-skin-20") == allowable_strain("dragon-skin-20", "cyclic")
    assert allowable_strain("dragon-skin-20", 0.3) == 0.3
    mine = StrainCriterion("mine", divisor=4.0, cap=0.5)
    assert allowable_strain("sylgard-184", mine) == pytest.approx(0.25)
    # softer silicones stretch further before breaking in this library, the harder Dragon Skin 30 less
    assert SILICONES["dragon-skin-30"].elongation_at_break < SILICONES["dragon-skin-10"].elongation_at_break
    assert set(CRITERIA) >= {"cyclic", "static"}
    with pytest.raises(ValueError, match="unknown silicone"):
        get_silicone("unobtainium")


def test_criterion_changes_only_the_verdict(example):
    static = check_bladder(EXAMPLE, criterion="static", n_elements=N)
    assert static.strain_bound == pytest.approx(example.strain_bound)
    assert static.allowable_strain == pytest.approx(SILICONES["dragon-skin-20"].elongation_at_break / 3)
    tight = check_bladder(EXAMPLE, criterion=0.5 * example.strain_bound, n_elements=N)
    assert not tight.passes_strain and not tight.passes


@pytest.mark.parametrize("kwargs, match", [
    (dict(mid_radius_mm=0.0), "mid_radius_mm"),
    (dict(free_length_mm=-5.0), "free_length_mm"),
    (dict(thickness_mm=float("nan")), "thickness_mm"),
    (dict(material="unobtainium"), "unknown silicone"),
    (dict(criterion="forever"), "unknown strain criterion"),
    (dict(volume_change_mm3={"expanded": -1.0, "compressed": -10.0}), "expanded"),
    (dict(volume_change_mm3={"expanded": 10.0, "compressed": -1e7}), "cannot give up"),
    (dict(volume_change_mm3={"expanded": 1e7, "compressed": -10.0}), "cannot take more"),
    (dict(volume_change_mm3={"expanded": 10.0}), "keys"),
    (dict(inner_tube_outer_radius_mm=21.5), "does not clear the inner tube"),
])
def test_bad_input_gets_a_clear_error(kwargs, match):
    args = dict(mid_radius_mm=22.0, free_length_mm=90.0, thickness_mm=1.5,
                volume_change_mm3={"expanded": 1000.0, "compressed": -1000.0},
                inner_tube_outer_radius_mm=19.0, outer_bore_radius_mm=28.0, n_elements=16)
    args.update(kwargs)
    with pytest.raises(BladderError, match=match):
        check_membrane(**args)


def test_paper_bladder_reconstruction_runs_with_the_paper_stroke():
    p = PAPER_BLADDER
    half = p["stroke_volume_mm3"] / 2
    r = check_membrane(p["mid_radius_mm"], p["free_length_mm"], p["thickness_mm"],
                       {"expanded": half, "compressed": -half}, n_elements=N,
                       inner_tube_outer_radius_mm=p["inner_tube_outer_radius_mm"],
                       outer_bore_radius_mm=p["outer_bore_radius_mm"])
    assert p["inner_tube_outer_radius_mm"] < p["mid_radius_mm"] < p["outer_bore_radius_mm"]
    assert 0 < r.ends["expanded"].max_principal_strain < r.strain_bound < 1


def test_report_files(tmp_path, optimum):
    from vvea_design.bladder.check import BladderReport, BladderResult

    report = write_bladder_report(OPTIMUM, tmp_path / "out", n_elements=N)
    assert isinstance(report, BladderReport) and isinstance(report.result, BladderResult)
    assert (tmp_path / "out" / "bladder.json").is_file()
    assert (tmp_path / "out" / "bladder.png").stat().st_size > 10_000
    rows = (tmp_path / "out" / "bladder_profile.csv").read_text().splitlines()
    assert len(rows) == 1 + 2 * N
    on_disk = json.loads((tmp_path / "out" / "bladder.json").read_text())
    assert on_disk["strain_bound"] == pytest.approx(optimum.strain_bound)
    assert on_disk == report.to_dict()
    assert dict(report.files) == {"json": "bladder.json", "csv": "bladder_profile.csv", "png": "bladder.png"}
    assert on_disk["files"] == dict(report.files)
    for role in report.files:
        assert report.path(role) == tmp_path / "out" / report.files[role] and report.path(role).is_file()
    with pytest.raises(KeyError, match="roles: json, csv, png"):
        report.path("pdf")


def test_report_of_a_computed_check_solves_nothing_again(tmp_path, optimum, monkeypatch):
    """`vvea design` checks the bladder once and writes that check (no second FE solve)."""
    import vvea_design.bladder.check as check

    monkeypatch.setattr(check, "check_bladder", lambda *a, **k: pytest.fail("solved the bladder again"))
    report = write_bladder_report(OPTIMUM, tmp_path / "out", n_elements=N, result=optimum)
    assert report.result is optimum
    d = report.to_dict()
    assert d["strain_bound"] == pytest.approx(optimum.strain_bound)
    assert json.loads((tmp_path / "out" / "bladder.json").read_text()) == d


def _app():
    return make_app(register)


def _design_json(path):
    from vvea_design.spring.design_file import save_design
    from vvea_design.spring.problem import evaluate_design
    from vvea_design.spring.requirements import Requirements

    req = Requirements()
    return save_design(path, evaluate_design(OPTIMUM, req), req)


def test_cli_writes_bladder_json(tmp_path):
    dj = _design_json(tmp_path / "design.json")
    res = CliRunner().invoke(_app(), ["bladder", str(dj), "--out", str(tmp_path / "b"), "--elements", str(N)])
    assert res.exit_code == 0, res.output
    d = json.loads((tmp_path / "b" / "bladder.json").read_text())
    assert REQUIRED_KEYS <= set(d)
    assert (tmp_path / "b" / "bladder.png").is_file()
    assert "strain bound" in res.output


@pytest.mark.parametrize("args, match", [
    (["--material", "unobtainium"], "unknown --material"),
    (["--criterion", "forever"], "unknown --criterion"),
    (["--elements", "2"], "--elements"),
])
def test_cli_bad_options(tmp_path, args, match):
    dj = _design_json(tmp_path / "design.json")
    res = CliRunner().invoke(_app(), ["bladder", str(dj), "--out", str(tmp_path / "b"), *args])
    assert res.exit_code == 2
    assert match in " ".join(res.output.split())


def test_cli_missing_design_file(tmp_path):
    res = CliRunner().invoke(_app(), ["bladder", str(tmp_path / "nope.json"), "--out", str(tmp_path / "b")])
    assert res.exit_code == 2
    assert "nope.json" in " ".join(res.output.split())


def _study():
    import importlib.util
    from pathlib import Path

    path = REPO / "studies" / "bladder_verification.py"
    spec = importlib.util.spec_from_file_location("bladder_verification", path)
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod


def test_verification_study_quick(tmp_path):
    """The verification study (balloon, tube, convergence, surrogate, paper) at reduced size passes."""
    s = _study().run_all(tmp_path, quick=True)
    assert s["balloon"]["max_relative_error"] <= 1e-3
    assert s["tube"]["max_relative_error_laplace_small_strain"] <= 1e-3
    assert s["convergence"]["observed_order"]["balloon_pressure"] > 1.8
    assert s["surrogate"]["min_ratio_fast_over_fine"] >= 1.0
    assert s["passes"]
    for name in ("balloon.png", "tube.png", "convergence.png", "paper.png", "paper_sensitivity.png", "summary.json"):
        assert (tmp_path / name).is_file()


@pytest.mark.slow
def test_verification_study_full(tmp_path):
    s = _study().run_all(tmp_path, quick=False)
    assert s["passes"], s


def test_cli_allowable_override_decides_the_verdict(tmp_path):
    dj = _design_json(tmp_path / "design.json")
    res = CliRunner().invoke(_app(), ["bladder", str(dj), "--out", str(tmp_path / "b"), "--elements", str(N),
                                      "--allowable", "0.01", "--material", "dragon-skin-30"])
    assert res.exit_code == 0, res.output
    d = json.loads((tmp_path / "b" / "bladder.json").read_text())
    assert d["allowable_strain"] == 0.01 and not d["passes_strain"] and not d["passes"]
    assert d["material"]["key"] == "dragon-skin-30" and d["criterion"]["name"] == "given"


def test_plot_bladder_returns_a_figure_with_verdict_and_allowable():
    """Both wall surfaces, the allowable strain line and the verdict; no backend switch, nothing saved."""
    import matplotlib

    from vvea_design.bladder.check import check_bladder, plot_bladder
    from vvea_design.spring.design import Design

    backend = matplotlib.get_backend()
    res = check_bladder(OPTIMUM, n_elements=24)
    fig = plot_bladder(res, title="t")
    assert matplotlib.get_backend() == backend
    strain_ax = fig.axes[2]
    assert any(abs(line.get_xdata()[0] - 100 * res.allowable_strain) < 1e-9 for line in strain_ax.lines
               if len(line.get_xdata()) == 2 and line.get_xdata()[0] == line.get_xdata()[1])
    verdict = "PASS" if res.passes else "FAIL"
    assert strain_ax.get_title().startswith(verdict) and verdict in fig._suptitle.get_text()
    gaps = [t.get_text() for ax in fig.axes[:2] for t in ax.texts if t.get_text().startswith("gap")]
    e = res.ends["compressed"]
    assert f"gap {e.gap_inner_tube_mm:.2f} mm" in gaps
    # the drawn inner wall surface sits exactly the reported gap from the inner tube
    from vvea_design.bladder.check import _surfaces

    inner, outer = _surfaces(e.solution)
    assert inner[:, 0].min() - res.inner_tube_outer_radius_mm == pytest.approx(e.gap_inner_tube_mm, abs=0.02)
    assert (outer[:, 0] - inner[:, 0]).min() > 0
