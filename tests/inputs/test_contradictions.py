"""Issue 24, third pass, class 3: objective and search settings that contradict each other are refused or noted."""

from __future__ import annotations

import re
import warnings

import pytest

from tests.helpers import REPO
from vvea_design.spring.contradictions import CONTRADICTIONS, SettingsNote, check_optimiser_options
from vvea_design.spring.requirements import Requirements, SpecError, load_requirements
from vvea_design.spring.studies import check_pareto_values

REFUSED = {  # key of CONTRADICTIONS -> (file, words the message must hold: the fields and what is accepted)
    "objective_twice": ('objective = "adiabatic"\nobjective_n = [1.0, 1.2]\n', r"objective = .*objective_n.*give one"),
    "cast_fill_bounds": ("[bounds]\nbladder_cast_fill = [0.2, 0.8]\n", r"\[bounds\] bladder_cast_fill.*optimise_cast_fill"),
    "cast_fill_fixed": ("optimise_cast_fill = true\n[fixed]\nbladder_cast_fill = 0.5\n",
                        r"\[fixed\] bladder_cast_fill = 0.5 and optimise_cast_fill.*\[bounds\] bladder_cast_fill"),
    "bounds_other_layout": ('layouts = ["inner_tube"]\n[bounds]\nV2_top_mm3 = [0, 1000]\n',
                            r"\[bounds\] V2_top_mm3.*layouts = \['inner_tube'\]"),
    "listed_twice": ('layouts = ["inner_tube", "inner_tube"]\n', r"layouts = .*twice"),
    "gas_only_joints": ('joints = ["thread"]\n[fixed]\nsizing_rules = "gas_only"\n', r"joints given with .*gas_only"),
    "piston_vs_rod": ("[bounds]\npiston_diameter_mm = [3, 8]\n",
                      r"piston_diameter_mm = \[3, 8\].*rod_diameter_mm = 8.*must exceed 8"),
    # campaign B: a port volume of a cubic metre (1e9 mm³) was blamed on the bladder's room after a 30 s search
    "dead_volume_vs_gas": ("[fixed]\ndead_volume_1_mm3 = 1e9\n",
                           r"\[fixed\] dead_volume_1_mm3 = 1e\+09 mm³ is at or above the high end of the default "
                           r"V1_mm3 range.*below 300000 mm³"),
}


@pytest.mark.parametrize("key", sorted(REFUSED))
def test_contradictory_requirements_are_refused_naming_both_settings(tmp_path, key):
    text, words = REFUSED[key]
    f = tmp_path / "req.toml"
    f.write_text(text)
    with pytest.raises(SpecError) as exc:
        load_requirements(f)
    assert str(exc.value).startswith(str(f)) and re.search(words, str(exc.value)), str(exc.value)
    assert CONTRADICTIONS[key][1] == "refused"


@pytest.mark.parametrize("text, words", [
    ("[fixed]\ndead_volume_2_mm3 = 1e9\n", r"\[fixed\] dead_volume_2_mm3 = 1e\+09 mm³.*no V2_mm3 in the range"),
    ("[bounds]\nV1_mm3 = [5000, 20000]\n[fixed]\ndead_volume_1_mm3 = 30000\n",
     r"dead_volume_1_mm3 = 30000 mm³ is at or above the high end of \[bounds\] V1_mm3 = \[5000, 20000\]"),
])
def test_a_dead_volume_no_gas_volume_in_the_range_holds_is_refused_naming_it(tmp_path, text, words):
    """Named before any search (it was a 'no room for the bladder' message after the whole search)."""
    f = tmp_path / "req.toml"
    f.write_text(text)
    with pytest.raises(SpecError, match=words):
        load_requirements(f)
    f.write_text("[fixed]\ndead_volume_1_mm3 = 1000\ndead_volume_2_mm3 = 1000\n")  # real port volumes: accepted
    assert load_requirements(f).fixed.dead_volume_1_mm3 == 1000


def test_the_same_settings_written_once_are_accepted(tmp_path):
    for text in ('objective = "adiabatic"\n', "objective_n = [1.0, 1.2]\n",
                 "optimise_cast_fill = true\n[bounds]\nbladder_cast_fill = [0.2, 0.8]\n",
                 'layouts = ["inner_tube"]\n', "[bounds]\npiston_diameter_mm = [20, 40]\n"):
        f = tmp_path / "ok.toml"
        f.write_text(text)
        with warnings.catch_warnings():
            warnings.simplefilter("error")
            load_requirements(f)


def test_a_design_files_spec_is_not_judged_by_what_a_user_wrote():
    """A design file's spec holds every field (defaults included); only a requirements file is judged."""
    import json

    spec = json.loads((REPO / "cad" / "design.json").read_text())["spec"]
    Requirements.from_dict(spec, "cad/design.json")


def test_an_objective_that_ignores_the_nominal_exponent_is_noted(tmp_path):
    f = tmp_path / "req.toml"
    f.write_text('objective = "isothermal"\nn_polytropic = 1.2\n')
    with pytest.warns(SettingsNote, match=r"objective = 'isothermal'.*n_polytropic = 1.2"):
        load_requirements(f)


@pytest.mark.parametrize("kw", [dict(popsize=0), dict(maxiter=0), dict(maxiter=-3), dict(tol=float("nan")),
                                dict(tol=-1.0), dict(maxiter=2.5)])
def test_optimiser_numbers_with_which_no_search_runs_are_refused(kw):
    from vvea_design.spring.optimise import optimise

    name = next(iter(kw))
    with pytest.raises(ValueError, match=name):
        optimise(Requirements(), progress=False, **kw)


def test_polish_off_under_a_strain_limit_is_noted():
    with pytest.warns(SettingsNote, match="polish=False with max_bladder_strain"):
        check_optimiser_options(10, 60, 1e-5, False, 0.2)


def test_pareto_repeated_value_is_refused_and_misreadable_sweeps_are_noted():
    with pytest.raises(ValueError, match=r"values\[2\] = 800 repeats values\[0\]"):
        check_pareto_values(Requirements(), "mass", [800, 700, 800])
    with pytest.warns(SettingsNote, match="one value"):
        check_pareto_values(Requirements(), "stiffness", [90.0])
    with pytest.warns(SettingsNote, match="max_mass_g = 900 is replaced"):
        check_pareto_values(Requirements(max_mass_g=900), "mass", [800, 700])
    with pytest.warns(SettingsNote, match="objective itself"):
        check_pareto_values(Requirements(objective="adiabatic"), "adiabatic", [0.02, 0.03])


def test_the_table_is_on_the_reliability_page():
    page = (REPO / "docs" / "reliability.md").read_text()
    for key, (settings, action, why) in CONTRADICTIONS.items():
        assert f"| {settings} | {action} | {why} |" in page, key
