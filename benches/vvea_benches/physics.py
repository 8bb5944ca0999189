"""The bench's parts, each from its physics: throttle and relief valve (orifice laws), chamber thermodynamics,
LuGre friction and the force sensor's filter (see :mod:`vvea_benches.physbench` for the laws and the campaign).

Units: mm, mm², mm³, MPa = N/mm², N, s; SI inside the orifice laws. Like the campaign simulator, this module
shares no formula with the effect catalogue of ``vvea_design.identification``.
"""

from __future__ import annotations

import math

import numpy as np

__all__ = [
    "KAPPA",
    "RHO_OIL",
    "NU_OIL",
    "CD_INF",
    "PISTON_MASS_KG",
    "discharge_coefficient",
    "orifice",
    "throttle_coefficients",
    "throttle_dp_MPa",
    "throttle_flow_mm3_s",
    "relief_flow_mm3_s",
    "damping_dp_MPa",
    "chamber_states",
    "lugre_friction",
    "second_order_filter",
]

KAPPA = 1.4  #: cp/cv of nitrogen/air
RHO_OIL = 870.0  #: kg/m³
NU_OIL = 3.0e-5  #: m²/s (30 cSt)
CD_INF = 0.7  #: turbulent discharge coefficient of the throttle
PISTON_MASS_KG = 0.2  #: piston + rod (sets the LuGre micro-damping σ1)


# ---------------------------------------------------------------- throttle and relief valve
def discharge_coefficient(Re, Re_c: float, cd_inf: float = CD_INF):
    """Cd(Re) = Cd∞ sqrt(Re/(Re+Re_c)): ∝ sqrt(Re) (laminar) below Re_c, -> Cd∞ (turbulent) above.

    Parameters
    ----------
    Re : float or array
        Reynolds number of the jet, u D / ν (dimensionless).
    Re_c : float
        Transition Reynolds number (dimensionless).
    cd_inf : float
        Turbulent discharge coefficient (dimensionless).

    Returns
    -------
    array
        Discharge coefficient (dimensionless).
    """
    Re = np.abs(np.asarray(Re, float))
    return cd_inf * np.sqrt(Re / (Re + Re_c))


def orifice(L_N_s_per_mm: float, vt_mm_s: float, A2_mm2: float):
    """Orifice area A (m²), hydraulic diameter D (m) and Re_c of a valve position.

    Chosen so that the laminar damping is L and the turbulent Δp equals the
    laminar one at piston speed v_t (v_t = inf: a purely laminar channel).
    """
    A2 = A2_mm2 * 1e-6
    L = L_N_s_per_mm * 1e3  # N s/m
    if not np.isfinite(vt_mm_s):
        return math.inf, math.nan, math.inf
    K = L / (vt_mm_s * 1e-3)  # N s²/m²: K v_t = L
    A = A2**1.5 * math.sqrt(RHO_OIL / (2 * CD_INF**2 * K))
    D = math.sqrt(4 * A / math.pi)
    Re_c = L * 2 * CD_INF**2 * A * D / (A2**2 * RHO_OIL * NU_OIL)
    return A, D, Re_c


def throttle_coefficients(L_N_s_per_mm, vt_mm_s, A2_mm2):
    """Δp = b Q + a Q|Q| (MPa, Q in mm³/s): b, a from the orifice law with Cd(Re)."""
    L = np.asarray(L_N_s_per_mm, float)
    b = L / A2_mm2**2  # laminar limit: A2 Δp = L ẋ
    K = np.where(np.isfinite(vt_mm_s), L / np.asarray(vt_mm_s, float), 0.0)  # N s²/mm²
    a = K / A2_mm2**3
    return b, a


