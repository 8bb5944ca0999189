"""Issue 24, third pass, class 1: a value that makes the design infeasible is named as the field the user edited,
with its value, what would be accepted, and the file (not only the derived quantity it breaks)."""

from __future__ import annotations

import pytest

from vvea_design.spring.explain import CONSTRAINT_FIELDS, LIMIT_FIELD, explain_infeasible, fields_of
from vvea_design.spring.optimise import Infeasible, optimise
from vvea_design.spring.problem import constraint_names
from vvea_design.spring.requirements import Requirements, SpecError, load_requirements

FAST = dict(maxiter=4, popsize=5, progress=False, polish=False)


@pytest.mark.parametrize("field, value", [("min_mean_stiffness_N_per_mm", 400.0), ("max_mass_g", 200.0),
                                          ("max_linearity_adiabatic", 0.001)])
def test_an_infeasible_requirement_is_named_with_its_value_and_what_would_be_accepted(field, value):
    req = Requirements(layouts=("inner_tube",), joints=("thread",), **{field: value})
    with pytest.raises(Infeasible) as exc:
        optimise(req, **FAST)
    msg = str(exc.value)
    assert f"{field} = {value:g}" in msg, msg
    assert "would accept it" in msg and f"{field} {'<=' if field.startswith('min') else '>='}" in msg, msg


def test_every_constraint_is_traced_to_the_fields_that_set_it():
    req = Requirements(max_mass_g=5000, max_linearity_adiabatic=0.05, max_bladder_strain=0.3)
    for layout in ("inner_tube", "bulkhead", "annulus_top"):
        for name in constraint_names(req, layout):
            assert fields_of(name), f"{name} ({layout}) is not traced to an input field"
    for name, limit in LIMIT_FIELD.items():
        assert CONSTRAINT_FIELDS[name][0] == limit


def test_what_holds_the_best_design_back_is_named_by_its_fields():
    from vvea_design.spring.problem import design_from_vector, evaluate_design

    req = Requirements(min_mean_stiffness_N_per_mm=200.0)
    ev = evaluate_design(design_from_vector((35.4, 59.5, 20000.0, 60000.0), req, "inner_tube", "thread"), req)
    lines = explain_infeasible(ev, req)
    assert any("min_mean_stiffness_N_per_mm = 200" in line for line in lines), lines
    assert any(line.lstrip().startswith("what holds it back") and "max_charge_MPa = 4" in line for line in lines)


@pytest.mark.parametrize("text, named", [
    ("travel_mm = 120\n", "travel_mm 120"),
    ("[fixed]\nmin_base_mm = 110\n", "[fixed] min_base_mm 110"),
    ("[fixed]\npiston_height_mm = 100\n", "[fixed] piston_height_mm 100"),
])
def test_a_housing_with_no_room_names_the_parts_and_what_is_accepted(tmp_path, text, named):
    f = tmp_path / "req.toml"
    f.write_text(text)
    with pytest.raises(SpecError) as exc:
        load_requirements(f)
    msg = str(exc.value)
    assert msg.startswith(str(f)) and named in msg and "accepted: max_housing_length_mm >" in msg, msg
