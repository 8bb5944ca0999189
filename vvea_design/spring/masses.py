"""One mass: every part's closed-form volume as the CAD draws it, times its own material's density.

The parts are the CAD's (:mod:`vvea_design.cad.registry`): ``housing_base``, ``housing_outer_tube``,
``housing_inner_tube`` (with the bulkhead and its fill tube, or the collar), ``housing_top_cap``, ``piston``
(piston and rod, one turned part in ``fixed.rod_material``), ``bladder``, ``support_ring``; then the items the CAD
has seats for: the joint's own parts (tie rods and nuts, the retaining ring), the oil and the lumped servo and
valve. Each volume mirrors the CAD's solid feature by feature (the bores, grooves, ports, channels and the
bladder's cuffs: :func:`part_volumes_mm3`); ``tests/spring/test_masses.py`` checks it against ``build_cad`` to
0.5 % per part. The feature sizes the CAD alone sets (ports, counterbores, the bladder's cuff and beads, the
seal glands) are mirrored here from its defaults (:data:`CAD_FEATURES`; the test checks they are the CAD's).

With a joint (the buildability rules) the end pieces' joint zones are drawn as the joint records say: the top
cap's and the base's spigots inside the outer tube (the static gland, the thread as its pitch cylinder, the run-out
undercut to the thread's minor diameter), the bore's lead-in behind each thread or tube end, the ring's counterbore,
groove and plug, the tie rods' tube inside the rod circle and the rods' holes. The O-ring sizes the CAD picks per
bore are mirrored by the glands' nominal depths (bd_warehouse's ISO 3601 tables). Lengths mm, volumes mm³, masses
g; vectorised.
"""

from __future__ import annotations

import math

import numpy as np

from ..materials.structural import DENSITY_HYDRAULIC_OIL_g_per_mm3, DENSITY_SILICONE_g_per_mm3, get_material
from .geometry import Array
from .joints import (INTERNAL_RUNOUT_PITCHES, LEAD_IN_GAP_MM, LEAD_IN_MIN_LENGTH_MM, RUNOUT_PITCHES, THREAD_PITCH_MM,
                     bd_warehouse_rows, SERIES_MM, seal_lead_in_land_mm, seal_zone_mm, static_gland_width_mm,
                     static_male_cross_section_mm)

__all__ = ["CAD_FEATURES", "part_volumes_mm3", "part_masses_g", "overlap_mm3", "dynamic_gland_mm", "lead_in_mm3"]

#: The CAD's own feature sizes (``cad.CadParameters`` defaults) the volumes mirror, mm.
CAD_FEATURES = {"fill_port_mm": 2.0, "fill_port_counterbore_mm": 4.2, "fill_port_counterbore_depth_mm": 4.0,
                "servo_screw_core_mm": 2.5, "servo_screw_depth_mm": 6.0, "clamp_groove_fraction": 0.6,
                "bead_height_mm": 0.4, "bead_length_mm": 1.5, "oring_cross_section_mm": 1.78,
                "rod_thread_core_mm": 4.2, "rod_thread_depth_mm": 10.0}

_GAUSS = np.polynomial.legendre.leggauss(24)


def overlap_mm3(a_mm, R_mm):
    """Volume of a cylinder of radius ``a`` that starts on the axis of a perpendicular cylinder of radius ``R`` and
    leaves it, inside that cylinder: ``int 2 sqrt(a^2 - y^2) sqrt(R^2 - y^2) dy`` over ``|y| < min(a, R)``, mm³.

    Parameters
    ----------
    a_mm, R_mm : float or array
        Radii of the drilling and of the bore it starts in, mm.

    Returns
    -------
    ndarray
        The shared volume, mm³ (24-point Gauss-Legendre).
    """
    a, R = np.asarray(a_mm, dtype=float), np.asarray(R_mm, dtype=float)
    m = np.fmin(a, R)
    x, w = _GAUSS
    y = m[..., None] * x
    f = 2 * np.sqrt(np.fmax(a[..., None] ** 2 - y**2, 0)) * np.sqrt(np.fmax(R[..., None] ** 2 - y**2, 0))
    return (f * w).sum(axis=-1) * m


