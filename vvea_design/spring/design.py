"""The frozen design: four decision variables + fixed parameters -> geometry.

Layout (``docs/layout.md`` has the drawing and the reasoning): the paper's
concentric unit, axis vertical, drawn at x = 0 (spring unloaded).

* The **housing** is an outer tube (outer diameter ``D_o``, wall
  ``t_o``) closed by the **top cap** (top eye, chamber fill ports) and the
  **base** (throttle valve bore with servo mount, relief-valve bore, fluid
  channels, rod seal). The **inner tube** (bore = piston diameter ``d_p``)
  runs concentrically from base to top cap.
* The **working piston** slides in the inner tube; its **rod** (diameter
  ``d_r``) leaves through the base and carries the bottom eye. Pulling the
  eyes apart (x > 0) draws the piston down, towards the base.
* **Chamber 1** (the paper's inner, negative chamber) is the gas in the inner
  tube above the piston: it grows by ``A1 x``, ``A1 = pi/4 d_p^2``.
* Below the piston the inner tube is full of **hydraulic fluid**. The piston
  pushes ``A2 x`` of it, ``A2 = pi/4 (d_p^2 - d_r^2)`` (the rod crosses the
  fluid), through the throttle in the base and the channels of the
  **support ring** into the **bladder**, a silicone sleeve clamped at both
  ends in the annulus between inner and outer tube.
* **Chamber 2** (the outer, positive chamber) is the gas in that annulus
  outside the bladder: it shrinks by ``A2 x``.

So the piston diameter sets both areas, ``V1`` sets the inner-tube (and so
the housing) length — "the travel and the length V1 needs add up to the
length of the outer chamber" (paper section 3.2) — and the outer diameter
sets how much gas the annulus can hold. ``V2`` must fit in it: the bladder is
cast at the radius that leaves exactly ``V2`` of gas (with the fluid it holds
at x = 0), and the constraints check that it has room to move at both ends
of the stroke. All lengths in mm, volumes mm³, pressures MPa.
"""

from __future__ import annotations

import math
from dataclasses import asdict, dataclass, field, fields, replace
from functools import cached_property

import numpy as np

from .gas_spring import GasSpring, setpoint_p1_MPa
from ..messages import show
from ..materials.structural import (
    DENSITY_HYDRAULIC_OIL_g_per_mm3,
    DENSITY_SILICONE_g_per_mm3,
    get_material,
)

__all__ = ["FixedParameters", "Design", "DesignError", "DECISION_VARIABLES", "LayoutVariant", "LAYOUTS",
           "get_layout", "derive", "piston_floor_moment", "WALLS", "CHANNEL_GAP_MM"]

#: The decision variables of today's layout (``inner_tube``), in order, with their units in the name.
DECISION_VARIABLES = ("piston_diameter_mm", "outer_diameter_mm", "V1_mm3", "V2_mm3")


@dataclass(frozen=True)
class LayoutVariant:
    """A named geometry of the unit: where each gas volume goes (``docs/layout.md`` draws each)."""

    name: str
    summary: str
    decision_variables: tuple[str, ...]
    has_bulkhead: bool  #: a bulkhead closes chamber 1; the inner-tube space above it is chamber-2 gas
    has_top_annulus: bool = False  #: chamber-1 gas also fills the annulus above a collar (the top bladder clamp)

    @property
    def walls(self) -> tuple[str, ...]:
        """The pressure walls :func:`derive` sizes in this layout (names of :data:`WALLS`)."""
        return WALLS[:4] + (("bulkhead",) if self.has_bulkhead else ()) + (("collar",) if self.has_top_annulus else ())


#: The layouts the optimiser chooses between.
LAYOUTS: dict[str, LayoutVariant] = {
    "inner_tube": LayoutVariant(
        "inner_tube",
        "chamber 1 fills the inner tube from the piston to the top cap; V1 sets the housing length",
        DECISION_VARIABLES, False),
    "bulkhead": LayoutVariant(
        "bulkhead",
        "a bulkhead closes chamber 1 inside the inner tube; the inner-tube space above it (V2_top) is "
        "chamber-2 gas, ported to the annulus through the top cap, so the housing length is free of V1",
        DECISION_VARIABLES + ("V2_top_mm3",), True),
    "annulus_top": LayoutVariant(
        "annulus_top",
        "chamber 1 fills the inner tube from the piston to the top cap and, through cross slots below the top cap, "
        "the annulus above a collar on the inner tube (V1_annulus); the collar is the top bladder clamp and the "
        "pressure wall between the chambers, chamber 2 is charged through the base",
        DECISION_VARIABLES + ("V1_annulus_mm3",), False, True),
}


def get_layout(name: str) -> LayoutVariant:
    """The layout variant called ``name``.

    Parameters
    ----------
    name : str
        A key of :data:`LAYOUTS` (``"inner_tube"``, ``"bulkhead"`` or ``"annulus_top"``).

    Returns
    -------
    LayoutVariant
        Its name, summary, decision variables and whether it has a bulkhead.

    Raises
    ------
    DesignError
        For an unknown name (the message lists the known ones).
    """
    try:
        return LAYOUTS[name]
    except (KeyError, TypeError):
        raise DesignError(f"unknown layout {name!r}; known: {', '.join(LAYOUTS)}") from None

#: Radial room the cast bladder must leave to the inner tube for the support ring's fluid channels, mm: the CAD
#: draws them (>= 0.5 mm) beside the cuff's sealing bead when the gap is >= 10/9 mm (``cad.layout``); with a margin.
CHANNEL_GAP_MM = 1.15

#: Pressure walls sized by :func:`derive` (the bulkhead only in the ``bulkhead`` layout, the collar only in
#: ``annulus_top``, the piston's pocket floor only with ``fixed.piston_pocket``; :attr:`LayoutVariant.walls`
#: lists a layout's, :meth:`Design.walls_mm` a design's).
WALLS = ("outer_tube", "inner_tube", "top_cap", "base", "bulkhead", "collar", "piston_floor")

#: Old names of the wall fields (design files written before the walls were sized): now the minimums.
_LEGACY_FIXED = {"outer_wall_mm": "min_outer_wall_mm", "inner_tube_wall_mm": "min_inner_tube_wall_mm",
                 "top_cap_mm": "min_top_cap_mm", "base_mm": "min_base_mm"}

_NONNEGATIVE = {"dead_volume_1_mm3", "dead_volume_2_mm3", "servo_and_valve_mass_g", "bladder_min_gap_mm"}


class DesignError(ValueError):
    """A design that cannot be built (names the field and what is wrong)."""


