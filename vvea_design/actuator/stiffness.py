"""The design's charge for a wanted joint stiffness, inside the unit's pressure limits.

The unit's stiffness is set by its charge: with p1 following p2 through the set point (paper eq. 6),
every chamber pressure, and so the force and its least-squares slope k, is proportional to p2. Through
the tendon pulley (section 3.4) the joint stiffness is ``K = n_units r² k``, so ``K(p2) = K_full p2 /
p2_full``. :func:`charge_for_stiffness` picks the charge that gives a target K and checks it against the
unit's pressure limits:

* **highest charge**: neither chamber may be charged above ``max_charge_MPa`` (the charge its walls and
  joints are sized for; by default the design's own charge, which the optimiser sets to the requirements'
  ``max_charge_MPa``);
* **lowest pressure**: neither chamber may fall below ``min_pressure_MPa`` anywhere on the stroke (default
  atmospheric pressure, 0.101325 MPa absolute: below it the unit would draw air in past its seals and the
  sealed-charge gas law no longer holds).

A target outside ``[K at the lowest charge, K at the highest]`` is clamped to the nearest end and the
limit that binds is named (:class:`ChargeChoice`).
"""

from __future__ import annotations

import math
from dataclasses import asdict, dataclass

import numpy as np

from ..messages import show
from ..spring.gas_spring import GasSpring

__all__ = ["ATMOSPHERE_MPA", "PAPER_K_NM_PER_RAD", "ChargeChoice", "charge_for_stiffness"]

#: Standard atmosphere, MPa (absolute): the default lowest chamber pressure.
ATMOSPHERE_MPA = 0.101325
#: The paper's joint stiffness of VVEA, iVVEA and SEA (Table 4), N m/rad: the default target.
PAPER_K_NM_PER_RAD = 362.0


@dataclass(frozen=True)
class ChargeChoice:
    """The charge chosen for a target joint stiffness (:func:`charge_for_stiffness`)."""

    target_K_Nm_per_rad: float  #: the wanted joint stiffness
    K_Nm_per_rad: float  #: the joint stiffness at the chosen charge (= the target when in range)
    p2_MPa: float  #: chosen chamber-2 charge (absolute, at x = 0)
    p1_MPa: float  #: chamber-1 charge that follows from the set point (absolute, at x = 0)
    k_N_per_mm: float  #: the unit's mean stiffness at the chosen charge
    K_full_Nm_per_rad: float  #: joint stiffness at the highest allowed charge
    K_lowest_Nm_per_rad: float  #: joint stiffness at the lowest allowed charge
    p2_full_MPa: float  #: chamber-2 charge at the highest allowed charge
    p2_lowest_MPa: float  #: chamber-2 charge at the lowest allowed charge
    max_charge_MPa: float  #: highest charge of either chamber
    min_pressure_MPa: float  #: lowest pressure of either chamber over the stroke
    in_range: bool  #: the target lies inside the unit's range
    binding_limit: str | None  #: None in range; else which limit stops the charge (a sentence)

    def to_dict(self) -> dict:
        """Plain-JSON dictionary.

        Returns
        -------
        dict
            Field name to value: stiffnesses in N m/rad and N/mm, pressures in MPa (absolute), ``in_range``
            and ``binding_limit`` (None or a sentence naming the limit).
        """
        return asdict(self)

    def describe(self) -> str:
        """One sentence for a report: the target, the charge chosen and, when clamped, the limit that binds.

        Returns
        -------
        str
            E.g. ``"K = 362 N m/rad (target 362) at p2 = 1.95 MPa (full charge 4 MPa gives 761 N m/rad)"``.
        """
        s = (f"K = {self.K_Nm_per_rad:.4g} N m/rad (target {self.target_K_Nm_per_rad:.4g}) at p2 = "
             f"{self.p2_MPa:.3g} MPa, p1 = {self.p1_MPa:.3g} MPa (the unit spans {self.K_lowest_Nm_per_rad:.3g}-"
             f"{self.K_full_Nm_per_rad:.4g} N m/rad between its pressure limits)")
        return s if self.in_range else s + f"; the target is out of range: {self.binding_limit}"


def _pressure_ratios(spring: GasSpring, num: int = 401) -> tuple[float, float]:
    """(p1/p2 at x = 0, lowest chamber pressure over the stroke / p2) of ``spring``: both do not depend on p2."""
    x = np.linspace(0.0, spring.travel_mm, num)
    P1, P2 = spring.pressures_MPa(x)
    lowest = float(min(np.min(P1), np.min(P2)))
    return spring.p1_MPa / spring.p2_MPa, lowest / spring.p2_MPa


