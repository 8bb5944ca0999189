"""The typed records of one design that the CAD, the FE check and the design file read: the load cases and
every pressure-bearing piece under them (:class:`~vvea_design.spring.loads.PieceLoad`), the joints
(:mod:`~vvea_design.spring.joints`), the drawn tolerances of the sized walls
(:class:`~vvea_design.spring.tolerances.DrawnTolerance`) and the damper's hydraulics
(:class:`~vvea_design.spring.hydraulics.Hydraulics`).

Under ``fixed.sizing_rules = "gas_only"`` (a design made before the buildability rules) the same records are
computed for the pieces as drawn: the load cases and tolerances applied to its walls, a thread chosen to pass its
bore; their safety factors then say what those rules missed. Lengths mm, pressures MPa, forces N.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace
from typing import Any

import numpy as np

from ..materials.structural import get_material
from .geometry import Section
from .hydraulics import Hydraulics, hydraulics_record
from .joints import (INTERNAL_RUNOUT_PITCHES, ISO261_FINE_MM, RUNOUT_PITCHES, seal_passage_mm, THREAD_CLASSES, THREAD_PITCH_MM, TIE_ROD_SIZES, RingJoint,
                     SeatJoint, ThreadJoint, TieRodJoint, select_thread, thread_geometry)
from .loads import Loads, PieceLoad, load_cases
from .records import Record
from .tolerances import DrawnTolerance

__all__ = ["Buildability", "buildability", "PIECE_PARTS"]

#: The CAD part each pressure-bearing piece belongs to.
PIECE_PARTS = {"outer_tube": "housing_outer_tube", "inner_tube": "housing_inner_tube", "top_cap": "housing_top_cap",
               "base": "housing_base", "bulkhead": "housing_inner_tube", "collar": "housing_inner_tube",
               "piston_floor": "piston"}
_FACES = {"outer_tube": "chamber 2 inside (annulus_top: chamber 1 too)",
          "inner_tube": "chamber 2 outside; chamber 1 / fluid inside",
          "top_cap": "the higher chamber on its underside (seal circle)",
          "base": "the higher of the fluid and chamber 2 on its top (seal circle)",
          "bulkhead": "chamber 2 above, chamber 1 below", "collar": "chamber 2 below, chamber 1 above",
          "piston_floor": "fluid below, chamber 1 above"}
_METHODS = {"outer_tube": "Lamé thick tube, Tresca at the bore (with the tie rods' clamp force)",
            "inner_tube": "Lamé thick tube, Tresca; elastic buckling of a long tube E/(4(1-nu²))(t/r)³",
            "top_cap": "circular plate simply supported at the joint, load on the seal circle (Timoshenko)",
            "base": "circular plate simply supported at the joint, load on the seal circle (Timoshenko)",
            "bulkhead": "circular plate simply supported over the bore",
            "collar": "annular plate cantilevered from the inner tube, 6 M / t²",
            "piston_floor": "annular plate clamped at the rod, free at the pocket wall: 6 M / t², Tresca 2 x 1.5 Q / t"}


@dataclass(frozen=True)
class Buildability(Record):
    """Everything the buildability rules say about one design (the design file's ``structure``, ``joints``
    and ``hydraulics`` blocks)."""

    sizing_rules: str  #: ``fixed.sizing_rules`` the design was sized by
    joint: str  #: the joint choice
    loads: Loads  #: the load cases (MPa, N)
    pieces: dict  #: piece -> :class:`~vvea_design.spring.loads.PieceLoad`
    joints: tuple  #: the joint records (thread / ring / tie rods, and the inner tube's seats)
    tolerances: tuple  #: :class:`~vvea_design.spring.tolerances.DrawnTolerance` of the sized walls
    hydraulics: Hydraulics

    def to_dict(self) -> dict[str, Any]:
        """JSON-ready content.

        Returns
        -------
        dict
            ``structure`` (the load cases, the pieces, the tolerances: MPa, N, mm), ``joints`` (list) and
            ``hydraulics`` (N s/mm, mm, MPa), with the sizing rules and the joint.
        """
        return {"structure": {"sizing_rules": self.sizing_rules, "joint": self.joint,
                              "load_cases": self.loads.to_dict(),
                              "pieces": {k: p.to_dict() for k, p in self.pieces.items()},
                              "tolerances": [t.to_dict() for t in self.tolerances]},
                "joints": [j.to_dict() for j in self.joints], "hydraulics": self.hydraulics.to_dict()}


def _f(v) -> float:
    """One design's value as a float."""
    return float(np.asarray(v, dtype=float).reshape(-1)[0])


