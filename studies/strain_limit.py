"""A bladder strain limit in the optimiser: fast (surrogate + FE correction) against a slow FE reference.

    python studies/strain_limit.py [--limits 0.10 0.12 0.14 0.16 0.18 0.20] [--reference 0.14] [--out DIR]

For each strain limit, the optimiser (`max_bladder_strain`, surrogate in the
global search, FE in the polish and the final check) gives the best
linearity; the curve shows the limit costs linearity smoothly. At the
reference limit a slow search polishes with the FE strain bound itself in
the constraints (no surrogate) from many starts per layout — the best final
members of an unconstrained global search and Sobol points — and the fast
optimum is compared with the best design it finds (target: within 0.1
percentage point). Writes strain_limit.csv/.png and summary.json into
studies/results/strain_limit/.
"""

from __future__ import annotations

import argparse
import csv
import json
import os
import time
from dataclasses import replace
from pathlib import Path

import numpy as np
from scipy.stats import qmc

from vvea_design.bladder.check import strain_bound
from vvea_design.figure_layout import tight_layout_once
from vvea_design.spring import optimise as opt
from vvea_design.spring.problem import design_from_vector, evaluate_design
from vvea_design.spring.requirements import Requirements

HERE = Path(__file__).resolve().parent


def fe_population_strain(req: Requirements, layout: str):
    """A population strain function that runs the FE strain bound on every design (slow)."""

    def fn(g, cols):
        names = list(cols)
        X = np.stack([cols[n] for n in names], axis=1)
        out = np.full(X.shape[0], np.inf)
        for k, x in enumerate(X):
            try:
                out[k] = strain_bound(design_from_vector(x, req, layout))
            except Exception:  # unbuildable: infeasible point
                pass
        return out

    return fn


def reference(req: Requirements, n_starts: int = 4, n_sobol: int = 4, seed: int = 0) -> dict:
    """Slow reference: FE-constrained epigraph polish from many starts per layout; the best feasible design."""
    t0 = time.perf_counter()
    best = None
    fe_calls = 0
    for layout in req.layouts:
        # starts: the best distinct final members of a global search without the strain limit, and Sobol points
        free = replace(req, max_bladder_strain=None)
        _, _, prob0 = opt._search(free, layout, seed, 10, 60, 1e-5, None, lambda *a: None)
        bounds = np.array(req.search_bounds(layout))
        sob = qmc.Sobol(len(bounds), seed=seed).random(n_sobol)
        starts = list(prob0.starts[:n_starts]) + list(bounds[:, 0] + sob * (bounds[:, 1] - bounds[:, 0]))
        prob = opt._Population(req, layout, fe_population_strain(req, layout))
        for s in starts:
            x, ok = opt._polish(prob, np.asarray(s, float), list(map(tuple, bounds)))
            obj, mar = prob(x)
            if np.all(mar[:, 0] >= -1e-9) and (best is None or obj[0] < best[0]):
                best = (float(obj[0]), layout, x)
        fe_calls += prob.count
    lin, layout, x = best
    d = design_from_vector(x, req, layout)
    ev = evaluate_design(d, req, bladder_strain=strain_bound(d))
    return {"linearity_error": ev.linearity_error, "layout": layout, "decision_vector": [float(v) for v in x],
            "bladder_strain": ev.details["bladder_strain"]["value"], "feasible": ev.feasible,
            "fe_evaluations": fe_calls, "seconds": time.perf_counter() - t0}


def main(limits: list[float], ref_limit: float, out: Path) -> dict:
    out.mkdir(parents=True, exist_ok=True)
    print(f"load average {os.getloadavg()[0]:.2f}")
    rows = []
    free = opt.optimise(Requirements(), seed=0, progress=False)
    print(f"no limit: {100 * free.evaluation.linearity_error:.4f} % ({free.layout}), FE strain "
          f"{100 * float(strain_bound(free.design)):.2f} %", flush=True)
    rows.append({"max_bladder_strain": None, "linearity_error": free.evaluation.linearity_error,
                 "bladder_strain_fe": float(strain_bound(free.design)), "layout": free.layout, "seconds": free.seconds})
    for lim in limits:
        r = opt.optimise(Requirements(max_bladder_strain=lim), seed=0, progress=False, bladder_strain_fn=strain_bound)
        rows.append({"max_bladder_strain": lim, "linearity_error": r.evaluation.linearity_error,
                     "bladder_strain_fe": r.bladder_strain_fe, "bladder_strain_surrogate": r.bladder_strain_surrogate,
                     "layout": r.layout, "seconds": r.seconds})
        print(f"limit {lim:.3f}: {100 * r.evaluation.linearity_error:.4f} % ({r.layout}), FE strain "
              f"{100 * r.bladder_strain_fe:.2f} %, {r.seconds:.1f} s", flush=True)
    ref = reference(Requirements(max_bladder_strain=ref_limit))
    fast = next(r for r in rows if r["max_bladder_strain"] == ref_limit)
    gap_pp = 100 * (fast["linearity_error"] - ref["linearity_error"])
    print(f"reference at {ref_limit}: {100 * ref['linearity_error']:.4f} % ({ref['layout']}, "
          f"{ref['fe_evaluations']} FE runs, {ref['seconds']:.0f} s); fast {100 * fast['linearity_error']:.4f} %: "
          f"{gap_pp:+.4f} percentage points")
    with open(out / "strain_limit.csv", "w", newline="") as fh:
        w = csv.DictWriter(fh, fieldnames=sorted({k for r in rows for k in r}))
        w.writeheader()
        w.writerows(rows)
    from matplotlib.figure import Figure

    from vvea_design.spring.plots import save_figure

    fig = Figure(figsize=(7, 4.6))
    ax = fig.subplots()
    lim_rows = [r for r in rows if r["max_bladder_strain"] is not None]
    ax.plot([100 * r["max_bladder_strain"] for r in lim_rows], [100 * r["linearity_error"] for r in lim_rows], "o-",
            label="optimiser (surrogate in the search, FE in polish and check)")
    ax.axhline(100 * rows[0]["linearity_error"], color="gray", ls="--", lw=1,
               label=f"no strain limit (FE strain {100 * rows[0]['bladder_strain_fe']:.1f} %)")
    ax.plot([100 * ref_limit], [100 * ref["linearity_error"]], "r*", ms=13, label="slow reference search (FE only)")
    ax.set(xlabel="max_bladder_strain (FE strain bound) [%]", ylabel="best linearity error, n = 1 [%]",
           title="what a bladder strain limit costs")
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8)
    tight_layout_once(fig)
    save_figure(fig, out / "strain_limit.png")
    summary = {"rows": rows, "reference": ref, "reference_limit": ref_limit, "fast_minus_reference_pp": gap_pp,
               "load_average": os.getloadavg()[0]}
    (out / "summary.json").write_text(json.dumps(summary, indent=2) + "\n")
    return summary


if __name__ == "__main__":
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--limits", type=float, nargs="+", default=[0.10, 0.11, 0.12, 0.13, 0.14, 0.15, 0.16])
    ap.add_argument("--reference", type=float, default=0.14)
    ap.add_argument("--out", type=Path, default=HERE / "results" / "strain_limit")
    a = ap.parse_args()
    main(a.limits, a.reference, a.out)
