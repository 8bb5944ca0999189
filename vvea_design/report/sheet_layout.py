"""Layout of one sheet: ISO A3 landscape at a true scale (1:1, 2:1, ...
stated in the title block), the section regions, the dimension lines in
tiers, the leader columns, the detail view, the notes and the title block.
All paper coordinates in mm, text 2.5-3.5 mm. Drawn with matplotlib
(``Figure`` objects, no pyplot, no backend switch).
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from ..cad.drafting import Dim, Revision, drawing_number
from .sheet_spec import Region, SheetSpec

__all__ = ["sheet_figure", "SHEET_MM"]

#: ISO A3 landscape, mm.
SHEET_MM = (420.0, 297.0)
_PT_PER_MM = 72.0 / 25.4
_TEXT_PT = 9.0  # ~3.2 mm font size, ~2.3 mm cap height
_SMALL_PT = 7.5
_TIER_MM = 6.5  # spacing of stacked dimension lines on paper
_GAP_MM = 6.0  # first dimension line from the outline
_SCALES = (5.0, 2.0, 1.0, 0.5)  # ISO 5455
_DETAIL_W = 150.0  # width of the detail area at the right of the sheet, mm
_BAND_MM = 40.0  # notes and title block at the bottom of the sheet, mm
_TITLE_W = 175.0  # width of the title block, mm
_NOTE_STEP_MM = 3.9  # line pitch of the numbered notes, mm


class _Paper:
    """Model mm -> paper mm at a scale, view placed in a box."""

    def __init__(self, scale: float, u0: float, z0: float, x0: float, y0: float) -> None:
        self.s, self.u0, self.z0, self.x0, self.y0 = scale, u0, z0, x0, y0

    def __call__(self, u, z):
        return self.x0 + self.s * (np.asarray(u) - self.u0), self.y0 + self.s * (np.asarray(z) - self.z0)


def _text_mm(text: str, pt: float = _TEXT_PT) -> float:
    """Approximate rendered width of ``text`` (DejaVu Sans; its longest line), mm."""
    return 0.6 * max(len(line) for line in text.split("\n")) * pt / _PT_PER_MM


#: Longest line of a leader's note, characters (longer notes wrap).
_LEADER_CHARS = 46
_LINE_MM = 3.3  # line pitch of a wrapped leader note, mm


def _wrap(text: str) -> str:
    """A leader's note wrapped to :data:`_LEADER_CHARS` per line."""
    import textwrap

    return "\n".join(textwrap.wrap(text, _LEADER_CHARS, break_long_words=False, break_on_hyphens=False))


def _tiers(items: list[tuple[float, float]]) -> list[int]:
    """Interval scheduling: tier index per (lo, hi) so intervals of one tier do not overlap (wider first)."""
    order = sorted(range(len(items)), key=lambda i: items[i][1] - items[i][0])
    tiers: list[list[tuple[float, float]]] = []
    out = [0] * len(items)
    for i in order:
        lo, hi = items[i]
        for k, tier in enumerate(tiers):
            if all(hi < a - 1.0 or lo > b + 1.0 for a, b in tier):
                tier.append((lo, hi))
                out[i] = k
                break
        else:
            tiers.append([(lo, hi)])
            out[i] = len(tiers) - 1
    return out


