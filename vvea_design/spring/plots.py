"""Figures of the spring side: force curve, Pareto fronts, linearity maps.

Every plot function builds a :class:`matplotlib.figure.Figure` (no pyplot, no
backend switch: importing this module leaves the user's backend alone), draws
into the ``ax`` / ``fig`` given or a new one, and returns the Figure; the
caller saves it (:func:`save_figure` writes a byte-stable PNG).
"""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np
from matplotlib.figure import Figure

from ..figure_layout import set_margins_in, tight_layout_once, ytick_label_width_in
from ..palette import GAS_LAW_STYLES, LIMIT_COLOUR, OTHER_COLOURS, SETTING_COLOURS, gas_law, gas_law_label, part_colour
from .gas_spring import GasSpring

__all__ = ["plot_spring", "plot_pareto", "plot_linearity_map", "save_figure", "VARIABLE_LABELS"]

_META = {"Software": "vvea-design"}  # no timestamps in PNG metadata: byte-stable figures

#: Axis labels (with units and the scale used on the axis) of the decision variables.
VARIABLE_LABELS = {
    "piston_diameter_mm": ("piston diameter d_p [mm]", 1.0),
    "outer_diameter_mm": ("outer diameter D_o [mm]", 1.0),
    "V1_mm3": ("chamber-1 gas V1 [10³ mm³]", 1e-3),
    "V2_mm3": ("chamber-2 gas V2 [10³ mm³]", 1e-3),
    "V2_top_mm3": ("chamber-2 gas above the bulkhead V2_top [10³ mm³]", 1e-3),
}


def save_figure(fig: Figure, path: str | Path, dpi: int = 120) -> Path:
    """Write ``fig`` as a PNG (parent folders created; no timestamp metadata) and return the path.

    A figure made with pyplot is closed after saving.

    Parameters
    ----------
    fig : matplotlib.figure.Figure
        The figure to write.
    path : str or Path
        Where to write the PNG.
    dpi : int
        Resolution, dots per inch.

    Returns
    -------
    Path
        ``path``.
    """
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(path, dpi=dpi, metadata=_META)
    plt = sys.modules.get("matplotlib.pyplot")  # not imported: the figure cannot be one of pyplot's
    if plt is not None:  # a figure made with pyplot would otherwise stay open
        plt.close(fig)
    return path


def _axes(ax, figsize, nrows=1, ncols=1):
    if ax is not None:
        return ax.figure, ax
    fig = Figure(figsize=figsize)
    return fig, fig.subplots(nrows, ncols)


#: Line styles and grey levels of the recharged curves, in order (none is a gas law's style).
_RECHARGE_STYLES = ((0, (6, 2)), (0, (1, 1.2)), (0, (8, 2, 1, 2)), (0, (3, 1.5, 1, 1.5, 1, 1.5)))
_RECHARGE_GREYS = ("0.25", "0.45", "0.6", "0.35")


def _own_charge(spring: GasSpring, p2_MPa: float) -> bool:
    """``p2_MPa`` is the spring's own charge (its recharged curve is the nominal one)."""
    return abs(p2_MPa - spring.p2_MPa) <= 1e-9 * max(1.0, abs(p2_MPa))


def _recharged(ax, spring: GasSpring, x, charges_MPa) -> None:
    """Draw the spring recharged to each p2 but its own (grey, each its own line style, labelled at its end)."""
    k = 0
    for p2 in charges_MPa:
        if _own_charge(spring, p2):
            continue
        F = spring.with_pressures(p2).force_N(x)
        ls, grey = _RECHARGE_STYLES[k % len(_RECHARGE_STYLES)], _RECHARGE_GREYS[k % len(_RECHARGE_GREYS)]
        ax.plot(x, F, lw=1.3, color=grey, ls=ls,
                label=f"recharged p2 = {p2:g} MPa, {gas_law_label(spring.n_polytropic)}")
        ax.annotate(f"p2 = {p2:g} MPa", (x[-1], F[-1]), xytext=(-3, 4), textcoords="offset points", ha="right",
                    va="bottom", fontsize=7, color=grey)
        k += 1


