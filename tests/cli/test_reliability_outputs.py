"""Outputs written whole or not at all (issue 11 item 5): the library helper and every writing command.

Root (as these tests usually run) may write in a folder whatever its mode
bits say, so a "read-only folder" is tested for real in a child process that
drops to user ``nobody`` (when the suite runs as root) — a chmod alone would
prove nothing. Paths under a file and existing files are unwritable for root
too and are tested directly.
"""

from __future__ import annotations

import json
import os
import signal
import tempfile
from pathlib import Path

import pytest
from typer.testing import CliRunner

import vvea_design.cli.main  # noqa: F401 - imported before any test patches the functions they bind
import vvea_design.pipeline  # noqa: F401
from vvea_design import outputs
from vvea_design.outputs import (
    OutputError,
    check_output_dir,
    check_output_file,
    output_dir,
    output_files,
    write_text_atomic,
)

runner = CliRunner()


def tree(folder: Path) -> dict[str, bytes]:
    """Every file under ``folder`` with its bytes."""
    return {str(p.relative_to(folder)): p.read_bytes() for p in sorted(folder.rglob("*")) if p.is_file()}


def visible(folder: Path) -> list[str]:
    return sorted(os.listdir(folder))


def interrupted(res) -> bool:
    """A command stopped by Ctrl-C (typer turns KeyboardInterrupt into exit 130)."""
    return res.exit_code == 130 or isinstance(res.exception, KeyboardInterrupt)


# ---------------------------------------------------------------------------
# the helper
# ---------------------------------------------------------------------------

def test_new_folder_appears_whole_with_parents(tmp_path):
    target = tmp_path / "a" / "b" / "out"
    with output_dir(target, "demo") as tmp:
        assert tmp.parent == target.parent and tmp.name.startswith(".out.vvea-tmp-")
        assert not target.exists()  # nothing visible while the work runs
        (tmp / "r.csv").write_text("1")
        (tmp / "sub").mkdir()
        (tmp / "sub" / "s.txt").write_text("s")
    assert visible(target) == [".vvea-demo.json", "r.csv", "sub"]
    assert json.loads((target / ".vvea-demo.json").read_text()) == {"command": "demo", "entries": ["r.csv", "sub"]}
    assert visible(target.parent) == ["out"]  # no temporaries left


@pytest.mark.parametrize("exchange", [True, False], ids=["renameat2", "two-renames"])
def test_rerun_replaces_the_folder_as_a_whole(tmp_path, monkeypatch, exchange):
    if not exchange:
        monkeypatch.setattr(outputs, "_exchange", lambda a, b: False)
    target = tmp_path / "out"
    with output_dir(target, "demo") as tmp:
        (tmp / "old_only.png").write_text("old")
        (tmp / "both.csv").write_text("old")
    inode = target.stat().st_ino
    with output_dir(target, "demo") as tmp:
        (tmp / "both.csv").write_text("new")
    assert visible(target) == [".vvea-demo.json", "both.csv"]  # the stale figure of the first run is gone
    assert (target / "both.csv").read_text() == "new"
    assert target.stat().st_ino != inode  # a new folder took the old one's place
    assert visible(tmp_path) == ["out"]


def test_foreign_files_are_never_touched(tmp_path):
    """--out . or a folder holding the input: replace our entries one by one, keep the rest."""
    target = tmp_path / "work"
    target.mkdir()
    (target / "design.json").write_text("input")
    (target / "notes").mkdir()
    (target / "notes" / "n.txt").write_text("mine")
    with output_dir(target, "demo") as tmp:
        assert tmp.parent == target  # temporary inside: the folder itself is never swapped away
        (tmp / "a.csv").write_text("1")
        (tmp / "figs").mkdir()
        (tmp / "figs" / "f.png").write_text("1")
    inode = target.stat().st_ino
    with output_dir(target, "demo") as tmp:
        (tmp / "figs").mkdir()
        (tmp / "figs" / "g.png").write_text("2")
        (tmp / "b.csv").write_text("2")
    assert target.stat().st_ino == inode
    assert visible(target) == [".vvea-demo.json", "b.csv", "design.json", "figs", "notes"]
    assert tree(target / "figs") == {"g.png": b"2"}  # the folder entry replaced as a whole
    assert (target / "design.json").read_text() == "input" and (target / "notes" / "n.txt").read_text() == "mine"
    # a second command writing into the same folder does not remove the first one's files
    with output_dir(target, "other") as tmp:
        (tmp / "c.txt").write_text("3")
    assert {"b.csv", "figs", "c.txt"} <= set(visible(target))


