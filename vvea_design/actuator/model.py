"""Variable visco-elastic actuator model (paper section 3.4, eqs 8-13, Table 4).

A motor inertia ``B`` drives a link inertia ``M`` through a series stiffness
``K`` in parallel with a variable damping ``D`` (SI units: N m, rad, kg m², s)::

    B θ'' + D (θ' - q') + K (θ - q) + C_f = τ_m          (8)
    M q'' - D (θ' - q') - K (θ - q) - C_f = 0            (9)
    D' = u_d                                             (10)
    D_min <= D <= D_max,  D(0) = D_min                   (11)
    |u_d| <= 1e4 N m rad⁻¹ s⁻²                           (12)
    |τ_m| <= 100 N m                                     (13)

The link torque is ``τ = D (θ' - q') + K (θ - q) + C_f``. Friction ``C_f`` is
zero throughout, as in the paper's studies.

Design → actuator
-----------------
The spring-damper units act on the joint through the tendon-pulley drive of
section 3.4: two pre-loaded units, one per tendon, on a pulley of radius
``r``. A relative rotation ``δ`` stretches one unit by ``r δ`` and relaxes the
other by ``r δ``; both stay in tension (pre-load), so both act::

    K = n_units · k · r²        D = n_units · L · r²

with ``k`` the unit's linear stiffness (N/m) and ``L`` its linear damping
(N s/m). ``K / D = k / L`` does not depend on ``r`` or ``n_units``. The paper
does not print ``r``; :data:`PAPER_PULLEY_RADIUS_M` is the radius that gives
K = 362 N m/rad with the paper's Fig. 5 spring, and :func:`paper_mapping_check`
shows what that radius gives for the damping range (see docs/actuator.md).
"""

from __future__ import annotations

import math
from dataclasses import asdict, dataclass, replace
from pathlib import Path

import numpy as np

from ..messages import show
from ..plausibility import LIMITS
from ..spring.gas_spring import PAPER_FIG5, GasSpring

__all__ = [
    "Actuator",
    "PAPER_SETTINGS",
    "B_MOTOR_KGM2",
    "M_LINK_KGM2",
    "U_D_MAX",
    "TAU_M_MAX_NM",
    "TABLE3_L_NS_PER_MM",
    "TABLE3_G_N_PER_MM_MPA",
    "PAPER_PULLEY_RADIUS_M",
    "dynamics",
    "link_torque_Nm",
    "throttle_damping_Ns_per_mm",
    "pulley_radius_for_stiffness_m",
    "actuator_from_spring",
    "from_design_json",
    "paper_mapping_check",
    "MappingCheck",
]

#: Motor-side inertia B (kg m²), section 3.4.
B_MOTOR_KGM2 = 0.598
#: Link inertia M (kg m²), section 3.4.
M_LINK_KGM2 = 1.0
#: Damping-rate limit |u_d| (N m rad⁻¹ s⁻²), eq. 12.
U_D_MAX = 1.0e4
#: Motor torque limit |τ_m| (N m), eq. 13.
TAU_M_MAX_NM = 100.0

#: Identified throttle damping L(γ) in N s/mm for valve angle γ in degrees (Table 3).
TABLE3_L_NS_PER_MM: dict[float, float] = {
    50.0: 0.4,
    80.0: 0.5,
    100.0: 7.1,
    104.0: 15.1,
    106.0: 25.3,
    108.0: 40.6,
    109.0: 52.7,
    110.0: 85.2,
    120.0: 1024.7,
}
#: Identified stiffness per charge pressure g in N mm⁻¹ MPa⁻¹ (Table 3).
TABLE3_G_N_PER_MM_MPA = 23.31


