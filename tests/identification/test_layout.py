"""The identification wing's shape: modules and functions within the size limits, and the bench simulators apart from
the library (``benches/``, distribution ``vvea-benches``: never imported by ``vvea_design``, not in its wheel)."""

from __future__ import annotations

import ast
import fnmatch
import tomllib

import pytest
from tests.helpers import REPO

IDENTIFICATION = REPO / "vvea_design" / "identification"
BENCHES = REPO / "benches"
MAX_MODULE_LINES = 800
MAX_FUNCTION_LINES = 120


def _modules(root):
    return sorted(p for p in root.rglob("*.py") if "__pycache__" not in p.parts)


@pytest.mark.parametrize("path", _modules(IDENTIFICATION) + _modules(BENCHES / "vvea_benches"),
                         ids=lambda p: str(p.relative_to(REPO)))
def test_modules_and_functions_are_within_the_limits(path):
    text = path.read_text()
    assert text.count("\n") <= MAX_MODULE_LINES, f"{path.name}: {text.count(chr(10))} lines > {MAX_MODULE_LINES}"
    long = [f"{n.name} ({n.end_lineno - n.lineno + 1} lines)" for n in ast.walk(ast.parse(text))
            if isinstance(n, (ast.FunctionDef, ast.AsyncFunctionDef)) and n.end_lineno - n.lineno + 1 > MAX_FUNCTION_LINES]
    assert not long, f"{path.name}: functions over {MAX_FUNCTION_LINES} lines: {long}"


def _imported_names(path) -> set[str]:
    out = set()
    for node in ast.walk(ast.parse(path.read_text())):
        if isinstance(node, ast.Import):
            out |= {a.name for a in node.names}
        elif isinstance(node, ast.ImportFrom) and node.level == 0 and node.module:
            out.add(node.module)
    return out


def test_the_library_never_imports_the_benches():
    """No module of vvea_design imports vvea_benches (at top level, in a function or for type hints)."""
    offenders = [str(p.relative_to(REPO)) for p in _modules(REPO / "vvea_design")
                 if any(m.split(".")[0] == "vvea_benches" for m in _imported_names(p))]
    assert not offenders, f"vvea_design imports the bench simulators: {offenders}"


def test_the_wheel_does_not_ship_the_benches():
    """The library's package find takes vvea_design only; the benches are their own distribution."""
    find = tomllib.loads((REPO / "pyproject.toml").read_text())["tool"]["setuptools"]["packages"]["find"]
    include, exclude = find.get("include", ["*"]), find.get("exclude", [])
    for name in ("vvea_benches", "vvea_benches.physbench", "vvea_benches.testbench", "benches"):
        taken = any(fnmatch.fnmatchcase(name, pat) for pat in include) and not any(fnmatch.fnmatchcase(name, pat) for pat in exclude)
        assert not taken, f"pyproject.toml's package find would ship {name}"
    benches = tomllib.loads((BENCHES / "pyproject.toml").read_text())
    assert benches["project"]["name"] == "vvea-benches"
    assert benches["tool"]["setuptools"]["packages"]["find"]["include"] == ["vvea_benches*"]
    assert (BENCHES / "vvea_benches" / "__init__.py").exists()
    assert not (REPO / "vvea_design" / "identification" / "physbench.py").exists()
    assert not (REPO / "vvea_design" / "identification" / "testbench.py").exists()


def test_the_test_install_installs_the_benches_and_the_plain_install_does_not_need_them():
    lines = (REPO / "scripts" / "install.sh").read_text().splitlines()
    i = next(k for k, line in enumerate(lines) if "-e benches" in line)
    assert 'if [ "${1:-}" = "test" ]' in lines[i - 1] and lines[i + 1].strip() == "fi"
