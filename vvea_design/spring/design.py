"""The frozen design: its layout, decision variables and fixed parameters -> geometry.

Layout (``docs/layout.md`` has the drawing and the reasoning): the paper's
concentric unit, axis vertical, drawn at x = 0 (spring unloaded). Below is the
``inner_tube`` variant; the others (:mod:`vvea_design.spring.layouts`, one
module each) place some of the gas elsewhere. Every derived quantity comes from
:func:`~vvea_design.spring.derive.derive`.

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
from dataclasses import dataclass, field, fields, replace
from functools import cached_property

import numpy as np

from ..messages import show
from ..plausibility import LIMITS
from .derive import Derived, derive
from .gas_spring import GasSpring, setpoint_p1_MPa
from .joints import JOINTS
from .layouts import DECISION_VARIABLES, LAYOUTS, BudgetShare, LayoutVariant, get_layout, layout_variables
from .parameters import DesignError, FixedParameters

__all__ = ["Design", "FixedParameters", "DesignError"]


def _budget_items() -> BudgetShare:
    """Every registered layout's volume-budget items (keys), in the order of the layouts."""
    walls, c1, c2 = {}, {}, {}
    for lay in LAYOUTS.values():
        items = lay.budget_items
        walls.update(dict.fromkeys(items.walls, 0.0))
        c1.update(dict.fromkeys(items.chamber_1, 0.0))
        c2.update(dict.fromkeys(items.chamber_2, 0.0))
    return BudgetShare(walls, c1, c2)


