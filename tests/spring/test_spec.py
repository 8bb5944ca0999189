"""Requirements files: defaults, overrides and clear errors."""

import pytest

from vvea_design.spring.design import Design, FixedParameters
from vvea_design.spring.problem import constraint_names, evaluate_design
from vvea_design.spring.requirements import Requirements, SpecError, load_requirements
from tests.helpers import REPO


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
        # issue 11 item 11: [fixed] travel_mm was silently overridden by the top-level value
        ("[fixed]\ntravel_mm = 30", r"\[fixed\] travel_mm = 30 disagrees with the top-level travel_mm = 40 \(the default\)"),
        ("travel_mm = 35\n[fixed]\ntravel_mm = 30", r"\[fixed\] travel_mm = 30 disagrees with the top-level travel_mm = 35;"),
        ("n_polytropic = 1.2\n[fixed]\nn_polytropic = 1.0", r"\[fixed\] n_polytropic = 1 disagrees"),
        ("min_gas_fraction_at_full_stroke = [0.2]", "min_gas_fraction_at_full_stroke must be a number, got \\[0.2\\]"),
        ("[bounds]\nV1_mm3 = [1, inf]", r"V1_mm3 = \[1, inf\] must satisfy"),
        ("n_polytropic = nan", r"n_polytropic must be in \[1, 1.4\], got nan"),
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


@pytest.mark.parametrize("rules", ["gas_only", "buildable"])
def test_margins_have_signs_and_details(rules):
    fixed = FixedParameters(sizing_rules=rules)
    # a design feasible under each rules' requirements (the buildable one: a thread joint, shorter gas columns; its
    # seal zones hold the bores' lead-ins)
    d = (Design(34.5, 59.5, 41500.0, 80000.0, fixed=fixed) if rules == "gas_only"
         else Design(31.5, 59.3, 26000.0, 65000.0, fixed=fixed))
    ev = evaluate_design(d, Requirements(fixed=fixed))
    assert ev.feasible
    assert list(ev.margins) == constraint_names(Requirements(fixed=fixed), d.layout)
    assert ev.margins["housing_length"] == pytest.approx(1 - d.housing_length_mm / 132.5)
    tight = evaluate_design(d, Requirements(min_mean_stiffness_N_per_mm=200.0, fixed=fixed))
    assert not tight.feasible and tight.margins["mean_stiffness"] < 0
    assert tight.details["mean_stiffness"]["unit"] == "N/mm"
    heavy = evaluate_design(d, Requirements(max_mass_g=100.0, fixed=fixed))
    assert heavy.margins["mass"] < 0
    assert list(heavy.margins) == constraint_names(Requirements(max_mass_g=100.0, fixed=fixed), d.layout)
    with pytest.raises(ValueError, match="bladder_strain"):
        evaluate_design(d, Requirements(max_bladder_strain=0.3, fixed=fixed))


def test_example_requirements_file_is_the_defaults():
    from pathlib import Path

    example = REPO / "examples" / "requirements.toml"
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


def test_fixed_copy_that_agrees_is_accepted(tmp_path):
    r = load_requirements(write(tmp_path, "travel_mm = 30\n[fixed]\ntravel_mm = 30\nmin_base_mm = 12"))
    assert r.travel_mm == 30 and r.fixed.travel_mm == 30 and r.fixed.min_base_mm == 12
    assert Requirements.from_dict(r.to_dict()) == r  # a design file's spec holds both copies


def test_latin1_file_names_file_line_and_byte(tmp_path):
    """Issue 11 item 8: a Latin-1 TOML was a UnicodeDecodeError traceback."""
    p = tmp_path / "latin1.toml"
    p.write_bytes("# Anforderungen\n# Au\u00dfendurchmesser begrenzt\nmax_outer_diameter_mm = 55\n".encode("latin-1"))
    with pytest.raises(SpecError, match=r"not UTF-8 text: byte 0xdf at line 2, column 5") as exc:
        load_requirements(p)
    assert str(p) in str(exc.value)


def test_messages_never_show_numpy_reprs():
    """Issue 11 item 11: values computed with numpy printed as np.float64(...)."""
    import numpy as np

    from vvea_design.spring.design import DesignError, FixedParameters
    from vvea_design.spring.gas_spring import GasSpring

    cases = [
        (SpecError, lambda: Requirements(max_outer_diameter_mm=np.float64(-3.0))),
        (SpecError, lambda: Requirements(n_polytropic=np.float64(2.0))),
        (SpecError, lambda: Requirements(setpoint_x0_mm=np.float64(50.0))),
        (SpecError, lambda: Requirements(bounds={"V1_mm3": (np.float64(5.0), np.float64(1.0))})),
        (DesignError, lambda: Design(np.float64(-34.5), 59.5, 41500.0, 90000.0)),
        (DesignError, lambda: FixedParameters(min_outer_wall_mm=np.float64(-1.0))),
        (ValueError, lambda: GasSpring(np.float64(-1.0), 900.0, 4e4, 9e4, 3.0, 4.0, 40.0)),
    ]
    for exc_type, make in cases:
        with pytest.raises(exc_type) as exc:
            make()
        assert "np." not in str(exc.value) and "float64" not in str(exc.value), str(exc.value)


def test_cast_fill_requirements_are_checked():
    from vvea_design.spring.requirements import Requirements, SpecError

    r = Requirements.from_dict({"optimise_cast_fill": True, "bounds": {"bladder_cast_fill": [0.2, 0.8]}})
    assert r.optimise_cast_fill and r.search_bounds("inner_tube")[-1] == (0.2, 0.8)
    with pytest.raises(SpecError, match="optimise_cast_fill must be true or false"):
        Requirements.from_dict({"optimise_cast_fill": 1})
    with pytest.raises(SpecError, match="bladder_cast_fill.*<= 1"):
        Requirements.from_dict({"bounds": {"bladder_cast_fill": [0.2, 1.5]}})
