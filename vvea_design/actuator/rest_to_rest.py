"""The rest-to-rest sweep (paper section 5): grids, the resumable results file, mesh convergence.

The sweep goes through :func:`vvea_design.parallel.parallel_map`; each
finished case is appended to ``results.csv`` at once, so an interrupted sweep
resumes where it stopped.
"""

from __future__ import annotations

import csv
import json
import math
import time
from collections.abc import Sequence
from dataclasses import asdict, dataclass
from pathlib import Path

import numpy as np

from ..outputs import output_files
from ..parallel import parallel_map
from ..progress import console
from .figures import plot_best_map, plot_trajectory
from .model import PAPER_SETTINGS, Actuator
from .multistart import (DEFAULT_FINE_MESH, DEFAULT_MESH, DEFAULT_REGULARISATION, DEFAULT_STARTS, RESULT_COLUMNS,
                         RestToRestCase, _sweep_item, solve_case, solve_case_results)
from .ocp import Mesh, Regularisation, WARM_START_IPOPT
from .statistics import table5_statistics

__all__ = ["Grid", "GRIDS", "run_rest_to_rest", "mesh_convergence"]


@dataclass(frozen=True)
class Grid:
    """A rest-to-rest grid: amplitudes (rad) x periods (s)."""

    A_rad: tuple[float, ...]  #: reference amplitudes
    T_s: tuple[float, ...]  #: reference periods; horizon 2T

    def __post_init__(self) -> None:
        for name in ("A_rad", "T_s"):
            v = getattr(self, name)
            if len(v) == 0 or any(not (math.isfinite(x) and x > 0) for x in v):
                raise ValueError(f"Grid.{name} must be a non-empty list of positive numbers, got {v!r}")

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
) -> dict:
    """Run (or resume) the rest-to-rest sweep and write its files.

    Parameters
    ----------
    out_dir
        Output folder; gets ``results.csv`` (one row per OCP), ``meta.json``,
        ``summary.json`` (Table 5 statistics), ``best_map.png`` (Fig. 13) and
        ``trajectory.png`` (Fig. 12-like example).
    grid
        A :class:`Grid` or a name in :data:`GRIDS`.
    settings
        Actuator settings (default Table 4: VVEA, iVVEA, SEA, LWR).
    mesh, starts, ipopt_options
        Collocation mesh of the multi-start, multi-start set, extra IPOPT options.
    fine_mesh
        Mesh on which the reported results are solved (two-level scheme, see
        :func:`_polish_on_fine_mesh`); ``None`` = report ``mesh`` itself;
        ``"auto"`` (default) = :data:`DEFAULT_FINE_MESH` when ``mesh`` is
        :data:`DEFAULT_MESH`, else ``None``.
    workers, scheduler
        Passed to :func:`~vvea_design.parallel.parallel_map` (all local cores
        by default; a Dask scheduler address runs on that cluster).
    restart
        Discard an existing ``results.csv`` instead of resuming it.
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
    dict
        The summary (also in ``summary.json``).

    Raises
    ------
    ValueError
        If ``out_dir`` holds a results.csv of a different sweep (grid,
        settings, mesh, starts) and ``restart`` is false.
    """
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
    # every option is checked here, before any file is touched or any case is solved
    if mesh.n_intervals % 4:
        raise ValueError(f"the mesh must have a multiple of 4 intervals (the reference switches at T/2, T, 3T/2), "
                         f"got {mesh.n_intervals}")
    unknown = set(starts) - set(DEFAULT_STARTS)
    if unknown or not starts:
        raise ValueError(f"starts must be a non-empty selection of {list(DEFAULT_STARTS)}, got {list(starts)}")
    if workers is not None and (int(workers) != workers or workers < 1):
        raise ValueError(f"workers must be a whole number >= 1, got {workers!r}")
    ipo = tuple(sorted((ipopt_options or {}).items()))
    if isinstance(fine_mesh, str):
        if fine_mesh != "auto":
            raise ValueError(f"fine_mesh must be a Mesh, None or 'auto', got {fine_mesh!r}")
        fine_mesh = DEFAULT_FINE_MESH if mesh == DEFAULT_MESH else None
    if fine_mesh is not None and fine_mesh == mesh:
        fine_mesh = None
    if fine_mesh is not None and fine_mesh.n_intervals % 4:
        raise ValueError(f"the fine mesh must have a multiple of 4 intervals, got {fine_mesh.n_intervals}")
    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    res_path, meta_path = out / "results.csv", out / "meta.json"
    meta = _meta(grid, settings, mesh, starts, ipo, fine_mesh, regularisation)
    meta_json = json.loads(json.dumps(meta))
    if res_path.exists() and not restart:
        old = json.loads(meta_path.read_text()) if meta_path.exists() else None
        if old != meta_json:
            raise ValueError(
                f"{res_path} belongs to a different sweep (grid/settings/mesh/starts/regularisation differ from "
                f"{meta_path}); use another output folder, or discard it with --restart (restart=True in Python)"
            )
    if restart and res_path.exists():
        res_path.unlink()
    meta_path.write_text(json.dumps(meta, indent=2))
    done_rows = _read_done(res_path, settings)
    done = {r["case_id"] for r in done_rows}
    # rewrite the file clean (drops a torn last line / incomplete case)
    with res_path.open("w", newline="") as fh:
        wr = csv.DictWriter(fh, fieldnames=RESULT_COLUMNS)
        wr.writeheader()
        wr.writerows(done_rows)
    cases = [RestToRestCase(A, T, settings, mesh, tuple(starts), ipo, fine_mesh, regularisation) for A, T in grid.cases()]
    todo = [c for c in cases if c.case_id not in done]
    if done:
        console.print(f"[bold]resuming[/]: {len(done)} of {len(cases)} cases already in {res_path}", soft_wrap=True)
    # the case of the trajectory figure (Fig. 12-like): the worker that solves it hands its best results back,
    # so the figure needs no second solve of it (only when it was solved in an earlier run)
    Aex = min(grid.A_rad, key=lambda a: abs(a - 0.8))
    Tex = min(grid.T_s, key=lambda t: abs(t - 1.4))
    ex_case = RestToRestCase(Aex, Tex, settings, mesh, tuple(starts), ipo, fine_mesh, regularisation)
    ex_best: list[dict] = []

    fh = res_path.open("a", newline="")
    wr = csv.DictWriter(fh, fieldnames=RESULT_COLUMNS)

    def on_result(i: int, res: tuple[list[dict], dict | None]) -> None:
        rows, best = res
        wr.writerows(rows)
        fh.flush()
        if best is not None:
            ex_best.append(best)

    t0 = time.perf_counter()
    try:
        parallel_map(_sweep_item, [(solve_case, c, figures and c == ex_case) for c in todo], workers=workers,
                     scheduler=scheduler,
                     description=f"rest-to-rest {grid_name} ({len(settings)} settings/case)",
                     on_result=on_result, progress=progress)
    finally:
        fh.close()
    wall = time.perf_counter() - t0
    import pandas as pd

    df = pd.read_csv(res_path)
    summary = table5_statistics(df, outperform_rtol=outperform_rtol)
    summary["run"] = {
        "grid": grid_name, "cases": len(cases), "cases_solved_this_run": len(todo), "ocps": len(cases) * len(settings),
        "wall_seconds_this_run": round(wall, 2), "mesh": asdict(mesh),
        "fine_mesh": asdict(fine_mesh) if fine_mesh is not None else None, "starts": list(starts),
        "regularisation": asdict(regularisation),
        "solver_seconds_total": round(float(df["seconds"].sum()), 2),
        "solver_cpu_seconds_total": round(float(df["cpu_seconds"].sum()), 2) if "cpu_seconds" in df else None,
    }
    # results.csv grows case by case (resumable); the summary and figures are replaced whole or not at all
    finals = [out / "summary.json"] + ([out / "best_map.png", out / "trajectory.png"] if figures else [])
    with output_files(*finals, option="") as tmps:
        tmps[0].write_text(json.dumps(summary, indent=2))
        if figures:
            plot_best_map(df).savefig(tmps[1], dpi=130)
            names_set = set(df["setting"])
            ex = "VVEA" if "VVEA" in names_set else next((a.name for a in settings if a.variable_damping),
                                                        settings[0].name)
            best = ex_best[0] if ex_best else solve_case_results(ex_case)[1]
            plot_trajectory(best, Aex, Tex, highlight=ex).savefig(tmps[2], dpi=130)
    return summary