@dataclass(frozen=True)
class Design:
    """One unit: its layout, decision variables, charge and fixed parameters.

    Derived geometry is exposed as properties (mm, mm², mm³), all computed by
    :func:`~vvea_design.spring.derive.derive` (:attr:`derived`); everything the CAD, the bladder check and
    the actuator study need is here. What differs between the layouts is their modules'
    (:mod:`vvea_design.spring.layouts`).

    Raises
    ------
    DesignError
        For a design that cannot be drawn at all (non-positive sizes, a rod
        thicker than the piston, no annulus left for the bladder, a chamber
        that bottoms out). Designs that can be drawn but violate a
        requirement are reported by :func:`vvea_design.spring.problem.constraint_margins`.
    """

    piston_diameter_mm: float  #: working piston = inner-tube bore
    outer_diameter_mm: float  #: outer tube outer diameter (the envelope)
    V1_mm3: float  #: chamber-1 gas volume at x = 0
    V2_mm3: float  #: chamber-2 gas volume at x = 0 (annulus + V2_top_mm3 + dead volume)
    p2_MPa: float = 4.0  #: charge of chamber 2 (p1 follows from the setpoint)
    setpoint_x0_mm: float = 0.0  #: displacement of zero force (paper eq. 6)
    fixed: FixedParameters = field(default_factory=FixedParameters)
    layout: str = "inner_tube"  #: a key of :data:`~vvea_design.spring.layouts.LAYOUTS`
    V2_top_mm3: float = 0.0  #: chamber-2 gas above the bulkhead (``bulkhead`` layout only)
    V1_annulus_mm3: float = 0.0  #: chamber-1 gas in the annulus above the collar (``annulus_top`` only; part of V1)
    joint: str = "thread"  #: what holds the end pieces to the outer tube (:data:`~vvea_design.spring.joints.JOINTS`)

    def __post_init__(self) -> None:
        f = self.fixed
        lay = get_layout(self.layout)
        for name in DECISION_VARIABLES:
            v = getattr(self, name)
            if isinstance(v, bool) or not isinstance(v, (int, float)) or not math.isfinite(v) or v <= 0:
                raise DesignError(f"{name} must be a positive number, got {show(v)}")
        self._check_layout_variables(lay)
        if self.joint not in JOINTS:
            raise DesignError(f"joint must be one of {list(JOINTS)}, got {show(self.joint)}")
        if not isinstance(self.p2_MPa, (int, float)) or not math.isfinite(self.p2_MPa) or self.p2_MPa <= 0:
            raise DesignError(f"p2_MPa must be > 0, got {show(self.p2_MPa)}")
        LIMITS["charge_MPa"].check(self.p2_MPa, "p2_MPa", DesignError)  # before the walls are sized for it
        if not isinstance(self.setpoint_x0_mm, (int, float)) or not math.isfinite(self.setpoint_x0_mm):
            raise DesignError(f"setpoint_x0_mm must be a finite number, got {show(self.setpoint_x0_mm)}")
        if not abs(self.setpoint_x0_mm) < f.travel_mm:
            raise DesignError(f"setpoint_x0_mm ({show(self.setpoint_x0_mm)}) must lie inside the travel "
                              f"(|x0| < travel_mm = {show(f.travel_mm)})")

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
                f"{need:.2f} mm (fixed.bladder_thickness_mm = {f.bladder_thickness_mm:g} + 2 x "
                f"fixed.bladder_min_gap_mm = {f.bladder_min_gap_mm:g}); reduce piston_diameter_mm "
                f"({self.piston_diameter_mm:g}) or those fixed values, or increase outer_diameter_mm "
                f"({self.outer_diameter_mm:g})"
            )
        if not self.chamber1_length_mm > 0:
            raise DesignError(f"V1_mm3 ({self.V1_mm3:g}) must exceed fixed.dead_volume_1_mm3 ({f.dead_volume_1_mm3:g})"
                              + lay.chamber1_note
                              + (f" plus the piston pocket ({self.piston_pocket_volume_mm3:.0f} mm³)" if f.piston_pocket else ""))
        if self.V2_mm3 <= self.displaced_volume_mm3:
            raise DesignError(
                f"chamber 2 bottoms out inside the stroke: V2_mm3 ({self.V2_mm3:.0f}) <= A2 * travel "
                f"({self.displaced_volume_mm3:.0f} mm³: the piston_diameter_mm = {self.piston_diameter_mm:g} annulus "
                f"around fixed.rod_diameter_mm = {f.rod_diameter_mm:g}, times travel_mm = {f.travel_mm:g}); "
                f"V2_mm3 must exceed {self.displaced_volume_mm3:.0f} mm³, or shorten the travel or the piston"
            )
        if not self.V2_annulus_mm3 > 0:
            raise DesignError(f"V2_top_mm3 ({self.V2_top_mm3:.0f}) leaves no chamber-2 gas around the bladder "
                              f"(V2_mm3 = {self.V2_mm3:.0f}); reduce V2_top_mm3")
        if self.bladder_gas_volume_cast_mm3 <= 0:
            raise DesignError(
                f"V2_mm3 ({self.V2_mm3:.0f}) is smaller than the gas the bladder gives up before reaching its "
                f"cast shape plus the dead volume{lay.chamber2_note}; increase V2_mm3"
            )
        if not self.bladder_free_length_mm > 0:
            raise DesignError(f"the bladder clamps{lay.bladder_note} take the whole inner length "
                              f"({self.inner_length_mm:.1f} mm)")

    def _check_layout_variables(self, lay: LayoutVariant) -> None:
        """Every layout's own variable is a number >= 0, and 0 outside its layout."""
        names = {f.name for f in fields(self)}
        for name in lay.decision_variables:
            if name not in names:
                raise DesignError(f"the {lay.name!r} layout's decision variable {name} is not a field of Design")
        for name, (owner, var) in layout_variables().items():
            if name not in names:
                continue
            v = getattr(self, name)
            if isinstance(v, bool) or not isinstance(v, (int, float)) or not math.isfinite(v) or v < 0:
                raise DesignError(f"{name} must be a number >= 0, got {show(v)}")
            if owner != lay.name and v != 0:
                raise DesignError(f"{name} = {v:g}: only the {owner!r} layout has {var.what} "
                                  f"(this design's layout is {self.layout!r})")

    def _variables(self) -> dict[str, float]:
        """The layout's decision variables by name (mm, mm³)."""
        return {n: getattr(self, n) for n in self.variant.decision_variables}

    @cached_property
    def derived(self) -> Derived:
        """Every derived quantity of this design as Python numbers (:func:`~vvea_design.spring.derive.derive`)."""
        return derive(self._variables(), self.p2_MPa, self.setpoint_x0_mm, self.fixed, self.layout,
                      joint=self.joint).item()

    @property
    def _g(self) -> dict:
        """Deprecated: the derived quantities by name (:attr:`derived` ``.to_dict()``); for readers of the old dict."""
        return self.derived.to_dict()

    @property
    def variant(self) -> LayoutVariant:
        """The layout variant (:mod:`vvea_design.spring.layouts`) named by :attr:`layout`."""
        return get_layout(self.layout)

    # ------------------------------------------------------------------ areas
    @property
    def A1_mm2(self) -> float:
        """Chamber-1 effective area: full piston face (inner tube bore), mm²."""
        return self.derived.A1_mm2

    @property
    def A2_mm2(self) -> float:
        """Chamber-2 effective area: piston minus rod (the rod crosses the fluid), mm²."""
        return self.derived.A2_mm2

    # ------------------------------------------------------------------ walls
    @property
    def outer_wall_mm(self) -> float:
        """Outer tube wall, sized (>= fixed.min_outer_wall_mm), mm."""
        return self.derived.walls_mm["outer_tube"]

    @property
    def inner_tube_wall_mm(self) -> float:
        """Inner tube wall, sized (>= fixed.min_inner_tube_wall_mm), mm."""
        return self.derived.walls_mm["inner_tube"]

    @property
    def top_cap_mm(self) -> float:
        """Top end cap, sized (>= fixed.min_top_cap_mm), mm."""
        return self.derived.walls_mm["top_cap"]

    @property
    def base_mm(self) -> float:
        """Base, sized (>= fixed.min_base_mm), mm."""
        return self.derived.walls_mm["base"]

    @property
    def bulkhead_mm(self) -> float:
        """Bulkhead web, sized (>= fixed.min_bulkhead_mm); 0 without a bulkhead, mm."""
        return self.derived.walls_mm.get("bulkhead", 0.0)

    @property
    def piston_floor_mm(self) -> float:
        """Floor of the piston pocket, sized (>= fixed.min_piston_floor_mm); the piston height without a pocket, mm."""
        return self.derived.piston_floor_mm

    @property
    def piston_pocket_radius_mm(self) -> float:
        """Radius of the chamber-1 pocket in the piston crown (0 without one), mm."""
        return self.derived.piston_pocket_radius_mm

    @property
    def piston_pocket_depth_mm(self) -> float:
        """Depth of the piston pocket from the piston's top face (0 without one), mm."""
        return self.derived.piston_pocket_depth_mm

    @property
    def piston_pocket_volume_mm3(self) -> float:
        """Chamber-1 gas in the piston pocket (part of V1; 0 without one), mm³."""
        return self.derived.piston_pocket_volume_mm3

    @property
    def collar_mm(self) -> float:
        """Collar plate above the top bladder clamp, sized (>= fixed.min_collar_mm); 0 outside ``annulus_top``, mm."""
        return self.derived.walls_mm.get("collar", 0.0)

    # ------------------------------------------------------------------ radii
    @property
    def outer_bore_radius_mm(self) -> float:
        return self.derived.outer_bore_radius_mm

    @property
    def inner_tube_outer_radius_mm(self) -> float:
        return self.derived.inner_tube_outer_radius_mm

    @property
    def annulus_gap_mm(self) -> float:
        return self.derived.annulus_gap_mm

    # ---------------------------------------------------------------- lengths
    @property
    def chamber1_length_mm(self) -> float:
        """Gas column above the piston at x = 0 (up to the top cap or the bulkhead), mm."""
        return self.derived.chamber1_length_mm

    @property
    def top_space_length_mm(self) -> float:
        """Length of the chamber-2 space above the bulkhead (0 without one), mm."""
        return self.derived.layout_quantities.get("top_space_length_mm", 0.0)

    @property
    def top_annulus_length_mm(self) -> float:
        """Length of the chamber-1 annulus between the collar and the top cap (``annulus_top``; else 0), mm."""
        return self.derived.layout_quantities.get("top_annulus_length_mm", 0.0)

    @property
    def cross_slot_volume_mm3(self) -> float:
        """``annulus_top``: chamber-1 gas in the slots through the inner tube's top end (part of V1; else 0), mm³."""
        return self.derived.layout_quantities.get("cross_slot_volume_mm3", 0.0)

    @property
    def cross_slot_room_mm(self) -> float:
        """``annulus_top``: room left for the cross slots below the top cap, in the annulus and above the piston
        at x = 0 (``min(L_annulus, chamber1_length) - cross_slot_mm - 1``; inf in the other layouts), mm."""
        return self.derived.layout_quantities.get("cross_slot_room_mm", math.inf)

    @property
    def fill_tube_volume_mm3(self) -> float:
        """Chamber-1 gas in the fill tube's bore (bulkhead layout; part of V1), mm³."""
        return self.derived.layout_quantities.get("fill_tube_volume_mm3", 0.0)

    @property
    def fluid_column_mm(self) -> float:
        """Fluid under the piston at x = 0: travel + clearance, mm."""
        return self.derived.fluid_column_mm

    @property
    def inner_length_mm(self) -> float:
        """Inner-tube bore length = housing interior (base top to top-cap underside), mm."""
        return self.derived.inner_length_mm

    @property
    def housing_length_mm(self) -> float:
        """Overall length of the housing (the envelope, eyes excluded), mm."""
        return self.derived.housing_length_mm

    @property
    def bladder_free_length_mm(self) -> float:
        """Bladder length between the two clamps, mm."""
        return self.derived.bladder_free_length_mm

    @property
    def rod_length_mm(self) -> float:
        """Rod from the piston's underside to its end outside the base at x = 0, mm."""
        return self.derived.rod_length_mm

    # ---------------------------------------------------------------- volumes
    @property
    def displaced_volume_mm3(self) -> float:
        """Fluid pushed into the bladder over the full stroke, A2 * travel, mm³."""
        return self.derived.displaced_volume_mm3

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
        return self.derived.V2_annulus_mm3

    @property
    def bladder_gas_volume_cast_mm3(self) -> float:
        """Chamber-2 gas around the bladder in its cast shape (dead volume and V2_top excluded), mm³."""
        return self.derived.bladder_gas_volume_cast_mm3

    @property
    def annulus_volume_mm3(self) -> float:
        """Annulus between the tubes over the bladder's free length, mm³."""
        return self.derived.annulus_volume_mm3

    @property
    def V2_capacity_mm3(self) -> float:
        """Largest V2 the annulus (+ V2_top) can hold: the bladder cast so close to the inner tube that
        at x = 0 (peak inward shift) it keeps just ``bladder_min_gap_mm``, mm³."""
        return self.derived.V2_capacity_mm3

    @property
    def bladder_outer_radius_mm(self) -> float:
        """Outer radius of the cast bladder that leaves exactly V2 of gas, mm (may be unphysical
        when V2 exceeds the capacity; see the ``bladder_room`` constraint)."""
        return self.derived.bladder_outer_radius_mm

    @property
    def bladder_inner_radius_mm(self) -> float:
        return self.derived.bladder_inner_radius_mm

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
        return self.derived.bladder_mid_radius_mm

    def bladder_shift_mm(self) -> dict[str, float]:
        """Mean radial shift of the bladder from its cast shape at both stroke ends (+ outward), mm.

        Returns
        -------
        dict of str to float
            ``compressed`` (x = 0) and ``expanded`` (x = travel), mm.
        """
        return {"compressed": self.derived.bladder_shift_compressed_mm, "expanded": self.derived.bladder_shift_expanded_mm}

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
        return {"compressed": self.derived.bladder_clearance_compressed_mm,
                "expanded": self.derived.bladder_clearance_expanded_mm}

    @property
    def bladder_fluid_volume_cast_mm3(self) -> float:
        """Fluid inside the cast bladder (between inner tube and bladder), mm³."""
        return self.derived.bladder_fluid_volume_cast_mm3

    @property
    def fluid_volume_mm3(self) -> float:
        """Hydraulic fluid to fill at x = 0 (inner-tube column + bladder at x = 0), mm³."""
        return self.derived.fluid_volume_mm3

    def volume_budget_mm3(self, envelope_length_mm: float | None = None) -> dict[str, float]:
        """Where every mm³ of the envelope cylinder goes at x = 0, mm³ (items sum to the envelope).

        The envelope is a cylinder of the outer diameter and ``envelope_length_mm``
        (default: the housing length); what the housing does not use is
        ``unused_length``. Items: the walls (outer tube, inner tube, top cap,
        base, and the layout's own: bulkhead, fill-tube wall, collar plate), the piston, the rod inside the fluid
        column, the fluid under the piston (the stroke's swept column and the
        clearance left at full stroke), the bladder clamps (support ring and
        top clamp over the annulus), the bladder's silicone, the fluid inside
        the bladder at x = 0 split into the ``bladder_min_gap_mm`` layer on the
        inner tube and the rest (the room the inward bulge at x = 0 needs, plus
        any slack), and the gas: chamber 1 (``V1``: the bore above the piston,
        in ``annulus_top`` the annulus above the collar, with ``fixed.piston_pocket``
        the pocket in the piston crown) and chamber 2 (``V2``,
        above the bulkhead and in the annulus). Every layout's items are listed
        (0 in the others: :attr:`~vvea_design.spring.layouts.base.LayoutVariant.budget_items`).

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
        share, items = self.variant.budget(self), _budget_items()
        H = self.housing_length_mm if envelope_length_mm is None else float(envelope_length_mm)
        ro, rb, rio, ri = (self.outer_diameter_mm / 2, self.outer_bore_radius_mm, self.inner_tube_outer_radius_mm,
                           self.piston_diameter_mm / 2)
        L_in, L = self.inner_length_mm, self.bladder_free_length_mm
        A1, a_rod = self.A1_mm2, pi / 4 * f.rod_diameter_mm**2
        fluid_x0 = self.bladder_fluid_volume_cast_mm3 + self.bladder_volume_change_mm3["compressed"]
        gap = pi * ((rio + f.bladder_min_gap_mm) ** 2 - rio**2) * L
        clearance = f.fluid_clearance_mm
        gas_1, gas_2 = self.V1_mm3, self.V2_mm3  # less the gas the layout holds elsewhere
        for v in share.chamber_1.values():
            gas_1 = gas_1 - v
        for v in share.chamber_2.values():
            gas_2 = gas_2 - v
        out = {
            "wall_outer_tube": pi * (ro**2 - rb**2) * L_in,
            "wall_inner_tube": pi * (rio**2 - ri**2) * L_in - self.derived.inner_tube_cut_mm3,
            "wall_top_cap": pi * ro**2 * self.top_cap_mm,
            "wall_base": pi * ro**2 * self.base_mm,
            **{k: share.walls.get(k, 0.0) for k in items.walls},
            "piston": A1 * f.piston_height_mm - self.piston_pocket_volume_mm3,
            "rod_in_fluid_column": a_rod * self.fluid_column_mm,
            "fluid_swept_by_stroke": (A1 - a_rod) * f.travel_mm,
            "fluid_clearance_under_piston": (A1 - a_rod) * clearance,
            "bladder_clamps": 2 * pi * (rb**2 - rio**2) * f.bladder_clamp_mm,
            "bladder_silicone": pi * (self.bladder_outer_radius_mm**2 - self.bladder_inner_radius_mm**2) * L,
            "bladder_fluid_min_gap": gap,
            "bladder_fluid_bulge_room": fluid_x0 - gap,
            "gas_chamber_1": gas_1 - self.piston_pocket_volume_mm3,
            **{k: share.chamber_1.get(k, 0.0) for k in items.chamber_1},
            "gas_chamber_1_piston_pocket": self.piston_pocket_volume_mm3,
            **{k: share.chamber_2.get(k, 0.0) for k in items.chamber_2},
            "gas_chamber_2_annulus": gas_2,
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
        return {"chamber_1": self.derived.peak_chamber_1_MPa, "chamber_2": self.derived.peak_chamber_2_MPa}

    def walls_mm(self) -> dict[str, float]:
        """The sized wall thicknesses, mm (the bulkhead only in the ``bulkhead`` layout, the collar plate only
        in ``annulus_top``, the piston pocket's floor only with ``fixed.piston_pocket``).

        Returns
        -------
        dict of str to float
            Wall name (:attr:`~vvea_design.spring.layouts.base.LayoutVariant.walls`, then ``piston_floor``)
            -> thickness, mm.
        """
        return dict(self.derived.walls_mm)

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
          tube, the same pressure, ``6 M / t^2`` (:mod:`~vvea_design.spring.layouts.annulus_top`).
        * ``piston_floor`` (``fixed.piston_pocket`` only): the pocket's floor,
          an annular plate from the rod to the pocket wall, the same pressure,
          the larger of ``6 M / t^2`` at the rod and Tresca's ``2 x 1.5 Q / t``.

        Returns
        -------
        dict of str to float
            Wall name -> peak stress, MPa.
        """
        return dict(self.derived.stresses_MPa)

    def wall_safety_factors(self) -> dict[str, float]:
        """Yield strength over peak stress, per wall.

        Returns
        -------
        dict of str to float
            Wall name -> safety factor (dimensionless; the inner tube's the smaller of yield and buckling).
        """
        return dict(self.derived.safety_factors)

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
        f = replace(f, **{fl.name: 1e-6 for fl in fields(f) if fl.name.startswith("min_")})  # every wall's minimum
        walls = derive(self._variables(), self.p2_MPa, self.setpoint_x0_mm, f, self.layout, joint=self.joint,
                       stresses=False, masses=False).walls_mm  # the design's own joint (a thread's walls differ)
        return {w: (float(walls[w]) if np.isfinite(walls[w]) else math.inf) for w in self.walls_mm()}

    # ------------------------------------------------------------ buildability
    @cached_property
    def buildability(self):
        """The buildability records (:func:`~vvea_design.spring.buildability.buildability`): the load cases, every
        pressure-bearing piece's governing case and safety factor, the joints, the drawn tolerances, the damper."""
        from .buildability import buildability

        return buildability(self)

    @property
    def load_cases(self):
        """The load cases (:class:`~vvea_design.spring.loads.Loads`): each face's pressure (MPa), the external force (N)."""
        return self.buildability.loads

    def piece_loads(self) -> dict:
        """Every pressure-bearing piece under its load cases.

        Returns
        -------
        dict of str to PieceLoad
            Piece -> its governing case, stress (MPa) and safety factor (dimensionless), per case too.
        """
        return dict(self.buildability.pieces)

    def joints(self) -> tuple:
        """The joints' records: thread, ring or tie rods per end, and the inner tube's seats.

        Returns
        -------
        tuple
            :class:`~vvea_design.spring.joints.ThreadJoint`, ``RingJoint``, ``TieRodJoint``, ``SeatJoint`` (mm, N).
        """
        return self.buildability.joints

    def drawn_tolerances(self) -> tuple:
        """The drawn tolerances of the sized walls (what the sizing took at the least-material condition).

        Returns
        -------
        tuple of DrawnTolerance
            Feature, part, nominal and deviations, least-material size (mm), standard.
        """
        return self.buildability.tolerances

    @property
    def hydraulics(self):
        """The built unit's damper (:class:`~vvea_design.spring.hydraulics.Hydraulics`): oil, restrictions, D_min, D_max."""
        return self.buildability.hydraulics

    @property
    def parasitic_damping_N_s_per_mm(self) -> float:
        """``D_min``: the damping of the fully open throttle, the flow path's own (the paper's identification), N s/mm."""
        return self.derived.parasitic_damping_N_s_per_mm

    @property
    def joint_utilisation(self) -> float | None:
        """The joint's worst check over its limit (<= 1 met; None under the gas-only rules), dimensionless."""
        return self.derived.joint_utilisation

    def damping_range_N_s_per_mm(self) -> tuple[float, float]:
        """The built unit's damping range: ``D_min`` (throttle open, the parasitic damping) and ``D_max``
        (closed, capped by the relief valve), the paper's least-squares damping over its identification speeds.

        Returns
        -------
        tuple of float
            ``(D_min, D_max)``, N s/mm.
        """
        h = self.hydraulics
        return h.D_min_N_s_per_mm, h.D_max_N_s_per_mm

    # ------------------------------------------------------------------- mass
    def mass_breakdown_g(self) -> dict[str, float]:
        """Mass estimate per component from closed-form volumes, g.

        Returns
        -------
        dict of str to float
            Component -> mass, g (the layout's own parts, bulkhead or collar, after the inner tube).
        """
        return dict(self.derived.masses_g)

    @property
    def mass_g(self) -> float:
        """Sum of :meth:`mass_breakdown_g`, g."""
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
        out.update(self.variant.geometry_summary(self))
        if self.fixed.piston_pocket:
            out.update(piston_pocket_radius_mm=self.piston_pocket_radius_mm,
                       piston_pocket_depth_mm=self.piston_pocket_depth_mm,
                       piston_pocket_volume_mm3=self.piston_pocket_volume_mm3, piston_floor_mm=self.piston_floor_mm)
        return out
