"""Radau collocation shared by the actuator's optimal control problems (:mod:`~vvea_design.actuator.ocp`).

:class:`Mesh` (intervals, degree, grading) and :class:`OcpResult` (one solve's outcome, trajectories on
the grid) are the public part; ``_Collocation`` transcribes the scaled actuator dynamics (eqs 8-10) on a
mesh: ``N`` intervals, Radau IIA collocation of degree ``d`` (stiff accurate, L-stable), inputs piecewise
constant per interval. State ``[θ, q, θ', q', D]``, inputs ``[τ_m, u_d]``; SI units (rad, rad/s,
N m s/rad, N m, N m s rad⁻¹ s⁻¹).
"""

from __future__ import annotations

import time
from dataclasses import dataclass, field

import casadi as ca
import numpy as np

from ..parallel import interrupt_noted
from ..plausibility import LIMITS
from .model import Actuator

__all__ = ["Mesh", "OcpResult"]

@dataclass(frozen=True)
class Mesh:
    """Collocation mesh: ``n_intervals`` intervals of Radau degree ``degree``."""

    n_intervals: int = 64  #: number of collocation intervals over the horizon
    degree: int = 3  #: Radau collocation degree (order 2d-1)
    #: end clustering β in [0, 1) inside each phase of the horizon (rest-to-rest: the
    #: four half periods): interval edges at (1-β)σ + β(1-cos πσ)/2, σ uniform.
    #: β = 0 is a uniform mesh; β > 0 refines around the reference jumps.
    grading: float = 0.0

    def __post_init__(self) -> None:
        if not (0.0 <= self.grading < 1.0):
            raise ValueError(f"Mesh.grading must be in [0, 1), got {self.grading!r}")
        if int(self.n_intervals) != self.n_intervals or self.n_intervals < 4:
            raise ValueError(f"Mesh.n_intervals must be a whole number >= 4, got {self.n_intervals!r}")
        LIMITS["mesh_intervals"].check(self.n_intervals, "Mesh.n_intervals", ValueError)
        if int(self.degree) != self.degree or not 1 <= self.degree <= 9:
            raise ValueError(f"Mesh.degree must be a whole number in 1..9, got {self.degree!r}")


@dataclass
class OcpResult:
    """Outcome of one OCP solve.

    ``objective`` is the problem's own cost (for rest-to-rest the tracking
    integral ``∫ (q - q_des)² dt`` in rad² s). Trajectories are sampled at the
    interval start points plus the end point (``t_s``, length N+1); inputs
    are per interval (length N).
    """

    status: str  #: IPOPT return status ("Solve_Succeeded", ...)
    success: bool  #: IPOPT reported success
    objective: float  #: cost value (nan if the solver failed badly)
    iterations: int  #: IPOPT iterations
    seconds: float  #: wall time of the solve, s
    w: np.ndarray = field(repr=False)  #: raw decision vector (for warm starts)
    t_s: np.ndarray = field(repr=False)  #: time grid, s
    theta_rad: np.ndarray = field(repr=False)  #: motor angle
    q_rad: np.ndarray = field(repr=False)  #: link angle
    dtheta_rad_s: np.ndarray = field(repr=False)  #: motor speed
    dq_rad_s: np.ndarray = field(repr=False)  #: link speed
    D_Nms_per_rad: np.ndarray = field(repr=False)  #: damping
    tau_m_Nm: np.ndarray = field(repr=False)  #: motor torque per interval
    u_d: np.ndarray = field(repr=False)  #: damping rate per interval
    tau_Nm: np.ndarray = field(repr=False)  #: link torque at the grid points
    Z: np.ndarray = field(repr=False)  #: physical states at every collocation point (N, d+1, 5)
    U: np.ndarray = field(repr=False)  #: physical inputs per interval (N, 2)
    t_points_s: np.ndarray = field(repr=False, default=None)  #: times of the points of Z (N, d+1)
    extra: dict = field(default_factory=dict)  #: problem-specific numbers


