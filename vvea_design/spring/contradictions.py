"""Settings of the objective and the search that contradict each other: refused, or named in a note.

A requirements file sets the objective (``objective``, ``objective_n``), the search (``layouts``, ``joints``,
``optimise_cast_fill``, ``[bounds]``) and the rules (``[fixed] sizing_rules``). Some combinations cannot all hold,
or one of them would be ignored without a word: the file is then refused naming both settings and what would be
accepted (:class:`~vvea_design.spring.requirements.SpecError`). Combinations that hold but are easily misread get
a :class:`SettingsNote` warning (the command line prints it as ``note: ...``). The table is
:data:`CONTRADICTIONS` (docs/reliability.md shows it; a test keeps them in sync).

The checks that need to know what the user *wrote* (a key given, not its default) run on the file's own table
(:func:`check_written`, from :func:`~vvea_design.spring.requirements.load_requirements`): a design file's ``spec``
holds every field, defaults included, and is not judged by them. The checks on values alone
(:func:`check_values`) run on every :class:`~vvea_design.spring.requirements.Requirements`.
"""

from __future__ import annotations

import warnings
from collections.abc import Callable, Mapping
from typing import Any

from ..messages import show

#: The requirements (:class:`~vvea_design.spring.requirements.Requirements`, which calls these checks: not imported
#: here, so the two modules form no cycle).
Requirements = Any

__all__ = ["CONTRADICTIONS", "SettingsNote", "check_written", "check_values", "check_optimiser_options",
           "check_pareto_settings"]


class SettingsNote(UserWarning):
    """Settings that hold together but are easily misread (printed as ``note: ...``)."""


#: key -> (the settings, what the toolkit does: ``refused`` or ``note``, why). Shown in docs/reliability.md.
CONTRADICTIONS: dict[str, tuple[str, str, str]] = {
    "objective_twice": ("`objective` other than nominal and `objective_n`", "refused",
                        "both choose the exponents the objective evaluates; `objective_n` would win silently"),
    "objective_vs_n": ("`objective` isothermal/adiabatic/worst and `n_polytropic` not among its exponents", "note",
                       "the objective minimises the linearity at its own exponents; `n_polytropic` sets only the "
                       "stiffness, the setpoint and the walls"),
    "cast_fill_bounds": ("`[bounds] bladder_cast_fill` without `optimise_cast_fill = true`", "refused",
                         "the cast fill is not searched: the range would be ignored"),
    "cast_fill_fixed": ("`optimise_cast_fill = true` and `[fixed] bladder_cast_fill`", "refused",
                        "the search chooses the cast fill: the fixed value would be ignored "
                        "(give `[bounds] bladder_cast_fill` instead)"),
    "bounds_other_layout": ("`[bounds]` of a variable no layout in `layouts` has", "refused",
                            "the range would be ignored"),
    "listed_twice": ("a layout or joint listed twice in `layouts` / `joints`", "refused",
                     "the same search would run twice"),
    "gas_only_joints": ("`joints` or `max_parasitic_damping_N_s_per_mm` with `[fixed] sizing_rules = \"gas_only\"`",
                        "refused", "the gas-only rules have no joints and no damper: the setting would be ignored"),
    "piston_vs_rod": ("`[bounds] piston_diameter_mm` high end at or below `[fixed] rod_diameter_mm`", "refused",
                      "no piston in the range holds the rod"),
    "dead_volume_vs_gas": ("`[fixed] dead_volume_1_mm3` / `dead_volume_2_mm3` at or above the high end of the "
                           "`V1_mm3` / `V2_mm3` search range (`[bounds]`, else the gas the envelope's bore holds)",
                           "refused", "each chamber's gas includes its ports' dead volume: no gas volume in the range "
                           "holds it"),
    "piston_vs_outer": ("`[bounds] piston_diameter_mm` low end plus two `min_outer_wall_mm` at or above the outer "
                        "diameter's high end (`[bounds] outer_diameter_mm`, `max_outer_diameter_mm`)", "exit 3",
                        "the search finds no buildable design inside the bounds and names them and why "
                        "(no room for the bladder)"),
    "linearity_target_on_objective": ("`max_linearity_adiabatic` with an objective that evaluates n = 1.4",
                                      "accepted", "a limit on the objective itself: met, or exit 3 naming it"),
    "narrower_bounds": ("`[bounds] outer_diameter_mm` high end below `max_outer_diameter_mm` (any range narrower than "
                        "the default)", "accepted", "the user's own search range; an optimum on it is reported as a "
                        "binding bound"),
    "seeded_steps": ("`--seed` of `optimise`, `design`, `pareto`, `diagnose`", "accepted",
                     "each seeds a random step (the global search's population, the held-out splits): no seed is "
                     "ignored"),
    "pareto_one_value": ("`vvea pareto` with one value", "note", "a front of one point is one optimisation"),
    "pareto_repeated": ("`vvea pareto` with a value given twice", "refused", "the same optimisation twice"),
    "pareto_replaces": ("`vvea pareto --axis mass` or `adiabatic` with `max_mass_g` / `max_linearity_adiabatic` set in "
                        "the requirements", "note", "the swept values replace the file's limit"),
    "pareto_widens": ("`vvea pareto --axis outer_diameter` with `[bounds] outer_diameter_mm`", "note",
                      "each swept envelope widens the pinned range to reach it"),
    "pareto_on_objective": ("`vvea pareto --axis adiabatic` with an objective that evaluates n = 1.4", "note",
                            "the swept limit bounds the objective itself: the front is flat where the limit is "
                            "met, infeasible below"),
    "optimiser_numbers": ("`optimise(popsize=, maxiter=, tol=)` below 1, below 1, negative or not finite", "refused",
                          "no search runs (maxiter = 0 returns the random first population)"),
    "polish_off_strain": ("`optimise(polish=False)` with `max_bladder_strain`", "note",
                          "only the polish enforces the FE strain bound; the global search uses the surrogate"),
}


