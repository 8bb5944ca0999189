"""The inner tube's ends and the bulkhead's fill tube seated and sealed in the end pieces (the buildability rules).

A hydraulic-cylinder designer does not clamp a tube between lapped faces: each end of the inner tube sits in an
annular **seat** (a counterbore of the tube's wall, ``r_piston .. r_inner_tube``) of the base and of the top cap,
one seal zone deep (:func:`~vvea_design.spring.joints.seal_zone_mm`: the entry land with the lead-in, the ISO 3601-2
static gland, a plain land). The end piece's material inside the seat is a spigot in the tube's bore: its static
male gland (ISO 3601-1 ring of ``fixed.joint_seal_cross_section_mm``) seals on the honed bore, which the tube's end
reaches over a lead-in chamfer (ISO 3601-2; at the bottom end the same chamfer leads the piston's rings in). So

* at the base, the fluid column (the tube's bore) is sealed from the bladder's oil (a throttle bypass otherwise);
* at the top cap, chamber 1 (or in ``bulkhead`` the chamber-2 space above the web) is sealed from the oil along the
  tube under the clamp.

``annulus_top`` has no top seat: chamber 1 is on both sides of the tube's slotted top end. In ``bulkhead`` the fill
tube's top end is turned to a Ø3.8 neck (:data:`FILL_NECK_MM`) that enters a bore in the top cap one seal zone
deep, sealed by O-ring 007 in a static female gland of the cap (the neck's end chamfered, ISO 3601-2).

A design sized by the gas-only rules has no seats (its tubes butt on the end pieces: the leak audit says so).
Lengths mm, assembly frame (z = 0 under the base).
"""

from __future__ import annotations

from dataclasses import dataclass, replace

from ..spring.joints import LEAD_IN_GAP_MM, seal_lead_in_land_mm, seal_zone_mm
from .errors import CadError
from .seals import Gland, LeadIn, SealError, static_female_gland, static_male_gland

__all__ = ["TubeSeats", "tube_seats", "FILL_NECK_MM", "SEAT_FLOOR_WALL_MM"]

#: Diameter of the fill tube's neck in the top cap: the largest under the Ø4 tube that an ISO 3601-1 ring seats on
#: with 0-5 % stretch (007, 3.68 x 1.78: 3.3 %), mm.
FILL_NECK_MM = 3.8
#: Least metal between a seat's floor and the valve bores under it (the base), mm.
SEAT_FLOOR_WALL_MM = 1.5


@dataclass(frozen=True)
class TubeSeats:
    """The seats of the inner tube's ends (and the fill tube's neck) with their glands and lead-ins, mm."""

    depth_mm: float  #: seat depth = the seal zone (entry land, gland, land)
    base: Gland  #: the base's spigot in the tube's bore (static male)
    z_base_floor: float  #: the seat's floor in the base: the tube's bottom end
    z_base_groove: tuple[float, float]
    lead_in_bottom: LeadIn  #: the tube's bore at its bottom end (the seat's ring and the piston's rings)
    top: Gland | None = None  #: the top cap's spigot in the tube's bore (None in ``annulus_top``)
    z_top_end: float = 0.0  #: the tube's top end in the cap's seat
    z_top_groove: tuple[float, float] = (0.0, 0.0)
    lead_in_top: LeadIn | None = None  #: the tube's bore at its top end
    fill: Gland | None = None  #: the fill tube's neck in the cap (``bulkhead``; static female)
    z_neck_top: float = 0.0  #: the neck's end
    z_neck_groove: tuple[float, float] = (0.0, 0.0)
    lead_in_neck: LeadIn | None = None  #: on the neck's outside edge

    @property
    def neck_radius_mm(self) -> float:
        """Radius of the fill tube's neck, mm."""
        return FILL_NECK_MM / 2


def _gland(fn, d_mm: float, cs: float, kind: str, where: str, field: str) -> Gland:
    try:
        return replace(fn(d_mm, cs, kind), where=where)
    except SealError as exc:
        raise CadError(f"{field} ({where}): {exc}") from None


def _lead_in(rings: list[Gland], room: float, field: str) -> LeadIn:
    ring = max(rings, key=lambda g: g.protrusion_mm + g.oring.cross_section_tolerance_mm)
    try:
        return ring.lead_in(room)
    except SealError as exc:
        raise CadError(f"{field}: {exc}") from None


def tube_seats(lay) -> TubeSeats | None:
    """The seats of ``lay`` (a :class:`~vvea_design.cad.layout.Layout`); None under the gas-only rules.

    Parameters
    ----------
    lay : Layout
        The design's layout (its joint, radii and levels), mm.

    Returns
    -------
    TubeSeats or None
        The seats, their glands and lead-ins.

    Raises
    ------
    CadError
        No ring fits, or a seat reaches the valve bores (names the field to change).
    """
    if not lay.has_joint:
        return None
    f = lay.design.fixed
    land, field = f.seal_land_mm, "fixed.joint_seal_cross_section_mm"
    bore = 2 * lay.piston_radius_mm
    z0, z1 = lay.z_base_top, lay.z_cap
    base = _gland(static_male_gland, bore, f.joint_seal_cross_section_mm, "tube_base", "inner tube's bottom end in "
                  "the base (static, on the tube's bore)", field)
    cs = base.oring.cross_section_mm  # the preferred series, or the other where none of it fits the bore
    h, entry = seal_zone_mm(cs, land), seal_lead_in_land_mm(cs, land)
    room = entry - LEAD_IN_GAP_MM
    floor = z0 - h
    if floor < lay.z_valve + 0.5 * lay.throttle_d + SEAT_FLOOR_WALL_MM - 1e-9:
        raise CadError(f"fixed.min_base_mm: the inner tube's seat in the base ({h:.2f} mm deep) leaves less than "
                       f"{SEAT_FLOOR_WALL_MM:g} mm over the valve bores")
    g0 = floor + entry
    out = dict(depth_mm=h, base=base, z_base_floor=floor, z_base_groove=(g0, g0 + base.width_mm),
               lead_in_bottom=_lead_in([base, lay.piston_seal], room, field))
    if not lay.has_top_annulus:
        top = _gland(static_male_gland, bore, cs, "tube_top", "inner tube's top end in the top cap (static, on "
                     "the tube's bore)", field)
        out.update(top=top, z_top_end=z1 + h, z_top_groove=(z1 + land, z1 + land + top.width_mm),
                   lead_in_top=_lead_in([top], room, field))
    if lay.has_bulkhead:
        fill = _gland(static_female_gland, FILL_NECK_MM, 1.78, "fill_tube", "fill tube's neck in the top cap "
                      "(static, on the neck)", "fixed.fill_tube_outer_mm")
        h_f = seal_zone_mm(1.78, land)
        out.update(fill=fill, z_neck_top=z1 + h_f, z_neck_groove=(z1 + land, z1 + land + fill.width_mm),
                   lead_in_neck=_lead_in([fill], seal_lead_in_land_mm(1.78, land) - LEAD_IN_GAP_MM,
                                         "fixed.fill_tube_outer_mm"))
        if FILL_NECK_MM >= f.fill_tube_outer_mm or fill.groove_diameter_mm / 2 >= lay.piston_radius_mm - 1.0:
            raise CadError(f"fixed.fill_tube_outer_mm = {f.fill_tube_outer_mm:g} mm: the fill tube's Ø"
                           f"{FILL_NECK_MM:g} neck and its O-ring {fill.oring.code} need a larger tube")
    return TubeSeats(**out)
