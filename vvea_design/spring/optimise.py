"""The linearity optimiser: global search + gradient polish over the four decision variables.

Objective: the linearity error (:func:`vvea_design.spring.gas_spring.linearity_error`)
of the design at the highest allowed charge. Constraints: every margin of
:func:`vvea_design.spring.requirements.evaluate_design` >= 0. Search: scipy's
``differential_evolution`` with the constraints handled by its feasibility
rules (Lampinen), seeded; then an SLSQP polish from the best point. When no
feasible design exists the least-violating design is returned with the
violated constraints named (:class:`Infeasible`).

Also here: Pareto fronts (linearity against stiffness, outer diameter or
mass; one optimisation per point through :func:`vvea_design.parallel.parallel_map`)
and 2-D linearity maps over any two decision variables.
"""

from __future__ import annotations

import time
from dataclasses import dataclass, replace
from typing import Literal

import numpy as np
from scipy.optimize import NonlinearConstraint, differential_evolution, minimize

from .design import DECISION_VARIABLES, Design, DesignError
from ..parallel import parallel_map
from ..progress import progress_bar
from .requirements import Evaluation, Requirements, constraint_names, design_from_vector, evaluate_design

__all__ = [
    "OptimisationResult",
    "Infeasible",
    "NoBuildableDesign",
    "optimise",
    "pareto_front",
    "linearity_map",
    "PARETO_AXES",
    "gas_volume_bound",
    "save_pareto",
]


class Infeasible(RuntimeError):
    """No design meets the requirements; ``result`` holds the least-violating one."""

    def __init__(self, result: "OptimisationResult"):
        self.result = result
        super().__init__(result.infeasibility_message())


class NoBuildableDesign(ValueError):
    """No point inside the search bounds can even be drawn; the message names why and the bounds."""


def _unbuildable_message(req: Requirements, x, bounds) -> str:
    try:
        design_from_vector(x, req)
        reason = "it violates every constraint by construction"
    except DesignError as exc:
        reason = str(exc)
    point = ", ".join(f"{n} = {float(v):.4g}" for n, v in zip(DECISION_VARIABLES, x))
    box = ", ".join(f"{n} in [{lo:.4g}, {hi:.4g}]" for n, (lo, hi) in zip(DECISION_VARIABLES, bounds))
    return (f"no buildable design inside the search bounds ({box}; outer_diameter_mm is capped at "
            f"max_outer_diameter_mm = {req.max_outer_diameter_mm:.4g}): the best point found ({point}) cannot be "
            f"drawn: {reason}; widen [bounds] or the envelope in the requirements file")


@dataclass(frozen=True)
class OptimisationResult:
    evaluation: Evaluation  #: the best design found, evaluated
    seed: int
    evaluations: int  #: model evaluations (objective + constraints share one)
    seconds: float
    generations: int
    de_message: str
    polished: bool  #: the SLSQP polish improved the global result

    @property
    def design(self) -> Design:
        return self.evaluation.design

    @property
    def evaluations_per_second(self) -> float:
        return self.evaluations / self.seconds if self.seconds > 0 else float("nan")

    def infeasibility_message(self) -> str:
        ev = self.evaluation
        lines = ["no design meets the requirements; the least-violating design found misses:"]
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
        return {
            "seed": self.seed,
            "evaluations": self.evaluations,
            "seconds": self.seconds,
            "evaluations_per_second": self.evaluations_per_second,
            "generations": self.generations,
            "message": self.de_message,
            "polished": self.polished,
            "binding_constraints": self.evaluation.binding(),
        }


