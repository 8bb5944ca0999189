"""The FE against the closed forms it must reproduce, on the geometries those closed forms are exact for.

Each function builds the section, meshes it with the main job's machinery (:func:`~.meshing.mesh_section`),
loads and supports it as the closed form assumes, and returns :class:`Comparison` records (FE, closed form,
relative error) at points away from edges and concentrations:

* :func:`thick_cylinder`: Lamé, internal and external pressure, open ends (``s_z = 0``: exact for a free
  cylinder of any length), hoop and radial stress at the bore, mid-wall and the outside;
* :func:`circular_plate`: simply supported (the reaction a narrow ring under the edge) or clamped (the edge
  face held), the radial and hoop stress at the centre of the unloaded face, and at mid-radius;
* :func:`annular_plate`: the piston pocket's floor as the sizing idealises it (clamped at the rod, free at the
  pocket wall with the rim's line load): the bending stress at the rod, linearised through the thickness,
  against :func:`~vvea_design.spring.derive.piston_floor_moment`;
* :func:`spherical_cavity`: a concentration with an exact solution, Goodier's spherical cavity in a body
  under uniaxial tension (``s_z = (27 - 15 nu) / (2 (7 - 5 nu)) s`` at its equator);
* :func:`grooved_tube`: a tube with a rectangular groove (the peak at its root: the convergence study's
  concentration case).

Lengths mm, pressures and stresses MPa.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..spring.derive import piston_floor_moment
from .closed_form import annular_plate_moment, lame, plate_clamped, plate_simply_supported
from .elasticity import AxiProblem, AxiSolution
from .evaluate import StressLine, linearise
from .meshing import MeshSpec, mesh_section
from .model import Bearing, boundary_facets, nearest_vertex
from .section import Corner, MeridianSection, section_from_outline, with_corner_radii

__all__ = ["Comparison", "thick_cylinder", "circular_plate", "annular_plate", "spherical_cavity", "grooved_tube"]

E_AL, NU_AL = 68.9e3, 0.33


@dataclass(frozen=True)
class Comparison:
    """One quantity, FE against closed form."""

    case: str
    quantity: str
    fe_MPa: float
    closed_form_MPa: float

    @property
    def relative_error(self) -> float:
        """``|FE - closed form| / |closed form|``."""
        return abs(self.fe_MPa - self.closed_form_MPa) / abs(self.closed_form_MPa)

    def to_dict(self) -> dict:
        """JSON-ready content.

        Returns
        -------
        dict
            Case, quantity, FE and closed-form values (MPa), relative error.
        """
        return {"case": self.case, "quantity": self.quantity, "fe_MPa": self.fe_MPa,
                "closed_form_MPa": self.closed_form_MPa, "relative_error": self.relative_error}


def _loaded(mesh, select, pressure):
    """Facets chosen by ``select(mid, normal)`` with a uniform pressure."""
    bf, mid, n, _ = boundary_facets(mesh)
    m = select(mid, n)
    return bf[m], np.full(m.sum(), float(pressure)), mid, n, bf


def thick_cylinder(inner_radius_mm: float = 10.0, outer_radius_mm: float = 15.0, p_inner_MPa: float = 10.0,
                   p_outer_MPa: float = 0.0, length_mm: float = 20.0,
                   spec: MeshSpec = MeshSpec()) -> tuple[list[Comparison], AxiSolution]:
    """A free-ended thick cylinder under internal and external pressure against Lamé.

    Parameters
    ----------
    inner_radius_mm, outer_radius_mm, length_mm : float
        The cylinder, mm.
    p_inner_MPa, p_outer_MPa : float
        Pressures, MPa.
    spec : MeshSpec
        Mesh sizes.

    Returns
    -------
    tuple
        Comparisons (hoop and radial at the bore, mid-wall and outside, mid-length) and the solution.
    """
    a, b, L = inner_radius_mm, outer_radius_mm, length_mm
    sec = section_from_outline([(a, 0), (b, 0), (b, L), (a, L)], "thick_cylinder")
    mesh = mesh_section(sec, spec)
    bf, mid, n, _ = boundary_facets(mesh)
    inner = np.abs(mid[0] - a) < 1e-9
    outer = np.abs(mid[0] - b) < 1e-9
    facets = bf[inner | outer]
    p = np.where(inner[inner | outer], p_inner_MPa, p_outer_MPa)
    prob = AxiProblem(mesh, E_AL, NU_AL, nearest_vertex(mesh, a, 0.0))
    sol = prob.solve(prob.load_vector(facets, p, np.zeros_like(p)))
    r = np.array([a, 0.5 * (a + b), b])
    eps = 1e-7 * (b - a)
    st = sol.stress_at(r + np.array([eps, 0, -eps]), np.full(3, 0.5 * L))
    ref = lame(r, a, b, p_inner_MPa, p_outer_MPa)
    name = f"thick cylinder {a:g}/{b:g} mm, p_i = {p_inner_MPa:g}, p_o = {p_outer_MPa:g} MPa"
    out = []
    for i, where in enumerate(("bore", "mid-wall", "outside")):
        out.append(Comparison(name, f"hoop stress at the {where}", float(st["s_tt"][i]), float(ref["s_tt"][i])))
        if abs(ref["s_rr"][i]) > 1e-9:
            out.append(Comparison(name, f"radial stress at the {where}", float(st["s_rr"][i]), float(ref["s_rr"][i])))
    return out, sol


def circular_plate(kind: str = "simply_supported", radius_mm: float = 40.0, thickness_mm: float = 2.0,
                   pressure_MPa: float = 1.0, spec: MeshSpec = MeshSpec()) -> tuple[list[Comparison], AxiSolution]:
    """A solid circular plate under uniform pressure on its top face against thin-plate theory.

    Simply supported: the reaction is a uniform upward traction on a ring of the bottom face under the edge
    (1 % of the radius wide, cut off inside the facets it straddles); clamped: the edge face is held. Pressure on the top face pushes down.

    Parameters
    ----------
    kind : str
        ``"simply_supported"`` or ``"clamped"``.
    radius_mm, thickness_mm : float
        The plate, mm.
    pressure_MPa : float
        Pressure, MPa.
    spec : MeshSpec
        Mesh sizes.

    Returns
    -------
    tuple
        Comparisons (radial and hoop stress on the bottom face at the centre and at half the radius) and the
        solution.
    """
    a, t, q = radius_mm, thickness_mm, pressure_MPa
    if kind not in ("simply_supported", "clamped"):
        raise ValueError(f"kind must be 'simply_supported' or 'clamped', got {kind!r}")
    sec = section_from_outline([(0, 0), (a, 0), (a, t), (0, t)], f"plate_{kind}")
    mesh = mesh_section(sec, spec)
    bf, mid, n, _ = boundary_facets(mesh)
    top = np.abs(mid[1] - t) < 1e-9
    if kind == "clamped":
        edge = bf[np.abs(mid[0] - a) < 1e-9]
        prob = AxiProblem(mesh, E_AL, NU_AL, None, clamped_facets=edge)
        f = prob.load_vector(bf[top], np.full(top.sum(), q), np.zeros(top.sum()))
        ref = plate_clamped
    else:
        box = (0.99 * a, a, 0.0, 0.0)
        ends = (mesh.p[:, mesh.facets[0, bf]], mesh.p[:, mesh.facets[1, bf]])
        ring = Bearing("ring under the edge", box[:2], box[2:], +1).select(mid, n, ends)
        prob = AxiProblem(mesh, E_AL, NU_AL, nearest_vertex(mesh, a, 0.0))
        f = prob.load_vector(bf[top], np.full(top.sum(), q), np.zeros(top.sum()))
        unit = prob.axial_force_N(prob.load_vector(bf[ring], np.zeros(ring.sum()), np.ones(ring.sum()), box))
        f = f + prob.load_vector(bf[ring], np.zeros(ring.sum()), np.full(ring.sum(), -prob.axial_force_N(f) / unit), box)
        ref = plate_simply_supported
    sol = prob.solve(f)
    r = np.array([0.0, 0.5 * a])
    st = sol.stress_at(r + 1e-9, np.full(2, 1e-9 * t))
    cf = ref(r, a, t, q, NU_AL)
    name = f"{kind.replace('_', ' ')} plate a = {a:g} mm, t = {t:g} mm, q = {q:g} MPa"
    out = []
    for i, where in enumerate(("centre", "half radius")):
        out.append(Comparison(name, f"radial stress, unloaded face, {where}", float(st["s_rr"][i]), float(cf["s_rr"][i])))
        out.append(Comparison(name, f"hoop stress, unloaded face, {where}", float(st["s_tt"][i]), float(cf["s_tt"][i])))
    return out, sol


def annular_plate(piston_radius_mm: float = 40.0, pocket_radius_mm: float = 36.0, rod_radius_mm: float = 4.0,
                  thickness_mm: float = 2.0, pressure_MPa: float = 1.0,
                  spec: MeshSpec = MeshSpec()) -> tuple[list[Comparison], AxiSolution]:
    """The piston pocket's floor as the sizing models it: an annular plate clamped at the rod, free at the
    pocket wall, the pressure between ``b`` and ``a`` and the rim's share ``q (rp^2 - a^2) / (2 a)`` as a line load
    at ``a``; the bending stress linearised through the thickness against ``6 M_r / t^2`` of thin-plate theory
    (:func:`~.closed_form.annular_plate_moment`): at the rod (the sizing's ``K``; the clamp's three-dimensional
    stress state puts the FE a few per cent below it there) and one and two thicknesses away from it, and at
    mid-span (within the thin-plate error).

    Parameters
    ----------
    piston_radius_mm, pocket_radius_mm, rod_radius_mm, thickness_mm : float
        ``rp``, ``a``, ``b`` and the floor, mm.
    pressure_MPa : float
        Pressure difference, MPa.
    spec : MeshSpec
        Mesh sizes.

    Returns
    -------
    tuple
        Comparisons (at the rod, at ``b + t``, ``b + 2 t`` and mid-span) and the solution.
    """
    rp, a, b, t, q = piston_radius_mm, pocket_radius_mm, rod_radius_mm, thickness_mm, pressure_MPa
    sec = section_from_outline([(b, 0), (a, 0), (a, t), (b, t)], "annular_plate")
    mesh = mesh_section(sec, spec)
    bf, mid, n, _ = boundary_facets(mesh)
    top = np.abs(mid[1] - t) < 1e-9
    rim = np.abs(mid[0] - a) < 1e-9
    clamp = bf[np.abs(mid[0] - b) < 1e-9]
    prob = AxiProblem(mesh, E_AL, NU_AL, None, clamped_facets=clamp)
    line = q * (rp**2 - a**2) / (2 * a)  # N/mm round the rim, downward, spread over the rim face
    f = prob.load_vector(bf[top], np.full(top.sum(), q), np.zeros(top.sum()))
    f = f + prob.load_vector(bf[rim], np.zeros(rim.sum()), np.full(rim.sum(), -line / t))
    sol = prob.solve(f)
    name = f"annular plate b = {b:g}, a = {a:g}, rp = {rp:g}, t = {t:g} mm, q = {q:g} MPa"
    out = [Comparison(name, "radial bending stress at the rod (linearised; the sizing's K)",
                      abs(_bending_rr(sol, b + 1e-6, t)), 6 * float(piston_floor_moment(rp, a, b, NU_AL)) * q / t**2)]
    for r in (b + t, b + 2 * t, 0.5 * (a + b)):
        out.append(Comparison(name, f"radial bending stress at r = {r:g} mm (linearised)", abs(_bending_rr(sol, r, t)),
                              6 * float(annular_plate_moment(r, rp, a, b, q, NU_AL)) / t**2))
    return out, sol


def _bending_rr(sol: AxiSolution, r_mm: float, t_mm: float, n: int = 81) -> float:
    """Linearised radial bending stress through a plate at radius r (the ``6/t^2 ∫ s_rr (t/2 - z) dz`` term)."""
    s = np.linspace(0.0, 1.0, n)
    z = 1e-9 + (t_mm - 2e-9) * s
    st = sol.stress_at(np.full(n, r_mm), z)
    return float(6 * np.trapezoid(st["s_rr"] * (0.5 - s), s))


def spherical_cavity(radius_mm: float = 1.0, body_mm: float = 15.0, stress_MPa: float = 1.0, poisson: float = 0.3,
                     spec: MeshSpec = MeshSpec(max_size_mm=2.0, growth=0.2)) -> tuple[list[Comparison], AxiSolution]:
    """A spherical cavity in a cylinder (radius and half-height ``body_mm``) pulled along the axis, against
    Goodier's solution for an infinite body: ``s_z = (27 - 15 nu) / (2 (7 - 5 nu)) s`` at the equator (the
    finite body adds a fraction of a per cent for ``body_mm / radius_mm = 15``).

    Parameters
    ----------
    radius_mm, body_mm : float
        The cavity and the body, mm.
    stress_MPa : float
        Remote axial stress, MPa.
    poisson : float
        Poisson's ratio.
    spec : MeshSpec
        Mesh sizes (``elements_per_radius`` resolves the cavity).

    Returns
    -------
    tuple
        One comparison (the peak axial stress at the equator) and the solution.
    """
    from build123d import Align, Circle, Rectangle

    a, R = radius_mm, body_mm
    face = (Rectangle(R, 2 * R, align=(Align.MIN, Align.CENTER)) - Circle(a)).faces()[0]
    sec = MeridianSection("spherical_cavity", face, math.nan, 1.0, (Corner(a, 0.0, 270.0, a),))
    mesh = mesh_section(sec, spec)
    bf, mid, n, _ = boundary_facets(mesh)
    tz = np.where(np.abs(mid[1] - R) < 1e-9, stress_MPa, 0.0) - np.where(np.abs(mid[1] + R) < 1e-9, stress_MPa, 0.0)
    prob = AxiProblem(mesh, E_AL, poisson, nearest_vertex(mesh, R, 0.0))
    sol = prob.solve(prob.load_vector(bf, np.zeros(bf.size), tz))
    st = sol.stress_at(np.array([a + 1e-6]), np.array([0.0]))
    exact = (27 - 15 * poisson) / (2 * (7 - 5 * poisson)) * stress_MPa
    return [Comparison(f"spherical cavity a = {a:g} mm in a body {R:g} mm, nu = {poisson:g}",
                       "axial stress at the equator (peak)", float(st["s_zz"][0]), exact)], sol


def grooved_tube(inner_radius_mm: float = 10.0, wall_mm: float = 3.0, groove_depth_mm: float = 1.0,
                 groove_width_mm: float = 2.0, root_radius_mm: float = 0.3, pressure_MPa: float = 10.0,
                 spec: MeshSpec = MeshSpec()) -> tuple[float, float, AxiSolution]:
    """A tube under internal pressure with a rectangular groove in its outside (a male gland), open ends.

    Parameters
    ----------
    inner_radius_mm, wall_mm : float
        Bore and wall, mm.
    groove_depth_mm, groove_width_mm, root_radius_mm : float
        The groove, mm.
    pressure_MPa : float
        Internal pressure, MPa.
    spec : MeshSpec
        Mesh sizes.

    Returns
    -------
    tuple
        Peak von Mises stress at the groove's root (MPa), the membrane-plus-bending von Mises stress on the
        net section under the groove's middle (MPa), and the solution.
    """
    a, w, d, g = inner_radius_mm, wall_mm, groove_depth_mm, groove_width_mm
    b = a + w
    L = 8 * w + g
    z0, z1 = 0.5 * (L - g), 0.5 * (L + g)
    sec = section_from_outline([(a, 0), (b, 0), (b, z0), (b - d, z0), (b - d, z1), (b, z1), (b, L), (a, L)],
                               "grooved_tube")
    sec = with_corner_radii(sec, root_radius_mm)
    mesh = mesh_section(sec, spec)
    bf, mid, n, _ = boundary_facets(mesh)
    inner = np.abs(mid[0] - a) < 1e-9
    prob = AxiProblem(mesh, E_AL, NU_AL, nearest_vertex(mesh, a, 0.0))
    sol = prob.solve(prob.load_vector(bf[inner], np.full(inner.sum(), pressure_MPa), np.zeros(inner.sum())))
    near = (np.abs(sol.nodes_mm[0] - (b - d)) < root_radius_mm + 0.05) & (sol.nodes_mm[1] > z0 - 0.05) \
        & (sol.nodes_mm[1] < z1 + 0.05)
    peak = float(sol.von_mises_MPa[near].max())
    nom = linearise(sol, StressLine("net section", (a, 0.5 * L), (b - d, 0.5 * L)), {}, 0.0)
    return peak, nom.membrane_bending_von_mises_MPa, sol


