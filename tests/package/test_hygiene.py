"""Library hygiene (issue 9 item 6): no backend switch on import, one version, the entry points,
declared dependencies, and numpydoc docstrings with units on every public function and on every public
method of a public class."""

import ast
import functools
import importlib
import inspect
import json
import os
import pkgutil
import re
import subprocess
import sys
import tomllib
from importlib import metadata
from pathlib import Path

import pytest
from typer.testing import CliRunner

import vvea_design
from tests.helpers import REPO

ROOT = REPO
PYPROJECT = tomllib.loads((ROOT / "pyproject.toml").read_text())


def _all_modules() -> list[str]:
    names = ["vvea_design"]
    for info in pkgutil.walk_packages(vvea_design.__path__, "vvea_design."):
        names.append(info.name)
    return sorted(names)


def _public_module(name: str) -> bool:
    return not any(part.startswith("_") and part != "__main__" for part in name.split("."))


MODULES = _all_modules()

# ------------------------------------------------------------------ backend
def fresh_import(package: str, modules: list[str]) -> dict:
    """Import ``modules`` of ``package`` afresh with ``matplotlib.use`` and ``pyplot.switch_backend`` recording
    their caller, the backend set to svg as a user's session would have it: ``{"callers", "backend"}``.

    The package's modules are taken out of ``sys.modules`` and imported again in this interpreter (the
    third-party libraries they import are already loaded here: a fresh interpreter spends ~9 s of CPU
    importing them again for the same answer), then the original modules and backend are put back, so the
    rest of the session keeps its objects.
    """
    import matplotlib
    import matplotlib.pyplot as plt

    callers: dict[str, str] = {}

    def recording(fn):
        def wrapper(backend, *a, **k):
            caller = sys._getframe(1).f_globals.get("__name__", "?")
            if caller.split(".")[0] != "matplotlib":  # matplotlib.use calls switch_backend itself
                callers.setdefault(caller, backend)
            return fn(backend, *a, **k)
        return wrapper

    def mine(k):
        return k == package or k.startswith(package + ".")

    saved = {k: m for k, m in sys.modules.items() if mine(k)}
    backend = matplotlib.get_backend()
    use, switch = matplotlib.use, plt.switch_backend
    matplotlib.use, plt.switch_backend = recording(use), recording(switch)
    try:
        plt.switch_backend("svg")
        callers.clear()
        for k in saved:
            del sys.modules[k]
        for name in modules:
            importlib.import_module(name)
        after = matplotlib.get_backend()
    finally:
        for k in [k for k in sys.modules if mine(k)]:
            del sys.modules[k]
        sys.modules.update(saved)
        matplotlib.use, plt.switch_backend = use, switch
        plt.switch_backend(backend)
    return {"callers": callers, "backend": after}


@pytest.fixture(scope="module")
def import_probe():
    """Every module of the package imported afresh (:func:`fresh_import`); the command-line test below
    runs a fresh interpreter."""
    return fresh_import("vvea_design", MODULES)


def test_the_probe_catches_a_module_that_switches_the_backend(tmp_path, monkeypatch):
    pkg = tmp_path / "probe_demo"
    pkg.mkdir()
    (pkg / "__init__.py").write_text("")
    (pkg / "quiet.py").write_text("import matplotlib.pyplot\n")
    (pkg / "loud.py").write_text("import matplotlib\nmatplotlib.use('agg')\n")
    monkeypatch.syspath_prepend(str(tmp_path))
    import matplotlib

    before = matplotlib.get_backend()
    probe = fresh_import("probe_demo", ["probe_demo", "probe_demo.quiet", "probe_demo.loud"])
    assert probe["callers"] == {"probe_demo.loud": "agg"} and probe["backend"].lower() == "agg"
    assert matplotlib.get_backend() == before and "probe_demo" not in sys.modules


@pytest.mark.parametrize("module", MODULES)
def test_no_module_switches_the_backend_on_import(import_probe, module):
    assert module not in import_probe["callers"], f"{module} calls matplotlib.use({import_probe['callers'][module]!r})"


def test_importing_everything_keeps_the_users_backend(import_probe):
    assert import_probe["backend"].lower() == "svg"


def test_the_command_line_selects_agg(tmp_path):
    """The CLI (not the library) selects Agg, so a command draws off-screen whatever MPLBACKEND says."""
    code = ("import matplotlib; from typer.testing import CliRunner; from vvea_design.cli.main import app; "
            "r = CliRunner().invoke(app, ['check', 'nonexistent.json', '--max-linearity', '0.1']); "
            "print(matplotlib.get_backend())")
    res = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, cwd=tmp_path,
                         env={**os.environ, "MPLBACKEND": "svg"}, timeout=120)
    assert res.stdout.strip().splitlines()[-1].lower() == "agg", res.stderr


