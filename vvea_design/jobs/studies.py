"""The actuator studies as jobs: ``vvea study rest-to-rest`` (paper section 5), ``vvea study safety``
(section 6) and the design's own study of ``vvea design`` (:func:`run_design_study`).

CasADi is imported when a study runs, not with this module.
"""

from __future__ import annotations

import json
import math
import tempfile
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field, replace
from pathlib import Path
from typing import TYPE_CHECKING, Any, Literal

from ..parallel import Terminated, note_interrupt
from .common import OptionError, PathLike, check_option, check_out, check_scheduler_option, design_of, folder, moved

if TYPE_CHECKING:
    from rich.console import Console

    from ..actuator.design_study import DesignStudy
    from ..actuator.sensitivity import DesignSensitivity
    from ..actuator.model import Actuator
    from ..actuator.ocp import Mesh
    from ..actuator.rest_to_rest import Grid, RestToRestSummary
    from ..actuator.safety import SafetyStudy
    from ..spring.design import Design
    from ..spring.gas_spring import GasSpring

__all__ = ["RestToRestRun", "run_rest_to_rest", "cases_saved", "print_rest_to_rest", "Terminated", "note_interrupt",
           "SafetyRun", "run_safety", "design_study_settings", "run_design_study", "design_study_lines",
           "target_stiffness", "run_design_sensitivity"]

#: A rest-to-rest grid: a named one, a :class:`~vvea_design.actuator.rest_to_rest.Grid`,
#: ``(amplitudes_rad, periods_s)`` or the text ``"A1,A2:T1,T2"``.
GridLike = Any


def _grid(grid: GridLike, option: str = "grid", named: bool = True) -> Grid | str:
    """``grid`` as the sweep takes it: a known name (``named``), or a checked :class:`Grid`.

    A text that is not a name is read as ``"A1,A2,..:T1,T2,.."`` (rad:s), the command line's form.
    """
    from ..actuator.rest_to_rest import GRIDS, Grid

    if isinstance(grid, Grid):
        return grid
    if named and isinstance(grid, str) and grid in GRIDS:
        return grid
    try:
        if isinstance(grid, str):
            a, t = grid.split(":")
            return Grid(tuple(float(x) for x in a.split(",")), tuple(float(x) for x in t.split(",")))
        amplitudes, periods = grid
        return Grid(tuple(float(x) for x in amplitudes), tuple(float(x) for x in periods))
    except (TypeError, ValueError) as exc:
        names = f"one of {sorted(GRIDS)} or " if named else ""
        from ..messages import show

        raise OptionError(option, f"must be {names}'A1,A2,..:T1,T2,..' (rad:s), got {show(grid)} "
                          f"({str(exc)[:400]})", "{option} {reason}") from None


def cases_saved(out: PathLike) -> int:
    """Complete cases in ``out/results.csv`` of a rest-to-rest sweep (what an interrupted sweep keeps).

    Parameters
    ----------
    out : path-like
        The sweep's folder.

    Returns
    -------
    int
        Cases with a row for every setting (0 when there is no results file).
    """
    import csv

    from ..actuator.multistart import RESULT_COLUMNS

    res = Path(out) / "results.csv"
    if not res.exists():
        return 0
    by_case: dict[str, set] = {}
    settings: set = set()
    with res.open(newline="") as fh:
        for row in csv.DictReader(fh):
            if None in row or any(row.get(c) is None for c in RESULT_COLUMNS):
                continue
            by_case.setdefault(row["case_id"], set()).add(row["setting"])
            settings.add(row["setting"])
    return sum(1 for s in by_case.values() if s == settings)


