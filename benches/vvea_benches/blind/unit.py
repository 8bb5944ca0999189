"""The unit on the bench: base physics of the spring–damper unit, written from the paper's design.

What every campaign of the blind bench holds before any mechanism is switched on:

- **Gas spring** — two antagonistic chambers (paper eq. 5) with the paper's reference geometry
  (:data:`vvea_design.spring.paper.PAPER_FIG5`: chamber 2 on the 30 mm working piston, chamber 1
  on the 57.1 mm bore, V1 = 1.22e5 mm³) and a chamber-2 gas volume V2 that varies by ±10 % with
  the oil fill (paper section 3.2.4: the oil volume sets V2). p1 follows eq. 7 (zero force at
  x = 0). The gas is isothermal (the paper's law); ``gas_law="linear"`` replaces eq. 5 by the
  straight line ``g p2 x`` (the strict null campaigns: eq. 14 holds exactly).
- **Throttle** — laminar: the damping force is ``L(γ) ẋ`` with ``L`` per valve roughly like the
  paper's Table 3 (each value scattered by ±10 %), and a continuous law between the valve
  angles (log ``L`` interpolated monotonically over γ) for a valve that is not exactly where it
  was commanded.
- **Seal friction** — Coulomb, 100–150 N (Table 2: 125 N), smoothed over 0.01 mm/s so that the
  force is single-valued at the start and at the reversal.

Units: mm, mm², mm³, MPa (= N/mm²), N, s. ``x > 0`` extends the pull spring and compresses
chamber 2; force > 0 is tension; the throttle and the friction oppose the motion.
"""

from __future__ import annotations

from dataclasses import asdict, dataclass

import numpy as np
from scipy.interpolate import PchipInterpolator

from vvea_design.spring.gas_spring import PAPER_FIG5

__all__ = [
    "VALVES_DEG",
    "PRESETS_MPA",
    "SPEEDS_MM_S",
    "TABLE3_L",
    "STROKE_MM",
    "BaseUnit",
    "sample_base",
    "smooth_sign",
]

#: The paper's campaign (section 4.1).
VALVES_DEG = (50.0, 80.0, 100.0, 104.0, 106.0, 108.0, 109.0, 110.0, 120.0)
PRESETS_MPA = (1.0, 2.0, 4.0)
SPEEDS_MM_S = (0.1, 1.0, 4.0, 8.0, 12.0)
STROKE_MM = 40.0
#: Table 3: linear damping per valve angle, N s/mm.
TABLE3_L = (0.4, 0.5, 7.1, 15.1, 25.3, 40.6, 52.7, 85.2, 1024.7)


def smooth_sign(v, eps_mm_s: float = 0.01):
    """Sign of the velocity, smoothed over ``eps_mm_s`` (a single-valued Coulomb law).

    Parameters
    ----------
    v : array_like
        Velocity, mm/s.
    eps_mm_s : float
        Velocity over which the sign goes from -1 to +1, mm/s.

    Returns
    -------
    numpy.ndarray
        ``tanh(v / eps)``, dimensionless, in [-1, 1].
    """
    return np.tanh(np.asarray(v, dtype=float) / eps_mm_s)


