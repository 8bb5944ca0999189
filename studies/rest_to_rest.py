"""Paper section 5: the rest-to-rest study on the paper grid (Table 5, Fig. 13).

    python studies/rest_to_rest.py                       # -> studies/results/rest_to_rest/
    python studies/rest_to_rest.py --design my.json --out runs/rest_to_rest_design
    python studies/rest_to_rest.py --scheduler tcp://host:8786

Same as ``vvea study rest-to-rest``; resumes an interrupted run in the same folder.
"""

from __future__ import annotations

import argparse
import json
import os
import time
from pathlib import Path

from vvea_design.actuator.model import PAPER_SETTINGS, from_design_json
from vvea_design.actuator.ocp import Mesh
from vvea_design.actuator.multistart import DEFAULT_MESH
from vvea_design.actuator.rest_to_rest import run_rest_to_rest


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--out", type=Path, default=Path(__file__).parent / "results" / "rest_to_rest")
    ap.add_argument("--grid", default="paper", choices=["paper", "coarse"])
    ap.add_argument("--design", type=Path, default=None, help="design JSON: adds setting 'design'")
    ap.add_argument("--scheduler", default=None)
    ap.add_argument("--workers", type=int, default=None)
    ap.add_argument("--restart", action="store_true")
    ap.add_argument("--mesh-n", type=int, default=0, help="multi-start mesh intervals (0 = default 64)")
    ap.add_argument("--fine-mesh-n", type=int, default=0,
                    help="reporting mesh intervals (0 = default: 192 with the default --mesh-n; -1 = none)")
    a = ap.parse_args()
    settings = list(PAPER_SETTINGS.values())
    if a.design:
        settings.append(from_design_json(a.design))
    load0 = os.getloadavg()
    t0 = time.perf_counter()
    mesh = DEFAULT_MESH if a.mesh_n == 0 else Mesh(a.mesh_n, DEFAULT_MESH.degree)
    fine = "auto" if a.fine_mesh_n == 0 else (None if a.fine_mesh_n < 0 else Mesh(a.fine_mesh_n, DEFAULT_MESH.degree))
    s = run_rest_to_rest(a.out, grid=a.grid, settings=settings, mesh=mesh, fine_mesh=fine, workers=a.workers,
                         scheduler=a.scheduler, restart=a.restart)
    wall = time.perf_counter() - t0
    st = s.statistics.to_dict()
    print(json.dumps({"wall_seconds": round(wall, 1), "loadavg_start": load0, "loadavg_end": os.getloadavg(),
                      "pairs": st["pairs"], "ivvea_vs_sea": st["ivvea_vs_sea_guarantee"],
                      "winning_starts": st["winning_starts"], "failures": st["solver_failures"]}, indent=1))


if __name__ == "__main__":
    main()
