"""Benchmark of the design's own actuator study (``run_design_study``), the part of ``vvea design``
that solves optimal-control problems.

    python studies/bench_design_study.py                       # cad/design.json, all cores
    python studies/bench_design_study.py --design my.json --workers 1
    python studies/bench_design_study.py --out studies/results/design_study   # keep the files

Prints the time breakdown (imports, solver builds, per-setting solve times, the whole study with
figures), the CPU seconds, where IPOPT spends its time (function evaluations vs its own linear
algebra: what CasADi code generation / JIT could save at most) and the load average. Asserts nothing.
"""

from __future__ import annotations

import argparse
import os
import tempfile
import time
from pathlib import Path

t_import0 = time.perf_counter()
from vvea_design.actuator.design_study import (  # noqa: E402
    DESIGN_MESH,
    DESIGN_SAFETY_MESH,
    design_actuator,
    run_design_study,
)
from vvea_design.actuator.model import PAPER_SETTINGS  # noqa: E402
from vvea_design.actuator.multistart import DEFAULT_REGULARISATION  # noqa: E402
from vvea_design.actuator.ocp import RestToRestSolver, TorqueStepSolver  # noqa: E402
from vvea_design.jobs.studies import design_study_lines  # noqa: E402
from vvea_design.spring.design_file import load_design  # noqa: E402

T_IMPORT = time.perf_counter() - t_import0


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--design", type=Path, default=Path(__file__).resolve().parents[1] / "cad" / "design.json")
    ap.add_argument("--workers", type=int, default=None)
    ap.add_argument("--out", type=Path, default=None, help="keep the study's files here (default: a temporary folder)")
    a = ap.parse_args()
    print(f"cores: {os.cpu_count()}; loadavg at start: {os.getloadavg()}")
    print(f"import of the actuator wing (casadi, scipy, matplotlib): {T_IMPORT:.2f} s")
    design = load_design(a.design)
    act = design_actuator(design)
    print(f"design actuator: K = {act.K_Nm_per_rad:.0f} N m/rad, D = {act.D_min_Nms_per_rad:.3g}-"
          f"{act.D_max_Nms_per_rad:.4g} N m s/rad")

    t0 = time.perf_counter()
    s = RestToRestSolver(DESIGN_MESH)
    print(f"rest-to-rest solver build, N = {DESIGN_MESH.n_intervals} (both structures): {time.perf_counter() - t0:.2f} s")
    t0 = time.perf_counter()
    TorqueStepSolver(DESIGN_SAFETY_MESH)
    print(f"torque-step solver build, N = {DESIGN_SAFETY_MESH.n_intervals}: {time.perf_counter() - t0:.2f} s")

    # one representative solve per setting: IPOPT's own time vs function evaluations
    A, T = 0.7, 1.0
    for name, x in (("design", act), ("VVEA", PAPER_SETTINGS["VVEA"]), ("SEA", PAPER_SETTINGS["SEA"])):
        c0 = time.process_time()
        r = s.solve(x, A, T, regularisation=DEFAULT_REGULARISATION)
        cpu = time.process_time() - c0
        st = s.solvers[x.variable_damping].stats()
        fev = sum(v for k, v in st.items() if k.startswith("t_wall_nlp_"))
        print(f"  one cold solve {name:6s} (A = {A} rad, T = {T} s): {r.iterations} iterations, {cpu:.3f} CPU-s, "
              f"function evaluations {fev:.3f} s = {100 * fev / max(r.seconds, 1e-9):.0f} % of the solve")

    with tempfile.TemporaryDirectory() as tmp:
        d = a.out if a.out is not None else tmp
        stages = []
        t0 = time.perf_counter()
        c0 = time.process_time()
        study = run_design_study(design, out_dir=d, workers=a.workers,
                                 progress=lambda i, n, m: stages.append((time.perf_counter() - t0, i, n, m)))
        wall = time.perf_counter() - t0
        cpu_parent = time.process_time() - c0
    print(f"\nrun_design_study: {len(study.grid.cases())} cases x {len(study.settings)} settings + 2 torque steps "
          f"on {study.timing.workers} worker(s)")
    for t, i, n, m in stages:
        print(f"  [{t:6.1f} s] {i:2d}/{n} {m}")
    tm = study.timing
    print(f"breakdown: solves (parallel) {tm.rest_to_rest_and_safety_s:.1f} s, figures + files {tm.figures_s:.1f} s, "
          f"total {tm.total_s:.1f} s (wall {wall:.1f} s); IPOPT wall summed over workers {tm.solver_seconds:.1f} s; "
          f"rest-to-rest IPOPT CPU summed over workers {tm.rest_to_rest_cpu_seconds:.1f} s; parent CPU {cpu_parent:.1f} s")
    print("mean rmse per setting over its valid, verified cases: " +
          ", ".join(f"{x.name} {x.mean_rmse_rad:.4f} rad" for x in study.settings))
    for line in design_study_lines(study):  # both runs, every case counted, the damping range's source
        print(line)
    for r in study.runs:
        u = r.damping_use
        print(f"[{r.label}] the valve: {u.n_cases} valid optima, {u.n_reach_D_max} reach D_max, {u.n_stay_at_D_min} "
              f"stay at D_min, highest D {u.largest_D_used_Nms_per_rad:.4g} N m s/rad, largest damping torque "
              f"{u.largest_damping_torque_Nm:.4g} N m (relief {'unknown' if u.relief_torque_Nm is None else f'{u.relief_torque_Nm:.4g}'} N m, above it: {u.n_over_relief})")
    print(f"unverified trajectories (counted as not valid): {study.n_left_out}; invalid per setting: " +
          ", ".join(f"{x.name} {x.n_cases - x.n_valid}" for x in study.settings))
    print(f"loadavg at the end: {os.getloadavg()}")


if __name__ == "__main__":
    main()
