"""Which property of the unit buys tracking: D_min, D_max or K (the design against an SEA of the same K).

    python studies/design_sensitivity.py                          # cad/design.json -> studies/results/design_sensitivity/
    python studies/design_sensitivity.py --design my.json --out runs/sens --workers 2
    python studies/design_sensitivity.py --grid 0.2,0.4,0.7,1.0:0.6,1.5 --D-min 0,24.4 --D-max 100,400 \
        --K-factors 0.75,1,1.5                                    # fewer cases and values (the committed run)

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
    ap.add_argument("--grid", default=None, help="'A1,A2,..:T1,T2,..' (rad:s); default the design study's 3 x 3")
    ap.add_argument("--D-min", default=None, help="D_min values, N m s/rad, comma separated (the unit's own is added; "
                                                  "default around it)")
    ap.add_argument("--D-max", default=None, help="D_max values, N m s/rad, comma separated (the unit's own is "
                                                  "added)")
    ap.add_argument("--K-factors", default="0.5,0.75,1,1.5,2", help="joint stiffnesses as multiples of the target")
    a = ap.parse_args()
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # an old design file loads with its own rules (said in the CAD's report)
        design = load_design(a.design)

    def floats(text):
        return None if text is None else tuple(float(v) for v in text.split(","))

    d_min, d_max = floats(a.D_min), floats(a.D_max)
    if d_min is not None or d_max is not None:  # the unit's own values join the asked ones (the star)
        from vvea_design.actuator.design_study import study_actuators

        rng = study_actuators(design, target_K_Nm_per_rad=a.target_K)[1]
        d_min = None if d_min is None else tuple(sorted({*d_min, rng.D_min_Nms_per_rad}))
        d_max = None if d_max is None else tuple(sorted({*d_max, rng.D_max_Nms_per_rad}))
    l0 = os.getloadavg()
    t0 = time.perf_counter()
    s = run_design_sensitivity(design, out=a.out, target_K_Nm_per_rad=a.target_K, workers=a.workers, grid=a.grid,
                               D_min_values=d_min, D_max_values=d_max, K_factors=floats(a.K_factors))
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
