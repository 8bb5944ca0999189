"""Margins of the product's figures in inches, without ``tight_layout`` or a constrained layout.

Both layout engines lay every tick label, title and legend of the figure out once more before the
figure is drawn (a constrained layout even draws the whole figure twice at ``savefig``). The
figures' font sizes are fixed, so the room their labels need is known; only the width of the y tick
labels depends on the data, and :func:`ytick_label_width_in` measures it from the handful of label
strings alone.
"""

from __future__ import annotations

from functools import lru_cache

__all__ = ["text_width_in", "ytick_label_width_in", "legend_width_in", "set_margins_in", "tight_layout_once"]


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
    from matplotlib import rcParams

    axis = ax.yaxis
    lo, hi = sorted(ax.get_ylim())
    locs = axis.get_majorticklocs()
    labels = axis.get_major_formatter().format_ticks(locs)
    size = getattr(axis, "_major_tick_kw", {}).get("labelsize", rcParams["ytick.labelsize"])  # tick_params
    tol = 1e-9 * max(abs(hi - lo), 1e-300)
    return max((text_width_in(s, size) for loc, s in zip(locs, labels) if s and lo - tol <= loc <= hi + tol),
               default=0.0)


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
