"""How much gas does a linearity need, and how much can the envelope hold? Packing-free bound and capacity.

    python studies/linearity_bound.py [--out DIR] [--quick]

* **Packing-free bound**: for each total gas volume V1 + V2, the best
  linearity any layout could reach under the requirements (charges <= the
  limit with F(0) = 0, stiffness, gas left at full stroke), ignoring where
  the gas goes (exact metric, `optimise.gas_volume_bound`).
* **Capacity** of each layout variant (``inner_tube``, ``bulkhead``,
  ``annulus_top``): the largest V1 + V2 it holds in the
  envelope with its sized walls, piston, fluid column and bladder while
  meeting every requirement but the linearity (`optimise.gas_capacity`).
  The bound at that capacity is a floor no design of the layout can beat.
* **The optimum** of each layout (`optimise`) against both: the bound at
  its own gas volume (how well the split and the areas are chosen) and at
  the layout's capacity (how much of the envelope it uses).

* **Each layout's own floor**: the bound with the layout's per-chamber
  capacities too (``V1 <= V1_max``, ``V2 <= V2_max``, each the largest the
  layout holds alone), a floor that knows a layout confines V1 or V2.
* **Volume budget** of the paper-requirement optimum: where every mm³ of the
  59.5 × 132.5 mm envelope goes (walls, piston, rod, fluid, bladder, clamps,
  gas), what is physically necessary and what is conservative, reconciled
  with the issue's count of 176,000 mm³ of gas (budget.csv, budget.png).
* **Relaxations**: the capacity, bound and optimum when each conservative
  item is relaxed (relaxations.csv), and with the piston pocket
  (``fixed.piston_pocket``, a design change: chamber-1 gas in the piston
  crown), alone and with the tight-manufacturing choices of
  examples/paper_tight.toml.

Done for the paper's requirements (isothermal and worst-of-n objectives, with
the bladder cast at mid-stroke and with the cast fill as a decision variable,
and the preset examples/paper_tight.toml)
and for requirements the project was not tuned on (with a figure of the short
housing, 65 × 120 mm and 50 mm travel, where chamber 1 needs the annulus:
bound_short_housing.png). Writes bound.csv,
bound.png, capacity.json, budget.csv, budget.png, relaxations.csv into
studies/results/linearity_bound/.
"""

from __future__ import annotations

import argparse
import csv
import json
import math
import os
from dataclasses import replace
from functools import partial
from pathlib import Path

from matplotlib.figure import Figure

from vvea_design.bladder.check import strain_bound
from vvea_design.figure_layout import tight_layout_once
from vvea_design.cad import CadError, Layout
from vvea_design.spring.layouts import get_layout
from vvea_design.spring.problem import design_from_vector

from vvea_design.parallel import parallel_map
from vvea_design.spring.optimise import Infeasible, optimise
from vvea_design.spring.studies import gas_capacity, gas_volume_bound
from vvea_design.spring.plots import save_figure
from vvea_design.spring.requirements import Requirements, load_requirements

from bench_optimise import UNSEEN  # studies/ is the script's folder, first on sys.path

HERE = Path(__file__).resolve().parent
#: The paper's requirements with tight manufacturing and a cupped piston (issue 12's 1.20 % target).
TIGHT_PRESET = HERE.parent / "examples" / "paper_tight.toml"
TIGHT = "paper, isothermal, tight + piston pocket (examples/paper_tight.toml)"
VOLUMES = [60e3, 80e3, 100e3, 120e3, 140e3, 160e3, 180e3, 200e3, 250e3, 300e3]

CASES = {
    "paper, isothermal": Requirements(),
    "paper, worst of n = 1 and 1.4": Requirements(objective="worst"),
    "paper, isothermal, cast fill free": Requirements(optimise_cast_fill=True),
    "paper, worst, cast fill free": Requirements(objective="worst", optimise_cast_fill=True),
    TIGHT: load_requirements(TIGHT_PRESET),
    **UNSEEN,  # the unseen requirements of the optimiser benchmark, one list for both
}

