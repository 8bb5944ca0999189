"""The assembly-order sheet: the unit exploded step by step along its axis.

One panel per insertion of :func:`~vvea_design.cad.sequence.assembly_plan`: the parts already assembled
(grey, in section A-A), the parts moved in that step in their colours and hatches at their start offset,
with an arrow to where they go; the step list beside the panels, and the assembly check's verdict
(:func:`~vvea_design.cad.sequence.check_assembly`) in the notes. ISO A3, the scale stated in the title
block; paper mm. The bladder is drawn as cast.
"""

from __future__ import annotations

import textwrap

import numpy as np

from ..cad.assembly import CadModel
from ..cad.drafting import Revision
from ..cad.registry import get_part
from ..cad.sequence import AssemblyCheck, AssemblyStep
from .sheet_layout import SHEET_MM, _BAND_MM, _SMALL_PT, _TEXT_PT, _draw_notes_and_title, _Paper, _scale_text
from .sheet_spec import Region, SheetSpec, _aligned_loops, hatch_pattern

__all__ = ["assembly_sheet_spec", "assembly_sheet_figure", "SHEET_NAME"]

#: The sheet's name (file ``drawing_<name>.svg``).
SHEET_NAME = "assembly_order"
_TEXT_W = 118.0  # width of the step list at the right, mm
_GREY = (0.85, 0.85, 0.85)


def assembly_sheet_spec(model: CadModel, check: AssemblyCheck) -> SheetSpec:
    """The sheet's title-block content and notes (the panels are drawn by :func:`assembly_sheet_figure`).

    Parameters
    ----------
    model : CadModel
        The built CAD set.
    check : AssemblyCheck
        The assembly order, checked.

    Returns
    -------
    SheetSpec
        Title, notes (the check's verdict per step), material and view note; no regions of its own.
    """
    bad = [s for s in check.steps if not s.passes]
    verdict = ("Every insertion swept along the axis without interference; every O-ring passes only lead-in "
               "chamfers (ISO 3601-2)." if not bad else
               "NOT ASSEMBLABLE as stated: " + "; ".join(f"step {s.step.number}: {s.where or 'sharp edge'}" for s in bad))
    notes = ["Parts in section A-A (left: valve plane, right: port plane); the moving parts at their start, the "
             "arrow to where they go.",
             f"Assembly check (vvea_design.cad.sequence): {verdict}",
             "The bladder is elastic: its cuffs' beads snap into their grooves (not swept as a rigid body).",
             "O-rings lubricated with the unit's oil; no ring over a thread or port."]
    return SheetSpec(SHEET_NAME, "Spring-damper unit: assembly order", [], [], [], notes,
                     material="see parts list (bom.csv)", view_note="Exploded, step by step, along the axis",
                     finish="see the parts' sheets")


def _panel_loops(model: CadModel, name: str, dz: float, R: float) -> tuple[np.ndarray, ...]:
    loops = _aligned_loops(model.solids[name], R + 5)
    return tuple(np.column_stack([lp[:, 0], lp[:, 1] + dz]) for lp in loops)