def _radau(d: int):
    """Collocation matrices on [0, 1]: derivative matrix C, quadrature B, mass matrix."""
    tau = np.append(0.0, ca.collocation_points(d, "radau"))
    C = np.zeros((d + 1, d + 1))
    Bq = np.zeros(d + 1)
    polys = []
    for j in range(d + 1):
        p = np.poly1d([1.0])
        for r in range(d + 1):
            if r != j:
                p *= np.poly1d([1.0, -tau[r]]) / (tau[j] - tau[r])
        polys.append(p)
        dp = np.polyder(p)
        for r in range(d + 1):
            C[j, r] = dp(tau[r])
        Bq[j] = np.polyint(p)(1.0)
    Mass = np.zeros((d + 1, d + 1))
    for i in range(d + 1):
        for j in range(d + 1):
            Mass[i, j] = np.polyint(polys[i] * polys[j])(1.0)
    return tau, C, Bq, Mass


class _Collocation:
    """Shared transcription: scaled states and inputs, Radau collocation.

    Scaled variables: ``θ = a θ̃``, ``θ' = (a/Ts) ω̃``, ``D = ds D̃``,
    ``τ_m = τmax τ̃``, ``u_d = umax ũ``; normalised time ``s ∈ [0, S]`` with
    ``t = Ts s``. ``a, Ts, ds, τmax, umax, K, B, M, D_const`` are NLP
    parameters. With ``variable_damping=False`` the damping is the parameter
    ``D_const`` (4 states, 1 input: a convex QP in the motor torque); with
    ``True`` it is the fifth state driven by ``u_d`` (eq. 10).
    """

    NP = 9  # a, Ts, ds, taumax, umax, K, B, M, D_const

    def __init__(self, mesh: Mesh, S: float, variable_damping: bool, phases: int = 1) -> None:
        self.mesh = mesh
        N, d = mesh.n_intervals, mesh.degree
        self.N, self.d, self.S = N, d, S
        if N % phases:
            raise ValueError(f"Mesh.n_intervals must be a multiple of {phases}, got {N}")
        npp = N // phases
        sig = np.linspace(0.0, 1.0, npp + 1)
        b = mesh.grading
        phi = (1 - b) * sig + b * (1 - np.cos(np.pi * sig)) / 2
        edges = np.concatenate([[0.0]] + [(i + phi[1:]) * S / phases for i in range(phases)])
        self.edges = edges  #: interval edges in normalised time, (N+1,)
        self.h = np.diff(edges)  #: interval lengths in normalised time, (N,)
        self.variable = variable_damping
        self.nx = nx = 5 if variable_damping else 4
        self.nu = nu = 2 if variable_damping else 1
        self.tau, self.C, self.Bq, self.Mass = _radau(d)
        p = ca.SX.sym("p", self.NP)
        self.p = p
        a, Ts, ds, taumax, umax, K, B, M, Dc = (p[i] for i in range(self.NP))
        z = ca.SX.sym("z", nx)
        v = ca.SX.sym("v", nu)
        dth = (a / Ts) * z[2]
        dq = (a / Ts) * z[3]
        D = ds * z[4] if variable_damping else Dc
        tau = D * (dth - dq) + K * a * (z[0] - z[1])
        tau_m = taumax * v[0]
        rhs = [z[2], z[3], Ts**2 / a * (tau_m - tau) / B, Ts**2 / a * tau / M]
        if variable_damping:
            rhs.append(Ts * umax * v[1] / ds)
        self.f = ca.Function("f", [z, v, p], [ca.vertcat(*rhs), tau, D])
        # decision vector: fixed start state, then per interval k: U_k, Z_k1..Z_kd
        self.nw = N * (nu + nx * d) + nx
        w = ca.SX.sym("w", self.nw)
        self.w = w
        self.iz0 = np.arange(nx)
        off = nx
        self.iu = np.zeros((N, nu), dtype=int)
        self.iz = np.zeros((N, d + 1, nx), dtype=int)  # index of the state at point j of interval k (j=0: start)
        prev = self.iz0
        for k in range(N):
            self.iu[k] = off + np.arange(nu)
            off += nu
            self.iz[k, 0] = prev
            for j in range(1, d + 1):
                self.iz[k, j] = off + np.arange(nx)
                off += nx
            prev = self.iz[k, d]
        assert off == self.nw
        g = []
        self.tau_at = []  # (link torque, damping) at collocation points j = 1..d of each interval
        for k in range(N):
            Zk = [w[list(self.iz[k, j])] for j in range(d + 1)]
            Uk = w[list(self.iu[k])]
            taus = []
            for j in range(1, d + 1):
                zp = sum(self.C[r, j] * Zk[r] for r in range(d + 1))
                fj, tj, Dj = self.f(Zk[j], Uk, p)
                g.append(zp - self.h[k] * fj)
                taus.append((tj, Dj))
            self.tau_at.append(taus)
        self.g = ca.vertcat(*g)

    def params(self, act: Actuator, a: float, Ts: float) -> np.ndarray:
        ds = max(act.D_max_Nms_per_rad, 1.0)
        return np.array(
            [a, Ts, ds, act.tau_m_max_Nm, act.u_d_max, act.K_Nm_per_rad, act.B_kgm2, act.M_kgm2,
             act.D_min_Nms_per_rad]
        )

    def bounds(self, act: Actuator, pv: np.ndarray, u_d_fixed=None):
        """lbx/ubx: start at rest at zero with D(0) = D_min; input and damping bounds."""
        lbx = np.full(self.nw, -np.inf)
        ubx = np.full(self.nw, np.inf)
        for k in range(self.N):
            lbx[self.iu[k, 0]], ubx[self.iu[k, 0]] = -1.0, 1.0
        if self.variable:
            ds = pv[2]
            iD = self.iz[:, 1:, 4].ravel()
            lbx[iD] = act.D_min_Nms_per_rad / ds
            ubx[iD] = act.D_max_Nms_per_rad / ds
            iu = self.iu[:, 1]
            if u_d_fixed is None:
                lbx[iu], ubx[iu] = -1.0, 1.0
            else:
                lbx[iu] = ubx[iu] = np.asarray(u_d_fixed, float) / act.u_d_max
        z0 = np.zeros(self.nx)
        if self.variable:
            z0[4] = act.D_min_Nms_per_rad / pv[2]
        lbx[self.iz0] = ubx[self.iz0] = z0
        return lbx, ubx

    # -- physical <-> decision vector ------------------------------------------------------
    def to_phys(self, w: np.ndarray, pv: np.ndarray):
        """(Z, U): states at every point (N, d+1, 5) and inputs (N, 2), physical units."""
        a, Ts, ds, taumax, umax = pv[:5]
        Z = w[self.iz].astype(float)  # (N, d+1, nx)
        U = w[self.iu].astype(float)  # (N, nu)
        Zp = np.empty((self.N, self.d + 1, 5))
        Zp[..., 0:2] = a * Z[..., 0:2]
        Zp[..., 2:4] = a / Ts * Z[..., 2:4]
        Zp[..., 4] = ds * Z[..., 4] if self.variable else pv[8]
        Up = np.zeros((self.N, 2))
        Up[:, 0] = taumax * U[:, 0]
        if self.variable:
            Up[:, 1] = umax * U[:, 1]
        return Zp, Up

    def from_phys(self, Zp: np.ndarray, Up: np.ndarray, pv: np.ndarray) -> np.ndarray:
        """Decision vector from physical states (N, d+1, 5) and inputs (N, 2)."""
        a, Ts, ds, taumax, umax = pv[:5]
        w = np.zeros(self.nw)
        Z = np.empty((self.N, self.d + 1, self.nx))
        Z[..., 0:2] = Zp[..., 0:2] / a
        Z[..., 2:4] = Zp[..., 2:4] * Ts / a
        if self.variable:
            Z[..., 4] = Zp[..., 4] / ds
        w[self.iz] = Z
        w[self.iu[:, 0]] = Up[:, 0] / taumax
        if self.variable:
            w[self.iu[:, 1]] = Up[:, 1] / umax
        return w

    def solve(self, solver, w0, pv, lbx, ubx):
        args = dict(x0=np.clip(w0, lbx, ubx), p=pv, lbx=lbx, ubx=ubx, lbg=0.0, ubg=0.0)
        t0 = time.perf_counter()
        c0 = time.process_time()
        try:
            sol = solver(**args)
            st = solver.stats()
            status = str(st.get("return_status", "unknown"))
            if status == "User_Requested_Stop" or (status == "NonIpopt_Exception_Thrown" and interrupt_noted()):
                # IPOPT's own Ctrl-C handler stopped it, or CasADi's signal check raised the KeyboardInterrupt
                # inside the solve and IPOPT swallowed it: the user's interrupt either way
                raise KeyboardInterrupt("interrupted during an IPOPT solve")
            success = bool(st.get("success", False))
            iters = int(st.get("iter_count", -1))
            w = np.asarray(sol["x"]).ravel()
            f = float(sol["f"])
        except RuntimeError as exc:  # an error inside CasADi/IPOPT: recorded, never raised
            if "KeyboardInterrupt" in str(exc) or "nterrupted" in str(exc):  # Ctrl-C seen inside CasADi
                raise KeyboardInterrupt("interrupted during a CasADi call") from None
            status, success, iters = f"error: {exc}".splitlines()[0][:200], False, -1
            w, f = np.full(self.nw, np.nan), float("nan")
        self.last_cpu_seconds = time.process_time() - c0
        return w, f, status, success, iters, time.perf_counter() - t0


