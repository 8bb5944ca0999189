"""The optimum of a unit that holds together: the default requirements under the buildability rules (joints
chosen like the layouts, the damper's loads, tolerances, the hydraulics' requirement), its design file and the
old files."""

import json
import warnings

import pytest

from vvea_design.schema import shipped_schema
from vvea_design.spring.design_file import load_design, load_design_dict, save_design
from vvea_design.spring.joints import JOINTS, joint_fits_layout
from vvea_design.spring.optimise import optimise
from vvea_design.spring.requirements import Requirements, SpecError
from tests.helpers import REPO

#: The default optimum under the gas-only rules (docs/layout.md), the number buildability is measured against.
GAS_ONLY_OPTIMUM = 0.013265


@pytest.fixture(scope="module")
def result():
    return optimise(Requirements(), seed=0, progress=False)


def test_the_default_optimum_holds_together_and_pays_for_it(result):
    ev, d = result.evaluation, result.design
    assert ev.feasible and d.fixed.sizing_rules == "buildable"
    # dearer than the gas-only optimum; the joints' O-rings pass no thread (the seal bore inside the thread's minor
    # diameter, a standard ring's bore, the internal run-out, the bulkhead cap's cross port above the tube) cost
    # about 0.4 pp more: above the paper's hand-tuned 1.86 %, which was sized for the gas alone
    assert GAS_ONLY_OPTIMUM < ev.linearity_error <= 0.0240
    assert d.layout == "inner_tube" and d.joint == "thread"
    assert d.parasitic_damping_N_s_per_mm <= 1.5 + 1e-9
    for piece, p in d.piece_loads().items():  # the final check: every case at its least-material condition
        for case, sf in p.safety_factor_per_case.items():
            assert sf >= (1.05 if case == "proof" else 2.0) * (1 - 1e-9), (piece, case)
    assert all(min(j.safety_factors.values()) >= j.required_safety_factor - 1e-9 for j in d.joints()
               if hasattr(j, "safety_factors"))
    assert {"joint_capacity", "parasitic_damping"} <= set(ev.margins)


def test_every_layout_and_joint_is_searched(result):
    pairs = {(s.layout, s.joint) for s in result.searches}
    # every pair a workshop can build: the ring's plug leaves no side face for bulkhead's cross port
    assert pairs == {(lay, j) for lay in ("inner_tube", "bulkhead", "annulus_top") for j in JOINTS
                     if joint_fits_layout(j, lay)}
    assert ("bulkhead", "ring_top") not in pairs and not joint_fits_layout("ring_top", "bulkhead")
    best = min((s for s in result.searches if s.feasible), key=lambda s: s.objective)
    assert (best.layout, best.joint) == (result.design.layout, result.design.joint)
    assert result.summary()["joint"] == result.design.joint


def test_the_design_file_carries_and_rederives_the_buildability_records(result, tmp_path):
    req = Requirements()
    path = save_design(tmp_path / "design.json", result.evaluation, req, result.summary())
    data = json.loads(path.read_text())
    import jsonschema

    jsonschema.validate(data, shipped_schema("design.schema.json"))
    assert data["parameters"]["joint"] == result.design.joint
    assert data["structure"]["sizing_rules"] == "buildable"
    assert set(data["structure"]["load_cases"]["cases"]) == {"gas_full_stroke", "gas_rest", "retraction", "relief",
                                                               "damping", "proof"}
    assert set(data["structure"]["pieces"]) == set(result.design.walls_mm())
    assert {j["joint"] for j in data["joints"]} >= {"top_cap", "base"}
    D_min, D_max = result.design.damping_range_N_s_per_mm()
    assert data["hydraulics"]["D_min_N_s_per_mm"] == pytest.approx(D_min)
    assert data["hydraulics"]["D_max_N_s_per_mm"] == pytest.approx(D_max)
    # the records are derived: the loaded design re-derives them from the decision variables and `fixed`
    data["hydraulics"]["D_min_N_s_per_mm"] = 99.0
    data["structure"]["pieces"]["outer_tube"]["safety_factor"] = 9.0
    d = load_design_dict(data)
    assert d == result.design and d.damping_range_N_s_per_mm() == pytest.approx((D_min, D_max))
    assert d.buildability.to_dict()["structure"]["pieces"] == json.loads(path.read_text())["structure"]["pieces"]


