"""The report's "What is verified" section: every check with its load case, method, result and what it leaves
out, built from the unit's own results; checks that did not run say so."""

from types import SimpleNamespace

import pytest

from vvea_design.bladder.check import check_bladder
from vvea_design.report.html.verification import (BLADDER_LEAVES_OUT, VERIFICATION_KEYS, verification_rows,
                                                  verification_section)
from vvea_design.spring.design import Design, FixedParameters
from vvea_design.spring.problem import evaluate_design
from vvea_design.spring.requirements import Requirements


@pytest.fixture(scope="module")
def unit():
    """A unit without CAD, FE or actuator study (the paper-like geometry under the gas-only rules)."""
    fixed = FixedParameters(sizing_rules="gas_only")
    design = Design(35.18, 59.5, 47107.0, 99735.0, fixed=fixed)
    req = Requirements(fixed=fixed)
    ev = evaluate_design(design, req)
    return SimpleNamespace(optimisation=SimpleNamespace(evaluation=ev), requirements=req,
                           bladder=check_bladder(design, n_elements=48), structure=None, cad_manifest=None,
                           bom=None, actuator_study=None)


def test_every_check_has_its_five_columns_and_a_verdict(unit):
    rows = verification_rows(unit)
    assert len(VERIFICATION_KEYS) == 5 and all(len(r) == 5 and all(isinstance(c, str) and c for c in r)
                                                for r in rows)
    checks = {r[0]: r for r in rows}
    # what did not run says so instead of passing
    assert checks["every pressure-bearing piece, FE"][3] == "not run (no CAD)"
    assert checks["seals and assembly"][3] == "not run (no CAD)"
    assert checks["actuator study"][3] == "not run"
    # the bladder: both stroke ends' wrinkled area, and what the membrane check leaves out
    bl = checks["bladder"]
    assert bl[3].startswith(("PASS", "FAIL")) and "compressed: wrinkled" in bl[3] and "expanded: wrinkled" in bl[3]
    assert all(item in bl[4] for item in BLADDER_LEAVES_OUT) and "permeation" in bl[4] and "swelling" in bl[4]
    # the closed form: its load cases, methods and standards, and that the FE row covers the concentrations
    closed = next(r for r in rows if "closed form" in r[0])
    assert "Tresca" in closed[2] or "Lamé" in closed[2]
    assert "concentrations" in closed[4] or "fluid loads" in closed[4]
    # a joint names its standard and its load; a threaded one its ISO standards
    threads = [r for r in rows if r[0].startswith("joint") and "ISO 261" in r[2]]
    assert threads and all("end load" in r[1] for r in threads)


def test_the_verdicts_follow_the_results(unit):
    failing = SimpleNamespace(**{**vars(unit), "bladder": SimpleNamespace(
        **{k: getattr(unit.bladder, k) for k in ("ends", "criterion", "silicone", "strain_bound",
                                                 "allowable_strain")}, passes=False)})
    bl = {r[0]: r for r in verification_rows(failing)}["bladder"]
    assert bl[3].startswith("FAIL")


def test_the_section_is_a_table_with_the_columns(unit):
    sec = verification_section(unit)
    assert sec.title == "What is verified" and sec.id == "verified"
    assert all(h in sec.body for h in ("load case", "method / standard", "not covered"))
