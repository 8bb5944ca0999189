"""One piece's FE model: its section meshed, its surface labelled, its joint's reaction, solved per load case.

The loads are statically right by construction: the pressures on the wetted surface have an axial resultant
``F`` (N); the piece's joint takes ``-F`` as a uniform axial traction over its bearing face (:class:`Bearing`:
the tie-rod nuts' annulus, a retaining ring's seat, a thread's flanks, the rod's section), the face on the
side that can push the piece the way it must be pushed (over the face's extent exactly, whatever the mesh:
the traction is cut off at the bearing's box inside a facet). One node on a bearing is pinned axially (the only
rigid motion of an axisymmetric body); it carries round-off only (:attr:`CaseSolution.pin_reaction_N`).

Lengths mm, pressures and stresses MPa, forces N.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from skfem import MeshTri2

from ..materials.structural import Material
from .elasticity import AxiProblem, AxiSolution
from .loads import LoadCase
from .section import MeridianSection
from .surroundings import Surroundings

__all__ = ["Bearing", "PieceModel", "CaseSolution", "boundary_facets", "nearest_vertex"]


@dataclass(frozen=True)
class Bearing:
    """Where a piece's joint takes its axial reaction: the boundary facets in a box of the (r, z) plane whose
    outward normal is axial (``faces = "axial"``) or radial (``"radial"``: a thread's flanks smeared)."""

    what: str  #: e.g. "tie-rod nuts on the top face, smeared over the rod circle"
    r_mm: tuple[float, float]
    z_mm: tuple[float, float]
    pushes: int  #: +1 the joint can push the piece up (+z), -1 down, 0 either way
    faces: str = "axial"
    cut: bool = False  #: a cut through the material (the rod's section): no pressure on it

    def select(self, mid: np.ndarray, normal: np.ndarray, ends: tuple[np.ndarray, np.ndarray] | None = None) -> np.ndarray:
        """Which boundary facets bear (bool mask): those that reach into the box, with the right orientation.

        Parameters
        ----------
        mid : ndarray
            ``(2, n)`` facet midpoints, mm.
        normal : ndarray
            ``(2, n)`` outward unit normals, dimensionless.
        ends : tuple of ndarray, optional
            The facets' end points (``(2, n)`` each, mm): a facet overlapping the box counts (a coarse mesh's
            facet may straddle the box's edge); without them the midpoint must be inside.

        Returns
        -------
        ndarray of bool
            The facets in the box with the right orientation (dimensionless flags).
        """
        tol = 1e-6
        if ends is None:
            lo, hi = mid, mid
        else:
            lo, hi = np.minimum(*ends), np.maximum(*ends)
        box = ((hi[0] >= self.r_mm[0] - tol) & (lo[0] <= self.r_mm[1] + tol)
               & (hi[1] >= self.z_mm[0] - tol) & (lo[1] <= self.z_mm[1] + tol))
        if ends is not None:  # a facet touching the box at one end only does not bear
            overlap_r = np.minimum(hi[0], self.r_mm[1]) - np.maximum(lo[0], self.r_mm[0])
            overlap_z = np.minimum(hi[1], self.z_mm[1]) - np.maximum(lo[1], self.z_mm[0])
            box &= (overlap_r > tol) | (overlap_z > tol)
        orient = np.abs(normal[1]) > 0.7 if self.faces == "axial" else np.abs(normal[0]) > 0.3
        return box & orient


def boundary_facets(mesh: MeshTri2) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """Boundary facets with their midpoints (the edge nodes, on curves), outward normals and lengths.

    Parameters
    ----------
    mesh : MeshTri2
        A section's mesh, mm.

    Returns
    -------
    tuple of ndarray
        Facet indices, midpoints ``(2, n)`` (mm), outward unit normals ``(2, n)`` of the chords, chord
        lengths (mm).
    """
    bf = mesh.boundary_facets()
    a, b = mesh.p[:, mesh.facets[0, bf]], mesh.p[:, mesh.facets[1, bf]]
    mid = mesh.doflocs[:, mesh.nvertices + bf]  # the facet's edge node (on the curve)
    t = b - a
    length = np.hypot(*t)
    n = np.vstack([t[1], -t[0]]) / length
    # orient outward: away from the third vertex of the one element on the facet
    el = mesh.f2t[0, bf]
    tv = mesh.t[:3, el]
    third = mesh.p[:, tv].sum(axis=1) - a - b  # the sum of the 3 vertices minus the facet's two
    flip = np.einsum("ij,ij->j", n, third - a) > 0
    n[:, flip] *= -1
    return bf, mid, n, length


def nearest_vertex(mesh: MeshTri2, r_mm: float, z_mm: float) -> int:
    """The mesh vertex (not an edge node) nearest a point.

    Parameters
    ----------
    mesh : MeshTri2
        A section's mesh, mm.
    r_mm, z_mm : float
        The point, mm.

    Returns
    -------
    int
        Vertex index (into ``mesh.p[:, :mesh.nvertices]``).
    """
    v = mesh.p[:, :mesh.nvertices]
    return int(np.argmin(np.hypot(v[0] - r_mm, v[1] - z_mm)))


@dataclass(frozen=True)
class CaseSolution:
    """A piece solved under one load case."""

    case: LoadCase
    solution: AxiSolution
    media: np.ndarray  #: medium of each boundary facet (:mod:`~vvea_design.structure.surroundings`)
    pressure_MPa: np.ndarray  #: gauge pressure on each boundary facet
    bearing: Bearing | None  #: the joint face that took the reaction (None: no net axial load)
    reaction_N: float  #: axial force the joint puts on the piece, N
    pin_reaction_N: float  #: what the pinned node carried, N (round-off)


class PieceModel:
    """A piece meshed and ready to solve: its section, material, joint faces and what surrounds it.

    Parameters
    ----------
    name : str
        The piece (CAD part name).
    section : MeridianSection
        Its meridian section, mm.
    mesh : MeshTri2
        The section's quadratic mesh, mm.
    material : Material
        Its material (E, nu and yield in MPa).
    bearings : tuple of Bearing
        Where its joint can take the axial reaction (the first that can push the right way is used).
    surroundings : callable
        ``surroundings(x_mm) -> Surroundings``: the spaces round it at a piston displacement.
    """

    def __init__(self, name: str, section: MeridianSection, mesh: MeshTri2, material: Material,
                 bearings: tuple[Bearing, ...], surroundings) -> None:
        self.name, self.section, self.mesh, self.material = name, section, mesh, material
        self.bearings, self.surroundings = tuple(bearings), surroundings
        self.facets, self.mid, self.normal, self.length = boundary_facets(mesh)
        ends = (mesh.p[:, mesh.facets[0, self.facets]], mesh.p[:, mesh.facets[1, self.facets]])
        masks = [b.select(self.mid, self.normal, ends) for b in self.bearings]
        #: the joint faces the drawn section does not have (e.g. a thread the CAD does not draw yet): not used
        self.missing_bearings = tuple(b for b, m in zip(self.bearings, masks) if not m.any())
        self.bearings = tuple(b for b, m in zip(self.bearings, masks) if m.any())
        self.bearing_masks = [m for m in masks if m.any()]
        self._ends = ends
        self.problem = AxiProblem(mesh, material.youngs_modulus_MPa, material.poisson, self._pin_node())
        self._probe_eps = min(0.02, 0.1 * float(np.median(self.length)))

    def _pin_node(self) -> int:
        """A vertex of the first bearing face (any vertex when the piece has none)."""
        if not self.bearings:
            return int(np.argmin(self.mesh.p[1, :self.mesh.nvertices]))
        f = self.facets[self.bearing_masks[0]][0]
        return int(self.mesh.facets[0, f])

    def media(self, x_mm: float) -> np.ndarray:
        """The medium outside each boundary facet at a piston displacement.

        A cylindrical (radially facing) face in contact with another piece is a joint's unsealed fit: it takes
        the joint's gap pressure (:meth:`~vvea_design.structure.surroundings.Surroundings.joint_gap`); an
        end face in contact takes none (the joint's reaction loads it).

        Parameters
        ----------
        x_mm : float
            Piston displacement, mm.

        Returns
        -------
        ndarray of str
            One label per boundary facet.
        """
        sur: Surroundings = self.surroundings(x_mm)
        p = self.mid + self._probe_eps * self.normal
        media = sur.medium(p[0], p[1])
        # a cylindrical face on another piece is not sealed there: the joint's gas or fluid gets in up to its seal
        radial = (media == "contact") & (np.abs(self.normal[0]) > 0.7)
        media[radial] = sur.joint_gap(p[1][radial])
        media[radial & sur.beyond_seals(p[0], p[1])] = "air"  # the static seal holds it back
        media[radial & sur.annulus_fit(p[0], p[1])] = "chamber_2"  # a fit in the outer bore: the annulus' gas
        return media

    def drawn(self, faces) -> Bearing | None:
        """The first of some joint faces the section has (None: none of them).

        Parameters
        ----------
        faces : sequence of Bearing
            Joint faces in order of preference.

        Returns
        -------
        Bearing or None
            The first that selects a boundary facet.
        """
        return next((b for b in faces if b.select(self.mid, self.normal, self._ends).any()), None)

    def _traction(self, b: Bearing, force_N: float) -> np.ndarray:
        """Load vector of an axial force spread uniformly over a bearing face (cut off at its box), N."""
        m = b.select(self.mid, self.normal, self._ends)
        if not m.any():
            raise ValueError(f"{self.name}: no boundary face for {b.what} (r {b.r_mm}, z {b.z_mm})")
        box = (*b.r_mm, *b.z_mm)
        prob = self.problem
        unit = prob.axial_force_N(prob.load_vector(self.facets[m], np.zeros(m.sum()), np.ones(m.sum()), box))
        return prob.load_vector(self.facets[m], np.zeros(m.sum()), np.full(m.sum(), force_N / unit), box)

    def solve(self, case: LoadCase, applied: tuple = ()) -> CaseSolution:
        """Solve the piece under a load case: the pressures on its surface, the reaction at its joint.

        Parameters
        ----------
        case : LoadCase
            Pressures (MPa) and the piston's displacement (mm).
        applied : tuple of (Bearing, float)
            Axial forces other pieces put on this one through a joint face (a tube's thread carrying the end
            piece's load), N (> 0 up); the reaction balances them with the pressures.

        Returns
        -------
        CaseSolution
            The solution and what loaded it.

        Raises
        ------
        ValueError
            If the loads push the piece along the axis and none of its joint faces can push back.
        """
        sur = self.surroundings(case.x_mm)
        media = self.media(case.x_mm)
        p = sur.pressures(media, case.gauge_MPa())
        for b, m in zip(self.bearings, self.bearing_masks):
            if b.cut:
                p = np.where(m, 0.0, p)
        prob = self.problem
        f = prob.load_vector(self.facets, p, np.zeros_like(p))
        for b, force in applied:
            if force:
                f = f + self._traction(b, force)
        F = prob.axial_force_N(f)
        bearing = None
        scale = max(1.0, float(np.abs(f).sum()))
        if abs(F) > 1e-9 * scale:
            need = -1 if F > 0 else 1  # the joint must push the opposite way
            bearing = next((b for b in self.bearings if b.pushes in (0, need)), None)
            if bearing is None:
                raise ValueError(f"{self.name} ({case.name}): the loads push it {'up' if F > 0 else 'down'} "
                                 f"with {abs(F):.0f} N and no joint face can take that")
            f = f + self._traction(bearing, -F)
        sol = prob.solve(f)
        return CaseSolution(case, sol, media, p, bearing, -F if bearing is not None else 0.0, sol.pin_reaction_N)