@pytest.mark.parametrize("interrupt", [RuntimeError("solver failed"), KeyboardInterrupt()], ids=["error", "ctrl-c"])
def test_failed_or_interrupted_run_leaves_the_old_folder(tmp_path, interrupt):
    target = tmp_path / "out"
    with output_dir(target, "demo") as tmp:
        (tmp / "identification.json").write_text("old")
        (tmp / "fig10.png").write_text("old")
    before = tree(target)
    with pytest.raises(type(interrupt)):
        with output_dir(target, "demo") as tmp:
            (tmp / "identification.json").write_text("new")
            raise interrupt
    assert tree(target) == before
    assert visible(tmp_path) == ["out"]


def test_failure_in_a_new_location_creates_nothing(tmp_path):
    with pytest.raises(RuntimeError):
        with output_dir(tmp_path / "x" / "y" / "out", "demo") as tmp:
            (tmp / "a").write_text("1")
            raise RuntimeError("boom")
    assert visible(tmp_path) == []


def test_signal_during_the_final_renames_waits_until_they_are_done(tmp_path, monkeypatch):
    target = tmp_path / "out"
    real_rename = os.rename

    def rename_and_get_interrupted(a, b):
        # Ctrl-C arrives in the middle of the move; raise_signal delivers it to this (the main)
        # thread at once -- os.kill may hand it to another thread of the xdist worker, late under load
        signal.raise_signal(signal.SIGINT)
        return real_rename(a, b)

    monkeypatch.setattr(os, "rename", rename_and_get_interrupted)
    # Ctrl-C's own handler (a suite started in the background without job control inherits SIGINT ignored)
    old_handler = signal.signal(signal.SIGINT, signal.default_int_handler)
    try:
        with pytest.raises(KeyboardInterrupt):
            with output_dir(target, "demo") as tmp:
                (tmp / "a.csv").write_text("1")
                (tmp / "b.csv").write_text("1")
    finally:
        signal.signal(signal.SIGINT, old_handler)
    assert visible(target) == [".vvea-demo.json", "a.csv", "b.csv"]  # whole, then the interrupt


def test_orphans_of_killed_processes_are_cleaned_live_ones_kept(tmp_path):
    dead = os.fork()
    if dead == 0:  # pragma: no cover - child
        os._exit(0)
    os.waitpid(dead, 0)
    orphan = tmp_path / f".out.vvea-tmp-{dead}-0123abcd"
    orphan.mkdir()
    (orphan / "half.csv").write_text("half")
    live = tmp_path / f".out.vvea-tmp-{os.getppid()}-0123abcd"
    live.mkdir()
    with output_dir(tmp_path / "out", "demo") as tmp:
        (tmp / "a").write_text("1")
    assert not orphan.exists() and live.exists()


def test_output_files_replace_together_or_not_at_all(tmp_path):
    j, png = tmp_path / "d" / "design.json", tmp_path / "d" / "design_force.png"
    with output_files(j, png) as (tj, tp):
        assert tj.suffix == ".json" and tp.suffix == ".png" and tj.parent == j.parent
        tj.write_text("old")
        tp.write_text("old")
    with pytest.raises(KeyboardInterrupt):
        with output_files(j, png) as (tj, tp):
            tj.write_text("new")
            raise KeyboardInterrupt
    assert j.read_text() == "old" and png.read_text() == "old"
    assert visible(j.parent) == ["design.json", "design_force.png"]
    with pytest.raises(RuntimeError, match="not written inside the block"):
        with output_files(j, png) as (tj, tp):
            tj.write_text("new")
    assert j.read_text() == "old"
    write_text_atomic(j, "newer")
    assert j.read_text() == "newer" and visible(j.parent) == ["design.json", "design_force.png"]