def print_rest_to_rest(summary: RestToRestSummary, console: Console) -> None:
    """Table 5 of a sweep against the paper's, and what was left out, on ``console``.

    Parameters
    ----------
    summary : RestToRestSummary
        The sweep's result (fractions, rmse in rad).
    console : rich.console.Console
        Where to print.
    """
    from rich.table import Table

    st = summary.statistics
    tab = Table(title="Table 5: ours (all solved cases / cases where both trajectories are valid) vs paper")
    for c in ("statistic", "ours (all)", "ours (both valid)", "paper"):
        tab.add_column(c)
    paper = st.paper_table5
    xs = list(dict.fromkeys(k.split("_vs_")[0] for k in st.pairs))
    for X in xs:
        for Y in ("SEA", "LWR"):
            a, v = st.pair(X, Y, "all"), st.pair(X, Y, "valid")
            if not a:
                continue
            fa = a.fraction_X_beats_Y
            fv = v.fraction_X_beats_Y if v else None
            pb = paper.get(f"{X}_beats_{Y}")
            tab.add_row(f"{X} beats {Y}", f"{fa:.1%}" if fa is not None else "-",
                        f"{fv:.1%}" if fv is not None else "-", f"{pb:.1%}" if pb is not None else "-")
            ra, rv = a.meanrmse_Y_over_X, v.meanrmse_Y_over_X if v else None
            pr = paper.get(f"meanrmse_{Y}_over_{X}")
            tab.add_row(f"mean rmse {Y} / {X}", f"{ra:.3f}" if ra else "-", f"{rv:.3f}" if rv else "-",
                        f"{pr:.3f}" if pr is not None else "-")
    console.print(tab)
    g = st.ivvea_vs_sea_guarantee
    if g:
        console.print(f"iVVEA worse than SEA in {g['iVVEA_worse_than_SEA_cases']} of {g['n_cases']} cases")
    console.print(f"winning starts: {json.dumps(st.winning_starts)}")
    console.print(f"solver failures: {st.solver_failures['count']}")
    unv = st.unverified
    if unv.get("count"):
        console.print(f"left out of every statistic, trajectory not reproduced by re-simulation: {unv['count']} "
                      f"({', '.join(unv['cases'][:8])}{' ...' if unv['count'] > 8 else ''})")
    else:
        console.print("every solved trajectory was reproduced by re-simulation")


@dataclass(frozen=True)
class RestToRestRun:
    """What :func:`run_rest_to_rest` found: the sweep's summary, its text and the files written."""

    summary: RestToRestSummary  #: Table 5 statistics of every case in results.csv, and the run
    summary_text: str  #: the Table 5 comparison as ``vvea study rest-to-rest`` prints it
    files: dict[str, Path] = field(default_factory=dict)  #: by role (empty: nothing kept)

    @property
    def solver_failures(self) -> int:
        """Optimal-control problems that failed to solve (a failed solve never passes for a result)."""
        return int(self.summary.statistics.solver_failures.get("count", 0))

    def to_dict(self) -> dict[str, Any]:
        """JSON-ready.

        Returns
        -------
        dict
            ``summary`` (the ``summary.json`` content: fractions, rmse in rad, times in s), ``summary_text``
            and ``files`` (paths as text).
        """
        return {"summary": self.summary.to_dict(), "summary_text": self.summary_text,
                "files": {k: str(v) for k, v in self.files.items()}}


def _settings(design, mapping: dict) -> list[Actuator]:
    """The paper's settings, plus the design's actuator (named ``design``) when given."""
    from ..actuator.model import PAPER_SETTINGS, from_design_json

    settings = list(PAPER_SETTINGS.values())
    if design is None:
        if mapping:
            raise OptionError(" and ".join(mapping), "apply to a design only", "{option} {reason}")
        return settings
    from ..actuator.design_study import design_actuator

    try:
        act = (from_design_json(design, **mapping) if isinstance(design, (str, Path))
               else design_actuator(design, **mapping))
    except ValueError as exc:
        raise OptionError("design", f"{design}: {exc}", "{option} {reason}") from None
    return [*settings, act]