class _Problem:
    """Objective and constraints sharing one cached evaluation per point."""

    def __init__(self, req: Requirements, bladder_strain_fn=None):
        self.req = req
        self.bladder_strain_fn = bladder_strain_fn
        self.names = constraint_names(req)
        self.count = 0
        self._cache: dict[bytes, tuple[float, np.ndarray]] = {}

    def _evaluate_design(self, v) -> Evaluation | None:
        try:
            d = design_from_vector(v, self.req)
        except DesignError:
            return None
        strain = self.bladder_strain_fn(d) if (self.bladder_strain_fn and self.req.max_bladder_strain) else None
        try:
            return evaluate_design(d, self.req, bladder_strain=strain)
        except (DesignError, ValueError):
            return None

    def __call__(self, v) -> tuple[float, np.ndarray]:
        key = np.asarray(v, dtype=float).tobytes()
        hit = self._cache.get(key)
        if hit is not None:
            return hit
        self.count += 1
        ev = self._evaluate_design(v)
        if ev is None:  # cannot be drawn at all: worst objective, every constraint violated
            out = (1.0, -np.ones(len(self.names)))
        else:
            out = (ev.linearity_error, np.array([ev.margins[k] for k in self.names]))
        if len(self._cache) > 50_000:
            self._cache.clear()
        self._cache[key] = out
        return out

    def objective(self, v) -> float:
        return self(v)[0]

    def constraints(self, v) -> np.ndarray:
        return self(v)[1]


def optimise(
    req: Requirements | None = None,
    *,
    seed: int = 0,
    popsize: int = 15,
    maxiter: int = 250,
    tol: float = 1e-4,
    polish: bool = True,
    progress: bool = True,
    bladder_strain_fn=None,
    raise_infeasible: bool = True,
) -> OptimisationResult:
    """Find the most linear design that meets ``req``.

    Parameters
    ----------
    req
        Requirements (default: the paper's unit).
    seed
        Seed of the global search: the same seed gives the same design.
    popsize, maxiter, tol
        Differential-evolution settings (population = popsize × 4).
    polish
        Run an SLSQP polish from the best point.
    bladder_strain_fn
        ``f(design) -> strain`` used when ``req.max_bladder_strain`` is set
        (e.g. :func:`vvea_design.bladder.check.strain_bound`, the FE bound). It is
        applied in the polish, which then always runs and must end feasible.
    raise_infeasible
        Raise :class:`Infeasible` (with the violated constraints) when no
        feasible design is found; otherwise return the least-violating one.
    """
    req = req or Requirements()
    if req.max_bladder_strain is not None and bladder_strain_fn is None:
        raise ValueError("max_bladder_strain is set: pass bladder_strain_fn (e.g. vvea_design.bladder.check.strain_bound)")
    # The FE strain bound costs ~0.1 s a call: the global search runs on the closed-form constraints
    # and the polish adds the bladder-strain constraint (and must end feasible with it).
    prob = _Problem(replace(req, max_bladder_strain=None))
    full = _Problem(req, bladder_strain_fn) if req.max_bladder_strain is not None else prob
    bounds = req.search_bounds()
    t0 = time.perf_counter()
    gens = 0
    with progress_bar("optimising linearity", total=maxiter, enabled=progress) as advance:

        def _cb(*_args, **_kw):
            nonlocal gens
            gens += 1
            advance()

        de = differential_evolution(
            prob.objective,
            bounds,
            constraints=[NonlinearConstraint(prob.constraints, 0.0, np.inf)],
            seed=seed,
            popsize=popsize,
            maxiter=maxiter,
            tol=tol,
            atol=0.0,
            mutation=(0.5, 1.0),
            recombination=0.7,
            init="sobol",
            polish=False,
            callback=_cb,
        )
        advance(maxiter - gens)  # converged early: complete the bar
    best_x = np.asarray(de.x, dtype=float)
    polished = False
    if polish or full is not prob:
        best_x, polished = _polish(full, best_x, bounds)
    seconds = time.perf_counter() - t0
    ev = full._evaluate_design(best_x)
    if ev is None:  # every point DE tried is unbuildable: name why and the bounds (issue 11 item 8)
        raise NoBuildableDesign(_unbuildable_message(req, best_x, bounds))
    result = OptimisationResult(ev, seed, prob.count + (full.count if full is not prob else 0), seconds, gens,
                                str(de.message), polished)
    if raise_infeasible and not ev.feasible:
        raise Infeasible(result)
    return result


