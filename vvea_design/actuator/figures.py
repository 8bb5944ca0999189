"""Figures of the actuator studies: Fig. 13 (best setting map), Fig. 12-like trajectory,
Fig. 14 (safety) and the design comparison map.

Every function builds a :class:`matplotlib.figure.Figure` without pyplot (so
nothing here touches the user's backend), draws into ``ax=``/``fig=`` when
given, and returns the Figure; the caller saves it (``fig.savefig(path)``).
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np
from matplotlib import colormaps
from matplotlib.colors import TwoSlopeNorm, to_rgb
from matplotlib.figure import Figure
from matplotlib.patches import Patch

from ..figure_layout import legend_width_in, set_margins_in, ytick_label_width_in
from ..palette import FIXED_DAMPING_STYLES, OTHER_COLOURS, SETTING_COLOURS, setting_colour
from .ocp import OcpResult, rest_to_rest_reference

# SETTING_COLOURS: the palette's (vvea_design.palette), named here as before
__all__ = ["SETTING_COLOURS", "plot_best_map", "plot_trajectory", "plot_safety", "plot_design_map",
           "plot_design_vs_sea", "plot_sensitivity"]


def _colour(name: str, i: int = 0) -> str:
    """A setting's colour; ``"<setting>, <run>"`` (e.g. ``"design, full charge"``) takes its setting's."""
    head = name.split(",")[0]
    return setting_colour(head if head in SETTING_COLOURS else name, i)


def _bool(series):
    return series.astype(str).str.lower().isin(["true", "1"])


def _usable(df):
    """Rows whose trajectory counts: solved, valid (95 % rule) and verified by re-simulation."""
    ok = _bool(df["valid"]) & _bool(df["success"])
    if "verified" in df:
        ok &= _bool(df["verified"])
    return ok


def plot_best_map(df, fig: Figure | None = None) -> Figure:
    """Fig. 13: best valid setting per (T, A); colour depth = gain over the next best; white = none valid.

    One panel per variable-damping setting, each against the constant-damping
    settings. A result counts when it is solved, valid (link reaches 95 % of A
    in both up-phases) and verified by re-simulation.

    Parameters
    ----------
    df
        ``results.csv`` as a pandas DataFrame.
    fig
        Figure to draw into (default: a new one sized to the panels).

    Returns
    -------
    Figure
    """
    df = df.copy()
    df["usable"] = _usable(df)
    settings = list(dict.fromkeys(df["setting"]))
    varset = [s for s in settings if (df.loc[df.setting == s, "D_max_Nms_per_rad"]
                                      > df.loc[df.setting == s, "D_min_Nms_per_rad"]).any()]
    consts = [s for s in settings if s not in varset]
    panels = varset or [None]
    if fig is None:
        fig = Figure(figsize=(8.0, 3.4 * len(panels)))
    axes = np.atleast_1d(fig.subplots(len(panels), 1, squeeze=False)[:, 0])
    A_vals = sorted(df["A_rad"].unique())
    T_vals = sorted(df["T_s"].unique())
    for ax, v in zip(axes, panels):
        group = consts + ([v] if v else [])
        cols = {s: _colour(s, i) for i, s in enumerate(group)}
        for (A, T), sub in df[df.setting.isin(group)].groupby(["A_rad", "T_s"]):
            sub = sub[sub["usable"]].sort_values("rmse")
            if sub.empty:
                ax.scatter(T, A, s=110, facecolor="white", edgecolor="0.6", linewidth=0.6)
                continue
            w = sub.iloc[0]
            gain = (sub.iloc[1]["rmse"] / w["rmse"] - 1.0) if len(sub) > 1 else 1.0
            depth = 0.25 + 0.75 * min(1.0, gain / 0.3)
            rgb = np.array(to_rgb(cols[w["setting"]]))
            ax.scatter(T, A, s=110, color=1 - depth * (1 - rgb), edgecolor="0.3", linewidth=0.4)
        ax.set_xlabel("period T (s)")
        ax.set_ylabel("amplitude A (rad)")
        ax.set_xticks(T_vals)
        ax.set_xticklabels([f"{t:g}" for t in T_vals], fontsize=7)
        ax.set_yticks(A_vals)
        ax.set_xlim(min(T_vals) - 0.06, max(T_vals) + 0.06)
        ax.set_ylim(min(A_vals) - 0.06, max(A_vals) + 0.06)
        title = " vs ".join(group)
        if v is not None:
            D = df.loc[df.setting == v, ["D_min_Nms_per_rad", "D_max_Nms_per_rad"]].iloc[0]
            title += f"  ({D.iloc[0]:.3g} ≤ D ≤ {D.iloc[1]:.3g} N m s/rad)"
        ax.set_title(title, fontsize=9, y=1.0)
        handles = [Patch(color=cols[s], label=s) for s in group] + [Patch(facecolor="white", edgecolor="0.6",
                                                                          label="no valid setting")]
        ax.legend(handles=handles, fontsize=7, loc="upper left", bbox_to_anchor=(1.01, 1.0))
    fig.suptitle("Best valid setting per case (deeper colour = bigger gain over the next best)", fontsize=9)
    # margins in inches as tight_layout set them, without its extra layout pass: fixed room for the titles and
    # labels; measured, the widest amplitude tick label (left) and the legend right of the panels
    W = fig.get_size_inches()[0]
    left = 0.456 + max(ytick_label_width_in(ax) for ax in axes)
    lw = max(legend_width_in(ax.get_legend()) for ax in axes)
    right = (0.2 + lw + 0.01 * (W - left)) / 1.01  # the legend starts 1 % of the panel width right of it
    set_margins_in(fig, left=left, bottom=0.543, right=right, top=0.633, hspace=0.736)
    return fig


def plot_trajectory(best: dict[str, OcpResult], A_rad: float, T_s: float, highlight: str | None = None,
                    fig: Figure | None = None) -> Figure:
    """Fig. 12-like plot: link angle vs reference, motor torque and damping of every setting.

    Parameters
    ----------
    best
        Optimal result per setting name (``None`` entries are skipped).
    A_rad, T_s
        Amplitude (rad) and period (s) of the case.
    highlight
        Setting drawn with a thicker line.
    fig
        Figure to draw into (3 rows).

    Returns
    -------
    Figure
    """
    own = fig is None
    if own:
        fig = Figure(figsize=(7.5, 7.5))
    axes = fig.subplots(3, 1, sharex=True)
    tt = np.linspace(0, 2 * T_s, 801)
    axes[0].plot(tt, rest_to_rest_reference(tt, A_rad, T_s), "k--", lw=1, label="q_des")
    for i, (name, r) in enumerate(best.items()):
        if r is None or not np.all(np.isfinite(r.q_rad)):
            continue
        lw = 2.0 if name == highlight else 1.1
        c = _colour(name, i)
        axes[0].plot(r.t_s, r.q_rad, lw=lw, color=c, label=f"{name} (rmse {r.extra['rmse_rad']:.4f} rad)")
        axes[1].step(r.t_s[:-1], r.tau_m_Nm, where="post", lw=lw, color=c, label=name)
        axes[2].plot(r.t_s, r.D_Nms_per_rad, lw=lw, color=c, label=name)
    axes[0].set_ylabel("link angle q (rad)")
    axes[1].set_ylabel("motor torque τ_m (N m)")
    axes[2].set_ylabel("damping D (N m s/rad)")
    axes[2].set_yscale("symlog", linthresh=10)
    axes[2].set_xlabel("time t (s)")
    # one legend for the three panels (one colour per setting in each), right of them: it covers no trace
    title = f"setting (thick: {highlight})" if highlight in best else "setting"
    leg = axes[0].legend(fontsize=7, loc="upper left", bbox_to_anchor=(1.02, 1.0), title=title, title_fontsize=7)
    for ax in axes:
        ax.grid(alpha=0.3)
    axes[1].set_ylim(-125, 140)
    axes[0].set_title(f"Rest-to-rest optimum, A = {A_rad:g} rad, T = {T_s:g} s", fontsize=9, y=1.0)
    lw = legend_width_in(leg)
    if own:  # the panels keep their width; the figure grows by the legend's
        fig.set_size_inches(7.5 + lw + 0.1, 7.5)
    # margins in inches as tight_layout set them, without its extra layout pass: fixed room for the title and
    # the labels, the room of the widest y tick labels (measured) and the legend right of the panels
    W = fig.get_size_inches()[0]
    left = 0.475 + max(ytick_label_width_in(ax) for ax in axes)
    set_margins_in(fig, left=left, bottom=0.585, right=(0.15 + lw + 0.02 * (W - left)) / 1.02, top=0.343,
                   hspace=0.2)
    return fig


def _safety_styles(names, base_setting: str) -> dict[str, tuple[str, object]]:
    """(colour, line style) of each torque-step case: a variable-damping case in its setting's colour, solid;
    a fixed-damping case dashed (then dash-dotted, dotted) in the palette's other colours, in order.

    A case named ``"<setting>, ..."`` belongs to that setting; any other to ``base_setting``.
    """
    out, k = {}, 0
    for name in names:
        head, sep, rest = name.partition(", ")
        setting = head if sep and head in SETTING_COLOURS else base_setting
        if (rest if sep else name).startswith("fixed D"):
            out[name] = (OTHER_COLOURS[k % len(OTHER_COLOURS)], FIXED_DAMPING_STYLES[k % len(FIXED_DAMPING_STYLES)])
            k += 1
        else:
            out[name] = (setting_colour(setting), "-")
    return out


def plot_safety(results: dict[str, OcpResult], tau_ref: float, zoom_s: float = 0.03,
                fig: Figure | None = None, base_setting: str = "VVEA") -> Figure:
    """Fig. 14: τ, τ_m and D over the horizon (left) and over the first ``zoom_s`` seconds (right).

    A variable-damping case is drawn solid in its setting's colour (:mod:`vvea_design.palette`), a
    fixed-damping case dashed in a colour of no setting.

    Parameters
    ----------
    results
        Torque-step result per case name (``"design, variable D"``, ``"fixed D 31"``, ...).
    tau_ref
        Step height (N m).
    zoom_s
        Width of the zoomed column (s).
    fig
        Figure to draw into (3 x 2 panels).
    base_setting
        Setting of the cases whose name does not start with a setting's (``"VVEA"``: the paper's study).

    Returns
    -------
    Figure
    """
    styles = _safety_styles(results, base_setting)
    if fig is None:
        fig = Figure(figsize=(11, 7))
    axes = fig.subplots(3, 2, sharex="col", gridspec_kw={"width_ratios": [1.4, 1]})
    for col, xmax in ((0, None), (1, zoom_s)):
        ax = axes[:, col]
        for name, r in results.items():
            c, ls = styles[name]
            lab = f"{name}: mean D {r.extra['mean_D_Nms_per_rad']:.1f}, t95 {r.extra['t95_s'] * 1e3:.1f} ms"
            ax[0].plot(r.t_s, r.tau_Nm, color=c, ls=ls, label=lab)
            ax[1].step(r.t_s[:-1], r.tau_m_Nm, where="post", color=c, ls=ls, label=name)
            ax[2].plot(r.t_s, r.D_Nms_per_rad, color=c, ls=ls, label=name)
        ax[0].axhline(tau_ref, color="k", ls="--", lw=0.8, label="τ_ref")
        ax[0].axhline(0.95 * tau_ref, color="0.5", ls=":", lw=0.8)
        for a in ax:
            a.grid(alpha=0.3)
            if xmax:
                a.set_xlim(0, xmax)
        ax[2].set_xlabel("time t (s)")
    axes[0, 0].set_ylabel("link torque τ (N m)")
    axes[1, 0].set_ylabel("motor torque τ_m (N m)")
    axes[2, 0].set_ylabel("damping D (N m s/rad)")
    axes[0, 0].legend(fontsize=7, loc="lower right")
    axes[2, 0].legend(fontsize=7)
    axes[0, 0].set_title(f"Optimal {tau_ref:g} N m torque step (paper Fig. 14)", fontsize=9, y=1.0)
    axes[0, 1].set_title(f"first {zoom_s * 1e3:g} ms", fontsize=9, y=1.0)
    # margins in inches as tight_layout set them, without its extra layout pass: fixed room for the titles,
    # the labels and the zoom's last time tick, and left of each column the room of its widest y tick labels
    w = [max(ytick_label_width_in(ax) for ax in axes[:, c]) for c in range(2)]
    set_margins_in(fig, left=0.466 + w[0], bottom=0.585, right=0.35, top=0.343, wspace=0.267 + w[1], hspace=0.2)
    return fig


def plot_design_map(df, design: str = "design", references: Sequence[str] | None = None,
                    fig: Figure | None = None) -> Figure:
    """The design against the other settings, case by case, and on average.

    Left: one cell per (T, A); colour = the design's rmse relative to the best
    valid other setting (green: the design tracks better), the number in %,
    and the name of that best other setting; grey cells = the design's
    trajectory is not valid or not verified (left out of every statistic).
    Right: each setting's mean rmse over the cases where every setting is valid.

    Parameters
    ----------
    df
        Results table (``results.csv`` columns) holding ``design`` and the references.
    design
        Name of the design's setting.
    references
        Settings to compare with (default: every other setting in ``df``).
    fig
        Figure to draw into (two panels).

    Returns
    -------
    Figure
    """
    df = df.copy()
    df["usable"] = _usable(df)
    refs = [s for s in dict.fromkeys(df["setting"]) if s != design] if references is None else list(references)
    A_vals = sorted(df["A_rad"].unique())
    T_vals = sorted(df["T_s"].unique())
    ok = df.pivot_table(index=["A_rad", "T_s"], columns="setting", values="usable", aggfunc="first").fillna(False)
    rmse = df.pivot_table(index=["A_rad", "T_s"], columns="setting", values="rmse", aggfunc="first")
    rel = np.full((len(A_vals), len(T_vals)), np.nan)
    who = np.full(rel.shape, "", dtype=object)
    for i, A in enumerate(A_vals):
        for j, T in enumerate(T_vals):
            if (A, T) not in ok.index or not bool(ok.loc[(A, T), design]):
                continue
            others = {s: rmse.loc[(A, T), s] for s in refs if bool(ok.loc[(A, T), s])}
            if not others:
                who[i, j] = "only valid"
                continue
            b = min(others, key=others.get)
            rel[i, j] = 100.0 * (rmse.loc[(A, T), design] / others[b] - 1.0)
            who[i, j] = b
    if fig is None:
        fig = Figure(figsize=(11, 4.6))
    ax, bx = fig.subplots(1, 2, gridspec_kw={"width_ratios": [1.7, 1]})
    lim = max(5.0, float(np.nanmax(np.abs(rel)))) if np.isfinite(rel).any() else 5.0
    cmap = colormaps["RdYlGn_r"].with_extremes(bad="0.85")
    im = ax.imshow(np.ma.masked_invalid(rel), origin="lower", cmap=cmap, aspect="auto",
                   norm=TwoSlopeNorm(vcenter=0.0, vmin=-lim, vmax=lim))
    for i in range(len(A_vals)):
        for j in range(len(T_vals)):
            if np.isfinite(rel[i, j]):
                ax.text(j, i, f"{rel[i, j]:+.1f} %\nvs {who[i, j]}", ha="center", va="center", fontsize=7)
            else:
                ax.text(j, i, "design\nnot valid" if who[i, j] == "" else who[i, j], ha="center", va="center",
                        fontsize=7, color="0.3")
    ax.set_xticks(range(len(T_vals)))
    ax.set_xticklabels([f"{t:g}" for t in T_vals])
    ax.set_yticks(range(len(A_vals)))
    ax.set_yticklabels([f"{a:g}" for a in A_vals])
    ax.set_xlabel("period T (s)")
    ax.set_ylabel("amplitude A (rad)")
    ax.set_title(f"{design} rmse vs the best valid of {', '.join(refs)}\n(negative = {design} tracks better)",
                 fontsize=9, y=1.0)
    cb = fig.colorbar(im, ax=ax, shrink=0.9)
    cb.set_label(f"rmse_{design} / rmse_best other − 1 (%)")
    names = [design] + refs
    all_ok = ok[names].all(axis=1) if set(names) <= set(ok.columns) else ok.iloc[:, 0] & False
    means = [float(rmse.loc[all_ok, s].mean()) if all_ok.any() else np.nan for s in names]
    y = np.arange(len(names))
    bx.barh(y, means, color=[_colour(s, i) for i, s in enumerate(names)])
    for k, m in enumerate(means):
        if np.isfinite(m):
            bx.text(m, k, f" {m:.4f}", va="center", fontsize=8)
    bx.set_yticks(y)
    bx.set_yticklabels(names)
    bx.invert_yaxis()
    bx.set_xlabel("mean rmse (rad)")
    bx.set_xlim(0, (np.nanmax(means) if np.isfinite(means).any() else 1.0) * 1.35)
    bx.set_title(f"mean over the {int(all_ok.sum())} of {len(ok)} cases\nwhere every setting is valid", fontsize=9, y=1.0)
    bx.grid(axis="x", alpha=0.3)
    # margins in inches as tight_layout set them, without its extra layout pass: fixed room for the titles and
    # labels; measured, the amplitude tick labels (left) and, between the panels, the colour bar's tick labels
    # and the setting names
    set_margins_in(fig, left=0.453 + ytick_label_width_in(ax), bottom=0.585, right=0.15, top=0.521,
                   wspace=-0.03 + ytick_label_width_in(cb.ax) + ytick_label_width_in(bx))
    return fig


def plot_design_vs_sea(df, runs: Sequence[tuple[str, str, str, float]], damping: str = "",
                       fig: Figure | None = None) -> Figure:
    """The designer's figure: rmse of the design over rmse of an SEA of the same stiffness, case by case.

    One panel per run (equal stiffness, full charge): a cell per (T, A) with ``rmse_design / rmse_SEA - 1`` in %
    (green: the design tracks better). Every case is drawn: a case where only the SEA is valid is a loss of the
    design (dark cell, "design not valid"), one where only the design is valid a win ("SEA not valid"), one
    where neither is valid a grey cell.

    Parameters
    ----------
    df
        Results table (``results.csv`` columns) holding every setting of the runs.
    runs
        Per run: ``(label, design setting, SEA setting, K in N m/rad)``.
    damping
        The damping range used, for the title (text).
    fig
        Figure to draw into (one panel per run).

    Returns
    -------
    Figure
    """
    df = df.copy()
    df["usable"] = _usable(df)
    A_vals = sorted(df["A_rad"].unique())
    T_vals = sorted(df["T_s"].unique())
    ok = df.pivot_table(index=["A_rad", "T_s"], columns="setting", values="usable", aggfunc="first").fillna(False)
    rmse = df.pivot_table(index=["A_rad", "T_s"], columns="setting", values="rmse", aggfunc="first")
    n = len(runs)
    if fig is None:
        fig = Figure(figsize=(5.0 * n + 1.4, 4.6))
    gs = fig.add_gridspec(1, n + 1, width_ratios=[1.0] * n + [0.05])
    axes = [fig.add_subplot(gs[0, k]) for k in range(n)]
    cax = fig.add_subplot(gs[0, n])
    rels, texts = [], []
    for label, dname, sname, K in runs:
        rel = np.full((len(A_vals), len(T_vals)), np.nan)
        text = np.full(rel.shape, "", dtype=object)
        for i, A in enumerate(A_vals):
            for j, T in enumerate(T_vals):
                d_ok = (A, T) in ok.index and bool(ok.loc[(A, T)].get(dname, False))
                s_ok = (A, T) in ok.index and bool(ok.loc[(A, T)].get(sname, False))
                if d_ok and s_ok:
                    rel[i, j] = 100.0 * (rmse.loc[(A, T), dname] / rmse.loc[(A, T), sname] - 1.0)
                    text[i, j] = f"{rel[i, j]:+.1f} %"
                else:
                    text[i, j] = ("design not valid\n(a loss)" if s_ok else "SEA not valid\n(a win)" if d_ok
                                  else "neither\nvalid")
        rels.append(rel)
        texts.append(text)
    finite = np.concatenate([r[np.isfinite(r)] for r in rels]) if rels else np.array([])
    lim = max(5.0, float(np.max(np.abs(finite)))) if finite.size else 5.0
    cmap = colormaps["RdYlGn_r"].with_extremes(bad="0.85")
    norm = TwoSlopeNorm(vcenter=0.0, vmin=-lim, vmax=lim)
    im = None
    for ax, (label, dname, sname, K), rel, text in zip(axes, runs, rels, texts):
        im = ax.imshow(np.ma.masked_invalid(rel), origin="lower", cmap=cmap, aspect="auto", norm=norm)
        wins = losses = 0
        for i in range(len(A_vals)):
            for j in range(len(T_vals)):
                t = text[i, j]
                if np.isfinite(rel[i, j]):
                    wins += rel[i, j] < -0.1
                    losses += rel[i, j] > 0.1
                    ax.text(j, i, t, ha="center", va="center", fontsize=8)
                else:
                    loss = t.startswith("design not valid")
                    wins += t.startswith("SEA not valid")
                    losses += loss
                    if loss:
                        ax.add_patch(_dark_cell(j, i))
                    ax.text(j, i, t, ha="center", va="center", fontsize=7, color="white" if loss else "0.25")
        ax.set_xticks(range(len(T_vals)))
        ax.set_xticklabels([f"{t:g}" for t in T_vals])
        ax.set_yticks(range(len(A_vals)))
        ax.set_yticklabels([f"{a:g}" for a in A_vals])
        ax.set_xlabel("period T (s)")
        ax.set_ylabel("amplitude A (rad)")
        ax.set_title(f"{label}: K = {K:.4g} N m/rad\n{dname} better in {wins}, worse in {losses} of "
                     f"{len(A_vals) * len(T_vals)} cases", fontsize=9, y=1.0)
    cb = fig.colorbar(im, cax=cax)
    cb.set_label("rmse design / rmse SEA (same K) − 1 (%)")
    fig.suptitle("The design against an SEA of the same stiffness (negative = the design tracks better)"
                 + (f"\n{damping}" if damping else ""), fontsize=9)
    # margins in inches: fixed room for the titles and labels; measured, the amplitude tick labels (left and
    # between the panels) and the colour bar's tick labels and label (right)
    yw = ytick_label_width_in(axes[0])
    W = fig.get_size_inches()[0]
    set_margins_in(fig, left=0.453 + yw, bottom=0.585, right=0.45 + ytick_label_width_in(cax), top=1.0,
                   wspace=0.5 + yw)
    last, bar = axes[-1].get_position(), cax.get_position()
    cax.set_position([last.x1 + 0.15 / W, bar.y0, bar.width, bar.height])  # the bar close to the last panel
    return fig


def _dark_cell(j: float, i: float):
    """A dark cell (the design not valid while the SEA is: a loss), centred on column ``j``, row ``i``."""
    from matplotlib.patches import Rectangle

    return Rectangle((j - 0.5, i - 0.5), 1.0, 1.0, facecolor="0.3", edgecolor="none", zorder=0.5)


def plot_sensitivity(study, fig: Figure | None = None) -> Figure:
    """Which property buys tracking: the design's mean rmse over an SEA's of the same K, as D_min, D_max, K move.

    One panel per property (:data:`~vvea_design.actuator.sensitivity.PARAMETERS`): the mean rmse ratio
    design / SEA over the cases both track validly (below 1: the design tracks better), each point labelled
    with the cases the design tracks better / worse over every case of the grid; the design as the study
    takes it is the star.

    Parameters
    ----------
    study : DesignSensitivity
        Result of :func:`~vvea_design.actuator.sensitivity.run_design_sensitivity`.
    fig
        Figure to draw into (three panels).

    Returns
    -------
    Figure
    """
    if fig is None:
        fig = Figure(figsize=(12.0, 4.0))
    axes = fig.subplots(1, 3, sharey=True)
    titles = {"D_min": ("throttle open: D_min (N m s/rad)", "linear"),
              "D_max": ("throttle closed: D_max (N m s/rad)", "log"),
              "K": ("joint stiffness K (N m/rad), SEA at the same K", "linear")}
    colour = _colour("design")
    for ax, par in zip(axes, ("D_min", "D_max", "K")):
        pts = [p for p in study.of(par) if p.mean_rmse_ratio_design_over_sea is not None]
        x = [p.value for p in pts]
        y = [p.mean_rmse_ratio_design_over_sea for p in pts]
        ax.plot(x, y, "o-", color=colour, lw=1.2, ms=5)
        for p in pts:
            ax.annotate(f"{p.design_beats}/{p.design_worse}", (p.value, p.mean_rmse_ratio_design_over_sea),
                        textcoords="offset points", xytext=(0, 7), ha="center", fontsize=7)
            if p.is_base:
                ax.plot([p.value], [p.mean_rmse_ratio_design_over_sea], "*", color="k", ms=12, zorder=5)
        ax.axhline(1.0, color="0.4", lw=0.8, ls="--")
        ax.text(0.98, 1.0, "below: the design tracks better", transform=ax.get_yaxis_transform(), ha="right",
                va="top", fontsize=7, color="0.35")
        ax.set_xscale(titles[par][1])
        if titles[par][1] == "log":  # plain numbers (100, 200, 400), not 2 x 10^2
            from matplotlib.ticker import FixedLocator, FuncFormatter, NullFormatter

            ax.xaxis.set_major_locator(FixedLocator(x))
            ax.xaxis.set_major_formatter(FuncFormatter(lambda v, _: f"{v:.4g}"))
            ax.xaxis.set_minor_formatter(NullFormatter())
        ax.set_xlabel(titles[par][0])
        ax.grid(alpha=0.3)
        spread = study.spread(par)
        ax.set_title(f"{par}: the ratio moves by {spread:.3f}" if np.isfinite(spread) else f"{par}: one value",
                     fontsize=9, y=1.0)
    axes[0].set_ylabel("mean rmse design / SEA of the same K")
    ys = [p.mean_rmse_ratio_design_over_sea for p in study.points if p.mean_rmse_ratio_design_over_sea is not None]
    if ys:
        lo, hi = min(min(ys), 1.0), max(max(ys), 1.0)
        pad = 0.15 * (hi - lo) + 0.005
        axes[0].set_ylim(lo - pad, hi + pad)
    n = study.points[0].n_cases if study.points else 0
    fig.suptitle("What buys tracking: the design against an SEA of the same stiffness, one property changed at a time "
                 f"(star: the design as studied)\nlabel: cases the design tracks better / worse of all {n} (a case only "
                 "one of them tracks validly goes to it; the rest: neither valid or a tie); the ratio is over the cases "
                 "both track validly", fontsize=8)
    set_margins_in(fig, left=0.45 + ytick_label_width_in(axes[0]), bottom=0.585, right=0.2, top=0.75, wspace=0.3)
    return fig
