"""Small solid primitives on top of build123d (internal)."""

from __future__ import annotations

from collections.abc import Sequence

from build123d import Axis, Plane, Polygon, Solid, revolve

__all__ = ["cylinder", "ring", "bar", "cone", "revolved", "single_solid", "fuse", "cut"]


def cylinder(r: float, z0: float, z1: float, x: float = 0.0, y: float = 0.0) -> Solid:
    """Cylinder of radius ``r`` along +Z from ``z0`` to ``z1`` centred on (x, y), mm."""
    return Solid.make_cylinder(r, z1 - z0, Plane((x, y, z0), z_dir=(0, 0, 1)))


def ring(r_in: float, r_out: float, z0: float, z1: float) -> Solid:
    """Tube r_in..r_out (r_in = 0: cylinder) from ``z0`` to ``z1``, mm."""
    if r_in <= 0:
        return cylinder(r_out, z0, z1)
    return revolved([(r_in, z0), (r_out, z0), (r_out, z1), (r_in, z1)])


def bar(r: float, start: Sequence[float], direction: Sequence[float], length: float) -> Solid:
    """Cylinder of radius ``r`` from ``start`` along unit ``direction`` for ``length``, mm."""
    return Solid.make_cylinder(r, length, Plane(tuple(start), z_dir=tuple(direction)))


def cone(r0: float, r1: float, start: Sequence[float], direction: Sequence[float], length: float) -> Solid:
    """Truncated cone from radius ``r0`` at ``start`` to ``r1`` after ``length``, mm."""
    return Solid.make_cone(r0, r1, length, Plane(tuple(start), z_dir=tuple(direction)))


def revolved(profile_rz: Sequence[tuple[float, float]], angle_deg: float = 360.0) -> Solid:
    """Revolution about Z of a closed (r, z) polygon (r >= 0), mm: full, or ``angle_deg`` from the +x axis
    towards +y."""
    face = Plane.XZ * Polygon(*[(r, z) for r, z in profile_rz], align=None)
    return single_solid(revolve(face, Axis.Z, angle_deg))


def single_solid(shape) -> Solid:
    """The one solid of ``shape``; raises if there are none or several."""
    solids = shape.solids() if not isinstance(shape, Solid) else [shape]
    if len(solids) != 1:
        raise RuntimeError(f"expected one solid, got {len(solids)}")
    s = solids[0]
    return s if isinstance(s, Solid) else Solid(s.wrapped)


def fuse(a, *others) -> Solid:
    out = a
    for b in others:
        out = out.fuse(b)
    return single_solid(out.clean())


def cut(a, *tools) -> Solid:
    out = a
    if tools:
        out = a.cut(*tools)
    return single_solid(out.clean())
