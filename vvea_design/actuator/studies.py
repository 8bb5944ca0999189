"""Actuator studies: the rest-to-rest sweep (paper section 5) and the safety study (section 6).

Rest-to-rest
------------
One *case* is an amplitude ``A`` and a period ``T``; for it every actuator
setting is solved on one mesh (:func:`solve_case`). Constant-damping settings
are convex QPs and are solved once. Variable-damping settings are non-convex
and are solved from several starts; the best objective wins:

* ``const-Dmin`` - the solution with D held at D_min (for iVVEA this is the
  SEA solution). It is feasible, so it is also *adopted* as a candidate
  itself: a variable-damping result is never worse than the constant
  setting at its D_min on the same mesh (iVVEA <= SEA, exactly);
* ``ramp`` - the QP solution with D ramped to D_max as fast as eq. 12 allows
  (feasible, adopted too);
* ``cold`` - at rest with D = D_min;
* ``cross`` - the best solution of the other variable-damping settings of the
  same case, clipped into this setting's damping range.

Each row of ``results.csv`` names the start that won. The sweep goes through
:func:`vvea_design.parallel.parallel_map`; each finished case is appended to
``results.csv`` at once, so an interrupted sweep resumes where it stopped.

Safety
------
The 50 N m torque step with ``M = 1e4 kg m²`` (Table 6), variable damping vs
fixed ``D = 31`` and ``D = 200`` (:func:`run_safety`).
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

from .model import PAPER_SETTINGS, Actuator
from .ocp import (Mesh, OcpResult, RestToRestSolver, TorqueStepSolver, TorqueStepWeights, PAPER_TABLE6, WARM_START_IPOPT,
                  ramp_u_d_profile)
from ..parallel import parallel_map
from ..progress import console

__all__ = [
    "Grid",
    "GRIDS",
    "RestToRestCase",
    "DEFAULT_MESH",
    "DEFAULT_FINE_MESH",
    "DEFAULT_STARTS",
    "RESULT_COLUMNS",
    "solve_case",
    "run_rest_to_rest",
    "table5_statistics",
    "PAPER_TABLE5",
    "plot_best_map",
    "plot_trajectory",
    "run_safety",
    "PAPER_SAFETY",
    "mesh_convergence",
    "solve_single",
]

#: Collocation mesh used by the studies (chosen by ``studies/mesh_convergence.py``).
DEFAULT_MESH = Mesh(n_intervals=64, degree=3)
#: Mesh on which the reported results are solved (two-level scheme): the multi-start runs on
#: :data:`DEFAULT_MESH`, then every setting is solved once more here (QPs directly, variable
#: damping by one warm-started polish of the coarse optimum). SEA's rmse changes < 0.5 % case by
#: case from N = 192 on (``studies/mesh_convergence.py``).
DEFAULT_FINE_MESH = Mesh(n_intervals=192, degree=3)
#: Starts tried for variable-damping settings.
DEFAULT_STARTS = ("const-Dmin", "ramp", "cold", "cross")
_ALL_STARTS = set(DEFAULT_STARTS)


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
        """All (A, T) pairs, A-major."""
        return [(A, T) for A in self.A_rad for T in self.T_s]


#: Named grids: the paper's (10 A x 15 T) and a coarse 3 x 3 one.
GRIDS: dict[str, Grid] = {
    "paper": Grid(tuple(np.round(np.linspace(0.1, 1.0, 10), 10)), tuple(np.round(np.arange(2, 17) * 0.1, 10))),
    "coarse": Grid((0.2, 0.6, 1.0), (0.4, 1.0, 1.6)),
}


@dataclass(frozen=True)
class RestToRestCase:
    """One work item of the sweep: every setting at one (A, T)."""

    A_rad: float
    T_s: float
    settings: tuple[Actuator, ...]
    mesh: Mesh = DEFAULT_MESH
    starts: tuple[str, ...] = DEFAULT_STARTS
    ipopt_options: tuple[tuple[str, object], ...] = ()  #: extra IPOPT options (hashable)
    fine_mesh: Mesh | None = None  #: if set, report results polished on this mesh (two-level)

    @property
    def case_id(self) -> str:
        return f"A{self.A_rad:.6g}_T{self.T_s:.6g}"


#: Columns of results.csv, in order.
RESULT_COLUMNS = [
    "case_id", "setting", "A_rad", "T_s", "rmse", "valid", "status", "seconds", "cpu_seconds", "success", "objective",
    "iterations", "start", "n_starts", "start_objectives", "peak_q_up1_rad", "peak_q_up2_rad",
    "mean_D_Nms_per_rad", "max_D_Nms_per_rad", "K_Nm_per_rad", "D_min_Nms_per_rad", "D_max_Nms_per_rad",
    "mesh_N", "mesh_degree", "coarse_mesh_N", "coarse_rmse",
]

# -- per-process solver cache (one parametric solver per mesh and options) ------------------------
_SOLVERS: dict[tuple, RestToRestSolver] = {}


def _solver(mesh: Mesh, ipopt_options: tuple) -> RestToRestSolver:
    key = (mesh, ipopt_options)
    if key not in _SOLVERS:
        _SOLVERS[key] = RestToRestSolver(mesh, dict(ipopt_options))
    return _SOLVERS[key]


def _mean_D(r: OcpResult, solver: RestToRestSolver) -> float:
    col = solver.cols[True]
    D = r.Z[:, 1:, 4]
    return float(np.sum(D * col.Bq[1:] * col.h[:, None]) / col.S)


def _row(case: RestToRestCase, act: Actuator, r: OcpResult | None, start: str, n_starts: int,
         secs: float, iters: int, start_obj: dict, solver: RestToRestSolver | None, status: str | None = None,
         cpu: float = float("nan")) -> dict:
    ok = r is not None and r.success and np.isfinite(r.objective)
    return {
        "case_id": case.case_id,
        "setting": act.name,
        "A_rad": case.A_rad,
        "T_s": case.T_s,
        "rmse": r.extra["rmse_rad"] if ok else float("nan"),
        "valid": bool(r.extra["valid"]) if ok else False,
        "status": status if status is not None else (r.status if r is not None else "not solved"),
        "seconds": round(secs, 4),
        "cpu_seconds": round(cpu, 4),
        "success": bool(ok),
        "objective": r.objective if ok else float("nan"),
        "iterations": iters,
        "start": start if ok else "",
        "n_starts": n_starts,
        "start_objectives": json.dumps({k: (None if not np.isfinite(v) else float(f"{v:.10g}"))
                                        for k, v in start_obj.items()}),
        "peak_q_up1_rad": r.extra["peak_q_up_rad"][0] if ok else float("nan"),
        "peak_q_up2_rad": r.extra["peak_q_up_rad"][1] if ok else float("nan"),
        "mean_D_Nms_per_rad": _mean_D(r, solver) if ok else float("nan"),
        "max_D_Nms_per_rad": float(np.max(r.Z[..., 4])) if ok else float("nan"),
        "K_Nm_per_rad": act.K_Nm_per_rad,
        "D_min_Nms_per_rad": act.D_min_Nms_per_rad,
        "D_max_Nms_per_rad": act.D_max_Nms_per_rad,
        "mesh_N": case.mesh.n_intervals,
        "mesh_degree": case.mesh.degree,
        "coarse_mesh_N": case.mesh.n_intervals,
        "coarse_rmse": r.extra["rmse_rad"] if ok else float("nan"),
    }


def _better(a: OcpResult | None, b: OcpResult | None) -> bool:
    """True when ``b`` is a successful result strictly better than ``a``."""
    if b is None or not b.success or not np.isfinite(b.objective):
        return False
    return a is None or b.objective < a.objective


def solve_case_results(case: RestToRestCase) -> tuple[list[dict], dict[str, OcpResult]]:
    """Solve every setting of one case; return (rows, best results by setting name).

    With ``case.fine_mesh`` the multi-start runs on ``case.mesh`` and the rows
    and results come from the fine mesh (:func:`_polish_on_fine_mesh`).
    """
    rows, best = _solve_case_one_mesh(case)
    if case.fine_mesh is None or case.fine_mesh == case.mesh:
        return rows, best
    return _polish_on_fine_mesh(case, rows, best)


def _polish_on_fine_mesh(case: RestToRestCase, coarse_rows: list[dict],
                         coarse_best: dict[str, OcpResult]) -> tuple[list[dict], dict[str, OcpResult]]:
    """Second level: solve every setting of the case on ``case.fine_mesh``.

    Constant damping: the convex QP, directly. Variable damping: candidates are
    (1) the fine-mesh QP at D_min adopted as is (feasible; for iVVEA it *is*
    the fine SEA solution, so iVVEA <= SEA holds exactly on the fine mesh) and
    (2) one warm-started polish of the coarse multi-start optimum interpolated
    onto the fine mesh (a cold-option retry only if that fails). Best wins.
    """
    fm = case.fine_mesh
    fs = _solver(fm, case.ipopt_options)
    fw = _solver(fm, tuple(sorted({**dict(case.ipopt_options), **WARM_START_IPOPT}.items())))
    A, T = case.A_rad, case.T_s
    fcase = RestToRestCase(A, T, case.settings, fm, case.starts, case.ipopt_options)
    crow = {r["setting"]: r for r in coarse_rows}
    qp_cache: dict[tuple, OcpResult] = {}

    def const_solve(act: Actuator) -> OcpResult:
        key = (act.K_Nm_per_rad, act.D_min_Nms_per_rad, act.B_kgm2, act.M_kgm2, act.tau_m_max_Nm)
        if key not in qp_cache:
            qp_cache[key] = fs.solve(act.with_(D_max_Nms_per_rad=act.D_min_Nms_per_rad), A, T)
        return qp_cache[key]

    rows, best = [], {}
    cN = case.mesh.n_intervals
    for act in case.settings:
        cr = crow[act.name]
        secs, cpu, iters = float(cr["seconds"]), float(cr["cpu_seconds"]), int(cr["iterations"])
        obj = {f"N{cN} {k}": v for k, v in json.loads(cr["start_objectives"]).items()}
        obj = {k: (float("nan") if v is None else v) for k, v in obj.items()}
        cand: dict[str, OcpResult] = {}
        qp = const_solve(act)
        secs += qp.seconds
        cpu += qp.extra.get("cpu_seconds", 0.0)
        iters += max(qp.iterations, 0)
        if not act.variable_damping:
            cand["qp"] = qp
        else:
            cand["const-Dmin (adopted)"] = fs.evaluate_as(qp, act, A, T, status=qp.status)
            cb = coarse_best.get(act.name)
            if cb is not None and cb.success:
                lab = f"polish:{cr['start']}"
                r = fw.solve(act, A, T, w0=fw.guess_from_other_mesh(cb, act, A, T))
                if not r.success:  # retry with the default options from the same start
                    secs, cpu, iters = secs + r.seconds, cpu + r.extra.get("cpu_seconds", 0.0), iters + max(r.iterations, 0)
                    obj[lab + " (warm)"] = float("nan")
                    r = fs.solve(act, A, T, w0=fs.guess_from_other_mesh(cb, act, A, T))
                secs += r.seconds
                cpu += r.extra.get("cpu_seconds", 0.0)
                iters += max(r.iterations, 0)
                cand[lab] = r
        for k, r in cand.items():
            obj[k] = r.objective if r.success else float("nan")
        label = _pick_label(cand)
        b = cand[label] if label else None
        best[act.name] = b
        status = None
        if label is None:
            first = next(iter(cand.values()), None)
            status = first.status if first is not None else "no start tried"
        row = _row(fcase, act, b, label or "", len(cand), secs, iters, obj, fs, status=status, cpu=cpu)
        row["coarse_mesh_N"] = cN
        row["coarse_rmse"] = cr["rmse"]
        rows.append(row)
    return rows, best


def _solve_case_one_mesh(case: RestToRestCase) -> tuple[list[dict], dict[str, OcpResult]]:
    """Multi-start on ``case.mesh`` only."""
    s = _solver(case.mesh, case.ipopt_options)
    A, T = case.A_rad, case.T_s
    dt = s.interval_seconds(T)
    unknown = set(case.starts) - _ALL_STARTS
    if unknown:
        raise ValueError(f"unknown start(s) {sorted(unknown)}; choose from {sorted(_ALL_STARTS)}")
    rows: dict[str, dict] = {}
    best: dict[str, OcpResult] = {}
    info: dict[str, dict] = {}
    qp_cache: dict[tuple, OcpResult] = {}
    cpu = {a.name: 0.0 for a in case.settings}  # CPU seconds of each setting's solves

    def const_solve(act: Actuator) -> OcpResult:
        key = ("const", act.K_Nm_per_rad, act.D_min_Nms_per_rad, act.B_kgm2, act.M_kgm2, act.tau_m_max_Nm)
        if key not in qp_cache:
            qp_cache[key] = s.solve(act.with_(D_max_Nms_per_rad=act.D_min_Nms_per_rad), A, T)
        return qp_cache[key]

    # constant-damping settings: one convex QP each
    for act in case.settings:
        if not act.variable_damping:
            r = const_solve(act)
            cpu[act.name] += r.extra.get("cpu_seconds", 0.0)
            best[act.name] = r
            info[act.name] = dict(start="qp", n=1, secs=r.seconds, iters=r.iterations, obj={"qp": r.objective})
    variable = [a for a in case.settings if a.variable_damping]
    # variable damping: starts from feasible QP solutions, cold, then cross starts
    for act in variable:
        cand: dict[str, OcpResult] = {}
        secs, iters = 0.0, 0
        inf = dict(obj={})

        def attempt(label: str, r: OcpResult) -> None:
            nonlocal secs, iters
            secs += r.seconds
            cpu[act.name] += r.extra.get("cpu_seconds", 0.0)
            iters += max(r.iterations, 0)
            inf["obj"][label] = r.objective if r.success else float("nan")
            cand[label] = r

        if "const-Dmin" in case.starts:
            qp = const_solve(act)
            secs += qp.seconds
            cpu[act.name] += qp.extra.get("cpu_seconds", 0.0)
            attempt("const-Dmin (adopted)", s.evaluate_as(qp, act, A, T, status=qp.status))
            attempt("const-Dmin", s.solve(act, A, T, w0=s.guess_from(qp, act, A, T)))
        if "ramp" in case.starts:
            prof = ramp_u_d_profile(act, dt, act.D_max_Nms_per_rad)
            rq = s.solve(act, A, T, u_d_fixed=prof)
            attempt("ramp (adopted)", rq)
            if rq.success:
                attempt("ramp", s.solve(act, A, T, w0=s.guess_from(rq, act, A, T)))
        if "cold" in case.starts:
            attempt("cold", s.solve(act, A, T))
        info[act.name] = dict(cand=cand, secs=secs, iters=iters, obj=inf["obj"])
    if "cross" in case.starts and len(variable) > 1:
        for act in variable:
            for other in variable:
                if other is act:
                    continue
                ob = _pick(info[other.name]["cand"])
                if ob is None:
                    continue
                r = s.solve(act, A, T, w0=s.guess_from(ob, act, A, T))
                inf = info[act.name]
                inf["secs"] += r.seconds
                cpu[act.name] += r.extra.get("cpu_seconds", 0.0)
                inf["iters"] += max(r.iterations, 0)
                label = f"cross:{other.name}"
                inf["obj"][label] = r.objective if r.success else float("nan")
                inf["cand"][label] = r
    for act in variable:
        inf = info[act.name]
        label = _pick_label(inf["cand"])
        best[act.name] = inf["cand"][label] if label else None
        inf["start"] = label or ""
        inf["n"] = len(inf["cand"])
        if label is None:  # every start failed: record the first failure's status
            first = next(iter(inf["cand"].values()), None)
            inf["status"] = first.status if first is not None else "no start tried"
    for act in case.settings:
        inf = info[act.name]
        rows[act.name] = _row(case, act, best.get(act.name), inf["start"], inf["n"], inf["secs"], inf["iters"],
                              inf["obj"], s, status=inf.get("status"), cpu=cpu[act.name])
    return [rows[a.name] for a in case.settings], best


#: Starts whose objectives agree to this relative tolerance count as a tie;
#: a tie goes to the earlier start (so "won" means "first to reach the best").
TIE_RTOL = 1e-6


def _pick_label(cand: dict[str, OcpResult]) -> str | None:
    ok = {k: r.objective for k, r in cand.items() if r.success and np.isfinite(r.objective)}
    if not ok:
        return None
    fbest = min(ok.values())
    for k, f in ok.items():  # insertion order
        if f <= fbest + TIE_RTOL * abs(fbest) + 1e-15:
            return k
    return None  # pragma: no cover


def _pick(cand: dict[str, OcpResult]) -> OcpResult | None:
    lab = _pick_label(cand)
    return cand[lab] if lab else None


def solve_case(case: RestToRestCase) -> list[dict]:
    """Work function of the sweep: rows for one (A, T) case; never raises.

    Any exception becomes rows with ``status = "error: ..."`` and no result.
    """
    t0 = time.perf_counter()
    try:
        rows, _ = solve_case_results(case)
        return rows
    except Exception as exc:  # noqa: BLE001 - a sweep must never stop on one case
        msg = f"error: {type(exc).__name__}: {exc}".splitlines()[0][:200]
        out = []
        for act in case.settings:
            out.append(_row(case, act, None, "", 0, time.perf_counter() - t0, 0, {}, None, status=msg))
        return out


# -- results file: case-by-case, resumable -----------------------------------------------------------
def _meta(grid: Grid, settings: Sequence[Actuator], mesh: Mesh, starts: Sequence[str], ipopt_options,
          fine_mesh: Mesh | None = None) -> dict:
    m = {
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
    by_case: dict[str, list[dict]] = {}
    with path.open(newline="") as fh:
        for row in csv.DictReader(fh):
            if None in row or any(row.get(c) is None for c in RESULT_COLUMNS):
                continue  # torn / malformed line
            by_case.setdefault(row["case_id"], []).append(row)
    keep = []
    for cid, rs in by_case.items():
        got = {r["setting"] for r in rs}
        if got == names and len(rs) == len(names):
            keep.extend(rs)
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
        Relative margin for "X outperforms Y": ``rmse_X < (1 - rtol) rmse_Y``.

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
    settings = tuple(PAPER_SETTINGS.values()) if settings is None else tuple(settings)
    names = [a.name for a in settings]
    if len(set(names)) != len(names):
        raise ValueError(f"setting names must be unique, got {names}")
    ipo = tuple(sorted((ipopt_options or {}).items()))
    if isinstance(fine_mesh, str):
        if fine_mesh != "auto":
            raise ValueError(f"fine_mesh must be a Mesh, None or 'auto', got {fine_mesh!r}")
        fine_mesh = DEFAULT_FINE_MESH if mesh == DEFAULT_MESH else None
    if fine_mesh is not None and fine_mesh == mesh:
        fine_mesh = None
    if fine_mesh is not None and fine_mesh.n_intervals % 4:
        raise ValueError(f"fine_mesh.n_intervals must be a multiple of 4, got {fine_mesh.n_intervals}")
    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    res_path, meta_path = out / "results.csv", out / "meta.json"
    meta = _meta(grid, settings, mesh, starts, ipo, fine_mesh)
    meta_json = json.loads(json.dumps(meta))
    if res_path.exists() and not restart:
        old = json.loads(meta_path.read_text()) if meta_path.exists() else None
        if old != meta_json:
            raise ValueError(
                f"{res_path} belongs to a different sweep (grid/settings/mesh/starts differ from "
                f"{meta_path}); use another --out folder or restart=True"
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
    cases = [RestToRestCase(A, T, settings, mesh, tuple(starts), ipo, fine_mesh) for A, T in grid.cases()]
    todo = [c for c in cases if c.case_id not in done]
    if done:
        console.print(f"[bold]resuming[/]: {len(done)} of {len(cases)} cases already in {res_path}")

    fh = res_path.open("a", newline="")
    wr = csv.DictWriter(fh, fieldnames=RESULT_COLUMNS)

    def on_result(i: int, rows: list[dict]) -> None:
        wr.writerows(rows)
        fh.flush()

    t0 = time.perf_counter()
    try:
        parallel_map(solve_case, todo, workers=workers, scheduler=scheduler,
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
        "solver_seconds_total": round(float(df["seconds"].sum()), 2),
        "solver_cpu_seconds_total": round(float(df["cpu_seconds"].sum()), 2) if "cpu_seconds" in df else None,
    }
    (out / "summary.json").write_text(json.dumps(summary, indent=2))
    if figures:
        plot_best_map(df, out / "best_map.png")
        names_set = set(df["setting"])
        ex = "VVEA" if "VVEA" in names_set else next((a.name for a in settings if a.variable_damping), settings[0].name)
        Aex = min(grid.A_rad, key=lambda a: abs(a - 0.8))
        Tex = min(grid.T_s, key=lambda t: abs(t - 1.4))
        _, best = solve_case_results(RestToRestCase(Aex, Tex, settings, mesh, tuple(starts), ipo, fine_mesh))
        plot_trajectory(best, Aex, Tex, out / "trajectory.png", highlight=ex)
    return summary


# -- Table 5 ---------------------------------------------------------------------------------------------
#: Table 5 of the paper (fractions and ratios).
PAPER_TABLE5 = {
    "VVEA_beats_SEA": 0.291,
    "VVEA_beats_LWR": 0.892,
    "iVVEA_beats_SEA": 0.896,
    "iVVEA_beats_LWR": 0.908,
    "meanrmse_SEA_over_VVEA": 0.934,
    "meanrmse_LWR_over_VVEA": 1.104,
    "meanrmse_SEA_over_iVVEA": 1.243,
    "meanrmse_LWR_over_iVVEA": 1.521,
}


def table5_statistics(df, outperform_rtol: float = 1e-3) -> dict:
    """Table 5 statistics from a results table (pandas DataFrame of results.csv).

    For every pair (X, Y) of settings with X variable-damping: the fraction of
    cases where ``rmse_X < (1 - rtol) rmse_Y`` and ``mean(rmse_Y)/mean(rmse_X)``,
    over (a) all cases both solved and (b) the cases where at least one
    setting is valid (Fig. 13's coloured points). Also: iVVEA-worse-than-SEA
    count, the winning starts, solver failures, and the paper's numbers.
    """
    import pandas as pd

    df = df.copy()
    df["success"] = df["success"].astype(str).str.lower().isin(["true", "1"])
    df["valid"] = df["valid"].astype(str).str.lower().isin(["true", "1"])
    one = df.drop_duplicates(["case_id", "setting"], keep="last")
    piv = one.pivot(index="case_id", columns="setting", values="rmse").astype(float)
    valid = one.pivot(index="case_id", columns="setting", values="valid").fillna(False).astype(bool)
    any_valid = valid.any(axis=1)
    settings = list(dict.fromkeys(df["setting"]))
    varset = sorted({s for s in settings if (df.loc[df.setting == s, "D_max_Nms_per_rad"]
                                           > df.loc[df.setting == s, "D_min_Nms_per_rad"]).any()},
                    key=settings.index)
    pairs = {}
    for X in varset:
        for Y in settings:
            if Y == X:
                continue
            for scope, mask in (("all", pd.Series(True, index=piv.index)), ("valid", any_valid)):
                sub = piv.loc[mask.reindex(piv.index, fill_value=False), [X, Y]].dropna()
                n = len(sub)
                beats = int((sub[X] < (1 - outperform_rtol) * sub[Y]).sum()) if n else 0
                worse = int((sub[X] > (1 + outperform_rtol) * sub[Y]).sum()) if n else 0
                pairs[f"{X}_vs_{Y}_{scope}"] = {
                    "n_cases": n,
                    "X_beats_Y": beats,
                    "fraction_X_beats_Y": beats / n if n else None,
                    "X_worse_than_Y": worse,
                    "meanrmse_Y_over_X": float(sub[Y].mean() / sub[X].mean()) if n else None,
                }
    guarantee = {}
    if "iVVEA" in settings and "SEA" in settings:
        sub = piv[["iVVEA", "SEA"]].dropna()
        diff = sub["iVVEA"] - sub["SEA"]
        guarantee = {
            "n_cases": len(sub),
            "iVVEA_worse_than_SEA_cases": int((diff > 0).sum()),
            "max_rmse_iVVEA_minus_SEA_rad": float(diff.max()) if len(sub) else None,
        }
    wins = {}
    for X in varset:
        wins[X] = {str(k): int(v) for k, v in df.loc[(df.setting == X) & df.success, "start"]
                   .fillna("").astype(str).str.replace(r"^cross:.*", "cross", regex=True).value_counts().items()}
    failures = df.loc[~df.success, ["case_id", "setting", "status"]]
    best_counts = {}
    for scope_sets in ([s for s in settings if s not in varset or s == v] for v in varset):
        cols = [c for c in scope_sets if c in piv.columns]
        label = "+".join(cols)
        rm = piv[cols].where(valid[cols])
        winner = rm.apply(lambda r: r.dropna().idxmin() if r.notna().any() else "none-valid", axis=1)
        best_counts[label] = {str(k): int(v) for k, v in winner.value_counts().items()}
    return {
        "outperform_rtol": outperform_rtol,
        "n_cases": int(piv.shape[0]),
        "n_cases_any_valid": int(any_valid.sum()),
        "valid_cases_per_setting": {s: int(valid[s].sum()) for s in valid.columns},
        "mean_rmse_rad": {s: float(piv[s].mean()) for s in piv.columns},
        "pairs": pairs,
        "ivvea_vs_sea_guarantee": guarantee,
        "winning_starts": wins,
        "best_valid_setting_counts": best_counts,
        "solver_failures": {"count": int(len(failures)),
                            "by_status": {str(k): int(v) for k, v in failures["status"].value_counts().items()}},
        "paper_table5": PAPER_TABLE5,
        "seconds_per_setting": {s: float(df.loc[df.setting == s, "seconds"].mean()) for s in settings},
    }


# -- figures ---------------------------------------------------------------------------------------------
_COLOURS = {"SEA": "tab:blue", "LWR": "tab:cyan", "VVEA": "tab:purple", "iVVEA": "tab:purple"}


def plot_best_map(df, path: str | Path) -> Path:
    """Fig. 13: best valid setting per (T, A); colour depth = gain over the next best; white = none valid."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from matplotlib.colors import to_rgb
    from matplotlib.patches import Patch

    df = df.copy()
    df["valid"] = df["valid"].astype(str).str.lower().isin(["true", "1"])
    settings = list(dict.fromkeys(df["setting"]))
    varset = [s for s in settings if (df.loc[df.setting == s, "D_max_Nms_per_rad"]
                                      > df.loc[df.setting == s, "D_min_Nms_per_rad"]).any()]
    consts = [s for s in settings if s not in varset]
    panels = varset or [None]
    fig, axes = plt.subplots(len(panels), 1, figsize=(7.5, 3.2 * len(panels)), squeeze=False)
    A_vals = sorted(df["A_rad"].unique())
    T_vals = sorted(df["T_s"].unique())
    palette = ["tab:purple", "tab:green", "tab:red", "tab:orange", "tab:olive"]
    for ax, v in zip(axes[:, 0], panels):
        group = consts + ([v] if v else [])
        cols = {s: _COLOURS.get(s, palette[i % len(palette)]) for i, s in enumerate(group)}
        if v:
            cols[v] = palette[varset.index(v) % len(palette)] if v not in ("VVEA", "iVVEA") else "tab:purple"
        for (A, T), sub in df[df.setting.isin(group)].groupby(["A_rad", "T_s"]):
            sub = sub[sub["valid"]].sort_values("rmse")
            if sub.empty:
                ax.scatter(T, A, s=110, facecolor="white", edgecolor="0.6", linewidth=0.6)
                continue
            w = sub.iloc[0]
            gain = (sub.iloc[1]["rmse"] / w["rmse"] - 1.0) if len(sub) > 1 else 1.0
            depth = 0.25 + 0.75 * min(1.0, gain / 0.3)
            rgb = np.array(to_rgb(cols[w["setting"]]))
            ax.scatter(T, A, s=110, color=1 - depth * (1 - rgb), edgecolor="0.3", linewidth=0.4)
        ax.set_xlabel("period T (s)")
        ax.set_ylabel("amplitude A (rad)")
        ax.set_xticks(T_vals)
        ax.set_xticklabels([f"{t:g}" for t in T_vals], fontsize=7)
        ax.set_yticks(A_vals)
        title = " vs ".join(group)
        D = df.loc[df.setting == v, ["D_min_Nms_per_rad", "D_max_Nms_per_rad"]].iloc[0] if v else None
        if v is not None:
            title += f"  ({D.iloc[0]:.3g} <= D <= {D.iloc[1]:.3g} N m s/rad)"
        ax.set_title(title, fontsize=9)
        handles = [Patch(color=cols[s], label=s) for s in group] + [Patch(facecolor="white", edgecolor="0.6",
                                                                          label="no valid setting")]
        ax.legend(handles=handles, fontsize=7, loc="upper left", bbox_to_anchor=(1.01, 1.0))
    fig.suptitle("Best valid setting per case (deeper colour = bigger gain over the next best)", fontsize=9)
    fig.tight_layout()
    path = Path(path)
    fig.savefig(path, dpi=130)
    plt.close(fig)
    return path


def plot_trajectory(best: dict[str, OcpResult], A_rad: float, T_s: float, path: str | Path,
                    highlight: str | None = None) -> Path:
    """Fig. 12-like plot: link angle vs reference, motor torque and damping of every setting."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from .ocp import rest_to_rest_reference

    fig, axes = plt.subplots(3, 1, figsize=(7, 7), sharex=True)
    tt = np.linspace(0, 2 * T_s, 801)
    axes[0].plot(tt, rest_to_rest_reference(tt, A_rad, T_s), "k--", lw=1, label="q_des")
    for name, r in best.items():
        if r is None or not np.all(np.isfinite(r.q_rad)):
            continue
        lw = 2.0 if name == highlight else 1.0
        axes[0].plot(r.t_s, r.q_rad, lw=lw, label=f"{name} (rmse {r.extra['rmse_rad']:.4f} rad)")
        axes[1].step(r.t_s[:-1], r.tau_m_Nm, where="post", lw=lw, label=name)
        axes[2].plot(r.t_s, r.D_Nms_per_rad, lw=lw, label=name)
    axes[0].set_ylabel("link angle q (rad)")
    axes[1].set_ylabel("motor torque τ_m (N m)")
    axes[2].set_ylabel("damping D (N m s/rad)")
    axes[2].set_yscale("symlog", linthresh=10)
    axes[2].set_xlabel("time t (s)")
    for ax in axes:
        ax.legend(fontsize=7)
        ax.grid(alpha=0.3)
    axes[0].set_title(f"Rest-to-rest optimum, A = {A_rad:g} rad, T = {T_s:g} s", fontsize=9)
    fig.tight_layout()
    path = Path(path)
    fig.savefig(path, dpi=130)
    plt.close(fig)
    return path


# -- safety study (section 6) ---------------------------------------------------------------------------------
#: What the paper states about Fig. 14.
PAPER_SAFETY = {
    "mean_D_variable_Nms_per_rad": 31.0,
    "statement_speed": "variable D reaches tau_ref nearly as fast as D = 200; D = 31 is significantly slower",
    "D_converges_to_min_Nms_per_rad": 12.1,
    "D_converges_at_s": 0.4,
}


def run_safety(
    out_dir: str | Path,
    *,
    base: Actuator = PAPER_SETTINGS["VVEA"],
    M_kgm2: float = 1e4,
    tau_ref_Nm: float = 50.0,
    fixed_D_Nms_per_rad: Sequence[float] = (31.0, 200.0),
    weights: TorqueStepWeights = PAPER_TABLE6,
    mesh: Mesh = Mesh(200, 3, grading=0.8),
    figures: bool = True,
) -> dict:
    """Section 6: torque step with variable damping vs fixed damping.

    Case (a) varies D in [D_min, D_max] of ``base`` from D(0) = D_min and is
    solved from several starts (cold, each fixed-D solution, a ramp) keeping
    the best; cases (b), (c), ... hold D constant. Writes ``safety.json``
    (numbers + the paper's statements), ``safety_trajectories.csv`` and
    ``safety.png``.

    Returns
    -------
    dict
        Per case: objective, mean/max D, time to 95 % of τ_ref, status.
    """
    if not (math.isfinite(M_kgm2) and M_kgm2 > 0):
        raise ValueError(f"M_kgm2 must be a positive inertia, got {M_kgm2!r}")
    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    s = TorqueStepSolver(mesh)
    var = base.with_(M_kgm2=M_kgm2, name=f"variable D {base.D_min_Nms_per_rad:g}-{base.D_max_Nms_per_rad:g}")
    results: dict[str, OcpResult] = {}
    cases = {}
    t0 = time.perf_counter()
    fixed = {}
    for Dc in fixed_D_Nms_per_rad:
        act = base.with_(M_kgm2=M_kgm2, D_min_Nms_per_rad=float(Dc), D_max_Nms_per_rad=float(Dc), name=f"fixed D {Dc:g}")
        # damping cost referenced to the variable case's D_min, as in the paper's single cost
        fixed[act.name] = s.solve(act, tau_ref_Nm, weights, D_cost_ref_Nms_per_rad=base.D_min_Nms_per_rad)
    cand = {"cold": s.solve(var, tau_ref_Nm, weights)}
    col = s.cols[True]
    for name, r in fixed.items():
        if r.success:
            Zp, Up = np.array(r.Z), np.array(r.U)
            Zp[..., 4] = np.clip(Zp[..., 4], var.D_min_Nms_per_rad, var.D_max_Nms_per_rad)
            pv = col.params(var, abs(tau_ref_Nm) / var.K_Nm_per_rad, weights.t_e_s)
            cand[f"from {name}"] = s.solve(var, tau_ref_Nm, weights, w0=col.from_phys(Zp, Up, pv))
    label = _pick_label(cand)
    results[var.name] = cand[label] if label else cand["cold"]
    results.update(fixed)
    for name, r in results.items():
        cases[name] = {
            "status": r.status,
            "success": r.success,
            "objective": r.objective,
            "J_tau_N2m2s": r.extra["J_tau"],
            "J_D": r.extra["J_D"],
            "J_m_N2m2s": r.extra["J_m"],
            "mean_D_Nms_per_rad": r.extra["mean_D_Nms_per_rad"],
            "max_D_Nms_per_rad": r.extra["max_D_Nms_per_rad"],
            "t95_s": r.extra["t95_s"],
            "final_D_Nms_per_rad": float(r.D_Nms_per_rad[-1]),
            "final_tau_Nm": float(r.tau_Nm[-1]),
            "seconds": r.seconds,
        }
    vr = results[var.name]
    near = np.nonzero(vr.D_Nms_per_rad <= var.D_min_Nms_per_rad + 0.05 * (var.D_max_Nms_per_rad - var.D_min_Nms_per_rad))[0]
    # first time after which D stays within 5 % of the range above D_min
    settle = None
    above = np.nonzero(vr.D_Nms_per_rad > var.D_min_Nms_per_rad + 0.05 * (var.D_max_Nms_per_rad - var.D_min_Nms_per_rad))[0]
    if len(near):
        settle = float(vr.t_s[above[-1] + 1]) if len(above) and above[-1] + 1 < len(vr.t_s) else (
            0.0 if not len(above) else None)
    summary = {
        "cases": cases,
        "variable_case": var.name,
        "variable_start_won": label,
        "variable_start_objectives": {k: (v.objective if v.success else None) for k, v in cand.items()},
        "variable_D_settles_near_min_at_s": settle,
        "setup": {"K_Nm_per_rad": base.K_Nm_per_rad, "B_kgm2": base.B_kgm2, "M_kgm2": M_kgm2,
                  "tau_ref_Nm": tau_ref_Nm, "weights": asdict(weights), "mesh": asdict(mesh),
                  "D_range_Nms_per_rad": [base.D_min_Nms_per_rad, base.D_max_Nms_per_rad]},
        "paper": PAPER_SAFETY,
        "wall_seconds": round(time.perf_counter() - t0, 2),
    }
    (out / "safety.json").write_text(json.dumps(summary, indent=2))
    with (out / "safety_trajectories.csv").open("w", newline="") as fh:
        wr = csv.writer(fh)
        wr.writerow(["case", "t_s", "tau_Nm", "tau_m_Nm", "D_Nms_per_rad", "theta_rad", "q_rad"])
        for name, r in results.items():
            taum = np.append(r.tau_m_Nm, r.tau_m_Nm[-1])
            for i in range(len(r.t_s)):
                wr.writerow([name, f"{r.t_s[i]:.6g}", f"{r.tau_Nm[i]:.8g}", f"{taum[i]:.8g}",
                             f"{r.D_Nms_per_rad[i]:.8g}", f"{r.theta_rad[i]:.8g}", f"{r.q_rad[i]:.8g}"])
    if figures:
        _plot_safety(results, tau_ref_Nm, out / "safety.png")
    return summary


def _plot_safety(results: dict[str, OcpResult], tau_ref: float, path: Path, zoom_s: float = 0.03) -> Path:
    """Fig. 14: τ, τ_m and D over the horizon (left) and over the first ``zoom_s`` seconds (right)."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    colours = ["tab:green", "tab:red", "tab:blue", "tab:orange"]
    fig, axes = plt.subplots(3, 2, figsize=(11, 7), sharex="col", gridspec_kw={"width_ratios": [1.4, 1]})
    for col, xmax in ((0, None), (1, zoom_s)):
        ax = axes[:, col]
        for c, (name, r) in zip(colours, results.items()):
            lab = f"{name}: mean D {r.extra['mean_D_Nms_per_rad']:.1f}, t95 {r.extra['t95_s'] * 1e3:.1f} ms"
            ax[0].plot(r.t_s, r.tau_Nm, color=c, label=lab)
            ax[1].step(r.t_s[:-1], r.tau_m_Nm, where="post", color=c, label=name)
            ax[2].plot(r.t_s, r.D_Nms_per_rad, color=c, label=name)
        ax[0].axhline(tau_ref, color="k", ls="--", lw=0.8, label="τ_ref")
        ax[0].axhline(0.95 * tau_ref, color="0.5", ls=":", lw=0.8)
        for a in ax:
            a.grid(alpha=0.3)
            if xmax:
                a.set_xlim(0, xmax)
        ax[2].set_xlabel("time t (s)")
    axes[0, 0].set_ylabel("link torque τ (N m)")
    axes[1, 0].set_ylabel("motor torque τ_m (N m)")
    axes[2, 0].set_ylabel("damping D (N m s/rad)")
    axes[0, 0].legend(fontsize=7, loc="lower right")
    axes[2, 0].legend(fontsize=7)
    axes[0, 0].set_title(f"Optimal {tau_ref:g} N m torque step (paper Fig. 14)", fontsize=9)
    axes[0, 1].set_title(f"first {zoom_s * 1e3:g} ms", fontsize=9)
    fig.tight_layout()
    fig.savefig(path, dpi=130)
    plt.close(fig)
    return path


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


def solve_single(item: tuple[Mesh, Actuator, float, float]) -> dict:
    """Work function: one setting at one (A, T) on one mesh, single start (for QP convergence checks)."""
    mesh, act, A, T = item
    r = _solver(mesh, ()).solve(act, A, T)
    return {"mesh_N": mesh.n_intervals, "mesh_degree": mesh.degree, "setting": act.name, "A_rad": A, "T_s": T,
            "rmse": r.extra["rmse_rad"] if r.success else float("nan"), "status": r.status, "seconds": r.seconds}