def assembly_sheet_figure(model: CadModel, plan: tuple[AssemblyStep, ...], spec: SheetSpec, sheet_no: int,
                          n_sheets: int, design_id: str, revision: Revision | None = None):
    """The assembly-order sheet as a matplotlib Figure (paper mm coordinates).

    Parameters
    ----------
    model : CadModel
        The built CAD set (the parts at x = 0).
    plan : tuple of AssemblyStep
        The assembly order.
    spec : SheetSpec
        Title block and notes (:func:`assembly_sheet_spec`).
    sheet_no, n_sheets : int
        For the title block.
    design_id : str
        Short design identifier (drawing number).
    revision : Revision, optional
        Revision of the title block.

    Returns
    -------
    matplotlib.figure.Figure
        Not saved; ``fig._vvea_scale`` holds the scale.
    """
    from matplotlib.figure import Figure
    from matplotlib.patches import FancyArrowPatch, PathPatch, Rectangle
    from matplotlib.path import Path as MPath

    W, H = SHEET_MM
    fig = Figure(figsize=(W / 25.4, H / 25.4))
    ax = fig.add_axes((0, 0, 1, 1))
    ax.set_xlim(0, W)
    ax.set_ylim(0, H)
    ax.set_aspect("equal")
    ax.axis("off")
    ax.add_patch(Rectangle((10, 10), W - 20, H - 20, fill=False, lw=0.7, color="black"))
    lay = model.layout
    R = lay.r_outer
    moves = [s for s in plan if s.moving]
    done: list[str] = []
    extents = []
    for st in moves:  # the z range each panel needs
        zs = [model.solids[n].bounding_box() for n in st.moving]
        zf = [model.solids[n].bounding_box() for n in (*done, *st.against)] or zs
        extents.append((min(min(b.min.Z for b in zf), min(b.min.Z for b in zs) + min(st.start_mm, 0)),
                        max(max(b.max.Z for b in zf), max(b.max.Z for b in zs) + max(st.start_mm, 0))))
        done = list(dict.fromkeys([*done, *st.against, *st.moving]))
    span = max(hi - lo for lo, hi in extents)
    avail_w = W - 20 - _TEXT_W - 8
    avail_h = H - 20 - _BAND_MM - 30
    panel_w = avail_w / len(moves)
    scale = next((s for s in (1.0, 0.5, 0.2) if s * span <= avail_h and s * 2 * R <= panel_w - 8), 0.2)
    y_base = 10 + _BAND_MM + 22
    done = []
    for i, (st, (lo, hi)) in enumerate(zip(moves, extents)):
        cx = 10 + panel_w * (i + 0.5)
        P = _Paper(scale, 0.0, lo, cx, y_base + 0.5 * (avail_h - scale * (hi - lo)))
        regions = []
        for n in dict.fromkeys([*done, *st.against]):
            regions.append(Region(n, _panel_loops(model, n, 0.0, R), _GREY, None))
        for n in st.moving:
            p = get_part(n)
            regions.append(Region(n, _panel_loops(model, n, st.start_mm, R), p.colour, hatch_pattern(p)))
        for reg in regions:
            for loop in reg.loops:
                x, y = P(loop[:, 0], loop[:, 1])
                ax.add_patch(PathPatch(MPath(np.column_stack([x, y])), facecolor=reg.colour, edgecolor="black",
                                       lw=0.35, hatch=reg.hatch))
        # the arrow: from the moving parts' start to their place, beside the unit
        bb = [model.solids[n].bounding_box() for n in st.moving]
        z_mid = 0.5 * (min(b.min.Z for b in bb) + max(b.max.Z for b in bb))
        xa = P(R + 3.0, 0)[0]
        y0, y1 = P(0, z_mid + st.start_mm)[1], P(0, z_mid)[1]
        ax.add_patch(FancyArrowPatch((xa, y0), (xa, y1), arrowstyle="-|>", mutation_scale=8, lw=0.7, color="black"))
        ax.text(cx, y_base - 6, f"{st.number}", ha="center", va="top", fontsize=11, weight="bold",
                family="DejaVu Sans")
        names = ", ".join(get_part(n).title.split(" (")[0] for n in st.moving)
        ax.text(cx, y_base - 12, textwrap.fill(names, 24), ha="center", va="top", fontsize=_SMALL_PT,
                family="DejaVu Sans", linespacing=1.1)
        done = list(dict.fromkeys([*done, *st.against, *st.moving]))
    # the step list
    xt, yt = W - 10 - _TEXT_W + 2, H - 16
    ax.text(xt, yt, "Assembly order", fontsize=_TEXT_PT, weight="bold", va="top", family="DejaVu Sans")
    yt -= 7
    for st in plan:
        txt = textwrap.fill(f"{st.number}. {st.text}", 62)
        ax.text(xt, yt, txt, fontsize=_SMALL_PT, va="top", family="DejaVu Sans", linespacing=1.15)
        yt -= 3.25 * (txt.count("\n") + 1) + 2.2
    _draw_notes_and_title(ax, spec, scale, sheet_no, n_sheets, design_id, revision)
    fig._vvea_scale = scale
    ax.text(10 + avail_w / 2, H - 14, f"scale {_scale_text(scale)}", ha="center", va="top", fontsize=_SMALL_PT,
            family="DejaVu Sans")
    return fig
