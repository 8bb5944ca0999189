"""The design's own actuator study, fast enough for the main job (``vvea design``).

:func:`run_design_study` answers the designer's question — does this unit track better than a plain SEA
*of the same stiffness*? — in two labelled runs:

* **equal stiffness** (the default comparison): the design charged for a target joint stiffness
  (``target_K_Nm_per_rad``, default the paper's 362 N m/rad; :func:`~vvea_design.actuator.stiffness.charge_for_stiffness`
  picks the charge inside the unit's pressure limits and says which limit binds when the target is out of
  range) against an SEA of the same K, and against the paper's VVEA and LWR for context;
* **full charge**: the design at the charge it is sized for, against an SEA of that (higher) K.

The design's damping range is the built unit's own (``Design.damping_range_N_s_per_mm()``: throttle open and
closed, relief-capped) through the tendon pulley, or the paper's Table 4 range when the design carries none
(:mod:`~vvea_design.actuator.damping`); the result names which and why. Every case is counted
(:class:`~vvea_design.actuator.design_results.Comparison`): a case where the design is not valid (or not
verified) while the other is valid is a loss. :class:`~vvea_design.actuator.design_results.DampingUse` says
what the optima ask of the valve (peak damping per case, cases at D_max, damping torque against the relief
valves).

Rest-to-rest (section 5) on :data:`DESIGN_GRID` (3 amplitudes x 3 periods spread over the paper's grid), one
mesh (:data:`DESIGN_MESH`, 64 Radau intervals), the multi-start reduced to :data:`DESIGN_STARTS` (a start
list with ``"neighbour"`` solves the cases in chains over the periods of each amplitude,
:func:`~vvea_design.actuator.multistart.solve_chain`; the default, without, one work item per case), the study
regularisation; every trajectory is re-simulated (:mod:`~vvea_design.actuator.verify`). Safety (section 6):
the 50 N m torque step of the design at equal stiffness with variable damping and with fixed D = 31 N m s/rad
(the paper's slow case), and of the paper's VVEA with variable damping. Settings that differ only by name are
solved once (with Table 4's range, the design at 362 N m/rad *is* the paper's VVEA).

One parametric CasADi solver per mesh and process serves every case (cached on disk,
:mod:`~vvea_design.actuator.solver_cache`); the cases (or chains) and torque steps run through
:func:`vvea_design.parallel.parallel_map`. ``studies/bench_design_study.py`` prints the time breakdown.

Example
-------
>>> from vvea_design.spring.design_file import load_design      # doctest: +SKIP
>>> study = run_design_study(load_design("cad/design.json"), out_dir="out/actuator")  # doctest: +SKIP
>>> study.comparison("SEA").fraction_design_beats                # doctest: +SKIP
"""

from __future__ import annotations

import csv
import dataclasses
import json
import math
import time
from collections.abc import Callable, Sequence
from dataclasses import asdict, dataclass, field
from pathlib import Path

import numpy as np

from ..parallel import parallel_map
from ..spring.gas_spring import GasSpring
from .damping import DampingRange, unit_damping_range
from .design_results import (EQUAL_STIFFNESS, FULL_CHARGE, CaseResult, Comparison, DampingUse, SettingSummary,
                             StudyFiles, StudyRun, StudyTiming, damping_use)
from .figures import plot_design_vs_sea, plot_safety, plot_trajectory
from .model import PAPER_PULLEY_RADIUS_M, PAPER_SETTINGS, Actuator, actuator_from_spring
from .multistart import (DEFAULT_REGULARISATION, RESULT_COLUMNS, CaseRow, RestToRestCase, _chain_item, chains,
                         solve_chain)
from .ocp import Mesh, Regularisation
from .rest_to_rest import Grid
from .safety import SafetyStudy, solve_safety
from .statistics import PAPER_TABLE5, table5_statistics
from .stiffness import ATMOSPHERE_MPA, PAPER_K_NM_PER_RAD, ChargeChoice, charge_for_stiffness

