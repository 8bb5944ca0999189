"""Quadratic triangle meshes of meridian sections with gmsh (its OpenCASCADE kernel reads the section as BREP).

The element size is set per point by a size callback: a global size a fraction of the section's mean wall
(:func:`mean_wall_mm`, ``2 A / P``: the thickness of a thin-walled section), refined towards every re-entrant
corner (grooves, steps, fillets: where stress concentrates) to a size that resolves the corner's radius, and
growing linearly away from it. The mesh is second order (6-node triangles, edge nodes on the curved
boundary) and is returned as a scikit-fem :class:`~skfem.MeshTri2`, triangles counter-clockwise.

Lengths in mm.
"""

from __future__ import annotations

import tempfile
from dataclasses import dataclass
from pathlib import Path

import numpy as np
from build123d import export_brep
from skfem import MeshTri2

from .section import MeridianSection

__all__ = ["MeshSpec", "mesh_section", "mean_wall_mm"]

_GMSH_TRIANGLE6 = 9


@dataclass(frozen=True)
class MeshSpec:
    """How fine a section is meshed (lengths relative to the section's mean wall and corner radii).

    ``elements_per_wall`` sets the global size ``mean_wall / elements_per_wall`` (never above
    ``max_size_mm``); at a re-entrant corner of radius ``rho`` the size is ``rho / elements_per_radius``
    (a sharp corner: the global size / 8), growing by ``growth`` mm per mm of distance.
    """

    elements_per_wall: float = 3.0
    elements_per_radius: float = 3.0
    growth: float = 0.3
    max_size_mm: float = 2.5
    min_size_mm: float = 0.02

    def sizes(self, section: MeridianSection) -> tuple[float, list[tuple[float, float, float]]]:
        """The global size and each corner's ``(r, z, size)``, mm.

        Parameters
        ----------
        section : MeridianSection
            The section meshed.

        Returns
        -------
        tuple
            Global size (mm) and the refined corners ``(r_mm, z_mm, size_mm)``.
        """
        h = min(self.max_size_mm, mean_wall_mm(section) / self.elements_per_wall)
        pts = []
        for c in section.corners:
            hc = c.radius_mm / self.elements_per_radius if c.radius_mm > 0 else h / 8
            pts.append((c.r_mm, c.z_mm, max(self.min_size_mm, min(h, hc))))
        return h, pts


def mean_wall_mm(section: MeridianSection) -> float:
    """Mean wall of a section, ``2 A / P`` (the thickness of a thin strip), mm.

    Parameters
    ----------
    section : MeridianSection
        The section.

    Returns
    -------
    float
        ``2 x area / perimeter``, mm.
    """
    perimeter = sum(e.length for e in section.face.edges())
    return 2 * section.area_mm2 / perimeter


def _gmsh():
    import gmsh

    if not gmsh.isInitialized():
        gmsh.initialize(readConfigFiles=False, interruptible=False)
    gmsh.option.setNumber("General.Terminal", 0)
    gmsh.option.setNumber("General.Verbosity", 1)
    return gmsh


