"""Benchmark of the rest-to-rest OCPs: what each speed-up buys, what it changes, and the targets.

How to run it for the record (on an idle machine, nothing else running; the load is printed and stored):

    python studies/bench_ocp.py --full --no-starts   # the targets only: paper grid + design study (~5 min idle)
    python studies/bench_ocp.py --full               # + the A/B of the starts and their CPU shares (~15 min idle)
    python studies/bench_ocp.py                      # the A/B only (2 amplitudes x 15 periods), CPU time
    python studies/bench_ocp.py --full --jit         # + one NLP compiled with gcc (minutes of compiling)
    python studies/bench_ocp.py --design-starts      # + the design study's starts and barrier update, A/B
    python studies/bench_ocp.py --full --no-starts --multistart-monotone   # the grid with the monotone option
    python studies/bench_ocp.py --full --no-starts --warm-multistart       # the grid with the warm-start option

Run it from the repository root with the package importable (``PYTHONPATH=$PWD`` in a worktree). It ends
with a summary block: the paper grid's wall time (target <= 180 s), the design study's (target <= 8 s, cold
and warm solver cache), the 1/5/15-minute load before and after each, the Table 5 changes against the
committed ``studies/results/rest_to_rest/results.csv`` (target: every fraction and ratio within 0.005) and
each change's share of the CPU saved.

Writes ``studies/results/bench_ocp/bench_ocp.json`` and ``bench_ocp.png`` (``--out`` moves them). Wall times
mean something only on an idle machine (load below ~0.5 per core); CPU times (``time.process_time``) are the
fair A/B measure on a shared one.

Parts:

1. **solver build**: each parametric solver built from its expressions vs read back from the disk cache
   (:mod:`vvea_design.actuator.solver_cache`): the saving of one solver per process, read from disk;
2. **starts** (A/B, same process, same cases): the earlier multi-start (``const-Dmin, ramp, cold, cross``,
   every case on its own), the same without ``cold`` and ``cross``, ``const-Dmin, ramp, neighbour`` in chains
   over the periods of each amplitude (the default), the monotone-barrier option, and the warm-start option
   (``MULTISTART_WARM_IPOPT``) without and with the ``cold`` start: CPU per case, and how many optima change and
   by how much;
3. **shares**: where each variant's CPU goes (coarse QPs, ramp QPs, coarse NLP starts, fine QPs, fine
   polish, re-simulation);
4. ``--jit``: one variable-damping NLP compiled with the system C compiler against CasADi's virtual machine;
5. ``--full``: the paper grid (600 OCPs) with the defaults on all cores, its Table 5 against the committed
   run, and the design study of ``cad/design.json`` (both runs, equal stiffness and full charge), with a cold
   and a warm solver cache.
"""

from __future__ import annotations

import argparse
import contextlib
import json
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np
import pandas as pd

ROOT = Path(__file__).resolve().parents[1]
SAMPLE_A = (0.3, 0.7)
OLD_STARTS = ("const-Dmin", "ramp", "cold", "cross")
#: the starts of the warm-start option's variant that keeps a cold start (``--warm-multistart``)
WARM_COLD_STARTS = ("const-Dmin", "ramp", "cold", "neighbour")


def load() -> list[float]:
    """The 1, 5 and 15 minute load averages."""
    return [round(x, 2) for x in os.getloadavg()]


@contextlib.contextmanager
def cache_in(folder: str | None):
    """The solver cache in ``folder`` (None: off) for the block."""
    old = {k: os.environ.get(k) for k in ("VVEA_CACHE_DIR", "VVEA_SOLVER_CACHE")}
    if folder is None:
        os.environ["VVEA_SOLVER_CACHE"] = "0"
    else:
        os.environ["VVEA_CACHE_DIR"] = folder
        os.environ["VVEA_SOLVER_CACHE"] = "1"
    try:
        yield
    finally:
        for k, v in old.items():
            if v is None:
                os.environ.pop(k, None)
            else:
                os.environ[k] = v


