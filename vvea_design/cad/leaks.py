"""Every path a medium could leak along -- each joint between two parts, each port -- and what seals it.

A :class:`LeakPath` names the joint or port, the two spaces it would join (chamber 1, chamber 2, the oil, the
outside), the seal that closes it and its standard, or says that it is **open** and what it needs. The report
prints the list; nothing is marked sealed that the CAD does not draw.

Under the buildability rules the inner tube's ends sit in seats of the base and of the top cap, each sealed by a
static O-ring on the end piece's spigot in the tube's bore, and the bulkhead's fill tube has a neck sealed in the
cap (:mod:`vvea_design.cad.tube_seats`). A design sized by the gas-only rules has no seats: its tube ends butt on
the end pieces and the gas-only ``annulus_top`` plain cap has no spigot; the audit lists those paths as open.
"""

from __future__ import annotations

from dataclasses import dataclass

from .layout import Layout
from .seals import ORING_STANDARD

__all__ = ["LeakPath", "leak_paths"]


@dataclass(frozen=True)
class LeakPath:
    """One joint or port: the spaces it would join, its seal (or none) and its standard."""

    where: str  #: the joint or port
    between: str  #: the two spaces, e.g. ``chamber 2 | outside``
    sealed_by: str  #: the seal ("" when open)
    standard: str  #: the seal's standard
    note: str = ""  #: what is not verified, or what an open path needs

    @property
    def is_sealed(self) -> bool:
        """A seal closes the path."""
        return bool(self.sealed_by)

    @property
    def is_port(self) -> bool:
        """A port (drilled, tapped or plugged), not a joint between parts."""
        return self.where.startswith("port:")

    def to_dict(self) -> dict:
        """JSON-ready content.

        Returns
        -------
        dict
            ``where``, ``between``, ``sealed_by``, ``standard``, ``note`` and ``sealed``.
        """
        return {"where": self.where, "between": self.between, "sealed_by": self.sealed_by, "standard": self.standard,
                "note": self.note, "sealed": self.is_sealed}


def _oring(g, what: str) -> str:
    return f"{what}: O-ring {g.oring.code} ({g.application}, squeeze {100 * g.squeeze:.0f} %)"


