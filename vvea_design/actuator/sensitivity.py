"""Which property of the unit buys tracking: the design against an SEA of the same K as D_min, D_max and K move.

:func:`run_design_sensitivity` solves the rest-to-rest grid of the design study for the design at its
equal-stiffness charge with one property changed at a time — the open-throttle damping ``D_min``, the
closed-throttle damping ``D_max`` (what the designer asks of the valve) and the joint stiffness ``K`` (the
charge; each K against an SEA of that K) — and reports, per value, the design against the SEA over every case
(:class:`~vvea_design.actuator.statistics.CountedPair`) and the mean rmse ratio over the cases both track
validly. :meth:`DesignSensitivity.answer` says which property moves the ratio most.
"""

from __future__ import annotations

import csv
import json
import math
import time
from collections.abc import Sequence
from dataclasses import asdict, dataclass, field
from pathlib import Path

from ..parallel import parallel_map
from .damping import DampingRange
from .design_study import DESIGN_GRID, DESIGN_IPOPT, DESIGN_MESH, DESIGN_STARTS, study_actuators, unit_mapping
from .model import Actuator
from .multistart import DEFAULT_REGULARISATION, RESULT_COLUMNS, RestToRestCase, _chain_item, chains, solve_chain
from .ocp import Mesh
from .rest_to_rest import Grid
from .statistics import counted_pair
from .stiffness import PAPER_K_NM_PER_RAD, charge_for_stiffness

__all__ = ["SensitivityPoint", "DesignSensitivity", "run_design_sensitivity", "PARAMETERS"]

#: The properties varied, in the order of the figure's panels.
PARAMETERS = ("D_min", "D_max", "K")


@dataclass(frozen=True)
class SensitivityPoint:
    """The design with one property changed, against an SEA of its K, over every case of the grid."""

    parameter: str  #: "D_min", "D_max" or "K"
    value: float  #: the property's value (N m s/rad for D_min, D_max; N m/rad for K)
    is_base: bool  #: the design as the study takes it
    K_Nm_per_rad: float  #: joint stiffness of this design (and of its SEA)
    D_min_Nms_per_rad: float  #: damping, throttle open
    D_max_Nms_per_rad: float  #: damping, throttle closed
    n_cases: int  #: every case of the grid
    design_beats: int  #: better than the SEA, or the only one valid
    design_worse: int  #: worse than the SEA, or not valid while the SEA is
    only_sea_valid: int  #: the design not valid, the SEA valid (in ``design_worse``)
    n_both_valid: int  #: cases both track validly
    mean_rmse_ratio_design_over_sea: float | None  #: mean rmse of the design / of the SEA, both-valid cases (< 1: better)
    setting: str  #: setting name in ``sensitivity.csv``
    note: str = ""  #: e.g. the pressure limit that clamped a K

    def to_dict(self) -> dict:
        """Plain-JSON dictionary.

        Returns
        -------
        dict
            Field name to value (damping N m s/rad, stiffness N m/rad, counts, the ratio dimensionless).
        """
        return asdict(self)


