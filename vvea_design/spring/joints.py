"""The housing's joints: what holds the top cap and the base to the outer tube, sized by a standard method.

A **joint** is a design decision chosen like a layout (``Requirements.joints``; the design's ``joint``):

``thread``
    Both end pieces screw into the outer tube: an internal ISO 261 fine thread (pitch 1.5 mm) cut in each end of
    the tube, an external one on each end piece's spigot, tolerance class 6H/6g (ISO 965-1). The largest standard
    size whose tube wall under the thread root carries the end load is taken; the engagement length is the
    longer of ISO 965-1's normal engagement (group N) and what stripping of the weaker thread needs; the tube's
    bore cannot exceed the internal thread's minor diameter (the bladder, the support ring and the inner tube pass
    through it on assembly).
``ring_top``
    The top cap is a plug held in the tube by an internal retaining ring (DIN 472, data: bd_warehouse) in a groove
    above it; the base screws in as for ``thread``. The ring's groove capacity (``F_N`` for a groove material of
    200 N/mm² yield, scaled by the housing's yield), the ring's own capacity (``F_R``, sharp-edged abutment), the
    tube wall under the groove and the land above it (shear) carry the top end load.
``tie_rods``
    ``N`` tie rods (DIN 976-1 threaded rods, ISO 898-1 property class ``fixed.tie_rod_property_class``, ISO 4032
    nuts) run outside the outer tube between the end pieces, on a circle inside the envelope. Preloaded by torque
    (VDI 2230-1: ``F_Mzul`` at 90 % of the yield with thread friction 0.12, tightening factor 1.6), they hold the
    joint closed at the end load (``F_M,min >= SF (1 - Phi) F_A``, ``Phi`` the rods' share of the load) and stay
    below yield (``F_Mzul + Phi F_A <= R_p0.2 A_s``). The outer tube, inside the rods, carries their clamp force.

Each joint's **footprint** takes room from the gas: the tube wall at a thread or ring groove (the bore is capped),
the rod circle (the tube's outside radius), the axial zones the end pieces need for the thread, its run-out and
the static O-ring's gland (:class:`JointSizing`). Standard data are read from bd_warehouse's tables
(``din472.csv``, ``hex_nut_parameters.csv``, ``clearance_hole_sizes.csv``, ``o-ring_static_gland_parameters.csv``);
ISO 261's fine sizes, ISO 965-1's tolerance formulas and ISO 898-1's property classes are written out here.
Lengths mm, forces N, stresses MPa; vectorised over a population.
"""

from __future__ import annotations

import csv
import math
from dataclasses import dataclass, field
from functools import lru_cache
from importlib import resources
import bd_warehouse
import numpy as np

from .geometry import Array
from .records import Record

__all__ = ["JOINTS", "PROPERTY_CLASSES", "ISO261_FINE_MM", "THREAD_PITCH_MM", "JointSizing", "ThreadJoint",
           "RingJoint", "TieRodJoint", "SeatJoint", "thread_geometry", "iso965_tolerances_mm", "select_thread",
           "engagement_group_n_mm", "THREAD_CLASSES",
           "select_ring", "tie_rod_candidates", "tie_rod_preload", "static_gland_width_mm", "din472_table",
           "JOINT_SHOULDER_MM", "bd_warehouse_rows", "RUNOUT_PITCHES", "INTERNAL_RUNOUT_PITCHES", "LEAD_IN_MARGIN_MM",
           "seal_passage_mm", "CROSS_PORT_SHOULDER_MM",
           "EXCLUDED_PAIRS", "joint_fits_layout",
           "standard_seal_bore_radius_mm", "LEAD_IN_MIN_LENGTH_MM", "LEAD_IN_GAP_MM", "seal_lead_in_land_mm",
           "seal_zone_mm", "static_male_cross_section_mm", "SERIES_MM"]

#: The joint choices (the design's ``joint``; ``Requirements.joints`` lists which the optimiser tries).
JOINTS = ("thread", "ring_top", "tie_rods")

#: Joint and layout pairs a workshop cannot build, with the reason: ``ring_top``'s cap is a plug inside the tube, so
#: the ``bulkhead`` layout's chamber-2 cross port (drilled from the outside and plugged) would pass through the tube
#: wall, where the cap's O-ring also passes it. The optimiser does not try them.
EXCLUDED_PAIRS = {("bulkhead", "ring_top"): "the top cap's cross port would be drilled through the outer tube "
                                            "around the retaining ring's plug"}


def joint_fits_layout(joint: str, layout: str) -> bool:
    """Whether ``joint`` can be built with ``layout`` (:data:`EXCLUDED_PAIRS`).

    Parameters
    ----------
    joint : str
        One of :data:`JOINTS`.
    layout : str
        A layout's name (``inner_tube``, ``bulkhead``, ``annulus_top``).

    Returns
    -------
    bool
        False for the pairs in :data:`EXCLUDED_PAIRS`.
    """
    return (layout, joint) not in EXCLUDED_PAIRS


#: ISO 898-1 property classes: (R_p0.2 min, R_m min) in MPa (d <= 16 mm for 8.8).
PROPERTY_CLASSES: dict[str, tuple[float, float]] = {"8.8": (640.0, 800.0), "10.9": (940.0, 1040.0),
                                                   "12.9": (1100.0, 1220.0)}

