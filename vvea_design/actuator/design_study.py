"""The design's own actuator study, fast enough for the main job (``vvea design``).

:func:`run_design_study` maps a design's gas spring to a joint actuator (the
section 3.4 mapping, :func:`~vvea_design.actuator.model.actuator_from_spring`)
and compares it with the paper's VVEA, SEA and LWR:

* **rest-to-rest** (section 5) on :data:`DESIGN_GRID` (4 amplitudes x 4 periods
  spread over the paper's grid), every setting on one mesh
  (:data:`DESIGN_MESH`, 64 Radau intervals) with the multi-start of
  :mod:`~vvea_design.actuator.multistart` reduced to the starts that win
  almost always (D_min solution, ramp) and the study regularisation; every
  trajectory is re-simulated (:mod:`~vvea_design.actuator.verify`) and only
  valid, verified results enter the statistics (how many were left out is
  part of the result);
* **safety** (section 6): the 50 N m torque step of the design with variable
  damping and with fixed D = 31 N m s/rad (the paper's slow case), and of the
  paper's VVEA with variable damping.

One parametric CasADi solver per mesh and process serves every case (the
per-process cache of :mod:`~vvea_design.actuator.multistart`); the cases run
through :func:`vvea_design.parallel.parallel_map`. ``studies/bench_design_study.py``
prints the time breakdown.

Example
-------
>>> from vvea_design.spring.design_file import load_design      # doctest: +SKIP
>>> study = run_design_study(load_design("cad/design.json"), out_dir="out/actuator")  # doctest: +SKIP
>>> study.comparison("SEA").fraction_design_beats                # doctest: +SKIP
"""

from __future__ import annotations

import csv
import dataclasses
import json
import math
import time
from collections.abc import Callable, Sequence
from dataclasses import asdict, dataclass, field
from pathlib import Path

import numpy as np

from ..parallel import parallel_map
from ..spring.gas_spring import GasSpring
from .figures import plot_design_map, plot_safety, plot_trajectory
from .model import PAPER_SETTINGS, Actuator, actuator_from_spring
from .multistart import DEFAULT_REGULARISATION, RESULT_COLUMNS, CaseRow, RestToRestCase, solve_case_results
from .ocp import Mesh, Regularisation
from .rest_to_rest import Grid
from .safety import SafetyStudy, solve_safety
from .statistics import PAPER_TABLE5, Table5Statistics, table5_statistics

__all__ = [
    "DESIGN_GRID",
    "DESIGN_MESH",
    "DESIGN_STARTS",
    "DESIGN_SAFETY_MESH",
    "DESIGN_REFERENCES",
    "CaseResult",
    "SettingSummary",
    "Comparison",
    "StudyTiming",
    "StudyFiles",
    "DesignStudy",
    "design_actuator",
    "run_design_study",
]

#: Rest-to-rest grid of the design study: 4 amplitudes x 4 periods of the paper's grid.
DESIGN_GRID = Grid((0.2, 0.4, 0.7, 1.0), (0.3, 0.6, 1.0, 1.5))
#: Mesh of the design study (single level; SEA's grid-mean rmse is within 0.6 % of N = 256 here).
DESIGN_MESH = Mesh(64, 3)
#: Starts of the variable-damping settings (on the paper grid these two won 133 of 150 VVEA cases).
DESIGN_STARTS = ("const-Dmin", "ramp")
#: Mesh of the design's torque step (t95 within 0.3 % of the 200-interval mesh, docs/actuator.md).
DESIGN_SAFETY_MESH = Mesh(100, 3, grading=0.8)
#: Fixed dampings (N m s/rad) the design's variable-damping torque step is compared with (paper: 31 and 200).
DESIGN_SAFETY_FIXED_D = (31.0,)
#: The paper's settings the design is compared with.
DESIGN_REFERENCES = ("VVEA", "SEA", "LWR")