def test_write_error_inside_the_block_names_the_target(tmp_path):
    with pytest.raises(OutputError, match=r"could not write .*out: .*nothing was changed") as exc:
        with output_dir(tmp_path / "out", "demo") as tmp:
            open(tmp / "no" / "such" / "dir.csv", "w")
    assert "Traceback" not in str(exc.value)
    assert visible(tmp_path) == []


@pytest.fixture()
def a_file(tmp_path):
    f = tmp_path / "results.txt"
    f.write_text("a file, not a folder")
    return f


def test_bad_locations_are_rejected_before_anything(tmp_path, a_file):
    with pytest.raises(OutputError, match="is an existing file, not a folder"):
        check_output_dir(a_file)
    with pytest.raises(OutputError, match=r"results.txt is a file, so nothing can be written under it"):
        check_output_dir(a_file / "sub" / "out")
    with pytest.raises(OutputError, match="is an existing folder; give a file path"):
        check_output_file(tmp_path)
    with pytest.raises(OutputError, match="results.txt is a file"):
        check_output_file(a_file / "design.json")
    with pytest.raises(OutputError, match="is an existing file"):
        with output_dir(a_file, "demo"):
            pytest.fail("the block must not run")
    assert a_file.read_text() == "a file, not a folder"


# ---------------------------------------------------------------------------
# a read-only folder, for real
# ---------------------------------------------------------------------------

NOBODY = 65534


@pytest.fixture()
def readonly_dir():
    """A folder without write permission, inside folders user ``nobody`` may traverse."""
    base = Path(tempfile.mkdtemp(prefix="vvea-ro-"))
    os.chmod(base, 0o755)
    ro = base / "ro"
    ro.mkdir()
    os.chmod(ro, 0o555)
    yield ro
    os.chmod(ro, 0o755)
    import shutil

    shutil.rmtree(base)


def as_unprivileged(fn):
    """Run ``fn()`` (returning a JSON-able value) as it would run for a normal user; return its value.

    As root the call runs in a forked child that dropped to ``nobody``; the
    modules it needs must be imported before (the child may not read /root).
    """
    if os.geteuid() != 0:
        return fn()
    r, w = os.pipe()
    pid = os.fork()
    if pid == 0:  # pragma: no cover - child
        try:
            os.setgroups([])
            os.setgid(NOBODY)
            os.setuid(NOBODY)
            out = {"ok": fn()}
        except BaseException as exc:  # noqa: BLE001 - report anything to the parent
            out = {"error": f"{type(exc).__name__}: {exc}"}
        os.write(w, json.dumps(out).encode())
        os._exit(0)
    os.close(w)
    with os.fdopen(r) as fh:
        data = fh.read()
    os.waitpid(pid, 0)
    got = json.loads(data)
    if "error" in got:
        raise AssertionError(got["error"])
    return got["ok"]


def test_readonly_folder_is_rejected_for_a_normal_user(readonly_dir):
    def attempt():
        msgs = []
        for fn, path in ((check_output_dir, readonly_dir / "out"), (check_output_dir, readonly_dir),
                         (check_output_file, readonly_dir / "design.json")):
            try:
                fn(path)
                msgs.append("accepted")
            except OutputError as exc:
                msgs.append(str(exc))
        return msgs

    for msg in as_unprivileged(attempt):
        assert "cannot write in" in msg and str(readonly_dir) in msg and "Permission denied" in msg


# ---------------------------------------------------------------------------
# every command that writes: bad --out exits 2 before any computation
# ---------------------------------------------------------------------------

def _design_json(folder: Path) -> Path:
    from vvea_design.spring.design import Design
    from vvea_design.spring.design_file import save_design
    from vvea_design.spring.problem import evaluate_design
    from vvea_design.spring.requirements import Requirements

    req = Requirements()
    return save_design(folder / "design.json", evaluate_design(Design(34.5, 59.5, 41500.0, 90000.0), req), req)


