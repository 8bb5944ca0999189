"""The design JSON: round trip, reproducible curve from parameters, clear errors for bad files."""

import json

import numpy as np
import pytest

from vvea_design.spring.design import Design
from vvea_design.spring.design_file import (
    DesignFileError,
    load_design,
    load_requirements_from_design,
    save_design,
    spring_from_json,
)
from vvea_design.spring.gas_spring import force_N
from vvea_design.spring.problem import evaluate_design
from vvea_design.spring.requirements import Requirements
from tests.helpers import REPO

REQUIRED = {
    "parameters": ["piston_diameter_mm", "outer_diameter_mm", "V1_mm3", "V2_mm3", "A1_mm2", "A2_mm2", "p1_MPa",
                   "p2_MPa", "travel_mm", "n_polytropic"],
    "performance": ["linearity_error", "mean_stiffness_N_per_mm", "max_force_N", "mass_g", "peak_pressure_MPa"],
}


@pytest.fixture()
def design_file(tmp_path):
    req = Requirements()
    ev = evaluate_design(Design(34.5, 59.5, 41500.0, 90000.0), req)
    return save_design(tmp_path / "design.json", ev, req, optimiser={"seed": 0}), ev, req


def test_contents_and_round_trip(design_file):
    path, ev, req = design_file
    data = json.loads(path.read_text())
    assert data["format"] == "vvea-design" and data["format_version"] == 1
    for section, keys in REQUIRED.items():
        assert set(keys) <= set(data[section])
    assert set(data["constraints"]) == set(ev.margins)
    assert all(isinstance(v, float) for v in data["constraints"].values())
    assert load_design(path) == ev.design
    assert load_requirements_from_design(path) == req


def test_force_curve_reproducible_from_parameters_alone(design_file):
    path, ev, _ = design_file
    p = json.loads(path.read_text())["parameters"]
    x = np.linspace(0, p["travel_mm"], 201)
    F = force_N(x, p["A1_mm2"], p["A2_mm2"], p["V1_mm3"], p["V2_mm3"], p["p1_MPa"], p["p2_MPa"], p["n_polytropic"])
    np.testing.assert_allclose(F, ev.design.gas_spring.force_N(x), rtol=1e-12)
    assert spring_from_json(path).linearity_error() == pytest.approx(ev.linearity_error, rel=1e-12)


def test_byte_stable(design_file, tmp_path):
    path, ev, req = design_file
    again = save_design(tmp_path / "again.json", ev, req, optimiser={"seed": 0})
    assert again.read_bytes() == path.read_bytes()


def _mutate(path, fn):
    data = json.loads(path.read_text())
    fn(data)
    path.write_text(json.dumps(data))
    return path


@pytest.mark.parametrize(
    "mutation, match",
    [
        (lambda d: d.update(format="something-else"), "not a vvea design file"),
        (lambda d: d.update(format_version=99), "unsupported format_version"),
        (lambda d: d["parameters"].pop("V2_mm3"), r"parameters.V2_mm3 is missing"),
        (lambda d: d["parameters"].update(A1_mm2="big"), r"parameters.A1_mm2 must be a finite number"),
        (lambda d: d["parameters"].update(A1_mm2=1234.0), r"parameters.A1_mm2 = 1234 disagrees"),
        (lambda d: d["parameters"].update(piston_diameter_mm=-3.0), "piston_diameter_mm must be a positive number"),
        (lambda d: d["fixed"].update(colour="red"), "unknown fixed parameter"),
        (lambda d: d.pop("parameters"), "missing object 'parameters'"),
        # issue 11 item 3: nothing that shapes the geometry is taken from a default
        (lambda d: d.pop("fixed"), r"missing object 'fixed'.*min_outer_wall_mm = 1.5"),
        (lambda d: d["fixed"].pop("min_base_mm"), r"fixed.min_base_mm missing"),
        (lambda d: [d["fixed"].pop(k) for k in ("min_outer_wall_mm", "housing_material")],
         r"fixed.min_outer_wall_mm, fixed.housing_material missing"),
        (lambda d: d["parameters"].pop("layout"), r"parameters.layout is missing"),
        (lambda d: d["parameters"].update(layout="sideways"), r"parameters.layout is 'sideways'"),
        (lambda d: d.update(fixed=[1, 2]), "'fixed' must be an object, got list"),
        (lambda d: d["parameters"].pop("setpoint_x0_mm"), r"parameters.setpoint_x0_mm is missing"),
        (lambda d: d["parameters"].update(setpoint_x0_mm="0"), r"parameters.setpoint_x0_mm must be a finite number"),
        (lambda d: d["fixed"].update(travel_mm=30.0), r"fixed.travel_mm = 30 disagrees with parameters.travel_mm = 40"),
        (lambda d: d["fixed"].update(n_polytropic=1.4), r"fixed.n_polytropic = 1.4 disagrees"),
        # issue 11 item 11: unknown keys are errors naming them
        (lambda d: d.update(version="99"), r"unknown top-level key\(s\) \['version'\].*format_version, parameters"),
        (lambda d: d["parameters"].update(p3_MPa=1.0), r"unknown key\(s\) \['p3_MPa'\] in 'parameters'"),
    ],
)
def test_bad_design_json_gets_a_clear_error(design_file, mutation, match):
    path = _mutate(design_file[0], mutation)
    with pytest.raises(DesignFileError, match=match) as exc:
        load_design(path)
    assert str(path) in str(exc.value)