#: Conservative fixed parameters relaxed one at a time (then all together): what each would buy.
RELAXATIONS = {
    "as specified": {},
    "cast fill free (FE strain <= 25 %)": {"optimise_cast_fill": True},
    "bladder_min_gap_mm 0.5 -> 0.2": {"fixed": {"bladder_min_gap_mm": 0.2}},
    "fluid_clearance_mm 2 -> 0.5 (the CAD's minimum)": {"fixed": {"fluid_clearance_mm": 0.5}},
    "min_base_mm 14 -> 11 (the CAD's minimum)": {"fixed": {"min_base_mm": 11.0}},
    "cast fill free, clearance 0.5, base 11": {"optimise_cast_fill": True,
                                               "fixed": {"fluid_clearance_mm": 0.5, "min_base_mm": 11.0}},
    "all four": {"optimise_cast_fill": True, "fixed": {"bladder_min_gap_mm": 0.2, "fluid_clearance_mm": 0.5,
                                                     "min_base_mm": 11.0}},
    # not a relaxation but a design change: chamber-1 gas in a pocket in the piston crown (fixed.piston_pocket)
    "piston pocket": {"fixed": {"piston_pocket": True}},
    "cast fill free, clearance 0.5, base 11, piston pocket (paper_tight.toml)": {
        "optimise_cast_fill": True, "fixed": {"fluid_clearance_mm": 0.5, "min_base_mm": 11.0, "piston_pocket": True}},
    # the same with the piston turned from the housing's aluminium: what the floor's material is worth
    "paper_tight.toml with the piston in 6061-T6": {
        "optimise_cast_fill": True, "fixed": {"fluid_clearance_mm": 0.5, "min_base_mm": 11.0, "piston_pocket": True,
                                              "rod_material": "al-6061-t6"}},
    "all four, piston pocket": {"optimise_cast_fill": True, "fixed": {"bladder_min_gap_mm": 0.2,
                                                                      "fluid_clearance_mm": 0.5, "min_base_mm": 11.0,
                                                                      "piston_pocket": True}},
}


def chamber1_length_max_mm(req: Requirements, layout: str) -> tuple[float, float]:
    """The longest gas column above the piston a layout's housing leaves (every wall at its minimum), mm, and
    the chamber-1 gas outside that column (dead volume, the fill tube's bore at most over the housing), mm³.
    With a piston pocket the column reaches into the piston down to the thinnest floor (the pocket's area is
    less than A1: still an upper bound on V1)."""
    f = req.fixed
    bulkhead = get_layout(layout).has_bulkhead  # the layout declares it (data for the CAD and here)
    L = (req.max_housing_length_mm - f.min_top_cap_mm - f.min_base_mm - f.piston_height_mm - req.travel_mm
         - f.fluid_clearance_mm - (f.min_bulkhead_mm if bulkhead else 0.0))
    if f.piston_pocket:
        L += max(f.piston_height_mm - f.min_piston_floor_mm, 0.0)
    extra = f.dead_volume_1_mm3 + (math.pi / 4 * f.fill_tube_bore_mm**2 * req.max_housing_length_mm if bulkhead else 0.0)
    return L, extra


def _strain_fn(req: Requirements):
    return partial(strain_bound, material=req.bladder_material) if req.max_bladder_strain is not None else None


def _bound(args):
    volume, req = args
    return gas_volume_bound(volume, req)