__all__ = [
    "DESIGN_GRID",
    "DESIGN_MESH",
    "DESIGN_STARTS",
    "DESIGN_IPOPT",
    "DESIGN_SAFETY_MESH",
    "DESIGN_REFERENCES",
    "CaseResult",
    "SettingSummary",
    "Comparison",
    "StudyRun",
    "DampingUse",
    "StudyTiming",
    "StudyFiles",
    "DesignStudy",
    "EQUAL_STIFFNESS",
    "FULL_CHARGE",
    "design_actuator",
    "study_actuators",
    "unit_mapping",
    "run_design_study",
]

#: Rest-to-rest grid of the design study: 3 amplitudes x 3 periods of the paper's grid (small, large and the largest
#: amplitude; fast, medium and slow periods). A subset of the earlier 4 x 4 grid (A = 0.2, 0.4, 0.7, 1.0 rad;
#: T = 0.3, 0.6, 1.0, 1.5 s) at 9/16 of its solves (the same optima case by case): on ``cad/design.json`` the
#: answer stays (the design beats SEA of equal stiffness in 3/9 cases against 6/16, mean rmse ratio SEA / design
#: 0.899 against 0.919; full charge 2/9 against 3/16, 0.936 both; VVEA / design 1.015 against 1.016): the dropped
#: A = 0.4 rad row sits near a tie. A = 0.7 rad, T = 0.3 s (the design not valid, SEA valid) is kept.
DESIGN_GRID = Grid((0.2, 0.7, 1.0), (0.3, 0.6, 1.5))
#: Mesh of the design study (single level; SEA's grid-mean rmse is within 0.6 % of N = 256 here).
DESIGN_MESH = Mesh(64, 3)
#: Starts of the variable-damping settings: the D_min solution (adopted as is, and the NLP started from it).
#: The neighbouring period's optimum (``"neighbour"``, in chains) never won on this grid: on the committed study
#: of ``cad/design.json`` it tied or lost in all 36 chained cases of the three variable settings, so the optima
#: are the same without it at half the NLP solves (``studies/bench_ocp.py --design-starts``); on the paper grid
#: the D_min start alone comes within 0.2 % of the full multi-start for VVEA. Without it every case is its own
#: work item (no chains), so the two workers share the grid evenly.
DESIGN_STARTS = ("const-Dmin",)
#: IPOPT options of the design study's rest-to-rest solves: the monotone barrier update, 23 % less CPU than the
#: adaptive one on 2 x 4 cases of ``cad/design.json`` (``studies/bench_ocp.py --design-starts``); 6 of the 48
#: optima changed, 3 better by up to 0.8 %, 3 worse by up to 0.3 %, none changed validity.
DESIGN_IPOPT = (("ipopt.mu_strategy", "monotone"),)
#: Mesh of the design's torque step (t95 within 0.3 % of the 200-interval mesh, docs/actuator.md).
DESIGN_SAFETY_MESH = Mesh(100, 3, grading=0.8)
#: Fixed dampings (N m s/rad) the design's variable-damping torque step is compared with (paper: 31 and 200).
DESIGN_SAFETY_FIXED_D = (31.0,)
#: The paper's settings the design is compared with at equal stiffness (SEA: at the design's K).
DESIGN_REFERENCES = ("VVEA", "SEA", "LWR")
#: Setting names of the full-charge run.
FULL_DESIGN, FULL_SEA = "design, full charge", "SEA, full charge"