def bench_build() -> dict:
    """CPU seconds of building each solver from its expressions and of reading it back from the cache."""
    from vvea_design.actuator import solver_cache
    from vvea_design.actuator.design_study import DESIGN_SAFETY_MESH
    from vvea_design.actuator.multistart import DEFAULT_FINE_MESH, DEFAULT_MESH, MULTISTART_WARM_IPOPT
    from vvea_design.actuator.ocp import WARM_START_IPOPT, RestToRestSolver, TorqueStepSolver

    out = {}
    with tempfile.TemporaryDirectory() as d, cache_in(d):
        for label, make in (("rest_to_rest N=64", lambda: RestToRestSolver(DEFAULT_MESH)),
                            ("rest_to_rest N=64 warm-start options (the multi-start's starts from a point)",
                             lambda: RestToRestSolver(DEFAULT_MESH, MULTISTART_WARM_IPOPT or WARM_START_IPOPT)),
                            ("rest_to_rest N=192", lambda: RestToRestSolver(DEFAULT_FINE_MESH)),
                            ("rest_to_rest N=192 warm-start options",
                             lambda: RestToRestSolver(DEFAULT_FINE_MESH, WARM_START_IPOPT)),
                            ("torque step N=100", lambda: TorqueStepSolver(DESIGN_SAFETY_MESH))):
            times = []
            for _ in range(2):  # first: built and written; second: read back
                solver_cache._FINGERPRINT = None
                c0 = time.process_time()
                s = make()
                for v in (False, True):
                    s.solvers[v]
                times.append(time.process_time() - c0)
            out[label] = {"build_cpu_s": round(times[0], 3), "cached_cpu_s": round(times[1], 3)}
            print(f"  {label:40s} build {times[0]:6.2f} CPU-s, from the cache {times[1]:5.2f} CPU-s")
    return out


class _Shares:
    """CPU seconds of every solve and re-simulation by kind (wraps the solver's and the verifier's entry points)."""

    def __init__(self, coarse_N: int) -> None:
        self.coarse_N = coarse_N
        self.cpu: dict[str, float] = {}
        self.n: dict[str, int] = {}

    def add(self, kind: str, seconds: float) -> None:
        self.cpu[kind] = self.cpu.get(kind, 0.0) + seconds
        self.n[kind] = self.n.get(kind, 0) + 1

    @contextlib.contextmanager
    def patch(self):
        import vvea_design.actuator.multistart as ms
        from vvea_design.actuator.ocp import RestToRestSolver

        real_solve, real_verify = RestToRestSolver.solve, ms.verify_rest_to_rest

        def solve(solver, actuator, A, T, w0=None, u_d_fixed=None, regularisation=None):
            c0 = time.process_time()
            r = real_solve(solver, actuator, A, T, w0=w0, u_d_fixed=u_d_fixed, regularisation=regularisation)
            coarse = solver.mesh.n_intervals == self.coarse_N
            if not actuator.variable_damping:
                kind = "coarse QP (constant D)" if coarse else "fine QP (constant D)"
            elif u_d_fixed is not None:
                kind = "coarse QP (ramp)"
            else:
                kind = "coarse NLP (every start)" if coarse else "fine polish (NLP)"
            self.add(kind, time.process_time() - c0)
            return r

        def verify(*a, **k):
            c0 = time.process_time()
            v = real_verify(*a, **k)
            self.add("re-simulation", time.process_time() - c0)
            return v

        RestToRestSolver.solve, ms.verify_rest_to_rest = solve, verify
        try:
            yield self
        finally:
            RestToRestSolver.solve, ms.verify_rest_to_rest = real_solve, real_verify


@contextlib.contextmanager
def _replaced(target: dict, options: dict | None):
    """``target`` (a module's option dict) set to ``options`` for the block (None: left as it is)."""
    old = dict(target)
    if options is not None:
        target.clear()
        target.update(options)
    try:
        yield
    finally:
        target.clear()
        target.update(old)


def multistart_options(options: dict | None):
    """The multi-start mesh's IPOPT options (``multistart.MULTISTART_IPOPT``) set to ``options`` for the block
    (None: left as they are)."""
    from vvea_design.actuator.multistart import MULTISTART_IPOPT

    return _replaced(MULTISTART_IPOPT, options)


def warm_multistart(options: dict | None):
    """The multi-start NLPs' warm-start options (``multistart.MULTISTART_WARM_IPOPT``) set to ``options`` for the
    block (None: left as they are; ``{}``: cold starts)."""
    from vvea_design.actuator.multistart import MULTISTART_WARM_IPOPT

    return _replaced(MULTISTART_WARM_IPOPT, options)


