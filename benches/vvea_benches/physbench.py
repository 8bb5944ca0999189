"""An independent tension-test bench, simulated from physics.

This module exists to *prove* the diagnosis (``shared/specs/diagnosis-report.md``,
section "Proof"): it must never share a formula with the candidates of the
effect catalogue, so it imports nothing of ``vvea_design.identification``
(the effects, the fit, the diagnosis) nor ``vvea_benches.testbench`` (a test
checks that). It simulates the paper's
tension-test campaign (section 4: p2 x nine valve positions x five speeds,
0 -> travel -> 0 at constant speed, shuffled run order) on a unit given as a
:class:`~vvea_design.spring.design.Design` or a
:class:`~vvea_design.spring.gas_spring.GasSpring` (default: the paper's
reference unit :data:`~vvea_design.spring.paper.PAPER_FIG5`) and writes the
recordings in the exchange format of ``shared/specs/recordings.md``.

Physics (units: mm, mm², mm³, MPa = N/mm², N, s; SI inside the orifice laws)
---------------------------------------------------------------------------
The test machine imposes the displacement x(t) (its motion profile: constant
acceleration ``accel_mm_s2`` to the cruise speed, cruise, symmetric reversal).
The hydraulic fluid is incompressible, so the throttle carries Q = A2 ẋ and
the chamber volumes follow x: V1 = V1₀ + A1 x, V2 = V2₀ - A2 x.

* **Chamber thermodynamics** (per chamber, ideal gas, κ = cp/cv = 1.4)::

      m cv Ṫ = hA (T_w - T) - P V̇ + R T ṁ      (dU = dQ - p dV + h dm)

  written for θ = T / T_w and τ = m cv / (hA)::

      θ̇ = (1 - θ)/τ - (κ-1) θ V̇/V + (κ-1) θ ṁ/m,      P = P₀ (m/m₀) θ V₀/V

  τ -> 0 is the isothermal law of the paper's eq. 5, τ -> ∞ the adiabatic
  one (n = κ); in between stiffness and hysteresis depend on speed.
  Pressures are those of eq. 5 (the gas law applied to the preset, as the
  paper does); ``ambient_MPa > 0`` turns the presets into gauge pressures
  with the atmosphere acting on the rod.
* **Throttle**: orifice law Q = Cd(Re) A sqrt(2 Δp/ρ) with a discharge
  coefficient that depends on the flow regime, Cd(Re) = Cd∞ sqrt(Re/(Re+Re_c))
  (laminar, Cd ∝ sqrt(Re), below Re_c; turbulent, Cd -> Cd∞, above). With
  Re = u D/ν and u = Q/A this gives Δp = ρ/(2 Cd∞²) (Q|Q|/A² + Re_c ν Q/(A D)):
  linear in Q at low Reynolds number, quadratic at high. Damping force =
  A2 Δp. Each valve position γ has its own area A(γ) and Re_c(γ); they are
  drawn so that the laminar damping matches Table 3's L(γ) (randomised) and
  the turbulent part equals the laminar one at a transition speed v_t(γ).
* **Relief valve** (spring-loaded ball, one per flow direction, in parallel
  with the throttle): closed below the cracking pressure p_c; above it the
  ball lifts z = (|Δp| - p_c) A_seat / k_s (<= z_max), flow area π d_seat z,
  Q_r = Cd_r π d_seat z sqrt(2 |Δp|/ρ). Δp solves Q_throttle(Δp) + Q_r(Δp) = A2 ẋ
  (monotone; vectorised bisection).
* **Friction**: LuGre, ż = ẋ - σ0 |ẋ| z / g(ẋ), g = F_c + (F_s - F_c) exp(-|ẋ/v_s|^δ),
  F = σ0 z + σ1 ż + σ2 ẋ with σ1 = 2 sqrt(σ0 m_piston); optionally the seal
  preload grows with the charge, F_c = F_c0 + c_p p2 (F_s scales alike).
* **Leak**: chamber 2 loses mass through a laminar leak path, ṁ ∝ (P2 - p_amb),
  during the experiments and the pauses between them. Presets are realised
  by metering the gas relative to the campaign-start calibration, so lost
  gas is never made up: the p2 charge drifts down over campaign time.
* **Load string and sensor**: a force periodic in crosshead position (spindle
  ripple: amplitude, pitch, phase), a force periodic in campaign time
  (motor/mains-related ripple: amplitude, frequency, phase), a one-sided
  contact spring that loads the piston only while it extends
  (direction-dependent stiffness), a second-order force-sensor/amplifier
  filter (natural frequency, damping ratio; equivalent lag 2ζ/ω_n), and
  AR(1)-correlated force noise of a few N plus white displacement noise.

Integration: the motion is prescribed, so every state equation is linear in
its own state with coefficients known from x(t): θ̇ = a - bθ, ż = ẋ - cz, the
sensor filter ẏ = Ay + Bu. They are integrated on a fine grid (``substeps``
per sample interval; 0.014 mm of travel per step at the default sampling)
with the exponential integrator that is exact for coefficients frozen over
a step: unconditionally stable for the stiff bristle equation (σ0|ẋ|/g up to
1e4 1/s), first order in the coefficient variation. ``tests/identification/test_physbench.py``
checks it against ``scipy.integrate.solve_ivp`` (Radau) and the energy
balance. All experiments of a campaign are integrated together (vectorised).

Each effect is switchable (:data:`EFFECTS`); off means the idealisation the
paper's eq. 14 assumes: the isothermal curvature of eq. 5 replaced by its
least-squares line through the origin, isothermal gas, purely laminar
throttle, no relief, Coulomb friction (σ0 = 1e5 N/mm, F_s = F_c), no leak,
ideal sensor, no ripple, no contact spring. Parameters are drawn per
campaign from a seed (:func:`random_parameters`, ranges in
:data:`PARAMETER_RANGES`); :class:`BenchTruth` returns which effects were on,
their parameters, the noise and the noise-free force.

Example
-------
>>> from vvea_benches.physbench import random_parameters, simulate_campaign
>>> camp = simulate_campaign(random_parameters(("thermal",), seed=3))   # doctest: +SKIP
>>> camp.frame.head()                                                     # doctest: +SKIP
"""

