"""Figures of the identification (Figs 10 and 11 of the paper) and of the diagnosis (residual maps, held-out error,
worst experiments).

Margins are set in inches from the fonts (``vvea_design.figure_layout``) instead of by a layout engine where
the labels' sizes are known; the figures draw into a given ``Figure`` or a new one and return it.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

from ..figure_layout import set_margins_in, text_width_in, tick_labels_in_view, tight_layout_once, ytick_label_width_in
from .effects import REGISTRY
from .fit_data import FitData
from .recordings import Recordings

if TYPE_CHECKING:
    from .report import Diagnosis, DiagnosisReport

__all__ = ["Fig11Example", "plot_fig10", "plot_fig11", "plot_residual_maps", "plot_heldout_steps", "plot_worst"]


# ------------------------------------------------------------------ identification: Figs 10 and 11
@dataclass(frozen=True)
class Fig11Example:
    """The experiment Fig. 11 draws, with its largest error and force."""

    experiment: str
    max_abs_error_N: float | None  #: largest |measurement − model| of the experiment, N
    max_force_N: float | None  #: largest |measured force|, N

    def to_dict(self) -> dict:
        """The example as JSON (``fig11`` of ``identification.json``).

        Returns
        -------
        dict
            ``experiment``, ``max_abs_error_N`` and ``max_force_N`` (N; None for an empty experiment).
        """
        return dict(experiment=self.experiment, max_abs_error_N=self.max_abs_error_N, max_force_N=self.max_force_N)


def plot_fig10(rec: Recordings, D: FitData, fmod: np.ndarray, p2_MPa: float, fig=None):
    """Fig. 10 for one charge pressure: measurement, model and error per valve (rows) and speed (columns).

    Error is measurement − model. Repeated test conditions are drawn in the
    same panel.

    Parameters
    ----------
    rec : Recordings
        The campaign (its ``experiments`` table, run order).
    D : FitData
        The fitted samples (force N, displacement mm).
    fmod : array
        Model force per sample of ``D`` (N).
    p2_MPa : float
        Charge pressure whose experiments are drawn (MPa).
    fig : matplotlib Figure, optional
        Figure to draw into (default: a new one sized to the grid).

    Returns
    -------
    matplotlib.figure.Figure
    """
    import matplotlib.pyplot as plt

    ex = rec.experiments.reset_index(drop=True)
    speeds = sorted(ex["speed_mm_s"].unique())
    valves = sorted(ex["valve_deg"].unique())
    sel = ex.index[ex["p2_MPa"] == p2_MPa]
    nr, nc = len(valves), len(speeds)
    if fig is None:
        fig = plt.figure(figsize=(2.9 * nc + 1.2, 1.75 * nr + 1.3))
    # Margins in inches, set once: the labels' sizes are fixed (7-9 pt), and the automatic
    # layout engines measure every tick label of the ~90 axes (it was ~80 % of the figure's time).
    W, H = fig.get_figwidth(), fig.get_figheight()
    fig.subplots_adjust(left=0.8 / W, right=1.0 - 0.62 / W, bottom=0.5 / H, top=1.0 - 1.0 / H,
                        wspace=0.5 / ((W - 1.42 - 0.5 * (nc - 1)) / nc), hspace=0.12 / ((H - 1.5 - 0.12 * (nr - 1)) / nr))
    # one x range for every panel, set rather than shared: a 90-axes shared group makes every
    # limit look-up walk the whole group
    axes = fig.subplots(nr, nc, squeeze=False)
    cell = {k: (valves.index(ex.loc[k, "valve_deg"]), speeds.index(ex.loc[k, "speed_mm_s"])) for k in sel}
    # the right-hand (error) axes, made before any data is drawn: a twin made after the shared x
    # axes hold data re-scales the whole shared group
    twins = {ij: axes[ij].twinx() for ij in sorted(set(cell.values()))}
    err_lim = 1.0
    for k in sel:
        a, b = D.bounds[k], D.bounds[k + 1]
        err_lim = max(err_lim, float(np.max(np.abs(D.y[a:b] - fmod[a:b]))) if b > a else 0.0)
    for k in sel:
        i, j = cell[k]
        a, b = D.bounds[k], D.bounds[k + 1]
        ax = axes[i, j]
        ax.plot(D.x[a:b], D.y[a:b], ".", ms=1.5, color="C0")
        ax.plot(D.x[a:b], fmod[a:b], "-", lw=0.9, color="k")
        twins[(i, j)].plot(D.x[a:b], D.y[a:b] - fmod[a:b], "-", lw=0.7, color="C3")
    for (i, j), tw in twins.items():
        tw.set_ylim(-1.1 * err_lim, 1.1 * err_lim)
        tw.tick_params(labelsize=7, colors="C3")
        if j != nc - 1:
            tw.set_yticklabels([])
        else:
            tw.set_ylabel("meas. − model [N]", fontsize=7, color="C3")
    for i, v in enumerate(valves):
        axes[i, 0].set_ylabel(f"γ = {v:g}°\nforce [N]", fontsize=8)
    for j, sp in enumerate(speeds):
        axes[0, j].set_title(f"ẋ = {sp:g} mm/s", fontsize=9)
        axes[-1, j].set_xlabel("displacement x [mm]", fontsize=8)
    xs = [D.x[D.bounds[k]:D.bounds[k + 1]] for k in sel if D.bounds[k + 1] > D.bounds[k]]
    if xs:
        lo, hi = min(float(v.min()) for v in xs), max(float(v.max()) for v in xs)
        pad = 0.05 * (hi - lo) or 0.5
        for ax in axes.flat:
            ax.set_xlim(lo - pad, hi + pad)
    for ax in axes[:-1].flat:
        ax.tick_params(labelbottom=False)
    for ax in axes.flat:
        ax.tick_params(labelsize=7)
        if not ax.lines:
            ax.text(0.5, 0.5, "not recorded", ha="center", va="center", transform=ax.transAxes, fontsize=7, color="0.5")
    handles = [
        plt.Line2D([], [], color="C0", marker=".", ls="", label="measurement"),
        plt.Line2D([], [], color="k", label="model eq. 14"),
        plt.Line2D([], [], color="C3", label="error = measurement − model (right axis)"),
    ]
    fig.suptitle(f"Fig. 10 — eq. 14 against the recordings at p2 = {p2_MPa:g} MPa ({len(sel)} experiments)",
                 fontsize=11, y=1.0 - 0.08 / H, va="top")
    fig.legend(handles=handles, loc="upper center", bbox_to_anchor=(0.5, 1.0 - 0.35 / H), ncol=3,
               fontsize=8, frameon=False)
    return fig


def plot_fig11(rec: Recordings, D: FitData, fmod: np.ndarray, fig=None):
    """Fig. 11: force over displacement of one slow experiment (lowest speed, middle pressure and valve).

    Repeated test conditions are fine (the first in run order is drawn).

    Parameters
    ----------
    rec : Recordings
        The campaign.
    D : FitData
        The fitted samples (force N, displacement mm).
    fmod : array
        Model force per sample of ``D`` (N).
    fig : matplotlib Figure, optional
        Figure to draw into.

    Returns
    -------
    fig : matplotlib.figure.Figure
    info : Fig11Example
        The experiment drawn, its largest |error| and largest |force| (N).
    """
    import matplotlib.pyplot as plt

    ex = rec.experiments.reset_index(drop=True)
    sel = ex[ex["speed_mm_s"] == ex["speed_mm_s"].min()]
    ps = sorted(sel["p2_MPa"].unique())
    sel = sel[sel["p2_MPa"] == ps[len(ps) // 2]]
    vs = sorted(sel["valve_deg"].unique())
    k = int(sel.index[sel["valve_deg"] == vs[len(vs) // 2]][0])
    r = ex.loc[k]
    a, b = D.bounds[k], D.bounds[k + 1]
    err = D.y[a:b] - fmod[a:b]
    if fig is None:
        fig = plt.figure(figsize=(6.5, 5.5))
    ax, axe = fig.subplots(2, 1, sharex=True, gridspec_kw={"height_ratios": [3, 1]})
    ax.plot(D.x[a:b], D.y[a:b], ".", ms=3, label="measurement")
    ax.plot(D.x[a:b], fmod[a:b], "-", color="k", label="model eq. 14")
    ax.set_ylabel("force [N] (+ = tension)")
    ax.set_title(f"{r['experiment']}: ẋ = {r['speed_mm_s']:g} mm/s, p2 = {r['p2_MPa']:g} MPa, γ = {r['valve_deg']:g}°",
                 fontsize=10)
    ax.legend()
    axe.plot(D.x[a:b], err, "-", color="C3")
    axe.axhline(0, color="0.6", lw=0.6)
    axe.set_ylabel("meas. − model [N]")
    axe.set_xlabel("displacement x [mm]")
    tight_layout_once(fig)
    info = Fig11Example(
        experiment=str(r["experiment"]),
        max_abs_error_N=float(np.abs(err).max()) if len(err) else None,
        max_force_N=float(np.abs(D.y[a:b]).max()) if len(err) else None,
    )
    return fig, info


# ------------------------------------------------------------------ diagnosis: residual maps, held-out error, worst experiments
def _in_view_log_locator(subs):
    """A log-axis LogLocator that returns only the ticks inside the view.

    matplotlib makes a Tick (two lines, two texts) for every location a locator returns and then draws only
    those in view; a plain LogLocator returns whole decades beyond both ends, about half of them never drawn.
    """
    from matplotlib.ticker import LogLocator

    class InView(LogLocator):
        def __call__(self):
            lo, hi = sorted(self.axis.get_view_interval())
            if not (lo > 0 and np.isfinite(hi)):
                return super().__call__()
            tol = 1e-9 * max(np.log10(hi / lo), 1e-12)  # matplotlib keeps ticks within ~1e-10 of the ends
            a, b = np.log10(lo) - tol, np.log10(hi) + tol
            return [v for v in super().__call__() if v > 0 and a <= np.log10(v) <= b]

    return InView(10.0, subs)


def _plain_log_ticks(ax) -> None:
    """Log axis with plain numbers (4, 6, 10, 20 rather than 4x10^0); ticks made only where drawn."""
    from matplotlib.ticker import FuncFormatter

    ax.yaxis.set_major_locator(_in_view_log_locator((1.0,)))
    ax.yaxis.set_minor_locator(_in_view_log_locator(None))
    fmt = FuncFormatter(lambda v, _: f"{v:g}")
    ax.yaxis.set_major_formatter(fmt)
    ax.yaxis.set_minor_formatter(FuncFormatter(lambda v, _: f"{v:g}" if f"{v:.1e}"[0] in "2468" or f"{v:.1e}"[0] == "5" else ""))


# Figure margins are set in inches from the fonts instead of by fig.tight_layout(): tight_layout draws every
# tick of every panel to measure it, and leaves a layout engine on the figure that makes savefig draw it twice.
# Only the strings that decide the margins are measured (tick labels in view, rotated bin labels), with the
# same paddings tight_layout uses (1.08 x the 10 pt font between a label and the figure edge or the next panel).
_PAD_PT = 10.8  # tight_layout's default pad
_TICK_PT = 3.5 + 3.5  # major tick length + tick-label pad
_LABELPAD_PT = 4.0
_TITLEPAD_PT = 6.0
_LINE = 1.07  # height of one line of text / font size (DejaVu Sans as matplotlib lays it out: 1.0 to 1.07)
_TITLE = 0.8  # a title's rise above its baseline (which sits _TITLEPAD_PT above the axes) / font size


def _rotated_h_pt(s: str, size: float, deg: float) -> float:
    """Vertical extent in points of a label rotated by ``deg`` degrees (its width from ``figure_layout``, no drawing)."""
    a = np.radians(deg)
    return 72.0 * text_width_in(s, size) * abs(np.sin(a)) + _LINE * size * abs(np.cos(a))


def _has_offset_text(ax) -> bool:
    """True if either axis of ``ax`` will draw an offset or scientific-notation text (margins then need tight_layout)."""
    for axis in (ax.xaxis, ax.yaxis):
        for which in ("major", "minor"):
            tick_labels_in_view(axis, which)  # formatting the ticks in view sets the formatter's offset
            fmt = axis.get_major_formatter() if which == "major" else axis.get_minor_formatter()
            if hasattr(fmt, "get_offset") and fmt.get_offset():
                return True
    return False


def _ytick_w_pt(ax) -> float:
    """Room in points left of the spine for the y tick labels (tick, pad, widest major or minor label)."""
    return _TICK_PT + 72.0 * ytick_label_width_in(ax, minor=True)


def plot_residual_maps(r: DiagnosisReport, fig=None):
    """Residual RMS per bin of each feature, eq. 14 against the final model, with the noise floor.

    Parameters
    ----------
    r : DiagnosisReport
        The diagnosis report (its residual maps, RMS in N, and noise floor, N).
    fig : matplotlib.figure.Figure, optional
        Figure to draw into (default: a new 15 x 7.5 in one).

    Returns
    -------
    matplotlib.figure.Figure
        Seven panels (one per feature, RMS of measurement − model in N on a log axis) and the legend.
    """
    import matplotlib.pyplot as plt

    noise = r.noise_floor_N
    fig = fig or plt.figure(figsize=(15, 7.5))
    axes = fig.subplots(2, 4)
    for ax, fb, ff in zip(axes.flat, r.where_baseline, r.where_final):
        lab = [b.bin for b in fb.bins]
        xi = np.arange(len(lab))
        ax.bar(xi - 0.2, [b.rms_N for b in fb.bins], 0.4, color="C3")
        ax.bar(xi + 0.2, [b.rms_N for b in ff.bins], 0.4, color="C2")
        ax.axhline(noise, color="k", ls="--", lw=0.8)
        ax.set_xticks(xi, lab, rotation=45, fontsize=7)
        ax.set_title(f"{fb.name}" + (f" [{fb.unit}]" if fb.unit else ""), fontsize=9, y=1.0)  # fixed: ticks are below
        ax.set_ylabel("RMS of measurement − model [N]", fontsize=7)
        ax.set_yscale("log")
        _plain_log_ticks(ax)
        ax.tick_params(labelsize=7, which="both")
    ax = axes.flat[-1]
    ax.axis("off")
    from matplotlib.patches import Patch
    from matplotlib.lines import Line2D

    ax.legend(handles=[Patch(color="C3", label="eq. 14"), Patch(color="C2", label="final model"),
                       Line2D([], [], color="k", ls="--", lw=0.8, label=f"noise floor {noise:.1f} N")],
              loc="upper left", fontsize=8, frameon=False)
    acc = [e.id for e in r.accepted]
    h = r.heldout
    ax.text(0, 0.55, "accepted: " + (", ".join(acc) or "none"), fontsize=8, transform=ax.transAxes, wrap=True)
    if h.assessable:
        ax.text(0, 0.42, f"held-out RMS: {h.baseline_N:.1f} N -> {h.final_N:.1f} N", fontsize=8, transform=ax.transAxes)
    ax.text(0, 0.30, f"unexplained structure: {r.unexplained_structure}", fontsize=8, transform=ax.transAxes)
    fig.suptitle("Where the model and the recordings disagree: RMS of (measurement − model) per bin, before (eq. 14) and after")
    # margins in points (what tight_layout found, without drawing every tick): y tick labels + the 7 pt y label
    # left of each panel, the 45 degree bin labels below each row, the 9 pt titles and the 12 pt suptitle above
    ylab = _LINE * 7 + _LABELPAD_PT
    ywid = [_ytick_w_pt(ax) + ylab for ax in axes.flat[:-1]]
    xlab = [max((_rotated_h_pt(b.bin, 7, 45) for fb in r.where_baseline[4 * i:4 * i + 4] for b in fb.bins), default=0.0) + _TICK_PT
            for i in range(2)]
    title = _TITLEPAD_PT + _TITLE * 9
    pt = 1 / 72  # inches per point
    set_margins_in(fig, left=pt * (_PAD_PT + max(ywid[0], ywid[4] if len(ywid) > 4 else 0.0)), right=pt * _PAD_PT,
                   top=pt * (_PAD_PT + title + _PAD_PT + _LINE * 12), bottom=pt * (_PAD_PT + xlab[1]),
                   wspace=pt * (_PAD_PT + max(ywid[1:4] + ywid[5:])), hspace=pt * (_PAD_PT + xlab[0] + title))
    return fig


def plot_heldout_steps(r: DiagnosisReport, fig=None):
    """Held-out RMS after each accepted term (fitted without those experiments), against the noise floor.

    Parameters
    ----------
    r : DiagnosisReport
        The diagnosis report (held-out RMS per step and noise floor, N).
    fig : matplotlib.figure.Figure, optional
        Figure to draw into (default: a new 7 x 4.2 in one).

    Returns
    -------
    matplotlib.figure.Figure
        One bar per step (held-out RMS of measurement − model, N, log axis), the noise floor and twice it.
    """
    import matplotlib.pyplot as plt

    fig = fig or plt.figure(figsize=(7, 4.2))
    ax = fig.subplots()
    steps = [s for s in r.heldout.steps if s.rmse_N is not None]
    if steps:
        xi = np.arange(len(steps))
        cols = ["C3"] + ["C0" if s.effects[-1] in REGISTRY and REGISTRY[s.effects[-1]].catalogue else "C1" for s in steps[1:]]
        ax.bar(xi, [s.rmse_N for s in steps], color=cols)
        for x, s in zip(xi, steps):
            ax.text(x, s.rmse_N, f"{s.rmse_N:.1f}", ha="center", va="bottom", fontsize=8)
        ax.set_xticks(xi, [s.label for s in steps], rotation=20, ha="right", fontsize=8)
        ax.set_yscale("log")
        _plain_log_ticks(ax)
        top = max(s.rmse_N for s in steps)
        ax.set_ylim(min(min(s.rmse_N for s in steps), r.noise_floor_N) * 0.6, top * 2.2)
    else:
        ax.text(0.5, 0.5, "held-out error not assessable\n(too few experiments)", ha="center", va="center", transform=ax.transAxes)
    ax.axhline(r.noise_floor_N, color="k", ls="--", lw=0.8)
    ax.axhline(2 * r.noise_floor_N, color="k", ls=":", lw=0.8)
    from matplotlib.patches import Patch
    from matplotlib.lines import Line2D

    ax.legend(handles=[Patch(color="C3", label="eq. 14"), Patch(color="C0", label="+ catalogue effect"), Patch(color="C1", label="+ discovered term"),
                       Line2D([], [], color="k", ls="--", lw=0.8, label="noise floor"), Line2D([], [], color="k", ls=":", lw=0.8, label="2 x noise floor")],
              fontsize=7, loc="upper right", ncol=2)
    ax.set_ylabel("held-out RMS of measurement − model [N]")
    ax.set_title("Held-out error as terms are added (experiments not used in selection or fit)", fontsize=9)
    tight_layout_once(fig)  # the rotated step names may reach into the left margin: let tight_layout measure them
    return fig


def plot_worst(diag: Diagnosis, fig=None):
    """The worst experiments of eq. 14: force and residual (measurement − model) against x.

    Parameters
    ----------
    diag : Diagnosis
        The diagnosis (its data, baseline and final fits, and the report's worst experiments).
    fig : matplotlib.figure.Figure, optional
        Figure to draw into (default: a new one, 4 in wide per experiment).

    Returns
    -------
    matplotlib.figure.Figure
        Per experiment (up to four): force (N) against displacement (mm), measured, eq. 14 and final model,
        and below it the residual (N).
    """
    import matplotlib.pyplot as plt

    D = diag.data
    fb, ff = diag.baseline.predict(D), diag.final.predict(D)
    worst = diag.report.worst_experiments[:4]
    fig = fig or plt.figure(figsize=(4 * max(len(worst), 1), 6))
    axes = fig.subplots(2, max(len(worst), 1), squeeze=False, gridspec_kw={"height_ratios": [2, 1]})
    titles = []
    for j, w in enumerate(worst):
        e = w.exp_index
        a, b = D.bounds[e], D.bounds[e + 1]
        ax, axr = axes[0, j], axes[1, j]
        ax.plot(D.x[a:b], D.y[a:b], ".", ms=2, color="0.4", label="measured")
        ax.plot(D.x[a:b], fb[a:b], "-", color="C3", lw=1, label="eq. 14")
        ax.plot(D.x[a:b], ff[a:b], "-", color="C2", lw=1, label="final model")
        titles.append((ax, f"{w.experiment}: p2 {w.p2_MPa:g} MPa, γ {w.valve_deg:g}°, {w.speed_mm_s:g} mm/s"))
        axr.plot(D.x[a:b], D.y[a:b] - fb[a:b], color="C3", lw=0.8)
        axr.plot(D.x[a:b], D.y[a:b] - ff[a:b], color="C2", lw=0.8)
        axr.axhline(0, color="k", lw=0.5)
        axr.set_xlabel("displacement x [mm]")
        if j == 0:
            ax.set_ylabel("force (+ = tension) [N]")
            axr.set_ylabel("measurement − model [N]")
            ax.legend(fontsize=7)
    fig.suptitle("Worst experiments of eq. 14, before and after the accepted terms")
    if any(_has_offset_text(a) for a in axes.flat):  # an offset text above a panel: let tight_layout place it
        for ax, t in titles:
            ax.set_title(t, fontsize=8)
        tight_layout_once(fig)
        return fig
    for ax, t in titles:
        ax.set_title(t, fontsize=8, y=1.0)  # fixed: ticks are below and there is no offset text
    # margins in points (what tight_layout found, without drawing every tick): the 10 pt y tick labels of each
    # column (+ the y labels left of the first), 10 pt x tick labels below each row (+ the x label under the
    # second), the 8 pt titles and the 12 pt suptitle above
    line = _LINE * 10
    yw = [max(_ytick_w_pt(axes[0, j]), _ytick_w_pt(axes[1, j])) for j in range(axes.shape[1])]
    left = _PAD_PT + yw[0] + _LABELPAD_PT + line
    top = _PAD_PT + (_TITLEPAD_PT + _TITLE * 8 if titles else 0.0) + _PAD_PT + _LINE * 12
    hgap = _PAD_PT + _TICK_PT + line
    bottom = _PAD_PT + _TICK_PT + line + _LABELPAD_PT + line
    pt = 1 / 72  # inches per point
    set_margins_in(fig, left=pt * left, right=pt * _PAD_PT, top=pt * top, bottom=pt * bottom,
                   wspace=pt * (_PAD_PT + max(yw[1:], default=0.0)), hspace=pt * hgap)
    return fig