@dataclass(frozen=True)
class FixedParameters:
    """Parameters the optimiser does not change (mm, mm³, g)."""

    travel_mm: float = 40.0  #: stroke, x from 0 to travel
    rod_diameter_mm: float = 8.0  #: piston rod (crosses the fluid, leaves through the base)
    min_outer_wall_mm: float = 1.5  #: thinnest outer tube wall made (sized up for chamber-2 pressure)
    min_inner_tube_wall_mm: float = 1.5  #: thinnest inner tube wall made (sized up for external chamber-2 pressure)
    min_top_cap_mm: float = 8.0  #: thinnest top end cap (fill ports, top eye)
    min_base_mm: float = 14.0  #: thinnest base (valve bores, channels, rod seal)
    min_bulkhead_mm: float = 4.0  #: thinnest bulkhead web (``bulkhead`` layout: a web left when boring the inner tube)
    fill_tube_outer_mm: float = 4.0  #: chamber-1 fill tube through the upper chamber-2 space (``bulkhead`` layout)
    fill_tube_bore_mm: float = 1.5  #: its bore (counted in V1)
    #: thinnest collar plate above the top bladder clamp (``annulus_top`` layout): it holds the static O-ring
    #: groove to the outer bore (1.78 mm series: 2.41 mm wide, 0.75 mm lands; the CAD checks it)
    min_collar_mm: float = 4.0
    cross_slot_mm: float = 2.0  #: axial height of the slots in the inner tube's top end joining the chamber-1 annulus to the bore (``annulus_top``)
    cross_slot_fraction: float = 1 / 3  #: share of the inner tube's circumference the slots take (their gas is in V1)
    wall_safety_factor: float = 2.0  #: walls are sized to this safety factor on yield (the requirements set it)
    wall_sizing_n: float = 1.4  #: walls carry the peak pressure of this polytropic exponent (1.4: a fast, adiabatic stroke)
    piston_height_mm: float = 10.0  #: working piston incl. seal grooves
    piston_pocket: bool = False  #: a coaxial pocket bored into the piston crown holds chamber-1 gas (a cupped piston)
    piston_pocket_wall_mm: float = 3.0  #: radial wall from the piston's sliding diameter to the pocket (seal groove depth + the wall under its root)
    min_piston_floor_mm: float = 3.0  #: thinnest pocket floor made (sized up: a plate carrying the chamber-1 / fluid differential to the rod)
    fluid_clearance_mm: float = 2.0  #: fluid column left under the piston at full stroke
    bladder_thickness_mm: float = 1.5  #: silicone sleeve wall as cast
    bladder_clamp_mm: float = 5.0  #: axial length of each clamped end (support ring / top clamp)
    bladder_cast_fill: float = 0.5  #: stroke fraction at which the bladder has its cast shape
    bladder_min_gap_mm: float = 0.5  #: radial clearance the bladder keeps at both stroke ends
    bladder_bulge_factor: float = 1.5  #: peak / mean radial shift between the clamps (1.5 = parabolic, as the FE check finds)
    dead_volume_1_mm3: float = 0.0  #: chamber-1 gas outside the inner-tube column (ports)
    dead_volume_2_mm3: float = 0.0  #: chamber-2 gas outside the bladder annulus (ports)
    housing_material: str = "al-6061-t6"
    rod_material: str = "steel-42crmo4"
    support_ring_material: str = "pa12-sls"
    servo_and_valve_mass_g: float = 40.0  #: servo (BMS-390DMH class), valve core, fittings
    n_polytropic: float = 1.0  #: 1 isothermal (paper) ... 1.4 adiabatic

    def __post_init__(self) -> None:
        for f in fields(self):
            v = getattr(self, f.name)
            if f.type in ("bool", bool) and not isinstance(v, bool):
                raise DesignError(f"fixed.{f.name} must be true or false, got {show(v)}")
            if f.type in ("float", float):
                if isinstance(v, bool) or not isinstance(v, (int, float)) or not math.isfinite(v):
                    raise DesignError(f"fixed.{f.name} must be a finite number, got {show(v)}")
                if f.name in _NONNEGATIVE:
                    if v < 0:
                        raise DesignError(f"fixed.{f.name} must be >= 0, got {show(v)}")
                elif v <= 0 and f.name != "bladder_cast_fill":
                    raise DesignError(f"fixed.{f.name} must be > 0, got {show(v)}")
        if not 0.0 <= self.bladder_cast_fill <= 1.0:
            raise DesignError(f"fixed.bladder_cast_fill must be in [0, 1], got {show(self.bladder_cast_fill)}")
        if not 1.0 <= self.n_polytropic <= 1.4:
            raise DesignError(f"fixed.n_polytropic must be in [1, 1.4], got {show(self.n_polytropic)}")
        if not 1.0 <= self.wall_sizing_n <= 1.67:
            raise DesignError(f"fixed.wall_sizing_n must be in [1, 1.67], got {show(self.wall_sizing_n)}")
        if not self.cross_slot_fraction < 1.0:
            raise DesignError(f"fixed.cross_slot_fraction must be in (0, 1), got {show(self.cross_slot_fraction)}")
        if self.fill_tube_bore_mm >= self.fill_tube_outer_mm:
            raise DesignError("fixed.fill_tube_bore_mm must be smaller than fixed.fill_tube_outer_mm")
        for key in ("housing_material", "rod_material", "support_ring_material"):
            try:
                get_material(getattr(self, key))
            except ValueError as exc:
                raise DesignError(f"fixed.{key}: {exc}") from None

    def to_dict(self) -> dict:
        """JSON-ready content.

        Returns
        -------
        dict
            Every field by name (lengths mm, volumes mm³, masses g, fractions, material keys).
        """
        return asdict(self)

    @classmethod
    def from_dict(cls, data, **override) -> "FixedParameters":
        """Build from a mapping (a TOML table or the design JSON's ``fixed``); unknown keys are an error.

        Parameters
        ----------
        data : dict
            Field name -> value (mm, mm³, g, fractions, material keys); the old wall names
            (``outer_wall_mm`` ...) are read as the minimums.
        **override
            Fields that replace those of ``data``.

        Returns
        -------
        FixedParameters
            The validated parameters.

        Raises
        ------
        DesignError
            If ``data`` is not a mapping, names an unknown field or holds a bad value.
        """
        if not isinstance(data, dict):
            raise DesignError(f"fixed parameters must be a table/object, got {type(data).__name__}")
        # files written before the walls were sized: their fixed walls become the minimums
        data = {_LEGACY_FIXED.get(k, k): v for k, v in data.items()}
        known = {f.name for f in fields(cls)}
        bad = set(data) - known
        if bad:
            raise DesignError(f"unknown fixed parameter(s) {sorted(bad)}; known: {sorted(known)}")
        try:
            return cls(**{**data, **override})
        except TypeError as exc:  # pragma: no cover - guarded by the key check
            raise DesignError(str(exc)) from None


# ---------------------------------------------------------------------------
# One set of formulas for one design and for a whole population (numpy broadcast)
# ---------------------------------------------------------------------------

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


