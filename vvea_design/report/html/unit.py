"""The report of one designed unit (``vvea design``): :func:`unit_report` of a :class:`UnitResult`."""

from __future__ import annotations

import hashlib
import html
import json
import platform
import sys
from pathlib import Path
from typing import TYPE_CHECKING, Protocol

import numpy as np

from ...messages import show_margin
from ...palette import GAS_LAW_STYLES, LIMIT_COLOUR, SETTING_COLOURS, part_colour
from .page import HtmlReport, Section, figure_svg, image, paragraph, pass_fail, preformatted, table, verdict
from .viewer import viewer, viewer_parts_from_cad

if TYPE_CHECKING:  # pragma: no cover
    from matplotlib.figure import Figure

    from ...actuator.design_study import DesignStudy
    from ...actuator.model import Actuator
    from ...bladder.check import BladderResult
    from ...cad.manifest import CadManifest
    from ...spring.curve import SpringCurve
    from ...spring.optimise import OptimisationResult
    from ...spring.requirements import Requirements
    from ..bom import BillOfMaterials
    from ..drawing import DrawingSet
    from ...structure.check import StructureResult

__all__ = ["UnitResult", "unit_report", "MAX_INLINE_DRAWINGS_BYTES"]


# ------------------------------------------------------------- unit report
class UnitResult(Protocol):
    """What :func:`unit_report` reads of a designed unit.

    The main job's result (``UnitDesign`` of the pipeline module, which sits above this
    one and calls it) has every member; the report states the shape it needs
    instead of importing its caller. Read-only members, units as in the result.
    """

    @property
    def requirements(self) -> Requirements:
        """What was asked for."""

    @property
    def optimisation(self) -> OptimisationResult:
        """The optimised design, evaluated (margins, performance)."""

    @property
    def spring(self) -> SpringCurve:
        """Isothermal and adiabatic force curves (N), deviations (N), pressures (MPa) over x (mm)."""

    @property
    def bladder(self) -> BladderResult:
        """The bladder check with the requirements' silicone."""

    @property
    def actuator(self) -> Actuator:
        """Joint-level K, D range of the unit (SI)."""

    @property
    def cad_manifest(self) -> CadManifest | None:
        """The CAD set's manifest (None when CAD was skipped)."""

    @property
    def bom(self) -> BillOfMaterials | None:
        """Bill of materials (None: no CAD)."""

    @property
    def drawings(self) -> DrawingSet | None:
        """Dimensioned drawings (None: no CAD)."""

    @property
    def structure(self) -> StructureResult | None:
        """FE check of the pressure-bearing pieces (None: no CAD)."""

    @property
    def actuator_study(self) -> DesignStudy | None:
        """The design's rest-to-rest and torque-step study (None when skipped)."""

    @property
    def out_dir(self) -> Path:
        """The folder written."""

    @property
    def files(self) -> dict[str, Path]:
        """What was written, by role."""

    @property
    def seconds(self) -> dict[str, float]:
        """Wall time of each step (s)."""

    @property
    def seed(self) -> int:
        """Seed of the optimiser."""

    @property
    def version(self) -> str:
        """vvea-design version that made it."""

    @property
    def spec_path(self) -> str | None:
        """Requirements file (None: the built-in defaults)."""

    @property
    def passes(self) -> bool:
        """Every constraint met and the bladder check passed."""