# ------------------------------------------------------------------ version, entry points
def test_version_in_one_place():
    assert PYPROJECT["project"]["dynamic"] == ["version"]
    assert "version" not in PYPROJECT["project"]
    assert PYPROJECT["tool"]["setuptools"]["dynamic"]["version"] == {"attr": "vvea_design.__version__"}
    assert re.fullmatch(r"\d+\.\d+\.\d+", vvea_design.__version__)
    try:
        assert metadata.version("vvea-design") == vvea_design.__version__
    except metadata.PackageNotFoundError:  # pragma: no cover - run from a plain checkout
        pass


def test_version_option_and_python_dash_m():
    from vvea_design.cli.main import app

    res = CliRunner().invoke(app, ["--version"])
    assert res.exit_code == 0 and res.stdout.strip() == f"vvea-design {vvea_design.__version__}"
    res = subprocess.run([sys.executable, "-m", "vvea_design", "--version"], capture_output=True, text=True,
                         cwd=ROOT, timeout=120)
    assert res.returncode == 0 and res.stdout.strip() == f"vvea-design {vvea_design.__version__}"


def test_typed_licensed_package():
    assert (ROOT / "vvea_design" / "py.typed").exists()
    assert "py.typed" in PYPROJECT["tool"]["setuptools"]["package-data"]["vvea_design"]
    assert PYPROJECT["project"]["license"] == "MIT"  # PEP 639 expression
    for f in PYPROJECT["project"]["license-files"]:
        assert (ROOT / f).is_file()
    assert "MIT License" in (ROOT / "LICENSE").read_text()
    req = PYPROJECT["build-system"]["requires"][0]
    assert int(re.search(r">=(\d+)", req).group(1)) >= 77  # setuptools that reads PEP 639 license fields


# ------------------------------------------------------------------ import graph
def _module_files() -> dict[str, Path]:
    """Every module of the package (vendored files aside) by dotted name."""
    pkg = ROOT / "vvea_design"
    out = {}
    for path in sorted(pkg.rglob("*.py")):
        rel = path.relative_to(ROOT).with_suffix("").parts
        if "vendor" in rel:
            continue
        out[".".join(rel[:-1] if rel[-1] == "__init__" else rel)] = path
    return out


@functools.lru_cache(maxsize=None)
def _tree(source: str) -> ast.Module:
    """``ast.parse(source)``, once per source text (the import graph and the dependency check read the same files)."""
    return ast.parse(source)


def package_imports(source: str, module: str, is_package: bool, known: set[str]) -> set[str]:
    """The package modules that ``source`` imports: top-level, inside functions and under ``TYPE_CHECKING``.

    Parameters
    ----------
    source : str
        Python source of the module.
    module : str
        Its dotted name (``vvea_design.report.html``), to resolve relative imports.
    is_package : bool
        True for an ``__init__.py`` (its relative imports start from itself).
    known : set of str
        Dotted names of the package's modules; ``from a import b`` maps to ``a.b`` when that is a module.

    Returns
    -------
    set of str
        Dotted names of the imported package modules (the module itself left out).
    """
    base = module.split(".") if is_package else module.split(".")[:-1]
    out = set()
    for node in ast.walk(_tree(source)):
        if isinstance(node, ast.ImportFrom):
            if node.level:
                head = base[:len(base) - node.level + 1] + ([node.module] if node.module else [])
                src = ".".join(head)
            else:
                src = node.module or ""
            names = [f"{src}.{a.name}" for a in node.names]
        elif isinstance(node, ast.Import):
            names = [a.name for a in node.names]
        else:
            continue
        for name in names:
            if not name.startswith("vvea_design"):
                continue
            while name not in known and "." in name:
                name = name.rsplit(".", 1)[0]
            if name in known and name != module:
                out.add(name)
    return out


def _import_graph() -> dict[str, set[str]]:
    files = _module_files()
    return {m: package_imports(p.read_text(), m, p.name == "__init__.py", set(files)) for m, p in files.items()}