def run_rest_to_rest(out: PathLike | None = None, *, grid: GridLike = "paper",
                     design: Design | GasSpring | PathLike | None = None, pulley_radius_m: float | None = None,
                     p2_MPa: float | None = None, gamma_min_deg: float | None = None,
                     gamma_max_deg: float | None = None, mesh_n: int | None = None,
                     fine_mesh_n: int | Literal["auto"] | None = "auto", workers: int | None = None,
                     scheduler: str | None = None, restart: bool = False, progress: bool = True) -> RestToRestRun:
    """Rest-to-rest optimal control sweep of VVEA, iVVEA, SEA and LWR (+ a design), Table 5 (``vvea study rest-to-rest``).

    Resumes an interrupted sweep in the same ``out`` (``results.csv`` grows case by case there); the summary,
    figures and ``report.html`` land whole at the end.

    Parameters
    ----------
    out : path-like, optional
        The sweep's folder; None: a temporary folder that is removed (no figures, no report).
    grid : str, Grid or (sequence of float, sequence of float)
        ``"paper"``, ``"coarse"``, or the amplitudes (rad) and periods (s), also as text ``"A1,A2:T1,T2"``.
    design : Design, GasSpring or path-like, optional
        A design (or its design JSON) whose actuator joins as the setting ``design``.
    pulley_radius_m : float, optional
        Pulley radius r of the design's actuator (default: the paper's stiffness at the paper's spring).
    p2_MPa : float, optional
        Recharge the design's spring to this chamber-2 pressure.
    gamma_min_deg, gamma_max_deg : float, optional
        Throttle angles used (deg; defaults: the actuator mapping's).
    mesh_n : int, optional
        Collocation intervals of the multi-start (a multiple of 4; None: 64).
    fine_mesh_n : int, "auto" or None
        Intervals of the mesh the results are reported on (a multiple of 4); ``"auto"``: 192 with the
        default ``mesh_n``, none otherwise; None: none.
    workers : int, optional
        Local worker processes (None: all cores).
    scheduler : str, optional
        Dask scheduler address (``tcp://host:port``).
    restart : bool
        Discard existing results instead of resuming.
    progress : bool
        Show a progress bar on stderr.

    Returns
    -------
    RestToRestRun
        The summary (fractions, rmse in rad), its text and the files written.

    Raises
    ------
    OptionError
        An unknown grid, a bad design mapping, a throttle range outside 0 ... 360 deg or upside down, a
        charge or pulley radius no real unit has, a bad ``workers`` or an unreachable ``scheduler`` (all
        checked before anything is solved).
    OutputError
        ``out`` cannot be written (before anything is solved).
    ValueError
        A mesh that is not a multiple of 4, or an ``out`` holding a different sweep without ``restart``.
    KeyboardInterrupt, Terminated
        The sweep was interrupted; the finished cases stay in ``out/results.csv`` (:func:`cases_saved`).
    """
    grid_spec = _grid(grid)
    _check_mapping(pulley_radius_m, p2_MPa, gamma_min_deg, gamma_max_deg)
    check_option("mesh_intervals", mesh_n, "mesh_n")
    check_option("mesh_intervals", None if fine_mesh_n == "auto" else fine_mesh_n, "fine_mesh_n")
    check_option("workers", workers, "workers")
    check_scheduler_option(scheduler)
    mapping = {k: v for k, v in dict(pulley_radius_m=pulley_radius_m, p2_MPa=p2_MPa, gamma_min_deg=gamma_min_deg,
                                     gamma_max_deg=gamma_max_deg).items() if v is not None}
    if design is not None and isinstance(design, (str, Path)) and not Path(design).exists():
        raise OptionError("design", f"file {design} does not exist", "{option}: {reason}")
    if p2_MPa is not None and design is not None:
        _within_rating(design, p2_MPa)
    settings = _settings(design, mapping)
    check_out(out)
    from ..actuator.multistart import DEFAULT_MESH
    from ..actuator.ocp import Mesh
    from ..actuator.rest_to_rest import run_rest_to_rest as sweep

    mesh = DEFAULT_MESH if mesh_n is None else Mesh(mesh_n, DEFAULT_MESH.degree)
    fine = fine_mesh_n if fine_mesh_n in ("auto", None) else Mesh(fine_mesh_n, DEFAULT_MESH.degree)
    options = dict(grid=grid_spec, settings=settings, mesh=mesh, fine_mesh=fine, workers=workers, scheduler=scheduler,
                   restart=restart, progress=progress)
    if out is None:
        with tempfile.TemporaryDirectory() as scratch:
            summary = sweep(scratch, **options, figures=False)
        return RestToRestRun(summary, _rest_to_rest_text(summary))
    summary = sweep(out, **options)
    text = _rest_to_rest_text(summary)
    from ..outputs import output_files
    from ..report.html import folder_report

    out = Path(out)
    with output_files(out / "report.html", option="") as (tmp_report,):  # whole or not at all
        folder_report("vvea study rest-to-rest", out, summary_text=text, data=summary.to_dict(),
                      provenance={"grid": grid, "design": design, "mesh_n": mesh_n, "fine_mesh_n": fine_mesh_n}
                      ).write(tmp_report)
    names = {"results_csv": "results.csv", "summary_json": "summary.json", "best_map_png": "best_map.png",
             "trajectory_png": "trajectory.png", "report_html": "report.html"}
    return RestToRestRun(summary, text, {k: out / v for k, v in names.items()})


