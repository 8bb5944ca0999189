"""Figures of the spring side: force curve, Pareto fronts, linearity maps.

Pure functions from results to a PNG file (matplotlib, Agg backend).
"""

from __future__ import annotations

from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

from .gas_spring import GasSpring, least_squares_line, linearity_error  # noqa: E402

__all__ = ["plot_spring", "plot_pareto", "plot_linearity_map", "save_figure"]

_META = {"Software": "vvea-design"}  # no timestamps in PNG metadata: byte-stable figures


def save_figure(fig, path: str | Path) -> Path:
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(path, dpi=120, metadata=_META)
    plt.close(fig)
    return path


def plot_spring(spring: GasSpring, path: str | Path, title: str = "", extra_charges_MPa=()) -> Path:
    """Force–displacement with its least-squares line, the deviation, stiffness and pressures."""
    x = spring.x_mm(401)
    F = spring.force_N(x)
    k, b = least_squares_line(x, F)
    lin = float(linearity_error(x, F))
    fig, axes = plt.subplots(2, 2, figsize=(10, 7))
    ax = axes[0, 0]
    ax.plot(x, F, lw=2, label=f"F(x), p2 = {spring.p2_MPa:.2f} MPa")
    ax.plot(x, k * x + b, "k--", lw=1, label=f"least-squares line, {float(k):.1f} N/mm")
    for p2 in extra_charges_MPa:
        s = spring.with_pressures(p2)
        ax.plot(x, s.force_N(x), lw=1, alpha=0.7, label=f"p2 = {p2:g} MPa")
    ax.set(xlabel="displacement x [mm]", ylabel="force [N] (tension > 0)", title="force–displacement")
    ax.legend(fontsize=8)
    ax.grid(alpha=0.3)
    ax = axes[0, 1]
    dev = F - (k * x + b)
    ax.plot(x, dev, color="C3")
    ax.axhline(0, color="k", lw=0.5)
    ax.set(xlabel="x [mm]", ylabel="F − line [N]",
           title=f"deviation: max {np.abs(dev).max():.1f} N = {100 * lin:.2f} % of span")
    ax.grid(alpha=0.3)
    ax = axes[1, 0]
    ax.plot(x, spring.stiffness_N_per_mm(x), color="C2")
    ax.axhline(float(k), color="k", ls="--", lw=1, label="mean (LS slope)")
    ax.set(xlabel="x [mm]", ylabel="dF/dx [N/mm]", title="local stiffness")
    ax.legend(fontsize=8)
    ax.grid(alpha=0.3)
    ax = axes[1, 1]
    P1, P2 = spring.pressures_MPa(x)
    ax.plot(x, P1, label="chamber 1 (expands)")
    ax.plot(x, P2, label="chamber 2 (compressed)")
    ax.set(xlabel="x [mm]", ylabel="pressure [MPa]", title="chamber pressures")
    ax.legend(fontsize=8)
    ax.grid(alpha=0.3)
    fig.suptitle(title or f"gas spring: linearity error {100 * lin:.2f} %")
    fig.tight_layout()
    return save_figure(fig, path)


def plot_pareto(rows: list[dict], x_key: str, x_label: str, path: str | Path, title: str = "") -> Path:
    """Best linearity against a swept requirement; infeasible points marked."""
    fig, ax = plt.subplots(figsize=(7, 4.5))
    xs = np.array([r[x_key] for r in rows], dtype=float)
    ys = np.array([100 * r.get("linearity_error", np.nan) if r.get("feasible") else np.nan for r in rows])
    ax.plot(xs, ys, "o-", label="best feasible design")
    bad = [r[x_key] for r in rows if not r.get("feasible")]
    if bad:
        ax.plot(bad, [np.nanmax(ys) if np.isfinite(ys).any() else 1.0] * len(bad), "rx", label="infeasible")
    ax.set(xlabel=x_label, ylabel="linearity error [%]", title=title or "Pareto front")
    ax.grid(alpha=0.3)
    ax.legend()
    fig.tight_layout()
    return save_figure(fig, path)


def plot_linearity_map(m: dict, path: str | Path, optimum: tuple[float, float] | None = None) -> Path:
    """Filled contours of linearity (%) over two variables, infeasible region hatched."""
    fig, ax = plt.subplots(figsize=(7.5, 5.5))
    X, Y = np.meshgrid(m["x"], m["y"])
    lin = 100 * np.clip(m["linearity"], 0, 0.1)
    cs = ax.contourf(X, Y, lin, levels=np.linspace(0, 10, 41), cmap="viridis_r", extend="max")
    ax.contour(X, Y, lin, levels=[1, 1.86, 3, 5, 10], colors="w", linewidths=0.7)
    fig.colorbar(cs, ax=ax, label="linearity error [%]")
    infeas = (~m["feasible"]).astype(float)
    ax.contourf(X, Y, infeas, levels=[0.5, 1.5], colors="none", hatches=["//"])
    ax.contour(X, Y, infeas, levels=[0.5], colors="r", linewidths=1)
    if optimum is not None:
        ax.plot(*optimum, "r*", ms=14, label="optimum")
        ax.legend(loc="best")
    ax.set(xlabel=m["var_x"], ylabel=m["var_y"],
           title="linearity over two design variables (hatched: violates a requirement)")
    fig.tight_layout()
    return save_figure(fig, path)
