"""Search bounds follow the requirements, and a bound that limits the optimum is reported (issue 24 item 1).

The default ``[bounds]`` used to be the paper's unit's whatever the envelope: a 70 x 160 mm envelope was searched
only up to a 59.5 mm outer diameter (1.409 % where 0.879 % is reachable) and the design file showed the diameter
as slack. Now every range a requirements file does not give derives from its envelope, never below the paper's.
"""

from __future__ import annotations

import math
from dataclasses import replace

import pytest

from vvea_design.spring.problem import binding_bounds
from vvea_design.spring.requirements import (DEFAULT_BOUNDS, Requirements, default_bounds, envelope_room,
                                             load_requirements)

ENV70 = dict(max_outer_diameter_mm=70.0, max_housing_length_mm=160.0, min_mean_stiffness_N_per_mm=120.0)


def test_the_paper_envelope_keeps_the_paper_bounds():
    assert Requirements().resolved_bounds == DEFAULT_BOUNDS == default_bounds()
    assert Requirements().bounds == {}
    assert Requirements().to_dict()["bounds"] == {k: list(v) for k, v in DEFAULT_BOUNDS.items()}


def test_a_larger_envelope_widens_every_default_bound():
    req = Requirements(**ENV70)
    b = req.resolved_bounds
    piston, gas = envelope_room(70.0, 160.0, req.fixed)
    assert b["outer_diameter_mm"] == (25.0, 70.0)
    assert b["piston_diameter_mm"] == (12.0, pytest.approx(piston)) and piston == pytest.approx(59.0)
    assert b["V1_mm3"][1] == b["V2_mm3"][1] == pytest.approx(gas)
    assert gas == pytest.approx(math.pi / 4 * 67.0**2 * (160 - 8 - 14))
    assert b["V2_top_mm3"][1] == pytest.approx(gas / 2)  # a layout's own volume scales like V1 and V2
    assert req.search_bounds("inner_tube")[1] == (25.0, 70.0)


def test_an_explicit_bound_pins_its_variable_and_a_derived_one_follows_a_replace():
    req = Requirements(**ENV70, bounds={"outer_diameter_mm": (25.0, 59.5)})
    assert req.resolved_bounds["outer_diameter_mm"] == (25.0, 59.5)
    assert Requirements(bounds={"outer_diameter_mm": (25.0, 59.5)}).bounds == {}  # equal to the derived one
    wider = replace(Requirements(), max_outer_diameter_mm=80.0)
    assert wider.resolved_bounds["outer_diameter_mm"] == (25.0, 80.0)


def test_the_example_requirements_file_leaves_the_bounds_to_follow():
    from tests.helpers import REPO

    req = load_requirements(REPO / "examples" / "requirements.toml")
    assert req == Requirements() and req.bounds == {}


def test_optimise_on_70_by_160_at_120_N_per_mm_reaches_0_879_without_bounds():
    """The README's 70 x 160 mm figure, reproduced by `vvea optimise --spec` with no [bounds] edit."""
    from vvea_design.spring.optimise import optimise

    r = optimise(Requirements(**ENV70), seed=0, progress=False)
    assert r.evaluation.feasible
    assert r.evaluation.linearity_error <= 0.00880
    assert r.design.outer_diameter_mm == pytest.approx(70.0)
    assert r.binding_bounds == ()  # the diameter sits on the envelope: its constraint says so


def test_a_bound_that_limits_the_optimum_is_reported_like_a_constraint():
    """Campaign A req-05: an explicit [25, 59.5] on a 70 mm envelope binds and is named."""
    from vvea_design.spring.design_file import design_to_dict
    from vvea_design.spring.optimise import optimise

    req = Requirements(**ENV70, bounds={"outer_diameter_mm": (25.0, 59.5)})
    r = optimise(req, seed=0, progress=False)
    names = [b["name"] for b in r.binding_bounds]
    assert "bound outer_diameter_mm (high end)" in names
    assert "bound outer_diameter_mm (high end)" in r.binding()
    assert r.summary()["binding_bounds"][0]["bound"] == 59.5
    assert design_to_dict(r.evaluation, req, r.summary())["optimiser"]["binding_bounds"]
    assert binding_bounds(r.design, req) == list(r.binding_bounds)
