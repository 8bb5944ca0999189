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

__all__ = ["FixedParameters", "Design", "DesignError", "DECISION_VARIABLES"]

#: The optimiser's decision variables, in order, with their units in the name.
DECISION_VARIABLES = ("piston_diameter_mm", "outer_diameter_mm", "V1_mm3", "V2_mm3")

_NONNEGATIVE = {"dead_volume_1_mm3", "dead_volume_2_mm3", "servo_and_valve_mass_g", "bladder_min_gap_mm"}


class DesignError(ValueError):
    """A design that cannot be built (names the field and what is wrong)."""


@dataclass(frozen=True)
class FixedParameters:
    """Parameters the optimiser does not change (mm, mm³, g)."""

    travel_mm: float = 40.0  #: stroke, x from 0 to travel
    rod_diameter_mm: float = 8.0  #: piston rod (crosses the fluid, leaves through the base)
    outer_wall_mm: float = 1.5  #: outer tube wall (carries chamber-2 pressure)
    inner_tube_wall_mm: float = 1.5  #: inner tube wall (chamber 2 outside, chamber 1 / fluid inside)
    top_cap_mm: float = 8.0  #: top end cap (fill ports, top eye)
    base_mm: float = 14.0  #: bottom end cap (valve bores, channels, rod seal)
    piston_height_mm: float = 10.0  #: working piston incl. seal grooves
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
        for key in ("housing_material", "rod_material", "support_ring_material"):
            try:
                get_material(getattr(self, key))
            except ValueError as exc:
                raise DesignError(f"fixed.{key}: {exc}") from None

    def to_dict(self) -> dict:
        return asdict(self)

    @classmethod
    def from_dict(cls, data, **override) -> "FixedParameters":
        """Build from a mapping (a TOML table or the design JSON's ``fixed``); unknown keys are an error."""
        if not isinstance(data, dict):
            raise DesignError(f"fixed parameters must be a table/object, got {type(data).__name__}")
        known = {f.name for f in fields(cls)}
        bad = set(data) - known
        if bad:
            raise DesignError(f"unknown fixed parameter(s) {sorted(bad)}; known: {sorted(known)}")
        try:
            return cls(**{**data, **override})
        except TypeError as exc:  # pragma: no cover - guarded by the key check
            raise DesignError(str(exc)) from None