def case_study(label: str, req: Requirements) -> dict:
    """Optimum, capacity and bounds of every layout for one set of requirements."""
    out: dict = {"case": label, "objective_exponents": list(req.objective_exponents), "layouts": {}}
    try:
        res = optimise(req, seed=0, progress=False, bladder_strain_fn=_strain_fn(req))
    except Infeasible as exc:
        out["infeasible"] = str(exc)
        return out
    out["chosen_layout"] = res.layout
    out["optimum"] = res.evaluation.objective
    out["optimum_isothermal"] = res.evaluation.linearity_isothermal
    out["optimum_adiabatic"] = res.evaluation.linearity_adiabatic
    out["bladder_cast_fill"] = res.design.fixed.bladder_cast_fill
    out["bladder_strain_fe"] = res.bladder_strain_fe
    out["seconds"] = res.seconds
    out["design"] = res.design
    out["layout_designs"] = {s.layout: design_from_vector(s.decision_vector, req, s.layout) for s in res.searches}
    for s in res.searches:
        # the chosen layout's final design (with a strain limit: corrected by the FE itself) is the optimum
        final = s.layout == res.layout
        lay = {"optimum": res.evaluation.objective if final else s.objective,
               "feasible": res.evaluation.feasible if final else s.feasible}
        vec = dict(zip(req.decision_variables(s.layout), s.decision_vector))
        lay["total_gas_mm3"] = vec["V1_mm3"] + vec["V2_mm3"]
        lay["V1_mm3"], lay["V2_mm3"] = vec["V1_mm3"], vec["V2_mm3"]
        cap = gas_capacity(req, s.layout)
        lay["capacity_mm3"] = cap.total_gas_mm3
        lay["capacity_binding"] = cap.binding
        lay["V1_max_mm3"] = gas_capacity(req, s.layout, maximise="V1").V1_mm3
        lay["V2_max_mm3"] = gas_capacity(req, s.layout, maximise="V2").V2_mm3
        lay["bound_at_own_gas"] = gas_volume_bound(lay["total_gas_mm3"], req).linearity_error
        at_cap = gas_volume_bound(cap.total_gas_mm3, req)
        lay["bound_at_capacity"] = at_cap.linearity_error
        lay["bound_at_capacity_V1_V2_mm3"] = [at_cap.V1_mm3, at_cap.V2_mm3]
        floor = gas_volume_bound(cap.total_gas_mm3, req, V1_max_mm3=lay["V1_max_mm3"], V2_max_mm3=lay["V2_max_mm3"])
        lay["layout_floor"] = floor.linearity_error
        lay["layout_floor_V1_V2_mm3"] = [floor.V1_mm3, floor.V2_mm3]
        # tighter: chamber 1 confined to the piston bore (V1 <= A1 * the longest column + ports); annulus_top puts
        # chamber-1 gas outside the bore, so its only floor is the layout floor
        L1, extra = chamber1_length_max_mm(req, s.layout)
        if get_layout(s.layout).has_top_annulus:
            bore = floor
        else:
            bore = gas_volume_bound(cap.total_gas_mm3, req, V1_max_mm3=lay["V1_max_mm3"],
                                    V2_max_mm3=lay["V2_max_mm3"], chamber1_length_max_mm=L1, V1_extra_mm3=extra)
        lay["chamber1_length_max_mm"] = L1
        lay["bore_floor"] = bore.linearity_error
        lay["bore_floor_A1_V1_V2"] = [bore.A1_mm2, bore.V1_mm3, bore.V2_mm3]
        if s.layout == res.layout:
            d = res.design
            lay["V1_annulus_mm3"] = d.V1_annulus_mm3
            lay["chamber1_column_mm"] = d.chamber1_length_mm
        lay["gap_to_bore_floor_pp"] = 100 * (lay["optimum"] - lay["bore_floor"])
        lay["gap_to_bound_at_capacity_pp"] = 100 * (lay["optimum"] - lay["bound_at_capacity"])
        lay["gap_to_bound_at_own_gas_pp"] = 100 * (lay["optimum"] - lay["bound_at_own_gas"])
        lay["gap_to_layout_floor_pp"] = 100 * (lay["optimum"] - lay["layout_floor"])
        out["layouts"][s.layout] = lay
    return out


# ---------------------------------------------------------------------------
# Volume budget
# ---------------------------------------------------------------------------

#: Budget items: (group, label, judgement). Groups colour the figure.
BUDGET_ITEMS = {
    "wall_outer_tube": ("walls", "outer tube wall", "pressure-sized (Lame, safety 2 on yield at the n = 1.4 peak)"),
    "wall_inner_tube": ("walls", "inner tube wall", "pressure- and buckling-sized"),
    "wall_top_cap": ("walls", "top cap", "plate needs 7.5 mm at the peak; 8 mm minimum (fill ports)"),
    "wall_base": ("walls", "base", "14 mm minimum for valve bores, channels, rod seal; the CAD fits them in 11 mm; "
                  "the pressure needs 4 mm"),
    "wall_bulkhead": ("walls", "bulkhead", "pressure-sized; the price of freeing the housing length from V1"),
    "wall_fill_tube": ("walls", "chamber-1 fill tube wall", "necessary in the bulkhead layout"),
    "wall_collar": ("walls", "collar plate (annulus_top)", "pressure-sized; the price of chamber-1 gas in the annulus"),
    "piston": ("piston and rod", "piston with two seal grooves (less its pocket)", "necessary"),
    "rod_in_fluid_column": ("piston and rod", "rod inside the fluid column", "necessary"),
    "fluid_swept_by_stroke": ("fluid under the piston", "fluid under the piston, swept by the stroke", "necessary: the piston sweeps "
                              "A1 x travel of the bore (fluid at x = 0, chamber 1 at full stroke)"),
    "fluid_clearance_under_piston": ("fluid under the piston", "fluid clearance under the piston at full stroke",
                                     "2 mm; the CAD needs 0.5 mm"),
    "bladder_clamps": ("bladder", "bladder clamps (support ring, top clamp)", "2 x 5 mm of the annulus; necessary to "
                       "clamp and seal the sleeve (the length is a choice)"),
    "bladder_silicone": ("bladder", "bladder silicone (1.5 mm sleeve)", "necessary (a thinner wall strains more)"),
    "bladder_fluid_min_gap": ("fluid in the bladder", "fluid in the bladder: 0.5 mm min gap to the inner tube",
                              "conservative: the bladder is pressure-balanced at x = 0; the gap keeps the fluid path "
                              "open"),
    "bladder_fluid_bulge_room": ("fluid in the bladder", "fluid in the bladder: room for its inward bulge at x = 0",
                                 "recoverable by casting the bladder nearer x = 0, bounded by its strain "
                                 "(optimise_cast_fill)"),
    "gas_chamber_1": ("gas", "gas, chamber 1 (V1) in the bore (and the slots)", "gas"),
    "gas_chamber_1_annulus": ("gas", "gas, chamber 1 in the annulus above the collar (annulus_top)", "gas"),
    "gas_chamber_1_piston_pocket": ("gas", "gas, chamber 1 in the piston pocket (fixed.piston_pocket)", "gas"),
    "gas_chamber_2_above_bulkhead": ("gas", "gas, chamber 2 above the bulkhead", "gas"),
    "gas_chamber_2_annulus": ("gas", "gas, chamber 2 around the bladder", "gas"),
    "unused_length": ("unused", "envelope length the housing does not use", "unused"),
}
GROUP_COLORS = {"walls": "#7f7f7f", "piston and rod": "#8c564b", "fluid under the piston": "#d62728",
                "bladder": "#ff7f0e", "fluid in the bladder": "#f7b6d2", "gas": "#1f77b4", "unused": "#ffffff"}
