"""The assembly order and its check: the parts go together in the stated order along the axis without
interference, and no O-ring passes a sharp edge.

:func:`assembly_plan` lists the steps (:class:`AssemblyStep`): which parts move, along the axis, from where,
against which parts already assembled, and the O-rings fitted. :func:`check_assembly` checks each insertion
on the parts' meridian sections:

* **sweep**: the moving parts' material, swept along the axis from the start offset to the assembled
  position, must not overlap the material of the parts it moves against. Exact for bodies of revolution;
  the sections of the valve plane and of the port plane (both halves) are united per part, so holes do not
  hide material (max-material, conservative). The bladder is elastic: its cuffs' beads snap into their
  grooves, so it is not swept as a rigid body (:data:`ELASTIC`).
* **O-rings**: every O-ring that one side carries past the other sweeps the band between the surface it
  seals on and its free radius (cross-section tolerance included). Every outline edge of the other part
  in that band, over the ring's path, must be the sealing surface itself or a lead-in chamfer at 15 ... 20
  deg that reaches beyond the band (ISO 3601-2); anything else is a sharp edge the ring is dragged over. The
  internal threads are drawn at their pitch cylinder: their crests (the minor diameter ``D1``, ISO 965-1) are
  checked as cylinders of their own (:func:`thread_crests`), so a ring that would ride over a thread is caught.

Lengths in mm; z along the axis, r from it.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass

import numpy as np

from .layout import Layout
from .seals import Gland

__all__ = ["AssemblyStep", "RingCrossing", "StepCheck", "AssemblyCheck", "assembly_plan", "check_assembly",
           "ring_paths", "thread_crests", "ELASTIC", "sweep_overlap_mm", "part_profile"]

#: Parts that are not swept as rigid bodies: the bladder's cuffs snap into their grooves (elastic).
ELASTIC = ("bladder",)
_TOL = 1e-4  # overlap (mm) accepted: line-to-line fits touch


@dataclass(frozen=True)
class AssemblyStep:
    """One step of the assembly: the parts moved along the axis, from ``start_mm`` above (> 0) or below (< 0)
    their assembled position, against the parts already assembled; the O-rings fitted; what to do."""

    number: int
    text: str  #: the instruction
    moving: tuple[str, ...] = ()  #: part names moved together in this step (empty: no insertion)
    against: tuple[str, ...] = ()  #: part names already assembled that the moving ones pass
    start_mm: float = 0.0  #: axial offset the moving parts start at, mm (they end at 0)
    rings: tuple[str, ...] = ()  #: gland kinds whose O-rings are fitted before this step

    def to_dict(self) -> dict:
        """JSON-ready content.

        Returns
        -------
        dict
            ``number``, ``text``, ``moving``, ``against``, ``start_mm`` (mm) and ``rings``.
        """
        return {"number": self.number, "text": self.text, "moving": list(self.moving), "against": list(self.against),
                "start_mm": round(self.start_mm, 6), "rings": list(self.rings)}


@dataclass(frozen=True)
class RingCrossing:
    """An O-ring carried past an edge on assembly: the edge's outline in the ring's band and whether it is a
    lead-in chamfer (ISO 3601-2)."""

    step: int
    ring: str  #: gland kind
    part: str  #: the part whose edges the ring passes
    edges: tuple[str, ...]  #: the outline edges met in the band (``lead-in`` ones and any other)
    ok: bool  #: only the sealing surface and lead-in chamfers in the band

    def to_dict(self) -> dict:
        """JSON-ready content.

        Returns
        -------
        dict
            ``step``, ``ring``, ``part``, ``edges`` and ``ok``.
        """
        return {"step": self.step, "ring": self.ring, "part": self.part, "edges": list(self.edges), "ok": bool(self.ok)}


@dataclass(frozen=True)
class StepCheck:
    """One step checked: the largest overlap of the swept material (mm along the axis; 0: free), where, and the
    O-rings' crossings."""

    step: AssemblyStep
    max_overlap_mm: float
    where: str  #: "" or the parts and the radius of the worst overlap
    crossings: tuple[RingCrossing, ...]

    @property
    def passes(self) -> bool:
        """No overlap beyond line-to-line contact and every O-ring meets only lead-in chamfers."""
        return self.max_overlap_mm <= _TOL and all(c.ok for c in self.crossings)

    def to_dict(self) -> dict:
        """JSON-ready content.

        Returns
        -------
        dict
            The step (:meth:`AssemblyStep.to_dict`), ``max_overlap_mm`` (mm), ``where``, ``crossings`` and
            ``passes``.
        """
        return {**self.step.to_dict(), "max_overlap_mm": round(self.max_overlap_mm, 6), "where": self.where,
                "crossings": [c.to_dict() for c in self.crossings], "passes": self.passes}