#: command -> argv with {design} and {out}; every one must reject a bad --out before computing.
COMMANDS = {
    "optimise": ["optimise", "--out", "{out}/design.json"],
    "spring": ["spring", "{design}", "--out", "{out}"],
    "pareto": ["pareto", "--axis", "outer_diameter", "--values", "55", "--out", "{out}"],
    "map": ["map", "{design}", "--n", "5", "--out", "{out}"],
    "design": ["design", "--no-renders", "--out", "{out}"],
    "cad": ["cad", "{design}", "--no-renders", "--out", "{out}"],
    "bladder": ["bladder", "{design}", "--out", "{out}"],
    "identify": ["identify", "{design}", "--out", "{out}"],
    "diagnose": ["diagnose", "{design}", "--out", "{out}"],
    "study-rest-to-rest": ["study", "rest-to-rest", "--grid", "0.2:0.4", "--out", "{out}"],
    "study-safety": ["study", "safety", "--out", "{out}"],
}

#: Library functions that do the work; a bad --out must be rejected before any of them runs.
HEAVY = [
    ("vvea_design.spring.optimise", "optimise"),
    ("vvea_design.spring.studies", "pareto_front"),
    ("vvea_design.spring.studies", "linearity_map"),
    ("vvea_design.cad", "write_cad"),
    ("vvea_design.cad", "build_cad"),
    ("vvea_design.bladder.check", "write_bladder_report"),
    ("vvea_design.identification.recordings", "read_recordings"),
    ("vvea_design.actuator.rest_to_rest", "run_rest_to_rest"),
    ("vvea_design.actuator.safety", "run_safety"),
]


@pytest.fixture()
def no_computation(monkeypatch):
    import importlib

    for mod, name in HEAVY:
        def refuse(*a, _name=name, **k):
            raise AssertionError(f"{_name} ran although --out was unusable")

        monkeypatch.setattr(importlib.import_module(mod), name, refuse)


def _argv(command, design, out):
    return [a.format(design=design, out=out) for a in COMMANDS[command]]


def _main_app():
    from vvea_design.cli.main import app

    return app


@pytest.mark.parametrize("command", sorted(COMMANDS))
@pytest.mark.parametrize("where", ["existing-file", "under-a-file"])
def test_bad_out_exits_2_naming_the_path(tmp_path, a_file, no_computation, command, where):
    design = _design_json(tmp_path)
    if where == "existing-file":
        # for optimise the --out is the design file: make it a folder to be wrong
        out = a_file if command != "optimise" else tmp_path
        argv = _argv(command, design, out)
        if command == "optimise":
            (tmp_path / "design.json").unlink()
            (tmp_path / "design.json").mkdir()
    else:
        out = a_file / "sub"
        argv = _argv(command, design, out)
    before = tree(tmp_path)
    res = runner.invoke(_main_app(), argv)
    assert res.exit_code == 2, (argv, res.output, res.exception)
    assert "Traceback" not in res.output and not isinstance(res.exception, AssertionError)
    assert "error:" in res.output and str(a_file.name if where == "under-a-file" or command != "optimise"
                                          else "design.json") in res.output
    assert tree(tmp_path) == before


@pytest.mark.parametrize("command", sorted(COMMANDS))
def test_readonly_out_exits_2_for_every_command(readonly_dir, tmp_path, command, monkeypatch):
    """The same table with a folder a normal user may not write in (checked as `nobody` when root)."""
    import importlib

    for mod, name in HEAVY:
        monkeypatch.setattr(importlib.import_module(mod), name,
                            lambda *a, _n=name, **k: (_ for _ in ()).throw(AssertionError(f"{_n} ran")))
    design = _design_json(Path(tempfile.mkdtemp(dir=readonly_dir.parent)))
    os.chmod(design.parent, 0o755)
    os.chmod(design, 0o644)
    argv = _argv(command, design, readonly_dir / "out")
    app = _main_app()
    import vvea_design.cli.bladder  # noqa: F401 - imported before dropping privileges
    import vvea_design.cli.cad  # noqa: F401
    import vvea_design.spring.design_file  # noqa: F401
    import vvea_design.spring.requirements  # noqa: F401

    def attempt():
        res = runner.invoke(app, argv)
        return [res.exit_code, res.output, repr(res.exception)]

    code, output, exc = as_unprivileged(attempt)
    assert code == 2, (output, exc)
    assert "cannot write in" in output and "ro" in output and "Traceback" not in output
    assert os.listdir(readonly_dir) == []


