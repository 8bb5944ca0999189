"""The main job as one function: requirements in, a checked unit and its folder out.

:func:`design_unit` runs the jobs of :mod:`vvea_design.jobs` in order, each into its part of the unit
folder::

    requirements -> optimise (design.json) -> spring curve (spring/) -> CAD set (cad/) -> FE of the
    pressure-bearing pieces (structure/) -> bladder check
    with the requirements' silicone (bladder/) -> actuator parameters and the design's actuator study
    (actuator/) -> report.html

and returns a :class:`UnitDesign` (frozen, ``to_dict()`` is ``unit.json``). The folder lands whole or not
at all. The ``vvea design`` command only calls it and prints the result.
"""

from __future__ import annotations

import contextlib
import json
import time
from collections.abc import Callable, Iterator
from dataclasses import asdict, dataclass, replace
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from . import __version__
from .actuator.model import Actuator
from .bladder.result import BladderResult
from .jobs.bladder import check_bladder
from .jobs.cad import build_cad
from .jobs.common import OptionError, PathLike, check_option, check_out, folder, inputs_kept, moved, requirements_of
from .jobs.spring import force_plot_path, optimise, spring_report, write_spring_files
from .jobs.structure import check_structure
from .jobs.studies import design_study_settings, run_design_study, target_stiffness
from .spring.curve import SpringCurve, spring_curve
from .spring.optimise import Infeasible, OptimisationResult
from .spring.requirements import Requirements
from .report.html.verification import VERIFICATION_KEYS, verification_rows

if TYPE_CHECKING:  # the CAD kernel and CasADi load only when the job needs them (`vvea spring` stays light)
    from .actuator.design_study import DesignStudy
    from .cad.manifest import CadManifest
    from .report.bom import BillOfMaterials
    from .report.drawing import DrawingSet
    from .structure.check import StructureResult

__all__ = ["SpringCurve", "UnitDesign", "design_unit", "spring_curve", "write_spring_files", "STEPS",
           "Infeasible"]

#: The steps of :func:`design_unit` in order (the names its ``progress`` callback receives).
STEPS = ("optimise", "spring", "cad", "structure", "bladder", "actuator", "actuator_study", "report")


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
    structure: StructureResult | None = None  #: FE check of the pressure-bearing pieces (None: no CAD)

    @property
    def passes(self) -> bool:
        """Every constraint met, the bladder check passed, and when the CAD was made every pressure-bearing piece
        keeps its required factor in the FE and the parts go together in order with no O-ring over a thread or a
        sharp edge (the CAD's assembly check, ISO 3601-2) and every joint and port is sealed (the leak audit)."""
        m = self.cad_manifest
        cad_ok = m is None or (m.assembly_passes is not False and not m.unsealed_paths)
        return bool(self.optimisation.evaluation.feasible and self.bladder.passes
                    and (self.structure is None or self.structure.passes) and cad_ok)

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
            "actuator": asdict(self.actuator),
            "bom": None if self.bom is None else self.bom.to_dict(),
            "drawings": None if self.drawings is None else self.drawings.to_dict(),
            "structure": None if self.structure is None else self.structure.to_dict(),
            "verification": [dict(zip(VERIFICATION_KEYS, row)) for row in verification_rows(self)],
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


class _Steps:
    """Times each step of :data:`STEPS` and announces it to ``progress(step, index, total)``."""

    def __init__(self, progress: ProgressFn | None):
        self.progress = progress
        self.seconds: dict[str, float] = {}

    @contextlib.contextmanager
    def __call__(self, name: str) -> Iterator[None]:
        from .parallel import interrupt_noted

        if interrupt_noted():  # a Ctrl-C a library printed and dropped: stop before the next step
            raise KeyboardInterrupt(f"interrupted (Ctrl-C) before the {name} step")
        if self.progress is not None:
            self.progress(name, STEPS.index(name), len(STEPS))
        t = time.perf_counter()
        yield
        self.seconds[name] = time.perf_counter() - t


