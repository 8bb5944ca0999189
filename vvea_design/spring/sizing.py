"""The buildability rules (``fixed.sizing_rules = "buildable"``): every pressure-bearing piece sized for every
load case (:mod:`~vvea_design.spring.loads`) at the least-material condition of its drawn tolerance
(:mod:`~vvea_design.spring.tolerances`), the joint chosen (:mod:`~vvea_design.spring.joints`) with its
footprint, and the check of the drawn pieces (:func:`check_section`).

Pieces and their loads (each case's pressures, the working cases at ``fixed.wall_safety_factor`` on yield, the
proof test at ``fixed.proof_safety_factor``):

* **outer tube**: chamber-2 gas inside (``annulus_top``: chamber 1 too), Lamé, Tresca ``2 p ro^2/(ro^2 - rb^2)``
  at the bore, with tie rods also the rods' clamp force as axial compression; at most the joint's bore (thread
  minor diameter, ring bore) and never thinner than ``fixed.min_outer_wall_mm``;
* **inner tube**: chamber 2 outside with nothing inside (the fluid cavitating, conservative) and the fluid or
  chamber 1 inside above chamber 2 outside (the relief and damping cases): Tresca ``2 |p_i - p_o| ro^2/(ro^2 -
  ri^2)``; elastic buckling of a long tube, ``p_cr = E/(4 (1 - nu^2)) (t/r)^3``, under chamber 2 less the lower
  of chamber 1 and the fluid;
* **top cap**, **base**: circular plates simply supported at the joint (thread pitch radius, ring bore, rod
  circle): the higher of the chambers on the seal's circle (cap), the fluid on the bore's circle and chamber 2 on
  the rest of the seal's (base)
  (:func:`~vvea_design.spring.loads.plate_centre_moment_per_MPa`); the cap at least its joint zone plus a
  shoulder, the base its own part (valves, channels, rod seal) plus its joint zone;
* **bulkhead**, **collar** (the layouts' own walls): ``|chamber 2 - chamber 1|``;
* **piston floor** (``fixed.piston_pocket``): ``|fluid - chamber 1|``, the relief case's fluid among them.

Lengths mm, pressures and stresses MPa, forces N; arrays broadcast over a population.
"""

from __future__ import annotations

import math
from dataclasses import replace

import numpy as np

from ..materials.structural import get_material
from .geometry import Array, Section
from .joints import (CROSS_PORT_SHOULDER_MM, INTERNAL_RUNOUT_PITCHES, JOINT_SHOULDER_MM, RUNOUT_PITCHES, THREAD_PITCH_MM,
                     E_STEEL_MPa, JointSizing, PROPERTY_CLASSES, seal_passage_mm, seal_zone_mm, select_ring,
                     select_thread, standard_seal_bore_radius_mm, tie_rod_candidates,
                     tie_rod_preload, SERIES_MM, static_male_cross_section_mm)
from .concentration import concentration_factor
from .layouts.base import LayoutVariant
from .loads import LoadCase, Loads, lame_tresca_MPa, plate_centre_moment_per_MPa
from .parameters import FixedParameters
from .tolerances import it_tolerance_mm

#: The pressure-bearing pieces.
PIECES = ("outer_tube", "inner_tube", "top_cap", "base", "bulkhead", "collar", "piston_floor")

__all__ = ["PIECES", "size_section", "size_joint", "check_section", "governing", "outer_tube_pressure", "tube_seat_mm"]


def outer_tube_pressure(case: LoadCase, layout: LayoutVariant) -> Array:
    """Pressure inside the outer tube in a load case: chamber 2 (``annulus_top``: the higher of both chambers), MPa.

    Parameters
    ----------
    case : LoadCase
        The pressures on each kind of face, MPa.
    layout : LayoutVariant
        Whether chamber 1 also fills the annulus (``has_top_annulus``).

    Returns
    -------
    ndarray
        Pressure on the outer tube's bore, MPa.
    """
    if layout.has_top_annulus:
        return np.fmax(case.chamber_2_MPa, case.chamber_1_MPa)
    return case.chamber_2_MPa


# The pressure on each loaded face of the end pieces in a load case, MPa: the top cap's underside (the higher of
# the two chambers, conservative for every layout), the base inside the inner tube (the fluid under the piston)
# and the base around it (chamber 2: the bladder's fluid and gas).
def cap_pressure(case: LoadCase) -> Array:  # noqa: D103 - the comment above
    return np.fmax(case.chamber_1_MPa, case.chamber_2_MPa)


