"""Stress-field pictures of the FE check: the piece's meridian section coloured by the check's equivalent stress.

Left, the whole section to scale (axis of the unit on the left edge, r to the right, z up) with the peak
marked; right, a close-up of the peak's neighbourhood with the mesh. The colour scale is the same in both
(MPa), its top the peak; the title states the piece, the governing case, the material and the safety factor.
Each quadratic triangle is drawn as its four straight sub-triangles (vertex and edge nodes), so the field
is shown at the resolution it was solved at.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from .meshing import mean_wall_mm
from .model import CaseSolution, PieceModel

__all__ = ["piece_figure", "stress_triangulation"]


def stress_triangulation(nodes_mm: np.ndarray, elements: np.ndarray):
    """A matplotlib triangulation of a quadratic mesh: each 6-node triangle split into four.

    Parameters
    ----------
    nodes_mm : ndarray
        ``(2, n)`` r, z of the nodes, mm.
    elements : ndarray
        ``(6, m)`` node indices (vertices, then the edge nodes 0-1, 1-2, 0-2).

    Returns
    -------
    matplotlib.tri.Triangulation
        ``4 m`` triangles over the nodes.
    """
    from matplotlib.tri import Triangulation

    v0, v1, v2, e01, e12, e02 = elements
    tris = np.concatenate([np.stack([v0, e01, e02]), np.stack([e01, v1, e12]), np.stack([e02, e12, v2]),
                           np.stack([e01, e12, e02])], axis=1).T
    return Triangulation(nodes_mm[0], nodes_mm[1], tris)


def piece_figure(pm: PieceModel, spec, cs: CaseSolution, criterion: str, path: str | Path) -> Path:
    """Draw a piece's stress field under a case and save it as PNG.

    Parameters
    ----------
    pm : PieceModel
        The meshed piece.
    spec : PieceSpec
        Its walls (the peak of each is marked).
    cs : CaseSolution
        The solved case drawn.
    criterion : str
        ``"tresca"`` or ``"von_mises"``.
    path : path-like
        The PNG written.

    Returns
    -------
    Path
        ``path``.
    """
    from matplotlib.figure import Figure

    from .evaluate import peak_in

    sol = cs.solution
    s = sol.tresca_MPa if criterion == "tresca" else sol.von_mises_MPa
    label = "Tresca stress (MPa)" if criterion == "tresca" else "von Mises stress (MPa)"
    tri = stress_triangulation(sol.nodes_mm, sol.elements)
    peaks = [(reg.wall, peak_in(sol, reg, spec.section, criterion)) for reg in spec.regions]
    peaks = [(w, p) for w, p in peaks if p is not None]
    wall, top = max(peaks, key=lambda wp: wp[1].tresca_MPa if criterion == "tresca" else wp[1].von_mises_MPa)
    vmax = top.tresca_MPa if criterion == "tresca" else top.von_mises_MPa
    levels = np.linspace(0.0, max(vmax, 1e-9), 25)
    r0, r1, z0, z1 = spec.section.bounds_mm()
    half = float(np.clip(1.5 * mean_wall_mm(spec.section), 1.5, 6.0))
    rl = min(max(top.r_mm - half, r0 - 0.3), max(r1 + 0.3 - 2 * half, r0 - 0.3))  # square, inside when it fits
    win = (rl, rl + 2 * half, top.z_mm - half, top.z_mm + half)
    # fixed margins (no layout engine: one draw); the overview's width follows the section's aspect
    fig = Figure(figsize=(11.0, 6.2))
    aspect = (r1 - r0) / max(z1 - z0, 1e-9)
    w_all = float(np.clip(0.78 * aspect * 6.2 / 11.0, 0.12, 0.42))
    ax_all = fig.add_axes((0.07, 0.19, w_all, 0.67))
    ax_zoom = fig.add_axes((0.15 + w_all, 0.19, 0.7 - w_all, 0.67))
    ax_cb = fig.add_axes((0.9, 0.19, 0.018, 0.67))
    sub = _window(tri, sol.nodes_mm, win)
    for ax, t in ((ax_all, tri), (ax_zoom, sub)):
        cf = ax.tricontourf(t, np.clip(s, 0, None), levels=levels, cmap="viridis")
        ax.set_aspect("equal", adjustable="box")
        ax.set_xlabel("r (mm)")
        ax.set_ylabel("z (mm)")
    ax_zoom.triplot(sub, lw=0.15, color="white", alpha=0.45)
    for (w, p), colour in zip(peaks, ("red", "orange", "magenta", "white")):
        v = p.tresca_MPa if criterion == "tresca" else p.von_mises_MPa
        ax_all.plot(p.r_mm, p.z_mm, ls="none", marker="o", ms=10, mfc="none", mec=colour, mew=2.2,
                    label=f"peak of the {w.replace('_', ' ')}: {v:.0f} MPa ({p.feature}, r {p.r_mm:.2f}, "
                          f"z {p.z_mm:.2f} mm)")
    fig.legend(loc="lower left", bbox_to_anchor=(0.07, 0.0), fontsize=9, frameon=False, facecolor="0.85")
    ax_zoom.set_autoscale_on(False)
    ax_zoom.set_xlim(win[0], win[1])
    ax_zoom.set_ylim(win[2], win[3])
    ax_zoom.plot(top.r_mm, top.z_mm, marker="x", ms=12, color="red", mew=2.5)
    feat = top.feature + (f", R{top.corner_radius_mm:.2f} mm" if np.isfinite(top.corner_radius_mm) else "")
    ax_zoom.set_title(f"close-up: peak {vmax:.0f} MPa ({feat})\nat r = {top.r_mm:.2f} mm, z = {top.z_mm:.2f} mm",
                      fontsize=10)
    ax_all.set_title("whole section\n(axis at r = 0)", fontsize=10)
    cb = fig.colorbar(cf, cax=ax_cb)
    cb.set_label(label)
    sf = pm.material.yield_MPa / vmax if vmax > 0 else np.inf
    fig.suptitle(f"{spec.title} ({spec.part}) — case {cs.case.name}: peak {vmax:.0f} MPa, "
                 f"{pm.material.name} yield {pm.material.yield_MPa:.0f} MPa, safety {sf:.2f} "
                 f"(required {cs.case.required_safety:g})", fontsize=11)
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(path, dpi=110, metadata={"Software": "vvea-design"})
    return path


def _window(tri, nodes_mm: np.ndarray, win) -> object:
    """The triangles of a triangulation near a window (what the close-up draws)."""
    from matplotlib.tri import Triangulation

    r0, r1, z0, z1 = win
    pad = max(r1 - r0, z1 - z0)
    c = nodes_mm[:, tri.triangles].mean(axis=2)
    keep = (c[0] > r0 - pad) & (c[0] < r1 + pad) & (c[1] > z0 - pad) & (c[1] < z1 + pad)
    return Triangulation(nodes_mm[0], nodes_mm[1], tri.triangles[keep])
