"""The shipped JSON Schemas equal what the dataclasses generate, and accept the files the toolkit writes."""

import json
import tomllib
from pathlib import Path

import jsonschema
import pytest

from vvea_design.schema import SCHEMAS, design_schema, requirements_schema, shipped_schema
from vvea_design.spring.design import Design
from vvea_design.spring.design_file import save_design
from vvea_design.spring.problem import evaluate_design
from vvea_design.spring.requirements import Requirements, SpecError
from tests.helpers import REPO

ROOT = REPO


@pytest.mark.parametrize("name", sorted(SCHEMAS))
def test_shipped_schema_is_the_generated_one(name):
    assert shipped_schema(name) == SCHEMAS[name](), f"run `python -m vvea_design.schema` to regenerate {name}"
    jsonschema.Draft202012Validator.check_schema(shipped_schema(name))


def test_example_requirements_file_validates():
    data = tomllib.loads((ROOT / "examples" / "requirements.toml").read_text())
    jsonschema.validate(data, shipped_schema("requirements.schema.json"))
    Requirements.from_dict(data)  # and the loader agrees


def test_schema_and_loader_agree_on_bad_requirements():
    schema = requirements_schema()
    for bad in ({"max_outer_diameter": 50.0},  # unknown key (unit missing from the name)
                {"bladder_material": "rubber"},  # unknown silicone
                {"fixed": {"housing_material": "wood"}},  # unknown structural material
                {"bounds": {"V1_mm3": [1.0]}}):  # not [low, high]
        with pytest.raises(jsonschema.ValidationError):
            jsonschema.validate(bad, schema)
        with pytest.raises(SpecError):
            Requirements.from_dict(bad)


def test_design_files_validate(tmp_path):
    schema = shipped_schema("design.schema.json")
    req = Requirements()
    path = save_design(tmp_path / "d.json", evaluate_design(Design(34.5, 59.5, 41500.0, 90000.0), req), req,
                       optimiser={"seed": 0})
    jsonschema.validate(json.loads(path.read_text()), schema)
    # the schema and the loader agree on the committed design files: one accepts what the other does
    from vvea_design.spring.design_file import DesignFileError, load_design

    for f in (ROOT / "cad" / "design.json", ROOT / "studies" / "results" / "optimise" / "design.json"):
        try:
            load_design(f)
        except DesignFileError:
            with pytest.raises(jsonschema.ValidationError):
                jsonschema.validate(json.loads(f.read_text()), schema)
        else:
            jsonschema.validate(json.loads(f.read_text()), schema)
    data = json.loads(path.read_text())
    del data["parameters"]["A1_mm2"]
    with pytest.raises(jsonschema.ValidationError, match="A1_mm2"):
        jsonschema.validate(data, schema)


def test_every_requirements_field_is_in_the_schema():
    from dataclasses import fields

    assert set(requirements_schema()["properties"]) == {f.name for f in fields(Requirements)}
    assert set(design_schema()["properties"]["spec"]["properties"]) == {f.name for f in fields(Requirements)}
    from vvea_design.spring.design_file import DESIGN_PARAMETER_KEYS, TOP_LEVEL_KEYS

    assert set(design_schema()["properties"]) == set(TOP_LEVEL_KEYS)
    assert set(design_schema()["properties"]["parameters"]["required"]) == set(DESIGN_PARAMETER_KEYS)