@dataclass(frozen=True)
class CaseResult:
    """One setting at one (A, T)."""

    A_rad: float  #: reference amplitude
    T_s: float  #: reference period
    setting: str  #: setting name
    rmse_rad: float  #: tracking rmse (nan if not solved)
    valid: bool  #: link reaches 95 % of A in both up-phases
    verified: bool  #: re-simulation agrees, bounds kept
    status: str  #: IPOPT status (or the error)
    start: str  #: start that won

    @property
    def usable(self) -> bool:
        """Counts in the statistics: solved, valid and verified."""
        return self.valid and self.verified and math.isfinite(self.rmse_rad)

    @classmethod
    def from_row(cls, row: CaseRow) -> "CaseResult":
        """The case of a ``results.csv`` row.

        Parameters
        ----------
        row : CaseRow
            A row of :func:`~vvea_design.actuator.multistart.solve_case_results` (SI units).

        Returns
        -------
        CaseResult
            Amplitude (rad), period (s), setting, rmse (rad), validity, verification, status and start.
        """
        return cls(float(row.A_rad), float(row.T_s), row.setting, float(row.rmse), bool(row.valid),
                   bool(row.verified), str(row.status), str(row.start))

    def to_dict(self) -> dict:
        """Plain-JSON dictionary.

        Returns
        -------
        dict
            JSON-ready fields by name: ``A_rad`` (rad), ``T_s`` (s), ``setting``, ``rmse_rad`` (rad, NaN when
            not solved), ``valid``, ``verified``, ``status``, ``start``.
        """
        return asdict(self)


@dataclass(frozen=True)
class SettingSummary:
    """One setting over the grid."""

    name: str  #: setting name
    K_Nm_per_rad: float  #: series stiffness
    D_min_Nms_per_rad: float  #: damping range, lower end
    D_max_Nms_per_rad: float  #: damping range, upper end
    n_cases: int  #: cases of the grid
    n_solved: int  #: IPOPT success
    n_valid: int  #: solved and valid (95 % rule)
    n_unverified: int  #: solved but failed the re-simulation check (left out)
    mean_rmse_rad: float  #: mean rmse over the cases where every setting is usable

    def to_dict(self) -> dict:
        """Plain-JSON dictionary.

        Returns
        -------
        dict
            JSON-ready fields by name: ``name``, ``K_Nm_per_rad`` (N m/rad), ``D_min_Nms_per_rad`` and
            ``D_max_Nms_per_rad`` (N m s/rad), the case counts ``n_cases``, ``n_solved``, ``n_valid``,
            ``n_unverified`` and ``mean_rmse_rad`` (rad).
        """
        return asdict(self)


@dataclass(frozen=True)
class Comparison:
    """The design against one other setting (Table-5-like), over the cases where both are usable."""

    other: str  #: the other setting
    n_cases: int  #: cases where both trajectories are valid and verified
    n_excluded: int  #: grid cases left out (either one invalid, unverified or not solved)
    design_beats: int  #: cases with rmse_design < (1 - 1e-3) rmse_other
    design_worse: int  #: cases with rmse_design > (1 + 1e-3) rmse_other
    fraction_design_beats: float | None  #: design_beats / n_cases
    meanrmse_other_over_design: float | None  #: mean rmse ratio (> 1: the design tracks better)
    paper_vvea_beats: float | None  #: the paper's Table 5 "VVEA beats <other>" (context)
    paper_meanrmse_other_over_vvea: float | None  #: the paper's Table 5 ratio for VVEA (context)

    def to_dict(self) -> dict:
        """Plain-JSON dictionary.

        Returns
        -------
        dict
            JSON-ready fields by name: ``other``, the case counts (``n_cases``, ``n_excluded``,
            ``design_beats``, ``design_worse``), ``fraction_design_beats`` (fraction),
            ``meanrmse_other_over_design`` (dimensionless ratio) and the paper's Table 5 values
            (``paper_vvea_beats``, ``paper_meanrmse_other_over_vvea``); ``None`` where not defined.
        """
        return asdict(self)


