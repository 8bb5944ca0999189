"""The optimiser's study: the optimum on the default requirements, Pareto fronts and linearity maps.

    python studies/optimise_design.py [--out DIR] [--quick]

Writes into studies/results/optimise/ by default:
  design.json, design_force.png         the optimum (seed 0)
  pareto_<axis>.csv/.png                 linearity vs stiffness, outer diameter, mass
  map_<x>_<y>.npz/.png                   linearity over two variables around the optimum
  cast_fill.csv/.png                     where the bladder is cast: linearity vs FE strain bound
  summary.json                           the numbers quoted in the README
"""

from __future__ import annotations

import argparse
import csv
import json
from pathlib import Path

import numpy as np

from vvea_design.figure_layout import tight_layout_once
from vvea_design.jobs.spring import optimise as optimise_job
from vvea_design.spring.optimise import optimise
from vvea_design.spring.studies import PARETO_AXES, linearity_map, pareto_front, save_pareto
from vvea_design.spring.plots import plot_linearity_map, save_figure
from vvea_design.spring.requirements import Requirements

HERE = Path(__file__).resolve().parent

SWEEPS = {
    "stiffness": [30.0, 50.0, 70.0, 93.2, 110.0, 130.0],
    "outer_diameter": [45.0, 50.0, 55.0, 59.5, 65.0, 70.0],
    "mass": [450.0, 480.0, 500.0, 550.0, 600.0],
}
#: Caps on the adiabatic (n = 1.4) linearity: the isothermal vs adiabatic Pareto front.
ADIABATIC_CAPS = [0.0208, 0.0215, 0.0225, 0.0240, 0.0255, 0.0270]
MAPS = [("outer_diameter_mm", "V2_mm3"), ("piston_diameter_mm", "V1_mm3")]


def cast_fill_tradeoff(out: Path, fills=(0.0, 0.25, 0.5, 0.75)) -> list[dict]:
    """Optimum and FE bladder check for bladders cast at different stroke fractions.

    Cast at x = 0 (fill 0) the bladder only expands: no inward room is needed, so the annulus holds
    more gas (better linearity) but the whole displaced volume stretches it. Cast at mid-stroke
    (fill 0.5, the default, like the paper's ±0.03 MPa cases) it shares the volume both ways.
    """
    from dataclasses import replace

    import matplotlib.pyplot as plt

    from vvea_design.bladder.check import check_bladder
    from vvea_design.spring.plots import save_figure

    rows = []
    for fill in fills:
        req = Requirements()
        req = replace(req, fixed=replace(req.fixed, bladder_cast_fill=fill))
        r = optimise(req, seed=0, progress=False)
        b = check_bladder(r.design).to_dict()
        rows.append({"bladder_cast_fill": fill, "linearity_error": r.evaluation.linearity_error,
                     "strain_bound": b["strain_bound"], "allowable_strain": b["allowable_strain"],
                     "passes": b["passes"], "V2_mm3": r.design.V2_mm3})
    with open(out / "cast_fill.csv", "w", newline="") as fh:
        w = csv.DictWriter(fh, fieldnames=list(rows[0]))
        w.writeheader()
        w.writerows(rows)
    fig, ax = plt.subplots(figsize=(7, 4.5))
    ax.plot([100 * r["strain_bound"] for r in rows], [100 * r["linearity_error"] for r in rows], "o-")
    for r in rows:
        ax.annotate(f"cast at {r['bladder_cast_fill']:g} of stroke", (100 * r["strain_bound"], 100 * r["linearity_error"]),
                    textcoords="offset points", xytext=(5, 5), fontsize=8)
    ax.axvline(100 * rows[0]["allowable_strain"], color="r", ls="--", label="allowable (Dragon Skin 20, cyclic)")
    ax.set(xlabel="bladder strain bound (FE, membrane + clamp bending) [%]", ylabel="best linearity error [%]",
           title="where to cast the bladder: linearity vs bladder strain")
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8)
    save_figure(fig, out / "cast_fill.png")
    return rows


