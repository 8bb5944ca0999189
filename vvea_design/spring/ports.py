"""What the CAD must find room for, as the optimiser's constraints: the chamber-2 fill port, the piston's seal and
the base's valve bores.

The chamber-2 gas is charged through a port drilled axially through the bladder clamp's spigot (the top cap's;
in ``annulus_top`` the base's), between the bladder's sealing bead and the root of the spigot's static O-ring
groove. The CAD drills it ``min(cad.fill_port_mm, PORT_ROOM_FRACTION x (groove root radius - bead's outer
radius))`` wide (:attr:`vvea_design.cad.layout.Layout.fill_port_d`), keeps :data:`PORT_WALL_MM` of metal on
each side and cannot draw a port narrower than :data:`MIN_FILL_PORT_MM` (:func:`chamber2_port_fit_mm`); the
optimiser's constraint ``chamber2_port_room`` asks the same of every design, with the deepest groove root the
ISO 3601 static gland allows (:func:`static_groove_root_radius_min_mm`), so a design that meets it always draws.

The piston's O-ring (``piston_seal_fit``): the CAD seats a standard ISO 3601-1 ring of the 1.78 or 2.62 mm series
in a male dynamic gland (0 ... 5 % stretch on the groove's root, the squeeze in bd_warehouse's dynamic window,
:func:`vvea_design.cad.seals.piston_gland`); the ring sizes leave gaps, and a piston bore in a gap cannot be
sealed. :func:`piston_seal_fit_mm` is how far the bore lies inside the nearest window (negative: in a gap).

The base's valve bores (``valve_bore_reach``): the radial throttle and relief bores end
:data:`VALVE_ROD_WALL_MM` outside the rod's bore and must reach the vertical channel from the fluid column, which
sits midway between the rod and the bore, ``min(fixed.fluid_channel_mm, (r_piston - r_rod) / 2)`` wide
(:func:`valve_bore_reach_mm`; a piston less than about 12 mm over the rod leaves no room).

The bead's height (:func:`bead_height_mm`) is the CAD's and the damper's flow path's too
(:mod:`vvea_design.spring.hydraulics`). Lengths mm; vectorised over a population.
"""

from __future__ import annotations

from functools import lru_cache

import numpy as np

from .geometry import Array
from .joints import SERIES_MM, bd_warehouse_rows, static_male_cross_section_mm

__all__ = ["MIN_FILL_PORT_MM", "GAS_ONLY_SEAL_MM", "PORT_ROOM_FRACTION", "BEAD_HEIGHT_MM", "bead_height_mm", "chamber2_port_room_mm", "chamber2_port_fit_mm", "PORT_WALL_MM",
           "static_groove_root_radius_min_mm", "design_chamber2_port_room_mm", "MIN_PISTON_SEAL_FIT_MM",
           "piston_seal_windows_mm", "piston_seal_fit_mm", "VALVE_ROD_WALL_MM", "MIN_VALVE_REACH_MM",
           "valve_bore_reach_mm"]

#: The narrowest chamber-2 fill port the CAD drills (a Ø0.5 mm drill; below it the charging valve's flow and the
#: drill's life are not worth a design), mm.
MIN_FILL_PORT_MM = 0.5
#: Least metal on each side of the chamber-2 port (to the bead's seat and to the groove's root), mm.
PORT_WALL_MM = 0.4
#: Share of the radial land between the bead and the groove's root the port may take (the rest: 20 % wall on
#: each side of the drilling), dimensionless.
PORT_ROOM_FRACTION = 0.6
#: The spigots' O-ring series of a design sized by the gas-only rules (no joint: the CAD's
#: ``cad.CadParameters.oring_cross_section_mm``), mm.
GAS_ONLY_SEAL_MM = 1.78
#: How far inside a ring's window the piston's bore must lie (a design on a window's edge is one rounding away
#: from a gap), mm.
MIN_PISTON_SEAL_FIT_MM = 0.01
#: Wall the radial valve bores keep to the rod's bore in the base, mm.
VALVE_ROD_WALL_MM = 1.5
#: How far the base's channel must reach past the valve bores' inner end (they must meet), mm.
MIN_VALVE_REACH_MM = 0.05
#: Largest radial height of the bladder's sealing beads (``cad.CadParameters.bead_height_mm``), mm.
BEAD_HEIGHT_MM = 0.4


