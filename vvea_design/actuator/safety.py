"""Safety study of paper section 6: the torque step, variable vs fixed damping (Table 6, Fig. 14)."""

from __future__ import annotations

import csv
import json
import math
import time
from collections.abc import Sequence
from dataclasses import asdict, dataclass, field
from pathlib import Path

import numpy as np

from ..plausibility import LIMITS
from .figures import plot_safety
from .model import PAPER_SETTINGS, Actuator
from .multistart import _pick_label
from .ocp import Mesh, OcpResult, PAPER_TABLE6, TorqueStepSolver, TorqueStepWeights

__all__ = ["PAPER_SAFETY", "TorqueStepCase", "SafetyStudy", "solve_safety", "run_safety", "SAFETY_MESH",
           "PAPER_LINK_INERTIA_KGM2", "PAPER_TAU_REF_NM", "PAPER_FIXED_D_NMS_PER_RAD"]


#: What the paper states about Fig. 14.
PAPER_SAFETY = {
    "mean_D_variable_Nms_per_rad": 31.0,
    "statement_speed": "variable D reaches tau_ref nearly as fast as D = 200; D = 31 is significantly slower",
    "D_converges_to_min_Nms_per_rad": 12.1,
    "D_converges_at_s": 0.4,
}


#: Mesh of the safety study: 200 Radau intervals clustered towards both ends of the 0.5 s horizon.
SAFETY_MESH = Mesh(200, 3, grading=0.8)
#: Link inertia of the paper's torque step (kg m²): an almost fixed link.
PAPER_LINK_INERTIA_KGM2 = 1e4
#: Height of the paper's torque step (N m).
PAPER_TAU_REF_NM = 50.0
#: The constant dampings the paper compares variable damping with (N m s/rad; Fig. 14).
PAPER_FIXED_D_NMS_PER_RAD = (31.0, 200.0)

# -- per-process solver cache: building the two parametric torque-step NLPs takes ~0.6 s, a solve ~0.5 s
_SOLVERS: dict[Mesh, TorqueStepSolver] = {}


def _solver(mesh: Mesh) -> TorqueStepSolver:
    if mesh not in _SOLVERS:
        _SOLVERS[mesh] = TorqueStepSolver(mesh)
    return _SOLVERS[mesh]


@dataclass(frozen=True)
class TorqueStepCase:
    """One actuator's optimal torque step (SI units; integrals unweighted)."""

    name: str  #: case label ("variable D 12.1-200", "fixed D 31", ...)
    status: str  #: IPOPT status
    success: bool  #: IPOPT success
    objective: float  #: Table-6 cost
    J_tau_N2m2s: float  #: ∫ (τ - τ_ref)² dt
    J_D: float  #: ∫ (D - D_min)² dt, (N m s/rad)² s
    J_m_N2m2s: float  #: ∫ τ_m² dt
    mean_D_Nms_per_rad: float  #: time-mean damping
    max_D_Nms_per_rad: float  #: peak damping
    t95_s: float  #: first time τ >= 0.95 τ_ref
    final_D_Nms_per_rad: float  #: damping at the horizon's end
    final_tau_Nm: float  #: link torque at the horizon's end
    seconds: float  #: solver wall time

    def to_dict(self) -> dict:
        """Plain-JSON dictionary (the fields except ``name``).

        Returns
        -------
        dict
            JSON-ready fields by name, SI: ``status``, ``success``, ``objective`` (Table-6 cost),
            ``J_tau_N2m2s`` (N² m² s), ``J_D`` ((N m s/rad)² s), ``J_m_N2m2s`` (N² m² s),
            ``mean_D_Nms_per_rad`` / ``max_D_Nms_per_rad`` / ``final_D_Nms_per_rad`` (N m s/rad),
            ``t95_s`` (s), ``final_tau_Nm`` (N m) and ``seconds`` (solver wall time, s).
        """
        d = asdict(self)
        d.pop("name")
        return d

    @classmethod
    def from_result(cls, name: str, r: OcpResult) -> "TorqueStepCase":
        """From a :class:`~vvea_design.actuator.ocp.TorqueStepSolver` result.

        Parameters
        ----------
        name : str
            Case label, e.g. ``"variable D 12.1-200"`` or ``"fixed D 31"``.
        r : OcpResult
            Result of :meth:`~vvea_design.actuator.ocp.TorqueStepSolver.solve`; its ``extra`` must hold
            ``J_tau``, ``J_D``, ``J_m``, ``mean_D_Nms_per_rad``, ``max_D_Nms_per_rad`` and ``t95_s``.

        Returns
        -------
        TorqueStepCase
            The case, SI; ``final_D_Nms_per_rad`` (N m s/rad) and ``final_tau_Nm`` (N m) are the
            trajectory's last grid-point values.

        Raises
        ------
        KeyError
            When ``r.extra`` lacks one of the torque-step numbers (``r`` is not a torque-step result).
        """
        return cls(name, r.status, r.success, r.objective, r.extra["J_tau"], r.extra["J_D"], r.extra["J_m"],
                   r.extra["mean_D_Nms_per_rad"], r.extra["max_D_Nms_per_rad"], r.extra["t95_s"],
                   float(r.D_Nms_per_rad[-1]), float(r.tau_Nm[-1]), r.seconds)


