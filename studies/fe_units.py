"""The FE verdict of the optimised units: the defaults, ``examples/paper_tight.toml``, a 70 x 160 mm envelope and
``examples/small_40.toml`` (40 x 120 mm) and a short 65 x 120 mm envelope with 50 mm travel.

Each is optimised (seed 0, the buildability rules), drawn, and every pressure-bearing piece is checked by the
main job's FE (:func:`vvea_design.jobs.structure.check_structure`, coarse mesh) under every load case. The
table says per wall the governing case, the FE peak (Tresca), its place and feature, the safety factor against
the required one, and the margin (safety / required - 1: negative fails by that fraction).

    python studies/fe_units.py            # -> studies/results/fe_units/{units.json, units.md, <unit>/fe_*.png}
    python studies/fe_units.py defaults   # one unit
    python studies/fe_units.py --reuse    # the FE again on the designs of a previous run
        # with studies/results/fe_units/units_before.json (the previous code's verdict): units_before_after.md
    python studies/fe_units.py --radii defaults paper_tight   # the verdict if the sharp roots were drawn R0.5 / R1
        # -> studies/results/fe_units/corner_radii.json
"""

from __future__ import annotations

import argparse
import json
import time
from dataclasses import replace
from pathlib import Path

from vvea_design.jobs.spring import optimise
from vvea_design.jobs.structure import check_structure
from vvea_design.spring.requirements import Requirements, load_requirements

ROOT = Path(__file__).resolve().parents[1]
OUT = ROOT / "studies" / "results" / "fe_units"


def units() -> dict:
    """The requirements of each unit checked."""
    return {"defaults": Requirements(),
            "paper_tight": load_requirements(ROOT / "examples" / "paper_tight.toml"),
            "envelope_70x160": replace(Requirements(), max_outer_diameter_mm=70.0, max_housing_length_mm=160.0),
            "small_40": load_requirements(ROOT / "examples" / "small_40.toml"),
            # the cost-of-buildability study's short, long-stroke envelope
            "short_65x120": Requirements(max_outer_diameter_mm=65.0, max_housing_length_mm=120.0, travel_mm=50.0,
                                         min_mean_stiffness_N_per_mm=80.0)}


def check_unit(name: str, req: Requirements, out: Path, reuse: bool = False) -> dict:
    """Optimise (or, with ``reuse``, read the design of a previous run), draw, FE-check one unit; its rows."""
    from vvea_design.cad import build_cad
    from vvea_design.spring.design_file import load_design

    t = time.perf_counter()
    path = out / name / "design.json"
    design = load_design(path) if reuse and path.exists() else optimise(req, seed=0, out=path, progress=False).design
    model = build_cad(design)
    fe = check_structure(model, out=out / name / "structure")
    rows = []
    for w in fe.walls:
        g = w.governing
        rows.append({"unit": name, "wall": w.wall, "piece": w.piece, "material": w.material,
                     "governing_case": g.case, "peak_tresca_MPa": g.peak.tresca_MPa, "r_mm": g.peak.r_mm,
                     "z_mm": g.peak.z_mm, "feature": g.peak.feature, "safety": g.safety,
                     "required_safety": g.required_safety, "margin": g.safety / g.required_safety - 1,
                     "passes": w.passes, "nominal_safety": g.nominal_safety})
    from vvea_design.spring.concentration import concentration_factors

    perf = json.loads(path.read_text())["performance"]
    return {"unit": name, "layout": design.layout, "joint": design.joint,
            "outer_diameter_mm": design.outer_diameter_mm, "linearity_error": perf["linearity_error"],
            "mass_g": perf["mass_g"], "factors": dict(concentration_factors()), "passes": fe.passes,
            "fe_seconds": fe.seconds,
            "fe_cpu_seconds": fe.cpu_seconds, "seconds": time.perf_counter() - t, "walls": rows}


def corner_radii(names: list[str], out: Path, radii=(0.2, 0.5, 1.0)) -> dict:
    """Each wall's safety factor (governing case, feature, place) with the corners the CAD draws sharp taken
    at each radius (mm): what rounding the roots on the drawing would buy."""
    from vvea_design.cad import build_cad
    from vvea_design.spring.design_file import load_design

    res = {}
    for name in names:
        model = build_cad(load_design(out / name / "design.json"))
        for r in radii:
            fe = check_structure(model, corner_radius_mm=r)
            res[f"{name} R{r}"] = {w.wall: (round(w.governing.safety, 2), w.governing.case, w.governing.peak.feature,
                                           round(w.governing.peak.r_mm, 1), round(w.governing.peak.z_mm, 1))
                                   for w in fe.walls}
            print(name, r, res[f"{name} R{r}"], flush=True)
    (out / "corner_radii.json").write_text(json.dumps(res, indent=1) + "\n")
    return res


