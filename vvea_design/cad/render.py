"""Off-screen PNG renders of the CAD set (pyvista / VTK, no display needed).

Headless: with no ``DISPLAY`` this module selects VTK's EGL render window
(``VTK_DEFAULT_OPENGL_WINDOW=vtkEGLRenderWindow``) before VTK is imported;
Debian needs ``libegl1 libegl-mesa0 libgl1-mesa-dri`` (Mesa llvmpipe).

* :func:`render_assembly_cutaway` -- the unit cut on the meridian plane at
  x = 0 and x = travel side by side, cropped, parts named, key dimensions and
  a scale bar; bladder and chamber 2 deformed volume-consistently at each x;
  chamber-1 gas blue, chamber-2 gas red (the paper's Fig. 2 colours).
* :func:`render_mould_open` -- the two mould halves laid open, parting faces
  up, with the core and the cast bladder between them, each piece named.

Every colour is the palette's (:mod:`vvea_design.palette`), as in every figure and the report's 3-D view.
"""

from __future__ import annotations

import os

import numpy as np

from ..palette import PART_LABELS, part_colour

if not os.environ.get("DISPLAY"):
    os.environ.setdefault("VTK_DEFAULT_OPENGL_WINDOW", "vtkEGLRenderWindow")

__all__ = ["render_assembly_cutaway", "render_mould_open", "WINDOW_SIZE"]

#: Size of every render, pixels.
WINDOW_SIZE = (1400, 900)


def _pv():
    import pyvista as pv

    pv.OFF_SCREEN = True
    return pv


def _poly(mesh):
    pv = _pv()
    faces = np.hstack([np.full((len(mesh.faces), 1), 3, dtype=np.int64), np.asarray(mesh.faces, dtype=np.int64)])
    return pv.PolyData(np.asarray(mesh.vertices, dtype=np.float64), faces.ravel())


def _cut(poly):
    """Keep the half y >= 0 and cap the cut (meridian section)."""
    try:
        return poly.clip_closed_surface(normal=(0, 1, 0), origin=(0, 0, 0))
    except Exception:  # non-manifold input: plain clip
        return poly.clip(normal=(0, 1, 0), origin=(0, 0, 0))


def _png(plotter) -> bytes:
    import io

    from PIL import Image

    img = plotter.screenshot(None, return_img=True)
    plotter.close()
    buf = io.BytesIO()
    Image.fromarray(np.asarray(img)).save(buf, format="PNG", optimize=False)
    return buf.getvalue()


def _section_meshes(model, x_mm: float, offset_mm: float) -> list[tuple[str, object, tuple, float]]:
    """(name, meridian-cut PolyData, colour, opacity) of the unit at ``x_mm``, shifted by ``offset_mm`` in x:
    piston at x, bladder and chamber-2 gas in their volume-consistent shape at x, chamber-1 gas and fluid at x."""
    from ._shapes import ring
    from .bladder import bladder_deformed
    from .mesh import to_mesh

    lay = model.layout
    solids = model.solids_at(x_mm, "assembly", "gas")
    bl, g2 = bladder_deformed(lay, x_mm)
    top = [s for s in solids["gas_chamber_2"].solids() if s.bounding_box().min.Z >= lay.z_free1 - 1e-6]
    solids["bladder"], solids["gas_chamber_2"] = bl, g2
    fluid = ring(lay.r_rod, lay.r_piston, lay.z_base_top, lay.z_piston_bottom(x_mm))
    extra = [("gas_chamber_2", t) for t in top]  # bulkhead layout: chamber-2 gas above the bulkhead
    out = []
    for name, solid in [*solids.items(), *extra, ("fluid", fluid)]:
        colour = part_colour(name)
        alpha = 0.55 if name in ("fluid", "gas_chamber_1", "gas_chamber_2") else 1.0
        poly = _poly(to_mesh(solid, 0.05, 0.1)).translate((offset_mm, 0.0, 0.0), inplace=False)
        out.append((name, _cut(poly), colour, alpha))
    return out


