"""What a piece's surface touches: the medium just outside each boundary point of a meridian section.

Every boundary facet of a piece's mesh is labelled by the point a hair outside it (along its outward normal):

* ``air`` outside the housing's envelope (atmosphere, 0 gauge);
* ``contact`` inside another machined piece (or the piston when the housing is labelled, the inner tube when
  the piston is): a joint face, loaded only by the joint's reaction (:mod:`~vvea_design.structure.pieces`);
* ``chamber_1``, ``chamber_2`` (gas) and ``fluid`` (the column under the piston, the throttle's high side):
  the unit's spaces at the piston's position of the load case, from the CAD's levels
  (:class:`~vvea_design.cad.layout.Layout`). The fluid inside the bladder and in the support ring's channels
  is at chamber-2 pressure (the bladder is a membrane); so is the rubber of the bladder's cuffs in their
  clamp grooves (rubber transmits the pressure round it);
* the sliding seals split the bore: above the piston's upper O-ring groove chamber 1, below its lower groove
  the fluid, between them ``air`` (vented by the seals); the rod's bore in the base carries fluid down to the
  rod seal groove's lower flank and air below;
* ``gap:<a>|<b>``: a void inside a joint (an O-ring gland, a thread's clearance, an undercut) takes the highest
  pressure of the spaces that joint separates (conservative: either may reach it), except beyond the static
  O-ring of the end pieces' joints (ISO 3601 glands, the base's and the top cap's): the pressure stops at the
  ring, its gland is loaded, the thread, run-out and tube end on the far side are ``air`` (the seal's job; a
  seal that leaks is found by the proof test, not by the walls).

Pressures per medium come from the load case (:class:`~vvea_design.structure.loads.LoadCase`). Lengths mm.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from matplotlib.path import Path as _Path

from ..cad.layout import Layout

__all__ = ["Surroundings", "MEDIA"]

#: The media a boundary can touch (``gap:a|b`` combine them).
MEDIA = ("air", "contact", "chamber_1", "chamber_2", "fluid")

#: Gaps of the joints at the base (the fluid column and the bladder's fluid at chamber-2 pressure reach them)
_BASE_GAP = "gap:chamber_2|fluid"
#: Gaps of the joints at the top (chamber 1 in the bore, chamber 2 in the annulus or above a bulkhead)
_TOP_GAP = "gap:chamber_1|chamber_2"


@dataclass(frozen=True)
class Surroundings:
    """The unit's spaces round the pieces at one piston displacement.

    Parameters
    ----------
    lay : Layout
        The CAD's radii and levels, mm.
    x_mm : float
        Piston displacement, mm (x > 0 moves the piston down).
    solids : tuple of ndarray
        Outlines (``(n, 2)`` r, z, mm) of the other solids a point may be inside: the other machined pieces
        and the piston (the ``contact`` faces).
    """

    lay: Layout
    x_mm: float
    solids: tuple = ()

    def medium(self, r_mm, z_mm) -> np.ndarray:
        """The medium at points of the (r, z) plane.

        Parameters
        ----------
        r_mm, z_mm : array_like
            Points, mm.

        Returns
        -------
        ndarray of str
            One of :data:`MEDIA` or ``gap:a|b`` per point.
        """
        r = np.atleast_1d(np.asarray(r_mm, dtype=float))
        z = np.atleast_1d(np.asarray(z_mm, dtype=float))
        out = self._spaces(r, z)
        inside = np.zeros(r.shape, dtype=bool)
        pts = np.column_stack([r, z])
        for poly in self.solids:
            inside |= _Path(poly).contains_points(pts)
        out[inside] = "contact"
        lay = self.lay
        out[(r >= lay.outer_radius_mm) | (z <= 0.0) | (z >= lay.z_top)] = "air"
        return out

    def _spaces(self, r: np.ndarray, z: np.ndarray) -> np.ndarray:
        """The spaces by the CAD's levels (every point; the solids are set over them after)."""
        lay, x = self.lay, self.x_mm
        d = lay.design
        rb, rio, rp, rr = lay.outer_bore_radius_mm, lay.inner_tube_outer_radius_mm, lay.piston_radius_mm, lay.rod_radius_mm
        z0, zc, zt = lay.z_base_top, lay.z_cap, lay.z_top
        out = np.full(r.shape, _TOP_GAP, dtype=object)
        mid_z = 0.5 * (z0 + zc)
        # joint gaps in the tube walls (threads, glands, reliefs): by the end they are at
        walls = (z > z0) & (z < zc) & (r >= rp)
        out[walls] = np.where(z[walls] < mid_z, _BASE_GAP, _TOP_GAP)
        # --- base: the rod's bore and seal groove, other voids are joint gaps
        base = z <= z0
        rod_gap = base & (r < rr + lay.rod_seal.depth_mm + 0.05)
        out[base] = _BASE_GAP
        out[rod_gap] = np.where(z[rod_gap] >= lay.z_rod_seal[0], "fluid", "air")
        # --- top cap: the chamber-1 port on the axis (bulkhead layout), the counterbore at its top
        cap = z >= zc
        out[cap] = _TOP_GAP
        cb = cap & (r < lay.cad.fill_port_counterbore_mm / 2 + 0.05) & (z > zt - lay.cad.fill_port_counterbore_depth_mm)
        if lay.has_bulkhead:
            out[cap & (r < lay.fill_tube_bore_radius_mm + 0.05)] = "chamber_1"
        out[cb] = "air"
        # beyond the end pieces' static seals (their pressure side is the housing's inside): atmosphere
        out[self.beyond_seals(r, z)] = "air"
        # --- the bore: chamber 1 above the piston, fluid below, the seals between
        bore = (z > z0) & (z < zc) & (r < rp)
        zpb, zpt = lay.z_piston_bottom(x), lay.z_piston_top(x)
        hp, w = d.fixed.piston_height_mm, lay.piston_seal.width_mm
        z_up, z_lo = zpb + 0.73 * hp - w / 2, zpb + 0.27 * hp + w / 2  # lower flank of the upper groove, upper of the lower
        col = np.where(z >= zpt, "chamber_1", np.where(z <= zpb, "fluid", np.where(z >= z_up, "chamber_1",
                                                                                  np.where(z <= z_lo, "fluid", "air"))))
        out[bore] = col[bore]
        out[bore & (z <= zpb) & (r < rr)] = "fluid"  # (the rod: contact where its outline is given)
        # the seals' rule holds in the sliding gap on both sides of the bore
        slide = (z > zpb) & (z < zpt) & (np.abs(r - rp) < 0.05)
        out[slide] = col[slide]
        if lay.has_bulkhead:
            zb0, zb1 = lay.z_bulkhead0, lay.z_bulkhead1
            above = bore & (z >= zb1)
            out[above] = np.where(r[above] < lay.fill_tube_bore_radius_mm, "chamber_1",
                                  np.where(r[above] < lay.fill_tube_outer_radius_mm, _TOP_GAP, "chamber_2"))
            out[bore & (z > zb0) & (z < zb1)] = _TOP_GAP
            out[bore & (z <= zb0) & (z >= zpt)] = "chamber_1"
        # --- the annulus between the tubes
        ann = (z > z0) & (z < zc) & (r > rio) & (r < rb)
        out[ann] = "chamber_2"  # gas outside the bladder, fluid inside it and in the support ring at its pressure
        if lay.has_top_annulus:
            out[ann & (z >= lay.z_collar1)] = "chamber_1"
            collar = ann & (z > lay.z_free1) & (z < lay.z_collar1)
            out[collar] = np.where(z[collar] > lay.z_collar_seal[0] - 0.05, _TOP_GAP, "chamber_2")
        return out

    def beyond_seals(self, r_mm, z_mm) -> np.ndarray:
        """Points of the end pieces' joints on the far side of their static O-rings (the thread, its run-out, the
        tube's ends): at atmospheric pressure while the seal holds.

        Parameters
        ----------
        r_mm, z_mm : array_like
            Points, mm.

        Returns
        -------
        ndarray of bool
            True beyond the base's seal (below its groove) or the top cap's (above its groove), outside the
            groove's root radius; all False for a design without a joint (flags, dimensionless).
        """
        r = np.atleast_1d(np.asarray(r_mm, dtype=float))
        z = np.atleast_1d(np.asarray(z_mm, dtype=float))
        lay = self.lay
        out = np.zeros(r.shape, dtype=bool)
        if not lay.has_joint:
            return out
        out |= (z <= lay.z_base_top) & (r > lay.base_seal.groove_diameter_mm / 2 - 0.05) & (z < lay.z_base_seal[0] - 1e-3)
        if lay.cap_seal is not None:
            out |= (z >= lay.z_cap) & (r > lay.cap_seal.groove_diameter_mm / 2 - 0.05) & (z > lay.z_cap_seal[1] + 1e-3)
        return out

    def annulus_fit(self, r_mm, z_mm) -> np.ndarray:
        """Points of a fit in the outer tube's bore between the base's seal and mid-length (the base's bladder
        clamp in the bore): open to the annulus only, so at chamber-2 pressure (the fluid under the piston
        reaches the base's joints through its own bores, not the outer bore; the bladder's fluid is at chamber 2).

        Parameters
        ----------
        r_mm, z_mm : array_like
            Points, mm.

        Returns
        -------
        ndarray of bool
            True in such a fit; all False for a design without a joint (flags, dimensionless).
        """
        r = np.atleast_1d(np.asarray(r_mm, dtype=float))
        z = np.atleast_1d(np.asarray(z_mm, dtype=float))
        lay = self.lay
        if not lay.has_joint:
            return np.zeros(r.shape, dtype=bool)
        return ((r >= lay.outer_bore_radius_mm - 0.05) & (z > lay.z_base_seal[1] + 1e-3)
                & (z < 0.5 * (lay.z_base_top + lay.z_cap)))

    def joint_gap(self, z_mm) -> np.ndarray:
        """The gap medium of the joint nearest a level (the base's below mid-length, the top's above).

        Parameters
        ----------
        z_mm : array_like
            Levels, mm.

        Returns
        -------
        ndarray of str
            ``gap:chamber_2|fluid`` or ``gap:chamber_1|chamber_2`` (labels, dimensionless).
        """
        z = np.atleast_1d(np.asarray(z_mm, dtype=float))
        return np.where(z < 0.5 * (self.lay.z_base_top + self.lay.z_cap), _BASE_GAP, _TOP_GAP).astype(object)

    def pressures(self, media: np.ndarray, case_gauge_MPa: dict[str, float]) -> np.ndarray:
        """Gauge pressure on each labelled point for a load case.

        Parameters
        ----------
        media : ndarray of str
            Labels from :meth:`medium` (dimensionless).
        case_gauge_MPa : dict of str to float
            Gauge pressure of ``chamber_1``, ``chamber_2`` and ``fluid``, MPa.

        Returns
        -------
        ndarray
            MPa (0 on ``air`` and ``contact``).
        """
        return np.array([_pressure(m, case_gauge_MPa) for m in media], dtype=float)


def _pressure(medium: str, p: dict[str, float]) -> float:
    if medium in ("air", "contact"):
        return 0.0
    if medium.startswith("gap:"):
        return max(p[k] for k in medium[4:].split("|"))
    return p[medium]
