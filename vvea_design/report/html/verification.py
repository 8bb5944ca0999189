"""The report's "What is verified" section: every check with its load case, its method or standard, its result
and what it leaves out (issue: a unit a workshop can build; a pressure-equipment designer reads this first).

Each row is built from the unit's own results (the design file's load cases and joints, the FE check, the
bladder's stroke ends, the CAD manifest's assembly check and leak paths, the hydraulics); nothing here is a
fixed claim. A check that did not run (no CAD, no FE, no actuator study) says so instead of passing.
"""

from __future__ import annotations

from typing import Any

from .page import Section, paragraph, table

__all__ = ["VERIFICATION_KEYS", "verification_rows", "verification_section"]

#: The keys of one check in ``unit.json``'s ``verification`` list (the columns of the report's table).
VERIFICATION_KEYS = ("check", "load_case", "method", "result", "not_covered")

#: What the bladder check does not cover (named in the report next to its verdict).
BLADDER_LEAVES_OUT = ("creasing fatigue where the sleeve folds (the wrinkled area is not a strain the membrane "
                      "computes)", "swelling of the silicone in the oil", "gas permeation of the nitrogen through "
                      "the silicone (the charge falls over time)", "cure shrinkage and the bond at the clamps")


def _verdict(ok: bool | None) -> str:
    return "not run" if ok is None else ("PASS" if ok else "FAIL")


def _design_dict(unit: Any) -> dict[str, Any]:
    from ...spring.design_file import design_to_dict

    return design_to_dict(unit.optimisation.evaluation, unit.requirements)


def _closed_form_row(d: dict[str, Any]) -> tuple:
    st = d.get("structure") or {}
    pieces = st.get("pieces") or {}
    cases = sorted((st.get("load_cases") or {}).get("cases", {}))
    tol = sorted({t.get("standard", "") for t in st.get("tolerances", ()) if t.get("standard")})
    if not pieces:
        walls = d["performance"].get("wall_safety_factors", {})
        worst = min(walls.items(), key=lambda kv: kv[1]) if walls else ("-", float("nan"))
        return ("walls, closed form", "gas at the adiabatic peak (gas-only rules)", "Lamé hoop stress, plates",
                f"{_verdict(all(m >= -1e-9 for m in d['constraints'].values()))}: least factor {worst[1]:.2f} "
                f"({worst[0]})", "the damper's fluid loads, tolerances and stress concentrations (gas-only rules)")
    worst = min(pieces.values(), key=lambda p: p["safety_factor"] / p["required_safety_factor"])
    methods = sorted({p["method"].split(",")[0] for p in pieces.values()})
    ok = all(p["safety_factor"] >= p["required_safety_factor"] - 1e-9 for p in pieces.values())
    return ("every pressure-bearing piece, closed form (the optimiser's sizing)",
            f"each piece's worst of {len(cases)} cases ({', '.join(cases)})",
            f"{'; '.join(methods)}; Tresca; least-material size of the drawn tolerance ({', '.join(tol) or '-'})",
            f"{_verdict(ok)}: least factor {worst['safety_factor']:.2f} of {worst['required_safety_factor']:g} "
            f"({worst['piece']}, {worst['governing_case']})",
            "stress concentrations at grooves and steps (the FE row), fatigue under pressure cycles")


def _joint_rows(d: dict[str, Any]) -> list[tuple]:
    rows = []
    for j in d.get("joints") or ():
        if j.get("kind") == "seat":
            sf, std = j["safety_factor"], "bearing stress on the seat"
        else:
            sf, std = min(j.get("safety_factors", {"-": float("nan")}).values()), j.get("standard", "-")
        req = j["required_safety_factor"]
        name = f"joint {j['joint']} ({j.get('designation', j['kind'])})"
        result = ("PASS: carries no end load" if sf is None or not j["end_load_N"]
                  else f"{_verdict(sf >= req - 1e-9)}: least factor {sf:.2f} of {req:g}")
        rows.append((name, f"{j.get('governing_case', '-')}: end load {j['end_load_N']:.0f} N", std, result,
                     "fatigue" if j.get("kind") == "seat" else
                     "fatigue, thread galling; the tightening is by the drawing's note"))
    return rows


def _fe_row(unit: Any) -> tuple:
    fe = unit.structure
    if fe is None:
        return ("every pressure-bearing piece, FE", "-", "axisymmetric linear-elastic FE", "not run (no CAD)",
                "-")
    worst = min(fe.walls, key=lambda w: w.governing.safety / w.governing.required_safety)
    g = worst.governing
    return ("every pressure-bearing piece, FE (the final check)", f"every case; governing for the worst piece: {g.case}",
            f"axisymmetric linear-elastic FE (scikit-fem on gmsh sections of the CAD), {fe.criterion} peak / yield, "
            + ("inside corners at the drawing's root radii" if fe.corner_radius_mm is None
               else f"inside corners at R{fe.corner_radius_mm:g} mm"),
            f"{_verdict(fe.passes)}: least factor {g.safety:.2f} of {g.required_safety:g} ({worst.wall}, "
            f"{g.peak.feature})",
            "fatigue, thread flanks (the thread is a smeared ring), contact and preload at the joints, "
            "non-axisymmetric ports (their share of the volume is in the FE table)")


