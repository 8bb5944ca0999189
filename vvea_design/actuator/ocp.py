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

Discretisation (:mod:`~vvea_design.actuator.collocation`, which also holds
:class:`Mesh` and :class:`OcpResult`): ``N`` intervals, Radau IIA collocation of degree ``d`` (stiff
accurate, L-stable: the LWR setting has a relative mode at ≈ -8e4 1/s),
inputs piecewise constant per interval. The rest-to-rest reference switches
at ``s = 0.5, 1, 1.5``, so ``N`` must be a multiple of 4; the tracking
integral is then evaluated exactly for the collocation polynomial.

State ``[θ, q, θ', q', D]``, inputs ``[τ_m, u_d]``; SI units (rad, rad/s,
N m s/rad, N m, N m s rad⁻¹ s⁻¹).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import casadi as ca
import numpy as np

from .collocation import Mesh, OcpResult, _Collocation, _result_from, _resample
from .model import Actuator
from .solver_cache import cached_functions

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


class _PerStructure:
    """``obj[variable]``: one of a solver's functions for a structure (True: variable damping), built on first use."""

    def __init__(self, functions, name: str) -> None:
        self._functions, self._name = functions, name

    def __getitem__(self, variable: bool):
        return self._functions(bool(variable))[self._name]


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
        self._opts = dict(_IPOPT_DEFAULTS)
        self._opts.update(ipopt_options or {})
        self.cols: dict[bool, _Collocation] = {v: _Collocation(mesh, S=2.0, variable_damping=v, phases=4)
                                              for v in (False, True)}
        self.qdes = np.where(np.mod(self.cols[True].edges[:-1] + 1e-12, 1.0) < 0.5, 0.0, 1.0)
        self._funcs: dict[bool, dict] = {}
        #: IPOPT solver per structure (True: variable damping), built or loaded on first use
        self.solvers = _PerStructure(self._functions, "solver")
        #: tracking integral J(w) per structure (normalised, dimensionless)
        self.Jfuns = _PerStructure(self._functions, "J")

    def _functions(self, variable: bool) -> dict:
        if variable not in self._funcs:
            key = (self.mesh, variable, tuple(sorted(self._opts.items())))
            self._funcs[variable] = cached_functions("rest_to_rest", key, lambda: self._build(variable))
        return self._funcs[variable]

    def _build(self, variable: bool) -> dict:
        """The NLP of one structure: IPOPT solver and the tracking integral J(w)."""
        col = self.cols[variable].symbolic()
        N = self.mesh.n_intervals
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
        return {"solver": ca.nlpsol(name, "ipopt", nlp, self._opts), "J": ca.Function("J", [col.w], [J])}

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
        self._opts = dict(_IPOPT_DEFAULTS)
        self._opts.update(ipopt_options or {})
        self.cols = {v: _Collocation(mesh, S=1.0, variable_damping=v) for v in (False, True)}
        self._funcs: dict[bool, dict] = {}
        #: IPOPT solver per structure (True: variable damping), built or loaded on first use
        self.solvers = _PerStructure(self._functions, "solver")
        #: the cost's terms (J_tau, J_D, J_m, scale) per structure
        self.terms = _PerStructure(self._functions, "terms")

    def _functions(self, variable: bool) -> dict:
        if variable not in self._funcs:
            key = (self.mesh, variable, tuple(sorted(self._opts.items())))
            self._funcs[variable] = cached_functions("torque_step", key, lambda: self._build(variable))
        return self._funcs[variable]

    def _build(self, variable: bool) -> dict:
        """The NLP of one structure: IPOPT solver and the cost's terms."""
        col = self.cols[variable].symbolic()
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
        return {"solver": ca.nlpsol("torque_step_" + str(variable), "ipopt", nlp, self._opts),
                "terms": ca.Function("terms", [col.w, p_all], [Jt, Jd, Jm, scale])}

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