def dynamic_gland_mm(cross_section_mm: float) -> tuple[float, float]:
    """Nominal depth and width of an ISO 3601 dynamic gland (bd_warehouse's table), mm.

    Parameters
    ----------
    cross_section_mm : float
        O-ring cross-section, mm.

    Returns
    -------
    tuple of float
        (depth: the mean of the table's range, width ``g_w_0``), mm.
    """
    for r in bd_warehouse_rows("o-ring_dynamic_gland_parameters.csv"):
        if abs(float(r["w"]) - cross_section_mm) < 1e-6:
            return 0.5 * (float(r["d_min"]) + float(r["d_max"])), float(r["g_w_0"])
    raise ValueError(f"no ISO 3601 dynamic gland of cross-section {cross_section_mm:g} mm")


def _static_gland_depth_mm(cross_section_mm: float) -> float:
    """Nominal depth of an ISO 3601 static radial gland (bd_warehouse's table: the mean of its range), mm."""
    for r in bd_warehouse_rows("o-ring_static_gland_parameters.csv"):
        if abs(float(r["w"]) - cross_section_mm) < 1e-6:
            return 0.5 * (float(r["d_r_min"]) + float(r["d_r_max"]))
    raise ValueError(f"no ISO 3601 static gland of cross-section {cross_section_mm:g} mm")


def _static_gland(cs: Array) -> tuple[Array, Array]:
    """Nominal depth and width of the static glands of rings of cross-sections ``cs`` (mm), mm."""
    dep = sum(np.where(cs == w, _static_gland_depth_mm(w), 0.0) for w in SERIES_MM)
    return dep, sum(np.where(cs == w, static_gland_width_mm(w), 0.0) for w in SERIES_MM)


def lead_in_mm3(r_mm, cross_section_mm: float, gland_depth_mm: float, outward: bool, room_mm=None) -> Array:
    """Material a lead-in chamfer (ISO 3601-2, as the CAD draws it) removes from the edge at radius ``r``, mm³.

    Radial depth: the ring's protrusion over its gland (``cross_section - gland_depth``), its class A tolerance
    (0.08 mm) and 0.1 mm; length: the makers' shortest 15 deg chamfer or the depth at 15 deg, at most ``room_mm``
    (the angle then raised towards 20 deg, never under the 20 deg length).

    Parameters
    ----------
    r_mm : float or array
        Radius of the chamfered edge (bore or shaft), mm.
    cross_section_mm, gland_depth_mm : float
        The ring's cross-section and its gland's depth, mm.
    outward : bool
        True for a bore, False for a shaft.
    room_mm : float or array, optional
        The axial room the part has for the chamfer, mm.

    Returns
    -------
    ndarray
        Volume (a triangle revolved at its centroid), mm³.
    """
    depth = round(cross_section_mm - gland_depth_mm + 0.08 + 0.1, 2)
    length = np.asarray(max(LEAD_IN_MIN_LENGTH_MM[cross_section_mm], depth / math.tan(math.radians(15.0))))
    if room_mm is not None:
        length = np.fmax(np.fmin(length, room_mm), depth / math.tan(math.radians(20.0)))
    rc = np.asarray(r_mm) + (depth / 3 if outward else -depth / 3)
    return math.pi * rc * depth * length


def _bladder_terms(g: dict) -> dict:
    """Radii and levels of the bladder's cuffs and beads, as the CAD's layout derives them."""
    c = CAD_FEATURES
    rio, rb, rbi, rbo = g["rio"], g["rb"], g["rbi"], g["rbo"]
    bead = np.fmin(c["bead_height_mm"], np.fmin(0.25 * (rbi - rio), 0.25 * (rb - rbo)))
    cuff = c["clamp_groove_fraction"] * g["clamp"]
    lb = np.fmin(c["bead_length_mm"], 0.5 * cuff)
    beads = math.pi * ((rbo + bead) ** 2 - rbo**2 + rbi**2 - (rbi - bead) ** 2) * lb
    return {"bead": bead, "cuff": cuff, "lb": lb, "beads": beads}