def throttle_dp_MPa(Q_mm3_s, A_m2: float, D_m: float, Re_c: float, rho: float = RHO_OIL, nu: float = NU_OIL):
    """Pressure drop (MPa) over an orifice of area ``A`` carrying ``Q`` with Cd(Re).

    From Q = Cd(Re) A sqrt(2Δp/ρ), Re = (Q/A) D/ν:
    Δp = ρ/(2 Cd∞²) (Q|Q|/A² + Re_c ν Q/(A D)).

    Parameters
    ----------
    Q_mm3_s : float or array
        Flow (mm³/s), signed.
    A_m2 : float
        Orifice area (m²).
    D_m : float
        Hydraulic diameter (m).
    Re_c : float
        Transition Reynolds number (dimensionless).
    rho : float
        Oil density (kg/m³).
    nu : float
        Kinematic viscosity (m²/s).

    Returns
    -------
    array
        Pressure drop (MPa), sign of ``Q``.
    """
    Q = np.asarray(Q_mm3_s, float) * 1e-9
    dp = rho / (2 * CD_INF**2) * (Q * np.abs(Q) / A_m2**2 + Re_c * nu * Q / (A_m2 * D_m))
    return dp * 1e-6


def throttle_flow_mm3_s(dp_MPa, A_m2: float, D_m: float, Re_c: float, rho: float = RHO_OIL, nu: float = NU_OIL):
    """Flow (mm³/s) through the orifice at pressure drop ``dp`` (inverse of :func:`throttle_dp_MPa`).

    Parameters
    ----------
    dp_MPa : float or array
        Pressure drop (MPa), signed.
    A_m2 : float
        Orifice area (m²).
    D_m : float
        Hydraulic diameter (m).
    Re_c : float
        Transition Reynolds number (dimensionless).
    rho : float
        Oil density (kg/m³).
    nu : float
        Kinematic viscosity (m²/s).

    Returns
    -------
    array
        Flow (mm³/s), sign of ``dp``.
    """
    dp = np.asarray(dp_MPa, float) * 1e6
    c = rho / (2 * CD_INF**2)
    a, b = c / A_m2**2, c * Re_c * nu / (A_m2 * D_m)
    q = (-b + np.sqrt(b * b + 4 * a * np.abs(dp))) / (2 * a)
    return np.sign(dp) * q * 1e9


def relief_flow_mm3_s(dp_MPa, cracking_MPa: float, spring_N_per_mm: float, seat_mm: float = 2.5,
                      max_lift_mm: float = 0.5, cd: float = 0.6, rho: float = RHO_OIL):
    """Flow (mm³/s, sign of Δp) through the spring-loaded ball relief valve (one per direction).

    Parameters
    ----------
    dp_MPa : float or array
        Pressure drop over the valve (MPa), signed.
    cracking_MPa : float
        Opening pressure (MPa).
    spring_N_per_mm : float
        Ball spring rate (N/mm).
    seat_mm : float
        Seat diameter (mm).
    max_lift_mm : float
        Lift stop (mm).
    cd : float
        Discharge coefficient of the curtain area (dimensionless).
    rho : float
        Oil density (kg/m³).

    Returns
    -------
    array
        Flow (mm³/s).
    """
    dp = np.asarray(dp_MPa, float)
    a_seat = math.pi / 4 * seat_mm**2
    lift = np.clip((np.abs(dp) - cracking_MPa) * a_seat / spring_N_per_mm, 0.0, max_lift_mm)  # mm
    area_m2 = math.pi * seat_mm * lift * 1e-6
    u = np.sqrt(2 * np.abs(dp) * 1e6 / rho)  # m/s
    return np.sign(dp) * cd * area_m2 * u * 1e9