from __future__ import annotations

import math
from dataclasses import asdict, dataclass, field
from pathlib import Path

import numpy as np
import pandas as pd

from vvea_design.spring.gas_spring import GasSpring
from vvea_design.spring.paper import PAPER_FIG5

from .physics import (
    KAPPA,
    chamber_states,
    damping_dp_MPa,
    discharge_coefficient,
    lugre_friction,
    orifice,
    relief_flow_mm3_s,
    second_order_filter,
    throttle_coefficients,
    throttle_dp_MPa,
    throttle_flow_mm3_s,
)

__all__ = [
    "CATALOGUE_EFFECTS",
    "OTHER_EFFECTS",
    "EFFECTS",
    "PARAMETER_RANGES",
    "TABLE3_L",
    "UnitGeometry",
    "CampaignGrid",
    "BenchParameters",
    "BenchTruth",
    "BenchCampaign",
    "unit_geometry",
    "motion_profile",
    "discharge_coefficient",
    "throttle_dp_MPa",
    "throttle_flow_mm3_s",
    "relief_flow_mm3_s",
    "damping_dp_MPa",
    "lugre_friction",
    "chamber_states",
    "random_parameters",
    "simulate_campaign",
    "write_campaign",
]

#: Effects the diagnosis catalogue names (spec ids).
CATALOGUE_EFFECTS = (
    "gas_nonlinearity",
    "thermal",
    "quadratic_damping",
    "relief_valve",
    "stiction",
    "pressure_friction",
    "leakage",
)
#: Physics no catalogue entry describes.
OTHER_EFFECTS = ("force_lag", "position_ripple", "time_ripple", "hysteresis", "direction_stiffness")
EFFECTS = CATALOGUE_EFFECTS + OTHER_EFFECTS

#: Table 3 of the paper: linear damping per valve position (N s/mm).
TABLE3_L: dict[float, float] = {
    50.0: 0.4, 80.0: 0.5, 100.0: 7.1, 104.0: 15.1, 106.0: 25.3, 108.0: 40.6, 109.0: 52.7, 110.0: 85.2, 120.0: 1024.7,
}

#: Ranges the randomised parameters are drawn from (uniform, or log-uniform
#: where marked), with the physical reason.
PARAMETER_RANGES: dict[str, tuple] = {
    "V2_fill_factor": (0.9, 1.1, "fluid fill tolerance moves V2 by ±10 %"),
    "L_log_sd": (0.15, None, "valve-to-valve manufacturing spread of Table 3's L(γ), log-normal sd"),
    "coulomb_N": (100.0, 150.0, "seal friction around the paper's 125.5 N"),
    "viscous_N_s_per_mm": (0.0, 0.02, "seal viscous friction σ2 (small against L)"),
    "stiction_ratio": (1.3, 2.0, "breakaway / Coulomb, elastomer seals"),
    "stribeck_speed_mm_s": (0.05, 1.0, "log-uniform; Stribeck velocity of lubricated seals"),
    "stribeck_exponent": (1.0, 2.0, "shape δ of the Stribeck curve"),
    "pressure_friction_N_per_MPa": (10.0, 35.0, "O-ring contact force grows with the charge"),
    "bristle_stiffness_N_per_mm": (60.0, 400.0, "log-uniform; seal pre-sliding: 0.3-2.5 mm of pre-sliding travel"),
    "thermal_tau_s": (0.5, 15.0, "log-uniform; thermal time constant m cv/(hA) of a 0.1 l gas chamber"),
    "thermal_tau1_factor": (0.5, 2.0, "chamber 1 / chamber 2 time constant"),
    "turbulent_transition_mm_s": (10.0, 100.0, "log-uniform; piston speed where the turbulent Δp equals the laminar one (turbulent part 10-100 % of the laminar one at 12 mm/s)"),
    "turbulent_valve_log_sd": (0.3, None, "spread of that speed over valve positions"),
    "relief_force_N": (1500.0, 4000.0, "cracking pressure x A2: the blow-off protects the unit above friction level"),
    "relief_spring_N_per_mm": (2.0, 20.0, "ball spring rate: sets the pressure override"),
    "leak_rate_per_h": (0.002, 0.015, "fraction of the charge lost per hour at the preset (2-13 % over the 9 h campaign)"),
    "sensor_lag_s": (0.02, 0.15, "log-uniform; equivalent lag 2ζ/ω_n of the load-cell amplifier (1-10 Hz bandwidth)"),
    "sensor_damping": (0.7, 1.0, "damping ratio ζ of the amplifier filter"),
    "position_ripple_N": (6.0, 25.0, "spindle ripple amplitude"),
    "position_ripple_pitch_mm": (2.0, 10.0, "lead-screw pitch"),
    "time_ripple_N": (6.0, 25.0, "time-periodic ripple amplitude"),
    "time_ripple_Hz": (0.05, 1.0, "log-uniform; drive/mains-related ripple seen at the recording's sample rate"),
    "contact_stiffness_N_per_mm": (1.0, 4.0, "one-sided contact spring engaged while extending"),
    "noise_N": (2.0, 5.0, "marginal RMS of the force noise"),
    "noise_rho": (0.3, 0.9, "AR(1) correlation of the force noise between samples"),
}