@dataclass(frozen=True)
class SafetyStudy:
    """Result of :func:`solve_safety`: the variable-damping step and the fixed-damping ones."""

    cases: tuple[TorqueStepCase, ...]  #: variable case first, then each fixed D
    variable_case: str  #: name of the variable-damping case
    variable_start_won: str | None  #: start that gave the variable case's optimum
    variable_start_objectives: dict  #: objective of every start (None = failed)
    variable_D_settles_near_min_at_s: float | None  #: D within 5 % of the range above D_min from then on
    setup: dict  #: K, B, M, τ_ref, weights, mesh, damping range
    wall_seconds: float  #: time of all solves
    results: dict = field(repr=False, default_factory=dict)  #: OcpResult per case name (trajectories)

    def case(self, name: str) -> TorqueStepCase:
        """The case called ``name``.

        Parameters
        ----------
        name : str
            Case label as in :attr:`TorqueStepCase.name`.

        Returns
        -------
        TorqueStepCase
            The first case with that name.

        Raises
        ------
        KeyError
            When no case has that name (the message lists the names there are).
        """
        for c in self.cases:
            if c.name == name:
                return c
        raise KeyError(f"no torque-step case {name!r}; cases: {[c.name for c in self.cases]}")

    @property
    def variable(self) -> TorqueStepCase:
        """The variable-damping case."""
        return self.case(self.variable_case)

    def to_dict(self) -> dict:
        """JSON summary (the format of ``safety.json``).

        Returns
        -------
        dict
            JSON-ready: ``cases`` (case name to :meth:`TorqueStepCase.to_dict`, SI), ``variable_case``,
            ``variable_start_won``, ``variable_start_objectives`` (start to its objective, ``None`` when it
            failed), ``variable_D_settles_near_min_at_s`` (s or ``None``), ``setup`` (K, B, M, τ_ref,
            weights, mesh, damping range; SI), ``paper`` (the paper's numbers, for context) and
            ``wall_seconds`` (time of all solves, s, 2 decimals).
        """
        return {
            "cases": {c.name: c.to_dict() for c in self.cases},
            "variable_case": self.variable_case,
            "variable_start_won": self.variable_start_won,
            "variable_start_objectives": self.variable_start_objectives,
            "variable_D_settles_near_min_at_s": self.variable_D_settles_near_min_at_s,
            "setup": self.setup,
            "paper": PAPER_SAFETY,
            "wall_seconds": round(self.wall_seconds, 2),
        }


