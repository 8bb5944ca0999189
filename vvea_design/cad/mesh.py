"""Tessellation of build123d solids into trimesh meshes (shared by export, renders and the GLB)."""

from __future__ import annotations

import numpy as np
import trimesh
from build123d import Shape

__all__ = ["to_mesh"]


def to_mesh(shape: Shape, tolerance_mm: float = 0.05, angular_tolerance_rad: float = 0.25) -> trimesh.Trimesh:
    """Tessellate ``shape`` into a merged triangle mesh (mm).

    Parameters
    ----------
    shape : Shape
        Any build123d shape.
    tolerance_mm : float
        Linear deflection, mm.
    angular_tolerance_rad : float
        Angular deflection, rad.

    Returns
    -------
    trimesh.Trimesh
        Vertices merged to 1e-6 mm, degenerate faces removed (watertight for a valid solid).
    """
    verts, tris = shape.tessellate(tolerance_mm, angular_tolerance_rad)
    v = np.array([(p.X, p.Y, p.Z) for p in verts], dtype=np.float64)
    f = np.array(tris, dtype=np.int64).reshape(-1, 3)
    mesh = trimesh.Trimesh(v, f, process=False)
    mesh.merge_vertices(digits_vertex=6)
    mesh.update_faces(mesh.nondegenerate_faces())
    mesh.remove_unreferenced_vertices()
    return mesh