@dataclass(frozen=True)
class DesignStudy:
    """Result of :func:`run_design_study`."""

    actuator: Actuator  #: the design's joint actuator at equal stiffness (name "design")
    references: tuple[Actuator, ...]  #: the settings it is compared with at equal stiffness ("SEA" at its K)
    runs: tuple[StudyRun, ...]  #: equal stiffness first, then full charge (when the design can be recharged)
    damping: DampingRange  #: the damping range used and why
    grid: Grid  #: rest-to-rest grid
    mesh: Mesh  #: collocation mesh
    starts: tuple[str, ...]  #: variable-damping starts
    regularisation: Regularisation  #: input smoothing (rmse stays the pure tracking cost)
    cases: tuple[CaseResult, ...]  #: every setting at every case
    settings: tuple[SettingSummary, ...]  #: design first, then the references, then the full-charge run's
    comparisons: tuple[Comparison, ...]  #: the design against each other setting of its run, every case counted
    safety_design: SafetyStudy  #: torque step of the design at equal stiffness (variable D, and fixed D = 31)
    safety_reference: SafetyStudy  #: the same for the paper's VVEA
    timing: StudyTiming  #: time breakdown
    files: StudyFiles = field(default_factory=StudyFiles)  #: what was written
    trajectory_case: tuple[float, float] = (float("nan"), float("nan"))  #: (A, T) of the trajectory figure
    best: dict = field(default_factory=dict, repr=False)  #: OcpResult per setting at ``trajectory_case``

    def comparison(self, other: str, run: str = EQUAL_STIFFNESS) -> Comparison:
        """The comparison with the setting called ``other`` in ``run``.

        Parameters
        ----------
        other : str
            Name of a setting of the run (``"SEA"``, ``"VVEA"``, ``"LWR"`` at equal stiffness;
            ``"SEA, full charge"`` at full charge).
        run : str
            :data:`EQUAL_STIFFNESS` (default) or :data:`FULL_CHARGE`.

        Returns
        -------
        Comparison
            The design against ``other`` over every case of the grid.

        Raises
        ------
        KeyError
            When the study has no such comparison (the message lists the ones it has).
        """
        for c in self.comparisons:
            if c.other == other and c.run == run:
                return c
        raise KeyError(f"no comparison with {other!r} in run {run!r}; have "
                       f"{[(c.run, c.other) for c in self.comparisons]}")

    def run(self, label: str) -> StudyRun:
        """The run called ``label``.

        Parameters
        ----------
        label : str
            :data:`EQUAL_STIFFNESS` or :data:`FULL_CHARGE`.

        Returns
        -------
        StudyRun
            The design's actuator, charge and damping use in that run.

        Raises
        ------
        KeyError
            When the study has no such run.
        """
        for r in self.runs:
            if r.label == label:
                return r
        raise KeyError(f"no run {label!r}; have {[r.label for r in self.runs]}")

    def report_tables(self) -> list[tuple[str, tuple[str, ...], list[tuple]]]:
        """Tables for a report: (title, header, rows) each; numbers rounded for reading.

        Returns
        -------
        list of (str, tuple of str, list of tuple)
            Four tables, each as (title, column headers, rows of formatted cells; ``"-"`` for a missing or
            non-finite number): the comparisons of both runs over every case (counts, percent of every case,
            rmse ratios), the settings over the grid (K in N m/rad, D range in N m s/rad, mean rmse in rad),
            what the optima ask of the valve (N m s/rad, N m) and the torque steps (t95 in ms, mean and max D
            in N m s/rad, status).
        """
        def f(x, fmt):
            return "-" if x is None or (isinstance(x, float) and not math.isfinite(x)) else format(x, fmt)

        n = len(self.grid.cases())
        comp = [(c.run, f"{c.design} vs {c.other}", f"{c.design_beats} of {c.n_cases}", f(c.fraction_design_beats, ".0%"),
                 c.design_worse, c.only_other_valid, c.neither_valid, f(c.meanrmse_other_over_design, ".3f"),
                 c.n_both_valid, f(c.paper_vvea_beats, ".1%")) for c in self.comparisons]
        sets = [(s.name, f(s.K_Nm_per_rad, ".0f"), f"{s.D_min_Nms_per_rad:.3g}-{s.D_max_Nms_per_rad:.4g}",
                 f"{s.n_valid} of {s.n_cases}", s.n_unverified, f(s.mean_rmse_rad, ".4f")) for s in self.settings]
        use = [(r.label, r.damping_use.n_cases, r.damping_use.n_reach_D_max, r.damping_use.n_stay_at_D_min,
                f(r.damping_use.largest_D_used_Nms_per_rad, ".4g"), f(r.damping_use.largest_damping_torque_Nm, ".0f"),
                f(r.damping_use.relief_torque_Nm, ".0f"), r.damping_use.n_over_relief) for r in self.runs]
        steps = []
        for st in (self.safety_design, self.safety_reference):
            for c in st.cases:
                steps.append((c.name, f(c.t95_s * 1e3, ".1f"), f(c.mean_D_Nms_per_rad, ".1f"),
                              f(c.max_D_Nms_per_rad, ".1f"), c.status))
        return [
            (f"Rest-to-rest: the design against the other settings, every one of the {n} cases counted (the design "
             "not valid while the other is: a loss)",
             ("run", "comparison", "design better", "of every case", "design worse", "of those: only the other valid",
              "neither valid", "mean rmse other / design (both valid)", "both valid", "paper: VVEA better"), comp),
            ("Settings over the grid", ("setting", "K (N m/rad)", "D (N m s/rad)", "valid cases",
                                        "not verified", "mean rmse (rad), cases all valid"), sets),
            (f"What the optima ask of the valve ({self.damping.source})",
             ("run", "valid optima", "reach D_max", "stay at D_min", "highest D used (N m s/rad)",
              "largest damping torque (N m)", "relief torque (N m)", "above the relief torque"), use),
            (f"Torque step {self.safety_design.setup['tau_ref_Nm']:g} N m (M = "
             f"{self.safety_design.setup['M_kgm2']:g} kg m²)",
             ("case", "t95 (ms)", "mean D (N m s/rad)", "max D (N m s/rad)", "status"), steps),
        ]

    @property
    def n_left_out(self) -> int:
        """Results whose trajectory did not verify (each counted as not usable, so a loss against a usable rival)."""
        return sum(s.n_unverified for s in self.settings)

    def to_dict(self) -> dict:
        """JSON-ready summary (what ``design_study.json`` holds).

        Returns
        -------
        dict
            JSON-ready: the design actuator and the references (their fields, SI), the runs (charge in MPa,
            K in N m/rad, damping use), the damping range and its source, the grid (``A_rad`` in rad, ``T_s``
            in s), mesh, starts, regularisation, per-setting summaries, comparisons (every case counted), the
            number of unverified results, both torque-step studies, timing (s), file names, the trajectory
            figure's case (``A_rad``, ``T_s``) and every case result (see the ``to_dict`` of each part).
        """
        return {
            "actuator": asdict(self.actuator),
            "references": [asdict(a) for a in self.references],
            "runs": [r.to_dict() for r in self.runs],
            "damping": self.damping.to_dict(),
            "grid": {"A_rad": list(self.grid.A_rad), "T_s": list(self.grid.T_s)},
            "mesh": asdict(self.mesh),
            "starts": list(self.starts),
            "regularisation": asdict(self.regularisation),
            "settings": [s.to_dict() for s in self.settings],
            "comparisons": [c.to_dict() for c in self.comparisons],
            "n_left_out_unverified": self.n_left_out,
            "safety_design": self.safety_design.to_dict(),
            "safety_reference": self.safety_reference.to_dict(),
            "timing": self.timing.to_dict(),
            "files": self.files.to_dict(),
            "trajectory_case": {"A_rad": self.trajectory_case[0], "T_s": self.trajectory_case[1]},
            "cases": [c.to_dict() for c in self.cases],
        }