def part_volumes_mm3(g: dict, fixed, layout, spec: str = "today") -> dict[str, Array]:
    """Closed-form volume of every made part as the CAD draws it, mm³.

    Every layout and spec: the base's spigot around the bladder's lower cuff (out to the bore; the support ring
    inside it, its collector groove and channels as the CAD cuts them), the lead-in chamfers (ISO 3601-2) of the
    bores the O-rings enter (the piston's, the rod end's, the outer tube's). ``spec = "today"``: the gas-only
    rules' drawing (the end pieces and the tubes split by planes, the static seals' grooves in the clamp spigots,
    the valves at the top of the whole base); ``"buildable"``: the buildability rules' drawing without the joint's
    zones (:func:`part_masses_g` adds them, the seals' glands and the tube's lead-ins with them): the valves in the
    base's own part (``g["base_own"]``), the channels up through the base's spigot.

    Parameters
    ----------
    g : dict
        The design's geometry, arrays (mm, mm³): ``ro``, ``rb``, ``rp``, ``rio``, ``rbi``, ``rbo`` (radii),
        ``base``, ``cap``, ``L_in``, ``clamp``, ``rod_length``, ``fluid_column``, ``pocket_r``, ``pocket_depth``,
        ``bulkhead``, ``top_space``, ``collar``, ``top_annulus``, ``cross_slot_volume``, ``L_free``, ``base_own``.
    fixed : FixedParameters
        The rod, the fill tube, the piston, the feature sizes (mm).
    layout : LayoutVariant
        Which layout's features (bulkhead, collar) are drawn.
    spec : str
        ``"today"`` or ``"buildable"`` (above).

    Returns
    -------
    dict of str to ndarray
        ``housing_base``, ``housing_outer_tube``, ``housing_inner_tube``, ``housing_top_cap``, ``piston``,
        ``bladder``, ``support_ring``: volume, mm³.
    """
    c, f, pi = CAD_FEATURES, fixed, math.pi
    ro, rb, rp, rio, rbi, rbo = g["ro"], g["rb"], g["rp"], g["rio"], g["rbi"], g["rbo"]
    rr = f.rod_diameter_mm / 2
    b = _bladder_terms(g)
    bead, cuff, lb = b["bead"], b["cuff"], b["lb"]
    z0 = g["base"]
    z1 = z0 + g["L_in"]
    t_cap = g["cap"]
    L_free = g["L_free"]
    out = {}
    # --- bladder: sleeve over the free length and both cuffs, and the four beads
    out["bladder"] = pi * (rbo**2 - rbi**2) * (L_free + 2 * cuff) + 2 * b["beads"]
    # --- support ring: annulus over the clamp less the lower cuff, channels and collector groove
    ring_d = np.fmin(f.ring_channel_mm, 0.6 * (rbi - bead - rio))
    r_rc = 0.5 * (rio + rbi - bead)
    h = g["clamp"]
    hg = np.fmin(1.0, 0.2 * h)
    # the CAD's ring ends at the cuff's outer face (the base's spigot holds the cuff's outer bead), its collector
    # groove under the channels
    sr = pi * (rbo**2 - rio**2) * h - pi * (rbo**2 - rbi**2) * cuff - pi * (rbi**2 - (rbi - bead) ** 2) * lb
    collector = pi * ((r_rc + 0.6 * ring_d) ** 2 - (r_rc - 0.6 * ring_d) ** 2) * hg
    out["support_ring"] = sr - f.ring_channels * pi * (ring_d / 2) ** 2 * (h - hg) - collector
    cs = static_male_cross_section_mm(2 * rb, c["oring_cross_section_mm"])  # the clamp spigots' and collar's seals
    s_dep, s_wid = _static_gland(cs)
    seal_root = rb - s_dep
    fp = np.fmin(c["fill_port_mm"], 0.6 * (seal_root - rbo - bead))
    r_port2 = 0.5 * (rbo + bead + seal_root)
    # --- outer tube
    out["housing_outer_tube"] = pi * (ro**2 - rb**2) * g["L_in"]
    if spec != "buildable":  # the bore's lead-ins at both ends, in the spigots' room (the joint's: _joint_deltas)
        room = h - 0.5 - s_wid - LEAD_IN_GAP_MM  # the spigot's land above the groove: 0.5 mm
        li = sum(np.where(cs == w, lead_in_mm3(rb, w, _static_gland_depth_mm(w), True, room), 0.0) for w in SERIES_MM)
        out["housing_outer_tube"] = out["housing_outer_tube"] - (1 if layout.has_top_annulus else 2) * li
    # --- inner tube (+ bulkhead web and fill tube, or the collar)
    pd, pw = dynamic_gland_mm(c["oring_cross_section_mm"])
    it = pi * (rio**2 - rp**2) * g["L_in"] - lead_in_mm3(rp, c["oring_cross_section_mm"], pd, True)  # the piston's
    if layout.has_bulkhead:
        r_fb, r_fo = f.fill_tube_bore_mm / 2, f.fill_tube_outer_mm / 2
        it = it + pi * (rp**2 - r_fb**2) * g["bulkhead"] + pi * (r_fo**2 - r_fb**2) * g["top_space"]
    if layout.has_top_annulus:
        it = it + pi * (rb**2 - rio**2) * (g["collar"] + h) - pi * (rbo**2 - rbi**2) * cuff - b["beads"]
        it = it - g["cross_slot_volume"] - pi * (rb**2 - seal_root**2) * s_wid  # the collar's static seal
    out["housing_inner_tube"] = it
    out["housing_top_cap"] = _top_cap_mm3(g, f, layout, b, fp, r_port2, z1, t_cap, h)
    if spec != "buildable" and not layout.has_top_annulus:  # the static seal's groove in the cap's clamp spigot
        out["housing_top_cap"] = out["housing_top_cap"] - pi * (rb**2 - seal_root**2) * s_wid
    base = _base_mm3(g, f, layout, spec, ring_d, r_rc, fp, r_port2, z0)
    # the base's spigot around the lower cuff (out to the bore), its groove for the cuff's outer bead, and without
    # a joint its static seal's groove (annulus_top: the chamber-2 port runs up through it)
    base = base + pi * (rb**2 - rbo**2) * h - pi * ((rbo + bead) ** 2 - rbo**2) * lb
    if spec != "buildable":
        base = base - pi * (rb**2 - seal_root**2) * s_wid
    if layout.has_top_annulus:
        base = base - pi * (fp / 2) ** 2 * h
    out["housing_base"] = base
    # --- piston and rod
    pv = pi * rp**2 * f.piston_height_mm + pi * rr**2 * g["rod_length"]
    pv = pv - lead_in_mm3(rr, c["oring_cross_section_mm"], pd, False)  # the rod end's, for the rod seal
    pv = pv - 2 * pi * (rp**2 - (rp - pd) ** 2) * pw - pi * (c["rod_thread_core_mm"] / 2) ** 2 * c["rod_thread_depth_mm"]
    out["piston"] = pv - pi * g["pocket_r"] ** 2 * g["pocket_depth"]
    return out


