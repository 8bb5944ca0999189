"""Stress-concentration factors of the unit's features from axisymmetric FE, fitted and shipped as data.

For each feature kind of :mod:`vvea_design.structure.concentration` (O-ring groove root, thread relief,
retaining-ring groove, shoulder fillet, a plate's root in a tube) the FE is run over a grid of its two
dimensionless variables, ``ln Kt = c0 + c1 ln x1 + c2 ln x2 + c3 ln x1 ln x2`` is fitted (Tresca and von Mises), and the data file the
spring sizing reads is written (it must not import the FE: it reads the numbers). The FE is the final check of
every drawn unit in the main job; these factors let the optimiser size for the features before it.

    python studies/fe_stress_concentration.py
        # -> vvea_design/spring/data/stress_concentration.json,
        #    studies/results/fe_stress_concentration/{points.csv, fits.json, kt.png}
    python studies/fe_stress_concentration.py --quick   # a 2 x 2 grid per kind (a smoke run, not shipped)
    python studies/fe_stress_concentration.py --refit   # fit again from points.csv (no FE), rewrite the outputs

A check of the FE on concentrations against an exact solution (Goodier's spherical cavity under tension) is
in ``studies/fe_convergence.py`` and ``tests/structure``.
"""

from __future__ import annotations

import argparse
import csv
import json
import time
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import numpy as np  # noqa: E402
from matplotlib.figure import Figure  # noqa: E402

from vvea_design.progress import progress_bar  # noqa: E402
from vvea_design.structure.concentration import KINDS, KtPoint, fit_kt, kt_point, write_factors  # noqa: E402
from vvea_design.structure.meshing import MeshSpec  # noqa: E402

ROOT = Path(__file__).resolve().parents[1]
DATA = ROOT / "vvea_design" / "spring" / "data" / "stress_concentration.json"
OUT = ROOT / "studies" / "results" / "fe_stress_concentration"

#: The grid of each kind's variables (x1 values, x2 values): the ranges the unit's features span.
GRID = {
    "oring_groove_root": ((2.0, 4.0, 7.0, 12.0), (0.15, 0.3, 0.5)),  # depth / root radius, depth / wall
    "thread_relief": ((1.5, 3.0, 6.0, 10.0), (0.15, 0.3, 0.5)),  # depth / root radius, depth / wall
    "ring_groove": ((2.0, 4.0, 8.0), (0.15, 0.25, 0.4)),  # depth / root radius, depth / wall
    "shoulder_fillet": ((5.0, 10.0, 20.0, 40.0), (1.5, 2.0, 4.0)),  # diameter / radius, D / d
    "web_root": ((4.0, 7.0, 12.0, 20.0), (0.3, 0.6, 1.2)),  # plate thickness / radius, wall / thickness
}
QUICK = {k: ((v[0][0], v[0][-1]), (v[1][0], v[1][-1])) for k, v in GRID.items()}
#: The FE's mesh for the factors: the root radius resolved by 3 elements per radius of arc.
SPEC = MeshSpec(elements_per_radius=3.0)


def run(grid: dict, spec: MeshSpec = SPEC) -> dict:
    """Every FE point of the grid, by kind."""
    items = [(k, x1, x2) for k, (a, b) in grid.items() for x1 in a for x2 in b]
    points: dict = {k: [] for k in grid}
    with progress_bar("FE stress concentration", len(items)) as advance:
        for kind, x1, x2 in items:
            points[kind].append(kt_point(kind, x1, x2, spec))
            advance()
    return points


def read_points(path: Path) -> dict:
    """The FE points of a previous run (``points.csv``), by kind."""
    points: dict = {}
    with open(path, newline="") as fh:
        for row in csv.DictReader(fh):
            points.setdefault(row["kind"], []).append(
                KtPoint(row["kind"], float(row["x1"]), float(row["x2"]), float(row["kt_tresca"]),
                        float(row["kt_von_mises"])))
    return points