def _within_rating(design: Any, p2_MPa: float) -> None:
    """Refuse a study charge above the design's rating (:func:`vvea_design.jobs.rating.charge_rating`: the
    ``max_charge_MPa`` it was optimised for, or the charge its walls are sized for); a bare gas spring has none."""
    from .rating import check_charge

    check_charge(design, p2_MPa)


def _check_mapping(pulley_radius_m: float | None, p2_MPa: float | None, gamma_min_deg: float | None,
                   gamma_max_deg: float | None) -> None:
    """The design mapping's numbers in the ranges a real actuator has, the throttle range the right way up."""
    check_option("pulley_radius_m", pulley_radius_m, "pulley_radius_m")
    check_option("charge_MPa", p2_MPa, "p2_MPa")
    check_option("valve_deg", gamma_min_deg, "gamma_min_deg")
    check_option("valve_deg", gamma_max_deg, "gamma_max_deg")
    highest = max((g for g in (gamma_min_deg, gamma_max_deg) if g is not None), default=None)
    if highest is not None and 0 < highest < 2 * math.pi and any(g != int(g) for g in (gamma_min_deg, gamma_max_deg)
                                                                 if g is not None):
        which = "gamma_max_deg" if gamma_max_deg is not None else "gamma_min_deg"
        raise OptionError(which, f"= {highest:g}: a throttle range that ends below {2 * math.pi:.4g} deg with "
                          f"fractional angles looks like radians ({highest:g} rad is {math.degrees(highest):.4g} deg); "
                          "give the angles in degrees (the paper's range is 50 ... 120 deg)", "{option} {reason}")
    if gamma_min_deg is not None and gamma_max_deg is not None and gamma_min_deg > gamma_max_deg:
        raise OptionError("gamma_min_deg", f"({gamma_min_deg:g} deg) must not exceed the highest throttle angle "
                          f"({gamma_max_deg:g} deg)",
                          "{option} {reason}")


def _rest_to_rest_text(summary: RestToRestSummary) -> str:
    from ..report.html import recorded_text

    return recorded_text(lambda c: print_rest_to_rest(summary, c))


# ---------------------------------------------------------------------------------------------- safety
@dataclass(frozen=True)
class SafetyRun:
    """What :func:`run_safety` found: the torque-step study, its text and the files written."""

    study: SafetyStudy  #: every case (objective, mean / max D in N m s/rad, t95 in s, status)
    summary_text: str  #: the table ``vvea study safety`` prints
    files: dict[str, Path] = field(default_factory=dict)  #: by role (empty: nothing written)

    @property
    def solver_failures(self) -> int:
        """Torque-step cases that failed to solve."""
        return sum(1 for c in self.study.cases if not c.success)

    def to_dict(self) -> dict[str, Any]:
        """JSON-ready.

        Returns
        -------
        dict
            ``study`` (the ``safety.json`` content, SI), ``summary_text`` and ``files`` (paths as text).
        """
        return {"study": self.study.to_dict(), "summary_text": self.summary_text,
                "files": {k: str(v) for k, v in self.files.items()}}


def _safety_text(study: SafetyStudy, tau_ref_Nm: float) -> str:
    from rich.table import Table

    from ..report.html import recorded_text

    tab = Table(title=f"{tau_ref_Nm:g} N m torque step")
    for c in ("case", "mean D (N m s/rad)", "max D", "t95 (ms)", "status"):
        tab.add_column(c)
    for c in study.cases:
        tab.add_row(c.name, f"{c.mean_D_Nms_per_rad:.1f}", f"{c.max_D_Nms_per_rad:.1f}",
                    f"{c.t95_s * 1e3:.1f}", c.status)
    return recorded_text(lambda con: con.print(tab))


