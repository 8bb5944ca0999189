"""Meridian sections of the machined pieces: the 2-D region an axisymmetric model revolves.

A piece's section is its CAD solid cut by a half-plane through the axis (:func:`section_of_solid`), so the FE
sees exactly what the drawing and the STEP file hold (grooves, steps, threads, radii as the CAD draws them),
and follows the CAD when it changes. The half-plane's angle is chosen clear of the features that are not
surfaces of revolution about the axis (valve bores, ports, screw holes, slots: :func:`clear_angle_deg`): the
largest angular gap between them, so the section is the piece's axisymmetric body. What the section leaves out
is measured, not assumed: ``volume_fraction`` is the solid's volume over the section's revolved volume
(Pappus), 1.0 for a body of revolution, below it by the share of material the holes take.

Machined internal corners are never sharp: a corner the CAD draws sharp is given the root radius the drawing
states for it (:meth:`~vvea_design.cad.layout.Layout.corner_radius_mm`: R1 at steps and shoulders unless
stated, the ISO 3601 gland's root radius at O-ring grooves, R1.5 at the rod's shoulder; the FE check's
default) or one radius for all (a study's; :data:`DEFAULT_CORNER_RADIUS_MM` is a turning tool's least nose
radius), so the stress at it is finite and converges with the mesh (:func:`with_corner_radii`).

Frame: the section lies in the plane ``(x, y) = (r, z)``, mm, r >= 0.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace

import numpy as np
from matplotlib.path import Path as _Path
from build123d import Align, Axis, Face, GeomType, Location, Plane, Polygon, Rectangle, Solid

__all__ = ["MeridianSection", "Corner", "outline_polygon", "reentrant_corners", "section_of_solid", "section_from_outline", "clear_angle_deg",
           "with_corner_radii", "truncated", "DEFAULT_CORNER_RADIUS_MM"]

#: Radius given to an internal corner the CAD draws sharp (a turning tool's least nose radius), mm.
DEFAULT_CORNER_RADIUS_MM = 0.2

_AXIAL_TOL = 1e-6


@dataclass(frozen=True)
class Corner:
    """A re-entrant (internal) corner of a section's outline: where stress concentrates."""

    r_mm: float
    z_mm: float
    angle_deg: float  #: interior angle of the material, > 180 for a re-entrant corner
    radius_mm: float  #: its fillet (0: sharp)


@dataclass(frozen=True)
class MeridianSection:
    """A piece's meridian section: a face in the ``(r, z)`` plane (x = r, y = z), mm."""

    name: str  #: the piece (CAD part name)
    face: Face  #: the region, x = r >= 0, y = z, mm
    angle_deg: float  #: angle of the half-plane it was cut at, from +x towards +y (nan: made from an outline)
    volume_fraction: float  #: CAD volume / the section's revolved volume (1: a body of revolution)
    corners: tuple[Corner, ...] = ()  #: re-entrant corners, with the radius each was given

    @property
    def area_mm2(self) -> float:
        """Area of the section, mm²."""
        return float(self.face.area)

    @property
    def revolved_volume_mm3(self) -> float:
        """Volume of the section revolved about the axis (Pappus: ``2 pi r_c A``), mm³."""
        return 2 * math.pi * float(self.face.center().X) * self.area_mm2

    def contains(self, r_mm, z_mm) -> np.ndarray:
        """Whether points lie inside the section (its outline sampled at 0.05 mm).

        Parameters
        ----------
        r_mm, z_mm : array_like
            Points, mm.

        Returns
        -------
        ndarray of bool
            One per point.
        """
        pts = np.column_stack([np.atleast_1d(r_mm), np.atleast_1d(z_mm)]).astype(float)
        return _Path(outline_polygon(self.face)).contains_points(pts)

    def bounds_mm(self) -> tuple[float, float, float, float]:
        """The section's bounding box.

        Returns
        -------
        tuple of float
            ``(r_min, r_max, z_min, z_max)``, mm.
        """
        bb = self.face.bounding_box()
        return float(bb.min.X), float(bb.max.X), float(bb.min.Y), float(bb.max.Y)


