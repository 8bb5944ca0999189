"""Figures of the blind bench: per-campaign outcome of the diagnosis, and the peers beside it."""

from __future__ import annotations

from pathlib import Path

import numpy as np

__all__ = ["OUTCOME_COLOURS", "plot_scores", "plot_peers"]

#: Colour of each outcome (score.py's outcome names).
OUTCOME_COLOURS = {
    "clean": "#2a9d8f", "found": "#2a9d8f", "modelled": "#2a9d8f",
    "found_not_modelled": "#8ab17d", "flagged": "#e9c46a",
    "modelled+misnamed": "#f4a261", "misnamed+flagged": "#e76f51", "misnamed": "#c1121f",
    "extra": "#e76f51", "missed": "#6c757d", "missed+extra": "#c1121f", "false_accept": "#c1121f",
    "error": "#000000",
}

PEER_MARKERS = {"sindy_gradient_N": ("v", "#457b9d", "SINDy, np.gradient ẋ"),
                "sindy_fitted_N": ("^", "#1d3557", "SINDy, fitted ẋ"),
                "trees_gradient_N": ("s", "#e76f51", "eq. 14 + trees, np.gradient ẋ"),
                "trees_fitted_N": ("D", "#9d0208", "eq. 14 + trees, fitted ẋ")}


def _frame(rows):
    """Sorted rows, a wide figure with one slot per campaign, and the slot positions."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    rows = sorted(rows, key=lambda r: (r["kind"], r["campaign_id"]))
    fig, ax = plt.subplots(figsize=(max(8.0, 0.32 * len(rows) + 2.5) + 2.5, 6.0))
    return rows, fig, ax, np.arange(len(rows))


def _finish(fig, ax, rows, path, title, ylabel, handles=None) -> Path:
    """Log axis from 0.5, the 2 × noise line, campaign labels, legend, title; write the PNG."""
    import matplotlib.pyplot as plt

    n = len(rows)
    ax.axhline(2.0, color="black", ls="--", lw=0.8, zorder=1)
    ax.text(n - 0.5, 2.05, "2 × true noise", ha="right", va="bottom", fontsize=8)
    ax.set_yscale("log")
    ax.set_ylim(bottom=0.5)
    ax.set_ylabel(ylabel)
    ax.set_xticks(np.arange(n))
    ax.set_xticklabels([r["campaign_id"] for r in rows], rotation=90, fontsize=7)
    ax.set_xlim(-0.7, n - 0.3)
    ax.legend(handles=handles, fontsize=7, loc="upper left", bbox_to_anchor=(1.01, 1.0))
    ax.set_title(title, fontsize=10)
    ax.grid(axis="y", which="both", alpha=0.3)
    fig.tight_layout()
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(path, dpi=110, bbox_inches="tight")  # long campaign names below the axis
    plt.close(fig)
    return path


def plot_scores(rows: list[dict], path: Path, title: str) -> Path:
    """Final and baseline held-out RMS over the true noise, one bar per campaign, coloured by outcome.

    Parameters
    ----------
    rows : list of dict
        Scored campaigns (score.score_campaign rows; failed runs carry ``outcome="error"``).
    path : pathlib.Path
        PNG to write.
    title : str
        Figure title.

    Returns
    -------
    pathlib.Path
        ``path``.
    """
    from matplotlib.patches import Patch

    rows, fig, ax, y = _frame(rows)
    fin = np.array([r.get("final_over_noise", np.nan) for r in rows], dtype=float)
    bas = np.array([r.get("heldout_baseline_N", np.nan) / r.get("true_noise_N", np.nan) for r in rows], dtype=float)
    cols = [OUTCOME_COLOURS.get(r.get("outcome", "error"), "#000000") for r in rows]
    ax.bar(y, np.nan_to_num(fin, nan=0.0), color=cols, edgecolor="black", linewidth=0.4, zorder=2)
    base = ax.scatter(y, bas, marker="o", s=28, facecolors="none", edgecolors="black", zorder=3,
                      label="baseline (eq. 14) held-out RMS / noise")
    used = [k for k in OUTCOME_COLOURS if any(r.get("outcome") == k for r in rows)]
    handles = [Patch(facecolor=OUTCOME_COLOURS[k], edgecolor="black", label=k) for k in used] + [base]
    return _finish(fig, ax, rows, path, title, "held-out RMS / true noise (bar: final model)",
                   handles)


def plot_peers(rows: list[dict], path: Path, title: str) -> Path:
    """Held-out RMS over the true noise: diagnose's final model and each peer, per campaign.

    Parameters
    ----------
    rows : list of dict
        Peer rows (``campaign_id``, ``kind``, ``true_noise_N``, ``diagnose_final_N``,
        ``diagnose_baseline_N`` and the peers' ``*_N`` columns).
    path : pathlib.Path
        PNG to write.
    title : str
        Figure title.

    Returns
    -------
    pathlib.Path
        ``path``.
    """
    rows, fig, ax, y = _frame(rows)
    noise = np.array([r["true_noise_N"] for r in rows], dtype=float)
    ax.bar(y, [r["diagnose_final_N"] for r in rows] / noise, color="#bcbcbc", edgecolor="black", lw=0.4,
           label="vvea diagnose, final model", zorder=2)
    ax.scatter(y, [r["diagnose_baseline_N"] for r in rows] / noise, marker="o", s=28, facecolors="none",
               edgecolors="black", zorder=3, label="eq. 14 (diagnose's baseline)")
    for key, (m, c, lab) in PEER_MARKERS.items():
        vals = np.array([r.get(key, np.nan) for r in rows], dtype=float) / noise
        ax.scatter(y, vals, marker=m, color=c, s=22, zorder=4, label=lab)
    return _finish(fig, ax, rows, path, title, "held-out RMS / true noise RMS")