def bead_height_mm(inner_tube_outer_radius_mm, bladder_inner_radius_mm, outer_bore_radius_mm,
                   bladder_outer_radius_mm, largest_mm: float = BEAD_HEIGHT_MM) -> Array:
    """Radial height of the bladder's sealing beads: ``largest_mm``, shrunk to a quarter of the free gap on
    either side of the cast bladder, mm.

    Parameters
    ----------
    inner_tube_outer_radius_mm, bladder_inner_radius_mm, outer_bore_radius_mm, bladder_outer_radius_mm : array
        Radii of the inner tube's outside, the cast bladder's inside and outside and the outer bore, mm.
    largest_mm : float
        The largest bead (the CAD's ``bead_height_mm``), mm.

    Returns
    -------
    ndarray
        Bead height, mm.
    """
    rio, rbi, rb, rbo = (np.asarray(v, dtype=float) for v in (inner_tube_outer_radius_mm, bladder_inner_radius_mm,
                                                              outer_bore_radius_mm, bladder_outer_radius_mm))
    return np.fmin(largest_mm, np.fmin(0.25 * (rbi - rio), 0.25 * (rb - rbo)))


def chamber2_port_room_mm(seal_root_radius_mm, bladder_outer_radius_mm, bead_mm) -> Array:
    """Widest chamber-2 fill port between the bladder's bead and the spigot's seal groove root, mm.

    Parameters
    ----------
    seal_root_radius_mm : array
        Root radius of the spigot's static O-ring groove, mm.
    bladder_outer_radius_mm : array
        The cast bladder's outer radius, mm.
    bead_mm : array
        The sealing bead's height (:func:`bead_height_mm`), mm.

    Returns
    -------
    ndarray
        ``PORT_ROOM_FRACTION x (root - (bladder outer radius + bead))``, mm (a port needs at least
        :data:`MIN_FILL_PORT_MM`).
    """
    return PORT_ROOM_FRACTION * (np.asarray(seal_root_radius_mm, dtype=float)
                                 - np.asarray(bladder_outer_radius_mm, dtype=float) - np.asarray(bead_mm, dtype=float))


def chamber2_port_fit_mm(seal_root_radius_mm, bladder_outer_radius_mm, bead_mm) -> Array:
    """Widest chamber-2 fill port both of the CAD's rules allow: the drilling, ``PORT_ROOM_FRACTION`` of the land
    between the bead and the groove's root (:func:`chamber2_port_room_mm`), and :data:`PORT_WALL_MM` of metal on
    each side of it, mm (the CAD draws the port when this is at least :data:`MIN_FILL_PORT_MM`).

    Parameters
    ----------
    seal_root_radius_mm, bladder_outer_radius_mm, bead_mm : array
        As :func:`chamber2_port_room_mm`, mm.

    Returns
    -------
    ndarray
        ``min(PORT_ROOM_FRACTION x land, land - 2 PORT_WALL_MM)``, mm.
    """
    room = chamber2_port_room_mm(seal_root_radius_mm, bladder_outer_radius_mm, bead_mm)
    return np.fmin(room, room / PORT_ROOM_FRACTION - 2 * PORT_WALL_MM)


def _deepest_static_groove_mm(cross_section_mm: float) -> float:
    """Deepest radial groove of an ISO 3601 static male gland (the least squeeze of bd_warehouse's table), mm."""
    row = next(r for r in bd_warehouse_rows("o-ring_static_gland_parameters.csv")
               if abs(float(r["w"]) - cross_section_mm) < 1e-6)
    return cross_section_mm * (1 - float(row["sq_r_p_min"]) / 100)


def static_groove_root_radius_min_mm(bore_radius_mm, cross_section_mm: float) -> Array:
    """Smallest root radius of the static male O-ring groove that seals a bore: the ring of the preferred series
    where one fits (:func:`~vvea_design.spring.joints.static_male_cross_section_mm`), its groove at the deepest
    the ISO 3601 squeeze window allows (the CAD's groove, whichever standard ring it seats, is never deeper), mm.

    Parameters
    ----------
    bore_radius_mm : array
        Radius of the bore the ring seals on, mm.
    cross_section_mm : float
        The preferred O-ring cross-section, mm (1.78 or 2.62).

    Returns
    -------
    ndarray
        Root radius, mm.
    """
    rb = np.asarray(bore_radius_mm, dtype=float)
    w = static_male_cross_section_mm(2 * rb, cross_section_mm)
    depth = np.select([w == s for s in SERIES_MM], [_deepest_static_groove_mm(s) for s in SERIES_MM], np.nan)
    return rb - depth


