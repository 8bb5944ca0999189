"""Every command refuses a bad input with one line naming it and the documented exit code (``docs/reliability.md``):
the BAD and WEAK cases of the hostile-input campaign A (``studies/hostile_inputs.py``; case ids in the test ids)
that a command rejects before any work, run in-process. The checks live in the jobs (:mod:`vvea_design.jobs`), so
the library refuses the same values; the command only names its option.

The library-side cases (requirements, design files, recordings) are in ``test_validation_requirements.py``,
``test_validation_design_file.py`` and ``test_validation_recordings.py``; the bounds in
``tests/spring/test_bounds_follow.py``.
"""

from __future__ import annotations

import errno
import json
import math
import os
import shutil

import pandas as pd
import pytest
import typer
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from typer.testing import CliRunner

from tests.helpers import REPO, SHARED_RECORDINGS
from vvea_design.cli.errors import VveaGroup
from vvea_design.cli.main import app

runner = CliRunner()
DESIGN = REPO / "cad" / "design.json"


def _run(*argv: str):
    """Exit code and output, typer's error box unwrapped into one line of text."""
    res = runner.invoke(app, [str(a) for a in argv], env={"COLUMNS": "400", "TERMINAL_WIDTH": "400"})
    text = " ".join(res.output.replace("│", " ").split())
    return res.exit_code, text


def _refused(argv, words, code: int = 2):
    got, text = _run(*argv)
    assert got == code, (got, text)
    assert "Traceback" not in text, text
    for w in words:
        assert w.lower() in text.lower(), (w, text)
    return text


@pytest.fixture()
def d_json(tmp_path):
    p = tmp_path / "d.json"
    shutil.copy(DESIGN, p)
    return p


# ------------------------------------------------------------------------------------------------ numbers
NUMBER_CASES = [  # (case, argv after the design file / folder, words)
    ("cli-01 spring --p2 1e9", ["spring", "{d}", "-o", "{t}/sp", "--p2", "1e9"], ("--p2", "<= 20 MPa")),
    ("cli-02 spring --p2 nan", ["spring", "{d}", "-o", "{t}/sp", "--p2", "nan"], ("--p2",)),
    ("cli-03 spring --p2 inf", ["spring", "{d}", "-o", "{t}/sp", "--p2", "inf"], ("--p2",)),
    ("cli-05 spring --p2 1e-300", ["spring", "{d}", "-o", "{t}/sp", "--p2", "1e-300"], ("--p2", ">= 0.01")),
    ("spring --p2 above the walls", ["spring", "{d}", "-o", "{t}/sp", "--p2", "19"], ("--p2", "walls", "yield")),
    ("cli-10 map --n 0", ["map", "{d}", "-o", "{t}/map", "--n", "0"], ("--n", ">= 2")),
    ("cli-11 map --n 100000", ["map", "{d}", "-o", "{t}/map", "--n", "100000"], ("--n", "<= 401")),
    ("cli-13 map --x = --y", ["map", "{d}", "-o", "{t}/map", "--x", "V1_mm3", "--y", "V1_mm3", "--n", "5"],
     ("V1_mm3",)),
    ("cli-14 pareto --values -5,nan", ["pareto", "-o", "{t}/par", "--values", "-5,nan"], ("--values",)),
    ("cli-15 pareto --values inf", ["pareto", "-o", "{t}/par", "--values", "inf"], ("--values",)),
    ("cli-18 pareto unreachable scheduler", ["pareto", "--values", "93.2", "--scheduler", "tcp://127.0.0.1:1",
                                             "-o", "{t}/par"], ("--scheduler", "127.0.0.1:1")),
    ("cli-19 design --workers -3", ["design", "-o", "{t}/out", "--no-renders", "--workers", "-3"],
     ("--workers", ">= 1")),
    ("cli-25 study gamma upside down", ["study", "rest-to-rest", "-o", "{t}/st", "--grid", "0.5:1.0", "--mesh-n",
                                        "16", "--gamma-min-deg", "130", "--gamma-max-deg", "60"],
     ("--gamma-min-deg", "must not exceed")),
    ("study gamma beyond a turn", ["study", "rest-to-rest", "-o", "{t}/st", "--grid", "0.5:1.0", "--mesh-n", "16",
                                   "--design", "{d}", "--gamma-max-deg", "1100"], ("--gamma-max-deg", "<= 360")),
    ("cli-27 study pulley 1000 m", ["study", "rest-to-rest", "-o", "{t}/st", "--grid", "0.5:1.0", "--mesh-n", "16",
                                    "--design", "{d}", "--pulley-radius-m", "1000"], ("--pulley-radius-m", "<= 1")),
    ("cli-29 study --p2-mpa 1e9", ["study", "rest-to-rest", "-o", "{t}/st", "--grid", "0.5:1.0", "--mesh-n", "16",
                                   "--design", "{d}", "--p2-mpa", "1e9"], ("--p2-mpa", "<= 20")),
    ("cli-31 safety --tau-ref-nm 1e12", ["study", "safety", "-o", "{t}/saf", "--mesh-n", "8", "--tau-ref-nm",
                                         "1e12"], ("tau_ref", "100")),
    ("cli-33 bladder --allowable 25", ["bladder", "{d}", "-o", "{t}/bl", "--elements", "16", "--allowable", "25"],
     ("--allowable", "fraction")),
    ("cli-34 optimise --seed -1", ["optimise", "-o", "{t}/o/d.json", "--seed", "-1"], ("--seed",)),
    ("size-10 bladder --elements 1e7", ["bladder", "{d}", "-o", "{t}/bl", "--elements", "10000000"],
     ("--elements", "<= 4000")),
    ("size-11 study grid of 1e6 cases", ["study", "rest-to-rest", "-o", "{t}/st", "--no-progress", "--grid",
                                         ",".join(f"{0.1 + 0.001 * i:.4f}" for i in range(1000)) + ":"
                                         + ",".join(f"{0.5 + 0.001 * i:.4f}" for i in range(1000))],
     ("cases", "<= 2500")),
    ("size-12 design --study-mesh-n 1e6", ["design", "-o", "{t}/out", "--no-renders", "--study-mesh-n", "1000000"],
     ("--study-mesh-n", "4096")),
    ("size-13 study --mesh-n 400000", ["study", "rest-to-rest", "-o", "{t}/st", "--grid", "0.5:1.0", "--mesh-n",
                                       "400000", "--workers", "1"], ("--mesh-n", "4096")),
]


