"""Issue 23's done-when, FE part: the optimised units' every pressure-bearing piece keeps its required safety
factor on yield under every load case (the main job's coarse mesh, the drawing's root radii, the shipped
concentration factors in the sizing): the defaults here, the other envelopes (``examples/paper_tight.toml``, a
70 x 160 mm envelope, ``examples/small_40.toml``) in the slow run."""

from dataclasses import replace

import pytest

from tests.helpers import REPO
from vvea_design.cad import build_cad
from vvea_design.jobs.spring import optimise
from vvea_design.jobs.structure import check_structure
from vvea_design.spring.concentration import concentration_factors
from vvea_design.spring.requirements import Requirements, load_requirements


def _check(req: Requirements):
    design = optimise(req, seed=0, progress=False).design
    return design, check_structure(build_cad(design))


def _assert_passes(design, fe):
    assert fe.corner_radius_mm is None  # the drawing's root radii, not a study's
    assert {w.wall for w in fe.walls} >= {"outer_tube", "inner_tube", "top_cap", "base"}
    for w in fe.walls:
        assert len(w.cases) == len(design.load_cases.cases)
        for c in w.cases:
            assert c.safety >= c.required_safety, (
                f"{w.wall} under {c.case}: FE safety {c.safety:.2f} < {c.required_safety:.2f} at the "
                f"{c.peak.feature} (r {c.peak.r_mm:.1f}, z {c.peak.z_mm:.1f} mm)")
    assert fe.passes


def test_the_shipped_factors_are_measured():
    """The factors the sizing reads are FE ratios >= 1 with their provenance: the unit and case, the FE peak over
    the sizing's closed form there (the factor covers it), the FE safety that unit kept."""
    import json

    data = json.loads((REPO / "vvea_design" / "spring" / "data" / "stress_concentration.json").read_text())
    factors = concentration_factors()
    assert all(v >= 1.0 for v in factors.values())
    raised = {p for p, v in factors.items() if v > 1.0}
    assert raised, "no piece factor measured: the sizing does not learn what the FE finds"
    for piece in raised:
        prov = data["factors_provenance"][piece]
        for feature, k in data["factors"][piece].items():
            if k > 1.0:
                p = prov[feature]
                assert p["unit"] and p["case"] and p["factor"] == k
                assert p["peak_tresca_MPa"] > p["closed_form_MPa"] > 0
                assert p["peak_over_closed_form"] == pytest.approx(p["peak_tresca_MPa"] / p["closed_form_MPa"])
                assert 1.0 < p["peak_over_closed_form"] <= k
                assert p["fe_safety"] >= p["required_safety"]


def test_the_optimised_default_unit_passes_the_fe():
    _assert_passes(*_check(Requirements()))


@pytest.mark.slow
@pytest.mark.parametrize("name", ["paper_tight", "envelope_70x160", "small_40"])
def test_the_other_envelopes_pass_the_fe(name):
    req = {"paper_tight": lambda: load_requirements(REPO / "examples" / "paper_tight.toml"),
           "envelope_70x160": lambda: replace(Requirements(), max_outer_diameter_mm=70.0,
                                              max_housing_length_mm=160.0),
           "small_40": lambda: load_requirements(REPO / "examples" / "small_40.toml")}[name]()
    _assert_passes(*_check(req))