@dataclass(frozen=True)
class AssemblyCheck:
    """The assembly order checked step by step."""

    steps: tuple[StepCheck, ...]

    @property
    def passes(self) -> bool:
        """Every step passes."""
        return all(s.passes for s in self.steps)

    def to_dict(self) -> dict:
        """JSON-ready content (the manifest's ``assembly``).

        Returns
        -------
        dict
            ``passes``, ``method`` and ``steps`` (:meth:`StepCheck.to_dict` each).
        """
        return {"passes": self.passes,
                "method": "each insertion swept along the axis on the parts' meridian sections (valve and port "
                          "planes united); O-rings' bands checked for lead-in chamfers 15-20 deg (ISO 3601-2) and for "
                          "the internal threads' crests (D1, ISO 965-1); the "
                          "bladder is elastic (snap-in beads), not swept",
                "steps": [s.to_dict() for s in self.steps]}


# ------------------------------------------------------------------------------------------- the plan
def assembly_plan(lay: Layout) -> tuple[AssemblyStep, ...]:
    """The unit's assembly order (every layout: the piston and the bladder go over the inner tube from its
    bottom end, the sub-assembly onto the base, the outer tube and the top cap from above).

    Parameters
    ----------
    lay : Layout
        Radii and levels of the design, mm.

    Returns
    -------
    tuple of AssemblyStep
        In order, numbered from 1.
    """
    from .bill import proof_pressure_MPa, relief_ball_mm
    from .fill import oil_fill_mm3

    d = lay.design
    z0, z1 = lay.z_base_top, lay.z_cap
    zr = lay.z_piston_bottom(0.0) - d.rod_length_mm
    cuff = ("until its upper cuff snaps into the collar's groove" if lay.has_top_annulus else
            "(its upper cuff is clamped by the top cap later)")
    seats = lay.seats
    z_tube0 = seats.z_base_floor if seats is not None else z0  # the inner tube's bottom end
    top_rings = tuple(k for k, g in (("tube_top", seats and seats.top), ("fill_tube", seats and seats.fill)) if g)
    seat_text = ""
    if top_rings:
        seat_text = (f" Fit O-ring {seats.top.oring.code} on the spigot in the cap's seat"
                     + (f" and O-ring {seats.fill.oring.code} into the groove round the fill tube's neck bore"
                        if seats.fill is not None else "") + "; the tube's top end enters the seat over its lead-in.")
    cap = (f"Fit the top cap's O-ring {lay.cap_seal.oring.code}; lower the cap: its spigot enters the outer tube "
           "over the tube's top lead-in and clamps the bladder's upper cuff in its groove." + seat_text
           if lay.cap_seal is not None else "Lower the plain top cap onto the tubes.")
    cap_start = max(z1 - lay.z_free1, seats.depth_mm if seats is not None else 0.0,
                    seats.z_neck_top - z1 if seats is not None and seats.fill is not None else 0.0) + 1.0
    base_rings = ("rod", "base") + (("tube_base",) if seats is not None else ())
    seat_base = (f" and O-ring {seats.base.oring.code} onto the spigot in the inner tube's seat"
                 if seats is not None else "")
    steps = [
        (f"Fit the rod O-ring {lay.rod_seal.oring.code} and the base spigot's O-ring {lay.base_seal.oring.code} "
         f"into the base's grooves{seat_base} (lubricate with the unit's oil).", (), (), 0.0, base_rings),
        (f"Fit the piston's two O-rings {lay.piston_seal.oring.code}; push the piston, rod first, into the inner "
         "tube from its bottom end (the bore's lead-in guides the rings).", ("piston",), ("housing_inner_tube",),
         -(lay.z_piston_top(0.0) - z_tube0 + 1.0), ("piston",)),
        (f"Press the bladder's lower cuff into the support ring; slide both over the inner tube from its bottom end "
         f"{cuff}.", ("bladder", "support_ring"), ("housing_inner_tube", "piston"),
         -(lay.z_bladder1 - z0 + 1.0), ("collar",) if lay.has_top_annulus else ()),
        ("Lower the inner tube with piston, bladder and support ring onto the base: the rod passes the rod seal "
         "(rod-end lead-in), the support ring enters the base spigot, the bladder's outer bead snaps into the "
         "spigot's groove" + ("; the tube's bottom end enters its seat over the bore's lead-in." if seats is not None
                              else "."), ("housing_inner_tube", "piston", "bladder", "support_ring"), ("housing_base",),
         z0 - zr + 1.0, ()),
        ("Slide the outer tube down over the bladder onto the base: the spigot's O-ring"
         + (" and the collar's" if lay.has_top_annulus else "") + " enter the bore over its bottom lead-in.",
         ("housing_outer_tube",), ("housing_base", "housing_inner_tube", "support_ring", "piston"),
         z1 - z0 + 1.0, ()),
        (cap, ("housing_top_cap",), ("housing_outer_tube", "housing_inner_tube", "piston"),
         cap_start, (("cap",) if lay.cap_seal is not None else ()) + top_rings),
        ("Fit the housing's joints as their drawings and records state (threads, tie rods or retaining rings; "
         "torques in the parts list).", (), (), 0.0, ()),
        (f"Oil: with the piston held at x = 0 and the unit upright, evacuate and fill "
         f"{oil_fill_mm3(lay)['total'] / 1000:.1f} cm³ of oil through the relief bore; fit the relief ball "
         f"Ø{relief_ball_mm(lay):g}, its spring and the set screw (sealant), set to the relief pressure.",
         (), (), 0.0, ()),
        ("Fit the throttle core and the servo (2x M3 ISO 4762, 1.1 N m)"
         + ("; press the expander plug into the cross port's bore." if lay.has_cross_port else "."), (), (), 0.0, ()),
        (f"Screw in the two charging valves (1.5 N m); with the piston held at x = 0 charge nitrogen to chambers 1 "
         f"and 2 alternately in steps of <= 0.5 MPa to p1 = {d.p1_MPa:.2f} and p2 = {d.p2_MPa:.2f} MPa at 20 °C; "
         f"leak test; proof test at {proof_pressure_MPa(lay):.1f} MPa before the charge.", (), (), 0.0, ()),
    ]
    return tuple(AssemblyStep(i, t, m, a, s, r) for i, (t, m, a, s, r) in enumerate(steps, start=1))


