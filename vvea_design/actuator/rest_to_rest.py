"""The rest-to-rest sweep (paper section 5): grids, the resumable results file, mesh convergence.

The sweep goes through :func:`vvea_design.parallel.parallel_map` in chains
(:func:`~vvea_design.actuator.multistart.chains`: the periods of one amplitude, each case starting from its
neighbour's optima); each finished chain is appended to ``results.csv`` at once, so an interrupted sweep
resumes where it stopped. A chain that was cut short is solved again from its first case (the same
numbers as an uninterrupted run); only its missing cases are written.
"""

from __future__ import annotations

import csv
import json
import math
import time
from collections.abc import Sequence
from dataclasses import asdict, dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

from ..messages import show
from ..plausibility import LIMITS

from ..outputs import output_files
from ..parallel import parallel_map
from ..progress import console
from .figures import plot_best_map, plot_trajectory
from .model import PAPER_SETTINGS, Actuator
from .multistart import (ALL_STARTS, DEFAULT_FINE_MESH, DEFAULT_MESH, DEFAULT_REGULARISATION, DEFAULT_STARTS,
                         MULTISTART_IPOPT, MULTISTART_WARM_IPOPT, RESULT_COLUMNS, CaseRow, RestToRestCase, _chain_item,
                         chains, solve_chain)
from .ocp import Mesh, Regularisation, WARM_START_IPOPT
from .statistics import Table5Statistics, table5_statistics

if TYPE_CHECKING:  # pragma: no cover
    import pandas as pd

__all__ = ["Grid", "GRIDS", "SweepRun", "RestToRestSummary", "MeshConvergence", "run_rest_to_rest", "mesh_convergence"]


@dataclass(frozen=True)
class Grid:
    """A rest-to-rest grid: amplitudes (rad) x periods (s)."""

    A_rad: tuple[float, ...]  #: reference amplitudes
    T_s: tuple[float, ...]  #: reference periods; horizon 2T

    def __post_init__(self) -> None:
        for name in ("A_rad", "T_s"):
            v = getattr(self, name)
            if len(v) == 0 or any(not (math.isfinite(x) and x > 0) for x in v):
                raise ValueError(f"Grid.{name} must be a non-empty list of positive numbers, got {show(list(v))}")
        # every amplitude a joint swing (rad, not deg), every period a motion's length (s, not ms)
        for name, key, unit in (("A_rad", "amplitude_rad", "rad"), ("T_s", "period_s", "s")):
            for x in getattr(self, name):
                LIMITS[key].check(x, f"Grid.{name} (the grid's {'amplitudes' if unit == 'rad' else 'periods'}, "
                                     f"{unit})", ValueError)
        LIMITS["grid_cases"].check(len(self.A_rad) * len(self.T_s), "the grid's cases (amplitudes x periods)",
                                   ValueError, hint=f"{len(self.A_rad)} amplitudes x {len(self.T_s)} periods")

    def cases(self) -> list[tuple[float, float]]:
        """All (A, T) pairs, A-major.

        Returns
        -------
        list of (float, float)
            Every (amplitude in rad, period in s) pair; all periods of the first amplitude first.
        """
        return [(A, T) for A in self.A_rad for T in self.T_s]

    def repeated(self) -> dict[str, list[float]]:
        """Values that occur more than once (equal to the 6 significant digits of a case id), per axis.

        Returns
        -------
        dict of str to list of float
            ``"A_rad"`` (rad) and/or ``"T_s"`` (s) to the repeated values (rounded to 6 significant
            digits); an axis without repeats is absent, so an empty dict means no repeats.
        """
        out = {}
        for name in ("A_rad", "T_s"):
            seen: dict[str, int] = {}
            for x in getattr(self, name):
                seen[f"{x:.6g}"] = seen.get(f"{x:.6g}", 0) + 1
            rep = [float(k) for k, n in seen.items() if n > 1]
            if rep:
                out[name] = rep
        return out

    def unique(self) -> "Grid":
        """The grid with every repeated value kept once (first occurrence, order kept).

        Returns
        -------
        Grid
            A new grid whose amplitudes (rad) and periods (s) are distinct to 6 significant digits.
        """
        def once(v):
            keep: dict[str, float] = {}
            for x in v:
                keep.setdefault(f"{x:.6g}", x)
            return tuple(keep.values())

        return Grid(once(self.A_rad), once(self.T_s))


