"""The linearity cost of buildability: each envelope optimised under the gas-only rules and under the buildability
rules, and what binds.

    python studies/buildability_cost.py [--out DIR] [--quick] [--case NAME ...] [--rules buildable] [--plot-only]

The gas-only rules (``[fixed] sizing_rules = "gas_only"``) size the walls for the gas peak at nominal size, with no
joints and no damper loads: the rules of the published 1.3265 % optimum. The buildability rules (the default) size
every pressure-bearing piece for every load case (the gas peak, the relief valve's and the actuator's damping
pressures, the proof test) at the least-material condition of its drawn tolerance, choose the joint (a thread, a
retaining ring, tie rods) with its room, hold the open valve's parasitic damping to the requirement and weigh
every part as the CAD draws it. Requirements: the defaults (the paper's unit), ``examples/paper_tight.toml``,
a 70 x 160 mm envelope at 120 N/mm (also with wider base channels and twice the support ring's channels: what its
larger piston's flow needs to stay under the parasitic-damping limit), and a short housing with a long stroke
(65 x 120 mm, 50 mm travel, 80 N/mm).
Writes ``cost.csv``, ``cost.json`` and ``cost.png`` into ``studies/results/buildability_cost/`` and prints the
table; ``--plot-only`` redraws ``cost.png`` from an earlier run's ``cost.json``.
"""

from __future__ import annotations

import argparse
import csv
import json
import textwrap
from dataclasses import replace
from functools import partial
from pathlib import Path

from vvea_design.bladder.check import strain_bound
from vvea_design.palette import OTHER_COLOURS
from vvea_design.progress import progress_bar
from vvea_design.spring.optimise import optimise
from vvea_design.spring.requirements import Requirements, load_requirements

ROOT = Path(__file__).resolve().parents[1]
OUT = ROOT / "studies" / "results" / "buildability_cost"


def cases() -> dict[str, Requirements]:
    """The requirements the study optimises, by name.

    Returns
    -------
    dict of str to Requirements
        Name -> requirements (the buildability rules; the study also runs each under the gas-only rules).
    """
    big = Requirements(max_outer_diameter_mm=70.0, max_housing_length_mm=160.0, min_mean_stiffness_N_per_mm=120.0,
                       bounds={"outer_diameter_mm": (25.0, 70.0)})
    short = Requirements(max_outer_diameter_mm=65.0, max_housing_length_mm=120.0, travel_mm=50.0,
                         min_mean_stiffness_N_per_mm=80.0, bounds={"outer_diameter_mm": (25.0, 65.0)})
    wide = replace(big, fixed=replace(big.fixed, fluid_channel_mm=5.0, ring_channels=12))
    return {"defaults (59.5 x 132.5 mm, 93.2 N/mm)": Requirements(),
            "examples/paper_tight.toml": load_requirements(ROOT / "examples" / "paper_tight.toml"),
            "70 x 160 mm, 120 N/mm": big,
            "70 x 160 mm, 120 N/mm, 5 mm base channels, 12 ring channels": wide,
            "65 x 120 mm, 50 mm travel, 80 N/mm": short}


def _gas_only(req: Requirements) -> Requirements:
    """The same requirements under the gas-only rules."""
    return replace(req, fixed=replace(req.fixed, sizing_rules="gas_only"))