# ---------------------------------------------------------------------------
# interrupted commands leave the previous output as it was
# ---------------------------------------------------------------------------

def test_interrupted_map_keeps_the_previous_folder(tmp_path, monkeypatch):
    import vvea_design.spring.plots as plots

    design = _design_json(tmp_path)
    out = tmp_path / "m"
    argv = ["map", str(design), "--x", "piston_diameter_mm", "--y", "V1_mm3", "--n", "5", "--out", str(out)]
    assert runner.invoke(_main_app(), argv).exit_code == 0
    before = tree(out)
    assert "map_piston_diameter_mm_V1_mm3.csv" in before

    def save_then_get_interrupted(fig, path, *a, **kw):
        Path(path).write_bytes(b"half a png")
        raise KeyboardInterrupt

    monkeypatch.setattr(plots, "save_figure", save_then_get_interrupted)
    res = runner.invoke(_main_app(), argv[:-1] + [str(out)])
    assert interrupted(res)
    assert tree(out) == before and visible(tmp_path) == ["design.json", "m"]


def test_failed_cad_keeps_the_previous_set(tmp_path, monkeypatch):
    """A CAD run that fails half-way (after writing some STEP files) leaves the earlier set untouched."""
    import vvea_design.cad as cad
    from vvea_design.cad import CadError

    design = _design_json(tmp_path)
    out = tmp_path / "cad"
    out.mkdir()
    (out / "housing.step").write_text("earlier run")
    (out / "manifest.json").write_text("{}")

    def write_some_then_fail(design, folder, renders=True, **kw):
        (Path(folder) / "housing.step").write_text("new, half")
        raise CadError("the bladder mould does not close")

    monkeypatch.setattr(cad, "build_cad", lambda design: object())
    monkeypatch.setattr(cad, "write_cad", write_some_then_fail)
    res = runner.invoke(_main_app(), ["cad", str(design), "--no-renders", "--no-drawings", "--out", str(out)])
    assert res.exit_code == 2 and "does not close" in res.output
    assert tree(out) == {"housing.step": b"earlier run", "manifest.json": b"{}"}
    assert visible(tmp_path) == ["cad", "design.json"]


def test_design_job_lands_whole_or_not_at_all(tmp_path, monkeypatch):
    """`vvea design` writes the whole unit into one temporary folder: a step that fails leaves the old unit."""
    import vvea_design.pipeline as pipeline
    from vvea_design.cli.main import app

    out = tmp_path / "job"
    with output_dir(out, "design") as tmp:  # the unit of an earlier run
        (tmp / "design.json").write_text("earlier")
        (tmp / "cad").mkdir()
        (tmp / "cad" / "housing.step").write_text("earlier")
    first = tree(out)

    def unit_then_ctrl_c(req, folder, **kw):
        (Path(folder) / "design.json").write_text("new")
        (Path(folder) / "cad").mkdir()
        (Path(folder) / "cad" / "housing.step").write_text("new, half")
        raise KeyboardInterrupt  # e.g. during the bladder step

    monkeypatch.setattr(pipeline, "design_unit", unit_then_ctrl_c)
    res = runner.invoke(app, ["design", "--out", str(out), "--no-renders"])
    assert interrupted(res), res.output
    assert tree(out) == first and visible(tmp_path) == ["job"]


# The unit written through a temporary folder and moved into place naming no temporary folder is
# checked on the whole `vvea design` run of tests/pipeline/test_pipeline.py (test_design_unit_names_no_temporary_folder),
# which already writes the unit through `output_dir`: no second pipeline run here.


def test_optimise_writes_design_and_plot_together(tmp_path, monkeypatch):
    import vvea_design.spring.optimise as opt
    import vvea_design.spring.plots as plots
    from vvea_design.cli.main import app
    from vvea_design.spring.design import Design
    from vvea_design.spring.problem import evaluate_design
    from vvea_design.spring.requirements import Requirements

    ev = evaluate_design(Design(34.5, 59.5, 41500.0, 90000.0), Requirements())
    monkeypatch.setattr(opt, "optimise", lambda req, **kw: opt.OptimisationResult(ev, 0, 1, 0.1, 1, "stub", False))
    target = tmp_path / "d" / "design.json"
    assert runner.invoke(app, ["optimise", "--out", str(target)]).exit_code == 0
    before = tree(tmp_path / "d")
    assert set(before) == {"design.json", "design_force.png"}
    monkeypatch.setattr(plots, "plot_spring", lambda *a, **k: (_ for _ in ()).throw(KeyboardInterrupt()))
    res = runner.invoke(app, ["optimise", "--out", str(target)])
    assert interrupted(res)
    assert tree(tmp_path / "d") == before