_COULOMB_SIGMA0 = 1.0e5  #: N/mm: bristles so stiff that LuGre is Coulomb friction


# ---------------------------------------------------------------- unit and grid
@dataclass(frozen=True)
class UnitGeometry:
    """Areas (mm²), gas volumes at x = 0 (mm³) and travel (mm) of a unit."""

    A1_mm2: float
    A2_mm2: float
    V1_mm3: float
    V2_mm3: float
    travel_mm: float

    def to_dict(self) -> dict:
        """Plain-JSON dictionary of the fields.

        Returns
        -------
        dict
            JSON-ready: ``A1_mm2`` and ``A2_mm2`` (mm²), ``V1_mm3`` and ``V2_mm3`` (mm³, at x = 0) and
            ``travel_mm`` (mm).
        """
        return asdict(self)


def unit_geometry(unit=None) -> UnitGeometry:
    """Geometry of a :class:`~vvea_design.spring.design.Design` or a
    :class:`~vvea_design.spring.gas_spring.GasSpring` (default: the paper's reference unit).

    Parameters
    ----------
    unit : Design, GasSpring, UnitGeometry or None
        The unit (areas mm², volumes mm³, travel mm); ``None`` is ``PAPER_FIG5``.

    Returns
    -------
    UnitGeometry
        Areas (mm²), gas volumes at x = 0 (mm³) and travel (mm).
    """
    unit = PAPER_FIG5 if unit is None else unit
    if isinstance(unit, UnitGeometry):
        return unit
    if isinstance(unit, GasSpring):
        return UnitGeometry(unit.A1_mm2, unit.A2_mm2, unit.V1_mm3, unit.V2_mm3, unit.travel_mm)
    try:  # a Design (duck-typed: areas, volumes, fixed.travel_mm)
        return UnitGeometry(float(unit.A1_mm2), float(unit.A2_mm2), float(unit.V1_mm3), float(unit.V2_mm3),
                            float(unit.fixed.travel_mm))
    except AttributeError:
        raise TypeError(f"unit must be a Design, a GasSpring or a UnitGeometry, got {type(unit).__name__}") from None


@dataclass(frozen=True)
class CampaignGrid:
    """What the bench runs: the paper's campaign by default, sampled like the shared recordings."""

    pressures_MPa: tuple = (1.0, 2.0, 4.0)
    valves_deg: tuple = tuple(TABLE3_L)
    speeds_mm_s: tuple = (0.1, 1.0, 4.0, 8.0, 12.0)
    samples: int = 301  #: samples per experiment (out and back)
    accel_mm_s2: float = 40.0  #: test machine acceleration at start and reversal
    pause_s: float = 60.0  #: time between experiments (recharging, settling)
    substeps: int = 20  #: integration steps per sample interval
    shuffle: bool = True

    @property
    def n_experiments(self) -> int:
        return len(self.pressures_MPa) * len(self.valves_deg) * len(self.speeds_mm_s)

    def to_dict(self) -> dict:
        """Plain-JSON dictionary of the fields.

        Returns
        -------
        dict
            JSON-ready: ``pressures_MPa`` (MPa), ``valves_deg`` (deg), ``speeds_mm_s`` (mm/s), ``samples``
            (per experiment), ``accel_mm_s2`` (mm/s²), ``pause_s`` (s), ``substeps`` (per sample interval)
            and ``shuffle``.
        """
        return asdict(self)