def table(results: list[dict]) -> str:
    """A Markdown table of every unit's walls."""
    lines = ["| unit | linearity | wall | governing case | FE peak (Tresca) MPa | feature at (r, z) mm | safety | "
             "required | margin | verdict |", "|---|---|---|---|---|---|---|---|---|---|"]
    for u in results:
        for r in u["walls"]:
            lines.append(f"| {u['unit']} ({u['layout']}, {u['joint']}) | {100 * u['linearity_error']:.4f} % | "
                         f"{r['wall']} | {r['governing_case']} | "
                         f"{r['peak_tresca_MPa']:.0f} | {r['feature']} ({r['r_mm']:.1f}, {r['z_mm']:.1f}) | "
                         f"{r['safety']:.2f} | {r['required_safety']:.2f} | {100 * r['margin']:+.0f} % | "
                         f"{'PASS' if r['passes'] else 'FAIL'} |")
    return "\n".join(lines) + "\n"


def before_after(before: list[dict], after: list[dict]) -> str:
    """A Markdown table per unit and wall: the governing case, FE peak and safety factor before -> after, and
    the unit's linearity before -> after (what the buildable, FE-passing unit costs)."""
    old = {u["unit"]: u for u in before}
    lines = ["| unit | layout, joint | linearity | wall | governing case | FE peak (Tresca) MPa | safety "
             "(required) |", "|---|---|---|---|---|---|---|"]

    def lin(u):
        return "not drawn" if "error" in u else f"{100 * u['linearity_error']:.4f} %"

    for u in after:
        b = old.get(u["unit"], {"walls": [], "layout": "-", "joint": "-", "error": "not checked"})
        bw = {w["wall"]: w for w in b["walls"]}
        head = (f"| {u['unit']} | {b['layout']}, {b['joint']} → {u['layout']}, {u['joint']} | {lin(b)} → {lin(u)} ")
        for i, w in enumerate(u["walls"]):
            o = bw.get(w["wall"])
            was = ("—", "—", "—") if o is None else (o["governing_case"], f"{o['peak_tresca_MPa']:.0f}",
                                                      f"{o['safety']:.2f}")
            lines.append((head if i == 0 else "| | | ") + f"| {w['wall']} | {was[0]} → {w['governing_case']} | "
                         f"{was[1]} → {w['peak_tresca_MPa']:.0f} | {was[2]} → {w['safety']:.2f} "
                         f"({w['required_safety']:g}) |")
    return "\n".join(lines) + "\n"


def main(argv=None) -> int:
    """Check the units named (all by default) and write the table."""
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("names", nargs="*", help="units to check (default: all)")
    ap.add_argument("--out", type=Path, default=OUT)
    ap.add_argument("--reuse", action="store_true", help="check the designs of a previous run (no optimisation)")
    ap.add_argument("--radii", action="store_true", help="the named units' verdict against the corner radius")
    ap.add_argument("--before", type=Path, default=OUT / "units_before.json",
                    help="an earlier units.json: the before -> after table (units_before.md)")
    args = ap.parse_args(argv)
    if args.radii:
        corner_radii(args.names or ["defaults", "paper_tight"], args.out)
        return 0
    todo = {k: v for k, v in units().items() if not args.names or k in args.names}
    args.out.mkdir(parents=True, exist_ok=True)
    path = args.out / "units.json"
    done = {u["unit"]: u for u in json.loads(path.read_text())} if path.exists() else {}
    for name, req in todo.items():
        try:
            done[name] = check_unit(name, req, args.out, args.reuse)
        except Exception as exc:  # a unit the optimiser or the CAD cannot make is a result too
            done[name] = {"unit": name, "error": f"{type(exc).__name__}: {exc}", "walls": [], "layout": "-",
                          "joint": "-"}
        print(name, "passes" if done[name].get("passes") else "FAILS", done[name].get("error", ""))
        path.write_text(json.dumps(list(done.values()), indent=1) + "\n")
    results = list(done.values())
    (args.out / "units.md").write_text(table(results) + "".join(
        f"\n{u['unit']}: {u['error']}\n" for u in results if "error" in u))
    print(table(results))
    if args.before.exists():
        ba = before_after(json.loads(args.before.read_text()), results)
        (args.out / "units_before_after.md").write_text(ba)
        with (args.out / "units.md").open("a") as fh:
            fh.write("\nBefore → after (the previous code's verdict, units_before.json; linearity: what each envelope "
                     "pays):\n\n" + ba)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