def _top_cap_mm3(g, f, layout, b, fp, r_port2, z1, t_cap, h):
    """The top cap's volume: the plate, the top clamp (not in annulus_top), the upper cuff's groove, the ports and
    their counterbores, the bulkhead layout's fill-tube bore, riser and cross port, mm³."""
    c, pi = CAD_FEATURES, math.pi
    ro, rb, rp, rio, rbi, rbo = g["ro"], g["rb"], g["rp"], g["rio"], g["rbi"], g["rbo"]
    cuff = b["cuff"]
    cb, cbd = c["fill_port_counterbore_mm"] / 2, c["fill_port_counterbore_depth_mm"]
    cap = pi * ro**2 * t_cap
    if not layout.has_top_annulus:
        cap = cap + pi * (rb**2 - rio**2) * h - pi * (rbo**2 - rbi**2) * cuff - b["beads"]
    ports = []  # (radius of the port's axis, its length in the cap)
    if layout.has_bulkhead:
        r_fb = f.fill_tube_bore_mm / 2
        cap = cap - pi * r_fb**2 * t_cap - pi * (cb**2 - r_fb**2) * cbd
        rc = np.fmin(fp, 1.5) / 2
        y_r = 0.5 * (f.fill_tube_outer_mm / 2 + rp)
        z_cross = z1 + 0.5 * (t_cap - cbd)
        cap = cap - pi * rc**2 * (z_cross - z1) - pi * rc**2 * (r_port2 - y_r) + 4 * rc**3 / 3 + overlap_mm3(rc, fp / 2)
        ports.append((r_port2, t_cap + h, y_r))
    elif layout.has_top_annulus:
        ports.append((0.6 * rp, t_cap, None))
    else:
        ports += [(0.6 * rp, t_cap, None), (r_port2, t_cap + h, None)]
    for r_port, length, y_riser in ports:
        cap = cap - pi * (fp / 2) ** 2 * length
        ok = (r_port + cb < ro - 0.8) & ((r_port - cb > rp + 0.8) | (r_port + cb < rp - 0.8))
        if y_riser is not None:
            ok = ok & ~((r_port > 0) & (np.abs(r_port - y_riser) < cb + 0.8))
        cap = cap - np.where(ok, pi * (cb**2 - (fp / 2) ** 2) * cbd, 0.0)
    return cap