@dataclass(frozen=True)
class Actuator:
    """One actuator setting (a row of Table 4 plus the fixed plant data).

    All quantities SI. ``D_min == D_max`` is a constant-damping actuator (SEA,
    LWR); ``D_min < D_max`` a variable-damping one (VVEA, iVVEA).
    """

    name: str  #: label used in result tables ("VVEA", "SEA", ...)
    K_Nm_per_rad: float  #: series stiffness K
    D_min_Nms_per_rad: float  #: lower damping bound, also D(0)
    D_max_Nms_per_rad: float  #: upper damping bound
    B_kgm2: float = B_MOTOR_KGM2  #: motor inertia
    M_kgm2: float = M_LINK_KGM2  #: link inertia
    u_d_max: float = U_D_MAX  #: |dD/dt| limit, N m rad⁻¹ s⁻²
    tau_m_max_Nm: float = TAU_M_MAX_NM  #: |τ_m| limit

    def __post_init__(self) -> None:
        for field in ("K_Nm_per_rad", "B_kgm2", "M_kgm2", "u_d_max", "tau_m_max_Nm"):
            v = getattr(self, field)
            if not (isinstance(v, (int, float)) and math.isfinite(v) and v > 0):
                raise ValueError(f"Actuator.{field} must be a positive finite number, got {show(v)}")
        for field in ("D_min_Nms_per_rad", "D_max_Nms_per_rad"):
            v = getattr(self, field)
            if not (isinstance(v, (int, float)) and math.isfinite(v) and v >= 0):
                raise ValueError(f"Actuator.{field} must be a finite number >= 0, got {show(v)}")
        if self.D_max_Nms_per_rad < self.D_min_Nms_per_rad:
            raise ValueError(
                f"Actuator.D_max_Nms_per_rad ({self.D_max_Nms_per_rad}) must be >= "
                f"D_min_Nms_per_rad ({self.D_min_Nms_per_rad})"
            )
        if not self.name:
            raise ValueError("Actuator.name must be a non-empty string")

    @property
    def variable_damping(self) -> bool:
        """True when the damping can move (``D_max > D_min``)."""
        return self.D_max_Nms_per_rad > self.D_min_Nms_per_rad

    @property
    def eigenfrequency_Hz(self) -> float:
        """Link-side eigenfrequency ``sqrt(K/M)/(2π)`` in Hz, as in section 5.0.2."""
        return math.sqrt(self.K_Nm_per_rad / self.M_kgm2) / (2 * math.pi)

    def with_(self, **changes) -> "Actuator":
        """A copy with some fields changed (validated).

        Parameters
        ----------
        **changes
            Field names of :class:`Actuator` and their new values, in the fields' units (``K_Nm_per_rad`` in
            N m/rad, ``D_min_Nms_per_rad`` / ``D_max_Nms_per_rad`` in N m s/rad, ``B_kgm2`` / ``M_kgm2`` in
            kg m², ``u_d_max`` in N m rad⁻¹ s⁻², ``tau_m_max_Nm`` in N m).

        Returns
        -------
        Actuator
            A new actuator; the fields not named keep their values.

        Raises
        ------
        ValueError
            When a changed value breaks a field rule (a stiffness, inertia or limit not positive and finite,
            a damping bound negative, ``D_max < D_min``, an empty name).
        TypeError
            When a name in ``changes`` is not a field of :class:`Actuator`.
        """
        return replace(self, **changes)


#: Table 4 of the paper.
PAPER_SETTINGS: dict[str, Actuator] = {
    "VVEA": Actuator("VVEA", 362.0, 12.1, 200.0),
    "iVVEA": Actuator("iVVEA", 362.0, 0.0, 200.0),
    "SEA": Actuator("SEA", 362.0, 0.0, 0.0),
    "LWR": Actuator("LWR", 30000.0, 30000.0, 30000.0),
}


def dynamics(x, u, K, B=B_MOTOR_KGM2, M=M_LINK_KGM2):
    """Right-hand side of eqs 8-10 (C_f = 0).

    Works on numpy arrays and on CasADi symbols alike.

    Parameters
    ----------
    x : sequence
        State ``[θ (rad), q (rad), θ' (rad/s), q' (rad/s), D (N m s/rad)]``.
    u : sequence
        Inputs ``[τ_m (N m), u_d (N m s rad⁻¹ s⁻¹)]``.
    K, B, M : float or symbol
        Stiffness (N m/rad), motor and link inertia (kg m²).

    Returns
    -------
    list
        ``[θ', q', θ'', q'', D']``.
    """
    th, q, dth, dq, D = x[0], x[1], x[2], x[3], x[4]
    tau_m, u_d = u[0], u[1]
    tau = D * (dth - dq) + K * (th - q)
    return [dth, dq, (tau_m - tau) / B, tau / M, u_d]


def link_torque_Nm(theta, q, dtheta, dq, D, K):
    """Link torque ``τ = D (θ' - q') + K (θ - q)`` (C_f = 0).

    Parameters
    ----------
    theta, q
        Motor and link angle, rad.
    dtheta, dq
        Motor and link speed, rad/s.
    D
        Damping, N m s/rad.
    K
        Stiffness, N m/rad.

    Returns
    -------
    numpy.ndarray
        Link torque τ, N m.
    """
    return D * (np.asarray(dtheta) - dq) + K * (np.asarray(theta) - q)