def _spring_figure(unit: UnitResult) -> "Figure":
    from matplotlib.figure import Figure

    c = unit.spring
    x = c.x_mm
    fig = Figure(figsize=(12.5, 3.9))
    a, b, p = fig.subplots(1, 3)
    iso, adi = GAS_LAW_STYLES["isothermal"], GAS_LAW_STYLES["adiabatic"]  # one style per gas law, every figure
    c1, c2 = part_colour("gas_chamber_1"), part_colour("gas_chamber_2")  # the chambers' colours of the renders
    a.plot(x, c.force_isothermal_N, **iso, lw=2, label=f"isothermal (n = 1), {c.stiffness_isothermal_N_per_mm:.1f} N/mm")
    a.plot(x, c.force_adiabatic_N, **adi, lw=1.5,
           label=f"adiabatic (n = 1.4), {c.stiffness_adiabatic_N_per_mm:.1f} N/mm")
    a.set(xlabel="displacement x (mm), x > 0 extends", ylabel="force F (N), tension > 0")
    a.set_title("force over the stroke", y=1.0)  # placed, not searched for at the draw (no offset text here)
    a.legend(fontsize=8, loc="upper left")
    a.grid(alpha=0.3)
    b.plot(x, c.deviation_isothermal_N, **iso, lw=2, label=f"isothermal: {100 * c.linearity_isothermal:.2f} %")
    b.plot(x, c.deviation_adiabatic_N, **adi, lw=1.5, label=f"adiabatic: {100 * c.linearity_adiabatic:.2f} %")
    b.axhline(0, color="k", lw=0.6)
    b.set(xlabel="displacement x (mm)", ylabel="F − least-squares line (N)")
    b.set_title("deviation from the straight line (linearity error)", y=1.0)
    b.legend(fontsize=8, loc="best")
    b.grid(alpha=0.3)
    p.plot(x, c.P1_isothermal_MPa, color=c1, ls=iso["ls"], lw=2, label="chamber 1, isothermal")
    p.plot(x, c.P2_isothermal_MPa, color=c2, ls=iso["ls"], lw=2, label="chamber 2, isothermal")
    p.plot(x, c.P1_adiabatic_MPa, color=c1, ls=adi["ls"], lw=1.2, label="chamber 1, adiabatic")
    p.plot(x, c.P2_adiabatic_MPa, color=c2, ls=adi["ls"], lw=1.2, label="chamber 2, adiabatic")
    p.set(xlabel="displacement x (mm)", ylabel="gas pressure (MPa)")
    p.set_title("chamber pressures", y=1.0)
    p.legend(fontsize=8, loc="best")
    p.grid(alpha=0.3)
    # margins in inches as a constrained layout set them, without the second draw it costs: fixed room for
    # the titles and axis labels, and left of each panel the room of its widest y tick label
    from ...figure_layout import place_row_in, ytick_label_width_in

    place_row_in(fig, (a, b, p), left=0.365 + ytick_label_width_in(a), right=0.042, bottom=0.477, top=0.255,
                 gaps=[0.39 + ytick_label_width_in(ax) for ax in (b, p)])
    return fig


def _bladder_figure(unit: UnitResult) -> "Figure":
    from matplotlib.figure import Figure

    bl = unit.bladder
    ends = list(bl.ends)
    fig = Figure(figsize=(7.5, 3.2))
    ax = fig.subplots()
    kinds = [("membrane max principal", [bl.ends[k].max_principal_strain for k in ends]),
             ("clamp (membrane + bending)", [bl.ends[k].clamp_strain for k in ends])]
    w = 0.35
    for i, (label, vals) in enumerate(kinds):
        ax.bar(np.arange(len(ends)) + (i - 0.5) * w, 100 * np.asarray(vals), w, label=label)
    ax.axhline(100 * bl.allowable_strain, color=LIMIT_COLOUR, lw=1.5, ls="--",
               label=f"allowable {100 * bl.allowable_strain:.1f} % ({bl.silicone.name})")
    ax.set_xticks(np.arange(len(ends)), [f"{k}\n(ΔV = {bl.volume_change_mm3[k]:+.0f} mm³)" for k in ends])
    ax.set_ylabel("strain (%)")
    ax.set_ylim(0, 100 * max(bl.allowable_strain, bl.strain_bound) * 1.35)
    ax.set_title(f"bladder strain bound {100 * bl.strain_bound:.1f} % vs allowable {100 * bl.allowable_strain:.1f} %", y=1.0)
    ax.legend(fontsize=8, loc="upper left", ncols=3)
    ax.grid(axis="y", alpha=0.3)
    from ...figure_layout import set_margins_in, ytick_label_width_in

    # as a constrained layout set them (without its second draw); the y tick labels' room measured
    set_margins_in(fig, left=0.351 + ytick_label_width_in(ax), bottom=0.481, right=0.289, top=0.255)
    return fig


