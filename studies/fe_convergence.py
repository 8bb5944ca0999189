"""Mesh convergence of the FE check: the closed-form cases and the default design's pieces against element size.

Part 1, the verification cases (Lamé's thick cylinder, the simply supported and the clamped plate, the piston
floor's annular plate, Goodier's spherical cavity for a peak): the FE's error against the exact value as the
mesh is refined, and its observed order of convergence.

Part 2, the defaults' optimum (``studies/results/fe_units/defaults/design.json``, written by
``studies/fe_units.py``; ``cad/design.json`` without it, or ``--design``) under its load cases: every wall's
peak stress (at the grooves, shoulders and edges) and nominal stress (membrane plus bending on its
classification line) of the case governing on the finest mesh, as the mesh is refined by a factor ``f``
(``elements_per_wall = 3 f``, ``elements_per_radius = 3 f``); the change against the finest mesh, the observed
order from the three finest, the extrapolated value (Richardson) and the error of the main job's mesh
(``f = 1``) against both.

    python studies/fe_convergence.py            # -> studies/results/fe_convergence/
    python studies/fe_convergence.py --quick    # three levels, part 1 only (a smoke run)
    python studies/fe_convergence.py --replot   # the figure again from convergence.json
"""

from __future__ import annotations

import argparse
import json
import math
import time
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import numpy as np  # noqa: E402
from matplotlib.figure import Figure  # noqa: E402

from vvea_design.progress import progress_bar  # noqa: E402
from vvea_design.structure import verification as ver  # noqa: E402
from vvea_design.structure.meshing import MeshSpec  # noqa: E402

ROOT = Path(__file__).resolve().parents[1]
OUT = ROOT / "studies" / "results" / "fe_convergence"
FACTORS = (0.5, 0.75, 1.0, 1.5, 2.0, 3.0)
#: The design of part 2: the defaults' buildable optimum (written by studies/fe_units.py; else cad/design.json).
DESIGN = ROOT / "studies" / "results" / "fe_units" / "defaults" / "design.json"
QUICK_FACTORS = (0.5, 1.0, 2.0)


def spec_of(f: float, **kw) -> MeshSpec:
    """The main job's mesh refined by ``f`` (``f = 1``: the main job's)."""
    base = MeshSpec(**kw)
    return MeshSpec(elements_per_wall=base.elements_per_wall * f, elements_per_radius=base.elements_per_radius * f,
                    growth=base.growth, max_size_mm=base.max_size_mm / f, min_size_mm=base.min_size_mm)


def observed_order(values, factors) -> float:
    """Order of convergence from the three finest of a geometric-ish sequence of refinements.

    ``p = ln(|f2 - f1| / |f3 - f2|) / ln(r)`` with ``r`` the refinement ratio of the last step (element size
    ~ 1 / factor); nan when the changes vanish or change sign.
    """
    v, fa = np.asarray(values[-3:], float), np.asarray(factors[-3:], float)
    d1, d2 = v[1] - v[0], v[2] - v[1]
    if d1 == 0 or d2 == 0 or np.sign(d1) != np.sign(d2):
        return math.nan
    r = math.sqrt((fa[1] / fa[0]) * (fa[2] / fa[1]))
    return math.log(abs(d1 / d2)) / math.log(r)


def richardson(values, factors, p: float) -> float:
    """The value extrapolated to zero element size from the two finest, order ``p`` (the finest if p is nan)."""
    if not np.isfinite(p) or p <= 0:
        return float(values[-1])
    r = factors[-1] / factors[-2]
    return float(values[-1] + (values[-1] - values[-2]) / (r**p - 1))