def base_pressure(case: LoadCase) -> Array:  # noqa: D103 - the comment above
    return case.fluid_MPa


def base_annulus_pressure(case: LoadCase) -> Array:  # noqa: D103 - the comment above
    return case.chamber_2_MPa


def _inner_tube_pressure(case: LoadCase) -> Array:
    """What sizes the inner tube's wall: chamber 2 outside with nothing inside, or the higher of chamber 1 and the
    fluid inside less chamber 2 outside, MPa."""
    inside = np.fmax(case.chamber_1_MPa, case.fluid_MPa)
    return np.fmax(case.chamber_2_MPa, inside - case.chamber_2_MPa)


def _buckling_pressure(case: LoadCase) -> Array:
    """Net external pressure on the inner tube: chamber 2 less the lower of chamber 1 and the fluid, >= 0, MPa."""
    return np.fmax(case.chamber_2_MPa - np.fmin(case.chamber_1_MPa, case.fluid_MPa), 0.0)


def tube_seat_mm(piston_radius_mm, f: FixedParameters) -> Array:
    """Depth of the inner tube's seats in the base and the top cap (the CAD's :mod:`vvea_design.cad.tube_seats`): the
    seal zone of the static O-ring that the end piece's spigot carries in the tube's bore (the joint's series, the
    other where none of it fits that bore: ISO 3601-1 sizes, 0-5 % stretch), mm.

    Parameters
    ----------
    piston_radius_mm : float or array
        The tube's bore radius, mm.
    f : FixedParameters
        The joint's O-ring series and the seal land, mm.

    Returns
    -------
    ndarray
        The seat's depth, mm.
    """
    cs = static_male_cross_section_mm(2 * np.asarray(piston_radius_mm, dtype=float), f.joint_seal_cross_section_mm)
    return sum(np.where(cs == w, seal_zone_mm(w, f.seal_land_mm), 0.0) for w in SERIES_MM)


def _seal_zone_mm(f: FixedParameters) -> float:
    """Axial room of a joint's static O-ring: the ISO 3601 static gland (bd_warehouse), a land, and on the side the
    ring enters the bore the room of the bore's lead-in chamfer (:func:`~.joints.seal_zone_mm`, ISO 3601-2), mm."""
    return seal_zone_mm(f.joint_seal_cross_section_mm, f.seal_land_mm)


def _end_loads(loads: Loads, r_seal, layout: LayoutVariant, r_bore) -> tuple[Array, Array]:
    """Effective end loads of the top cap (the higher chamber on the seal's circle plus the tension on the eyes) and
    of the base (the fluid on the inner tube's bore circle ``r_bore``, chamber 2 on the rest of the seal's), N."""
    area = math.pi * np.asarray(r_seal) ** 2

    def m(x):  # a case's array against a seal circle per candidate (tie rods: one more axis)
        x = np.asarray(x)
        return x.reshape(x.shape + (1,) * (area.ndim - x.ndim)) if area.ndim > x.ndim else x

    bore = math.pi * np.asarray(r_bore) ** 2
    per = area.ndim <= np.ndim(loads.cases[0].chamber_2_MPa)  # the cases stacked unless a candidate axis follows
    top = loads.effective(lambda c: m(cap_pressure(c)) * area + m(np.fmax(c.external_force_N, 0.0)), stacked=per)
    base = loads.effective(lambda c: m(base_pressure(c)) * m(bore) + m(base_annulus_pressure(c)) * (area - m(bore)),
                           stacked=per)
    return top, base


def _tube_bore_lmc(r_t_lmc, loads: Loads, layout: LayoutVariant, yield_MPa: float, compression_N=0.0):  # yield / K
    """Largest bore radius at the least-material condition the outer tube carries every case with, mm (nan where
    none): Tresca ``2 p ro^2/(ro^2 - rb^2)`` and, with an axial compression ``F_c``, ``(p (ro^2 + rb^2) + F_c/pi)
    / (ro^2 - rb^2)``."""
    ro2 = np.asarray(r_t_lmc) ** 2
    Fc = np.asarray(compression_N)
    st = loads.stacked
    p = outer_tube_pressure(st, layout)  # (C, S)
    if np.ndim(ro2) > np.ndim(p) - 1:  # a candidate axis after the population's
        p = p[..., None]
    sa = (yield_MPa / st.required_safety_factor).reshape((-1,) + (1,) * (p.ndim - 1))
    with np.errstate(divide="ignore", invalid="ignore"):
        r2 = np.fmin(ro2 * (1 - 2 * p / sa), ((sa - p) * ro2 - Fc / math.pi) / (sa + p))
    rb2 = np.min(r2, axis=0)
    return np.sqrt(np.where(rb2 > 0, rb2, np.nan))