def motion_profile(t_s: np.ndarray, speed_mm_s: float, accel_mm_s2: float, travel_mm: float):
    """Displacement, velocity and acceleration of the machine's out-and-back ramp.

    Constant acceleration to ``speed``, cruise, symmetric reversal at
    ``travel`` (velocity zero there), and back to rest at 0; duration
    ``2 (travel/speed + speed/accel)``.

    Parameters
    ----------
    t_s : float or array
        Time since the start of the experiment (s).
    speed_mm_s : float
        Cruise speed (mm/s).
    accel_mm_s2 : float
        Acceleration at start and reversal (mm/s²).
    travel_mm : float
        Turning point (mm).

    Returns
    -------
    x_mm, v_mm_s, a_mm_s2 : arrays
        Displacement (mm), velocity (mm/s) and acceleration (mm/s²).
    """
    t = np.asarray(t_s, float)
    ta = speed_mm_s / accel_mm_s2
    t_rev = travel_mm / speed_mm_s + ta
    tm = np.clip(np.minimum(t, 2 * t_rev - t), 0.0, t_rev)  # mirror about the reversal
    x = np.where(tm < ta, 0.5 * accel_mm_s2 * tm**2,
                 np.where(tm < t_rev - ta, 0.5 * accel_mm_s2 * ta**2 + speed_mm_s * (tm - ta),
                          travel_mm - 0.5 * accel_mm_s2 * (t_rev - tm) ** 2))
    speed = np.where(tm < ta, accel_mm_s2 * tm, np.where(tm < t_rev - ta, speed_mm_s, accel_mm_s2 * (t_rev - tm)))
    out = t <= t_rev
    v = np.where(out, speed, -speed)
    acc = np.where(tm < ta, accel_mm_s2, np.where(tm < t_rev - ta, 0.0, -accel_mm_s2))
    return x, v, acc


# ---------------------------------------------------------------- parameters
@dataclass(frozen=True)
class BenchParameters:
    """Every physical parameter of one simulated campaign (see the module doc for the laws).

    ``effects`` lists the effects switched on; parameters of effects that are
    off are ignored (the idealisation is used instead).
    """

    effects: tuple = ()
    seed: int = 0  #: seed of the run order and the noise
    geometry: UnitGeometry = field(default_factory=lambda: unit_geometry(None))
    grid: CampaignGrid = field(default_factory=CampaignGrid)
    ambient_MPa: float = 0.0
    V2_fill_factor: float = 1.0
    L_N_s_per_mm: dict = field(default_factory=lambda: dict(TABLE3_L))  #: laminar damping per valve
    coulomb_N: float = 125.5  #: F_c at the mean charge (includes the pressure part when on)
    viscous_N_s_per_mm: float = 0.0
    stiction_ratio: float = 1.6
    stribeck_speed_mm_s: float = 0.3
    stribeck_exponent: float = 1.5
    pressure_friction_N_per_MPa: float = 20.0
    bristle_stiffness_N_per_mm: float = 150.0
    thermal_tau_s: float = 3.0  #: chamber 2
    thermal_tau1_s: float = 3.0  #: chamber 1
    turbulent_transition_mm_s: dict = field(default_factory=lambda: {g: 8.0 for g in TABLE3_L})
    relief_force_N: float = 2500.0  #: cracking pressure x A2
    relief_spring_N_per_mm: float = 8.0
    relief_seat_diameter_mm: float = 2.5
    relief_max_lift_mm: float = 0.5
    relief_cd: float = 0.6
    leak_rate_per_h: float = 0.01
    sensor_lag_s: float = 0.1
    sensor_damping: float = 0.8
    position_ripple_N: float = 12.0
    position_ripple_pitch_mm: float = 5.0
    position_ripple_phase: float = 0.0
    time_ripple_N: float = 12.0
    time_ripple_Hz: float = 0.2
    time_ripple_phase: float = 0.0
    contact_stiffness_N_per_mm: float = 2.0
    noise_N: float = 3.0
    noise_rho: float = 0.6
    displacement_noise_mm: float = 0.002

    def __post_init__(self) -> None:
        bad = [e for e in self.effects if e not in EFFECTS]
        if bad:
            raise ValueError(f"unknown effect(s) {bad}; known: {list(EFFECTS)}")

    def on(self, effect: str) -> bool:
        """Whether an effect is switched on in this campaign.

        Parameters
        ----------
        effect : str
            Effect id (one of the bench's ``EFFECTS``, e.g. ``"thermal"``).

        Returns
        -------
        bool
            True when ``effect`` is in :attr:`effects`; False for an effect that is off or unknown.
        """
        return effect in self.effects

    def effect_parameters(self) -> dict:
        """Parameters of the effects that are on, by effect id (physical units in the names).

        Returns
        -------
        dict of str to dict
            Effect id to its parameters, each name carrying its unit (e.g. ``thermal``: ``tau2_s``,
            ``tau1_s`` in s and ``kappa``, dimensionless; ``relief_valve``: ``cracking_force_N`` in N,
            ``cracking_dp_MPa`` in MPa, ``spring_N_per_mm``, ``seat_diameter_mm``; ``quadratic_damping``:
            the transition speed in mm/s per valve and the orifice table per valve, area in mm², hydraulic
            diameter in mm). Effects that are off are absent.
        """
        g = self.geometry
        out = {}
        for e in self.effects:
            if e == "gas_nonlinearity":
                out[e] = dict(V1_mm3=g.V1_mm3, V2_mm3=g.V2_mm3 * self.V2_fill_factor, A1_mm2=g.A1_mm2, A2_mm2=g.A2_mm2)
            elif e == "thermal":
                out[e] = dict(tau2_s=self.thermal_tau_s, tau1_s=self.thermal_tau1_s, kappa=KAPPA)
            elif e == "quadratic_damping":
                out[e] = dict(transition_speed_mm_s={str(k): v for k, v in self.turbulent_transition_mm_s.items()},
                              orifice=_orifice_table(self))
            elif e == "relief_valve":
                out[e] = dict(cracking_force_N=self.relief_force_N, cracking_dp_MPa=self.relief_force_N / g.A2_mm2,
                              spring_N_per_mm=self.relief_spring_N_per_mm, seat_diameter_mm=self.relief_seat_diameter_mm)
            elif e == "stiction":
                out[e] = dict(breakaway_ratio=self.stiction_ratio, stribeck_speed_mm_s=self.stribeck_speed_mm_s,
                              stribeck_exponent=self.stribeck_exponent)
            elif e == "pressure_friction":
                out[e] = dict(c_p_N_per_MPa=self.pressure_friction_N_per_MPa)
            elif e == "leakage":
                out[e] = dict(leak_rate_per_h=self.leak_rate_per_h)
            elif e == "force_lag":
                out[e] = dict(lag_s=self.sensor_lag_s, damping_ratio=self.sensor_damping,
                              natural_frequency_Hz=2 * self.sensor_damping / self.sensor_lag_s / (2 * math.pi))
            elif e == "position_ripple":
                out[e] = dict(amplitude_N=self.position_ripple_N, pitch_mm=self.position_ripple_pitch_mm,
                              phase_rad=self.position_ripple_phase)
            elif e == "time_ripple":
                out[e] = dict(amplitude_N=self.time_ripple_N, frequency_Hz=self.time_ripple_Hz,
                              phase_rad=self.time_ripple_phase)
            elif e == "hysteresis":
                k = self.bristle_stiffness_N_per_mm
                out[e] = dict(bristle_stiffness_N_per_mm=k, presliding_mm=self.coulomb_N / k)
            elif e == "direction_stiffness":
                out[e] = dict(contact_stiffness_N_per_mm=self.contact_stiffness_N_per_mm, engaged="extension")
        return out

    def to_dict(self) -> dict:
        """Plain-JSON dictionary of every parameter.

        Returns
        -------
        dict
            JSON-ready fields by name, units in the names (N, mm, MPa, s, Hz, rad): the nested
            ``geometry`` and ``grid`` as dicts, ``effects`` as a list, and the per-valve dicts
            ``L_N_s_per_mm`` (N s/mm) and ``turbulent_transition_mm_s`` (mm/s) keyed by the valve angle
            in deg as text.
        """
        d = asdict(self)
        d["L_N_s_per_mm"] = {str(k): v for k, v in self.L_N_s_per_mm.items()}
        d["turbulent_transition_mm_s"] = {str(k): v for k, v in self.turbulent_transition_mm_s.items()}
        d["effects"] = list(self.effects)
        return d


