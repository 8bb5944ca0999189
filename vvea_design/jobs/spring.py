"""The spring side's jobs: ``vvea optimise``, ``spring``, ``check``, ``map`` and ``pareto`` as functions.

* :func:`optimise` - the most linear spring that meets the requirements; ``design.json`` and its force plot.
* :func:`spring_report` - force curve, stiffness and linearity of a design; ``spring.csv`` and ``spring.png``.
* :func:`check_design` - a design's linearity against a limit (the regression gate).
* :func:`linearity_map` - linearity over two design variables; ``map_<x>_<y>.png`` and ``.csv``.
* :func:`pareto_front` - best linearity as one requirement is swept; ``pareto_<axis>.csv`` and ``.png``.

Each writes its files only when given ``out``, whole or not at all, and returns a typed result.
"""

from __future__ import annotations

import csv
import math
from collections.abc import Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING, Any

from .common import (OptionError, PathLike, check_option, check_out, check_scheduler_option, design_of, files, folder,
                     inputs_kept, lazy_errors, moved, requirements_of, spring_of)

if TYPE_CHECKING:
    from ..spring.curve import SpringCurve
    from ..spring.design import Design
    from ..spring.gas_spring import GasSpring
    from ..spring.optimise import OptimisationResult
    from ..spring.requirements import Requirements
    from ..spring.studies import LinearityMap, ParetoPoint

__all__ = ["optimise", "force_plot_path", "SpringReport", "spring_report", "write_spring_files", "LinearityCheck",
           "check_design", "LinearityMapReport", "linearity_map", "ParetoFront", "pareto_front",
           "SpecError", "DesignFileError", "Infeasible", "NoBuildableDesign"]

#: The errors these jobs raise, imported on first use.
__getattr__ = lazy_errors(__name__, ("SpecError", "DesignFileError", "Infeasible", "NoBuildableDesign"))


# ---------------------------------------------------------------------------------------------- optimise
def force_plot_path(design_json: PathLike) -> Path:
    """Where :func:`optimise` draws the force curve of the design it writes to ``design_json``.

    Parameters
    ----------
    design_json : path-like
        The design JSON.

    Returns
    -------
    Path
        ``<stem>_force.png`` beside it.
    """
    p = Path(design_json)
    return p.with_name(p.stem + "_force.png")


def optimise(requirements: Requirements | PathLike | None = None, *, seed: int = 0, out: PathLike | None = None,
             progress: bool = True) -> OptimisationResult:
    """Find the most linear spring that meets the requirements (``vvea optimise``).

    With the requirements' ``max_bladder_strain`` the FE bladder strain of the requirements' silicone
    constrains the search.

    Parameters
    ----------
    requirements : Requirements, path-like or None
        The requirements, a requirements TOML file, or None for the paper's unit.
    seed : int
        Seed of the global search (same seed, same design).
    out : path-like, optional
        The design JSON to write; its force plot goes beside it (:func:`force_plot_path`). Both land
        together or neither.
    progress : bool
        Show the search's progress bar on stderr.

    Returns
    -------
    OptimisationResult
        The evaluated best design (mm, mm³, MPa; linearity as a fraction) and how it was found.

    Raises
    ------
    OutputError
        ``out`` or the plot beside it cannot be written, or is the requirements file (before the search).
    OptionError
        A ``seed`` the search's generator cannot take.
    SpecError
        Requirements that cannot be read or hold a wrong value.
    Infeasible
        No design meets the requirements (``exc.result`` is the least-violating one); nothing is written.
    NoBuildableDesign
        No point inside the search bounds can be drawn.
    """
    if out is not None:
        check_out(out, "file")
        check_out(force_plot_path(out), "file")
        inputs_kept((out, force_plot_path(out)), (requirements,))
    check_option("seed", seed, "seed")
    req, _ = requirements_of(requirements)
    strain_fn = None
    if req.max_bladder_strain is not None:
        from functools import partial

        from ..bladder.check import strain_bound

        strain_fn = partial(strain_bound, material=req.bladder_material)
    from ..spring.optimise import optimise as search

    res = search(req, seed=seed, bladder_strain_fn=strain_fn, **({} if progress else {"progress": False}))
    if out is not None:
        from ..spring.design_file import save_design
        from ..spring.plots import plot_spring, save_figure

        with files(out, force_plot_path(out)) as (tmp_json, tmp_png):  # both files whole, or neither
            save_design(tmp_json, res.evaluation, req, optimiser=res.summary())
            save_figure(plot_spring(res.design.gas_spring, extra_charges_MPa=(1.0, 2.0),
                                    title=f"optimised design ({res.layout} layout): linearity "
                                          f"{100 * res.evaluation.linearity_error:.2f} %"), tmp_png)
    return res


