"""The housing's joints as drawn: what the design's joint records (:mod:`vvea_design.spring.joints`) put into the
geometry -- the end pieces' spigots inside the outer tube, their threads, run-outs and seal zones, the
retaining ring's plug and groove, the tie rods' circle and holes.

Under the buildability rules (``fixed.sizing_rules = "buildable"``) the design sizes a joint and its footprint
(:class:`~vvea_design.spring.joints.JointSizing`); this module turns them into axial levels and radii:

``thread``
    The outer tube runs from the base's own part (``base_own``) to the top cap's shoulder. Each end piece's spigot
    inside it, from the shoulder inwards: the thread's run-out undercut (DIN 76-1, to the external minor
    diameter ``d3``), the thread (drawn as its pitch cylinder ``d2``; ISO 261 fine, ISO 965-1 class), the tube's
    internal thread run-out (DIN 76-1, the spigot plain there), then the seal zone at the bore with its static
    O-ring. The tube's ends are threaded over run-out, thread and internal run-out; the bore (the seal's) lies
    inside the thread's minor diameter by the ring's passage (ISO 3601-2), reached over the lead-in chamfer at the
    seal zone's entry, so no O-ring touches a thread crest on assembly.
``ring_top``
    The base as for ``thread``. The top cap is a plug of the ring's bore ``d1`` in a counterbore of the tube's top
    end, its seal zone at the plug; a DIN 472 ring in its groove ``d2 x m`` above the plug, the tube's land above.
``tie_rods``
    The outer tube (thinner: inside the rod circle) from the base's own part to the top cap's shoulder; each end
    piece's spigot is its seal zone only; ``N`` rods (DIN 976-1, ISO 898-1 class, ISO 4032 nuts) pass holes in
    both end pieces outside the tube, at angles clear of the valve bores (+-x) and the ports (+y).

A design sized by the gas-only rules has none: its tubes butt on the base and the cap (the pieces are cut by
planes) and its static seals sit in spigots the CAD adds (``kind = "none"``). Lengths mm.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from ..spring.design import Design
from ..spring.joints import INTERNAL_RUNOUT_PITCHES

__all__ = ["ThreadZone", "RingZone", "RodPattern", "JointGeometry", "joint_geometry"]


@dataclass(frozen=True)
class ThreadZone:
    """One end piece's threaded spigot: levels (z, mm) and diameters (mm) of its run-out, thread and seal zone."""

    end: str  #: ``base`` or ``top_cap``
    designation: str  #: e.g. ``M56x1.5-5H/5g6g``
    major_mm: float  #: D
    pitch_mm: float
    pitch_diameter_mm: float  #: d2: the thread is drawn as this cylinder
    external_minor_mm: float  #: d3: the run-out undercut
    internal_minor_mm: float  #: D1
    engagement_mm: float
    runout: tuple[float, float]  #: z range of the run-out undercut (next to the shoulder)
    thread: tuple[float, float]  #: z range of the engaged thread
    seal: tuple[float, float]  #: z range of the seal zone (the spigot's tip)
    #: z range of the tube's internal thread run-out (DIN 76-1), between the engaged thread and the seal zone: the
    #: tube keeps the thread's minor bore there, the spigot is plain at its seal diameter
    relief: tuple[float, float] = (0.0, 0.0)

    @property
    def internal(self) -> tuple[float, float]:
        """z range of the tube's internal thread with its run-out (engaged thread and relief), mm."""
        return min(self.thread[0], self.relief[0]), max(self.thread[1], self.relief[1])


@dataclass(frozen=True)
class RingZone:
    """The ``ring_top`` joint: the cap plug in the tube's counterbore and the DIN 472 ring's groove above it."""

    designation: str
    bore_mm: float  #: d1: the counterbore and the plug
    groove_diameter_mm: float  #: d2
    groove_width_mm: float  #: m
    ring_thickness_mm: float  #: s
    plug: tuple[float, float]  #: z range of the plug (its seal zone at its bottom)
    groove: tuple[float, float]  #: z range of the groove (right above the plug)


@dataclass(frozen=True)
class RodPattern:
    """The ``tie_rods`` joint: rods, their circle, holes, nuts and the angles they stand at."""

    designation: str
    count: int
    diameter_mm: float
    pitch_mm: float
    property_class: str
    circle_radius_mm: float
    hole_mm: float  #: ISO 273 normal clearance hole
    nut_s_mm: float
    nut_m_mm: float
    length_mm: float
    torque_Nm: float
    angles_deg: tuple[float, ...]  #: from +x towards +y