def mesh_section(section: MeridianSection, spec: MeshSpec = MeshSpec()) -> MeshTri2:
    """Mesh a section with quadratic triangles, refined at its re-entrant corners.

    Parameters
    ----------
    section : MeridianSection
        The region (x = r, y = z), mm.
    spec : MeshSpec
        Sizes.

    Returns
    -------
    MeshTri2
        Quadratic triangles (counter-clockwise), nodes in mm.

    Raises
    ------
    RuntimeError
        If gmsh makes no triangles.
    """
    gmsh = _gmsh()
    h, corners = spec.sizes(section)
    name = f"section_{section.name}"
    with tempfile.TemporaryDirectory(prefix="vvea_fe_") as tmp:
        path = Path(tmp) / "section.brep"
        export_brep(section.face, str(path))
        gmsh.model.add(name)
        try:
            gmsh.model.occ.importShapes(str(path))
            gmsh.model.occ.synchronize()
            for opt, val in (("Mesh.MeshSizeExtendFromBoundary", 0), ("Mesh.MeshSizeFromPoints", 0),
                             ("Mesh.MeshSizeFromCurvature", 0), ("Mesh.MeshSizeMax", h),
                             ("Mesh.MeshSizeMin", spec.min_size_mm), ("Mesh.Algorithm", 6),
                             ("Mesh.ElementOrder", 2), ("Mesh.SecondOrderLinear", 0)):
                gmsh.option.setNumber(opt, val)
            _corner_fields(gmsh, h, corners, spec.growth)
            gmsh.model.mesh.generate(2)
            tags, coords, _ = gmsh.model.mesh.getNodes()
            _, enodes = gmsh.model.mesh.getElementsByType(_GMSH_TRIANGLE6)
        finally:
            gmsh.model.remove()
    if len(enodes) == 0:
        raise RuntimeError(f"{section.name}: gmsh made no triangles")
    index = np.full(int(tags.max()) + 1, -1, dtype=np.int64)
    index[tags.astype(np.int64)] = np.arange(len(tags))
    t = index[np.asarray(enodes, dtype=np.int64)].reshape(-1, 6).T
    xy = coords.reshape(-1, 3)[:, :2].T
    used = np.unique(t)
    remap = np.full(xy.shape[1], -1, dtype=np.int64)
    remap[used] = np.arange(used.size)
    p, t = xy[:, used], remap[t]
    # counter-clockwise: swap vertices 1 and 2 (and the edge nodes 0-1 and 2-0) where the area is negative
    a = ((p[0, t[1]] - p[0, t[0]]) * (p[1, t[2]] - p[1, t[0]]) - (p[0, t[2]] - p[0, t[0]]) * (p[1, t[1]] - p[1, t[0]]))
    neg = a < 0
    t[:, neg] = t[[0, 2, 1, 5, 4, 3]][:, neg]
    p[0] = np.maximum(p[0], 0.0)  # r >= 0 (round-off on the axis)
    p[0, np.abs(p[0]) < 1e-9] = 0.0
    return MeshTri2(p, t)


def _corner_fields(gmsh, h: float, corners, growth: float) -> None:
    """A background size field: ``h`` everywhere, ``h_c + growth d`` within reach of each corner (gmsh fields:
    a Distance to a free point at the corner, a Threshold on it, the Min of them all)."""
    if not corners:
        return
    fields = []
    for r, z, hc in corners:
        pt = gmsh.model.occ.addPoint(r, z, 0.0)
        gmsh.model.occ.synchronize()
        dist = gmsh.model.mesh.field.add("Distance")
        gmsh.model.mesh.field.setNumbers(dist, "PointsList", [pt])
        thr = gmsh.model.mesh.field.add("Threshold")
        gmsh.model.mesh.field.setNumber(thr, "InField", dist)
        gmsh.model.mesh.field.setNumber(thr, "SizeMin", hc)
        gmsh.model.mesh.field.setNumber(thr, "SizeMax", h)
        gmsh.model.mesh.field.setNumber(thr, "DistMin", 0.0)
        gmsh.model.mesh.field.setNumber(thr, "DistMax", max((h - hc) / growth, 1e-6))
        fields.append(thr)
    mn = gmsh.model.mesh.field.add("Min")
    gmsh.model.mesh.field.setNumbers(mn, "FieldsList", fields)
    gmsh.model.mesh.field.setAsBackgroundMesh(mn)


def element_size_mm(mesh: MeshTri2) -> float:
    """Median edge length of a mesh's triangles (vertex to vertex), mm.

    Parameters
    ----------
    mesh : MeshTri2
        A mesh.

    Returns
    -------
    float
        The median straight edge length, mm.
    """
    e = mesh.facets
    return float(np.median(np.hypot(*(mesh.p[:, e[0]] - mesh.p[:, e[1]]))))


__all__ += ["element_size_mm"]