#: Named grids: the paper's (10 A x 15 T) and a coarse 3 x 3 one.
GRIDS: dict[str, Grid] = {
    "paper": Grid(tuple(np.round(np.linspace(0.1, 1.0, 10), 10)), tuple(np.round(np.arange(2, 17) * 0.1, 10))),
    "coarse": Grid((0.2, 0.6, 1.0), (0.4, 1.0, 1.6)),
}



# -- results file: case-by-case, resumable -----------------------------------------------------------
def _meta(grid: Grid, settings: Sequence[Actuator], mesh: Mesh, starts: Sequence[str], ipopt_options,
          fine_mesh: Mesh | None = None, regularisation: Regularisation = DEFAULT_REGULARISATION) -> dict:
    m = {
        "regularisation": asdict(regularisation),
        "grid": {"A_rad": list(grid.A_rad), "T_s": list(grid.T_s)},
        "settings": [asdict(a) for a in settings],
        "mesh": asdict(mesh),
        "starts": list(starts),
        "ipopt_options": [list(kv) for kv in ipopt_options],
    }
    if fine_mesh is not None:  # absent for single-level runs (older meta.json files still resume)
        m["fine_mesh"] = asdict(fine_mesh)
        m["fine_ipopt_options"] = [list(kv) for kv in sorted(WARM_START_IPOPT.items())]
        if MULTISTART_IPOPT:  # the multi-start mesh's own options (a sweep solved without them does not resume)
            m["multistart_ipopt_options"] = [list(kv) for kv in sorted(MULTISTART_IPOPT.items())]
        if MULTISTART_WARM_IPOPT:  # the multi-start NLPs start at their points (older runs: cold, not resumed with it)
            m["multistart_warm_ipopt_options"] = [list(kv) for kv in sorted(MULTISTART_WARM_IPOPT.items())]
    return m


def _read_done(path: Path, settings: Sequence[Actuator]) -> list[dict]:
    """Rows of complete cases in an existing results.csv (a torn last line is dropped)."""
    if not path.exists():
        return []
    names = {a.name for a in settings}
    by_case: dict[str, dict[str, dict]] = {}
    with path.open(newline="") as fh:
        for row in csv.DictReader(fh):
            if None in row or any(row.get(c) is None for c in RESULT_COLUMNS):
                continue  # torn / malformed line
            by_case.setdefault(row["case_id"], {})[row["setting"]] = row  # a repeated row: the last one counts
    keep = []
    for cid, rs in by_case.items():
        if set(rs) == names:
            keep.extend(rs.values())
    return keep


@dataclass(frozen=True)
class SweepRun:
    """How a sweep ran (the ``run`` record of ``summary.json``)."""

    grid: str  #: grid name ("paper", "coarse" or "custom")
    cases: int  #: (A, T) cases of the grid
    cases_solved_this_run: int  #: cases solved by this call (the others were resumed from results.csv)
    ocps: int  #: cases x settings
    wall_seconds_this_run: float  #: wall time of this call's solves, s (2 decimals)
    mesh: Mesh  #: multi-start mesh
    fine_mesh: Mesh | None  #: mesh the results are reported on (None: ``mesh`` itself)
    starts: tuple[str, ...]  #: multi-start set
    regularisation: Regularisation  #: input smoothing (rmse stays the pure tracking cost)
    solver_seconds_total: float  #: summed solver wall time of every row, s (2 decimals)
    solver_cpu_seconds_total: float | None  #: summed solver CPU time, s (None: an old results.csv without it)

    def to_dict(self) -> dict:
        """Plain-JSON dictionary (the ``run`` entry of ``summary.json``).

        Returns
        -------
        dict
            Field name to value: meshes and regularisation as dicts, starts as a list, times in s.
        """
        return {
            "grid": self.grid, "cases": self.cases, "cases_solved_this_run": self.cases_solved_this_run,
            "ocps": self.ocps, "wall_seconds_this_run": self.wall_seconds_this_run, "mesh": asdict(self.mesh),
            "fine_mesh": asdict(self.fine_mesh) if self.fine_mesh is not None else None, "starts": list(self.starts),
            "regularisation": asdict(self.regularisation), "solver_seconds_total": self.solver_seconds_total,
            "solver_cpu_seconds_total": self.solver_cpu_seconds_total,
        }