#: ISO 261 nominal diameters with a fine pitch of 1.5 mm, mm (the joints' thread series).
ISO261_FINE_MM = (12, 14, 15, 16, 17, 18, 20, 22, 24, 25, 26, 27, 28, 30, 32, 33, 35, 36, 38, 39, 40, 42, 45, 48,
                  50, 52, 55, 56, 58, 60, 62, 64, 65, 68, 70, 72, 75, 76, 80)
#: The joints' thread pitch, mm.
THREAD_PITCH_MM = 1.5
#: Axial shoulder of full outside diameter an end piece keeps beyond its joint zone (the tube end bears on it), mm.
JOINT_SHOULDER_MM = 2.0
#: Axial shoulder of the top cap above the outer tube when the cap holds the chamber-2 cross port (``bulkhead``): the
#: cross port is drilled from the outside and plugged, so it must lie above the tube's end, mm. From the CAD's
#: feature sizes (``cad.CadParameters``): a 0.5 mm land over the tube, the plug's bore (Ø3.0), 0.3 mm and the
#: valves' tapped holes (4.0 mm deep) under the top face.
CROSS_PORT_SHOULDER_MM = 0.5 + 3.0 + 0.3 + 4.0
#: Thread run-out of the spigot's external thread, in pitches (DIN 76-1's short run-out x1, about 1.25 P: the
#: thread is cut on a lathe up to the undercut at the shoulder).
RUNOUT_PITCHES = 1.25
#: Run-out of the outer tube's internal thread at its inner end, in pitches (DIN 76-1's short run-out of an internal
#: thread, x1 = 1 P: the thread is cut on a lathe). The tube keeps the thread's minor bore ``D1`` over it; deeper in,
#: the bore steps down to the seal bore over the O-ring's lead-in (:func:`seal_passage_mm`).
INTERNAL_RUNOUT_PITCHES = 1.0
#: Radial margin of a lead-in chamfer over the O-ring's largest protrusion (ISO 3601-2: the ring meets only the
#: chamfer, never the edge behind it), mm.
LEAD_IN_MARGIN_MM = 0.1
#: The tie rods' metric coarse sizes (ISO 261) with an ISO 4032 nut in bd_warehouse's table.
TIE_ROD_SIZES = ("M3-0.5", "M4-0.7", "M5-0.8", "M6-1", "M8-1.25")
#: Tie-rod counts tried.
TIE_ROD_COUNTS = (4, 6, 8)
#: VDI 2230-1: utilisation of the yield in assembly, thread and head friction, tightening factor (torque wrench).
VDI_NU, VDI_MU, VDI_ALPHA_A = 0.9, 0.12, 1.6
#: Young's modulus of the tie rods (steel), MPa.
E_STEEL_MPa = 210e3
#: Land left outside a tie rod's hole and clearance between a rod and the outer tube, mm.
ROD_EDGE_MM, ROD_GAP_MM = 1.0, 0.5


# ----------------------------------------------------------------------------------------------- standard data
def bd_warehouse_rows(name: str) -> list[dict[str, str]]:
    """The rows of one of bd_warehouse's data tables (``bd_warehouse/data/<name>``).

    Parameters
    ----------
    name : str
        File name in ``bd_warehouse/data``.

    Returns
    -------
    list of dict
        One mapping per row, column -> text.
    """
    with resources.as_file(resources.files(bd_warehouse) / "data" / name) as path, \
            path.open(encoding="utf-8", newline="") as fh:
        return [{k.strip(): (v or "").strip() for k, v in row.items() if k} for row in csv.DictReader(fh)]


@lru_cache(maxsize=None)
def din472_table() -> dict[str, np.ndarray]:
    """DIN 472 internal retaining rings (bd_warehouse ``din472.csv``), one array per column.

    Returns
    -------
    dict of str to ndarray
        ``d1`` bore, ``d2`` groove diameter (``d2_tol`` its upper deviation), ``m`` groove width, ``t`` groove
        depth, ``n`` least land, ``s`` ring thickness (mm); ``FN`` groove and ``FR`` ring load capacity (kN);
        ``W`` mass of 1000 rings (kg), in the order of the bore.
    """
    rows = bd_warehouse_rows("din472.csv")
    cols = {"d1": "d1", "d2": "d2", "d2_tol": "d2_tol+", "m": "m", "t": "t", "n": "n", "s": "s", "FN": "FN",
            "FR": "FR", "W": "W"}
    return {k: np.array([float(r[c]) for r in rows]) for k, c in cols.items()}


@lru_cache(maxsize=None)
def _tie_rod_table() -> dict[str, np.ndarray]:
    """Nominal diameter, pitch, ISO 4032 nut (s, m) and ISO 273 normal clearance hole of :data:`TIE_ROD_SIZES`, mm."""
    nuts = {r["Size"]: r for r in bd_warehouse_rows("hex_nut_parameters.csv")}
    holes = {r["Size"]: r for r in bd_warehouse_rows("clearance_hole_sizes.csv")}
    out: dict[str, list] = {"d": [], "P": [], "s": [], "m": [], "hole": []}
    for size in TIE_ROD_SIZES:
        d, P = (float(x) for x in size[1:].split("-"))
        out["d"].append(d)
        out["P"].append(P)
        out["s"].append(float(nuts[size]["iso4032:s"]))
        out["m"].append(float(nuts[size]["iso4032:m"]))
        out["hole"].append(float(holes[size.split("-")[0]]["Normal"]))
    return {k: np.array(v) for k, v in out.items()}