# ------------------------------------------------------------------------------------------- geometry
def part_profile(solid) -> list[list[np.ndarray]]:
    """A part's meridian sections, (r, z) with r >= 0: the valve plane's and the port plane's halves, each a
    list of closed loops (even-odd inside).

    Parameters
    ----------
    solid : build123d.Solid
        The part in the assembly frame, mm.

    Returns
    -------
    list of list of ndarray
        Four loop sets, mm.
    """
    from .section import section_loops

    bb = solid.bounding_box()
    R = max(abs(bb.min.X), abs(bb.max.X), abs(bb.min.Y), abs(bb.max.Y)) + 1.0
    out = []
    for plane in ("xz", "yz"):
        out.append(section_loops(solid, plane, 0.0, R))
        out.append([np.column_stack([-lp[:, 0], lp[:, 1]]) for lp in section_loops(solid, plane, -R, 0.0)])
    return out


def _intervals(loops: Sequence[np.ndarray], r: float) -> list[tuple[float, float]]:
    """z-intervals of material at radius ``r`` (even-odd over the loops)."""
    zs = []
    for lp in loops:
        a, b = lp[:-1], lp[1:]
        cross = (a[:, 0] - r) * (b[:, 0] - r) < 0
        t = (r - a[cross, 0]) / (b[cross, 0] - a[cross, 0])
        zs.extend(a[cross, 1] + t * (b[cross, 1] - a[cross, 1]))
    zs.sort()
    return [(zs[i], zs[i + 1]) for i in range(0, len(zs) - 1, 2)]


def _union(ivs: list[tuple[float, float]]) -> list[tuple[float, float]]:
    out: list[tuple[float, float]] = []
    for lo, hi in sorted(ivs):
        if out and lo <= out[-1][1]:
            out[-1] = (out[-1][0], max(out[-1][1], hi))
        else:
            out.append((lo, hi))
    return out


def _material(profiles: Sequence[list[list[np.ndarray]]], r: float) -> list[tuple[float, float]]:
    return _union([iv for prof in profiles for loops in prof for iv in _intervals(loops, r)])


def _radii(profiles) -> np.ndarray:
    rs = np.unique(np.round(np.concatenate([np.abs(lp[:, 0]) for prof in profiles for loops in prof for lp in loops]),
                            9))
    fr = np.array([0.25, 0.5, 0.75])
    return (rs[:-1, None] + np.diff(rs)[:, None] * fr).ravel()