def render_assembly_cutaway(model, meshes: dict | None = None) -> bytes:
    """PNG: meridian cut-away of the unit at x = 0 (left) and x = travel (right), cropped to the part,
    with the parts named, key dimensions and a scale bar.

    The bladder and chamber 2 are drawn deformed at each stroke end in a volume-consistent shape
    (parabolic bulge between the clamps, chamber-2 gas = ``V2 - A2 x``); chamber 1 blue, chamber 2
    red (the paper's Fig. 2), fluid green.

    Parameters
    ----------
    model : CadModel
        The built CAD set (mm).
    meshes : dict, optional
        Unused (kept for the ``write_cad`` call signature).

    Returns
    -------
    bytes
        The PNG (110 dpi, no timestamp metadata); dimensions in the picture are in mm.
    """
    import io

    from matplotlib.figure import Figure

    pv = _pv()
    d, lay = model.design, model.layout
    travel = d.fixed.travel_mm
    R = lay.r_outer
    dx = 2.7 * R
    z_lo = lay.z_piston_bottom(travel) - d.rod_length_mm - 2.0
    z_hi = d.housing_length_mm + 2.0
    x_lo, x_hi = -R - 2.0, dx + R + 2.0
    px_mm = 6.0
    size = (int(round((x_hi - x_lo) * px_mm)), int(round((z_hi - z_lo) * px_mm)))
    pl = pv.Plotter(off_screen=True, window_size=size, border=False)
    pl.set_background("white")
    for x, off in ((0.0, 0.0), (travel, dx)):
        for _, poly, colour, alpha in _section_meshes(model, x, off):
            pl.add_mesh(poly, color=colour, opacity=alpha, smooth_shading=False)
    xc, zc = 0.5 * (x_lo + x_hi), 0.5 * (z_lo + z_hi)
    pl.camera.parallel_projection = True
    pl.camera_position = [(xc, -1000.0, zc), (xc, 0.0, zc), (0.0, 0.0, 1.0)]
    pl.camera.parallel_scale = 0.5 * (z_hi - z_lo)
    img = np.asarray(pl.screenshot(None, return_img=True))
    pl.close()

    margin_l, margin_r, margin_t, margin_b = 52.0, 44.0, 16.0, 14.0  # mm of drawing space around the image
    w_mm, h_mm = x_hi - x_lo + margin_l + margin_r, z_hi - z_lo + margin_t + margin_b
    fig = Figure(figsize=(w_mm / 22.0, h_mm / 22.0))
    ax = fig.add_axes((0, 0, 1, 1))
    ax.imshow(img, extent=(x_lo, x_hi, z_lo, z_hi), interpolation="bilinear")
    ax.set_xlim(x_lo - margin_l, x_hi + margin_r)
    ax.set_ylim(z_lo - margin_b, z_hi + margin_t)
    ax.set_aspect("equal")
    ax.axis("off")
    txt = dict(fontsize=8, va="center", bbox=dict(facecolor="white", edgecolor="none", pad=0.5))
    arrow = dict(arrowstyle="<|-|>", lw=0.7, color="black", shrinkA=0, shrinkB=0, mutation_scale=8)
    for x, off, head in ((0.0, 0.0, "x = 0 mm (piston up)"), (travel, dx, f"x = {travel:g} mm (full stroke)")):
        ax.text(off, z_hi + 9.0, head, ha="center", fontsize=10, weight="bold")
    # part names (left view)
    zm = 0.5 * (lay.z_free0 + lay.z_free1)
    labels = [
        ("housing (Al)", (-R + 0.5 * d.outer_wall_mm, lay.z_top - 3.0)),
        ("gas chamber 2", (-(lay.r_bore - 0.6), zm + 18.0)),
        ("bladder (silicone)", (-0.5 * (lay.r_bladder_in + lay.r_bladder_out) + 0.3, zm)),
        ("gas chamber 1", (-0.5 * lay.r_piston, 0.5 * (lay.z_piston_top(0.0) + lay.z_cap))),
        ("piston with rod", (-0.7 * lay.r_piston, lay.z_piston_bottom(0.0) + 0.5 * d.fixed.piston_height_mm)),
        ("fluid column", (-0.5 * (lay.r_rod + lay.r_piston), 0.5 * (lay.z_base_top + lay.z_piston_bottom(0.0)))),
        ("support ring", (-0.5 * (lay.r_inner_tube + lay.r_bore), lay.z_base_top + 0.5 * lay.clamp)),
        ("base (valves)", (-R + 4.0, 0.5 * lay.z_base_top)),
    ]
    labels.sort(key=lambda item: -item[1][1])  # by height, so the leader lines do not cross
    ys = np.linspace(z_hi - 6.0, lay.z_base_top - 20.0, len(labels))
    for (name, (u, z)), yt in zip(labels, ys):
        ax.plot([u], [z], "o", ms=2.2, color="black")
        ax.plot([x_lo - 3.0, u], [yt, z], color="black", lw=0.5)
        ax.text(x_lo - 4.0, yt, name, ha="right", **txt)
    # dimensions: outer diameter (top, left view), housing length and stroke (right of the right view)
    zt = d.housing_length_mm
    ax.annotate("", (R, zt + 4.0), (-R, zt + 4.0), arrowprops=arrow)
    ax.text(0.0, zt + 4.0, f"Ø{2 * R:.1f}", ha="center", **txt)
    xr = dx + R + 6.0
    ax.annotate("", (xr, zt), (xr, 0.0), arrowprops=arrow)
    ax.plot([dx + R + 0.5, xr + 1.5], [zt, zt], color="black", lw=0.4)
    ax.plot([dx + R + 0.5, xr + 1.5], [0.0, 0.0], color="black", lw=0.4)
    ax.text(xr + 1.5, 0.5 * zt, f"{zt:.1f}", ha="left", rotation=90, **txt)
    z0t, z1t = lay.z_piston_top(0.0), lay.z_piston_top(travel)
    xs = dx + R + 20.0
    ax.plot([lay.r_piston, xs + 1.5], [z0t, z0t], color="black", lw=0.4, ls=(0, (4, 2)))
    ax.plot([dx + lay.r_piston, xs + 1.5], [z1t, z1t], color="black", lw=0.4, ls=(0, (4, 2)))
    ax.annotate("", (xs, z0t), (xs, z1t), arrowprops=arrow)
    ax.text(xs + 1.5, 0.5 * (z0t + z1t), f"stroke {travel:g}", ha="left", rotation=90, **txt)
    # scale bar
    y_sb = lay.z_piston_bottom(0.0) - d.rod_length_mm - 15.0  # under the left view's rod end
    ax.plot([-10.0, 10.0], [y_sb, y_sb], color="black", lw=2.5, solid_capstyle="butt")
    ax.text(0.0, y_sb - 4.0, "20 mm", ha="center", **txt)
    ax.text(x_lo - margin_l + 2.0, z_lo - margin_b + 3.0,
            "dimensions in mm; bladder and chamber 2 drawn volume-consistent at each x "
            "(parabolic bulge, chamber-2 gas = V2 - A2 x)", fontsize=6.5, ha="left", color="0.3")
    buf = io.BytesIO()
    fig.savefig(buf, format="png", dpi=110, metadata={"Software": None})
    return buf.getvalue()


