"""Issue 24, second pass, class 5: no command writes over a file the user gave or that sits where an output would
land, unless the command's own manifest (``.vvea-<command>.json``) says its earlier run wrote it (exit 2)."""

from __future__ import annotations

import shutil

import pytest
from typer.testing import CliRunner

from tests.helpers import REPO, SHARED_RECORDINGS
from vvea_design.cli.main import app
from vvea_design.outputs import OutputError, output_dir

runner = CliRunner()
DESIGN = REPO / "cad" / "design.json"


def _run(*argv):
    res = runner.invoke(app, [str(a) for a in argv], env={"COLUMNS": "400", "TERMINAL_WIDTH": "400"})
    return res.exit_code, " ".join(res.output.replace("│", " ").split())


def test_spring_beside_the_input_keeps_a_users_spring_csv(tmp_path):
    shutil.copy(DESIGN, tmp_path / "d.json")
    (tmp_path / "spring.csv").write_text("my own measurements\n")
    code, text = _run("spring", tmp_path / "d.json", "-o", tmp_path)
    assert code == 2 and "spring.csv" in text and "did not write" in text and "Traceback" not in text, text
    assert (tmp_path / "spring.csv").read_text() == "my own measurements\n"
    assert not (tmp_path / "spring.png").exists()


def test_spring_replaces_its_own_earlier_output(tmp_path):
    shutil.copy(DESIGN, tmp_path / "d.json")
    assert _run("spring", tmp_path / "d.json", "-o", tmp_path)[0] == 0
    first = (tmp_path / "spring.csv").read_bytes()
    code, text = _run("spring", tmp_path / "d.json", "-o", tmp_path)  # its manifest names spring.csv: replaced
    assert code == 0, text
    assert (tmp_path / "spring.csv").read_bytes() == first
    assert (tmp_path / "d.json").read_bytes() == DESIGN.read_bytes()


def test_identify_keeps_a_users_table3_and_refuses_before_any_work(tmp_path):
    (tmp_path / "table3.csv").write_text("the paper's table, typed in\n")
    code, text = _run("identify", SHARED_RECORDINGS / "campaign_a.csv", "-o", tmp_path)
    assert code == 2 and "table3.csv" in text, text
    assert (tmp_path / "table3.csv").read_text() == "the paper's table, typed in\n"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["table3.csv"]


def test_an_output_of_unknown_name_never_replaces_a_users_file(tmp_path):
    (tmp_path / "a.csv").write_text("mine")
    with pytest.raises(OutputError, match=r"a\.csv.*did not write"):
        with output_dir(tmp_path, "demo") as tmp:
            (tmp / "a.csv").write_text("ours")
            (tmp / "b.csv").write_text("ours")
    assert (tmp_path / "a.csv").read_text() == "mine"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["a.csv"]  # nothing half-landed, no temporary left


def test_known_names_are_refused_before_the_block(tmp_path):
    (tmp_path / "a.csv").write_text("mine")
    ran = []
    with pytest.raises(OutputError, match=r"a\.csv"):
        with output_dir(tmp_path, "demo", names=("a.csv",)):
            ran.append(1)
    assert ran == [] and (tmp_path / "a.csv").read_text() == "mine"