@dataclass(frozen=True)
class RestToRestSummary:
    """Result of :func:`run_rest_to_rest`: the Table 5 statistics of the whole results file and the run."""

    statistics: Table5Statistics  #: Table 5 statistics of every case in results.csv (fractions, rmse in rad)
    run: SweepRun  #: grid, meshes, starts, case counts and times (s) of this call
    out_dir: Path  #: the sweep's folder (results.csv, meta.json, summary.json, figures)

    def to_dict(self) -> dict:
        """The content of ``summary.json``: the statistics, then ``run``.

        Returns
        -------
        dict
            :meth:`Table5Statistics.to_dict` with the key ``run`` (:meth:`SweepRun.to_dict`) added.
        """
        return {**self.statistics.to_dict(), "run": self.run.to_dict()}


@dataclass(frozen=True)
class _Options:
    """The checked options of one sweep."""

    grid_name: str
    grid: Grid
    settings: tuple[Actuator, ...]
    mesh: Mesh
    fine_mesh: Mesh | None
    starts: tuple[str, ...]
    ipopt: tuple
    regularisation: Regularisation

    def case(self, A: float, T: float) -> RestToRestCase:
        return RestToRestCase(A, T, self.settings, self.mesh, self.starts, self.ipopt, self.fine_mesh,
                              self.regularisation)


def _check_options(grid, settings, mesh, fine_mesh, starts, workers, ipopt_options, regularisation) -> _Options:
    """Every option checked before any file is touched or any case is solved (ValueError names it)."""
    if isinstance(grid, str):
        if grid not in GRIDS:
            raise ValueError(f"grid must be one of {sorted(GRIDS)} or a Grid, got {grid!r}")
        grid_name, grid = grid, GRIDS[grid]
    else:
        grid_name = "custom"
    rep = grid.repeated()
    if rep:
        grid = grid.unique()
        console.print(f"[bold yellow]note[/]: the grid repeats {rep}; each case is solved once "
                      f"({len(grid.A_rad)} amplitudes x {len(grid.T_s)} periods)", soft_wrap=True)
    settings = tuple(PAPER_SETTINGS.values()) if settings is None else tuple(settings)
    names = [a.name for a in settings]
    if len(set(names)) != len(names):
        raise ValueError(f"setting names must be unique, got {names}")
    if mesh.n_intervals % 4:
        raise ValueError(f"the mesh must have a multiple of 4 intervals (the reference switches at T/2, T, 3T/2), "
                         f"got {mesh.n_intervals}")
    unknown = set(starts) - set(ALL_STARTS)
    if unknown or not starts:
        raise ValueError(f"starts must be a non-empty selection of {list(ALL_STARTS)}, got {list(starts)}")
    if workers is not None and (int(workers) != workers or workers < 1):
        raise ValueError(f"workers must be a whole number >= 1, got {workers!r}")
    if isinstance(fine_mesh, str):
        if fine_mesh != "auto":
            raise ValueError(f"fine_mesh must be a Mesh, None or 'auto', got {fine_mesh!r}")
        fine_mesh = DEFAULT_FINE_MESH if mesh == DEFAULT_MESH else None
    if fine_mesh is not None and fine_mesh == mesh:
        fine_mesh = None
    if fine_mesh is not None and fine_mesh.n_intervals % 4:
        raise ValueError(f"the fine mesh must have a multiple of 4 intervals, got {fine_mesh.n_intervals}")
    return _Options(grid_name, grid, settings, mesh, fine_mesh, tuple(starts),
                    tuple(sorted((ipopt_options or {}).items())), regularisation)