#: What the issue's author subtracted from the envelope to count 176,000 mm³ of gas.
ISSUE_GAS_COUNT_MM3 = 176_000.0


def issue_count_mm3(design, envelope_length_mm: float) -> dict:
    """The issue's way of counting the gas room (envelope minus walls at their minimum, end caps, piston, the
    swept fluid column, bladder silicone and clamps) and what it leaves out, item by item, mm³."""
    b = design.volume_budget_mm3(envelope_length_mm)
    f = design.fixed
    ro, ri, L_in = design.outer_diameter_mm / 2, design.piston_diameter_mm / 2, design.inner_length_mm
    walls_min = math.pi * (ro**2 - (ro - f.min_outer_wall_mm) ** 2) * L_in \
        + math.pi * ((ri + f.min_inner_tube_wall_mm) ** 2 - ri**2) * L_in
    envelope = sum(b.values())
    subtracted = (walls_min + b["wall_top_cap"] + b["wall_base"] + b["piston"] + b["fluid_swept_by_stroke"]
                  + b["bladder_silicone"] + b["bladder_clamps"])
    count = envelope - subtracted - b["unused_length"]
    left_out = {
        "walls sized above their 1.5 mm minimum": b["wall_outer_tube"] + b["wall_inner_tube"] - walls_min,
        "rod in the fluid column and the 2 mm clearance": b["rod_in_fluid_column"] + b["fluid_clearance_under_piston"],
        "bulkhead and fill tube": b["wall_bulkhead"] + b["wall_fill_tube"],
        "bladder fluid: 0.5 mm min gap": b["bladder_fluid_min_gap"],
        "bladder fluid: room for the inward bulge at x = 0": b["bladder_fluid_bulge_room"],
    }
    gas = design.V1_mm3 + design.V2_mm3
    return {"count_mm3": count, "left_out_mm3": left_out, "gas_mm3": gas,
            "check_mm3": count - sum(left_out.values()) - gas}


