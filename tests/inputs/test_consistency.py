"""Issue 24, second pass, class 2: a field that bounds another (a study charge and the design's rating)."""

from __future__ import annotations

import json

import pytest
from typer.testing import CliRunner

from tests.helpers import REPO
from vvea_design.cli.main import app
from vvea_design.jobs.common import OptionError
from vvea_design.jobs.studies import _within_rating, run_rest_to_rest

DESIGN_FILE = REPO / "cad" / "design.json"
RATED = json.loads(DESIGN_FILE.read_text())["spec"]["max_charge_MPa"]


def test_a_study_charge_above_the_designs_rating_is_refused(tmp_path):
    with pytest.raises(OptionError, match=r"p2_MPa.*above the design's rating .*max_charge_MPa"):
        run_rest_to_rest(tmp_path / "st", grid="0.5:1.0", design=DESIGN_FILE, p2_MPa=2 * RATED, mesh_n=16)
    assert not (tmp_path / "st").exists()
    _within_rating(DESIGN_FILE, RATED)  # at the rating: accepted
    _within_rating(DESIGN_FILE, RATED / 2)


def test_the_command_names_its_option(tmp_path):
    res = CliRunner().invoke(app, ["study", "rest-to-rest", "-o", str(tmp_path / "st"), "--grid", "0.5:1.0",
                                   "--mesh-n", "16", "--design", str(DESIGN_FILE), "--p2-mpa", str(2 * RATED)],
                             env={"COLUMNS": "400"})
    assert res.exit_code == 2 and "--p2-mpa" in res.output and "rating" in res.output, res.output