def figure(points: dict, fits: dict, path: Path) -> Path:
    """FE factors and the fit per kind (Tresca), against x1, one line per x2."""
    from matplotlib.ticker import NullFormatter, ScalarFormatter

    kinds = list(points)
    ncol = 3
    nrow = -(-len(kinds) // ncol)
    fig = Figure(figsize=(4.4 * ncol, 3.8 * nrow), layout="constrained")
    axes = np.atleast_1d(fig.subplots(nrow, ncol)).ravel()
    for ax in axes[len(kinds):]:
        ax.set_visible(False)
    for ax, kind in zip(axes, kinds):
        pts = points[kind]
        f = fits[kind]["tresca"]
        for x2 in sorted({p.x2 for p in pts}):
            sel = sorted((p for p in pts if p.x2 == x2), key=lambda p: p.x1)
            x1 = np.array([p.x1 for p in sel])
            line = ax.plot(x1, [p.kt_tresca for p in sel], "o", label=f"{KINDS[kind]['x2']} = {x2:g}")[0]
            xs = np.geomspace(x1.min(), x1.max(), 50)
            ax.plot(xs, f(xs, x2), "-", color=line.get_color(), lw=1)
        ax.set_xscale("log")
        ticks = []
        for t in sorted({round(p.x1, 1) for p in pts}):
            if not ticks or t / ticks[-1] > 1.25:  # labels apart
                ticks.append(t)
        ax.set_xticks(ticks, [f"{t:g}" for t in ticks])
        ax.xaxis.set_minor_formatter(NullFormatter())
        ax.yaxis.set_major_formatter(ScalarFormatter())
        ax.set_xlabel(KINDS[kind]["x1"].replace("_", " "))
        ax.set_ylabel("Kt (Tresca peak / nominal)")
        ax.set_title(f"{kind.replace('_', ' ')}: FE (dots), fit (lines)\nfit error ≤ {100 * f.max_relative_error:.1f} %",
                     fontsize=10)
        ax.grid(alpha=0.3, which="both")
        ax.legend(fontsize=7)
    path.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(path, dpi=110, metadata={"Software": "vvea-design"})
    return path


def main(argv=None) -> int:
    """Run the grid, fit, write the data file (not in ``--quick``), the table and the figure."""
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true", help="a 2 x 2 grid per kind; the data file is not written")
    ap.add_argument("--refit", action="store_true", help="read the FE points of points.csv instead of running them")
    ap.add_argument("--out", type=Path, default=OUT)
    args = ap.parse_args(argv)
    grid = QUICK if args.quick else GRID
    t0 = time.perf_counter()
    points = read_points(args.out / "points.csv") if args.refit else run(grid)
    out = args.out / ("quick" if args.quick else "")
    out.mkdir(parents=True, exist_ok=True)
    with open(out / "points.csv", "w", newline="") as fh:
        w = csv.writer(fh)
        w.writerow(["kind", "x1_name", "x1", "x2_name", "x2", "kt_tresca", "kt_von_mises"])
        for k, pts in points.items():
            for p in pts:
                w.writerow([k, KINDS[k]["x1"], p.x1, KINDS[k]["x2"], p.x2, f"{p.kt_tresca:.5f}", f"{p.kt_von_mises:.5f}"])
    fits = {k: {c: fit_kt(p, c) for c in ("tresca", "von_mises")} for k, p in points.items()}
    summary = {k: {c: {"coefficients": f.coefficients, "max_relative_error": f.max_relative_error,
                       "x1_range": f.x1_range, "x2_range": f.x2_range} for c, f in fk.items()}
               for k, fk in fits.items()}
    (out / "fits.json").write_text(json.dumps({"seconds": time.perf_counter() - t0, "fits": summary}, indent=2) + "\n")
    figure(points, fits, out / "kt.png")
    if not args.quick:
        old = json.loads(DATA.read_text()) if DATA.exists() else {}  # the piece factors (fe_concentration.py) kept
        write_factors(DATA, points, fits, {
            "command": "python studies/fe_stress_concentration.py",
            "mesh": {"elements_per_radius": SPEC.elements_per_radius, "elements_per_wall": SPEC.elements_per_wall,
                     "growth": SPEC.growth},
            "material": "isotropic, nu = 0.33 (the factors are nearly independent of E and weakly of nu)",
            "criteria": "tresca: largest principal difference; von_mises"},
            old.get("factors"), old.get("source", ""), old.get("factors_provenance"))
        print(f"wrote {DATA.relative_to(ROOT)}")
    for k, fk in fits.items():
        f = fk["tresca"]
        print(f"{k:18s} ln Kt = " + " ".join(f"{c:+.4f}" for c in f.coefficients)
              + f" [1, ln x1, ln x2, ln x1 ln x2]  (Tresca; fit error <= {100 * f.max_relative_error:.1f} %)")
    print(f"-> {out}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
