"""The report's section on the FE check of the pressure-bearing pieces (:mod:`vvea_design.structure`).

It states what was checked and how (the load cases with their pressures, the criterion, the required factor),
per wall of the design the governing case, the peak stress and the feature it sits at, the safety factor and
the verdict, the nominal (membrane plus bending) stress beside the closed form the sizing uses, each piece's
model (where its section was cut, what the axisymmetric model leaves out, the mesh, the joint's reaction),
the assumptions, and the stress-field pictures.
"""

from __future__ import annotations

from pathlib import Path
from typing import TYPE_CHECKING

from .page import Section, image, paragraph, pass_fail, table, verdict

if TYPE_CHECKING:  # pragma: no cover
    from ...structure.check import StructureResult

__all__ = ["structure_section"]


def _crit(result: "StructureResult") -> str:
    return "Tresca" if result.criterion == "tresca" else "von Mises"


def _walls_table(result: "StructureResult") -> str:
    rows = []
    for w in result.walls:
        g = w.governing
        peak = g.peak.tresca_MPa if w.criterion == "tresca" else g.peak.von_mises_MPa
        feat = g.peak.feature + (f" R{g.peak.corner_radius_mm:.2f}" if g.peak.corner_radius_mm == g.peak.corner_radius_mm
                                 else "")
        nom = g.nominal
        nom_v = None if nom is None else (nom.membrane_bending_tresca_MPa if w.criterion == "tresca"
                                          else nom.membrane_bending_von_mises_MPa)
        rows.append((pass_fail(w.passes), w.wall, w.piece, w.material, g.case, peak,
                     f"{feat} (r {g.peak.r_mm:.2f}, z {g.peak.z_mm:.2f})", g.safety, g.required_safety, nom_v,
                     w.concentration, None if nom is None else nom.fe_comparable_MPa,
                     None if nom is None else nom.closed_form_MPa))
    return table(("verdict", "wall", "piece", "material", "governing case", f"peak {_crit(result)} (MPa)",
                  "where (mm)", "safety on yield", "required", "nominal m+b (MPa)", "peak / nominal",
                  "FE at the sizing's point (MPa)", "sizing's closed form (MPa)"), rows, raw_columns=(0,))


def _cases_table(result: "StructureResult") -> str:
    rows = [(c.name, c.x_mm, c.chamber_1_MPa, c.chamber_2_MPa, c.fluid_MPa, c.required_safety, c.what)
            for c in result.cases]
    return table(("load case", "piston x (mm)", "chamber 1 (MPa abs)", "chamber 2 (MPa abs)", "fluid (MPa abs)",
                  "required safety", "what"), rows)


def _safety_matrix(result: "StructureResult") -> str:
    names = [c.name for c in result.cases]
    rows = []
    for w in result.walls:
        by = {c.case: c for c in w.cases}
        rows.append((w.wall, *[None if n not in by else by[n].safety for n in names]))
    return table(("wall", *[f"safety, {n}" for n in names]), rows)


def _pieces_table(result: "StructureResult") -> str:
    rows = [(p.piece, p.material, p.section_angle_deg, p.volume_fraction, p.elements, p.element_size_mm, p.corners,
             p.joint) for p in result.pieces]
    return table(("piece", "material", "section cut at (°)", "CAD volume / revolved section", "elements",
                  "median element (mm)", "re-entrant corners", "axial load to the joint"), rows)


def structure_section(result: "StructureResult | None") -> Section | None:
    """The report's section on the FE check (None when the job made none).

    Parameters
    ----------
    result : StructureResult or None
        The FE check (:func:`vvea_design.structure.check_structure`; its pictures' paths are its own).

    Returns
    -------
    Section or None
        Titled "Strength (FE)".
    """
    if result is None:
        return None
    crit = _crit(result)
    failing = [w for w in result.walls if not w.passes]
    text = (f"every wall keeps its required factor on yield ({crit}, peak stress)" if not failing else
            "below the required factor on yield (" + crit + ", peak stress): " + "; ".join(
                f"{w.wall} {w.governing.safety:.2f} against {w.governing.required_safety:.2f} "
                f"({100 * (w.governing.safety / w.governing.required_safety - 1):+.0f} %, {w.governing.case}, "
                f"at the {w.governing.peak.feature})" for w in failing))
    body = verdict(result.passes, text)
    body += paragraph(
        "Axisymmetric linear-elastic FE (scikit-fem, quadratic triangles meshed by gmsh) of each machined piece's "
        "meridian section, cut from its CAD solid; the peak includes the grooves, shoulders and edges the CAD "
        f"draws (internal corners drawn sharp taken {_radii(result)}); the nominal is the "
        "membrane-plus-bending stress linearised on a line through the wall (EN 13445-3 annex C practice), "
        "shown beside the sizing's closed form. Checking the peak against the factor is stricter than a "
        "design-by-analysis check to EN 13445-3 annex B, which leaves peaks to the fatigue check. Verified "
        "against Lamé and the plate formulas within 2 % (tests/structure, studies/fe_convergence.py).")
    body += "<h3>Walls</h3>" + _walls_table(result)
    body += "<h3>Safety factor per load case</h3>" + _safety_matrix(result)
    body += "<h3>Load cases</h3>" + _cases_table(result)
    body += "<h3>Models</h3>" + _pieces_table(result)
    body += "<h3>Assumptions</h3>" + "".join(paragraph(n, "note") for n in result.notes)
    for p in result.pieces:
        if p.figure and Path(p.figure).exists():
            body += image(p.figure, f"{p.title}: {crit} stress under its governing case, the peak of each wall "
                                    "marked; right, the close-up at the highest peak with the mesh. MPa, mm.")
    cpu = result.cpu_seconds
    body += paragraph(f"FE time {result.seconds:.1f} s" + ("" if cpu != cpu else f" (CPU {cpu:.1f} s)") + ".", "note")
    return Section("Strength (FE)", body, anchor="strength")


def _radii(result) -> str:
    """How the check rounded the corners the CAD draws sharp (the drawing's root radii or one radius)."""
    if result.corner_radius_mm is None:
        return "with the drawing's root radii (R1 at steps, the ISO 3601 gland's at O-ring grooves)"
    return f"as R{result.corner_radius_mm:g}"