def _thread_joint(ro, loads, layout, f, Re, sf, seal, ring_top: bool, r_bore) -> JointSizing:
    """``thread`` (both ends) or ``ring_top`` (ring at the top, thread at the base) for a population."""
    r_t_l = ro - it_tolerance_mm(2 * ro, f.outside_tolerance_grade) / 2
    rb_l = _tube_bore_lmc(r_t_l, loads, layout, Re)
    r_seal = np.where(np.isfinite(rb_l), rb_l, ro - f.min_outer_wall_mm)
    top, base = _end_loads(loads, r_seal, layout, r_bore)
    th = select_thread(r_t_l, top, base, Re, sf, base_only=ring_top)
    P = THREAD_PITCH_MM
    # the O-rings pass the internal thread on assembly: its crests (D1) clear the free ring and the bore's lead-in
    # (ISO 3601-2), the bore at its largest included
    passage = seal_passage_mm(f.joint_seal_cross_section_mm)
    cap = th["minor_mm"] / 2 - passage - it_tolerance_mm(th["minor_mm"], f.bore_tolerance_grade) / 2
    run = (RUNOUT_PITCHES + INTERNAL_RUNOUT_PITCHES) * P  # the spigot's and the tube's thread run-outs (DIN 76-1)
    base_zone = th["engagement_base_mm"] + run + seal
    q = {"thread_" + k: v for k, v in th.items()}
    q.update(top_end_load_N=top, base_end_load_N=base)
    if not ring_top:
        return JointSizing("thread", ro * np.ones_like(r_t_l), cap, th["pitch_diameter_mm"] / 2,
                           th["pitch_diameter_mm"] / 2, th["engagement_top_mm"] + run + seal,
                           base_zone, np.zeros_like(r_t_l), th["utilisation"], seal, q)
    rg = select_ring(r_t_l, top, Re, sf)
    # the cap plug seals in the bore below its counterbore: the O-ring passes the ring's groove and the counterbore
    # clear (ISO 3601-2)
    cap_ring = rg["bore_mm"] / 2 - passage - it_tolerance_mm(rg["bore_mm"], f.bore_tolerance_grade) / 2
    q.update({"ring_" + k: v for k, v in rg.items()})
    return JointSizing("ring_top", ro * np.ones_like(r_t_l), np.fmin(cap, cap_ring), rg["bore_mm"] / 2,
                       th["pitch_diameter_mm"] / 2, seal * np.ones_like(r_t_l), base_zone,
                       rg["groove_width_mm"] + rg["land_mm"], np.fmax(th["utilisation"], rg["utilisation"]), seal, q)


