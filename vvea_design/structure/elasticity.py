"""Axisymmetric linear elasticity on a meridian section with scikit-fem: assemble, load, solve, recover stress.

The body is the section revolved about the axis (``x[0] = r``, ``x[1] = z``); the displacement is
``u = (u_r, u_z)`` in quadratic Lagrange elements (``ElementVector(ElementTriP2)``) on a quadratic
(curved-edged) triangle mesh. The strains are

``e_rr = du_r/dr``, ``e_zz = du_z/dz``, ``e_tt = u_r / r``, ``g_rz = du_r/dz + du_z/dr``

and the weak form is the virtual work over the revolved body, ``∫ σ : ε(v) 2π r dr dz = ∫_Γ t · v 2π r ds``
(written out as decorated scikit-fem forms below; no plane-strain model is reused). Loads are a pressure per
boundary facet (traction ``-p n``, with the facet's own normal at each quadrature point, so curved edges are
loaded right) and an axial traction per boundary facet (the joints' reactions). Supports: ``u_r = 0`` on the
axis, ``u_z = 0`` at one pinned node (the only rigid motion left: the reactions are applied as tractions that
balance the loads, so the pin carries only round-off, which :class:`AxiSolution` reports).

Stress is evaluated at each element's six nodes and averaged over the elements meeting at a node. Units: mm,
MPa, N.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from scipy.sparse import coo_matrix
from skfem import Basis, BilinearForm, ElementTriP2, ElementVector, FacetBasis, LinearForm, MeshTri1, MeshTri2
from skfem.mapping import MappingIsoparametric
from skfem.helpers import grad

__all__ = ["AxiProblem", "AxiSolution", "RobustIsoparametric", "solve_axisymmetric", "von_mises", "tresca", "principal_stresses", "probe_matrix"]

TWO_PI = 2 * math.pi


def _lame(E: float, nu: float) -> tuple[float, float]:
    return E * nu / ((1 + nu) * (1 - 2 * nu)), E / (2 * (1 + nu))


def _strains(u, r):
    """(e_rr, e_zz, e_tt, g_rz) of a vector field at quadrature points (r > 0 there)."""
    g = grad(u)
    return g[0, 0], g[1, 1], u[0] / r, g[0, 1] + g[1, 0]


def _stiffness_form(E: float, nu: float) -> BilinearForm:
    lam, mu = _lame(E, nu)

    @BilinearForm
    def stiffness(u, v, w):
        r = w.x[0]
        err, ezz, ett, grz = _strains(u, r)
        vrr, vzz, vtt, vrz = _strains(v, r)
        tr = err + ezz + ett
        return (((lam * tr + 2 * mu * err) * vrr + (lam * tr + 2 * mu * ezz) * vzz
                 + (lam * tr + 2 * mu * ett) * vtt + mu * grz * vrz) * TWO_PI * r)

    return stiffness


@LinearForm
def _boundary_load(v, w):
    """Pressure ``p`` (along -n) and axial traction ``tz`` on boundary facets, over the revolved surface."""
    tr = -w.p * w.n[0]
    tz = -w.p * w.n[1] + w.tz
    return (tr * v[0] + tz * v[1]) * TWO_PI * w.x[0]


def principal_stresses(s_rr, s_zz, s_tt, s_rz) -> np.ndarray:
    """The three principal stresses of an axisymmetric stress state, MPa.

    Parameters
    ----------
    s_rr, s_zz, s_tt, s_rz : ndarray
        Radial, axial, hoop and shear stress, MPa (arrays of one shape).

    Returns
    -------
    ndarray
        Shape ``(3, ...)``: the in-plane pair and the hoop stress, MPa (unsorted).
    """
    c = 0.5 * (s_rr + s_zz)
    rad = np.sqrt((0.5 * (s_rr - s_zz)) ** 2 + s_rz**2)
    return np.stack([c + rad, c - rad, s_tt])


def von_mises(s_rr, s_zz, s_tt, s_rz) -> np.ndarray:
    """Von Mises equivalent stress, MPa.

    Parameters
    ----------
    s_rr, s_zz, s_tt, s_rz : ndarray
        Radial, axial, hoop and shear stress, MPa.

    Returns
    -------
    ndarray
        ``sqrt(((s_rr - s_zz)^2 + (s_zz - s_tt)^2 + (s_tt - s_rr)^2) / 2 + 3 s_rz^2)``, MPa.
    """
    return np.sqrt(0.5 * ((s_rr - s_zz) ** 2 + (s_zz - s_tt) ** 2 + (s_tt - s_rr) ** 2) + 3 * s_rz**2)


def tresca(s_rr, s_zz, s_tt, s_rz) -> np.ndarray:
    """Tresca equivalent stress (largest principal difference), MPa.

    Parameters
    ----------
    s_rr, s_zz, s_tt, s_rz : ndarray
        Radial, axial, hoop and shear stress, MPa.

    Returns
    -------
    ndarray
        ``max(s1, s2, s3) - min(s1, s2, s3)``, MPa.
    """
    p = principal_stresses(s_rr, s_zz, s_tt, s_rz)
    return p.max(axis=0) - p.min(axis=0)


def probe_matrix(basis: Basis, points_mm: np.ndarray):
    """The matrix that evaluates a scalar P2 field of ``basis`` at points of a curved quadratic mesh.

    scikit-fem's own ``probes`` has no element finder for quadratic meshes; the cells are found with the
    straight-edged mesh of the same vertices and the curved (isoparametric) mapping.

    Parameters
    ----------
    basis : Basis
        A scalar basis on a :class:`~skfem.MeshTri2`.
    points_mm : ndarray
        ``(2, n)`` points inside the section, mm.

    Returns
    -------
    scipy.sparse.coo_matrix
        ``(n, basis.N)``: field values at the points = matrix @ nodal values.
    """
    m = basis.mesh
    finder = MeshTri1(np.ascontiguousarray(m.p[:, :m.nvertices]), m.t).element_finder()  # straight cells find; the curved mapping maps
    x = np.asarray(points_mm, dtype=float)
    cells = finder(*x)
    mapping = basis.mapping if isinstance(basis.mapping, RobustIsoparametric) else RobustIsoparametric(m)
    pts = mapping.invF(x[:, :, np.newaxis], tind=cells)
    phis = np.array([basis.elem.gbasis(basis.mapping, pts, k, tind=cells)[0] for k in range(basis.Nbfun)]).flatten()
    rows = np.tile(np.arange(x.shape[1], dtype=np.int32), basis.Nbfun)
    cols = basis.element_dofs[:, cells].flatten()
    return coo_matrix((phis, (rows, cols)), shape=(x.shape[1], basis.N)).tocsr()


class RobustIsoparametric(MappingIsoparametric):
    """scikit-fem's isoparametric mapping with an inverse that starts from the straight cell's.

    scikit-fem's own inverse starts every Newton iteration at the reference triangle's centre and clips to the
    unit square, which stalls for points on a strongly curved edge (a fillet meshed with few elements). Starting
    from the straight cell's affine inverse converges in two or three steps; a point that still does not
    converge keeps the affine inverse (it is on a straight-enough cell).

    Parameters
    ----------
    mesh : MeshTri2
        A quadratic triangle mesh.
    """

    def __init__(self, mesh: MeshTri2) -> None:
        super().__init__(mesh, mesh.elem(), getattr(mesh, "bndelem", None))

    def _affine_inverse(self, x: np.ndarray, tind) -> np.ndarray:
        t = self.mesh.t if tind is None else self.mesh.t[:, tind]
        p = self.mesh.p
        v0, v1, v2 = (p[:, t[k]] for k in range(3))  # (2, n)
        a, b, c, d = v1[0] - v0[0], v2[0] - v0[0], v1[1] - v0[1], v2[1] - v0[1]
        det = a * d - b * c
        dx, dy = x[0] - v0[0][:, None], x[1] - v0[1][:, None]
        return np.array([(d[:, None] * dx - b[:, None] * dy) / det[:, None],
                         (-c[:, None] * dx + a[:, None] * dy) / det[:, None]])

    def invF(self, x, tind=None, newton_max_iters=25, newton_tol=1e-12):
        """Reference coordinates of global points ``x`` (``(2, n_cells, n_points)``) in cells ``tind``.

        Parameters
        ----------
        x : ndarray
            Global points, mm, one row of points per cell.
        tind : ndarray, optional
            The cells (indices, dimensionless; all when None).
        newton_max_iters : int
            Newton steps at most (a count).
        newton_tol : float
            Step size that ends the iteration (reference coordinates, dimensionless).

        Returns
        -------
        ndarray
            Reference coordinates, same shape as ``x``.
        """
        X0 = self._affine_inverse(x, tind)
        X = X0.copy()
        for _ in range(newton_max_iters):
            dX = np.einsum("ijkl,jkl->ikl", self.invDF(X, tind), x - self.F(X, tind))
            X = X + dX
            if np.abs(dX).max() < newton_tol:
                return X
        bad = np.abs(self.F(X, tind) - x).max(axis=(0, 2)) > 1e-8
        X[:, bad] = X0[:, bad]
        return X


@dataclass(frozen=True)
class AxiSolution:
    """A solved axisymmetric problem: displacement and stress at the quadratic mesh's nodes.

    ``nodes_mm`` are the P2 nodes (vertices and edge midpoints), ``(2, n)``: r and z in mm. The stress
    components are nodal averages of the element values, MPa; ``elements`` are the six node indices of each
    triangle (vertices first), for plotting.
    """

    nodes_mm: np.ndarray  #: (2, n) r, z of every node, mm
    elements: np.ndarray  #: (6, n_elements) node indices of each quadratic triangle
    displacement_mm: np.ndarray  #: (2, n) u_r, u_z at the nodes, mm
    s_rr_MPa: np.ndarray
    s_zz_MPa: np.ndarray
    s_tt_MPa: np.ndarray  #: hoop stress
    s_rz_MPa: np.ndarray
    applied_axial_N: float  #: sum of the axial loads over the revolved surface (pressure and tractions), N
    pin_reaction_N: float  #: axial force the pinned node carries (round-off when the loads balance; 0 clamped), N
    basis: Basis  #: the scalar P2 basis of the nodes (probes, plotting)

    @property
    def von_mises_MPa(self) -> np.ndarray:
        """Von Mises stress at the nodes, MPa."""
        return von_mises(self.s_rr_MPa, self.s_zz_MPa, self.s_tt_MPa, self.s_rz_MPa)

    @property
    def tresca_MPa(self) -> np.ndarray:
        """Tresca stress at the nodes, MPa."""
        return tresca(self.s_rr_MPa, self.s_zz_MPa, self.s_tt_MPa, self.s_rz_MPa)

    def stress_at(self, r_mm, z_mm) -> dict[str, np.ndarray]:
        """The nodal stress field interpolated at points of the section.

        Parameters
        ----------
        r_mm, z_mm : array_like
            Points inside the section, mm.

        Returns
        -------
        dict of str to ndarray
            ``s_rr``, ``s_zz``, ``s_tt``, ``s_rz``, MPa, one value per point.
        """
        pts = np.vstack([np.atleast_1d(np.asarray(r_mm, dtype=float)), np.atleast_1d(np.asarray(z_mm, dtype=float))])
        P = probe_matrix(self.basis, pts)
        return {k: P @ getattr(self, f"{k}_MPa") for k in ("s_rr", "s_zz", "s_tt", "s_rz")}


class AxiProblem:
    """One section's stiffness, assembled and factorised once, solved for any number of boundary loads.

    Parameters
    ----------
    mesh : MeshTri2
        Quadratic triangles of the section, r >= 0 (mm).
    youngs_modulus_MPa, poisson : float
        Isotropic elastic constants (MPa, dimensionless).
    pin_node : int or None
        Vertex whose axial displacement is held (removes the rigid axial motion); None with ``clamped_facets``.
    axis_tol_mm : float
        Boundary facets within this of r = 0 are on the axis (``u_r = 0`` there), mm.
    clamped_facets : ndarray of int, optional
        Boundary facets held in both directions (a clamped edge: the verification's plates).
    """

    def __init__(self, mesh: MeshTri2, youngs_modulus_MPa: float, poisson: float, pin_node: int | None,
                 axis_tol_mm: float = 1e-7, clamped_facets=None) -> None:
        from scipy.sparse.linalg import splu

        if pin_node is None and clamped_facets is None:
            raise ValueError("AxiProblem: give a pin node or clamped facets (the axial rigid motion must be held)")
        self.mesh, self.E, self.nu = mesh, float(youngs_modulus_MPa), float(poisson)
        self.pin_node = None if pin_node is None else int(pin_node)
        self.element = ElementVector(ElementTriP2())
        self.mapping = RobustIsoparametric(mesh)
        self.basis = Basis(mesh, self.element, mapping=self.mapping, intorder=4)
        self.K = _stiffness_form(self.E, self.nu).assemble(self.basis).tocsr()
        bf = mesh.boundary_facets()
        on_axis = bf[np.all(mesh.p[0, mesh.facets[:, bf]] < axis_tol_mm, axis=0)]
        D = [] if self.pin_node is None else [self.basis.nodal_dofs[1, self.pin_node]]
        if on_axis.size:
            D = np.concatenate([self.basis.get_dofs(facets=on_axis).all("u^1"), D])
        if clamped_facets is not None and len(clamped_facets):
            D = np.concatenate([self.basis.get_dofs(facets=np.asarray(clamped_facets)).all(), D])
        self.D = np.unique(np.asarray(D, dtype=np.int64))
        self.free = np.setdiff1d(np.arange(self.basis.N), self.D)
        self._lu = splu(self.K[self.free][:, self.free].tocsc())

    def load_vector(self, facets, pressure_MPa, axial_traction_MPa, traction_box=None) -> np.ndarray:
        """The load vector of pressures (along -n) and axial tractions on boundary facets.

        Parameters
        ----------
        facets : ndarray of int
            Boundary facets loaded (indices into ``mesh.facets``, dimensionless).
        pressure_MPa, axial_traction_MPa : ndarray
            Per facet, MPa.
        traction_box : tuple of float, optional
            ``(r0, r1, z0, z1)``, mm: the axial traction acts only where the surface is inside it (a bearing
            face that ends inside a facet), so the loaded area is the box's, whatever the mesh.

        Returns
        -------
        ndarray
            Nodal forces, N (over the revolved surface).
        """
        facets = np.asarray(facets, dtype=np.int64)
        if not facets.size:
            return self.basis.zeros()
        fb = FacetBasis(self.mesh, self.element, mapping=self.mapping, facets=facets, intorder=4)
        nqp = fb.X.shape[-1]
        p = np.repeat(np.asarray(pressure_MPa, dtype=float)[:, None], nqp, axis=1)
        tz = np.repeat(np.asarray(axial_traction_MPa, dtype=float)[:, None], nqp, axis=1)
        if traction_box is not None:
            x = np.asarray(fb.global_coordinates())
            r0, r1, z0, z1 = traction_box
            tol = 1e-6
            tz = tz * ((x[0] >= r0 - tol) & (x[0] <= r1 + tol) & (x[1] >= z0 - tol) & (x[1] <= z1 + tol))
        return _boundary_load.assemble(fb, p=p, tz=tz)

    def axial_force_N(self, f: np.ndarray) -> float:
        """The axial resultant of a load vector, N.

        Parameters
        ----------
        f : ndarray
            Nodal forces (:meth:`load_vector`), N.

        Returns
        -------
        float
            Sum of the axial components, N.
        """
        b = self.basis
        return float(f[b.nodal_dofs[1]].sum() + f[b.facet_dofs[1]].sum())

    def solve(self, f: np.ndarray) -> "AxiSolution":
        """Displacement and stress under a load vector.

        Parameters
        ----------
        f : ndarray
            Nodal forces, N.

        Returns
        -------
        AxiSolution
            Displacements (mm) and stresses (MPa) at the nodes, the applied axial load and the pin's reaction (N).
        """
        u = np.zeros(self.basis.N)
        u[self.free] = self._lu.solve(f[self.free])
        residual = self.K @ u - f
        reaction = 0.0 if self.pin_node is None else float(residual[self.basis.nodal_dofs[1, self.pin_node]])
        return _recover(self.mesh, self.basis, u, self.E, self.nu, self.axial_force_N(f), reaction)


def solve_axisymmetric(mesh: MeshTri2, youngs_modulus_MPa: float, poisson: float, *, facets: np.ndarray,
                       pressure_MPa: np.ndarray, axial_traction_MPa: np.ndarray, pin_node: int,
                       axis_tol_mm: float = 1e-7) -> AxiSolution:
    """Solve the axisymmetric linear-elastic problem of a meridian section under boundary loads (one load).

    Parameters
    ----------
    mesh : MeshTri2
        Quadratic triangles of the section, r >= 0 (mm).
    youngs_modulus_MPa, poisson : float
        Isotropic elastic constants (MPa, dimensionless).
    facets : ndarray of int
        The loaded boundary facets (indices into ``mesh.facets``; a count-free list, dimensionless).
    pressure_MPa : ndarray
        Pressure on each of ``facets`` (acts along the inward normal), MPa.
    axial_traction_MPa : ndarray
        Axial traction (+z) on each of ``facets``, MPa (the joints' reactions).
    pin_node : int
        Vertex whose axial displacement is held (removes the rigid axial motion).
    axis_tol_mm : float
        Boundary facets within this of r = 0 are on the axis (``u_r = 0``), mm.

    Returns
    -------
    AxiSolution
        Displacements (mm) and stresses (MPa) at the nodes, the applied axial load and the pin's reaction (N).
    """
    prob = AxiProblem(mesh, youngs_modulus_MPa, poisson, pin_node, axis_tol_mm)
    return prob.solve(prob.load_vector(facets, pressure_MPa, axial_traction_MPa))


def _recover(mesh, basis, u, E, nu, applied, reaction) -> AxiSolution:
    """Stress at each element's six nodes, averaged at the nodes; displacement at the nodes."""
    ref = ElementTriP2.doflocs.T  # (2, 6) reference nodes, in the order of the scalar basis's element dofs
    sb = Basis(mesh, ElementTriP2(), mapping=basis.mapping, quadrature=(ref, np.ones(ref.shape[1]) / 6))
    vb = Basis(mesh, ElementVector(ElementTriP2()), mapping=basis.mapping, quadrature=(ref, np.ones(ref.shape[1]) / 6))
    uf = vb.interpolate(u)
    g = uf.grad  # (2, 2, n_el, 6)
    r = sb.mapping.F(ref)[0]  # (n_el, 6) r of each element node
    ur = np.asarray(uf)[0]
    on_axis = r < 1e-9
    err, ezz, grz = g[0, 0], g[1, 1], g[0, 1] + g[1, 0]
    ett = np.where(on_axis, err, ur / np.where(on_axis, 1.0, r))  # on the axis e_tt = e_rr (symmetry)
    lam, mu = _lame(E, nu)
    tr = err + ezz + ett
    comps = {"s_rr": lam * tr + 2 * mu * err, "s_zz": lam * tr + 2 * mu * ezz, "s_tt": lam * tr + 2 * mu * ett,
             "s_rz": mu * grz}
    dofs = sb.element_dofs  # (6, n_el) global node of each element node
    n = sb.N
    count = np.bincount(dofs.ravel(), minlength=n).astype(float)
    nodal = {k: np.bincount(dofs.ravel(), weights=v.T.ravel(), minlength=n) / count for k, v in comps.items()}
    disp = np.vstack([u[basis.nodal_dofs[0]], u[basis.nodal_dofs[1]]])
    disp_edges = np.vstack([u[basis.facet_dofs[0]], u[basis.facet_dofs[1]]])
    displacement = np.hstack([disp, disp_edges])
    return AxiSolution(nodes_mm=sb.doflocs, elements=dofs, displacement_mm=displacement,
                       s_rr_MPa=nodal["s_rr"], s_zz_MPa=nodal["s_zz"], s_tt_MPa=nodal["s_tt"], s_rz_MPa=nodal["s_rz"],
                       applied_axial_N=applied, pin_reaction_N=reaction, basis=sb)
