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
    import matplotlib

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
    pad = 0.3
    win = (max(rl, r0 - pad), min(rl + 2 * half, r1 + pad), max(top.z_mm - half, z0 - pad),
           min(top.z_mm + half, z1 + pad))  # the close-up stays on the part
    fig, ax_all, ax_zoom, ax_cb = _axes(spec.section.bounds_mm(), win)
    sub = _window(tri, sol.nodes_mm, win)
    # stress above the checked peak lies only in the zones the check leaves out (the thread's loaded band):
    # drawn in grey, not left blank (a blank would read as a hole in the part)
    over = bool(np.nanmax(s) > levels[-1] * (1 + 1e-9))
    cmap = matplotlib.colormaps["viridis"].with_extremes(over="0.72")
    for ax, t in ((ax_all, tri), (ax_zoom, sub)):
        cf = ax.tricontourf(t, np.clip(s, 0, None), levels=levels, cmap=cmap, extend="max" if over else "neither")
        ax.set_xlabel("r (mm)")
        ax.set_ylabel("z (mm)")
    ax_zoom.triplot(sub, lw=0.15, color="white", alpha=0.45)
    for (w, p), colour in zip(peaks, ("red", "orange", "magenta", "white")):
        v = p.tresca_MPa if criterion == "tresca" else p.von_mises_MPa
        ax_all.plot(p.r_mm, p.z_mm, ls="none", marker="o", ms=10, mfc="none", mec=colour, mew=2.2, clip_on=False,
                    label=f"peak of the {w.replace('_', ' ')}: {v:.0f} MPa ({p.feature}, r {p.r_mm:.2f}, "
                          f"z {p.z_mm:.2f} mm)")
    if over:
        ax_all.fill([], [], color="0.72", label=f"above {vmax:.0f} MPa: in a zone the check leaves out (the thread's "
                                                "loaded band, checked by ISO 965-1)")
    fig.legend(loc="lower left", bbox_to_anchor=(0.07, 0.0), fontsize=9, frameon=False)
    ax_zoom.plot(top.r_mm, top.z_mm, marker="x", ms=12, color="red", mew=2.5, clip_on=False)
    feat = top.feature + (f", R{top.corner_radius_mm:.2f} mm" if np.isfinite(top.corner_radius_mm) else "")
    ax_zoom.set_title(f"close-up: peak {vmax:.0f} MPa ({feat})\nat r = {top.r_mm:.2f} mm, z = {top.z_mm:.2f} mm",
                      fontsize=10)
    ax_all.set_title("whole section\n" + ("(axis at r = 0)" if r0 < 0.05 else f"(to scale, from r = {r0:.1f})"),
                     fontsize=10)
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


def _axes(bounds_mm, win):
    """The figure and its three axes: the whole section to scale (padded so no marker is cut), the close-up
    beside it and the colour bar beside that, each moved up to its neighbour once the equal aspect has shrunk it
    (no layout engine: one draw)."""
    from matplotlib.figure import Figure
    from matplotlib.ticker import MaxNLocator

    r0, r1, z0, z1 = bounds_mm
    fig = Figure(figsize=(11.0, 6.2))
    aspect = (r1 - r0) / max(z1 - z0, 1e-9)
    w_all = float(np.clip(0.78 * aspect * 6.2 / 11.0, 0.12, 0.42))
    bottom, height = 0.22, 0.64
    ax_all = fig.add_axes((0.08, bottom, w_all, height))
    pad = 0.04 * max(r1 - r0, z1 - z0)
    ax_all.set_xlim(r0 - pad, r1 + pad)
    ax_all.set_ylim(z0 - pad, z1 + pad)
    ax_all.set_aspect("equal", adjustable="box")
    ax_all.set_autoscale_on(False)
    ax_all.apply_aspect()
    box = ax_all.get_position()
    if box.width * 11.0 < 0.35:  # a very thin wall drawn to scale: one upright label with both radii
        ax_all.set_xticks([0.5 * (r0 + r1)], [f"{r0:.1f}–{r1:.1f}"], rotation=90, fontsize=8)
    elif box.width * 11.0 < 1.0:  # a thin wall: its two radii, upright, so no labels collide
        ax_all.set_xticks([r0, r1], [f"{r0:.1f}", f"{r1:.1f}"], rotation=90, fontsize=8)
    else:
        ax_all.xaxis.set_major_locator(MaxNLocator(nbins=max(2, int(box.width * 11.0 / 0.45)), steps=[1, 2, 2.5, 5, 10]))
    x = max(box.x1 + 0.09, 0.27)  # clear of the whole section's title
    ax_zoom = fig.add_axes((x, bottom, 0.86 - x, height))
    ax_zoom.set_xlim(win[0], win[1])
    ax_zoom.set_ylim(win[2], win[3])
    ax_zoom.set_aspect("equal", adjustable="box")
    ax_zoom.set_anchor("W")
    ax_zoom.set_autoscale_on(False)
    ax_zoom.apply_aspect()
    zb = ax_zoom.get_position()
    ax_cb = fig.add_axes((zb.x1 + 0.02, zb.y0, 0.018, zb.height))
    return fig, ax_all, ax_zoom, ax_cb


def _window(tri, nodes_mm: np.ndarray, win) -> object:
    """The triangles of a triangulation near a window (what the close-up draws)."""
    from matplotlib.tri import Triangulation

    r0, r1, z0, z1 = win
    pad = max(r1 - r0, z1 - z0)
    c = nodes_mm[:, tri.triangles].mean(axis=2)
    keep = (c[0] > r0 - pad) & (c[0] < r1 + pad) & (c[1] > z0 - pad) & (c[1] < z1 + pad)
    return Triangulation(nodes_mm[0], nodes_mm[1], tri.triangles[keep])