def charge_for_stiffness(
    spring: GasSpring,
    target_K_Nm_per_rad: float = PAPER_K_NM_PER_RAD,
    *,
    pulley_radius_m: float,
    n_units: int = 2,
    max_charge_MPa: float | None = None,
    min_pressure_MPa: float = ATMOSPHERE_MPA,
    setpoint_x0_mm: float = 0.0,
) -> ChargeChoice:
    """The chamber-2 charge that gives the joint stiffness ``target_K_Nm_per_rad``, within the pressure limits.

    Parameters
    ----------
    spring
        The unit's gas spring at any charge (its geometry and set point matter; mm, MPa).
    target_K_Nm_per_rad
        Wanted joint stiffness, N m/rad (default the paper's 362).
    pulley_radius_m
        Tendon-pulley radius r, m.
    n_units
        Pre-loaded units on the pulley (count).
    max_charge_MPa
        Highest charge of either chamber, MPa (absolute); default the spring's own charge ``max(p1, p2)``
        (the charge the unit is sized for).
    min_pressure_MPa
        Lowest absolute pressure either chamber may reach over the stroke, MPa (default atmospheric).
    setpoint_x0_mm
        Displacement of zero force (eq. 6), mm: p1 follows p2 through it.

    Returns
    -------
    ChargeChoice
        The charge (MPa), the stiffness it gives (N m/rad, N/mm), the unit's stiffness range and, when the
        target is out of range, the limit that binds.

    Raises
    ------
    ValueError
        When a number is not positive and finite, or the limits leave no charge (``min_pressure_MPa`` above
        what ``max_charge_MPa`` allows).
    """
    for name, v in (("target_K_Nm_per_rad", target_K_Nm_per_rad), ("pulley_radius_m", pulley_radius_m),
                    ("min_pressure_MPa", min_pressure_MPa)):
        if isinstance(v, bool) or not isinstance(v, (int, float)) or not math.isfinite(v) or v <= 0:
            raise ValueError(f"{name} must be a positive number, got {show(v)}")
    if int(n_units) != n_units or n_units < 1:
        raise ValueError(f"n_units must be a whole number >= 1, got {show(n_units)}")
    ref = spring.with_pressures(spring.p2_MPa, setpoint_x0_mm)
    if max_charge_MPa is None:
        max_charge_MPa = max(ref.p1_MPa, ref.p2_MPa)
    if isinstance(max_charge_MPa, bool) or not math.isfinite(max_charge_MPa) or max_charge_MPa <= 0:
        raise ValueError(f"max_charge_MPa must be a positive pressure in MPa, got {show(max_charge_MPa)}")
    c1, lowest_per_p2 = _pressure_ratios(ref)
    if not (c1 > 0 and lowest_per_p2 > 0):
        raise ValueError(f"the spring's chamber pressures must stay positive over the stroke (p1/p2 = {c1:.3g}, "
                         f"lowest/p2 = {lowest_per_p2:.3g})")
    p2_hi = max_charge_MPa / max(1.0, c1)
    p2_lo = min_pressure_MPa / lowest_per_p2
    if p2_lo > p2_hi:
        raise ValueError(f"no charge fits: keeping every chamber above {min_pressure_MPa:g} MPa needs p2 >= "
                         f"{p2_lo:.3g} MPa, the highest charge {max_charge_MPa:g} MPa allows p2 <= {p2_hi:.3g} MPa")
    r2n = n_units * pulley_radius_m**2 * 1e3  # N/mm -> N m/rad
    k_per_p2 = ref.mean_stiffness_N_per_mm() / ref.p2_MPa  # k is proportional to p2 (p1 = c1 p2)
    K_hi, K_lo = r2n * k_per_p2 * p2_hi, r2n * k_per_p2 * p2_lo
    p2 = target_K_Nm_per_rad / (r2n * k_per_p2)
    binding = None
    if p2 > p2_hi * (1 + 1e-12):
        chamber = "chamber 1 (p1)" if c1 > 1.0 else "chamber 2 (p2)"
        binding = (f"highest charge: {chamber} would need {p2 * max(1.0, c1):.3g} MPa > max_charge_MPa = "
                   f"{max_charge_MPa:g} MPa; the unit reaches at most K = {K_hi:.4g} N m/rad")
        p2 = p2_hi
    elif p2 < p2_lo * (1 - 1e-12):
        binding = (f"lowest pressure: a chamber would fall to {p2 * lowest_per_p2:.3g} MPa over the stroke < "
                   f"min_pressure_MPa = {min_pressure_MPa:g} MPa; the unit reaches at least K = {K_lo:.4g} N m/rad")
        p2 = p2_lo
    charged = ref.with_pressures(p2, setpoint_x0_mm)
    k = charged.mean_stiffness_N_per_mm()
    return ChargeChoice(
        target_K_Nm_per_rad=float(target_K_Nm_per_rad), K_Nm_per_rad=float(r2n * k), p2_MPa=float(p2),
        p1_MPa=float(charged.p1_MPa), k_N_per_mm=float(k), K_full_Nm_per_rad=float(K_hi),
        K_lowest_Nm_per_rad=float(K_lo), p2_full_MPa=float(p2_hi), p2_lowest_MPa=float(p2_lo),
        max_charge_MPa=float(max_charge_MPa), min_pressure_MPa=float(min_pressure_MPa),
        in_range=binding is None, binding_limit=binding)