@lru_cache(maxsize=None)
def static_gland_width_mm(cross_section_mm: float) -> float:
    """Axial width of an ISO 3601 static radial gland without back-up ring (bd_warehouse's table), mm.

    Parameters
    ----------
    cross_section_mm : float
        O-ring cross-section, mm (1.78, 2.62 ...).

    Returns
    -------
    float
        Groove width ``g_w_0``, mm.

    Raises
    ------
    ValueError
        If the table has no such cross-section.
    """
    for r in bd_warehouse_rows("o-ring_static_gland_parameters.csv"):
        if abs(float(r["w"]) - cross_section_mm) < 1e-6:
            return float(r["g_w_0"])
    raise ValueError(f"no ISO 3601 static gland of cross-section {cross_section_mm:g} mm in bd_warehouse's table")


#: Shortest lead-in chamfer (mm along the axis) at 15 deg by O-ring cross-section (mm): the installation chamfers
#: of the seal makers' design guides (ISO 3601-2: 15 ... 20 deg, radial depth over the ring's protrusion). The CAD
#: draws them (:func:`vvea_design.cad.seals.lead_in`); the joints' seal zones reserve their room.
LEAD_IN_MIN_LENGTH_MM = {1.78: 2.10, 2.62: 3.10, 3.53: 4.00, 5.33: 6.00, 6.99: 7.20}
#: Axial clearance between a lead-in chamfer's end and the seal groove the ring sits in after assembly, mm.
LEAD_IN_GAP_MM = 0.3


#: The O-ring series the CAD's glands are drawn in (``cad.seals.SERIES``), mm.
SERIES_MM = (1.78, 2.62)


@lru_cache(maxsize=4)
def _male_static_windows(cross_section_mm: float) -> np.ndarray:
    """Bore intervals (rows lo, hi, mm) a ring of the series seals as a static male gland: the ring's inner
    diameter stretched 0-5 % onto the groove's root, the radial squeeze in the ISO 3601 static window."""
    row = next(r for r in bd_warehouse_rows("o-ring_static_gland_parameters.csv")
               if abs(float(r["w"]) - cross_section_mm) < 1e-6)
    lo_d = cross_section_mm * (1 - float(row["sq_r_p_max"]) / 100)
    hi_d = cross_section_mm * (1 - float(row["sq_r_p_min"]) / 100)
    ids = [float(r["iso3601:id"]) for r in bd_warehouse_rows("o-ring_parameters.csv")
           if abs(float(r["iso3601:w"]) - cross_section_mm) < 1e-6]
    return np.array([(d + 2 * lo_d, 1.05 * d + 2 * hi_d) for d in ids])


def static_male_cross_section_mm(bore_mm, preferred_mm: float = 1.78) -> Array:
    """Cross-section of the O-ring the CAD seats in a static male gland sealing ``bore_mm``: the preferred series
    where one of its rings fits (ISO 3601-1 sizes, the static squeeze window, 0-5 % stretch), else the other.

    Parameters
    ----------
    bore_mm : float or array
        Bore the ring seals on, mm.
    preferred_mm : float
        The preferred series, mm (1.78 or 2.62).

    Returns
    -------
    ndarray
        Cross-section, mm.
    """
    b = np.asarray(bore_mm, dtype=float)
    win = _male_static_windows(preferred_mm)
    fits = ((b[..., None] >= win[:, 0] - 1e-12) & (b[..., None] <= win[:, 1] + 1e-12)).any(axis=-1)
    other = next(w for w in SERIES_MM if w != preferred_mm)
    return np.where(fits, preferred_mm, other)


def seal_lead_in_land_mm(cross_section_mm: float, land_mm: float) -> float:
    """Land of a joint's static O-ring groove on the side the ring enters the bore: the bore's lead-in chamfer
    (:data:`LEAD_IN_MIN_LENGTH_MM`, ISO 3601-2) and :data:`LEAD_IN_GAP_MM` before the groove, at least ``land_mm``.

    The ring passes the step from the joint (thread, tube end) into the sealing bore there; the chamfer must end
    before the groove so the ring never seals on it. A 15 deg chamfer of this length has room for any ring of the
    cross-section (a deeper one is raised towards 20 deg within the length).

    Parameters
    ----------
    cross_section_mm : float
        O-ring cross-section, mm (1.78, 2.62 ...).
    land_mm : float
        The plain land of the groove's other side (``fixed.seal_land_mm``), mm.

    Returns
    -------
    float
        Axial land between the zone's entry end and the groove, mm.

    Raises
    ------
    ValueError
        If the cross-section has no lead-in length in the table.
    """
    for w, length in LEAD_IN_MIN_LENGTH_MM.items():
        if abs(w - cross_section_mm) < 1e-6:
            return max(float(land_mm), length + LEAD_IN_GAP_MM)
    raise ValueError(f"no lead-in chamfer length for an O-ring of cross-section {cross_section_mm:g} mm")


def seal_zone_mm(cross_section_mm: float, land_mm: float) -> float:
    """Axial room of a joint's static O-ring: the entry land with the bore's lead-in (:func:`seal_lead_in_land_mm`),
    the ISO 3601 static gland (bd_warehouse) and a plain land, mm.

    Parameters
    ----------
    cross_section_mm : float
        O-ring cross-section, mm.
    land_mm : float
        Plain land beside the groove (``fixed.seal_land_mm``), mm.

    Returns
    -------
    float
        The zone's length, mm.
    """
    return (seal_lead_in_land_mm(cross_section_mm, land_mm) + static_gland_width_mm(cross_section_mm)
            + float(land_mm))