def derive(piston_diameter_mm, outer_diameter_mm, V1_mm3, V2_mm3, V2_top_mm3, p2_MPa, setpoint_x0_mm,
           fixed: FixedParameters, bulkhead: bool, cast_fill=None, V1_annulus_mm3=0.0,
           top_annulus: bool = False, stresses: bool = True, masses: bool = True) -> dict[str, np.ndarray]:
    """Every derived quantity of a design, from its decision variables (arrays broadcast).

    The single source of the geometry, strength and mass formulas: :class:`Design`
    reads its properties from it, and the optimiser evaluates a whole population
    with it in one call. Units: mm, mm², mm³, MPa, g.

    Walls are **sized**: each wall is the thinnest that carries its peak
    pressure with ``fixed.wall_safety_factor`` on yield, but never thinner than
    its manufacturable minimum (``fixed.min_*``). Peak pressures are those of a
    stroke with ``max(n_polytropic, fixed.wall_sizing_n)`` (adiabatic by
    default: a fast stroke compresses chamber 2 harder). Outer tube: Lamé,
    internal pressure; inner tube: Lamé, external pressure, and elastic
    buckling of a long tube under the net pressure (chamber 2 outside,
    chamber 1 at its lowest inside); end caps and the
    bulkhead: simply supported circular plates. When no wall can carry the
    pressure the minimum is drawn and ``wall_capacity`` (value/limit) says so.

    In the ``annulus_top`` layout (``top_annulus``) the top bladder clamp is a
    collar on the inner tube: ``V1_annulus_mm3`` of chamber-1 gas fills the
    annulus between the tubes above it (length ``V1_annulus / (pi (rb^2 -
    rio^2))``), the collar is a plate ``clamp + t`` long, ``t`` sized as a
    ring cantilevered from the inner tube (its seal on the outer bore carries
    no axial load) under the largest chamber-2 minus chamber-1 pressure:
    root moment per unit circumference ``M = p/rio ((rb^3 - rio^3)/3 -
    rio (rb^2 - rio^2)/2)``, ``sigma = 6 M / t^2`` (the hoop stiffening of the
    ring is neglected: conservative). The bladder's free length loses
    ``t + L_annulus``.

    With ``fixed.piston_pocket`` (every layout) chamber-1 gas also fills a
    coaxial pocket bored into the piston crown, radius ``dp/2 -
    fixed.piston_pocket_wall_mm`` (inside the seal grooves), depth the piston
    height minus its floor; the floor is an annular plate from the rod to the
    pocket's wall carrying the same largest chamber-2 (fluid) minus chamber-1
    pressure to the rod, sized for bending at the rod
    (:func:`piston_floor_moment`) and for Tresca on the peak root shear
    ``1.5 Q/t``, ``Q = p (rp^2 - b^2)/(2 b)``, never thinner than
    ``fixed.min_piston_floor_mm`` (the pocket is absent where its radius would
    not exceed the rod's). The piston and its rod are one turned part of
    ``fixed.rod_material`` (as the CAD draws it): the floor's allowable stress
    and, with a pocket, the piston's mass are that material's. The fluid under
    the piston is taken at chamber-2 pressure (the throttle's pressure drop is
    not modelled, as for the base). The pocket's gas is part of V1: the bore
    column above the piston shrinks by ``pocket / A1``.

    Parameters
    ----------
    piston_diameter_mm, outer_diameter_mm : float or array
        Piston (= inner-tube bore) and outer diameter, mm.
    V1_mm3, V2_mm3, V2_top_mm3 : float or array
        Chamber gas volumes at x = 0 and the chamber-2 gas above the bulkhead, mm³.
    p2_MPa : float or array
        Chamber-2 charge, MPa.
    setpoint_x0_mm : float or array
        Displacement of zero force, mm.
    fixed : FixedParameters
        Everything the optimiser does not change (walls' minimums, safety factor, bladder, materials).
    bulkhead : bool
        The ``bulkhead`` layout (else ``inner_tube`` or ``annulus_top``).
    cast_fill : float or array, optional
        Stroke fraction at which the bladder has its cast shape, per design
        (when the optimiser varies it); default ``fixed.bladder_cast_fill``.
    V1_annulus_mm3 : float or array
        Chamber-1 gas in the annulus above the collar, mm³ (``annulus_top`` only; part of ``V1_mm3``).
    top_annulus : bool
        The ``annulus_top`` layout.
    stresses, masses : bool
        Also the drawn walls' stresses, safety factors and the inner tube's buckling pressure
        (``stress_*``, ``safety_*``, ``inner_tube_*``), and the masses (``mass_*``); the optimiser's
        search leaves out what its constraints do not read (every other value is the same).

    Returns
    -------
    dict of str to ndarray
        Areas (mm²), charges and peak pressures (MPa), sized walls and radii (mm),
        lengths (mm), volumes (mm³), bladder clearances (mm), stresses (MPa) and
        safety factors (dimensionless), masses (g, ``mass_*_g``), and the boolean
        ``buildable``; arrays broadcast like the inputs.
    """
    f = fixed
    pi = math.pi
    dp = np.asarray(piston_diameter_mm, dtype=float)
    Do = np.asarray(outer_diameter_mm, dtype=float)
    V1 = np.asarray(V1_mm3, dtype=float)
    V2 = np.asarray(V2_mm3, dtype=float)
    Vt = np.asarray(V2_top_mm3, dtype=float) if bulkhead else np.zeros_like(V2)
    Va = np.asarray(V1_annulus_mm3, dtype=float) if top_annulus else np.zeros_like(V1)
    p2 = np.asarray(p2_MPa, dtype=float)
    x0 = np.asarray(setpoint_x0_mm, dtype=float)
    T, n = f.travel_mm, f.n_polytropic
    mat = get_material(f.housing_material)
    g: dict[str, np.ndarray] = {}
    A1 = pi / 4 * dp**2
    A2 = pi / 4 * (dp**2 - f.rod_diameter_mm**2)
    g["A1_mm2"], g["A2_mm2"] = A1, A2
    with np.errstate(divide="ignore", invalid="ignore"):
        v2x0 = np.where(V2 - A2 * x0 > 0, V2 - A2 * x0, np.nan)
        p1 = (A2 / A1) * p2 * (V2 / v2x0) ** n * ((V1 + A1 * x0) / V1) ** n
        g["p1_MPa"] = p1
        nw = max(n, f.wall_sizing_n)
        v2T = np.where(V2 - A2 * T > 0, V2 - A2 * T, np.nan)
        P2_peak = p2 * (V2 / v2T) ** nw
        P1_min = p1 * (V1 / (V1 + A1 * T)) ** nw
        dP_bulkhead = np.maximum(np.maximum(P2_peak - P1_min, p1 - p2), 0.0)
        g["peak_chamber_1_MPa"], g["peak_chamber_2_MPa"] = p1 * (1 + 0 * P2_peak), P2_peak
        g["bulkhead_pressure_MPa"] = dP_bulkhead if bulkhead else np.zeros_like(P2_peak)
        sa = mat.yield_MPa / f.wall_safety_factor  # allowable stress
        kp = 3 * (3 + mat.poisson) / 8  # plate: sigma = kp p a^2 / t^2
        ro, ri = Do / 2, dp / 2
        # walls: required thickness (nan where no wall can carry the pressure), then the minimums
        t_o_req = ro - ro * np.sqrt((sa - P2_peak) / (sa + P2_peak))
        t_i_req = ri * (np.sqrt(sa / (sa - 2 * P2_peak)) - 1)
        # the inner tube must also not buckle under the net external pressure: chamber 2 outside, chamber 1
        # (at its lowest, full stroke) inside; long-tube elastic buckling p_cr = E/(4(1-nu^2)) (t/r_mean)^3
        dP_net = np.maximum(P2_peak - P1_min, 0.0)
        kb = mat.youngs_modulus_MPa / (4 * (1 - mat.poisson**2))
        cb = np.cbrt(f.wall_safety_factor * dP_net / kb)
        t_i_req = np.fmax(t_i_req, ri * cb / (1 - cb / 2))
        g["wall_capacity_value_MPa"] = P2_peak
        g["wall_capacity_limit_MPa"] = np.full_like(P2_peak, sa / 2)  # external pressure on the inner tube: p < sa/2
        t_o = np.fmax(f.min_outer_wall_mm, np.where(P2_peak < sa, t_o_req, np.nan))
        t_i = np.fmax(f.min_inner_tube_wall_mm, np.where(2 * P2_peak < sa, t_i_req, np.nan))
        rb = ro - t_o
        t_cap = np.fmax(f.min_top_cap_mm, np.sqrt(kp * P2_peak * rb**2 / sa))
        t_base = np.fmax(f.min_base_mm, np.sqrt(kp * P2_peak * rb**2 / sa))
        t_bh = np.fmax(f.min_bulkhead_mm, np.sqrt(kp * dP_bulkhead * ri**2 / sa)) if bulkhead else np.zeros_like(rb)
        rio = ri + t_i
        # collar (annulus_top): a ring cantilevered from the inner tube, root moment per unit circumference
        m_collar = dP_bulkhead / rio * ((rb**3 - rio**3) / 3 - rio * (rb**2 - rio**2) / 2)
        t_col = np.fmax(f.min_collar_mm, np.sqrt(6 * m_collar / sa)) if top_annulus else np.zeros_like(rb)
        g["collar_pressure_MPa"] = dP_bulkhead if top_annulus else np.zeros_like(P2_peak)
        # piston pocket (fixed.piston_pocket): its floor carries the same differential to the rod; the piston and
        # its rod are one turned part of fixed.rod_material (as the CAD draws it and the bill of materials lists it)
        pocket = f.piston_pocket
        mat_p = get_material(f.rod_material)
        sa_p = mat_p.yield_MPa / f.wall_safety_factor
        b_rod = f.rod_diameter_mm / 2
        r_pk = ri - f.piston_pocket_wall_mm
        has_pk = (r_pk > b_rod) if pocket else np.zeros_like(ri, dtype=bool)
        r_pk_s = np.where(has_pk, r_pk, 2 * b_rod)  # a harmless radius where there is no pocket
        k_floor = piston_floor_moment(ri, r_pk_s, b_rod, mat_p.poisson)
        q_floor = ri**2 - b_rod**2  # root shear per unit pressure x 2 b_rod
        t_fl_req = np.fmax(np.sqrt(6 * k_floor * dP_bulkhead / sa_p), 3 * dP_bulkhead * q_floor / (2 * b_rod * sa_p))
        t_fl = np.where(has_pk, np.fmin(np.fmax(f.min_piston_floor_mm, t_fl_req), f.piston_height_mm),
                        f.piston_height_mm)
        V_pk = np.where(has_pk, pi * r_pk_s**2 * (f.piston_height_mm - t_fl), 0.0)
        g["piston_floor_pressure_MPa"] = dP_bulkhead if pocket else np.zeros_like(P2_peak)
    g["outer_wall_mm"], g["inner_tube_wall_mm"] = t_o, t_i
    g["top_cap_mm"], g["base_mm"], g["bulkhead_mm"] = t_cap, t_base, t_bh
    g["collar_mm"] = t_col
    g["piston_floor_mm"] = t_fl * np.ones_like(ri)
    g["piston_pocket_radius_mm"] = np.where(has_pk, r_pk_s, 0.0) * np.ones_like(ri)
    g["piston_pocket_depth_mm"] = (f.piston_height_mm - t_fl) * np.ones_like(ri)
    g["piston_pocket_volume_mm3"] = V_pk * np.ones_like(ri)
    g["outer_bore_radius_mm"], g["inner_tube_outer_radius_mm"] = rb, rio
    g["annulus_gap_mm"] = rb - rio
    # axial stack
    a_fo = pi / 4 * f.fill_tube_outer_mm**2 if bulkhead else 0.0
    a_fb = pi / 4 * f.fill_tube_bore_mm**2 if bulkhead else 0.0
    L_top = Vt / (A1 - a_fo) if bulkhead else np.zeros_like(V1)
    g["top_space_length_mm"] = L_top
    g["fill_tube_volume_mm3"] = a_fb * (t_bh + L_top) if bulkhead else np.zeros_like(V1)
    A_ann = pi * (rb**2 - rio**2)
    with np.errstate(divide="ignore", invalid="ignore"):
        L_a = Va / A_ann if top_annulus else np.zeros_like(V1)
    g["top_annulus_length_mm"] = L_a
    g["V1_annulus_mm3"] = Va * np.ones_like(L_a)
    # the slots through the inner tube's top end (annulus_top) hold chamber-1 gas too
    v_slots = f.cross_slot_fraction * pi * (rio**2 - ri**2) * f.cross_slot_mm if top_annulus else np.zeros_like(V1)
    g["cross_slot_volume_mm3"] = v_slots * np.ones_like(L_a)
    L1 = (V1 - f.dead_volume_1_mm3 - g["fill_tube_volume_mm3"] - Va - v_slots - V_pk) / A1
    g["chamber1_length_mm"] = L1
    fluid_col = f.travel_mm + f.fluid_clearance_mm
    g["fluid_column_mm"] = np.full_like(L1, fluid_col)
    L_in = L1 + f.piston_height_mm + fluid_col + t_bh + L_top
    g["inner_length_mm"] = L_in
    g["housing_length_mm"] = t_cap + L_in + t_base
    L = L_in - 2 * f.bladder_clamp_mm - t_col - L_a
    g["bladder_free_length_mm"] = L
    g["rod_length_mm"] = np.full_like(L1, fluid_col) + t_base + f.travel_mm + 10.0
    # chamber 2 around the bladder
    disp = A2 * T
    g["displaced_volume_mm3"] = disp
    fill = f.bladder_cast_fill if cast_fill is None else np.asarray(cast_fill, dtype=float)
    g["bladder_cast_fill_fraction"] = fill * np.ones_like(L)
    V2_ann = V2 - f.dead_volume_2_mm3 - Vt
    g["V2_annulus_mm3"] = V2_ann
    cast_gas = V2_ann - disp * fill
    g["bladder_gas_volume_cast_mm3"] = cast_gas
    Ls = np.where(L > 0, L, np.nan)
    with np.errstate(divide="ignore", invalid="ignore"):
        g["annulus_volume_mm3"] = pi * (rb**2 - rio**2) * L
        a = rio + f.bladder_min_gap_mm
        c = f.bladder_bulge_factor * disp * fill / (2 * pi * Ls)
        r_bi_cap = 0.5 * (a + np.sqrt(a * a + 4 * c))
        r_bo_cap = r_bi_cap + f.bladder_thickness_mm
        gas_cap = pi * np.maximum(rb**2 - r_bo_cap**2, 0.0) * L
        g["V2_capacity_mm3"] = gas_cap + disp * fill + f.dead_volume_2_mm3 + Vt
        r_bo = np.sqrt(np.maximum(rb**2 - cast_gas / (pi * Ls), 1e-9))
        r_bi = r_bo - f.bladder_thickness_mm
        g["bladder_outer_radius_mm"], g["bladder_inner_radius_mm"] = r_bo, r_bi
        g["bladder_mid_radius_mm"] = r_bo - f.bladder_thickness_mm / 2
        dv_c, dv_e = -disp * fill, disp * (1.0 - fill)
        s_c = dv_c / (2 * pi * np.maximum(r_bi, 1e-9) * Ls)
        s_e = dv_e / (2 * pi * r_bo * Ls)
        k, gap = f.bladder_bulge_factor, f.bladder_min_gap_mm
        g["bladder_shift_compressed_mm"], g["bladder_shift_expanded_mm"] = s_c, s_e
        g["bladder_clearance_compressed_mm"] = r_bi + k * s_c - rio - gap
        g["bladder_clearance_expanded_mm"] = rb - (r_bo + k * s_e) - gap
        g["bladder_cast_gap_mm"] = r_bi - rio  # room inside the cast bladder (support-ring channels)
        fluid_cast = pi * np.maximum(r_bi**2 - rio**2, 0.0) * L
        g["bladder_fluid_volume_cast_mm3"] = fluid_cast
        g["fluid_volume_mm3"] = A2 * fluid_col + fluid_cast + dv_c
    if stresses:
        _stresses(g, P2_peak, ro, rb, rio, ri, t_cap, t_base, t_bh, t_col, t_fl, t_i, kp, dP_bulkhead, dP_net,
                  m_collar, k_floor, q_floor, b_rod, has_pk, kb, mat, mat_p, bulkhead, top_annulus, pocket)
    if masses:
        _masses(g, f, mat, ro, rb, rio, ri, t_cap, t_base, t_bh, t_col, L_in, L_top, L, a_fo, a_fb, v_slots, V_pk,
                A_ann, pocket)
    # what cannot be drawn at all (Design raises DesignError for these)
    g["buildable"] = ((dp > f.rod_diameter_mm) & (g["annulus_gap_mm"] > f.bladder_thickness_mm + 2 * f.bladder_min_gap_mm)
                      & (L1 > 0) & (V2 > disp) & (cast_gas > 0) & (L > 0) & (Vt >= 0) & (V2_ann > 0)
                      & (Va >= 0) & np.isfinite(p1))
    # annulus_top: the cross slots below the top cap need room in the annulus and above the piston at x = 0
    g["cross_slot_room_mm"] = (np.fmin(L_a, L1) - (f.cross_slot_mm + 1.0)) if top_annulus else np.full_like(L1, np.inf)
    return g


