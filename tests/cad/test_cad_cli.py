"""`vvea cad design.json --out DIR` through typer's CliRunner on an app built here."""

from __future__ import annotations

import json
import sys
from pathlib import Path

import pytest
from tests.helpers import make_app
from typer.testing import CliRunner


from tests.cad.cases import REFERENCE  # noqa: E402

from vvea_design.cli.cad import register  # noqa: E402


@pytest.fixture(scope="module")
def app():
    return make_app(register)


@pytest.fixture(scope="module")
def design_json(tmp_path_factory):
    from vvea_design.spring.design_file import save_design
    from vvea_design.spring.problem import evaluate_design
    from vvea_design.spring.requirements import Requirements

    req = Requirements(fixed=REFERENCE.fixed)  # the reference was sized by the gas-only rules (its fixed says so)
    path = tmp_path_factory.mktemp("cli") / "design.json"
    return save_design(path, evaluate_design(REFERENCE, req), req)


def test_cad_command_writes_the_set(reference_cad_run):
    """`vvea cad cad/design.json` (the session's shared run, renders, drawings and BOM included)."""
    out, exit_code, output = reference_cad_run
    assert exit_code == 0, output
    manifest = json.loads((out / "manifest.json").read_text())
    for stem in ("housing", "housing_base", "housing_outer_tube", "housing_inner_tube", "housing_top_cap", "piston",
                 "bladder", "support_ring", "mould_half_a", "mould_half_b", "mould_core"):
        assert (out / f"{stem}.step").is_file() and (out / f"{stem}.stl").is_file()
    assert (out / "assembly.step").is_file()
    assert (out / "gas_chamber_1.stl").is_file() and (out / "gas_chamber_2.stl").is_file()
    assert manifest["measured"]["chamber_1_volume_mm3"]["cad"] == pytest.approx(REFERENCE.V1_mm3, rel=0.01)
    assert "CAD vs design" in output and "drawings: 7 sheets (unit_section, " in output and "bom.csv" in output
    assert "assembly_order)" in output
    assert f"wrote {len(manifest['files'])} files" in output


def test_cad_command_bad_design_is_a_clear_error(app, design_json, tmp_path):
    data = json.loads(design_json.read_text())
    data["fixed"]["min_base_mm"] = 8.0  # the gas-only sizing keeps this thin base (the buildable rules size the
    data["fixed"]["sizing_rules"] = "gas_only"  # base for the relief case, far above the valves' 11 mm)
    data.pop("joints", None)
    data.pop("hydraulics", None)
    for block in ("geometry", "performance", "constraints", "constraint_details"):  # derived: rebuilt from the edit
        del data[block]  # (left in, the stale blocks are refused first, before the CAD sees the base)
    bad = tmp_path / "bad.json"
    bad.write_text(json.dumps(data))
    out = tmp_path / "never"
    res = CliRunner().invoke(app, ["cad", str(bad), "--out", str(out)])
    assert res.exit_code == 2
    assert "base_mm" in res.output
    assert not out.exists()


def test_cad_command_missing_file(app, tmp_path):
    res = CliRunner().invoke(app, ["cad", str(tmp_path / "nope.json"), "--out", str(tmp_path / "o")])
    assert res.exit_code == 2
    assert "nope.json" in res.output
