"""Off-screen PNG renders of the CAD set (pyvista / VTK, no display needed).

Headless: with no ``DISPLAY`` this module selects VTK's EGL render window
(``VTK_DEFAULT_OPENGL_WINDOW=vtkEGLRenderWindow``) before VTK is imported;
Debian needs ``libegl1 libegl-mesa0 libgl1-mesa-dri`` (Mesa llvmpipe).

* :func:`render_assembly_cutaway` -- the unit cut on the meridian plane at
  x = 0 and x = travel side by side; chamber-1 gas blue, chamber-2 gas red
  (the paper's Fig. 2 colours; chamber 2 drawn as the equal-volume sleeve).
* :func:`render_mould_open` -- the two mould halves laid open, parting faces
  up, with the core and the cast bladder between them.
"""

from __future__ import annotations

import os

import numpy as np

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


def _gas_meshes(model, x_mm: float):
    from ._shapes import ring
    from .mesh import to_mesh

    lay = model.layout
    gas = model.solids_at(x_mm, "gas")
    fluid = ring(lay.r_rod, lay.r_piston, lay.z_base_top, lay.z_piston_bottom(x_mm))
    return {name: to_mesh(s, 0.1, 0.2) for name, s in gas.items()}, to_mesh(fluid, 0.1, 0.2)


def render_assembly_cutaway(model, meshes: dict) -> bytes:
    """PNG: meridian cut-away of the unit at x = 0 (left) and x = travel (right).

    Parameters
    ----------
    model : CadModel
        The built CAD set.
    meshes : dict
        Tessellated parts by name (``piston_at_travel`` included).
    """
    from .registry import FLUID_COLOUR, get_part, parts_in

    pv = _pv()
    d = model.design
    travel = d.fixed.travel_mm
    z_lo = model.layout.z_piston_bottom(travel) - d.rod_length_mm
    z_hi = d.housing_length_mm
    zc = 0.5 * (z_lo + z_hi)
    pl = pv.Plotter(off_screen=True, shape=(1, 2), window_size=WINDOW_SIZE, border=False)
    for col, x in enumerate((0.0, travel)):
        pl.subplot(0, col)
        pl.set_background("white")
        for part in parts_in("assembly"):
            key = "piston_at_travel" if (part.name == "piston" and x) else part.name
            pl.add_mesh(_cut(_poly(meshes[key])), color=part.colour, smooth_shading=False)
        gas, fluid = _gas_meshes(model, x)
        for name, mesh in gas.items():
            pl.add_mesh(_cut(_poly(mesh)), color=get_part(name).colour, opacity=0.55)
        pl.add_mesh(_cut(_poly(fluid)), color=FLUID_COLOUR, opacity=0.55)
        pl.add_text(f"x = {x:g} mm  (blue: chamber 1, red: chamber 2, green: fluid column)",
                    font_size=10, color="black")
        pl.camera.parallel_projection = True
        pl.camera_position = [(0.0, -1000.0, zc), (0.0, 0.0, zc), (0.0, 0.0, 1.0)]
        pl.camera.parallel_scale = 0.55 * (z_hi - z_lo)
    return _png(pl)


def render_mould_open(model, meshes: dict) -> bytes:
    """PNG: the mould laid open -- half B, core with the cast bladder, half A (turned), parting faces up."""
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
    pl.add_mesh(hb, color=(0.55, 0.75, 0.95))
    pl.add_mesh(ha, color=(0.55, 0.75, 0.95))
    pl.add_mesh(core, color=(0.85, 0.85, 0.85))
    pl.add_mesh(cav, color=(0.95, 0.75, 0.20), opacity=0.6)
    pl.add_text("bladder mould: half B | core + cast bladder | half A (parting faces up)", font_size=11, color="black")
    pl.camera_position = [(0.0, 500.0, 420.0), (0.0, 0.0, 0.0), (0.0, 0.0, 1.0)]
    pl.reset_camera()
    return _png(pl)
