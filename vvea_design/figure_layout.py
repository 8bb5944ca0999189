"""Margins of the product's figures in inches, without ``tight_layout`` or a constrained layout.

Both layout engines lay every tick label, title and legend of the figure out once more before the
figure is drawn (a constrained layout even draws the whole figure twice at ``savefig``). The
figures' font sizes are fixed, so the room their labels need is known; only the width of the y tick
labels depends on the data, and :func:`ytick_label_width_in` measures it from the handful of label
strings alone.
"""

from __future__ import annotations

from functools import lru_cache

__all__ = ["tick_labels_in_view", "text_width_in", "ytick_label_width_in", "legend_width_in", "set_margins_in",
           "place_row_in", "tight_layout_once"]


@lru_cache(maxsize=1)
def _renderer():
    from matplotlib.backends.backend_agg import RendererAgg

    return RendererAgg(1, 1, 72)  # 72 dpi: widths come out in points


def tick_labels_in_view(axis, which: str = "major") -> list[str]:
    """The non-empty ``which`` ("major" or "minor") tick labels ``axis`` will draw in its current view, from
    its locator and formatter, without drawing.

    Parameters
    ----------
    axis : matplotlib.axis.Axis
        ``ax.xaxis`` or ``ax.yaxis``, its data and limits set.
    which : str
        "major" or "minor" (a log axis labels some of its minor ticks).

    Returns
    -------
    list of str
        The labels as drawn (count: one per labelled tick in view).
    """
    loc, fmt = ((axis.get_major_locator(), axis.get_major_formatter()) if which == "major"
                else (axis.get_minor_locator(), axis.get_minor_formatter()))
    lo, hi = sorted(axis.get_view_interval())
    tol = 1e-9 * max(abs(hi - lo), 1e-300)
    return [t for t in fmt.format_ticks([v for v in loc() if lo - tol <= v <= hi + tol]) if t]


def ytick_label_width_in(ax, minor: bool = False) -> float:
    """Width (inches) of the widest y tick label ``ax`` will draw, measured as drawn.

    Call it once the data and the limits are set (the limits are autoscaled here, as a draw would).

    Parameters
    ----------
    ax : matplotlib.axes.Axes
        Axes with the default (left) y tick labels.
    minor : bool
        Measure the minor tick labels too.

    Returns
    -------
    float
        Inches (the same unit as ``Figure.get_size_inches``); 0 when no label is drawn.
    """
    from matplotlib import rcParams

    ax.get_ylim()  # autoscale now, as a draw would
    width = 0.0
    for which in ("major", "minor") if minor else ("major",):
        kw = getattr(ax.yaxis, f"_{which}_tick_kw", {})  # the label size as tick_params set it
        size = kw.get("labelsize", rcParams["ytick.labelsize"])
        width = max([width, *(text_width_in(t, size) for t in tick_labels_in_view(ax.yaxis, which))])
    return width


def text_width_in(s: str, size) -> float:
    """Width (inches) of one line of text at font size ``size`` as a Text draws it (math text included), without drawing.

    Parameters
    ----------
    s : str
        The text (one line).
    size : float or str
        Font size in points, the same unit as matplotlib's ``fontsize`` (or a size name such as ``"small"``).

    Returns
    -------
    float
        Inches (the same unit as ``Figure.get_size_inches``); 0 for an empty string.
    """
    from matplotlib import cbook
    from matplotlib.font_manager import FontProperties

    if not s:
        return 0.0
    ismath = cbook.is_math_text(s)  # as a Text decides it
    text = s if ismath else s.replace(r"\$", "$")
    return _renderer().get_text_width_height_descent(text, FontProperties(size=size), ismath=ismath)[0] / 72.0


def set_margins_in(fig, left: float, bottom: float, right: float, top: float, wspace: float = 0.0,
                   hspace: float = 0.0) -> None:
    """``fig.subplots_adjust`` in inches: figure margins and the gaps between the panels of its grid.

    Parameters
    ----------
    fig : matplotlib.figure.Figure
        Figure whose first axes' grid is adjusted.
    left, bottom, right, top : float
        Margins, inches (the same unit as ``Figure.get_size_inches``).
    wspace, hspace : float
        Gaps between columns and between rows, inches (the same unit as the margins).
    """
    W, H = fig.get_size_inches()
    rows, cols = fig.axes[0].get_subplotspec().get_gridspec().get_geometry()
    aw = (W - left - right - (cols - 1) * wspace) / cols  # mean panel width and height, inches
    ah = (H - top - bottom - (rows - 1) * hspace) / rows
    fig.subplots_adjust(left=left / W, right=1 - right / W, bottom=bottom / H, top=1 - top / H,
                        wspace=wspace / aw, hspace=hspace / ah)


def legend_width_in(legend) -> float:
    """Width (inches) of ``legend`` as drawn (its entries laid out, nothing drawn).

    Parameters
    ----------
    legend : matplotlib.legend.Legend

    Returns
    -------
    float
        Inches (the same unit as ``Figure.get_size_inches``).
    """
    from matplotlib.backends.backend_agg import RendererAgg

    dpi = legend.figure.dpi
    return legend.get_window_extent(RendererAgg(1, 1, dpi)).width / dpi


def tight_layout_once(fig, **kwargs) -> None:
    """``fig.tight_layout(**kwargs)``, then drop the placeholder layout engine it leaves on the figure.

    With that engine in place (matplotlib 3.11), every ``savefig`` lays the figure out by drawing it once
    more before the real draw; without it the figure is drawn once, to the same pixels.

    Parameters
    ----------
    fig : matplotlib.figure.Figure
        The figure (its panels' positions are set; nothing is drawn to a file).
    **kwargs
        ``pad``, ``h_pad``, ``w_pad`` (font-size fractions) and ``rect`` (figure fraction), as ``tight_layout``.
    """
    fig.tight_layout(**kwargs)
    fig.set_layout_engine(None)


def place_row_in(fig, axes, left: float, right: float, bottom: float, top: float, gaps, ratios=None) -> list[float]:
    """Place a row of panels in inches: figure margins, the gap left of each panel after the first, width ratios.

    Parameters
    ----------
    fig : matplotlib.figure.Figure
        The figure of ``axes``.
    axes : sequence of matplotlib.axes.Axes
        The panels, left to right.
    left, right, bottom, top : float
        Figure margins, inches (the same unit as ``Figure.get_size_inches``).
    gaps : sequence of float
        Gap before each panel after the first, inches (the same unit); ``len(axes) - 1`` of them.
    ratios : sequence of float, optional
        Relative panel widths (dimensionless; equal by default).

    Returns
    -------
    list of float
        Left edge of each panel, inches from the figure's left edge (the same unit).
    """
    W, H = fig.get_size_inches()
    ratios = [1.0] * len(axes) if ratios is None else list(ratios)
    unit = (W - left - right - sum(gaps)) / sum(ratios)
    x, edges = left, []
    for ax, gap, r in zip(axes, [0.0, *gaps], ratios):
        x += gap
        ax.set_position([x / W, bottom / H, r * unit / W, (H - top - bottom) / H])
        edges.append(x)
        x += r * unit
    return edges