def run_variant(starts, chained: bool, amplitudes, coarse_options: dict | None = None, warm: dict | None = None,
                ) -> tuple[pd.DataFrame, float, dict]:
    """The sample's cases with ``starts`` (in chains or each on its own), the multi-start mesh's IPOPT options
    ``coarse_options`` and the multi-start NLPs' warm-start options ``warm`` (None: the defaults): rows, CPU
    seconds, CPU by kind."""
    from vvea_design.actuator.model import PAPER_SETTINGS
    from vvea_design.actuator.multistart import (DEFAULT_FINE_MESH, DEFAULT_MESH, RestToRestCase, chains,
                                                 solve_case, solve_chain)
    from vvea_design.actuator.rest_to_rest import GRIDS

    settings = tuple(PAPER_SETTINGS.values())
    cases = [RestToRestCase(A, T, settings, DEFAULT_MESH, tuple(starts), fine_mesh=DEFAULT_FINE_MESH)
             for A in amplitudes for T in GRIDS["paper"].T_s]
    rows = []
    shares = _Shares(DEFAULT_MESH.n_intervals)
    c0 = time.process_time()
    with shares.patch(), multistart_options(coarse_options), warm_multistart(warm):
        if chained:
            for ch in chains(cases):
                for rs in solve_chain(ch)[0]:
                    rows += rs
        else:
            for c in cases:
                rows += solve_case(c)
    cpu = time.process_time() - c0
    return pd.DataFrame([r.to_dict() for r in rows]), cpu, {k: round(v, 2) for k, v in shares.cpu.items()}


def changes(a: pd.DataFrame, b: pd.DataFrame) -> dict:
    """How the optima of ``b`` differ from ``a``'s, per variable-damping setting (relative rmse change)."""
    out = {}
    m = a.merge(b, on=["case_id", "setting"], suffixes=("_a", "_b"))
    for s in sorted(set(m.setting)):
        sub = m[m.setting == s]
        rel = (sub.rmse_b / sub.rmse_a - 1.0).to_numpy()
        out[s] = {"cases": int(len(rel)), "changed_over_1e-6": int(np.sum(np.abs(rel) > 1e-6)),
                  "changed_over_1e-3": int(np.sum(np.abs(rel) > 1e-3)), "better_over_1e-3": int(np.sum(rel < -1e-3)),
                  "worse_over_1e-3": int(np.sum(rel > 1e-3)), "max_worse": float(np.max(rel, initial=0.0)),
                  "max_better": float(-np.min(rel, initial=0.0)), "mean": float(np.mean(rel)) if len(rel) else 0.0,
                  "validity_changed": int((sub.valid_a != sub.valid_b).sum())}
    return out


def bench_starts(amplitudes) -> dict:
    """Part 2 and 3: the earlier multi-start against the default, on the sample, in this process."""
    from vvea_design.actuator.multistart import DEFAULT_STARTS
    from vvea_design.actuator.ocp import WARM_START_IPOPT
    from vvea_design.actuator.statistics import table5_statistics

    res = {}
    frames = {}
    adaptive: dict = {}  # the defaults: IPOPT's adaptive barrier update (the solver of the default run, no rebuild)
    cold: dict = {}  # the multi-start NLPs with IPOPT's cold options (pushed into the interior from their start)
    for label, starts, chained, opts, warm in (
            ("earlier: const-Dmin, ramp, cold, cross; case by case", OLD_STARTS, False, adaptive, cold),
            ("no cold, no cross", ("const-Dmin", "ramp"), False, adaptive, cold),
            ("default: const-Dmin, ramp, neighbour; chains", DEFAULT_STARTS, True, adaptive, None),
            ("option: the same, monotone barrier on the multi-start mesh", DEFAULT_STARTS, True,
             {"ipopt.mu_strategy": "monotone"}, None),
            ("option: the default started at their points (warm)", DEFAULT_STARTS, True, adaptive, WARM_START_IPOPT),
            ("option: warm, with the cold start", WARM_COLD_STARTS, True, adaptive, WARM_START_IPOPT)):
        print(f"  {label} (load {load()}) ...", flush=True)
        df, cpu, shares = run_variant(starts, chained, amplitudes, opts, warm)
        frames[label] = df
        n = df.case_id.nunique()
        st = table5_statistics(df)
        res[label] = {"starts": list(starts), "chains": chained, "cases": n, "cpu_s": round(cpu, 2),
                      "cpu_per_case_s": round(cpu / n, 3), "cpu_by_kind_s": shares,
                      "table5_counted": {k: p.fraction_X_beats_Y for k, p in st.counted.items()},
                      "meanrmse": {k: p.meanrmse_Y_over_X for k, p in st.counted.items()}, "load_after": load(),
                      "multistart_ipopt_options": opts,
                      "multistart_warm_options": warm if warm is not None else "default"}
        print(f"    {cpu:.1f} CPU-s, {cpu / n:.2f} CPU-s per case; " +
              ", ".join(f"{k} {v:.1f}" for k, v in shares.items()), flush=True)
    base = next(iter(frames.values()))
    items = list(frames.items())
    for (_, prev), (label, df) in zip(items, items[1:]):
        res[label]["optima_vs_earlier"] = changes(base, df)
        res[label]["optima_vs_previous"] = changes(prev, df)
        print(f"  optima of '{label}' against the earlier multi-start's: {json.dumps(res[label]['optima_vs_earlier'])}")
        print(f"  ... against the variant before it: {json.dumps(res[label]['optima_vs_previous'])}")
    return res