@lru_cache(maxsize=None)
def seal_passage_mm(cross_section_mm: float) -> float:
    """Radial room a joint's static O-ring needs between the bore it seals on and any edge it passes on assembly
    (the internal thread's crests, a retaining ring's bore), mm.

    The free ring on a male gland reaches its largest protrusion, ``w`` times the static gland's largest squeeze
    (ISO 3601-2 via bd_warehouse's table), plus the cross-section's tolerance (ISO 3601-1 class A), beyond the seal
    bore; the bore's lead-in chamfer (15 ... 20 deg) reaches :data:`LEAD_IN_MARGIN_MM` further, rounded up to
    0.01 mm. A thread or groove whose smallest diameter lies outside this ring is never touched by the O-ring:
    ``D1 >= seal bore + 2 seal_passage_mm``.

    Parameters
    ----------
    cross_section_mm : float
        O-ring cross-section ``w``, mm (1.78, 2.62 ...).

    Returns
    -------
    float
        Radial room, mm.

    Raises
    ------
    ValueError
        If bd_warehouse's tables have no such cross-section.
    """
    w = float(cross_section_mm)
    row = next((r for r in bd_warehouse_rows("o-ring_static_gland_parameters.csv") if abs(float(r["w"]) - w) < 1e-6),
               None)
    tol = [float(r["iso3601:w_tol"]) for r in bd_warehouse_rows("o-ring_parameters.csv")
           if r.get("iso3601:w") and abs(float(r["iso3601:w"]) - w) < 1e-6]
    if row is None or not tol:
        raise ValueError(f"no ISO 3601 static gland of cross-section {w:g} mm in bd_warehouse's tables")
    reach = w * float(row["sq_r_p_max"]) / 100 + max(tol) + LEAD_IN_MARGIN_MM
    return math.ceil(round(reach * 100, 6)) / 100


def standard_seal_bore_radius_mm(radius_mm, cross_section_mm: float) -> Array:
    """The largest seal bore radius, at most ``radius_mm``, that an ISO 3601-1 O-ring of the cross-section seals in a
    static male gland (ISO 3601-2 squeeze window, 0 ... 5 % stretch on the groove root), mm.

    The ring sizes leave gaps (the 1.78 mm series steps about 3 mm in diameter above Ø25): a bore in a gap is
    lowered to the top of the window below it, so the joint's seal is the standard ring the design reserved room
    for (its gland width, its passage past the thread). Where no ring fits at all the radius is returned as is.

    Parameters
    ----------
    radius_mm : float or array
        Largest bore radius allowed, mm.
    cross_section_mm : float
        O-ring cross-section, mm (``fixed.joint_seal_cross_section_mm``).

    Returns
    -------
    ndarray
        Bore radius, mm (<= ``radius_mm``).
    """
    win = _male_static_windows(float(cross_section_mm))
    lo, hi = win[:, 0] + 1e-6, win[:, 1] - 1e-6
    b = 2 * np.asarray(radius_mm, dtype=float)[..., None]
    fit = np.where(lo <= b, np.fmin(b, hi), -np.inf).max(axis=-1)
    return np.where(np.isfinite(fit), fit / 2, b[..., 0] / 2)


# ----------------------------------------------------------------------------------------------- threads
def thread_geometry(major_mm, pitch_mm: float) -> dict[str, Array]:
    """Basic diameters of an ISO 68-1 metric thread, mm.

    Parameters
    ----------
    major_mm : float or array
        Nominal (major) diameter ``D = d``, mm.
    pitch_mm : float
        Pitch ``P``, mm.

    Returns
    -------
    dict of str to ndarray
        ``d2`` pitch (``d - 0.649519 P``), ``D1`` internal minor (``d - 1.082532 P``) and ``d3`` external minor
        (``d - 1.226869 P``) diameters, mm.
    """
    d = np.asarray(major_mm, dtype=float)
    P = pitch_mm
    return {"d2": d - 0.649519 * P, "D1": d - 1.082532 * P, "d3": d - 1.226869 * P}


#: ISO 965-1 tolerance grade factors relative to grade 6 (the grades' ratios of T_d2, T_D2, T_D1).
_GRADE_FACTOR = {4: 0.63, 5: 0.8, 6: 1.0, 7: 1.25, 8: 1.6}