@dataclass(frozen=True)
class Design:
    """One unit: the paper's four decision variables, its charge and fixed parameters.

    Derived geometry is exposed as properties (mm, mm², mm³); everything the
    CAD, the bladder check and the actuator study need is here.

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
    V2_mm3: float  #: chamber-2 gas volume at x = 0
    p2_MPa: float = 4.0  #: charge of chamber 2 (p1 follows from the setpoint)
    setpoint_x0_mm: float = 0.0  #: displacement of zero force (paper eq. 6)
    fixed: FixedParameters = field(default_factory=FixedParameters)

    def __post_init__(self) -> None:
        f = self.fixed
        for name in DECISION_VARIABLES:
            v = getattr(self, name)
            if isinstance(v, bool) or not isinstance(v, (int, float)) or not math.isfinite(v) or v <= 0:
                raise DesignError(f"{name} must be a positive number, got {show(v)}")
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
        if self.annulus_gap_mm <= need:
            raise DesignError(
                f"no room for the bladder: the annulus between inner tube (outer radius "
                f"{self.inner_tube_outer_radius_mm:.2f} mm) and outer tube bore (radius "
                f"{self.outer_bore_radius_mm:.2f} mm) is {self.annulus_gap_mm:.2f} mm wide, needs more than "
                f"{need:.2f} mm; reduce piston_diameter_mm or increase outer_diameter_mm"
            )
        if self.V1_mm3 <= f.dead_volume_1_mm3:
            raise DesignError(f"V1_mm3 ({self.V1_mm3:g}) must exceed fixed.dead_volume_1_mm3 ({f.dead_volume_1_mm3:g})")
        if self.V2_mm3 <= self.displaced_volume_mm3:
            raise DesignError(
                f"chamber 2 bottoms out inside the stroke: V2_mm3 ({self.V2_mm3:.0f}) <= A2 * travel "
                f"({self.displaced_volume_mm3:.0f} mm³)"
            )
        if self.bladder_gas_volume_cast_mm3 <= 0:
            raise DesignError(
                f"V2_mm3 ({self.V2_mm3:.0f}) is smaller than the gas the bladder gives up before reaching its "
                f"cast shape plus the dead volume; increase V2_mm3"
            )

    # ------------------------------------------------------------------ areas
    @property
    def A1_mm2(self) -> float:
        """Chamber-1 effective area: full piston face (inner tube bore), mm²."""
        return math.pi / 4 * self.piston_diameter_mm**2

    @property
    def A2_mm2(self) -> float:
        """Chamber-2 effective area: piston minus rod (the rod crosses the fluid), mm²."""
        return math.pi / 4 * (self.piston_diameter_mm**2 - self.fixed.rod_diameter_mm**2)

    # ------------------------------------------------------------------ radii
    @property
    def outer_bore_radius_mm(self) -> float:
        return self.outer_diameter_mm / 2 - self.fixed.outer_wall_mm

    @property
    def inner_tube_outer_radius_mm(self) -> float:
        return self.piston_diameter_mm / 2 + self.fixed.inner_tube_wall_mm

    @property
    def annulus_gap_mm(self) -> float:
        return self.outer_bore_radius_mm - self.inner_tube_outer_radius_mm

    # ---------------------------------------------------------------- lengths
    @property
    def chamber1_length_mm(self) -> float:
        """Gas column above the piston at x = 0, mm."""
        return (self.V1_mm3 - self.fixed.dead_volume_1_mm3) / self.A1_mm2

    @property
    def fluid_column_mm(self) -> float:
        """Fluid under the piston at x = 0: travel + clearance, mm."""
        return self.fixed.travel_mm + self.fixed.fluid_clearance_mm

    @property
    def inner_length_mm(self) -> float:
        """Inner-tube bore length = housing interior (base top to top-cap underside), mm."""
        return self.chamber1_length_mm + self.fixed.piston_height_mm + self.fluid_column_mm

    @property
    def housing_length_mm(self) -> float:
        """Overall length of the housing (the envelope, eyes excluded), mm."""
        return self.fixed.top_cap_mm + self.inner_length_mm + self.fixed.base_mm

    @property
    def bladder_free_length_mm(self) -> float:
        """Bladder length between the two clamps, mm."""
        return self.inner_length_mm - 2 * self.fixed.bladder_clamp_mm

    @property
    def rod_length_mm(self) -> float:
        """Rod from the piston's underside to its end outside the base at x = 0, mm."""
        f = self.fixed
        return self.fluid_column_mm + f.base_mm + f.travel_mm + 10.0

    # ---------------------------------------------------------------- volumes
    @property
    def displaced_volume_mm3(self) -> float:
        """Fluid pushed into the bladder over the full stroke, A2 * travel, mm³."""
        return self.A2_mm2 * self.fixed.travel_mm

    @property
    def bladder_volume_change_mm3(self) -> dict[str, float]:
        """Fluid in the bladder relative to its cast shape at both stroke ends, mm³."""
        fill = self.fixed.bladder_cast_fill
        return {
            "compressed": -self.displaced_volume_mm3 * fill,  # x = 0
            "expanded": self.displaced_volume_mm3 * (1.0 - fill),  # x = travel
        }

    @property
    def bladder_gas_volume_cast_mm3(self) -> float:
        """Chamber-2 gas around the bladder in its cast shape (dead volume excluded), mm³."""
        f = self.fixed
        return self.V2_mm3 - f.dead_volume_2_mm3 - self.displaced_volume_mm3 * f.bladder_cast_fill

    @property
    def annulus_volume_mm3(self) -> float:
        """Annulus between the tubes over the bladder's free length, mm³."""
        return math.pi * (self.outer_bore_radius_mm**2 - self.inner_tube_outer_radius_mm**2) * self.bladder_free_length_mm

    @property
    def V2_capacity_mm3(self) -> float:
        """Largest V2 the annulus can hold: the bladder cast so close to the inner tube that at
        x = 0 (peak inward shift) it keeps just ``bladder_min_gap_mm``, mm³."""
        f = self.fixed
        L = self.bladder_free_length_mm
        a = self.inner_tube_outer_radius_mm + f.bladder_min_gap_mm
        c = -f.bladder_bulge_factor * self.bladder_volume_change_mm3["compressed"] / (2 * math.pi * L)
        r_bi = 0.5 * (a + math.sqrt(a * a + 4 * c))  # r_bi - c / r_bi = a
        r_bo = r_bi + f.bladder_thickness_mm
        gas = math.pi * max(self.outer_bore_radius_mm**2 - r_bo**2, 0.0) * L
        return gas + self.displaced_volume_mm3 * f.bladder_cast_fill + f.dead_volume_2_mm3

    @property
    def bladder_outer_radius_mm(self) -> float:
        """Outer radius of the cast bladder that leaves exactly V2 of gas, mm (may be unphysical
        when V2 exceeds the capacity; see the ``bladder_room`` constraint)."""
        L = self.bladder_free_length_mm
        r2 = self.outer_bore_radius_mm**2 - self.bladder_gas_volume_cast_mm3 / (math.pi * L) if L > 0 else 0.0
        return math.sqrt(max(r2, 1e-9))

    @property
    def bladder_inner_radius_mm(self) -> float:
        return self.bladder_outer_radius_mm - self.fixed.bladder_thickness_mm

    def bladder_equivalent_outer_radius_mm(self, x_mm: float) -> float:
        """Outer radius of the straight sleeve that leaves exactly the chamber-2 gas of
        displacement ``x_mm`` (``V2 - A2 x`` minus dead volume) in the annulus, mm.

        The real bladder bulges between its clamps; this equal-volume cylinder
        is what the CAD draws as the chamber-2 gas domain at x = 0.
        """
        L = self.bladder_free_length_mm
        gas = self.V2_mm3 - self.fixed.dead_volume_2_mm3 - self.A2_mm2 * x_mm
        return math.sqrt(max(self.outer_bore_radius_mm**2 - gas / (math.pi * L), 1e-9))

    @property
    def bladder_mid_radius_mm(self) -> float:
        return self.bladder_outer_radius_mm - self.fixed.bladder_thickness_mm / 2

    def bladder_shift_mm(self) -> dict[str, float]:
        """Mean radial shift of the bladder from its cast shape at both stroke ends (+ outward), mm."""
        dv = self.bladder_volume_change_mm3
        L = self.bladder_free_length_mm
        return {
            "compressed": dv["compressed"] / (2 * math.pi * max(self.bladder_inner_radius_mm, 1e-9) * L),
            "expanded": dv["expanded"] / (2 * math.pi * self.bladder_outer_radius_mm * L),
        }

    def bladder_clearance_mm(self) -> dict[str, float]:
        """Radial room left beyond ``bladder_min_gap_mm`` at both stroke ends, mm (negative = collision).

        The bladder's largest shift is ``bladder_bulge_factor`` times its mean
        shift: clamped at both ends it deflects about parabolically (peak = 1.5
        × mean), which the FE check (``vvea bladder``) confirms.
        """
        s = self.bladder_shift_mm()
        g = self.fixed.bladder_min_gap_mm
        k = self.fixed.bladder_bulge_factor
        return {
            "compressed": self.bladder_inner_radius_mm + k * s["compressed"] - self.inner_tube_outer_radius_mm - g,
            "expanded": self.outer_bore_radius_mm - (self.bladder_outer_radius_mm + k * s["expanded"]) - g,
        }

    @property
    def bladder_fluid_volume_cast_mm3(self) -> float:
        """Fluid inside the cast bladder (between inner tube and bladder), mm³."""
        return math.pi * max(self.bladder_inner_radius_mm**2 - self.inner_tube_outer_radius_mm**2, 0.0) * self.bladder_free_length_mm

    @property
    def fluid_volume_mm3(self) -> float:
        """Hydraulic fluid to fill at x = 0 (inner-tube column + bladder at x = 0), mm³."""
        return (self.A2_mm2 * self.fluid_column_mm + self.bladder_fluid_volume_cast_mm3
                + self.bladder_volume_change_mm3["compressed"])

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
        """The same hardware charged differently."""
        x0 = self.setpoint_x0_mm if setpoint_x0_mm is None else setpoint_x0_mm
        return replace(self, p2_MPa=p2_MPa, setpoint_x0_mm=x0)

    # --------------------------------------------------------------- strength
    def peak_pressures_MPa(self) -> dict[str, float]:
        """Highest gas pressure of each chamber over the stroke, MPa."""
        P1, P2 = self.gas_spring.pressures_MPa(np.array([0.0, self.fixed.travel_mm]))
        return {"chamber_1": float(P1.max()), "chamber_2": float(P2.max())}

    def wall_stresses_MPa(self) -> dict[str, float]:
        """Peak stresses of the pressure-carrying walls, MPa.

        * ``outer_tube``: thick-walled tube (Lamé), internal chamber-2 pressure.
        * ``inner_tube``: Lamé, external chamber-2 pressure over chamber 1 at
          its lowest (conservatively the full peak chamber-2 pressure),
          ``2 p ro^2 / (ro^2 - ri^2)``.
        * ``top_cap`` and ``base``: circular plates, simply supported, peak
          chamber-2 pressure, ``3 (3 + nu) p a^2 / (8 t^2)``.
        """
        p2 = self.peak_pressures_MPa()["chamber_2"]
        f = self.fixed
        nu = get_material(f.housing_material).poisson
        rb, ro = self.outer_bore_radius_mm, self.outer_diameter_mm / 2
        ri_in, ri_out = self.piston_diameter_mm / 2, self.inner_tube_outer_radius_mm
        return {
            "outer_tube": p2 * (ro**2 + rb**2) / (ro**2 - rb**2),
            "inner_tube": 2 * p2 * ri_out**2 / (ri_out**2 - ri_in**2),
            "top_cap": 3 * (3 + nu) * p2 * rb**2 / (8 * f.top_cap_mm**2),
            "base": 3 * (3 + nu) * p2 * rb**2 / (8 * f.base_mm**2),
        }

    def wall_safety_factors(self) -> dict[str, float]:
        """Yield strength over peak stress, per wall."""
        sy = get_material(self.fixed.housing_material).yield_MPa
        return {k: (sy / s if s > 0 else math.inf) for k, s in self.wall_stresses_MPa().items()}

    def minimum_walls_mm(self, safety_factor: float = 2.0) -> dict[str, float]:
        """Thinnest walls that carry the peak pressure with ``safety_factor`` (same formulas inverted), mm."""
        p2 = self.peak_pressures_MPa()["chamber_2"]
        f = self.fixed
        mat = get_material(f.housing_material)
        allow = mat.yield_MPa / safety_factor
        if allow <= p2:
            return {k: math.inf for k in ("outer_tube", "inner_tube", "top_cap", "base")}
        rb = self.outer_bore_radius_mm
        ro_min = rb * math.sqrt((allow + p2) / (allow - p2))  # Lamé internal
        ri = self.piston_diameter_mm / 2
        ri_out_min = ri * math.sqrt(allow / (allow - 2 * p2)) if allow > 2 * p2 else math.inf  # Lamé external
        plate_t = math.sqrt(3 * (3 + mat.poisson) * p2 * rb**2 / (8 * allow))
        return {"outer_tube": ro_min - rb, "inner_tube": ri_out_min - ri, "top_cap": plate_t, "base": plate_t}

    # ------------------------------------------------------------------- mass
    def mass_breakdown_g(self) -> dict[str, float]:
        """Mass estimate per component from closed-form volumes, g."""
        f = self.fixed
        rho_h = get_material(f.housing_material).density_g_per_mm3
        rho_r = get_material(f.rod_material).density_g_per_mm3
        rho_s = get_material(f.support_ring_material).density_g_per_mm3
        pi = math.pi
        ro, rb = self.outer_diameter_mm / 2, self.outer_bore_radius_mm
        ri_in, ri_out = self.piston_diameter_mm / 2, self.inner_tube_outer_radius_mm
        L = self.inner_length_mm
        bladder_len = self.bladder_free_length_mm + 2 * f.bladder_clamp_mm
        return {
            "outer_tube": pi * (ro**2 - rb**2) * L * rho_h,
            "end_caps": pi * ro**2 * (f.top_cap_mm + f.base_mm) * rho_h,
            "inner_tube": pi * (ri_out**2 - ri_in**2) * L * rho_h,
            "piston": pi * ri_in**2 * f.piston_height_mm * rho_h,
            "rod": pi / 4 * f.rod_diameter_mm**2 * self.rod_length_mm * rho_r,
            "bladder": 2 * pi * self.bladder_mid_radius_mm * f.bladder_thickness_mm * bladder_len * DENSITY_SILICONE_g_per_mm3,
            "support_ring": pi * (rb**2 - ri_out**2) * f.bladder_clamp_mm * 0.5 * rho_s,
            "fluid": max(self.fluid_volume_mm3, 0.0) * DENSITY_HYDRAULIC_OIL_g_per_mm3,
            "servo_and_valve": f.servo_and_valve_mass_g,
        }

    @property
    def mass_g(self) -> float:
        return float(sum(self.mass_breakdown_g().values()))

    # ---------------------------------------------------------------- export
    def decision_vector(self) -> np.ndarray:
        return np.array([getattr(self, n) for n in DECISION_VARIABLES], dtype=float)

    def geometry_summary(self) -> dict[str, float]:
        """Derived geometry (mm, mm², mm³) for the design JSON and the CAD."""
        return {
            "outer_bore_radius_mm": self.outer_bore_radius_mm,
            "inner_tube_outer_radius_mm": self.inner_tube_outer_radius_mm,
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
            "V2_capacity_mm3": self.V2_capacity_mm3,
            "fluid_volume_mm3": self.fluid_volume_mm3,
        }
