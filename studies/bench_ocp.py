"""Benchmark of the rest-to-rest OCPs: solver build time, time per OCP by setting, total.

    python studies/bench_ocp.py                 # sample of 12 paper-grid cases, serial
    python studies/bench_ocp.py --full          # the whole paper grid on all cores (600 OCPs)

Prints figures; asserts nothing. The machine is shared, so the load average is printed too.
"""

from __future__ import annotations

import argparse
import os
import tempfile
import time

import numpy as np

from vvea_design.actuator.model import PAPER_SETTINGS
from vvea_design.actuator.ocp import RestToRestSolver
from vvea_design.actuator.multistart import DEFAULT_FINE_MESH, DEFAULT_MESH, RestToRestCase, solve_case
from vvea_design.actuator.rest_to_rest import GRIDS, run_rest_to_rest


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("--full", action="store_true", help="run the full paper grid (all cores)")
    ap.add_argument("--workers", type=int, default=None)
    a = ap.parse_args()
    print(f"mesh: {DEFAULT_MESH} (multi-start), {DEFAULT_FINE_MESH} (reported, one polish); cores: {os.cpu_count()}; loadavg: {os.getloadavg()}")
    t0 = time.perf_counter()
    RestToRestSolver(DEFAULT_MESH)
    print(f"solver build (both structures): {time.perf_counter() - t0:.2f} s")
    t0 = time.perf_counter()
    RestToRestSolver(DEFAULT_FINE_MESH)
    print(f"solver build on the fine mesh (both structures): {time.perf_counter() - t0:.2f} s")
    cases = GRIDS["paper"].cases()
    rng = np.random.default_rng(0)
    sample = [cases[i] for i in sorted(rng.choice(len(cases), 12, replace=False))]
    settings = tuple(PAPER_SETTINGS.values())
    per = {s.name: [] for s in settings}
    t0 = time.perf_counter()
    for A, T in sample:
        for row in solve_case(RestToRestCase(A, T, settings, DEFAULT_MESH, fine_mesh=DEFAULT_FINE_MESH)):
            per[row.setting].append(row.seconds)
    wall = time.perf_counter() - t0
    print(f"sample: {len(sample)} cases x {len(settings)} settings = {len(sample) * len(settings)} OCPs, "
          f"{wall:.1f} s serial ({wall / (len(sample) * len(settings)):.2f} s per OCP incl. multi-start)")
    for name, v in per.items():
        print(f"  {name:6s} mean {np.mean(v):.3f} s per OCP (all its starts), max {np.max(v):.3f} s")
    print(f"estimated paper grid (150 cases) on {os.cpu_count()} idle cores: "
          f"{wall / len(sample) * 150 / (os.cpu_count() or 1):.0f} s")
    if a.full:
        with tempfile.TemporaryDirectory() as d:
            t0 = time.perf_counter()
            run_rest_to_rest(d, grid="paper", workers=a.workers, figures=False)
            wall = time.perf_counter() - t0
        print(f"full paper grid: 600 OCPs in {wall:.1f} s wall = {wall / 600:.3f} s per OCP; "
              f"loadavg now {os.getloadavg()}")


if __name__ == "__main__":
    main()
