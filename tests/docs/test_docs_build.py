"""The documentation builds with Sphinx, warnings as errors, offline; the README stays a short
front door; the pages follow the documentation's rules (times only on the benchmarks page, every
image exists).

The build runs the gallery without executing the examples (``-D plot_gallery=0``): every example
runs as its own test in ``test_examples.py`` (at its small size), so executing them again here
would only double the suite's time. Nitpicky mode is off: the docstrings name types in prose
(``float``, ``path-like``, ``array of shape (n,)``) that no inventory resolves without intersphinx,
which the offline build cannot fetch.
"""

from __future__ import annotations

import importlib.util
import os
import re
import subprocess
import sys
from pathlib import Path

# The documentation tools (the test extra): imported here so a missing one fails loudly, by name.
import myst_parser  # noqa: F401
import numpydoc  # noqa: F401
import pydata_sphinx_theme  # noqa: F401
import sphinx
import sphinx_gallery  # noqa: F401

from tests.helpers import REPO

DOCS = REPO / "docs"


def test_sphinx_build_has_no_warnings(tmp_path):
    """``sphinx-build -W`` into a temporary folder: any warning fails, and the main pages are there."""
    out = tmp_path / "html"
    env = {**os.environ, "PYTHONPATH": os.pathsep.join([str(REPO), os.environ.get("PYTHONPATH", "")]),
           "MPLBACKEND": "Agg"}
    res = subprocess.run(
        [sys.executable, "-m", "sphinx", "-b", "html", "-W", "--keep-going", "-q", "-E",
         "-d", str(tmp_path / "doctrees"), "-D", "plot_gallery=0", str(DOCS), str(out)],
        capture_output=True, text=True, cwd=REPO, env=env, timeout=1200)
    assert res.returncode == 0, f"sphinx {sphinx.__version__} failed:\n{res.stderr[-6000:]}"
    for page in ("index", "tutorial", "howto/diagnose", "howto/linearity-tests", "howto/dask",
                 "explanation/physics", "explanation/optimiser", "layout", "reference/cli", "reference/api",
                 "reference/formats", "reference/_schemas/requirements", "benchmarks", "auto_examples/index"):
        assert (out / f"{page}.html").is_file(), f"{page}.html was not built"
    cli = (out / "reference" / "cli.html").read_text()
    for path, params in _cli_commands():
        assert f'id="cli-{"-".join(path) or "vvea"}"' in cli, f"the CLI reference lacks vvea {' '.join(path)}"
        for opt in params:
            assert opt in cli, f"the CLI reference lacks {opt} of vvea {' '.join(path)}"
    api = (out / "reference" / "api.html").read_text()
    assert "design_unit" in api and "assert_linearity" in api


def _cli_commands():
    """``(path, option names)`` of every command of the ``vvea`` app, e.g. ``(["study", "safety"], ["--out", ...])``."""
    import typer.main

    from vvea_design.cli.main import app

    out = []

    def walk(cmd, path):
        out.append((path, [o for p in cmd.params for o in p.opts if o.startswith("--") and o != "--help"]))
        for name, sub in getattr(cmd, "commands", {}).items():
            walk(sub, [*path, name])

    walk(typer.main.get_command(app), [])
    return out


def test_the_face_is_what_the_api_reference_lists():
    """The API page's face table is generated from ``vvea_design.__all__``, every name in it."""
    import vvea_design as vd

    spec = importlib.util.spec_from_file_location("vvea_docs", DOCS / "_ext" / "vvea_docs.py")
    vvea_docs = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(vvea_docs)  # the docs' own extension (not a package on sys.path)

    listed = [name for names in vvea_docs.face_groups().values() for name in names]
    assert sorted(listed) == sorted(vd.__all__)
    text = vvea_docs.face_rst()
    modules = vvea_docs.documented_modules()
    for name in vd.__all__:
        home = re.search(rf"^   ~([\w.]+)\.{name}$", text, re.M)
        assert home, f"{name} is not in the face table"
        # the row links to the name's entry in its module's page: that module must be documented
        assert any(home.group(1) == m or home.group(1).startswith(m + ".") for m in modules), (
            f"vd.{name} lives in {home.group(1)}, which the API reference does not document")


README = (REPO / "README.md").read_text()


def test_readme_is_a_short_front_door():
    lines = README.splitlines()
    assert len(lines) <= 200, f"README.md has {len(lines)} lines (at most 200)"
    assert "import vvea_design as vd" in README
    assert "bash scripts/install.sh && vvea design -o vvea_out" in README
    ci = (REPO / ".ci" / "run").read_text()
    test_command = re.search(r"bash scripts/install.sh test && python3 -m pytest -n 2", ci).group(0)
    assert test_command in README, "the README's test command is what .ci/run runs"
    assert README.count("![") == 1, "one picture"


#: A date, a commit id, an issue number, a machine load or a measured time (physics times such as a
#: period or a rise time are not measured times: only a time something took is one).
DIARY = {
    "date": re.compile(r"\b20\d\d-\d\d-\d\d\b"),
    "issue number": re.compile(r"\bissues? \d+|\bissue-\d+|\bissue's\b|#\d{1,4}\b", re.I),
    "commit id": re.compile(r"`[0-9a-f]{7,40}`"),
    "machine load": re.compile(r"\bload (average )?\d|\buptime\b|\btoday\b"),
    "measured time": re.compile(r"\b(took|takes|taking|lasted|runs? in)\b[^.;]{0,30}?\d+(\.\d+)? ?(s|ms|min|h)\b"
                                r"|\bCPU[- ]s\b|\d ?(s|min) (of )?(wall|CPU)\b"),
}


def _pages():
    yield REPO / "README.md"
    yield from sorted(p for p in DOCS.rglob("*.md") if "_build" not in p.parts and p.name != "benchmarks.md")


def test_no_diary_outside_the_benchmarks_page():
    """Dates, machine loads, commit ids, issue numbers and measured times live on docs/benchmarks.md only."""
    found = []
    for page in _pages():
        for i, line in enumerate(page.read_text().splitlines(), 1):
            for what, pattern in DIARY.items():
                found += [f"{page.relative_to(REPO)}:{i}: {what}: {m.group(0)!r}" for m in pattern.finditer(line)]
    assert not found, "\n".join(found)


def test_every_image_the_docs_show_exists():
    missing = []
    for page in _pages():
        text = page.read_text()
        for target in re.findall(r"!\[[^\]]*\]\(([^)\s]+)\)", text):
            if not (page.parent / target).resolve().is_file():
                missing.append(f"{page.relative_to(REPO)}: {target}")
    assert not missing, "\n".join(missing)