def bench_design_starts(amplitudes=(0.4, 1.0)) -> dict:
    """The design study's starts and IPOPT options, A/B in this process (workers=1): with and without the
    neighbour start, adaptive or monotone barrier.

    On a sub-grid of :data:`~vvea_design.actuator.design_study.DESIGN_GRID` (``amplitudes`` x its periods) for
    ``cad/design.json``: CPU seconds of the rest-to-rest solves and how many optima change. Each variant builds its
    own solver (the options are part of the solver), so the first call of a variant includes a build from the
    disk cache.
    """
    import vvea_design.actuator.design_study as ds
    from vvea_design.actuator.rest_to_rest import Grid
    from vvea_design.spring.design_file import load_design

    design = load_design(ROOT / "cad" / "design.json")
    grid = Grid(tuple(amplitudes), ds.DESIGN_GRID.T_s)
    out, frames = {}, {}
    default_options = ds.DESIGN_IPOPT
    adaptive = (("ipopt.mu_strategy", "adaptive"),)
    for label, starts, options in (("const-Dmin, neighbour; adaptive barrier (before)", ("const-Dmin", "neighbour"),
                                    adaptive),
                                   ("const-Dmin; adaptive barrier", ("const-Dmin",), adaptive),
                                   ("const-Dmin; monotone barrier (default)", ("const-Dmin",), default_options)):
        ds.DESIGN_IPOPT = options
        c0 = time.process_time()
        try:
            st = ds.run_design_study(design, workers=1, grid=grid, starts=starts)
        finally:
            ds.DESIGN_IPOPT = default_options
        cpu = time.process_time() - c0
        df = pd.DataFrame([c.to_dict() for c in st.cases])
        df["case_id"] = [f"A{a:.6g}_T{t:.6g}" for a, t in zip(df.A_rad, df.T_s)]
        df = df.rename(columns={"rmse_rad": "rmse"})
        frames[label] = df
        out[label] = {"starts": list(starts), "ipopt": dict(options), "cases": len(grid.cases()),
                      "cpu_s_whole_study": round(cpu, 2),
                      "cpu_s_rest_to_rest_solves": round(st.timing.rest_to_rest_cpu_seconds, 2), "load_after": load()}
        print(f"  {label}: {cpu:.1f} CPU-s (rest-to-rest solves {st.timing.rest_to_rest_cpu_seconds:.1f})", flush=True)
    items = list(frames.items())
    for (_, prev), (label, df) in zip(items, items[1:]):
        out[label]["optima_vs_previous"] = changes(prev, df)
        out[label]["optima_vs_before"] = changes(items[0][1], df)
        print(f"  optima of '{label}' against the variant before it: {json.dumps(out[label]['optima_vs_previous'])}")
    return out