def _polish(prob: _Problem, x0: np.ndarray, bounds) -> tuple[np.ndarray, bool]:
    """SLSQP in scaled variables from ``x0``; keep the result only if feasible and better."""
    lo = np.array([b[0] for b in bounds])
    hi = np.array([b[1] for b in bounds])
    span = hi - lo

    def unscale(z):
        return lo + z * span

    f0, c0 = prob(x0)
    res = minimize(
        lambda z: prob.objective(unscale(z)),
        (x0 - lo) / span,
        method="SLSQP",
        bounds=[(0.0, 1.0)] * len(bounds),
        constraints=[{"type": "ineq", "fun": lambda z: prob.constraints(unscale(z))}],
        options={"maxiter": 200, "ftol": 1e-12},
    )
    x1 = np.clip(unscale(res.x), lo, hi)
    f1, c1 = prob(x1)
    feasible0 = bool(np.all(c0 >= -1e-9))
    if np.all(c1 >= -1e-9) and (f1 < f0 or not feasible0):
        return x1, True
    return x0, False


# ---------------------------------------------------------------------------
# Pareto fronts
# ---------------------------------------------------------------------------

PARETO_AXES = {
    "stiffness": ("min_mean_stiffness_N_per_mm", "mean stiffness at max charge [N/mm]"),
    "outer_diameter": ("max_outer_diameter_mm", "max outer diameter [mm]"),
    "mass": ("max_mass_g", "max mass [g]"),
}


def _pareto_point(args) -> dict:
    req, seed, popsize, maxiter = args
    try:
        r = optimise(req, seed=seed, popsize=popsize, maxiter=maxiter, progress=False, raise_infeasible=False)
    except Exception as exc:  # a point that cannot even be set up is recorded, not fatal
        return {"feasible": False, "error": str(exc)}
    ev = r.evaluation
    row = {"feasible": ev.feasible, "linearity_error": ev.linearity_error, "mass_g": ev.mass_g,
           "mean_stiffness_at_max_charge_N_per_mm": ev.details["mean_stiffness"]["value"],
           "outer_diameter_mm": ev.design.outer_diameter_mm, "binding": ",".join(ev.binding())}
    row.update({n: float(getattr(ev.design, n)) for n in DECISION_VARIABLES})
    return row


