"""Safety study of paper section 6: the torque step, variable vs fixed damping (Table 6, Fig. 14)."""

from __future__ import annotations

import csv
import json
import math
import time
from collections.abc import Sequence
from dataclasses import asdict
from pathlib import Path

import numpy as np

from .figures import plot_safety
from .model import PAPER_SETTINGS, Actuator
from .multistart import _pick_label
from .ocp import Mesh, OcpResult, PAPER_TABLE6, TorqueStepSolver, TorqueStepWeights

__all__ = ["PAPER_SAFETY", "run_safety"]


#: What the paper states about Fig. 14.
PAPER_SAFETY = {
    "mean_D_variable_Nms_per_rad": 31.0,
    "statement_speed": "variable D reaches tau_ref nearly as fast as D = 200; D = 31 is significantly slower",
    "D_converges_to_min_Nms_per_rad": 12.1,
    "D_converges_at_s": 0.4,
}


def run_safety(
    out_dir: str | Path,
    *,
    base: Actuator = PAPER_SETTINGS["VVEA"],
    M_kgm2: float = 1e4,
    tau_ref_Nm: float = 50.0,
    fixed_D_Nms_per_rad: Sequence[float] = (31.0, 200.0),
    weights: TorqueStepWeights = PAPER_TABLE6,
    mesh: Mesh = Mesh(200, 3, grading=0.8),
    figures: bool = True,
) -> dict:
    """Section 6: torque step with variable damping vs fixed damping.

    Case (a) varies D in [D_min, D_max] of ``base`` from D(0) = D_min and is
    solved from several starts (cold, each fixed-D solution, a ramp) keeping
    the best; cases (b), (c), ... hold D constant. Writes ``safety.json``
    (numbers + the paper's statements), ``safety_trajectories.csv`` and
    ``safety.png``.

    Returns
    -------
    dict
        Per case: objective, mean/max D, time to 95 % of τ_ref, status.
    """
    if not (math.isfinite(M_kgm2) and M_kgm2 > 0):
        raise ValueError(f"M_kgm2 must be a positive inertia, got {M_kgm2!r}")
    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    s = TorqueStepSolver(mesh)
    var = base.with_(M_kgm2=M_kgm2, name=f"variable D {base.D_min_Nms_per_rad:g}-{base.D_max_Nms_per_rad:g}")
    results: dict[str, OcpResult] = {}
    cases = {}
    t0 = time.perf_counter()
    fixed = {}
    for Dc in fixed_D_Nms_per_rad:
        act = base.with_(M_kgm2=M_kgm2, D_min_Nms_per_rad=float(Dc), D_max_Nms_per_rad=float(Dc), name=f"fixed D {Dc:g}")
        # damping cost referenced to the variable case's D_min, as in the paper's single cost
        fixed[act.name] = s.solve(act, tau_ref_Nm, weights, D_cost_ref_Nms_per_rad=base.D_min_Nms_per_rad)
    cand = {"cold": s.solve(var, tau_ref_Nm, weights)}
    col = s.cols[True]
    for name, r in fixed.items():
        if r.success:
            Zp, Up = np.array(r.Z), np.array(r.U)
            Zp[..., 4] = np.clip(Zp[..., 4], var.D_min_Nms_per_rad, var.D_max_Nms_per_rad)
            pv = col.params(var, abs(tau_ref_Nm) / var.K_Nm_per_rad, weights.t_e_s)
            cand[f"from {name}"] = s.solve(var, tau_ref_Nm, weights, w0=col.from_phys(Zp, Up, pv))
    label = _pick_label(cand)
    results[var.name] = cand[label] if label else cand["cold"]
    results.update(fixed)
    for name, r in results.items():
        cases[name] = {
            "status": r.status,
            "success": r.success,
            "objective": r.objective,
            "J_tau_N2m2s": r.extra["J_tau"],
            "J_D": r.extra["J_D"],
            "J_m_N2m2s": r.extra["J_m"],
            "mean_D_Nms_per_rad": r.extra["mean_D_Nms_per_rad"],
            "max_D_Nms_per_rad": r.extra["max_D_Nms_per_rad"],
            "t95_s": r.extra["t95_s"],
            "final_D_Nms_per_rad": float(r.D_Nms_per_rad[-1]),
            "final_tau_Nm": float(r.tau_Nm[-1]),
            "seconds": r.seconds,
        }
    vr = results[var.name]
    near = np.nonzero(vr.D_Nms_per_rad <= var.D_min_Nms_per_rad + 0.05 * (var.D_max_Nms_per_rad - var.D_min_Nms_per_rad))[0]
    # first time after which D stays within 5 % of the range above D_min
    settle = None
    above = np.nonzero(vr.D_Nms_per_rad > var.D_min_Nms_per_rad + 0.05 * (var.D_max_Nms_per_rad - var.D_min_Nms_per_rad))[0]
    if len(near):
        settle = float(vr.t_s[above[-1] + 1]) if len(above) and above[-1] + 1 < len(vr.t_s) else (
            0.0 if not len(above) else None)
    summary = {
        "cases": cases,
        "variable_case": var.name,
        "variable_start_won": label,
        "variable_start_objectives": {k: (v.objective if v.success else None) for k, v in cand.items()},
        "variable_D_settles_near_min_at_s": settle,
        "setup": {"K_Nm_per_rad": base.K_Nm_per_rad, "B_kgm2": base.B_kgm2, "M_kgm2": M_kgm2,
                  "tau_ref_Nm": tau_ref_Nm, "weights": asdict(weights), "mesh": asdict(mesh),
                  "D_range_Nms_per_rad": [base.D_min_Nms_per_rad, base.D_max_Nms_per_rad]},
        "paper": PAPER_SAFETY,
        "wall_seconds": round(time.perf_counter() - t0, 2),
    }
    (out / "safety.json").write_text(json.dumps(summary, indent=2))
    with (out / "safety_trajectories.csv").open("w", newline="") as fh:
        wr = csv.writer(fh)
        wr.writerow(["case", "t_s", "tau_Nm", "tau_m_Nm", "D_Nms_per_rad", "theta_rad", "q_rad"])
        for name, r in results.items():
            taum = np.append(r.tau_m_Nm, r.tau_m_Nm[-1])
            for i in range(len(r.t_s)):
                wr.writerow([name, f"{r.t_s[i]:.6g}", f"{r.tau_Nm[i]:.8g}", f"{taum[i]:.8g}",
                             f"{r.D_Nms_per_rad[i]:.8g}", f"{r.theta_rad[i]:.8g}", f"{r.q_rad[i]:.8g}"])
    if figures:
        plot_safety(results, tau_ref_Nm, out / "safety.png")
    return summary