def leak_paths(lay: Layout) -> tuple[LeakPath, ...]:
    """The unit's leak paths and their seals.

    Parameters
    ----------
    lay : Layout
        The design's layout (its glands, ports and layout variant).

    Returns
    -------
    tuple of LeakPath
        Joints first, then ports.
    """
    iso = f"{ORING_STANDARD}, ISO 3601-2 gland"
    bead = ("the bladder's sealing bead, clamped in its groove (silicone, drawn line-to-line: its squeeze comes "
            "from the cast size, not verified)")
    top_inside = ("chamber 2 above the bulkhead" if lay.has_bulkhead else "chamber 1")
    out = [
        LeakPath("rod in the base", "oil | outside", _oring(lay.rod_seal, "rod seal"), iso),
        LeakPath("piston in the inner tube", "oil | chamber 1", _oring(lay.piston_seal, "2 piston seals"), iso),
        LeakPath("base spigot in the outer tube", "chamber 2 | outside", _oring(lay.base_seal, "base seal"), iso),
        LeakPath("bladder's lower cuff in the base spigot", "chamber 2 | oil", "bladder bead", "-", bead),
        LeakPath("bladder's upper cuff in its clamp", "chamber 2 | oil", "bladder bead", "-", bead),
    ]
    seats = lay.seats
    bypass = "oil in the column | oil in the bladder (a throttle bypass)"
    if seats is not None:
        out.append(LeakPath("inner tube on the base", bypass, _oring(seats.base, "tube seat seal (base)"), iso,
                            f"the tube's end {seats.depth_mm:.2f} mm deep in the base's seat, the ring on the seat's "
                            "spigot seals on the tube's bore"))
    else:
        out.append(LeakPath("inner tube on the base", bypass, "", "",
                            "gas-only rules: the tube butts on the base (lapped faces, internal leak only); the "
                            "buildability rules seat it with an O-ring"))
    if lay.cap_seal is not None:
        out.append(LeakPath("top cap spigot in the outer tube", "chamber 2 | outside", _oring(lay.cap_seal, "cap seal"),
                            iso))
    if not lay.has_top_annulus and seats is not None:
        out.append(LeakPath("inner tube's top end at the top cap", f"{top_inside} | oil (along the tube under the "
                            "clamp)", _oring(seats.top, "tube seat seal (top cap)"), iso,
                            f"the tube's end {seats.depth_mm:.2f} mm deep in the cap's seat, the ring on the seat's "
                            "spigot seals on the tube's bore"))
    elif not lay.has_top_annulus:
        out.append(LeakPath("inner tube's top end at the top cap", f"{top_inside} | oil (along the tube under the "
                            "clamp)", "", "", "gas-only rules: the tube butts on the cap; the buildability rules seat "
                            "it with an O-ring"))
    if lay.cap_seal is None:
        out.append(LeakPath("top cap on the outer tube", "chamber 1 (annulus) | outside", "", "",
                            "the plain cap has no spigot: a seal needs the joint's footprint (a spigot or a sealed "
                            "joint face) inside the chamber-1 annulus"))
    if lay.collar_seal is not None:
        out.append(LeakPath("collar in the outer tube", "chamber 1 | chamber 2", _oring(lay.collar_seal, "collar seal"),
                            iso))
    if lay.has_bulkhead and seats is not None:
        out.append(LeakPath("fill tube's top end at the top cap", "chamber 1 | chamber 2",
                            _oring(seats.fill, "fill tube neck seal"), iso,
                            f"the fill tube's Ø{2 * seats.neck_radius_mm:g} neck in the cap's bore, the ring in the "
                            "cap's groove"))
    elif lay.has_bulkhead:
        out.append(LeakPath("fill tube's top end at the top cap", "chamber 1 | chamber 2", "", "",
                            "gas-only rules: the fill tube butts on the cap; the buildability rules give it a neck "
                            "and an O-ring"))
    valve = "charging valve with its own seal on the spot face (bought)"
    out += [
        LeakPath("port: chamber-1 charging valve", "chamber 1 | outside", valve, "ISO 261 M5x0.8"),
        LeakPath("port: chamber-2 charging valve", "chamber 2 | outside", valve, "ISO 261 M5x0.8"),
        LeakPath("port: relief valve bore", "oil | outside", "set screw with anaerobic hydraulic thread sealant",
                 "ISO 4026", "a thread sealant, not an O-ring: leak-test after setting"),
        LeakPath("port: throttle bore", "oil | outside", "the throttle core's own O-ring (bought servo-valve)", "-"),
    ]
    if lay.has_cross_port and _cross_port_in_the_tube(lay):
        out.append(LeakPath("port: chamber-2 cross port", "chamber 2 | outside (along the joint)", "", "",
                            "OPEN: drilled from the outside through the outer tube's wall into the cap's spigot, above "
                            "the cap's seal: chamber 2 reaches the joint's thread, and the plug in the tube locks the "
                            "cap; needs the cross port above the tube's end (a thicker cap shoulder) or the valve "
                            "over its port"))
    elif lay.has_cross_port:
        out.append(LeakPath("port: chamber-2 cross port", "chamber 2 | outside", "expander plug (metal-to-metal)",
                            "SFC Koenig MB type"))
    return tuple(out)


def _cross_port_in_the_tube(lay: Layout) -> bool:
    """The top cap's cross port (or its plug's bore) lies below the outer tube's top end: drilled through the tube."""
    if not lay.has_joint or lay.has_top_annulus:
        return False
    return lay.z_cross_port - 0.5 * lay.cad.plug_bore_mm < lay.joint.z_tube_top - 1e-9
