"""Dimensioned workshop drawings (SVG per sheet, one multi-page PDF) from the
build123d model: the unit's section and a sheet per part of the table with
a drawing hook (the housing's machined pieces, the piston).

The work is split by concern: :mod:`vvea_design.cad.sheets` says what each
sheet dimensions and notes (each part's drawing hook, the unit's section),
in the vocabulary of :mod:`vvea_design.cad.drafting` (:class:`Dim`,
:class:`Leader`, :class:`Detail`, ISO 286 fits);
:mod:`~vvea_design.report.sheet_spec` cuts the solids into section regions
and checks the dimensions' anchors against them;
:mod:`~vvea_design.report.sheet_layout` lays one sheet out on ISO A3 at a
true scale; this module writes the files. SVG and PDF carry no date, so the
files are byte-stable.

Sheets are ISO A3 landscape at a true scale (1:1, 2:1, ... stated in the
title block), all dimensions in mm, text 2.5-3.5 mm. Tolerances: general
tolerances ISO 2768-m; the sliding fits are ISO 286 H8/f7 (piston in its
bore, rod in the base); seal grooves from the O-ring's gland
(:mod:`vvea_design.cad.seals`).
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

from ..cad.assembly import CadModel
from ..cad.drafting import Detail, Dim, Leader, Revision, fit_deviations_um
from ..cad.sequence import assembly_plan
from .assembly_sheet import assembly_sheet_figure, assembly_sheet_spec
from .sheet_layout import SHEET_MM, sheet_figure
from .sheet_spec import SheetSpec, check_anchors, section_loops, sheet_specs

__all__ = ["Dim", "Leader", "Detail", "SheetSpec", "DrawingSet", "fit_deviations_um", "sheet_specs", "sheet_figure",
           "write_drawings", "check_anchors", "section_loops", "SHEET_MM"]


@dataclass(frozen=True)
class DrawingSet:
    """The drawing files written (paths) and each sheet's scale."""

    sheets: tuple[str, ...]  #: sheet names, in page order
    svg: tuple[Path, ...]
    pdf: Path  #: all sheets, one page each
    scales: tuple[float, ...]

    def to_dict(self) -> dict:
        """Plain-JSON dictionary of the files and scales.

        Returns
        -------
        dict
            JSON-ready: ``sheets`` (names in page order), ``svg`` (one path per sheet, as text), ``pdf``
            (path of the multi-page PDF) and ``scales`` (per sheet, drawing length per model length,
            dimensionless; 2.0 is 2:1).
        """
        return {"sheets": list(self.sheets), "svg": [str(p) for p in self.svg], "pdf": str(self.pdf),
                "scales": list(self.scales)}


def write_drawings(model: CadModel, out_dir, revision: Revision | None = None) -> DrawingSet:
    """Write ``drawing_<sheet>.svg`` per sheet and ``drawings.pdf`` (all sheets) into ``out_dir``: the unit's
    section, a sheet per drawn part, and the assembly order (exploded, step by step).

    Parameters
    ----------
    model : CadModel
        The built CAD set (:func:`~vvea_design.cad.build_cad`).
    out_dir : path-like
        Output folder (created).
    revision : Revision, optional
        Revision letter, date and note of the title blocks (default: revision A at the fixed date, or
        ``SOURCE_DATE_EPOCH``'s).

    Returns
    -------
    DrawingSet
        Paths and scales; the files carry no date (byte-stable).
    """
    import hashlib
    import json

    import matplotlib as mpl
    from matplotlib.backends.backend_pdf import PdfPages

    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    from dataclasses import asdict

    design_id = hashlib.sha256(json.dumps(asdict(model.design), sort_keys=True).encode()).hexdigest()[:10]
    specs = sheet_specs(model)
    plan = assembly_plan(model.layout)
    order = assembly_sheet_spec(model, model.assembly_check())
    n = len(specs) + 1
    rev = revision or Revision()
    svgs, scales = [], []
    with mpl.rc_context({"svg.hashsalt": "vvea", "svg.fonttype": "none", "pdf.fonttype": 42,
                         "hatch.linewidth": 0.3, "path.simplify": False}):
        with PdfPages(out / "drawings.pdf", metadata={"CreationDate": None, "ModDate": None,
                                                       "Creator": "vvea_design", "Producer": "matplotlib"}) as pdf:
            figs = [(spec.name, sheet_figure(spec, i + 1, n, design_id, rev)) for i, spec in enumerate(specs)]
            figs.append((order.name, assembly_sheet_figure(model, plan, order, n, n, design_id, rev)))
            for name, fig in figs:
                path = out / f"drawing_{name}.svg"
                fig.savefig(path, format="svg", metadata={"Date": None})
                pdf.savefig(fig)
                svgs.append(path)
                scales.append(fig._vvea_scale)
    specs = [*specs, order]
    return DrawingSet(tuple(s.name for s in specs), tuple(svgs), out / "drawings.pdf", tuple(scales))
