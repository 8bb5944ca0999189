"""The main job as one function: requirements in, a checked unit and its folder out.

:func:`design_unit` runs the chain of the toolkit in order::

    requirements -> optimise -> spring curve -> CAD -> bladder check (the
    requirements' silicone) -> actuator parameters -> the design's actuator
    study -> report.html

and returns a :class:`UnitDesign` (frozen, ``to_dict()`` for JSON). The
``vvea design`` command only calls it and prints the result.
"""

from __future__ import annotations

import csv
import json
import time
from collections.abc import Callable
from dataclasses import asdict, dataclass, replace
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from . import __version__
from .actuator.model import Actuator, actuator_from_spring
from .bladder.check import DEFAULT_ELEMENTS, BladderResult, check_bladder, write_bladder_report
from .spring.curve import SpringCurve, spring_curve
from .spring.design_file import save_design
from .spring.gas_spring import GasSpring
from .spring.optimise import Infeasible, OptimisationResult, optimise
from .spring.requirements import Requirements

if TYPE_CHECKING:  # the CAD kernel and CasADi load only when the job needs them (`vvea spring` stays light)
    from .actuator.design_study import DesignStudy
    from .cad.manifest import CadManifest
    from .report.bom import BillOfMaterials
    from .report.drawing import DrawingSet

__all__ = ["SpringCurve", "UnitDesign", "design_unit", "spring_curve", "write_spring_files", "STEPS",
           "Infeasible"]

#: The steps of :func:`design_unit` in order (the names its ``progress`` callback receives).
STEPS = ("optimise", "spring", "cad", "bladder", "actuator", "actuator_study", "report")

def write_spring_files(spring: GasSpring, out_dir: str | Path, layout: str | None = None) -> dict[str, Path]:
    """Write ``spring.csv`` (x, force, stiffness, pressures) and ``spring.png`` into ``out_dir``.

    Parameters
    ----------
    spring : GasSpring
        The gas spring (mm, mm², mm³, MPa).
    out_dir : path-like
        Folder (created).
    layout : str, optional
        The design's layout, named in the figure's title.

    Returns
    -------
    dict of str to Path
        ``{"csv": ..., "png": ...}``.
    """
    from .spring.plots import plot_spring

    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    x = spring.x_mm(81)
    F = spring.force_N(x)
    k = spring.stiffness_N_per_mm(x)
    P1, P2 = spring.pressures_MPa(x)
    csv_path = out / "spring.csv"
    with open(csv_path, "w", newline="") as fh:
        w = csv.writer(fh)
        w.writerow(["x_mm", "force_N", "stiffness_N_per_mm", "P1_MPa", "P2_MPa"])
        for row in zip(x, F, k, P1, P2):
            w.writerow([f"{v:.6g}" for v in row])
    png = _save(plot_spring(spring, extra_charges_MPa=(1.0, 2.0, 4.0), layout=layout), out / "spring.png")
    return {"csv": csv_path, "png": png}


def _save(fig_or_path, path: Path) -> Path:
    """Accept a plot function that returns a Figure (new style) or the path it saved (old style)."""
    if isinstance(fig_or_path, (str, Path)):
        return Path(fig_or_path)
    path.parent.mkdir(parents=True, exist_ok=True)
    fig_or_path.savefig(path, dpi=120, metadata={"Software": "vvea-design"})
    return path