def design_actuator(design, **mapping) -> Actuator:
    """The design's joint actuator named ``"design"`` at its own charge, with the Table 3 valve mapping.

    Parameters
    ----------
    design
        An :class:`Actuator` (used as is, renamed), a
        :class:`~vvea_design.spring.gas_spring.GasSpring`, or any object with
        a ``gas_spring`` attribute (a :class:`~vvea_design.spring.design.Design`).
    **mapping
        Keyword arguments of :func:`~vvea_design.actuator.model.actuator_from_spring`
        (``pulley_radius_m``, ``p2_MPa``, ``gamma_min_deg``, ``gamma_max_deg``, ``n_units``).

    Returns
    -------
    Actuator
        K (N m/rad) and damping range (N m s/rad) of the joint, named ``"design"``.
    """
    if isinstance(design, Actuator):
        if mapping:
            raise ValueError(f"mapping options {sorted(mapping)} need a spring, not an Actuator")
        return design.with_(name="design")
    spring = design if isinstance(design, GasSpring) else getattr(design, "gas_spring", None)
    if not isinstance(spring, GasSpring):
        raise ValueError(f"design must be an Actuator, a GasSpring or have a .gas_spring, got {type(design).__name__}")
    return actuator_from_spring(spring, name="design", **mapping)


_MAPPING_KEYS = ("pulley_radius_m", "n_units")


