"""Fuzz over requirements files (issue 11): no input produces a traceback, only clean errors.

Random keys (known, misspelt, unknown), values of every TOML type (NaN, inf,
huge, negative, strings, arrays, tables), ``[bounds]`` and ``[fixed]``
tables, several text encodings and plain garbage bytes. The loader either
returns valid requirements or raises :class:`SpecError` naming the file; the
command line (``vvea optimise --spec F`` on a tiny search budget) exits 0, 2
(bad input) or 3 (no design meets them) and never shows a traceback.
Hypothesis is derandomised (the same examples every run) with bounded counts.
"""

from __future__ import annotations

import functools
import math
from pathlib import Path

import numpy as np
import pytest
import tomli_w
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from typer.testing import CliRunner

from vvea_design.spring.design import FixedParameters
from vvea_design.spring.layouts import DECISION_VARIABLES
from vvea_design.spring.requirements import Requirements, SpecError, load_requirements

KNOWN = [f for f in Requirements.__dataclass_fields__ if f not in ("bounds", "fixed")]
FIXED = list(FixedParameters.__dataclass_fields__)

numbers = st.one_of(
    st.floats(allow_nan=True, allow_infinity=True),
    st.floats(min_value=-1e3, max_value=1e6),  # plausible magnitudes dominate
    st.integers(min_value=-(2**63), max_value=2**63 - 1),
    st.integers(min_value=-5, max_value=500),
)
scalars = st.one_of(numbers, st.booleans(), st.text(max_size=12),
                    st.sampled_from(["dragon-skin-20", "al-7075-t6", "steel-42crmo4", "wood", ""]))
values = st.one_of(scalars, st.lists(scalars, max_size=3), st.dictionaries(st.text(max_size=5), scalars, max_size=2))
names = lambda known: st.one_of(st.sampled_from(known), st.text(min_size=1, max_size=10))  # noqa: E731
pairs = st.one_of(st.lists(numbers, min_size=2, max_size=2), values)

requirements_tables = st.fixed_dictionaries(
    {},
    optional={
        **{k: values for k in ("bounds", "fixed")},
        "_top": st.dictionaries(names(KNOWN), st.one_of(numbers, values), max_size=6),
        "_bounds": st.dictionaries(names(list(DECISION_VARIABLES)), pairs, max_size=4),
        "_fixed": st.dictionaries(names(FIXED), st.one_of(numbers, scalars), max_size=4),
    },
)


def _to_toml(d: dict) -> str:
    doc = dict(d.get("_top", {}))
    if "_bounds" in d:
        doc["bounds"] = d["_bounds"]
    elif "bounds" in d:
        doc["bounds"] = d["bounds"]
    if "_fixed" in d:
        doc["fixed"] = d["_fixed"]
    elif "fixed" in d:
        doc["fixed"] = d["fixed"]
    return tomli_w.dumps(doc)


_DEFAULTS = {k: v for k, v in Requirements().to_dict().items() if isinstance(v, float)}
#: Near-valid files (known keys, values around the defaults, sometimes across a limit) reach the optimiser.
plausible = st.fixed_dictionaries(
    {},
    optional={
        "_top": st.dictionaries(st.sampled_from(sorted(_DEFAULTS)), st.floats(0.3, 3.0), max_size=4).map(
            lambda d: {k: _DEFAULTS[k] * f if _DEFAULTS[k] else f - 1.0 for k, f in d.items()}),
        "_bounds": st.dictionaries(st.sampled_from(DECISION_VARIABLES),
                                   st.tuples(st.floats(1.0, 1e5), st.floats(1.0, 3e5)).map(sorted), max_size=2),
    },
).map(_to_toml)

encodings = st.sampled_from(["utf-8", "utf-8-sig", "latin-1", "utf-16", "cp1252"])
files = st.one_of(
    plausible.map(str.encode),
    st.tuples(requirements_tables.map(_to_toml), encodings).map(lambda te: te[0].encode(te[1], errors="replace")),
    st.tuples(requirements_tables.map(_to_toml), st.binary(max_size=8)).map(lambda tb: tb[0].encode() + tb[1]),
    st.binary(max_size=64),
    st.text(max_size=80).map(lambda t: t.encode("utf-8", errors="replace")),
)

FUZZ = settings(derandomize=True, database=None, deadline=None,
                suppress_health_check=[HealthCheck.function_scoped_fixture, HealthCheck.too_slow])


def _check_loaded(req: Requirements) -> None:
    """Valid requirements give finite search bounds, and a design in them is either drawn and evaluated
    or refused with a DesignError (what the optimiser scores as unbuildable): nothing else is raised."""
    from vvea_design.spring.design import DesignError
    from vvea_design.spring.problem import design_from_vector, evaluate_design

    for layout in req.layouts:
        bounds = req.search_bounds(layout)
        assert all(math.isfinite(lo) and math.isfinite(hi) and 0 <= lo < hi for lo, hi in bounds)
        for t in (0.0, 0.5, 1.0):
            try:
                design = design_from_vector([lo + t * (hi - lo) for lo, hi in bounds], req, layout)
            except DesignError:
                continue
            if req.max_bladder_strain is None:
                ev = evaluate_design(design, req)
                assert np.isfinite(ev.linearity_error) or np.isnan(ev.linearity_error)


