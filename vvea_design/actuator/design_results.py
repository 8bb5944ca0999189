"""Typed results of the design's own actuator study (:func:`~vvea_design.actuator.design_study.run_design_study`).

Frozen dataclasses with ``to_dict()``: one :class:`CaseResult` per setting and case, :class:`SettingSummary`
per setting, :class:`Comparison` per pair (every case counted), :class:`StudyRun` per labelled run (equal
stiffness, full charge), :class:`DampingUse` (what the optima ask of the valve), the timing and the files.
"""

from __future__ import annotations

import math
from dataclasses import asdict, dataclass
from pathlib import Path

from .damping import DampingRange
from .model import Actuator
from .multistart import CaseRow
from .statistics import CountedPair
from .stiffness import ChargeChoice

__all__ = ["CaseResult", "SettingSummary", "Comparison", "StudyRun", "DampingUse", "StudyTiming", "StudyFiles",
           "EQUAL_STIFFNESS", "FULL_CHARGE"]

#: Label of the run at the target joint stiffness (the design and an SEA of the same K).
EQUAL_STIFFNESS = "equal stiffness"
#: Label of the run at the design's full charge (the design and an SEA of the same, higher K).
FULL_CHARGE = "full charge"


@dataclass(frozen=True)
class CaseResult:
    """One setting at one (A, T)."""

    A_rad: float  #: reference amplitude
    T_s: float  #: reference period
    setting: str  #: setting name
    rmse_rad: float  #: tracking rmse (nan if not solved)
    valid: bool  #: link reaches 95 % of A in both up-phases
    verified: bool  #: re-simulation agrees, bounds kept
    status: str  #: IPOPT status (or the error)
    start: str  #: start that won
    max_D_Nms_per_rad: float = float("nan")  #: peak damping of the optimum
    mean_D_Nms_per_rad: float = float("nan")  #: time-mean damping of the optimum
    max_damping_torque_Nm: float = float("nan")  #: largest |D (θ' - q')| of the optimum

    @property
    def usable(self) -> bool:
        """Counts as a result: solved, valid and verified (else a loss against a usable rival)."""
        return self.valid and self.verified and math.isfinite(self.rmse_rad)

    @classmethod
    def from_row(cls, row: CaseRow) -> "CaseResult":
        """The case of a ``results.csv`` row.

        Parameters
        ----------
        row : CaseRow
            A row of :func:`~vvea_design.actuator.multistart.solve_case_results` (SI units).

        Returns
        -------
        CaseResult
            Amplitude (rad), period (s), setting, rmse (rad), validity, verification, status, start and the
            optimum's damping (N m s/rad) and damping torque (N m).
        """
        return cls(float(row.A_rad), float(row.T_s), row.setting, float(row.rmse), bool(row.valid),
                   bool(row.verified), str(row.status), str(row.start), float(row.max_D_Nms_per_rad),
                   float(row.mean_D_Nms_per_rad), float(row.max_damping_torque_Nm))

    def to_dict(self) -> dict:
        """Plain-JSON dictionary.

        Returns
        -------
        dict
            JSON-ready fields by name: ``A_rad`` (rad), ``T_s`` (s), ``setting``, ``rmse_rad`` (rad, NaN when
            not solved), ``valid``, ``verified``, ``status``, ``start``, the damping (N m s/rad) and damping
            torque (N m) of the optimum.
        """
        return asdict(self)


@dataclass(frozen=True)
class SettingSummary:
    """One setting over the grid."""

    name: str  #: setting name
    K_Nm_per_rad: float  #: series stiffness
    D_min_Nms_per_rad: float  #: damping range, lower end
    D_max_Nms_per_rad: float  #: damping range, upper end
    n_cases: int  #: cases of the grid
    n_solved: int  #: IPOPT success
    n_valid: int  #: solved and valid (95 % rule)
    n_unverified: int  #: solved but failed the re-simulation check (not a result: counted as not usable)
    mean_rmse_rad: float  #: mean rmse over the cases where every setting of its run is usable

    def to_dict(self) -> dict:
        """Plain-JSON dictionary.

        Returns
        -------
        dict
            JSON-ready fields by name: ``name``, ``K_Nm_per_rad`` (N m/rad), ``D_min_Nms_per_rad`` and
            ``D_max_Nms_per_rad`` (N m s/rad), the case counts ``n_cases``, ``n_solved``, ``n_valid``,
            ``n_unverified`` and ``mean_rmse_rad`` (rad).
        """
        return asdict(self)


