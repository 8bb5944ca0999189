"""Every derived quantity of a design from its decision variables: one set of formulas for one design and for
a whole population (numpy broadcast).

:func:`derive` runs the named steps in order: the areas, the charge and peak pressures
(:func:`peak_pressures`), the cross-section with its walls sized (:func:`size_walls`), the axial stack
(lengths and the gas accounting, with the layout's own volumes), the bladder cast to hold exactly V2, and
optionally the walls' stresses (:func:`wall_stresses`) and the parts' masses (:func:`part_masses`). What a
layout variant adds (its walls, volumes, lengths, constraints) is its module's
(:mod:`vvea_design.spring.layouts`); nothing here asks which layout it is. The result is a frozen
:class:`Derived` whose fields are arrays broadcast like the inputs.

Units: lengths mm, areas mm², volumes mm³, pressures and stresses MPa, masses g.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, fields, replace
from typing import Any

import numpy as np

from ..materials.structural import DENSITY_HYDRAULIC_OIL_g_per_mm3, DENSITY_SILICONE_g_per_mm3, get_material
from .geometry import Array, Pressures, Section
from .hydraulics import hydraulic_path, linear_damping_N_s_per_mm
from .layouts import DECISION_VARIABLES, LayoutStack, LayoutVariant, get_layout
from .masses import part_masses_g
from .parameters import DesignError, FixedParameters
from .ports import GAS_ONLY_SEAL_MM, design_chamber2_port_room_mm

__all__ = ["Derived", "Stack", "derive", "peak_pressures", "size_walls", "wall_stresses", "part_masses",
           "piston_floor_moment"]


@dataclass(frozen=True)
class Stack:
    """The axial stack of a population: lengths from the base up, mm (arrays broadcast)."""

    chamber1_length_mm: Array  #: gas column above the piston at x = 0 (up to the top cap or a bulkhead)
    fluid_column_mm: Array  #: fluid under the piston at x = 0: travel + clearance
    inner_length_mm: Array  #: inner-tube bore = housing interior (base top to top-cap underside)
    housing_length_mm: Array  #: overall length of the housing (eyes excluded)
    bladder_free_length_mm: Array  #: bladder between its two clamps
    rod_length_mm: Array  #: rod from the piston's underside to its end outside the base at x = 0
    layout: LayoutStack  #: what the layout added or took (its quantities among them)


#: Fields of :class:`Derived` that hold objects (records, nested results), kept as they are by :meth:`Derived.item`.
_OBJECT_FIELDS = {"load_cases", "section", "check", "governing", "hydraulic_path"}


@dataclass(frozen=True)
class Derived:
    """Every derived quantity of one design or of a population (arrays broadcast like the inputs).

    The names are those of :class:`~vvea_design.spring.design.Design` and of the design file. Units:
    lengths mm, areas mm², volumes mm³, pressures and stresses MPa, masses g; ``bladder_cast_fill`` a
    fraction of the stroke; safety factors dimensionless. ``stresses_MPa``, ``safety_factors`` and
    ``inner_tube_buckling_MPa`` are None when :func:`derive` was asked for no stresses, ``masses_g`` and
    ``mass_g`` when asked for no masses.
    """

    layout: str  #: name of the layout variant
    piston_diameter_mm: Array
    outer_diameter_mm: Array
    V1_mm3: Array
    V2_mm3: Array
    A1_mm2: Array  #: chamber-1 area: the full piston face
    A2_mm2: Array  #: chamber-2 area: piston minus rod
    p1_MPa: Array  #: chamber-1 charge that puts zero force at the set point
    peak_chamber_1_MPa: Array  #: highest chamber-1 pressure over a stroke (at x = 0)
    peak_chamber_2_MPa: Array  #: highest chamber-2 pressure over a stroke (at full stroke, wall-sizing exponent)
    chamber_difference_MPa: Array  #: largest chamber-2 minus chamber-1 pressure (on the walls between the chambers)
    inner_tube_net_pressure_MPa: Array  #: external net pressure on the inner tube at full stroke
    wall_capacity_value_MPa: Array  #: peak chamber-2 pressure (constraint ``wall_capacity``)
    wall_capacity_limit_MPa: Array  #: highest pressure any inner tube carries (half the allowable stress)
    walls_mm: dict[str, Array]  #: sized walls by name (the layout's and the piston pocket's floor among them)
    outer_bore_radius_mm: Array
    inner_tube_outer_radius_mm: Array
    annulus_gap_mm: Array  #: radial gap between inner tube and outer bore
    piston_floor_mm: Array  #: floor of the piston pocket (the piston height without one)
    piston_pocket_radius_mm: Array
    piston_pocket_depth_mm: Array
    piston_pocket_volume_mm3: Array
    chamber1_length_mm: Array
    fluid_column_mm: Array
    inner_length_mm: Array
    housing_length_mm: Array
    bladder_free_length_mm: Array
    rod_length_mm: Array
    displaced_volume_mm3: Array  #: fluid pushed into the bladder over the stroke, A2 * travel
    V2_annulus_mm3: Array  #: chamber-2 gas around the bladder at x = 0
    annulus_volume_mm3: Array  #: annulus between the tubes over the bladder's free length
    V2_capacity_mm3: Array  #: largest V2 the annulus can hold with the bladder's room at x = 0
    bladder_cast_fill: Array  #: stroke fraction at which the bladder has its cast shape
    bladder_gas_volume_cast_mm3: Array
    bladder_outer_radius_mm: Array
    bladder_inner_radius_mm: Array
    bladder_mid_radius_mm: Array
    bladder_shift_compressed_mm: Array
    bladder_shift_expanded_mm: Array
    bladder_clearance_compressed_mm: Array
    bladder_clearance_expanded_mm: Array
    bladder_cast_gap_mm: Array  #: room inside the cast bladder (support-ring channels)
    bladder_fluid_volume_cast_mm3: Array
    fluid_volume_mm3: Array  #: hydraulic fluid to fill at x = 0
    buildable: Array  #: bool: the geometry can be drawn at all
    layout_quantities: dict[str, Array]  #: the layout's own quantities by name (``V2_top_mm3``, ``cross_slot_room_mm`` ...)
    inner_tube_cut_mm3: Array  #: inner-tube material the layout cuts away (the annulus_top slots), 0 in the others
    stresses_MPa: dict[str, Array] | None = None  #: peak stress of each wall as drawn
    safety_factors: dict[str, Array] | None = None  #: yield over peak stress (inner tube: also buckling)
    inner_tube_buckling_MPa: Array | None = None  #: elastic buckling pressure of the inner tube
    masses_g: dict[str, Array] | None = None  #: mass of each part
    mass_g: Array | None = None  #: their sum
    joint: str = "thread"  #: the joint choice (:data:`~vvea_design.spring.joints.JOINTS`)
    sizing_rules: str = "buildable"  #: ``fixed.sizing_rules``
    #: the buildability rules' results (None under ``gas_only``): the load cases, the sized section (with the
    #: joint's sizing), every piece's check per case, the governing case per piece, the damper's flow path
    load_cases: Any = None
    section: Any = None
    check: Any = None
    governing: Any = None
    hydraulic_path: Any = None
    required_safety_factors: dict[str, Array] | None = None  #: per piece, what its governing case asks
    joint_utilisation: Array | None = None  #: the joint's worst check over its limit (<= 1 met)
    parasitic_damping_N_s_per_mm: Array | None = None  #: D_min: the damping with the throttle fully open, N s/mm
    #: widest chamber-2 fill port the design guarantees between the bladder's bead and the spigot's seal groove
    #: (:func:`~vvea_design.spring.ports.design_chamber2_port_room_mm`), mm
    chamber2_port_room_mm: Array | None = None

    def to_dict(self) -> dict[str, Any]:
        """Every field by name (the dictionaries as dictionaries).

        Returns
        -------
        dict
            Field name -> value (arrays, or floats after :meth:`item`; units as in the names: mm, mm²,
            mm³, MPa, g).
        """
        return {f.name: getattr(self, f.name) for f in fields(self)}

    def item(self) -> "Derived":
        """The same quantities as Python numbers (a single design: every array has one element).

        Returns
        -------
        Derived
            Floats (``buildable`` a bool, ``layout`` a str), dictionaries of floats; units unchanged.
        """
        def one(name, v):
            if v is None or isinstance(v, str) or name in _OBJECT_FIELDS:
                return v
            if isinstance(v, dict):
                return {k: float(x) for k, x in v.items()}
            return bool(v) if name == "buildable" else float(v)

        return Derived(**{f.name: one(f.name, getattr(self, f.name)) for f in fields(self)})


def piston_floor_moment(piston_radius_mm, pocket_radius_mm, rod_radius_mm, poisson):
    """Radial bending moment at the rod of the piston pocket's floor per unit pressure, N·mm/mm per MPa.

    The floor is an annular plate from the rod (radius ``b``, where the rod ends in it: edge clamped) to the
    pocket's wall (radius ``a``: edge free to rotate, conservatively, carrying the rim's load). The pressure
    difference ``q`` between chamber 1 above and the fluid below acts on ``b .. a`` and, through the rim, as a
    line load ``q (rp^2 - a^2) / (2 a)`` at ``a``: the whole net load ``q pi (rp^2 - b^2)`` goes to the rod.
    Thin-plate theory (axisymmetric: ``d/dr[(1/r) d/dr(r w')] = Q/D``, ``Q = q (rp^2 - r^2)/(2 r)``) gives the
    largest moment at the rod, ``|M_r(b)| = q K`` with

    ``K = [(3 + nu) a^4 - 2 (1 + nu) a^2 b^2 - (1 - nu) b^4 - 2 (1 - nu) rp^2 (a^2 - b^2)
    - 4 (1 + nu) a^2 rp^2 ln(a/b)] / (-8 (a^2 (1 + nu) + b^2 (1 - nu)))``

    (checked against a numerical solution of the plate equation in ``tests/spring/test_design.py``).

    Parameters
    ----------
    piston_radius_mm, pocket_radius_mm, rod_radius_mm : float or array
        ``rp``, ``a`` and ``b``, mm (``b < a < rp``).
    poisson : float
        Poisson's ratio of the piston's material.

    Returns
    -------
    float or ndarray
        ``K``, mm² (moment per unit circumference per MPa: N·mm/mm per N/mm²).
    """
    rp, a, b, nu = (np.asarray(piston_radius_mm, dtype=float), np.asarray(pocket_radius_mm, dtype=float),
                    float(rod_radius_mm), float(poisson))
    num = (-(3 + nu) * a**4 + 2 * (1 + nu) * a**2 * b**2 + (1 - nu) * b**4 + 2 * (1 - nu) * rp**2 * (a**2 - b**2)
           + 4 * (1 + nu) * a**2 * rp**2 * np.log(a / b))
    return np.abs(num / (8 * (a**2 * (1 + nu) + b**2 * (1 - nu))))


def peak_pressures(A1_mm2, A2_mm2, V1_mm3, V2_mm3, p2_MPa, setpoint_x0_mm, fixed: FixedParameters) -> Pressures:
    """The chamber-1 charge of the set point (eq. 6) and the pressures the walls are sized for.

    The peaks are those of a stroke at ``max(fixed.n_polytropic, fixed.wall_sizing_n)``: chamber 2 is
    highest at full stroke, chamber 1 lowest there.

    Parameters
    ----------
    A1_mm2, A2_mm2 : float or array
        Chamber areas, mm².
    V1_mm3, V2_mm3 : float or array
        Gas volumes at x = 0, mm³.
    p2_MPa : float or array
        Chamber-2 charge, MPa.
    setpoint_x0_mm : float or array
        Displacement of zero force, mm.
    fixed : FixedParameters
        Travel (mm) and the polytropic exponents.

    Returns
    -------
    Pressures
        p1 and the peaks, MPa (nan where a chamber bottoms out).
    """
    A1, A2, V1, V2 = A1_mm2, A2_mm2, V1_mm3, V2_mm3
    p2 = np.asarray(p2_MPa, dtype=float)
    x0 = np.asarray(setpoint_x0_mm, dtype=float)
    T, n = fixed.travel_mm, fixed.n_polytropic
    with np.errstate(divide="ignore", invalid="ignore"):
        v2x0 = np.where(V2 - A2 * x0 > 0, V2 - A2 * x0, np.nan)
        p1 = (A2 / A1) * p2 * (V2 / v2x0) ** n * ((V1 + A1 * x0) / V1) ** n
        nw = max(n, fixed.wall_sizing_n)
        v2T = np.where(V2 - A2 * T > 0, V2 - A2 * T, np.nan)
        P2_peak = p2 * (V2 / v2T) ** nw
        P1_min = p1 * (V1 / (V1 + A1 * T)) ** nw
        between = np.maximum(np.maximum(P2_peak - P1_min, p1 - p2), 0.0)
        net = np.maximum(P2_peak - P1_min, 0.0)
    return Pressures(p1, P2_peak, P1_min, between, net)


def size_walls(piston_diameter_mm, outer_diameter_mm, A1_mm2, A2_mm2, pressures: Pressures,
               fixed: FixedParameters, layout: LayoutVariant) -> Section:
    """The cross-section with every wall sized for its peak pressure, never below its minimum.

    Each wall is the thinnest that carries its peak pressure with ``fixed.wall_safety_factor`` on yield, but
    never thinner than its manufacturable minimum (``fixed.min_*``). Outer tube: Lamé, internal pressure;
    inner tube: Lamé, external pressure, and elastic buckling of a long tube under the net pressure
    (``p_cr = E / (4 (1 - nu^2)) (t / r_mean)^3``); end caps: simply supported circular plates; the layout's
    own walls by its module. Where no wall can carry the pressure the minimum is drawn (the constraint
    ``wall_capacity`` says so). With ``fixed.piston_pocket`` the piston pocket's floor too: an annular plate
    from the rod to the pocket wall carrying the largest chamber-2 (fluid) minus chamber-1 pressure to the
    rod, sized for bending at the rod (:func:`piston_floor_moment`) and for Tresca on the peak root shear
    ``1.5 Q/t``, ``Q = p (rp^2 - b^2)/(2 b)``, in the rod's material (piston and rod are one turned part);
    no pocket where its radius would not exceed the rod's.

    Parameters
    ----------
    piston_diameter_mm, outer_diameter_mm : float or array
        Piston (= inner-tube bore) and outer diameter, mm.
    A1_mm2, A2_mm2 : float or array
        Chamber areas, mm².
    pressures : Pressures
        Peaks the walls carry, MPa.
    fixed : FixedParameters
        Minimums, safety factor, materials, the piston pocket's sizes.
    layout : LayoutVariant
        Sizes its own walls (:meth:`~vvea_design.spring.layouts.base.LayoutVariant.size_walls`).

    Returns
    -------
    Section
        Radii, walls (mm) and the pocket (mm, mm³).
    """
    f, pi = fixed, math.pi
    mat = get_material(f.housing_material)
    P2 = pressures.peak_chamber_2_MPa
    with np.errstate(divide="ignore", invalid="ignore"):
        sa = mat.yield_MPa / f.wall_safety_factor  # allowable stress
        kp = 3 * (3 + mat.poisson) / 8  # plate: sigma = kp p a^2 / t^2
        ro, ri = np.asarray(outer_diameter_mm, dtype=float) / 2, np.asarray(piston_diameter_mm, dtype=float) / 2
        # required thickness (nan where no wall can carry the pressure), then the minimums
        t_o_req = ro - ro * np.sqrt((sa - P2) / (sa + P2))
        t_i_req = ri * (np.sqrt(sa / (sa - 2 * P2)) - 1)
        kb = mat.youngs_modulus_MPa / (4 * (1 - mat.poisson**2))
        cb = np.cbrt(f.wall_safety_factor * pressures.inner_tube_net_pressure_MPa / kb)
        t_i_req = np.fmax(t_i_req, ri * cb / (1 - cb / 2))
        t_o = np.fmax(f.min_outer_wall_mm, np.where(P2 < sa, t_o_req, np.nan))
        t_i = np.fmax(f.min_inner_tube_wall_mm, np.where(2 * P2 < sa, t_i_req, np.nan))
        rb = ro - t_o
        t_cap = np.fmax(f.min_top_cap_mm, np.sqrt(kp * P2 * rb**2 / sa))
        t_base = np.fmax(f.min_base_mm, np.sqrt(kp * P2 * rb**2 / sa))
        rio = ri + t_i
        ph = f.piston_height_mm
        if f.piston_pocket:
            has_pk, r_pk_s, t_fl = _size_piston_floor(ri, pressures.chamber_difference_MPa, f)
            V_pk = np.where(has_pk, pi * r_pk_s**2 * (ph - t_fl), 0.0)
        else:
            has_pk = np.zeros_like(ri, dtype=bool)
            r_pk_s, t_fl, V_pk = np.zeros_like(ri), np.full_like(ri, ph), np.zeros_like(ri)
        walls = {"outer_tube": t_o, "inner_tube": t_i, "top_cap": t_cap, "base": t_base}
        sec = Section(A1_mm2, A2_mm2, ro, rb, ri, rio, walls, sa, kp, t_fl * np.ones_like(ri),
                      np.where(has_pk, r_pk_s, 0.0) * np.ones_like(ri), V_pk * np.ones_like(ri), has_pk)
        own = layout.size_walls(sec, pressures, f)
        pocket = {"piston_floor": sec.piston_floor_mm} if f.piston_pocket else {}
    return replace(sec, walls_mm={**walls, **own, **pocket})


def _size_piston_floor(ri, dP, f: FixedParameters, sized=None):
    """Whether each piston has a pocket, its radius (a harmless one where none) and the floor, mm (``sized`` adds
    the floor's tolerance to what the load needs: the buildability rules)."""
    mat_p = get_material(f.rod_material)
    sa_p = mat_p.yield_MPa / f.wall_safety_factor
    b_rod = f.rod_diameter_mm / 2
    r_pk = ri - f.piston_pocket_wall_mm
    has_pk = r_pk > b_rod
    r_pk_s = np.where(has_pk, r_pk, 2 * b_rod)  # a harmless radius where there is no pocket
    k_floor = piston_floor_moment(ri, r_pk_s, b_rod, mat_p.poisson)
    q_floor = ri**2 - b_rod**2  # root shear per unit pressure x 2 b_rod
    t_fl_req = np.fmax(np.sqrt(6 * k_floor * dP / sa_p), 3 * dP * q_floor / (2 * b_rod * sa_p))
    if sized is not None:
        t_fl_req = sized(t_fl_req)
    t_fl = np.where(has_pk, np.fmin(np.fmax(f.min_piston_floor_mm, t_fl_req), f.piston_height_mm),
                    f.piston_height_mm)
    if sized is not None:  # the buildability rules: also the room the floor leaves (< 0: capped at the height)
        return has_pk, r_pk_s, t_fl, np.where(has_pk, f.piston_height_mm - t_fl_req, np.inf)
    return has_pk, r_pk_s, t_fl


def _floor_stress(sec: Section, dP, f: FixedParameters):
    """The piston floor's peak stress at a pressure ``dP`` across it, MPa: the larger of ``6 M / t^2`` at the rod
    and Tresca's ``2 x 1.5 Q / t``, the floor at its least-material thickness (0 without a pocket)."""
    mat_p = get_material(f.rod_material)
    b_rod = f.rod_diameter_mm / 2
    ri, has_pk = sec.piston_radius_mm, sec.has_piston_pocket
    t_fl = sec.least_material_thickness_mm(sec.piston_floor_mm)
    k_floor = piston_floor_moment(ri, np.where(has_pk, sec.piston_pocket_radius_mm, 2 * b_rod), b_rod, mat_p.poisson)
    q_floor = ri**2 - b_rod**2
    return np.where(has_pk, np.fmax(6 * k_floor * dP / t_fl**2, 3 * dP * q_floor / (2 * b_rod * t_fl)), 0.0)


def _axial_stack(sec: Section, lay_stack: LayoutStack, V1, fixed: FixedParameters) -> Stack:
    """Lengths from the base up: the chamber-1 column is what V1 leaves after the gas held elsewhere."""
    f = fixed
    w = sec.walls_mm
    with np.errstate(divide="ignore", invalid="ignore"):
        col = V1 - f.dead_volume_1_mm3
        for v in lay_stack.chamber1_elsewhere_mm3:
            col = col - v
        L1 = (col - sec.piston_pocket_volume_mm3) / sec.A1_mm2
        fluid_col = f.travel_mm + f.fluid_clearance_mm
        L_in = L1 + f.piston_height_mm + fluid_col
        for v in lay_stack.inner_length_extra_mm:
            L_in = L_in + v
        L = L_in - 2 * f.bladder_clamp_mm
        for v in lay_stack.bladder_length_taken_mm:
            L = L - v
    extra = 0.0 if sec.joint is None else sec.joint.top_extra_mm  # a retaining ring's groove and land above the cap
    return Stack(L1, np.full_like(L1, fluid_col), L_in, w["top_cap"] + L_in + w["base"] + extra, L,
                 np.full_like(L1, fluid_col) + w["base"] + f.travel_mm + 10.0, lay_stack)


def _bladder(sec: Section, stack: Stack, V2, fill, fixed: FixedParameters) -> dict[str, Array]:
    """The bladder cast at the radius that leaves exactly V2 of gas, its room at both stroke ends, the fluid."""
    f, pi = fixed, math.pi
    rb, rio, A2 = sec.outer_bore_radius_mm, sec.inner_tube_outer_radius_mm, sec.A2_mm2
    L = stack.bladder_free_length_mm
    disp = A2 * f.travel_mm
    V2_ann = V2 - f.dead_volume_2_mm3 - stack.layout.chamber2_elsewhere_mm3
    cast_gas = V2_ann - disp * fill
    Ls = np.where(L > 0, L, np.nan)
    with np.errstate(divide="ignore", invalid="ignore"):
        a = rio + f.bladder_min_gap_mm
        c = f.bladder_bulge_factor * disp * fill / (2 * pi * Ls)
        r_bi_cap = 0.5 * (a + np.sqrt(a * a + 4 * c))
        r_bo_cap = r_bi_cap + f.bladder_thickness_mm
        gas_cap = pi * np.maximum(rb**2 - r_bo_cap**2, 0.0) * L
        r_bo = np.sqrt(np.maximum(rb**2 - cast_gas / (pi * Ls), 1e-9))
        r_bi = r_bo - f.bladder_thickness_mm
        dv_c, dv_e = -disp * fill, disp * (1.0 - fill)
        s_c = dv_c / (2 * pi * np.maximum(r_bi, 1e-9) * Ls)
        s_e = dv_e / (2 * pi * r_bo * Ls)
        k, gap = f.bladder_bulge_factor, f.bladder_min_gap_mm
        fluid_cast = pi * np.maximum(r_bi**2 - rio**2, 0.0) * L
        return {
            "displaced_volume_mm3": disp, "V2_annulus_mm3": V2_ann,
            "annulus_volume_mm3": pi * (rb**2 - rio**2) * L,
            "V2_capacity_mm3": gas_cap + disp * fill + f.dead_volume_2_mm3 + stack.layout.chamber2_elsewhere_mm3,
            "bladder_cast_fill": fill * np.ones_like(L), "bladder_gas_volume_cast_mm3": cast_gas,
            "bladder_outer_radius_mm": r_bo, "bladder_inner_radius_mm": r_bi,
            "bladder_mid_radius_mm": r_bo - f.bladder_thickness_mm / 2,
            "bladder_shift_compressed_mm": s_c, "bladder_shift_expanded_mm": s_e,
            "bladder_clearance_compressed_mm": r_bi + k * s_c - rio - gap,
            "bladder_clearance_expanded_mm": rb - (r_bo + k * s_e) - gap,
            "bladder_cast_gap_mm": r_bi - rio,
            "bladder_fluid_volume_cast_mm3": fluid_cast,
            "fluid_volume_mm3": A2 * (f.travel_mm + f.fluid_clearance_mm) + fluid_cast + dv_c,
        }


def wall_stresses(section: Section, pressures: Pressures, fixed: FixedParameters,
                  layout: LayoutVariant) -> tuple[dict[str, Array], dict[str, Array], Array]:
    """Peak stresses and safety factors of the walls as drawn, and the inner tube's buckling pressure.

    * outer tube: thick-walled tube (Lamé), internal peak chamber-2 pressure;
    * inner tube: Lamé, external peak chamber-2 pressure (conservatively nothing inside),
      ``2 p ro^2 / (ro^2 - ri^2)``; its safety factor is also the buckling one, ``p_cr / (P2 - P1)``, if smaller;
    * top cap, base: circular plates, simply supported, ``3 (3 + nu) p a^2 / (8 t^2)``;
    * the layout's own walls (its module);
    * the piston pocket's floor (``fixed.piston_pocket``): the larger of ``6 M / t^2`` at the rod and Tresca's
      ``2 x 1.5 Q / t``, in the rod's material.

    Parameters
    ----------
    section : Section
        The cross-section with every wall sized (mm).
    pressures : Pressures
        Peaks, MPa.
    fixed : FixedParameters
        Materials, the rod (mm).
    layout : LayoutVariant
        Gives its own walls' stresses.

    Returns
    -------
    stresses : dict of str to ndarray
        Wall name -> peak stress, MPa.
    safety : dict of str to ndarray
        Wall name -> yield over peak stress, dimensionless (inf where unloaded).
    buckling : ndarray
        Elastic buckling pressure of the inner tube, MPa.
    """
    f, s = fixed, section
    mat, mat_p = get_material(f.housing_material), get_material(f.rod_material)
    P2, dP = pressures.peak_chamber_2_MPa, pressures.chamber_difference_MPa
    ro, rb, rio, ri, w, kp = (s.outer_radius_mm, s.outer_bore_radius_mm, s.inner_tube_outer_radius_mm,
                              s.piston_radius_mm, s.walls_mm, s.plate_factor)
    with np.errstate(divide="ignore", invalid="ignore"):
        st = {
            "outer_tube": P2 * (ro**2 + rb**2) / (ro**2 - rb**2),
            "inner_tube": 2 * P2 * rio**2 / (rio**2 - ri**2),
            "top_cap": kp * P2 * rb**2 / w["top_cap"]**2,
            "base": kp * P2 * rb**2 / w["base"]**2,
        }
        st.update(layout.wall_stresses(s, pressures, f))
        if f.piston_pocket:  # bending at the rod (6 M / t^2) or, if larger, Tresca's 2 x the peak root shear 1.5 Q / t
            b_rod = f.rod_diameter_mm / 2
            has_pk, t_fl = s.has_piston_pocket, s.piston_floor_mm
            k_floor = piston_floor_moment(ri, np.where(has_pk, s.piston_pocket_radius_mm, 2 * b_rod), b_rod,
                                          mat_p.poisson)
            q_floor = ri**2 - b_rod**2
            st["piston_floor"] = np.where(has_pk, np.fmax(6 * k_floor * dP / t_fl**2,
                                                          3 * dP * q_floor / (2 * b_rod * t_fl)), 0.0)
        safety = {k: np.where(v > 0, (mat_p if k == "piston_floor" else mat).yield_MPa / v, np.inf)
                  for k, v in st.items()}
        kb = mat.youngs_modulus_MPa / (4 * (1 - mat.poisson**2))
        t_i = w["inner_tube"]
        p_cr = kb * (t_i / (ri + t_i / 2)) ** 3
        dP_net = pressures.inner_tube_net_pressure_MPa
        safety["inner_tube"] = np.fmin(safety["inner_tube"], np.where(dP_net > 0, p_cr / dP_net, np.inf))
    return st, safety, p_cr


def part_masses(section: Section, stack: Stack, bladder_mid_radius_mm, fluid_volume_mm3, fixed: FixedParameters,
                layout: LayoutVariant) -> dict[str, Array]:
    """Mass of each part from closed-form volumes, g.

    Parameters
    ----------
    section : Section
        The cross-section with every wall sized (mm).
    stack : Stack
        Lengths (mm) and the layout's contributions.
    bladder_mid_radius_mm : float or array
        Mid-wall radius of the cast bladder, mm.
    fluid_volume_mm3 : float or array
        Hydraulic fluid at x = 0, mm³.
    fixed : FixedParameters
        Materials, the piston, rod and bladder sizes, the servo's mass.
    layout : LayoutVariant
        Gives its own parts' masses (after the inner tube's).

    Returns
    -------
    dict of str to ndarray
        Part -> mass, g: outer tube, end caps, inner tube, the layout's parts, piston, rod, bladder, support
        ring, fluid, servo and valve.
    """
    f, s, pi = fixed, section, math.pi
    ro, rb, rio, ri, w = (s.outer_radius_mm, s.outer_bore_radius_mm, s.inner_tube_outer_radius_mm,
                          s.piston_radius_mm, s.walls_mm)
    L_in, L = stack.inner_length_mm, stack.bladder_free_length_mm
    rho_h = get_material(f.housing_material).density_g_per_mm3
    rho_r = get_material(f.rod_material).density_g_per_mm3
    rho_s = get_material(f.support_ring_material).density_g_per_mm3
    m = {
        "outer_tube": pi * (ro**2 - rb**2) * L_in * rho_h,
        "end_caps": pi * ro**2 * (w["top_cap"] + w["base"]) * rho_h,
        "inner_tube": (pi * (rio**2 - ri**2) * L_in - stack.layout.inner_tube_cut_mm3) * rho_h,
        **layout.part_masses(s, stack.layout.quantities, f, rho_h),
        # the piston with a pocket in its material (fixed.rod_material); without one as before (the housing's
        # density: the published masses are unchanged; docs/layout.md)
        "piston": (pi * ri**2 * f.piston_height_mm - s.piston_pocket_volume_mm3) * (rho_r if f.piston_pocket else rho_h),
        "rod": pi / 4 * f.rod_diameter_mm**2 * stack.rod_length_mm * rho_r,
        "bladder": 2 * pi * bladder_mid_radius_mm * f.bladder_thickness_mm * (L + 2 * f.bladder_clamp_mm)
        * DENSITY_SILICONE_g_per_mm3,
        "support_ring": pi * (rb**2 - rio**2) * f.bladder_clamp_mm * 0.5 * rho_s,
        "fluid": np.maximum(fluid_volume_mm3, 0.0) * DENSITY_HYDRAULIC_OIL_g_per_mm3,
        "servo_and_valve": np.full_like(stack.chamber1_length_mm, f.servo_and_valve_mass_g),
    }
    return m


def _variables(variables, lay: LayoutVariant) -> dict[str, np.ndarray]:
    """The layout's decision variables as float arrays (the cast fill too, when given)."""
    out = {}
    for name in lay.decision_variables:
        if name not in variables:
            raise DesignError(f"derive: the {lay.name!r} layout needs {name} (its decision variables: "
                              f"{', '.join(lay.decision_variables)})")
        out[name] = np.asarray(variables[name], dtype=float)
    if variables.get("bladder_cast_fill") is not None:
        out["bladder_cast_fill"] = np.asarray(variables["bladder_cast_fill"], dtype=float)
    return out


def _mass_geometry(sec: Section, stack: Stack, bl: dict, quantities: dict, f: FixedParameters) -> dict:
    """The geometry :func:`~vvea_design.spring.masses.part_volumes_mm3` reads (arrays, mm, mm³)."""
    w = sec.walls_mm
    z = np.zeros_like(stack.inner_length_mm)
    return {"ro": sec.outer_radius_mm, "rb": sec.outer_bore_radius_mm, "rp": sec.piston_radius_mm,
            "rio": sec.inner_tube_outer_radius_mm, "rbi": bl["bladder_inner_radius_mm"],
            "rbo": bl["bladder_outer_radius_mm"], "base": w["base"], "L_in": stack.inner_length_mm,
            "cap": stack.housing_length_mm - stack.inner_length_mm - w["base"], "clamp": f.bladder_clamp_mm,
            "rod_length": stack.rod_length_mm, "pocket_r": sec.piston_pocket_radius_mm,
            "pocket_depth": f.piston_height_mm - sec.piston_floor_mm, "bulkhead": w.get("bulkhead", z),
            "top_space": quantities.get("top_space_length_mm", z), "collar": w.get("collar", z),
            "top_annulus": quantities.get("top_annulus_length_mm", z),
            "cross_slot_volume": quantities.get("cross_slot_volume_mm3", z), "L_free": stack.bladder_free_length_mm,
            "base_own": w["base"] if sec.base_own_mm is None else sec.base_own_mm}


def _buildable_checks(sec: Section, loads, f: FixedParameters, lay: LayoutVariant) -> dict:
    """Every piece's check per case, its governing case, and the stresses / safety factors / limits it reports."""
    from .sizing import check_section, governing

    chk = check_section(sec, loads, f, lay, _floor_stress)
    gov = governing(chk)
    return {"check": chk, "governing": gov, "stresses": {k: g[1] for k, g in gov.items()},
            "safety": {k: g[2] for k, g in gov.items()}, "required": {k: g[3] for k, g in gov.items()},
            "buckling": chk["buckling_MPa"]}


def _section(dp, Do, A1, A2, pr: Pressures, p2_MPa, f: FixedParameters, lay: LayoutVariant, joint: str):
    """The sized cross-section by ``fixed.sizing_rules`` and, under the buildability rules, the load cases."""
    if f.sizing_rules == "gas_only":
        return size_walls(dp, Do, A1, A2, pr, f, lay), None
    from .loads import load_cases
    from .sizing import size_section

    loads = load_cases(pr, p2_MPa, A1, A2, f)
    return size_section(dp, Do, A1, A2, loads, f, lay, joint, _size_piston_floor), loads


def derive(variables, p2_MPa, setpoint_x0_mm, fixed: FixedParameters, layout="inner_tube", *, joint: str = "thread",
           stresses: bool = True, masses: bool = True) -> Derived:
    """Every derived quantity of a design, from its decision variables (arrays broadcast).

    The single source of the geometry, strength and mass formulas: :class:`~vvea_design.spring.design.Design`
    reads its properties from it, and the optimiser evaluates a whole population with it in one call. The
    steps: :func:`peak_pressures`, the cross-section (under ``fixed.sizing_rules = "buildable"``: the load cases
    of :mod:`~vvea_design.spring.loads`, every piece sized at its least-material condition and the joint,
    :mod:`~vvea_design.spring.sizing`; under ``"gas_only"``: :func:`size_walls`), the layout's stack
    (:meth:`~vvea_design.spring.layouts.base.LayoutVariant.stack`), the axial stack, the bladder, the
    layout's rooms, the damper's flow path and its parasitic damping (:mod:`~vvea_design.spring.hydraulics`),
    then optionally the pieces' checks and the parts' masses (:mod:`~vvea_design.spring.masses`; under
    ``"gas_only"`` :func:`wall_stresses` and :func:`part_masses`).

    With ``fixed.piston_pocket`` (every layout) chamber-1 gas also fills a coaxial pocket bored into the
    piston crown, radius ``dp/2 - fixed.piston_pocket_wall_mm``, depth the piston height minus its floor;
    its gas is part of V1: the bore column above the piston shrinks by ``pocket / A1``.

    Parameters
    ----------
    variables : mapping of str to float or array
        The layout's decision variables by name (``piston_diameter_mm``, ``outer_diameter_mm`` in mm,
        ``V1_mm3``, ``V2_mm3`` and the layout's own in mm³) and optionally ``bladder_cast_fill`` (a fraction
        of the stroke, per design; default ``fixed.bladder_cast_fill``).
    p2_MPa : float or array
        Chamber-2 charge, MPa.
    setpoint_x0_mm : float or array
        Displacement of zero force, mm.
    fixed : FixedParameters
        Everything the optimiser does not change (walls' minimums, safety factor, bladder, materials).
    layout : str or LayoutVariant
        The layout variant (a name of :data:`~vvea_design.spring.layouts.LAYOUTS`).
    joint : str
        The joint (:data:`~vvea_design.spring.joints.JOINTS`; ignored under ``sizing_rules = "gas_only"``).
    stresses, masses : bool
        Also the drawn walls' stresses, safety factors and the inner tube's buckling pressure, and the
        masses; the optimiser's search leaves out what its constraints do not read (every other value is
        the same).

    Returns
    -------
    Derived
        Areas (mm²), charges and peak pressures (MPa), sized walls and radii (mm), lengths (mm), volumes
        (mm³), bladder clearances (mm), stresses (MPa) and safety factors (dimensionless), masses (g), the
        parasitic damping (N s/mm) and ``buildable``; arrays broadcast like the inputs.

    Raises
    ------
    DesignError
        If the layout is unknown or a decision variable of it is missing.
    """
    f = fixed
    lay = get_layout(layout)
    v = _variables(variables, lay)
    dp, Do, V1, V2 = (v[name] for name in DECISION_VARIABLES)
    A1 = math.pi / 4 * dp**2
    A2 = math.pi / 4 * (dp**2 - f.rod_diameter_mm**2)
    pr = peak_pressures(A1, A2, V1, V2, p2_MPa, setpoint_x0_mm, f)
    sec, loads = _section(dp, Do, A1, A2, pr, p2_MPa, f, lay, joint)
    stack = _axial_stack(sec, lay.stack(sec, v, f), V1, f)
    fill = v.get("bladder_cast_fill", f.bladder_cast_fill)
    bl = _bladder(sec, stack, V2, fill, f)
    quantities = {**stack.layout.quantities, **lay.rooms(stack, f)}
    buildable_rules = loads is not None
    base_own = sec.base_own_mm if buildable_rules else sec.walls_mm["base"]
    with np.errstate(all="ignore"):
        path = hydraulic_path(A2, sec.piston_radius_mm, sec.inner_tube_outer_radius_mm, bl["bladder_inner_radius_mm"],
                              sec.outer_bore_radius_mm, bl["bladder_outer_radius_mm"], base_own, sec.walls_mm["base"], f)
        d_min = linear_damping_N_s_per_mm(path, 1.0)
        port2 = design_chamber2_port_room_mm(sec.outer_bore_radius_mm, sec.inner_tube_outer_radius_mm,
                                             bl["bladder_inner_radius_mm"], bl["bladder_outer_radius_mm"],
                                             f.joint_seal_cross_section_mm if buildable_rules else GAS_ONLY_SEAL_MM)
    st = safety = buckling = m = checks = None
    if stresses:
        if buildable_rules:
            checks = _buildable_checks(sec, loads, f, lay)
            st, safety, buckling = checks["stresses"], checks["safety"], checks["buckling"]
        else:
            st, safety, buckling = wall_stresses(sec, pr, f, lay)
    if masses:
        if buildable_rules:
            m = part_masses_g(_mass_geometry(sec, stack, bl, quantities, f), f, lay, sec.joint, bl["fluid_volume_mm3"])
        else:
            m = part_masses(sec, stack, bl["bladder_mid_radius_mm"], bl["fluid_volume_mm3"], f, lay)
    rio, rb, L1, L = sec.inner_tube_outer_radius_mm, sec.outer_bore_radius_mm, stack.chamber1_length_mm, \
        stack.bladder_free_length_mm
    # what cannot be drawn at all (Design raises DesignError for these)
    with np.errstate(invalid="ignore"):
        buildable = ((dp > f.rod_diameter_mm) & (rb - rio > f.bladder_thickness_mm + 2 * f.bladder_min_gap_mm)
                     & (L1 > 0) & (V2 > bl["displaced_volume_mm3"]) & (bl["bladder_gas_volume_cast_mm3"] > 0)
                     & (L > 0) & stack.layout.buildable & (bl["V2_annulus_mm3"] > 0) & np.isfinite(pr.p1_MPa))
    P2 = pr.peak_chamber_2_MPa
    cap_value = P2 if loads is None else _capacity_pressure(loads, lay)
    return Derived(
        layout=lay.name, piston_diameter_mm=dp, outer_diameter_mm=Do, V1_mm3=V1, V2_mm3=V2, A1_mm2=A1, A2_mm2=A2,
        p1_MPa=pr.p1_MPa, peak_chamber_1_MPa=pr.p1_MPa * (1 + 0 * P2), peak_chamber_2_MPa=P2,
        chamber_difference_MPa=pr.chamber_difference_MPa, inner_tube_net_pressure_MPa=pr.inner_tube_net_pressure_MPa,
        wall_capacity_value_MPa=cap_value, wall_capacity_limit_MPa=np.full_like(P2, sec.allowable_MPa / 2),
        walls_mm=sec.walls_mm, outer_bore_radius_mm=rb, inner_tube_outer_radius_mm=rio, annulus_gap_mm=rb - rio,
        piston_floor_mm=sec.piston_floor_mm, piston_pocket_radius_mm=sec.piston_pocket_radius_mm,
        piston_pocket_depth_mm=(f.piston_height_mm - sec.piston_floor_mm) * np.ones_like(sec.piston_radius_mm),
        piston_pocket_volume_mm3=sec.piston_pocket_volume_mm3,
        chamber1_length_mm=L1, fluid_column_mm=stack.fluid_column_mm, inner_length_mm=stack.inner_length_mm,
        housing_length_mm=stack.housing_length_mm, bladder_free_length_mm=L, rod_length_mm=stack.rod_length_mm,
        **bl, buildable=buildable, layout_quantities=quantities, inner_tube_cut_mm3=stack.layout.inner_tube_cut_mm3,
        stresses_MPa=st, safety_factors=safety,
        inner_tube_buckling_MPa=buckling, masses_g=m, mass_g=None if m is None else sum(m.values()),
        joint=joint, sizing_rules=f.sizing_rules, load_cases=loads, section=sec,
        check=None if checks is None else checks["check"], governing=None if checks is None else checks["governing"],
        hydraulic_path=path, required_safety_factors=None if checks is None else checks["required"],
        joint_utilisation=None if sec.joint is None else sec.joint.utilisation, parasitic_damping_N_s_per_mm=d_min,
        chamber2_port_room_mm=port2)


def _capacity_pressure(loads, lay: LayoutVariant):
    """The buildability rules' ``wall_capacity`` value: the larger effective pressure of the outer tube and the
    inner tube, times its stress-concentration factor (each carries at most half the allowable stress), MPa."""
    from .concentration import concentration_factor
    from .sizing import _inner_tube_pressure, outer_tube_pressure

    return np.fmax(loads.effective(lambda c: outer_tube_pressure(c, lay)) * concentration_factor("outer_tube"),
                   loads.effective(_inner_tube_pressure) * concentration_factor("inner_tube"))