def run_safety(out: PathLike | None = None, *, mesh_n: int | None = None, tau_ref_Nm: float | None = None,
               M_kgm2: float | None = None) -> SafetyRun:
    """The torque step of paper section 6 (Table 6, Fig. 14): variable damping vs fixed D = 31 and D = 200
    (``vvea study safety``).

    Parameters
    ----------
    out : path-like, optional
        Folder for ``safety.json``, ``safety_trajectories.csv``, ``safety.png`` and ``report.html``.
    mesh_n : int, optional
        Collocation intervals over the 0.5 s horizon, clustered at both ends (at least 4; None: the study's
        200).
    tau_ref_Nm : float, optional
        Torque step height, non-zero (None: the paper's 50 N m).
    M_kgm2 : float, optional
        Link inertia, > 0 (None: the paper's almost fixed link, 1e4 kg m²).

    Returns
    -------
    SafetyRun
        The study (SI), its table as text and the files written.

    Raises
    ------
    OptionError
        ``mesh_n`` < 4, a zero or non-finite ``tau_ref_Nm``, or ``M_kgm2`` <= 0.
    OutputError
        ``out`` cannot be written (before anything is solved).
    """
    from ..actuator import safety

    mesh_n = safety.SAFETY_MESH.n_intervals if mesh_n is None else mesh_n
    tau_ref_Nm = safety.PAPER_TAU_REF_NM if tau_ref_Nm is None else tau_ref_Nm
    M_kgm2 = safety.PAPER_LINK_INERTIA_KGM2 if M_kgm2 is None else M_kgm2
    if mesh_n < 4:
        raise OptionError("mesh_n", f"must be >= 4 intervals, got {mesh_n}", "{option} {reason}")
    check_option("mesh_intervals", mesh_n, "mesh_n")
    if not (math.isfinite(tau_ref_Nm) and tau_ref_Nm != 0):
        raise OptionError("tau_ref_Nm", f"must be a non-zero torque in N m, got {tau_ref_Nm}", "{option} {reason}")
    if not (math.isfinite(M_kgm2) and M_kgm2 > 0):
        raise OptionError("M_kgm2", f"must be > 0, got {M_kgm2}", "{option} {reason}")
    check_out(out)
    mesh = replace(safety.SAFETY_MESH, n_intervals=mesh_n)
    if out is None:
        study = safety.solve_safety(mesh=mesh, tau_ref_Nm=tau_ref_Nm, M_kgm2=M_kgm2)
        return SafetyRun(study, _safety_text(study, tau_ref_Nm))
    from ..report.html import write_folder_report

    with folder(out, "safety") as tmp:  # results, figure and report land together
        study = safety.run_safety(tmp, mesh=mesh, tau_ref_Nm=tau_ref_Nm, M_kgm2=M_kgm2)
        text = _safety_text(study, tau_ref_Nm)
        write_folder_report("vvea study safety", tmp, summary_text=text, data=study.to_dict(), label=str(out),
                            provenance={"tau_ref_Nm": tau_ref_Nm, "mesh_n": mesh_n, "link_inertia_kgm2": M_kgm2})
    names = {"safety_json": "safety.json", "trajectories_csv": "safety_trajectories.csv", "safety_png": "safety.png",
             "report_html": "report.html"}
    return SafetyRun(study, text, {k: Path(out) / v for k, v in names.items()})


# ---------------------------------------------------------------------------------------------- design study
def design_study_settings(grid: GridLike | None = None, mesh_n: int | None = None,
                          safety_mesh_n: int | None = None) -> tuple[Grid, Mesh, Mesh]:
    """The checked grid and meshes of a design study (:func:`run_design_study`).

    Parameters
    ----------
    grid : Grid, (sequence of float, sequence of float) or str, optional
        Rest-to-rest amplitudes (rad) and periods (s), also as text ``"A1,A2:T1,T2"``; None: 3 x 3 cases
        over the paper's grid.
    mesh_n : int, optional
        Collocation intervals of each rest-to-rest case (None: 64).
    safety_mesh_n : int, optional
        Collocation intervals of the torque steps (None: 100, clustered at the step).

    Returns
    -------
    (Grid, Mesh, Mesh)
        The grid (rad, s), the rest-to-rest mesh and the torque-step mesh.

    Raises
    ------
    OptionError
        A grid without positive amplitudes and periods, or a mesh of fewer than 4 intervals (names the option).
    """
    from ..actuator.design_study import DESIGN_GRID, DESIGN_MESH, DESIGN_SAFETY_MESH

    g = DESIGN_GRID if grid is None else _grid(grid, named=False)
    meshes = []
    for option, n, base in (("mesh_n", mesh_n, DESIGN_MESH), ("safety_mesh_n", safety_mesh_n, DESIGN_SAFETY_MESH)):
        try:
            meshes.append(base if n is None else replace(base, n_intervals=n))
        except ValueError as exc:
            raise OptionError(option, str(exc)) from None
    return g, meshes[0], meshes[1]