def _cycle(graph: dict[str, set[str]]) -> list[str] | None:
    """One cycle of ``graph`` (as a path that ends where it starts), or None."""
    state: dict[str, int] = {}

    def visit(node, path):
        state[node] = 1
        for nxt in sorted(graph.get(node, ())):
            if state.get(nxt) == 1:
                return [*path[path.index(nxt):], nxt] if nxt in path else [*path, nxt]
            if nxt not in state:
                found = visit(nxt, [*path, nxt])
                if found:
                    return found
        state[node] = 2
        return None

    for start in sorted(graph):
        if start not in state:
            found = visit(start, [start])
            if found:
                return found
    return None


#: The floors of the package (STYLE.md, "the shape we want"): a room imports only rooms on its own floor or
#: below. A room is a subpackage or a top-level module; a new one must be placed here.
FLOORS = {
    "vvea_design": 0, "messages": 0, "progress": 0, "outputs": 0, "parallel": 0, "materials": 0, "figure_layout": 0,
    "palette": 0, "inputs": 0, "plausibility": 0,
    "spring": 1, "bladder": 1,
    "cad": 2, "identification": 2, "actuator": 2, "schema": 2, "testing": 2,
    "report": 3,
    "jobs": 4,  # one function per command, over the wings and the report; the pipeline composes them
    "pipeline": 5,
    "cli": 6,
    "__main__": 7,
}


def _room(module: str) -> str:
    parts = module.split(".")
    return parts[1] if len(parts) > 1 else parts[0]


def test_the_import_graph_has_no_cycle_and_no_upward_import():
    """Lazy and TYPE_CHECKING-only imports count: a cycle in type hints is still a cycle of the design."""
    graph = _import_graph()
    cycle = _cycle(graph)
    assert cycle is None, "import cycle: " + " -> ".join(cycle)
    rooms: dict[str, set[str]] = {}
    for a, targets in graph.items():
        for b in targets:
            if _room(a) != _room(b):
                rooms.setdefault(_room(a), set()).add(_room(b))
    unplaced = sorted({_room(m) for m in graph} - set(FLOORS))
    assert not unplaced, f"rooms without a floor (add them to FLOORS): {unplaced}"
    upward = sorted(f"{a} -> {b}" for a, targets in graph.items() for b in targets
                    if FLOORS[_room(b)] > FLOORS[_room(a)])
    assert not upward, "imports that run upward: " + "; ".join(upward)
    cycle = _cycle(rooms)
    assert cycle is None, "cycle between rooms: " + " -> ".join(cycle)


#: What the command line may import from the package: the jobs (their functions, result types and errors), the
#: main job, messages, outputs and progress; the root only for its version.
CLI_MAY_IMPORT = ("vvea_design.jobs", "vvea_design.pipeline", "vvea_design.messages", "vvea_design.outputs",
                  "vvea_design.progress", "vvea_design.cli")


def imported_names(source: str, module: str, is_package: bool) -> list[tuple[str, str | None]]:
    """Every import of the package in ``source``: (module imported from, name or None for ``import m``).

    Parameters
    ----------
    source : str
        Python source of the module.
    module : str
        Its dotted name, to resolve relative imports.
    is_package : bool
        True for an ``__init__.py``.

    Returns
    -------
    list of (str, str or None)
        Top-level, lazy and TYPE_CHECKING imports alike, in source order.
    """
    base = module.split(".") if is_package else module.split(".")[:-1]
    out = []
    for node in ast.walk(_tree(source)):
        if isinstance(node, ast.ImportFrom):
            head = (base[:len(base) - node.level + 1] + ([node.module] if node.module else [])) if node.level \
                else [node.module or ""]
            src = ".".join(head)
            if src.split(".")[0] == "vvea_design":
                out += [(node.lineno, src, a.name) for a in node.names]
        elif isinstance(node, ast.Import):
            out += [(node.lineno, a.name, None) for a in node.names if a.name.split(".")[0] == "vvea_design"]
    return [(src, name) for _, src, name in sorted(out)]


def cli_import_problems(source: str, module: str, is_package: bool) -> list[str]:
    """The imports of a command-line module that reach past the jobs (see :data:`CLI_MAY_IMPORT`).

    Parameters
    ----------
    source : str
        Python source of the module.
    module : str
        Its dotted name.
    is_package : bool
        True for an ``__init__.py``.

    Returns
    -------
    list of str
        ``"from a import b"`` for every import of another room, or of a name a jobs module does not offer
        (not in its ``__all__``).
    """
    bad = []
    for src, name in imported_names(source, module, is_package):
        full = f"{src}.{name}" if name else src
        if src == "vvea_design" and name == "__version__":
            continue
        if src == "vvea_design" and name is not None:  # `from vvea_design import jobs` and the like
            src, name = full, None
        if not any(src == ok or src.startswith(ok + ".") for ok in CLI_MAY_IMPORT):
            bad.append(f"from {src} import {name}" if name else f"import {src}")
        elif name is not None and src.startswith("vvea_design.jobs.") and name != "*":
            if name not in getattr(importlib.import_module(src), "__all__", ()):
                bad.append(f"from {src} import {name} (not in its __all__)")
    return bad


