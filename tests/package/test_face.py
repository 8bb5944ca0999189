"""The package's face (issue 22 item 4): ``import vvea_design as vd`` offers the jobs, loaders and result types,
imported on first use, so the import itself loads neither the CAD kernel nor CasADi."""

import ast
import inspect
import json
import subprocess
import sys

import pytest

import vvea_design as vd
from tests.helpers import REPO

#: The names the documentation is written against (the contract of issue 22).
CONTRACT = ("load_requirements", "Requirements", "load_design", "Design", "optimise", "design_unit", "build_cad",
            "check_bladder", "identify", "diagnose", "run_rest_to_rest", "run_safety", "run_design_study",
            "linearity_map", "pareto_front", "assert_linearity", "load_final_model", "UnitDesign",
            "OptimisationResult", "CadSet", "BladderResult", "BladderReport", "Identification", "DiagnosisReport",
            "RestToRestSummary", "SafetyStudy", "DesignStudy")
#: The face's jobs: one per command (and the main job), each writing only when given ``out``.
JOBS = ("optimise", "spring_report", "linearity_map", "pareto_front", "build_cad", "check_bladder", "identify",
        "diagnose", "run_rest_to_rest", "run_safety", "run_design_study", "design_unit")
HEAVY = ("build123d", "OCP", "casadi", "pyvista", "trimesh")


def test_import_loads_neither_the_cad_kernel_nor_casadi():
    """A fresh interpreter: ``import vvea_design`` imports no module of the package but the root, nor a heavy library."""
    code = ("import json, sys; import vvea_design as vd; "
            "print(json.dumps(sorted(m for m in sys.modules if m.split('.')[0] in "
            f"{('vvea_design', *HEAVY)!r})))")
    res = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, cwd=REPO, timeout=120)
    assert res.returncode == 0, res.stderr
    assert json.loads(res.stdout) == ["vvea_design"]


def test_a_job_is_light_until_it_runs():
    """Reaching a job loads its module, not the CAD kernel or CasADi (those load when the job runs)."""
    code = ("import json, sys; import vvea_design as vd; "
            "[getattr(vd, n) for n in ('optimise', 'build_cad', 'check_bladder', 'identify', 'diagnose', "
            "'run_rest_to_rest', 'run_safety', 'run_design_study', 'linearity_map', 'pareto_front')]; "
            f"print(json.dumps(sorted(m for m in sys.modules if m.split('.')[0] in {HEAVY!r})))")
    res = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, cwd=REPO, timeout=300)
    assert res.returncode == 0, res.stderr
    assert json.loads(res.stdout) == []


def test_the_face_offers_the_contract_and_every_name_resolves():
    assert set(CONTRACT) <= set(vd.__all__)
    assert len(vd.__all__) == len(set(vd.__all__))
    assert set(vd.__all__) == set(vd._FACE)
    for name in vd.__all__:
        value = getattr(vd, name)
        assert value.__name__ == name, name
        assert value.__module__.startswith("vvea_design."), name
    with pytest.raises(AttributeError, match="no attribute 'not_a_name'"):
        vd.not_a_name  # noqa: B018
    assert set(vd.__all__) <= set(dir(vd))


def test_the_face_is_sorted_in_commented_groups():
    """``__all__`` in the source: groups, each sorted (case-insensitively) and headed by a comment."""
    src = (REPO / "vvea_design" / "__init__.py").read_text()
    lines = src[src.index("__all__ = ["):].split("]\n", 1)[0].splitlines()[1:]
    groups, current = [], None
    for line in lines:
        line = line.strip()
        if line.startswith("#"):
            current = []
            groups.append((line, current))
        elif line:
            assert current is not None, "a name before the first group's comment"
            current += [ast.literal_eval(n.strip()) for n in line.rstrip(",").split(",")]
    assert len(groups) >= 4 and sum(len(g) for _, g in groups) == len(vd.__all__)
    for comment, names in groups:
        assert names == sorted(names, key=str.lower), comment


def test_face_functions_are_the_jobs_taking_an_optional_out():
    for name in JOBS:
        fn = getattr(vd, name)
        assert fn.__module__.startswith(("vvea_design.jobs.", "vvea_design.pipeline")), name
        params = inspect.signature(fn).parameters
        assert "out" in params, name
        if name != "design_unit":  # the unit is its folder
            assert params["out"].default is None, name
    for name in vd.__all__:
        if name.endswith("Error") or name in ("Infeasible", "LinearityRegression"):
            assert issubclass(getattr(vd, name), Exception), name


def test_face_result_types_are_frozen_with_to_dict():
    import dataclasses

    for name in ("UnitDesign", "OptimisationResult", "SpringReport", "LinearityCheck", "LinearityMapReport",
                 "ParetoFront", "CadSet", "BladderReport", "BladderResult", "Identification", "DiagnosisRun",
                 "DiagnosisReport", "RestToRestRun", "RestToRestSummary", "SafetyRun", "SafetyStudy", "DesignStudy"):
        cls = getattr(vd, name)
        assert dataclasses.is_dataclass(cls), name
        assert callable(getattr(cls, "to_dict", None)), name
        if name not in ("DiagnosisReport",):  # the identification wing's report is frozen by convention only
            assert cls.__dataclass_params__.frozen, name