def part1(factors) -> dict:
    """The verification cases: error against the closed form per refinement."""
    cases = {
        "lame_internal": lambda s: ver.thick_cylinder(spec=s)[0][0],
        "plate_simply_supported": lambda s: ver.circular_plate("simply_supported", spec=s)[0][0],
        "plate_clamped": lambda s: ver.circular_plate("clamped", spec=s)[0][0],
        "annular_plate_b_plus_t": lambda s: ver.annular_plate(spec=s)[0][1],
        "spherical_cavity_peak": lambda s: ver.spherical_cavity(spec=spec_of_cavity(s))[0][0],
    }
    out = {}
    with progress_bar("FE convergence: closed-form cases", len(cases) * len(factors)) as advance:
        for name, fn in cases.items():
            rows = []
            for f in factors:
                t = time.perf_counter()
                c = fn(spec_of(f))
                rows.append({"factor": f, "fe_MPa": c.fe_MPa, "closed_form_MPa": c.closed_form_MPa,
                             "relative_error": c.relative_error, "seconds": time.perf_counter() - t})
                advance()
            errs = [r["relative_error"] for r in rows]
            out[name] = {"quantity": c.quantity, "case": c.case, "levels": rows,
                         "order": _error_order(errs, factors)}
    return out


def spec_of_cavity(s: MeshSpec) -> MeshSpec:
    """The cavity's body is large: cap the far-field size, keep the refinement at the cavity."""
    return MeshSpec(elements_per_wall=s.elements_per_wall, elements_per_radius=s.elements_per_radius,
                    growth=0.2, max_size_mm=min(s.max_size_mm, 2.0))


def _error_order(errs, factors) -> float:
    """Observed order of an error sequence (slope of log error against log factor, the finest three)."""
    e, f = np.asarray(errs[-3:]), np.asarray(factors[-3:])
    if (e <= 0).any():
        return math.nan
    return float(-np.polyfit(np.log(f), np.log(e), 1)[0])


def part2(factors, design_path: Path) -> dict:
    """A design's walls: the peak and nominal of the case governing on the finest mesh, against refinement."""
    from vvea_design.cad import build_cad
    from vvea_design.spring.design_file import load_design
    from vvea_design.structure.check import check_structure

    design = load_design(design_path)
    model = build_cad(design)
    levels = []
    with progress_bar("FE convergence: the design's pieces", len(factors)) as advance:
        for f in factors:
            t, c = time.perf_counter(), time.process_time()
            res = check_structure(model, mesh=spec_of(f))
            levels.append({"factor": f, "seconds": time.perf_counter() - t, "cpu_seconds": time.process_time() - c,
                           "elements": {p.piece: p.elements for p in res.pieces},
                           "walls": {w.wall: _wall_numbers(w) for w in res.walls}})
            advance()
    walls = {}
    i1 = list(factors).index(1.0)
    for wall, finest in levels[-1]["walls"].items():
        case = finest["case"]  # one case through every level (the governing one may switch on coarse meshes)
        entry = {"case": case, "feature": finest["by_case"][case]["feature"]}
        for q in ("peak_MPa", "nominal_MPa"):
            vals = [lv["walls"][wall]["by_case"][case][q] for lv in levels]
            if any(v is None for v in vals):
                continue
            p = observed_order(vals, factors)
            ext = richardson(vals, factors, p)
            entry[q] = {"values": vals, "order": p, "extrapolated": ext,
                        "main_job_vs_finest": vals[i1] / vals[-1] - 1,
                        "main_job_error": abs(vals[i1] - ext) / abs(ext),
                        "finest_change": abs(vals[-1] - vals[-2]) / abs(vals[-1])}
        walls[wall] = entry
    return {"design": str(design_path.relative_to(ROOT)) if design_path.is_relative_to(ROOT) else str(design_path),
            "levels": levels, "walls": walls}


def _wall_numbers(w) -> dict:
    def nums(c):
        nom = None if c.nominal is None else (c.nominal.membrane_bending_tresca_MPa if w.criterion == "tresca"
                                              else c.nominal.membrane_bending_von_mises_MPa)
        return {"feature": c.peak.feature, "nominal_MPa": nom,
                "peak_MPa": c.peak.tresca_MPa if w.criterion == "tresca" else c.peak.von_mises_MPa}

    return {"case": w.governing.case, **nums(w.governing), "by_case": {c.case: nums(c) for c in w.cases}}