@pytest.mark.parametrize("case, argv, words", NUMBER_CASES, ids=[c for c, *_ in NUMBER_CASES])
def test_an_absurd_number_is_refused_before_any_work(tmp_path, d_json, case, argv, words):
    argv = [a.format(d=d_json, t=tmp_path) for a in argv]
    _refused(argv, words)
    assert not any(p.name not in ("d.json",) for p in tmp_path.iterdir()), "nothing may be written"


# ------------------------------------------------------------------------------------------------ design files
def _edited(path, edit):
    data = json.loads(path.read_text())
    edit(data)
    path.write_text(json.dumps(data))
    return path


DESIGN_EDITS = [  # (case, edit, words); the library test checks every edit against every reader
    ("design-01/02 stale piston", lambda d: d["parameters"].__setitem__("piston_diameter_mm", 30.0),
     ("piston_diameter_mm",)),
    ("design-08 piston 70", lambda d: d["parameters"].__setitem__("piston_diameter_mm", 70.0), ("piston_diameter_mm",)),
    ("design-13 outer 20", lambda d: d["parameters"].__setitem__("outer_diameter_mm", 20.0), ("outer_diameter_mm",)),
    ("design-15 rod 40", lambda d: d["fixed"].__setitem__("rod_diameter_mm", 40.0), ("rod_diameter_mm",)),
    ("design-18 min wall 0", lambda d: d["fixed"].__setitem__("min_outer_wall_mm", 0.0), ("min_outer_wall_mm",)),
    ("design-20 hexagon", lambda d: d["parameters"].__setitem__("layout", "hexagon"), ("hexagon",)),
    ("design-27 p1 inconsistent", lambda d: d["parameters"].__setitem__("p1_MPa", 2.0), ("p1_MPa",)),
    ("design-42 setpoint 1e6", lambda d: d["parameters"].__setitem__("setpoint_x0_mm", 1e6), ("setpoint_x0_mm",)),
]


@pytest.mark.parametrize("command", ["check", "spring"])
@pytest.mark.parametrize("case, edit, words", DESIGN_EDITS, ids=[c for c, *_ in DESIGN_EDITS])
def test_spring_and_check_refuse_a_design_file_that_disagrees_with_itself(tmp_path, d_json, command, case, edit,
                                                                          words):
    _edited(d_json, edit)
    argv = (["check", d_json, "--max-linearity", "0.015"] if command == "check"
            else ["spring", d_json, "-o", tmp_path / "sp"])
    _refused(argv, (str(d_json.name), *words))