def _refuse(error: type[Exception], source: str, msg: str) -> None:
    raise error(f"{source + ': ' if source else ''}{msg}")


def _note(source: str, msg: str) -> None:
    warnings.warn(f"{source + ': ' if source else ''}{msg}", SettingsNote, stacklevel=3)


def check_written(req: Requirements, data: Mapping[str, Any], source: str, error: type[Exception]) -> None:
    """Refuse the settings a requirements file *wrote* that contradict each other (:data:`CONTRADICTIONS`).

    Parameters
    ----------
    req : Requirements
        The requirements built from ``data`` (already validated field by field).
    data : mapping
        The file's own table (its keys: what the user wrote).
    source : str
        The file, put in front of every message.
    error : type of Exception
        Raised for a contradiction (:class:`~vvea_design.spring.requirements.SpecError`).
    """
    fixed = data.get("fixed") if isinstance(data.get("fixed"), Mapping) else {}
    bounds = data.get("bounds") if isinstance(data.get("bounds"), Mapping) else {}
    if "objective_n" in data and data.get("objective", "nominal") != "nominal":
        _refuse(error, source, f"objective = {show(data['objective'])} and objective_n = {show(data['objective_n'])} "
                "both choose the exponents whose linearity is minimised (objective_n would win without a word); "
                "give one of them")
    if "bladder_cast_fill" in bounds and not req.optimise_cast_fill:
        _refuse(error, source, f"[bounds] bladder_cast_fill = {show(list(bounds['bladder_cast_fill']))} is a search "
                "range, but optimise_cast_fill is false: the cast fill is not searched and the range would be "
                "ignored; set optimise_cast_fill = true, or give the fill as [fixed] bladder_cast_fill")
    if req.optimise_cast_fill and "bladder_cast_fill" in fixed:
        _refuse(error, source, f"[fixed] bladder_cast_fill = {show(fixed['bladder_cast_fill'])} and optimise_cast_fill "
                "= true: the search chooses the cast fill, the fixed value would be ignored; give its range as "
                "[bounds] bladder_cast_fill = [low, high], or set optimise_cast_fill = false")
    for name in ("layouts", "joints"):
        given = data.get(name)
        if isinstance(given, (list, tuple)) and len(set(given)) < len(given):
            twice = sorted({v for v in given if list(given).count(v) > 1})
            _refuse(error, source, f"{name} = {show(list(given))} lists {show(twice)} twice: the same search would "
                    "run twice; list each once")
    if not req.buildable:
        ignored = [k for k in ("joints", "max_parasitic_damping_N_s_per_mm") if data.get(k) is not None]
        if ignored:
            _refuse(error, source, f"{' and '.join(ignored)} given with [fixed] sizing_rules = "
                    f"{show(req.fixed.sizing_rules)}: those rules have no joints and no damper, so "
                    f"{'they' if len(ignored) > 1 else 'it'} would be ignored; remove {' and '.join(ignored)} or use "
                    "sizing_rules = \"buildable\"")
    _bounds_of_other_layouts(req, bounds, source, error)
    if "objective" in data and "n_polytropic" in data and req.objective != "nominal" and req.objective_n is None \
            and req.n_polytropic not in req.objective_exponents:
        _note(source, f"objective = {show(req.objective)} minimises the linearity at n = "
              f"{show(list(req.objective_exponents))}; n_polytropic = {show(req.n_polytropic)} sets only the "
              "stiffness, the setpoint and the walls (use objective = \"nominal\" to minimise it at n_polytropic)")