@dataclass(frozen=True)
class Comparison:
    """The design against one other setting over *every* case of the grid (nothing left out).

    A case where only one of the two has a usable result (solved, valid, verified) goes to that one: the design
    invalid while the other is valid is a loss (``only_other_valid``); neither usable is its own column.
    ``design_beats + design_worse + ties + neither_valid == n_cases``.
    """

    run: str  #: :data:`EQUAL_STIFFNESS` or :data:`FULL_CHARGE`
    design: str  #: the design's setting name in that run
    other: str  #: the other setting
    n_cases: int  #: every case of the grid
    design_beats: int  #: rmse_design < (1 - 1e-3) rmse_other, or only the design valid
    design_worse: int  #: rmse_design > (1 + 1e-3) rmse_other, or only the other valid
    ties: int  #: both valid, within 1e-3
    only_design_valid: int  #: the design valid, the other not (in ``design_beats``)
    only_other_valid: int  #: the design not valid (or not verified / not solved), the other valid (in ``design_worse``)
    neither_valid: int  #: no usable result on either side
    fraction_design_beats: float | None  #: design_beats / n_cases
    n_both_valid: int  #: cases where both are usable (the ratio's cases)
    meanrmse_other_over_design: float | None  #: mean rmse ratio over the both-usable cases (> 1: the design tracks better)
    paper_vvea_beats: float | None  #: the paper's Table 5 "VVEA beats <other>" (context)
    paper_meanrmse_other_over_vvea: float | None  #: the paper's Table 5 ratio for VVEA (context)

    @classmethod
    def from_counted(cls, run: str, design: str, other: str, c: CountedPair, paper: tuple) -> "Comparison":
        """From a :class:`~vvea_design.actuator.statistics.CountedPair` of the design (X) against ``other`` (Y).

        Parameters
        ----------
        run, design, other : str
            Run label, the design's setting name, the other setting's name.
        c : CountedPair
            The counts over every case.
        paper : tuple
            ``(paper_vvea_beats, paper_meanrmse_other_over_vvea)`` (fractions; None where the paper has none).

        Returns
        -------
        Comparison
            The same counts with the design's names.
        """
        return cls(run, design, other, c.n_cases, c.X_beats_Y, c.X_worse_than_Y, c.ties, c.only_X_usable,
                   c.only_Y_usable, c.neither_usable, c.fraction_X_beats_Y, c.n_both_usable, c.meanrmse_Y_over_X,
                   *paper)

    def to_dict(self) -> dict:
        """Plain-JSON dictionary.

        Returns
        -------
        dict
            JSON-ready fields by name: labels, case counts, ``fraction_design_beats`` (of every case),
            ``meanrmse_other_over_design`` (dimensionless) and the paper's Table 5 values; ``None`` where not
            defined.
        """
        return asdict(self)


@dataclass(frozen=True)
class DampingUse:
    """What the design's optima ask of the valve in one run (from every case's optimum)."""

    run: str  #: run label
    n_cases: int  #: cases with a usable design optimum
    n_reach_D_max: int  #: optima whose damping reaches 99 % of D_max (a wider range could help them)
    n_stay_at_D_min: int  #: optima whose damping never leaves D_min by more than 1 % of the range (the valve idles)
    largest_D_used_Nms_per_rad: float  #: the highest damping any optimum uses
    D_needed_Nms_per_rad: dict[str, float]  #: case id ``A<A>_T<T>`` to its optimum's peak damping
    largest_damping_torque_Nm: float  #: the largest |D (θ' - q')| of any optimum
    relief_torque_Nm: float | None  #: damping torque at which the unit's relief valves open (None: unknown)
    n_over_relief: int  #: optima whose damping torque exceeds the relief torque (the linear model is optimistic there)

    def to_dict(self) -> dict:
        """Plain-JSON dictionary.

        Returns
        -------
        dict
            Counts, damping (N m s/rad) and torques (N m) by name.
        """
        return asdict(self)


@dataclass(frozen=True)
class StudyRun:
    """One labelled run: the design at a charge, against an SEA of the same joint stiffness."""

    label: str  #: :data:`EQUAL_STIFFNESS` or :data:`FULL_CHARGE`
    design: str  #: the design's setting name
    sea: str  #: the SEA of the same K
    actuator: Actuator  #: the design's actuator in this run
    charge: ChargeChoice  #: the charge that gives this run's K
    damping_use: DampingUse  #: what the optima ask of the valve

    def to_dict(self) -> dict:
        """Plain-JSON dictionary.

        Returns
        -------
        dict
            ``label``, ``design``, ``sea``, the actuator (SI fields), the charge (MPa, N m/rad) and the damping use.
        """
        return {"label": self.label, "design": self.design, "sea": self.sea, "actuator": asdict(self.actuator),
                "charge": self.charge.to_dict(), "damping_use": self.damping_use.to_dict()}