def _axisymmetric(face: Face) -> bool:
    """A face that is a surface of revolution about the z axis (or a plane normal to it)."""
    gt = face.geom_type
    if gt == GeomType.PLANE:
        n = face.normal_at()
        return abs(n.X) < _AXIAL_TOL and abs(n.Y) < _AXIAL_TOL
    ax = face.axis_of_rotation
    if ax is None:
        return False
    d, p = ax.direction, ax.position
    return abs(d.X) < _AXIAL_TOL and abs(d.Y) < _AXIAL_TOL and math.hypot(p.X, p.Y) < 1e-6


def _face_angles(face: Face, n: int = 5) -> np.ndarray:
    """Angles (deg, 0..360) of points sampled over a face, away from the axis."""
    pts = [face.position_at(u, v) for u in np.linspace(0, 1, n) for v in np.linspace(0, 1, n)]
    bb = face.bounding_box()
    pts += [bb.min, bb.max, face.center()]
    out = [math.degrees(math.atan2(p.Y, p.X)) % 360 for p in pts if math.hypot(p.X, p.Y) > 1e-6]
    return np.asarray(out)


def clear_angle_deg(solid: Solid, prefer_deg: float = 270.0, step_deg: float = 0.5) -> float:
    """The half-plane angle farthest from every feature that is not a surface of revolution about z.

    Faces that are planes normal to z, or cylinders, cones, spheres or tori on the z axis, are the body of
    revolution; every other face (a radial bore, an off-axis port, a slot's side) blocks the angles its points
    lie at. A face wrapped all round the axis (a helical thread) blocks nothing: its section is the same
    profile at every angle, shifted by the pitch.

    Parameters
    ----------
    solid : Solid
        A piece in the assembly frame (axis = z), mm.
    prefer_deg : float
        Angle returned on ties (and when nothing blocks), degrees from +x towards +y.
    step_deg : float
        Resolution of the search, degrees.

    Returns
    -------
    float
        The angle, degrees in [0, 360).
    """
    blocked: list[np.ndarray] = []
    for face in solid.faces():
        if _axisymmetric(face):
            continue
        a = _face_angles(face)
        if a.size == 0:
            continue
        gaps = np.diff(np.sort(np.concatenate([a, [a.min() + 360]])))
        if 360 - gaps.max() > 300:  # wrapped round the axis (thread): no angle is clear of it, none is worse
            continue
        blocked.append(a)
    if not blocked:
        return float(prefer_deg % 360)
    b = np.concatenate(blocked)
    cand = np.arange(0, 360, step_deg)
    d = np.abs((cand[:, None] - b[None, :] + 180) % 360 - 180).min(axis=1)
    pref = np.abs((cand - prefer_deg + 180) % 360 - 180)
    best = np.lexsort((pref, -np.round(d, 6)))[0]
    return float(cand[best])


def section_of_solid(solid: Solid, name: str, angle_deg: float | None = None, *,
                     z_range_mm: tuple[float, float] | None = None) -> MeridianSection:
    """Cut a piece by the half-plane through the axis at ``angle_deg`` and lay the cut in the (r, z) plane.

    Parameters
    ----------
    solid : Solid
        The piece, assembly frame (axis = z), mm.
    name : str
        The piece's name (kept with the section).
    angle_deg : float, optional
        The half-plane's angle from +x towards +y, degrees; default :func:`clear_angle_deg`.
    z_range_mm : tuple of float, optional
        Keep only ``z_min <= z <= z_max`` (e.g. the piston with a stub of its rod), mm.

    Returns
    -------
    MeridianSection
        The face (x = r, y = z), the angle, and the volume fraction it represents.

    Raises
    ------
    ValueError
        If the cut is empty or falls apart into several regions.
    """
    if angle_deg is None:
        angle_deg = clear_angle_deg(solid)
    bb = solid.bounding_box()
    R = max(abs(bb.min.X), abs(bb.max.X), abs(bb.min.Y), abs(bb.max.Y)) + 1.0
    z0, z1 = (bb.min.Z - 1.0, bb.max.Z + 1.0) if z_range_mm is None else z_range_mm
    turned = solid.rotate(Axis.Z, -angle_deg)
    half_plane = Plane.XZ * Rectangle(R, z1 - z0, align=(Align.MIN, Align.MIN))
    half_plane = half_plane.moved(Location((0, 0, z0)))
    faces = turned.intersect(half_plane).faces()
    if len(faces) != 1:
        raise ValueError(f"{name}: the cut at {angle_deg:g}° gives {len(faces)} regions, expected one")
    face = faces[0].rotate(Axis.X, -90)  # (x, 0, z) -> (x, z, 0)
    sec = MeridianSection(name, face, float(angle_deg), 1.0)
    vol = float(solid.volume) if z_range_mm is None else float(solid.volume)
    frac = vol / sec.revolved_volume_mm3 if z_range_mm is None else math.nan
    return replace(sec, volume_fraction=frac, corners=reentrant_corners(face))