#: Every file a rest-to-rest sweep writes in its folder (``report.html``: the command's report of it); a restart
#: removes them all before the first new case, so an interrupted restart leaves the new partial sweep alone.
SWEEP_FILES = ("results.csv", "meta.json", "summary.json", "best_map.png", "trajectory.png", "report.html")


def _prepare_results(out: Path, opt: _Options, restart: bool) -> set[str]:
    """Check an existing sweep in ``out`` is this one, write meta.json and rewrite results.csv clean.

    Returns the ids of the complete cases already in results.csv (resumed, not solved again).
    """
    res_path, meta_path = out / "results.csv", out / "meta.json"
    meta = _meta(opt.grid, opt.settings, opt.mesh, opt.starts, opt.ipopt, opt.fine_mesh, opt.regularisation)
    if res_path.exists() and not restart:
        old = json.loads(meta_path.read_text()) if meta_path.exists() else None
        if old != json.loads(json.dumps(meta)):
            raise ValueError(
                f"{res_path} belongs to a different sweep (grid/settings/mesh/starts/regularisation differ from "
                f"{meta_path}); use another output folder, or discard it with --restart (restart=True in Python)"
            )
    if restart:  # the whole earlier sweep goes, not only its results: never a new results.csv beside an old summary
        for name in SWEEP_FILES:
            if (out / name).is_file() or (out / name).is_symlink():
                (out / name).unlink()
    meta_path.write_text(json.dumps(meta, indent=2))
    done_rows = _read_done(res_path, opt.settings)
    # rewrite the file clean (drops a torn last line / incomplete case)
    with res_path.open("w", newline="") as fh:
        wr = csv.DictWriter(fh, fieldnames=RESULT_COLUMNS)
        wr.writeheader()
        wr.writerows(done_rows)
    return {r["case_id"] for r in done_rows}


def _solve_cases(res_path: Path, todo: list[list[RestToRestCase]], done: set[str], keep: RestToRestCase | None,
                 description: str, workers, scheduler, progress: bool) -> tuple[float, list[dict]]:
    """Solve the chains ``todo``, appending each finished chain's rows of cases not in ``done`` to results.csv.

    Returns the wall time (s) and the best results of ``keep`` (the trajectory figure's case) when it was
    solved here (a one-element list; empty otherwise).
    """
    kept: list[dict] = []
    fh = res_path.open("a", newline="")
    wr = csv.DictWriter(fh, fieldnames=RESULT_COLUMNS)

    def on_result(i: int, res: tuple[list[list[CaseRow]], dict | None]) -> None:
        per_case, best = res
        for case, rows in zip(todo[i], per_case):
            if case.case_id not in done:
                wr.writerows(r.to_dict() for r in rows)
        fh.flush()
        if best is not None:
            kept.append(best)

    t0 = time.perf_counter()
    try:
        parallel_map(_chain_item, [(solve_chain, ch, keep if keep in ch else None) for ch in todo], workers=workers,
                     scheduler=scheduler, description=description, on_result=on_result, progress=progress)
    finally:
        fh.close()
    return time.perf_counter() - t0, kept


def _write_summary_and_figures(out: Path, summary: RestToRestSummary, df, opt: _Options, figures: bool,
                               ex_case: RestToRestCase, ex_best: list[dict]) -> None:
    """summary.json, best_map.png and trajectory.png, replaced whole or not at all."""
    finals = [out / "summary.json"] + ([out / "best_map.png", out / "trajectory.png"] if figures else [])
    with output_files(*finals, option="") as tmps:
        tmps[0].write_text(json.dumps(summary.to_dict(), indent=2))
        if figures:
            plot_best_map(df).savefig(tmps[1], dpi=130)
            names_set = set(df["setting"])
            ex = "VVEA" if "VVEA" in names_set else next((a.name for a in opt.settings if a.variable_damping),
                                                        opt.settings[0].name)
            if ex_best:
                best = ex_best[0]
            else:  # solved in an earlier run: its chain up to it again (the same numbers as in results.csv)
                chain = next(ch for ch in chains([opt.case(A, T) for A, T in opt.grid.cases()]) if ex_case in ch)
                best = solve_chain(chain[:chain.index(ex_case) + 1], ex_case)[1] or {}
            plot_trajectory(best, ex_case.A_rad, ex_case.T_s, highlight=ex).savefig(tmps[2], dpi=130)


