"""The studies return typed records whose ``to_dict()`` is the row or object they wrote before; the wing keeps
its size limits."""

import ast
import csv

import numpy as np
import pytest

from tests.spring.rules import GAS_ONLY, gas_only_defaults

from tests.helpers import REPO
from vvea_design.spring.design import Design
from vvea_design.spring.requirements import Requirements
from vvea_design.spring.studies import (GasCapacity, GasVolumeBound, LinearityMap, ParetoPoint, gas_capacity,
                                        gas_volume_bound, linearity_map, save_pareto)

BULK = Design(35.4, 59.5, 48800.0, 102000.0, layout="bulkhead", V2_top_mm3=3800.0, fixed=GAS_ONLY)


@pytest.fixture(scope="module", autouse=True)
def _gas_only_rules():
    """These tests are the gas-only rules' (tests/spring/rules.py): every FixedParameters() here defaults to them."""
    with gas_only_defaults():
        yield


def test_a_pareto_point_is_the_csv_row():
    variables = {"piston_diameter_mm": 35.4, "outer_diameter_mm": 59.5, "V1_mm3": 48800.0, "V2_mm3": 102000.0,
                 "V2_top_mm3": 3800.0, "V1_annulus_mm3": 0.0}
    p = ParetoPoint("min_mean_stiffness_N_per_mm", 80.0, True, 0.012, 0.012, 0.02, 0.012, 480.0, "bulkhead", 93.2,
                    "mean_stiffness,housing_length", variables)
    assert list(p.to_dict()) == ["feasible", "linearity_error", "linearity_error_isothermal",
                                 "linearity_error_adiabatic", "objective", "mass_g", "layout",
                                 "mean_stiffness_at_max_charge_N_per_mm", "outer_diameter_mm", "binding",
                                 "piston_diameter_mm", "V1_mm3", "V2_mm3", "V2_top_mm3", "V1_annulus_mm3",
                                 "min_mean_stiffness_N_per_mm"]
    assert p.to_dict()["outer_diameter_mm"] == 59.5 and p.to_dict()["min_mean_stiffness_N_per_mm"] == 80.0
    bad = ParetoPoint("max_mass_g", 300.0, False, error="no buildable design")
    assert bad.to_dict() == {"feasible": False, "error": "no buildable design", "max_mass_g": 300.0}
    # the deprecated mapping view (the command line's and the plots' readers) is the dict's
    assert p["layout"] == "bulkhead" and bad.get("linearity_error", "none") == "none" and bad.binding == ""


def test_save_pareto_writes_the_same_csv_from_points_and_from_rows(tmp_path):
    pytest.importorskip("matplotlib")
    pts = [ParetoPoint("max_mass_g", v, True, 0.01 * v / 300, 0.01, 0.02, 0.01, v, "bulkhead", 93.2, "mass",
                       {"piston_diameter_mm": 35.0, "outer_diameter_mm": 59.5}) for v in (300.0, 400.0)]
    pts.append(ParetoPoint("max_mass_g", 200.0, False, error="too light"))
    a, _ = save_pareto(pts, "mass", tmp_path / "a")
    b, _ = save_pareto([p.to_dict() for p in pts], "mass", tmp_path / "b")
    assert a.read_bytes() == b.read_bytes()
    rows = list(csv.DictReader(a.open()))
    assert rows[2]["error"] == "too light" and rows[0]["max_mass_g"] == "300.0"


def test_linearity_map_bound_and_capacity_are_typed():
    m = linearity_map(BULK, Requirements(), "V1_mm3", "V2_mm3", n=5)
    assert isinstance(m, LinearityMap) and m.linearity.shape == (5, 5) and m.x.shape == (5,)
    assert set(m.to_dict()) == {"var_x", "var_y", "x", "y", "linearity", "feasible", "worst", "margins"}
    assert m["feasible"] is m.feasible  # the deprecated mapping view
    b = gas_volume_bound(180e3, maxiter=5)
    assert isinstance(b, GasVolumeBound) and b.total_gas_mm3 == 180e3
    assert list(b.to_dict()) == ["total_gas_mm3", "linearity_error", "A1_mm2", "A2_mm2", "V1_mm3", "V2_mm3",
                                 "feasible", "objective_exponents", "V1_max_mm3", "V2_max_mm3",
                                 "chamber1_length_max_mm"]
    c = gas_capacity(layout="bulkhead", maxiter=3)
    assert isinstance(c, GasCapacity) and c.layout == "bulkhead" and c.total_gas_mm3 == c.V1_mm3 + c.V2_mm3
    assert list(c.to_dict()) == ["layout", "maximise", "total_gas_mm3", "V1_mm3", "V2_mm3", "bladder_cast_fill",
                                 "bladder_strain_surrogate", "feasible", "decision_vector", "binding",
                                 "housing_length_mm", "piston_diameter_mm"]
    assert np.isfinite(c.housing_length_mm)


def _sizes(path):
    tree = ast.parse(path.read_text())
    funcs = [(n.name, n.end_lineno - n.lineno + 1) for n in ast.walk(tree)
             if isinstance(n, (ast.FunctionDef, ast.AsyncFunctionDef))]
    return len(path.read_text().splitlines()), funcs


def test_the_spring_wing_keeps_its_size_limits():
    """No module of vvea_design/spring over 800 lines, no function over 120 lines."""
    files = sorted((REPO / "vvea_design" / "spring").rglob("*.py"))
    assert any(f.parent.name == "layouts" for f in files)
    for f in files:
        lines, funcs = _sizes(f)
        assert lines <= 800, f"{f.relative_to(REPO)}: {lines} lines"
        long = [(n, k) for n, k in funcs if k > 120]
        assert not long, f"{f.relative_to(REPO)}: functions over 120 lines: {long}"