def sweep_overlap_mm(moving, fixed, start_mm: float) -> tuple[float, float]:
    """Largest axial overlap between the moving parts' material swept from ``start_mm`` to 0 along the axis and
    the fixed parts' material, and the radius where it is.

    Parameters
    ----------
    moving, fixed : sequence of profiles
        :func:`part_profile` of each part, mm.
    start_mm : float
        Axial offset the moving parts start at, mm.

    Returns
    -------
    (float, float)
        Overlap (mm; line-to-line contact gives 0) and its radius (mm).
    """
    worst, at = 0.0, math.nan
    lo_sh, hi_sh = min(start_mm, 0.0), max(start_mm, 0.0)
    for r in _radii([*moving, *fixed]):
        fix = _material(fixed, r)
        if not fix:
            continue
        for a, b in _material(moving, r):
            a, b = a + lo_sh, b + hi_sh  # swept
            for c, d in fix:
                ov = min(b, d) - max(a, c)
                if ov > worst:
                    worst, at = ov, float(r)
    return worst, at


# ------------------------------------------------------------------------------------------- O-rings
def ring_paths(lay: Layout) -> dict[str, tuple[Gland, str, str, tuple[tuple[float, float], ...]]]:
    """Every gland: the part with the groove, the part it seals on, and the groove's axial extents.

    Parameters
    ----------
    lay : Layout
        The design's layout.

    Returns
    -------
    dict
        Gland kind -> (gland, groove part, counter part, ((z0, z1), ...)), mm.
    """
    d = lay.design
    zpb, w = lay.z_piston_bottom(0.0), lay.piston_seal.width_mm
    out = {"piston": (lay.piston_seal, "piston", "housing_inner_tube",
                      tuple((zpb + d.fixed.piston_height_mm * q - w / 2, zpb + d.fixed.piston_height_mm * q + w / 2)
                            for q in (0.27, 0.73))),
           "rod": (lay.rod_seal, "housing_base", "piston", (lay.z_rod_seal,)),
           "base": (lay.base_seal, "housing_base", "housing_outer_tube", (lay.z_base_seal,))}
    if lay.cap_seal is not None:
        out["cap"] = (lay.cap_seal, "housing_top_cap", "housing_outer_tube", (lay.z_cap_seal,))
    if lay.collar_seal is not None:
        out["collar"] = (lay.collar_seal, "housing_inner_tube", "housing_outer_tube", (lay.z_collar_seal,))
    s = lay.seats
    if s is not None:  # the end pieces' spigots in the tube's bore, the cap's groove round the fill tube's neck
        out["tube_base"] = (s.base, "housing_base", "housing_inner_tube", (s.z_base_groove,))
        if s.top is not None:
            out["tube_top"] = (s.top, "housing_top_cap", "housing_inner_tube", (s.z_top_groove,))
        if s.fill is not None:
            out["fill_tube"] = (s.fill, "housing_top_cap", "housing_inner_tube", (s.z_neck_groove,))
    return out


def thread_crests(lay: Layout) -> dict[str, tuple[tuple[float, float, float], ...]]:
    """The internal threads' crests the CAD does not draw (threads are drawn at their pitch cylinder): per part,
    ``(r, z0, z1)`` of each internal thread's minor diameter ``D1`` (ISO 965-1's smallest, H position) over the
    thread and its run-out, mm.

    Parameters
    ----------
    lay : Layout
        The design's layout (its joint).

    Returns
    -------
    dict
        Part name -> crest cylinders ``(r, z0, z1)``, mm.
    """
    out = []
    for t in (lay.joint.base_thread, lay.joint.cap_thread):
        if t is not None:
            z0, z1 = t.internal
            out.append((t.internal_minor_mm / 2, z0, z1))
    return {"housing_outer_tube": tuple(out)} if out else {}