@dataclass(frozen=True)
class DesignSensitivity:
    """Result of :func:`run_design_sensitivity`."""

    base: Actuator  #: the design at equal stiffness with its own damping range
    damping: DampingRange  #: where the base damping range comes from
    grid: Grid  #: rest-to-rest grid
    mesh: Mesh  #: collocation mesh
    starts: tuple[str, ...]  #: variable-damping starts
    points: tuple[SensitivityPoint, ...]  #: every value of every property
    wall_seconds: float  #: time of the solves, s
    files: dict = field(default_factory=dict)  #: written file names by role

    def of(self, parameter: str) -> list[SensitivityPoint]:
        """The points of one property, by value.

        Parameters
        ----------
        parameter : str
            ``"D_min"``, ``"D_max"`` or ``"K"``.

        Returns
        -------
        list of SensitivityPoint
            Sorted by value.
        """
        return sorted((p for p in self.points if p.parameter == parameter), key=lambda p: p.value)

    def spread(self, parameter: str) -> float:
        """How far the mean rmse ratio moves over a property's values (largest - smallest; nan without two).

        Parameters
        ----------
        parameter : str
            ``"D_min"``, ``"D_max"`` or ``"K"``.

        Returns
        -------
        float
            Difference of two rmse ratios, dimensionless.
        """
        r = [p.mean_rmse_ratio_design_over_sea for p in self.of(parameter)
             if p.mean_rmse_ratio_design_over_sea is not None]
        return float(max(r) - min(r)) if len(r) > 1 else float("nan")

    def answer(self) -> str:
        """Which property buys tracking: one sentence per property, the largest first.

        Returns
        -------
        str
            E.g. ``"D_min moves the mean rmse ratio design/SEA by 0.041 (0.952 at 0 ... 0.993 at 48.8 N m s/rad); ..."``.
        """
        units = {"D_min": "N m s/rad", "D_max": "N m s/rad", "K": "N m/rad"}
        parts = []
        for par in sorted(PARAMETERS, key=lambda q: -(self.spread(q) if math.isfinite(self.spread(q)) else -1)):
            pts = [p for p in self.of(par) if p.mean_rmse_ratio_design_over_sea is not None]
            if len(pts) < 2:
                continue
            lo, hi = pts[0], pts[-1]
            parts.append(f"{par} moves the mean rmse ratio design/SEA by {self.spread(par):.3f} "
                         f"({lo.mean_rmse_ratio_design_over_sea:.3f} at {lo.value:.4g} ... "
                         f"{hi.mean_rmse_ratio_design_over_sea:.3f} at {hi.value:.4g} {units[par]}; wins "
                         f"{lo.design_beats} ... {hi.design_beats} of {lo.n_cases})")
        return "; ".join(parts)

    def to_dict(self) -> dict:
        """Plain-JSON dictionary (``sensitivity.json``).

        Returns
        -------
        dict
            The base actuator (SI), the damping range's source, grid, mesh, starts, every point, the spread per
            property, the answer, the time (s) and the files.
        """
        return {"base": asdict(self.base), "damping": self.damping.to_dict(),
                "grid": {"A_rad": list(self.grid.A_rad), "T_s": list(self.grid.T_s)}, "mesh": asdict(self.mesh),
                "starts": list(self.starts), "points": [p.to_dict() for p in self.points],
                "spread": {q: self.spread(q) for q in PARAMETERS}, "answer": self.answer(),
                "wall_seconds": round(self.wall_seconds, 2), "files": dict(self.files)}


def _variants(base: Actuator, spring_runs, D_min_values, D_max_values, K_values):
    """(parameter, value, is_base, design actuator, SEA actuator, note) of every point."""
    out = []
    sea = spring_runs["sea"]
    for v in D_min_values:
        v = min(float(v), base.D_max_Nms_per_rad)
        out.append(("D_min", v, math.isclose(v, base.D_min_Nms_per_rad),
                    base.with_(name=f"design D_min={v:.4g}", D_min_Nms_per_rad=v), sea, ""))
    for v in D_max_values:
        v = max(float(v), base.D_min_Nms_per_rad)
        out.append(("D_max", v, math.isclose(v, base.D_max_Nms_per_rad),
                    base.with_(name=f"design D_max={v:.4g}", D_max_Nms_per_rad=v), sea, ""))
    for K, note in spring_runs["K"](K_values):
        out.append(("K", K, math.isclose(K, base.K_Nm_per_rad, rel_tol=1e-9),
                    base.with_(name=f"design K={K:.4g}", K_Nm_per_rad=K),
                    sea.with_(name=f"SEA K={K:.4g}", K_Nm_per_rad=K), note))
    return out