def _bounds_of_other_layouts(req: Requirements, bounds: Mapping[str, Any], source: str,
                             error: type[Exception]) -> None:
    """Refuse a ``[bounds]`` variable that none of the chosen layouts searches."""
    from .layouts import get_layout

    searched = {v for lay in req.layouts for v in get_layout(lay).decision_variables} | {"bladder_cast_fill"}
    other = sorted(set(bounds) - searched)
    if other:
        owners = {name: [lay for lay in _all_layouts() if name in get_layout(lay).decision_variables]
                  for name in other}
        _refuse(error, source, f"[bounds] {', '.join(other)}: "
                + "; ".join(f"{n} belongs to layout(s) {show(o)}" for n, o in owners.items())
                + f", not among layouts = {show(list(req.layouts))}: the range would be ignored; add the layout or "
                "remove the range")


def _all_layouts() -> list[str]:
    from .layouts import LAYOUTS

    return list(LAYOUTS)


def check_values(req: Requirements, error: type[Exception]) -> None:
    """Refuse search ranges that no design can satisfy against the fixed parts (whatever wrote them).

    Parameters
    ----------
    req : Requirements
        The requirements (their explicit ``[bounds]``, ``[fixed]`` and envelope).
    error : type of Exception
        Raised naming the fields (:class:`~vvea_design.spring.requirements.SpecError`).
    """
    b, f = req.resolved_bounds, req.fixed
    p_lo, p_hi = b["piston_diameter_mm"]
    if p_hi <= f.rod_diameter_mm:
        src = "[bounds] piston_diameter_mm" if "piston_diameter_mm" in req.bounds else "the default piston range"
        _refuse(error, "", f"{src} = {show([p_lo, p_hi])} mm: its high end is at or below [fixed] rod_diameter_mm = "
                f"{show(f.rod_diameter_mm)} mm, so no piston in the range holds the rod; the high end must exceed "
                f"{show(f.rod_diameter_mm)} mm (or use a thinner rod)")
    for chamber in ("1", "2"):
        dead, (v_lo, v_hi) = getattr(f, f"dead_volume_{chamber}_mm3"), b[f"V{chamber}_mm3"]
        if dead >= v_hi:
            src = (f"[bounds] V{chamber}_mm3" if f"V{chamber}_mm3" in req.bounds
                   else f"the default V{chamber}_mm3 range (it follows the envelope)")
            _refuse(error, "", f"[fixed] dead_volume_{chamber}_mm3 = {show(dead)} mm³ is at or above the high end of "
                    f"{src} = {show([v_lo, v_hi])} mm³: chamber {chamber}'s gas includes its ports' dead volume, so "
                    f"no V{chamber}_mm3 in the range holds it; give the ports' volume in mm³ (below "
                    f"{show(v_hi)} mm³) or widen the range or the envelope")