def bench_jit() -> dict:
    """The variable-damping NLP at N = 64 compiled with gcc against CasADi's virtual machine (same solves)."""
    import casadi as ca

    from vvea_design.actuator.model import PAPER_SETTINGS
    from vvea_design.actuator.multistart import DEFAULT_MESH, DEFAULT_REGULARISATION
    from vvea_design.actuator.ocp import RestToRestSolver

    with cache_in(None):
        s = RestToRestSolver(DEFAULT_MESH)
        nlp = s.solvers[True]
    col = s.cols[True]
    out = {}
    with tempfile.TemporaryDirectory() as d:
        c0 = time.process_time()
        cwd = os.getcwd()
        os.chdir(d)
        try:
            nlp.generate_dependencies("rr.c")
        finally:
            os.chdir(cwd)
        out["generate_cpu_s"] = round(time.process_time() - c0, 2)
        out["c_source_MB"] = round(os.path.getsize(Path(d) / "rr.c") / 1e6, 2)
        t0 = time.perf_counter()
        subprocess.run(["gcc", "-O1", "-shared", "-fPIC", str(Path(d) / "rr.c"), "-o", str(Path(d) / "rr.so"), "-lm"],
                       check=True)
        out["gcc_O1_wall_s"] = round(time.perf_counter() - t0, 1)
        compiled = ca.nlpsol("rr", "ipopt", str(Path(d) / "rr.so"), {"ipopt.print_level": 0, "print_time": False,
                                                                       "ipopt.sb": "yes", "ipopt.tol": 1e-8,
                                                                       "ipopt.mu_strategy": "adaptive",
                                                                       "ipopt.max_iter": 1000})
        act = PAPER_SETTINGS["VVEA"]
        for label, solver in (("virtual machine", nlp), ("compiled -O1", compiled)) * 2:
            cpu, objs = 0.0, []
            for A, T in ((0.3, 0.5), (0.7, 1.0), (1.0, 1.4), (0.2, 0.3)):
                pv = col.params(act, A, T)
                lbx, ubx = col.bounds(act, pv)
                w0 = np.clip(np.where(np.isin(np.arange(col.nw), col.iz[:, :, 4].ravel()),
                                      act.D_min_Nms_per_rad / pv[2], 0.0), lbx, ubx)
                c0 = time.process_time()
                sol = solver(x0=w0, p=np.append(pv, DEFAULT_REGULARISATION.weights()), lbx=lbx, ubx=ubx, lbg=0, ubg=0)
                cpu += time.process_time() - c0
                objs.append(float(sol["f"]))
            out[f"{label} solve_cpu_s"] = round(cpu, 3)
            out[f"{label} objectives"] = objs
    print(f"  {json.dumps(out)}")
    return out


def bench_full(out_dir: Path, coarse_options: dict | None = None, warm: dict | None = None,
               starts: tuple[str, ...] | None = None) -> dict:
    """Part 5: the paper grid and the design study with the defaults (wall time; meaningful on an idle machine);
    ``coarse_options``: the paper grid's multi-start mesh IPOPT options instead of the default ones."""
    from vvea_design.actuator.design_study import run_design_study
    from vvea_design.actuator.rest_to_rest import run_rest_to_rest
    from vvea_design.actuator.statistics import table5_statistics
    from vvea_design.spring.design_file import load_design

    res = {}
    with tempfile.TemporaryDirectory() as d, cache_in(str(Path(d) / "cache")):
        l0 = load()
        t0 = time.perf_counter()
        with multistart_options(coarse_options), warm_multistart(warm):
            s = run_rest_to_rest(Path(d) / "grid", grid="paper", figures=False, progress=True,
                                 **({} if starts is None else {"starts": starts}))
        wall = time.perf_counter() - t0
        df = pd.read_csv(Path(d) / "grid" / "results.csv")
        res["paper_grid"] = {"wall_s": round(wall, 1), "target_s": 180, "load_before": l0, "load_after": load(),
                             "multistart_ipopt_options": coarse_options if coarse_options is not None else "default",
                             "multistart_warm_options": warm if warm is not None else "default",
                             "starts": list(starts) if starts is not None else "default",
                             "cpu_of_the_solves_s": round(float(df.cpu_seconds.sum()), 1),
                             "failures": s.statistics.solver_failures["count"],
                             "unverified": s.statistics.unverified["count"],
                             "ivvea_worse_than_sea": s.statistics.ivvea_vs_sea_guarantee["iVVEA_worse_than_SEA_cases"]}
        print(f"  paper grid: {wall:.1f} s wall (target 180 s), load {l0} -> {load()}", flush=True)
        committed = ROOT / "studies" / "results" / "rest_to_rest" / "results.csv"
        if committed.exists():
            old = pd.read_csv(committed)
            a, b = table5_statistics(old), s.statistics
            deltas = {}
            for k, p in b.pairs.items():
                q = a.pairs.get(k)
                if q is not None:
                    deltas[k] = {"fraction": _delta(q.fraction_X_beats_Y, p.fraction_X_beats_Y),
                                 "meanrmse_ratio": _delta(q.meanrmse_Y_over_X, p.meanrmse_Y_over_X)}
            for k, p in b.counted.items():  # every case counted
                q = a.counted.get(k)
                if q is not None:
                    deltas[f"{k}_every_case"] = {"fraction": _delta(q.fraction_X_beats_Y, p.fraction_X_beats_Y),
                                                 "meanrmse_ratio": _delta(q.meanrmse_Y_over_X, p.meanrmse_Y_over_X)}
            res["paper_grid"]["table5_change_vs_committed"] = deltas
            res["paper_grid"]["largest_table5_change"] = max(
                (abs(v) for d_ in deltas.values() for v in d_.values() if v is not None), default=None)
            res["paper_grid"]["optima_vs_committed"] = changes(old, df)
            print(f"  largest Table 5 change against the committed run: {res['paper_grid']['largest_table5_change']}")
        design = load_design(ROOT / "cad" / "design.json")
        for label in ("design study, cold solver cache", "design study, warm solver cache"):
            l0 = load()
            t0 = time.perf_counter()
            st = run_design_study(design, out_dir=Path(d) / "study")
            wall = time.perf_counter() - t0
            res[label] = {"wall_s": round(wall, 2), "target_s": 8, "load_before": l0, "load_after": load(),
                          "timing": st.timing.to_dict()}
            print(f"  {label}: {wall:.1f} s wall (target 8 s), load {l0} -> {load()}", flush=True)
    return res


