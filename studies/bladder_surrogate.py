"""Fit and validate the optimiser's surrogate of the bladder FE strain bound.

    python studies/bladder_surrogate.py [--train 300] [--test 100] [--out DIR]

Samples designs of both layouts over the design space (piston, outer
diameter, V1, V2, V2_top, and the fixed travel, bladder wall and cast fill),
keeps those whose bladder can be drawn and has room (the region the optimiser
searches), runs the FE strain bound (:func:`vvea_design.bladder.check.strain_bound`)
on each, fits polynomials in the log-groups of
:mod:`vvea_design.spring.strain_surrogate` and keeps the degree with the
smallest held-out error. Writes the coefficients into the package
(``vvea_design/spring/strain_surrogate.json``) and ``summary.json`` +
``validation.png`` into studies/results/bladder_surrogate/.
"""

from __future__ import annotations

import argparse
import json
import time
from dataclasses import replace
from pathlib import Path

import numpy as np

from vvea_design.bladder.check import strain_bound
from vvea_design.figure_layout import tight_layout_once
from vvea_design.parallel import parallel_map
from vvea_design.spring.layouts import LAYOUTS
from vvea_design.spring.problem import design_from_vector, evaluate_population
from vvea_design.spring.requirements import Requirements
from vvea_design.spring.strain_surrogate import COEFFICIENTS_FILE, features, poly_terms

HERE = Path(__file__).resolve().parent


def sample_designs(n: int, seed: int) -> list[tuple]:
    """``n`` (requirements, layout, vector) triples whose bladder fits and has room at both stroke ends."""
    rng = np.random.default_rng(seed)
    out = []
    while len(out) < n:
        travel = float(rng.uniform(25.0, 60.0))
        fixed = replace(Requirements().fixed, bladder_thickness_mm=float(rng.uniform(1.0, 2.5)),
                        bladder_cast_fill=float(rng.uniform(0.0, 0.8)))
        req = Requirements(travel_mm=travel, max_outer_diameter_mm=80.0, max_housing_length_mm=250.0, fixed=fixed)
        layout = str(rng.choice(list(LAYOUTS)))
        b = np.array(req.search_bounds(layout))
        b[1] = (40.0, 80.0)
        X = b[:, 0] + rng.random((4000, len(b))) * (b[:, 1] - b[:, 0])
        _, mar, ok = evaluate_population(X, req, layout)
        from vvea_design.spring.problem import constraint_names

        names = constraint_names(req, layout)
        room = np.minimum(mar[names.index("bladder_room_compressed")], mar[names.index("bladder_room_expanded")])
        good = np.flatnonzero(ok & (room >= 0) & (room < 3.0) & (mar[names.index("gas_left_at_full_stroke")] >= 0))
        for k in good[: max(1, n // 40)]:
            out.append((req, layout, X[k]))
    return out[:n]


def _fe(item) -> dict:
    req, layout, x = item
    d = design_from_vector(x, req, layout)
    t0 = time.perf_counter()
    s = strain_bound(d)
    return {"strain": float(s), "seconds": time.perf_counter() - t0, "R": d.bladder_mid_radius_mm,
            "L": d.bladder_free_length_mm, "H": d.fixed.bladder_thickness_mm,
            "dv_e": d.bladder_volume_change_mm3["expanded"], "dv_c": d.bladder_volume_change_mm3["compressed"],
            "layout": layout}


def fit(rows: list[dict], degree: int) -> dict:
    Z = features(*(np.array([r[k] for r in rows]) for k in ("R", "L", "H", "dv_e", "dv_c")))
    center, scale = Z.mean(axis=0), Z.std(axis=0) + 1e-12
    P = poly_terms((Z - center) / scale, degree)
    y = np.log([r["strain"] for r in rows])
    coef, *_ = np.linalg.lstsq(P, y, rcond=None)
    return {"degree": degree, "center": center.tolist(), "scale": scale.tolist(), "coefficients": coef.tolist()}


def predict(model: dict, rows: list[dict]) -> np.ndarray:
    Z = features(*(np.array([r[k] for r in rows]) for k in ("R", "L", "H", "dv_e", "dv_c")))
    P = poly_terms((Z - np.array(model["center"])) / np.array(model["scale"]), model["degree"])
    return np.exp(P @ np.array(model["coefficients"]))


def main(n_train: int, n_test: int, out: Path) -> dict:
    out.mkdir(parents=True, exist_ok=True)
    t0 = time.perf_counter()
    train = [r for r in parallel_map(_fe, sample_designs(n_train, 1), description="FE, training set") if np.isfinite(r["strain"])]
    test = [r for r in parallel_map(_fe, sample_designs(n_test, 2), description="FE, held-out set") if np.isfinite(r["strain"])]
    fe_seconds = time.perf_counter() - t0
    results = {}
    for degree in (1, 2, 3):
        m = fit(train, degree)
        s_test = np.array([r["strain"] for r in test])
        rel = predict(m, test) / s_test - 1
        rel_train = predict(m, train) / np.array([r["strain"] for r in train]) - 1
        results[degree] = (m, {"degree": degree, "terms": len(m["coefficients"]),
                               "test_rms_rel": float(np.sqrt(np.mean(rel**2))),
                               "test_max_abs_rel": float(np.abs(rel).max()),
                               "test_max_abs_strain": float(np.abs(predict(m, test) - s_test).max()),
                               "train_rms_rel": float(np.sqrt(np.mean(rel_train**2)))})
    best = min(results, key=lambda d: results[d][1]["test_rms_rel"])
    model, stats = results[best]
    model["validation"] = {**stats, "train": len(train), "test": len(test),
                           "fe_function": "vvea_design.bladder.check.strain_bound"}
    COEFFICIENTS_FILE.write_text(json.dumps(model, indent=2) + "\n", encoding="utf-8")
    summary = {"chosen_degree": best, "by_degree": [results[d][1] for d in sorted(results)],
               "train": len(train), "test": len(test), "fe_seconds": fe_seconds,
               "strain_range": [min(r["strain"] for r in train + test), max(r["strain"] for r in train + test)]}
    (out / "summary.json").write_text(json.dumps(summary, indent=2) + "\n")
    (out / "test.json").write_text(json.dumps(test, indent=1) + "\n")
    from matplotlib.figure import Figure

    from vvea_design.spring.plots import save_figure

    fig = Figure(figsize=(6.2, 5.4))
    ax = fig.subplots()
    s_test = np.array([r["strain"] for r in test])
    p_test = predict(model, test)
    ax.plot(100 * s_test, 100 * p_test, "o", ms=4, label=f"held-out designs ({len(test)})")
    lim = [0, 100 * max(s_test.max(), p_test.max()) * 1.05]
    ax.plot(lim, lim, "k-", lw=0.8, label="surrogate = FE")
    ax.set(xlim=lim, ylim=lim, xlabel="FE strain bound (strain_bound) [%]", ylabel="surrogate [%]",
           title=f"bladder strain surrogate, degree {best}: held-out rms {100 * stats['test_rms_rel']:.1f} %,\n"
                 f"max {100 * stats['test_max_abs_rel']:.1f} % (relative)")
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8)
    tight_layout_once(fig)
    save_figure(fig, out / "validation.png")
    print(json.dumps(summary, indent=2))
    return summary


if __name__ == "__main__":
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--train", type=int, default=300)
    ap.add_argument("--test", type=int, default=100)
    ap.add_argument("--out", type=Path, default=HERE / "results" / "bladder_surrogate")
    a = ap.parse_args()
    main(a.train, a.test, a.out)