def test_identify_refuses_a_stale_design_before_reading_the_recordings(tmp_path, d_json):
    """design-04/14/16/21/25: identify --design reads the design file through the same loader."""
    _edited(d_json, lambda d: d["parameters"].__setitem__("piston_diameter_mm", 30.0))
    _refused(["identify", SHARED_RECORDINGS / "campaign_a.csv", "--design", d_json, "-o", tmp_path / "id"],
             ("piston_diameter_mm",))


def test_a_folder_a_device_and_a_deep_file_are_named(tmp_path):
    """design-34/36, size-08: a folder is a folder (not "does not exist"), /dev/zero a device, 100,000-deep JSON
    names its depth, all without a trace."""
    (tmp_path / "dir.json").mkdir()
    _refused(["check", tmp_path / "dir.json", "--max-linearity", "0.015"], ("folder",))
    _refused(["check", "/dev/zero", "--max-linearity", "0.015"], ("/dev/zero",))
    deep = tmp_path / "deep.json"
    deep.write_text("[" * 100_000 + "]" * 100_000)
    _refused(["check", deep, "--max-linearity", "0.015"], ("deep.json", "deep"))


def test_huge_sparse_inputs_are_refused_for_their_size(tmp_path):
    """size-04/07/09: a 20 GB (sparse) file is refused before a byte is read."""
    for name, argv in (("rec.csv", ["identify", "{p}", "-o", "{t}/id"]),
                       ("req.toml", ["optimise", "--spec", "{p}", "-o", "{t}/d.json"]),
                       ("d.json", ["check", "{p}", "--max-linearity", "0.015"])):
        p = tmp_path / name
        with open(p, "wb") as fh:
            fh.truncate(20 * 2**30)
        _refused([a.format(p=p, t=tmp_path) for a in argv], (name, "GiB"))
        p.unlink()


def test_a_fifo_is_refused_without_waiting_for_a_writer(tmp_path):
    """size-03/06: a FIFO with no writer would block the read for ever."""
    fifo = tmp_path / "rec.csv"
    os.mkfifo(fifo)
    _refused(["identify", fifo, "-o", tmp_path / "id"], ("rec.csv", "FIFO"))
    _refused(["optimise", "--spec", fifo, "-o", tmp_path / "d.json"], ("rec.csv", "FIFO"))


def test_identify_refuses_dev_zero():
    """size-01/02: a device is no recordings file (it used to be read without bound)."""
    _refused(["identify", "/dev/zero", "-o", "/tmp/never-written-r24"], ("/dev/zero",))
    assert not os.path.exists("/tmp/never-written-r24")


# ------------------------------------------------------------------------------------------------ recordings
@pytest.fixture(scope="module")
def rec18_kN(tmp_path_factory):
    df = pd.read_csv(SHARED_RECORDINGS / "campaign_a.csv")
    df = df[df["experiment"].isin({f"E{i:03d}" for i in range(18)})].reset_index(drop=True)
    df["force_N"] = df["force_N"] / 1000.0
    p = tmp_path_factory.mktemp("rec") / "rec.csv"
    df.to_csv(p, index=False)
    return p


@pytest.mark.parametrize("command", ["identify", "diagnose"])
def test_recordings_in_kN_are_refused_naming_the_unit_and_the_override(tmp_path, rec18_kN, command):
    """rec-01/07/12: a force in kN is not fitted (g 0.02 before); the message names kN and --force-unit kN."""
    extra = ["--no-learner"] if command == "diagnose" else []
    _refused([command, rec18_kN, "-o", tmp_path / "o", *extra], ("force_N", "kN", "--force-unit kN"))
    _refused([command, rec18_kN, "-o", tmp_path / "o", "--design", DESIGN, *extra], ("force_N", "kN"))
    assert not (tmp_path / "o").exists()


# ------------------------------------------------------------------------------------------------ outputs
def test_an_input_is_never_an_output(tmp_path):
    """out-01/02: `optimise --spec req.toml -o req.toml` (or -o a link to it) leaves the requirements alone."""
    req = tmp_path / "req.toml"
    shutil.copy(REPO / "examples" / "requirements.toml", req)
    before = req.read_bytes()
    _refused(["optimise", "--spec", req, "-o", req], ("req.toml", "input"))
    (tmp_path / "link.json").symlink_to(req)
    _refused(["optimise", "--spec", req, "-o", tmp_path / "link.json"], ("link.json", "input"))
    assert req.read_bytes() == before