@dataclass(frozen=True)
class StudyTiming:
    """Wall-clock breakdown in s."""

    rest_to_rest_and_safety_s: float  #: the parallel solves (cases + torque steps)
    figures_s: float  #: figures and files
    total_s: float  #: the whole call
    workers: int  #: worker processes used
    solver_seconds: float  #: sum of all IPOPT wall times (all processes)
    rest_to_rest_cpu_seconds: float  #: CPU time of the rest-to-rest solves (all processes)

    def to_dict(self) -> dict:
        """Plain-JSON dictionary.

        Returns
        -------
        dict
            JSON-ready fields by name: ``rest_to_rest_and_safety_s``, ``figures_s``, ``total_s`` (wall clock,
            s), ``workers`` (count), ``solver_seconds`` (summed IPOPT wall time, s) and
            ``rest_to_rest_cpu_seconds`` (CPU time, s).
        """
        return asdict(self)


@dataclass(frozen=True)
class StudyFiles:
    """Files written by :func:`run_design_study` (``None`` when not written)."""

    results_csv: Path | None = None  #: one row per OCP (``results.csv`` columns)
    summary_json: Path | None = None  #: :meth:`DesignStudy.to_dict`
    map_png: Path | None = None  #: design vs the others, case by case (:func:`plot_design_map`)
    trajectory_png: Path | None = None  #: one case's optimal trajectories
    safety_png: Path | None = None  #: torque steps of the design and the paper's VVEA

    def to_dict(self) -> dict:
        """Plain-JSON dictionary: each file's name in the study's folder (``None``: not written).

        Names, not paths, so that a study written in a temporary folder and moved into place
        (``outputs.output_dir``) names no folder that no longer exists.

        Returns
        -------
        dict of str to str or None
            JSON-ready: field name (``results_csv``, ``summary_json``, ``map_png``, ``trajectory_png``,
            ``safety_png``) to the file's base name, or ``None`` when the file was not written.
        """
        return {k: (Path(v).name if v is not None else None) for k, v in asdict(self).items()}

    def __iter__(self):
        """The written files (paths), figures last."""
        return iter([p for p in (self.results_csv, self.summary_json, self.map_png, self.trajectory_png,
                                 self.safety_png) if p is not None])


