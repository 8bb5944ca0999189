"""Load cases of the FE check: the pressure of each space of the unit at one piston position.

A :class:`LoadCase` holds the absolute pressure of chamber 1, chamber 2 and the fluid column (MPa, as the
spring side states them), the piston displacement at which they act (it decides where the bore sees gas and
where fluid) and the safety factor on yield the case requires. The FE loads the walls with gauge pressure,
``p - P_ATM_MPa`` (the atmosphere is outside).

:func:`default_load_cases` gives the cases of today's sizing, until the spring side publishes its own (the
governing case per piece with its safety factor and the fluid pressure of the damper's relief valve):

* ``gas_peak``: full stroke at the adiabatic peak (``fixed.wall_sizing_n``): chamber 2 at its highest, chamber
  1 at its lowest, the fluid at chamber-2 pressure (no flow);
* ``gas_charge``: x = 0 at the charge (chamber 1 at its highest; it governs the walls between the chambers
  when ``p1 > p2``);
* ``fluid_relief``: full stroke at the gas peak with the fluid column at chamber 2 plus an overpressure (the
  pressure the throttle and the relief valve make while the piston is pushed down), by default the force
  :data:`DEFAULT_DAMPER_FORCE_N` over the piston's annulus A2.

Pressures MPa, lengths mm, forces N.
"""

from __future__ import annotations

from dataclasses import dataclass, field

from ..spring.derive import peak_pressures
from ..spring.design import Design

__all__ = ["LoadCase", "default_load_cases", "P_ATM_MPa", "DEFAULT_DAMPER_FORCE_N"]

#: Standard atmosphere, MPa (outside the unit; the gauge pressure on a wall is the absolute minus this).
P_ATM_MPa = 0.101325

#: Largest damping force the fluid column carries in ``fluid_relief`` until the spring side states the relief
#: valve's setting, N (the upper end of the relief forces estimated for examples/paper_tight.toml).
DEFAULT_DAMPER_FORCE_N = 4000.0


@dataclass(frozen=True)
class LoadCase:
    """One load case: absolute pressures of the unit's spaces at a piston displacement."""

    name: str
    x_mm: float  #: piston displacement, mm (x > 0 moves the piston down)
    chamber_1_MPa: float  #: absolute
    chamber_2_MPa: float  #: absolute
    fluid_MPa: float  #: absolute, the column under the piston (the throttle's high side)
    required_safety: float  #: on yield, dimensionless
    what: str = ""  #: how the pressures were set (and the standard behind the factor)
    walls: tuple[str, ...] = field(default=())  #: walls it governs (empty: every wall is checked under it)

    def gauge_MPa(self) -> dict[str, float]:
        """Gauge pressure of each space, MPa.

        Returns
        -------
        dict of str to float
            ``chamber_1``, ``chamber_2``, ``fluid``: absolute minus :data:`P_ATM_MPa`, MPa.
        """
        return {"chamber_1": self.chamber_1_MPa - P_ATM_MPa, "chamber_2": self.chamber_2_MPa - P_ATM_MPa,
                "fluid": self.fluid_MPa - P_ATM_MPa}

    def to_dict(self) -> dict:
        """JSON-ready content.

        Returns
        -------
        dict
            Name, displacement (mm), absolute pressures (MPa), required safety factor, description.
        """
        return {"name": self.name, "x_mm": self.x_mm, "chamber_1_MPa": self.chamber_1_MPa,
                "chamber_2_MPa": self.chamber_2_MPa, "fluid_MPa": self.fluid_MPa,
                "required_safety": self.required_safety, "what": self.what, "walls": list(self.walls)}


def default_load_cases(design: Design, damper_force_N: float = DEFAULT_DAMPER_FORCE_N) -> tuple[LoadCase, ...]:
    """Today's cases: the gas peak, the charge, and the fluid column under a damping force.

    Parameters
    ----------
    design : Design
        The unit (its charge, volumes, travel and wall-sizing exponent).
    damper_force_N : float
        Damping force the fluid column carries in ``fluid_relief``, N (its pressure over A2 adds to chamber 2).

    Returns
    -------
    tuple of LoadCase
        ``gas_peak``, ``gas_charge``, ``fluid_relief``; each requires ``fixed.wall_safety_factor``.
    """
    f = design.fixed
    pr = peak_pressures(design.A1_mm2, design.A2_mm2, design.V1_mm3, design.V2_mm3, design.p2_MPa,
                        design.setpoint_x0_mm, f)
    p1, P2, P1min = float(pr.p1_MPa), float(pr.peak_chamber_2_MPa), float(pr.min_chamber_1_MPa)
    T, sf = f.travel_mm, f.wall_safety_factor
    n = max(f.n_polytropic, f.wall_sizing_n)
    dp = damper_force_N / design.A2_mm2
    return (
        LoadCase("gas_peak", T, P1min, P2, P2, sf,
                 f"full stroke, polytropic n = {n:g}: chamber 2 at its peak, chamber 1 at its lowest, fluid at "
                 "chamber-2 pressure"),
        LoadCase("gas_charge", 0.0, p1, design.p2_MPa, design.p2_MPa, sf,
                 "x = 0 at the charge: chamber 1 at its highest"),
        LoadCase("fluid_relief", T, P1min, P2, P2 + dp, sf,
                 f"full stroke at the gas peak, the fluid column {dp:.2f} MPa above chamber 2 "
                 f"({damper_force_N:g} N of damping over A2)"),
    )