@dataclass(frozen=True)
class JointGeometry:
    """The joint as drawn: its kind, the outer tube's ends and radius, the threads, ring or rods, the seal zones."""

    kind: str  #: ``none`` (gas-only rules: butt joints), ``thread``, ``ring_top`` or ``tie_rods``
    z_tube_bottom: float  #: the outer tube's bottom end, mm
    z_tube_top: float  #: the outer tube's top end, mm
    tube_outer_radius_mm: float
    base_thread: ThreadZone | None = None
    cap_thread: ThreadZone | None = None
    ring: RingZone | None = None
    rods: RodPattern | None = None
    base_seal: tuple[float, float] | None = None  #: z range of the base's joint seal zone (None: the CAD's spigot)
    cap_seal: tuple[float, float] | None = None  #: z range of the top cap's joint seal zone

    def to_dict(self) -> dict:
        """JSON-ready content.

        Returns
        -------
        dict
            The kind, the tube's ends and radius (mm), and the designations of the threads, ring and rods.
        """
        out = {"kind": self.kind, "z_tube_bottom_mm": self.z_tube_bottom, "z_tube_top_mm": self.z_tube_top,
               "tube_outer_radius_mm": self.tube_outer_radius_mm}
        for name in ("base_thread", "cap_thread", "ring", "rods"):
            v = getattr(self, name)
            if v is not None:
                out[name] = v.designation
        return out


def _thread_zone(end: str, rec, z_shoulder: float, inward: float, seal_mm: float) -> ThreadZone:
    """Levels of a threaded spigot from its shoulder ``z_shoulder`` going ``inward`` (+1 up, -1 down)."""
    run, L = rec.runout_mm, rec.engagement_length_mm
    D, P = rec.major_diameter_mm, rec.pitch_mm
    z_a = z_shoulder
    z_b = z_a + inward * run
    z_c = z_b + inward * L
    z_r = z_c + inward * INTERNAL_RUNOUT_PITCHES * P
    z_d = z_r + inward * seal_mm
    return ThreadZone(end, rec.designation, D, P, rec.pitch_diameter_mm, D - 1.226869 * P, rec.minor_diameter_mm, L,
                      tuple(sorted((z_a, z_b))), tuple(sorted((z_b, z_c))), tuple(sorted((z_r, z_d))),
                      tuple(sorted((z_c, z_r))))


def _rod_angles(count: int, hole_r: float, circle_r: float) -> tuple[float, ...]:
    """Rod angles clear of the +-x valve bores and the +y ports: the offset (1 deg steps) that keeps the rods
    furthest, in angle, from 0, 90 and 180 deg."""
    keep = (0.0, 90.0, 180.0)
    best = None
    for off in range(0, int(360 / count)):
        angs = [(off + k * 360.0 / count) % 360.0 for k in range(count)]
        gap = min(min(abs((a - b + 180) % 360 - 180) for b in keep) for a in angs)
        if best is None or gap > best[0] + 1e-9:
            best = (gap, tuple(sorted(angs)))
    return best[1]


def joint_geometry(design: Design, z_cap: float, z_top: float) -> JointGeometry:
    """The joint of ``design`` as drawn (levels in the assembly frame, z = 0 under the base).

    Parameters
    ----------
    design : Design
        The design (its joint records under the buildability rules).
    z_cap : float
        The top cap's underside (top of the inner tube), mm.
    z_top : float
        The housing's top, mm.

    Returns
    -------
    JointGeometry
        ``kind = "none"`` for a gas-only design (its tubes butt between the base and the cap).
    """
    R = design.outer_diameter_mm / 2
    if design.fixed.sizing_rules == "gas_only":
        return JointGeometry("none", design.base_mm, z_cap, R)
    sec = design.derived.section
    js = sec.joint
    b_own = float(sec.base_own_mm)
    seal = float(js.seal_zone_mm)
    recs = {(r.joint, r.kind): r for r in design.joints()}
    base_rec = recs.get(("base", "thread"))
    if design.joint == "tie_rods":
        rec = recs[("top_cap_and_base", "tie_rods")]
        rods = RodPattern(rec.designation, int(rec.count), rec.nominal_diameter_mm, rec.pitch_mm, rec.property_class,
                          rec.rod_circle_radius_mm, rec.clearance_hole_mm, rec.nut_width_across_flats_mm,
                          rec.nut_height_mm, rec.rod_length_mm, rec.tightening_torque_Nm,
                          _rod_angles(int(rec.count), rec.clearance_hole_mm / 2, rec.rod_circle_radius_mm))
        top_zone = float(js.top_zone_mm)
        return JointGeometry("tie_rods", b_own, z_cap + top_zone, float(js.tube_outer_radius_mm), rods=rods,
                             base_seal=(b_own, b_own + seal), cap_seal=(z_cap, z_cap + seal))
    base = _thread_zone("base", base_rec, b_own, +1.0, seal)
    if design.joint == "thread":
        cap_rec = recs[("top_cap", "thread")]
        zs = z_cap + float(js.top_zone_mm)  # the cap's shoulder: the tube's top end
        cap = _thread_zone("top_cap", cap_rec, zs, -1.0, seal)
        return JointGeometry("thread", b_own, zs, R, base_thread=base, cap_thread=cap, base_seal=base.seal,
                             cap_seal=cap.seal)
    rec = recs[("top_cap", "ring_top")]
    plug = z_top - z_cap - float(js.top_extra_mm)
    ring = RingZone(rec.designation, rec.bore_mm, rec.groove_diameter_mm, rec.groove_width_mm, rec.ring_thickness_mm,
                    (z_cap, z_cap + plug), (z_cap + plug, z_cap + plug + rec.groove_width_mm))
    return JointGeometry("ring_top", b_own, z_top, R, base_thread=base, ring=ring, base_seal=base.seal,
                         cap_seal=(z_cap, z_cap + seal))