def damping_dp_MPa(Q_mm3_s, b, a, relief: dict | None = None, iters: int = 60):
    """Δp (MPa) over the throttle with the relief valve in parallel: Q_t(Δp) + Q_r(Δp) = Q.

    Parameters
    ----------
    Q_mm3_s : float or array
        Flow the piston pushes, A2 ẋ (mm³/s).
    b : float or array
        Laminar throttle coefficient (MPa s/mm³), broadcast with ``Q``.
    a : float or array
        Turbulent throttle coefficient (MPa s²/mm⁶): Δp = b Q_t + a Q_t|Q_t|.
    relief : dict or None
        Keyword arguments of :func:`relief_flow_mm3_s` (``None``: no relief valve).
    iters : int
        Bisection steps (dimensionless).

    Returns
    -------
    array
        Pressure drop (MPa), sign of ``Q``.
    """
    Q = np.asarray(Q_mm3_s, float)
    b = np.broadcast_to(b, Q.shape)
    a = np.broadcast_to(a, Q.shape)
    dp_t = b * Q + a * Q * np.abs(Q)
    if relief is None:
        return dp_t
    dp = dp_t.copy()
    m = np.abs(dp_t) > relief["cracking_MPa"]
    if not m.any():
        return dp
    q, bb, aa = np.abs(Q[m]), b[m], a[m]
    lo = np.full(q.shape, relief["cracking_MPa"])
    hi = np.abs(dp_t[m])

    def qt(d):
        lin = aa <= 0
        safe_a = np.where(lin, 1.0, aa)
        quad = (-bb + np.sqrt(bb * bb + 4 * safe_a * d)) / (2 * safe_a)
        return np.where(lin, d / np.where(bb > 0, bb, np.inf), quad)

    for _ in range(iters):  # Q_t + Q_r is increasing in Δp
        mid = 0.5 * (lo + hi)
        f = qt(mid) + relief_flow_mm3_s(mid, **relief) - q
        lo = np.where(f < 0, mid, lo)
        hi = np.where(f < 0, hi, mid)
    dp[m] = np.sign(Q[m]) * 0.5 * (lo + hi)
    return dp


# ---------------------------------------------------------------- time integration
def _expstep(y, a, b, h):
    """Exact step of ẏ = a - b y over h with a, b frozen (b may be 0 or negative)."""
    bh = b * h
    small = np.abs(bh) < 1e-8
    e = np.exp(-np.where(small, 0.0, bh))
    phi = np.where(small, h * (1 - 0.5 * bh), (1 - e) / np.where(small, 1.0, b))  # (1 - e^{-bh})/b
    return y * np.where(small, 1 - bh, e) + a * phi


def chamber_states(t, V, dV, tau_s, leak_per_s=None):
    """Temperature ratio θ = T/T_w and mass ratio μ = m/m₀ of a gas chamber over time.

    Parameters
    ----------
    t : array (..., n)
        Times (s).
    V : array (..., n)
        Gas volume (mm³, or any consistent unit).
    dV : array (..., n)
        Its rate (mm³/s, same unit per second).
    tau_s : float or array
        Thermal time constant m cv/(hA) (s), broadcast over the leading
        axes; ``inf`` adiabatic, ``0`` isothermal.
    leak_per_s : float, array or None
        Relative leak rate at the initial pressure (1/s; mass flow ∝ P).

    Returns
    -------
    theta, mu : arrays (..., n)
        T/T_w and m/m₀ (dimensionless); the pressure is ``P₀ μ θ V₀/V``.
    """
    t = np.asarray(t, float)
    n = t.shape[-1]
    tau = np.broadcast_to(np.asarray(tau_s, float), t.shape[:-1])
    theta = np.ones(t.shape)
    mu = np.ones(t.shape)
    if np.all(tau == 0) and leak_per_s is None:
        return theta, mu
    inv_tau = np.where(tau > 0, 1.0 / np.where(tau > 0, tau, 1.0), np.inf)
    iso = np.isinf(inv_tau)  # τ = 0: isothermal
    leak = 0.0 if leak_per_s is None else np.broadcast_to(np.asarray(leak_per_s, float), t.shape[:-1])
    th = np.ones(t.shape[:-1])
    m = np.ones(t.shape[:-1])
    V0 = V[..., 0]
    for k in range(n - 1):
        h = t[..., k + 1] - t[..., k]
        Vm = 0.5 * (V[..., k] + V[..., k + 1])
        dVm = 0.5 * (dV[..., k] + dV[..., k + 1])
        # leak: μ̇ = -leak μ θ V₀/V (mass flow ∝ P), frozen θ over the step
        rate = leak * th * V0 / Vm
        m_new = m * np.exp(-rate * h)
        mdot_over_m = -rate
        # θ̇ = 1/τ - θ (1/τ + (κ-1)(V̇/V - ṁ/m))
        a = np.where(iso, 0.0, inv_tau)
        b = a + (KAPPA - 1) * (dVm / Vm - mdot_over_m)
        th_new = np.where(iso, 1.0, _expstep(th, a, b, h))
        th, m = th_new, m_new
        theta[..., k + 1] = th
        mu[..., k + 1] = m
    return theta, mu


