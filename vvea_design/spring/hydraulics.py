"""The damper's hydraulics from the geometry: the flow path's restrictions, the damping force, D_min and D_max.

Extending the unit (x > 0) pushes ``A2 v`` of oil from under the piston through the base into the bladder:

1. a vertical channel in the base from the fluid column to the valves' axis (laminar pipe with entry and exit
   losses), diameter ``min(fixed.fluid_channel_mm, (rp - r_rod)/2)``;
2. the **rotary throttle**: a sharp-edged orifice (``C_d = 0.61``) whose open area is the valve port's,
   ``pi/4 d_port^2`` with ``d_port = min(channel, throttle bore / 2)``, times the window's open fraction at the
   valve angle (linear between :data:`GAMMA_OPEN_DEG` and :data:`GAMMA_CLOSED_DEG`, fitted to the paper's Table 3:
   an orifice with a linearly closing window gives ``L ∝ 1/(gamma_c - gamma)^2``, which Table 3 follows from 100° to
   110°); closed, only the leakage through the core's clearance passes (a laminar slit, H7/g6 fit);
3. a vertical channel up to the support ring's collector groove, diameter ``min(channel, collector width -
   0.5 mm)``; the collector groove under the support ring spans the annulus less 0.5 mm at each tube
   (:func:`collector_width_mm`);
4. the support ring's ``fixed.ring_channels`` axial channels in parallel, diameter
   ``min(fixed.ring_channel_mm, 0.6 (bladder inner radius - bead - inner tube radius))`` (the CAD's rule),
   over the clamp's length less the collector groove.

The **relief valve** bypasses the throttle: the throttle's pressure drop never exceeds ``fixed.relief_force_N /
A2`` (its cracking pressure; its override is not modelled). Pipe friction: ``f_D = max(64/Re, 0.3164 Re^-0.25)``
(Hagen-Poiseuille, Blasius), minor losses ``K rho v^2/2`` with ``K = 0.5`` (entry) and ``1.0`` (exit). The oil is
``fixed.oil`` at ``fixed.oil_temperature_C`` (kinematic viscosity by ASTM D341 from its grade's 40 °C and
100 °C values).

The unit's damping ``L`` (N s/mm) is the paper's: the least-squares slope through the origin of the damping
force over the identification speeds (:data:`PAPER_SPEEDS_MM_S`, section 4.1, eq. 14-15). ``D_min`` is the valve
fully open (the parasitic damping of the path), ``D_max`` the valve closed (capped by the relief valve).
Lengths mm, speeds mm/s, forces N, pressures MPa; vectorised over a population.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from .geometry import Array
from .ports import BEAD_HEIGHT_MM, bead_height_mm  # the CAD's bead: the ring channels sit inside it
from .records import Record

__all__ = ["Oil", "OILS", "PAPER_SPEEDS_MM_S", "GAMMA_OPEN_DEG", "GAMMA_CLOSED_DEG", "TABLE3_L_N_S_PER_MM",
           "HydraulicPath", "Restriction", "Hydraulics", "kinematic_viscosity_mm2_s", "throttle_open_fraction",
           "damping_force_N", "linear_damping_N_s_per_mm", "BEAD_HEIGHT_MM", "COLLECTOR_DEPTH_MAX_MM",
           "hydraulic_path", "damping_range", "hydraulics_record", "collector_width_mm", "COLLECTOR_LAND_MM"]

#: The identification speeds of the paper (section 4.1), mm/s.
PAPER_SPEEDS_MM_S = (0.1, 1.0, 4.0, 8.0, 12.0)
#: The paper's Table 3: identified damping L(gamma) of its unit, N s/mm, by valve angle in degrees.
TABLE3_L_N_S_PER_MM = {50.0: 0.4, 80.0: 0.5, 100.0: 7.1, 104.0: 15.1, 106.0: 25.3, 108.0: 40.6, 109.0: 52.7,
                       110.0: 85.2, 120.0: 1024.7}
#: Valve angles (deg) at which the rotary throttle's window is fully open and closed (fitted to Table 3,
#: ``tests/spring/test_hydraulics.py``).
GAMMA_OPEN_DEG, GAMMA_CLOSED_DEG = 32.0, 114.0
#: Discharge coefficient of the throttle's sharp-edged port (ISO 5167-2's orifice plates: about 0.6).
DISCHARGE_COEFFICIENT = 0.61
#: Loss coefficients of a channel's entry and exit.
K_ENTRY, K_EXIT = 0.5, 1.0
#: Deepest collector groove under the support ring (the CAD's), mm.
COLLECTOR_DEPTH_MAX_MM = 1.0
#: Land the collector groove leaves at each tube, and the base's ring-side channel inside the groove, mm.
COLLECTOR_LAND_MM = 0.5
#: Radial clearance of the throttle core in its bore (H7/g6 on a 3 .. 10 mm bore: mean diametral clearance
#: about 14 µm), mm, and the length of the land the leakage crosses, in port diameters.
CORE_CLEARANCE_MM, LAND_PORTS = 0.007, 1.0


@dataclass(frozen=True)
class Oil(Record):
    """A hydraulic oil: density and the two viscosities of its grade (ISO 3448)."""

    name: str
    standard: str
    density_g_per_mm3: float  #: g/mm³
    viscosity_40C_mm2_s: float  #: kinematic viscosity at 40 °C, mm²/s (cSt)
    viscosity_100C_mm2_s: float  #: kinematic viscosity at 100 °C, mm²/s (cSt)


#: The oils a design may name (``fixed.oil``); the bill of materials names the same (ISO VG 32, HM).
OILS = {"iso-vg-32": Oil("hydraulic oil ISO VG 32 (HM)", "ISO 3448 VG 32, ISO 6743-4 HM", 0.87e-3, 32.0, 5.4),
        "iso-vg-22": Oil("hydraulic oil ISO VG 22 (HM)", "ISO 3448 VG 22, ISO 6743-4 HM", 0.86e-3, 22.0, 4.3),
        "iso-vg-46": Oil("hydraulic oil ISO VG 46 (HM)", "ISO 3448 VG 46, ISO 6743-4 HM", 0.875e-3, 46.0, 6.8)}


def kinematic_viscosity_mm2_s(oil: Oil, temperature_C: float) -> float:
    """Kinematic viscosity of ``oil`` at ``temperature_C`` by ASTM D341 (Walther), mm²/s.

    ``log10 log10 (nu + 0.7) = A - B log10 T`` through the grade's 40 °C and 100 °C values.

    Parameters
    ----------
    oil : Oil
        The oil (its 40 °C and 100 °C viscosities, mm²/s).
    temperature_C : float
        Temperature, °C.

    Returns
    -------
    float
        Viscosity, mm²/s.
    """
    T1, T2 = 313.15, 373.15
    y1 = math.log10(math.log10(oil.viscosity_40C_mm2_s + 0.7))
    y2 = math.log10(math.log10(oil.viscosity_100C_mm2_s + 0.7))
    B = (y1 - y2) / (math.log10(T2) - math.log10(T1))
    A = y1 + B * math.log10(T1)
    return 10 ** 10 ** (A - B * math.log10(temperature_C + 273.15)) - 0.7


def throttle_open_fraction(gamma_deg):
    """Open fraction of the rotary throttle's window at a valve angle (linear between fully open and closed).

    Parameters
    ----------
    gamma_deg : float or array
        Valve angle, deg (the paper's Table 3 angles: 50° open .. 120° closed).

    Returns
    -------
    float or ndarray
        Fraction of the port open, 0 .. 1, dimensionless.
    """
    g = np.asarray(gamma_deg, dtype=float)
    return np.clip((GAMMA_CLOSED_DEG - g) / (GAMMA_CLOSED_DEG - GAMMA_OPEN_DEG), 0.0, 1.0)


@dataclass(frozen=True)
class HydraulicPath:
    """The flow path's sizes (arrays over a population), mm: what the CAD draws and the damping follows from."""

    A2_mm2: Array  #: the piston's annulus that pushes the oil, mm²
    channel_mm: Array  #: the base's channel from the fluid column to the valves
    ring_side_channel_mm: Array  #: the base's channel from the valves to the support ring
    channel_length_mm: Array  #: each base channel, from the valves' axis to the base's top
    throttle_bore_mm: Array  #: the rotary throttle's bore
    port_mm: Array  #: the throttle port's diameter (its fully open area is pi/4 port^2)
    ring_channel_mm: Array  #: each support-ring channel
    ring_channel_length_mm: Array  #: the support ring's channels above its collector groove
    ring_channels: int
    relief_force_N: float  #: the relief valve opens at this force on the piston
    density_kg_m3: float
    viscosity_mm2_s: float


def _pipe_dp_Pa(Q, d_mm, L_mm, rho, nu_m2s, K):
    """Pressure drop of ``Q`` (m³/s) through a pipe (friction + minor losses), Pa."""
    d = np.asarray(d_mm, dtype=float) * 1e-3
    A = math.pi / 4 * d**2
    with np.errstate(divide="ignore", invalid="ignore"):
        v = Q / A
        Re = np.fmax(np.abs(v) * d / nu_m2s, 1e-12)
        fD = np.fmax(64 / Re, 0.3164 * Re**-0.25)
        dp = (fD * (np.asarray(L_mm) * 1e-3) / d + K) * rho * v**2 / 2
    return np.where(d > 0, dp, np.inf)  # no channel drawn: no flow


def _throttle_dp_Pa(Q, path: HydraulicPath, open_fraction):
    """Pressure drop across the throttle (orifice, or the closed core's leakage), Pa, before the relief's cap."""
    rho, nu = path.density_kg_m3, path.viscosity_mm2_s * 1e-6
    port = np.asarray(path.port_mm) * 1e-3
    A = math.pi / 4 * port**2 * open_fraction
    c = CORE_CLEARANCE_MM * 1e-3
    g_leak = 2 * port * c**3 / (12 * rho * nu * LAND_PORTS * port)  # two lands, each a slit as wide as the port
    with np.errstate(divide="ignore", invalid="ignore"):
        orifice = rho / 2 * (Q / (DISCHARGE_COEFFICIENT * A)) ** 2
        return np.where(open_fraction > 0, orifice, Q / g_leak)


def damping_force_N(path: HydraulicPath, speed_mm_s, open_fraction=1.0):
    """Damping force on the piston at a piston speed and valve opening, N (the relief valve caps the throttle).

    Parameters
    ----------
    path : HydraulicPath
        The flow path (mm, the oil).
    speed_mm_s : float or array
        Piston speed, mm/s (> 0: extending).
    open_fraction : float or array
        Open fraction of the throttle's window, 0 (closed) .. 1 (open), dimensionless.

    Returns
    -------
    ndarray
        ``A2 dp(Q)``, N.
    """
    rho, nu = path.density_kg_m3, path.viscosity_mm2_s * 1e-6
    A2 = np.asarray(path.A2_mm2, dtype=float)
    Q = A2 * np.asarray(speed_mm_s, dtype=float) * 1e-9  # m³/s
    n = path.ring_channels
    K = K_ENTRY + K_EXIT
    series = (_pipe_dp_Pa(Q, path.channel_mm, path.channel_length_mm, rho, nu, K)
              + _pipe_dp_Pa(Q, path.ring_side_channel_mm, path.channel_length_mm, rho, nu, K)
              + _pipe_dp_Pa(Q / n, path.ring_channel_mm, path.ring_channel_length_mm, rho, nu, K))
    with np.errstate(divide="ignore", invalid="ignore"):
        relief_Pa = path.relief_force_N / A2 * 1e6
    throttle = np.fmin(_throttle_dp_Pa(Q, path, np.asarray(open_fraction, dtype=float)), relief_Pa)
    return A2 * (series + throttle) * 1e-6


def linear_damping_N_s_per_mm(path: HydraulicPath, open_fraction=1.0, speeds_mm_s=PAPER_SPEEDS_MM_S):
    """The unit's linear damping as the paper identifies it: least squares ``F = L v`` over its speeds, N s/mm.

    Parameters
    ----------
    path : HydraulicPath
        The flow path (mm, the oil).
    open_fraction : float or array
        Open fraction of the throttle, 0 .. 1, dimensionless.
    speeds_mm_s : sequence of float
        Piston speeds, mm/s (default: the paper's identification speeds).

    Returns
    -------
    ndarray
        ``L = sum F(v) v / sum v^2``, N s/mm.
    """
    v = np.asarray(speeds_mm_s, dtype=float)
    A2 = np.asarray(path.A2_mm2, dtype=float)
    shape = (v.size,) + (1,) * A2.ndim  # the speeds on a leading axis, the population after
    F = damping_force_N(path, v.reshape(shape), np.asarray(open_fraction, dtype=float))
    return np.tensordot(v, F, axes=(0, 0)) / float(np.sum(v**2))


@dataclass(frozen=True)
class Restriction(Record):
    """One restriction of the flow path (one design), for the design file."""

    name: str
    law: str  #: ``laminar pipe`` (friction + entry/exit), ``orifice``, ``relief``
    diameter_mm: float
    length_mm: float
    count: int  #: in parallel
    pressure_drop_at_12mm_s_MPa: float  #: its share at the paper's fastest identification speed, valve open, MPa


@dataclass(frozen=True)
class Hydraulics(Record):
    """The built unit's damper: its oil, its restrictions and its damping range (one design)."""

    oil: str
    oil_standard: str
    oil_temperature_C: float
    density_g_per_mm3: float
    kinematic_viscosity_mm2_s: float
    restrictions: list  #: :class:`Restriction` contents
    throttle_bore_mm: float
    throttle_port_mm: float
    relief_bore_mm: float
    relief_seat_mm: float
    relief_force_N: float
    relief_pressure_MPa: float
    D_min_N_s_per_mm: float  #: valve open: the parasitic damping of the path
    D_max_N_s_per_mm: float  #: valve closed, capped by the relief valve
    closed_leakage_damping_N_s_per_mm: float  #: valve closed, relief shut (the core's leakage only)
    identification_speeds_mm_s: list
    table3_model_N_s_per_mm: dict = field(default_factory=dict)  #: the model's L at each of Table 3's angles


def collector_width_mm(outer_bore_radius_mm, inner_tube_outer_radius_mm):
    """Radial width of the collector groove under the support ring: the annulus less a land at each tube, mm.

    Parameters
    ----------
    outer_bore_radius_mm, inner_tube_outer_radius_mm : float or array
        The annulus's radii, mm.

    Returns
    -------
    float or ndarray
        ``rb - rio - 2 x COLLECTOR_LAND_MM``, mm (the base's ring-side channel opens into it, a land narrower).
    """
    return np.asarray(outer_bore_radius_mm) - np.asarray(inner_tube_outer_radius_mm) - 2 * COLLECTOR_LAND_MM


def hydraulic_path(A2_mm2, piston_radius_mm, inner_tube_outer_radius_mm, bladder_inner_radius_mm,
                   outer_bore_radius_mm, bladder_outer_radius_mm, base_own_mm, base_mm, fixed) -> HydraulicPath:
    """The flow path of a design (or a population) from its geometry, as the CAD draws it.

    Parameters
    ----------
    A2_mm2 : array
        The piston's annulus, mm².
    piston_radius_mm, inner_tube_outer_radius_mm, bladder_inner_radius_mm, outer_bore_radius_mm, bladder_outer_radius_mm : array
        Radii of the bore, the inner tube's outside, the cast bladder and the outer bore, mm.
    base_own_mm : array
        The base's own part (below its joint zone): holds the valves, mm.
    base_mm : array
        The whole base (the channels run from the valves to its top), mm.
    fixed : FixedParameters
        The feature sizes (``throttle_bore_mm``, ``fluid_channel_mm``, ``ring_channel_mm``, ``ring_channels``),
        the rod, the clamp, the relief force (N), the oil and its temperature (°C).

    Returns
    -------
    HydraulicPath
        Every size of the path, mm; the oil's density (kg/m³) and viscosity (mm²/s).
    """
    f = fixed
    rio, rbi, rb, rbo = (np.asarray(v, dtype=float) for v in (inner_tube_outer_radius_mm, bladder_inner_radius_mm,
                                                              outer_bore_radius_mm, bladder_outer_radius_mm))
    bead = bead_height_mm(rio, rbi, rb, rbo)
    ring = np.fmin(f.ring_channel_mm, 0.6 * (rbi - bead - rio))
    channel = np.fmin(f.fluid_channel_mm, 0.5 * (np.asarray(piston_radius_mm) - f.rod_diameter_mm / 2))
    throttle = np.fmin(f.throttle_bore_mm, np.asarray(base_own_mm) - 8.0)
    z_valve = np.asarray(base_own_mm) - 2.0 - throttle / 2
    oil = OILS[f.oil]
    clamp = f.bladder_clamp_mm
    return HydraulicPath(A2_mm2=np.asarray(A2_mm2, dtype=float), channel_mm=channel,
                         ring_side_channel_mm=np.fmin(channel, collector_width_mm(rb, rio) - COLLECTOR_LAND_MM),
                         channel_length_mm=np.asarray(base_mm) - z_valve, throttle_bore_mm=throttle,
                         port_mm=np.fmin(channel, throttle / 2), ring_channel_mm=ring,
                         ring_channel_length_mm=np.full_like(ring, clamp - min(COLLECTOR_DEPTH_MAX_MM, 0.2 * clamp)),
                         ring_channels=f.ring_channels, relief_force_N=f.relief_force_N,
                         density_kg_m3=oil.density_g_per_mm3 * 1e6,
                         viscosity_mm2_s=kinematic_viscosity_mm2_s(oil, f.oil_temperature_C))


def damping_range(path: HydraulicPath) -> tuple[Array, Array]:
    """``D_min`` (valve open) and ``D_max`` (valve closed, relief-capped) of a path, N s/mm.

    Parameters
    ----------
    path : HydraulicPath
        The flow path (mm, the oil).

    Returns
    -------
    tuple of ndarray
        ``(D_min, D_max)``, N s/mm (the paper's least-squares damping over its identification speeds).
    """
    return linear_damping_N_s_per_mm(path, 1.0), linear_damping_N_s_per_mm(path, 0.0)


def hydraulics_record(path: HydraulicPath, fixed) -> Hydraulics:
    """The design file's record of one design's damper.

    Parameters
    ----------
    path : HydraulicPath
        One design's flow path (0-d arrays or floats, mm).
    fixed : FixedParameters
        The oil, its temperature (°C), the relief valve's sizes (mm) and force (N).

    Returns
    -------
    Hydraulics
        Oil, restrictions with their pressure drops (MPa), the damping range (N s/mm) and the model's damping at
        Table 3's valve angles (N s/mm).
    """
    f, oil = fixed, OILS[fixed.oil]
    fl = lambda v: float(np.asarray(v).reshape(-1)[0])  # noqa: E731
    A2 = fl(path.A2_mm2)
    Q = A2 * 12.0 * 1e-9
    rho, nu = path.density_kg_m3, path.viscosity_mm2_s * 1e-6
    K = K_ENTRY + K_EXIT
    rs = [
        Restriction("base channel, fluid column to the valves", "laminar pipe", fl(path.channel_mm),
                    fl(path.channel_length_mm), 1,
                    fl(_pipe_dp_Pa(Q, path.channel_mm, path.channel_length_mm, rho, nu, K)) * 1e-6),
        Restriction("rotary throttle port (open)", "orifice", fl(path.port_mm), 0.0, 1,
                    fl(_throttle_dp_Pa(Q, path, np.asarray(1.0))) * 1e-6),
        Restriction("base channel, valves to the support ring", "laminar pipe", fl(path.ring_side_channel_mm),
                    fl(path.channel_length_mm), 1,
                    fl(_pipe_dp_Pa(Q, path.ring_side_channel_mm, path.channel_length_mm, rho, nu, K)) * 1e-6),
        Restriction("support-ring channels", "laminar pipe", fl(path.ring_channel_mm),
                    fl(path.ring_channel_length_mm), path.ring_channels,
                    fl(_pipe_dp_Pa(Q / path.ring_channels, path.ring_channel_mm, path.ring_channel_length_mm, rho, nu,
                                   K)) * 1e-6),
        Restriction("relief valve (bypasses the throttle)", "relief", f.relief_seat_mm, 0.0, 1,
                    f.relief_force_N / A2),
    ]
    dmin, dmax = damping_range(path)
    leak = linear_damping_N_s_per_mm(HydraulicPath(**{**path.__dict__, "relief_force_N": math.inf}), 0.0)
    t3 = {f"{g:g}": fl(linear_damping_N_s_per_mm(path, throttle_open_fraction(g))) for g in TABLE3_L_N_S_PER_MM}
    return Hydraulics(oil=oil.name, oil_standard=oil.standard, oil_temperature_C=f.oil_temperature_C,
                      density_g_per_mm3=oil.density_g_per_mm3, kinematic_viscosity_mm2_s=path.viscosity_mm2_s,
                      restrictions=[r.to_dict() for r in rs], throttle_bore_mm=fl(path.throttle_bore_mm),
                      throttle_port_mm=fl(path.port_mm), relief_bore_mm=min(f.relief_bore_mm, fl(path.throttle_bore_mm)),
                      relief_seat_mm=f.relief_seat_mm, relief_force_N=f.relief_force_N,
                      relief_pressure_MPa=f.relief_force_N / A2, D_min_N_s_per_mm=fl(dmin), D_max_N_s_per_mm=fl(dmax),
                      closed_leakage_damping_N_s_per_mm=fl(leak), identification_speeds_mm_s=list(PAPER_SPEEDS_MM_S),
                      table3_model_N_s_per_mm=t3)