def _row(name: str, rules: str, req: Requirements, quick: bool) -> dict:
    """One optimisation and what it found."""
    fe = partial(strain_bound, material=req.bladder_material) if req.max_bladder_strain is not None else None
    kw = {"maxiter": 20} if quick else {}
    res = optimise(req, seed=0, progress=False, bladder_strain_fn=fe, raise_infeasible=False, **kw)
    ev, d = res.evaluation, res.design
    row = {"requirements": name, "rules": rules, "feasible": ev.feasible, "layout": d.layout,
           "joint": d.joint if rules == "buildable" else "-", "linearity_pct": 100 * ev.linearity_error,
           "linearity_adiabatic_pct": 100 * ev.linearity_adiabatic, "piston_diameter_mm": d.piston_diameter_mm,
           "outer_diameter_mm": d.outer_diameter_mm, "outer_bore_radius_mm": d.outer_bore_radius_mm,
           "top_cap_mm": d.top_cap_mm, "base_mm": d.base_mm, "gas_mm3": d.V1_mm3 + d.V2_mm3, "mass_g": d.mass_g,
           "D_min_N_s_per_mm": d.parasitic_damping_N_s_per_mm, "binding": " ".join(ev.binding()),
           "violated": " ".join(k for k, m in ev.margins.items() if m < -1e-9)}
    if rules == "buildable":
        row["joints"] = "; ".join(j.designation for j in d.joints() if hasattr(j, "designation"))
        row["D_max_N_s_per_mm"] = d.damping_range_N_s_per_mm()[1]
    return row


def main(out: Path = OUT, quick: bool = False, only: list[str] | None = None,
         rules_run: tuple[str, ...] = ("gas_only", "buildable")) -> list[dict]:
    """Optimise every case under both rules, write the table and print it.

    Parameters
    ----------
    out : Path
        Folder of ``cost.csv``, ``cost.json`` and ``cost.png``.
    quick : bool
        Fewer generations (a smoke run, not the published numbers).
    only : list of str, optional
        Run only the cases whose name contains one of these strings; the folder's other rows (from its
        ``cost.json``) are kept.
    rules_run : tuple of str
        The rules optimised (``buildable`` alone after a change of the buildability rules or of the shipped
        stress-concentration factors: the gas-only rows do not depend on them); the others kept from ``cost.json``.

    Returns
    -------
    list of dict
        One row per case and rules: linearity (%), layout, joint, sizes (mm), gas (mm³), mass (g), damping
        (N s/mm), the binding and violated constraints.
    """
    todo = [(name, rules, req if rules == "buildable" else _gas_only(req))
            for name, req in cases().items() for rules in ("gas_only", "buildable")
            if (not only or any(o in name for o in only)) and rules in rules_run]
    if not todo:
        raise SystemExit(f"--case {only}: no case matches; the cases are {list(cases())}")
    earlier = out / "cost.json"
    partial_run = only or tuple(rules_run) != ("gas_only", "buildable")
    kept = [] if not partial_run or not earlier.is_file() else json.loads(earlier.read_text(encoding="utf-8"))
    rows = []
    with progress_bar("buildability cost", total=len(todo)) as advance:
        for name, rules, req in todo:
            rows.append(_row(name, rules, req, quick))
            advance()
    new = {(r["requirements"], r["rules"]) for r in rows}
    order = list(cases())
    rows = sorted([r for r in kept if (r["requirements"], r["rules"]) not in new] + rows,
                  key=lambda r: (order.index(r["requirements"]) if r["requirements"] in order else len(order),
                                 r["rules"] != "gas_only"))
    out.mkdir(parents=True, exist_ok=True)
    keys = list(dict.fromkeys(k for r in rows for k in r))
    with (out / "cost.csv").open("w", newline="", encoding="utf-8") as fh:
        w = csv.DictWriter(fh, keys)
        w.writeheader()
        w.writerows(rows)
    (out / "cost.json").write_text(json.dumps(rows, indent=2) + "\n", encoding="utf-8")
    plot(rows, out / "cost.png")
    print(f"{'requirements':62s} {'rules':9s} {'lin %':>7s} {'n=1.4 %':>8s} layout/joint            mass g  D_min  binding")
    for r in rows:
        print(f"{r['requirements']:62s} {r['rules']:9s} {r['linearity_pct']:7.4f} {r['linearity_adiabatic_pct']:8.3f} "
              f"{r['layout'] + '/' + r['joint']:22s} {r['mass_g']:7.1f} {r['D_min_N_s_per_mm']:6.2f}  {r['binding']}"
              + ("" if r["feasible"] else f"  INFEASIBLE: {r['violated']}"))
    return rows