def plot_spring(spring: GasSpring, title: str = "", extra_charges_MPa=(), *, fig: Figure | None = None,
                adiabatic: bool = True, layout: str | None = None) -> Figure:
    """Force–displacement with its least-squares line, the deviation, stiffness and pressures.

    Four panels into ``fig`` (a new Figure by default). With ``adiabatic``
    the same charged spring compressed at n = 1.4 is drawn dashed next to the
    nominal curve. Linearity numbers are the exact (continuous) metric. Colours
    and line styles come from :mod:`vvea_design.palette`: one per gas law
    (isothermal solid, adiabatic dashed) and, for the pressures, one per chamber
    (chamber 1 blue, chamber 2 red, as in the CAD renders).

    Parameters
    ----------
    spring : GasSpring
        The charged spring (mm², mm³, MPa, travel mm).
    title : str
        Figure title; empty: the layout (when given), the linearity error, the gas law and p2.
    extra_charges_MPa : sequence of float
        Further p2 charges (MPa) drawn in grey on the force panel (p1 from eq. 6 each), each in its own line
        style and labelled at its end; a charge equal to the spring's own is not drawn again (the legend says so).
    fig : matplotlib.figure.Figure or None
        Figure to draw into (it must be empty); None: a new 10.5 × 7.5 in Figure.
    adiabatic : bool
        Also draw the same charged spring at n = 1.4 (dashed) when its own exponent is not 1.4.
    layout : str or None
        The design's layout (``"bulkhead"``, ...), named in the default title.

    Returns
    -------
    matplotlib.figure.Figure
        Four panels: force (N) with least-squares lines, deviation (N), local stiffness (N/mm) and
        chamber pressures (MPa), over x (mm).
    """
    fig = fig or Figure(figsize=(10.5, 7.5))
    axes = fig.subplots(2, 2)
    x = spring.x_mm(401)
    cases = [spring]
    if adiabatic and spring.n_polytropic != 1.4:
        cases.append(spring.with_polytropic(1.4))
    lin0 = spring.linearity()
    same = [p2 for p2 in extra_charges_MPa if _own_charge(spring, p2)]
    for s in cases:
        r = s.linearity()
        k, b = float(r.mean_stiffness_N_per_mm), float(r.intercept_N)
        F = s.force_N(x)
        lab = gas_law_label(s.n_polytropic)
        st = GAS_LAW_STYLES[gas_law(s.n_polytropic)]
        color, ls = st["color"], st["ls"]
        own = f" (charge p2 = {same[0]:g} MPa)" if same and s is spring else ""
        axes[0, 0].plot(x, F, ls=ls, color=color, lw=2,
                        label=f"F(x), {lab}: {100 * float(r.linearity_error):.2f} %{own}")
        axes[0, 0].plot(x, k * x + b, ":", color="k", lw=1)
        axes[0, 1].plot(x, F - (k * x + b), ls=ls, color=color,
                        label=f"{lab}: max {float(r.max_deviation_N):.1f} N = {100 * float(r.linearity_error):.2f} % of span")
        axes[1, 0].plot(x, s.stiffness_N_per_mm(x), ls=ls, color=color, label=f"{lab}, mean {k:.1f} N/mm")
        P1, P2 = s.pressures_MPa(x)
        axes[1, 1].plot(x, P1, ls=ls, color=part_colour("gas_chamber_1"), label=f"chamber 1 (expands), {lab}")
        axes[1, 1].plot(x, P2, ls=ls, color=part_colour("gas_chamber_2"), label=f"chamber 2 (compressed), {lab}")
    _recharged(axes[0, 0], spring, x, extra_charges_MPa)
    axes[0, 0].set(xlabel="displacement x [mm] (extension > 0)", ylabel="force F [N] (tension > 0)")
    axes[0, 0].set_title("force–displacement (dotted: least-squares lines)", y=1.0)
    axes[0, 1].axhline(0, color="k", lw=0.5)
    axes[0, 1].set(xlabel="displacement x [mm]", ylabel="F − least-squares line [N]")
    axes[1, 0].set(xlabel="displacement x [mm]", ylabel="local stiffness dF/dx [N/mm]")
    axes[1, 1].set(xlabel="displacement x [mm]", ylabel="absolute pressure [MPa]")
    # titles at y = 1 given, not left to the draw to place (it would lay out the y tick labels once more to
    # look for an offset text under them; these axes have none)
    axes[0, 1].set_title("deviation from the line", y=1.0)
    axes[1, 0].set_title("local stiffness", y=1.0)
    axes[1, 1].set_title("chamber pressures", y=1.0)
    for ax in axes.flat:
        ax.grid(alpha=0.3)
        ax.legend(fontsize=7)
    head = f"gas spring, {layout} layout" if layout else "gas spring"
    fig.suptitle(title or f"{head}: linearity error {100 * float(lin0.linearity_error):.2f} % "
                          f"({gas_law(spring.n_polytropic)}, n = {spring.n_polytropic:g}; p2 = {spring.p2_MPa:.2f} MPa)")
    # margins in inches as tight_layout set them, without its extra layout pass: fixed room for the titles
    # and labels, and, left of each column, the room of its widest y tick labels
    w = [max(ytick_label_width_in(ax) for ax in axes[:, c]) for c in range(2)]
    set_margins_in(fig, left=0.473 + w[0], bottom=0.585, right=0.15, top=0.683, wspace=0.468 + w[1], hspace=0.798)
    return fig