@dataclass(frozen=True)
class DesignStudy:
    """Result of :func:`run_design_study`."""

    actuator: Actuator  #: the design's joint actuator (name "design")
    references: tuple[Actuator, ...]  #: the settings compared with
    grid: Grid  #: rest-to-rest grid
    mesh: Mesh  #: collocation mesh
    starts: tuple[str, ...]  #: variable-damping starts
    regularisation: Regularisation  #: input smoothing (rmse stays the pure tracking cost)
    cases: tuple[CaseResult, ...]  #: every setting at every case
    settings: tuple[SettingSummary, ...]  #: design first, then the references
    comparisons: tuple[Comparison, ...]  #: the design against each reference
    safety_design: SafetyStudy  #: torque step of the design (variable D, and fixed D = 31 with the design's K)
    safety_reference: SafetyStudy  #: the same for the paper's VVEA
    timing: StudyTiming  #: time breakdown
    files: StudyFiles = field(default_factory=StudyFiles)  #: what was written
    trajectory_case: tuple[float, float] = (float("nan"), float("nan"))  #: (A, T) of the trajectory figure
    best: dict = field(default_factory=dict, repr=False)  #: OcpResult per setting at ``trajectory_case``

    def comparison(self, other: str) -> Comparison:
        """The comparison with the setting called ``other``.

        Parameters
        ----------
        other : str
            Name of a reference setting of the study (``"VVEA"``, ``"SEA"``, ``"LWR"`` by default).

        Returns
        -------
        Comparison
            The design against ``other`` over the cases where both are usable.

        Raises
        ------
        KeyError
            When the study has no comparison with ``other`` (the message lists the ones it has).
        """
        for c in self.comparisons:
            if c.other == other:
                return c
        raise KeyError(f"no comparison with {other!r}; have {[c.other for c in self.comparisons]}")

    def report_tables(self) -> list[tuple[str, tuple[str, ...], list[tuple]]]:
        """Tables for a report: (title, header, rows) each; numbers rounded for reading.

        Returns
        -------
        list of (str, tuple of str, list of tuple)
            Three tables, each as (title, column headers, rows of formatted cells; ``"-"`` for a missing or
            non-finite number): the rest-to-rest comparison of the design with each reference (fractions
            as percent, rmse ratios dimensionless), the settings over the grid (K in N m/rad, D range in
            N m s/rad, mean rmse in rad) and the torque-step cases of the design and of the paper's VVEA
            (t95 in ms, mean and max D in N m s/rad, status).
        """
        def f(x, fmt):
            return "-" if x is None or (isinstance(x, float) and not math.isfinite(x)) else format(x, fmt)

        n = len(self.grid.cases())
        comp = [(c.other, f"{c.design_beats} of {c.n_cases}", f(c.fraction_design_beats, ".0%"),
                 f(c.meanrmse_other_over_design, ".3f"), c.n_excluded,
                 f(c.paper_vvea_beats, ".1%"), f(c.paper_meanrmse_other_over_vvea, ".3f")) for c in self.comparisons]
        sets = [(s.name, f(s.K_Nm_per_rad, ".0f"), f"{s.D_min_Nms_per_rad:.3g}-{s.D_max_Nms_per_rad:.4g}",
                 f"{s.n_valid} of {s.n_cases}", s.n_unverified, f(s.mean_rmse_rad, ".4f")) for s in self.settings]
        steps = []
        for st in (self.safety_design, self.safety_reference):
            for c in st.cases:
                steps.append((c.name, f(c.t95_s * 1e3, ".1f"), f(c.mean_D_Nms_per_rad, ".1f"),
                              f(c.max_D_Nms_per_rad, ".1f"), c.status))
        return [
            (f"Rest-to-rest: the design against the paper's settings ({n} cases, only cases where both "
             f"trajectories are valid and verified)",
             ("other setting", "design better", "fraction", "mean rmse other / design", "cases left out",
              "paper: VVEA better", "paper: mean rmse other / VVEA"), comp),
            ("Settings over the grid", ("setting", "K (N m/rad)", "D (N m s/rad)", "valid cases",
                                        "not verified (left out)", "mean rmse (rad), cases all valid"), sets),
            (f"Torque step {self.safety_design.setup['tau_ref_Nm']:g} N m (M = "
             f"{self.safety_design.setup['M_kgm2']:g} kg m²)",
             ("case", "t95 (ms)", "mean D (N m s/rad)", "max D (N m s/rad)", "status"), steps),
        ]

    @property
    def n_left_out(self) -> int:
        """Results left out of the statistics because the trajectory did not verify."""
        return sum(s.n_unverified for s in self.settings)

    def to_dict(self) -> dict:
        """JSON-ready summary (what ``design_study.json`` holds).

        Returns
        -------
        dict
            JSON-ready: the design actuator and the references (their fields, SI), the grid (``A_rad`` in
            rad, ``T_s`` in s), mesh, starts, regularisation, per-setting summaries, comparisons, the number
            of cases left out as unverified, both torque-step studies, timing (s), file names, the
            trajectory figure's case (``A_rad``, ``T_s``) and every case result (see the ``to_dict`` of
            each part).
        """
        return {
            "actuator": asdict(self.actuator),
            "references": [asdict(a) for a in self.references],
            "grid": {"A_rad": list(self.grid.A_rad), "T_s": list(self.grid.T_s)},
            "mesh": asdict(self.mesh),
            "starts": list(self.starts),
            "regularisation": asdict(self.regularisation),
            "settings": [s.to_dict() for s in self.settings],
            "comparisons": [c.to_dict() for c in self.comparisons],
            "n_left_out_unverified": self.n_left_out,
            "safety_design": self.safety_design.to_dict(),
            "safety_reference": self.safety_reference.to_dict(),
            "timing": self.timing.to_dict(),
            "files": self.files.to_dict(),
            "trajectory_case": {"A_rad": self.trajectory_case[0], "T_s": self.trajectory_case[1]},
            "cases": [c.to_dict() for c in self.cases],
        }