def _crossing(step: AssemblyStep, kind: str, gland: Gland, counter: str, zgs, ring_moves: bool,
              profile, crests=()) -> RingCrossing:
    """The edges of ``counter`` an O-ring's band meets over its path in ``step`` (``crests``: its internal
    threads' crest cylinders ``(r, z0, z1)``, which its drawn outline does not show)."""
    rs = gland.sliding_diameter_mm / 2
    rf = gland.free_sealing_radius_mm
    lo_r, hi_r = min(rs, rf), max(rs, rf)
    # the ring's z path relative to the counter part: it moves by start -> 0 (or the counter part does, the
    # ring then moves the other way relative to it)
    sh = step.start_mm if ring_moves else -step.start_mm
    z_lo = min(min(z0 for z0, _ in zgs) + min(sh, 0.0), min(z0 for z0, _ in zgs))
    z_hi = max(max(z1 for _, z1 in zgs) + max(sh, 0.0), max(z1 for _, z1 in zgs))
    edges, ok = [], True
    seen = set()
    for r, c0, c1 in crests:  # a ring whose band reaches a thread's crests is dragged over them
        if lo_r + 1e-6 < r < hi_r - 1e-6 and c1 >= z_lo - 1e-6 and c0 <= z_hi + 1e-6:
            ok = False
            edges.append(f"thread crests D1 r = {r:.3f} at z = {c0:.2f}...{c1:.2f}")
    for loops in profile:
        for lp in loops:
            for a, b in zip(lp[:-1], lp[1:]):
                if np.allclose(a, b, atol=1e-9):
                    continue
                r0, r1 = sorted((abs(a[0]), abs(b[0])))
                z_a, z_b = sorted((a[1], b[1]))
                if r1 <= lo_r + 1e-6 or r0 >= hi_r - 1e-6 or z_b < z_lo - 1e-6 or z_a > z_hi + 1e-6:
                    continue  # outside the band or the path
                if abs(r1 - r0) < 1e-6:
                    if abs(r0 - rs) < 1e-6:
                        continue  # the sealing surface itself
                    key = f"cylinder r = {r0:.3f} at z = {z_a:.2f}...{z_b:.2f}"
                    ok = False
                elif abs(z_b - z_a) < 1e-6:
                    key = f"face z = {z_a:.3f} over r = {r0:.3f}...{r1:.3f} (sharp edge)"
                    ok = False
                else:
                    ang = math.degrees(math.atan2(r1 - r0, z_b - z_a))
                    good = bool(15.0 - 0.05 <= ang <= 20.0 + 0.05 and r0 <= lo_r + 1e-6 and r1 >= hi_r - 1e-6)
                    key = f"{'lead-in' if good else 'chamfer too short or steep'} {z_b - z_a:.2f} x {ang:.1f}° " \
                          f"(radial {r1 - r0:.2f} over a band of {hi_r - lo_r:.2f})"
                    ok &= good
                if key not in seen:
                    seen.add(key)
                    edges.append(key)
    return RingCrossing(step.number, kind, counter, tuple(edges), ok)


def check_assembly(solids: Mapping[str, object], lay: Layout,
                   plan: Sequence[AssemblyStep] | None = None) -> AssemblyCheck:
    """Check the assembly order on the parts' sections: sweeps without overlap, O-rings only over lead-ins.

    Parameters
    ----------
    solids : mapping of str to Solid
        The parts at x = 0 by name (assembly frame), mm.
    lay : Layout
        The design's layout.
    plan : sequence of AssemblyStep, optional
        The steps (default :func:`assembly_plan`).

    Returns
    -------
    AssemblyCheck
        Per step: the largest overlap (mm), where, and each O-ring's crossing.
    """
    plan = tuple(plan) if plan is not None else assembly_plan(lay)
    names = {n for st in plan for n in (*st.moving, *st.against)}
    prof = {n: part_profile(solids[n]) for n in sorted(names)}
    paths = ring_paths(lay)
    crests = thread_crests(lay)
    out = []
    for st in plan:
        if not st.moving:
            out.append(StepCheck(st, 0.0, "", ()))
            continue
        mov = [prof[n] for n in st.moving if n not in ELASTIC]
        fix = [prof[n] for n in st.against if n not in ELASTIC]
        ov, r = sweep_overlap_mm(mov, fix, st.start_mm) if mov and fix else (0.0, math.nan)
        where = f"{'+'.join(st.moving)} against {'+'.join(st.against)} at r = {r:.2f}" if ov > _TOL else ""
        crossings = []
        for kind, (g, groove_part, counter, zgs) in paths.items():
            if groove_part in st.moving and counter in st.against:
                crossings.append(_crossing(st, kind, g, counter, zgs, True, prof[counter], crests.get(counter, ())))
            elif counter in st.moving and groove_part in st.against:
                # the counter part moves: take its profile at its start and run the ring backwards over it
                crossings.append(_crossing(st, kind, g, counter, zgs, False, prof[counter], crests.get(counter, ())))
        out.append(StepCheck(st, float(ov), where, tuple(crossings)))
    return AssemblyCheck(tuple(out))