def thermo_front(out: Path, res, quick: bool = False) -> dict:
    """Isothermal against adiabatic linearity: the best isothermal design under caps on the n = 1.4 one,
    the worst-of-both optimum and the isothermal optimum; CSV + PNG."""
    from matplotlib.figure import Figure

    caps = ADIABATIC_CAPS[::2] if quick else ADIABATIC_CAPS
    rows = pareto_front(Requirements(), "adiabatic", caps, seed=0)
    worst = optimise(Requirements(objective="worst"), seed=0, progress=False)
    pts = [{"case": f"cap {c:g}", "feasible": r.feasible, "isothermal": r.linearity_error_isothermal,
            "adiabatic": r.linearity_error_adiabatic, "layout": r.layout} for c, r in zip(caps, rows)]
    pts.append({"case": "worst of n = 1, 1.4", "feasible": True, "isothermal": worst.evaluation.linearity_isothermal,
                "adiabatic": worst.evaluation.linearity_adiabatic, "layout": worst.layout})
    pts.append({"case": "isothermal objective", "feasible": True, "isothermal": res.evaluation.linearity_isothermal,
                "adiabatic": res.evaluation.linearity_adiabatic, "layout": res.layout})
    with open(out / "pareto_isothermal_adiabatic.csv", "w", newline="") as fh:
        w = csv.DictWriter(fh, fieldnames=list(pts[0]))
        w.writeheader()
        w.writerows(pts)
    fig = Figure(figsize=(7, 4.8))
    ax = fig.subplots()
    front = sorted([p for p in pts if p["feasible"]], key=lambda p: p["adiabatic"])
    ax.plot([100 * p["adiabatic"] for p in front], [100 * p["isothermal"] for p in front], "o-", label="Pareto front")
    ax.plot([100 * worst.evaluation.linearity_adiabatic], [100 * worst.evaluation.linearity_isothermal], "s", ms=10,
            mfc="none", mec="C3", mew=2, label=f"objective = worst: {100 * worst.evaluation.objective:.2f} %")
    ax.plot([100 * res.evaluation.linearity_adiabatic], [100 * res.evaluation.linearity_isothermal], "D", ms=9,
            mfc="none", mec="C2", mew=2, label=f"isothermal objective: {100 * res.evaluation.linearity_isothermal:.2f} %")
    lim = [min(100 * p["adiabatic"] for p in front) - 0.1, max(100 * p["adiabatic"] for p in front) + 0.1]
    ax.plot(lim, lim, "k:", lw=0.8, label="equal")
    ax.set(xlabel="linearity error at n = 1.4 (adiabatic, fast stroke) [%]",
           ylabel="linearity error at n = 1 (isothermal, slow) [%]",
           title="one unit, two gas laws: what adiabatic linearity costs isothermally")
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8)
    tight_layout_once(fig)
    save_figure(fig, out / "pareto_isothermal_adiabatic.png")
    return {"points": pts}


def main(out: Path, quick: bool = False) -> dict:
    out.mkdir(parents=True, exist_ok=True)
    req = Requirements()
    res = optimise_job(req, seed=0, out=out / "design.json")  # `vvea optimise`: design.json, design_force.png
    summary = {"optimum": {**res.evaluation.performance(), "binding": res.evaluation.binding(),
                           "seconds": res.seconds, "evaluations": res.evaluations}}
    for axis, values in SWEEPS.items():
        vals = values[::2] if quick else values
        rows = pareto_front(req, axis, vals, seed=0)
        save_pareto(rows, axis, out)
        field = PARETO_AXES[axis][0]
        summary[f"pareto_{axis}"] = [{field: r.value, "linearity_error": r.linearity_error,
                                      "feasible": r.feasible, "binding": r.binding} for r in rows]
    for vx, vy in MAPS:
        m = linearity_map(res.design, req, vx, vy, n=31 if quick else 61)
        save_figure(plot_linearity_map(m.to_dict(), optimum=(getattr(res.design, vx), getattr(res.design, vy))),
                    out / f"map_{vx}_{vy}.png")
        np.savez_compressed(out / f"map_{vx}_{vy}.npz", x=m.x, y=m.y, linearity=m.linearity, feasible=m.feasible)
    summary["isothermal_vs_adiabatic"] = thermo_front(out, res, quick)
    summary["cast_fill"] = cast_fill_tradeoff(out)
    (out / "summary.json").write_text(json.dumps(summary, indent=2, sort_keys=True, default=float) + "\n")
    print(json.dumps(summary["optimum"], indent=2, default=float))
    return summary


if __name__ == "__main__":
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--out", type=Path, default=HERE / "results" / "optimise")
    ap.add_argument("--quick", action="store_true", help="fewer Pareto points and coarser maps")
    a = ap.parse_args()
    main(a.out, a.quick)
