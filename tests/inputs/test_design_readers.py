"""Issue 24, second pass, class 3: every command that reads a design refuses a file whose stored derived value
disagrees with the design rebuilt from its decision variables (exit 2, naming the value), before any work.

The commands are enumerated from the ``vvea`` app itself (every command with a ``design`` parameter), so a new
command reading a design fails :func:`test_every_command_taking_a_design_is_covered` until it is added here.
"""

from __future__ import annotations

import inspect
import json

import pytest
from typer.testing import CliRunner

from tests.helpers import REPO, SHARED_RECORDINGS
from vvea_design.cli.main import app
from vvea_design.spring.design_file import DesignFileError, load_design, load_design_dict, spring_from_json
from vvea_design.testing import check_linearity

runner = CliRunner()
SOURCE = REPO / "cad" / "design.json"
RECORDINGS = SHARED_RECORDINGS / "campaign_a.csv"

#: The argv of every command that reads a design ({d}: the design file, {t}: a scratch folder).
COMMANDS = {
    ("spring",): ["spring", "{d}", "-o", "{t}/sp"],
    ("check",): ["check", "{d}", "--max-linearity", "0.015"],
    ("map",): ["map", "{d}", "--n", "3", "-o", "{t}/map"],
    ("cad",): ["cad", "{d}", "--out", "{t}/cad"],
    ("bladder",): ["bladder", "{d}", "--out", "{t}/bl"],
    ("identify",): ["identify", str(RECORDINGS), "--design", "{d}", "-o", "{t}/id"],
    ("diagnose",): ["diagnose", str(RECORDINGS), "--design", "{d}", "-o", "{t}/dg"],
    ("study", "rest-to-rest"): ["study", "rest-to-rest", "-o", "{t}/st", "--grid", "0.5:1.0", "--mesh-n", "16",
                                "--design", "{d}"],
}

#: Derived values (path in the design JSON) each scaled by 10: volumes, walls, eq.-5 values, performance, margins.
DERIVED = [
    ("parameters", "A1_mm2"),
    ("geometry", "V2_annulus_mm3"),
    ("geometry", "V2_capacity_mm3"),
    ("geometry", "walls_mm", "outer_tube"),
    ("geometry", "housing_length_mm"),
    ("performance", "mean_stiffness_N_per_mm"),
    ("performance", "max_force_N"),
    ("performance", "total_gas_mm3"),
    ("performance", "peak_pressure_MPa"),
]


def _commands_taking_a_design() -> set[tuple[str, ...]]:
    found: set[tuple[str, ...]] = set()

    def walk(a, prefix=()):
        for c in a.registered_commands:
            name = c.name or c.callback.__name__.replace("_", "-")
            if any("design" in p for p in inspect.signature(c.callback).parameters):
                found.add(prefix + (name,))
        for g in a.registered_groups:
            walk(g.typer_instance, prefix + (g.name,))

    walk(app)
    return found


def test_every_command_taking_a_design_is_covered():
    assert _commands_taking_a_design() == set(COMMANDS)


def _scaled(path: tuple[str, ...], factor: float = 10.0) -> dict:
    data = json.loads(SOURCE.read_text())
    node = data
    for k in path[:-1]:
        node = node[k]
    assert isinstance(node[path[-1]], (int, float)) and node[path[-1]] != 0, path
    node[path[-1]] *= factor
    return data


@pytest.mark.parametrize("command", sorted(COMMANDS), ids=lambda c: " ".join(c))
@pytest.mark.parametrize("path", [DERIVED[0], DERIVED[1], DERIVED[5]], ids=lambda p: ".".join(p))
def test_every_command_refuses_a_design_with_one_derived_value_scaled_by_10(tmp_path, command, path):
    d = tmp_path / "d.json"
    d.write_text(json.dumps(_scaled(path)))
    argv = [a.format(d=d, t=tmp_path) for a in COMMANDS[command]]
    res = runner.invoke(app, argv, env={"COLUMNS": "400", "TERMINAL_WIDTH": "400"})
    text = " ".join(res.output.replace("│", " ").split())
    assert res.exit_code == 2, (res.exit_code, text)
    assert ".".join(path) in text and "Traceback" not in text, text
    written = {p.name for p in tmp_path.iterdir()} - {"d.json"}
    assert not written, written  # refused before any output


@pytest.mark.parametrize("path", DERIVED, ids=lambda p: ".".join(p))
@pytest.mark.parametrize("reader", [load_design_dict, spring_from_json, lambda d: check_linearity(d, 0.015)],
                         ids=["load_design_dict", "spring_from_json", "check_linearity"])
def test_every_library_reader_refuses_each_derived_value_scaled(path, reader):
    with pytest.raises(DesignFileError, match=".".join(path).replace(".", r"\.")):
        reader(_scaled(path))


def test_the_unedited_file_loads_and_a_design_outside_its_envelope_is_refused():
    load_design(SOURCE)
    data = json.loads(SOURCE.read_text())
    data["spec"]["max_outer_diameter_mm"] = data["parameters"]["outer_diameter_mm"] * 0.9
    with pytest.raises(DesignFileError, match="outside its own envelope"):
        load_design_dict(data, "d.json")


def test_an_edited_margin_is_refused():
    data = json.loads(SOURCE.read_text())
    name = next(k for k, v in data["constraints"].items() if isinstance(v, (int, float)) and v != 0
                and "strain" not in k)
    data["constraints"][name] = -data["constraints"][name]
    with pytest.raises(DesignFileError, match=rf"constraints\.{name}"):
        load_design_dict(data, "d.json")
