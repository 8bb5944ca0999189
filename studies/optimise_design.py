"""The optimiser's study: the optimum on the default requirements, Pareto fronts and linearity maps.

    python studies/optimise_design.py [--out DIR] [--quick]

Writes into studies/results/optimise/ by default:
  design.json, design_force.png         the optimum (seed 0)
  pareto_<axis>.csv/.png                 linearity vs stiffness, outer diameter, mass
  map_<x>_<y>.csv/.png                   linearity over two variables around the optimum
  summary.json                           the numbers quoted in the README
"""

from __future__ import annotations

import argparse
import csv
import json
from pathlib import Path

import numpy as np

from vvea_design.design_io import save_design
from vvea_design.optimise import PARETO_AXES, linearity_map, optimise, pareto_front
from vvea_design.plots import plot_linearity_map, plot_pareto, plot_spring
from vvea_design.spec import Requirements

HERE = Path(__file__).resolve().parent

SWEEPS = {
    "stiffness": [30.0, 50.0, 70.0, 93.2, 110.0, 130.0],
    "outer_diameter": [45.0, 50.0, 55.0, 59.5, 65.0, 70.0],
    "mass": [350.0, 400.0, 450.0, 500.0, 600.0],
}
MAPS = [("outer_diameter_mm", "V2_mm3"), ("piston_diameter_mm", "V1_mm3")]


def main(out: Path, quick: bool = False) -> dict:
    out.mkdir(parents=True, exist_ok=True)
    req = Requirements()
    res = optimise(req, seed=0)
    save_design(out / "design.json", res.evaluation, req, optimiser=res.summary())
    plot_spring(res.design.gas_spring, out / "design_force.png", extra_charges_MPa=(1.0, 2.0),
                title=f"optimum on the default requirements: {100 * res.evaluation.linearity_error:.2f} %")
    summary = {"optimum": {**res.evaluation.performance(), "binding": res.evaluation.binding(),
                           "seconds": res.seconds, "evaluations": res.evaluations}}
    for axis, values in SWEEPS.items():
        vals = values[::2] if quick else values
        rows = pareto_front(req, axis, vals, seed=0)
        keys = sorted({k for r in rows for k in r})
        with open(out / f"pareto_{axis}.csv", "w", newline="") as fh:
            w = csv.DictWriter(fh, fieldnames=keys)
            w.writeheader()
            w.writerows(rows)
        field, label = PARETO_AXES[axis]
        plot_pareto(rows, field, label, out / f"pareto_{axis}.png", title=f"best linearity vs {axis}")
        summary[f"pareto_{axis}"] = [{field: r[field], "linearity_error": r.get("linearity_error"),
                                      "feasible": r["feasible"], "binding": r.get("binding", "")} for r in rows]
    for vx, vy in MAPS:
        m = linearity_map(res.design, req, vx, vy, n=31 if quick else 61)
        plot_linearity_map(m, out / f"map_{vx}_{vy}.png", optimum=(getattr(res.design, vx), getattr(res.design, vy)))
        np.savez_compressed(out / f"map_{vx}_{vy}.npz", x=m["x"], y=m["y"], linearity=m["linearity"], feasible=m["feasible"])
    (out / "summary.json").write_text(json.dumps(summary, indent=2, sort_keys=True, default=float) + "\n")
    print(json.dumps(summary["optimum"], indent=2, default=float))
    return summary


if __name__ == "__main__":
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--out", type=Path, default=HERE / "results" / "optimise")
    ap.add_argument("--quick", action="store_true", help="fewer Pareto points and coarser maps")
    a = ap.parse_args()
    main(a.out, a.quick)