def test_the_command_line_imports_only_jobs_messages_outputs_progress_and_the_main_job():
    """Issue 22: each command parses, calls one job and prints; it builds nothing from the wings itself."""
    files = {m: p for m, p in _module_files().items() if _room(m) == "cli"}
    assert len(files) >= 6
    bad = {m: found for m, p in files.items() if (found := cli_import_problems(p.read_text(), m, p.name == "__init__.py"))}
    assert not bad, "the command line reaches past the jobs: " + "; ".join(f"{m}: {', '.join(v)}" for m, v in bad.items())


def test_the_cli_import_check_finds_each_form():
    src = ("from ..jobs.spring import optimise, SpecError\n"  # a job and a re-exported error: allowed
           "from ..spring.design_file import load_design\n"  # a wing: not allowed
           "from ..jobs.spring import _write_map\n"  # not offered by the job module
           "from .. import __version__\n"  # the version: allowed
           "from ..outputs import OutputError\n"  # allowed
           "def f():\n    import vvea_design.cad\n    from ..report.html import recorded_text\n")
    assert cli_import_problems(src, "vvea_design.cli.main", False) == [
        "from vvea_design.spring.design_file import load_design",
        "from vvea_design.jobs.spring import _write_map (not in its __all__)",
        "import vvea_design.cad", "from vvea_design.report.html import recorded_text"]


# ------------------------------------------------------------------ size limits
#: Modules allowed over MAX_MODULE_LINES and functions over MAX_FUNCTION_LINES, each with its reason (none today).
SIZE_EXCEPTIONS: dict[str, str] = {}
MAX_MODULE_LINES = 800
MAX_FUNCTION_LINES = 120


def size_problems(source: str, name: str) -> list[str]:
    """A module over :data:`MAX_MODULE_LINES` lines and its functions over :data:`MAX_FUNCTION_LINES` lines.

    Parameters
    ----------
    source : str
        Python source of the module.
    name : str
        Its path (relative to the repository), which names the module and prefixes each function.

    Returns
    -------
    list of str
        ``"<path>: N lines"`` and ``"<path>:<function>: N lines"`` (methods and nested functions included),
        leaving out those in :data:`SIZE_EXCEPTIONS`.
    """
    out = []
    lines = len(source.splitlines())
    if lines > MAX_MODULE_LINES and name not in SIZE_EXCEPTIONS:
        out.append(f"{name}: {lines} lines")
    for node in ast.walk(_tree(source)):
        if isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef)):
            n = node.end_lineno - node.lineno + 1
            key = f"{name}:{node.name}"
            if n > MAX_FUNCTION_LINES and key not in SIZE_EXCEPTIONS:
                out.append(f"{key}: {n} lines")
    return out


def test_no_module_over_800_lines_and_no_function_over_120():
    found = [p for path in sorted((ROOT / "vvea_design").rglob("*.py"))
             for p in size_problems(path.read_text(), str(path.relative_to(ROOT)))]
    assert not found, "over the size limits (split them, or list them in SIZE_EXCEPTIONS with the reason): " + \
        "; ".join(found)


def test_the_size_check_finds_a_long_module_and_function():
    body = "\n".join(f"    x{i} = {i}" for i in range(121))
    src = f"def long():\n{body}\n" + "y = 1\n" * 700
    assert size_problems(src, "m.py") == ["m.py: 822 lines", "m.py:long: 122 lines"]
    assert size_problems("def short():\n    return 1\n", "m.py") == []


def test_the_import_graph_sees_type_checking_and_lazy_imports():
    """The check would have caught report/html importing the pipeline's UnitDesign for type hints only."""
    known = {"vvea_design", "vvea_design.pipeline", "vvea_design.report", "vvea_design.report.html",
             "vvea_design.report.bom"}
    src = ("from typing import TYPE_CHECKING\nif TYPE_CHECKING:\n    from ..pipeline import UnitDesign\n"
           "def f():\n    from .bom import x\n    import vvea_design.pipeline\n")
    assert package_imports(src, "vvea_design.report.html", False, known) == {"vvea_design.pipeline",
                                                                              "vvea_design.report.bom"}
    graph = {"vvea_design.pipeline": {"vvea_design.report.html"},
             "vvea_design.report.html": package_imports(src, "vvea_design.report.html", False, known)}
    assert _cycle(graph) == ["vvea_design.pipeline", "vvea_design.report.html", "vvea_design.pipeline"]