# ---------------------------------------------------------------------------------------------- spring
@dataclass(frozen=True)
class SpringReport:
    """What :func:`spring_report` found: the spring, its curves and the files written."""

    spring: GasSpring  #: the gas spring evaluated (mm, mm², mm³, MPa)
    curve: SpringCurve  #: isothermal and adiabatic force curves, deviations, pressures
    layout: str | None  #: the design's layout (None when read from a design file's parameters)
    files: dict[str, Path] = field(default_factory=dict)  #: ``csv``, ``png`` (empty: nothing written)
    #: ``""``, or the label of a charge above the design's rating computed on request (``allow_over_rating``)
    over_rating: str = ""

    @property
    def linearity_error(self) -> float:
        """Linearity error at the spring's own polytropic exponent (fraction)."""
        return float(self.spring.linearity_error())

    @property
    def linearity_error_adiabatic(self) -> float:
        """Linearity error at n = 1.4 (fraction)."""
        return float(self.spring.with_polytropic(1.4).linearity_error())

    @property
    def mean_stiffness_N_per_mm(self) -> float:
        """Least-squares slope of the force over the travel."""
        return float(self.spring.mean_stiffness_N_per_mm())

    @property
    def force_at_travel_N(self) -> float:
        """Force at full travel (tension > 0)."""
        return float(self.spring.force_N(self.spring.travel_mm))

    def to_dict(self) -> dict[str, Any]:
        """JSON-ready summary.

        Returns
        -------
        dict
            ``layout``, ``n_polytropic``, ``p2_MPa``, ``travel_mm``, ``linearity_error`` and
            ``linearity_error_adiabatic`` (fractions), ``mean_stiffness_N_per_mm``, ``force_at_travel_N`` (N),
            the curve's scalars (stiffness in N/mm, linearity as fractions) and ``files`` (paths as text);
            ``over_rating`` (the label) when computed above the design's rating.
        """
        s = self.spring
        return {**({"over_rating": self.over_rating} if self.over_rating else {}),
                "layout": self.layout, "n_polytropic": float(s.n_polytropic), "p2_MPa": float(s.p2_MPa),
                "travel_mm": float(s.travel_mm), "linearity_error": self.linearity_error,
                "linearity_error_adiabatic": self.linearity_error_adiabatic,
                "mean_stiffness_N_per_mm": self.mean_stiffness_N_per_mm, "force_at_travel_N": self.force_at_travel_N,
                **{k: v for k, v in self.curve.to_dict().items() if not isinstance(v, list)},
                "files": {k: str(v) for k, v in self.files.items()}}


def write_spring_files(spring: GasSpring, out_dir: PathLike, layout: str | None = None,
                       label: str = "") -> dict[str, Path]:
    """Write ``spring.csv`` (x, force, stiffness, pressures) and ``spring.png`` into ``out_dir``.

    Parameters
    ----------
    spring : GasSpring
        The gas spring (mm, mm², mm³, MPa).
    out_dir : path-like
        Folder (created).
    layout : str, optional
        The design's layout, named in the figure's title.
    label : str, optional
        A warning every file carries (an over-rating charge): the figure's title and a first line of
        the CSV that starts with ``#``.

    Returns
    -------
    dict of str to Path
        ``{"csv": ..., "png": ...}``.
    """
    from ..spring.plots import plot_spring, save_figure

    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    x = spring.x_mm(81)
    F = spring.force_N(x)
    k = spring.stiffness_N_per_mm(x)
    P1, P2 = spring.pressures_MPa(x)
    csv_path = out / "spring.csv"
    with open(csv_path, "w", newline="") as fh:
        if label:
            fh.write(f"# {label}\n")
        w = csv.writer(fh)
        w.writerow(["x_mm", "force_N", "stiffness_N_per_mm", "P1_MPa", "P2_MPa"])
        for row in zip(x, F, k, P1, P2):
            w.writerow([f"{v:.6g}" for v in row])
    png = save_figure(plot_spring(spring, label.split(" (")[0], extra_charges_MPa=(1.0, 2.0, 4.0), layout=layout), out / "spring.png")
    return {"csv": csv_path, "png": png}