def plot_pareto(rows: list[dict], x_key: str, x_label: str, title: str = "", *, ax=None) -> Figure:
    """Best linearity against a swept requirement.

    Feasible optima are joined by a line; a requirement value no design meets
    is drawn as a red cross on a separate "infeasible" strip under the axis
    (its least-violating design has no meaningful linearity), labelled with
    the constraint it misses.

    Parameters
    ----------
    rows : list of dict
        Rows of :func:`vvea_design.spring.optimise.pareto_front`: each with ``x_key``,
        ``feasible``, ``linearity_error`` (fraction) and, when infeasible, ``binding`` or ``error``.
    x_key : str
        Row key of the swept requirement (e.g. ``max_mass_g``); its unit is the one in the key.
    x_label : str
        Label of the x axis, with its unit.
    title : str
        Axes title; empty: "Pareto front".
    ax : matplotlib.axes.Axes or None
        Axes to draw into; None: a new 7.5 × 4.8 in Figure.

    Returns
    -------
    matplotlib.figure.Figure
        The figure holding the axes; best linearity error in % on the y axis.
    """
    own = ax is None  # the figure is ours: tight_layout without the engine it leaves (else the caller's layout)
    fig, ax = _axes(ax, (7.5, 4.8))
    xs = np.array([r[x_key] for r in rows], dtype=float)
    feas = np.array([bool(r.get("feasible")) for r in rows])
    ys = np.array([100 * float(r.get("linearity_error", np.nan)) if f else np.nan for r, f in zip(rows, feas)])
    order = np.argsort(xs)
    ax.plot(xs[order][feas[order]], ys[order][feas[order]], "o-", color=SETTING_COLOURS["design"],
            label="best feasible design")
    if (~feas).any():
        trans = ax.get_xaxis_transform()  # x in data, y in axes fraction
        ax.plot(xs[~feas], np.full((~feas).sum(), 0.04), "x", color=LIMIT_COLOUR, ms=10, mew=2, transform=trans,
                clip_on=False, label="no feasible design (misses: see label)")
        for r, xv in zip([r for r, f in zip(rows, feas) if not f], xs[~feas]):
            miss = r.get("binding") or r.get("error", "")
            ax.annotate(str(miss).split(",")[0][:28], (xv, 0.04), xycoords=trans, textcoords="offset points",
                        xytext=(0, 8), ha="center", fontsize=7, color=LIMIT_COLOUR)
    if np.isfinite(ys).any():
        ax.set_ylim(0.0, 1.1 * np.nanmax(ys))  # linearity >= 0; the infeasible strip sits at the bottom
    ax.set(xlabel=x_label, ylabel="best linearity error [%]", title=title or "Pareto front")
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8, loc="upper left")
    if own:
        tight_layout_once(fig)
    else:  # the caller's figure: its layout is theirs
        fig.tight_layout()
    return fig