def sheet_figure(spec: SheetSpec, sheet_no: int = 1, n_sheets: int = 1, design_id: str = "",
                 revision: Revision | None = None):
    """The A3 sheet of ``spec`` as a matplotlib Figure (paper mm coordinates; true scale).

    Parameters
    ----------
    spec : SheetSpec
        Regions, dimensions, leaders and notes (model mm).
    sheet_no, n_sheets : int
        For the title block.
    design_id : str
        Short design identifier for the title block (and the drawing number).
    revision : Revision, optional
        Revision letter, date and note of the title block (default: :class:`~vvea_design.cad.drafting.Revision`).

    Returns
    -------
    matplotlib.figure.Figure
        Not saved; the caller writes SVG/PDF.
    """
    from matplotlib.figure import Figure
    from matplotlib.patches import Rectangle

    W, H = SHEET_MM
    fig = Figure(figsize=(W / 25.4, H / 25.4))
    ax = fig.add_axes((0, 0, 1, 1))
    ax.set_xlim(0, W)
    ax.set_ylim(0, H)
    ax.set_aspect("equal")
    ax.axis("off")
    ax.add_patch(Rectangle((10, 10), W - 20, H - 20, fill=False, lw=0.7, color="black"))
    scale, P = _place_view(spec)
    fig._vvea_paper = P
    _draw_regions(ax, spec.regions, P)
    # centre line
    _, _, z0, z1 = spec.extent
    cx, _ = P(0.0, 0.0)
    _, yb = P(0.0, z0)
    _, yt = P(0.0, z1)
    ax.plot([cx, cx], [yb - 6, yt + 6], color="0.2", lw=0.4, ls=(0, (12, 3, 2, 3)))
    _draw_dims(ax, spec.dims, P, spec.extent)
    if spec.detail is not None:
        _draw_detail(ax, spec, fig)
    _draw_leaders(ax, spec, P)
    _draw_notes_and_title(ax, spec, scale, sheet_no, n_sheets, design_id, revision)
    fig._vvea_scale = scale  # for the tests
    return fig


def _place_view(spec: SheetSpec) -> tuple[float, _Paper]:
    """The largest ISO scale at which the view, its dimension tiers, leader columns and detail fit the sheet,
    and the map from model to paper mm that centres the view in the room left."""
    W, H = SHEET_MM
    u0, u1, z0, z1 = spec.extent
    n_top = len([d for d in spec.dims if d.axis == "u" and d.side == "top"])
    n_bot = len([d for d in spec.dims if d.axis == "u" and d.side == "bottom"])
    top = (_GAP_MM + n_top * _TIER_MM + 4) if n_top else 8.0
    bot = (_GAP_MM + n_bot * _TIER_MM + 4) if n_bot else 8.0

    def side_room(side: str) -> float:
        n = len([d for d in spec.dims if d.axis == "z" and d.side == side])
        texts = [_wrap(lead.text) for lead in spec.leaders if lead.side == side]
        return (_GAP_MM + n * _TIER_MM if n else 4.0) + (max(_text_mm(t, _SMALL_PT) for t in texts) + 14 if texts else 6)

    left, right = side_room("left"), side_room("right") + (_DETAIL_W + 6 if spec.detail else 0)
    avail_w, avail_h = W - 20 - left - right, H - 20 - _BAND_MM - top - bot
    scale = next((s for s in _SCALES if s * (u1 - u0) <= avail_w and s * (z1 - z0) <= avail_h), _SCALES[-1])
    vx0 = 10 + left + 0.5 * (avail_w - scale * (u1 - u0))
    vy0 = 10 + _BAND_MM + bot + 0.5 * (avail_h - scale * (z1 - z0))
    return scale, _Paper(scale, u0, z0, vx0, vy0)


def _draw_regions(ax, regions: Sequence[Region], P: _Paper) -> None:
    """The section regions: filled and hatched loops, or dashed outlines (paper mm via ``P``)."""
    from matplotlib.patches import PathPatch
    from matplotlib.path import Path as MPath

    for reg in regions:
        for loop in reg.loops:
            x, y = P(loop[:, 0], loop[:, 1])
            path = MPath(np.column_stack([x, y]))
            if reg.dashed:
                ax.plot(x, y, color="0.25", lw=0.6, ls=(0, (4, 2)))
                continue
            face = (*reg.colour, reg.alpha) if reg.alpha > 0 else "none"
            ax.add_patch(PathPatch(path, facecolor=face, edgecolor="black" if reg.outline else "none",
                                   lw=0.7 if reg.outline else 0, hatch=reg.hatch))


