"""Load cases of the FE check: the pressure of each space of the unit at one piston position.

A :class:`LoadCase` holds the pressure of chamber 1, chamber 2 and the fluid column (MPa, the spring side's
convention: as the charges, i.e. what the walls carry; the FE loads the walls with them and the outside is
at 0), the external (tendon) force, the piston displacement at which they act (it decides where the bore sees
gas and where fluid) and the safety factor on yield the case requires.

:func:`default_load_cases` takes the spring side's cases (:attr:`vvea_design.spring.design.Design.load_cases`:
``gas_full_stroke``, ``gas_rest``, ``retraction``, ``relief``, ``damping``, ``proof``) and places each at its
piston position (:data:`CASE_POSITION`: full stroke where chamber 2 peaks, x = 0 where chamber 1 does).

Pressures MPa, lengths mm, forces N.
"""

from __future__ import annotations

from dataclasses import dataclass, field

from ..spring.design import Design

__all__ = ["LoadCase", "default_load_cases", "CASE_POSITION"]

#: Where the piston is in each of the spring side's cases: ``"travel"`` (full stroke) or ``"rest"`` (x = 0).
#: ``retraction``: x = 0 (chamber 1 at its highest, the whole column under the piston cavitating); ``proof``:
#: full stroke (every face pressurised; the bore under the piston is the fluid's).
CASE_POSITION = {"gas_full_stroke": "travel", "gas_rest": "rest", "retraction": "rest", "relief": "travel",
                 "damping": "travel", "proof": "travel"}


@dataclass(frozen=True)
class LoadCase:
    """One load case: absolute pressures of the unit's spaces at a piston displacement."""

    name: str
    x_mm: float  #: piston displacement, mm (x > 0 moves the piston down)
    chamber_1_MPa: float
    chamber_2_MPa: float
    fluid_MPa: float  #: the column under the piston (the throttle's high side)
    required_safety: float  #: on yield, dimensionless
    what: str = ""  #: how the pressures were set (and the standard behind the factor)
    external_force_N: float = 0.0  #: tension on the unit's eyes (the top cap's joint carries it too), N
    standard: str = ""  #: where the case and its factor come from
    walls: tuple[str, ...] = field(default=())  #: walls it governs (empty: every wall is checked under it)

    def gauge_MPa(self) -> dict[str, float]:
        """The pressure each space puts on the walls, MPa.

        Returns
        -------
        dict of str to float
            ``chamber_1``, ``chamber_2``, ``fluid``, MPa.
        """
        return {"chamber_1": self.chamber_1_MPa, "chamber_2": self.chamber_2_MPa, "fluid": self.fluid_MPa}

    def to_dict(self) -> dict:
        """JSON-ready content.

        Returns
        -------
        dict
            Name, displacement (mm), pressures (MPa), external force (N), required safety factor, description,
            standard.
        """
        return {"name": self.name, "x_mm": self.x_mm, "chamber_1_MPa": self.chamber_1_MPa,
                "chamber_2_MPa": self.chamber_2_MPa, "fluid_MPa": self.fluid_MPa,
                "external_force_N": self.external_force_N, "required_safety": self.required_safety,
                "what": self.what, "standard": self.standard, "walls": list(self.walls)}


def default_load_cases(design: Design) -> tuple[LoadCase, ...]:
    """The spring side's load cases of a design, each at its piston position.

    Parameters
    ----------
    design : Design
        The unit (:attr:`~vvea_design.spring.design.Design.load_cases`: pressures in MPa, forces in N, the
        safety factor each case requires).

    Returns
    -------
    tuple of LoadCase
        One per case of the design, in its order; a case the table :data:`CASE_POSITION` does not know is put
        at full stroke.
    """
    T = design.fixed.travel_mm
    out = []
    for c in design.load_cases.cases:
        x = 0.0 if CASE_POSITION.get(c.name, "travel") == "rest" else T
        out.append(LoadCase(c.name, x, float(c.chamber_1_MPa), float(c.chamber_2_MPa), float(c.fluid_MPa),
                            float(c.required_safety_factor), c.what, float(c.external_force_N), c.standard))
    return tuple(out)