def run_rest_to_rest(
    out_dir: str | Path,
    *,
    grid: Grid | str = "paper",
    settings: Sequence[Actuator] | None = None,
    mesh: Mesh = DEFAULT_MESH,
    fine_mesh: Mesh | None | str = "auto",
    starts: Sequence[str] = DEFAULT_STARTS,
    workers: int | None = None,
    scheduler: str | None = None,
    ipopt_options: dict | None = None,
    restart: bool = False,
    progress: bool = True,
    figures: bool = True,
    outperform_rtol: float = 1e-3,
    regularisation: Regularisation = DEFAULT_REGULARISATION,
) -> RestToRestSummary:
    """Run (or resume) the rest-to-rest sweep and write its files.

    Parameters
    ----------
    out_dir
        Output folder; gets ``results.csv`` (one row per OCP), ``meta.json``,
        ``summary.json`` (Table 5 statistics), ``best_map.png`` (Fig. 13) and
        ``trajectory.png`` (Fig. 12-like example).
    grid
        A :class:`Grid` (A in rad, T in s) or a name in :data:`GRIDS`.
    settings
        Actuator settings (default Table 4: VVEA, iVVEA, SEA, LWR).
    mesh, starts, ipopt_options
        Collocation mesh of the multi-start, multi-start set, extra IPOPT options.
    fine_mesh
        Mesh on which the reported results are solved (two-level scheme, see
        :func:`~vvea_design.actuator.multistart.solve_case_results`); ``None`` = report ``mesh`` itself;
        ``"auto"`` (default) = :data:`DEFAULT_FINE_MESH` when ``mesh`` is
        :data:`DEFAULT_MESH`, else ``None``.
    workers, scheduler
        Passed to :func:`~vvea_design.parallel.parallel_map` (all local cores
        by default; a Dask scheduler address runs on that cluster).
    restart
        Discard an existing sweep (every file of :data:`SWEEP_FILES`, before the first case is solved)
        instead of resuming it; other files in ``out_dir`` are kept.
    progress, figures
        Show the progress bar; write the PNGs.
    outperform_rtol
        Relative margin for "X outperforms Y" (fraction, dimensionless):
        ``rmse_X < (1 - rtol) rmse_Y``.
    regularisation
        Penalties that smooth the optimal inputs (:class:`~vvea_design.actuator.ocp.Regularisation`);
        the reported rmse is always the pure tracking cost.

    Returns
    -------
    RestToRestSummary
        The statistics (rmse in rad, fractions dimensionless) and the run record (times in s);
        ``to_dict()`` is what ``summary.json`` holds.

    Raises
    ------
    ValueError
        If ``out_dir`` holds a results.csv of a different sweep (grid,
        settings, mesh, starts) and ``restart`` is false, or an option is out of range.
    """
    opt = _check_options(grid, settings, mesh, fine_mesh, starts, workers, ipopt_options, regularisation)
    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    res_path = out / "results.csv"
    done = _prepare_results(out, opt, restart)
    cases = [opt.case(A, T) for A, T in opt.grid.cases()]
    todo = [ch for ch in chains(cases) if any(c.case_id not in done for c in ch)]
    if done:
        console.print(f"[bold]resuming[/]: {len(done)} of {len(cases)} cases already in {res_path}", soft_wrap=True)
    # the case of the trajectory figure (Fig. 12-like): the worker that solves it hands its best results back,
    # so the figure needs no second solve of it (only when it was solved in an earlier run)
    ex_case = opt.case(min(opt.grid.A_rad, key=lambda a: abs(a - 0.8)), min(opt.grid.T_s, key=lambda t: abs(t - 1.4)))
    wall, ex_best = _solve_cases(res_path, todo, done, ex_case if figures else None,
                                 f"rest-to-rest {opt.grid_name} ({len(opt.settings)} settings/case, "
                                 f"{len(todo)} chain(s))", workers, scheduler, progress)
    import pandas as pd

    df = pd.read_csv(res_path)
    run = SweepRun(
        grid=opt.grid_name, cases=len(cases), cases_solved_this_run=sum(c.case_id not in done for ch in todo for c in ch),
        ocps=len(cases) * len(opt.settings),
        wall_seconds_this_run=round(wall, 2), mesh=opt.mesh, fine_mesh=opt.fine_mesh, starts=opt.starts,
        regularisation=opt.regularisation, solver_seconds_total=round(float(df["seconds"].sum()), 2),
        solver_cpu_seconds_total=round(float(df["cpu_seconds"].sum()), 2) if "cpu_seconds" in df else None)
    summary = RestToRestSummary(table5_statistics(df, outperform_rtol=outperform_rtol), run, out)
    # results.csv grows case by case (resumable); the summary and figures are replaced whole or not at all
    _write_summary_and_figures(out, summary, df, opt, figures, ex_case, ex_best)
    return summary


