"""Which property of the unit buys tracking: D_min, D_max or K (the design against an SEA of the same K).

    python studies/design_sensitivity.py                          # cad/design.json -> studies/results/design_sensitivity/
    python studies/design_sensitivity.py --design my.json --out runs/sens --workers 2

Writes ``sensitivity.csv`` (every OCP), ``sensitivity.json`` and ``sensitivity.png`` and prints the answer
(:meth:`vvea_design.actuator.sensitivity.DesignSensitivity.answer`) and the load average.
"""

from __future__ import annotations

import argparse
import os
import time
import warnings
from pathlib import Path

from vvea_design.jobs.studies import run_design_sensitivity
from vvea_design.spring.design_file import load_design

ROOT = Path(__file__).resolve().parents[1]


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--design", type=Path, default=ROOT / "cad" / "design.json")
    ap.add_argument("--out", type=Path, default=ROOT / "studies" / "results" / "design_sensitivity")
    ap.add_argument("--target-K", type=float, default=362.0, help="joint stiffness of the base design, N m/rad")
    ap.add_argument("--workers", type=int, default=None)
    a = ap.parse_args()
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # an old design file loads with its own rules (said in the CAD's report)
        design = load_design(a.design)
    l0 = os.getloadavg()
    t0 = time.perf_counter()
    s = run_design_sensitivity(design, out=a.out, target_K_Nm_per_rad=a.target_K, workers=a.workers)
    print(f"{time.perf_counter() - t0:.1f} s wall, load {l0} -> {os.getloadavg()}")
    print(f"damping range: {s.damping.D_min_Nms_per_rad:.3g}-{s.damping.D_max_Nms_per_rad:.4g} N m s/rad "
          f"({s.damping.source})")
    for p in s.points:
        r = "-" if p.mean_rmse_ratio_design_over_sea is None else f"{p.mean_rmse_ratio_design_over_sea:.3f}"
        print(f"  {p.parameter:5s} {p.value:9.4g}{' (base)' if p.is_base else '       '}: design/SEA {r}, wins "
              f"{p.design_beats} of {p.n_cases}, losses {p.design_worse} (of those, design not valid "
              f"{p.only_sea_valid}) {p.note}")
    print(s.answer())


if __name__ == "__main__":
    main()