def test_an_old_design_file_loads_under_its_own_rules_with_a_notice():
    path = REPO / "cad" / "design.json"
    old = json.loads(path.read_text())
    if "sizing_rules" in old["fixed"]:
        pytest.skip("cad/design.json has been regenerated under the buildability rules")
    with pytest.warns(UserWarning, match="written before the buildability rules"):
        d = load_design(path)
    assert d.fixed.sizing_rules == "gas_only" and d.joint == "thread"
    assert d.walls_mm() == pytest.approx(old["geometry"]["walls_mm"], rel=1e-12)  # the design it was: unchanged
    # what those rules missed is reported, not hidden
    assert d.piece_loads()["outer_tube"].safety_factor < 2.0


def test_requirements_name_the_joints_and_the_parasitic_damping_limit():
    req = Requirements.from_dict({"joints": ["thread"], "max_parasitic_damping_N_s_per_mm": None})
    assert req.joints == ("thread",) and req.max_parasitic_damping_N_s_per_mm is None
    assert Requirements.from_dict(req.to_dict()) == req
    with pytest.raises(SpecError, match="joints must be a non-empty list"):
        Requirements(joints=("weld",))
    with pytest.raises(SpecError, match=r"max_parasitic_damping_N_s_per_mm must be >= 0\.0001 and <= 10000 N s/mm, got 0"):
        Requirements(max_parasitic_damping_N_s_per_mm=0.0)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        assert Requirements().joint_choices == JOINTS


def test_a_single_joint_and_the_gas_only_rules_search_what_they_say():
    from vvea_design.spring.parameters import FixedParameters

    one = optimise(Requirements(layouts=("inner_tube",), joints=("ring_top",)), seed=0, progress=False, maxiter=20,
                   raise_infeasible=False)
    assert {(s.layout, s.joint) for s in one.searches} == {("inner_tube", "ring_top")}
    with pytest.raises(ValueError, match="no pair a workshop can build"):  # the ring's plug has no cross port
        optimise(Requirements(layouts=("bulkhead",), joints=("ring_top",)), seed=0, progress=False, maxiter=2)
    old = optimise(Requirements(layouts=("bulkhead",), fixed=FixedParameters(sizing_rules="gas_only")), seed=0,
                   progress=False, maxiter=20)
    assert len(old.searches) == 1 and "joint_capacity" not in old.evaluation.margins


def test_the_tight_manufacturing_preset_holds_together(result):
    """examples/paper_tight.toml under the buildability rules (its 14 mm base): feasible, its open valve's
    parasitic damping at most the requirement (it binds: the larger piston's flow through the base), every
    piece at its least-material condition, the cupped piston's floor under the relief valve's fluid. With the joints'
    seals clear of the threads its optimum (2.394 %) is no longer more linear than the defaults' (the inner_tube
    unit, 2.337 %): the defaults' optimum is not feasible under the preset (bladder room at x = 0 with the forced
    pocket, parasitic damping with a nearer cast fill); the number is pinned (docs/layout.md, the cost of
    buildability)."""
    from functools import partial

    from vvea_design.bladder.check import strain_bound
    from vvea_design.spring.requirements import load_requirements

    req = load_requirements(REPO / "examples" / "paper_tight.toml")
    assert req.fixed.sizing_rules == "buildable" and req.fixed.min_base_mm == 14.0
    r = optimise(req, seed=0, progress=False, bladder_strain_fn=partial(strain_bound, material=req.bladder_material))
    ev, d = r.evaluation, r.design
    assert ev.feasible and all(m >= -1e-9 for m in ev.margins.values())
    assert d.parasitic_damping_N_s_per_mm <= req.max_parasitic_damping_N_s_per_mm + 1e-9
    assert ev.margins["wall_safety_piston_floor"] >= -1e-9 and d.piston_pocket_volume_mm3 > 0.0
    assert GAS_ONLY_OPTIMUM < ev.linearity_isothermal == pytest.approx(0.023892, abs=2e-5)  # studies/fe_units.py
    assert ev.linearity_isothermal < result.evaluation.linearity_isothermal + 0.0006  # within 0.06 pp of the defaults'
    assert r.bladder_strain_fe <= req.max_bladder_strain
