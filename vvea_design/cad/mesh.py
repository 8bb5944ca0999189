"""Tessellation of build123d solids into trimesh meshes (shared by export, renders and the GLB)."""

from __future__ import annotations

import numpy as np
import trimesh
from build123d import Shape

__all__ = ["to_mesh"]


def _tessellate(shape: Shape, tolerance: float, angular_tolerance: float) -> tuple[np.ndarray, np.ndarray]:
    """``Shape.tessellate`` as arrays: the same nodes in the same order and the same triangles (bit for bit),
    without build123d's one ``Vector`` per node and one tuple per triangle (most of the time it took)."""
    from OCP.BRep import BRep_Tool
    from OCP.TopAbs import TopAbs_Orientation
    from OCP.TopLoc import TopLoc_Location

    if shape.wrapped is None:
        raise ValueError("Cannot tessellate an empty shape")
    shape.mesh(tolerance, angular_tolerance)  # meshes only if there is no fine enough triangulation yet
    verts, tris = [], []
    offset = 0
    for face in shape.faces():
        loc = TopLoc_Location()
        poly = BRep_Tool.Triangulation_s(face.wrapped, loc)
        n = poly.NbNodes()
        node = poly.Node
        if loc.IsIdentity():  # gp_Pnt.Transformed by the identity is a no-op
            verts += [node(i).Coord() for i in range(1, n + 1)]
        else:
            trsf = loc.Transformation()
            verts += [node(i).Transformed(trsf).Coord() for i in range(1, n + 1)]
        tri = poly.Triangle  # by index: iterating poly.Triangles() is ~5x slower in OCP
        t = np.array([tri(i).Get() for i in range(1, poly.NbTriangles() + 1)], dtype=np.int64).reshape(-1, 3)
        t += offset - 1
        if face.wrapped.Orientation() == TopAbs_Orientation.TopAbs_REVERSED:
            t = t[:, [0, 2, 1]]
        tris.append(t)
        offset += n
    v = np.array(verts, dtype=np.float64).reshape(-1, 3)
    f = np.concatenate(tris) if tris else np.zeros((0, 3), dtype=np.int64)
    return v, f


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
    v, f = _tessellate(shape, tolerance_mm, angular_tolerance_rad)
    mesh = trimesh.Trimesh(v, f, process=False)
    mesh.merge_vertices(digits_vertex=6)
    mesh.update_faces(mesh.nondegenerate_faces())
    mesh.remove_unreferenced_vertices()
    return mesh