def _requirements_section(unit: UnitResult) -> Section:
    from dataclasses import fields

    req = unit.requirements
    rows = []
    for f in fields(req):
        if f.name in ("bounds", "fixed"):
            continue
        rows.append((f.name, getattr(req, f.name)))
    bounds = table(("decision variable (unit in the name)", "search low", "search high"),
                   [(k, v[0], v[1]) for k, v in req.resolved_bounds.items()])
    src = unit.spec_path or "built-in defaults (the paper's unit)"
    return Section("Requirements", paragraph(f"source: {src}") +
                   table(("requirement (unit in the name)", "value"), rows) + bounds)


def _layout_text(unit: UnitResult) -> str:
    """"the bulkhead layout (chosen of inner_tube, bulkhead, annulus_top)"."""
    layout = unit.optimisation.evaluation.performance()["layout"]
    searched = [str(x) for x in (getattr(unit.requirements, "layouts", None) or ())]
    others = f" (chosen of {', '.join(searched)})" if len(searched) > 1 else ""
    return f"the {layout} layout{others}"


def _margins_section(unit: UnitResult) -> Section:
    from ...palette import gas_law_label

    ev = unit.optimisation.evaluation
    rows = []
    for name, m in ev.margins.items():
        d = ev.details[name]
        rel = "≤" if d["kind"] == "max" else "≥"
        unit_s = d["unit"] if d["unit"] != "-" else ""
        # verdict first: on a phone a row reads top-down; round-off of a binding constraint reads 0
        rows.append((pass_fail(m >= -1e-9), name, f"{show_margin(d['value'])} {unit_s}".strip(),
                     f"{rel} {float(d['limit']):.4g} {unit_s}".strip(), show_margin(m)))
    perf = ev.performance()
    law = gas_law_label(ev.design.gas_spring.n_polytropic)
    prow = [("layout", str(perf["layout"])),
            ("linearity error, isothermal (n = 1)", f"{100 * perf['linearity_error_isothermal']:.3f} %"),
            ("linearity error, adiabatic (n = 1.4)", f"{100 * perf['linearity_error_adiabatic']:.3f} %"),
            (f"mean stiffness at the charge, {law}", f"{perf['mean_stiffness_N_per_mm']:.2f} N/mm"),
            ("largest force over the stroke", f"{perf['max_force_N']:.1f} N"),
            ("charge p1 / p2", f"{perf['p1_MPa']:.3f} / {ev.design.p2_MPa:.3f} MPa"),
            ("peak pressure", f"{perf['peak_pressure_MPa']:.2f} MPa"),
            ("mass", f"{perf['mass_g']:.0f} g"),
            ("housing length", f"{perf['housing_length_mm']:.1f} mm"),
            ("piston diameter", f"{ev.design.piston_diameter_mm:.2f} mm"),
            ("outer diameter", f"{ev.design.outer_diameter_mm:.2f} mm"),
            ("V1 / V2", f"{ev.design.V1_mm3:.0f} / {ev.design.V2_mm3:.0f} mm³")]
    body = (verdict(ev.feasible, "every constraint met" if ev.feasible else "a constraint is violated") +
            table(("quantity", "value"), prow) +
            table(("verdict", "constraint", "value", "limit", "margin (> 0 met, scaled)"), rows, raw_columns=(0,),
                  num_columns=(4,)) +
            paragraph(f"binding (margin < 0.001): {', '.join(unit.optimisation.binding()) or 'none'}; optimiser: "
                      f"{unit.optimisation.evaluations} evaluations in {unit.optimisation.seconds:.1f} s, seed "
                      f"{unit.seed}.", "note"))
    return Section("Design and constraint margins", paragraph(f"Design of {_layout_text(unit)}.") + body)