def design_actuator(design, **mapping) -> Actuator:
    """The design's joint actuator named ``"design"``.

    Parameters
    ----------
    design
        An :class:`Actuator` (used as is, renamed), a
        :class:`~vvea_design.spring.gas_spring.GasSpring`, or any object with
        a ``gas_spring`` attribute (a :class:`~vvea_design.spring.design.Design`).
    **mapping
        Keyword arguments of :func:`~vvea_design.actuator.model.actuator_from_spring`
        (``pulley_radius_m``, ``p2_MPa``, ``gamma_min_deg``, ``gamma_max_deg``, ``n_units``).

    Returns
    -------
    Actuator
        K (N m/rad) and damping range (N m s/rad) of the joint, named ``"design"``.
    """
    if isinstance(design, Actuator):
        if mapping:
            raise ValueError(f"mapping options {sorted(mapping)} need a spring, not an Actuator")
        return design.with_(name="design")
    spring = design if isinstance(design, GasSpring) else getattr(design, "gas_spring", None)
    if not isinstance(spring, GasSpring):
        raise ValueError(f"design must be an Actuator, a GasSpring or have a .gas_spring, got {type(design).__name__}")
    return actuator_from_spring(spring, name="design", **mapping)


def _work(item):
    """Worker: a rest-to-rest case -> (rows, best results), or a torque-step study. Never raises for a case."""
    kind, payload = item
    if kind == "safety":
        base, mesh, name, fixed = payload
        return solve_safety(base, mesh=mesh, name=name, fixed_D_Nms_per_rad=fixed)
    try:
        return solve_case_results(payload)
    except Exception:  # noqa: BLE001 - one case must not stop the study (solve_case records the error)
        from .multistart import solve_case

        return solve_case(payload), {}


def _solve_items(items: list, workers: int | None, progress, total: int) -> tuple[list, int]:
    """Every work item through :func:`~vvea_design.parallel.parallel_map`; (results in order, workers used)."""
    from ..parallel import default_workers

    done = [0]

    def on_result(i, r) -> None:
        done[0] += 1
        if progress is not None:
            kind, payload = items[i]
            msg = (f"torque step {payload[2]}" if kind == "safety"
                   else f"rest-to-rest A = {payload.A_rad:g} rad, T = {payload.T_s:g} s")
            progress(done[0], total, msg)

    used = 1 if workers == 1 else min(default_workers() if workers is None else workers, len(items))
    return parallel_map(_work, items, workers=workers, on_result=on_result, progress=False), used


def _setting_summaries(settings: Sequence[Actuator], cases: tuple[CaseResult, ...],
                       grid: Grid) -> tuple[SettingSummary, ...]:
    """Each setting over the grid; the mean rmse over the cases where every setting is usable."""
    names = [a.name for a in settings]
    usable = {(c.A_rad, c.T_s, c.setting): c.usable for c in cases}
    all_ok = [k for k in grid.cases() if all(usable.get((k[0], k[1], n), False) for n in names)]
    rm = {(c.A_rad, c.T_s, c.setting): c.rmse_rad for c in cases}
    out = []
    for a in settings:
        mine = [c for c in cases if c.setting == a.name]
        out.append(SettingSummary(
            a.name, a.K_Nm_per_rad, a.D_min_Nms_per_rad, a.D_max_Nms_per_rad, len(mine),
            sum(1 for c in mine if math.isfinite(c.rmse_rad)),
            sum(1 for c in mine if c.valid and math.isfinite(c.rmse_rad)),
            sum(1 for c in mine if math.isfinite(c.rmse_rad) and not c.verified),
            float(np.mean([rm[(A, T, a.name)] for A, T in all_ok])) if all_ok else float("nan")))
    return tuple(out)