def test_study_summary_and_figures_are_replaced_whole_results_kept(tmp_path, monkeypatch):
    """`vvea study rest-to-rest` stays resumable (results.csv in place); its summary and figures land whole."""
    import vvea_design.actuator.rest_to_rest as rr
    from vvea_design.actuator.ocp import Mesh

    grid, mesh = rr.Grid((0.4,), (0.8,)), Mesh(16, 3)
    rr.run_rest_to_rest(tmp_path, grid=grid, mesh=mesh, fine_mesh=None, workers=1, progress=False)
    before = tree(tmp_path)
    assert {"results.csv", "summary.json", "best_map.png", "trajectory.png"} <= set(before)

    def trajectory_then_ctrl_c(*a, **k):
        raise KeyboardInterrupt

    monkeypatch.setattr(rr, "plot_trajectory", trajectory_then_ctrl_c)
    with pytest.raises(KeyboardInterrupt):  # resume: nothing to solve, then the figures are interrupted
        rr.run_rest_to_rest(tmp_path, grid=grid, mesh=mesh, fine_mesh=None, workers=1, progress=False)
    assert tree(tmp_path) == before  # summary.json and best_map.png not replaced alone


# ---------------------------------------------------------------------------
# nested results: a job inside the main job's folder (issue 22)
# ---------------------------------------------------------------------------

def test_a_folder_inside_an_open_one_is_written_in_place(tmp_path):
    """design_unit runs each step's job into its own sub-folder of the unit's temporary folder: in place, no
    temporary and no marker of its own; the unit lands whole with everything in it."""
    target = tmp_path / "unit"
    with output_dir(target, "design") as tmp:
        with output_dir(tmp / "cad", "cad") as inner:
            assert inner == Path(os.path.realpath(tmp / "cad")) and inner.is_dir()
            (inner / "part.step").write_text("solid")
        with output_dir(tmp, "design") as same:  # the open folder itself
            assert same == Path(os.path.realpath(tmp))
        assert sorted(os.listdir(tmp)) == ["cad"]  # no temporary, no marker inside
    assert tree(target) == {".vvea-design.json": b'{\n "command": "design",\n "entries": [\n  "cad"\n ]\n}\n',
                            "cad/part.step": b"solid"}
    with output_dir(tmp_path / "alone", "cad") as tmp:  # once the block is closed, a folder is its own again
        assert tmp != tmp_path / "alone" and ".vvea-tmp-" in tmp.name
        (tmp / "x").write_text("1")
    assert visible(tmp_path / "alone") == [".vvea-cad.json", "x"]


def test_a_failed_step_inside_an_open_folder_leaves_the_old_unit(tmp_path):
    target = tmp_path / "unit"
    with output_dir(target, "design") as tmp:
        (tmp / "design.json").write_text("old")
    before = tree(target)
    with pytest.raises(RuntimeError, match="mould"):
        with output_dir(target, "design") as tmp:
            with output_dir(tmp / "cad", "cad") as inner:
                (inner / "housing.step").write_text("half")
                raise RuntimeError("the mould does not close")
    assert tree(target) == before and visible(tmp_path) == ["unit"]


def test_a_refused_location_is_named_for_its_option(tmp_path, a_file):
    with pytest.raises(OutputError) as exc:
        check_output_dir(a_file, "")
    assert str(exc.value).startswith(f"{a_file}: is an existing file") and exc.value.path == a_file
    assert exc.value.named("--out") == f"--out {a_file}: is an existing file, not a folder; give a folder path"
    failed = OutputError("could not move the results into /x: busy")  # not a refused location: as it is
    assert failed.named("--out") == str(failed)
