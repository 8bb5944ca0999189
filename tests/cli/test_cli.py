"""The `vvea` command line of the spring side, and the linearity regression helpers."""

import json

import pytest
from typer.testing import CliRunner

from vvea_design.cli.main import app
from vvea_design.spring.design import Design
from vvea_design.spring.design_file import save_design
from vvea_design.spring.problem import evaluate_design
from vvea_design.spring.requirements import Requirements
from vvea_design.testing import LinearityRegression, assert_linearity, check_linearity

runner = CliRunner()


@pytest.fixture()
def design_json(tmp_path):
    req = Requirements()
    return save_design(tmp_path / "d.json", evaluate_design(Design(34.5, 59.5, 41500.0, 90000.0), req), req)


def test_check_passes_and_fails_with_exit_codes(design_json):
    ok = runner.invoke(app, ["check", str(design_json), "--max-linearity", "0.02"])
    assert ok.exit_code == 0, ok.output
    bad = runner.invoke(app, ["check", str(design_json), "--max-linearity", "0.01"])
    assert bad.exit_code == 1
    assert "exceeds the limit" in bad.output


def test_check_catches_an_edited_design(design_json):
    data = json.loads(design_json.read_text())
    data["parameters"]["V2_mm3"] *= 0.6  # a designer shrinks the gas volume by hand
    design_json.write_text(json.dumps(data))
    # issue 24: the stored derived values (geometry, performance) now disagree with the edit: refused, named
    res = runner.invoke(app, ["check", str(design_json), "--max-linearity", "0.02"])
    assert res.exit_code == 2 and "disagree" in res.output and "delete the blocks" in res.output, res.output
    for block in ("geometry", "performance", "constraints", "constraint_details"):  # as the message says
        data.pop(block, None)
    design_json.write_text(json.dumps(data))
    res = runner.invoke(app, ["check", str(design_json), "--max-linearity", "0.02"])
    assert res.exit_code == 1 and "FAIL" in res.output


def test_pytest_helper(design_json):
    lin = check_linearity(design_json, 0.02)
    assert 0 < lin < 0.02
    assert_linearity(design_json, 0.02)
    with pytest.raises(LinearityRegression, match="exceeds the limit"):
        assert_linearity(design_json, 0.005)


def test_spring_command_writes_curve_and_plot(design_json, tmp_path):
    res = runner.invoke(app, ["spring", str(design_json), "--out", str(tmp_path / "s"), "--p2", "2"])
    assert res.exit_code == 0, res.output
    lines = (tmp_path / "s" / "spring.csv").read_text().splitlines()
    assert lines[0] == "x_mm,force_N,stiffness_N_per_mm,P1_MPa,P2_MPa" and len(lines) == 82
    assert (tmp_path / "s" / "spring.png").stat().st_size > 10_000


def test_bad_inputs_exit_with_messages(tmp_path, design_json):
    res = runner.invoke(app, ["spring", str(tmp_path / "none.json")])
    assert res.exit_code == 2 and "does not exist" in res.output
    spec = tmp_path / "bad.toml"
    spec.write_text("max_outer_diameter_mm = -1\n")
    res = runner.invoke(app, ["optimise", "--spec", str(spec), "--out", str(tmp_path / "o.json")])
    assert res.exit_code == 2 and "max_outer_diameter_mm" in res.output
    res = runner.invoke(app, ["check", str(design_json), "--max-linearity", "5"])
    assert res.exit_code == 2


def test_infeasible_spec_exits_3_and_names_the_constraint(tmp_path):
    spec = tmp_path / "tight.toml"
    # one layout: the exit code and message are the point here (the library's multi-layout report: test_optimise)
    spec.write_text('max_outer_diameter_mm = 36.0\nmin_mean_stiffness_N_per_mm = 150.0\nlayouts = ["inner_tube"]\n')
    res = runner.invoke(app, ["optimise", "--spec", str(spec), "--out", str(tmp_path / "o.json")])
    assert res.exit_code == 3
    assert "no design meets the requirements" in res.output
    assert not (tmp_path / "o.json").exists()


def test_map_command(design_json, tmp_path):
    res = runner.invoke(app, ["map", str(design_json), "--x", "piston_diameter_mm", "--y", "V1_mm3", "--n", "9",
                              "--out", str(tmp_path / "m")])
    assert res.exit_code == 0, res.output
    assert (tmp_path / "m" / "map_piston_diameter_mm_V1_mm3.png").exists()
    assert len((tmp_path / "m" / "map_piston_diameter_mm_V1_mm3.csv").read_text().splitlines()) == 82


def test_pareto_command(tmp_path):
    # one layout (--spec): the command's sweep, files and errors are the point (choosing layouts: test_optimise)
    spec = tmp_path / "one_layout.toml"
    spec.write_text('layouts = ["bulkhead"]\n')
    res = runner.invoke(app, ["pareto", "--axis", "outer_diameter", "--values", "55", "--spec", str(spec),
                              "--out", str(tmp_path)])
    assert res.exit_code == 0, res.output
    rows = (tmp_path / "pareto_outer_diameter.csv").read_text().splitlines()
    assert len(rows) == 2 and "linearity_error" in rows[0]
    assert "bulkhead" in rows[1]
    assert (tmp_path / "pareto_outer_diameter.png").exists()
    bad = runner.invoke(app, ["pareto", "--axis", "colour", "--values", "1"])
    assert bad.exit_code == 2 and "--axis must be one of" in bad.output