def _comparisons(refs: Sequence[Actuator], stats: Table5Statistics, n_grid: int) -> tuple[Comparison, ...]:
    """The design against each reference over the cases where both are usable (Table-5-like)."""
    out = []
    for r in refs:
        p = stats.pair("design", r.name, "valid")
        paper = (PAPER_TABLE5.get(f"VVEA_beats_{r.name}"), PAPER_TABLE5.get(f"meanrmse_{r.name}_over_VVEA"))
        if p is None:
            out.append(Comparison(r.name, 0, n_grid, 0, 0, None, None, *paper))
        else:
            out.append(Comparison(r.name, p.n_cases, p.n_excluded, p.X_beats_Y, p.X_worse_than_Y,
                                  p.fraction_X_beats_Y, p.meanrmse_Y_over_X, *paper))
    return tuple(out)


def run_design_study(
    design,
    out_dir: str | Path | None = None,
    *,
    progress: Callable[[int, int, str], None] | None = None,
    workers: int | None = None,
    grid: Grid = DESIGN_GRID,
    mesh: Mesh = DESIGN_MESH,
    references: Sequence[str] = DESIGN_REFERENCES,
    mapping: dict | None = None,
    safety_mesh: Mesh = DESIGN_SAFETY_MESH,
) -> DesignStudy:
    """Rest-to-rest and torque-step study of one design against the paper's VVEA, SEA and LWR.

    Parameters
    ----------
    design
        The design: a :class:`~vvea_design.spring.design.Design` (or anything
        with ``.gas_spring``), a :class:`~vvea_design.spring.gas_spring.GasSpring`,
        or a ready :class:`~vvea_design.actuator.model.Actuator`.
    out_dir
        If given, writes ``results.csv``, ``design_study.json``,
        ``design_map.png``, ``design_trajectory.png`` and ``design_safety.png``
        there (the folder is created).
    progress
        Called as ``progress(done, total, message)`` after each finished work
        item (16 rest-to-rest cases + 2 torque steps by default) and once per
        later stage.
    workers
        Local worker processes (default: all cores; 1 = in this process).
    grid, mesh
        Rest-to-rest grid (A in rad, T in s) and collocation mesh (defaults :data:`DESIGN_GRID`,
        :data:`DESIGN_MESH`).
    references
        Names in :data:`~vvea_design.actuator.model.PAPER_SETTINGS` to compare with.
    mapping
        Options of the design -> actuator mapping (see :func:`design_actuator`).
    safety_mesh
        Collocation mesh of the two torque steps (default :data:`DESIGN_SAFETY_MESH`, 100 intervals
        clustered at the step; a coarser one is quicker and blurs the damping switch).

    Returns
    -------
    DesignStudy
        Typed result (rmse in rad, times in s); ``to_dict()`` gives the JSON.
    """
    import pandas as pd

    t_start = time.perf_counter()
    act = design_actuator(design, **(mapping or {}))
    unknown = [r for r in references if r not in PAPER_SETTINGS]
    if unknown:
        raise ValueError(f"references {unknown} are not paper settings; choose from {sorted(PAPER_SETTINGS)}")
    refs = tuple(PAPER_SETTINGS[r] for r in references)
    settings = (act,) + refs
    reg = DEFAULT_REGULARISATION
    items: list = [("safety", (act, safety_mesh, "design, variable D", DESIGN_SAFETY_FIXED_D)),
                   ("safety", (PAPER_SETTINGS["VVEA"], safety_mesh, "VVEA, variable D", ()))]
    items += [("r2r", RestToRestCase(A, T, settings, mesh, DESIGN_STARTS, (), None, reg)) for A, T in grid.cases()]
    total = len(items) + 1
    out, used = _solve_items(items, workers, progress, total)
    t_solved = time.perf_counter()
    safety_design, safety_ref = out[0], out[1]
    rows: list[CaseRow] = [row for rs, _ in out[2:] for row in rs]
    bests = {(case.A_rad, case.T_s): best for (_, case), (_, best) in zip(items[2:], out[2:])}
    df = pd.DataFrame([r.to_dict() for r in rows], columns=RESULT_COLUMNS)
    cases = tuple(CaseResult.from_row(r) for r in rows)
    # the trajectory figure: the case closest to A = 0.7 rad, T = 1.0 s
    ex = (min(grid.A_rad, key=lambda a: abs(a - 0.7)), min(grid.T_s, key=lambda t: abs(t - 1.0)))
    study = DesignStudy(
        actuator=act, references=refs, grid=grid, mesh=mesh, starts=DESIGN_STARTS, regularisation=reg,
        cases=cases, settings=_setting_summaries(settings, cases, grid),
        comparisons=_comparisons(refs, table5_statistics(df), len(grid.cases())), safety_design=safety_design,
        safety_reference=safety_ref,
        timing=StudyTiming(t_solved - t_start, 0.0, 0.0, used,
                           float(df["seconds"].sum()) + safety_design.wall_seconds + safety_ref.wall_seconds,
                           float(df["cpu_seconds"].sum())),
        trajectory_case=ex, best=bests.get(ex, {}),
    )
    if out_dir is not None:
        study = dataclasses.replace(study, files=_write(study, df, Path(out_dir)))
        if progress is not None:
            progress(total, total, f"wrote {out_dir}")
    elif progress is not None:
        progress(total, total, "done")
    t_end = time.perf_counter()
    study = dataclasses.replace(study, timing=dataclasses.replace(study.timing, figures_s=t_end - t_solved,
                                                                   total_s=t_end - t_start))
    if out_dir is not None:  # the JSON carries the final timing
        Path(study.files.summary_json).write_text(json.dumps(study.to_dict(), indent=2))
    return study