def _log_uniform(rng, lo, hi):
    return float(np.exp(rng.uniform(np.log(lo), np.log(hi))))


def random_parameters(effects=(), seed: int = 0, unit=None, grid: CampaignGrid | None = None) -> BenchParameters:
    """A campaign's bench with parameters drawn from :data:`PARAMETER_RANGES` (seeded).

    Every parameter is drawn, whether its effect is on or not, so that the
    same seed gives the same bench with and without an effect.

    Parameters
    ----------
    effects : sequence of str
        Effects to switch on (ids of :data:`EFFECTS`).
    seed : int
        Seed of the parameters, the run order and the noise (dimensionless).
    unit : Design, GasSpring or None
        The unit (default: the paper's reference unit).
    grid : CampaignGrid, optional
        What the bench runs (default: the paper's campaign).

    Returns
    -------
    BenchParameters
        Every physical parameter of the campaign.
    """
    rng = np.random.default_rng(seed)
    R = PARAMETER_RANGES
    u = lambda k: float(rng.uniform(R[k][0], R[k][1]))  # noqa: E731
    lu = lambda k: _log_uniform(rng, R[k][0], R[k][1])  # noqa: E731
    grid = grid or CampaignGrid()
    geom = unit_geometry(unit)
    valves = tuple(float(v) for v in grid.valves_deg)
    L = {}
    for v in valves:
        base = TABLE3_L.get(v)
        if base is None:  # a valve outside Table 3: interpolate log L over γ
            ks = np.array(sorted(TABLE3_L))
            base = float(np.exp(np.interp(v, ks, np.log([TABLE3_L[k] for k in ks]))))
        L[v] = float(base * np.exp(rng.normal(0.0, R["L_log_sd"][0])))
    vt0 = lu("turbulent_transition_mm_s")
    vt = {v: float(vt0 * np.exp(rng.normal(0.0, R["turbulent_valve_log_sd"][0]))) for v in valves}
    return BenchParameters(
        effects=tuple(effects),
        seed=int(seed),
        geometry=geom,
        grid=grid,
        V2_fill_factor=u("V2_fill_factor"),
        L_N_s_per_mm=L,
        coulomb_N=u("coulomb_N"),
        viscous_N_s_per_mm=u("viscous_N_s_per_mm"),
        stiction_ratio=u("stiction_ratio"),
        stribeck_speed_mm_s=lu("stribeck_speed_mm_s"),
        stribeck_exponent=u("stribeck_exponent"),
        pressure_friction_N_per_MPa=u("pressure_friction_N_per_MPa"),
        bristle_stiffness_N_per_mm=lu("bristle_stiffness_N_per_mm"),
        thermal_tau_s=(tau := lu("thermal_tau_s")),
        thermal_tau1_s=tau * u("thermal_tau1_factor"),
        turbulent_transition_mm_s=vt,
        relief_force_N=u("relief_force_N"),
        relief_spring_N_per_mm=u("relief_spring_N_per_mm"),
        leak_rate_per_h=u("leak_rate_per_h"),
        sensor_lag_s=lu("sensor_lag_s"),
        sensor_damping=u("sensor_damping"),
        position_ripple_N=u("position_ripple_N"),
        position_ripple_pitch_mm=u("position_ripple_pitch_mm"),
        position_ripple_phase=float(rng.uniform(0, 2 * np.pi)),
        time_ripple_N=u("time_ripple_N"),
        time_ripple_Hz=lu("time_ripple_Hz"),
        time_ripple_phase=float(rng.uniform(0, 2 * np.pi)),
        contact_stiffness_N_per_mm=u("contact_stiffness_N_per_mm"),
        noise_N=u("noise_N"),
        noise_rho=u("noise_rho"),
    )