def iso965_tolerances_mm(major_mm, pitch_mm: float, internal_grade: int = 6, external_grade: int = 6) -> dict[str, Array]:
    """ISO 965-1 tolerances of an ``<internal_grade>H/<external_grade>g6g`` fit from the standard's formulas, mm.

    Grade 6: ``T_d2(6) = 90 P^0.4 d^0.1`` µm (``d`` the geometric mean of the standard's diameter range),
    ``T_D2(6) = 1.32 T_d2(6)``, ``T_D1(6) = 230 P^0.7`` (P >= 1) or ``433 P - 190 P^1.22``,
    ``T_d(6) = 180 P^(2/3) - 3.15 / sqrt(P)``; other grades scale ``T_d2``, ``T_D2`` and ``T_D1`` by 0.63 (4),
    0.8 (5), 1.25 (7), 1.6 (8), the major diameter stays grade 6; fundamental deviation ``es(g) = -(15 + 11 P)`` µm,
    ``EI(H) = 0``. The standard's tables round these values (to within a few µm).

    Parameters
    ----------
    major_mm : float or array
        Nominal diameter, mm.
    pitch_mm : float
        Pitch, mm.
    internal_grade, external_grade : int
        Tolerance grades of the internal (H) and external (g) pitch diameters (4 .. 8, dimensionless).

    Returns
    -------
    dict of str to ndarray
        ``T_d2``, ``T_D2``, ``T_D1``, ``T_d`` and ``es``, mm.
    """
    d = np.asarray(major_mm, dtype=float)
    bounds = np.array([1.4, 2.8, 5.6, 11.2, 22.4, 45.0, 90.0, 180.0, 355.0])
    i = np.clip(np.searchsorted(bounds, d, side="left"), 1, len(bounds) - 1)
    dm = np.sqrt(bounds[i - 1] * bounds[i])
    P = pitch_mm
    ki, ke = _GRADE_FACTOR[internal_grade], _GRADE_FACTOR[external_grade]
    Td2 = 90 * P**0.4 * dm**0.1
    TD1 = 230 * P**0.7 if P >= 1 else 433 * P - 190 * P**1.22
    return {"T_d2": ke * Td2 * 1e-3, "T_D2": ki * 1.32 * Td2 * 1e-3, "T_D1": np.full_like(d, ki * TD1 * 1e-3),
            "T_d": np.full_like(d, (180 * P ** (2 / 3) - 3.15 / math.sqrt(P)) * 1e-3),
            "es": np.full_like(d, -(15 + 11 * P) * 1e-3)}


def _stripping_areas_per_mm(D, P: float, internal_grade: int, external_grade: int) -> tuple[np.ndarray, np.ndarray]:
    """Shear areas per mm of engagement at the least-material condition, mm²/mm: the internal thread's
    ``pi d_min [1/2 + tan30 (d_min - D2_max)/P]`` and the external thread's ``pi D1_max [1/2 + tan30 (d2_min -
    D1_max)/P]`` (FED-STD-H28/2, Machinery's Handbook)."""
    g, t = thread_geometry(D, P), iso965_tolerances_mm(D, P, internal_grade, external_grade)
    d_min = D + t["es"] - t["T_d"]
    D2_max = g["d2"] + t["T_D2"]
    D1_max = g["D1"] + t["T_D1"]
    d2_min = g["d2"] + t["es"] - t["T_d2"]
    k = math.tan(math.radians(30))
    a_int = math.pi * d_min * (0.5 + k * (d_min - D2_max) / P)
    a_ext = math.pi * D1_max * (0.5 + k * (d2_min - D1_max) / P)
    return a_int, a_ext


def engagement_group_n_mm(major_mm, pitch_mm: float) -> tuple[Array, Array]:
    """ISO 965-1 normal length of engagement (group N), from ``2.24 P d^0.2`` to ``6.7 P d^0.2``, mm.

    Parameters
    ----------
    major_mm : float or array
        Nominal diameter, mm.
    pitch_mm : float
        Pitch, mm.

    Returns
    -------
    tuple of ndarray
        Lower and upper bound of group N, mm (below: group S; above: group L).
    """
    d02 = np.asarray(major_mm, dtype=float) ** 0.2
    return 2.24 * pitch_mm * d02, 6.7 * pitch_mm * d02


#: ISO 965-1 recommended tolerance classes (medium quality) by length of engagement, and the least engagement
#: taken in group S (three pitches).
THREAD_CLASSES = {"S": (5, 5, "5H/5g6g"), "N": (6, 6, "6H/6g")}
MIN_ENGAGEMENT_PITCHES = 3.0


@lru_cache(maxsize=8)
def _thread_table(candidates: tuple, P: float) -> dict[str, np.ndarray]:
    """Per candidate size: group N's bounds, the shear areas per mm of groups S and N, the basic diameters."""
    Dk = np.asarray(candidates, dtype=float)
    Ln_min, Ln_max = engagement_group_n_mm(Dk, P)
    g = thread_geometry(Dk, P)
    return {"D": Dk, "Ln_min": Ln_min, "Ln_max": Ln_max, "a_S": np.fmin(*_stripping_areas_per_mm(Dk, P, 5, 5)),
            "a_N": np.fmin(*_stripping_areas_per_mm(Dk, P, 6, 6)), "d2": g["d2"], "D1": g["D1"]}


def _engagement(F, safety_factor, tau, table, P):
    """Engagement length per end and candidate: group S (5H/5g6g) when stripping needs less than group N's lower
    bound, else group N (6H/6g); the utilisation of group N's upper bound, and the shear area per mm used."""
    Ln_min, Ln_max, a_S, a_N = table["Ln_min"], table["Ln_max"], table["a_S"], table["a_N"]
    with np.errstate(divide="ignore", invalid="ignore"):
        L_S = np.fmax(MIN_ENGAGEMENT_PITCHES * P, F * safety_factor / (tau * a_S))
        L_N = np.fmax(Ln_min, F * safety_factor / (tau * a_N))
    short = L_S <= Ln_min
    L = np.where(short, L_S, L_N)
    a = np.where(short, a_S, a_N)
    return L, short, L_N / Ln_max, a