def spring_report(design: Design | GasSpring | PathLike, *, p2_MPa: float | None = None,
                  allow_over_rating: bool = False, out: PathLike | None = None) -> SpringReport:
    """Force curve, stiffness and linearity of a design from its parameters alone (``vvea spring``).

    Parameters
    ----------
    design : Design, GasSpring or path-like
        The design, its gas spring, or a design JSON (its ``parameters`` alone, paper eq. 5).
    p2_MPa : float, optional
        Evaluate at this chamber-2 charge (p1 from eq. 7); None: the design's own.
    allow_over_rating : bool
        Evaluate a ``p2_MPa`` above the design's rating (:func:`vvea_design.jobs.rating.charge_rating`: its
        ``spec.max_charge_MPa`` or its own charge); the report and every file are then labelled.
    out : path-like, optional
        Folder for ``spring.csv`` and ``spring.png``.

    Returns
    -------
    SpringReport
        The spring, its isothermal and adiabatic curves, the files written and the over-rating label.

    Raises
    ------
    DesignFileError
        A design file that is missing or incomplete.
    OptionError
        ``p2_MPa`` <= 0, outside the range a real charge has, above what the design's walls hold, or above
        the design's rating without ``allow_over_rating``.
    OutputError
        ``out`` cannot be written (before any work).
    """
    from ..spring.curve import spring_curve

    check_out(out)
    if p2_MPa is not None:
        if p2_MPa <= 0:
            raise OptionError("p2_MPa", f"must be > 0 MPa, got {p2_MPa}", "{option} {reason}")
        check_option("charge_MPa", p2_MPa, "p2_MPa")
    spring, layout = spring_of(design)  # a design file is rebuilt from its decision variables, never trusted
    label = ""
    if p2_MPa is not None:
        _within_walls(design, p2_MPa)
        from .rating import check_charge

        label = check_charge(design, p2_MPa, allow_over_rating=allow_over_rating)
        spring = spring.with_pressures(p2_MPa)
    written: dict[str, Path] = {}
    with folder(out, "spring", names=("spring.csv", "spring.png")) as tmp:
        if tmp is not None:
            written = write_spring_files(spring, tmp, layout=layout, label=label)
    if out is not None:
        written = {k: moved(v, tmp, Path(out)) for k, v in written.items()}
    return SpringReport(spring, spring_curve(spring), layout, written, label)


def _within_walls(design: Any, p2_MPa: float) -> None:
    """Raise :class:`OptionError` when the design's walls yield below the charge ``p2_MPa`` (MPa)."""
    from ..spring.design import Design
    from ..spring.design_file import load_design_dict

    if isinstance(design, dict):
        d = load_design_dict(design)
    elif isinstance(design, (str, Path)):
        d = design_of(design)
    elif isinstance(design, Design):
        d = design
    else:
        return  # a bare gas spring has no walls
    sf = min(d.wall_safety_factors().values())
    if p2_MPa > d.p2_MPa * sf:
        raise OptionError("p2_MPa", f"= {p2_MPa:g} MPa: the walls of {design if isinstance(design, (str, Path)) else 'the design'} "
                          f"yield above {d.p2_MPa * sf:.3g} MPa (they are sized for p2 = {d.p2_MPa:g} MPa at a "
                          f"safety factor of {sf:.3g}); recharge at most to that, or optimise a design for the higher "
                          "charge (max_charge_MPa)", "{option} {reason}")


# ---------------------------------------------------------------------------------------------- check
@dataclass(frozen=True)
class LinearityCheck:
    """A design's linearity error against a limit (:func:`check_design`)."""

    design: str  #: what was checked (the file, or a description)
    linearity_error: float  #: fraction of the force span, the exact metric over the continuous travel
    max_linearity: float  #: the limit, fraction
    message: str = ""  #: why it fails ("" when it passes)

    @property
    def passes(self) -> bool:
        """The linearity error is within the limit."""
        return not self.message

    def to_dict(self) -> dict[str, Any]:
        """JSON-ready.

        Returns
        -------
        dict
            ``design``, ``linearity_error`` and ``max_linearity`` (fractions), ``passes`` and ``message``.
        """
        return {"design": self.design, "linearity_error": self.linearity_error,
                "max_linearity": self.max_linearity, "passes": self.passes, "message": self.message}