def _post_hoc_section(design, loads: Loads) -> Section:
    """A gas-only design's section with the buildability rules' tolerances and a thread chosen to pass its bore
    (its sizes are as drawn; the checks say what they carry)."""
    from .sizing import _end_loads, size_joint
    from .tolerances import it_tolerance_mm

    f = design.fixed
    sec: Section = design.derived.section
    built = replace(f, sizing_rules="buildable")
    ro = np.asarray(design.outer_diameter_mm / 2)
    ri = design.piston_diameter_mm / 2
    ri_l = np.asarray(ri + it_tolerance_mm(2 * ri, f.bore_tolerance_grade) / 2)
    js = size_joint("thread", ro, loads, design.variant, built, ri_l)
    rb = _f(sec.outer_bore_radius_mm)
    P = THREAD_PITCH_MM
    passage = seal_passage_mm(f.joint_seal_cross_section_mm)  # the O-rings pass the thread's crests (ISO 3601-2)
    D = next((d for d in ISO261_FINE_MM if thread_geometry(d, P)["D1"] >= 2 * (rb + passage)), ISO261_FINE_MM[-1])
    top, base = _end_loads(loads, np.asarray(rb + it_tolerance_mm(2 * rb, f.bore_tolerance_grade) / 2), design.variant,
                           ri_l)
    th = select_thread(ro - it_tolerance_mm(2 * ro, f.outside_tolerance_grade) / 2, top, base,
                       get_material(f.housing_material).yield_MPa, f.wall_safety_factor, candidates=(D,))
    q = dict(js.quantities, **{"thread_" + k: v for k, v in th.items()}, top_end_load_N=top, base_end_load_N=base)
    P_zone = (RUNOUT_PITCHES + INTERNAL_RUNOUT_PITCHES) * P + js.seal_zone_mm
    js = replace(js, quantities=q, top_support_radius_mm=th["pitch_diameter_mm"] / 2,
                 base_support_radius_mm=th["pitch_diameter_mm"] / 2, bore_cap_radius_mm=np.asarray(np.inf),
                 top_zone_mm=th["engagement_top_mm"] + P_zone, base_zone_mm=th["engagement_base_mm"] + P_zone,
                 utilisation=th["utilisation"])
    return replace(sec, thickness_tolerance_class=f.thickness_tolerance_class, bore_grade=f.bore_tolerance_grade,
                   outside_grade=f.outside_tolerance_grade, outer_tube_outer_radius_mm=sec.outer_radius_mm, joint=js,
                   base_own_mm=sec.walls_mm["base"])


def _pieces(design, sec: Section, loads: Loads) -> dict[str, PieceLoad]:
    """Every piece's check in every case, its governing case."""
    from .derive import _floor_stress
    from .sizing import check_section, governing

    f = design.fixed
    chk = check_section(sec, loads, f, design.variant, _floor_stress)
    gov = governing(chk)
    names = [c.name for c in loads.cases]
    out = {}
    for piece, (k, st, sf, req) in gov.items():
        out[piece] = PieceLoad(piece, PIECE_PARTS[piece], _FACES[piece], _METHODS[piece], names[int(k)], _f(st),
                               _f(sf), _f(req), {n: _f(chk["safety"][piece][n]) for n in names})
    return out


def _governing_case(loads: Loads, load) -> str:
    """The case with the largest ``load(case) x SF(case)``."""
    vals = [_f(load(c)) * c.required_safety_factor for c in loads.cases]
    return loads.cases[int(np.argmax(vals))].name


def _end_load_fns(design):
    """The top cap's and the base's end load in a case, N (as the sizing takes them)."""
    from .sizing import base_annulus_pressure, base_pressure, cap_pressure
    from .tolerances import it_tolerance_mm

    f = design.fixed
    rb, ri = design.outer_bore_radius_mm, design.piston_diameter_mm / 2
    area = math.pi * (rb + it_tolerance_mm(2 * rb, f.bore_tolerance_grade) / 2) ** 2
    bore = math.pi * (ri + it_tolerance_mm(2 * ri, f.bore_tolerance_grade) / 2) ** 2
    return ((lambda c: cap_pressure(c) * area + np.fmax(c.external_force_N, 0.0)),
            (lambda c: base_pressure(c) * bore + base_annulus_pressure(c) * (area - bore)))