def _draw_leaders(ax, spec: SheetSpec, P: _Paper) -> None:
    """Leaders: text columns outside the dimension tiers, spread vertically, clear of the notes band."""
    H = SHEET_MM[1]
    u0, u1, _, _ = spec.extent
    n_left_tiers = 1 + max([0] + _tiers_count(spec, "left", P))
    n_right_tiers = 1 + max([0] + _tiers_count(spec, "right", P))
    for side in ("left", "right"):
        items = [lead for lead in spec.leaders if lead.side == side]
        if not items:
            continue
        items.sort(key=lambda lead: -lead.at[1])
        if side == "left":
            xt = P(u0, 0)[0] - _GAP_MM - n_left_tiers * _TIER_MM - 4
        else:
            xt = P(u1, 0)[0] + _GAP_MM + n_right_tiers * _TIER_MM + 4
        texts = [_wrap(lead.text) for lead in items]
        heights = [_LINE_MM * t.count("\n") for t in texts]  # extra height of a wrapped note
        ys = [P(*lead.at)[1] for lead in items]
        step = 5.0
        top = H - 16.0
        bottom = 10 + _BAND_MM + 6.0
        placed: list[float] = []
        for y, h, h_prev in zip(ys, heights, [0.0, *heights[:-1]]):
            y = min(y, top - 0.5 * h) if not placed else min(y, placed[-1] - step - 0.5 * (h + h_prev))
            placed.append(y)
        if placed and placed[-1] - 0.5 * heights[-1] < bottom:  # push up if the column runs into the notes
            shift = bottom - (placed[-1] - 0.5 * heights[-1])
            placed = [p + shift for p in placed]
        for lead, yt, t in zip(items, placed, texts):
            xa, ya = P(*lead.at)
            ax.plot([xa], [ya], marker="o", ms=1.6, color="black")
            ax.plot([xa, xt], [ya, yt], color="black", lw=0.35)
            ha = "right" if side == "left" else "left"
            ax.plot([xt, xt + (-3 if side == "left" else 3)], [yt, yt], color="black", lw=0.35)
            ax.text(xt + (-4 if side == "left" else 4), yt, t, ha=ha, va="center", fontsize=_SMALL_PT,
                    family="DejaVu Sans", linespacing=1.1)


def _draw_notes_and_title(ax, spec: SheetSpec, scale: float, sheet_no: int, n_sheets: int, design_id: str,
                          revision: Revision | None = None) -> None:
    """The numbered notes (bottom left) and the title block (bottom right): title, drawing number, revision and
    its date, sheet, material and mass, finish, scale and the standards, the view, the design."""
    from matplotlib.patches import Rectangle

    W = SHEET_MM[0]
    rev = revision or Revision()
    y = 10 + _BAND_MM - 2.0
    ax.text(14, y, "Notes", fontsize=_TEXT_PT, weight="bold", va="top", family="DejaVu Sans")
    for i, n in enumerate(spec.notes):
        ax.text(14, y - 5.0 - _NOTE_STEP_MM * i, f"{i + 1}. {n}", fontsize=_SMALL_PT, va="top", family="DejaVu Sans")
    bx, by, bw, bh = W - 10 - _TITLE_W, 10, _TITLE_W, _BAND_MM
    ax.add_patch(Rectangle((bx, by), bw, bh, fill=False, lw=0.7, color="black"))
    rows = [
        (spec.title, 11.0, "bold"),
        (f"Drawing no. {drawing_number(design_id, sheet_no)} | Rev. {rev.letter} ({rev.date}) | Sheet "
         f"{sheet_no}/{n_sheets} | A3", _SMALL_PT, "normal"),
        (f"Material: {spec.material}" + (f" | Mass: {spec.mass_g:.1f} g" if spec.mass_g else ""), _SMALL_PT, "normal"),
        (f"Finish: {spec.finish or 'see parts list'}", _SMALL_PT, "normal"),
        (f"Scale {_scale_text(scale)} | mm | ISO 2768-m, ISO 8015 | sections ISO 128-50", _SMALL_PT, "normal"),
        (spec.view_note, _SMALL_PT, "normal"),
        (f"vvea_design, design {design_id} | {rev.note}", _SMALL_PT, "normal"),
    ]
    for i, (t, pt, wgt) in enumerate(rows):
        ax.text(bx + 3, by + bh - 4.5 - 5.4 * i, t, fontsize=pt, weight=wgt, va="center", family="DejaVu Sans")