def _seal_rows(unit: Any) -> list[tuple]:
    m = unit.cad_manifest
    if m is None:
        return [("seals and assembly", "-", "ISO 3601", "not run (no CAD)", "-")]
    leaks = list(m.leak_paths or ())
    sealed = sum(bool(p.get("sealed")) for p in leaks)
    rows = [("every joint and port sealed", "proof pressure (the glands' extrusion gap at proof is not checked)",
             "ISO 3601-1 rings in ISO 3601-2 glands, NBR for the oil and nitrogen (ISO 3601-5)",
             f"{_verdict(bool(leaks) and sealed == len(leaks))}: {sealed} of {len(leaks)} leak paths sealed"
             + "".join(f"; not sealed: {p['where']} ({p['between']})" for p in leaks if not p.get("sealed")),
             "seal friction and wear, long-term compression set")]
    a = m.assembly or {}
    if a:
        bad = [s["number"] for s in a.get("steps", ()) if not s.get("passes", True)]
        rows.append(("assembly order", "the parts moved along the axis in the stated order",
                     "sweep of each part's section; O-rings only over 15-20° lead-ins (ISO 3601-2)",
                     f"{_verdict(bool(a.get('passes')))}" + (f": steps {', '.join(map(str, bad))} fail"
                                                              if bad else f": {len(a.get('steps', ()))} steps"),
                     "tool access, thread-locker cure, the bladder's snap-in beads (elastic, not swept)"))
    return rows


def _hydraulics_row(d: dict[str, Any]) -> tuple | None:
    h = d.get("hydraulics")
    if not h:
        return None
    return ("damping range of the built unit", f"{h.get('oil', '-')} at {h.get('oil_temperature_C', '-')} °C",
            f"orifice and laminar (Hagen–Poiseuille) restrictions of the throttle, ring channels and relief valve; "
            f"oil viscosity {h.get('oil_standard', '-')}",
            f"D = {h['D_min_N_s_per_mm']:.3g} … {h['D_max_N_s_per_mm']:.4g} N s/mm",
            "oil heating, entrained air, the valve's own dynamics")


def _bladder_row(unit: Any) -> tuple:
    bl = unit.bladder
    ends = "; ".join(f"{k}: wrinkled {100 * e.wrinkled_fraction:.1f} % of its area"
                     for k, e in bl.ends.items())
    crit = "the allowable strain given" if bl.criterion is None else f"the '{bl.criterion.name}' criterion"
    return ("bladder", "both stroke ends (the fluid volume each end moves)",
            f"axisymmetric neo-Hookean membrane FE; largest strain vs {crit} of {bl.silicone.name}",
            f"{_verdict(bl.passes)}: strain bound {100 * bl.strain_bound:.1f} % of {100 * bl.allowable_strain:.1f} %;"
            f" {ends}", "; ".join(BLADDER_LEAVES_OUT))


def verification_rows(unit: Any) -> list[tuple]:
    """Every check of the unit: (check, load case, method or standard, result, what it leaves out).

    Parameters
    ----------
    unit : UnitDesign
        The main job's result (:class:`~vvea_design.pipeline.UnitDesign`, or anything with its attributes).

    Returns
    -------
    list of tuple
        Five strings per check; the result starts with PASS, FAIL or "not run".
    """
    d = _design_dict(unit)
    ev = unit.optimisation.evaluation
    rows = [("spring force and linearity", "x over ± the travel at the charge, isothermal and adiabatic",
             "the paper's gas-spring equations (ideal gas, polytropic)",
             f"linearity {100 * ev.linearity_error:.2f} %; every constraint "
             f"{'met' if ev.feasible else 'NOT met'}",
             "seal friction, heat exchange between the two limits, real-gas effects (see vvea diagnose)"),
            _closed_form_row(d), *_joint_rows(d), _fe_row(unit), *_seal_rows(unit)]
    hyd = _hydraulics_row(d)
    if hyd is not None:
        rows.append(hyd)
    rows.append(_bladder_row(unit))
    rows.append(("actuator study", "rest-to-rest and torque-step optimal control",
                 "the paper's actuator model; every optimum re-simulated",
                 "not run" if unit.actuator_study is None else "run (the Actuator section)",
                 "the valve's bandwidth, the motor's limits beyond the paper's"))
    return rows


def verification_section(unit: Any) -> Section:
    """The report section listing every check, its load case and standard, and what it leaves out.

    Parameters
    ----------
    unit : UnitDesign
        The main job's result (:class:`~vvea_design.pipeline.UnitDesign`, or anything with its attributes).

    Returns
    -------
    Section
        Titled "What is verified".
    """
    rows = verification_rows(unit)
    body = paragraph("Every check the tool ran on this unit, with the load case it used, the method or standard "
                     "behind it, its result and what it does not cover. A PASS holds only inside its own "
                     "column of assumptions; the last column is what a designer still has to judge or test.")
    body += table(("check", "result", "load case", "method / standard", "not covered"),
                  [(c, res, case, how, left) for c, case, how, res, left in rows], cards=True)
    return Section("What is verified", body, anchor="verified")