@dataclass(frozen=True)
class StudyTiming:
    """Wall-clock breakdown in s."""

    rest_to_rest_and_safety_s: float  #: the parallel solves (cases + torque steps)
    figures_s: float  #: figures and files
    total_s: float  #: the whole call
    workers: int  #: worker processes used
    solver_seconds: float  #: sum of all IPOPT wall times (all processes)
    rest_to_rest_cpu_seconds: float  #: CPU time of the rest-to-rest solves (all processes)

    def to_dict(self) -> dict:
        """Plain-JSON dictionary.

        Returns
        -------
        dict
            JSON-ready fields by name: ``rest_to_rest_and_safety_s``, ``figures_s``, ``total_s`` (wall clock,
            s), ``workers`` (count), ``solver_seconds`` (summed IPOPT wall time, s) and
            ``rest_to_rest_cpu_seconds`` (CPU time, s).
        """
        return asdict(self)


@dataclass(frozen=True)
class StudyFiles:
    """Files written by :func:`~vvea_design.actuator.design_study.run_design_study` (``None`` when not written)."""

    results_csv: Path | None = None  #: one row per OCP (``results.csv`` columns)
    summary_json: Path | None = None  #: :meth:`DesignStudy.to_dict`
    map_png: Path | None = None  #: rmse ratio design / SEA at equal K over A and T (:func:`plot_design_vs_sea`)
    trajectory_png: Path | None = None  #: one case's optimal trajectories
    safety_png: Path | None = None  #: torque steps of the design and the paper's VVEA

    def to_dict(self) -> dict:
        """Plain-JSON dictionary: each file's name in the study's folder (``None``: not written).

        Names, not paths, so that a study written in a temporary folder and moved into place
        (``outputs.output_dir``) names no folder that no longer exists.

        Returns
        -------
        dict of str to str or None
            JSON-ready: field name (``results_csv``, ``summary_json``, ``map_png``, ``trajectory_png``,
            ``safety_png``) to the file's base name, or ``None`` when the file was not written.
        """
        return {k: (Path(v).name if v is not None else None) for k, v in asdict(self).items()}

    def __iter__(self):
        """The written files (paths), figures last."""
        return iter([p for p in (self.results_csv, self.summary_json, self.map_png, self.trajectory_png,
                                 self.safety_png) if p is not None])


def damping_use(run: str, design: Actuator, cases, damping: DampingRange) -> DampingUse:
    """What the design's usable optima of one run ask of the valve.

    Parameters
    ----------
    run
        Run label.
    design
        The design's actuator in this run (its name selects the cases; damping range in N m s/rad).
    cases
        Every :class:`CaseResult` of the study.
    damping
        The damping range used (its relief torque, N m).

    Returns
    -------
    DampingUse
        Counts of optima at D_max and idle at D_min, the peak damping per case (N m s/rad) and the damping
        torques (N m) against the relief torque.
    """
    mine = [c for c in cases if c.setting == design.name and c.usable]
    lo, hi = design.D_min_Nms_per_rad, design.D_max_Nms_per_rad
    span = max(hi - lo, 1e-12)
    peaks = {f"A{c.A_rad:.6g}_T{c.T_s:.6g}": float(c.max_D_Nms_per_rad) for c in mine}
    torques = [c.max_damping_torque_Nm for c in mine if math.isfinite(c.max_damping_torque_Nm)]
    relief = damping.relief_torque_Nm
    return DampingUse(
        run=run, n_cases=len(mine),
        n_reach_D_max=sum(c.max_D_Nms_per_rad >= lo + 0.99 * span for c in mine),
        n_stay_at_D_min=sum(c.max_D_Nms_per_rad <= lo + 0.01 * span for c in mine),
        largest_D_used_Nms_per_rad=max(peaks.values(), default=float("nan")), D_needed_Nms_per_rad=peaks,
        largest_damping_torque_Nm=max(torques, default=float("nan")), relief_torque_Nm=relief,
        n_over_relief=0 if relief is None else sum(t > relief for t in torques))