@settings(FUZZ, max_examples=250)
@given(content=files)
def test_loader_gives_requirements_or_a_clean_error(tmp_path_factory, content):
    path = tmp_path_factory.mktemp("fuzz") / "spec.toml"
    path.write_bytes(content)
    try:
        req = load_requirements(path)
    except SpecError as exc:
        msg = str(exc)
        assert str(path) in msg
        assert "np.float64" not in msg and "Traceback" not in msg
        return
    _check_loaded(req)


@pytest.fixture(scope="module")
def tiny_budget():
    """`vvea optimise` on a few dozen evaluations, the FE strain bound replaced by a cheap stand-in."""
    import vvea_design.bladder.check as check
    import vvea_design.spring.optimise as opt

    mp = pytest.MonkeyPatch()
    mp.setattr(opt, "optimise", functools.partial(opt.optimise, popsize=2, maxiter=2, polish=False, progress=False))
    mp.setattr(check, "strain_bound", lambda design, material=None: 0.1)
    yield
    mp.undo()


@settings(FUZZ, max_examples=60)
@given(content=st.one_of(files, plausible.map(str.encode)))
def test_optimise_command_never_shows_a_traceback(tmp_path_factory, tiny_budget, content):
    from vvea_design.cli.main import app

    folder = tmp_path_factory.mktemp("fuzzcli")
    spec = folder / "spec.toml"
    spec.write_bytes(content)
    res = CliRunner().invoke(app, ["optimise", "--spec", str(spec), "--out", str(folder / "d.json")])
    assert res.exit_code in (0, 2, 3), (content, res.output, res.exception)
    assert res.exception is None or isinstance(res.exception, SystemExit), (content, res.output, repr(res.exception))
    assert "Traceback" not in res.output
    if res.exit_code == 2:
        assert "error:" in res.output
    if res.exit_code != 0:
        assert not (folder / "d.json").exists()


def test_bounds_without_a_buildable_design_exit_3_naming_why(tmp_path, tiny_budget):
    """Issue 11 item 8: used to be a RuntimeError traceback (exit 1). (Drawable but infeasible requirements:
    test_cli.test_infeasible_spec_exits_3_and_names_the_constraint.)"""
    from vvea_design.cli.main import app

    spec = tmp_path / "spec.toml"
    spec.write_text("[bounds]\npiston_diameter_mm = [48, 50]\nouter_diameter_mm = [25, 40]\n")  # nothing fits
    res = CliRunner().invoke(app, ["optimise", "--spec", str(spec), "--out", str(tmp_path / "d.json")])
    assert res.exit_code == 3, res.output
    assert "Traceback" not in res.output
    assert "found no buildable design inside the search bounds" in res.output
    assert "piston_diameter_mm in [48, 50]" in res.output and "no room for the bladder" in res.output
    assert not (tmp_path / "d.json").exists()


def test_bom_is_read(tmp_path):
    """A UTF-8 file with a byte-order mark (as some Windows editors save) reads like one without."""
    p = tmp_path / "bom.toml"
    p.write_bytes("max_outer_diameter_mm = 55.0\n".encode("utf-8-sig"))
    assert load_requirements(p).max_outer_diameter_mm == 55.0


# ---------------------------------------------------------------------------
# design files: random edits of a valid design JSON
# ---------------------------------------------------------------------------

@functools.lru_cache(maxsize=1)
def _valid_design_json() -> str:
    import json

    from vvea_design.spring.design import Design
    from vvea_design.spring.design_file import design_to_dict
    from vvea_design.spring.problem import evaluate_design

    req = Requirements()
    return json.dumps(design_to_dict(evaluate_design(Design(34.5, 59.5, 41500.0, 90000.0), req), req))


def _valid_design() -> dict:
    """A fresh copy of one valid design's JSON content (evaluated once per session, edited per example)."""
    import json

    return json.loads(_valid_design_json())


_SECTIONS = ("parameters", "fixed", "spec", None)
edits = st.lists(
    st.tuples(
        st.sampled_from(_SECTIONS),  # where: a section, or the top level
        st.one_of(st.sampled_from(sorted(_valid_design()["parameters"]) + FIXED + KNOWN + ["format", "fixed",
                                                                                          "parameters", "version"]),
                  st.text(max_size=6)),
        st.one_of(st.just("<delete>"), values, st.none()),
    ),
    min_size=1, max_size=4,
)


@settings(FUZZ, max_examples=200)
@given(changes=edits)
def test_design_loader_gives_a_design_or_a_clean_error(tmp_path_factory, changes):
    import json

    from vvea_design.spring.design_file import DesignFileError, load_design, load_requirements_from_design

    data = _valid_design()
    for section, key, value in changes:
        target = data if section is None else data.get(section)
        if not isinstance(target, dict):
            continue
        if value == "<delete>":
            target.pop(key, None)
        else:
            target[key] = value
    path = tmp_path_factory.mktemp("fuzzdesign") / "design.json"
    path.write_text(json.dumps(data))
    for load in (load_design, load_requirements_from_design):
        try:
            load(path)
        except DesignFileError as exc:
            assert str(path) in str(exc) and "np.float64" not in str(exc)