def select_thread(ro_lmc_mm, top_load_N, base_load_N, yield_MPa: float, safety_factor: float,
                  base_only: bool = False, candidates=ISO261_FINE_MM) -> dict[str, Array]:
    """The largest ISO 261 fine thread (pitch 1.5) the outer tube's ends carry their end loads with.

    For every size: the tube wall under the internal thread's root (``D + 2 H/8``, the basic profile's root
    truncation, at the least-material outside) in tension carries the larger end load with ``safety_factor``
    on yield; each end's engagement is what stripping of the weaker thread needs (shear at ``yield/2``, Tresca,
    at the least-material condition of its tolerance class), at least three pitches: within ISO 965-1's short
    group S it is toleranced 5H/5g6g, else it is at least group N's lower bound and toleranced 6H/6g (medium
    quality, ISO 965-1 Table 7), and must stay within group N.

    Parameters
    ----------
    ro_lmc_mm : array
        Outer tube's outside radius at its least-material condition, mm.
    top_load_N, base_load_N : array
        Effective end loads of the top cap and the base, N (:meth:`Loads.effective`).
    yield_MPa : float
        Yield of the housing material (tube and end pieces), MPa.
    safety_factor : float
        Reference safety factor the loads are normalised to, dimensionless.
    base_only : bool
        Only the base is threaded (``ring_top``): the top load is ignored.
    candidates : sequence of float
        Nominal diameters tried, mm (default the ISO 261 fine series of pitch 1.5).

    Returns
    -------
    dict of str to ndarray
        ``major_mm`` ``D``, ``minor_mm`` ``D1``, ``pitch_diameter_mm`` ``d2``, ``engagement_top_mm``,
        ``engagement_base_mm`` (mm), ``short_top``, ``short_base`` (bool: group S, 5H/5g6g), ``utilisation``
        (worst check / its limit, dimensionless, <= 1 met) and ``wall_safety``, ``stripping_top_safety``,
        ``stripping_base_safety`` (dimensionless).
    """
    P = THREAD_PITCH_MM
    table = _thread_table(tuple(float(d) for d in candidates), P)
    Dk = table["D"]  # (K,)
    ro = np.asarray(ro_lmc_mm, dtype=float)[..., None]  # (S, 1)
    Ft = np.asarray(top_load_N, dtype=float)[..., None] * (0.0 if base_only else 1.0)
    Fb = np.asarray(base_load_N, dtype=float)[..., None]
    tau = yield_MPa / 2
    Lt, st, ut, at = _engagement(Ft, safety_factor, tau, table, P)
    Lb, sb, ub, ab = _engagement(Fb, safety_factor, tau, table, P)
    with np.errstate(divide="ignore", invalid="ignore"):
        A_wall = math.pi * (ro**2 - ((Dk + 0.2165 * P) / 2) ** 2)
        F = np.fmax(Ft, Fb)
        u_wall = np.where(A_wall > 0, F * safety_factor / (A_wall * yield_MPa), np.inf)
        util = np.fmax(u_wall, np.fmax(np.where(st, 0.0, ut), np.where(sb, 0.0, ub)))
    ok = util <= 1.0
    K = Dk.size
    # the largest that fits, else the least utilised (the joint's capacity constraint then fails)
    k = np.where(ok.any(axis=-1), K - 1 - np.argmax(ok[..., ::-1], axis=-1), np.argmin(np.nan_to_num(util, nan=np.inf), axis=-1))

    def pick(arr):
        return np.take_along_axis(np.broadcast_to(arr, util.shape), k[..., None], axis=-1)[..., 0]

    g = table
    Lt_k, Lb_k = pick(Lt), pick(Lb)
    with np.errstate(divide="ignore", invalid="ignore"):
        return {"major_mm": pick(Dk), "minor_mm": pick(g["D1"]), "pitch_diameter_mm": pick(g["d2"]),
                "engagement_top_mm": np.where(base_only, 0.0, Lt_k), "engagement_base_mm": Lb_k,
                "short_top": pick(st), "short_base": pick(sb),
                "utilisation": pick(util), "wall_safety": safety_factor / pick(u_wall),
                "stripping_top_safety": np.where(base_only, np.inf, tau * pick(at) * Lt_k / Ft[..., 0]),
                "stripping_base_safety": tau * pick(ab) * Lb_k / Fb[..., 0]}