def check_design(design: GasSpring | PathLike | dict, max_linearity: float) -> LinearityCheck:
    """A design's linearity against a limit, from its parameters alone (``vvea check``, a regression gate).

    Parameters
    ----------
    design : GasSpring, path-like or dict
        A design JSON, its parsed content, or a gas spring.
    max_linearity : float
        Largest acceptable linearity error, a fraction in (0, 1) (0.015 = 1.5 %).

    Returns
    -------
    LinearityCheck
        The error (fraction) and whether it passes (``message`` says why not).

    Raises
    ------
    OptionError
        ``max_linearity`` outside (0, 1).
    DesignFileError
        A design file that is missing or incomplete.
    """
    from ..testing import LinearityRegression, check_linearity

    if not 0 < max_linearity < 1:
        raise OptionError("max_linearity", f"is a fraction in (0, 1), got {max_linearity}", "{option} {reason}")
    label = str(design) if isinstance(design, (str, Path)) else "design"
    try:
        return LinearityCheck(label, float(check_linearity(design, max_linearity)), max_linearity)
    except LinearityRegression as exc:
        return LinearityCheck(label, float(spring_of(design)[0].linearity_error()), max_linearity, str(exc))


# ---------------------------------------------------------------------------------------------- map
@dataclass(frozen=True)
class LinearityMapReport:
    """What :func:`linearity_map` found: the map around a design and the files written."""

    map: LinearityMap  #: linearity and feasibility over the two variables (grids ``[iy, ix]``)
    optimum: tuple[float, float]  #: the design's own (x, y), in the variables' units (mm, mm³)
    files: dict[str, Path] = field(default_factory=dict)  #: ``png``, ``csv`` (empty: nothing written)

    def to_dict(self) -> dict[str, Any]:
        """JSON-ready.

        Returns
        -------
        dict
            ``var_x``, ``var_y``, the axes ``x`` and ``y`` (the variables' units, mm or mm³), ``linearity``
            (fractions, None where the design cannot be built), ``feasible``, ``worst`` (the most violated
            constraint), ``optimum`` and ``files`` (paths as text).
        """
        m = self.map
        return {"var_x": m.var_x, "var_y": m.var_y, "x": [float(v) for v in m.x], "y": [float(v) for v in m.y],
                "linearity": [[None if math.isnan(v) else float(v) for v in row] for row in m.linearity],
                "feasible": [[bool(v) for v in row] for row in m.feasible],
                "worst": [[str(v) for v in row] for row in m.worst], "optimum": list(self.optimum),
                "files": {k: str(v) for k, v in self.files.items()}}


def _write_map(m: LinearityMap, optimum: tuple[float, float], out: Path) -> dict[str, Path]:
    """``map_<x>_<y>.png`` and ``.csv`` of ``m`` into ``out``."""
    import numpy as np

    from ..spring.plots import plot_linearity_map, save_figure

    x, y = m.var_x, m.var_y
    png, csv_path = out / f"map_{x}_{y}.png", out / f"map_{x}_{y}.csv"
    save_figure(plot_linearity_map(m, optimum=optimum), png)
    with open(csv_path, "w", newline="") as fh:
        w = csv.writer(fh)
        w.writerow([x, y, "linearity_error", "feasible", "most_violated"])
        for iy, yv in enumerate(m["y"]):
            for ix, xv in enumerate(m["x"]):
                lin = m["linearity"][iy, ix]
                w.writerow([f"{xv:.6g}", f"{yv:.6g}", "" if np.isnan(lin) else f"{lin:.6g}",
                            int(m["feasible"][iy, ix]), m["worst"][iy, ix]])
    return {"png": png, "csv": csv_path}


def linearity_map(design: Design | PathLike, *, x: str = "outer_diameter_mm", y: str = "V2_mm3", n: int = 61,
                  requirements: Requirements | PathLike | None = None,
                  out: PathLike | None = None) -> LinearityMapReport:
    """Linearity over two design variables around a design, the infeasible region marked (``vvea map``).

    Parameters
    ----------
    design : Design or path-like
        The design (the other variables held at its values), or its design JSON.
    x, y : str
        Decision variables on the axes (unit in the name: mm, mm³).
    n : int
        Grid points per axis (the map has n × n points).
    requirements : Requirements, path-like or None
        Requirements whose margins decide feasibility; None: those stored in the design JSON (a design
        given as an object: the defaults).
    out : path-like, optional
        Folder for ``map_<x>_<y>.png`` and ``map_<x>_<y>.csv``.

    Returns
    -------
    LinearityMapReport
        The map (linearity as a fraction) and the files written.

    Raises
    ------
    DesignFileError
        A design file that is missing, incomplete or without requirements.
    ValueError
        A variable that is not a decision variable of the design's layout, or ``x`` = ``y``.
    OptionError
        ``n`` outside 2 ... 401 points per axis (before anything is allocated).
    OutputError
        ``out`` cannot be written, or is the design file (before any work).
    """
    from ..spring.studies import linearity_map as grid_map

    from ..spring.design import Design

    check_option("map_points", n, "n")
    check_out(out)
    inputs_kept((out,), (design, requirements))
    d = design_of(design)
    if requirements is None and not isinstance(design, Design):
        from ..spring.design_file import load_requirements_from_design

        req = load_requirements_from_design(design)
    else:
        req, _ = requirements_of(requirements)
    m = grid_map(d, req, x, y, n=n)
    optimum = (getattr(d, x), getattr(d, y))
    written: dict[str, Path] = {}
    with folder(out, "map") as tmp:
        if tmp is not None:
            written = _write_map(m, optimum, tmp)
    if out is not None:
        written = {k: moved(v, tmp, Path(out)) for k, v in written.items()}
    return LinearityMapReport(m, optimum, written)