def _orifice_table(p: BenchParameters) -> dict:
    out = {}
    for g, L in p.L_N_s_per_mm.items():
        A, D, Re_c = orifice(L, p.turbulent_transition_mm_s.get(g, math.inf), p.geometry.A2_mm2)
        out[str(g)] = dict(area_mm2=A * 1e6, hydraulic_diameter_mm=D * 1e3, Re_c=Re_c)
    return out


# ---------------------------------------------------------------- campaign
@dataclass(frozen=True)
class BenchTruth:
    """What the bench really did (for scoring a diagnosis; never shown to it)."""

    parameters: BenchParameters
    effects: tuple  #: effects switched on
    effect_parameters: dict  #: effect id -> its parameters (physical units)
    noise_N: float  #: marginal RMS of the force noise
    noise_rho: float
    force_true_N: np.ndarray  #: noise-free recorded force per row (after sensor, with ripples)
    displacement_true_mm: np.ndarray  #: displacement per row without measurement noise or rounding
    force_unit_N: np.ndarray  #: force on the unit's eyes per row (before sensor)
    components_N: dict  #: per row: "gas", "damping", "friction", "contact", "position_ripple", "time_ripple"
    p2_start_MPa: np.ndarray  #: actual chamber-2 pressure at the start of each experiment (run order)
    campaign_start_s: np.ndarray  #: start time of each experiment in campaign time
    run_order: pd.DataFrame  #: experiment, p2_MPa, valve_deg, speed_mm_s in run order

    def to_dict(self) -> dict:
        """JSON-able summary (no per-row arrays).

        Returns
        -------
        dict
            JSON-ready: ``effects`` (ids switched on), ``effect_parameters`` (see
            :meth:`BenchParameters.effect_parameters`), ``noise_N`` (marginal noise RMS, N), ``noise_rho``
            (AR(1) correlation, dimensionless), ``parameters`` (:meth:`BenchParameters.to_dict`) and
            ``p2_start_MPa`` (chamber-2 pressure at the start of each experiment in run order, MPa);
            non-finite numbers inside ``effect_parameters`` and ``parameters`` become ``None``.
        """
        return dict(
            effects=list(self.effects),
            effect_parameters=_jsonable(self.effect_parameters),
            noise_N=self.noise_N,
            noise_rho=self.noise_rho,
            parameters=_jsonable(self.parameters.to_dict()),
            p2_start_MPa=[float(v) for v in self.p2_start_MPa],
        )


@dataclass(frozen=True)
class BenchCampaign:
    """Recordings in the exchange format plus the truth."""

    frame: pd.DataFrame  #: exchange-format columns only (what ``read_recordings`` reads)
    truth: BenchTruth


def _jsonable(o):
    if isinstance(o, dict):
        return {str(k): _jsonable(v) for k, v in o.items()}
    if isinstance(o, (list, tuple)):
        return [_jsonable(v) for v in o]
    if isinstance(o, (np.floating, float)):
        return float(o) if np.isfinite(o) else None
    if isinstance(o, np.integer):
        return int(o)
    return o


def _nonlinear_part(F: np.ndarray, x_ref: np.ndarray, F_ref: np.ndarray, x: np.ndarray) -> np.ndarray:
    """Curvature of a chamber force: F(x) minus its value at 0 and its least-squares line through there."""
    d = F_ref - F_ref[..., :1]
    s = (d * x_ref).sum(-1) / (x_ref * x_ref).sum()
    Fx = F - F_ref[..., :1]
    return Fx - s[..., None] * x


def _schedule(p: BenchParameters, rng: np.random.Generator):
    """Run order, fine time grid and the machine's motion: ``(P2, GAM, SPD, tf, x, v, start)`` (per experiment, run order)."""
    g, G = p.geometry, p.grid
    combos = [(pr, float(v), s) for pr in G.pressures_MPa for v in G.valves_deg for s in G.speeds_mm_s]
    order = rng.permutation(len(combos)) if G.shuffle else np.arange(len(combos))
    runs = [combos[i] for i in order]
    P2 = np.array([r[0] for r in runs], float)
    GAM = np.array([r[1] for r in runs], float)
    SPD = np.array([r[2] for r in runs], float)
    T_end = 2 * (g.travel_mm / SPD + SPD / G.accel_mm_s2)
    nf = (G.samples - 1) * G.substeps + 1
    tf = np.linspace(0.0, 1.0, nf)[None, :] * T_end[:, None]
    x = np.empty_like(tf)
    v = np.empty_like(tf)
    for e in range(len(runs)):
        x[e], v[e], _ = motion_profile(tf[e], SPD[e], G.accel_mm_s2, g.travel_mm)
    start = np.concatenate([[0.0], np.cumsum(T_end + G.pause_s)[:-1]])
    return P2, GAM, SPD, tf, x, v, start