def study_actuators(design, *, target_K_Nm_per_rad: float = PAPER_K_NM_PER_RAD, damping: DampingRange | None = None,
                    mapping: dict | None = None, max_charge_MPa: float | None = None,
                    min_pressure_MPa: float = ATMOSPHERE_MPA,
                    ) -> tuple[list[tuple[str, Actuator, Actuator, ChargeChoice | None]], DampingRange]:
    """The design's actuators of the study's runs, each with an SEA of the same stiffness.

    Parameters
    ----------
    design
        A :class:`~vvea_design.spring.design.Design` (or anything with ``.gas_spring``), a
        :class:`~vvea_design.spring.gas_spring.GasSpring`, or an :class:`Actuator` (used as is: one run at its
        own K).
    target_K_Nm_per_rad
        Joint stiffness of the equal-stiffness run, N m/rad.
    damping
        The damping range to use (default: the unit's own, :func:`~vvea_design.actuator.damping.unit_damping_range`).
    mapping
        ``pulley_radius_m`` (m; default the design's ``fixed.pulley_radius_mm``, else the paper's) and
        ``n_units`` (default 2).
    max_charge_MPa, min_pressure_MPa
        The unit's pressure limits (MPa, absolute; see :func:`~vvea_design.actuator.stiffness.charge_for_stiffness`).

    Returns
    -------
    (list of (str, Actuator, Actuator, ChargeChoice or None), DampingRange)
        Per run: its label, the design's actuator, the SEA of the same K, the charge (None for an
        Actuator); and the damping range used.

    Raises
    ------
    ValueError
        For an unknown mapping option or a design of an unknown kind.
    """
    mapping = dict(mapping or {})
    unknown = sorted(set(mapping) - set(_MAPPING_KEYS))
    if unknown:
        raise ValueError(f"mapping options {unknown} are not used by the study; it takes {list(_MAPPING_KEYS)} "
                         "(the charge follows from target_K_Nm_per_rad, the damping from the unit)")
    if isinstance(design, Actuator):
        act = design.with_(name="design")
        if damping is not None:
            act = act.with_(D_min_Nms_per_rad=damping.D_min_Nms_per_rad, D_max_Nms_per_rad=damping.D_max_Nms_per_rad)
        rng = damping or DampingRange(act.D_min_Nms_per_rad, act.D_max_Nms_per_rad, "the given actuator",
                                      "the design was given as an Actuator")
        sea = Actuator("SEA", act.K_Nm_per_rad, 0.0, 0.0, act.B_kgm2, act.M_kgm2, act.u_d_max, act.tau_m_max_Nm)
        return [(EQUAL_STIFFNESS, act, sea, None)], rng
    spring, r, n, x0, tau_max = unit_mapping(design, mapping)
    rng = damping or unit_damping_range(design, pulley_radius_m=r, n_units=n)
    runs = []
    for label, target, dname, sname in ((EQUAL_STIFFNESS, target_K_Nm_per_rad, "design", "SEA"),
                                        (FULL_CHARGE, None, FULL_DESIGN, FULL_SEA)):
        if target is None:  # the highest allowed charge
            target = charge_for_stiffness(spring, 1.0, pulley_radius_m=r, n_units=n, max_charge_MPa=max_charge_MPa,
                                          min_pressure_MPa=min_pressure_MPa, setpoint_x0_mm=x0).K_full_Nm_per_rad
        ch = charge_for_stiffness(spring, target, pulley_radius_m=r, n_units=n, max_charge_MPa=max_charge_MPa,
                                  min_pressure_MPa=min_pressure_MPa, setpoint_x0_mm=x0)
        act = Actuator(dname, ch.K_Nm_per_rad, rng.D_min_Nms_per_rad, rng.D_max_Nms_per_rad, tau_m_max_Nm=tau_max)
        runs.append((label, act, Actuator(sname, ch.K_Nm_per_rad, 0.0, 0.0, tau_m_max_Nm=tau_max), ch))
    return runs, rng