def section_from_outline(points_rz, name: str) -> MeridianSection:
    """A section from a closed polygon in the (r, z) plane (test geometries, the concentration study).

    Parameters
    ----------
    points_rz : sequence of (float, float)
        Corners in order, mm (r >= 0).
    name : str
        Its name.

    Returns
    -------
    MeridianSection
        The face, angle nan, volume fraction 1.
    """
    face = Face(Polygon(*[(float(r), float(z)) for r, z in points_rz], align=None).wire())
    return MeridianSection(name, face, math.nan, 1.0, reentrant_corners(face))


def reentrant_corners(face: Face) -> tuple[Corner, ...]:
    """The re-entrant corners of a face's outline: vertices where the material's interior angle exceeds 180°.

    At each vertex the two edges' tangents pointing away from it bound two angles; a point a hair along their
    bisector tells which one is material.

    Parameters
    ----------
    face : Face
        A section (x = r, y = z), mm.

    Returns
    -------
    tuple of Corner
        Each re-entrant corner (radius 0: as drawn), sorted by z then r.
    """
    out = []
    edges = list(face.edges())
    for v in face.vertices():
        c = v.center()
        touching = [e for e in edges if min((e.start_point() - c).length, (e.end_point() - c).length) < 1e-7]
        if len(touching) != 2:
            continue
        ta, tb = (_tangent_away(e, c) for e in touching)
        cosang = max(-1.0, min(1.0, ta[0] * tb[0] + ta[1] * tb[1]))
        between = math.degrees(math.acos(cosang))  # the angle between the two edges, 0..180
        if between > 179.0:
            continue  # tangent continuation (a fillet meets its line)
        bis = (ta[0] + tb[0], ta[1] + tb[1])
        n = math.hypot(*bis)
        eps = 1e-4
        probe = (c.X + eps * bis[0] / n, c.Y + eps * bis[1] / n, 0.0)
        if face.is_inside(probe):
            continue  # the material fills the smaller angle: a convex corner
        out.append(Corner(float(c.X), float(c.Y), 360.0 - between, 0.0))
    return tuple(sorted(out, key=lambda k: (round(k.z_mm, 9), round(k.r_mm, 9))))


def _tangent_away(edge, c) -> tuple[float, float]:
    """Unit tangent of ``edge`` at its end ``c``, pointing into the edge."""
    at_start = (edge.start_point() - c).length < 1e-7
    t = edge.tangent_at(0.0 if at_start else 1.0)
    v = (float(t.X), float(t.Y)) if at_start else (-float(t.X), -float(t.Y))
    n = math.hypot(*v)
    return v[0] / n, v[1] / n