def solve_safety(
    base: Actuator = PAPER_SETTINGS["VVEA"],
    *,
    M_kgm2: float = PAPER_LINK_INERTIA_KGM2,
    tau_ref_Nm: float = PAPER_TAU_REF_NM,
    fixed_D_Nms_per_rad: Sequence[float] = PAPER_FIXED_D_NMS_PER_RAD,
    weights: TorqueStepWeights = PAPER_TABLE6,
    mesh: Mesh = SAFETY_MESH,
    solver: TorqueStepSolver | None = None,
    name: str | None = None,
) -> SafetyStudy:
    """Section 6: the torque step with variable damping vs fixed damping (no files).

    Case (a) varies D in [D_min, D_max] of ``base`` from D(0) = D_min and is
    solved from a cold start and from each fixed-D solution (D clipped into
    the range), keeping the best; cases (b), (c), ... hold D at each of
    ``fixed_D_Nms_per_rad`` (the damping cost referenced to ``base``'s D_min, as
    in the paper's single cost).

    Parameters
    ----------
    base
        Setting whose K, inertia B, limits and damping range are used.
    M_kgm2
        Link inertia (kg m²); 1e4 = the paper's almost fixed link.
    tau_ref_Nm
        Step height (N m).
    fixed_D_Nms_per_rad
        Constant dampings to compare (N m s/rad); may be empty.
    weights, mesh
        Table 6 weights and horizon; collocation mesh.
    solver
        A :class:`TorqueStepSolver` on ``mesh`` to reuse (built if ``None``).
    name
        Label of the variable case (default ``"variable D <min>-<max>"``).

    Returns
    -------
    SafetyStudy
    """
    if not (math.isfinite(M_kgm2) and M_kgm2 > 0):
        raise ValueError(f"M_kgm2 must be a positive inertia, got {M_kgm2!r}")
    LIMITS["link_inertia_kgm2"].check(M_kgm2, "M_kgm2", ValueError)
    LIMITS["torque_step_Nm"].check(abs(tau_ref_Nm) if isinstance(tau_ref_Nm, (int, float)) else tau_ref_Nm,
                                   "|tau_ref_Nm|", ValueError)
    s = solver if solver is not None else _solver(mesh)
    var = base.with_(M_kgm2=M_kgm2,
                     name=name or f"variable D {base.D_min_Nms_per_rad:.3g}-{base.D_max_Nms_per_rad:.3g}")
    t0 = time.perf_counter()
    fixed: dict[str, OcpResult] = {}
    for Dc in fixed_D_Nms_per_rad:
        act = base.with_(M_kgm2=M_kgm2, D_min_Nms_per_rad=float(Dc), D_max_Nms_per_rad=float(Dc), name=f"fixed D {Dc:g}")
        fixed[act.name] = s.solve(act, tau_ref_Nm, weights, D_cost_ref_Nms_per_rad=base.D_min_Nms_per_rad)
    cand = {"cold": s.solve(var, tau_ref_Nm, weights)}
    col = s.cols[True]
    for fname, r in fixed.items():
        if r.success:
            Zp, Up = np.array(r.Z), np.array(r.U)
            Zp[..., 4] = np.clip(Zp[..., 4], var.D_min_Nms_per_rad, var.D_max_Nms_per_rad)
            pv = col.params(var, abs(tau_ref_Nm) / var.K_Nm_per_rad, weights.t_e_s)
            cand[f"from {fname}"] = s.solve(var, tau_ref_Nm, weights, w0=col.from_phys(Zp, Up, pv))
    label = _pick_label(cand)
    results: dict[str, OcpResult] = {var.name: cand[label] if label else cand["cold"]}
    results.update(fixed)
    vr = results[var.name]
    # first time after which D stays within 5 % of the range above D_min
    thr = var.D_min_Nms_per_rad + 0.05 * (var.D_max_Nms_per_rad - var.D_min_Nms_per_rad)
    settle = None
    if np.all(np.isfinite(vr.D_Nms_per_rad)) and np.any(vr.D_Nms_per_rad <= thr):
        above = np.nonzero(vr.D_Nms_per_rad > thr)[0]
        if not len(above):
            settle = 0.0
        elif above[-1] + 1 < len(vr.t_s):
            settle = float(vr.t_s[above[-1] + 1])
    return SafetyStudy(
        cases=tuple(TorqueStepCase.from_result(n, r) for n, r in results.items()),
        variable_case=var.name,
        variable_start_won=label,
        variable_start_objectives={k: (v.objective if v.success else None) for k, v in cand.items()},
        variable_D_settles_near_min_at_s=settle,
        setup={"K_Nm_per_rad": base.K_Nm_per_rad, "B_kgm2": base.B_kgm2, "M_kgm2": M_kgm2,
               "tau_ref_Nm": tau_ref_Nm, "weights": asdict(weights), "mesh": asdict(mesh),
               "D_range_Nms_per_rad": [base.D_min_Nms_per_rad, base.D_max_Nms_per_rad]},
        wall_seconds=time.perf_counter() - t0,
        results=results,
    )