def run_design_study(design: Design | GasSpring | PathLike, *, out: PathLike | None = None,
                     grid: GridLike | None = None, mesh_n: int | None = None, safety_mesh_n: int | None = None,
                     workers: int | None = None, target_K_Nm_per_rad: float | None = None,
                     progress: Callable[[int, int, str], None] | None = None) -> DesignStudy:
    """A design's actuator against an SEA of the same stiffness and the paper's VVEA and LWR; the torque step.

    The study of ``vvea design`` (its ``actuator/`` folder): the design charged for the target joint
    stiffness (inside its pressure limits) against an SEA of that K, VVEA and LWR, then at full charge
    against an SEA of the full-charge K (two labelled runs), every case counted, with the unit's own
    damping range; rest-to-rest on a 3 x 3 grid and the 50 N m torque step.

    Parameters
    ----------
    design : Design, GasSpring or path-like
        The design, its gas spring, or its design JSON.
    out : path-like, optional
        Folder for ``results.csv``, ``design_study.json`` and the figures.
    grid : Grid, (sequence of float, sequence of float) or str, optional
        Rest-to-rest amplitudes (rad) and periods (s), also as text ``"A1,A2:T1,T2"``; None: 3 x 3 cases
        over the paper's grid.
    mesh_n : int, optional
        Collocation intervals of each rest-to-rest case (None: 64).
    safety_mesh_n : int, optional
        Collocation intervals of the torque steps (None: 100, clustered at the step).
    workers : int, optional
        Worker processes (None: all cores; 1: in this process).
    target_K_Nm_per_rad : float, optional
        Joint stiffness of the equal-stiffness run, N m/rad, > 0 (None: the paper's 362).
    progress : callable, optional
        ``progress(done, total, message)`` after each finished case.

    Returns
    -------
    DesignStudy
        Both runs (charge, K), the comparisons over every case (counts, rmse ratios), per-setting summaries,
        the damping range and its source, both torque steps (SI) and the files written.

    Raises
    ------
    OptionError
        A bad grid, mesh or target stiffness (before anything is solved).
    OutputError
        ``out`` cannot be written (before anything is solved).
    DesignFileError
        A design file that is missing or incomplete.
    """
    from ..actuator.design_study import StudyFiles, run_design_study as study_of

    g, mesh, safety_mesh = design_study_settings(grid, mesh_n, safety_mesh_n)
    target = target_stiffness(target_K_Nm_per_rad)
    check_out(out)
    d = design_of(design) if isinstance(design, (str, Path)) else design
    with folder(out, "design_study") as tmp:
        study = study_of(d, out_dir=tmp, progress=progress, workers=workers, grid=g, mesh=mesh, safety_mesh=safety_mesh,
                         target_K_Nm_per_rad=target)
    if out is None:
        return study
    f = study.files
    return replace(study, files=StudyFiles(*(None if p is None else moved(Path(p), tmp, Path(out)) for p in (
        f.results_csv, f.summary_json, f.map_png, f.trajectory_png, f.safety_png))))


def target_stiffness(target_K_Nm_per_rad: float | None, option: str = "target_K_Nm_per_rad") -> float:
    """The checked joint stiffness of a design study's equal-stiffness run.

    Parameters
    ----------
    target_K_Nm_per_rad : float, optional
        N m/rad (None: the paper's 362).
    option : str
        The caller's name for it (in the error).

    Returns
    -------
    float
        N m/rad, finite and > 0.

    Raises
    ------
    OptionError
        Not a finite positive stiffness.
    """
    from ..actuator.stiffness import PAPER_K_NM_PER_RAD

    if target_K_Nm_per_rad is None:
        return PAPER_K_NM_PER_RAD
    k = float(target_K_Nm_per_rad)
    if not (math.isfinite(k) and k > 0):
        raise OptionError(option, f"must be a positive joint stiffness in N m/rad, got {target_K_Nm_per_rad!r}")
    return k