def _bladder_section(unit: UnitResult) -> Section:
    bl = unit.bladder
    rows = []
    for k, e in bl.ends.items():
        rows.append((k, float(bl.volume_change_mm3[k]), e.pressure_MPa, 100 * e.max_principal_strain,
                     100 * e.clamp_strain, 100 * e.strain_bound, 100 * e.wrinkled_fraction, e.gap_inner_tube_mm,
                     e.gap_outer_bore_mm))
    body = (verdict(bl.passes, f"strain bound {100 * bl.strain_bound:.2f} % vs allowable "
                               f"{100 * bl.allowable_strain:.2f} % ({bl.silicone.name}); radial room "
                               f"{'ok' if bl.passes_room else 'the bladder touches'}") +
            figure_svg(_bladder_figure(unit), "FE membrane strain at both stroke ends against the silicone's "
                                              "allowable strain (dashed).") +
            table(("stroke end", "ΔV (mm³)", "fluid − gas (MPa)", "membrane strain (%)", "clamp strain (%)",
                   "strain bound (%)", "wrinkled area (%)", "gap to inner tube (mm)", "gap to outer bore (mm)"), rows))
    png = unit.files.get("bladder_png")
    if png and Path(png).exists():
        body += image(png, "Deformed meridian at both stroke ends, coloured by strain.")
    return Section("Bladder", body)


def _actuator_section(unit: UnitResult) -> Section:
    from ...actuator.model import PAPER_SETTINGS

    a = unit.actuator
    rows = [(s.name, s.K_Nm_per_rad, s.D_min_Nms_per_rad, s.D_max_Nms_per_rad, s.eigenfrequency_Hz)
            for s in [a, *PAPER_SETTINGS.values()]]
    from ...palette import gas_law_label

    law = gas_law_label(unit.optimisation.evaluation.design.gas_spring.n_polytropic)
    body = (paragraph("Joint-level parameters of the unit (two pre-loaded units on the tendon pulley, paper "
                      f"section 3.4; K from the design's mean stiffness, {law}) beside the paper's Table 4 "
                      "settings.") +
            table(("setting", "K (N m/rad)", "D_min (N m s/rad)", "D_max (N m s/rad)", "eigenfrequency (Hz)"), rows))
    study = unit.actuator_study
    if study is None:
        body += paragraph("The design's own rest-to-rest and safety study was not run in this job "
                          "(--no-actuator-study); `vvea study rest-to-rest --design design.json` runs it.", "note")
    else:
        body += _design_study_blocks(study)
    return Section("Actuator", body)


def _setting_swatches(names) -> str:
    """A line of the settings' colours (:data:`vvea_design.palette.SETTING_COLOURS`), as every figure draws them."""
    items = "".join(f'<span><i style="border-top:3px solid {SETTING_COLOURS[n]}"></i>{html.escape(n)}</span>'
                    for n in names if n in SETTING_COLOURS)
    return f'<p class="swatches note">Colours in every actuator figure: {items}</p>'