def _tie_rod_joint(ro, loads, layout, f, Re, sf, seal, r_bore) -> JointSizing:
    """``tie_rods``: every arrangement tried, the one that leaves the largest bore kept."""
    c = tie_rod_candidates(ro)
    Rp = PROPERTY_CLASSES[f.tie_rod_property_class][0]
    pre = tie_rod_preload(c["d"], c["P"], Rp)
    r_t = c["tube_outer_radius_mm"]
    r_t_l = r_t - it_tolerance_mm(2 * r_t, f.outside_tolerance_grade) / 2
    rb_l0 = _tube_bore_lmc(r_t_l, loads, layout, Re)
    top, base = _end_loads(loads, np.where(np.isfinite(rb_l0), rb_l0, r_t_l), layout, r_bore)
    FA = np.fmax(top, base) / c["count"]
    Fc = c["count"] * pre["preload_max_N"]
    rb_l = _tube_bore_lmc(r_t_l, loads, layout, Re, Fc)
    rb = rb_l - it_tolerance_mm(2 * np.nan_to_num(rb_l), f.bore_tolerance_grade) / 2
    E_h = get_material(f.housing_material).youngs_modulus_MPa
    with np.errstate(divide="ignore", invalid="ignore"):
        k_rod = E_STEEL_MPa * pre["stress_area_mm2"]
        phi = k_rod / (k_rod + E_h * math.pi * (r_t_l**2 - rb_l**2) / c["count"])
        u_sep = sf * (1 - phi) * FA / pre["preload_min_N"]
        u_rod = (pre["preload_max_N"] + phi * FA) / (Rp * pre["stress_area_mm2"])
    util = np.fmax(u_sep, u_rod)
    ok = c["fits"] & (util <= 1.0) & np.isfinite(rb)
    score = np.where(ok, np.fmin(np.nan_to_num(rb, nan=-1.0), r_t - f.min_outer_wall_mm), -np.inf)
    k = np.argmax(score, axis=-1)

    def pick(arr):
        return np.take_along_axis(np.broadcast_to(arr, score.shape), k[..., None], axis=-1)[..., 0]

    found = np.isfinite(pick(score))
    q = {"rods_" + name: pick(v) for name, v in c.items()}
    q.update({"rods_" + name: pick(v) for name, v in pre.items()})
    q.update(rods_load_factor=pick(phi), rods_separation_safety=sf / pick(u_sep), rods_yield_safety=1 / pick(u_rod),
             rods_compression_N=pick(Fc * np.ones_like(score)), top_end_load_N=pick(top), base_end_load_N=pick(base))
    Rc = pick(c["rod_circle_radius_mm"])
    return JointSizing("tie_rods", pick(r_t), np.where(found, pick(rb), np.nan), Rc, Rc, seal * np.ones_like(Rc),
                       seal * np.ones_like(Rc), np.zeros_like(Rc), np.where(found, pick(util), np.inf), seal, q)


def size_joint(kind: str, ro_mm, loads: Loads, layout: LayoutVariant, fixed: FixedParameters, bore_radius_mm) -> JointSizing:
    """The joint ``kind`` sized for a population: its footprint and its own sizes.

    Parameters
    ----------
    kind : str
        ``"thread"``, ``"ring_top"`` or ``"tie_rods"`` (:data:`~vvea_design.spring.joints.JOINTS`).
    ro_mm : array
        Envelope radius (half the outer diameter), mm.
    loads : Loads
        The load cases (MPa, N).
    layout : LayoutVariant
        The layout (which pressure fills the outer tube).
    fixed : FixedParameters
        Tolerance grades, seals, the rods' property class, the housing material.
    bore_radius_mm : array
        The inner tube's bore at its least-material condition (the fluid's circle on the base), mm.

    Returns
    -------
    JointSizing
        Tube radius, bore cap, support radii, axial zones (mm), utilisation (dimensionless), sizes.

    Raises
    ------
    ValueError
        For an unknown joint kind.
    """
    Re = get_material(fixed.housing_material).yield_MPa
    sf, seal = fixed.wall_safety_factor, _seal_zone_mm(fixed)
    ro = np.asarray(ro_mm, dtype=float)
    Re = Re / concentration_factor("outer_tube")  # the joint's wall checks are the outer tube's
    if kind in ("thread", "ring_top"):
        return _thread_joint(ro, loads, layout, fixed, Re, sf, seal, kind == "ring_top", bore_radius_mm)
    if kind == "tie_rods":
        return _tie_rod_joint(ro, loads, layout, fixed, Re, sf, seal, bore_radius_mm)
    raise ValueError(f"unknown joint {kind!r}; known: thread, ring_top, tie_rods")


def _base_moment_per(case: LoadCase, r_bore, r_seal, r_support, nu):
    """The base's centre moment in one case: the fluid on the bore's circle, chamber 2 on the rest of the seal's
    (superposed central loads), N·mm/mm."""
    k_bore = plate_centre_moment_per_MPa(r_bore, r_support, nu)
    k_seal = plate_centre_moment_per_MPa(r_seal, r_support, nu)
    return base_pressure(case) * k_bore + base_annulus_pressure(case) * (k_seal - k_bore)


def _base_moment_eff(loads: Loads, r_bore, r_seal, r_support, nu):
    """The base's effective centre moment over the cases (:meth:`Loads.effective`), N·mm/mm."""
    return loads.effective(lambda c: _base_moment_per(c, r_bore, r_seal, r_support, nu))