def _result_from(col: _Collocation, w, f_obj, status, success, iters, secs, pv, extra) -> OcpResult:
    """Pack a solution into an :class:`OcpResult` (grid = interval starts + end)."""
    N, d = col.N, col.d
    if np.all(np.isfinite(w)):
        Zp, Up = col.to_phys(w, pv)
    else:
        Zp, Up = np.full((N, d + 1, 5), np.nan), np.full((N, 2), np.nan)
    grid = np.concatenate([Zp[:, 0, :], Zp[-1:, d, :]], axis=0)  # (N+1, 5)
    K = pv[5]
    tau = grid[:, 4] * (grid[:, 2] - grid[:, 3]) + K * (grid[:, 0] - grid[:, 1])
    return OcpResult(
        status=status,
        success=success,
        objective=f_obj,
        iterations=iters,
        seconds=secs,
        w=w,
        t_s=pv[1] * col.edges,
        theta_rad=grid[:, 0],
        q_rad=grid[:, 1],
        dtheta_rad_s=grid[:, 2],
        dq_rad_s=grid[:, 3],
        D_Nms_per_rad=grid[:, 4],
        tau_m_Nm=Up[:, 0],
        u_d=Up[:, 1],
        tau_Nm=tau,
        Z=Zp,
        U=Up,
        t_points_s=pv[1] * (col.edges[:-1, None] + col.h[:, None] * col.tau[None, :]),
        extra=extra,
    )


def _resample(other: OcpResult, edges_s: np.ndarray, tau: np.ndarray):
    """States (linear interpolation through all points) and inputs (value at the interval midpoint)
    of ``other`` on another mesh with interval edges ``edges_s`` (s) and collocation points ``tau``."""
    t_old = other.t_points_s[:, 1:].ravel()
    t_old = np.concatenate([[0.0], t_old])
    Z_old = np.concatenate([other.Z[:1, 0, :], other.Z[:, 1:, :].reshape(-1, 5)], axis=0)
    h = np.diff(edges_s)
    t_new = edges_s[:-1, None] + h[:, None] * tau[None, :]
    Zp = np.stack([np.interp(t_new, t_old, Z_old[:, c]) for c in range(5)], axis=-1)
    mid = edges_s[:-1] + h / 2
    k = np.clip(np.searchsorted(other.t_s, mid, side="right") - 1, 0, len(other.U) - 1)
    return Zp, other.U[k]
