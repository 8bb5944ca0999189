"""The linearity optimiser: a vectorised global search per layout variant + a gradient polish.

Objective: the exact linearity error (:func:`vvea_design.spring.gas_spring.linearity_exact`)
at the highest allowed charge, worst over the requirements' polytropic
exponents (``objective``: nominal, isothermal, adiabatic or worst of both).
Constraints: every margin of :func:`vvea_design.spring.requirements.evaluate_design`
>= 0. Search, for each layout in ``req.layouts``: scipy's
``differential_evolution`` over the layout's decision variables, the whole
population evaluated in one numpy call (:func:`~vvea_design.spring.requirements.evaluate_population`),
constraints by its feasibility rules (Lampinen), seeded; then an SLSQP polish.
The best layout wins. With ``max_bladder_strain`` the global search uses a
cheap surrogate of the FE strain bound (:mod:`vvea_design.spring.strain_surrogate`)
and the FE itself corrects it in the polish and checks the final design.
When no feasible design exists the least-violating design is returned with the
violated constraints named (:class:`Infeasible`).

Also here: Pareto fronts (linearity against stiffness, outer diameter or
mass; one optimisation per point through :func:`vvea_design.parallel.parallel_map`)
and 2-D linearity maps over any two decision variables.
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass, replace
from typing import Callable, Literal

import numpy as np
from scipy.optimize import NonlinearConstraint, differential_evolution, minimize

from .design import LAYOUTS, Design, DesignError, get_layout
from ..parallel import parallel_map
from ..progress import progress_bar
from .requirements import (
    Evaluation,
    Requirements,
    constraint_names,
    design_from_vector,
    evaluate_design,
    evaluate_population,
)

__all__ = [
    "OptimisationResult",
    "LayoutSearch",
    "Infeasible",
    "NoBuildableDesign",
    "optimise",
    "pareto_front",
    "linearity_map",
    "PARETO_AXES",
    "gas_volume_bound",
    "gas_capacity",
    "save_pareto",
]


class Infeasible(RuntimeError):
    """No design meets the requirements; ``result`` holds the least-violating one."""

    def __init__(self, result: "OptimisationResult"):
        self.result = result
        super().__init__(result.infeasibility_message())


class NoBuildableDesign(ValueError):
    """No point inside the search bounds can even be drawn; the message names why and the bounds."""


def _unbuildable_message(req: Requirements, x, layout: str, layouts, reason: Exception) -> str:
    names = req.decision_variables(layout)
    point = ", ".join(f"{n} = {float(v):.4g}" for n, v in zip(names, x))
    box = ", ".join(f"{n} in [{lo:.4g}, {hi:.4g}]" for n, (lo, hi) in zip(names, req.search_bounds(layout)))
    tried = f" (layouts tried: {', '.join(layouts)})" if len(layouts) > 1 else ""
    return (f"the search found no buildable design inside the search bounds{tried}: {box}; outer_diameter_mm is capped at "
            f"max_outer_diameter_mm = {req.max_outer_diameter_mm:.4g}. The best point found ({layout} layout: "
            f"{point}) cannot be drawn: {reason}; widen [bounds] or the envelope in the requirements file")


@dataclass(frozen=True)
class LayoutSearch:
    """The global search of one layout variant."""

    layout: str
    objective: float  #: best objective found (fraction; 1.0 = nothing buildable)
    feasible: bool
    evaluations: int
    generations: int
    seconds: float
    message: str
    decision_vector: tuple[float, ...]
    worst_margin: float  #: smallest constraint margin of its best design

    def to_dict(self) -> dict:
        """JSON-ready content of this search.

        Returns
        -------
        dict
            Every field; ``decision_vector`` as a list (the decision variables in their
            own units, mm and mm³), ``seconds`` in s, ``objective`` a fraction.
        """
        return {**self.__dict__, "decision_vector": list(self.decision_vector)}


@dataclass(frozen=True)
class OptimisationResult:
    """What :func:`optimise` found: the evaluated best design and how it was found."""

    evaluation: Evaluation  #: the best design found, evaluated (with the FE strain when constrained)
    seed: int
    evaluations: int  #: model evaluations over all layouts and the polish
    seconds: float
    generations: int
    de_message: str
    polished: bool  #: the SLSQP polish improved the global result
    searches: tuple[LayoutSearch, ...] = ()  #: one per layout variant tried
    bladder_strain_fe: float | None = None  #: FE strain bound of the final design (when constrained)
    bladder_strain_surrogate: float | None = None  #: the surrogate's value at the final design

    @property
    def design(self) -> Design:
        """The best design found (geometry in mm, mm³; charge in MPa)."""
        return self.evaluation.design

    @property
    def layout(self) -> str:
        """Name of the winning layout variant."""
        return self.design.layout

    @property
    def evaluations_per_second(self) -> float:
        """Model evaluations per second of wall time (1/s); nan when no time was measured."""
        return self.evaluations / self.seconds if self.seconds > 0 else float("nan")

    def infeasibility_message(self) -> str:
        """What the least-violating design misses, for the user.

        Returns
        -------
        str
            One line per violated constraint, worst first: its value and limit with their unit
            and the (scaled, dimensionless) margin.
        """
        ev = self.evaluation
        lines = [f"no design meets the requirements; the least-violating design found "
                 f"(layout {ev.design.layout!r}) misses:"]
        for name, m in sorted(ev.margins.items(), key=lambda kv: kv[1]):
            if m < -1e-9:
                d = ev.details[name]
                rel = "<=" if d["kind"] == "max" else ">="
                lines.append(
                    f"  - {name}: {float(d['value']):.4g} {d['unit']} (required {rel} {float(d['limit']):.4g} {d['unit']}; "
                    f"margin {m:+.3f})"
                )
        return "\n".join(lines)

    def summary(self) -> dict:
        """The ``optimiser`` block of the design JSON.

        Returns
        -------
        dict
            Seed, evaluation count, ``seconds`` (s), evaluations per second (1/s), generations,
            the search's message, whether the polish improved it, the layout, the binding
            constraints, one entry per layout search and the FE / surrogate bladder strain
            (fraction, None when unconstrained).
        """
        return {
            "seed": self.seed,
            "evaluations": self.evaluations,
            "seconds": self.seconds,
            "evaluations_per_second": self.evaluations_per_second,
            "generations": self.generations,
            "message": self.de_message,
            "polished": self.polished,
            "layout": self.layout,
            "binding_constraints": self.evaluation.binding(),
            "searches": [s.to_dict() for s in self.searches],
            "bladder_strain_fe": self.bladder_strain_fe,
            "bladder_strain_surrogate": self.bladder_strain_surrogate,
        }

    def to_dict(self) -> dict:
        """Everything as plain JSON-able data (the design, its evaluation, the search).

        Returns
        -------
        dict
            ``layout``, ``decision_variables`` (name -> value, unit in the name), the evaluation's
            content (:meth:`Evaluation.to_dict`) and ``optimiser`` (:meth:`summary`).
        """
        d = self.design
        return {"layout": d.layout,
                "decision_variables": {n: float(getattr(d, n)) for n in d.variant.decision_variables},
                **self.evaluation.to_dict(), "optimiser": self.summary()}


class _RowMemo:
    """Results of a vectorised function of designs, remembered per design (by its decision vector's bytes).

    ``fn(XS)`` maps designs ``(S, N)`` to a tuple of arrays whose last axis runs over the designs
    (``(S,)`` or ``(M, S)``); only designs not seen before are passed to it. Differential evolution
    asks for the constraints of a whole population and then for the objective of its feasible
    members (and for the best member's constraints once per generation); the polish re-reads its
    last point. Each design's values must not depend on which others share its call (true of the
    elementwise formulas here, not of a matrix product whose rounding may change with the batch).
    """

    def __init__(self, fn):
        self.fn = fn
        self.memo: dict[bytes, np.ndarray] = {}  # design -> its values of every output, stacked
        self.shapes: tuple | None = None  # leading shapes of the outputs
        self.widths: tuple = ()  # values per design of each output (the products of shapes)

    def __call__(self, XS: np.ndarray) -> tuple:
        memo = self.memo
        keys = [row.tobytes() for row in XS]
        new: dict[bytes, int] = {}
        for i, k in enumerate(keys):
            if k not in memo and k not in new:
                new[k] = i
        if new:
            idx = list(new.values())
            out = self.fn(XS[idx] if len(idx) < len(keys) else XS)
            self.shapes = tuple(np.shape(o)[:-1] for o in out)
            self.widths = tuple(math.prod(sh) for sh in self.shapes)
            stacked = np.vstack([np.reshape(o, (-1, len(idx))) for o in out]).T  # copies: the same values
            memo.update(zip(new, stacked))
        if self.shapes is None:  # nothing evaluated yet and an empty population: let fn say its shapes
            return self.fn(XS)
        rows = np.array([memo[k] for k in keys], dtype=float).reshape(len(keys), sum(self.widths))
        res, at = [], 0
        for sh, m in zip(self.shapes, self.widths):
            block = rows[:, at:at + m]
            res.append(block.T.reshape(sh + (len(keys),)) if sh else block[:, 0].copy())
            at += m
        return tuple(res)


class _Population:
    """Vectorised objective and constraints of one layout, sharing one evaluation per population.

    Designs seen before are not evaluated again (:class:`_RowMemo`; not with a strain surrogate,
    whose matrix product may round differently with the batch: those populations are evaluated as
    asked). ``count`` counts every design asked for.
    """

    def __init__(self, req: Requirements, layout: str, strain_fn=None):
        self.req, self.layout, self.strain_fn = req, layout, strain_fn
        self.count = 0
        self._key: bytes | None = None
        self._count_key: bytes | None = None
        self._val = None
        self._eval = self._evaluate
        self._objmemo: dict[bytes, float] | None = None
        if strain_fn is None or req.max_bladder_strain is None:
            self._eval = _RowMemo(self._evaluate)
        else:  # the objective (the linearity) does not involve the surrogate: only it is remembered
            self._objmemo = {}

    def _evaluate(self, XS: np.ndarray, remember: bool = True):
        obj, mar, _, ext = evaluate_population(XS, self.req, self.layout, self.strain_fn, extremes=True)
        if remember and self._objmemo is not None:
            self._objmemo.update(zip([row.tobytes() for row in XS], obj))
        return obj, mar, ext

    def _remembered_objective(self, X):
        """The objective of designs all evaluated before (with a strain surrogate), else None."""
        X = np.asarray(X, dtype=float)
        key = X.tobytes()
        if self._objmemo is None or key == self._key:
            return None
        XS = X.T if X.ndim == 2 else X[None, :]
        try:
            obj = np.array([self._objmemo[row.tobytes()] for row in XS], dtype=float)
        except KeyError:
            return None
        self._counted(key, XS.shape[0])
        return obj

    def _counted(self, key: bytes, n: int) -> None:
        # the count of designs asked for, as when every call evaluated all of them unless it repeated the last call
        if key != self._count_key:
            self.count += n
            self._count_key = key

    def __call__(self, X, extremes: bool = False, remember: bool = True):
        """Objective ``(S,)``, margins ``(M, S)`` (and the extremes) of the designs ``X`` ``(N, S)`` or ``(N,)``;
        ``remember=False``: designs unlikely to be asked for again (the polish's gradient points) are evaluated
        without being remembered (the same values)."""
        X = np.asarray(X, dtype=float)
        key = X.tobytes()
        XS = X.T if X.ndim == 2 else X[None, :]
        self._counted(key, XS.shape[0])
        if key != self._key:
            self._key, self._val = key, (self._eval(XS) if remember else self._evaluate(XS, remember=False))
        return self._val if extremes else self._val[:2]

    def objective(self, X):
        obj = self._remembered_objective(X)
        if obj is None:
            obj = self(X)[0]
        return obj if np.asarray(X).ndim == 2 else float(obj[0])

    def constraints(self, X):
        mar = self(X)[1]
        return mar if np.asarray(X).ndim == 2 else mar[:, 0]


def _search(req: Requirements, layout: str, seed: int, popsize: int, maxiter: int, tol: float,
            strain_fn, advance, n_starts: int = 8) -> tuple[np.ndarray, LayoutSearch, "_Population"]:
    prob = _Population(req, layout, strain_fn)
    bounds = req.search_bounds(layout)
    t0 = time.perf_counter()
    gens = 0

    def _cb(*_args, **_kw):
        nonlocal gens
        gens += 1
        advance()

    de = differential_evolution(
        prob.objective, bounds,
        constraints=[NonlinearConstraint(prob.constraints, 0.0, np.inf)],
        seed=seed, popsize=popsize, maxiter=maxiter, tol=tol, atol=0.0,
        mutation=(0.5, 1.0), recombination=0.7, init="sobol", polish=False,
        vectorized=True, updating="deferred", callback=_cb,
    )
    advance(maxiter - gens)
    x = np.asarray(de.x, dtype=float)
    prob.starts = _starts(prob, de, bounds, n_starts)
    obj, mar = prob(x)
    return x, LayoutSearch(layout, float(obj[0]), bool(np.all(mar[:, 0] >= -1e-9)), prob.count, gens,
                           time.perf_counter() - t0, str(de.message), tuple(float(v) for v in x),
                           float(mar[:, 0].min())), prob


def _starts(prob, de, bounds, n_starts: int) -> list[np.ndarray]:
    """The best point of a differential-evolution run and the best distinct members of its final
    population (feasible first, then by objective), as starts for the polish."""
    x = np.asarray(de.x, dtype=float)
    starts = [x]
    pop = getattr(de, "population", None)
    if pop is not None and len(pop):
        span = np.array([b[1] - b[0] for b in bounds])
        obj_p, mar_p = prob(pop.T)
        viol = np.clip(-mar_p, 0, None).sum(axis=0)
        for k in np.lexsort((obj_p, viol)):
            cand = pop[k]
            if all(np.abs((cand - s_) / span).max() > 0.05 for s_ in starts):
                starts.append(cand)
            if len(starts) >= n_starts:
                break
    return starts


def _best_polish(prob, starts, bounds) -> tuple[np.ndarray, bool]:
    """Polish from every start; the best feasible result (or the first start)."""
    x, best, polished = starts[0], np.inf, False
    if np.all(prob.constraints(x) >= -1e-9):
        best = prob.objective(x)
    for start in starts:
        xs, ok = _polish(prob, start, bounds)
        fs = prob.objective(xs)
        if np.all(prob.constraints(xs) >= -1e-9) and fs < best:
            x, best, polished = xs, fs, True
    return x, polished


def optimise(
    req: Requirements | None = None,
    *,
    seed: int = 0,
    popsize: int = 10,
    maxiter: int = 60,
    tol: float = 1e-5,
    polish: bool = True,
    progress: bool = True,
    bladder_strain_fn: Callable[[Design], float] | None = None,
    raise_infeasible: bool = True,
    layouts: tuple[str, ...] | None = None,
) -> OptimisationResult:
    """Find the most linear design that meets ``req``, choosing between its layout variants.

    Parameters
    ----------
    req : Requirements or None
        Requirements (default: the paper's unit).
    seed : int
        Seed of the global search: the same seed gives the same design.
    popsize, maxiter : int
        Differential-evolution population factor (population = popsize × number of variables)
        and generation limit.
    tol : float
        Differential-evolution convergence tolerance, relative, dimensionless.
    polish : bool
        Run an SLSQP polish from the best point of each layout.
    progress : bool
        Show a progress bar on stderr (one step per generation and layout).
    bladder_strain_fn : callable or None
        ``f(design) -> strain`` (fraction), the FE strain bound (e.g.
        :func:`vvea_design.bladder.check.strain_bound`), required when
        ``req.max_bladder_strain`` is set. The global search uses the
        surrogate of :mod:`vvea_design.spring.strain_surrogate`; the polish
        corrects it with this function until the final design meets the
        limit by this function's own value.
    raise_infeasible : bool
        Raise :class:`Infeasible` (with the violated constraints) when no
        feasible design is found; otherwise return the least-violating one.
    layouts : tuple of str or None
        Layout variants to search (default ``req.layouts``).

    Returns
    -------
    OptimisationResult
        The evaluated best design, per-layout searches, counts and seconds.

    Raises
    ------
    ValueError
        If ``req.max_bladder_strain`` is set without ``bladder_strain_fn``.
    DesignError
        If a layout name is unknown (the message lists the known ones).
    NoBuildableDesign
        If no point the search tried inside the bounds can be drawn (the message names the bounds).
    Infeasible
        If no design meets the requirements and ``raise_infeasible`` is true.
    """
    req = req or Requirements()
    if req.max_bladder_strain is not None and bladder_strain_fn is None:
        raise ValueError("max_bladder_strain is set: pass bladder_strain_fn (e.g. vvea_design.bladder.check.strain_bound)")
    layouts = tuple(layouts or req.layouts)
    for lay in layouts:
        get_layout(lay)
    surrogate = None
    if req.max_bladder_strain is not None:
        from .strain_surrogate import population_strain

        surrogate = population_strain
    t0 = time.perf_counter()
    found = []
    with progress_bar("optimising linearity", total=maxiter * len(layouts), enabled=progress) as advance:
        for lay in layouts:
            x, info, prob = _search(req, lay, seed, popsize, maxiter, tol, surrogate, advance)
            polished = False
            if polish:
                x, polished = _best_polish(prob, prob.starts, req.search_bounds(lay))
                mar = prob.constraints(x)
                info = replace(info, objective=float(prob.objective(x)), feasible=bool(np.all(mar >= -1e-9)),
                               decision_vector=tuple(float(v) for v in x), worst_margin=float(mar.min()),
                               evaluations=prob.count)
            found.append((lay, x, info, prob, polished))
    # best layout: feasible first, then the lowest objective (or the least violation)
    def rank(item):
        lay, x, info, prob, _ = item
        obj, mar = prob(x)
        worst = float(mar[:, 0].min())
        return (0, float(obj[0])) if worst >= -1e-9 else (1, -worst)

    found.sort(key=rank)
    lay, best_x, info, prob, polished = found[0]
    try:  # every point the search tried may be unbuildable: name why and the bounds (issue 11 item 8)
        design_from_vector(best_x, req, lay)
    except DesignError as exc:
        raise NoBuildableDesign(_unbuildable_message(req, best_x, lay, layouts, exc)) from None
    strain_fe = strain_sur = None
    if req.max_bladder_strain is not None:
        best_x, strain_fe, strain_sur, extra = _fe_correct(req, lay, best_x, bladder_strain_fn, prob)
        polished = polished or extra
    design = design_from_vector(best_x, req, lay)
    ev = evaluate_design(design, req, bladder_strain=strain_fe)
    seconds = time.perf_counter() - t0
    searches = tuple(item[2] for item in sorted(found, key=lambda it: layouts.index(it[0])))
    result = OptimisationResult(ev, seed, sum(item[3].count for item in found), seconds,
                                sum(s.generations for s in searches), info.message, polished, searches,
                                strain_fe, strain_sur)
    if raise_infeasible and not ev.feasible:
        raise Infeasible(result)
    return result


def _polish(prob, x0: np.ndarray, bounds) -> tuple[np.ndarray, bool]:
    """SLSQP from ``x0`` in scaled variables; keep the result only if feasible and better.

    The objective is a maximum of deviations whose location jumps (an end of
    the travel, an interior extremum) — kinks exactly where the optimum sits.
    So the polish works on its epigraph: minimise ``t`` subject to
    ``t >= ±(signed deviation)/span`` at each place, smooth constraints, and
    the requirements' margins. Gradients by forward differences, all points
    of one gradient evaluated as one population.
    """
    lo = np.array([b[0] for b in bounds])
    hi = np.array([b[1] for b in bounds])
    span = hi - lo
    N = len(bounds)
    h = 1e-7
    epi = isinstance(prob, _Population)

    def unscale(z):
        return lo + np.asarray(z) * span

    cache: dict[bytes, tuple] = {}

    def evalz(z):
        z = np.clip(np.asarray(z, dtype=float), 0.0, 1.0)
        key = z.tobytes()
        if key not in cache:
            step = np.where(z + h <= 1.0, h, -h)
            Z = np.vstack([z, z + np.diag(step)])
            if epi:
                obj, mar, ext = prob(unscale(Z).T, extremes=True, remember=False)
                cons = np.vstack([mar, ext, -ext])  # margins >= 0; t - ext >= 0; t + ext >= 0 (t added below)
            else:
                obj, mar = prob(unscale(Z).T)
                cons = mar
            cache.clear()
            cache[key] = (obj[0], cons[:, 0], (obj[1:] - obj[0]) / step, (cons[:, 1:] - cons[:, :1]) / step,
                          mar.shape[0])
        return cache[key]

    x0 = np.asarray(x0, dtype=float)
    f0, c0 = prob.objective(x0), prob.constraints(x0)
    z0 = (x0 - lo) / span
    if epi:
        m = evalz(z0)[4]

        def fun(w):
            return w[-1]

        def jac(w):
            g = np.zeros_like(w)
            g[-1] = 1.0
            return g

        def cfun(w):
            c = evalz(w[:-1])[1].copy()
            c[m:] += w[-1]
            return c

        def cjac(w):
            J = evalz(w[:-1])[3]
            tcol = np.zeros((J.shape[0], 1))
            tcol[m:] = 1.0
            return np.hstack([J, tcol])

        res = minimize(fun, np.append(z0, f0 if np.isfinite(f0) else 1.0), jac=jac, method="SLSQP",
                       bounds=[(0.0, 1.0)] * N + [(0.0, 1.0)],
                       constraints=[{"type": "ineq", "fun": cfun, "jac": cjac}],
                       options={"maxiter": 300, "ftol": 1e-12})
        z1 = res.x[:-1]
    else:
        res = minimize(lambda z: evalz(z)[0], z0, jac=lambda z: evalz(z)[2], method="SLSQP",
                       bounds=[(0.0, 1.0)] * N,
                       constraints=[{"type": "ineq", "fun": lambda z: evalz(z)[1], "jac": lambda z: evalz(z)[3]}],
                       options={"maxiter": 200, "ftol": 1e-12})
        z1 = res.x
    x1 = np.clip(unscale(z1), lo, hi)
    f1, c1 = prob.objective(x1), prob.constraints(x1)
    feasible0 = bool(np.all(c0 >= -1e-9))
    if np.all(c1 >= -1e-9) and (f1 < f0 or not feasible0):
        return x1, True
    return x0, False


def _fe_correct(req: Requirements, layout: str, x: np.ndarray, fe_fn, prob: _Population, rounds: int = 6):
    """Make the FE strain bound, not the surrogate, meet ``req.max_bladder_strain`` — and no more.

    The surrogate is scaled by FE / surrogate at the current design and the
    polish re-run with that corrected surrogate from there; repeated until the
    FE value at the polished design is within 0.3 % below the limit (a fixed
    point of the correction, a few FE checks in all). The best design whose
    FE value meets the limit is kept.
    """
    from .strain_surrogate import population_strain

    limit = req.max_bladder_strain
    improved = False
    best = None  # (objective, x, fe, sur)
    fe = sur = None
    # with a free cast fill the surrogate's error changes along the fill (it is poorest at low fills): the
    # correction is then a line in the fill through the FE / surrogate ratios seen so far
    i_fill = req.decision_variables(layout).index("bladder_cast_fill") if req.optimise_cast_fill else None
    seen: list[tuple[float, float]] = []  # (fill, log(FE / surrogate))
    for _ in range(rounds):
        design = design_from_vector(x, req, layout)
        fe = float(fe_fn(design))
        sur = float(np.ravel(population_strain(*_g_cols(x, req, layout)))[0])
        if fe <= limit * (1 + 1e-9):
            obj = float(evaluate_design(design, req, bladder_strain=fe).objective)
            if best is None or obj < best[0]:
                best = (obj, x, fe, sur)
            if fe >= limit * (1 - 0.003):
                break
        factor = fe / sur if (np.isfinite(fe) and sur > 0) else 1.2
        slope = 0.0
        if i_fill is not None and np.isfinite(fe) and sur > 0:
            seen.append((float(x[i_fill]), float(np.log(factor))))
            pts = np.array(seen[-3:])
            if len(pts) >= 2 and np.ptp(pts[:, 0]) > 1e-3:
                slope, icpt = np.polyfit(pts[:, 0], pts[:, 1], 1)
                factor = float(np.exp(icpt + slope * x[i_fill]))

        def corrected(g, cols, f=factor, k=slope, x_fill=(float(x[i_fill]) if i_fill is not None else 0.0)):
            if k == 0.0:
                return f * population_strain(g, cols)
            return f * np.exp(k * (np.asarray(cols["bladder_cast_fill"]) - x_fill)) * population_strain(g, cols)

        corrected.reads_bladder_geometry_only = True

        p2 = _Population(req, layout, corrected)
        x_new, ok = _polish(p2, x, req.search_bounds(layout))
        prob.count += p2.count
        if not ok:
            break
        x, improved = x_new, True
    if best is None:  # never met the limit: report the last point (the caller names the violation)
        return x, fe, sur, improved
    return best[1], best[2], best[3], improved


def _g_cols(x, req, layout):
    from .design import derive

    lay = get_layout(layout)
    cols = {name: np.atleast_1d(float(v)) for name, v in zip(req.decision_variables(layout), x)}
    g = derive(cols["piston_diameter_mm"], cols["outer_diameter_mm"], cols["V1_mm3"], cols["V2_mm3"],
               cols.get("V2_top_mm3", np.zeros(1)), np.full(1, req.max_charge_MPa), req.setpoint_x0_mm,
               req.fixed, lay.has_bulkhead, cast_fill=cols.get("bladder_cast_fill"),
               V1_annulus_mm3=cols.get("V1_annulus_mm3", np.zeros(1)), top_annulus=lay.has_top_annulus)
    return g, cols


# ---------------------------------------------------------------------------
# Pareto fronts
# ---------------------------------------------------------------------------

PARETO_AXES = {
    "stiffness": ("min_mean_stiffness_N_per_mm", "mean stiffness at max charge [N/mm]"),
    "outer_diameter": ("max_outer_diameter_mm", "max outer diameter [mm]"),
    "mass": ("max_mass_g", "max mass [g]"),
    "adiabatic": ("max_linearity_adiabatic", "largest linearity error allowed at n = 1.4 [fraction]"),
}


def _pareto_point(args) -> dict:
    req, seed, popsize, maxiter = args
    try:
        r = optimise(req, seed=seed, popsize=popsize, maxiter=maxiter, progress=False, raise_infeasible=False)
    except Exception as exc:  # a point that cannot even be set up is recorded, not fatal
        return {"feasible": False, "error": str(exc)}
    ev = r.evaluation
    row = {"feasible": ev.feasible, "linearity_error": ev.linearity_error,
           "linearity_error_isothermal": ev.linearity_isothermal, "linearity_error_adiabatic": ev.linearity_adiabatic,
           "objective": ev.objective, "mass_g": ev.mass_g, "layout": ev.design.layout,
           "mean_stiffness_at_max_charge_N_per_mm": ev.details["mean_stiffness"]["value"],
           "outer_diameter_mm": ev.design.outer_diameter_mm,
           "binding": ",".join(ev.binding() if ev.feasible else [k for k, m in ev.margins.items() if m < -1e-9])}
    row.update({n: float(getattr(ev.design, n)) for n in dict.fromkeys(v for lay in LAYOUTS.values()
                                                                      for v in lay.decision_variables)})
    return row


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
) -> list[dict]:
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
    list of dict
        One row per value, in order: ``feasible``, ``linearity_error`` (fraction; also at n = 1
        and n = 1.4), ``objective``, ``mass_g``, ``layout``,
        ``mean_stiffness_at_max_charge_N_per_mm``, ``outer_diameter_mm``, ``binding`` (binding or,
        when infeasible, violated constraints, comma-separated), the decision variables (unit in
        the name) and the swept field itself. A point that cannot be set up is a row with
        ``feasible = False`` and ``error``.

    Raises
    ------
    ValueError
        If ``axis`` is not one of :data:`PARETO_AXES`.
    """
    if axis not in PARETO_AXES:
        raise ValueError(f"unknown Pareto axis {axis!r}; choose one of {sorted(PARETO_AXES)}")
    field_name = PARETO_AXES[axis][0]
    jobs = []
    for v in values:
        kw = {field_name: float(v)}
        if axis == "outer_diameter":
            b = dict(req.bounds)
            lo, hi = b.get("outer_diameter_mm", (25.0, 59.5))
            b["outer_diameter_mm"] = (min(lo, 0.5 * float(v)), max(hi, float(v)))
            kw["bounds"] = b
        jobs.append((replace(req, **kw), seed, popsize, maxiter))
    rows = parallel_map(_pareto_point, jobs, workers=workers, scheduler=scheduler,
                        description=f"Pareto front over {axis}", progress=progress)
    for v, row in zip(values, rows):
        row[field_name] = float(v)
    return rows


def save_pareto(rows: list[dict], axis: str, out_dir, title: str = "") -> tuple:
    """Write a Pareto front as ``pareto_<axis>.csv`` and ``.png`` into ``out_dir``.

    Parameters
    ----------
    rows : list of dict
        Rows of :func:`pareto_front` (the CSV gets the union of their keys as columns, units in
        the names).
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

    out_dir = Path(out_dir)
    out_dir.mkdir(parents=True, exist_ok=True)
    csv_path = out_dir / f"pareto_{axis}.csv"
    keys = sorted({k for r in rows for k in r})
    with open(csv_path, "w", newline="") as fh:
        w = csv.DictWriter(fh, fieldnames=keys)
        w.writeheader()
        w.writerows(rows)
    field, label = PARETO_AXES[axis]
    png = save_figure(plot_pareto(rows, field, label, title=title or f"best linearity vs {axis}"),
                      out_dir / f"pareto_{axis}.png")
    return csv_path, png


# ---------------------------------------------------------------------------
# 2-D maps
# ---------------------------------------------------------------------------

def linearity_map(
    design: Design,
    req: Requirements,
    var_x: str,
    var_y: str,
    *,
    x_range: tuple[float, float] | None = None,
    y_range: tuple[float, float] | None = None,
    n: int = 61,
) -> dict:
    """Linearity and feasibility over two decision variables, the others held at ``design``.

    Returns a dict with the axes (``x``, ``y``), ``linearity`` (nan where the
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
    dict
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
        raise ValueError("the two map variables must differ")
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
    return {"var_x": var_x, "var_y": var_y, "x": xs, "y": ys, "linearity": lin, "feasible": feas, "worst": worst,
            "margins": margins}


# ---------------------------------------------------------------------------
# Packing-free bound
# ---------------------------------------------------------------------------

def gas_volume_bound(total_gas_mm3: float, req: Requirements | None = None, *, seed: int = 0,
                     maxiter: int = 400, V1_max_mm3: float | None = None, V2_max_mm3: float | None = None,
                     chamber1_length_max_mm: float | None = None, V1_extra_mm3: float = 0.0) -> dict:
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
    dict
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
    return {"total_gas_mm3": float(total_gas_mm3), "linearity_error": float(obj[0]), "A1_mm2": A1, "A2_mm2": A2,
            "V1_mm3": V1, "V2_mm3": V2, "feasible": bool(np.all(cons >= -1e-6)),
            "objective_exponents": list(ns), "V1_max_mm3": V1_max_mm3, "V2_max_mm3": V2_max_mm3,
            "chamber1_length_max_mm": chamber1_length_max_mm}


# ---------------------------------------------------------------------------
# The envelope's gas capacity
# ---------------------------------------------------------------------------

def gas_capacity(req: Requirements | None = None, layout: str = "inner_tube", *, seed: int = 0,
                 maxiter: int = 200, maximise: Literal["total", "V1", "V2"] = "total") -> dict:
    """The largest gas volume ``V1 + V2`` a layout can hold in the requirements' envelope.

    Every constraint of :func:`~vvea_design.spring.requirements.evaluate_design`
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
        Layout variant (a name of :data:`vvea_design.spring.design.LAYOUTS`).
    seed : int
        Seed of the differential evolution.
    maxiter : int
        Generation limit of the differential evolution.
    maximise : {"total", "V1", "V2"}
        What to make largest: the total gas volume V1 + V2, or one chamber's (mm³ each).

    Returns
    -------
    dict
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
    return {"layout": layout, "maximise": maximise, "total_gas_mm3": d.V1_mm3 + d.V2_mm3, "V1_mm3": d.V1_mm3,
            "V2_mm3": d.V2_mm3, "bladder_cast_fill": d.fixed.bladder_cast_fill, "bladder_strain_surrogate": strain,
            "feasible": ev.feasible, "decision_vector": [float(v) for v in x],
            "binding": [n for n in names if ev.margins[n] < 1e-3],
            "housing_length_mm": d.housing_length_mm, "piston_diameter_mm": d.piston_diameter_mm}
