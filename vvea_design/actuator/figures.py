"""Figures of the actuator studies: Fig. 13 (best setting map), Fig. 12-like trajectory, Fig. 14 (safety)."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from .ocp import OcpResult

__all__ = ["plot_best_map", "plot_trajectory", "plot_safety"]

_COLOURS = {"SEA": "tab:blue", "LWR": "tab:cyan", "VVEA": "tab:purple", "iVVEA": "tab:purple"}


def plot_best_map(df, path: str | Path) -> Path:
    """Fig. 13: best valid setting per (T, A); colour depth = gain over the next best; white = none valid."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from matplotlib.colors import to_rgb
    from matplotlib.patches import Patch

    df = df.copy()
    df["valid"] = df["valid"].astype(str).str.lower().isin(["true", "1"])
    settings = list(dict.fromkeys(df["setting"]))
    varset = [s for s in settings if (df.loc[df.setting == s, "D_max_Nms_per_rad"]
                                      > df.loc[df.setting == s, "D_min_Nms_per_rad"]).any()]
    consts = [s for s in settings if s not in varset]
    panels = varset or [None]
    fig, axes = plt.subplots(len(panels), 1, figsize=(7.5, 3.2 * len(panels)), squeeze=False)
    A_vals = sorted(df["A_rad"].unique())
    T_vals = sorted(df["T_s"].unique())
    palette = ["tab:purple", "tab:green", "tab:red", "tab:orange", "tab:olive"]
    for ax, v in zip(axes[:, 0], panels):
        group = consts + ([v] if v else [])
        cols = {s: _COLOURS.get(s, palette[i % len(palette)]) for i, s in enumerate(group)}
        if v:
            cols[v] = palette[varset.index(v) % len(palette)] if v not in ("VVEA", "iVVEA") else "tab:purple"
        for (A, T), sub in df[df.setting.isin(group)].groupby(["A_rad", "T_s"]):
            sub = sub[sub["valid"]].sort_values("rmse")
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
        title = " vs ".join(group)
        D = df.loc[df.setting == v, ["D_min_Nms_per_rad", "D_max_Nms_per_rad"]].iloc[0] if v else None
        if v is not None:
            title += f"  ({D.iloc[0]:.3g} <= D <= {D.iloc[1]:.3g} N m s/rad)"
        ax.set_title(title, fontsize=9)
        handles = [Patch(color=cols[s], label=s) for s in group] + [Patch(facecolor="white", edgecolor="0.6",
                                                                          label="no valid setting")]
        ax.legend(handles=handles, fontsize=7, loc="upper left", bbox_to_anchor=(1.01, 1.0))
    fig.suptitle("Best valid setting per case (deeper colour = bigger gain over the next best)", fontsize=9)
    fig.tight_layout()
    path = Path(path)
    fig.savefig(path, dpi=130)
    plt.close(fig)
    return path


def plot_trajectory(best: dict[str, OcpResult], A_rad: float, T_s: float, path: str | Path,
                    highlight: str | None = None) -> Path:
    """Fig. 12-like plot: link angle vs reference, motor torque and damping of every setting."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from .ocp import rest_to_rest_reference

    fig, axes = plt.subplots(3, 1, figsize=(7, 7), sharex=True)
    tt = np.linspace(0, 2 * T_s, 801)
    axes[0].plot(tt, rest_to_rest_reference(tt, A_rad, T_s), "k--", lw=1, label="q_des")
    for name, r in best.items():
        if r is None or not np.all(np.isfinite(r.q_rad)):
            continue
        lw = 2.0 if name == highlight else 1.0
        axes[0].plot(r.t_s, r.q_rad, lw=lw, label=f"{name} (rmse {r.extra['rmse_rad']:.4f} rad)")
        axes[1].step(r.t_s[:-1], r.tau_m_Nm, where="post", lw=lw, label=name)
        axes[2].plot(r.t_s, r.D_Nms_per_rad, lw=lw, label=name)
    axes[0].set_ylabel("link angle q (rad)")
    axes[1].set_ylabel("motor torque τ_m (N m)")
    axes[2].set_ylabel("damping D (N m s/rad)")
    axes[2].set_yscale("symlog", linthresh=10)
    axes[2].set_xlabel("time t (s)")
    for ax in axes:
        ax.legend(fontsize=7)
        ax.grid(alpha=0.3)
    axes[0].set_title(f"Rest-to-rest optimum, A = {A_rad:g} rad, T = {T_s:g} s", fontsize=9)
    fig.tight_layout()
    path = Path(path)
    fig.savefig(path, dpi=130)
    plt.close(fig)
    return path



def plot_safety(results: dict[str, OcpResult], tau_ref: float, path: Path, zoom_s: float = 0.03) -> Path:
    """Fig. 14: τ, τ_m and D over the horizon (left) and over the first ``zoom_s`` seconds (right)."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    colours = ["tab:green", "tab:red", "tab:blue", "tab:orange"]
    fig, axes = plt.subplots(3, 2, figsize=(11, 7), sharex="col", gridspec_kw={"width_ratios": [1.4, 1]})
    for col, xmax in ((0, None), (1, zoom_s)):
        ax = axes[:, col]
        for c, (name, r) in zip(colours, results.items()):
            lab = f"{name}: mean D {r.extra['mean_D_Nms_per_rad']:.1f}, t95 {r.extra['t95_s'] * 1e3:.1f} ms"
            ax[0].plot(r.t_s, r.tau_Nm, color=c, label=lab)
            ax[1].step(r.t_s[:-1], r.tau_m_Nm, where="post", color=c, label=name)
            ax[2].plot(r.t_s, r.D_Nms_per_rad, color=c, label=name)
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
    axes[0, 0].set_title(f"Optimal {tau_ref:g} N m torque step (paper Fig. 14)", fontsize=9)
    axes[0, 1].set_title(f"first {zoom_s * 1e3:g} ms", fontsize=9)
    fig.tight_layout()
    fig.savefig(path, dpi=130)
    plt.close(fig)
    return path