def _write(study: DesignStudy, df, out: Path) -> StudyFiles:
    """results.csv, design_study.json and the three figures."""
    out.mkdir(parents=True, exist_ok=True)
    res = out / "results.csv"
    with res.open("w", newline="") as fh:
        wr = csv.DictWriter(fh, fieldnames=RESULT_COLUMNS)
        wr.writeheader()
        wr.writerows(df.to_dict("records"))
    files = StudyFiles(results_csv=res, summary_json=out / "design_study.json", map_png=out / "design_map.png",
                       trajectory_png=out / "design_trajectory.png", safety_png=out / "design_safety.png")
    plot_design_map(df, "design", [r.name for r in study.references]).savefig(files.map_png, dpi=120)
    if study.best:
        A, T = study.trajectory_case
        plot_trajectory(study.best, A, T, highlight="design").savefig(files.trajectory_png, dpi=120)
    else:
        files = StudyFiles(files.results_csv, files.summary_json, files.map_png, None, files.safety_png)
    sr = {study.safety_design.variable_case: study.safety_design.results[study.safety_design.variable_case],
          study.safety_reference.variable_case: study.safety_reference.results[study.safety_reference.variable_case]}
    for name in ("fixed D 31", "fixed D 200"):
        if name in study.safety_design.results:
            sr[f"design, {name}"] = study.safety_design.results[name]
    tau = float(study.safety_design.setup["tau_ref_Nm"])
    plot_safety(sr, tau).savefig(files.safety_png, dpi=120)
    return files