@dataclass(frozen=True)
class BaseUnit:
    """Base physics of one simulated unit (see the module docstring)."""

    gas_law: str  #: "chambers" (paper eq. 5) or "linear" (g p2 x)
    A1_mm2: float  #: chamber-1 area (expands as x grows), mm²
    A2_mm2: float  #: chamber-2 area (compressed as x grows), mm²
    V1_mm3: float  #: chamber-1 gas volume at x = 0, mm³
    V2_mm3: float  #: chamber-2 gas volume at x = 0, mm³
    g_N_per_mm_MPa: float  #: stiffness per MPa of the linear law, N/mm/MPa
    L_N_s_per_mm: tuple  #: laminar damping per valve of VALVES_DEG, N s/mm
    C_N: float  #: Coulomb friction, N
    friction_eps_mm_s: float = 0.01  #: smoothing velocity of the Coulomb sign, mm/s

    def __post_init__(self) -> None:
        if self.gas_law not in ("chambers", "linear"):
            raise ValueError(f"BaseUnit.gas_law must be 'chambers' or 'linear', got {self.gas_law!r}")
        if len(self.L_N_s_per_mm) != len(VALVES_DEG):
            raise ValueError(f"BaseUnit.L_N_s_per_mm needs {len(VALVES_DEG)} values, got {len(self.L_N_s_per_mm)}")
        if self.V2_mm3 <= self.A2_mm2 * STROKE_MM:
            raise ValueError(f"BaseUnit.V2_mm3 = {self.V2_mm3} bottoms chamber 2 out within the stroke")

    def damping_N_s_per_mm(self, valve_deg) -> np.ndarray:
        """Laminar damping ``L(γ)`` at any valve angle (log L interpolated monotonically).

        Parameters
        ----------
        valve_deg : float or array_like
            Actual valve angle, degree; clipped to the table's 50–120°.

        Returns
        -------
        numpy.ndarray
            Damping coefficient, N s/mm (> 0).
        """
        interp = PchipInterpolator(np.array(VALVES_DEG), np.log(np.array(self.L_N_s_per_mm)))
        g = np.clip(np.asarray(valve_deg, dtype=float), VALVES_DEG[0], VALVES_DEG[-1])
        return np.exp(interp(g))

    def p1_MPa(self, p2_MPa):
        """Chamber-1 charge from eq. 7 (zero spring force at x = 0).

        Parameters
        ----------
        p2_MPa : float or array_like
            Chamber-2 charge, MPa.

        Returns
        -------
        float or numpy.ndarray
            Chamber-1 charge ``A2/A1 p2``, MPa.
        """
        return self.A2_mm2 / self.A1_mm2 * np.asarray(p2_MPa, dtype=float)

    def chamber_pressures_MPa(self, x_mm, p2_MPa, f2=1.0, f1=1.0):
        """Isothermal chamber pressures ``(P1, P2)`` at displacement ``x``.

        Parameters
        ----------
        x_mm : array_like
            Piston displacement, mm (x > 0 compresses chamber 2).
        p2_MPa : float
            Chamber-2 preset, MPa (chamber 1 from eq. 7).
        f2, f1 : float or array_like
            Factors on the charges of chamber 2 and chamber 1 (1 = the preset), dimensionless.

        Returns
        -------
        P1, P2 : numpy.ndarray
            Absolute pressures, MPa.
        """
        x = np.asarray(x_mm, dtype=float)
        P2 = f2 * p2_MPa * self.V2_mm3 / (self.V2_mm3 - self.A2_mm2 * x)
        P1 = f1 * self.p1_MPa(p2_MPa) * self.V1_mm3 / (self.V1_mm3 + self.A1_mm2 * x)
        return P1, P2

    def gas_force_N(self, x_mm, p2_MPa, f2=1.0, f1=1.0) -> np.ndarray:
        """Spring force of the gas: eq. 5 (``A2 P2 - A1 P1``) or the straight line ``g p2 x``.

        Parameters
        ----------
        x_mm : array_like
            Piston displacement, mm.
        p2_MPa : float
            Chamber-2 preset, MPa.
        f2, f1 : float or array_like
            Factors on the charges of chamber 2 and chamber 1, dimensionless. For the linear law
            their mean scales the line.

        Returns
        -------
        numpy.ndarray
            Force, N (tension > 0).
        """
        x = np.asarray(x_mm, dtype=float)
        if self.gas_law == "linear":
            return 0.5 * (np.asarray(f1) + np.asarray(f2)) * self.g_N_per_mm_MPa * p2_MPa * x
        P1, P2 = self.chamber_pressures_MPa(x, p2_MPa, f2, f1)
        return self.A2_mm2 * P2 - self.A1_mm2 * P1

    def friction_sign(self, v_mm_s) -> np.ndarray:
        """Smoothed sign of the velocity for the Coulomb law, dimensionless.

        Parameters
        ----------
        v_mm_s : array_like
            Piston velocity, mm/s.

        Returns
        -------
        numpy.ndarray
            ``tanh(v / friction_eps_mm_s)``.
        """
        return smooth_sign(v_mm_s, self.friction_eps_mm_s)

    def to_dict(self) -> dict:
        """Plain-JSON form.

        Returns
        -------
        dict
            The fields, tuples as lists.
        """
        d = asdict(self)
        d["L_N_s_per_mm"] = list(self.L_N_s_per_mm)
        d["valves_deg"] = list(VALVES_DEG)
        return d


def sample_base(rng: np.random.Generator, gas_law: str = "chambers") -> BaseUnit:
    """Draw one unit's base physics.

    Parameters
    ----------
    rng : numpy.random.Generator
        Source of randomness (the campaign's seed).
    gas_law : str
        "chambers" (eq. 5) or "linear" (g p2 x, the strict null).

    Returns
    -------
    BaseUnit
        Paper geometry with V2 × U(0.9, 1.1) (oil-fill tolerance), Table 3 damping × U(0.9, 1.1)
        per valve, Coulomb friction U(100, 150) N, linear stiffness U(21, 25) N/mm/MPa (the
        chambers' mean stiffness per MPa is about 23).
    """
    L = tuple(float(v * rng.uniform(0.9, 1.1)) for v in TABLE3_L)
    return BaseUnit(
        gas_law=gas_law,
        A1_mm2=float(PAPER_FIG5.A1_mm2),
        A2_mm2=float(PAPER_FIG5.A2_mm2),
        V1_mm3=float(PAPER_FIG5.V1_mm3),
        V2_mm3=float(PAPER_FIG5.V2_mm3 * rng.uniform(0.9, 1.1)),
        g_N_per_mm_MPa=float(rng.uniform(21.0, 25.0)),
        L_N_s_per_mm=L,
        C_N=float(rng.uniform(100.0, 150.0)),
    )