def design_chamber2_port_room_mm(outer_bore_radius_mm, inner_tube_outer_radius_mm, bladder_inner_radius_mm,
                                 bladder_outer_radius_mm, cross_section_mm: float) -> Array:
    """The chamber-2 fill port a design guarantees the CAD (the optimiser's ``chamber2_port_room``), mm.

    Both spigots the port may pass (the top cap's, the base's in ``annulus_top``) seal on the outer bore with a
    static male gland; the groove is taken at its deepest (:func:`static_groove_root_radius_min_mm`).

    Parameters
    ----------
    outer_bore_radius_mm, inner_tube_outer_radius_mm, bladder_inner_radius_mm, bladder_outer_radius_mm : array
        Radii of the outer bore, the inner tube's outside and the cast bladder, mm.
    cross_section_mm : float
        The preferred cross-section of the spigot's O-ring (``fixed.joint_seal_cross_section_mm``; 1.78 without
        a joint), mm.

    Returns
    -------
    ndarray
        Port room (:func:`chamber2_port_fit_mm`), mm (>= :data:`MIN_FILL_PORT_MM` draws).
    """
    bead = bead_height_mm(inner_tube_outer_radius_mm, bladder_inner_radius_mm, outer_bore_radius_mm,
                          bladder_outer_radius_mm)
    root = static_groove_root_radius_min_mm(outer_bore_radius_mm, cross_section_mm)
    return chamber2_port_fit_mm(root, bladder_outer_radius_mm, bead)


@lru_cache(maxsize=1)
def piston_seal_windows_mm() -> np.ndarray:
    """The piston bores a standard O-ring of the 1.78 or 2.62 mm series seals in a male dynamic gland, mm.

    A ring of inner diameter ``d`` and cross-section ``w`` seats when its groove root lies in
    ``[d, 1.05 d]`` (0 ... 5 % stretch) and the groove depth in ``w (1 - squeeze)`` over bd_warehouse's dynamic
    squeeze window: the bore lies in ``[d + 2 w (1 - sq_max), 1.05 d + 2 w (1 - sq_min)]``.

    Returns
    -------
    ndarray
        Rows (lowest, highest bore), mm.
    """
    out = []
    for w in SERIES_MM:
        row = next(r for r in bd_warehouse_rows("o-ring_dynamic_gland_parameters.csv") if abs(float(r["w"]) - w) < 1e-6)
        lo_d, hi_d = w * (1 - float(row["sq_p_max"]) / 100), w * (1 - float(row["sq_p_min"]) / 100)
        out += [(d + 2 * lo_d, 1.05 * d + 2 * hi_d) for d in (float(r["iso3601:id"]) for r in
                bd_warehouse_rows("o-ring_parameters.csv") if r.get("iso3601:w") and abs(float(r["iso3601:w"]) - w) < 1e-6)]
    return np.array(sorted(out))


def piston_seal_fit_mm(piston_diameter_mm) -> Array:
    """How far the piston's bore lies inside the nearest window of :func:`piston_seal_windows_mm` (the distance to
    the window's nearer edge; negative in a gap between the standard rings: the CAD cannot seal it), mm.

    Parameters
    ----------
    piston_diameter_mm : float or array
        The piston's bore, mm.

    Returns
    -------
    ndarray
        Fit, mm.
    """
    b = np.asarray(piston_diameter_mm, dtype=float)[..., None]
    win = piston_seal_windows_mm()
    return np.max(np.fmin(b - win[:, 0], win[:, 1] - b), axis=-1)


def valve_bore_reach_mm(piston_diameter_mm, rod_diameter_mm: float, fluid_channel_mm: float) -> Array:
    """How far the base's channel from the fluid column reaches inside the valve bores' inner end (> 0: they
    meet), mm.

    Parameters
    ----------
    piston_diameter_mm : float or array
        The piston's bore, mm.
    rod_diameter_mm, fluid_channel_mm : float
        ``fixed.rod_diameter_mm`` and ``fixed.fluid_channel_mm``, mm.

    Returns
    -------
    ndarray
        ``(r_rod + r_piston)/2 - channel/2 - (r_rod + VALVE_ROD_WALL_MM)``, mm.
    """
    rp, rr = 0.5 * np.asarray(piston_diameter_mm, dtype=float), 0.5 * rod_diameter_mm
    channel = np.fmin(fluid_channel_mm, 0.5 * (rp - rr))
    return 0.5 * (rr + rp) - 0.5 * channel - (rr + VALVE_ROD_WALL_MM)