def throttle_damping_Ns_per_mm(gamma_deg) -> np.ndarray:
    """Throttle damping L(γ) in N s/mm, from Table 3.

    Between identified angles the damping is interpolated linearly in
    ``log L`` (the table spans more than three decades).

    Parameters
    ----------
    gamma_deg
        Valve angle(s), degrees, within 50°-120°.

    Returns
    -------
    numpy.ndarray
        Damping L, N s/mm.

    Raises
    ------
    ValueError
        If ``gamma_deg`` lies outside the identified 50°-120°.
    """
    g = np.asarray(gamma_deg, dtype=float)
    angles = np.array(sorted(TABLE3_L_NS_PER_MM))
    if np.any(~np.isfinite(g)) or np.any(g < angles[0]) or np.any(g > angles[-1]):
        raise ValueError(
            f"gamma_deg must lie in the identified valve range {angles[0]:g}-{angles[-1]:g} deg, got {show(gamma_deg)}"
        )
    logL = np.log([TABLE3_L_NS_PER_MM[a] for a in angles])
    return np.exp(np.interp(g, angles, logL))


def pulley_radius_for_stiffness_m(k_N_per_mm: float, K_Nm_per_rad: float, n_units: int = 2) -> float:
    """Pulley radius ``r = sqrt(K / (n_units k))`` giving joint stiffness ``K``.

    Parameters
    ----------
    k_N_per_mm
        One unit's linear stiffness, N/mm.
    K_Nm_per_rad
        Wanted joint stiffness, N m/rad.
    n_units
        Pre-loaded units acting on the pulley (count, dimensionless).

    Returns
    -------
    float
        Pulley radius r, m.
    """
    if k_N_per_mm <= 0:
        raise ValueError(f"k_N_per_mm must be > 0, got {show(k_N_per_mm)}")
    if K_Nm_per_rad <= 0:
        raise ValueError(f"K_Nm_per_rad must be > 0, got {show(K_Nm_per_rad)}")
    return math.sqrt(K_Nm_per_rad / (n_units * k_N_per_mm * 1e3))


#: Pulley radius (m) that turns the paper's Fig. 5 spring (p2 = 2.385 MPa) into
#: the paper's K = 362 N m/rad with two pre-loaded units. Inferred: the paper
#: does not print the radius.
PAPER_PULLEY_RADIUS_M = pulley_radius_for_stiffness_m(PAPER_FIG5.mean_stiffness_N_per_mm(), 362.0, 2)


def actuator_from_spring(
    spring: GasSpring,
    *,
    pulley_radius_m: float = PAPER_PULLEY_RADIUS_M,
    p2_MPa: float | None = None,
    gamma_min_deg: float = 50.0,
    gamma_max_deg: float = 120.0,
    n_units: int = 2,
    D_max_cap_Nms_per_rad: float | None = None,
    name: str = "design",
) -> Actuator:
    """Joint-level actuator from a gas spring and the throttle (section 3.4 mapping).

    Parameters
    ----------
    spring
        The unit's gas spring (mm, MPa).
    pulley_radius_m
        Tendon-pulley radius r in m (default: :data:`PAPER_PULLEY_RADIUS_M`).
    p2_MPa
        Recharge the spring to this chamber-2 pressure first (p1 from eq. 6);
        ``None`` keeps the spring's own charge.
    gamma_min_deg, gamma_max_deg
        Usable throttle-valve range; the damping range is L(γ_min)..L(γ_max)
        of Table 3 (default the whole identified range 50°-120°).
    n_units
        Pre-loaded spring-damper units acting on the pulley (2 in the paper).
    D_max_cap_Nms_per_rad
        Optional upper cap on D_max (N m s/rad), e.g. 200 as in Table 4.
    name
        Label of the setting.

    Returns
    -------
    Actuator
        ``K = n r² k``, ``D_min/max = n r² L(γ_min/max)``, SI units.
    """
    if not (math.isfinite(pulley_radius_m) and pulley_radius_m > 0):
        raise ValueError(f"pulley_radius_m must be a positive number of metres, got {pulley_radius_m!r}")
    LIMITS["pulley_radius_m"].check(pulley_radius_m, "pulley_radius_m", ValueError)
    for option, g in (("gamma_min_deg", gamma_min_deg), ("gamma_max_deg", gamma_max_deg)):
        LIMITS["valve_deg"].check(g, option, ValueError)
    if int(n_units) != n_units or n_units < 1:
        raise ValueError(f"n_units must be a whole number >= 1, got {n_units!r}")
    if gamma_max_deg < gamma_min_deg:
        raise ValueError(f"gamma_max_deg ({gamma_max_deg}) must be >= gamma_min_deg ({gamma_min_deg})")
    if p2_MPa is not None:
        if not (math.isfinite(p2_MPa) and p2_MPa > 0):
            raise ValueError(f"p2_MPa must be a positive pressure in MPa, got {show(p2_MPa)}")
        spring = spring.with_pressures(p2_MPa)
    k = spring.mean_stiffness_N_per_mm()
    if not k > 0:
        raise ValueError(f"the spring's mean stiffness must be > 0 N/mm, got {show(k)} (is it charged?)")
    r2n = n_units * pulley_radius_m**2
    L_lo, L_hi = throttle_damping_Ns_per_mm([gamma_min_deg, gamma_max_deg])
    D_min = r2n * L_lo * 1e3
    D_max = r2n * L_hi * 1e3
    if D_max_cap_Nms_per_rad is not None:
        D_max = max(D_min, min(D_max, D_max_cap_Nms_per_rad))
    return Actuator(name, r2n * k * 1e3, float(D_min), float(D_max))