def _stresses(g, P2_peak, ro, rb, rio, ri, t_cap, t_base, t_bh, t_col, t_fl, t_i, kp, dP_bulkhead, dP_net,
              m_collar, k_floor, q_floor, b_rod, has_pk, kb, mat, mat_p, bulkhead, top_annulus, pocket) -> None:
    """Stresses and safety factors of the drawn walls, the inner tube's buckling pressure (into ``g``)."""
    with np.errstate(divide="ignore", invalid="ignore"):
        # stresses of the drawn walls (their safety factors are reported)
        st = {
            "outer_tube": P2_peak * (ro**2 + rb**2) / (ro**2 - rb**2),
            "inner_tube": 2 * P2_peak * rio**2 / (rio**2 - ri**2),
            "top_cap": kp * P2_peak * rb**2 / t_cap**2,
            "base": kp * P2_peak * rb**2 / t_base**2,
        }
        if bulkhead:
            st["bulkhead"] = kp * dP_bulkhead * ri**2 / t_bh**2
        if top_annulus:
            st["collar"] = 6 * m_collar / t_col**2
        if pocket:  # bending at the rod (6 M / t^2) or, if larger, Tresca's 2 x the peak root shear 1.5 Q / t
            st["piston_floor"] = np.where(has_pk, np.fmax(6 * k_floor * dP_bulkhead / t_fl**2,
                                                          3 * dP_bulkhead * q_floor / (2 * b_rod * t_fl)), 0.0)
        for w, v in st.items():
            g[f"stress_{w}_MPa"] = v
            g[f"safety_{w}"] = np.where(v > 0, (mat_p if w == "piston_floor" else mat).yield_MPa / v, np.inf)
        p_cr = kb * (t_i / (ri + t_i / 2)) ** 3
        g["inner_tube_buckling_MPa"] = p_cr
        g["inner_tube_net_pressure_MPa"] = dP_net
        g["safety_inner_tube"] = np.fmin(g["safety_inner_tube"], np.where(dP_net > 0, p_cr / dP_net, np.inf))