def design_study_lines(study: DesignStudy) -> list[str]:
    """The design study as the ``vvea design`` command prints it: the damping range and its source, then per
    labelled run its charge and every comparison with every case counted.

    Parameters
    ----------
    study : DesignStudy
        A finished :func:`run_design_study`.

    Returns
    -------
    list of str
        One line each (damping N m s/rad, stiffness N m/rad, pressures MPa, counts of cases).
    """
    dmp = study.damping
    lines = [f"actuator study damping: D = {dmp.D_min_Nms_per_rad:.3g} ... {dmp.D_max_Nms_per_rad:.4g} N m s/rad "
             f"from {dmp.source} ({dmp.why})"]
    for r in study.runs:
        lines.append(f"[{r.label}] " + (r.charge.describe() if r.charge is not None
                                        else f"K = {r.actuator.K_Nm_per_rad:.4g} N m/rad"))
        for c in (c for c in study.comparisons if c.run == r.label):
            beats = "-" if c.fraction_design_beats is None else f"{100 * c.fraction_design_beats:.1f} %"
            ratio = "-" if c.meanrmse_other_over_design is None else f"{c.meanrmse_other_over_design:.3f}"
            lines.append(f"[{r.label}] {c.design} vs {c.other}: better in {c.design_beats} of {c.n_cases} cases "
                         f"({beats}), worse in {c.design_worse} (of those, {c.only_other_valid} where only "
                         f"{c.other} is valid), {c.neither_valid} neither valid; mean rmse {c.other}/design {ratio} "
                         f"over the {c.n_both_valid} cases both are valid")
    return lines


def run_design_sensitivity(design: Design | GasSpring | PathLike, *, out: PathLike | None = None,
                           target_K_Nm_per_rad: float | None = None, D_min_values: Sequence[float] | None = None,
                           D_max_values: Sequence[float] | None = None,
                           K_factors: Sequence[float] = (0.5, 0.75, 1.0, 1.5, 2.0), grid: GridLike | None = None,
                           mesh_n: int | None = None, workers: int | None = None,
                           progress: bool = True) -> DesignSensitivity:
    """Which property of the unit buys tracking: the design against an SEA of the same K as D_min, D_max and K move.

    Parameters
    ----------
    design : Design, GasSpring or path-like
        The design, its gas spring, or its design JSON.
    out : path-like, optional
        Folder for ``sensitivity.csv`` (every OCP), ``sensitivity.json`` and ``sensitivity.png``.
    target_K_Nm_per_rad : float, optional
        Joint stiffness of the base design, N m/rad (None: the paper's 362).
    D_min_values, D_max_values : sequence of float, optional
        Damping values to try, N m s/rad, >= 0 (None: around the unit's own range).
    K_factors : sequence of float
        Joint stiffnesses to try as multiples of the base K, > 0 (each charge inside the unit's pressure limits).
    grid : Grid, (sequence of float, sequence of float) or str, optional
        Rest-to-rest amplitudes (rad) and periods (s); None: the design study's 3 x 3 cases.
    mesh_n : int, optional
        Collocation intervals of each case (None: the design study's 64).
    workers : int, optional
        Worker processes (None: all cores; 1: in this process).
    progress : bool
        Show a progress bar.

    Returns
    -------
    DesignSensitivity
        Every point (counts over every case, mean rmse ratio design/SEA) and its ``answer()``.

    Raises
    ------
    OptionError
        A bad grid, mesh, stiffness, damping value or factor (before anything is solved).
    OutputError
        ``out`` cannot be written (before anything is solved).
    """
    from ..actuator.sensitivity import run_design_sensitivity as sensitivity_of

    g, mesh, _ = design_study_settings(grid, mesh_n, None)
    target = target_stiffness(target_K_Nm_per_rad)
    for option, values, low in (("D_min_values", D_min_values, 0.0), ("D_max_values", D_max_values, 0.0),
                                ("K_factors", K_factors, None)):
        for v in values or ():
            ok = math.isfinite(float(v)) and (float(v) >= low if low is not None else float(v) > 0)
            if not ok:
                raise OptionError(option, f"must hold finite values {'>= 0' if low is not None else '> 0'}, "
                                          f"got {v!r}")
    check_out(out)
    d = design_of(design) if isinstance(design, (str, Path)) else design
    kw = dict(target_K_Nm_per_rad=target, D_min_values=D_min_values, D_max_values=D_max_values,
              K_factors=tuple(K_factors), grid=g, mesh=mesh, workers=workers, progress=progress)
    if out is None:
        return sensitivity_of(d, None, **kw)
    with folder(out, "sensitivity") as tmp:
        study = sensitivity_of(d, tmp, **kw)
    return study