def figure(p1: dict, p2: dict | None, path: Path) -> Path:
    """Left: the verification cases' errors; right: the design's walls against the finest mesh."""
    fig = Figure(figsize=(12.0, 4.6), layout="constrained")
    axes = fig.subplots(1, 2 if p2 else 1)
    ax = np.atleast_1d(axes)[0]
    for name, d in p1.items():
        f = [r["factor"] for r in d["levels"]]
        ax.loglog(f, [max(r["relative_error"], 1e-6) * 100 for r in d["levels"]], "o-",
                  label=f"{name.replace('_', ' ')} (order {d['order']:.1f})")
    ax.axhline(2.0, color="k", ls="--", lw=1, label="2 % (the verification's limit)")
    ax.axvline(1.0, color="grey", ls=":", lw=1)
    ax.set_xlabel("mesh refinement factor f (element size ∝ 1/f; f = 1 the main job's)")
    ax.set_ylabel("|FE − closed form| / closed form (%)")
    ax.set_title("closed-form cases")
    ax.grid(alpha=0.3, which="both")
    ax.legend(fontsize=8)
    if p2:
        ax = np.atleast_1d(axes)[1]
        colours: dict = {}
        for wall, d in p2["walls"].items():
            for q, ls in (("peak_MPa", "-"), ("nominal_MPa", "--")):
                if q not in d:
                    continue
                v = np.asarray(d[q]["values"])
                f = [lv["factor"] for lv in p2["levels"]]
                line = ax.plot(f, 100 * (v / v[-1] - 1), ls, marker="o" if q == "peak_MPa" else ".", ms=4,
                               color=colours.get(wall), label=f"{wall}: peak at the {d['feature']} ({d['case']})"
                               if q == "peak_MPa" else None)[0]
                colours[wall] = line.get_color()
        ax.axvline(1.0, color="grey", ls=":", lw=1)
        ax.axhline(0.0, color="k", lw=0.6)
        ax.set_xscale("log")
        ax.set_xlabel("mesh refinement factor f")
        ax.set_ylabel("stress / finest mesh's − 1 (%)")
        ax.set_title(f"{p2['design']}: each wall's governing case,\n"
                     "peak (solid) and nominal membrane + bending (dashed)", fontsize=10)
        ax.grid(alpha=0.3, which="both")
        ax.legend(fontsize=7, ncols=2, loc="upper center", bbox_to_anchor=(0.5, -0.16))
    path.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(path, dpi=110, metadata={"Software": "vvea-design"})
    return path


def main(argv=None) -> int:
    """Run both parts (part 1 only with ``--quick``), write the JSON and the figure."""
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true")
    ap.add_argument("--design", type=Path, default=DESIGN,
                    help="the design whose pieces are refined (default: the defaults' optimum of studies/fe_units.py)")
    ap.add_argument("--out", type=Path, default=OUT)
    ap.add_argument("--replot", action="store_true", help="redraw the figure from convergence.json (no FE)")
    args = ap.parse_args(argv)
    if args.replot:
        d = json.loads((args.out / "convergence.json").read_text())
        print(figure(d["closed_form_cases"], d["default_design"], args.out / "convergence.png"))
        return 0
    factors = QUICK_FACTORS if args.quick else FACTORS
    t0 = time.perf_counter()
    p1 = part1(factors)
    p2 = None if args.quick else part2(factors, args.design if args.design.exists() else ROOT / "cad" / "design.json")
    out = args.out / ("quick" if args.quick else "")
    out.mkdir(parents=True, exist_ok=True)
    (out / "convergence.json").write_text(json.dumps({"factors": factors, "closed_form_cases": p1,
                                                      "default_design": p2,
                                                      "seconds": time.perf_counter() - t0}, indent=2) + "\n")
    figure(p1, p2, out / "convergence.png")
    for name, d in p1.items():
        i1 = list(factors).index(1.0)
        print(f"{name:26s} error at f = 1: {100 * d['levels'][i1]['relative_error']:.2f} %, order {d['order']:.2f}")
    if p2:
        for wall, d in p2["walls"].items():
            pk = d.get("peak_MPa", {})
            print(f"{wall:12s} peak order {pk.get('order', math.nan):.2f}, main job vs finest "
                  f"{100 * pk.get('main_job_vs_finest', math.nan):+.2f} %, vs extrapolated "
                  f"{100 * pk.get('main_job_error', math.nan):.2f} %")
    print(f"-> {out}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