def _plate_required_mm(p_eff, r_load, r_support, nu, sa):
    """Plate thickness carrying ``p_eff`` on ``r_load`` supported at ``r_support`` at ``sa``, mm (least material)."""
    return np.sqrt(6 * plate_centre_moment_per_MPa(r_load, r_support, nu) * p_eff / sa)


def size_section(dp_mm, Do_mm, A1_mm2, A2_mm2, loads: Loads, fixed: FixedParameters, layout: LayoutVariant,
                 joint: str, piston_floor) -> Section:
    """The cross-section with every piece sized by the buildability rules (this module's docstring).

    Parameters
    ----------
    dp_mm, Do_mm : array
        Piston (= inner-tube bore) and outer diameter, mm.
    A1_mm2, A2_mm2 : array
        Chamber areas, mm².
    loads : Loads
        The load cases, MPa and N.
    fixed : FixedParameters
        Minimums, safety factors, tolerance grades, materials.
    layout : LayoutVariant
        Sizes its own walls.
    joint : str
        The joint kind.
    piston_floor : callable
        ``piston_floor(ri, dP, fixed, allowance)`` -> (has pocket, pocket radius, floor, the room the floor leaves
        in the piston's height) (the derivation's).

    Returns
    -------
    Section
        Radii, walls (mm), the pocket, the joint's sizing and the tolerance data.
    """
    f, pi = fixed, math.pi
    mat = get_material(f.housing_material)
    Re, nu, sf = mat.yield_MPa, mat.poisson, f.wall_safety_factor
    sa = Re / sf
    K = concentration_factor
    kp = 3 * (3 + nu) / 8
    ro, ri = np.asarray(Do_mm, dtype=float) / 2, np.asarray(dp_mm, dtype=float) / 2
    with np.errstate(divide="ignore", invalid="ignore"):
        # inner tube: the bore at its largest, the outside at its smallest
        ri_l = ri + it_tolerance_mm(2 * ri, f.bore_tolerance_grade) / 2
        p_in = loads.effective(_inner_tube_pressure)
        sa_i = sa / K("inner_tube")
        rio_l = np.where(2 * p_in < sa_i, ri_l * np.sqrt(sa_i / (sa_i - 2 * p_in)), np.nan)
        kb = mat.youngs_modulus_MPa / (4 * (1 - nu**2))
        cb = np.cbrt(sf * K("inner_tube") * loads.effective(_buckling_pressure) / kb)
        rio_l = np.fmax(rio_l, ri_l + ri_l * cb / (1 - cb / 2))
        rio = np.fmax(ri + f.min_inner_tube_wall_mm,
                      rio_l + it_tolerance_mm(2 * np.nan_to_num(rio_l) + 0.2, f.outside_tolerance_grade) / 2)
        rio = np.where(np.isfinite(rio_l), rio, ri + f.min_inner_tube_wall_mm)
        # the joint, then the outer tube inside it
        js = size_joint(joint, ro, loads, layout, f, ri_l)
        r_t = js.tube_outer_radius_mm
        r_t_l = r_t - it_tolerance_mm(2 * r_t, f.outside_tolerance_grade) / 2
        Fc = js.quantities.get("rods_compression_N", 0.0)
        rb_l = _tube_bore_lmc(r_t_l, loads, layout, Re / K("outer_tube"), Fc)
        rb_gas = rb_l - it_tolerance_mm(2 * np.nan_to_num(rb_l), f.bore_tolerance_grade) / 2
        rb = np.fmin(np.where(np.isfinite(rb_gas), rb_gas, r_t - f.min_outer_wall_mm), r_t - f.min_outer_wall_mm)
        rb = np.fmin(rb, np.where(np.isfinite(js.bore_cap_radius_mm), js.bore_cap_radius_mm, rb))
        # the joints' static O-rings seal on the bore: a standard ring's bore (ISO 3601-1 sizes leave gaps)
        rb = np.where(np.isfinite(rb), standard_seal_bore_radius_mm(np.nan_to_num(rb), f.joint_seal_cross_section_mm),
                      rb)
        rb_seal = rb + it_tolerance_mm(2 * rb, f.bore_tolerance_grade) / 2
        # end pieces: plates on the seal's circle supported at the joint
        t_cap_req = _plate_required_mm(loads.effective(cap_pressure), rb_seal, js.top_support_radius_mm, nu,
                                       sa / K("top_cap"))
        t_base_req = np.sqrt(6 * _base_moment_eff(loads, ri_l, rb_seal, js.base_support_radius_mm, nu) * K("base") / sa)
        tc = f.thickness_tolerance_class
        shoulder = 0.0 if joint == "ring_top" else JOINT_SHOULDER_MM
        if layout.has_bulkhead and joint != "ring_top":  # the cap's cross port lies above the tube's end
            shoulder = max(shoulder, CROSS_PORT_SHOULDER_MM)
        sec0 = Section(A1_mm2, A2_mm2, ro, rb, ri, rio, {}, sa, kp, np.zeros_like(ri), np.zeros_like(ri),
                       np.zeros_like(ri), np.zeros_like(ri, dtype=bool), tc, f.bore_tolerance_grade,
                       f.outside_tolerance_grade, r_t, js)
        t_cap = np.fmax(np.fmax(f.min_top_cap_mm, sec0.sized_thickness_mm(t_cap_req)), js.top_zone_mm + shoulder)
        if not layout.has_top_annulus:  # the inner tube's end in the cap's seat: the sized plate stays above it
            t_cap = np.fmax(t_cap, sec0.sized_thickness_mm(t_cap_req) + tube_seat_mm(ri, f))
        base_own = np.fmax(f.min_base_mm, sec0.sized_thickness_mm(t_base_req))
        t_base = base_own + js.base_zone_mm
        ph = f.piston_height_mm
        if f.piston_pocket:
            has_pk, r_pk_s, t_fl, floor_room = piston_floor(ri, loads.piston_floor_difference_MPa * K("piston_floor"),
                                                            f, sec0.sized_thickness_mm)
            V_pk = np.where(has_pk, pi * r_pk_s**2 * (ph - t_fl), 0.0)
        else:
            has_pk = np.zeros_like(ri, dtype=bool)
            r_pk_s, t_fl, V_pk = np.zeros_like(ri), np.full_like(ri, ph), np.zeros_like(ri)
            floor_room = np.full_like(ri, np.inf)
        walls = {"outer_tube": r_t - rb, "inner_tube": rio - ri, "top_cap": t_cap, "base": t_base}
        sec = replace(sec0, walls_mm=walls, piston_floor_mm=t_fl * np.ones_like(ri),
                      piston_pocket_radius_mm=np.where(has_pk, r_pk_s, 0.0) * np.ones_like(ri),
                      piston_pocket_volume_mm3=V_pk * np.ones_like(ri), has_piston_pocket=has_pk,
                      base_own_mm=base_own, piston_floor_room_mm=floor_room * np.ones_like(ri))
        own = {}
        for wall in layout.own_walls:  # each with its own concentration factor
            own[wall] = layout.size_walls(replace(sec, allowable_MPa=sa / K(wall)), loads, f)[wall]
        pocket = {"piston_floor": sec.piston_floor_mm} if f.piston_pocket else {}
    return replace(sec, walls_mm={**walls, **own, **pocket})