def test_the_unit_report_reads_only_what_the_pipeline_result_has():
    """report.html types its input as a Protocol (no import of its caller); UnitDesign meets it member by member."""
    import typing

    from vvea_design.pipeline import UnitDesign
    from vvea_design.report import html

    from vvea_design.actuator.design_study import DesignStudy
    from vvea_design.cad.manifest import CadManifest
    from vvea_design.report.bom import BillOfMaterials
    from vvea_design.report.drawing import DrawingSet

    lazy = dict(DesignStudy=DesignStudy, BillOfMaterials=BillOfMaterials, DrawingSet=DrawingSet,
                CadManifest=CadManifest)  # TYPE_CHECKING-only
    members = {n for n, v in vars(html.UnitResult).items() if isinstance(v, property)}
    hints = typing.get_type_hints(UnitDesign, localns=lazy)
    for name in members:
        want = typing.get_type_hints(getattr(html.UnitResult, name).fget, vars(html) | vars(sys.modules[
            "vvea_design.pipeline"]) | lazy)["return"]
        have = hints[name] if name in hints else typing.get_type_hints(getattr(UnitDesign, name).fget,
                                                                        localns=lazy)["return"]
        assert want == have, f"UnitResult.{name}: {want} but UnitDesign.{name}: {have}"


# ------------------------------------------------------------------ dependencies
def _imports(paths) -> set[str]:
    out = set()
    for path in paths:
        tree = _tree(path.read_text())
        for node in ast.walk(tree):
            if isinstance(node, ast.Import):
                out |= {a.name.split(".")[0] for a in node.names}
            elif isinstance(node, ast.ImportFrom) and node.level == 0 and node.module:
                out.add(node.module.split(".")[0])
            elif (isinstance(node, ast.Call) and getattr(node.func, "attr", "") == "importorskip" and node.args
                  and isinstance(node.args[0], ast.Constant)):
                out.add(node.args[0].value.split(".")[0])
    return out


@functools.cache
def _distributions() -> dict[str, list[str]]:
    """Top-level import name -> distributions that provide it (one scan of the installed metadata: ~2 s)."""
    return metadata.packages_distributions()


def _third_party(mods: set[str]) -> dict[str, str]:
    dists = _distributions()
    local = {"vvea_design", "vvea_benches", "tests"} | {p.stem for d in ("tests", "studies") for p in (ROOT / d).rglob("*.py")}
    out = {}
    for m in sorted(mods - set(sys.stdlib_module_names) - local):
        assert m in dists, f"import {m}: no installed distribution provides it"
        out[m] = dists[m][0].lower().replace("_", "-")
    return out


def _names(reqs) -> set[str]:
    return {re.split(r"[<>=\[ ;]", r, maxsplit=1)[0].lower().replace("_", "-") for r in reqs}


#: Declared but not imported by name: used through another package.
INDIRECT = {"pyarrow": "pandas' Parquet engine (read_parquet / to_parquet)",
            "rtree": "trimesh's spatial index (proximity queries of the CAD wall-thickness check)"}


def test_every_import_is_declared_and_every_dependency_imported():
    runtime = _names(PYPROJECT["project"]["dependencies"])
    test_extra = _names(PYPROJECT["project"]["optional-dependencies"]["test"])
    lib = _third_party(_imports((ROOT / "vvea_design").rglob("*.py")))
    missing = {m: d for m, d in lib.items() if d not in runtime}
    assert not missing, f"imported by the package but not in [project] dependencies: {missing}"
    studies = _third_party(_imports((ROOT / "studies").glob("*.py")))
    missing = {m: d for m, d in studies.items() if d not in runtime | test_extra}
    assert not missing, f"imported by studies/ but not declared: {missing}"
    tests = _third_party(_imports((ROOT / "tests").rglob("*.py")))
    missing = {m: d for m, d in tests.items() if d not in runtime | test_extra}
    assert not missing, f"imported by the tests but not declared: {missing}"
    unused = runtime - set(lib.values()) - set(INDIRECT)
    assert not unused, f"declared but never imported: {sorted(unused)}"
    unused = test_extra - set(tests.values()) - set(studies.values()) - {"pytest-xdist"}  # xdist: the -n option of the test command
    assert not unused, f"test extras never imported: {sorted(unused)}"


