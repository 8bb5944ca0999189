"""Optimal control of the VVEA by direct collocation (CasADi + IPOPT).

Two parametric solvers, each built once per mesh and solved many times
(the pattern of casadi's ``direct_collocation.py`` and rockit's
``repeated_solve.py``):

* :class:`RestToRestSolver` - paper section 5, eq. 16: minimise
  ``∫₀^{2T} (q - q_des)² dt`` for the square-wave reference of amplitude
  ``A`` and period ``T``, starting at rest at zero. Time is scaled by ``T``
  (``s = t/T``, ``s ∈ [0, 2]``) and angles by ``A``, so one solver serves every
  ``A``, ``T``, ``K``, ``B``, ``M``; the damping and input bounds are IPOPT
  bounds given per solve, so it also serves every actuator setting (a
  constant-damping setting fixes ``D`` and ``u_d``, which IPOPT removes).
* :class:`TorqueStepSolver` - paper section 6, Table 6: track a torque step
  while keeping the damping low.

Discretisation: ``N`` intervals, Radau IIA collocation of degree ``d`` (stiff
accurate, L-stable: the LWR setting has a relative mode at ≈ -8e4 1/s),
inputs piecewise constant per interval. The rest-to-rest reference switches
at ``s = 0.5, 1, 1.5``, so ``N`` must be a multiple of 4; the tracking
integral is then evaluated exactly for the collocation polynomial.

State ``[θ, q, θ', q', D]``, inputs ``[τ_m, u_d]``; SI units (rad, rad/s,
N m s/rad, N m, N m s rad⁻¹ s⁻¹).
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass, field

import casadi as ca
import numpy as np

from .model import Actuator

__all__ = [
    "Mesh",
    "OcpResult",
    "Regularisation",
    "NO_REGULARISATION",
    "RestToRestSolver",
    "TorqueStepSolver",
    "TorqueStepWeights",
    "PAPER_TABLE6",
    "ramp_u_d_profile",
    "rest_to_rest_reference",
    "WARM_START_IPOPT",
]

_IPOPT_DEFAULTS = {
    "ipopt.print_level": 0,
    "print_time": False,
    "ipopt.sb": "yes",
    "ipopt.max_iter": 1000,
    "ipopt.max_cpu_time": 60.0,
    "ipopt.tol": 1e-8,
    "ipopt.mu_strategy": "adaptive",
}


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
            success = bool(st.get("success", False))
            iters = int(st.get("iter_count", -1))
            w = np.asarray(sol["x"]).ravel()
            f = float(sol["f"])
        except RuntimeError as exc:  # an error inside CasADi/IPOPT: recorded, never raised
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


#: IPOPT options for polishing a good start (an interpolated coarse-mesh optimum) on a finer
#: mesh: start at the given point, not pushed into the interior (measured: ~30 % fewer iterations).
WARM_START_IPOPT = {
    "ipopt.warm_start_init_point": "yes",
    "ipopt.warm_start_bound_push": 1e-9,
    "ipopt.warm_start_mult_bound_push": 1e-9,
    "ipopt.mu_init": 1e-5,
}


@dataclass(frozen=True)
class Regularisation:
    """Small penalties that pick, among (nearly) equally good rest-to-rest optima, a smooth one.

    The tracking cost of eq. 16 is flat in many directions: while the link
    rests, the motor can chatter at ±τ_max and D switch between its bounds at
    almost no cost. The penalties are added to the normalised cost
    ``mean(((q - q_des)/A)²)`` (typically 1e-3 ... 1e-1):

    * ``u_d``: weight of ``mean((u_d/u_d_max)²)`` over the horizon;
    * ``tau_rate``: weight of ``Σ_k ((τ_m[k+1] - τ_m[k])/τ_max)²`` over the
      interval steps (a bang-bang switch costs ``4 tau_rate``).

    Reported objectives and rmse stay the pure tracking cost.
    """

    u_d: float = 0.0  #: weight of the mean squared normalised damping rate
    tau_rate: float = 0.0  #: weight of the summed squared normalised motor-torque steps

    def __post_init__(self) -> None:
        for f in ("u_d", "tau_rate"):
            v = getattr(self, f)
            if not (isinstance(v, (int, float)) and math.isfinite(v) and v >= 0):
                raise ValueError(f"Regularisation.{f} must be a finite number >= 0, got {v!r}")

    def weights(self) -> np.ndarray:
        """The NLP parameter values ``[u_d, tau_rate]``.

        Returns
        -------
        numpy.ndarray
            Shape (2,): the two penalty weights (dimensionless; they multiply normalised, dimensionless
            penalty terms).
        """
        return np.array([self.u_d, self.tau_rate], dtype=float)


#: No regularisation: the pure tracking cost of eq. 16.
NO_REGULARISATION = Regularisation()


def rest_to_rest_reference(t_s, A_rad: float, T_s: float) -> np.ndarray:
    """Square-wave reference of section 5.0.1: 0 in the first half period, A in the second.

    Parameters
    ----------
    t_s
        Times, s.
    A_rad
        Amplitude, rad.
    T_s
        Period, s.

    Returns
    -------
    numpy.ndarray
        Reference link angle q_des, rad.
    """
    t = np.asarray(t_s, dtype=float)
    return np.where(np.mod(t, T_s) < 0.5 * T_s, 0.0, A_rad)


def ramp_u_d_profile(actuator: Actuator, dt_s, D_target: float) -> np.ndarray:
    """Piecewise-constant u_d driving D from D_min to ``D_target`` as fast as eq. 12 allows.

    Parameters
    ----------
    actuator
        Setting (D_min, u_d limit).
    dt_s
        Interval lengths in s, one per collocation interval.
    D_target
        Damping to reach and hold, N m s/rad.

    Feasible for the variable-damping problem; used to build multi-start
    initial guesses.

    Returns
    -------
    numpy.ndarray
        u_d per interval, N m s rad⁻¹ s⁻¹.
    """
    dt = np.asarray(dt_s, dtype=float)
    D = actuator.D_min_Nms_per_rad
    out = np.zeros(len(dt))
    for k, h in enumerate(dt):
        u = float(np.clip((D_target - D) / h, -actuator.u_d_max, actuator.u_d_max))
        out[k] = u
        D += u * h
    return out


class RestToRestSolver:
    """Parametric rest-to-rest OCP (paper eq. 16), built once per :class:`Mesh`.

    Holds two IPOPT solvers on the same mesh: one with constant damping
    (SEA, LWR, or a fixed D; a convex QP) and one with the damping state
    (VVEA, iVVEA). Both evaluate the same tracking integral, so objectives
    compare exactly, and any solution can start any other solve
    (:meth:`guess_from`).

    Examples
    --------
    >>> from vvea_design.actuator.model import PAPER_SETTINGS
    >>> s = RestToRestSolver(Mesh(16, 3))
    >>> r = s.solve(PAPER_SETTINGS["SEA"], A_rad=0.5, T_s=1.0)
    >>> r.success and r.extra["rmse_rad"] < 0.5
    True
    """

    def __init__(self, mesh: Mesh = Mesh(), ipopt_options: dict | None = None) -> None:
        if mesh.n_intervals % 4:
            raise ValueError(
                f"Mesh.n_intervals must be a multiple of 4 for rest-to-rest (the reference switches at "
                f"t = T/2, T, 3T/2), got {mesh.n_intervals}"
            )
        self.mesh = mesh
        opts = dict(_IPOPT_DEFAULTS)
        opts.update(ipopt_options or {})
        self.cols: dict[bool, _Collocation] = {}
        self.solvers = {}
        self.Jfuns = {}
        N = mesh.n_intervals
        for variable in (False, True):
            col = _Collocation(mesh, S=2.0, variable_damping=variable, phases=4)
            self.qdes = np.where(np.mod(col.edges[:-1] + 1e-12, 1.0) < 0.5, 0.0, 1.0)
            # exact tracking integral of the collocation polynomial, normalised:
            # mean of ((q - q_des)/A)^2 over the horizon = sum_k h e_k^T Mass e_k / S
            J = 0
            for k in range(N):
                e = ca.vertcat(*[col.w[int(col.iz[k, j, 1])] - self.qdes[k] for j in range(col.d + 1)])
                J += col.h[k] * ca.mtimes([e.T, ca.DM(col.Mass), e])
            J = J / col.S
            # optional regularisation (weights = NLP parameters, 0 = none, see Regularisation):
            # the damping rate, mean of (u_d/u_d_max)^2, and the motor-torque steps,
            # sum_k ((tau_m[k+1] - tau_m[k])/tau_max)^2. Candidates are always compared on J alone.
            reg = ca.SX.sym("reg", 2)
            R_ud = 0
            if variable:
                for k in range(N):
                    R_ud += col.h[k] * col.w[int(col.iu[k, 1])] ** 2
            R_tau = 0
            for k in range(N - 1):
                R_tau += (col.w[int(col.iu[k + 1, 0])] - col.w[int(col.iu[k, 0])]) ** 2
            f = J + reg[0] * R_ud / col.S + reg[1] * R_tau
            nlp = {"x": col.w, "p": ca.vertcat(col.p, reg), "f": f, "g": col.g}
            name = "rest_to_rest_" + ("variable" if variable else "constant")
            self.cols[variable] = col
            self.solvers[variable] = ca.nlpsol(name, "ipopt", nlp, opts)
            self.Jfuns[variable] = ca.Function("J", [col.w], [J])

    def _col(self, act: Actuator) -> _Collocation:
        return self.cols[act.variable_damping]

    def interval_seconds(self, T_s: float) -> np.ndarray:
        """Physical interval lengths (s) for period ``T_s``.

        Parameters
        ----------
        T_s : float
            Period of the rest-to-rest reference; the horizon is two periods.

        Returns
        -------
        numpy.ndarray
            Shape (N,) for the mesh's N intervals: each interval's length in s (they sum to ``2 T_s``).
        """
        return self.cols[True].h * T_s

    def guess_from(self, other: OcpResult, actuator: Actuator, A_rad: float, T_s: float) -> np.ndarray:
        """A start for ``actuator`` built from any solution on this mesh (D clipped into range).

        When ``other`` was not solved on this mesh at this period (other shape or other collocation
        times), its states are first resampled onto this mesh as in :meth:`guess_from_other_mesh`.

        Parameters
        ----------
        other : OcpResult
            A rest-to-rest solution (of any setting), whose physical states ``Z`` and inputs ``U`` seed the start.
        actuator : Actuator
            The setting the start is for; its damping range and damping-rate limit clip the start's D and u_d.
        A_rad : float
            Reference amplitude of the case to solve.
        T_s : float
            Reference period of the case to solve.

        Returns
        -------
        numpy.ndarray
            Decision vector of this solver's NLP for ``actuator`` (scaled, dimensionless variables:
            angles / A, speeds · T / A, D / its scale, inputs / their limits), usable as ``w0``.
        """
        col = self._col(actuator)
        pv = col.params(actuator, A_rad, T_s)
        Zp = np.array(other.Z, dtype=float)
        Up = np.array(other.U, dtype=float)
        if Zp.shape[:2] != (col.N, col.d + 1) or not np.allclose(other.t_points_s, pv[1] * (
                col.edges[:-1, None] + col.h[:, None] * col.tau[None, :])):
            Zp, Up = _resample(other, pv[1] * col.edges, col.tau)
        Zp[..., 4] = np.clip(Zp[..., 4], actuator.D_min_Nms_per_rad, actuator.D_max_Nms_per_rad)
        Up[:, 1] = np.clip(Up[:, 1], -actuator.u_d_max, actuator.u_d_max)
        return col.from_phys(Zp, Up, pv)

    def guess_from_other_mesh(self, other: OcpResult, actuator: Actuator, A_rad: float, T_s: float) -> np.ndarray:
        """A start on *this* mesh from a solution on another (coarser or finer) mesh.

        The states (including D) are interpolated linearly in time through all
        of ``other``'s collocation points onto this mesh's collocation points;
        the piecewise-constant inputs (τ_m, u_d) take ``other``'s value at each
        new interval's midpoint. D is clipped into ``actuator``'s range. Used to
        polish a coarse-mesh multi-start optimum on a fine mesh with one
        warm-started solve (see :data:`WARM_START_IPOPT`).

        Parameters
        ----------
        other : OcpResult
            A rest-to-rest solution on any mesh, for the same case.
        actuator : Actuator
            The setting the start is for (its damping range and damping-rate limit clip D and u_d).
        A_rad : float
            Reference amplitude of the case to solve.
        T_s : float
            Reference period of the case to solve.

        Returns
        -------
        numpy.ndarray
            Decision vector of this solver's NLP for ``actuator`` (scaled, dimensionless variables), usable
            as ``w0``.
        """
        col = self._col(actuator)
        pv = col.params(actuator, A_rad, T_s)
        Zp, Up = _resample(other, pv[1] * col.edges, col.tau)
        Zp[..., 4] = np.clip(Zp[..., 4], actuator.D_min_Nms_per_rad, actuator.D_max_Nms_per_rad)
        Up[:, 1] = np.clip(Up[:, 1], -actuator.u_d_max, actuator.u_d_max)
        return col.from_phys(Zp, Up, pv)

    def evaluate_as(self, other: OcpResult, actuator: Actuator, A_rad: float, T_s: float,
                    status: str = "adopted") -> OcpResult:
        """Re-express a solution of another setting as a candidate for ``actuator``.

        Exact when the solution is feasible for ``actuator`` (e.g. the SEA
        solution, D ≡ 0, for iVVEA): same mesh, same objective, same value.
        No solve is run: the start of :meth:`guess_from` is evaluated on this solver's tracking cost.

        Parameters
        ----------
        other : OcpResult
            A rest-to-rest solution of another setting.
        actuator : Actuator
            The setting the candidate is for.
        A_rad : float
            Reference amplitude of the case.
        T_s : float
            Reference period of the case.
        status : str, optional
            Status string recorded in the result (default ``"adopted"``).

        Returns
        -------
        OcpResult
            The candidate: ``objective`` is the tracking integral in rad² s, ``success`` is ``other``'s,
            0 iterations and 0 s; ``extra`` holds ``rmse_rad`` (rad), ``valid`` (95 % rule),
            ``peak_q_up_rad`` (rad), ``A_rad``, ``T_s`` and ``setting``.
        """
        w = self.guess_from(other, actuator, A_rad, T_s)
        col = self._col(actuator)
        pv = col.params(actuator, A_rad, T_s)
        f = float(self.Jfuns[actuator.variable_damping](w))
        return self._result(col, w, f, status, other.success, 0, 0.0, pv, actuator, A_rad, T_s)

    def solve(
        self,
        actuator: Actuator,
        A_rad: float,
        T_s: float,
        w0: np.ndarray | None = None,
        u_d_fixed: np.ndarray | None = None,
        regularisation: "Regularisation | None" = None,
    ) -> OcpResult:
        """Solve eq. 16 for one actuator setting, amplitude and period.

        Parameters
        ----------
        actuator
            The setting (K, damping range, inertias, limits).
        A_rad, T_s
            Reference amplitude (rad) and period (s); horizon ``t_e = 2 T``.
        w0
            Initial guess (a decision vector for this setting), e.g. from
            :meth:`guess_from`. Default: everything at rest, D at D_min.
        u_d_fixed
            Fix the damping input to this per-interval profile
            (N m s rad⁻¹ s⁻², length N; variable-damping settings only); the
            problem is then a convex QP in the motor torque.
        regularisation
            Small penalties added to the tracking cost (:class:`Regularisation`);
            ``None`` = none (pure eq. 16). ``objective`` and ``rmse_rad`` are
            always the pure tracking integral.

        Returns
        -------
        OcpResult
            ``objective`` = ``∫₀^{t_e} (q - q_des)² dt`` (rad² s); ``extra`` holds
            ``rmse_rad``, ``valid`` (link above 95 % of A in both up-phases)
            and ``peak_q_up_rad``.
        """
        if not (isinstance(A_rad, (int, float)) and math.isfinite(A_rad) and A_rad > 0):
            raise ValueError(f"A_rad must be a positive amplitude in rad, got {A_rad!r}")
        if not (isinstance(T_s, (int, float)) and math.isfinite(T_s) and T_s > 0):
            raise ValueError(f"T_s must be a positive period in s, got {T_s!r}")
        if u_d_fixed is not None and not actuator.variable_damping:
            raise ValueError("u_d_fixed needs a variable-damping actuator (D_max > D_min)")
        col = self._col(actuator)
        pv = col.params(actuator, A_rad, T_s)
        lbx, ubx = col.bounds(actuator, pv, u_d_fixed)
        if w0 is None:
            w0 = np.zeros(col.nw)
            if col.variable:
                w0[col.iz[:, :, 4].ravel()] = actuator.D_min_Nms_per_rad / pv[2]
        w, f, status, success, iters, secs = col.solve(self.solvers[col.variable], w0,
                                                       np.append(pv, (regularisation or NO_REGULARISATION).weights()),
                                                       lbx, ubx)
        if np.all(np.isfinite(w)):
            f = float(self.Jfuns[col.variable](w))
        return self._result(col, w, f, status, success, iters, secs, pv, actuator, A_rad, T_s)

    def _result(self, col, w, f, status, success, iters, secs, pv, act, A, T) -> OcpResult:
        te = 2.0 * T
        r = _result_from(col, w, f * A**2 * te, status, success, iters, secs, pv, {})
        r.extra["cpu_seconds"] = getattr(col, "last_cpu_seconds", 0.0) if secs > 0 else 0.0
        N = col.N
        if np.all(np.isfinite(w)):
            qc = r.Z[:, :, 1]  # (N, d+1)
            q4 = N // 4
            peaks = [float(np.max(qc[q4:2 * q4])), float(np.max(qc[3 * q4:]))]
            valid = bool(success and min(peaks) >= 0.95 * A)
            rmse = A * math.sqrt(max(f, 0.0))
        else:
            peaks, valid, rmse = [float("nan")] * 2, False, float("nan")
        r.extra.update(rmse_rad=rmse, valid=valid, peak_q_up_rad=peaks, A_rad=A, T_s=T, setting=act.name)
        return r


@dataclass(frozen=True)
class TorqueStepWeights:
    """Weights and horizon of the torque-step OCP (paper Table 6)."""

    P_tau: float = 4e4  #: torque tracking weight, 1/(N² m²)
    P_d: float = 2.5e-2  #: damping weight, s² N⁻² m² (per (N m s/rad)²)
    P_m: float = 1e1  #: motor-torque weight, 1/(N² m²)
    t_e_s: float = 0.5  #: horizon, s

    def __post_init__(self) -> None:
        for f in ("P_tau", "P_d", "P_m"):
            v = getattr(self, f)
            if not (math.isfinite(v) and v >= 0):
                raise ValueError(f"TorqueStepWeights.{f} must be >= 0, got {v!r}")
        if not (math.isfinite(self.t_e_s) and self.t_e_s > 0):
            raise ValueError(f"TorqueStepWeights.t_e_s must be > 0 s, got {self.t_e_s!r}")


#: Table 6 of the paper.
PAPER_TABLE6 = TorqueStepWeights()


class TorqueStepSolver:
    """Parametric torque-step OCP of section 6, built once per :class:`Mesh`.

    Minimises ``∫₀^{t_e} P_τ (τ - τ_ref)² + P_d (D - D_min)² + P_m τ_m² dt``
    from rest, for a step ``τ_ref`` applied at ``t = 0``. The damping cost uses
    the *actuator's* ``D_min``; for fixed-damping settings it is a constant.
    The cost integral uses the Radau quadrature.
    """

    def __init__(self, mesh: Mesh = Mesh(100, 3), ipopt_options: dict | None = None) -> None:
        self.mesh = mesh
        opts = dict(_IPOPT_DEFAULTS)
        opts.update(ipopt_options or {})
        self.cols, self.solvers, self.terms = {}, {}, {}
        for variable in (False, True):
            col = _Collocation(mesh, S=1.0, variable_damping=variable)
            wts = ca.SX.sym("wts", 5)  # P_tau, P_d, P_m, tau_ref, D_min_cost
            P_tau, P_d, P_m, tau_ref, Dmin = (wts[i] for i in range(5))
            Ts = col.p[1]
            Jt = Jd = Jm = 0
            for k in range(col.N):
                tau_m = col.p[3] * col.w[int(col.iu[k, 0])]
                Jm += col.h[k] * Ts * tau_m**2
                for j in range(1, col.d + 1):
                    tj, Dj = col.tau_at[k][j - 1]
                    Jt += col.h[k] * Ts * col.Bq[j] * (tj - tau_ref) ** 2
                    Jd += col.h[k] * Ts * col.Bq[j] * (Dj - Dmin) ** 2
            J = P_tau * Jt + P_d * Jd + P_m * Jm
            scale = P_tau * tau_ref**2 * Ts + 1e-12
            p_all = ca.vertcat(col.p, wts)
            nlp = {"x": col.w, "p": p_all, "f": J / scale, "g": col.g}
            self.cols[variable] = col
            self.solvers[variable] = ca.nlpsol("torque_step_" + str(variable), "ipopt", nlp, opts)
            self.terms[variable] = ca.Function("terms", [col.w, p_all], [Jt, Jd, Jm, scale])

    def solve(
        self,
        actuator: Actuator,
        tau_ref_Nm: float = 50.0,
        weights: TorqueStepWeights = PAPER_TABLE6,
        D_cost_ref_Nms_per_rad: float | None = None,
        w0: np.ndarray | None = None,
    ) -> OcpResult:
        """Solve the torque-step OCP.

        Parameters
        ----------
        actuator
            Setting; use ``M_kgm2 = 1e4`` for the paper's near-fixed link.
        tau_ref_Nm
            Step height τ_ref (N m), applied at t = 0.
        weights
            Table 6 weights and horizon.
        D_cost_ref_Nms_per_rad
            ``D_min`` inside the damping cost (default: the actuator's).
        w0
            Initial guess (decision vector of the matching solver: scaled, dimensionless variables, e.g.
            ``OcpResult.w`` of an earlier solve); default zeros with D at its lower bound.

        Returns
        -------
        OcpResult
            ``extra`` holds ``J_tau``, ``J_D``, ``J_m`` (unweighted integrals),
            ``mean_D_Nms_per_rad``, ``t95_s`` (first time τ >= 0.95 τ_ref) and
            ``max_D_Nms_per_rad``.

        Raises
        ------
        ValueError
            When ``tau_ref_Nm`` is zero or not finite.
        """
        if not (math.isfinite(tau_ref_Nm) and tau_ref_Nm != 0):
            raise ValueError(f"tau_ref_Nm must be a non-zero torque in N m, got {tau_ref_Nm!r}")
        col = self.cols[actuator.variable_damping]
        a = abs(tau_ref_Nm) / actuator.K_Nm_per_rad
        pv = col.params(actuator, a, weights.t_e_s)
        Dref = actuator.D_min_Nms_per_rad if D_cost_ref_Nms_per_rad is None else D_cost_ref_Nms_per_rad
        wv = np.array([weights.P_tau, weights.P_d, weights.P_m, tau_ref_Nm, Dref])
        p_all = np.concatenate([pv, wv])
        lbx, ubx = col.bounds(actuator, pv)
        if w0 is None:
            w0 = np.zeros(col.nw)
            if col.variable:
                w0[col.iz[:, :, 4].ravel()] = actuator.D_min_Nms_per_rad / pv[2]
        w, f, status, success, iters, secs = col.solve(self.solvers[col.variable], w0, p_all, lbx, ubx)
        if np.all(np.isfinite(w)):
            Jt, Jd, Jm, scale = (float(v) for v in self.terms[col.variable](w, p_all))
            obj = f * scale
        else:
            Jt = Jd = Jm = obj = float("nan")
        r = _result_from(col, w, obj, status, success, iters, secs, pv, {})
        # time-weighted mean damping from the collocation polynomial (quadrature)
        Dq = r.Z[:, 1:, 4]
        meanD = float(np.sum(Dq * col.Bq[1:] * col.h[:, None]) / col.S)
        # time to 95 % of the step, from the states at every collocation point
        t_pts = np.concatenate([[0.0], r.t_points_s[:, 1:].ravel()])
        Zf = np.concatenate([r.Z[:1, 0, :], r.Z[:, 1:, :].reshape(-1, 5)], axis=0)
        tau = Zf[:, 4] * (Zf[:, 2] - Zf[:, 3]) + actuator.K_Nm_per_rad * (Zf[:, 0] - Zf[:, 1])
        y = tau / tau_ref_Nm
        reach = np.nonzero(y >= 0.95)[0]
        if len(reach) == 0 or not np.all(np.isfinite(y)):
            t95 = float("nan")
        elif reach[0] == 0:
            t95 = 0.0
        else:
            i = reach[0]
            t95 = float(np.interp(0.95, [y[i - 1], y[i]], [t_pts[i - 1], t_pts[i]]))
        r.extra.update(
            J_tau=Jt, J_D=Jd, J_m=Jm, mean_D_Nms_per_rad=meanD, t95_s=t95,
            max_D_Nms_per_rad=float(np.max(r.Z[..., 4])), setting=actuator.name, tau_ref_Nm=tau_ref_Nm,
        )
        return r