def check_optimiser_options(popsize: Any, maxiter: Any, tol: Any, polish: bool, strain_limit: float | None,
                            error: Callable[[str], Exception] = ValueError) -> None:
    """Refuse optimiser numbers with which no search runs; note a polish turned off under a strain limit.

    Parameters
    ----------
    popsize, maxiter : int
        Differential evolution's population factor and generation limit (each >= 1).
    tol : float
        Its relative convergence tolerance, dimensionless (finite, >= 0).
    polish : bool
        Whether the SLSQP polish runs.
    strain_limit : float or None
        The requirements' ``max_bladder_strain`` (fraction).
    error : callable
        Builds the exception raised (``ValueError``).
    """
    import math
    import numbers

    for name, v in (("popsize", popsize), ("maxiter", maxiter)):
        if isinstance(v, bool) or not isinstance(v, numbers.Integral) or v < 1:
            raise error(f"{name} must be a whole number >= 1, got {show(v)} (with {name} = 0 no search runs: "
                        "the result would be a random point)")
    if isinstance(tol, bool) or not isinstance(tol, (int, float)) or not math.isfinite(tol) or tol < 0:
        raise error(f"tol must be a finite number >= 0, got {show(tol)}")
    if not polish and strain_limit is not None:
        _note("", f"polish=False with max_bladder_strain = {show(strain_limit)}: only the polish holds the FE strain "
              "bound; the global search uses its surrogate, so the design's FE strain is not guaranteed")


def check_pareto_settings(req: Requirements, axis: str, values: list) -> None:
    """Refuse a Pareto sweep that repeats a value; note one value, a replaced limit, a widened range.

    Parameters
    ----------
    req : Requirements
        The requirements held fixed.
    axis : str
        The swept requirement (``stiffness``, ``outer_diameter``, ``mass``, ``adiabatic``).
    values : list
        Its values, in the axis' unit (N/mm, mm, g, fraction).

    Raises
    ------
    ValueError
        A value given twice (names both positions).
    """
    seen: dict[Any, int] = {}
    for i, v in enumerate(values):
        if v in seen:
            raise ValueError(f"values[{i}] = {show(v)} repeats values[{seen[v]}]: the same optimisation would run "
                             "twice; give each value once")
        seen[v] = i
    if len(values) == 1:
        _note("", f"a Pareto front of one value ({show(values[0])}) is one optimisation: give several values to see "
              "the trade-off (or use vvea optimise)")
    replaced = {"mass": "max_mass_g", "adiabatic": "max_linearity_adiabatic"}.get(axis)
    if replaced and getattr(req, replaced) is not None:
        _note("", f"the requirements' {replaced} = {show(getattr(req, replaced))} is replaced by each swept value "
              f"(--axis {axis})")
    if axis == "outer_diameter" and "outer_diameter_mm" in req.bounds:
        _note("", f"[bounds] outer_diameter_mm = {show(list(req.bounds['outer_diameter_mm']))} is widened to reach "
              "each swept envelope")
    if axis == "adiabatic" and 1.4 in req.objective_exponents:
        _note("", f"the objective already minimises the linearity at n = 1.4 ({show(req.objective)}): the swept "
              "limit bounds the objective itself, so the front is flat where it is met and infeasible below")