def write_trajectories_csv(results: dict[str, OcpResult], path: Path) -> Path:
    """τ, τ_m, D, θ, q of every case over time, one row per grid point."""
    with Path(path).open("w", newline="") as fh:
        wr = csv.writer(fh)
        wr.writerow(["case", "t_s", "tau_Nm", "tau_m_Nm", "D_Nms_per_rad", "theta_rad", "q_rad"])
        for name, r in results.items():
            taum = np.append(r.tau_m_Nm, r.tau_m_Nm[-1])
            for i in range(len(r.t_s)):
                wr.writerow([name, f"{r.t_s[i]:.6g}", f"{r.tau_Nm[i]:.8g}", f"{taum[i]:.8g}",
                             f"{r.D_Nms_per_rad[i]:.8g}", f"{r.theta_rad[i]:.8g}", f"{r.q_rad[i]:.8g}"])
    return Path(path)


def run_safety(
    out_dir: str | Path,
    *,
    base: Actuator = PAPER_SETTINGS["VVEA"],
    M_kgm2: float = PAPER_LINK_INERTIA_KGM2,
    tau_ref_Nm: float = PAPER_TAU_REF_NM,
    fixed_D_Nms_per_rad: Sequence[float] = PAPER_FIXED_D_NMS_PER_RAD,
    weights: TorqueStepWeights = PAPER_TABLE6,
    mesh: Mesh = SAFETY_MESH,
    figures: bool = True,
) -> SafetyStudy:
    """:func:`solve_safety` and its files: ``safety.json`` (numbers + the paper's
    statements), ``safety_trajectories.csv`` and ``safety.png`` (Fig. 14).

    Parameters
    ----------
    out_dir
        Output folder (created).
    base, M_kgm2, tau_ref_Nm, fixed_D_Nms_per_rad, weights, mesh
        As in :func:`solve_safety` (inertia in kg m², torque in N m, damping in N m s/rad).
    figures
        Write ``safety.png``.

    Returns
    -------
    SafetyStudy
        The study (per case: objective, mean/max D in N m s/rad, time to 95 % of τ_ref in s, status);
        ``to_dict()`` is the content of ``safety.json``.
    """
    study = solve_safety(base, M_kgm2=M_kgm2, tau_ref_Nm=tau_ref_Nm, fixed_D_Nms_per_rad=fixed_D_Nms_per_rad,
                         weights=weights, mesh=mesh)
    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    (out / "safety.json").write_text(json.dumps(study.to_dict(), indent=2))
    write_trajectories_csv(study.results, out / "safety_trajectories.csv")
    if figures:
        plot_safety(study.results, tau_ref_Nm, base_setting=base.name).savefig(out / "safety.png", dpi=130)
    return study