def test_a_windows_path_is_named(tmp_path, monkeypatch):
    """out-11: `-o 'Z:\\designs\\d.json'` used to make a file with backslashes in its name."""
    monkeypatch.chdir(tmp_path)
    _refused(["optimise", "-o", "Z:\\designs\\d.json"], ("Windows path",))
    assert list(tmp_path.iterdir()) == []


def test_a_full_disk_is_one_line_and_keeps_the_old_output(tmp_path, d_json, monkeypatch):
    """disk-01..10: ENOSPC while writing is `could not write ...: no space left on device`, exit 2, no trace."""
    from vvea_design.jobs import spring as jobs_spring

    out = tmp_path / "sp"
    code, _ = _run("spring", d_json, "-o", out)
    assert code == 0
    old = (out / "spring.csv").read_bytes()

    def full(*a, **k):
        raise OSError(errno.ENOSPC, "No space left on device", str(out) + "/spring.csv")

    monkeypatch.setattr(jobs_spring, "write_spring_files", full)
    _refused(["spring", d_json, "-o", out], ("no space left on device",))
    assert (out / "spring.csv").read_bytes() == old


# ------------------------------------------------------------------------------------------------ exit codes
def _app_raising(exc: BaseException) -> typer.Typer:
    a = typer.Typer(cls=VveaGroup, pretty_exceptions_enable=False)

    @a.command()
    def boom() -> None:
        raise exc

    @a.command()
    def other() -> None:  # two commands, so `boom` is a sub-command as in `vvea`
        pass

    return a


@pytest.mark.parametrize("exc, code, words", [
    (KeyboardInterrupt(), 130, ("interrupted",)),
    (__import__("vvea_design.parallel", fromlist=["Terminated"]).Terminated("signal 15"), 143, ("terminated",)),
    (__import__("vvea_design.parallel", fromlist=["WorkerLost"]).WorkerLost("a worker process died"), 4,
     ("worker process died",)),
    (OSError(errno.ENOSPC, "No space left on device", "/x/d.json"), 2, ("no space left", "/x/d.json")),
    (__import__("vvea_design.plausibility", fromlist=["PlausibilityError"]).PlausibilityError("p2_MPa must be"),
     2, ("p2_MPa",)),
    (ZeroDivisionError("division by zero"), 1, ("internal error", "--debug")),
], ids=["sigint-130", "sigterm-143", "worker-lost-4", "full-disk-2", "plausibility-2", "bug-1"])
def test_every_error_maps_to_its_documented_exit_code_and_one_line(exc, code, words):
    """int-04/07/08/09/10/11, int-05, tb-*: what escapes a command is an exit code and a line, never a trace."""
    res = runner.invoke(_app_raising(exc), ["boom"])
    assert res.exit_code == code, res.output
    assert "Traceback" not in res.output
    for w in words:
        assert w in res.output, (w, res.output)


def test_debug_shows_the_trace():
    from vvea_design.cli.errors import set_debug

    set_debug(True)
    try:
        res = runner.invoke(_app_raising(ZeroDivisionError("x")), ["boom"])
    finally:
        set_debug(False)
    assert isinstance(res.exception, ZeroDivisionError)


def test_a_restart_removes_the_whole_earlier_sweep(tmp_path):
    """int-01/02: `--restart` over a finished sweep removes its summary, report and figures before the first new
    case, so an interrupt never leaves a new results.csv beside the old summary."""
    from vvea_design.actuator.multistart import DEFAULT_MESH, DEFAULT_REGULARISATION, DEFAULT_STARTS
    from vvea_design.actuator.rest_to_rest import SWEEP_FILES, Grid, _check_options, _prepare_results

    for name in SWEEP_FILES:
        (tmp_path / name).write_text("old")
    (tmp_path / "mine.txt").write_text("keep")
    opt = _check_options(Grid((0.5,), (1.0,)), None, DEFAULT_MESH, None, DEFAULT_STARTS, 1, None,
                         DEFAULT_REGULARISATION)
    _prepare_results(tmp_path, opt, restart=True)
    left = {p.name for p in tmp_path.iterdir()}
    assert "mine.txt" in left
    assert not ({"summary.json", "report.html", "best_map.png", "trajectory.png"} & left)


# ------------------------------------------------------------------------------------------------ properties
_OUTSIDE_CHARGE = st.one_of(st.floats(max_value=0.0099), st.floats(min_value=20.001),
                            st.sampled_from([math.nan, math.inf, -math.inf, 1e300, -0.0]))