def design_unit(
    requirements: Requirements | PathLike | None,
    out: PathLike,
    *,
    seed: int = 0,
    renders: bool = True,
    cad: bool = True,
    actuator_study: bool = True,
    report: bool = True,
    bladder_elements: int | None = None,
    study_grid: Any = None,
    study_mesh_n: int | None = None,
    safety_mesh_n: int | None = None,
    workers: int | None = None,
    study_target_K_Nm_per_rad: float | None = None,
    spec_path: PathLike | None = None,
    progress: ProgressFn | None = None,
) -> UnitDesign:
    """Run the main job: optimise the spring, then spring curve, CAD, bladder check, actuator, report.

    Parameters
    ----------
    requirements : Requirements, path-like or None
        What the unit must meet (mm, MPa, N/mm; ``bladder_material`` names the silicone checked), a
        requirements TOML file, or None for the paper's unit.
    out : path-like
        Folder for everything, written whole or not at all: ``design.json``, ``design_force.png``,
        ``spring/``, ``cad/`` (with drawings and ``bom.csv``), ``structure/`` (the FE's stress pictures),
        ``bladder/``, ``actuator/``, ``unit.json``, ``report.html``.
    seed : int
        Seed of the optimiser's global search (same seed, same design).
    renders : bool
        Make the CAD PNG renders (off-screen pyvista).
    cad : bool
        Build and export the CAD set, its drawings and bill of materials, and check its pressure-bearing
        pieces by FE (False skips them, the FE and the 3-D view of the report).
    actuator_study : bool
        Run the design's own actuator study (rest-to-rest against VVEA, SEA, LWR and the torque step,
        :func:`vvea_design.jobs.studies.run_design_study`) into ``actuator/``.
    report : bool
        Write ``report.html``.
    bladder_elements : int, optional
        Finite elements along the bladder meridian (None: the check's default).
    study_grid : Grid, (sequence of float, sequence of float) or str, optional
        Rest-to-rest amplitudes (rad) and periods (s) of the actuator study (text ``"A1,A2:T1,T2"`` too);
        None: 3 x 3 cases over the paper's grid.
    study_mesh_n : int, optional
        Collocation intervals of each rest-to-rest case of the actuator study (None: 64).
    safety_mesh_n : int, optional
        Collocation intervals of the actuator study's torque steps (None: 100, clustered at the step).
    workers : int, optional
        Worker processes of the actuator study (None: all cores but one, which the CAD beside it uses; at least 1).
    study_target_K_Nm_per_rad : float, optional
        Joint stiffness (N m/rad) at which the actuator study compares the design with an SEA of the same K
        (None: the paper's 362); the study's second run is at full charge.
    spec_path : path-like, optional
        Where ``requirements`` came from (recorded as provenance only; a file given as ``requirements``
        records itself).
    progress : callable, optional
        ``progress(step, index, total)`` before each step of :data:`STEPS`.

    Returns
    -------
    UnitDesign
        The typed result; ``unit.json`` in ``out`` holds its ``to_dict()``.

    Raises
    ------
    SpecError
        Requirements that cannot be read or hold a wrong value.
    OptionError
        A bad study grid, mesh or stiffness (named ``study_grid``, ``study_mesh_n``, ``safety_mesh_n``,
        ``study_target_K_Nm_per_rad``), ``seed``, ``workers`` or ``bladder_elements``, before any work.
    OutputError
        ``out`` cannot be written, or is the requirements file (before any work).
    Infeasible
        No design meets the requirements (``exc.result`` is the least-violating one); nothing is written.
    """
    check_option("seed", seed, "seed")
    check_option("workers", workers, "workers")
    check_option("bladder_elements", bladder_elements, "bladder_elements")
    inputs_kept((out,), (requirements, spec_path))
    req, read_from = requirements_of(requirements)
    spec = spec_path if spec_path is not None else read_from
    try:
        design_study_settings(study_grid, study_mesh_n, safety_mesh_n)  # every option checked before any work
        target_stiffness(study_target_K_Nm_per_rad, "study_target_K_Nm_per_rad")
    except OptionError as exc:
        raise exc.renamed({"grid": "study_grid", "mesh_n": "study_mesh_n"}.get(exc.option, exc.option)) from None
    check_out(out)
    study = dict(grid=study_grid, mesh_n=study_mesh_n, safety_mesh_n=safety_mesh_n, workers=workers,
                 target_K_Nm_per_rad=study_target_K_Nm_per_rad)
    with folder(out, "design") as tmp:  # the whole unit lands in `out` only when every step succeeded
        unit = _write_unit(req, tmp, seed=seed, renders=renders, cad=cad, study=study if actuator_study else None,
                           report=report, bladder_elements=bladder_elements,
                           spec_path=None if spec is None else str(spec), progress=progress)
    return _relocated(unit, tmp, Path(out))