def unit_mapping(design, mapping: dict | None = None) -> tuple[GasSpring, float, int, float, float]:
    """The unit's gas spring and how it acts on the joint.

    Parameters
    ----------
    design
        A :class:`~vvea_design.spring.design.Design` (or anything with ``.gas_spring``) or a
        :class:`~vvea_design.spring.gas_spring.GasSpring`.
    mapping
        ``pulley_radius_m`` (m) and ``n_units`` overriding the design's.

    Returns
    -------
    (GasSpring, float, int, float, float)
        The spring (mm, MPa), the pulley radius (m; the design's ``fixed.pulley_radius_mm``, else the paper's),
        the units on the pulley, the set point x0 (mm) and the motor torque limit (N m).

    Raises
    ------
    ValueError
        For a design of an unknown kind.
    """
    mapping = dict(mapping or {})
    spring = design if isinstance(design, GasSpring) else getattr(design, "gas_spring", None)
    if not isinstance(spring, GasSpring):
        raise ValueError(f"design must be an Actuator, a GasSpring or have a .gas_spring, got {type(design).__name__}")
    fixed = getattr(design, "fixed", None)
    own_r = getattr(fixed, "pulley_radius_mm", None)
    r = float(mapping.get("pulley_radius_m", own_r / 1e3 if own_r else PAPER_PULLEY_RADIUS_M))
    n = int(mapping.get("n_units", 2))
    tau_max = float(getattr(fixed, "max_motor_torque_Nm", PAPER_SETTINGS["VVEA"].tau_m_max_Nm))
    return spring, r, n, float(getattr(design, "setpoint_x0_mm", 0.0)), tau_max


def _work(item):
    """Worker: a chain of rest-to-rest cases -> (rows per case, kept best), or the torque-step studies (a tuple).

    The torque steps are one work item, so one process builds (or reads) the torque-step solver, once, while the
    other starts on the rest-to-rest cases."""
    kind, payload = item
    if kind == "safety":
        return tuple(solve_safety(base, mesh=mesh, name=name, fixed_D_Nms_per_rad=fixed)
                     for base, mesh, name, fixed in payload)
    return _chain_item(payload)


def _solve_items(items: list, workers: int | None, progress, total: int) -> tuple[list, int]:
    """Every work item through :func:`~vvea_design.parallel.parallel_map`; (results in order, workers used)."""
    from ..parallel import default_workers

    done = [0]

    def on_result(i, r) -> None:
        done[0] += 1
        if progress is not None:
            kind, payload = items[i]
            msg = ("torque steps " + ", ".join(p[2] for p in payload) if kind == "safety"
                   else f"rest-to-rest A = {payload[1][0].A_rad:g} rad, {len(payload[1])} period(s)")
            progress(done[0], total, msg)

    used = 1 if workers == 1 else min(default_workers() if workers is None else workers, len(items))
    return parallel_map(_work, items, workers=workers, on_result=on_result, progress=False), used


def _setting_summaries(groups: Sequence[Sequence[Actuator]], cases: tuple[CaseResult, ...],
                       grid: Grid) -> tuple[SettingSummary, ...]:
    """Each setting over the grid; the mean rmse over the cases where every setting of its run is usable."""
    usable = {(c.A_rad, c.T_s, c.setting): c.usable for c in cases}
    rm = {(c.A_rad, c.T_s, c.setting): c.rmse_rad for c in cases}
    out = []
    for group in groups:
        names = [a.name for a in group]
        all_ok = [k for k in grid.cases() if all(usable.get((k[0], k[1], n), False) for n in names)]
        for a in group:
            mine = [c for c in cases if c.setting == a.name]
            out.append(SettingSummary(
                a.name, a.K_Nm_per_rad, a.D_min_Nms_per_rad, a.D_max_Nms_per_rad, len(mine),
                sum(1 for c in mine if math.isfinite(c.rmse_rad)),
                sum(1 for c in mine if c.valid and math.isfinite(c.rmse_rad)),
                sum(1 for c in mine if math.isfinite(c.rmse_rad) and not c.verified),
                float(np.mean([rm[(A, T, a.name)] for A, T in all_ok])) if all_ok else float("nan")))
    return tuple(out)


def _comparisons(runs, refs: Sequence[Actuator], stats) -> tuple[Comparison, ...]:
    """The design of each run against its SEA (and, at equal stiffness, the references), every case counted."""
    out = []
    for label, act, sea, _ in runs:
        others = [sea.name] + ([r.name for r in refs if r.name != sea.name] if label == EQUAL_STIFFNESS else [])
        for o in others:
            c = stats.counted_pair(act.name, o)
            paper = (PAPER_TABLE5.get(f"VVEA_beats_{o}"), PAPER_TABLE5.get(f"meanrmse_{o}_over_VVEA"))
            if c is not None:
                out.append(Comparison.from_counted(label, act.name, o, c, paper))
    return tuple(out)


