"""The axisymmetric solver, the stress measures and the sections it works on."""

import math

import numpy as np
import pytest
from build123d import Axis, Box, Cylinder, Location

from vvea_design.structure.elasticity import AxiProblem, principal_stresses, tresca, von_mises
from vvea_design.structure.meshing import MeshSpec, mean_wall_mm, mesh_section
from vvea_design.structure.model import Bearing, boundary_facets, nearest_vertex
from vvea_design.structure.section import (clear_angle_deg, reentrant_corners, section_from_outline,
                                           section_of_solid, truncated, with_corner_radii)


def test_equivalent_stresses():
    s = np.array([100.0])
    z = np.zeros(1)
    assert von_mises(s, z, z, z) == pytest.approx(100.0) and tresca(s, z, z, z) == pytest.approx(100.0)
    tau = np.array([50.0])
    assert von_mises(z, z, z, tau) == pytest.approx(math.sqrt(3) * 50) and tresca(z, z, z, tau) == pytest.approx(100)
    assert sorted(principal_stresses(np.array([3.0]), np.array([1.0]), np.array([2.0]), z).ravel()) == [1, 2, 3]


def test_a_problem_needs_a_support():
    sec = section_from_outline([(1, 0), (2, 0), (2, 1), (1, 1)], "ring")
    mesh = mesh_section(sec)
    with pytest.raises(ValueError, match="pin node or clamped"):
        AxiProblem(mesh, 70e3, 0.3, None)


def test_boundary_normals_point_out_and_bearings_select_faces():
    sec = section_from_outline([(0, 0), (5, 0), (5, 2), (0, 2)], "disc")
    mesh = mesh_section(sec)
    bf, mid, n, length = boundary_facets(mesh)
    assert np.all(length > 0)
    centre = np.array([[2.5], [1.0]])
    assert np.all(np.einsum("ij,ij->j", n, mid - centre) > 0)  # outward
    top = Bearing("top", (0, 5), (2, 2), -1).select(mid, n)
    assert top.any() and np.allclose(mid[1, top], 2.0)
    assert not Bearing("none", (6, 7), (0, 2), 0).select(mid, n).any()
    v = nearest_vertex(mesh, 5.0, 0.0)
    assert v < mesh.nvertices and np.allclose(mesh.p[:, v], [5.0, 0.0])


def test_a_ring_section_of_a_solid_and_the_angle_clear_of_its_holes():
    ring = Cylinder(20, 10) - Cylinder(15, 10)
    hole = Cylinder(1.5, 30, rotation=(0, 90, 0)).moved(Location((15, 0, 0)))  # a radial bore along +x
    solid = (ring - hole).solids()[0]
    a = clear_angle_deg(solid)
    assert 150 <= a <= 210  # away from the bore at 0 deg
    sec = section_of_solid(solid, "ring", a)
    r0, r1, z0, z1 = sec.bounds_mm()
    assert (r0, r1, z0, z1) == pytest.approx((15, 20, -5, 5))
    assert sec.area_mm2 == pytest.approx(50.0)
    assert sec.volume_fraction < 0.999  # the bore is missing from the solid, not from the section
    plain = section_of_solid(ring.solids()[0], "ring")
    assert plain.volume_fraction == pytest.approx(1.0, abs=1e-6)
    assert mean_wall_mm(plain) == pytest.approx(2 * 50 / 30)


def test_reentrant_corners_are_found_and_rounded():
    L = section_from_outline([(0, 0), (4, 0), (4, 1), (1, 1), (1, 4), (0, 4)], "L")
    (c,) = L.corners
    assert (c.r_mm, c.z_mm, c.angle_deg) == pytest.approx((1, 1, 270))
    rounded = with_corner_radii(L, 0.3)
    assert rounded.corners[0].radius_mm == pytest.approx(0.3)
    assert rounded.area_mm2 - L.area_mm2 == pytest.approx((1 - math.pi / 4) * 0.09, rel=1e-6)
    assert reentrant_corners(rounded.face) == ()  # a fillet is tangent: no corner left
    groove = [(0, 0), (4, 0), (4, 1.9), (3, 1.9), (3, 2.1), (4, 2.1), (4, 4), (0, 4)]  # 0.2 mm wide, 1 mm deep
    tight = with_corner_radii(section_from_outline(groove, "groove"), 0.3)
    assert [c.radius_mm for c in tight.corners] == pytest.approx([0.45 * 0.2] * 2)  # no larger than its edges allow
    cut = truncated(L, z_min_mm=0.5)
    assert cut.bounds_mm()[2] == pytest.approx(0.5)


def test_meshes_are_quadratic_counter_clockwise_and_refined_at_corners():
    L = with_corner_radii(section_from_outline([(0, 0), (10, 0), (10, 2), (2, 2), (2, 10), (0, 10)], "L"), 0.2)
    mesh = mesh_section(L, MeshSpec())
    t, p = mesh.t, mesh.p
    area = ((p[0, t[1]] - p[0, t[0]]) * (p[1, t[2]] - p[1, t[0]]) - (p[0, t[2]] - p[0, t[0]]) * (p[1, t[1]] - p[1, t[0]]))
    assert np.all(area > 0)
    assert mesh.doflocs.shape[1] > mesh.nvertices  # edge nodes
    centroid = p[:, t].mean(axis=1)
    size = np.sqrt(np.abs(area))
    near = np.hypot(centroid[0] - 2, centroid[1] - 2) < 0.3
    far = np.hypot(centroid[0] - 8, centroid[1] - 1) < 1.0
    assert size[near].mean() < 0.3 * size[far].mean()