@dataclass(frozen=True)
class UnitDesign:
    """Everything :func:`design_unit` made: the design, its checks, its files.

    ``to_dict()`` is what ``unit.json`` holds.
    """

    requirements: Requirements  #: what was asked for
    optimisation: OptimisationResult  #: the optimised design, evaluated (margins, performance)
    spring: SpringCurve  #: isothermal and adiabatic force curves, deviations, pressures
    bladder: BladderResult  #: the bladder check with the requirements' silicone
    actuator: Actuator  #: joint-level K, D range of the unit (section 3.4 mapping, SI)
    cad_manifest: CadManifest | None  #: the CAD set's manifest (None when CAD was skipped)
    bom: BillOfMaterials | None  #: bill of materials, the bladder in the requirements' silicone (None: no CAD)
    drawings: DrawingSet | None  #: dimensioned drawings (None: no CAD)
    actuator_study: DesignStudy | None  #: the design's rest-to-rest and torque-step study (None when skipped)
    out_dir: Path  #: the folder written
    files: dict[str, Path]  #: what was written, by role
    seconds: dict[str, float]  #: wall time of each step (s)
    seed: int  #: seed of the optimiser
    version: str  #: vvea-design version that made it
    spec_path: str | None = None  #: requirements file (None: the built-in defaults)

    @property
    def passes(self) -> bool:
        """Every constraint met and the bladder check passed."""
        return bool(self.optimisation.evaluation.feasible and self.bladder.passes)

    def to_dict(self) -> dict[str, Any]:
        """JSON-ready summary (no arrays of the CAD meshes).

        Returns
        -------
        dict
            Requirements, performance, margins, bladder, actuator, files, timings (s), provenance.
        """
        ev = self.optimisation.evaluation
        study = self.actuator_study
        return _relative_tree({
            "generator": "vvea_design.pipeline.design_unit",
            "version": self.version,
            "seed": self.seed,
            "spec": self.spec_path,
            "passes": self.passes,
            "requirements": self.requirements.to_dict(),
            "performance": ev.performance(),
            "constraint_margins": dict(ev.margins),
            "optimiser": self.optimisation.summary(),
            "spring": {k: v for k, v in self.spring.to_dict().items() if not isinstance(v, list)},
            "bladder": self.bladder.to_dict(),
            "actuator": _actuator_dict(self.actuator),
            "bom": None if self.bom is None else self.bom.to_dict(),
            "drawings": None if self.drawings is None else self.drawings.to_dict(),
            "actuator_study": None if study is None else {
                "runs": [r.to_dict() for r in study.runs],
                "damping": study.damping.to_dict(),
                "comparisons": [c.to_dict() for c in study.comparisons],
                "settings": [s.to_dict() for s in study.settings],
                "n_left_out_unverified": study.n_left_out,
                "safety_design": study.safety_design.to_dict(),
                "timing": study.timing.to_dict(),
                "files": {k: (None if v is None else str(v)) for k, v in asdict(study.files).items()}},
            "files": {k: str(v) for k, v in self.files.items()},
            "seconds": dict(self.seconds),
        }, self.out_dir)  # paths relative to the unit folder: it is moved into place after writing


ProgressFn = Callable[[str, int, int], None]