# -- mesh convergence ------------------------------------------------------------------------------------------
def mesh_convergence(
    meshes: Sequence[Mesh],
    *,
    grid: Grid | str = "paper",
    settings: Sequence[Actuator] | None = None,
    workers: int | None = None,
    scheduler: str | None = None,
    progress: bool = True,
) -> list[dict]:
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
    list of dict
        Per mesh: the mesh, Table 5 statistics, per-setting mean rmse and the
        per-case rmse arrays (for relative-change comparisons), solver seconds.
    """
    import pandas as pd

    grid = GRIDS[grid] if isinstance(grid, str) else grid
    settings = tuple(PAPER_SETTINGS.values()) if settings is None else tuple(settings)
    out = []
    for m in meshes:
        cases = [RestToRestCase(A, T, settings, m) for A, T in grid.cases()]
        t0 = time.perf_counter()
        rows = parallel_map(solve_case, cases, workers=workers, scheduler=scheduler,
                            description=f"mesh N={m.n_intervals} d={m.degree}", progress=progress)
        wall = time.perf_counter() - t0
        df = pd.DataFrame([r for rs in rows for r in rs])
        out.append({"mesh": m, "df": df, "stats": table5_statistics(df), "wall_seconds": wall,
                    "solver_seconds": float(df["seconds"].sum())})
    return out