# ----------------------------------------------------------------------------------------------- retaining ring
def select_ring(ro_lmc_mm, load_N, yield_MPa: float, safety_factor: float) -> dict[str, Array]:
    """The largest DIN 472 internal retaining ring the outer tube's top end holds the top cap with.

    Checks (each with ``safety_factor`` on the load): the groove, ``F_N x yield / 200 MPa`` (DIN 472's ``F_N`` is
    for a groove material of 200 N/mm² yield); the ring, ``F_R`` (sharp-edged abutment: the cap's edge is not
    chamfered); the tube wall under the groove's largest diameter in tension at the least-material outside; the
    land above the groove in shear at ``yield/2`` (Tresca), never shorter than DIN 472's ``n``.

    Parameters
    ----------
    ro_lmc_mm : array
        Outer tube's outside radius at its least-material condition, mm.
    load_N : array
        Effective top end load, N.
    yield_MPa : float
        Yield of the housing material, MPa.
    safety_factor : float
        Reference safety factor, dimensionless.

    Returns
    -------
    dict of str to ndarray
        ``index`` (row of :func:`din472_table`), ``bore_mm`` ``d1``, ``groove_diameter_mm`` ``d2``,
        ``groove_width_mm`` ``m``, ``land_mm`` (mm), ``utilisation`` (dimensionless, <= 1 met) and the safety
        factors ``groove_safety``, ``ring_safety``, ``wall_safety`` (dimensionless).
    """
    T = din472_table()
    ro = np.asarray(ro_lmc_mm, dtype=float)[..., None]
    F = np.asarray(load_N, dtype=float)[..., None] * safety_factor
    with np.errstate(divide="ignore", invalid="ignore"):
        A_wall = math.pi * (ro**2 - ((T["d2"] + T["d2_tol"]) / 2) ** 2)
        u_groove = F / (T["FN"] * 1e3 * yield_MPa / 200.0)
        u_ring = F / (T["FR"] * 1e3)
        u_wall = np.where(A_wall > 0, F / (A_wall * yield_MPa), np.inf)
        land = np.fmax(T["n"], F / (math.pi * T["d2"] * yield_MPa / 2))
        util = np.fmax(np.fmax(u_groove, u_ring), u_wall)
    ok = util <= 1.0
    K = T["d1"].size
    # the largest that fits, else the least utilised (the joint's capacity constraint then fails)
    k = np.where(ok.any(axis=-1), K - 1 - np.argmax(ok[..., ::-1], axis=-1), np.argmin(np.nan_to_num(util, nan=np.inf), axis=-1))
    def pick(arr):
        return np.take_along_axis(np.broadcast_to(arr, util.shape), k[..., None], axis=-1)[..., 0]

    return {"index": k, "bore_mm": T["d1"][k], "thickness_mm": T["s"][k], "mass_g": T["W"][k], "groove_diameter_mm": T["d2"][k], "groove_width_mm": T["m"][k],
            "land_mm": pick(land), "utilisation": pick(util), "groove_safety": safety_factor / pick(u_groove),
            "ring_safety": safety_factor / pick(u_ring), "wall_safety": safety_factor / pick(u_wall)}


# ----------------------------------------------------------------------------------------------- tie rods
def tie_rod_preload(d_mm, P_mm, yield_MPa: float) -> dict[str, Array]:
    """VDI 2230-1 assembly preload and tightening torque of a rod with an ISO 4032 nut, N and N m.

    ``A_s = pi/4 ((d2 + d3)/2)^2`` (ISO 898-1); ``F_Mzul = A_s nu R_p0.2 / sqrt(1 + 3 [3/2 d2/d_s (P/(pi d2) +
    1.155 mu)]^2)`` with ``nu = 0.9`` and ``mu = 0.12``; ``M_A = F_Mzul (0.16 P + 0.58 mu d2 + mu D_Km/2)``,
    ``D_Km`` the mean of the nut's width across flats and the clearance hole; ``F_M,min = F_Mzul / 1.6``.

    Parameters
    ----------
    d_mm, P_mm : array
        Nominal diameter and pitch, mm.
    yield_MPa : float
        R_p0.2 of the property class, MPa.

    Returns
    -------
    dict of str to ndarray
        ``stress_area_mm2`` (mm²), ``preload_max_N``, ``preload_min_N`` (N) and ``torque_Nm`` (N m, with the
        nut and hole of :data:`TIE_ROD_SIZES` when ``d_mm`` are theirs, else a nut of ``1.6 d`` across flats).
    """
    d, P = np.asarray(d_mm, dtype=float), np.asarray(P_mm, dtype=float)
    g = {"d2": d - 0.649519 * P, "d3": d - 1.226869 * P}
    ds = (g["d2"] + g["d3"]) / 2
    As = math.pi / 4 * ds**2
    k = 1.5 * g["d2"] / ds * (P / (math.pi * g["d2"]) + 1.155 * VDI_MU)
    FM = As * VDI_NU * yield_MPa / np.sqrt(1 + 3 * k**2)
    tab = _tie_rod_table()
    s = np.interp(d, tab["d"], tab["s"])
    hole = np.interp(d, tab["d"], tab["hole"])
    MA = FM * (0.16 * P + 0.58 * VDI_MU * g["d2"] + VDI_MU * (s + hole) / 4) * 1e-3
    return {"stress_area_mm2": As, "preload_max_N": FM, "preload_min_N": FM / VDI_ALPHA_A, "torque_Nm": MA}


def tie_rod_candidates(ro_mm) -> dict[str, Array]:
    """Every tie-rod arrangement tried (count x size), with its rod circle and the outer tube it leaves, mm.

    The nut (ISO 4032, across corners ``2 s / sqrt 3``) stays inside the envelope and the hole keeps
    :data:`ROD_EDGE_MM` outside it; the rods keep :data:`ROD_GAP_MM` from the tube; the nuts of neighbouring
    rods clear each other by 1 mm.

    Parameters
    ----------
    ro_mm : array
        Envelope radius (the end pieces' outside), mm, shape ``(S,)``.

    Returns
    -------
    dict of str to ndarray
        Shape ``(S, K)`` or ``(K,)``: ``count``, ``size`` (index into :data:`TIE_ROD_SIZES`), ``d``, ``P``,
        ``hole``, ``nut_s``, ``nut_m`` (mm), ``rod_circle_radius_mm``, ``tube_outer_radius_mm`` (mm) and
        ``fits`` (the nuts clear each other and the tube keeps a radius).
    """
    tab = _tie_rod_table()
    n_s = len(TIE_ROD_SIZES)
    count = np.repeat(np.array(TIE_ROD_COUNTS, dtype=float), n_s)
    size = np.tile(np.arange(n_s), len(TIE_ROD_COUNTS))
    d, P, hole, s, m = (tab[k][size] for k in ("d", "P", "hole", "s", "m"))
    e = 2 * s / math.sqrt(3)
    ro = np.asarray(ro_mm, dtype=float)[..., None]
    Rc = ro - np.fmax(e / 2, hole / 2 + ROD_EDGE_MM)
    rt = Rc - d / 2 - ROD_GAP_MM
    fits = (2 * Rc * np.sin(math.pi / count) >= e + 1.0) & (rt > 0)
    return {"count": count, "size": size, "d": d, "P": P, "hole": hole, "nut_s": s, "nut_m": m,
            "rod_circle_radius_mm": Rc, "tube_outer_radius_mm": rt, "fits": fits}