def design_unit(
    requirements: Requirements,
    out_dir: str | Path,
    *,
    seed: int = 0,
    renders: bool = True,
    cad: bool = True,
    actuator_study: bool = True,
    report: bool = True,
    bladder_elements: int = DEFAULT_ELEMENTS,
    study_options: dict[str, Any] | None = None,
    spec_path: str | Path | None = None,
    progress: ProgressFn | None = None,
) -> UnitDesign:
    """Run the main job: optimise the spring, then spring curve, CAD, bladder check, actuator, report.

    Parameters
    ----------
    requirements : Requirements
        What the unit must meet (mm, MPa, N/mm; ``bladder_material`` names the silicone checked).
    out_dir : path-like
        Folder for everything (created): ``design.json``, ``design_force.png``,
        ``spring/``, ``cad/`` (with drawings and ``bom.csv``), ``bladder/``, ``actuator/``,
        ``unit.json``, ``report.html``.
    seed : int
        Seed of the optimiser's global search (same seed, same design).
    renders : bool
        Make the CAD PNG renders (off-screen pyvista).
    cad : bool
        Build and export the CAD set, its drawings and bill of materials (False skips them and the
        3-D view of the report).
    actuator_study : bool
        Run the design's own actuator study (rest-to-rest against VVEA, SEA, LWR and the torque step,
        :func:`vvea_design.actuator.design_study.run_design_study`) into ``actuator/``.
    report : bool
        Write ``report.html``.
    bladder_elements : int
        Finite elements along the bladder meridian.
    study_options : dict, optional
        Keyword arguments of ``run_design_study`` (``grid``, ``mesh``, ``workers``, ...).
    spec_path : path-like, optional
        Where ``requirements`` came from (recorded as provenance only).
    progress : callable, optional
        ``progress(step, index, total)`` before each step of :data:`STEPS`.

    Returns
    -------
    UnitDesign
        The typed result; ``unit.json`` in ``out_dir`` holds its ``to_dict()``.

    Raises
    ------
    Infeasible
        No design meets the requirements (``exc.result`` is the least-violating one).
    """
    from .spring.plots import plot_spring

    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    seconds: dict[str, float] = {}
    files: dict[str, Path] = {}

    def step(name: str) -> float:
        if progress is not None:
            progress(name, STEPS.index(name), len(STEPS))
        return time.perf_counter()

    # 1. optimise ------------------------------------------------------------
    t = step("optimise")
    strain_fn = None
    if requirements.max_bladder_strain is not None:
        from functools import partial

        from .bladder.check import strain_bound

        strain_fn = partial(strain_bound, material=requirements.bladder_material)
    res = optimise(requirements, seed=seed, bladder_strain_fn=strain_fn)  # raises Infeasible
    files["design"] = save_design(out / "design.json", res.evaluation, requirements, optimiser=res.summary())
    lin = res.evaluation.linearity_error
    files["design_force_png"] = _save(
        plot_spring(res.design.gas_spring, extra_charges_MPa=(1.0, 2.0),
                    title=f"optimised design ({res.layout} layout): linearity {100 * lin:.2f} %"), out / "design_force.png")
    seconds["optimise"] = time.perf_counter() - t

    # 2. spring curve --------------------------------------------------------
    t = step("spring")
    gs = res.design.gas_spring
    curve = spring_curve(gs)
    sp = write_spring_files(gs, out / "spring", layout=res.layout)
    files["spring_csv"], files["spring_png"] = sp["csv"], sp["png"]
    seconds["spring"] = time.perf_counter() - t

    # 3. CAD -----------------------------------------------------------------
    t = step("cad")
    manifest = bom = drawings = None
    if cad:
        from .cad import build_cad, write_cad
        from .report.bom import write_bom
        from .report.drawing import write_drawings

        model = build_cad(res.design)
        manifest = write_cad(res.design, out / "cad", renders=renders, show_progress=False, model=model)
        files["cad"] = out / "cad"
        drawings = write_drawings(model, out / "cad")
        files["drawings_pdf"] = Path(drawings.pdf)
        bom = write_bom(model, out / "cad", requirements.bladder_material)
        files["bom_csv"] = out / "cad" / "bom.csv"
    seconds["cad"] = time.perf_counter() - t

    # 4. bladder, with the requirements' silicone ------------------------------
    t = step("bladder")
    bl = check_bladder(res.design, requirements.bladder_material, n_elements=bladder_elements)
    brep = write_bladder_report(res.design, out / "bladder", requirements.bladder_material,
                                n_elements=bladder_elements, result=bl)  # solved once
    files["bladder_json"] = brep.path("json")  # bladder.json lists names in its folder
    files["bladder_png"] = brep.path("png")
    seconds["bladder"] = time.perf_counter() - t

    # 5. actuator parameters ---------------------------------------------------
    t = step("actuator")
    act = actuator_from_spring(gs, name="design")
    act_dir = out / "actuator"
    act_dir.mkdir(exist_ok=True)
    files["actuator_json"] = act_dir / "actuator.json"
    files["actuator_json"].write_text(json.dumps(
        {**_actuator_dict(act),
         "mapping": "K = 2 r^2 k, D = 2 r^2 L(gamma), paper section 3.4 (vvea_design.actuator.model)"},
        indent=2) + "\n")
    seconds["actuator"] = time.perf_counter() - t

    # 6. the design's actuator study -------------------------------------------
    t = step("actuator_study")
    study = None
    if actuator_study:
        from .actuator.design_study import run_design_study

        study = run_design_study(res.design, out_dir=act_dir, **(study_options or {}))
        files["actuator_study_json"] = Path(study.files.summary_json)
    seconds["actuator_study"] = time.perf_counter() - t

    unit = UnitDesign(requirements=requirements, optimisation=res, spring=curve, bladder=bl, actuator=act,
                      cad_manifest=manifest, bom=bom, drawings=drawings, actuator_study=study, out_dir=out, files=dict(files),
                      seconds=dict(seconds), seed=seed, version=__version__,
                      spec_path=None if spec_path is None else str(spec_path))

    # 7. report ----------------------------------------------------------------
    t = step("report")
    if report:
        from .report.html import unit_report

        files["report"] = unit_report(unit).write(out / "report.html")
    seconds["report"] = time.perf_counter() - t
    unit = replace(unit, files=dict(files), seconds=dict(seconds))
    files["unit_json"] = out / "unit.json"
    unit = replace(unit, files=dict(files))
    files["unit_json"].write_text(json.dumps(unit.to_dict(), indent=2, default=_json_default) + "\n")
    return unit


def _relative_tree(value: Any, folder: Path) -> Any:
    """``value`` with every path string inside ``folder`` made relative to it (the folder is moved at the end)."""
    if isinstance(value, dict):
        return {k: _relative_tree(v, folder) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [_relative_tree(v, folder) for v in value]
    if isinstance(value, (str, Path)) and str(value).startswith(str(folder) + "/"):
        return str(Path(value).relative_to(folder))
    return value


def _actuator_dict(act: Actuator) -> dict[str, Any]:
    from dataclasses import asdict

    return asdict(act)


def _json_default(v: Any) -> Any:
    if isinstance(v, np.generic):
        return v.item()
    if isinstance(v, np.ndarray):
        return v.tolist()
    if isinstance(v, Path):
        return str(v)
    raise TypeError(f"not JSON-serialisable: {type(v).__name__}")