def plot_linearity_map(m: dict, optimum: tuple[float, float] | None = None, *, ax=None) -> Figure:
    """Filled contours of linearity (%) over two variables; infeasible region hatched, the optimum starred.

    Axes are labelled with names and units (volumes in 10³ mm³); the optimum
    marker is drawn unclipped, so it shows even on the edge of the map.

    Parameters
    ----------
    m : dict
        A map of :func:`vvea_design.spring.optimise.linearity_map`: ``var_x``, ``var_y`` (decision
        variable names, unit in the name), ``x``, ``y`` (axes), ``linearity`` (fraction, grid
        ``[iy, ix]``), ``feasible`` (bool grid) and optionally ``margins`` (constraint name ->
        margin grid, dimensionless; each zero line is drawn where it crosses the map).
    optimum : tuple of float or None
        ``(x, y)`` of the optimum in the variables' own units (mm, mm³); None: no marker.
    ax : matplotlib.axes.Axes or None
        Axes to draw into; None: a new 8.2 × 6.0 in Figure.

    Returns
    -------
    matplotlib.figure.Figure
        The figure holding the map and its colour bar (linearity error in %).
    """
    from matplotlib.lines import Line2D
    from matplotlib.ticker import MaxNLocator

    own = ax is None  # the figure is ours: its margins are set here (else tight_layout, as always)
    fig, ax = _axes(ax, (8.2, 6.0))
    lx, sx = VARIABLE_LABELS.get(m["var_x"], (m["var_x"], 1.0))
    ly, sy = VARIABLE_LABELS.get(m["var_y"], (m["var_y"], 1.0))
    X, Y = np.meshgrid(np.asarray(m["x"]) * sx, np.asarray(m["y"]) * sy)
    lin = 100 * np.asarray(m["linearity"], dtype=float)
    finite = lin[np.isfinite(lin)]
    lo = float(finite.min()) if finite.size else 0.0
    top = float(np.nanpercentile(finite, 90)) if finite.size else 10.0
    levels = MaxNLocator(nbins=24).tick_values(lo, max(top, lo + 1e-3))
    cs = ax.contourf(X, Y, np.clip(lin, levels[0], levels[-1]), levels=levels, cmap="viridis_r", extend="max")
    fig.colorbar(cs, ax=ax, label="linearity error [%]")
    infeas = (~np.asarray(m["feasible"], dtype=bool)).astype(float)
    ax.contourf(X, Y, infeas, levels=[0.5, 1.5], colors="none", hatches=["///"], alpha=0.3)
    # where each constraint binds: its zero-margin line, labelled, on the side it is violated the hatching
    # neutral and "other" colours: red is the design's (the optimum's star), no setting's colour is a constraint's
    styles = [("w", "-"), ("k", "--"), (OTHER_COLOURS[3], "-."), (OTHER_COLOURS[2], ":"), ("w", ":"), ("k", "-.")]
    handles = []
    k = 0
    for name, grid in (m.get("margins") or {}).items():
        g = np.asarray(grid, dtype=float)
        if not (np.nanmin(g) < 0 < np.nanmax(g)):
            continue
        col, ls = styles[k % len(styles)]
        ax.contour(X, Y, g, levels=[0.0], colors=col, linewidths=1.8, linestyles=ls)
        handles.append(Line2D([], [], color=col, ls=ls, lw=1.8, label=f"{name.replace('_', ' ')} binds"))
        k += 1
    if optimum is not None:
        handles += ax.plot(optimum[0] * sx, optimum[1] * sy, "*", color=SETTING_COLOURS["design"], ms=16, mec="w",
                           mew=1.0, clip_on=False, zorder=10,
                           label="optimum")
    if handles:
        leg = ax.legend(handles=handles, loc="upper left", fontsize=7, framealpha=0.9)
        leg.get_frame().set_facecolor("0.85")
    ax.set_xmargin(0.03)
    ax.set_ymargin(0.03)
    ax.set(xlabel=lx, ylabel=ly)
    ax.set_title("linearity over two design variables, the others at the optimum\n"
                 "(hatched: violates a requirement; lines: where each one binds)", y=1.0)
    if own:  # margins in inches as tight_layout set them, without its extra layout pass (the colour bar's
        # labels fit in its own slot): fixed room for the title and labels, the y tick labels' room measured
        set_margins_in(fig, left=0.462 + ytick_label_width_in(ax), bottom=0.585, right=0.15, top=0.583)
    else:  # the caller's figure: its layout is theirs
        fig.tight_layout()
    return fig