def test_foreign_and_broken_files(tmp_path):
    p = tmp_path / "x.json"
    p.write_text("{not json")
    with pytest.raises(DesignFileError, match="not valid JSON"):
        load_design(p)
    p.write_text("[1, 2, 3]")
    with pytest.raises(DesignFileError, match="expected a JSON object"):
        load_design(p)
    with pytest.raises(DesignFileError, match="does not exist"):
        load_design(tmp_path / "missing.json")


def test_missing_spec_is_an_error_not_the_defaults(design_file):
    path = _mutate(design_file[0], lambda d: d.pop("spec"))
    load_design(path)  # the geometry does not need the spec
    with pytest.raises(DesignFileError, match="missing object 'spec'"):
        load_requirements_from_design(path)
    path = _mutate(path, lambda d: d.update(spec={"travel_mm": "long"}))
    with pytest.raises(DesignFileError, match=r"spec: travel_mm must be a number"):
        load_requirements_from_design(path)


def test_equal_fixed_copies_and_every_committed_design_load():
    """Every design.json in the repository is complete and loads (the CAD and study inputs)."""
    from pathlib import Path

    root = REPO
    found = [p for p in root.rglob("*.json")
             if ".git" not in p.parts and '"format": "vvea-design"' in p.read_text(errors="replace")]
    assert len(found) >= 2
    for path in found:
        d = load_design(path)
        assert d.fixed.travel_mm == d.gas_spring.travel_mm
        load_requirements_from_design(path)


@pytest.mark.parametrize("command", ["cad", "bladder", "spring", "map"])
def test_commands_refuse_an_incomplete_design(design_file, tmp_path, command):
    """Issue 11 item 3: `vvea cad`/`bladder` used to exit 0 with the default housing and bladder."""
    from typer.testing import CliRunner

    from vvea_design.cli.main import app

    path = _mutate(design_file[0], lambda d: d["fixed"].pop("min_base_mm"))
    if command == "spring":  # the spring is eq. 5 of `parameters` alone: the file's parameters are complete
        path = _mutate(path, lambda d: d.update(version="99"))
    res = CliRunner().invoke(app, [command, str(path), "--out", str(tmp_path / "out")])
    assert res.exit_code == 2, res.output
    assert str(path) in res.output and ("fixed.min_base_mm missing" in res.output or "'version'" in res.output)
    assert "Traceback" not in res.output
    assert not (tmp_path / "out").exists()


@pytest.mark.parametrize(
    "mutation",
    [lambda d: d.pop("fixed"), lambda d: d["fixed"].pop("min_base_mm"), lambda d: d["parameters"].pop("setpoint_x0_mm"),
     lambda d: d.update(version="99")],
    ids=["no-fixed", "no-fixed.min_base_mm", "no-setpoint", "unknown-key"],
)
def test_schema_and_loader_agree_a_design_is_self_contained(design_file, mutation):
    import jsonschema

    from vvea_design.schema import shipped_schema

    path = _mutate(design_file[0], mutation)
    with pytest.raises(jsonschema.ValidationError):
        jsonschema.validate(json.loads(path.read_text()), shipped_schema("design.schema.json"))
    with pytest.raises(DesignFileError):
        load_design(path)