def _gas_force(p: BenchParameters, tf, x, v, P2):
    """Force of the two gas chambers (N per sample of the fine grid) and the chamber-2 mass at each experiment's start
    (fraction of the calibrated charge)."""
    g, G = p.geometry, p.grid
    pa = p.ambient_MPa
    V1_0 = g.V1_mm3
    V2_0 = g.V2_mm3 * p.V2_fill_factor
    p2a = P2 + pa  # absolute charge of chamber 2
    p1a = g.A2_mm2 / g.A1_mm2 * P2 + pa  # eq. 7 in gauge: zero force at x = 0
    V1 = V1_0 + g.A1_mm2 * x
    V2 = V2_0 - g.A2_mm2 * x
    if np.any(V2 <= 0):
        raise ValueError(f"chamber 2 bottoms out: V2 = {V2_0:.0f} mm³ <= A2 * travel = {g.A2_mm2 * g.travel_mm:.0f} mm³")
    dV1 = g.A1_mm2 * v
    dV2 = -g.A2_mm2 * v
    thermal = p.on("thermal")
    tau2 = p.thermal_tau_s if thermal else 0.0
    tau1 = p.thermal_tau1_s if thermal else 0.0
    leak_per_s = p.leak_rate_per_h / 3600.0 if p.on("leakage") else None
    th1, _ = chamber_states(tf, V1, dV1, tau1)
    th2, mu2 = chamber_states(tf, V2, dV2, tau2, leak_per_s)
    # mass at the start of each experiment: the within-experiment loss scales
    # with the start mass (ṁ ∝ μ), pauses lose exp(-rate * pause) at rest
    if leak_per_s is not None:
        r = mu2[:, -1]
        mu_start = np.cumprod(np.r_[1.0, r[:-1] * np.exp(-leak_per_s * G.pause_s)])
    else:
        mu_start = np.ones(len(P2))
    mu2 = mu2 * mu_start[:, None]
    P1 = p1a[:, None] * th1 * V1_0 / V1
    P2c = p2a[:, None] * mu2 * th2 * V2_0 / V2
    F_gas = g.A2_mm2 * (P2c - pa) - g.A1_mm2 * (P1 - pa)
    if not p.on("gas_nonlinearity"):
        # eq. 14's straight spring: remove the isothermal curvature of each chamber
        xr = np.linspace(0.0, g.travel_mm, 201)
        f2r = g.A2_mm2 * p2a[:, None] * mu_start[:, None] * V2_0 / (V2_0 - g.A2_mm2 * xr[None, :])
        f1r = g.A1_mm2 * p1a[:, None] * V1_0 / (V1_0 + g.A1_mm2 * xr[None, :])
        f2 = g.A2_mm2 * p2a[:, None] * mu_start[:, None] * V2_0 / V2
        f1 = g.A1_mm2 * p1a[:, None] * V1_0 / V1
        F_gas = F_gas - _nonlinear_part(f2, xr, f2r, x) + _nonlinear_part(f1, xr, f1r, x)
    return F_gas, mu_start


def _damping_force(p: BenchParameters, v, GAM):
    """Throttle and relief valve (algebraic: incompressible fluid): the damping force, N per sample of the fine grid."""
    g = p.geometry
    L = np.array([p.L_N_s_per_mm[gm] for gm in GAM])
    if p.on("quadratic_damping"):
        vt = np.array([p.turbulent_transition_mm_s[gm] for gm in GAM])
    else:
        vt = np.full(len(GAM), np.inf)
    b, a = throttle_coefficients(L, vt, g.A2_mm2)
    relief = None
    if p.on("relief_valve"):
        relief = dict(cracking_MPa=p.relief_force_N / g.A2_mm2, spring_N_per_mm=p.relief_spring_N_per_mm,
                      seat_mm=p.relief_seat_diameter_mm, max_lift_mm=p.relief_max_lift_mm, cd=p.relief_cd)
    dp = damping_dp_MPa(g.A2_mm2 * v, b[:, None], a[:, None], relief)
    return g.A2_mm2 * dp


def _friction_force(p: BenchParameters, tf, v, P2, mu_start):
    """LuGre seal friction (N per sample of the fine grid), its Coulomb level growing with the charge when that is on."""
    G = p.grid
    if p.on("pressure_friction"):
        p_mean = float(np.mean(G.pressures_MPa))
        Fc0 = max(p.coulomb_N - p.pressure_friction_N_per_MPa * p_mean, 0.2 * p.coulomb_N)
        Fc = Fc0 + p.pressure_friction_N_per_MPa * P2 * mu_start
    else:
        Fc = np.full(len(P2), p.coulomb_N)
    Fs = Fc * (p.stiction_ratio if p.on("stiction") else 1.0)
    sigma0 = p.bristle_stiffness_N_per_mm if p.on("hysteresis") else _COULOMB_SIGMA0
    F_fric, _ = lugre_friction(tf, v, Fc, Fs, p.stribeck_speed_mm_s, p.stribeck_exponent, sigma0, p.viscous_N_s_per_mm)
    return F_fric