def _write_unit(req: Requirements, out: Path, *, seed: int, renders: bool, cad: bool, study: dict | None,
                report: bool, bladder_elements: int | None, spec_path: str | None,
                progress: ProgressFn | None) -> UnitDesign:
    """Every step of :func:`design_unit` into ``out``, each through its job.

    The actuator study needs only the design: it runs in a thread beside the CAD, the FE and the bladder check
    (its solves in worker processes started from a fork server, :func:`vvea_design.parallel.clean_workers`; all
    cores but the one the CAD uses unless ``workers`` says otherwise), and the ``actuator_study`` step waits for
    it. Its time in ``seconds`` is its own run, overlapping those steps.
    """
    step = _Steps(progress)
    files: dict[str, Path] = {}
    with step("optimise"):
        res = optimise(req, seed=seed, out=out / "design.json")  # raises Infeasible
        files["design"], files["design_force_png"] = out / "design.json", force_plot_path(out / "design.json")
    with step("spring"):
        sp = spring_report(res.design, out=out / "spring")
        files["spring_csv"], files["spring_png"] = sp.files["csv"], sp.files["png"]
    with step("actuator"):  # before the study, which writes into the same folder
        act = _write_actuator(res.design.gas_spring, out / "actuator")
        files["actuator_json"] = out / "actuator" / "actuator.json"
    if study is not None and study.get("workers") is None:  # the CAD's thread keeps one core for itself
        from .parallel import default_workers

        study = {**study, "workers": max(1, default_workers() - 1)}
    with _beside(run_design_study if study is not None else None, res.design, out=out / "actuator",
                 **(study or {})) as study_run:
        cad_set = None
        with step("cad"):
            if cad:
                cad_set = build_cad(res.design, out=out / "cad", renders=renders, silicone=req.bladder_material,
                                    progress=False)
                files["cad"], files["drawings_pdf"] = out / "cad", cad_set.drawings.pdf
                files["bom_csv"] = out / "cad" / "bom.csv"
        structure = None
        with step("structure"):
            if cad_set is not None:
                structure = check_structure(cad_set, out=out / "structure")
                files["structure"] = out / "structure"
        with step("bladder"):
            bl = check_bladder(res.design, material=req.bladder_material, elements=bladder_elements,
                               out=out / "bladder", progress=False)
            files["bladder_json"], files["bladder_png"] = bl.path("json"), bl.path("png")  # bladder.json names its folder's files
        ds = None
        with step("actuator_study"):
            if study is not None:
                ds, study_seconds = study_run()
                files["actuator_study_json"] = Path(ds.files.summary_json)
    seconds = dict(step.seconds)
    if ds is not None:
        seconds["actuator_study"] = study_seconds
    unit = UnitDesign(requirements=req, optimisation=res, spring=sp.curve, bladder=bl.result, actuator=act,
                      cad_manifest=None if cad_set is None else cad_set.manifest,
                      bom=None if cad_set is None else cad_set.bom,
                      drawings=None if cad_set is None else cad_set.drawings, actuator_study=ds, out_dir=out,
                      files=dict(files), seconds=seconds, seed=seed, version=__version__,
                      spec_path=spec_path, structure=structure)
    with step("report"):
        if report:
            from .report.html import unit_report

            files["report"] = unit_report(unit).write(out / "report.html")
    files["unit_json"] = out / "unit.json"
    unit = replace(unit, files=dict(files), seconds={**seconds, "report": step.seconds["report"]})
    files["unit_json"].write_text(json.dumps(unit.to_dict(), indent=2, default=_json_default) + "\n")
    return unit


