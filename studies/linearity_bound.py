"""How much gas does a linearity need, and how much can the envelope hold? Packing-free bound and capacity.

    python studies/linearity_bound.py [--out DIR] [--quick]

* **Packing-free bound**: for each total gas volume V1 + V2, the best
  linearity any layout could reach under the requirements (charges <= the
  limit with F(0) = 0, stiffness, gas left at full stroke), ignoring where
  the gas goes (exact metric, `optimise.gas_volume_bound`).
* **Capacity** of each layout variant: the largest V1 + V2 it holds in the
  envelope with its sized walls, piston, fluid column and bladder while
  meeting every requirement but the linearity (`optimise.gas_capacity`).
  The bound at that capacity is a floor no design of the layout can beat.
* **The optimum** of each layout (`optimise`) against both: the bound at
  its own gas volume (how well the split and the areas are chosen) and at
  the layout's capacity (how much of the envelope it uses).

Done for the paper's requirements (isothermal and worst-of-n objectives) and
for requirements the project was not tuned on. Writes bound.csv, bound.png,
capacity.json into studies/results/linearity_bound/.
"""

from __future__ import annotations

import argparse
import csv
import json
import os
from pathlib import Path

from matplotlib.figure import Figure

from vvea_design.parallel import parallel_map
from vvea_design.spring.optimise import Infeasible, gas_capacity, gas_volume_bound, optimise
from vvea_design.spring.plots import save_figure
from vvea_design.spring.requirements import Requirements

from bench_optimise import UNSEEN  # studies/ is the script's folder, first on sys.path

HERE = Path(__file__).resolve().parent
VOLUMES = [60e3, 80e3, 100e3, 120e3, 140e3, 160e3, 180e3, 200e3, 250e3, 300e3]

CASES = {
    "paper, isothermal": Requirements(),
    "paper, worst of n = 1 and 1.4": Requirements(objective="worst"),
    **UNSEEN,  # the unseen requirements of the optimiser benchmark, one list for both
}


def _bound(args):
    volume, req = args
    return gas_volume_bound(volume, req)


def case_study(label: str, req: Requirements) -> dict:
    """Optimum, capacity and bounds of every layout for one set of requirements."""
    out: dict = {"case": label, "objective_exponents": list(req.objective_exponents), "layouts": {}}
    try:
        res = optimise(req, seed=0, progress=False)
    except Infeasible as exc:
        out["infeasible"] = str(exc)
        return out
    out["chosen_layout"] = res.layout
    out["optimum"] = res.evaluation.objective
    out["seconds"] = res.seconds
    for s in res.searches:
        lay = {"optimum": s.objective, "feasible": s.feasible}
        from vvea_design.spring.design import get_layout

        names = get_layout(s.layout).decision_variables
        vec = dict(zip(names, s.decision_vector))
        lay["total_gas_mm3"] = vec["V1_mm3"] + vec["V2_mm3"]
        cap = gas_capacity(req, s.layout)
        lay["capacity_mm3"] = cap["total_gas_mm3"]
        lay["capacity_binding"] = cap["binding"]
        lay["bound_at_own_gas"] = gas_volume_bound(lay["total_gas_mm3"], req)["linearity_error"]
        lay["bound_at_capacity"] = gas_volume_bound(cap["total_gas_mm3"], req)["linearity_error"]
        lay["gap_to_bound_at_capacity_pp"] = 100 * (s.objective - lay["bound_at_capacity"])
        lay["gap_to_bound_at_own_gas_pp"] = 100 * (s.objective - lay["bound_at_own_gas"])
        out["layouts"][s.layout] = lay
    return out


def main(out: Path, quick: bool = False) -> dict:
    out.mkdir(parents=True, exist_ok=True)
    load0 = os.getloadavg()[0]
    cases = {k: v for k, v in CASES.items() if not quick or k.startswith("paper, iso")}
    studies = [case_study(k, v) for k, v in cases.items()]
    vols = VOLUMES[::2] if quick else VOLUMES
    curves = {}
    for label in ("paper, isothermal", "paper, worst of n = 1 and 1.4"):
        if label in cases:
            curves[label] = parallel_map(_bound, [(v, cases[label]) for v in vols], description=f"bound: {label}",
                                         progress=False)
    with open(out / "bound.csv", "w", newline="") as fh:
        w = csv.writer(fh)
        w.writerow(["objective", "total_gas_mm3", "linearity_error", "A1_mm2", "A2_mm2", "V1_mm3", "V2_mm3"])
        for label, rows in curves.items():
            for r in rows:
                w.writerow([label, r["total_gas_mm3"], r["linearity_error"], r["A1_mm2"], r["A2_mm2"], r["V1_mm3"],
                            r["V2_mm3"]])
    fig = Figure(figsize=(8.2, 5.2))
    ax = fig.subplots()
    colors = {"inner_tube": "C2", "bulkhead": "C3"}
    for (label, rows), c in zip(curves.items(), ("C0", "C1")):
        ax.plot([r["total_gas_mm3"] / 1e3 for r in rows], [100 * r["linearity_error"] for r in rows], "-", color=c,
                label=f"packing-free bound, {label.split(', ', 1)[1]} (eq. 5 only)")
        st = next(s for s in studies if s["case"] == label)
        for lay, d in st.get("layouts", {}).items():
            ax.axvline(d["capacity_mm3"] / 1e3, color=colors[lay], ls=":", lw=1)
            ax.plot([d["total_gas_mm3"] / 1e3], [100 * d["optimum"]], "*", color=colors[lay], ms=13, mec="k",
                    label=f"optimum, {lay} layout, {label.split(', ', 1)[1]}: {100 * d['optimum']:.3f} %")
    for lay, c in colors.items():
        ax.plot([], [], ":", color=c, label=f"capacity of the {lay} layout in 59.5 × 132.5 mm")
    ax.axhline(1.86, color="gray", ls="--", lw=1, label="paper, hand-tuned: 1.86 %")
    ax.set(xlabel="total gas volume V1 + V2 [10³ mm³]", ylabel="linearity error [%]", ylim=(0, None),
           title="linearity needs gas: bound, envelope capacity and optimum (93.2 N/mm at 4 MPa)")
    ax.grid(alpha=0.3)
    ax.legend(fontsize=7, loc="upper right")
    fig.tight_layout()
    save_figure(fig, out / "bound.png")
    summary = {"cases": studies, "load_average_start": load0, "load_average_end": os.getloadavg()[0]}
    (out / "capacity.json").write_text(json.dumps(summary, indent=2, default=float) + "\n")
    for st in studies:
        if "infeasible" in st:
            print(f"{st['case']}: infeasible\n{st['infeasible']}")
            continue
        for lay, d in st["layouts"].items():
            print(f"{st['case']:<42} {lay:<10} optimum {100 * d['optimum']:.3f} %  gas {d['total_gas_mm3']:>7.0f} "
                  f"(capacity {d['capacity_mm3']:>7.0f}) mm³  bound at own gas {100 * d['bound_at_own_gas']:.3f} %, "
                  f"at capacity {100 * d['bound_at_capacity']:.3f} %  gap {d['gap_to_bound_at_capacity_pp']:+.3f} pp")
    return summary


if __name__ == "__main__":
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--out", type=Path, default=HERE / "results" / "linearity_bound")
    ap.add_argument("--quick", action="store_true", help="paper requirements only, fewer volumes")
    a = ap.parse_args()
    main(a.out, a.quick)