def _masses(g, f, mat, ro, rb, rio, ri, t_cap, t_base, t_bh, t_col, L_in, L_top, L, a_fo, a_fb, v_slots, V_pk,
            A_ann, pocket) -> None:
    """The parts' masses and their sum, g (into ``g``)."""
    pi = math.pi
    L1 = g["chamber1_length_mm"]
    rho_h = mat.density_g_per_mm3
    rho_r = get_material(f.rod_material).density_g_per_mm3
    rho_s = get_material(f.support_ring_material).density_g_per_mm3
    m = {
        "outer_tube": pi * (ro**2 - rb**2) * L_in * rho_h,
        "end_caps": pi * ro**2 * (t_cap + t_base) * rho_h,
        "inner_tube": (pi * (rio**2 - ri**2) * L_in - v_slots) * rho_h,
        "bulkhead": (pi * ri**2 * t_bh + (a_fo - a_fb) * L_top) * rho_h,
        "collar": A_ann * t_col * rho_h,  # the plate above the top clamp (the clamp itself is counted nowhere, as before)
        # the piston with a pocket in its material (fixed.rod_material); without one as before (the housing's
        # density: the published masses are unchanged; docs/layout.md)
        "piston": (pi * ri**2 * f.piston_height_mm - V_pk) * (rho_r if pocket else rho_h),
        "rod": pi / 4 * f.rod_diameter_mm**2 * g["rod_length_mm"] * rho_r,
        "bladder": 2 * pi * g["bladder_mid_radius_mm"] * f.bladder_thickness_mm * (L + 2 * f.bladder_clamp_mm)
        * DENSITY_SILICONE_g_per_mm3,
        "support_ring": pi * (rb**2 - rio**2) * f.bladder_clamp_mm * 0.5 * rho_s,
        "fluid": np.maximum(g["fluid_volume_mm3"], 0.0) * DENSITY_HYDRAULIC_OIL_g_per_mm3,
        "servo_and_valve": np.full_like(L1, f.servo_and_valve_mass_g),
    }
    for k_, v in m.items():
        g[f"mass_{k_}_g"] = v
    g["mass_g"] = sum(m.values())