class _CaseView:
    """One load case as the layouts' stress hooks read pressures (``chamber_difference_MPa``, unscaled)."""

    def __init__(self, case: LoadCase) -> None:
        self.chamber_difference_MPa = np.abs(case.chamber_2_MPa - case.chamber_1_MPa)
        self.piston_floor_difference_MPa = np.abs(case.fluid_MPa - case.chamber_1_MPa)


def check_section(section: Section, loads: Loads, fixed: FixedParameters, layout: LayoutVariant,
                  floor_stress) -> dict:
    """Every piece's stress and safety factor in every load case, as drawn at its least-material condition.

    Parameters
    ----------
    section : Section
        The sized cross-section (mm).
    loads : Loads
        The load cases (MPa, N).
    fixed : FixedParameters
        Materials, the rod, the safety factors.
    layout : LayoutVariant
        Gives its own walls' stresses per case.
    floor_stress : callable
        ``floor_stress(section, dP, fixed)`` -> the piston floor's peak stress (MPa) at ``dP`` (the derivation's).

    Returns
    -------
    dict
        ``stress`` and ``safety``: piece -> case -> array (MPa, dimensionless); ``required``: case -> safety
        factor; ``buckling_MPa``: the inner tube's elastic buckling pressure (MPa).
    """
    s, f = section, fixed
    mat, mat_p = get_material(f.housing_material), get_material(f.rod_material)
    js = s.joint
    r_t = s.outer_tube_outer_radius_mm
    r_t_l = r_t - it_tolerance_mm(2 * r_t, f.outside_tolerance_grade) / 2
    rb_l, ri_l, rio_l = s.outer_bore_lmc_radius_mm, s.piston_bore_lmc_radius_mm, s.inner_tube_outer_lmc_radius_mm
    Fc = js.quantities.get("rods_compression_N", 0.0)
    sz = -np.asarray(Fc) / (math.pi * (r_t_l**2 - rb_l**2))
    t_cap = s.least_material_thickness_mm(s.walls_mm["top_cap"])
    t_base = s.least_material_thickness_mm(s.base_own_mm)
    kb = mat.youngs_modulus_MPa / (4 * (1 - mat.poisson**2))
    t_i = rio_l - ri_l
    p_cr = kb * (t_i / (ri_l + t_i / 2)) ** 3
    stress: dict[str, dict] = {}
    safety: dict[str, dict] = {}
    k_cap = 6 * plate_centre_moment_per_MPa(rb_l, js.top_support_radius_mm, mat.poisson) / t_cap**2
    k_bore = plate_centre_moment_per_MPa(ri_l, js.base_support_radius_mm, mat.poisson)
    k_seal = plate_centre_moment_per_MPa(rb_l, js.base_support_radius_mm, mat.poisson)
    k_base = 6 / t_base**2
    Ks = {piece: concentration_factor(piece) for piece in PIECES}
    with np.errstate(divide="ignore", invalid="ignore"):
        for c in loads.cases:
            view = _CaseView(c)
            st = {
                "outer_tube": lame_tresca_MPa(outer_tube_pressure(c, layout), 0.0, rb_l, r_t_l, sz),
                "inner_tube": np.fmax(lame_tresca_MPa(0.0, c.chamber_2_MPa, ri_l, rio_l),
                                      lame_tresca_MPa(np.fmax(c.chamber_1_MPa, c.fluid_MPa), c.chamber_2_MPa,
                                                      ri_l, rio_l)),
                "top_cap": k_cap * cap_pressure(c),
                "base": k_base * (base_pressure(c) * k_bore + base_annulus_pressure(c) * (k_seal - k_bore)),
            }
            st.update(layout.wall_stresses(s, view, f))
            if f.piston_pocket:
                st["piston_floor"] = floor_stress(s, view.piston_floor_difference_MPa, f)
            for piece, v in st.items():
                v = v * Ks[piece]
                m = mat_p if piece == "piston_floor" else mat
                stress.setdefault(piece, {})[c.name] = v
                sfv = np.where(v > 0, m.yield_MPa / v, np.inf)
                if piece == "inner_tube":
                    pn = _buckling_pressure(c) * Ks[piece]
                    sfv = np.fmin(sfv, np.where(pn > 0, p_cr / pn, np.inf))
                safety.setdefault(piece, {})[c.name] = sfv
    return {"stress": stress, "safety": safety, "required": {c.name: c.required_safety_factor for c in loads.cases},
            "buckling_MPa": p_cr}


def governing(check: dict) -> dict[str, tuple[Array, Array, Array, Array]]:
    """Each piece's governing case: the largest ``required / safety`` over the cases.

    Parameters
    ----------
    check : dict
        :func:`check_section`'s result.

    Returns
    -------
    dict of str to tuple
        Piece -> (index of the governing case in the cases' order, its stress in MPa, its safety factor and the
        safety factor it asks, dimensionless), arrays.
    """
    out = {}
    names = list(check["required"])
    req = np.array([check["required"][n] for n in names])
    for piece, per in check["safety"].items():
        sfs = np.array(np.broadcast_arrays(*[per[n] for n in names]), dtype=float)
        st = np.array(np.broadcast_arrays(*[check["stress"][piece][n] for n in names]), dtype=float)
        util = req.reshape((-1,) + (1,) * (sfs.ndim - 1)) / sfs
        k = np.argmax(np.nan_to_num(util, nan=np.inf), axis=0)
        idx = k[None, ...]
        out[piece] = (k, np.take_along_axis(st, idx, axis=0)[0], np.take_along_axis(sfs, idx, axis=0)[0], req[k])
    return out