def _design_study_blocks(study: "DesignStudy") -> str:
    """The design's actuator study (:class:`vvea_design.actuator.design_study.DesignStudy`): both runs, every case
    counted, the damping range and what the optima ask of it, the designer's figure, safety."""
    grid = study.grid
    dmp = study.damping
    out = paragraph(f"Rest-to-rest optimal control (paper section 5) on {len(grid.A_rad)} × {len(grid.T_s)} cases "
                    f"(A = {', '.join(f'{v:g}' for v in grid.A_rad)} rad; T = {', '.join(f'{v:g}' for v in grid.T_s)} s), "
                    f"{study.mesh.n_intervals} collocation intervals (Radau degree {study.mesh.degree}). The design is "
                    "compared with an SEA of the same joint stiffness; every case counts: where the design's trajectory "
                    "is not valid (95 % of A not reached) or not verified by re-simulation while the other's is, the "
                    "design loses the case.")
    out += paragraph(f"Damping range used: D = {dmp.D_min_Nms_per_rad:.3g} … {dmp.D_max_Nms_per_rad:.4g} N m s/rad, "
                     f"from {dmp.source}: {dmp.why}.")
    out += "".join(paragraph(f"{r.label.capitalize()}: " + (r.charge.describe() if r.charge is not None else
                                                             f"K = {r.actuator.K_Nm_per_rad:.4g} N m/rad") + ".")
                   for r in study.runs)
    rows = [(c.run, f"{c.design} vs {c.other}", c.n_cases, c.design_beats, c.design_worse, c.only_other_valid,
             c.neither_valid, None if c.fraction_design_beats is None else 100 * c.fraction_design_beats,
             c.meanrmse_other_over_design, c.n_both_valid,
             None if c.paper_vvea_beats is None else 100 * c.paper_vvea_beats) for c in study.comparisons]
    out += "<h3>The design against an SEA of the same stiffness (and the paper's settings)</h3>" + table(
        ("run", "comparison", "cases", "design better", "design worse", "of those: design not valid",
         "neither valid", "design better (% of every case)", "mean rmse other / design (both valid)",
         "both valid", "paper: VVEA better (%)"), rows)
    srows = [(s.name, s.K_Nm_per_rad, s.D_min_Nms_per_rad, s.D_max_Nms_per_rad, s.n_cases, s.n_solved, s.n_valid,
              s.n_unverified, s.mean_rmse_rad) for s in study.settings]
    out += table(("setting", "K (N m/rad)", "D_min (N m s/rad)", "D_max (N m s/rad)", "cases", "solved", "valid",
                  "not verified", "mean rmse (rad)"), srows)
    urows = [(r.label, r.damping_use.n_cases, r.damping_use.n_reach_D_max, r.damping_use.n_stay_at_D_min,
              r.damping_use.largest_D_used_Nms_per_rad, r.damping_use.largest_damping_torque_Nm,
              r.damping_use.relief_torque_Nm, r.damping_use.n_over_relief) for r in study.runs]
    out += "<h3>What the optima ask of the valve</h3>" + table(
        ("run", "valid optima", "reach D_max", "stay at D_min", "highest D used (N m s/rad)",
         "largest damping torque (N m)", "relief torque (N m)", "above the relief torque"), urows)
    out += _setting_swatches(["design", *(r.name for r in study.references)])
    f = study.files
    if getattr(f, "map_png", None) and Path(f.map_png).exists():
        out += image(f.map_png, "rmse of the design over rmse of an SEA of the same stiffness, case by case, in "
                                "each run (green: the design tracks better; dark: the design not valid while the "
                                "SEA is, a loss; grey: neither valid).")
    if getattr(f, "trajectory_png", None) and Path(f.trajectory_png).exists():
        A, T = study.trajectory_case
        out += image(f.trajectory_png, f"Optimal trajectories at A = {A:g} rad, T = {T:g} s, equal stiffness: link "
                                       "angle against the reference (dashed), motor torque and damping of every "
                                       "setting; the design drawn thick.")
    cases = list(study.safety_design.cases) + [study.safety_reference.variable]
    tau = float(study.safety_design.setup["tau_ref_Nm"])
    out += f"<h3>Safety: {tau:g} N m torque step (paper section 6)</h3>" + table(
        ("case", "mean D (N m s/rad)", "max D (N m s/rad)", "t95 (ms)", "status"),
        [(c.name, c.mean_D_Nms_per_rad, c.max_D_Nms_per_rad, 1e3 * c.t95_s, c.status) for c in cases])
    if getattr(f, "safety_png", None) and Path(f.safety_png).exists():
        out += image(f.safety_png, "Torque step of the design and of the paper's VVEA: variable damping solid in "
                                   "the setting's colour, fixed damping dashed.")
    t = study.timing
    out += paragraph(f"study time {t.total_s:.1f} s on {t.workers} worker(s); {study.n_left_out} result(s) whose "
                     "trajectory did not verify count as not valid.", "note")
    return out


