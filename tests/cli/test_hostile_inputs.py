"""The hostile-input campaign's judge (studies/hostile_inputs.py): its cases and its classification rules."""

import importlib.util
import os
import shutil
import sys
from pathlib import Path

from tests.helpers import REPO

_spec = importlib.util.spec_from_file_location("hostile_inputs", REPO / "studies" / "hostile_inputs.py")
hi = importlib.util.module_from_spec(_spec)
sys.modules["hostile_inputs"] = hi  # dataclasses look their module up
_spec.loader.exec_module(hi)


def _result(case, code=2, out="", err="", **kw):
    defaults = dict(timed_out=False, wall=1.0, cpu=1.0, maxrss_mb=100.0, w=Path("/nonexistent"), changed=[], orphans=[],
                    events=[])
    defaults.update(kw)
    return hi.Result(case, code, out=out, err=err, **defaults)


def _case(**kw):
    base = dict(id="t-01", family="t", title="t", argv=[], expect="refused", codes=(2,), mention=(r"max_charge_MPa",))
    base.update(kw)
    return hi.Case(**base)


def test_cases_are_unique_complete_and_cover_every_family():
    cases = hi.all_cases()
    assert len(cases) >= 182
    assert len({c.id for c in cases}) == len(cases)
    assert {c.family for c in cases} == {"req", "design", "rec", "cli", "out", "interrupt", "disk", "size"}
    for c in cases:
        assert c.expect and c.codes and c.argv, c.id
        assert c.id.startswith({"interrupt": "int"}.get(c.family, c.family) + "-"), c.id
    issue_items = {c.issue for c in cases}
    assert {"1", "2", "3", "4", "5", "6", "7", "8", "tb", "weak"} <= issue_items


def test_classification_rules():
    c = _case()
    assert hi.classify(_result(c, 2, err="error: req.toml: max_charge_MPa must be > 0"))[0] == "GOOD"
    assert hi.classify(_result(c, 2, err="error: req.toml: something is wrong"))[0] == "WEAK"  # field not named
    assert hi.classify(_result(c, 0, out="wrote d.json"))[0] == "BAD"  # accepted silently
    assert hi.classify(_result(c, 3, err="error: max_charge_MPa"))[0] == "BAD"  # wrong exit code class
    tb = "Traceback (most recent call last):\n  File \"x.py\", line 1, in <module>\nValueError: boom"
    assert hi.classify(_result(c, 1, err=tb)) == ("BAD", "traceback: ValueError: boom")
    assert hi.classify(_result(c, 2, err="error: max_charge_MPa", cpu=99.0))[0] == "WEAK"  # slow rejection
    assert hi.classify(_result(c, 2, err="error: max_charge_MPa", changed=["req.toml changed"]))[0] == "BAD"
    assert hi.classify(_result(c, 2, err="error: max_charge_MPa", orphans=[123]))[0] == "BAD"
    assert hi.classify(_result(c, None, timed_out=True))[0] == "BAD"
    assert hi.classify(_result(c, 2, err="MemoryError"))[0] == "BAD"
    assert hi.classify(_result(c, -11))[0] == "BAD"  # a crash
    intr = _case(codes=(130,), mention=(r"interrupt",))
    assert hi.classify(_result(intr, -2, err=""))[0] == "WEAK"  # died of SIGINT: 130, but no message
    assert hi.classify(_result(intr, 130, err="interrupted"))[0] == "GOOD"
    planned = _case(codes=(130,), mention=(), actions=((hi.after_cpu(1.0), ("killpg", 2)),))
    assert hi.classify(_result(planned, 0, extra={"fired": 0}))[0] == "ERROR"  # the interrupt never came


def test_bounds_judge_and_linearity_judge(tmp_path):
    import json

    from vvea_design.spring.design import Design
    from vvea_design.spring.design_file import save_design
    from vvea_design.spring.problem import evaluate_design
    from vvea_design.spring.requirements import Requirements

    # an explicit design with its outer diameter at the 59.5 mm envelope (the default optimum, cad/design.json, is
    # an inner_tube unit at 59.06 mm: on no bound, it would not exercise the bound judge)
    (tmp_path / "out").mkdir()
    req = Requirements()
    save_design(tmp_path / "out" / "d.json", evaluate_design(Design(34.5, 59.5, 41500.0, 90000.0), req), req)
    d = json.loads((tmp_path / "out" / "d.json").read_text())
    assert d["parameters"]["outer_diameter_mm"] == d["spec"]["max_outer_diameter_mm"] == 59.5
    lin = d["performance"]["linearity_error"]
    c = _case(codes=(0,), mention=())
    # reported as the binding envelope constraint
    r = _result(c, 0, w=tmp_path, err="binding: outer_diameter, housing_length")
    assert hi.judge_bounds_not_silent()(r) is None
    assert hi.judge_linearity_at_most(lin)(r) is None  # at the limit: passes
    bad = hi.judge_linearity_at_most(0.99 * lin)(r)  # just above it: BAD, with both numbers
    assert bad[0] == "BAD" and f"linearity {100 * lin:.3f} %" in bad[1] and f"{99 * lin:.3f} % is reachable" in bad[1]
    # a 70 mm envelope with the diameter stuck at the 59.5 mm search bound and nothing saying so
    d["spec"]["max_outer_diameter_mm"] = 70.0
    (tmp_path / "out" / "d.json").write_text(json.dumps(d))
    assert hi.judge_bounds_not_silent()(_result(c, 0, w=tmp_path, err="binding: housing_length"))[0] == "BAD"
    reported = _result(c, 0, w=tmp_path, err="binding: housing_length, outer_diameter_mm (search bound)")
    assert hi.judge_bounds_not_silent()(reported) is None


def test_one_case_end_to_end(tmp_path):
    """A real rejection runs under the limits and is judged GOOD; its input is watched for changes."""
    ctx = hi.Ctx(REPO, [str(Path(sys.executable).with_name("vvea"))],
                 {**os.environ, "PYTHONPATH": str(REPO), "COLUMNS": "250"}, tmp_path, tmp_path / "_base", REPO)
    ctx.base.mkdir()
    shutil.copy(REPO / "cad" / "design.json", ctx.base / "design.json")
    shutil.copy(REPO / "cad" / "design.json", ctx.base / "rec18.csv")  # only copied by the prepare step, never read
    case = next(c for c in hi.cli_cases() if c.title == "check --max-linearity nan")
    r = hi.run_case(case, ctx)
    assert (r.code, r.changed, r.orphans, r.timed_out) == (2, [], [], False)
    assert hi.classify(r) == ("GOOD", "as expected (exit 2)")
