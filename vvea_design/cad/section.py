"""Meridian sections of the CAD solids: the closed outlines a solid leaves in the valve plane (y = 0) or the
port plane (x = 0), canonical and sorted so the drawings are byte-stable. The drawings draw them; the feature
check and the assembly check read them.
"""

from __future__ import annotations

import math

import numpy as np

__all__ = ["section_loops"]


def section_loops(solid, plane: str, u_min: float, u_max: float) -> list[np.ndarray]:
    """Closed outlines of a solid cut by a meridian plane.

    Straight edges give their end points, curved ones 24 points; the loops are
    sorted and canonicalised (start vertex, counter-clockwise) so the output
    does not depend on OCCT's result order.

    Parameters
    ----------
    solid : build123d.Solid
        Solid in the assembly frame, mm.
    plane : str
        ``"xz"`` (u = x, at y = 0) or ``"yz"`` (u = y, at x = 0).
    u_min, u_max : float
        Part of the plane kept, mm.

    Returns
    -------
    list of ndarray
        Closed loops of (u, z) points, mm.
    """
    from build123d import Face, Wire

    bb = solid.bounding_box()
    z0, z1 = bb.min.Z - 1.0, bb.max.Z + 1.0
    if plane == "xz":
        pts = [(u_min, 0, z0), (u_max, 0, z0), (u_max, 0, z1), (u_min, 0, z1)]
    elif plane == "yz":
        pts = [(0, u_min, z0), (0, u_max, z0), (0, u_max, z1), (0, u_min, z1)]
    else:
        raise ValueError(f"plane must be 'xz' or 'yz', got {plane!r}")
    cutter = Face(Wire.make_polygon(pts, close=True))
    sec = solid.intersect(cutter)
    loops = []
    if sec is None:
        return loops
    k = 0 if plane == "xz" else 1
    for face in sec.faces():
        for wire in [face.outer_wire(), *face.inner_wires()]:
            pts_uz: list[tuple[float, float]] = []
            for edge in wire.order_edges():
                n = 2 if edge.geom_type.name == "LINE" else 24
                ps = [edge.position_at(t) for t in np.linspace(0.0, 1.0, n)]
                seg = [((p.X, p.Y)[k], p.Z) for p in ps]
                if pts_uz and math.dist(pts_uz[-1], seg[-1]) < math.dist(pts_uz[-1], seg[0]):
                    seg = seg[::-1]
                pts_uz.extend(seg if not pts_uz else seg[1:])
            loops.append(_canonical(np.asarray(pts_uz, dtype=float)))
    # OCCT's boolean result order is not stable between calls: sort (and canonicalise) for byte-stable files
    return sorted(loops, key=lambda lp: (round(float(lp[:, 1].min()), 6), round(float(lp[:, 0].min()), 6),
                                         len(lp), round(float(lp.sum()), 6)))


def _canonical(loop: np.ndarray) -> np.ndarray:
    """A closed loop started at its lowest-leftmost vertex, counter-clockwise, closed."""
    pts = loop[:-1] if len(loop) > 1 and np.allclose(loop[0], loop[-1]) else loop
    area2 = float(np.sum(pts[:, 0] * np.roll(pts[:, 1], -1) - np.roll(pts[:, 0], -1) * pts[:, 1]))
    if area2 < 0:
        pts = pts[::-1]
    r = np.round(pts, 9)
    k = min(range(len(r)), key=lambda i: (r[i, 1], r[i, 0]))
    pts = np.roll(pts, -k, axis=0)
    return np.vstack([pts, pts[:1]])