#: Colour of each rules' bars.
_RULE_COLOURS = {"gas_only": "#9a9a9a", "buildable": OTHER_COLOURS[0]}
_RULE_LABELS = {"gas_only": "gas-only rules (the published optimum's)", "buildable": "buildability rules"}


def plot(rows: list[dict], path: Path) -> Path:
    """Draw the cost: each case's isothermal linearity error, gas volume and mass under both rules.

    Parameters
    ----------
    rows : list of dict
        :func:`main`'s rows (or ``cost.json``'s).
    path : Path
        The PNG to write.

    Returns
    -------
    Path
        ``path``.
    """
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    import numpy as np

    names = list(dict.fromkeys(r["requirements"] for r in rows))
    by = {(r["requirements"], r["rules"]): r for r in rows}
    panels = (("linearity_pct", "isothermal linearity error, %", lambda v: v),
              ("gas_mm3", "gas volume V1 + V2, cm³", lambda v: v / 1000),
              ("mass_g", "mass, g", lambda v: v))
    fig, axes = plt.subplots(1, 3, figsize=(12.5, 0.9 + 0.75 * len(names)), sharey=True,
                             gridspec_kw={"width_ratios": (1.5, 1, 1)})
    y = np.arange(len(names))[::-1]
    h = 0.38
    for ax, (key, label, scale) in zip(axes, panels):
        for k, rules in enumerate(("gas_only", "buildable")):
            vals = [scale(by[(n, rules)][key]) if (n, rules) in by else np.nan for n in names]
            bars = ax.barh(y + (h / 2 if k == 0 else -h / 2), vals, h, color=_RULE_COLOURS[rules],
                           label=_RULE_LABELS[rules])
            for b, n, v in zip(bars, names, vals):
                r = by.get((n, rules))
                if r is None or not np.isfinite(v):
                    continue
                txt = f"{v:.3f}" if key == "linearity_pct" else f"{v:.0f}"
                if key == "linearity_pct":
                    txt += f"  {r['layout']}" + (f" / {r['joint']}" if rules == "buildable" else "")
                    txt += "  (D_min binds)" if "parasitic_damping" in r["binding"].split() else ""
                    txt += "" if r["feasible"] else "  INFEASIBLE"
                ax.text(v, b.get_y() + h / 2, " " + txt, va="center", ha="left", fontsize=7.5)
        ax.set_xlabel(label)
        ax.grid(axis="x", alpha=0.3)
        ax.set_xlim(0, ax.get_xlim()[1] * (1.9 if key == "linearity_pct" else 1.2))
    axes[0].set_yticks(y, [textwrap.fill(n, 30) for n in names], fontsize=8)
    fig.suptitle("The linearity cost of buildability (each case optimised under both rules, seed 0)", fontsize=10)
    handles, labels = axes[0].get_legend_handles_labels()
    fig.legend(handles, labels, loc="upper center", bbox_to_anchor=(0.5, 0.955), ncol=2, fontsize=8, frameon=False)
    fig.tight_layout(rect=(0, 0, 1, 1 - 0.3 / fig.get_figheight()))
    path.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return path


if __name__ == "__main__":
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--out", type=Path, default=OUT)
    ap.add_argument("--quick", action="store_true", help="fewer generations (a smoke run)")
    ap.add_argument("--case", action="append", help="run only the cases whose name contains this (repeatable); "
                    "the folder's other rows are kept")
    ap.add_argument("--plot-only", action="store_true", help="redraw cost.png from the folder's cost.json")
    ap.add_argument("--rules", choices=("gas_only", "buildable"), action="append",
                    help="optimise only under these rules (repeatable); the folder's other rows are kept")
    a = ap.parse_args()
    if a.plot_only:
        plot(json.loads((a.out / "cost.json").read_text(encoding="utf-8")), a.out / "cost.png")
    else:
        main(a.out, a.quick, a.case, tuple(a.rules) if a.rules else ("gas_only", "buildable"))