def _check(references: Sequence[str]) -> None:
    unknown = [r for r in references if r not in PAPER_SETTINGS]
    if unknown:
        raise ValueError(f"references {unknown} are not paper settings; choose from {sorted(PAPER_SETTINGS)}")


def run_design_study(
    design,
    out_dir: str | Path | None = None,
    *,
    progress: Callable[[int, int, str], None] | None = None,
    workers: int | None = None,
    grid: Grid = DESIGN_GRID,
    mesh: Mesh = DESIGN_MESH,
    references: Sequence[str] = DESIGN_REFERENCES,
    mapping: dict | None = None,
    safety_mesh: Mesh = DESIGN_SAFETY_MESH,
    target_K_Nm_per_rad: float = PAPER_K_NM_PER_RAD,
    damping: DampingRange | None = None,
    max_charge_MPa: float | None = None,
    min_pressure_MPa: float = ATMOSPHERE_MPA,
    starts: Sequence[str] = DESIGN_STARTS,
) -> DesignStudy:
    """Rest-to-rest and torque-step study of one design: at equal stiffness against an SEA, VVEA and LWR, and at full charge.

    Parameters
    ----------
    design
        The design: a :class:`~vvea_design.spring.design.Design` (or anything
        with ``.gas_spring``), a :class:`~vvea_design.spring.gas_spring.GasSpring`,
        or a ready :class:`~vvea_design.actuator.model.Actuator` (one run at its own K).
    out_dir
        If given, writes ``results.csv``, ``design_study.json``, ``design_map.png`` (rmse ratio design / SEA
        over A and T in both runs), ``design_trajectory.png`` and ``design_safety.png`` there (created).
    progress
        Called as ``progress(done, total, message)`` after each finished work
        item (one chain of periods per amplitude + 2 torque steps) and once at the end.
    workers
        Local worker processes (default: all cores; 1 = in this process).
    grid, mesh
        Rest-to-rest grid (A in rad, T in s) and collocation mesh (defaults :data:`DESIGN_GRID`,
        :data:`DESIGN_MESH`).
    references
        Names in :data:`~vvea_design.actuator.model.PAPER_SETTINGS` to compare with at equal stiffness
        (``"SEA"`` is taken at the design's K).
    mapping
        ``pulley_radius_m`` (m) and ``n_units`` of the section 3.4 mapping (see :func:`study_actuators`).
    safety_mesh
        Collocation mesh of the torque steps (default :data:`DESIGN_SAFETY_MESH`, 100 intervals
        clustered at the step; a coarser one is quicker and blurs the damping switch).
    target_K_Nm_per_rad
        Joint stiffness of the equal-stiffness run, N m/rad (default the paper's 362).
    damping
        Damping range (N m s/rad) to use instead of the unit's own.
    max_charge_MPa, min_pressure_MPa
        The unit's pressure limits (MPa, absolute): default the design's own charge and atmospheric pressure.
    starts
        Variable-damping starts (default :data:`DESIGN_STARTS`).

    Returns
    -------
    DesignStudy
        Typed result (rmse in rad, times in s); ``to_dict()`` gives the JSON.

    Raises
    ------
    ValueError
        For an unknown reference or mapping option, or pressure limits that leave no charge.
    """
    import pandas as pd

    t_start = time.perf_counter()
    _check(references)
    runs, rng = study_actuators(design, target_K_Nm_per_rad=target_K_Nm_per_rad, damping=damping, mapping=mapping,
                                max_charge_MPa=max_charge_MPa, min_pressure_MPa=min_pressure_MPa)
    act, sea = runs[0][1], runs[0][2]
    refs = tuple(sea if r == "SEA" else PAPER_SETTINGS[r] for r in references)
    groups = [(act,) + refs] + [(a, s) for _, a, s, _ in runs[1:]]
    settings = tuple(a for g in groups for a in g)
    reg = DEFAULT_REGULARISATION
    items: list = [("safety", ((act, safety_mesh, "design, variable D", DESIGN_SAFETY_FIXED_D),
                               (PAPER_SETTINGS["VVEA"], safety_mesh, "VVEA, variable D", ())))]
    cases = [RestToRestCase(A, T, settings, mesh, tuple(starts), DESIGN_IPOPT, None, reg) for A, T in grid.cases()]
    # the trajectory figure: the case closest to A = 0.7 rad, T = 1.0 s
    ex = (min(grid.A_rad, key=lambda a: abs(a - 0.7)), min(grid.T_s, key=lambda t: abs(t - 1.0)))
    ex_case = next(c for c in cases if (c.A_rad, c.T_s) == ex)
    items += [("r2r", (solve_chain, ch, ex_case if ex_case in ch else None)) for ch in chains(cases)]
    total = len(items) + 1
    out, used = _solve_items(items, workers, progress, total)
    t_solved = time.perf_counter()
    safety_design, safety_ref = out[0]
    rows: list[CaseRow] = [row for per_case, _ in out[1:] for rs in per_case for row in rs]
    best = next((b for _, b in out[1:] if b is not None), {})
    df = pd.DataFrame([r.to_dict() for r in rows], columns=RESULT_COLUMNS)
    results = tuple(CaseResult.from_row(r) for r in rows)
    study_runs = tuple(StudyRun(label, a.name, s.name, a, ch, damping_use(label, a, results, rng))
                       for label, a, s, ch in runs)
    study = DesignStudy(
        actuator=act, references=refs, runs=study_runs, damping=rng, grid=grid, mesh=mesh, starts=tuple(starts),
        regularisation=reg, cases=results, settings=_setting_summaries(groups, results, grid),
        comparisons=_comparisons(runs, refs, table5_statistics(df)), safety_design=safety_design,
        safety_reference=safety_ref,
        timing=StudyTiming(t_solved - t_start, 0.0, 0.0, used,
                           float(df["seconds"].sum()) + safety_design.wall_seconds + safety_ref.wall_seconds,
                           float(df["cpu_seconds"].sum())),
        trajectory_case=ex, best={k: v for k, v in best.items() if k in {a.name for a in groups[0]}},
    )
    if out_dir is not None:
        study = dataclasses.replace(study, files=_write(study, df, Path(out_dir)))
        if progress is not None:
            progress(total, total, f"wrote {out_dir}")
    elif progress is not None:
        progress(total, total, "done")
    t_end = time.perf_counter()
    study = dataclasses.replace(study, timing=dataclasses.replace(study.timing, figures_s=t_end - t_solved,
                                                                   total_s=t_end - t_start))
    if out_dir is not None:  # the JSON carries the final timing
        Path(study.files.summary_json).write_text(json.dumps(study.to_dict(), indent=2))
    return study