def _thread_records(design, js, loads: Loads, ends=("top_cap", "base")) -> list:
    """The threaded joints' records."""
    f, q = design.fixed, js.quantities
    sf = f.wall_safety_factor
    P = THREAD_PITCH_MM
    top_fn, base_fn = _end_load_fns(design)
    out = []
    for end in ends:
        key = "top" if end == "top_cap" else "base"
        short = bool(_f(q[f"thread_short_{key}"]))
        cls = THREAD_CLASSES["S" if short else "N"][2]
        D = _f(q["thread_major_mm"])
        L = _f(q[f"thread_engagement_{key}_mm"])
        fn = top_fn if end == "top_cap" else base_fn
        out.append(ThreadJoint(
            joint=end, kind="thread", designation=f"M{D:g}x{P:g}-{cls}", standard="ISO 261, ISO 965-1, ISO 68-1",
            tolerance_class=cls, major_diameter_mm=D, pitch_mm=P, pitch_diameter_mm=_f(q["thread_pitch_diameter_mm"]),
            minor_diameter_mm=_f(q["thread_minor_mm"]), engagement_length_mm=L, runout_mm=RUNOUT_PITCHES * P,
            seal_zone_mm=js.seal_zone_mm, zone_mm=L + (RUNOUT_PITCHES + INTERNAL_RUNOUT_PITCHES) * P + js.seal_zone_mm,
            end_load_N=_f(q[f"{key}_end_load_N"]), governing_case=_governing_case(loads, fn),
            safety_factors={"tube_wall_under_the_root": _f(q["thread_wall_safety"]),
                            "stripping": _f(q[f"thread_stripping_{key}_safety"])},
            required_safety_factor=sf))
    return out


def _ring_record(design, js, loads: Loads) -> RingJoint:
    q = js.quantities
    top_fn, _ = _end_load_fns(design)
    d1 = _f(q["ring_bore_mm"])
    return RingJoint(joint="top_cap", kind="ring_top", designation=f"DIN 472 - {d1:g} x {_f(q['ring_thickness_mm']):g}",
                     standard="DIN 472 (bd_warehouse data)", bore_mm=d1, groove_diameter_mm=_f(q["ring_groove_diameter_mm"]),
                     groove_width_mm=_f(q["ring_groove_width_mm"]), ring_thickness_mm=_f(q["ring_thickness_mm"]),
                     land_mm=_f(q["ring_land_mm"]), mass_g=_f(q["ring_mass_g"]), end_load_N=_f(q["top_end_load_N"]),
                     governing_case=_governing_case(loads, top_fn),
                     safety_factors={"groove": _f(q["ring_groove_safety"]), "ring": _f(q["ring_ring_safety"]),
                                     "tube_wall_under_the_groove": _f(q["ring_wall_safety"])},
                     required_safety_factor=design.fixed.wall_safety_factor)


def _rod_record(design, js, loads: Loads) -> TieRodJoint:
    f, q = design.fixed, js.quantities
    top_fn, base_fn = _end_load_fns(design)
    n, d = int(_f(q["rods_count"])), _f(q["rods_d"])
    size = TIE_ROD_SIZES[int(_f(q["rods_size"]))]
    cls = f.tie_rod_property_class
    m = _f(q["rods_nut_m"])
    L = design.housing_length_mm + 2 * m + 2 * d
    gov = max((_governing_case(loads, top_fn), _governing_case(loads, base_fn)),
              key=lambda name: _f(top_fn(loads.case(name))) + _f(base_fn(loads.case(name))))
    return TieRodJoint(
        joint="top_cap_and_base", kind="tie_rods",
        designation=f"{n} x DIN 976-1 M{d:g}x{_f(q['rods_P']):g} - {cls}, ISO 4032 nuts ({size})",
        standard="ISO 898-1, ISO 261, DIN 976-1, ISO 4032, ISO 273; preload and torque VDI 2230-1", count=n,
        nominal_diameter_mm=d, pitch_mm=_f(q["rods_P"]), property_class=cls,
        stress_area_mm2=_f(q["rods_stress_area_mm2"]), rod_circle_radius_mm=_f(q["rods_rod_circle_radius_mm"]),
        clearance_hole_mm=_f(q["rods_hole"]), nut_width_across_flats_mm=_f(q["rods_nut_s"]), nut_height_mm=m,
        rod_length_mm=L, preload_max_N=_f(q["rods_preload_max_N"]), preload_min_N=_f(q["rods_preload_min_N"]),
        tightening_torque_Nm=_f(q["rods_torque_Nm"]), load_factor=_f(q["rods_load_factor"]),
        end_load_N=max(_f(q["top_end_load_N"]), _f(q["base_end_load_N"])), governing_case=gov,
        safety_factors={"separation": _f(q["rods_separation_safety"]), "rod_yield": _f(q["rods_yield_safety"])},
        required_safety_factor=f.wall_safety_factor)