# ---------------------------------------------------------------------------------------------- pareto
@dataclass(frozen=True)
class ParetoFront:
    """What :func:`pareto_front` found: one optimum per value of the swept requirement, and the files."""

    axis: str  #: the swept requirement (a key of :data:`vvea_design.spring.studies.PARETO_AXES`)
    swept: str  #: its requirements field, unit in the name (``min_mean_stiffness_N_per_mm``)
    points: tuple[ParetoPoint, ...]  #: one per value, in order
    files: dict[str, Path] = field(default_factory=dict)  #: ``csv``, ``png`` (empty: nothing written)

    def to_dict(self) -> dict[str, Any]:
        """JSON-ready.

        Returns
        -------
        dict
            ``axis``, ``swept``, ``points`` (each the row of the CSV: linearity as fractions, mass in g,
            stiffness in N/mm, the decision variables in mm and mm³) and ``files`` (paths as text).
        """
        return {"axis": self.axis, "swept": self.swept, "points": [p.to_dict() for p in self.points],
                "files": {k: str(v) for k, v in self.files.items()}}


def pareto_front(axis: str, values: Sequence[float], *, requirements: Requirements | PathLike | None = None,
                 seed: int = 0, workers: int | None = None, scheduler: str | None = None,
                 out: PathLike | None = None, progress: bool = True) -> ParetoFront:
    """Best linearity as one requirement is swept: one optimisation per value (``vvea pareto``).

    Parameters
    ----------
    axis : str
        The swept requirement: ``stiffness`` (N/mm), ``outer_diameter`` (mm), ``mass`` (g) or ``adiabatic``
        (linearity at n = 1.4, fraction).
    values : sequence of float
        Its values, in the axis' unit (N/mm, mm, g or fraction).
    requirements : Requirements, path-like or None
        The other requirements (a TOML file, or None for the paper's unit).
    seed : int
        Seed of each point's global search.
    workers : int, optional
        Local worker processes (None: all cores).
    scheduler : str, optional
        Dask scheduler address (``tcp://host:port``); None: local processes.
    out : path-like, optional
        Folder for ``pareto_<axis>.csv`` and ``pareto_<axis>.png``.
    progress : bool
        Show a progress bar on stderr.

    Returns
    -------
    ParetoFront
        One point per value (feasible or not; linearity as a fraction) and the files written.

    Raises
    ------
    OptionError
        An unknown ``axis``, no ``values`` or a value its requirement cannot take, a bad ``seed`` or
        ``workers``, an unreachable ``scheduler`` (all before any work).
    OutputError
        ``out`` cannot be written (before any work).
    SpecError
        Requirements that cannot be read or hold a wrong value.
    """
    from ..spring.studies import PARETO_AXES, pareto_front as sweep, save_pareto

    if axis not in PARETO_AXES:
        raise OptionError("axis", f"must be one of {sorted(PARETO_AXES)}, got {axis!r}", "{option} {reason}")
    vals = [float(v) for v in values]
    if not vals:
        raise OptionError("values", "is empty", "{option} {reason}")
    check_option("seed", seed, "seed")
    check_option("workers", workers, "workers")
    check_out(out)
    inputs_kept((out,), (requirements,))
    req, _ = requirements_of(requirements)
    from ..spring.studies import check_pareto_values

    try:
        check_pareto_values(req, axis, vals)
    except ValueError as exc:
        raise OptionError("values", str(exc)) from None
    check_scheduler_option(scheduler)
    rows = sweep(req, axis, vals, seed=seed, workers=workers, scheduler=scheduler, progress=progress)
    written: dict[str, Path] = {}
    with folder(out, "pareto") as tmp:
        if tmp is not None:
            written = dict(zip(("csv", "png"), save_pareto(rows, axis, tmp)))
    if out is not None:
        written = {k: moved(Path(v), tmp, Path(out)) for k, v in written.items()}
    return ParetoFront(axis, PARETO_AXES[axis][0], tuple(rows), written)
