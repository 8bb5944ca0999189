"""Margins of the product's figures in inches, without ``tight_layout`` or a constrained layout.

Both layout engines lay every tick label, title and legend of the figure out once more before the
figure is drawn (a constrained layout even draws the whole figure twice at ``savefig``). The
figures' font sizes are fixed, so the room their labels need is known; only the width of the y tick
labels depends on the data, and :func:`ytick_label_width_in` measures it from the handful of label
strings alone.
"""

from __future__ import annotations

from functools import lru_cache

__all__ = ["ytick_label_width_in", "legend_width_in", "set_margins_in"]


@lru_cache(maxsize=1)
def _renderer():
    from matplotlib.backends.backend_agg import RendererAgg

    return RendererAgg(1, 1, 72)  # 72 dpi: widths come out in points


def ytick_label_width_in(ax) -> float:
    """Width (inches) of the widest major y tick label ``ax`` will draw, measured as drawn.

    Call it once the data and the limits are set (the limits are autoscaled here, as a draw would).

    Parameters
    ----------
    ax : matplotlib.axes.Axes
        Axes with the default (left) y tick labels.

    Returns
    -------
    float
        Inches (the same unit as ``Figure.get_size_inches``); 0 when no label is drawn.
    """
    from matplotlib import cbook, rcParams
    from matplotlib.font_manager import FontProperties

    axis = ax.yaxis
    lo, hi = sorted(ax.get_ylim())
    locs = axis.get_majorticklocs()
    labels = axis.get_major_formatter().format_ticks(locs)
    size = getattr(axis, "_major_tick_kw", {}).get("labelsize", rcParams["ytick.labelsize"])  # tick_params
    prop = FontProperties(size=size)
    tol = 1e-9 * max(abs(hi - lo), 1e-300)
    r = _renderer()
    width = 0.0
    for loc, s in zip(locs, labels):
        if s and lo - tol <= loc <= hi + tol:
            ismath = cbook.is_math_text(s)  # as a tick label (a Text) decides it
            text = s if ismath else s.replace(r"\$", "$")
            width = max(width, r.get_text_width_height_descent(text, prop, ismath=ismath)[0])
    return width / 72.0


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