def from_design_json(path: str | Path, **kwargs) -> Actuator:
    """Actuator from a design JSON (via :func:`vvea_design.spring.design_file.load_design`).

    Parameters
    ----------
    path
        Design JSON file.
    **kwargs
        Options of :func:`actuator_from_spring` (pulley radius in m, p2 in MPa, valve angles in deg).

    Returns
    -------
    Actuator
        K (N m/rad) and damping range (N m s/rad) of the joint.
    """
    from ..spring.design_file import load_design  # upper layer import kept local

    design = load_design(path)
    return actuator_from_spring(design.gas_spring, **kwargs)


@dataclass(frozen=True)
class MappingCheck:
    """What the section 3.4 mapping gives with the paper's numbers (:func:`paper_mapping_check`)."""

    pulley_radius_m: float  #: pulley radius r, m
    n_units: int  #: pre-loaded units on the pulley
    k_fig5_N_per_mm: float  #: mean stiffness of the paper's Fig. 5 spring, N/mm
    k_table3_at_2p385MPa_N_per_mm: float  #: Table 3's g times the Fig. 5 charge, N/mm
    K_Nm_per_rad: float  #: joint stiffness n r² k, N m/rad
    D_of_gamma_Nms_per_rad: dict[float, float]  #: joint damping of every Table 3 valve angle (deg), N m s/rad
    L_needed_for_D12p1_Ns_per_mm: float  #: throttle damping the paper's D_min = 12.1 would need, N s/mm
    L_needed_for_D200_Ns_per_mm: float  #: throttle damping the paper's D_max = 200 would need, N s/mm
    K_over_D_paper_min_per_s: float  #: 362 / 12.1, 1/s
    K_over_D_paper_max_per_s: float  #: 362 / 200, 1/s

    def to_dict(self) -> dict:
        """Plain-JSON dictionary.

        Returns
        -------
        dict
            Field name to value, units as in the names (m, N/mm, N m/rad, N m s/rad, N s/mm, 1/s); the
            valve angles of ``D_of_gamma_Nms_per_rad`` in deg.
        """
        return asdict(self)


def paper_mapping_check(pulley_radius_m: float = PAPER_PULLEY_RADIUS_M, n_units: int = 2) -> MappingCheck:
    """What the section 3.4 mapping gives with the paper's numbers.

    Parameters
    ----------
    pulley_radius_m
        Pulley radius r, m.
    n_units
        Pre-loaded units on the pulley (count, dimensionless).

    Returns
    -------
    MappingCheck
        Spring stiffness (N/mm), K (N m/rad), the damping of every Table 3 valve angle (N m s/rad), and
        the throttle damping (N s/mm) that the paper's 12.1 and 200 N m s/rad would need.
    """
    k_fig5 = PAPER_FIG5.mean_stiffness_N_per_mm()
    r2n = n_units * pulley_radius_m**2
    D_of = {g: r2n * L * 1e3 for g, L in TABLE3_L_NS_PER_MM.items()}
    return MappingCheck(
        pulley_radius_m=pulley_radius_m,
        n_units=n_units,
        k_fig5_N_per_mm=k_fig5,
        k_table3_at_2p385MPa_N_per_mm=TABLE3_G_N_PER_MM_MPA * PAPER_FIG5.p2_MPa,
        K_Nm_per_rad=r2n * k_fig5 * 1e3,
        D_of_gamma_Nms_per_rad=D_of,
        L_needed_for_D12p1_Ns_per_mm=12.1 / (r2n * 1e3),
        L_needed_for_D200_Ns_per_mm=200.0 / (r2n * 1e3),
        K_over_D_paper_min_per_s=362.0 / 12.1,
        K_over_D_paper_max_per_s=362.0 / 200.0,
    )
