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

import numpy as np

from build123d import Solid

from ._shapes import cut, cylinder, revolved, ring
from .layout import Layout

__all__ = ["bladder", "bladder_profile", "bladder_volume_mm3", "support_ring", "support_ring_volume_mm3",
           "bladder_shift_at_mm", "bladder_deformed"]


def bladder_profile(lay: Layout) -> list[tuple[float, float]]:
    """Closed (r, z) outline of the cast bladder: sleeve, cuffs and sealing beads.

    Parameters
    ----------
    lay : Layout
        Radii and axial levels of the design, mm (z = 0 under the base).

    Returns
    -------
    list of tuple of float
        The 12 corners ``(r, z)`` of the meridian section in order, mm.
    """
    ri, ro, e, lb = lay.r_bladder_in, lay.r_bladder_out, lay.bead_mm, lay.bead_length
    za, zb = lay.z_bladder0, lay.z_bladder1
    return [
        (ri - e, za), (ro + e, za), (ro + e, za + lb), (ro, za + lb),
        (ro, zb - lb), (ro + e, zb - lb), (ro + e, zb), (ri - e, zb),
        (ri - e, zb - lb), (ri, zb - lb), (ri, za + lb), (ri - e, za + lb),
    ]


def bladder(lay: Layout) -> Solid:
    """The cast bladder as one solid (its outline revolved about the axis).

    Parameters
    ----------
    lay : Layout
        Radii and axial levels of the design, mm (z = 0 under the base).

    Returns
    -------
    Solid
        The bladder in the assembly frame, mm.
    """
    return revolved(bladder_profile(lay))


def bladder_volume_mm3(lay: Layout) -> float:
    """Closed-form volume of :func:`bladder`: the sleeve plus the four bead rings.

    Parameters
    ----------
    lay : Layout
        Radii and axial levels of the design, mm (z = 0 under the base).

    Returns
    -------
    float
        Volume, mm³.
    """
    ri, ro, e, lb = lay.r_bladder_in, lay.r_bladder_out, lay.bead_mm, lay.bead_length
    sleeve = math.pi * (ro**2 - ri**2) * (lay.z_bladder1 - lay.z_bladder0)
    beads = 2 * math.pi * ((ro + e) ** 2 - ro**2 + ri**2 - (ri - e) ** 2) * lb
    return sleeve + beads


def support_ring(lay: Layout) -> Solid:
    """Printed support ring: fills the annulus between the inner tube and the base's spigot over the lower clamp
    length (out to the cuff's outer face, so it passes the spigot's bore on assembly), holds the bladder's lower
    cuff from inside and below (the spigot, metal, is the cuff groove's outer wall: the outer bead seals gas from
    fluid in its internal groove), and passes the fluid through ``fixed.ring_channels`` axial channels (inside the
    bladder) fed by an annular collector groove in its underside (over the base channels).

    Parameters
    ----------
    lay : Layout
        Radii and axial levels of the design, mm (z = 0 under the base).

    Returns
    -------
    Solid
        The support ring in the assembly frame, mm.
    """
    c = lay.cad
    z0, z1 = lay.z_base_top, lay.z_free0
    ro = lay.r_bladder_out
    body = ring(lay.r_inner_tube, ro, z0, z1)
    rc, dc = lay.r_ring_channel, lay.ring_channel_d
    tools = [bladder(lay), ring(rc - 0.6 * dc, rc + 0.6 * dc, z0 - 1.0, z0 + _collector_depth(lay))]
    for k in range(lay.ring_channels):
        a = 2 * math.pi * k / lay.ring_channels
        tools.append(cylinder(dc / 2, z0 - 1.0, z1 + 1.0, x=rc * math.cos(a), y=rc * math.sin(a)))
    return cut(body, *tools)


def _collector_depth(lay: Layout) -> float:
    """Depth of the support ring's collector groove (underside), mm."""
    return min(1.0, 0.2 * (lay.z_free0 - lay.z_base_top))


def support_ring_volume_mm3(lay: Layout) -> float:
    """Closed-form volume of :func:`support_ring`, mm³: the annulus out to the cuff's outer face minus the
    bladder's lower cuff (sleeve + inner bead), the axial channels above the collector groove and the groove (the
    channels lie inside the groove's annulus).

    Parameters
    ----------
    lay : Layout
        Radii and axial levels of the design, mm (z = 0 under the base).

    Returns
    -------
    float
        Volume, mm³.
    """
    h = lay.z_free0 - lay.z_base_top
    ri, ro, e, lb = lay.r_bladder_in, lay.r_bladder_out, lay.bead_mm, lay.bead_length
    rc, dc, hg = lay.r_ring_channel, lay.ring_channel_d, _collector_depth(lay)
    v = math.pi * (ro**2 - lay.r_inner_tube**2) * h
    v -= math.pi * (ro**2 - ri**2) * (lay.z_free0 - lay.z_bladder0)
    v -= math.pi * (ri**2 - (ri - e) ** 2) * lb  # the inner bead (the outer one sits in the base spigot)
    v -= lay.ring_channels * math.pi * (dc / 2) ** 2 * (h - hg)
    v -= math.pi * ((rc + 0.6 * dc) ** 2 - (rc - 0.6 * dc) ** 2) * hg
    return v