def _seats(design, loads: Loads) -> list[SeatJoint]:
    """The inner tube bears on the base and under the top cap (no fastener): the largest force through each seat."""
    f, sec = design.fixed, design.derived.section
    Re = get_material(f.housing_material).yield_MPa
    ri, rio = sec.piston_radius_mm, sec.inner_tube_outer_radius_mm
    area = math.pi * (_f(rio) ** 2 - _f(ri) ** 2)
    A1 = design.A1_mm2
    a_ann = math.pi * (design.outer_bore_radius_mm**2 - design.inner_tube_outer_radius_mm**2)
    lay = design.variant
    out = []
    for joint, what, load in (
            ("inner_tube_base", "the inner tube's lower end in the base's recess: bulkhead / collar pushed down, "
                                "the tube's own end pressure", lambda c: np.fmax(c.chamber_2_MPa - c.chamber_1_MPa, 0.0)),
            ("inner_tube_top", "the inner tube's upper end under the top cap: bulkhead / collar pushed up",
             lambda c: np.fmax(c.chamber_1_MPa - c.chamber_2_MPa, 0.0))):
        face = A1 if lay.has_bulkhead else (a_ann if lay.has_top_annulus else 0.0)
        F = max(_f(load(c)) * face * c.required_safety_factor / f.wall_safety_factor for c in loads.cases)
        sigma = F / area
        out.append(SeatJoint(joint=joint, kind="seat", what=what, end_load_N=F, bearing_stress_MPa=sigma,
                             safety_factor=Re / sigma if sigma > 0 else math.inf,
                             required_safety_factor=f.wall_safety_factor))
    return out


def _tolerances(design, sec: Section) -> tuple[DrawnTolerance, ...]:
    """The drawn tolerances of the sized walls."""
    f = design.fixed
    gb, go, tc = f.bore_tolerance_grade, f.outside_tolerance_grade, f.thickness_tolerance_class
    w = design.walls_mm()
    out = [DrawnTolerance.of("outside", "outer_tube_outside", "housing_outer_tube", 2 * _f(sec.outer_tube_outer_radius_mm), go),
           DrawnTolerance.of("bore", "outer_tube_bore", "housing_outer_tube", 2 * design.outer_bore_radius_mm, gb),
           DrawnTolerance.of("bore", "inner_tube_bore", "housing_inner_tube", design.piston_diameter_mm, gb),
           DrawnTolerance.of("outside", "inner_tube_outside", "housing_inner_tube", 2 * design.inner_tube_outer_radius_mm, go),
           DrawnTolerance.of("thickness", "top_cap_thickness", "housing_top_cap", w["top_cap"], tc),
           DrawnTolerance.of("thickness", "base_thickness", "housing_base", _f(sec.base_own_mm), tc)]
    for piece, part in (("bulkhead", "housing_inner_tube"), ("collar", "housing_inner_tube"), ("piston_floor", "piston")):
        if piece in w:
            out.append(DrawnTolerance.of("thickness", f"{piece}_thickness", part, w[piece], tc))
    return tuple(out)


def buildability(design) -> Buildability:
    """The buildability records of one design.

    Parameters
    ----------
    design : Design
        The design (either sizing rules).

    Returns
    -------
    Buildability
        Its load cases (MPa, N), pieces with their governing case and safety factor, joints, drawn tolerances
        (mm) and hydraulics (N s/mm).
    """
    g = design.derived
    loads = g.load_cases
    if loads is None:  # a gas-only design: the load cases of the pieces as drawn
        from .derive import peak_pressures

        pr = peak_pressures(np.asarray(design.A1_mm2), np.asarray(design.A2_mm2), np.asarray(design.V1_mm3),
                            np.asarray(design.V2_mm3), design.p2_MPa, design.setpoint_x0_mm, design.fixed)
        loads = load_cases(pr, design.p2_MPa, design.A1_mm2, design.A2_mm2, replace(design.fixed, sizing_rules="buildable"))
        sec = _post_hoc_section(design, loads)
    else:
        sec = g.section
    js = sec.joint
    if design.fixed.sizing_rules == "gas_only" or js.kind == "thread":
        joints = _thread_records(design, js, loads)
    elif js.kind == "ring_top":
        joints = [_ring_record(design, js, loads)] + _thread_records(design, js, loads, ends=("base",))
    else:
        joints = [_rod_record(design, js, loads)]
    joints += _seats(design, loads)
    kind = "thread" if design.fixed.sizing_rules == "gas_only" else js.kind
    return Buildability(design.fixed.sizing_rules, kind, loads, _pieces(design, sec, loads), tuple(joints),
                        _tolerances(design, sec), hydraulics_record(g.hydraulic_path, design.fixed))