@settings(max_examples=25, deadline=None, derandomize=True, suppress_health_check=list(HealthCheck))
@given(p2=_OUTSIDE_CHARGE)
def test_property_a_charge_outside_the_range_is_refused_naming_the_option(p2):
    """CLI numbers: any --p2 outside 0.01 ... 20 MPa exits 2 naming --p2; never a trace, never a file."""
    code, text = _run("spring", DESIGN, "-o", "/tmp/r24-never-written-sp", "--p2", repr(p2))
    assert code == 2 and "--p2" in text and "Traceback" not in text, text
    assert not os.path.exists("/tmp/r24-never-written-sp")


@settings(max_examples=25, deadline=None, derandomize=True, suppress_health_check=list(HealthCheck))
@given(n=st.one_of(st.integers(max_value=1), st.integers(min_value=402, max_value=10**12)))
def test_property_a_map_size_outside_the_range_is_refused_before_allocating(n):
    code, text = _run("map", DESIGN, "-o", "/tmp/r24-never-written-map", "--n", str(n))
    assert code == 2 and "--n" in text and "Traceback" not in text, text


@settings(max_examples=20, deadline=None, derandomize=True, suppress_health_check=list(HealthCheck))
@given(p2=st.floats(min_value=0.01, max_value=20.0), option=st.sampled_from(["charge_MPa"]))
def test_property_the_job_and_the_library_agree_on_a_charge(p2, option):
    """In range, the job's check passes the value on unchanged; the library's range is the same entry."""
    from vvea_design.jobs.common import check_option
    from vvea_design.plausibility import LIMITS

    assert check_option(option, p2, "p2_MPa") == p2
    assert LIMITS[option].problem(p2) is None


def test_vvea_optimise_on_70_by_160_mm_reaches_0_879_percent_without_a_bounds_edit(tmp_path):
    """req-01 (issue item 1): `vvea optimise --spec req.toml` on a 70 x 160 mm, 120 N/mm spec, no [bounds]."""
    req = tmp_path / "req.toml"
    req.write_text("max_outer_diameter_mm = 70.0\nmax_housing_length_mm = 160.0\nmin_mean_stiffness_N_per_mm = 120.0\n")
    code, text = _run("optimise", "--spec", req, "-o", tmp_path / "d.json")
    assert code == 0, text
    perf = json.loads((tmp_path / "d.json").read_text())["performance"]
    assert perf["linearity_error"] <= 0.00880, perf["linearity_error"]
    assert "search bound" not in text  # the default bounds follow the envelope: nothing but it binds the diameter


def test_a_failed_solve_never_exits_0(tmp_path, monkeypatch):
    """cli-27 (issue item 4): a study whose solves failed writes its results and exits 4, naming the count."""
    from types import SimpleNamespace

    from vvea_design.jobs import studies

    def sweep(out, **kw):
        return SimpleNamespace(summary_text="Table 5 ...", files={"results_csv": out / "results.csv"},
                               solver_failures=1, summary=SimpleNamespace(run=SimpleNamespace(ocps=5)))

    monkeypatch.setattr(studies, "run_rest_to_rest", sweep)
    _refused(["study", "rest-to-rest", "-o", tmp_path / "st", "--grid", "0.5:1.0", "--mesh-n", "16"],
             ("1 of 5", "failed to solve"), code=4)


def test_a_pareto_point_on_a_larger_envelope_searches_all_of_it():
    """req-36: the Pareto sweep's points keep the bounds that follow the envelope (70 mm, not 59.5 mm)."""
    from vvea_design.spring.requirements import Requirements
    from vvea_design.spring.studies import check_pareto_values

    req = Requirements(max_outer_diameter_mm=70.0, max_housing_length_mm=160.0)
    (point, value), = check_pareto_values(req, "stiffness", [120.0])
    bounds = dict(zip(point.decision_variables("inner_tube"), point.search_bounds("inner_tube")))
    assert value == 120.0 and point.min_mean_stiffness_N_per_mm == 120.0
    assert bounds["outer_diameter_mm"][1] == pytest.approx(70.0)


def test_the_throttle_range_check_keeps_the_actuators_name():
    """The valve-angle check of the design mapping must not rename the design's actuator (it is the setting
    ``design`` of every study)."""
    from vvea_design.actuator.model import actuator_from_spring
    from vvea_design.spring.paper import PAPER_FIG5

    assert actuator_from_spring(PAPER_FIG5, name="design").name == "design"
    with pytest.raises(ValueError, match="gamma_max_deg"):
        actuator_from_spring(PAPER_FIG5, name="design", gamma_max_deg=1100.0)