def _free_profile(lay: Layout, a_mm: float, n: int) -> tuple[np.ndarray, np.ndarray]:
    """Outer-surface radius of the free length with a parabolic shift of mean ``a_mm``: (z, r), mm."""
    z = np.linspace(lay.z_free0, lay.z_free1, n + 1)
    zeta = (z - lay.z_free0) / (lay.z_free1 - lay.z_free0)
    return z, lay.r_bladder_out + a_mm * 6.0 * zeta * (1.0 - zeta)


def _annulus_volume(z: np.ndarray, r_in: np.ndarray, r_out: float) -> float:
    """Volume between the bore ``r_out`` and the revolved polyline (z, r_in), exact for the polygon, mm³."""
    dz = np.diff(z)
    ra, rb = r_in[:-1], r_in[1:]
    cone = math.pi * dz * (ra**2 + ra * rb + rb**2) / 3.0  # frustum under each segment
    return float(math.pi * r_out**2 * (z[-1] - z[0]) - cone.sum())


def bladder_shift_at_mm(lay: Layout, x_mm: float, n: int = 32) -> float:
    """Mean radial shift of the bladder's outer surface from the cast one at displacement ``x_mm``
    (parabolic between the clamps, peak = 1.5 x mean, as the FE check finds), such that the
    drawn chamber-2 gas (polygon of ``n`` segments) holds exactly ``V2 - A2 x`` (dead volume and,
    in the bulkhead layout, the gas above the bulkhead excluded). Positive: outwards.

    Parameters
    ----------
    lay : Layout
        Radii and axial levels of the design, mm (z = 0 under the base).
    x_mm : float
        Piston displacement, mm (x > 0 extends the spring and moves the piston down, towards the base).
    n : int
        Segments of the polygon that approximates the shifted free length.

    Returns
    -------
    float
        Mean radial shift, mm (the peak at mid-length is 1.5 times it).

    Raises
    ------
    ValueError
        If no shift between touching the inner tube and touching the bore holds that volume (the
        displacement is outside what the chamber can take).
    """
    from scipy.optimize import brentq

    d = lay.design
    target = d.V2_annulus_mm3 - d.A2_mm2 * x_mm  # the annulus's share of chamber 2 (V2_top is above the bulkhead)

    def f(a: float) -> float:
        z, r = _free_profile(lay, a, n)
        return _annulus_volume(z, r, lay.r_bore) - target

    lo, hi = -(lay.r_bladder_out - lay.r_inner_tube), lay.r_bore - lay.r_bladder_out
    return float(brentq(f, lo / 1.5, hi / 1.5, xtol=1e-12))


def bladder_deformed(lay: Layout, x_mm: float, n: int = 32) -> tuple[Solid, Solid]:
    """The bladder and the chamber-2 gas at displacement ``x_mm`` in a volume-consistent shape:
    cuffs as cast, the free length shifted parabolically (wall thickness kept), so the gas
    solid around the bladder holds exactly ``V2 - V2_top - A2 x``. For pictures; the exported
    bladder is the cast one.

    Parameters
    ----------
    lay : Layout
        Radii and axial levels of the design, mm (z = 0 under the base).
    x_mm : float
        Piston displacement, mm (x > 0 extends the spring and moves the piston down, towards the base).
    n : int
        Segments of the polygon of the shifted free length.

    Returns
    -------
    bladder, gas : Solid
        The deformed bladder and the chamber-2 gas between it and the bore, assembly frame, mm.

    Raises
    ------
    ValueError
        If no shift holds the chamber-2 volume at ``x_mm`` (see :func:`bladder_shift_at_mm`).
    """
    a = bladder_shift_at_mm(lay, x_mm, n)
    z, r = _free_profile(lay, a, n)
    t = lay.r_bladder_out - lay.r_bladder_in
    ri, ro, e, lb = lay.r_bladder_in, lay.r_bladder_out, lay.bead_mm, lay.bead_length
    za, zb = lay.z_bladder0, lay.z_bladder1
    outer = [(float(rr), float(zz)) for zz, rr in zip(z, r)]
    inner = [(float(rr - t), float(zz)) for zz, rr in zip(z[::-1], r[::-1])]
    prof = [(ri - e, za), (ro + e, za), (ro + e, za + lb), (ro, za + lb), *outer,
            (ro, zb - lb), (ro + e, zb - lb), (ro + e, zb), (ri - e, zb), (ri - e, zb - lb), (ri, zb - lb), *inner,
            (ri, za + lb), (ri - e, za + lb)]
    clean = [prof[0]]
    for p in prof[1:]:
        if math.dist(p, clean[-1]) > 1e-9:
            clean.append(p)
    gas = [(float(rr), float(zz)) for zz, rr in zip(z, r)] + [(lay.r_bore, lay.z_free1), (lay.r_bore, lay.z_free0)]
    return revolved(clean), revolved(gas)