# ------------------------------------------------------------------ docstrings
#: A parameter name that carries its unit (or is a count, a flag, a path, a name).
_UNIT_IN_NAME = re.compile(r"(_(mm\d?|N|MPa|Pa|s|ms|Hz|rad|deg|g|kg|kgm2|Nm|m|m\d|J|pct)$)|_per_|^n_|^num|_n$")
#: A unit (or "fraction" / "dimensionless") named in a description.
_UNIT_TEXT = re.compile(r"(\b(mm|mm²|mm³|N|MPa|Pa|s|ms|Hz|rad|deg|kg|g|m|N m|N/mm|SI|K)\b|°|%|fraction|"
                        r"dimensionless|unitless|\(-\)|\[-\]|count|number of|per |same unit)")


#: A parameter name that ends in a unit, and how a description names that unit.
_NAME_UNIT = re.compile(r"_(mm|mm2|mm3|N|MPa|Pa|s|ms|Hz|rad|deg|g|kg|m|Nm)$")
_NAME_UNIT_TEXT = {"mm": r"\bmm\b", "mm2": r"mm²|mm2|mm\^2", "mm3": r"mm³|mm3|mm\^3", "N": r"\bN\b", "MPa": r"MPa",
                   "Pa": r"\bPa\b", "s": r"\bs\b|second", "ms": r"\bms\b", "Hz": r"Hz", "rad": r"rad", "deg": r"deg|°",
                   "g": r"\bg\b|gram", "kg": r"\bkg\b", "m": r"\bm\b|metre", "Nm": r"N ?m\b"}
#: Unit words in a description (not the possessive 's, not part of a compound unit like N/mm).
_ANY_UNIT = re.compile(r"(?<![\w/'’])(mm³|mm²|mm|MPa|Pa|N/mm|N m|N|ms|s|Hz|rad|deg|kg|g|m)(?![\w/²³])")


def _public_functions(module):
    names = getattr(module, "__all__", None)
    for name, obj in vars(module).items():
        if name.startswith("_") or not inspect.isfunction(obj) or obj.__module__ != module.__name__:
            continue
        if names is not None and name not in names:
            continue
        yield name, obj


def _is_command(fn) -> bool:
    """A typer command documents its parameters in help= (shown by --help), not in a docstring."""
    import typer.models

    return any(isinstance(p.default, (typer.models.OptionInfo, typer.models.ArgumentInfo))
               for p in inspect.signature(fn).parameters.values())


def _needs_unit(p: inspect.Parameter, annotation: str) -> bool:
    if _UNIT_IN_NAME.search(p.name):
        return False
    return bool(re.search(r"\bfloat\b|ArrayLike|ndarray", annotation))


def docstring_problems(fn) -> list[str]:
    """What the numpydoc docstring of ``fn`` lacks: a Parameters entry per parameter, Returns, units.

    Units: a float / array parameter without a unit in its name names one in its description; a
    parameter whose name ends in a unit (``depth_mm``) is not described in another; a function that
    returns a float / array without a unit in its name names one in 'Returns'.
    """
    from numpydoc.docscrape import FunctionDoc

    problems = []
    if not inspect.getdoc(fn):
        return ["no docstring"]
    doc = FunctionDoc(fn)
    documented = {}
    for item in doc["Parameters"]:
        for n in item.name.split(","):
            documented[n.strip().lstrip("*")] = (item.type, " ".join(item.desc))
    sig = inspect.signature(fn)
    for p in sig.parameters.values():
        if p.name in ("self", "cls"):
            continue
        if p.name not in documented:
            problems.append(f"parameter {p.name!r} not in 'Parameters'")
            continue
        annotation = p.annotation if isinstance(p.annotation, str) else getattr(p.annotation, "__name__", str(p.annotation))
        typ, desc = documented[p.name]
        if _needs_unit(p, f"{annotation} {typ}") and not _UNIT_TEXT.search(f"{typ} {desc}"):
            problems.append(f"parameter {p.name!r}: no unit (or 'fraction', 'dimensionless') in its description")
        named = _NAME_UNIT.search(p.name)
        if named and _ANY_UNIT.search(desc) and not re.search(_NAME_UNIT_TEXT[named.group(1)], desc):
            problems.append(f"parameter {p.name!r}: its description names a unit but not {named.group(1)!r}, "
                            "the one in its name")
    ret = sig.return_annotation
    if ret is inspect.Signature.empty:  # no annotation: does the body return a value?
        import textwrap

        tree = ast.parse(textwrap.dedent(inspect.getsource(fn)))
        returns_nothing = not any(isinstance(n, (ast.Return, ast.Yield)) and n.value is not None
                                  for n in ast.walk(tree.body[0]))
    else:
        returns_nothing = ret is None or str(ret) in ("None", "NoReturn", "typing.NoReturn")
    if not returns_nothing and not (doc["Returns"] or doc["Yields"]):
        problems.append("no 'Returns' section")
    elif (not returns_nothing and not _UNIT_IN_NAME.search(fn.__name__)
          and re.search(r"\bfloat\b|ndarray", ret if isinstance(ret, str) else str(ret))):
        text = " ".join(" ".join([r.name, r.type, *r.desc]) for r in doc["Returns"])
        if not _UNIT_TEXT.search(text):
            problems.append("returns a number: no unit (or 'fraction', 'dimensionless') in 'Returns'")
    return problems