def _load_string(p: BenchParameters, tf, x, v, start):
    """Contact spring, position ripple and time ripple of the load string: ``(F_contact, F_pos, F_time)``, N."""
    zero = np.zeros_like(tf)
    F_contact = (p.contact_stiffness_N_per_mm * x * 0.5 * (1 + np.tanh(v / 0.02))) if p.on("direction_stiffness") else zero
    F_pos = (p.position_ripple_N * np.sin(2 * np.pi * x / p.position_ripple_pitch_mm + p.position_ripple_phase)
             if p.on("position_ripple") else zero)
    tc = start[:, None] + tf
    F_time = p.time_ripple_N * np.sin(2 * np.pi * p.time_ripple_Hz * tc + p.time_ripple_phase) if p.on("time_ripple") else zero
    return F_contact, F_pos, F_time


def _recorded(p: BenchParameters, rng: np.random.Generator, f_true, xs):
    """The recorded force and displacement: AR(1) force noise (N) and white displacement noise (mm) on the samples."""
    ne, ns = f_true.shape
    w = rng.standard_normal((ne, ns))
    noise = np.empty((ne, ns))
    noise[:, 0] = w[:, 0] * p.noise_N
    c = p.noise_N * math.sqrt(1 - p.noise_rho**2)
    for k in range(1, ns):
        noise[:, k] = p.noise_rho * noise[:, k - 1] + c * w[:, k]
    xm = xs + rng.standard_normal((ne, ns)) * p.displacement_noise_mm
    return f_true + noise, xm


def simulate_campaign(params: BenchParameters) -> BenchCampaign:
    """Simulate the campaign of ``params`` (see the module doc).

    Parameters
    ----------
    params : BenchParameters
        The bench (effects, physical parameters, grid, seed).

    Returns
    -------
    BenchCampaign
        ``frame``: columns experiment, time_s, displacement_mm, force_N,
        p2_MPa, valve_deg, speed_mm_s, experiments in run order; ``truth``.
    """
    p = params
    rng = np.random.default_rng(p.seed)
    P2, GAM, SPD, tf, x, v, start = _schedule(p, rng)
    F_gas, mu_start = _gas_force(p, tf, x, v, P2)
    F_damp = _damping_force(p, v, GAM)
    F_fric = _friction_force(p, tf, v, P2, mu_start)
    F_contact, F_pos, F_time = _load_string(p, tf, x, v, start)
    F_unit = F_gas + F_damp + F_fric + F_contact
    F_meas = F_unit + F_pos + F_time
    if p.on("force_lag"):
        F_meas = second_order_filter(tf, F_meas, p.sensor_lag_s, p.sensor_damping)

    # ---- sample, add noise
    ne, ns = len(P2), p.grid.samples
    idx = np.arange(0, tf.shape[1], p.grid.substeps)
    ts = tf[:, idx]
    xs = x[:, idx]
    f_true = F_meas[:, idx]
    f_rec, xm = _recorded(p, rng, f_true, xs)
    names = np.array([f"E{k:03d}" for k in range(ne)])
    frame = pd.DataFrame(
        dict(
            experiment=np.repeat(names, ns),
            time_s=np.round(ts.ravel(), 5),
            displacement_mm=np.round(xm.ravel(), 4),
            force_N=np.round(f_rec.ravel(), 2),
            p2_MPa=np.repeat(P2, ns),
            valve_deg=np.repeat(GAM, ns),
            speed_mm_s=np.repeat(SPD, ns),
        )
    )
    comps = dict(gas=F_gas, damping=F_damp, friction=F_fric, contact=F_contact, position_ripple=F_pos, time_ripple=F_time)
    truth = BenchTruth(
        parameters=p,
        effects=tuple(p.effects),
        effect_parameters=p.effect_parameters(),
        noise_N=p.noise_N,
        noise_rho=p.noise_rho,
        force_true_N=f_true.ravel(),
        displacement_true_mm=xs.ravel(),
        force_unit_N=F_unit[:, idx].ravel(),
        components_N={k: np.asarray(q)[:, idx].ravel() for k, q in comps.items()},
        p2_start_MPa=P2 * mu_start,
        campaign_start_s=start,
        run_order=pd.DataFrame(dict(experiment=names, p2_MPa=P2, valve_deg=GAM, speed_mm_s=SPD)),
    )
    return BenchCampaign(frame, truth)


def write_campaign(campaign: BenchCampaign, path: str | Path) -> Path:
    """Write the recordings (CSV, exchange format) and the truth beside them (``<stem>.truth.json``).

    Parameters
    ----------
    campaign : BenchCampaign
        A simulated campaign.
    path : str or Path
        CSV file to write (its folder is created).

    Returns
    -------
    Path
        The CSV file.
    """
    import json

    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    campaign.frame.to_csv(path, index=False)
    (path.parent / f"{path.stem}.truth.json").write_text(json.dumps(campaign.truth.to_dict(), indent=1))
    return path