def _write(study: DesignStudy, df, out: Path) -> StudyFiles:
    """results.csv, design_study.json and the three figures."""
    out.mkdir(parents=True, exist_ok=True)
    res = out / "results.csv"
    with res.open("w", newline="") as fh:
        wr = csv.DictWriter(fh, fieldnames=RESULT_COLUMNS)
        wr.writeheader()
        wr.writerows(df.to_dict("records"))
    files = StudyFiles(results_csv=res, summary_json=out / "design_study.json", map_png=out / "design_map.png",
                       trajectory_png=out / "design_trajectory.png", safety_png=out / "design_safety.png")
    plot_design_vs_sea(df, [(r.label, r.design, r.sea, r.actuator.K_Nm_per_rad) for r in study.runs],
                       damping=f"D {study.damping.D_min_Nms_per_rad:.3g}-{study.damping.D_max_Nms_per_rad:.4g} "
                               f"N m s/rad ({study.damping.source})").savefig(files.map_png, dpi=120)
    if study.best:
        A, T = study.trajectory_case
        plot_trajectory(study.best, A, T, highlight="design").savefig(files.trajectory_png, dpi=120)
    else:
        files = StudyFiles(files.results_csv, files.summary_json, files.map_png, None, files.safety_png)
    sr = {study.safety_design.variable_case: study.safety_design.results[study.safety_design.variable_case],
          study.safety_reference.variable_case: study.safety_reference.results[study.safety_reference.variable_case]}
    for name in ("fixed D 31", "fixed D 200"):
        if name in study.safety_design.results:
            sr[f"design, {name}"] = study.safety_design.results[name]
    tau = float(study.safety_design.setup["tau_ref_Nm"])
    plot_safety(sr, tau).savefig(files.safety_png, dpi=120)
    return files
