"""Issue 24, third pass, class 2: a charge above the design's rating is refused unless asked for, then labelled."""

from __future__ import annotations

import json

import pytest
from typer.testing import CliRunner

from tests.helpers import REPO
from vvea_design.cli.main import app
from vvea_design.jobs.common import OptionError
from vvea_design.jobs.rating import OVER_RATING_LABEL, charge_rating, check_charge
from vvea_design.jobs.spring import spring_report
from vvea_design.spring.design_file import load_design

DESIGN_FILE = REPO / "cad" / "design.json"
DATA = json.loads(DESIGN_FILE.read_text())
RATED = DATA["spec"]["max_charge_MPa"]
OVER = 1.1 * RATED  # above the rating, below where the walls yield (safety factor >= 2)


def test_the_rating_is_the_lower_of_the_requirement_and_the_charge_the_walls_are_sized_for():
    r = charge_rating(DESIGN_FILE)
    assert r.rated_MPa == min(RATED, DATA["parameters"]["p2_MPa"]) and "max_charge_MPa" in r.source
    lower = json.loads(json.dumps(DATA))
    lower["spec"]["max_charge_MPa"] = 2 * RATED
    assert charge_rating(lower).rated_MPa == DATA["parameters"]["p2_MPa"]
    assert "parameters.p2_MPa" in charge_rating(lower).source
    d = load_design(DESIGN_FILE)
    assert charge_rating(d).rated_MPa == d.p2_MPa
    assert charge_rating(d.gas_spring) is None  # a bare spring has no walls, no rating
    assert check_charge(DESIGN_FILE, RATED) == ""  # at the rating: accepted, unlabelled


@pytest.mark.parametrize("design", ["file", "object"])
def test_spring_above_the_rating_is_refused_unless_allowed_then_every_output_is_labelled(tmp_path, design):
    d = DESIGN_FILE if design == "file" else load_design(DESIGN_FILE)
    with pytest.raises(OptionError, match=r"p2_MPa = .* above the design's rating .*allow_over_rating"):
        spring_report(d, p2_MPa=OVER, out=tmp_path / "refused")
    assert not (tmp_path / "refused").exists()
    rep = spring_report(d, p2_MPa=OVER, allow_over_rating=True, out=tmp_path / "s")
    assert rep.over_rating.startswith(OVER_RATING_LABEL) and rep.to_dict()["over_rating"] == rep.over_rating
    assert (tmp_path / "s" / "spring.csv").read_text().startswith(f"# {OVER_RATING_LABEL}")
    ok = spring_report(d, p2_MPa=RATED, out=tmp_path / "ok")
    assert ok.over_rating == "" and "over_rating" not in ok.to_dict()
    assert (tmp_path / "ok" / "spring.csv").read_text().startswith("x_mm,")


def test_the_flag_does_not_let_the_walls_yield(tmp_path):
    sf = min(load_design(DESIGN_FILE).wall_safety_factors().values())
    with pytest.raises(OptionError, match="yield"):
        spring_report(DESIGN_FILE, p2_MPa=min(1.05 * sf * RATED, 19.9), allow_over_rating=True)


def test_the_command_refuses_names_its_flag_and_labels_its_output(tmp_path):
    run = CliRunner()
    res = run.invoke(app, ["spring", str(DESIGN_FILE), "--p2", str(OVER), "-o", str(tmp_path / "a")],
                     env={"COLUMNS": "400"})
    assert res.exit_code == 2 and "--p2" in res.output and "--allow-over-rating" in res.output, res.output
    res = run.invoke(app, ["spring", str(DESIGN_FILE), "--p2", str(OVER), "--allow-over-rating", "-o",
                           str(tmp_path / "b")], env={"COLUMNS": "400"})
    assert res.exit_code == 0 and res.output.count(OVER_RATING_LABEL) >= 2, res.output


@pytest.fixture(scope="module")
def campaign(tmp_path_factory):
    from vvea_benches import physbench as pb

    grid = pb.CampaignGrid(pressures_MPa=(2.0, 4.0), valves_deg=(100.0, 110.0), speeds_mm_s=(4.0,), samples=40)
    f = tmp_path_factory.mktemp("rec") / "rec.csv"
    pb.simulate_campaign(pb.random_parameters((), seed=11, grid=grid)).frame.to_csv(f, index=False)
    return f


def test_recordings_charged_above_the_design_rating_are_refused_unless_allowed_then_noted(campaign):
    from dataclasses import replace

    from vvea_design.identification.recordings import RecordingsError
    from vvea_design.jobs.identification import identify

    rated3 = replace(load_design(DESIGN_FILE), p2_MPa=3.0)  # walls for 3 MPa: the campaign's 4 MPa is above it
    with pytest.raises(RecordingsError, match=r"rec.csv: column p2_MPa: the highest charge p2 = 4 MPa is above the "
                                              r"design's rating 3 MPa"):
        identify(campaign, design=rated3, progress=False)
    res = identify(campaign, design=rated3, progress=False, allow_over_rating=True)
    assert any(n.startswith(OVER_RATING_LABEL) for n in res.notes)
    assert not any(n.startswith(OVER_RATING_LABEL) for n in identify(campaign, design=DESIGN_FILE,
                                                                     progress=False).notes)