def _cad_section(unit: UnitResult) -> tuple[Section, tuple[str, ...]] | None:
    cad_dir = unit.out_dir / "cad"
    if unit.cad_manifest is None or not cad_dir.exists():
        return None
    parts = viewer_parts_from_cad(cad_dir)
    lay = _layout_text(unit)
    block, scripts = viewer(parts, f"The unit of {lay}. Drag to rotate, wheel to zoom. Assembly at x = 0 (cut-away: "
                                   "the half towards you removed; gas chambers: chamber 1 blue, chamber 2 red, as in "
                                   "the render below); mould: the two halves opened apart around the core. Units: mm.")
    m = unit.cad_manifest
    meas = [(k, v.cad, v.design, show_margin(v.rel_error, ".3g", tol=1e-12)) for k, v in m.measured.items()]
    body = block + table(("quantity", "CAD", "design", "relative error"), meas, num_columns=(3,))
    captions = {"assembly_cutaway.png": f"Meridian cut of the unit ({lay}) at x = 0 and at full stroke: gas of "
                                        "chamber 1 blue, chamber 2 red, fluid green, bladder yellow.",
                "mould_open.png": "The bladder mould laid open: half A (pins), the core with the cast bladder, "
                                  "half B (pin holes), each named on its colour."}
    for name, cap in captions.items():
        if (cad_dir / name).exists():
            body += image(cad_dir / name, cap)
    return Section("3-D model", body, anchor="model"), scripts


def _bom_section(unit: UnitResult) -> Section | None:
    bom = unit.bom
    if bom is None:
        return None
    rows = [(ln.item, ln.part, ln.description, ln.category, ln.material, ln.standard, ln.size, ln.quantity,
             ln.unit_volume_mm3, ln.unit_mass_g, ln.total_mass_g, ln.in_unit) for ln in bom.lines]
    body = (table(("item", "part", "description", "category", "material", "standard", "size", "qty",
                   "volume each (mm³)", "mass each (g)", "mass (g)", "in the unit"), rows) +
            table(("total", "value"), [("unit mass (g)", bom.unit_mass_g), ("bladder silicone", bom.silicone),
                                       ("cured bladder volume (mm³)", bom.bladder_volume_mm3),
                                       ("mould void incl. sprue, runner, vents (mm³)", bom.mould_void_mm3),
                                       ("silicone to mix (mm³)", bom.silicone_to_mix_mm3),
                                       ("silicone to mix (g)", bom.silicone_to_mix_g)]) +
            paragraph("Also in cad/bom.csv. Made parts: CAD volume × density; bought parts as listed.", "note"))
    return Section("Bill of materials", body)


#: Largest total size of drawing SVGs inlined in the report (bytes); beyond it only links are given.
MAX_INLINE_DRAWINGS_BYTES = 1_500_000


def _drawings_section(unit: UnitResult) -> Section | None:
    ds = unit.drawings
    if ds is None:
        return None
    body = paragraph("Dimensioned drawings made from the CAD solids (SVG per sheet and one PDF in cad/): "
                     + ", ".join(ds.sheets) + ".")
    used = 0
    for name, svg_path, scale in zip(ds.sheets, ds.svg, ds.scales):
        p = Path(svg_path)
        if not p.exists():
            continue
        size = p.stat().st_size
        href = html.escape(_relative(p, unit.out_dir), quote=True)  # the sheet beside the report, full size
        link = f'<a href="{href}">{html.escape(href)}</a>'
        if used + size > MAX_INLINE_DRAWINGS_BYTES:
            body += (f'<p class="note">sheet {html.escape(name)}: {link} (not inlined: the report stays '
                     "small)</p>")
            continue
        used += size
        svg = p.read_text(encoding="utf-8")
        svg = svg[svg.index("<svg"):]
        cap = html.escape(f"sheet {name}, scale {_scale(scale)}; full-size sheet: ")
        body += (f'<figure><a class="sheet" href="{href}" title="open the full-size sheet">{svg}</a>'
                 f"<figcaption>{cap}{link}</figcaption></figure>")
    return Section("Drawings", body)


def _relative(path: Path, folder: Path) -> str:
    """``path`` as a link from a page in ``folder`` (POSIX separators; absolute when outside it)."""
    try:
        return Path(path).resolve().relative_to(Path(folder).resolve()).as_posix()
    except ValueError:
        return Path(path).resolve().as_uri()