def volume_budget(designs: dict, out: Path, envelope_length_mm: float) -> list[dict]:
    """budget.csv and budget.png: every mm³ of the envelope for each design (label -> Design)."""
    rows = []
    budgets = {label: d.volume_budget_mm3(envelope_length_mm) for label, d in designs.items()}
    envelope = math.pi / 4 * max(d.outer_diameter_mm for d in designs.values()) ** 2 * envelope_length_mm
    for key, (group, label, judgement) in BUDGET_ITEMS.items():
        row = {"item": key, "group": group, "description": label, "judgement": judgement}
        for name, b in budgets.items():
            row[f"{name} [mm3]"] = round(b[key], 1)
            row[f"{name} [% of envelope]"] = round(100 * b[key] / envelope, 3)
        rows.append(row)
    total = {"item": "total", "group": "", "description": "envelope cylinder", "judgement": ""}
    for name, b in budgets.items():
        total[f"{name} [mm3]"] = round(sum(b.values()), 1)
        total[f"{name} [% of envelope]"] = round(100 * sum(b.values()) / envelope, 3)
    rows.append(total)
    with open(out / "budget.csv", "w", newline="") as fh:
        w = csv.DictWriter(fh, fieldnames=list(rows[0]))
        w.writeheader()
        w.writerows(rows)
    # figure: one stacked bar per design + the issue's count reconciled with ours
    ref_label = next(iter(designs))
    issue = issue_count_mm3(designs[ref_label], envelope_length_mm)
    fig = Figure(figsize=(12.5, 6.6))
    ax, ax2 = fig.subplots(1, 2, gridspec_kw={"width_ratios": [1.25, 1.0]})
    names = list(budgets)
    for i, name in enumerate(names):
        left = 0.0
        for key, (group, label, _) in BUDGET_ITEMS.items():
            v = budgets[name][key]
            if v <= 0:
                continue
            ax.barh(i, v / 1e3, left=left / 1e3, color=GROUP_COLORS[group], edgecolor="k", lw=0.4,
                    hatch="//" if group == "unused" else None)
            if v / envelope > 0.015:
                short = {"wall_outer_tube": "outer", "wall_inner_tube": "inner", "wall_top_cap": "cap",
                         "wall_base": "base", "piston": "piston", "fluid_swept_by_stroke": "swept fluid",
                         "bladder_clamps": "clamps", "bladder_silicone": "silicone",
                         "bladder_fluid_min_gap": "gap", "bladder_fluid_bulge_room": "bulge room",
                         "rod_in_fluid_column": "", "wall_bulkhead": "", "unused_length": "unused",
                         "gas_chamber_1": "V1", "gas_chamber_1_annulus": "V1 ann.",
                         "gas_chamber_1_piston_pocket": "V1 pocket",
                         "gas_chamber_2_annulus": "V2 annulus"}.get(key, "")
                ax.text((left + v / 2) / 1e3, i, short, ha="center", va="center", fontsize=7,
                        color="w" if group in ("walls", "gas", "piston and rod", "fluid under the piston") else "k",
                        rotation=90)
            left += v
    from matplotlib.patches import Patch

    handles = [Patch(facecolor=c, edgecolor="k", lw=0.4, hatch="//" if g == "unused" else None, label=g)
               for g, c in GROUP_COLORS.items()]
    ax.set_yticks(range(len(names)), [n.replace(", ", ",\n") for n in names], fontsize=8)
    ax.set(xlabel="volume at x = 0 [10³ mm³] (envelope 59.5 × 132.5 mm = %.0f × 10³ mm³)" % (envelope / 1e3),
           title="where the envelope goes (x = 0)", xlim=(0, envelope / 1e3 * 1.001))
    ax.legend(handles=handles, fontsize=8, loc="upper center", bbox_to_anchor=(0.5, -0.12), ncol=4)
    ax.invert_yaxis()
    # reconciliation waterfall: the issue's count down to our gas
    steps = [("issue's count,\nits method", issue["count_mm3"])] + [(k, -v) for k, v in issue["left_out_mm3"].items()]
    level = 0.0
    labels = []
    for j, (label, v) in enumerate(steps):
        if j == 0:
            ax2.bar(j, v / 1e3, color="#9467bd", edgecolor="k", lw=0.4)
            level = v
        else:
            ax2.bar(j, v / 1e3, bottom=level / 1e3, color="#d62728" if v < 0 else "#2ca02c", edgecolor="k", lw=0.4)
            ax2.text(j, (level + v) / 1e3 - 0.4, f"{v / 1e3:+.1f}", ha="center", va="top", fontsize=7)
            level += v
        labels.append(label.replace(": ", ":\n").replace(" and ", " and\n").replace(" at ", "\nat "))
    ax2.bar(len(steps), issue["gas_mm3"] / 1e3, color="#1f77b4", edgecolor="k", lw=0.4)
    labels.append("our gas\n(V1 + V2)")
    ax2.text(0, issue["count_mm3"] / 1e3 + 0.3, f"{issue['count_mm3'] / 1e3:.1f}", ha="center", fontsize=8)
    ax2.text(len(steps), issue["gas_mm3"] / 1e3 + 0.3, f"{issue['gas_mm3'] / 1e3:.1f}", ha="center", fontsize=8)
    ax2.axhline(ISSUE_GAS_COUNT_MM3 / 1e3, color="#9467bd", ls="--", lw=1,
                label=f"the issue: about {ISSUE_GAS_COUNT_MM3 / 1e3:.0f} × 10³ mm³")
    ax2.set_xticks(range(len(labels)), labels, fontsize=7, rotation=35, ha="right")
    ax2.set(ylabel="gas room [10³ mm³]", ylim=(issue["gas_mm3"] / 1e3 - 8, ISSUE_GAS_COUNT_MM3 / 1e3 + 4),
            title=f"the issue's count on the {ref_label.split(',')[0]} optimum")
    ax2.legend(fontsize=8, loc="upper right")
    ax2.grid(axis="y", alpha=0.3)
    tight_layout_once(fig)
    save_figure(fig, out / "budget.png")
    return rows


