"""Requirements files: defaults, overrides and clear errors."""

import pytest

from vvea_design.spring.design import Design
from vvea_design.spring.requirements import Requirements, SpecError, constraint_names, evaluate_design, load_requirements


def write(tmp_path, text, name="spec.toml"):
    p = tmp_path / name
    p.write_text(text)
    return p


def test_defaults_are_the_papers_unit():
    r = load_requirements(None)
    assert (r.travel_mm, r.max_outer_diameter_mm, r.max_housing_length_mm, r.max_charge_MPa) == (40, 59.5, 132.5, 4.0)
    assert r.min_mean_stiffness_N_per_mm == pytest.approx(23.31 * 4, abs=0.05)
    assert r.fixed.housing_material == "al-6061-t6" and r.min_wall_safety_factor == 2.0


def test_overrides_bounds_and_fixed(tmp_path):
    p = write(tmp_path, """
max_outer_diameter_mm = 55.0
min_mean_stiffness_N_per_mm = 70
[bounds]
piston_diameter_mm = [20, 40]
[fixed]
housing_material = "al-7075-t6"
min_outer_wall_mm = 2.0
""")
    r = load_requirements(p)
    assert r.max_outer_diameter_mm == 55.0 and r.min_mean_stiffness_N_per_mm == 70
    assert r.search_bounds()[0] == (20.0, 40.0)
    assert r.search_bounds()[1][1] == 55.0  # diameter bound clipped to the envelope
    assert r.fixed.housing_material == "al-7075-t6" and r.fixed.min_outer_wall_mm == 2.0


@pytest.mark.parametrize(
    "text, match",
    [
        ("max_outer_diameter_mm = -3", "max_outer_diameter_mm must be a positive number"),
        ("min_mean_stiffness_N_per_mm = 'stiff'", "must be a number"),
        ("max_diameter = 50", "unknown key"),
        ("[bounds]\nV1_mm3 = [5e4, 1e4]", "0 < low < high"),
        ("[bounds]\nV3_mm3 = [1, 2]", "unknown variable"),
        ("[fixed]\nhousing_material = 'wood'", "unknown material"),
        ("[fixed]\nwall = 3", r"\[fixed\] unknown fixed parameter"),
        ("max_outer_diameter_mm = 20", "contradictory envelope"),
        ("max_housing_length_mm = 60", "leaves no room for chamber 1"),
        ("setpoint_x0_mm = 50", "must lie inside the travel"),
        ("this is = not toml [", "not valid TOML"),
        ("objective = 'fastest'", "objective must be one of"),
        ("objective_n = [0.9]", "objective_n must be"),
        ("layouts = ['sideways']", "layouts must be"),
        ("[bounds]\nV2_top_mm3 = [-1, 2]", "0 < low < high"),
    ],
)
def test_bad_requirement_files_name_file_key_and_problem(tmp_path, text, match):
    p = write(tmp_path, text)
    with pytest.raises(SpecError, match=match) as exc:
        load_requirements(p)
    assert str(p) in str(exc.value)


def test_missing_file(tmp_path):
    with pytest.raises(SpecError, match="does not exist"):
        load_requirements(tmp_path / "nope.toml")


def test_margins_have_signs_and_details():
    d = Design(34.5, 59.5, 41500.0, 80000.0)
    ev = evaluate_design(d, Requirements())
    assert ev.feasible
    assert list(ev.margins) == constraint_names(Requirements())
    assert ev.margins["housing_length"] == pytest.approx(1 - d.housing_length_mm / 132.5)
    tight = evaluate_design(d, Requirements(min_mean_stiffness_N_per_mm=200.0))
    assert not tight.feasible and tight.margins["mean_stiffness"] < 0
    assert tight.details["mean_stiffness"]["unit"] == "N/mm"
    heavy = evaluate_design(d, Requirements(max_mass_g=100.0))
    assert heavy.margins["mass"] < 0
    assert list(heavy.margins) == constraint_names(Requirements(max_mass_g=100.0))
    with pytest.raises(ValueError, match="bladder_strain"):
        evaluate_design(d, Requirements(max_bladder_strain=0.3))


def test_example_requirements_file_is_the_defaults():
    from pathlib import Path

    example = Path(__file__).resolve().parents[1] / "examples" / "requirements.toml"
    assert load_requirements(example) == Requirements()


def test_unknown_bladder_material(tmp_path):
    with pytest.raises(SpecError, match="bladder_material: unknown silicone"):
        load_requirements(write(tmp_path, 'bladder_material = "chewing-gum"'))


def test_objective_layouts_and_wall_safety_reach_the_design(tmp_path):
    r = load_requirements(write(tmp_path, 'objective = "worst"\nlayouts = ["bulkhead"]\nmin_wall_safety_factor = 3\n'
                                          '[bounds]\nV2_top_mm3 = [0, 5e4]'))
    assert r.objective_exponents == (1.0, 1.4) and r.layouts == ("bulkhead",)
    assert r.fixed.wall_safety_factor == 3.0
    assert r.search_bounds("bulkhead")[-1] == (0.0, 5e4)
    assert len(r.search_bounds("inner_tube")) == 4
    assert Requirements().objective_exponents == (1.0,)
    assert Requirements(n_polytropic=1.2, objective="adiabatic").objective_exponents == (1.4,)