def render_mould_open(model, meshes: dict) -> bytes:
    """PNG: the mould laid open -- half A (turned), core with the cast bladder, half B, parting faces up,
    each piece named under it on a label of its colour.

    The cavity (the bladder scaled by the shrinkage) is drawn translucent on the core. Both halves are the
    palette's mould colour; the names under them tell them apart.

    Parameters
    ----------
    model : CadModel
        The built CAD set; its ``mould`` gives the block size and the cavity (mould frame, mm).
    meshes : dict of str to trimesh.Trimesh
        Tessellated parts by name (from :func:`~vvea_design.cad.export.export_files`); needs
        ``mould_half_a``, ``mould_half_b`` and ``mould_core``.

    Returns
    -------
    bytes
        The PNG, :data:`WINDOW_SIZE` pixels.
    """
    pv = _pv()
    m = model.mould
    x0, x1 = m.block_mm[0], m.block_mm[1]
    gap = (x1 - x0) * 1.15
    pl = pv.Plotter(off_screen=True, window_size=WINDOW_SIZE)
    pl.set_background("white")
    hb = _poly(meshes["mould_half_b"]).translate((-gap, 0, 0), inplace=False)
    ha = _poly(meshes["mould_half_a"]).rotate_z(180.0, inplace=False).translate((gap, 0, 0), inplace=False)
    core = _poly(meshes["mould_core"])
    from .mesh import to_mesh

    cav = _poly(to_mesh(m.cavity, 0.1, 0.2))
    pl.add_mesh(hb, color=part_colour("mould_half_b"))
    pl.add_mesh(ha, color=part_colour("mould_half_a"))
    pl.add_mesh(core, color=part_colour("mould_core"))
    pl.add_mesh(cav, color=part_colour("bladder"), opacity=0.6)
    pl.camera_position = [(0.0, 500.0, 420.0), (0.0, 0.0, 0.0), (0.0, 0.0, 1.0)]
    pl.reset_camera()
    img = np.asarray(pl.screenshot(None, return_img=True))
    # where each piece's name goes (under it) and the bladder's (beside the core), in pixels of the picture
    z_lo = min(p.bounds[4] for p in (hb, ha, core))
    height = max(p.bounds[5] for p in (hb, ha, core)) - z_lo
    mid = lambda p, z: (0.5 * (p.bounds[0] + p.bounds[1]), 0.5 * (p.bounds[2] + p.bounds[3]), z)  # noqa: E731
    labels = [(mid(hb, z_lo - 0.15 * height), PART_LABELS["mould_half_b"], "mould_half_b", "center"),
              (mid(core, z_lo - 0.2 * height), "core with the cast bladder", "mould_core", "center"),
              (mid(ha, z_lo - 0.15 * height), PART_LABELS["mould_half_a"], "mould_half_a", "center"),
              ((core.bounds[0], 0.5 * (core.bounds[2] + core.bounds[3]), z_lo + 0.55 * height),
               "cast bladder (cavity)", "bladder", "left")]
    at = []
    for xyz, *rest in labels:
        pl.renderer.SetWorldPoint(*xyz, 1.0)
        pl.renderer.WorldToDisplay()
        u, v, _ = pl.renderer.GetDisplayPoint()
        at.append((u, img.shape[0] - v, *rest))
    pl.close()
    return _labelled_png(img, "bladder mould laid open, parting faces up: each piece named on its colour "
                              "(both halves share one)", at)


def _labelled_png(img: np.ndarray, title: str, labels) -> bytes:
    """The render ``img`` with a title and ``(u, v, text, part, ha)`` labels (pixels from the top left) on
    boxes of the part's colour, as a PNG of the render's size (no timestamp metadata)."""
    import io

    from matplotlib.figure import Figure

    h, w = img.shape[:2]
    fig = Figure(figsize=(w / 100, h / 100), dpi=100)
    ax = fig.add_axes((0, 0, 1, 1))
    ax.imshow(img, interpolation="none")
    ax.set_xlim(0, w)
    ax.set_ylim(h, 0)
    ax.axis("off")
    ax.text(8, 8, title, fontsize=12, va="top", ha="left")
    for u, v, text, part, ha in labels:
        ax.text(u, v, text, fontsize=13, ha=ha, va="center", weight="bold",
                bbox=dict(facecolor=part_colour(part), edgecolor="0.3", boxstyle="round,pad=0.35"))
    buf = io.BytesIO()
    fig.savefig(buf, format="png", dpi=100, metadata={"Software": None})
    return buf.getvalue()