def lugre_friction(t, v, Fc, Fs, vs, delta, sigma0, sigma2=0.0, sigma1=None):
    """LuGre friction force along a prescribed velocity; bristles start relaxed (z = 0).

    Parameters
    ----------
    t : array (..., n)
        Times (s).
    v : array (..., n)
        Velocity (mm/s).
    Fc : float or array
        Coulomb force (N), broadcast over the leading axes.
    Fs : float or array
        Breakaway force (N).
    vs : float or array
        Stribeck velocity (mm/s).
    delta : float or array
        Stribeck exponent (dimensionless).
    sigma0 : float or array
        Bristle stiffness (N/mm).
    sigma2 : float or array
        Viscous friction (N s/mm).
    sigma1 : float, array or None
        Bristle damping (N s/mm); default the critical 2 sqrt(σ0 m) of a 0.2 kg piston.

    Returns
    -------
    F, z : arrays (..., n)
        Friction force (N, + opposes extension) and bristle deflection (mm).
    """
    t = np.asarray(t, float)
    v = np.asarray(v, float)
    shp = t.shape[:-1]
    Fc, Fs, vs, delta, sigma0, sigma2 = (np.broadcast_to(np.asarray(q, float), shp) for q in (Fc, Fs, vs, delta, sigma0, sigma2))
    if sigma1 is None:
        sigma1 = 2 * np.sqrt(sigma0 * 1e3 * PISTON_MASS_KG) * 1e-3  # N s/mm
    sigma1 = np.broadcast_to(np.asarray(sigma1, float), shp)
    z = np.zeros(t.shape)
    zk = np.zeros(shp)
    n = t.shape[-1]
    for k in range(n - 1):
        h = t[..., k + 1] - t[..., k]
        vm = 0.5 * (v[..., k] + v[..., k + 1])
        g = np.maximum(Fc + (Fs - Fc) * np.exp(-np.abs(vm / vs) ** delta), 1e-9)
        c = sigma0 * np.abs(vm) / g
        zk = _expstep(zk, vm, c, h)
        z[..., k + 1] = zk
    g = np.maximum(Fc[..., None] + (Fs - Fc)[..., None] * np.exp(-np.abs(v / vs[..., None]) ** delta[..., None]), 1e-9)
    zdot = v - sigma0[..., None] * np.abs(v) * z / g
    F = sigma0[..., None] * z + sigma1[..., None] * zdot + sigma2[..., None] * v
    return F, z


def second_order_filter(t, u, lag_s, zeta):
    """ÿ + 2ζω ẏ + ω² y = ω² u with ω = 2ζ/lag, exact for u held at the step midpoint; y(0) = u(0)."""
    from scipy.linalg import expm

    t = np.asarray(t, float)
    ne, n = t.shape
    w = 2 * zeta / lag_s
    A = np.array([[0.0, 1.0], [-w * w, -2 * zeta * w]])
    B = np.array([0.0, w * w])
    # steps of one experiment are uniform: one discretisation per experiment
    Ad = np.empty((ne, 2, 2))
    Bd = np.empty((ne, 2))
    for e in range(ne):
        h = t[e, 1] - t[e, 0]
        M = np.zeros((3, 3))
        M[:2, :2] = A * h
        M[:2, 2] = B * h
        E = expm(M)
        Ad[e], Bd[e] = E[:2, :2], E[:2, 2]
    y = np.zeros((ne, n))
    s = np.stack([u[:, 0], np.zeros(ne)], axis=1)
    y[:, 0] = u[:, 0]
    for k in range(n - 1):
        um = 0.5 * (u[:, k] + u[:, k + 1])
        s = np.einsum("eij,ej->ei", Ad, s) + Bd * um[:, None]
        y[:, k + 1] = s[:, 0]
    return y