def relaxations(out: Path) -> list[dict]:
    """Capacity (best layout), the bound there and the optimum when each conservative item is relaxed."""
    rows = []
    for label, change in RELAXATIONS.items():
        kw = {k: v for k, v in change.items() if k != "fixed"}
        base = Requirements()
        req = replace(base, **kw, fixed=replace(base.fixed, **change.get("fixed", {})))
        caps = {lay: gas_capacity(req, lay).total_gas_mm3 for lay in req.layouts}
        best_lay = max(caps, key=caps.get)
        res = optimise(req, seed=0, progress=False, bladder_strain_fn=_strain_fn(req))
        ev = res.evaluation
        try:  # can the CAD draw it (its feature checks, before any solid)?
            cad = Layout(res.design)
            drawable, throttle = "yes", cad.throttle_d
        except CadError as exc:
            drawable, throttle = f"no: {exc}", float("nan")
        rows.append({"relaxation": label, "drawable": drawable, "throttle_bore_mm": throttle, "capacity_mm3": caps[best_lay], "capacity_layout": best_lay,
                     "bound_at_capacity": gas_volume_bound(caps[best_lay], req).linearity_error,
                     "optimum_isothermal": ev.linearity_isothermal, "optimum_layout": res.layout,
                     "optimum_gas_mm3": res.design.V1_mm3 + res.design.V2_mm3,
                     "bladder_cast_fill": res.design.fixed.bladder_cast_fill,
                     "bladder_strain_fe": res.bladder_strain_fe, "feasible": ev.feasible,
                     "piston_pocket_mm3": res.design.piston_pocket_volume_mm3,
                     "piston_floor_mm": res.design.piston_floor_mm,
                     "optimum_adiabatic": ev.linearity_adiabatic, "mass_g": res.design.mass_g})
        print(f"relaxation {label:<48} capacity {caps[best_lay]:>7.0f} mm³ ({best_lay}), bound "
              f"{100 * rows[-1]['bound_at_capacity']:.3f} %, optimum {100 * ev.linearity_isothermal:.4f} % "
              f"({res.layout}, cast fill {res.design.fixed.bladder_cast_fill:.3f}); CAD: {drawable}"
              + (f" (throttle bore {throttle:g} mm)" if drawable == "yes" else ""))
    with open(out / "relaxations.csv", "w", newline="") as fh:
        w = csv.DictWriter(fh, fieldnames=list(rows[0]))
        w.writeheader()
        w.writerows(rows)
    return rows


#: The unseen requirements where chamber 1's bore column binds (the case annulus_top is for).
SHORT = "65x120 mm, 50 mm travel, 80 N/mm"
LAYOUT_COLORS = {"inner_tube": "C2", "bulkhead": "C3", "annulus_top": "C4"}


def short_housing_figure(st: dict, rows: list, out: Path) -> None:
    """bound_short_housing.png: the packing-free bound of the short-housing requirements, each layout's
    capacity, the bound there, its own floor and its optimum."""
    fig = Figure(figsize=(8.6, 5.6))
    ax = fig.subplots()
    ax.plot([r.total_gas_mm3 / 1e3 for r in rows], [100 * r.linearity_error for r in rows], "-", color="C0",
            label="packing-free bound (eq. 5 only)")
    for lay, d in st.get("layouts", {}).items():
        c = LAYOUT_COLORS[lay]
        cap = d["capacity_mm3"] / 1e3
        ax.axvline(cap, color=c, ls=":", lw=1)
        ax.plot([cap], [100 * d["bound_at_capacity"]], "o", color=c, mfc="w", ms=7,
                label=f"{lay}: capacity {cap:.1f} × 10³ mm³, bound there {100 * d['bound_at_capacity']:.3f} %")
        floor = d["bore_floor"] if lay != "annulus_top" else d["layout_floor"]
        ax.plot([cap], [100 * floor], "_", color=c, ms=22, mew=2,
                label=f"{lay}: its own floor{' (V1 in the bore)' if lay != 'annulus_top' else ''} {100 * floor:.3f} %")
        ax.plot([d["total_gas_mm3"] / 1e3], [100 * d["optimum"]], "*", color=c, ms=14, mec="k",
                label=f"{lay}: optimum {100 * d['optimum']:.3f} % ({d['gap_to_bound_at_capacity_pp']:+.3f} pp "
                      f"to the bound at its capacity)")
    ax.set(xlabel="total gas volume V1 + V2 [10³ mm³]", ylabel="linearity error at n = 1 [%]", ylim=(0, None),
           title="65 × 120 mm, 50 mm travel, 80 N/mm at 4 MPa: the layouts against the bound")
    ax.grid(alpha=0.3)
    ax.legend(fontsize=7, loc="upper right")
    tight_layout_once(fig)
    save_figure(fig, out / "bound_short_housing.png")