@pytest.mark.parametrize("module", [m for m in MODULES if _public_module(m)])
def test_public_functions_document_parameters_returns_and_units(module):
    mod = importlib.import_module(module)
    problems = {}
    for name, fn in _public_functions(mod):
        if _is_command(fn):
            continue
        p = docstring_problems(fn)
        if p:
            problems[name] = p
    assert not problems, "\n".join(f"{module}.{k}: {'; '.join(v)}" for k, v in problems.items())


def _public_methods(module):
    """The public methods of the public classes of ``module``: (``Class.method``, function) pairs.

    A public class is defined in ``module`` (not imported into it), has no leading underscore and is in
    ``__all__`` when the module has one. Its public methods are the plain, static and class methods
    defined in its own body whose name has no leading underscore; properties, dunders and inherited
    methods are left out (an inherited method is checked in the class that defines it).
    """
    names = getattr(module, "__all__", None)
    for cname, cls in vars(module).items():
        if cname.startswith("_") or not inspect.isclass(cls) or cls.__module__ != module.__name__:
            continue
        if names is not None and cname not in names:
            continue
        for mname, attr in vars(cls).items():
            if mname.startswith("_"):
                continue
            if isinstance(attr, (staticmethod, classmethod)):
                fn = attr.__func__
            elif inspect.isfunction(attr):
                fn = attr
            else:  # properties (functools.cached_property too), class attributes, nested classes
                continue
            yield f"{cname}.{mname}", fn


def _method_problems(module: str) -> dict[str, list[str]]:
    mod = importlib.import_module(module)
    problems = {}
    for name, fn in _public_methods(mod):
        p = docstring_problems(fn)
        if p:
            problems[name] = p
    return problems


@pytest.mark.parametrize("module", [m for m in MODULES if _public_module(m)])
def test_public_methods_document_parameters_returns_and_units(module):
    problems = _method_problems(module)
    assert not problems, "\n".join(f"{module}.{k}: {'; '.join(v)}" for k, v in problems.items())


def test_the_method_check_finds_an_undocumented_method():
    class Thing:
        def grow(self, by_mm: float, factor: float) -> float:
            """Grow the thing.

            Parameters
            ----------
            by_mm : float
                Growth.
            """
            return by_mm * factor

        @classmethod
        def make(cls, size_mm: float) -> "Thing":
            """A thing of ``size_mm``.

            Parameters
            ----------
            size_mm : float
                Size.

            Returns
            -------
            Thing
                A new thing.
            """
            return cls()

        @staticmethod
        def scale(x):
            return 2 * x

        @property
        def size_mm(self) -> float:
            return 1.0

        def _private(self, x):
            return x

    class Sub(Thing):
        pass

    module = type(sys)("fake_module")
    module.Thing, module.Sub, module.__all__ = Thing, Sub, ["Thing", "Sub"]
    Thing.__module__ = Sub.__module__ = "fake_module"
    found = dict(_public_methods(module))
    assert set(found) == {"Thing.grow", "Thing.make", "Thing.scale"}  # no property, private or inherited method
    assert docstring_problems(found["Thing.make"]) == []  # cls is not a parameter to document
    grow = docstring_problems(found["Thing.grow"])
    assert any("'factor' not in" in s for s in grow) and "no 'Returns' section" in grow
    assert "'by_mm'" not in " ".join(grow)  # self is skipped, by_mm is documented
    assert docstring_problems(found["Thing.scale"]) == ["no docstring"]
    module.__all__ = ["Sub"]
    assert dict(_public_methods(module)) == {}  # Thing is not public; Sub defines nothing itself


