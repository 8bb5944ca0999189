"""The housing's pieces where the design sized a joint (:mod:`vvea_design.cad.joints`): the bodies of the outer
tube, the base and the top cap with their spigots, threads, run-outs and plug, the regions that cut the united
housing into its pieces along the joints, and the joint's own cuts (the retaining ring's groove, the tie rods'
holes). Threads are drawn as their pitch cylinders (the thread's flanks are on the drawings, ISO 6410-1), the
run-out undercut to the external minor diameter. Lengths mm, assembly frame.
"""

from __future__ import annotations

import math

from build123d import Solid

from ._shapes import cylinder, fuse, revolved, ring
from .layout import Layout

__all__ = ["joint_bodies", "joint_regions", "joint_tools", "outer_tube_profile"]


def outer_tube_profile(lay: Layout, r_out: float | None = None) -> list[tuple[float, float]]:
    """Meridian outline (r, z) of the outer tube with its threaded or counterbored ends, mm: behind each thread the
    internal run-out at the thread's minor diameter ``D1`` (DIN 76-1), then the step into the bore (where the lead-in
    chamfer is cut).

    Parameters
    ----------
    lay : Layout
        The design's layout (its joint).
    r_out : float, optional
        Outside radius drawn (default the tube's; a larger one gives the tube's region for the cut).

    Returns
    -------
    list of tuple of float
        The corners in order, mm.
    """
    j, rb = lay.joint, lay.r_bore
    ro = j.tube_outer_radius_mm if r_out is None else r_out
    b0, zs = j.z_tube_bottom, j.z_tube_top
    pts = []
    if j.base_thread is not None:
        t = j.base_thread
        pts += [(t.pitch_diameter_mm / 2, b0)]
    else:
        pts += [(rb, b0)]
    pts += [(ro, b0), (ro, zs)]
    if j.cap_thread is not None:  # thread, then the internal run-out at the thread's minor bore, then the bore
        t = j.cap_thread
        pts += [(t.pitch_diameter_mm / 2, zs), (t.pitch_diameter_mm / 2, t.thread[0]),
                (t.internal_minor_mm / 2, t.thread[0]), (t.internal_minor_mm / 2, t.relief[0]), (rb, t.relief[0])]
    elif j.ring is not None:  # the counterbore above the cap plug's seal zone (the plug seals in the bore)
        pts += [(j.ring.bore_mm / 2, zs), (j.ring.bore_mm / 2, j.cap_seal[1]), (rb, j.cap_seal[1])]
    else:
        pts += [(rb, zs)]
    if j.base_thread is not None:
        t = j.base_thread
        pts += [(rb, t.relief[1]), (t.internal_minor_mm / 2, t.relief[1]), (t.internal_minor_mm / 2, t.thread[1]),
                (t.pitch_diameter_mm / 2, t.thread[1])]
    return pts


def _base_spigot(lay: Layout) -> list[tuple[float, float]]:
    """The base's spigot inside the tube: run-out, thread, seal zone (or the seal zone only)."""
    j, rb, z0 = lay.joint, lay.r_bore, lay.z_base_top
    b0 = j.z_tube_bottom
    t = j.base_thread
    if t is None:
        return [(0.0, b0), (rb, b0), (rb, z0), (0.0, z0)]
    d2, d3 = t.pitch_diameter_mm / 2, t.external_minor_mm / 2
    return [(0.0, b0), (d3, b0), (d3, t.runout[1]), (d2, t.runout[1]), (d2, t.thread[1]), (rb, t.thread[1]),
            (rb, z0), (0.0, z0)]