def pareto_front(
    req: Requirements,
    axis: Literal["stiffness", "outer_diameter", "mass"],
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
    stiffness, N/mm), ``outer_diameter`` (envelope diameter, mm) or ``mass``
    (maximum mass, g). Returns one row per value with the optimum's
    linearity, mass, stiffness and decision variables; infeasible values are
    rows with ``feasible = False``.
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
    """Write a Pareto front as ``pareto_<axis>.csv`` and ``.png`` into ``out_dir``; return both paths."""
    import csv
    from pathlib import Path

    from .plots import plot_pareto

    out_dir = Path(out_dir)
    out_dir.mkdir(parents=True, exist_ok=True)
    csv_path = out_dir / f"pareto_{axis}.csv"
    keys = sorted({k for r in rows for k in r})
    with open(csv_path, "w", newline="") as fh:
        w = csv.DictWriter(fh, fieldnames=keys)
        w.writeheader()
        w.writerows(rows)
    field, label = PARETO_AXES[axis]
    png = plot_pareto(rows, field, label, out_dir / f"pareto_{axis}.png", title=title or f"best linearity vs {axis}")
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
    ``(n, n)`` indexed ``[iy, ix]``, and the name of the most violated
    constraint at every point (``worst``). The default ranges are ±40 % around
    the design, clipped to the search bounds.
    """
    for v in (var_x, var_y):
        if v not in DECISION_VARIABLES:
            raise ValueError(f"unknown design variable {v!r}; choose from {list(DECISION_VARIABLES)}")
    if var_x == var_y:
        raise ValueError("the two map variables must differ")
    bounds = dict(zip(DECISION_VARIABLES, req.search_bounds()))

    def around(var):  # default range: ±40 % around the design, inside the search bounds
        v = float(getattr(design, var))
        lo, hi = bounds[var]
        return max(lo, 0.6 * v), min(hi, 1.4 * v)

    xs = np.linspace(*(x_range or around(var_x)), n)
    ys = np.linspace(*(y_range or around(var_y)), n)
    lin = np.full((n, n), np.nan)
    feas = np.zeros((n, n), dtype=bool)
    worst = np.full((n, n), "unbuildable", dtype=object)
    base = {k: float(getattr(design, k)) for k in DECISION_VARIABLES}
    with progress_bar(f"map {var_x} × {var_y}", total=n) as advance:
        for iy, yv in enumerate(ys):
            for ix, xv in enumerate(xs):
                kw = dict(base)
                kw[var_x], kw[var_y] = float(xv), float(yv)
                try:
                    d = Design(**kw, p2_MPa=design.p2_MPa, setpoint_x0_mm=design.setpoint_x0_mm, fixed=design.fixed)
                    ev = evaluate_design(d, req)
                except (DesignError, ValueError):
                    continue
                lin[iy, ix] = ev.linearity_error
                feas[iy, ix] = ev.feasible
                name, m = min(ev.margins.items(), key=lambda kv: kv[1])
                worst[iy, ix] = name if m < 0 else ""
            advance()
    return {"var_x": var_x, "var_y": var_y, "x": xs, "y": ys, "linearity": lin, "feasible": feas, "worst": worst}


# ---------------------------------------------------------------------------
# Packing-free bound
# ---------------------------------------------------------------------------

def gas_volume_bound(total_gas_mm3: float, req: Requirements | None = None, *, seed: int = 0,
                     maxiter: int = 400) -> dict:
    """Best linearity any layout could reach with ``V1 + V2 <= total_gas_mm3``.

    Ignores packing entirely: only eq. 5, the charge limit (both chambers <=
    ``max_charge_MPa``, F(0) = 0 so ``p1 = A2/A1 p2``), the stiffness
    requirement and the minimum gas left at full stroke. It tells how much
    gas a target linearity needs, whatever the housing.
    """
    from .gas_spring import force_N, linearity_error, mean_stiffness_N_per_mm

    req = req or Requirements()
    x = np.linspace(0.0, req.travel_mm, 201)
    pmax = req.max_charge_MPa
    fmin = req.min_gas_fraction_at_full_stroke

    def curve(v):
        A1, A2, V1, V2 = v
        if V2 - A2 * req.travel_mm <= max(fmin, 1e-3) * V2:
            return None
        return force_N(x, A1, A2, V1, V2, A2 / A1 * pmax, pmax, req.n_polytropic)

    def obj(v):
        F = curve(v)
        return 1.0 if F is None else float(linearity_error(x, F))

    def cons(v):
        F = curve(v)
        k = -1.0 if F is None else float(mean_stiffness_N_per_mm(x, F)) / req.min_mean_stiffness_N_per_mm - 1
        gas_left = (v[3] - v[1] * req.travel_mm) / v[3] - fmin
        return np.array([v[0] - v[1], 1 - (v[2] + v[3]) / total_gas_mm3, k, gas_left])

    r = differential_evolution(obj, [(100, 5000), (100, 5000), (1e3, total_gas_mm3), (1e3, total_gas_mm3)],
                               constraints=[NonlinearConstraint(cons, 0, np.inf)], seed=seed, popsize=20,
                               maxiter=maxiter, tol=1e-8, polish=False, init="sobol")
    A1, A2, V1, V2 = (float(v) for v in r.x)
    return {"total_gas_mm3": float(total_gas_mm3), "linearity_error": float(r.fun), "A1_mm2": A1, "A2_mm2": A2,
            "V1_mm3": V1, "V2_mm3": V2, "feasible": bool(np.all(cons(r.x) >= -1e-6))}