@contextlib.contextmanager
def _beside(fn: Callable[..., Any] | None, *args: Any, **kwargs: Any) -> Iterator[Callable[[], tuple[Any, float]]]:
    """Run ``fn(*args, **kwargs)`` in a thread while the block runs; the block gets ``wait() -> (result, s)``.

    Worker pools ``fn`` starts come from a fork server (the block's thread is busy: a fork would copy its locks,
    :func:`vvea_design.parallel.clean_workers`). Leaving the block waits for ``fn`` (its files are in the folder
    the block writes); when the block raised (an error, Ctrl-C, SIGTERM) ``fn``'s work is cancelled first and the
    block's exception wins. ``fn`` None: nothing runs.
    """
    from concurrent.futures import ThreadPoolExecutor

    from .parallel import WorkersHandle, clean_workers

    if fn is None:
        yield lambda: (None, 0.0)
        return
    handle = WorkersHandle()

    def timed() -> tuple[Any, float]:
        t = time.perf_counter()
        with clean_workers(handle):
            result = fn(*args, **kwargs)
        return result, time.perf_counter() - t

    with ThreadPoolExecutor(max_workers=1, thread_name_prefix="vvea-actuator-study") as pool:
        future = pool.submit(timed)
        try:
            yield future.result
        except BaseException:
            handle.cancel()
            future.exception()  # the thread has ended before the folder is removed
            raise
        future.exception()


def _write_actuator(spring, folder_: Path) -> Actuator:
    """``actuator.json``: the joint-level K and D range of the unit (section 3.4 mapping, SI)."""
    from .actuator.model import actuator_from_spring

    act = actuator_from_spring(spring, name="design")
    folder_.mkdir(exist_ok=True)
    (folder_ / "actuator.json").write_text(json.dumps(
        {**asdict(act), "mapping": "K = 2 r^2 k, D = 2 r^2 L(gamma), paper section 3.4 (vvea_design.actuator.model)"},
        indent=2) + "\n")
    return act


def _relocated(unit: UnitDesign, old: Path, new: Path) -> UnitDesign:
    """``unit`` with the paths it holds moved from the temporary folder ``old`` into ``new``."""
    if old == new:
        return unit
    drawings, study, structure = unit.drawings, unit.actuator_study, unit.structure
    if structure is not None:
        structure = replace(structure, pieces=tuple(
            replace(p, figure=None if p.figure is None else str(moved(Path(p.figure), old, new)))
            for p in structure.pieces))
    if drawings is not None:
        drawings = replace(drawings, svg=tuple(moved(Path(p), old, new) for p in drawings.svg),
                           pdf=moved(Path(drawings.pdf), old, new))
    if study is not None:
        study = replace(study, files=type(study.files)(*(None if p is None else moved(Path(p), old, new)
                                                         for p in asdict(study.files).values())))
    return replace(unit, out_dir=new, drawings=drawings, actuator_study=study, structure=structure,
                   files={k: moved(Path(v), old, new) for k, v in unit.files.items()})


def _relative_tree(value: Any, folder_: Path) -> Any:
    """``value`` with every path string inside ``folder_`` made relative to it (the folder is moved at the end)."""
    if isinstance(value, dict):
        return {k: _relative_tree(v, folder_) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [_relative_tree(v, folder_) for v in value]
    if isinstance(value, (str, Path)) and str(value).startswith(str(folder_) + "/"):
        return str(Path(value).relative_to(folder_))
    return value


def _json_default(v: Any) -> Any:
    if isinstance(v, np.generic):
        return v.item()
    if isinstance(v, np.ndarray):
        return v.tolist()
    if isinstance(v, Path):
        return str(v)
    raise TypeError(f"not JSON-serialisable: {type(v).__name__}")
