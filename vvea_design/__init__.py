"""vvea-design: design toolkit for the pneumatic spring-damper unit of a VVEA.

The face of the package: ``import vvea_design as vd`` gives the jobs (one function per ``vvea`` command,
each taking an optional output folder ``out``), the loaders and the result types::

    import vvea_design as vd

    req = vd.load_requirements("requirements.toml")
    unit = vd.design_unit(req, "unit")              # everything `vvea design` makes
    res = vd.optimise(req, out="design.json")       # one step on its own
    cad = vd.build_cad("design.json", out="cad")    # STEP/STL, drawings, bill of materials

Every name is imported on first use (module ``__getattr__``): ``import vvea_design`` loads neither the
CAD kernel nor CasADi.

The wings, one subpackage each; imports run downwards only:

* ground floor   - :mod:`materials`, :mod:`messages`, :mod:`progress`, :mod:`outputs`, :mod:`parallel`
* spring         - :mod:`spring` (gas-spring physics, design, requirements, design file, optimiser)
* bladder        - :mod:`bladder` (membrane FE, bladder check)
* cad            - :mod:`cad` (build123d parts, mould, export, renders)
* identification - :mod:`identification` (recordings, effects, identify, diagnose)
* actuator       - :mod:`actuator` (model, OCP transcription, studies)
* report         - :mod:`report` (drawings, bill of materials, HTML reports)
* jobs           - :mod:`jobs` (one function per command)
* main job       - :mod:`pipeline` (:func:`design_unit`)
* top            - :mod:`cli` (the ``vvea`` command)
"""

from __future__ import annotations

import importlib
from typing import Any

__version__ = "0.1.0"

#: Where each name of the face lives (a module of this package); imported on first use.
_FACE: dict[str, str] = {
    # the main job and the jobs, one per command
    "design_unit": "pipeline",
    "optimise": "jobs.spring",
    "spring_report": "jobs.spring",
    "check_design": "jobs.spring",
    "linearity_map": "jobs.spring",
    "pareto_front": "jobs.spring",
    "build_cad": "jobs.cad",
    "check_bladder": "jobs.bladder",
    "identify": "jobs.identification",
    "diagnose": "jobs.identification",
    "run_rest_to_rest": "jobs.studies",
    "run_safety": "jobs.studies",
    "run_design_study": "jobs.studies",
    # loaders and the regression helper
    "load_requirements": "spring.requirements",
    "load_design": "spring.design_file",
    "load_final_model": "identification.report",
    "assert_linearity": "testing",
    # inputs
    "Requirements": "spring.requirements",
    "Design": "spring.design",
    # results
    "UnitDesign": "pipeline",
    "OptimisationResult": "spring.optimise",
    "SpringReport": "jobs.spring",
    "LinearityCheck": "jobs.spring",
    "LinearityMapReport": "jobs.spring",
    "ParetoFront": "jobs.spring",
    "CadSet": "jobs.cad",
    "BladderReport": "bladder.result",
    "BladderResult": "bladder.result",
    "Identification": "identification.identify",
    "DiagnosisRun": "jobs.identification",
    "DiagnosisReport": "identification.report",
    "RestToRestRun": "jobs.studies",
    "RestToRestSummary": "actuator.rest_to_rest",
    "SafetyRun": "jobs.studies",
    "SafetyStudy": "actuator.safety",
    "DesignStudy": "actuator.design_study",
    # errors
    "OptionError": "jobs.common",
    "OutputError": "outputs",
    "SpecError": "spring.requirements",
    "DesignFileError": "spring.design_file",
    "Infeasible": "spring.optimise",
    "NoBuildableDesign": "spring.optimise",
    "CadError": "jobs.cad",
    "BladderError": "bladder.check",
    "RecordingsError": "identification.recordings",
    "LinearityRegression": "testing",
}

__all__ = [
    # the main job and the jobs (each takes an optional output folder `out`)
    "build_cad", "check_bladder", "check_design", "design_unit", "diagnose", "identify", "linearity_map", "optimise",
    "pareto_front", "run_design_study", "run_rest_to_rest", "run_safety", "spring_report",
    # loaders and the regression helper
    "assert_linearity", "load_design", "load_final_model", "load_requirements",
    # inputs
    "Design", "Requirements",
    # results
    "BladderReport", "BladderResult", "CadSet", "DesignStudy", "DiagnosisReport", "DiagnosisRun", "Identification",
    "LinearityCheck", "LinearityMapReport", "OptimisationResult", "ParetoFront", "RestToRestRun", "RestToRestSummary",
    "SafetyRun", "SafetyStudy", "SpringReport", "UnitDesign",
    # errors
    "BladderError", "CadError", "DesignFileError", "Infeasible", "LinearityRegression", "NoBuildableDesign",
    "OptionError", "OutputError", "RecordingsError", "SpecError",
]


def __getattr__(name: str) -> Any:
    """A name of the face, imported from its module on first use (then kept in this module).

    Parameters
    ----------
    name : str
        A name of :data:`__all__`.

    Returns
    -------
    object
        The function, class or exception.

    Raises
    ------
    AttributeError
        ``name`` is not part of the face.
    """
    where = _FACE.get(name)
    if where is None:
        raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
    value = getattr(importlib.import_module(f"{__name__}.{where}"), name)
    globals()[name] = value
    return value


def __dir__() -> list[str]:
    """The face and the module's own attributes.

    Returns
    -------
    list of str
        Sorted names.
    """
    return sorted({*globals(), *__all__})