def _draw_dims(ax, all_dims: Sequence[Dim], P: _Paper, extent: tuple[float, float, float, float]) -> None:
    """Draw ``dims`` of a view mapped by ``P`` (view extent ``u0, u1, z0, z1`` in model mm)."""
    u0, u1, z0, z1 = extent
    # labels on a white ground above every line, so a crossing leader is interrupted, never drawn through text
    kw = dict(fontsize=_TEXT_PT, color="black", family="DejaVu Sans", zorder=6,
              bbox=dict(facecolor="white", edgecolor="none", pad=0.4))
    arrow = dict(arrowstyle="<|-|>", lw=0.5, color="black", shrinkA=0, shrinkB=0, mutation_scale=7)

    # vertical dimensions
    for side in ("left", "right"):
        dims = [d for d in all_dims if d.axis == "z" and d.side == side]
        if not dims:
            continue
        spans = [(min(d.a[1], d.b[1]), max(d.a[1], d.b[1])) for d in dims]
        tiers = _tiers(_z_paper_spans(dims, P))
        edge = P(u0 if side == "left" else u1, 0)[0]
        sgn = -1 if side == "left" else 1
        for d, (lo, hi), k in zip(dims, spans, tiers):
            xl = edge + sgn * (_GAP_MM + k * _TIER_MM)
            for (u, z) in (d.a, d.b):
                xa, ya = P(u, z)
                ax.plot([xa + sgn * 1.0, xl + sgn * 1.5], [ya, ya], color="black", lw=0.35)
            ylo, yhi = P(0, lo)[1], P(0, hi)[1]
            ax.annotate("", (xl, yhi), (xl, ylo), arrowprops=arrow)
            # the label beside its line, centred on it (a label longer than the line reaches past the arrows;
            # the tiers reserved its height)
            ax.text(xl - 1.0, 0.5 * (ylo + yhi), d.label(), rotation=90, ha="center", va="bottom", **kw)
    # horizontal dimensions
    for side in ("top", "bottom"):
        dims = [d for d in all_dims if d.axis == "u" and d.side == side]
        if not dims:
            continue
        paper = []
        for d in dims:  # a label wider than its line is centred over it: reserve its width around the centre
            xa, xb = sorted((P(d.a[0], 0)[0], P(d.b[0], 0)[0]))
            need = _text_mm(d.label()) + 4
            if xb - xa < need:
                xa, xb = 0.5 * (xa + xb) - 0.5 * need, 0.5 * (xa + xb) + 0.5 * need
            paper.append((xa, xb))
        tiers = _tiers(paper)
        edge = P(0, z1 if side == "top" else z0)[1]
        sgn = 1 if side == "top" else -1
        for d, k in zip(dims, tiers):
            yl = edge + sgn * (_GAP_MM + k * _TIER_MM)
            for (u, z) in (d.a, d.b):
                xa, ya = P(u, z)
                ax.plot([xa, xa], [ya + sgn * 1.0, yl + sgn * 1.5], color="black", lw=0.35)
            xa, xb = sorted((P(d.a[0], 0)[0], P(d.b[0], 0)[0]))
            ax.annotate("", (xb, yl), (xa, yl), arrowprops=arrow)
            ax.text(0.5 * (xa + xb), yl + 0.8, d.label(), ha="center", va="bottom", **kw)
    # inside dimensions: the line at the anchors' u, text to its right
    for d in all_dims:
        if d.side != "inside":
            continue
        xl, ylo = P(d.a[0], min(d.a[1], d.b[1]))
        _, yhi = P(d.a[0], max(d.a[1], d.b[1]))
        ax.annotate("", (xl, yhi), (xl, ylo), arrowprops=arrow)
        t = d.label()
        ymid = 0.5 * (ylo + yhi)  # beside the line, so it may be longer than the span
        left_of = d.a[0] < 0  # text on the side away from the axis
        ax.text(xl + (-0.8 if left_of else 0.8), ymid, t, rotation=90, ha="right" if left_of else "left",
                va="center", **kw)