def test_the_docstring_check_finds_what_is_missing():
    def bad(x: float, depth_mm: float) -> float:
        """Does something.

        Parameters
        ----------
        x : float
            A length.
        """
        return x

    def good(x: float, depth_mm: float) -> float:
        """Does something.

        Parameters
        ----------
        x : float
            A length in mm.
        depth_mm : float
            Depth.

        Returns
        -------
        float
            The sum (mm).
        """
        return x + depth_mm

    def no_return_unit(depth_mm: float) -> float:
        """Does something.

        Parameters
        ----------
        depth_mm : float
            Depth.

        Returns
        -------
        float
            Twice the depth.
        """
        return 2 * depth_mm

    def wrong_unit(depth_mm: float) -> None:
        """Does something.

        Parameters
        ----------
        depth_mm : float
            Depth below the surface, in m.
        """

    assert docstring_problems(good) == []
    assert docstring_problems(wrong_unit) == [
        "parameter 'depth_mm': its description names a unit but not 'mm', the one in its name"]
    assert docstring_problems(no_return_unit) == [
        "returns a number: no unit (or 'fraction', 'dimensionless') in 'Returns'"]
    p = docstring_problems(bad)
    assert any("'x': no unit" in s for s in p) and any("'depth_mm' not in" in s for s in p)
    assert "no 'Returns' section" in p


# ------------------------------------------------------------------ private names stay in their room
def private_imports(source: str, module: str, is_package: bool) -> list[str]:
    """The imports in ``source`` that reach into another room for a private module or name.

    A private module or name starts with one underscore (dunders such as ``__version__`` are public); a room
    is a subpackage or a top-level module of the package (:func:`_room`). Imports inside a room may use its
    private parts; another room goes through its public API. Top-level, lazy and TYPE_CHECKING imports count.

    Parameters
    ----------
    source : str
        Python source of the module.
    module : str
        Its dotted name (``vvea_design.report.drawing``), to resolve relative imports.
    is_package : bool
        True for an ``__init__.py`` (its relative imports start from itself).

    Returns
    -------
    list of str
        ``"line N: from a.b import c"`` for every offending import, in source order.
    """
    def private(name: str) -> bool:
        return name.startswith("_") and not (name.startswith("__") and name.endswith("__"))

    base = module.split(".") if is_package else module.split(".")[:-1]
    out = []
    for node in ast.walk(_tree(source)):
        if isinstance(node, ast.ImportFrom):
            if node.level:
                target = base[:len(base) - node.level + 1] + (node.module.split(".") if node.module else [])
            else:
                target = (node.module or "").split(".")
            imported = [a.name for a in node.names]
            text = f"from {'.' * node.level}{node.module or ''} import {', '.join(imported)}"
        elif isinstance(node, ast.Import):
            for alias in node.names:
                if alias.name.split(".")[0] == "vvea_design" and _room(alias.name) != _room(module) \
                        and any(private(p) for p in alias.name.split(".")[1:]):
                    out.append((node.lineno, f"line {node.lineno}: import {alias.name}"))
            continue
        else:
            continue
        if target[0] != "vvea_design" or _room(".".join(target)) == _room(module):
            continue
        if any(private(p) for p in target[1:]) or any(private(n) for n in imported):
            out.append((node.lineno, f"line {node.lineno}: {text}"))
    return [text for _, text in sorted(out)]


def test_no_module_imports_a_private_module_or_name_of_another_room():
    """report/ draws the CAD through the cad room's public API (issue 22): no ``from ..cad._shapes import ring``."""
    files = _module_files()
    bad = {m: found for m, p in files.items()
           if (found := private_imports(p.read_text(), m, p.name == "__init__.py"))}
    assert not bad, "private imports across rooms: " + "; ".join(f"{m}: {', '.join(v)}" for m, v in sorted(bad.items()))


def test_the_private_import_check_finds_each_form():
    src = ("from ..cad._shapes import ring\n"  # private module of another room
           "from ..cad.registry import _fixed, get_part\n"  # private name of another room
           "from ._layout import x\n"  # private module of its own room: allowed
           "from .. import __version__\n"  # a dunder is public
           "def f():\n    import vvea_design.cad._shapes\n")  # lazy, absolute
    found = private_imports(src, "vvea_design.report.drawing", False)
    assert found == ["line 1: from ..cad._shapes import ring", "line 2: from ..cad.registry import _fixed, get_part",
                     "line 6: import vvea_design.cad._shapes"]
    assert private_imports("from ._shapes import ring\n", "vvea_design.cad.render", False) == []
