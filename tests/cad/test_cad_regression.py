"""Regression cases as data (like cq_gears): design in, volume and bounding box of
every part out. A geometry change shows up as a number that moved.

Regenerate after an *intended* change (and say why in the commit)::

    python tests/cad/test_cad_regression.py
"""

from __future__ import annotations

import json
import sys
from dataclasses import asdict
from pathlib import Path

import pytest


from vvea_design.cad import CadParameters, build_cad  # noqa: E402
from vvea_design.spring.design import Design, FixedParameters  # noqa: E402

DATA = Path(__file__).parent / "data" / "cad_regression.json"
REL = 1e-6  # volumes (OCCT mass properties are deterministic to ~1e-12)
ABS_BBOX = 1e-3  # mm


def _design(args: dict) -> Design:
    args = dict(args)
    fx = dict(args.pop("fixed", {}))
    fx.setdefault("sizing_rules", "gas_only")  # cases stored before the buildability rules were sized by the gas-only
    fixed = FixedParameters(**fx)
    return Design(**args, fixed=fixed)


def _measure(design: Design, cad: dict) -> dict:
    model = build_cad(design, CadParameters(**cad))
    solids = {**model.export_solids(), **model.gas}
    out = {}
    for name, s in sorted(solids.items()):
        bb = s.bounding_box()
        out[name] = {"volume_mm3": s.volume,
                     "bbox_mm": [[bb.min.X, bb.min.Y, bb.min.Z], [bb.max.X, bb.max.Y, bb.max.Z]]}
    return out


def _cases() -> list[dict]:
    return json.loads(DATA.read_text())["cases"] if DATA.exists() else []


@pytest.mark.parametrize("case", _cases(), ids=lambda c: c["name"])
def test_regression_case(case):
    got = _measure(_design(case["design"]), case["cad"])
    assert set(got) == set(case["expected"])
    for name, exp in case["expected"].items():
        assert got[name]["volume_mm3"] == pytest.approx(exp["volume_mm3"], rel=REL), name
        for a, b in zip(sum(got[name]["bbox_mm"], []), sum(exp["bbox_mm"], [])):
            assert a == pytest.approx(b, abs=ABS_BBOX), name


def _regenerate() -> None:  # pragma: no cover - maintenance
    from tests.cad.cases import DESIGNS, SLOW

    cases = []
    for name, d in {**DESIGNS, **{k: SLOW[k] for k in ("pareto_D55", "pareto_k50")}}.items():
        dd = asdict(d)
        defaults = asdict(FixedParameters())
        dd["fixed"] = {k: v for k, v in dd["fixed"].items() if defaults[k] != v}
        for cad_name, cad in (("default", {}), ("shrink2pct", {"mould_shrinkage": 0.02})):
            if cad_name != "default" and name != "reference":
                continue
            exp = _measure(d, cad)
            for v in exp.values():
                v["volume_mm3"] = round(v["volume_mm3"], 4)
                v["bbox_mm"] = [[round(c, 4) for c in row] for row in v["bbox_mm"]]
            cases.append({"name": f"{name}-{cad_name}", "design": dd, "cad": cad, "expected": exp})
    DATA.parent.mkdir(exist_ok=True)
    DATA.write_text(json.dumps({"about": "vvea_design.cad regression cases: design + CAD parameters in, "
                                         "volume (mm³) and bbox (mm) of every solid out; regenerate with "
                                         "`python tests/cad/test_cad_regression.py`", "cases": cases}, indent=1) + "\n")
    print(f"wrote {DATA} ({len(cases)} cases)")


if __name__ == "__main__":
    _regenerate()