# ----------------------------------------------------------------------------------------------- the sizing result
@dataclass(frozen=True)
class JointSizing:
    """A joint choice sized for a population: its footprint in the geometry (arrays broadcast, mm, N)."""

    kind: str  #: one of :data:`JOINTS`
    tube_outer_radius_mm: Array  #: the outer tube's outside radius (inside the rod circle for tie rods)
    bore_cap_radius_mm: Array  #: largest nominal outer-tube bore the joint allows (inf: no cap)
    top_support_radius_mm: Array  #: where the top cap is held (thread pitch radius, ring bore, rod circle)
    base_support_radius_mm: Array  #: where the base is held
    top_zone_mm: Array  #: axial length of the top cap inside the tube (thread, run-out, seal gland)
    base_zone_mm: Array  #: axial length of the base's spigot inside the tube
    top_extra_mm: Array  #: housing length beyond the top cap (the ring's groove and land), else 0
    utilisation: Array  #: the joint's worst check over its limit (<= 1 met), dimensionless
    seal_zone_mm: float  #: static O-ring gland + its two lands, mm
    quantities: dict[str, Array] = field(default_factory=dict)  #: the kind's own sizes (unit in the name)


# ----------------------------------------------------------------------------------------------- records
@dataclass(frozen=True)
class ThreadJoint(Record):
    """A threaded joint: an end piece's spigot screwed into the outer tube (ISO 261 fine, 6H/6g per ISO 965-1)."""

    joint: str  #: ``top_cap`` or ``base``
    kind: str  #: ``thread``
    designation: str  #: e.g. ``M56x1.5-6H/6g`` (or ``-5H/5g6g`` for a short engagement)
    standard: str  #: ISO 261, ISO 965-1, ISO 68-1
    tolerance_class: str  #: ISO 965-1 class (``6H/6g``: engagement group N; ``5H/5g6g``: group S)
    major_diameter_mm: float  #: nominal D
    pitch_mm: float
    pitch_diameter_mm: float  #: basic d2
    minor_diameter_mm: float  #: basic D1 of the internal thread (the tube's bore must pass it)
    engagement_length_mm: float  #: threaded length engaged
    runout_mm: float  #: the spigot's thread run-out (DIN 76-1 short run-out, 1.25 P)
    seal_zone_mm: float  #: the spigot's static O-ring gland and lands, below the thread
    zone_mm: float  #: the end piece's length inside the tube (engagement + run-out + seal zone)
    end_load_N: float  #: effective end load it carries (normalised to the reference safety factor)
    governing_case: str  #: the load case that sets the end load
    safety_factors: dict  #: check -> safety factor (tube wall under the root, stripping)
    required_safety_factor: float


@dataclass(frozen=True)
class RingJoint(Record):
    """The top cap held in the tube by a DIN 472 internal retaining ring."""

    joint: str  #: ``top_cap``
    kind: str  #: ``ring_top``
    designation: str  #: e.g. ``DIN 472 - 50 x 2``
    standard: str
    bore_mm: float  #: d1: the tube's bore at the ring (and the cap plug's diameter)
    groove_diameter_mm: float  #: d2
    groove_width_mm: float  #: m
    ring_thickness_mm: float  #: s
    land_mm: float  #: tube material left above the groove
    mass_g: float  #: the ring (DIN 472 W / 1000)
    end_load_N: float
    governing_case: str
    safety_factors: dict  #: groove, ring, wall under the groove
    required_safety_factor: float


@dataclass(frozen=True)
class TieRodJoint(Record):
    """Tie rods (threaded rods with nuts) clamping both end pieces onto the outer tube."""

    joint: str  #: ``top_cap_and_base``
    kind: str  #: ``tie_rods``
    designation: str  #: e.g. ``6 x DIN 976-1 M4 - 10.9, ISO 4032 nuts``
    standard: str
    count: int
    nominal_diameter_mm: float
    pitch_mm: float
    property_class: str
    stress_area_mm2: float
    rod_circle_radius_mm: float
    clearance_hole_mm: float  #: ISO 273 normal (medium) series
    nut_width_across_flats_mm: float
    nut_height_mm: float
    rod_length_mm: float  #: over both end pieces and both nuts
    preload_max_N: float  #: F_Mzul (VDI 2230-1)
    preload_min_N: float  #: F_Mzul / tightening factor
    tightening_torque_Nm: float
    load_factor: float  #: Phi, the rods' share of the working load
    end_load_N: float
    governing_case: str
    safety_factors: dict  #: separation, rod yield
    required_safety_factor: float


@dataclass(frozen=True)
class SeatJoint(Record):
    """A piece that only bears on another (no fastener): the inner tube in the base and under the top cap."""

    joint: str  #: ``inner_tube_base`` or ``inner_tube_top``
    kind: str  #: ``seat``
    what: str
    end_load_N: float  #: the largest axial force through the seat (compression)
    bearing_stress_MPa: float
    safety_factor: float
    required_safety_factor: float
