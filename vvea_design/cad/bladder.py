"""Bladder (silicone sleeve with sealing beads) and its support ring.

The bladder is drawn in its **cast** shape: a straight sleeve
``r_bladder_in .. r_bladder_out`` (design.bladder_inner/outer_radius_mm)
over the free length, continued into a cuff of depth
``clamp_groove_fraction * fixed.bladder_clamp_mm`` at each end, each cuff
ending in a sealing bead ``bead_mm`` proud on both sides. The lower cuff sits
in the support ring, the upper in the top clamp of the housing; both grooves
are the cuff's exact negative. In service the sleeve deflates inwards (x = 0)
and bulges outwards (x = travel) between its clamps -- see the bladder check.
"""

from __future__ import annotations

import math

from build123d import Solid

from ._shapes import cut, cylinder, revolved, ring
from .layout import Layout

__all__ = ["bladder", "bladder_profile", "bladder_volume_mm3", "support_ring", "support_ring_volume_mm3"]


def bladder_profile(lay: Layout) -> list[tuple[float, float]]:
    """Closed (r, z) outline of the cast bladder, mm."""
    ri, ro, e, lb = lay.r_bladder_in, lay.r_bladder_out, lay.bead_mm, lay.bead_length
    za, zb = lay.z_bladder0, lay.z_bladder1
    return [
        (ri - e, za), (ro + e, za), (ro + e, za + lb), (ro, za + lb),
        (ro, zb - lb), (ro + e, zb - lb), (ro + e, zb), (ri - e, zb),
        (ri - e, zb - lb), (ri, zb - lb), (ri, za + lb), (ri - e, za + lb),
    ]


def bladder(lay: Layout) -> Solid:
    """The cast bladder as one solid (assembly frame), mm."""
    return revolved(bladder_profile(lay))


def bladder_volume_mm3(lay: Layout) -> float:
    """Closed-form volume of :func:`bladder`, mm³."""
    ri, ro, e, lb = lay.r_bladder_in, lay.r_bladder_out, lay.bead_mm, lay.bead_length
    sleeve = math.pi * (ro**2 - ri**2) * (lay.z_bladder1 - lay.z_bladder0)
    beads = 2 * math.pi * ((ro + e) ** 2 - ro**2 + ri**2 - (ri - e) ** 2) * lb
    return sleeve + beads


def support_ring(lay: Layout) -> Solid:
    """Printed support ring: fills the annulus over the lower clamp length, holds the
    bladder's lower cuff in its groove, and passes the fluid through
    ``cad.ring_channels`` axial channels (inside the bladder) fed by an annular
    collector groove in its underside (over the base channels)."""
    c = lay.cad
    z0, z1 = lay.z_base_top, lay.z_free0
    body = ring(lay.r_inner_tube, lay.r_bore, z0, z1)
    rc, dc = lay.r_ring_channel, lay.ring_channel_d
    tools = [bladder(lay), ring(rc - 0.6 * dc, rc + 0.6 * dc, z0 - 1.0, z0 + _collector_depth(lay))]
    for k in range(c.ring_channels):
        a = 2 * math.pi * k / c.ring_channels
        tools.append(cylinder(dc / 2, z0 - 1.0, z1 + 1.0, x=rc * math.cos(a), y=rc * math.sin(a)))
    return cut(body, *tools)


def _collector_depth(lay: Layout) -> float:
    """Depth of the support ring's collector groove (underside), mm."""
    return min(1.0, 0.2 * (lay.z_free0 - lay.z_base_top))


def support_ring_volume_mm3(lay: Layout) -> float:
    """Closed-form volume of :func:`support_ring`, mm³: the annulus minus the bladder's
    lower cuff (sleeve + bead), the axial channels above the collector groove and the
    groove (the channels lie inside the groove's annulus)."""
    h = lay.z_free0 - lay.z_base_top
    ri, ro, e, lb = lay.r_bladder_in, lay.r_bladder_out, lay.bead_mm, lay.bead_length
    rc, dc, hg = lay.r_ring_channel, lay.ring_channel_d, _collector_depth(lay)
    v = math.pi * (lay.r_bore**2 - lay.r_inner_tube**2) * h
    v -= math.pi * (ro**2 - ri**2) * (lay.z_free0 - lay.z_bladder0)
    v -= math.pi * ((ro + e) ** 2 - ro**2 + ri**2 - (ri - e) ** 2) * lb
    v -= lay.cad.ring_channels * math.pi * (dc / 2) ** 2 * (h - hg)
    v -= math.pi * ((rc + 0.6 * dc) ** 2 - (rc - 0.6 * dc) ** 2) * hg
    return v
