"""Paper section 5: the rest-to-rest study on the paper grid (Table 5, Fig. 13).

    python studies/rest_to_rest.py                       # -> studies/results/rest_to_rest/
    python studies/rest_to_rest.py --design my.json --out studies/results/rest_to_rest_design
    python studies/rest_to_rest.py --scheduler tcp://host:8786

Same as ``vvea study rest-to-rest``; resumes an interrupted run in the same folder.
"""

from __future__ import annotations

import argparse
import json
import os
import time
from pathlib import Path

from vvea_design.actuator import PAPER_SETTINGS, from_design_json
from vvea_design.studies_actuator import run_rest_to_rest


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--out", type=Path, default=Path(__file__).parent / "results" / "rest_to_rest")
    ap.add_argument("--grid", default="paper", choices=["paper", "coarse"])
    ap.add_argument("--design", type=Path, default=None, help="design JSON: adds setting 'design'")
    ap.add_argument("--scheduler", default=None)
    ap.add_argument("--workers", type=int, default=None)
    ap.add_argument("--restart", action="store_true")
    a = ap.parse_args()
    settings = list(PAPER_SETTINGS.values())
    if a.design:
        settings.append(from_design_json(a.design))
    load0 = os.getloadavg()
    t0 = time.perf_counter()
    s = run_rest_to_rest(a.out, grid=a.grid, settings=settings, workers=a.workers, scheduler=a.scheduler,
                         restart=a.restart)
    wall = time.perf_counter() - t0
    print(json.dumps({"wall_seconds": round(wall, 1), "loadavg_start": load0, "loadavg_end": os.getloadavg(),
                      "pairs": s["pairs"], "ivvea_vs_sea": s["ivvea_vs_sea_guarantee"],
                      "winning_starts": s["winning_starts"], "failures": s["solver_failures"]}, indent=1))


if __name__ == "__main__":
    main()