def _draw_detail(ax, spec: SheetSpec, fig) -> None:
    """The enlarged detail view at the right of the sheet, its window marked on the main view."""
    from matplotlib.patches import PathPatch, Rectangle
    from matplotlib.path import Path as MPath

    det = spec.detail
    W, H = SHEET_MM
    u0, u1, z0, z1 = det.window
    s = det.scale
    x_area0, x_area1 = W - 10 - _DETAIL_W, W - 14
    y_area0, y_area1 = 10 + 40 + 20, H - 16
    x0 = 0.5 * (x_area0 + x_area1) - 0.5 * s * (u1 - u0)
    y0 = 0.5 * (y_area0 + y_area1) - 0.5 * s * (z1 - z0)
    P2 = _Paper(s, u0, z0, x0, y0)
    from matplotlib.transforms import Bbox

    box = Bbox.from_extents(x0, y0, x0 + s * (u1 - u0), y0 + s * (z1 - z0))
    for reg in spec.regions:
        for loop in reg.loops:
            x, y = P2(loop[:, 0], loop[:, 1])
            path = MPath(np.column_stack([x, y])).clip_to_bbox(box, inside=True)
            if len(path.vertices) < 3:
                continue
            face = (*reg.colour, reg.alpha) if reg.alpha > 0 else "none"
            ax.add_patch(PathPatch(path, facecolor=face, edgecolor="black" if reg.outline else "none",
                                   lw=0.7 if reg.outline else 0, hatch=reg.hatch))
    ax.add_patch(Rectangle((x0, y0), s * (u1 - u0), s * (z1 - z0), fill=False, lw=0.5, ls="-.", color="0.2"))
    ax.text(x0, y0 + s * (z1 - z0) + 2 + _GAP_MM + _TIER_MM * len([d for d in det.dims if d.side == "top"]),
            f"Detail {det.label} ({_scale_text(s)})", fontsize=_TEXT_PT, weight="bold", family="DejaVu Sans")
    _draw_dims(ax, det.dims, P2, det.window)
    for lead in det.leaders:
        xa, ya = P2(*lead.at)
        ax.plot([xa], [ya], marker="o", ms=1.6, color="black")
        xt, yt = x0 + 8, y0 - 12
        ax.plot([xa, xt], [ya, yt], color="black", lw=0.35)
        ax.text(xt, yt - 1.0, lead.text.replace("; ", ";\n"), ha="left", va="top", fontsize=_SMALL_PT,
                family="DejaVu Sans")
    # window on the main view
    P = fig._vvea_paper
    (wx0, wy0), (wx1, wy1) = [tuple(map(float, P(u, z))) for u, z in ((u0, z0), (u1, z1))]
    ax.add_patch(Rectangle((wx0, wy0), wx1 - wx0, wy1 - wy0, fill=False, lw=0.5, ls="-.", color="0.2"))
    ax.text(wx1 + 1.0, wy1 + 1.0, det.label, fontsize=_TEXT_PT, weight="bold", family="DejaVu Sans")


def _z_paper_spans(dims: Sequence[Dim], P) -> list[tuple[float, float]]:
    """Paper extent (y) each vertical dimension needs: its line, or its label's height centred on it when the
    label does not fit between the arrows (it is then written beside the line), mm."""
    out = []
    for d in dims:
        lo, hi = sorted((d.a[1], d.b[1]))
        ylo, yhi = P(0, lo)[1], P(0, hi)[1]
        need = _text_mm(d.label()) + 4
        if yhi - ylo < need:
            ylo, yhi = 0.5 * (ylo + yhi) - 0.5 * need, 0.5 * (ylo + yhi) + 0.5 * need
        out.append((ylo, yhi))
    return out


def _tiers_count(spec: SheetSpec, side: str, P) -> list[int]:
    dims = [d for d in spec.dims if d.axis == "z" and d.side == side]
    return _tiers(_z_paper_spans(dims, P)) if dims else []


def _scale_text(s: float) -> str:
    return f"{s:g}:1" if s >= 1 else f"1:{1 / s:g}"