def optimisations() -> dict:
    """Which speed-ups are on in this tree (what the paper grid and the design study below ran with)."""
    from vvea_design.actuator import solver_cache
    from vvea_design.actuator.design_study import DESIGN_GRID, DESIGN_IPOPT, DESIGN_STARTS
    from vvea_design.actuator.multistart import DEFAULT_STARTS, MULTISTART_IPOPT, MULTISTART_WARM_IPOPT

    return {"paper grid starts": list(DEFAULT_STARTS) + (["(chains)"] if "neighbour" in DEFAULT_STARTS else []),
            "multi-start mesh IPOPT options": dict(MULTISTART_IPOPT) or "defaults (adaptive barrier)",
            "multi-start NLPs warm-started at their start points": dict(MULTISTART_WARM_IPOPT) or "no (cold options)",
            "design study starts": list(DESIGN_STARTS), "design study IPOPT options": dict(DESIGN_IPOPT),
            "fine-mesh QPs": "warm-started from the multi-start mesh's QP",
            "design study grid": f"{len(DESIGN_GRID.A_rad)} x {len(DESIGN_GRID.T_s)}",
            "solver disk cache": solver_cache.cache_enabled(), "compiled functions": False}


def summary(res: dict) -> list[str]:
    """The lines the coordinator reads: targets, loads, Table 5 changes, each change's share of the CPU saved."""
    lines = [f"machine: {res['machine']['cores']} cores, load at start {res['machine']['load_start']}, "
             f"at the end {res['machine'].get('load_end')} (1/5/15 min; wall times count only near 0)",
             "optimisations on: " + "; ".join(f"{k} = {v}" for k, v in res.get("optimisations", {}).items())]
    full = res.get("full", {})
    g = full.get("paper_grid")
    if g:
        lines.append(f"paper grid (600 OCPs): {g['wall_s']} s wall, target {g['target_s']} s -> "
                     f"{'MET' if g['wall_s'] <= g['target_s'] else 'NOT met'}; load {g['load_before']} -> "
                     f"{g['load_after']}; {g['cpu_of_the_solves_s']} CPU-s of solves; failures {g['failures']}, "
                     f"unverified {g['unverified']}, iVVEA worse than SEA {g['ivvea_worse_than_sea']}")
        if "table5_change_vs_committed" in g:
            big = g["largest_table5_change"]
            lines.append(f"Table 5 against the committed run: largest change {big} (target 0.005 -> "
                         f"{'MET' if big is not None and big <= 0.005 else 'NOT met'})")
            for k, d in g["table5_change_vs_committed"].items():
                lines.append(f"  {k:32s} fraction {d['fraction']!s:>8s}   mean rmse ratio {d['meanrmse_ratio']!s:>8s}")
    for k, v in full.items():
        if k.startswith("design study"):
            lines.append(f"{k}: {v['wall_s']} s wall, target {v['target_s']} s -> "
                         f"{'MET' if v['wall_s'] <= v['target_s'] else 'NOT met'}; load {v['load_before']} -> "
                         f"{v['load_after']}")
    st = res.get("starts")
    if st and len(st) > 1:
        labels = list(st)
        cpu = [st[k]["cpu_per_case_s"] for k in labels]
        saved = cpu[0] - cpu[-1]
        lines.append(f"CPU per case (4 settings, both meshes): " + ", ".join(f"{k.split(';')[0]} {c:.2f} s"
                                                                           for k, c in zip(labels, cpu)))
        for (a, ca), (b, cb) in zip(zip(labels, cpu), zip(labels[1:], cpu[1:])):
            share = (ca - cb) / saved if saved > 0 else float("nan")
            lines.append(f"  '{a.split(';')[0]}' -> '{b.split(';')[0]}': {ca - cb:+.2f} CPU-s per case saved "
                         f"({100 * share:.0f} % of the starts' saving)")
        for k in labels[1:]:
            ch = st[k].get("optima_vs_earlier", {})
            lines.append(f"  optima changed by '{k.split(';')[0]}' (> 1e-3 relative rmse): " + ", ".join(
                f"{s_} {v['changed_over_1e-3']}/{v['cases']} (worst +{v['max_worse']:.2g}, best -{v['max_better']:.2g})"
                for s_, v in ch.items()))
    b = res.get("build")
    if b:
        per_process = sum(v["build_cpu_s"] - v["cached_cpu_s"] for v in b.values())
        lines.append(f"solver disk cache: {per_process:.1f} CPU-s saved per worker process (every solver read "
                     "back instead of built)")
    return lines