def _scale(s: float) -> str:
    return f"{s:g}:1" if s >= 1 else f"1:{1 / s:g}"


def _files_section(unit: UnitResult) -> Section:
    rows = []
    for role, p in unit.files.items():
        p = Path(p)
        try:
            rel = p.relative_to(unit.out_dir)
        except ValueError:
            rel = p
        rows.append((role, str(rel)))
    return Section("Files", table(("what", "path (in the output folder)"), rows))


def _provenance_section(unit: UnitResult) -> Section:
    spec_hash = ""
    if unit.spec_path and Path(unit.spec_path).exists():
        spec_hash = hashlib.sha256(Path(unit.spec_path).read_bytes()).hexdigest()
    rows = [("vvea-design version", unit.version), ("seed", unit.seed),
            ("requirements file", unit.spec_path or "none (built-in defaults)"),
            ("requirements sha256", spec_hash or "–"),
            ("Python", platform.python_version()), ("platform", f"{sys.platform} {platform.machine()}")]
    rows += [(f"time: {k} (s)", v) for k, v in unit.seconds.items()]
    return Section("Provenance", table(("item", "value"), rows) +
                   "<h3>Requirements as read</h3>" +
                   preformatted(json.dumps(unit.requirements.to_dict(), indent=2, default=str)))


def unit_report(unit: UnitResult) -> HtmlReport:
    """The report of one designed unit (what ``vvea design`` writes as ``report.html``).

    Parameters
    ----------
    unit : UnitResult
        The main job's result (``design_unit`` of the pipeline module returns one).

    Returns
    -------
    HtmlReport
        Call ``.write(path)``.
    """
    ev = unit.optimisation.evaluation
    from .verification import verification_section

    sections: list[Section] = [_margins_section(unit), verification_section(unit), _requirements_section(unit)]
    sections.append(Section("Force curve", figure_svg(
        _spring_figure(unit),
        f"The gas spring of {_layout_text(unit)}: isothermal (slow motion, n = 1; solid) and adiabatic (fast "
        "motion, n = 1.4; dashed) force from the same charge at x = 0; deviation = force minus its least-squares "
        "line; chamber pressures (chamber 1 blue, chamber 2 red, as in the renders).") +
        table(("gas law", "linearity error (%)", "mean stiffness (N/mm)", "F at full stroke (N)"),
              [("isothermal n = 1", 100 * unit.spring.linearity_isothermal, unit.spring.stiffness_isothermal_N_per_mm,
                float(unit.spring.force_isothermal_N[-1])),
               ("adiabatic n = 1.4", 100 * unit.spring.linearity_adiabatic, unit.spring.stiffness_adiabatic_N_per_mm,
                float(unit.spring.force_adiabatic_N[-1]))]), anchor="force"))
    scripts: tuple[str, ...] = ()
    cad = _cad_section(unit)
    if cad is not None:
        sec, scripts = cad
        sections.append(sec)
    sections.append(_bladder_section(unit))
    sections.append(_actuator_section(unit))
    from .structure import structure_section

    for extra in (structure_section(unit.structure), _drawings_section(unit), _bom_section(unit)):
        if extra is not None:
            sections.append(extra)
    sections += [_files_section(unit), _provenance_section(unit)]
    ok = unit.passes
    from ...palette import gas_law

    law = gas_law(ev.design.gas_spring.n_polytropic)
    sub = (f'{html.escape(str(ev.performance()["layout"]))} layout, '
           f'linearity error {100 * ev.linearity_error:.2f} % ({law}), stiffness {ev.mean_stiffness_N_per_mm:.1f} N/mm, '
           f'bladder {100 * unit.bladder.strain_bound:.1f} % of {100 * unit.bladder.allowable_strain:.0f} % — '
           f'<b>{"all checks pass" if ok else "a check fails"}</b> · vvea-design {html.escape(unit.version)}, '
           f'seed {unit.seed}')
    return HtmlReport("vvea design: spring–damper unit", tuple(sections), sub, scripts)
