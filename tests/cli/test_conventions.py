"""Conventions of every command (issue 13 item 6): results on stdout, progress and logs on stderr, no wrapping
off a terminal, -o on every command that writes, the README's examples pass on the shipped default design,
install.sh refuses a Python pip may not install into."""

import inspect
import os
import re
import shutil
import subprocess
import sys
from pathlib import Path

import pytest
import typer.models
from tests.helpers import REPO

ROOT = REPO
README = (ROOT / "README.md").read_text()
#: The shipped default design (what `vvea optimise` / `vvea design` make on the built-in requirements).
DEFAULT_DESIGN = ROOT / "studies" / "results" / "optimise" / "design.json"


def _vvea(*args, cwd=ROOT):
    env = {k: v for k, v in os.environ.items() if k != "COLUMNS"}
    return subprocess.run([sys.executable, "-m", "vvea_design", *map(str, args)], capture_output=True, text=True,
                          cwd=cwd, env=env, timeout=300)


def test_results_on_stdout_logs_on_stderr_and_no_wrapping(tmp_path):
    res = _vvea("spring", DEFAULT_DESIGN, "-o", tmp_path / "s")
    assert res.returncode == 0, res.stderr
    result = [line for line in res.stdout.splitlines() if line.strip()]
    assert len(result) == 1, res.stdout  # one result line, not wrapped at 80 columns
    assert len(result[0]) > 80 and re.search(r"F\(40\) = \d+\.\d N$", result[0])
    assert "wrote" in res.stderr and "wrote" not in res.stdout


def test_tables_go_to_stdout_unwrapped(tmp_path):
    res = _vvea("check", DEFAULT_DESIGN, "--max-linearity", "0.016")
    assert res.returncode == 0 and res.stdout.startswith("OK")
    # stderr: at most the toolkit's notes (the reference file predates the buildability rules), never a trace
    assert all(line.startswith("note: ") for line in res.stderr.splitlines()), res.stderr
    assert len(res.stdout.strip().splitlines()) == 1


def _commands():
    from vvea_design.cli.main import app
    from typer.main import get_command

    root = get_command(app)
    out = []

    def walk(cmd, path):
        if hasattr(cmd, "commands"):
            for name, sub in cmd.commands.items():
                walk(sub, path + [name])
        else:
            out.append((" ".join(path), cmd))

    walk(root, [])
    return out


def test_every_command_that_writes_has_dash_o():
    writers = 0
    for name, cmd in _commands():
        opts = {o: p for p in cmd.params for o in p.opts}
        if "--out" in opts:
            writers += 1
            assert "-o" in opts and opts["-o"] is opts["--out"], f"vvea {name}: --out has no -o"
    assert writers >= 10


def test_readme_check_example_passes_on_the_default_design(tmp_path):
    line = next(ln for ln in README.splitlines() if ln.startswith("vvea check design.json"))
    args = line.split("#")[0].split()[2:]
    shutil.copy(DEFAULT_DESIGN, tmp_path / "design.json")
    res = _vvea("check", *args, cwd=tmp_path)
    assert res.returncode == 0, res.stdout + res.stderr


def test_readme_pytest_snippet_passes_on_the_default_design(tmp_path, monkeypatch):
    snippet = re.search(r"```python\n(from vvea_design.testing import assert_linearity.*?)```", README, re.S).group(1)
    shutil.copy(DEFAULT_DESIGN, tmp_path / "design.json")
    monkeypatch.chdir(tmp_path)
    ns = {}
    exec(compile(snippet, "README.md", "exec"), ns)
    tests = [f for n, f in ns.items() if n.startswith("test_") and inspect.isfunction(f)]
    assert len(tests) == 1
    tests[0]()


def test_readme_says_to_make_a_virtual_environment_first():
    top = README.split("## The tour")[0]
    assert "python3 -m venv .venv && . .venv/bin/activate" in top


@pytest.mark.skipif(not Path("/usr/lib/python3.11/EXTERNALLY-MANAGED").exists() or not Path("/usr/bin/python3").exists(),
                    reason="needs a system Python marked EXTERNALLY-MANAGED (Debian 12)")
def test_install_refuses_an_externally_managed_python():
    res = subprocess.run(["bash", str(ROOT / "scripts" / "install.sh")], capture_output=True, text=True,
                         env={**os.environ, "PYTHON": "/usr/bin/python3"}, timeout=60)
    assert res.returncode == 1
    assert "python3 -m venv .venv && . .venv/bin/activate" in res.stderr


def test_generated_outputs_are_ignored_by_git(tmp_path):
    ignored = (ROOT / ".gitignore").read_text().split()
    for entry in ("/vvea_out/", "*.egg-info/", ".venv/", "__pycache__/"):
        assert entry in ignored
    default_out = inspect.signature(__import__("vvea_design.cli.main", fromlist=["design"]).design).parameters["out"]
    assert isinstance(default_out.default, typer.models.OptionInfo)
    assert f"/{default_out.default.default}/" in ignored


def test_ci_runs_exactly_the_readme_test_command():
    ci = (ROOT / ".ci" / "run").read_text()
    assert "bash scripts/install.sh test && python3 -m pytest -n 2" in ci
    assert "bash .ci/run" in README.split("## The tour")[0]
