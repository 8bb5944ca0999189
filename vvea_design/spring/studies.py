"""Studies over the optimisation problem: Pareto fronts, 2-D linearity maps, the packing-free gas bound and
the envelope's gas capacity.

* :func:`pareto_front`: best linearity as one requirement is swept (stiffness, outer diameter, mass or the
  adiabatic linearity), one optimisation per point through :func:`vvea_design.parallel.parallel_map`;
  :func:`save_pareto` writes it as CSV and PNG.
* :func:`linearity_map`: linearity and feasibility over any two decision variables.
* :func:`gas_volume_bound`: the best linearity any layout could reach with a total gas volume.
* :func:`gas_capacity`: the largest gas volume a layout holds in the envelope.

Each returns a typed result (a frozen dataclass with ``to_dict()``). The search itself is
:mod:`vvea_design.spring.optimise`, the problem :mod:`vvea_design.spring.problem`.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field, replace
from typing import Literal

import numpy as np
from scipy.optimize import NonlinearConstraint, differential_evolution

from ..parallel import parallel_map
from ..plausibility import check_count
from .design import Design
from .layouts import LAYOUTS
from .parameters import FixedParameters
from .optimise import _best_polish, _polish, _RowMemo, _starts, optimise
from .problem import constraint_names, design_from_vector, evaluate_design, evaluate_population
from .records import Record
from .requirements import Requirements

__all__ = ["PARETO_AXES", "ParetoPoint", "pareto_front", "check_pareto_values", "save_pareto", "LinearityMap",
           "linearity_map", "GasVolumeBound", "gas_volume_bound", "GasCapacity", "gas_capacity"]


# ---------------------------------------------------------------------------
# Pareto fronts
# ---------------------------------------------------------------------------

PARETO_AXES = {
    "stiffness": ("min_mean_stiffness_N_per_mm", "mean stiffness at max charge [N/mm]"),
    "outer_diameter": ("max_outer_diameter_mm", "max outer diameter [mm]"),
    "mass": ("max_mass_g", "max mass [g]"),
    "adiabatic": ("max_linearity_adiabatic", "largest linearity error allowed at n = 1.4 [fraction]"),
}


@dataclass(frozen=True)
class ParetoPoint(Record):
    """One point of a Pareto front: the swept requirement's value and the best design found for it.

    A point that could not even be set up has ``feasible = False`` and ``error``, nothing else.
    """

    swept: str  #: the swept requirement's field (unit in the name), e.g. ``min_mean_stiffness_N_per_mm``
    value: float  #: its value here, in that unit
    feasible: bool
    linearity_error: float | None = None  #: fraction, at the nominal exponent
    linearity_error_isothermal: float | None = None  #: fraction, n = 1
    linearity_error_adiabatic: float | None = None  #: fraction, n = 1.4
    objective: float | None = None  #: what the optimiser minimised (fraction)
    mass_g: float | None = None
    layout: str | None = None  #: the winning layout variant
    mean_stiffness_at_max_charge_N_per_mm: float | None = None
    binding: str = ""  #: binding or, when infeasible, violated constraints, comma-separated
    decision_variables: dict[str, float] = field(default_factory=dict)  #: every layout's variables (0 where unused)
    error: str | None = None  #: why the point could not be set up

    def to_dict(self) -> dict:
        """The row of the Pareto CSV.

        Returns
        -------
        dict
            ``feasible``, the linearity errors and objective (fraction), ``mass_g``, ``layout``,
            ``mean_stiffness_at_max_charge_N_per_mm``, ``binding``, the decision variables (mm, mm³) and the
            swept field; a point that could not be set up: ``feasible``, ``error`` and the swept field.
        """
        if self.error is not None:
            return {"feasible": self.feasible, "error": self.error, self.swept: self.value}
        row = {"feasible": self.feasible, "linearity_error": self.linearity_error,
               "linearity_error_isothermal": self.linearity_error_isothermal,
               "linearity_error_adiabatic": self.linearity_error_adiabatic, "objective": self.objective,
               "mass_g": self.mass_g, "layout": self.layout,
               "mean_stiffness_at_max_charge_N_per_mm": self.mean_stiffness_at_max_charge_N_per_mm,
               "outer_diameter_mm": self.decision_variables.get("outer_diameter_mm"), "binding": self.binding,
               **self.decision_variables}
        row[self.swept] = self.value
        return row


def _pareto_point(args) -> ParetoPoint:
    req, seed, popsize, maxiter, swept, value = args
    try:
        r = optimise(req, seed=seed, popsize=popsize, maxiter=maxiter, progress=False, raise_infeasible=False)
    except Exception as exc:  # a point that cannot even be set up is recorded, not fatal
        return ParetoPoint(swept, value, False, error=str(exc))
    ev = r.evaluation
    names = dict.fromkeys(v for lay in LAYOUTS.values() for v in lay.decision_variables)
    return ParetoPoint(
        swept, value, ev.feasible, ev.linearity_error, ev.linearity_isothermal, ev.linearity_adiabatic, ev.objective,
        ev.mass_g, ev.design.layout, ev.details["mean_stiffness"]["value"],
        ",".join(r.binding() if ev.feasible else [k for k, m in ev.margins.items() if m < -1e-9]),
        {n: float(getattr(ev.design, n)) for n in names})


def pareto_front(
    req: Requirements,
    axis: Literal["stiffness", "outer_diameter", "mass", "adiabatic"],
    values,
    *,
    seed: int = 0,
    popsize: int = 15,
    maxiter: int = 200,
    workers: int | None = None,
    scheduler: str | None = None,
    progress: bool = True,
) -> list[ParetoPoint]:
    """Best linearity as one requirement is swept: one optimisation per value.

    ``axis`` names the swept requirement: ``stiffness`` (minimum mean
    stiffness, N/mm), ``outer_diameter`` (envelope diameter, mm), ``mass``
    (maximum mass, g) or ``adiabatic`` (largest linearity error at n = 1.4,
    fraction: with the nominal objective this traces the isothermal vs
    adiabatic Pareto front). The points run through
    :func:`vvea_design.parallel.parallel_map`.

    Parameters
    ----------
    req : Requirements
        The other requirements, held fixed.
    axis : {"stiffness", "outer_diameter", "mass", "adiabatic"}
        The swept requirement (see above); :data:`PARETO_AXES` maps it to the requirements field.
    values : sequence of float
        Values of the swept requirement, in its field's unit (N/mm, mm, g or fraction).
    seed : int
        Seed of each point's global search (the same seed gives the same front).
    popsize, maxiter : int
        Differential-evolution population factor and generation limit of each point.
    workers : int or None
        Local worker processes; None: all cores, 1: serial in this process.
    scheduler : str or None
        Address of a Dask distributed scheduler (``tcp://host:port``); None: local processes.
    progress : bool
        Show a progress bar on stderr.

    Returns
    -------
    list of ParetoPoint
        One point per value, in order: ``feasible``, ``linearity_error`` (fraction; also at n = 1
        and n = 1.4), ``objective``, ``mass_g``, ``layout``,
        ``mean_stiffness_at_max_charge_N_per_mm`` (N/mm), ``binding`` (binding or, when infeasible,
        violated constraints, comma-separated), the decision variables (unit in the name) and the swept
        field and value (:meth:`ParetoPoint.to_dict` is the CSV row). A point that cannot be set up has
        ``feasible = False`` and ``error``.

    Raises
    ------
    ValueError
        If ``axis`` is not one of :data:`PARETO_AXES`, a value is not a finite number its requirement
        can take, or there are more than 500 values.
    """
    field_name = PARETO_AXES[axis][0] if axis in PARETO_AXES else ""
    jobs = [(point, seed, popsize, maxiter, field_name, v) for point, v in check_pareto_values(req, axis, values)]
    return parallel_map(_pareto_point, jobs, workers=workers, scheduler=scheduler,
                        description=f"Pareto front over {axis}", progress=progress)


def check_pareto_values(req: Requirements, axis: str, values) -> list[tuple[Requirements, float]]:
    """The requirements of each point of a Pareto front, checked before any optimisation.

    Parameters
    ----------
    req : Requirements
        The other requirements, held fixed.
    axis : str
        The swept requirement, a key of :data:`PARETO_AXES`.
    values : sequence of float
        Values of the swept requirement, in its field's unit (N/mm, mm, g or fraction).

    Returns
    -------
    list of (Requirements, float)
        One ``(requirements, value)`` per value, in order (a swept envelope widens a default diameter bound).

    Raises
    ------
    ValueError
        An unknown ``axis``, a value that is not a finite number its requirement can take (names it), a
        value given twice, or more than 500 values. Settings easily misread (one value, a limit of the
        requirements the sweep replaces) get a :class:`~vvea_design.spring.contradictions.SettingsNote`.
    """
    if axis not in PARETO_AXES:
        raise ValueError(f"unknown Pareto axis {axis!r}; choose one of {sorted(PARETO_AXES)}")
    field_name = PARETO_AXES[axis][0]
    values = list(values)
    check_count("pareto_points", len(values), "the number of values", ValueError)
    from .contradictions import check_pareto_settings

    check_pareto_settings(req, axis, values)
    points = []
    for i, v in enumerate(values):
        if isinstance(v, bool) or not isinstance(v, (int, float)) or not math.isfinite(v):
            raise ValueError(f"values[{i}] = {v!r}: each value of {field_name} must be a finite number")
        kw = {field_name: float(v)}
        if axis == "outer_diameter":  # the swept envelope: its default range follows; a pinned one is widened
            b = dict(req.bounds)
            lo = min(b.get("outer_diameter_mm", (25.0,))[0], 0.5 * float(v))
            b["outer_diameter_mm"] = (lo, max(b.get("outer_diameter_mm", (lo, float(v)))[1], float(v)))
            kw["bounds"] = b
            kw["fixed"] = _unfollowed(req)  # the flow path follows each swept envelope, not the file's
        try:
            points.append((replace(req, **kw), float(v)))
        except ValueError as exc:  # SpecError: a value no requirement can take
            raise ValueError(f"values[{i}] = {v:g}: {exc}") from None
    return points


def _unfollowed(req: Requirements) -> FixedParameters:
    """``req.fixed`` with the flow-path sizes that followed its envelope back at their defaults (a size the user
    wrote, or one that did not follow, is kept)."""
    from .requirements import FIXED_FOLLOW, follow_flow_path

    default = FixedParameters()
    plain = replace(req.fixed, **{n: getattr(default, n) for n in FIXED_FOLLOW})
    followed = follow_flow_path(plain, req.max_outer_diameter_mm)
    back = {n: getattr(default, n) for n in FIXED_FOLLOW
            if getattr(req.fixed, n) == getattr(followed, n) != getattr(default, n)}
    return replace(req.fixed, **back) if back else req.fixed


def save_pareto(rows: list, axis: str, out_dir, title: str = "") -> tuple:
    """Write a Pareto front as ``pareto_<axis>.csv`` and ``.png`` into ``out_dir``.

    Parameters
    ----------
    rows : list of ParetoPoint or dict
        Points of :func:`pareto_front` (or their rows, :meth:`ParetoPoint.to_dict`; the CSV gets the
        union of their keys as columns, units in the names).
    axis : str
        The swept requirement, a key of :data:`PARETO_AXES` (it names the files and the x axis).
    out_dir : str or Path
        Folder to write into (created).
    title : str
        Plot title; empty: "best linearity vs <axis>".

    Returns
    -------
    csv_path, png_path : Path
        The CSV and the PNG written.

    Raises
    ------
    KeyError
        If ``axis`` is not one of :data:`PARETO_AXES`.
    """
    import csv
    from pathlib import Path

    from .plots import plot_pareto, save_figure

    rows = [r.to_dict() if isinstance(r, ParetoPoint) else dict(r) for r in rows]
    out_dir = Path(out_dir)
    out_dir.mkdir(parents=True, exist_ok=True)
    csv_path = out_dir / f"pareto_{axis}.csv"
    keys = sorted({k for r in rows for k in r})
    with open(csv_path, "w", newline="") as fh:
        w = csv.DictWriter(fh, fieldnames=keys)
        w.writeheader()
        w.writerows(rows)
    x_key, label = PARETO_AXES[axis]
    png = save_figure(plot_pareto(rows, x_key, label, title=title or f"best linearity vs {axis}"),
                      out_dir / f"pareto_{axis}.png")
    return csv_path, png


# ---------------------------------------------------------------------------
# 2-D maps
# ---------------------------------------------------------------------------

@dataclass(frozen=True)
class LinearityMap(Record):
    """Linearity and feasibility over two decision variables (grids indexed ``[iy, ix]``)."""

    var_x: str  #: decision variable on the x axis (unit in the name: mm, mm³)
    var_y: str  #: decision variable on the y axis
    x: np.ndarray  #: x axis, in var_x's unit
    y: np.ndarray  #: y axis, in var_y's unit
    linearity: np.ndarray  #: linearity error (fraction), nan where the design cannot be built
    feasible: np.ndarray  #: bool: every margin >= 0
    worst: np.ndarray  #: name of the most violated constraint, "" where feasible, "unbuildable"
    margins: dict[str, np.ndarray]  #: constraint name -> scaled, dimensionless margin grid (nan where unbuildable)


def linearity_map(
    design: Design,
    req: Requirements,
    var_x: str,
    var_y: str,
    *,
    x_range: tuple[float, float] | None = None,
    y_range: tuple[float, float] | None = None,
    n: int = 61,
) -> LinearityMap:
    """Linearity and feasibility over two decision variables, the others held at ``design``.

    Returns the axes (``x``, ``y``), ``linearity`` (nan where the
    design cannot be built) and ``feasible`` (all margins >= 0) grids of shape
    ``(n, n)`` indexed ``[iy, ix]``, the name of the most violated
    constraint at every point (``worst``) and every constraint's margin grid
    (``margins``: name -> grid, nan where unbuildable). The default ranges are ±40 % around
    the design, clipped to the search bounds. The map is taken at the design's own charge
    (p2, MPa) and set point, without the bladder-strain constraint.

    Parameters
    ----------
    design : Design
        The design held fixed in every other variable (usually the optimum).
    req : Requirements
        Requirements whose margins decide feasibility.
    var_x, var_y : str
        Two different decision variables of the design's layout (unit in the name: mm, mm³).
    x_range, y_range : tuple of float or None
        ``(low, high)`` of each axis in the variable's own unit (mm, mm³); None: ±40 % around the
        design, inside the search bounds.
    n : int
        Grid points per axis (the map has n × n points).

    Returns
    -------
    LinearityMap
        ``var_x``, ``var_y``; ``x``, ``y`` (axes, in the variables' units); ``linearity``
        (fraction, ``(n, n)``), ``feasible`` (bool), ``worst`` (name of the most violated
        constraint, "" where feasible, "unbuildable") and ``margins`` (name -> scaled,
        dimensionless margin grid).

    Raises
    ------
    ValueError
        If a variable is not a decision variable of the layout or the two are the same.
    """
    names = design.variant.decision_variables
    for v in (var_x, var_y):
        if v not in names:
            raise ValueError(f"unknown design variable {v!r} of the {design.layout!r} layout; choose from {list(names)}")
    if var_x == var_y:
        raise ValueError(f"the two map variables must differ, got {var_x!r} twice")
    n = check_count("map_points", n, "n", ValueError)
    bounds = dict(zip(names, req.search_bounds(design.layout)))

    def around(var):  # default range: ±40 % around the design, inside the search bounds
        v = float(getattr(design, var))
        lo, hi = bounds[var]
        return max(lo, 0.6 * v), min(hi, max(1.4 * v, lo + 0.4 * (hi - lo) if v == 0 else 1.4 * v))

    xs = np.linspace(*(x_range or around(var_x)), n)
    ys = np.linspace(*(y_range or around(var_y)), n)
    YY, XX = np.meshgrid(ys, xs, indexing="ij")
    X = np.tile(design.decision_vector(), (n * n, 1))
    X[:, names.index(var_x)] = XX.ravel()
    X[:, names.index(var_y)] = YY.ravel()
    r = replace(req, max_bladder_strain=None, optimise_cast_fill=False, max_charge_MPa=design.p2_MPa,
                setpoint_x0_mm=design.setpoint_x0_mm)
    r = replace(r, fixed=design.fixed)
    obj, mar, ok = evaluate_population(X, r, design.layout)
    cn = constraint_names(r, design.layout, search=True)
    lin = np.where(ok, obj, np.nan).reshape(n, n)
    feas = (ok & np.all(mar >= -1e-9, axis=0)).reshape(n, n)
    worst_i = mar.argmin(axis=0)
    worst = np.array([("unbuildable" if not o else (cn[w] if mar[w, k] < 0 else ""))
                      for k, (o, w) in enumerate(zip(ok, worst_i))], dtype=object).reshape(n, n)
    margins = {name: np.where(ok, mar[i], np.nan).reshape(n, n) for i, name in enumerate(cn)}
    return LinearityMap(var_x, var_y, xs, ys, lin, feas, worst, margins)


# ---------------------------------------------------------------------------
# Packing-free bound
# ---------------------------------------------------------------------------

@dataclass(frozen=True)
class GasVolumeBound(Record):
    """The best linearity any layout could reach with a total gas volume (:func:`gas_volume_bound`)."""

    total_gas_mm3: float  #: largest V1 + V2 allowed
    linearity_error: float  #: the best objective found (fraction)
    A1_mm2: float  #: chamber areas that reach it
    A2_mm2: float
    V1_mm3: float  #: chamber volumes that reach it
    V2_mm3: float
    feasible: bool
    objective_exponents: list[float]  #: polytropic exponents of the objective (dimensionless)
    V1_max_mm3: float | None = None  #: the caps asked for (None where not given)
    V2_max_mm3: float | None = None
    chamber1_length_max_mm: float | None = None


def gas_volume_bound(total_gas_mm3: float, req: Requirements | None = None, *, seed: int = 0,
                     maxiter: int = 400, V1_max_mm3: float | None = None, V2_max_mm3: float | None = None,
                     chamber1_length_max_mm: float | None = None, V1_extra_mm3: float = 0.0) -> GasVolumeBound:
    """Best linearity any layout could reach with ``V1 + V2 <= total_gas_mm3``.

    Ignores packing entirely: only eq. 5, the charge limit (both chambers <=
    ``max_charge_MPa``, F(0) = 0 so ``p1 = A2/A1 p2``), the stiffness
    requirement and the minimum gas left at full stroke; the objective is the
    requirements' (worst over its exponents, exact metric). It tells how much
    gas a target linearity needs, whatever the housing. Vectorised
    differential evolution + SLSQP polish over (A1, A2, V1, V2).
    ``V1_max_mm3`` / ``V2_max_mm3`` cap each chamber too (a layout's
    per-chamber capacities: the bound is then that layout's own floor).
    ``chamber1_length_max_mm`` confines chamber 1 to the piston bore:
    ``V1 <= A1 * chamber1_length_max_mm + V1_extra_mm3`` (the longest gas
    column the housing leaves above the piston, plus ports).

    Parameters
    ----------
    total_gas_mm3 : float
        Largest total gas volume V1 + V2 allowed.
    req : Requirements or None
        Travel, charge limit, stiffness, gas left at full stroke and objective exponents
        (default: the paper's unit).
    seed : int
        Seed of the differential evolution.
    maxiter : int
        Generation limit of the differential evolution.
    V1_max_mm3, V2_max_mm3 : float or None
        Largest chamber-1 / chamber-2 gas volume; None: only the total caps it.
    chamber1_length_max_mm : float or None
        Longest gas column above the piston; None: chamber 1 is not confined to the bore.
    V1_extra_mm3 : float
        Chamber-1 gas outside that column (ports), added to its cap.

    Returns
    -------
    GasVolumeBound
        ``total_gas_mm3``, ``linearity_error`` (the best objective, fraction), the chamber areas
        ``A1_mm2``, ``A2_mm2`` and volumes ``V1_mm3``, ``V2_mm3`` that reach it, ``feasible``,
        ``objective_exponents`` (dimensionless) and the caps asked for (``V1_max_mm3``,
        ``V2_max_mm3``, ``chamber1_length_max_mm``; None where not given).
    """
    from .gas_spring import linearity_exact

    req = req or Requirements()
    T = req.travel_mm
    pmax = req.max_charge_MPa
    fmin = req.min_gas_fraction_at_full_stroke
    ns = req.objective_exponents

    def both(X):
        X = np.atleast_2d(X)
        A1, A2, V1, V2 = X[:, 0], X[:, 1], X[:, 2], X[:, 3]
        p1 = A2 / A1 * pmax
        with np.errstate(all="ignore"):
            objs = [linearity_exact(A1, A2, V1, V2, p1, pmax, T, n) for n in ns]
            obj = np.max([r.linearity_error for r in objs], axis=0)
            kn = linearity_exact(A1, A2, V1, V2, p1, pmax, T, req.n_polytropic).mean_stiffness_N_per_mm
            k = kn / req.min_mean_stiffness_N_per_mm - 1
            gas_left = (V2 - A2 * T) / V2 - fmin
            rows = [(A1 - A2) / A1, 1 - (V1 + V2) / total_gas_mm3, k, gas_left]
            if V1_max_mm3 is not None:
                rows.append(1 - V1 / V1_max_mm3)
            if V2_max_mm3 is not None:
                rows.append(1 - V2 / V2_max_mm3)
            if chamber1_length_max_mm is not None:
                rows.append(1 - V1 / (A1 * chamber1_length_max_mm + V1_extra_mm3))
            cons = np.array(rows)
        bad = ~np.isfinite(obj) | ~np.all(np.isfinite(cons), axis=0)
        return np.where(bad, 1.0, obj), np.where(bad[None, :], -1.0, cons)

    both_memo = _RowMemo(both)  # differential evolution asks for the objective of designs already evaluated

    def both_m(X):
        return both_memo(np.atleast_2d(X))

    bounds = [(100, 5000), (100, 5000), (1e3, min(total_gas_mm3, V1_max_mm3 or np.inf)),
              (1e3, min(total_gas_mm3, V2_max_mm3 or np.inf))]
    r = differential_evolution(lambda X: both_m(X.T)[0], bounds,
                               constraints=[NonlinearConstraint(lambda X: both_m(np.asarray(X).T)[1], 0, np.inf)],
                               seed=seed, popsize=20, maxiter=maxiter, tol=1e-8, polish=False, init="sobol",
                               vectorized=True, updating="deferred")

    class _P:
        count = 0

        def __call__(self, X):
            o, c = both_m(np.asarray(X).T)
            return o, c

        def objective(self, x):
            return float(both_m(x)[0][0])

        def constraints(self, x):
            return both_m(x)[1][:, 0]

    x, _ = _polish(_P(), np.asarray(r.x, dtype=float), bounds)
    A1, A2, V1, V2 = (float(v) for v in x)
    obj, cons = both_m(x)
    return GasVolumeBound(float(total_gas_mm3), float(obj[0]), A1, A2, V1, V2, bool(np.all(cons >= -1e-6)), list(ns),
                          V1_max_mm3, V2_max_mm3, chamber1_length_max_mm)


# ---------------------------------------------------------------------------
# The envelope's gas capacity
# ---------------------------------------------------------------------------

@dataclass(frozen=True)
class GasCapacity(Record):
    """The largest gas volume a layout holds in the requirements' envelope (:func:`gas_capacity`)."""

    layout: str
    maximise: str  #: what was made largest: "total", "V1" or "V2"
    total_gas_mm3: float  #: V1 + V2 of the design found
    V1_mm3: float
    V2_mm3: float
    bladder_cast_fill: float  #: stroke fraction
    bladder_strain_surrogate: float | None  #: fraction; None without ``optimise_cast_fill``
    feasible: bool
    decision_vector: list[float]  #: the layout's decision variables (mm, mm³)
    binding: list[str]  #: constraints with margin < 0.001
    housing_length_mm: float
    piston_diameter_mm: float


def gas_capacity(req: Requirements | None = None, layout: str = "inner_tube", *, seed: int = 0,
                 maxiter: int = 200, maximise: Literal["total", "V1", "V2"] = "total") -> GasCapacity:
    """The largest gas volume ``V1 + V2`` a layout can hold in the requirements' envelope.

    Every constraint of :func:`~vvea_design.spring.problem.evaluate_design`
    holds — envelope, walls sized for the peak pressure at the charge limit,
    the piston and fluid column, the bladder with its room at both stroke
    ends, the gas left at full stroke, and the stiffness (without it a thin
    piston would leave the whole housing to gas, for no spring) — only the
    linearity is not asked for. Since the packing-free bound
    (:func:`gas_volume_bound`) falls with the gas volume, the bound at this
    capacity is a floor no design of the layout can beat. ``maximise = "V1"``
    or ``"V2"`` finds the largest single chamber instead (the layout's
    per-chamber capacities).

    Parameters
    ----------
    req : Requirements or None
        The envelope and constraints (default: the paper's unit); the linearity objective is
        dropped, and so is the bladder-strain limit unless ``optimise_cast_fill`` is set (then
        the strain surrogate keeps it and the cast fill is searched too).
    layout : str
        Layout variant (a name of :data:`vvea_design.spring.layouts.LAYOUTS`).
    seed : int
        Seed of the differential evolution.
    maxiter : int
        Generation limit of the differential evolution.
    maximise : {"total", "V1", "V2"}
        What to make largest: the total gas volume V1 + V2, or one chamber's (mm³ each).

    Returns
    -------
    GasCapacity
        ``layout``, ``maximise``, ``total_gas_mm3`` (V1 + V2 of the design found), ``V1_mm3``,
        ``V2_mm3``, ``bladder_cast_fill`` (fraction), ``bladder_strain_surrogate`` (fraction; None
        without ``optimise_cast_fill``), ``feasible``, ``decision_vector`` (the decision variables,
        mm and mm³), ``binding`` (constraints with margin < 0.001), ``housing_length_mm`` and
        ``piston_diameter_mm``.

    Raises
    ------
    ValueError
        If ``maximise`` is not one of "total", "V1", "V2".
    DesignError
        If ``layout`` is unknown (the message lists the known ones).
    """
    req = req or Requirements()
    if maximise not in ("total", "V1", "V2"):
        raise ValueError(f"maximise must be 'total', 'V1' or 'V2', got {maximise!r}")
    # with a free cast fill the strain limit is part of what the bladder can hold (surrogate, then the
    # final design's surrogate value); otherwise the capacity ignores an optional strain limit
    strained = req.optimise_cast_fill
    r = replace(req, objective="nominal", objective_n=None,
                **({} if strained else {"max_bladder_strain": None}))
    strain_fn = None
    if strained:
        from .strain_surrogate import population_strain as strain_fn
    names = constraint_names(r, layout)
    bounds = r.search_bounds(layout)
    dvars = r.decision_variables(layout)
    i1, i2 = dvars.index("V1_mm3"), dvars.index("V2_mm3")
    w1, w2 = {"total": (1.0, 1.0), "V1": (1.0, 0.0), "V2": (0.0, 1.0)}[maximise]
    scale = 1.0 / max(b[1] for b in bounds)

    def cap_eval(XS):
        _, mar, ok = evaluate_population(XS, r, layout, strain_fn)
        return np.where(ok, -(w1 * XS[:, i1] + w2 * XS[:, i2]) * scale, 1.0), mar

    if not strained:  # designs already evaluated are not again (the surrogate's matrix product: as before)
        cap_eval = _RowMemo(cap_eval)

    class _Cap:
        count = 0

        def __call__(self, X):
            XS = np.atleast_2d(np.asarray(X).T)
            self.count += XS.shape[0]
            return cap_eval(XS)

        def objective(self, x):
            return float(self(np.asarray(x)[:, None])[0][0])

        def constraints(self, x):
            return self(np.asarray(x)[:, None])[1][:, 0]

    prob = _Cap()
    de = differential_evolution(lambda X: prob(X)[0], bounds,
                                constraints=[NonlinearConstraint(lambda X: prob(X)[1], 0.0, np.inf)],
                                seed=seed, popsize=15, maxiter=maxiter, tol=1e-8, atol=0.0, polish=False,
                                init="sobol", vectorized=True, updating="deferred")
    x, _ = _best_polish(prob, _starts(prob, de, bounds, 8), bounds)
    d = design_from_vector(x, r, layout)
    strain = None
    if strained:
        from .strain_surrogate import design_strain

        strain = design_strain(d)
    ev = evaluate_design(d, r, bladder_strain=strain)
    return GasCapacity(layout, maximise, d.V1_mm3 + d.V2_mm3, d.V1_mm3, d.V2_mm3, d.fixed.bladder_cast_fill, strain,
                       ev.feasible, [float(v) for v in x], [n for n in names if ev.margins[n] < 1e-3],
                       d.housing_length_mm, d.piston_diameter_mm)