def _base_mm3(g, f, layout, spec, ring_d, r_rc, fp, r_port2, z0):
    """The base's volume: the rod bore and its seal groove, the throttle and relief bores, the servo's screw holes,
    the channels (their overlap with the bores they start in), annulus_top's chamber-2 port, mm³."""
    c, pi = CAD_FEATURES, math.pi
    ro, rb, rp, rio = g["ro"], g["rb"], g["rp"], g["rio"]
    rr = f.rod_diameter_mm / 2
    cb, cbd = c["fill_port_counterbore_mm"] / 2, c["fill_port_counterbore_depth_mm"]
    buildable = spec == "buildable"
    dep, wid = dynamic_gland_mm(c["oring_cross_section_mm"])
    own = g["base_own"] if buildable else z0
    throttle = np.fmin(f.throttle_bore_mm, own - 8.0)
    relief = np.fmin(f.relief_bore_mm, throttle)
    seat = np.fmin(f.relief_seat_mm, relief) / 2
    zv = own - 2.0 - throttle / 2
    x_in = rr + 1.5
    ch = np.fmin(f.fluid_channel_mm, 0.5 * (rp - rr)) / 2
    r_a = 0.5 * (rr + rp)
    ring_ch = np.fmin(ch, ring_d / 2)  # the ring-side channel under the support ring's channels, as the CAD drills
    x_b = r_rc - ring_d / 2 - 0.5
    base = pi * ro**2 * z0 - pi * rr**2 * z0 - pi * ((rr + dep) ** 2 - rr**2) * wid
    base = base - pi * (throttle / 2) ** 2 * (ro - x_in) - pi * (relief / 2) ** 2 * (ro - x_b)
    base = base + pi * ((throttle / 2) ** 4 + (relief / 2) ** 4) / (8 * ro)  # the bores end on the curved outside
    base = base - pi * seat**2 * (x_b - x_in + 0.01) + pi * np.fmin(seat, relief / 2) ** 2 * 0.01
    base = base - 2 * pi * (c["servo_screw_core_mm"] / 2) ** 2 * c["servo_screw_depth_mm"]
    for a, R in ((ch, throttle / 2), (ring_ch, throttle / 2), (ch, seat), (ring_ch, relief / 2)):
        base = base - (pi * a**2 * (z0 - zv) - overlap_mm3(a, R))
    if layout.has_top_annulus:
        base = base - pi * (fp / 2) ** 2 * z0
        base = base - np.where(r_port2 + cb < ro - 0.8, pi * (cb**2 - (fp / 2) ** 2) * cbd, 0.0)
    return base