def run_design_sensitivity(
    design,
    out_dir: str | Path | None = None,
    *,
    target_K_Nm_per_rad: float = PAPER_K_NM_PER_RAD,
    damping: DampingRange | None = None,
    D_min_values: Sequence[float] | None = None,
    D_max_values: Sequence[float] | None = None,
    K_factors: Sequence[float] = (0.5, 0.75, 1.0, 1.5, 2.0),
    grid: Grid = DESIGN_GRID,
    mesh: Mesh = DESIGN_MESH,
    starts: Sequence[str] = DESIGN_STARTS,
    workers: int | None = None,
    progress: bool = True,
) -> DesignSensitivity:
    """The design against an SEA of the same K while D_min, D_max and K move, one at a time.

    Parameters
    ----------
    design
        As for :func:`~vvea_design.actuator.design_study.run_design_study` (a Design, a GasSpring or an Actuator).
    out_dir
        If given, writes ``sensitivity.csv`` (every OCP), ``sensitivity.json`` and ``sensitivity.png``.
    target_K_Nm_per_rad
        The base design's joint stiffness, N m/rad.
    damping
        Base damping range (default: the unit's own).
    D_min_values, D_max_values
        Values to try, N m s/rad (default: 0, 1/2, 1, 2, 4 x the base D_min; 100, 200, 400, 800 N m s/rad and
        the base D_max).
    K_factors
        Joint stiffnesses to try as multiples of the base K (each charge kept inside the unit's pressure
        limits; a clamped K says which limit binds in the point's ``note``).
    grid, mesh, starts
        Rest-to-rest grid (rad, s), mesh and variable-damping starts (the design study's by default).
    workers
        Local worker processes (default all cores).
    progress
        Show a progress bar.

    Returns
    -------
    DesignSensitivity
        Every point (counts over every case, the mean rmse ratio) and :meth:`~DesignSensitivity.answer`.
    """
    runs, rng = study_actuators(design, target_K_Nm_per_rad=target_K_Nm_per_rad, damping=damping)
    base, sea = runs[0][1], runs[0][2]
    if D_min_values is None:
        D_min_values = sorted({0.0, *(f * base.D_min_Nms_per_rad for f in (0.5, 1.0, 2.0, 4.0))})
    if D_max_values is None:
        D_max_values = sorted({*(v for v in (100.0, 200.0, 400.0, 800.0) if v > base.D_min_Nms_per_rad),
                               base.D_max_Nms_per_rad})

    def K_points(values):
        charge = runs[0][3]
        if charge is None:  # an Actuator: no charge to change, the K values as asked
            return [(f * base.K_Nm_per_rad, "") for f in K_factors]
        spring, r, n, x0, _ = unit_mapping(design)
        pts = {}
        for f in K_factors:
            ch = charge_for_stiffness(spring, f * base.K_Nm_per_rad, pulley_radius_m=r, n_units=n,
                                      max_charge_MPa=charge.max_charge_MPa, min_pressure_MPa=charge.min_pressure_MPa,
                                      setpoint_x0_mm=x0)
            pts.setdefault(round(ch.K_Nm_per_rad, 9), (ch.K_Nm_per_rad, ch.binding_limit or ""))
        return list(pts.values())

    points = _variants(base, {"sea": sea, "K": K_points}, D_min_values, D_max_values, K_factors)
    settings = tuple({a.name: a for p in points for a in (p[3], p[4])}.values())
    cases = [RestToRestCase(A, T, settings, mesh, tuple(starts), DESIGN_IPOPT, None, DEFAULT_REGULARISATION)
             for A, T in grid.cases()]
    t0 = time.perf_counter()
    res = parallel_map(_chain_item, [(solve_chain, ch, None) for ch in chains(cases)], workers=workers,
                       description=f"sensitivity ({len(settings)} settings/case)", progress=progress)
    wall = time.perf_counter() - t0
    rows = [r for per_case, _ in res for rs in per_case for r in rs]
    by = {(r.case_id, r.setting): r for r in rows}
    ids = [c.case_id for c in cases]

    def usable(r):
        return bool(r.success and r.valid and r.verified)

    out = []
    for par, value, is_base, act, s, note in points:
        d = [by[(i, act.name)] for i in ids]
        q = [by[(i, s.name)] for i in ids]
        c = counted_pair([r.rmse for r in d], [r.rmse for r in q], [usable(r) for r in d], [usable(r) for r in q])
        out.append(SensitivityPoint(
            par, float(value), bool(is_base), act.K_Nm_per_rad, act.D_min_Nms_per_rad, act.D_max_Nms_per_rad,
            c.n_cases, c.X_beats_Y, c.X_worse_than_Y, c.only_Y_usable, c.n_both_usable,
            None if c.meanrmse_Y_over_X is None else 1.0 / c.meanrmse_Y_over_X, act.name, note))
    study = DesignSensitivity(base, rng, grid, mesh, tuple(starts), tuple(out), wall)
    if out_dir is not None:
        study = _write(study, rows, Path(out_dir))
    return study


def _write(study: DesignSensitivity, rows, out: Path) -> DesignSensitivity:
    """sensitivity.csv, sensitivity.png and sensitivity.json."""
    from dataclasses import replace

    from .figures import plot_sensitivity

    out.mkdir(parents=True, exist_ok=True)
    with (out / "sensitivity.csv").open("w", newline="") as fh:
        wr = csv.DictWriter(fh, fieldnames=RESULT_COLUMNS)
        wr.writeheader()
        wr.writerows(r.to_dict() for r in rows)
    plot_sensitivity(study).savefig(out / "sensitivity.png", dpi=120)
    study = replace(study, files={"csv": "sensitivity.csv", "json": "sensitivity.json", "png": "sensitivity.png"})
    (out / "sensitivity.json").write_text(json.dumps(study.to_dict(), indent=2))
    return study