def _delta(a, b):
    return None if a is None or b is None else round(float(b) - float(a), 4)


def figure(res: dict, path: Path) -> None:
    """Bars: CPU per case of each start variant (split by kind), build vs cache, and the wall times vs targets."""
    from matplotlib.figure import Figure

    starts = res.get("starts", {})
    panels = 2 + ("full" in res)
    fig = Figure(figsize=(5.0 * panels, 4.2))
    axes = fig.subplots(1, panels)
    ax = axes[0]
    kinds = sorted({k for v in starts.values() for k in v["cpu_by_kind_s"]})
    labels = list(starts)
    bottom = np.zeros(len(labels))
    for k in kinds:
        vals = np.array([starts[l]["cpu_by_kind_s"].get(k, 0.0) / starts[l]["cases"] for l in labels])
        ax.bar(range(len(labels)), vals, bottom=bottom, label=k)
        bottom += vals
    for i, l in enumerate(labels):
        ax.text(i, starts[l]["cpu_per_case_s"], f"{starts[l]['cpu_per_case_s']:.2f}", ha="center", va="bottom",
                fontsize=8)
    ax.set_xticks(range(len(labels)))
    ax.set_xticklabels([l.split(":")[0].split(";")[0] for l in labels], fontsize=7, rotation=10)
    ax.set_ylabel("CPU s per case (4 settings, both meshes)")
    ax.set_title("Starts: CPU per case by kind of solve", fontsize=9)
    if starts:
        ax.legend(fontsize=6, loc="upper right")
    else:  # --no-starts: say so rather than leave an empty frame
        ax.text(0.5, 0.5, "not run (--no-starts)", ha="center", va="center", transform=ax.transAxes, fontsize=9)
        ax.set_xticks([])
    bx = axes[1]
    build = res.get("build", {})
    names = list(build)
    x = np.arange(len(names))
    bx.bar(x - 0.2, [build[n]["build_cpu_s"] for n in names], 0.4, label="built from the expressions")
    bx.bar(x + 0.2, [build[n]["cached_cpu_s"] for n in names], 0.4, label="read from the disk cache")
    bx.set_xticks(x)
    bx.set_xticklabels([n.replace("rest_to_rest ", "").split(" warm-start options")[0].replace(" N=", "\nN=") +
                        ("\nwarm" if "warm-start" in n else "") for n in names],
                       fontsize=7)
    bx.set_ylabel("CPU s per process")
    bx.set_title("Solver build, once per process", fontsize=9)
    bx.legend(fontsize=7, loc="upper left")
    bx.set_ylim(0, 1.3 * max([build[n]["build_cpu_s"] for n in names] or [1.0]))
    if "full" in res:
        cx = axes[2]
        items = [(k, v) for k, v in res["full"].items() if "wall_s" in v]
        cx.barh(range(len(items)), [v["wall_s"] for _, v in items], color="0.5")
        for i, (k, v) in enumerate(items):
            cx.plot([v["target_s"]] * 2, [i - 0.4, i + 0.4], color="red")
            cx.text(v["wall_s"], i, f" {v['wall_s']:.1f} s (load {v['load_before'][0]})", va="center", fontsize=7)
        cx.set_yticks(range(len(items)))
        cx.set_yticklabels([k.replace("_", " ").replace(", ", ",\n") for k, _ in items], fontsize=7)
        cx.set_xscale("log")
        cx.set_xlim(right=8 * max(v["wall_s"] for _, v in items))  # room for the value labels
        cx.set_xlabel("wall time (s); red: target")
        cx.set_title("Targets (meaningful only on an idle machine)", fontsize=9)
    fig.suptitle(f"bench_ocp: {res['machine']['cores']} cores, load at start {res['machine']['load_start']}",
                 fontsize=9)
    fig.subplots_adjust(left=0.06, right=0.98, bottom=0.2, top=0.85, wspace=0.6 if panels == 3 else 0.3)
    fig.savefig(path, dpi=120)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--full", action="store_true", help="also the paper grid and the design study (wall time)")
    ap.add_argument("--jit", action="store_true", help="also compile one NLP with gcc (minutes)")
    ap.add_argument("--design-starts", action="store_true",
                    help="also the design study's starts A/B (with and without the neighbour start)")
    ap.add_argument("--amplitudes", default=",".join(map(str, SAMPLE_A)),
                    help="amplitudes (rad) of the A/B sample; every period of the paper grid each")
    ap.add_argument("--multistart-monotone", action="store_true",
                    help="with --full: the paper grid with the monotone barrier on the multi-start mesh (an option, "
                         "not the default: it moves iVVEA optima)")
    ap.add_argument("--warm-multistart", action="store_true",
                    help="with --full: the grid with the warm-start option (the starts from a point started at it, plus "
                         "the cold start; not the default: it moves iVVEA optima)")
    ap.add_argument("--no-starts", action="store_true", help="skip the A/B of the starts (with --full: the targets only)")
    ap.add_argument("--out", type=Path, default=ROOT / "studies" / "results" / "bench_ocp")
    a = ap.parse_args()
    res = {"machine": {"cores": os.cpu_count(), "load_start": load(), "python": sys.version.split()[0],
                       "started": time.strftime("%Y-%m-%d %H:%M:%S")}, "optimisations": optimisations()}
    print(f"cores {os.cpu_count()}, load {load()}")
    print("optimisations on: " + "; ".join(f"{k} = {v}" for k, v in res["optimisations"].items()))
    import casadi

    res["machine"]["casadi"] = casadi.__version__
    print("1. solver build (CPU s; build vs disk cache):")
    res["build"] = bench_build()
    if not a.no_starts:
        print("2./3. starts, A/B on the sample (CPU s, one process):")
        res["starts"] = bench_starts(tuple(float(x) for x in a.amplitudes.split(",")))
    if a.design_starts:
        print("2b. the design study's starts (CPU s, one process):")
        res["design_starts"] = bench_design_starts()
    if a.jit:
        print("4. compiled functions:")
        res["jit"] = bench_jit()
    if a.full:
        print("5. the targets (wall s):")
        from vvea_design.actuator.ocp import WARM_START_IPOPT

        res["full"] = bench_full(a.out, {"ipopt.mu_strategy": "monotone"} if a.multistart_monotone else None,
                                 dict(WARM_START_IPOPT) if a.warm_multistart else None,
                                 WARM_COLD_STARTS if a.warm_multistart else None)
    res["machine"]["load_end"] = load()
    res["summary"] = summary(res)
    print("\nsummary:")
    print("\n".join(res["summary"]))
    a.out.mkdir(parents=True, exist_ok=True)
    (a.out / "bench_ocp.json").write_text(json.dumps(res, indent=2))
    figure(res, a.out / "bench_ocp.png")
    print(f"wrote {a.out / 'bench_ocp.json'} and bench_ocp.png; load at the end {load()}")


if __name__ == "__main__":
    main()