def main(out: Path, quick: bool = False) -> dict:
    out.mkdir(parents=True, exist_ok=True)
    load0 = os.getloadavg()[0]
    cases = {k: v for k, v in CASES.items() if not quick or k.startswith("paper, iso")}
    studies = [case_study(k, v) for k, v in cases.items()]
    # volume budget of the paper-requirement optima (the issue's 176,000 mm³ reconciled on the first)
    budget_designs = {}
    for st in studies:
        if st["case"].startswith("paper, isothermal") and "design" in st:
            budget_designs[f"{st['case']}: {st['chosen_layout']}, {100 * st['optimum']:.3f} %"] = st["design"]
            if st["case"] == "paper, isothermal":  # the other layout's optimum as well
                for lay, d in st["layouts"].items():
                    if lay != st["chosen_layout"]:
                        budget_designs[f"paper, isothermal: {lay}, {100 * d['optimum']:.3f} %"] = \
                            st["layout_designs"][lay]
    budget_rows = volume_budget(budget_designs, out, Requirements().max_housing_length_mm)
    first = next(iter(budget_designs.values()))
    issue = issue_count_mm3(first, Requirements().max_housing_length_mm)
    relax = [] if quick else relaxations(out)
    vols = VOLUMES[::2] if quick else VOLUMES
    curves = {}
    for label in ("paper, isothermal", "paper, worst of n = 1 and 1.4", SHORT):
        if label in cases:
            curves[label] = parallel_map(_bound, [(v, cases[label]) for v in vols], description=f"bound: {label}",
                                         progress=False)
    with open(out / "bound.csv", "w", newline="") as fh:
        w = csv.writer(fh)
        w.writerow(["objective", "total_gas_mm3", "linearity_error", "A1_mm2", "A2_mm2", "V1_mm3", "V2_mm3"])
        for label, rows in curves.items():
            for r in rows:
                w.writerow([label, r.total_gas_mm3, r.linearity_error, r.A1_mm2, r.A2_mm2, r.V1_mm3, r.V2_mm3])
    fig = Figure(figsize=(8.6, 6.0))
    ax = fig.subplots()
    colors = {"inner_tube": "C2", "bulkhead": "C3", "annulus_top": "C4"}
    for (label, rows), c in zip(((k, v) for k, v in curves.items() if k != SHORT), ("C0", "C1")):
        ax.plot([r.total_gas_mm3 / 1e3 for r in rows], [100 * r.linearity_error for r in rows], "-", color=c,
                label=f"packing-free bound, {label.split(', ', 1)[1]} (eq. 5 only)")
        st = next(s for s in studies if s["case"] == label)
        for lay, d in st.get("layouts", {}).items():
            ax.axvline(d["capacity_mm3"] / 1e3, color=colors[lay], ls=":", lw=1)
            ax.plot([d["total_gas_mm3"] / 1e3], [100 * d["optimum"]], "*", color=colors[lay], ms=13, mec="k",
                    label=f"optimum, {lay} layout, {label.split(', ', 1)[1]}: {100 * d['optimum']:.3f} %")
    for lay, c in colors.items():
        ax.plot([], [], ":", color=c, label=f"capacity of the {lay} layout in 59.5 × 132.5 mm")
    for label, mc in (("paper, isothermal, cast fill free", "C0"), ("paper, worst, cast fill free", "C1"),
                      (TIGHT, "C4")):
        st = next((s for s in studies if s["case"] == label and "layouts" in s), None)
        if st is not None:
            d = st["layouts"][st["chosen_layout"]]
            ax.plot([d["total_gas_mm3"] / 1e3], [100 * d["optimum"]], "D", color=mc, ms=7, mec="k",
                    label=(f"optimum, cast fill free ({st['chosen_layout']}, {label.split(', ')[1]}): " if label != TIGHT
                           else f"optimum, paper_tight.toml ({st['chosen_layout']}, pocket, cast fill free, "
                                f"clearance 0.5, base 11): ") + f"{100 * d['optimum']:.3f} %")
    for r in relax:
        if r["relaxation"] in ("all four", "cast fill free, clearance 0.5, base 11", "all four, piston pocket"):
            ok = r["drawable"] == "yes"
            ax.plot([r["optimum_gas_mm3"] / 1e3], [100 * r["optimum_isothermal"]], "o" if ok else "X", color="C0",
                    ms=7, mec="k", mfc="w" if ok else "C0",
                    label=f"optimum, {r['relaxation']} (relaxations.csv{'' if ok else '; the CAD cannot draw it'}): "
                          f"{100 * r['optimum_isothermal']:.3f} %")
    ax.axvline(ISSUE_GAS_COUNT_MM3 / 1e3, color="#9467bd", ls="--", lw=1,
               label="the issue's count of the gas room: 176 × 10³ mm³ (budget.png)")
    ax.axhline(1.86, color="gray", ls="--", lw=1, label="paper, hand-tuned: 1.86 %")
    ax.axhline(1.20, color="k", ls="-.", lw=0.8, label="issue 12's target: 1.20 %")
    ax.set(xlabel="total gas volume V1 + V2 [10³ mm³]", ylabel="linearity error [%]", ylim=(0, None),
           title="linearity needs gas: bound, envelope capacity and optimum (93.2 N/mm at 4 MPa)")
    ax.grid(alpha=0.3)
    ax.legend(fontsize=6.5, loc="upper right")
    tight_layout_once(fig)
    save_figure(fig, out / "bound.png")
    if SHORT in curves:
        short_housing_figure(next(s for s in studies if s["case"] == SHORT), curves[SHORT], out)
    for st in studies:
        st.pop("design", None)
        st.pop("layout_designs", None)
    summary = {"cases": studies, "issue_count": issue, "relaxations": relax, "budget": budget_rows,
               "load_average_start": load0, "load_average_end": os.getloadavg()[0]}
    (out / "capacity.json").write_text(json.dumps(summary, indent=2, default=float) + "\n")
    for st in studies:
        if "infeasible" in st:
            print(f"{st['case']}: infeasible\n{st['infeasible']}")
            continue
        for lay, d in st["layouts"].items():
            print(f"{st['case']:<42} {lay:<10} optimum {100 * d['optimum']:.3f} %  gas {d['total_gas_mm3']:>7.0f} "
                  f"(capacity {d['capacity_mm3']:>7.0f}; V1 <= {d['V1_max_mm3']:.0f}, V2 <= {d['V2_max_mm3']:.0f}) mm³  "
                  f"bound at own gas {100 * d['bound_at_own_gas']:.3f} %, at capacity {100 * d['bound_at_capacity']:.3f} % "
                  f"(gap {d['gap_to_bound_at_capacity_pp']:+.3f} pp), layout floor {100 * d['layout_floor']:.3f} % "
                  f"(gap {d['gap_to_layout_floor_pp']:+.3f} pp)"
                  + ("; chamber 1 also in the annulus (no bore floor)" if lay == "annulus_top" else
                     f", with V1 in the bore (column <= {d['chamber1_length_max_mm']:.1f} mm) "
                     f"{100 * d['bore_floor']:.3f} % (gap {d['gap_to_bore_floor_pp']:+.3f} pp)"))
        if st.get("bladder_strain_fe") is not None:
            print(f"{'':<42} cast fill {st['bladder_cast_fill']:.3f}, FE strain bound {100 * st['bladder_strain_fe']:.2f} %,"
                  f" n = 1: {100 * st['optimum_isothermal']:.3f} %, n = 1.4: {100 * st['optimum_adiabatic']:.3f} %")
    print(f"the issue's count on the first budget design: {issue['count_mm3']:.0f} mm³ = gas {issue['gas_mm3']:.0f} + "
          + " + ".join(f"{k} {v:.0f}" for k, v in issue["left_out_mm3"].items()) + f" (check {issue['check_mm3']:.2g})")
    return summary


if __name__ == "__main__":
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--out", type=Path, default=HERE / "results" / "linearity_bound")
    ap.add_argument("--quick", action="store_true", help="paper requirements only, fewer volumes")
    a = ap.parse_args()
    main(a.out, a.quick)