# -- mesh convergence ------------------------------------------------------------------------------------------
@dataclass(frozen=True)
class MeshConvergence:
    """The sweep on one mesh (no files): :func:`mesh_convergence` returns one per mesh."""

    mesh: Mesh  #: collocation mesh
    df: "pd.DataFrame" = field(repr=False)  #: every row (``results.csv`` columns; rmse in rad)
    stats: Table5Statistics  #: Table 5 statistics of the rows
    wall_seconds: float  #: wall time of the sweep, s
    solver_seconds: float  #: summed solver wall time of the rows, s

    def to_dict(self) -> dict:
        """Plain-JSON dictionary (the rows left out: ``df`` holds them).

        Returns
        -------
        dict
            ``mesh`` (dict), ``stats`` (:meth:`Table5Statistics.to_dict`), ``wall_seconds`` and
            ``solver_seconds`` (s).
        """
        return {"mesh": asdict(self.mesh), "stats": self.stats.to_dict(), "wall_seconds": self.wall_seconds,
                "solver_seconds": self.solver_seconds}


def mesh_convergence(
    meshes: Sequence[Mesh],
    *,
    grid: Grid | str = "paper",
    settings: Sequence[Actuator] | None = None,
    workers: int | None = None,
    scheduler: str | None = None,
    progress: bool = True,
) -> list[MeshConvergence]:
    """Run the sweep on several meshes (no files) and return per-mesh statistics.

    Parameters
    ----------
    meshes
        Collocation meshes to compare.
    grid
        A :class:`Grid` (A in rad, T in s) or a name in :data:`GRIDS`.
    settings
        Actuator settings (default Table 4).
    workers, scheduler
        Passed to :func:`~vvea_design.parallel.parallel_map`.
    progress
        Show a progress bar.

    Returns
    -------
    list of MeshConvergence
        Per mesh: the mesh, every row (for per-case relative-change comparisons; rmse in rad), the
        Table 5 statistics and the times (s).
    """
    import pandas as pd

    grid = GRIDS[grid] if isinstance(grid, str) else grid
    settings = tuple(PAPER_SETTINGS.values()) if settings is None else tuple(settings)
    out = []
    for m in meshes:
        cases = [RestToRestCase(A, T, settings, m) for A, T in grid.cases()]
        t0 = time.perf_counter()
        res = parallel_map(_chain_item, [(solve_chain, ch, None) for ch in chains(cases)], workers=workers,
                           scheduler=scheduler, description=f"mesh N={m.n_intervals} d={m.degree}", progress=progress)
        wall = time.perf_counter() - t0
        df = pd.DataFrame([r.to_dict() for per_case, _ in res for rs in per_case for r in rs])
        out.append(MeshConvergence(m, df, table5_statistics(df), wall, float(df["seconds"].sum())))
    return out