def _joint_deltas(g: dict, js, fixed) -> tuple[dict[str, Array], dict[str, Array]]:
    """What the joint's geometry moves between the housing's parts and adds (mm³), and the joint's own parts (g)."""
    pi = math.pi
    ro, rb = g["ro"], g["rb"]
    q = js.quantities
    dv = {"housing_base": 0.0, "housing_outer_tube": 0.0, "housing_top_cap": 0.0}
    own: dict[str, Array] = {}
    seal = js.seal_zone_mm
    w = fixed.joint_seal_cross_section_mm
    dep, wid = _static_gland_depth_mm(w), static_gland_width_mm(w)  # the spigots' static glands (ISO 3601)
    gland = pi * (rb**2 - (rb - dep) ** 2) * wid
    room = seal_lead_in_land_mm(w, fixed.seal_land_mm) - LEAD_IN_GAP_MM  # the bore's lead-in at each entry step
    # (ring_top: the cap's ring enters the bore at the counterbore's step, the base's behind its thread)
    dv["housing_outer_tube"] = -2 * lead_in_mm3(rb, w, dep, True, room)
    P = THREAD_PITCH_MM
    if js.kind in ("thread", "ring_top"):
        d2, D = q["thread_pitch_diameter_mm"] / 2, q["thread_major_mm"]
        d3 = (D - 1.226869 * P) / 2
        for end, key in (("housing_base", "engagement_base_mm"), ("housing_top_cap", "engagement_top_mm")):
            L = q["thread_" + key]
            if end == "housing_top_cap" and js.kind == "ring_top":
                continue
            run, rel = RUNOUT_PITCHES * P, INTERNAL_RUNOUT_PITCHES * P
            D1 = q["thread_minor_mm"] / 2
            # the tube over the thread, its internal run-out (at the minor bore D1, the spigot plain at the bore
            # there: an empty relief between them) and the seal zone
            moved = pi * (ro**2 - d2**2) * (L + run) + pi * (ro**2 - rb**2) * seal
            dv[end] = dv[end] - moved - pi * (d2**2 - d3**2) * run - gland - pi * (ro**2 - rb**2) * rel
            dv["housing_outer_tube"] = dv["housing_outer_tube"] + moved + pi * (ro**2 - D1**2) * rel
    if js.kind == "ring_top":  # g["cap"] is the plug and the tube beyond it (the CAD's z_top - z_cap)
        d1, d2r, m = q["ring_bore_mm"] / 2, q["ring_groove_diameter_mm"] / 2, q["ring_groove_width_mm"]
        plug = g["cap"] - js.top_extra_mm
        sz = js.top_zone_mm  # the plug's seal zone at the bore, below the counterbore (its gland is at the bore)
        dv["housing_outer_tube"] = (dv["housing_outer_tube"] + pi * (ro**2 - d1**2) * g["cap"]
                                    - pi * (d2r**2 - d1**2) * m - lead_in_mm3(d1, w, dep, True)
                                    + pi * (d1**2 - rb**2) * sz)
        dv["housing_top_cap"] = (dv["housing_top_cap"] + pi * d1**2 * plug - pi * ro**2 * g["cap"] - gland
                                 - pi * (d1**2 - rb**2) * sz)
        own["retaining_ring"] = np.asarray(q["ring_mass_g"], dtype=float)
    if js.kind == "tie_rods":
        rt = js.tube_outer_radius_mm
        n, d, hole = q["rods_count"], q["rods_d"], q["rods_hole"]
        dv["housing_outer_tube"] = (dv["housing_outer_tube"] - pi * (ro**2 - rt**2) * g["L_in"]
                                    + pi * (rt**2 - rb**2) * 2 * seal)
        for end, t in (("housing_top_cap", g["cap"]), ("housing_base", g["base"])):
            dv[end] = dv[end] - pi * (ro**2 - rb**2) * seal - gland - n * pi * (hole / 2) ** 2 * (t - seal)
        s, m = q["rods_nut_s"], q["rods_nut_m"]
        L_rod = g["cap"] + g["base"] + g["L_in"] + 2 * m + 2 * d
        rho_s = 7.85e-3
        own["tie_rods"] = n * (pi / 4 * d**2 * L_rod + 2 * (math.sqrt(3) / 2 * s**2 - pi / 4 * d**2) * m) * rho_s
    return dv, own


#: The bulkhead fill tube's neck in the top cap (``cad.tube_seats.FILL_NECK_MM``; O-ring 007 seats on it), mm.
FILL_NECK_MM = 3.8