@dataclass(frozen=True)
class Design:
    """One unit: its layout, decision variables, charge and fixed parameters.

    Derived geometry is exposed as properties (mm, mm², mm³), all computed by
    :func:`derive`; everything the CAD, the bladder check and the actuator
    study need is here.

    Raises
    ------
    DesignError
        For a design that cannot be drawn at all (non-positive sizes, a rod
        thicker than the piston, no annulus left for the bladder, a chamber
        that bottoms out). Designs that can be drawn but violate a
        requirement are reported by :func:`vvea_design.spring.requirements.constraint_margins`.
    """

    piston_diameter_mm: float  #: working piston = inner-tube bore
    outer_diameter_mm: float  #: outer tube outer diameter (the envelope)
    V1_mm3: float  #: chamber-1 gas volume at x = 0
    V2_mm3: float  #: chamber-2 gas volume at x = 0 (annulus + V2_top_mm3 + dead volume)
    p2_MPa: float = 4.0  #: charge of chamber 2 (p1 follows from the setpoint)
    setpoint_x0_mm: float = 0.0  #: displacement of zero force (paper eq. 6)
    fixed: FixedParameters = field(default_factory=FixedParameters)
    layout: str = "inner_tube"  #: a key of :data:`LAYOUTS`
    V2_top_mm3: float = 0.0  #: chamber-2 gas above the bulkhead (``bulkhead`` layout only)
    V1_annulus_mm3: float = 0.0  #: chamber-1 gas in the annulus above the collar (``annulus_top`` only; part of V1)

    def __post_init__(self) -> None:
        f = self.fixed
        lay = get_layout(self.layout)
        for name in DECISION_VARIABLES:
            v = getattr(self, name)
            if isinstance(v, bool) or not isinstance(v, (int, float)) or not math.isfinite(v) or v <= 0:
                raise DesignError(f"{name} must be a positive number, got {show(v)}")
        v = self.V2_top_mm3
        if isinstance(v, bool) or not isinstance(v, (int, float)) or not math.isfinite(v) or v < 0:
            raise DesignError(f"V2_top_mm3 must be a number >= 0, got {show(v)}")
        if not lay.has_bulkhead and v != 0:
            raise DesignError(f"V2_top_mm3 = {v:g}: only the 'bulkhead' layout has chamber-2 gas above chamber 1 "
                              f"(this design's layout is {self.layout!r})")
        v = self.V1_annulus_mm3
        if isinstance(v, bool) or not isinstance(v, (int, float)) or not math.isfinite(v) or v < 0:
            raise DesignError(f"V1_annulus_mm3 must be a number >= 0, got {show(v)}")
        if not lay.has_top_annulus and v != 0:
            raise DesignError(f"V1_annulus_mm3 = {v:g}: only the 'annulus_top' layout has chamber-1 gas in the annulus "
                              f"(this design's layout is {self.layout!r})")
        if not isinstance(self.p2_MPa, (int, float)) or not math.isfinite(self.p2_MPa) or self.p2_MPa <= 0:
            raise DesignError(f"p2_MPa must be > 0, got {show(self.p2_MPa)}")
        if not isinstance(self.setpoint_x0_mm, (int, float)) or not math.isfinite(self.setpoint_x0_mm):
            raise DesignError(f"setpoint_x0_mm must be a finite number, got {show(self.setpoint_x0_mm)}")
        if self.piston_diameter_mm <= f.rod_diameter_mm:
            raise DesignError(
                f"piston_diameter_mm ({self.piston_diameter_mm:g}) must exceed the rod diameter "
                f"(fixed.rod_diameter_mm = {f.rod_diameter_mm:g})"
            )
        need = f.bladder_thickness_mm + 2 * f.bladder_min_gap_mm
        if not self.annulus_gap_mm > need:
            raise DesignError(
                f"no room for the bladder: the annulus between inner tube (outer radius "
                f"{self.inner_tube_outer_radius_mm:.2f} mm) and outer tube bore (radius "
                f"{self.outer_bore_radius_mm:.2f} mm) is {self.annulus_gap_mm:.2f} mm wide, needs more than "
                f"{need:.2f} mm; reduce piston_diameter_mm or increase outer_diameter_mm"
            )
        if not self.chamber1_length_mm > 0:
            raise DesignError(f"V1_mm3 ({self.V1_mm3:g}) must exceed fixed.dead_volume_1_mm3 ({f.dead_volume_1_mm3:g})"
                              + (" plus the fill tube's bore" if lay.has_bulkhead else "")
                              + (f" plus the piston pocket ({self.piston_pocket_volume_mm3:.0f} mm³)" if f.piston_pocket else "")
                              + (" plus V1_annulus_mm3" if lay.has_top_annulus else ""))
        if self.V2_mm3 <= self.displaced_volume_mm3:
            raise DesignError(
                f"chamber 2 bottoms out inside the stroke: V2_mm3 ({self.V2_mm3:.0f}) <= A2 * travel "
                f"({self.displaced_volume_mm3:.0f} mm³)"
            )
        if not self._g["V2_annulus_mm3"] > 0:
            raise DesignError(f"V2_top_mm3 ({self.V2_top_mm3:.0f}) leaves no chamber-2 gas around the bladder "
                              f"(V2_mm3 = {self.V2_mm3:.0f}); reduce V2_top_mm3")
        if self.bladder_gas_volume_cast_mm3 <= 0:
            raise DesignError(
                f"V2_mm3 ({self.V2_mm3:.0f}) is smaller than the gas the bladder gives up before reaching its "
                f"cast shape plus the dead volume{' and V2_top_mm3' if lay.has_bulkhead else ''}; increase V2_mm3"
            )
        if not self.bladder_free_length_mm > 0:
            raise DesignError(f"the bladder clamps{', the collar and the chamber-1 annulus' if lay.has_top_annulus else ''}"
                              f" take the whole inner length ({self.inner_length_mm:.1f} mm)")

    @cached_property
    def _g(self) -> dict[str, float]:
        g = derive(self.piston_diameter_mm, self.outer_diameter_mm, self.V1_mm3, self.V2_mm3, self.V2_top_mm3,
                   self.p2_MPa, self.setpoint_x0_mm, self.fixed, self.variant.has_bulkhead,
                   V1_annulus_mm3=self.V1_annulus_mm3, top_annulus=self.variant.has_top_annulus)
        return {k: (bool(v) if k == "buildable" else float(v)) for k, v in g.items()}

    @property
    def variant(self) -> LayoutVariant:
        return LAYOUTS[self.layout]

    # ------------------------------------------------------------------ areas
    @property
    def A1_mm2(self) -> float:
        """Chamber-1 effective area: full piston face (inner tube bore), mm²."""
        return self._g["A1_mm2"]

    @property
    def A2_mm2(self) -> float:
        """Chamber-2 effective area: piston minus rod (the rod crosses the fluid), mm²."""
        return self._g["A2_mm2"]

    # ------------------------------------------------------------------ walls
    @property
    def outer_wall_mm(self) -> float:
        """Outer tube wall, sized (>= fixed.min_outer_wall_mm), mm."""
        return self._g["outer_wall_mm"]

    @property
    def inner_tube_wall_mm(self) -> float:
        """Inner tube wall, sized (>= fixed.min_inner_tube_wall_mm), mm."""
        return self._g["inner_tube_wall_mm"]

    @property
    def top_cap_mm(self) -> float:
        """Top end cap, sized (>= fixed.min_top_cap_mm), mm."""
        return self._g["top_cap_mm"]

    @property
    def base_mm(self) -> float:
        """Base, sized (>= fixed.min_base_mm), mm."""
        return self._g["base_mm"]

    @property
    def bulkhead_mm(self) -> float:
        """Bulkhead web, sized (>= fixed.min_bulkhead_mm); 0 without a bulkhead, mm."""
        return self._g["bulkhead_mm"]

    @property
    def piston_floor_mm(self) -> float:
        """Floor of the piston pocket, sized (>= fixed.min_piston_floor_mm); the piston height without a pocket, mm."""
        return self._g["piston_floor_mm"]

    @property
    def piston_pocket_radius_mm(self) -> float:
        """Radius of the chamber-1 pocket in the piston crown (0 without one), mm."""
        return self._g["piston_pocket_radius_mm"]

    @property
    def piston_pocket_depth_mm(self) -> float:
        """Depth of the piston pocket from the piston's top face (0 without one), mm."""
        return self._g["piston_pocket_depth_mm"]

    @property
    def piston_pocket_volume_mm3(self) -> float:
        """Chamber-1 gas in the piston pocket (part of V1; 0 without one), mm³."""
        return self._g["piston_pocket_volume_mm3"]

    @property
    def collar_mm(self) -> float:
        """Collar plate above the top bladder clamp, sized (>= fixed.min_collar_mm); 0 outside ``annulus_top``, mm."""
        return self._g["collar_mm"]

    # ------------------------------------------------------------------ radii
    @property
    def outer_bore_radius_mm(self) -> float:
        return self._g["outer_bore_radius_mm"]

    @property
    def inner_tube_outer_radius_mm(self) -> float:
        return self._g["inner_tube_outer_radius_mm"]

    @property
    def annulus_gap_mm(self) -> float:
        return self._g["annulus_gap_mm"]

    # ---------------------------------------------------------------- lengths
    @property
    def chamber1_length_mm(self) -> float:
        """Gas column above the piston at x = 0 (up to the top cap or the bulkhead), mm."""
        return self._g["chamber1_length_mm"]

    @property
    def top_space_length_mm(self) -> float:
        """Length of the chamber-2 space above the bulkhead (0 without one), mm."""
        return self._g["top_space_length_mm"]

    @property
    def top_annulus_length_mm(self) -> float:
        """Length of the chamber-1 annulus between the collar and the top cap (``annulus_top``; else 0), mm."""
        return self._g["top_annulus_length_mm"]

    @property
    def cross_slot_volume_mm3(self) -> float:
        """``annulus_top``: chamber-1 gas in the slots through the inner tube's top end (part of V1; else 0), mm³."""
        return self._g["cross_slot_volume_mm3"]

    @property
    def cross_slot_room_mm(self) -> float:
        """``annulus_top``: room left for the cross slots below the top cap, in the annulus and above the piston
        at x = 0 (``min(L_annulus, chamber1_length) - cross_slot_mm - 1``; inf in the other layouts), mm."""
        return self._g["cross_slot_room_mm"]

    @property
    def fill_tube_volume_mm3(self) -> float:
        """Chamber-1 gas in the fill tube's bore (bulkhead layout; part of V1), mm³."""
        return self._g["fill_tube_volume_mm3"]

    @property
    def fluid_column_mm(self) -> float:
        """Fluid under the piston at x = 0: travel + clearance, mm."""
        return self._g["fluid_column_mm"]

    @property
    def inner_length_mm(self) -> float:
        """Inner-tube bore length = housing interior (base top to top-cap underside), mm."""
        return self._g["inner_length_mm"]

    @property
    def housing_length_mm(self) -> float:
        """Overall length of the housing (the envelope, eyes excluded), mm."""
        return self._g["housing_length_mm"]

    @property
    def bladder_free_length_mm(self) -> float:
        """Bladder length between the two clamps, mm."""
        return self._g["bladder_free_length_mm"]

    @property
    def rod_length_mm(self) -> float:
        """Rod from the piston's underside to its end outside the base at x = 0, mm."""
        return self._g["rod_length_mm"]

    # ---------------------------------------------------------------- volumes
    @property
    def displaced_volume_mm3(self) -> float:
        """Fluid pushed into the bladder over the full stroke, A2 * travel, mm³."""
        return self._g["displaced_volume_mm3"]

    @property
    def bladder_volume_change_mm3(self) -> dict[str, float]:
        """Fluid in the bladder relative to its cast shape at both stroke ends, mm³."""
        fill = self.fixed.bladder_cast_fill
        return {
            "compressed": -self.displaced_volume_mm3 * fill,  # x = 0
            "expanded": self.displaced_volume_mm3 * (1.0 - fill),  # x = travel
        }

    @property
    def V2_annulus_mm3(self) -> float:
        """Chamber-2 gas around the bladder at x = 0 (V2 minus V2_top minus the dead volume), mm³."""
        return self._g["V2_annulus_mm3"]

    @property
    def bladder_gas_volume_cast_mm3(self) -> float:
        """Chamber-2 gas around the bladder in its cast shape (dead volume and V2_top excluded), mm³."""
        return self._g["bladder_gas_volume_cast_mm3"]

    @property
    def annulus_volume_mm3(self) -> float:
        """Annulus between the tubes over the bladder's free length, mm³."""
        return self._g["annulus_volume_mm3"]

    @property
    def V2_capacity_mm3(self) -> float:
        """Largest V2 the annulus (+ V2_top) can hold: the bladder cast so close to the inner tube that
        at x = 0 (peak inward shift) it keeps just ``bladder_min_gap_mm``, mm³."""
        return self._g["V2_capacity_mm3"]

    @property
    def bladder_outer_radius_mm(self) -> float:
        """Outer radius of the cast bladder that leaves exactly V2 of gas, mm (may be unphysical
        when V2 exceeds the capacity; see the ``bladder_room`` constraint)."""
        return self._g["bladder_outer_radius_mm"]

    @property
    def bladder_inner_radius_mm(self) -> float:
        return self._g["bladder_inner_radius_mm"]

    def bladder_equivalent_outer_radius_mm(self, x_mm: float) -> float:
        """Outer radius of the straight sleeve that leaves exactly the annulus's chamber-2 gas of
        displacement ``x_mm`` (``V2 - V2_top - A2 x`` minus dead volume) in the annulus, mm.

        The real bladder bulges between its clamps; this equal-volume cylinder
        is what the CAD draws as the chamber-2 gas domain at x = 0.

        Parameters
        ----------
        x_mm : float
            Piston displacement, mm (x > 0 extends the spring).

        Returns
        -------
        float
            The sleeve's outer radius, mm.
        """
        L = self.bladder_free_length_mm
        gas = self.V2_annulus_mm3 - self.A2_mm2 * x_mm
        return math.sqrt(max(self.outer_bore_radius_mm**2 - gas / (math.pi * L), 1e-9))

    @property
    def bladder_mid_radius_mm(self) -> float:
        return self._g["bladder_mid_radius_mm"]

    def bladder_shift_mm(self) -> dict[str, float]:
        """Mean radial shift of the bladder from its cast shape at both stroke ends (+ outward), mm.

        Returns
        -------
        dict of str to float
            ``compressed`` (x = 0) and ``expanded`` (x = travel), mm.
        """
        return {"compressed": self._g["bladder_shift_compressed_mm"], "expanded": self._g["bladder_shift_expanded_mm"]}

    def bladder_clearance_mm(self) -> dict[str, float]:
        """Radial room left beyond ``bladder_min_gap_mm`` at both stroke ends, mm (negative = collision).

        The bladder's largest shift is ``bladder_bulge_factor`` times its mean
        shift: clamped at both ends it deflects about parabolically (peak = 1.5
        × mean), which the FE check (``vvea bladder``) confirms.

        Returns
        -------
        dict of str to float
            ``compressed`` (x = 0, to the inner tube) and ``expanded`` (x = travel, to the outer bore), mm.
        """
        return {"compressed": self._g["bladder_clearance_compressed_mm"],
                "expanded": self._g["bladder_clearance_expanded_mm"]}

    @property
    def bladder_fluid_volume_cast_mm3(self) -> float:
        """Fluid inside the cast bladder (between inner tube and bladder), mm³."""
        return self._g["bladder_fluid_volume_cast_mm3"]

    @property
    def fluid_volume_mm3(self) -> float:
        """Hydraulic fluid to fill at x = 0 (inner-tube column + bladder at x = 0), mm³."""
        return self._g["fluid_volume_mm3"]

    def volume_budget_mm3(self, envelope_length_mm: float | None = None) -> dict[str, float]:
        """Where every mm³ of the envelope cylinder goes at x = 0, mm³ (items sum to the envelope).

        The envelope is a cylinder of the outer diameter and ``envelope_length_mm``
        (default: the housing length); what the housing does not use is
        ``unused_length``. Items: the walls (outer tube, inner tube, top cap,
        base, bulkhead, fill-tube wall, collar plate), the piston, the rod inside the fluid
        column, the fluid under the piston (the stroke's swept column and the
        clearance left at full stroke), the bladder clamps (support ring and
        top clamp over the annulus), the bladder's silicone, the fluid inside
        the bladder at x = 0 split into the ``bladder_min_gap_mm`` layer on the
        inner tube and the rest (the room the inward bulge at x = 0 needs, plus
        any slack), and the gas: chamber 1 (``V1``: the bore above the piston,
        in ``annulus_top`` the annulus above the collar, with ``fixed.piston_pocket``
        the pocket in the piston crown) and chamber 2 (``V2``,
        above the bulkhead and in the annulus).

        Parameters
        ----------
        envelope_length_mm : float or None
            Length of the envelope cylinder, mm (None: the housing length).

        Returns
        -------
        dict of str to float
            Item -> volume at x = 0, mm³; the items add up to ``pi/4 D^2 envelope_length``.
        """
        f, pi = self.fixed, math.pi
        H = self.housing_length_mm if envelope_length_mm is None else float(envelope_length_mm)
        ro, rb, rio, ri = (self.outer_diameter_mm / 2, self.outer_bore_radius_mm, self.inner_tube_outer_radius_mm,
                           self.piston_diameter_mm / 2)
        L_in, L = self.inner_length_mm, self.bladder_free_length_mm
        A1, a_rod = self.A1_mm2, pi / 4 * f.rod_diameter_mm**2
        a_fo = pi / 4 * f.fill_tube_outer_mm**2 if self.variant.has_bulkhead else 0.0
        a_fb = pi / 4 * f.fill_tube_bore_mm**2 if self.variant.has_bulkhead else 0.0
        fluid_x0 = self.bladder_fluid_volume_cast_mm3 + self.bladder_volume_change_mm3["compressed"]
        gap = pi * ((rio + f.bladder_min_gap_mm) ** 2 - rio**2) * L
        clearance = f.fluid_clearance_mm
        out = {
            "wall_outer_tube": pi * (ro**2 - rb**2) * L_in,
            "wall_inner_tube": pi * (rio**2 - ri**2) * L_in - self._g["cross_slot_volume_mm3"],
            "wall_top_cap": pi * ro**2 * self.top_cap_mm,
            "wall_base": pi * ro**2 * self.base_mm,
            "wall_bulkhead": (A1 - a_fb) * self.bulkhead_mm,
            "wall_fill_tube": (a_fo - a_fb) * self.top_space_length_mm,
            "wall_collar": pi * (rb**2 - rio**2) * self.collar_mm,
            "piston": A1 * f.piston_height_mm - self.piston_pocket_volume_mm3,
            "rod_in_fluid_column": a_rod * self.fluid_column_mm,
            "fluid_swept_by_stroke": (A1 - a_rod) * f.travel_mm,
            "fluid_clearance_under_piston": (A1 - a_rod) * clearance,
            "bladder_clamps": 2 * pi * (rb**2 - rio**2) * f.bladder_clamp_mm,
            "bladder_silicone": pi * (self.bladder_outer_radius_mm**2 - self.bladder_inner_radius_mm**2) * L,
            "bladder_fluid_min_gap": gap,
            "bladder_fluid_bulge_room": fluid_x0 - gap,
            "gas_chamber_1": self.V1_mm3 - self.V1_annulus_mm3 - self.piston_pocket_volume_mm3,
            "gas_chamber_1_annulus": self.V1_annulus_mm3,
            "gas_chamber_1_piston_pocket": self.piston_pocket_volume_mm3,
            "gas_chamber_2_above_bulkhead": self.V2_top_mm3,
            "gas_chamber_2_annulus": self.V2_mm3 - self.V2_top_mm3,
            "unused_length": pi * ro**2 * (H - self.housing_length_mm),
        }
        # the dead volumes are gas outside the drawn columns: not in the envelope's cylinder
        out["gas_chamber_1"] -= f.dead_volume_1_mm3
        out["gas_chamber_2_annulus"] -= f.dead_volume_2_mm3
        return out

    # --------------------------------------------------------------- springs
    @property
    def p1_MPa(self) -> float:
        """Chamber-1 charge that puts zero force at ``setpoint_x0_mm`` (eq. 6), MPa."""
        return float(setpoint_p1_MPa(self.p2_MPa, self.A1_mm2, self.A2_mm2, self.V1_mm3, self.V2_mm3,
                                     self.setpoint_x0_mm, self.fixed.n_polytropic))

    @cached_property
    def gas_spring(self) -> GasSpring:
        """The spring at this design's charge."""
        return GasSpring(self.A1_mm2, self.A2_mm2, self.V1_mm3, self.V2_mm3, self.p1_MPa, self.p2_MPa,
                         self.fixed.travel_mm, self.fixed.n_polytropic)

    def with_charge(self, p2_MPa: float, setpoint_x0_mm: float | None = None) -> "Design":
        """The same hardware charged differently (walls follow the new peak pressure).

        Parameters
        ----------
        p2_MPa : float
            Chamber-2 charge, MPa.
        setpoint_x0_mm : float or None
            Displacement of zero force, mm (None: this design's).

        Returns
        -------
        Design
            The recharged design (p1 follows from the set point).
        """
        x0 = self.setpoint_x0_mm if setpoint_x0_mm is None else setpoint_x0_mm
        return replace(self, p2_MPa=p2_MPa, setpoint_x0_mm=x0)

    # --------------------------------------------------------------- strength
    def peak_pressures_MPa(self) -> dict[str, float]:
        """Highest gas pressure of each chamber over a stroke at ``max(n, fixed.wall_sizing_n)``, MPa.

        Returns
        -------
        dict of str to float
            ``chamber_1`` and ``chamber_2``, MPa.
        """
        return {"chamber_1": self._g["peak_chamber_1_MPa"], "chamber_2": self._g["peak_chamber_2_MPa"]}

    def walls_mm(self) -> dict[str, float]:
        """The sized wall thicknesses, mm (the bulkhead only in the ``bulkhead`` layout, the collar plate only
        in ``annulus_top``, the piston pocket's floor only with ``fixed.piston_pocket``).

        Returns
        -------
        dict of str to float
            Wall name (:attr:`LayoutVariant.walls`) -> thickness, mm.
        """
        out = {"outer_tube": self.outer_wall_mm, "inner_tube": self.inner_tube_wall_mm,
               "top_cap": self.top_cap_mm, "base": self.base_mm}
        if self.variant.has_bulkhead:
            out["bulkhead"] = self.bulkhead_mm
        if self.variant.has_top_annulus:
            out["collar"] = self.collar_mm
        if self.fixed.piston_pocket:
            out["piston_floor"] = self.piston_floor_mm
        return out

    def wall_stresses_MPa(self) -> dict[str, float]:
        """Peak stresses of the pressure-carrying walls as drawn, MPa.

        * ``outer_tube``: thick-walled tube (Lamé), internal chamber-2 pressure.
        * ``inner_tube``: Lamé, external peak chamber-2 pressure (conservatively
          nothing inside), ``2 p ro^2 / (ro^2 - ri^2)``; its safety factor is
          also the buckling one, ``p_cr / (P2 - P1)`` with the long-tube
          ``p_cr = E / (4 (1 - nu^2)) (t / r_mean)^3``, if smaller.
        * ``top_cap``, ``base``: circular plates, simply supported, peak
          chamber-2 pressure, ``3 (3 + nu) p a^2 / (8 t^2)``.
        * ``bulkhead`` (its layout only): the same plate over the piston bore,
          the largest chamber-2 minus chamber-1 pressure.
        * ``collar`` (``annulus_top`` only): the annular plate between the
          chambers above the top bladder clamp, cantilevered from the inner
          tube, the same pressure, ``6 M / t^2`` (:func:`derive`).
        * ``piston_floor`` (``fixed.piston_pocket`` only): the pocket's floor,
          an annular plate from the rod to the pocket wall, the same pressure,
          the larger of ``6 M / t^2`` at the rod and Tresca's ``2 x 1.5 Q / t``.

        Returns
        -------
        dict of str to float
            Wall name -> peak stress, MPa.
        """
        return {w: self._g[f"stress_{w}_MPa"] for w in self.walls_mm()}

    def wall_safety_factors(self) -> dict[str, float]:
        """Yield strength over peak stress, per wall.

        Returns
        -------
        dict of str to float
            Wall name -> safety factor (dimensionless; the inner tube's the smaller of yield and buckling).
        """
        return {w: self._g[f"safety_{w}"] for w in self.walls_mm()}

    def minimum_walls_mm(self, safety_factor: float | None = None) -> dict[str, float]:
        """Thinnest walls that carry the peak pressure with ``safety_factor`` (default: the design's), mm.

        Parameters
        ----------
        safety_factor : float or None
            On yield (and on buckling for the inner tube), dimensionless; None: ``fixed.wall_safety_factor``.

        Returns
        -------
        dict of str to float
            Wall name -> thickness, mm, ignoring the manufacturable minimums (inf: no wall carries it).
        """
        f = self.fixed if safety_factor is None else replace(self.fixed, wall_safety_factor=safety_factor)
        f = replace(f, min_outer_wall_mm=1e-6, min_inner_tube_wall_mm=1e-6, min_top_cap_mm=1e-6,
                    min_base_mm=1e-6, min_bulkhead_mm=1e-6, min_collar_mm=1e-6, min_piston_floor_mm=1e-6)
        g = derive(self.piston_diameter_mm, self.outer_diameter_mm, self.V1_mm3, self.V2_mm3, self.V2_top_mm3,
                   self.p2_MPa, self.setpoint_x0_mm, f, self.variant.has_bulkhead,
                   V1_annulus_mm3=self.V1_annulus_mm3, top_annulus=self.variant.has_top_annulus)
        keys = {"outer_tube": "outer_wall_mm", "inner_tube": "inner_tube_wall_mm", "top_cap": "top_cap_mm",
                "base": "base_mm", "bulkhead": "bulkhead_mm", "collar": "collar_mm", "piston_floor": "piston_floor_mm"}
        return {w: (float(g[keys[w]]) if np.isfinite(g[keys[w]]) else math.inf) for w in self.walls_mm()}

    # ------------------------------------------------------------------- mass
    def mass_breakdown_g(self) -> dict[str, float]:
        """Mass estimate per component from closed-form volumes, g.

        Returns
        -------
        dict of str to float
            Component -> mass, g (the bulkhead / collar only in their layouts).
        """
        keys = ["outer_tube", "end_caps", "inner_tube", "piston", "rod", "bladder", "support_ring", "fluid",
                "servo_and_valve"]
        if self.variant.has_bulkhead:
            keys.insert(3, "bulkhead")
        if self.variant.has_top_annulus:
            keys.insert(3, "collar")
        return {k: self._g[f"mass_{k}_g"] for k in keys}

    @property
    def mass_g(self) -> float:
        return float(sum(self.mass_breakdown_g().values()))

    # ---------------------------------------------------------------- export
    def decision_vector(self) -> np.ndarray:
        """The layout's decision variables in the optimiser's order.

        Returns
        -------
        numpy.ndarray
            Values of ``variant.decision_variables`` (mm, mm³).
        """
        return np.array([getattr(self, n) for n in self.variant.decision_variables], dtype=float)

    def geometry_summary(self) -> dict[str, float]:
        """Derived geometry (mm, mm², mm³) for the design JSON and the CAD.

        Returns
        -------
        dict
            ``layout`` and the derived radii, lengths (mm), wall thicknesses (mm) and volumes (mm³); the
            layout's own quantities (``V2_top_mm3`` ..., ``V1_annulus_mm3`` ...) in its layout only, the piston
            pocket's (``piston_pocket_volume_mm3`` ...) with ``fixed.piston_pocket`` only.
        """
        out = {
            "layout": self.layout,
            "outer_bore_radius_mm": self.outer_bore_radius_mm,
            "inner_tube_outer_radius_mm": self.inner_tube_outer_radius_mm,
            "walls_mm": self.walls_mm(),
            "chamber1_length_mm": self.chamber1_length_mm,
            "fluid_column_mm": self.fluid_column_mm,
            "inner_length_mm": self.inner_length_mm,
            "housing_length_mm": self.housing_length_mm,
            "rod_length_mm": self.rod_length_mm,
            "bladder_outer_radius_mm": self.bladder_outer_radius_mm,
            "bladder_mid_radius_mm": self.bladder_mid_radius_mm,
            "bladder_free_length_mm": self.bladder_free_length_mm,
            "bladder_thickness_mm": self.fixed.bladder_thickness_mm,
            "displaced_volume_mm3": self.displaced_volume_mm3,
            "V2_annulus_mm3": self.V2_annulus_mm3,
            "V2_capacity_mm3": self.V2_capacity_mm3,
            "fluid_volume_mm3": self.fluid_volume_mm3,
        }
        if self.variant.has_bulkhead:
            out.update(V2_top_mm3=self.V2_top_mm3, top_space_length_mm=self.top_space_length_mm,
                       fill_tube_volume_mm3=self.fill_tube_volume_mm3)
        if self.variant.has_top_annulus:
            out.update(V1_annulus_mm3=self.V1_annulus_mm3, top_annulus_length_mm=self.top_annulus_length_mm,
                       collar_mm=self.collar_mm)
        if self.fixed.piston_pocket:
            out.update(piston_pocket_radius_mm=self.piston_pocket_radius_mm,
                       piston_pocket_depth_mm=self.piston_pocket_depth_mm,
                       piston_pocket_volume_mm3=self.piston_pocket_volume_mm3, piston_floor_mm=self.piston_floor_mm)
        return out
