"""The spring curve of a design: isothermal and adiabatic force, deviation from
the least-squares line and chamber pressures over the stroke (what the unit
report of a designed unit draws).

Units: mm, N, MPa; x > 0 extends the pull spring, force > 0 is tension.
"""

from __future__ import annotations

from dataclasses import dataclass, replace
from typing import Any

import numpy as np

from .gas_spring import GasSpring

__all__ = ["ADIABATIC_N", "SpringCurve", "spring_curve"]

#: Polytropic exponent of the adiabatic curve shown beside the isothermal one.
ADIABATIC_N = 1.4


@dataclass(frozen=True)
class SpringCurve:
    """Force, deviation from the least-squares line and chamber pressures over the stroke.

    Arrays are sampled on ``x_mm``; the isothermal (n = 1) and adiabatic
    (n = 1.4) curves start from the same charge at x = 0.
    """

    x_mm: np.ndarray  #: displacement over the travel (mm), x > 0 extends the pull spring
    force_isothermal_N: np.ndarray  #: force at n = 1 (N), tension > 0
    force_adiabatic_N: np.ndarray  #: force at n = 1.4 (N), tension > 0
    deviation_isothermal_N: np.ndarray  #: force minus its least-squares line, n = 1 (N)
    deviation_adiabatic_N: np.ndarray  #: force minus its least-squares line, n = 1.4 (N)
    stiffness_isothermal_N_per_mm: float  #: least-squares slope at n = 1 (N/mm)
    stiffness_adiabatic_N_per_mm: float  #: least-squares slope at n = 1.4 (N/mm)
    linearity_isothermal: float  #: max |deviation| / force span at n = 1 (fraction)
    linearity_adiabatic: float  #: max |deviation| / force span at n = 1.4 (fraction)
    P1_isothermal_MPa: np.ndarray  #: chamber-1 pressure at n = 1 (MPa)
    P2_isothermal_MPa: np.ndarray  #: chamber-2 pressure at n = 1 (MPa)
    P1_adiabatic_MPa: np.ndarray  #: chamber-1 pressure at n = 1.4 (MPa)
    P2_adiabatic_MPa: np.ndarray  #: chamber-2 pressure at n = 1.4 (MPa)

    def to_dict(self) -> dict[str, Any]:
        """JSON-ready content (lists of floats).

        Returns
        -------
        dict
            Every field; arrays as lists, units in the keys.
        """
        return {k: (v.tolist() if isinstance(v, np.ndarray) else float(v)) for k, v in self.__dict__.items()}


def spring_curve(spring: GasSpring, num: int = 401) -> SpringCurve:
    """The isothermal and adiabatic force curves of ``spring`` with deviations and pressures.

    Parameters
    ----------
    spring : GasSpring
        The unit's gas spring (mm, mm², mm³, MPa) as charged at x = 0.
    num : int
        Samples over the travel for the curves (the linearity and stiffness are the exact,
        continuous metric of :meth:`GasSpring.linearity`).

    Returns
    -------
    SpringCurve
        Forces in N, pressures in MPa, stiffness in N/mm, linearity as a fraction.
    """
    x = spring.x_mm(num)
    iso = replace(spring, n_polytropic=1.0)
    adi = replace(spring, n_polytropic=ADIABATIC_N)
    out: dict[str, Any] = {"x_mm": x}
    for tag, gs in (("isothermal", iso), ("adiabatic", adi)):
        F = gs.force_N(x)
        lin = gs.linearity()
        k, b = float(lin.mean_stiffness_N_per_mm), float(lin.intercept_N)
        P1, P2 = gs.pressures_MPa(x)
        out[f"force_{tag}_N"] = F
        out[f"deviation_{tag}_N"] = F - (k * x + b)
        out[f"stiffness_{tag}_N_per_mm"] = k
        out[f"linearity_{tag}"] = float(lin.linearity_error)
        out[f"P1_{tag}_MPa"] = np.asarray(P1, float)
        out[f"P2_{tag}_MPa"] = np.asarray(P2, float)
    return SpringCurve(**out)