def _seat_deltas(g: dict, fixed, layout) -> dict[str, Array]:
    """What the seats of the inner tube's ends (and the fill tube's neck) move between the pieces, mm³ (the CAD's
    :mod:`vvea_design.cad.tube_seats`): each end one seal zone deep in a seat of its end piece, whose spigot inside the
    tube's bore carries a static gland; the tube's bore chamfered at both ends for that ring (at the bottom it
    replaces the piston's lead-in: the seat's ring protrudes further); ``bulkhead``: the neck in the cap, the cap's
    groove around it, the neck's chamfer. ``annulus_top`` seats only the bottom end."""
    pi, rp, rio = math.pi, g["rp"], g["rio"]
    land = fixed.seal_land_mm
    cs = static_male_cross_section_mm(2 * rp, fixed.joint_seal_cross_section_mm)
    dep, wid = _static_gland(cs)
    h = sum(np.where(cs == w, seal_zone_mm(w, land), 0.0) for w in SERIES_MM)
    li = sum(np.where(cs == w, lead_in_mm3(rp, w, _static_gland_depth_mm(w), True,
                                           seal_lead_in_land_mm(w, land) - LEAD_IN_GAP_MM), 0.0) for w in SERIES_MM)
    pd = dynamic_gland_mm(CAD_FEATURES["oring_cross_section_mm"])[0]
    end = pi * (rio**2 - rp**2) * h
    groove = pi * (rp**2 - (rp - dep) ** 2) * wid
    dv = {"housing_inner_tube": end - li + lead_in_mm3(rp, CAD_FEATURES["oring_cross_section_mm"], pd, True),
          "housing_base": -end - groove, "housing_top_cap": 0.0}
    if not layout.has_top_annulus:
        dv["housing_inner_tube"] = dv["housing_inner_tube"] + end - li
        dv["housing_top_cap"] = -end - groove
    if layout.has_bulkhead:
        rn, rfb = FILL_NECK_MM / 2, fixed.fill_tube_bore_mm / 2
        fd = _static_gland_depth_mm(1.78)
        neck = pi * (rn**2 - rfb**2) * seal_zone_mm(1.78, land)
        room = seal_lead_in_land_mm(1.78, land) - LEAD_IN_GAP_MM
        dv["housing_inner_tube"] = dv["housing_inner_tube"] + neck - lead_in_mm3(rn, 1.78, fd, False, room)
        dv["housing_top_cap"] = dv["housing_top_cap"] - neck - pi * ((rn + fd) ** 2 - rn**2) * static_gland_width_mm(1.78)
    return dv


def part_masses_g(g: dict, fixed, layout, joint_sizing=None, fluid_volume_mm3=0.0) -> dict[str, Array]:
    """Every part's mass, g: the made parts (CAD volume x their material's density), the joint's own parts, the
    oil and the lumped servo and valve.

    Parameters
    ----------
    g : dict
        The design's geometry (:func:`part_volumes_mm3`), arrays (mm, mm³).
    fixed : FixedParameters
        Materials, sizes (mm), the servo's mass (g).
    layout : LayoutVariant
        Which layout's features are drawn.
    joint_sizing : JointSizing or None
        The joint (the buildability rules): its zones are drawn and its parts weighed; None: the plain split.
    fluid_volume_mm3 : float or array
        Oil to fill at x = 0, mm³.

    Returns
    -------
    dict of str to ndarray
        Part -> mass, g: ``housing_base``, ``housing_outer_tube``, ``housing_inner_tube``, ``housing_top_cap``,
        ``piston`` (piston and rod), ``bladder``, ``support_ring``, the joint's parts (``tie_rods``,
        ``retaining_ring``), ``fluid``, ``servo_and_valve``.
    """
    f = fixed
    v = part_volumes_mm3(g, f, layout, "today" if joint_sizing is None else "buildable")
    own = {}
    if joint_sizing is not None:
        dv, own = _joint_deltas(g, joint_sizing, f)
        seats = _seat_deltas(g, f, layout)
        v = {k: val + dv.get(k, 0.0) + seats.get(k, 0.0) for k, val in v.items()}
    rho_h = get_material(f.housing_material).density_g_per_mm3
    rho_r = get_material(f.rod_material).density_g_per_mm3
    rho_s = get_material(f.support_ring_material).density_g_per_mm3
    m = {k: v[k] * rho_h for k in ("housing_base", "housing_outer_tube", "housing_inner_tube", "housing_top_cap")}
    m["piston"] = v["piston"] * rho_r
    m["bladder"] = v["bladder"] * DENSITY_SILICONE_g_per_mm3
    m["support_ring"] = v["support_ring"] * rho_s
    m.update(own)
    m["fluid"] = np.maximum(fluid_volume_mm3, 0.0) * DENSITY_HYDRAULIC_OIL_g_per_mm3
    m["servo_and_valve"] = np.full_like(np.asarray(g["ro"], dtype=float), f.servo_and_valve_mass_g)
    return m