def _cap_spigot(lay: Layout) -> list[tuple[float, float]]:
    """The top cap's spigot inside the tube: seal zone, thread, run-out (or the seal zone only; ``ring_top``: the
    plug, its seal zone at the bore below the counterbore)."""
    j, rb, z1 = lay.joint, lay.r_bore, lay.z_cap
    zs = j.z_tube_top
    if j.ring is not None:
        r, zc = j.ring.bore_mm / 2, j.cap_seal[1]
        return [(0.0, z1), (rb, z1), (rb, zc), (r, zc), (r, j.ring.plug[1]), (0.0, j.ring.plug[1])]
    t = j.cap_thread
    if t is None:
        return [(0.0, z1), (rb, z1), (rb, zs), (0.0, zs)]
    d2, d3 = t.pitch_diameter_mm / 2, t.external_minor_mm / 2
    return [(0.0, z1), (rb, z1), (rb, t.thread[0]), (d2, t.thread[0]), (d2, t.runout[0]), (d3, t.runout[0]),
            (d3, zs), (0.0, zs)]


def joint_bodies(lay: Layout) -> list[Solid]:
    """The outer tube, the base and the top cap as bodies for the united housing (before the cuts), mm.

    Parameters
    ----------
    lay : Layout
        The design's layout (its joint: ``lay.has_joint``).

    Returns
    -------
    list of Solid
        Outer tube, base (its own part and its spigot), top cap (its shoulder above the tube and its spigot or
        plug), assembly frame.
    """
    j, R, zt = lay.joint, lay.r_outer, lay.z_top
    out = [revolved(outer_tube_profile(lay)), cylinder(R, 0.0, j.z_tube_bottom), revolved(_base_spigot(lay)),
           revolved(_cap_spigot(lay))]
    if j.ring is None:
        out.append(cylinder(R, j.z_tube_top, zt))
    return out


def joint_regions(lay: Layout, big: float) -> dict[str, Solid]:
    """The regions that cut the united housing into the base, the outer tube and the top cap along the joint
    (the inner tube's is the caller's), mm.

    Parameters
    ----------
    lay : Layout
        The design's layout.
    big : float
        A radius past the housing, mm.

    Returns
    -------
    dict of str to Solid
        ``housing_base``, ``housing_outer_tube``, ``housing_top_cap``.
    """
    j, zt = lay.joint, lay.z_top
    base = fuse(cylinder(big, -1.0, j.z_tube_bottom), revolved(_base_spigot(lay)),
                ring(lay.r_bladder_out - 1e-3, lay.r_bore, lay.z_base_top, lay.z_free0))
    tube_pts = outer_tube_profile(lay, big)
    if j.ring is not None:  # the tube runs to the housing's top: its region past it
        tube_pts = [(r, zt + 1.0 if abs(z - zt) < 1e-9 else z) for r, z in tube_pts]
    tube = revolved(tube_pts)
    cap_parts = [revolved(_cap_spigot(lay))]
    if j.ring is None:
        cap_parts.append(cylinder(big, j.z_tube_top, zt + 1.0))
    if not lay.has_top_annulus:
        cap_parts.append(ring(lay.r_inner_tube, lay.r_bore, lay.z_free1, lay.z_cap))
    return {"housing_base": base, "housing_outer_tube": tube, "housing_top_cap": fuse(*cap_parts)}


def joint_tools(lay: Layout) -> list[Solid]:
    """The joint's own cuts: the retaining ring's groove in the tube, the tie rods' holes in the end pieces, mm.

    Parameters
    ----------
    lay : Layout
        The design's layout.

    Returns
    -------
    list of Solid
        In cutting order (empty for a threaded joint).
    """
    j = lay.joint
    out: list[Solid] = []
    if j.ring is not None:
        out.append(ring(j.ring.bore_mm / 2, j.ring.groove_diameter_mm / 2, *j.ring.groove))
    if j.rods is not None:
        r = j.rods
        for a in r.angles_deg:
            x, y = r.circle_radius_mm * math.cos(math.radians(a)), r.circle_radius_mm * math.sin(math.radians(a))
            out.append(cylinder(r.hole_mm / 2, -1.0, j.z_tube_bottom + 0.01, x=x, y=y))
            out.append(cylinder(r.hole_mm / 2, j.z_tube_top - 0.01, lay.z_top + 1.0, x=x, y=y))
    return out