def with_corner_radii(section: MeridianSection, radius_mm: float = DEFAULT_CORNER_RADIUS_MM,
                      radius_at=None) -> MeridianSection:
    """The section with every sharp re-entrant corner rounded (at most 0.45 of its shorter neighbouring edge).

    One OpenCASCADE 2-D fillet builder (``BRepFilletAPI_MakeFillet2d``) rounds them all.

    Parameters
    ----------
    section : MeridianSection
        A section whose corners the CAD drew sharp.
    radius_mm : float
        The radius given, mm.
    radius_at : callable, optional
        ``radius_at(r_mm, z_mm)`` -> the radius the drawing gives the corner there, mm (the layout's root radii,
        :meth:`~vvea_design.cad.layout.Layout.corner_radius_mm`); None: ``radius_mm`` everywhere.

    Returns
    -------
    MeridianSection
        The rounded face; ``corners`` records the radius each re-entrant corner got (0 where OpenCASCADE
        refused the fillet: the corner stays sharp and its stress is mesh-dependent).
    """
    from OCP.BRepFilletAPI import BRepFilletAPI_MakeFillet2d
    from OCP.ChFi2d import ChFi2d_IsDone

    face = section.face
    corners = reentrant_corners(face)
    if not corners or (radius_mm <= 0 and radius_at is None):
        return replace(section, corners=corners)
    edges = list(face.edges())
    plan = []
    for c in corners:
        v = next(v for v in face.vertices() if abs(v.X - c.r_mm) + abs(v.Y - c.z_mm) < 1e-7)
        p = v.center()
        lengths = [e.length for e in edges if min((e.start_point() - p).length, (e.end_point() - p).length) < 1e-7]
        want = radius_mm if radius_at is None else radius_at(c.r_mm, c.z_mm)
        plan.append((c, v, min(want, 0.45 * min(lengths))))
    mk = BRepFilletAPI_MakeFillet2d(face.wrapped)
    done = []
    for c, v, r in plan:
        mk.AddFillet(v.wrapped, r)
        done.append(replace(c, radius_mm=r if mk.Status() == ChFi2d_IsDone else 0.0))
    mk.Build()
    if not mk.IsDone():
        return replace(section, corners=corners)
    return replace(section, face=Face(mk.Shape()), corners=tuple(done))


def truncated(section: MeridianSection, z_min_mm: float | None = None, z_max_mm: float | None = None) -> MeridianSection:
    """The part of a section between two levels (e.g. the piston with a stub of its rod).

    Parameters
    ----------
    section : MeridianSection
        The section.
    z_min_mm, z_max_mm : float, optional
        Levels kept between, mm (None: unbounded).

    Returns
    -------
    MeridianSection
        The clipped face (one region), same angle and volume fraction.
    """
    r0, r1, z0, z1 = section.bounds_mm()
    lo = z0 - 1 if z_min_mm is None else z_min_mm
    hi = z1 + 1 if z_max_mm is None else z_max_mm
    box = Rectangle(r1 + 2, hi - lo, align=(Align.MIN, Align.MIN)).moved(Location((-1, lo, 0)))
    faces = section.face.intersect(box).faces()
    if len(faces) != 1:
        raise ValueError(f"{section.name}: clipping to z in [{lo:g}, {hi:g}] gives {len(faces)} regions")
    return replace(section, face=faces[0], corners=tuple(c for c in section.corners if lo < c.z_mm < hi))


def outline_polygon(face, step_mm: float = 0.05) -> np.ndarray:
    """A section's outline as a closed polygon (every wire, edges sampled), for fast point-in-region tests.

    Parameters
    ----------
    face : build123d.Face
        A section in the (r, z) plane, mm.
    step_mm : float
        Largest chord along curved edges, mm.

    Returns
    -------
    ndarray
        ``(n, 2)`` points of the outer wire in order, mm (holes are not expected in a meridian section).
    """
    wire = face.outer_wire()
    pts = []
    for e in wire.order_edges() if hasattr(wire, "order_edges") else wire.edges():
        n = 1 if e.geom_type.name == "LINE" else max(2, int(np.ceil(e.length / step_mm)))
        pts.extend((float(p.X), float(p.Y)) for p in (e.position_at(t) for t in np.linspace(0, 1, n + 1)[:-1]))
    return np.asarray(pts)
