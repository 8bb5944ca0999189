"""Multi-start solve of one rest-to-rest case (paper section 5).

One *case* is an amplitude ``A`` and a period ``T``; for it every actuator
setting is solved on one mesh (:func:`solve_case`). Constant-damping settings
are convex QPs and are solved once. Variable-damping settings are non-convex
and are solved from several starts; the best objective wins:

* ``const-Dmin`` - the solution with D held at D_min (for iVVEA this is the
  SEA solution). It is feasible, so it is also *adopted* as a candidate
  itself: a variable-damping result is never worse than the constant
  setting at its D_min on the same mesh (iVVEA <= SEA, exactly);
* ``ramp`` - the QP solution with D ramped to D_max as fast as eq. 12 allows
  (feasible, adopted too);
* ``cold`` - at rest with D = D_min;
* ``cross`` - the best solution of the other variable-damping settings of the
  same case, clipped into this setting's damping range;
* ``neighbour`` - the multi-start optimum of the same setting at the neighbouring
  case of a chain (:func:`solve_chain`: the cases of one amplitude in the order of
  their periods), as is: the problem is scaled by A and T, so a neighbour's scaled
  decision vector is a start for this case. A chain's first case has none.

The default starts are ``const-Dmin``, ``ramp`` and ``neighbour`` (``cold`` and
``cross`` stay available; ``studies/bench_ocp.py`` measures what each costs and
which optima change). An option (:data:`MULTISTART_WARM_IPOPT`) solves the starts from a point
on the multi-start mesh of a two-level run with IPOPT started *at* that point, at about half
the CPU of the cold options; it moves iVVEA optima, so it is not the default.
Settings that differ only by name are solved once and
share their results (the design at the paper's K with the paper's damping range
*is* the paper's VVEA).

With a fine mesh the multi-start runs on the coarse mesh and every setting is
solved once more on the fine one (:func:`_polish_on_fine_mesh`).
"""

from __future__ import annotations

import contextlib
import json
import threading
import time
from collections.abc import Iterator, Sequence
from dataclasses import asdict, dataclass, fields, replace

import numpy as np

from .model import Actuator
from .verify import Verification, verify_rest_to_rest
from .ocp import Mesh, OcpResult, Regularisation, RestToRestSolver, WARM_START_IPOPT, ramp_u_d_profile

__all__ = [
    "RestToRestCase",
    "CaseRow",
    "SingleSolve",
    "DEFAULT_MESH",
    "DEFAULT_FINE_MESH",
    "DEFAULT_STARTS",
    "ALL_STARTS",
    "DEFAULT_REGULARISATION",
    "MULTISTART_IPOPT",
    "MULTISTART_WARM_IPOPT",
    "MULTISTART_WARM_STARTS",
    "RESULT_COLUMNS",
    "TIE_RTOL",
    "solve_case",
    "solve_case_results",
    "solve_chain",
    "chains",
    "solve_single",
    "keep_results",
]

#: Collocation mesh used by the studies (chosen by ``studies/mesh_convergence.py``).
DEFAULT_MESH = Mesh(n_intervals=64, degree=3)
#: Mesh on which the reported results are solved (two-level scheme): the multi-start runs on
#: :data:`DEFAULT_MESH`, then every setting is solved once more here (QPs directly, variable
#: damping by one warm-started polish of the coarse optimum). SEA's rmse changes < 0.5 % case by
#: case from N = 192 on (``studies/mesh_convergence.py``).
DEFAULT_FINE_MESH = Mesh(n_intervals=192, degree=3)
#: Regularisation of the studies: removes the chatter of τ_m (±τ_max) and of D (D_min <-> D_max) while
#: the link rests, at a cost of < 0.2 % in rmse (measured, docs/actuator.md).
DEFAULT_REGULARISATION = Regularisation(u_d=1e-3, tau_rate=1e-6)
#: Starts tried for variable-damping settings (``neighbour`` only inside a chain, :func:`solve_chain`).
DEFAULT_STARTS = ("const-Dmin", "ramp", "neighbour")
#: Every start there is (``cold``: at rest with D = D_min; ``cross``: the other variable settings' optima).
ALL_STARTS = ("const-Dmin", "ramp", "cold", "cross", "neighbour")
_ALL_STARTS = set(ALL_STARTS)
#: IPOPT options of every solve on the multi-start mesh of a two-level run (the case's own options override
#: them; the fine mesh keeps the defaults and :data:`WARM_START_IPOPT`). Empty by default. The monotone barrier
#: update (``{"ipopt.mu_strategy": "monotone"}``) needs about half the CPU of the adaptive one on these NLPs
#: (the whole case 23 % less, ``studies/bench_ocp.py``) but lands iVVEA in worse basins more often than in better
#: ones (on the 15 periods of A = 0.7 rad: 5 iVVEA optima worse by up to 2.1 %, none better; VVEA within 0.1 %),
#: beyond the mesh tolerance, so it is not the default; on the fine polish it costs more than it saves.
MULTISTART_IPOPT: dict = {}
#: IPOPT options of the multi-start NLPs that start from a point (:data:`MULTISTART_WARM_STARTS`) on the multi-start
#: mesh of a two-level run, added to that mesh's options (the case's own win); ``{}`` (the default) = the cold
#: options. With :data:`WARM_START_IPOPT` IPOPT starts *at* the point (a QP optimum, a neighbour's optimum) instead
#: of being pushed into the interior: these NLPs need about half the CPU (``studies/bench_ocp.py``,
#: docs/benchmarks.md). VVEA's optima stay within 5e-4, but iVVEA lands in other basins: alone (a case 30-36 %
#: less CPU) up to 0.84 % worse than the committed run; with the ``cold`` start added (10-18 % less CPU) 24 of 120
#: iVVEA optima better (up to 6.8 %) and 7 worse, 2 of them beyond the mesh tolerance (0.8 % and 0.95 %). So it is
#: an option. Single-level runs (the design study) never use it (there it saved 5 % and moved an optimum by 2.2 %).
MULTISTART_WARM_IPOPT: dict = {}
#: The starts solved with :data:`MULTISTART_WARM_IPOPT` (the others keep the mesh's cold options).
MULTISTART_WARM_STARTS: tuple[str, ...] = ("const-Dmin", "ramp", "neighbour", "cross")


@dataclass(frozen=True)
class RestToRestCase:
    """One work item of the sweep: every setting at one (A, T)."""

    A_rad: float
    T_s: float
    settings: tuple[Actuator, ...]
    mesh: Mesh = DEFAULT_MESH
    starts: tuple[str, ...] = DEFAULT_STARTS
    ipopt_options: tuple[tuple[str, object], ...] = ()  #: extra IPOPT options (hashable)
    fine_mesh: Mesh | None = None  #: if set, report results polished on this mesh (two-level)
    #: penalties that smooth the optimal inputs (objectives and rmse stay the pure tracking cost)
    regularisation: Regularisation = DEFAULT_REGULARISATION

    @property
    def case_id(self) -> str:
        return f"A{self.A_rad:.6g}_T{self.T_s:.6g}"


@dataclass(frozen=True)
class CaseRow:
    """One setting's result at one (A, T): a row of ``results.csv`` (SI units; NaN where not solved)."""

    case_id: str  #: ``A<A>_T<T>`` (6 significant digits)
    setting: str  #: setting name
    A_rad: float  #: reference amplitude, rad
    T_s: float  #: reference period, s
    rmse: float  #: tracking rmse, rad (NaN when not solved)
    valid: bool  #: the link reaches 95 % of A in both up-phases
    status: str  #: IPOPT status of the reported result (or the error)
    seconds: float  #: solver wall time of every solve of this setting, s
    cpu_seconds: float  #: solver CPU time of every solve of this setting, s
    success: bool  #: a result was found
    objective: float  #: tracking integral ∫ (q - q_des)² dt, rad² s
    iterations: int  #: IPOPT iterations of every solve of this setting
    start: str  #: start that won ("" when none succeeded)
    n_starts: int  #: starts tried
    start_objectives: str  #: JSON object: start label to its objective (rad² s; null = failed)
    peak_q_up1_rad: float  #: highest link angle in the first up-phase, rad
    peak_q_up2_rad: float  #: highest link angle in the second up-phase, rad
    mean_D_Nms_per_rad: float  #: time-mean damping, N m s/rad
    max_D_Nms_per_rad: float  #: peak damping, N m s/rad
    K_Nm_per_rad: float  #: series stiffness of the setting, N m/rad
    D_min_Nms_per_rad: float  #: damping range, lower end, N m s/rad
    D_max_Nms_per_rad: float  #: damping range, upper end, N m s/rad
    mesh_N: int  #: intervals of the mesh the row was solved on
    mesh_degree: int  #: Radau degree of that mesh
    coarse_mesh_N: int  #: intervals of the multi-start mesh (= mesh_N for a single-level run)
    coarse_rmse: float  #: rmse of the multi-start optimum, rad
    verified: bool  #: the re-simulation reproduces the trajectory within its tolerances
    verify_reason: str  #: "ok", or why not verified
    resim_rmse: float  #: rmse of the re-simulated trajectory, rad
    resim_rel_error: float  #: relative difference of the two rmse (fraction)
    #: largest damping torque |D (θ' - q')| over every collocation point, N m (the relief valves bound it)
    max_damping_torque_Nm: float = float("nan")

    def to_dict(self) -> dict:
        """The row as ``results.csv`` writes it.

        Returns
        -------
        dict
            Column name (:data:`RESULT_COLUMNS`, in order) to value, SI units as in the field names.
        """
        return {f.name: getattr(self, f.name) for f in fields(self)}


#: Columns of results.csv, in order (the fields of :class:`CaseRow`).
RESULT_COLUMNS = [f.name for f in fields(CaseRow)]

# -- per-process solver cache (one parametric solver per mesh and options) ------------------------
_SOLVERS: dict[tuple, RestToRestSolver] = {}


def _solver(mesh: Mesh, ipopt_options: tuple) -> RestToRestSolver:
    key = (mesh, ipopt_options)
    if key not in _SOLVERS:
        _SOLVERS[key] = RestToRestSolver(mesh, dict(ipopt_options))
    return _SOLVERS[key]


def _mean_D(r: OcpResult, solver: RestToRestSolver) -> float:
    col = solver.cols[True]
    D = r.Z[:, 1:, 4]
    return float(np.sum(D * col.Bq[1:] * col.h[:, None]) / col.S)


def _row(case: RestToRestCase, act: Actuator, r: OcpResult | None, start: str, n_starts: int,
         secs: float, iters: int, start_obj: dict, solver: RestToRestSolver | None, status: str | None = None,
         cpu: float = float("nan")) -> CaseRow:
    ok = r is not None and r.success and np.isfinite(r.objective)
    return CaseRow(
        case_id=case.case_id,
        setting=act.name,
        A_rad=case.A_rad,
        T_s=case.T_s,
        rmse=r.extra["rmse_rad"] if ok else float("nan"),
        valid=bool(r.extra["valid"]) if ok else False,
        status=status if status is not None else (r.status if r is not None else "not solved"),
        seconds=round(secs, 4),
        cpu_seconds=round(cpu, 4),
        success=bool(ok),
        objective=r.objective if ok else float("nan"),
        iterations=iters,
        start=start if ok else "",
        n_starts=n_starts,
        start_objectives=json.dumps({k: (None if not np.isfinite(v) else float(f"{v:.10g}"))
                                     for k, v in start_obj.items()}),
        peak_q_up1_rad=r.extra["peak_q_up_rad"][0] if ok else float("nan"),
        peak_q_up2_rad=r.extra["peak_q_up_rad"][1] if ok else float("nan"),
        mean_D_Nms_per_rad=_mean_D(r, solver) if ok else float("nan"),
        max_D_Nms_per_rad=float(np.max(r.Z[..., 4])) if ok else float("nan"),
        K_Nm_per_rad=act.K_Nm_per_rad,
        D_min_Nms_per_rad=act.D_min_Nms_per_rad,
        D_max_Nms_per_rad=act.D_max_Nms_per_rad,
        mesh_N=case.mesh.n_intervals,
        mesh_degree=case.mesh.degree,
        coarse_mesh_N=case.mesh.n_intervals,
        coarse_rmse=r.extra["rmse_rad"] if ok else float("nan"),
        verified=False,
        verify_reason="not checked",
        resim_rmse=float("nan"),
        resim_rel_error=float("nan"),
        max_damping_torque_Nm=float(np.max(np.abs(r.Z[..., 4] * (r.Z[..., 2] - r.Z[..., 3])))) if ok else float("nan"),
    )


def _same_numbers(act: Actuator) -> tuple:
    """Every field of a setting but its name (settings with equal keys have equal solutions)."""
    return tuple(getattr(act, f.name) for f in fields(act) if f.name != "name")


def solve_case_results(case: RestToRestCase,
                       neighbour: dict[str, OcpResult] | None = None) -> tuple[list[CaseRow], dict[str, OcpResult]]:
    """Solve every setting of one case; return (rows, best results by setting name).

    With ``case.fine_mesh`` the multi-start runs on ``case.mesh`` and the rows
    and results come from the fine mesh (:func:`_polish_on_fine_mesh`). Every
    reported result is re-simulated (:func:`~vvea_design.actuator.verify.verify_rest_to_rest`).
    Settings that differ only by name are solved once (the rows carry each one's name).

    Parameters
    ----------
    case
        Amplitude (rad), period (s), settings, mesh(es), starts, regularisation.
    neighbour
        The multi-start optima (on ``case.mesh``) of a neighbouring case by setting name: the ``neighbour``
        start of :func:`solve_chain` (used when ``"neighbour"`` is among ``case.starts``).

    Returns
    -------
    (list of CaseRow, dict)
        One ``results.csv`` row per setting (:class:`CaseRow`, SI units) and the best
        :class:`~vvea_design.actuator.ocp.OcpResult` per setting name; each best result's
        ``extra["multistart"]`` is its multi-start optimum on ``case.mesh`` (the next case's neighbour start).
    """
    first: dict[tuple, Actuator] = {}
    for act in case.settings:
        first.setdefault(_same_numbers(act), act)
    unique = replace(case, settings=tuple(first.values())) if len(first) < len(case.settings) else case
    two_level = unique.fine_mesh is not None and unique.fine_mesh != unique.mesh
    coarse_qps: dict[tuple, OcpResult] = {}
    rows, best = _solve_case_one_mesh(unique, neighbour or {}, _coarse_options(unique) if two_level else None,
                                      coarse_qps, warm=two_level)
    coarse = dict(best)
    if two_level:
        rows, best = _polish_on_fine_mesh(unique, rows, best, coarse_qps)
    acts = {a.name: a for a in unique.settings}
    checked = {}
    for row in rows:
        r = best.get(row.setting)
        if r is None:
            v = Verification(False, f"solver: {row.status}", *(4 * [float("nan")]))
        else:
            v = verify_rest_to_rest(r, acts[row.setting], unique.A_rad, unique.T_s)
            r.extra["verification"] = v
            r.extra["multistart"] = coarse.get(row.setting)
        checked[row.setting] = replace(row, verified=v.verified, verify_reason=v.reason or "ok",
                                       resim_rmse=v.resim_rmse_rad, resim_rel_error=v.rmse_rel_error)
    out_rows, out_best = [], {}
    for act in case.settings:
        twin = first[_same_numbers(act)].name
        out_rows.append(replace(checked[twin], setting=act.name))
        out_best[act.name] = best.get(twin)
    return out_rows, out_best


def _coarse_options(case: RestToRestCase) -> tuple:
    """IPOPT options of the multi-start mesh of a two-level case: :data:`MULTISTART_IPOPT`, then the case's own."""
    return tuple(sorted({**MULTISTART_IPOPT, **dict(case.ipopt_options)}.items()))


def _polish_on_fine_mesh(case: RestToRestCase, coarse_rows: list[CaseRow], coarse_best: dict[str, OcpResult],
                         coarse_qps: dict[tuple, OcpResult] | None = None,
                         ) -> tuple[list[CaseRow], dict[str, OcpResult]]:
    """Second level: solve every setting of the case on ``case.fine_mesh``.

    Constant damping: the convex QP, started from its coarse-mesh optimum (``coarse_qps``, by the QP's numbers)
    interpolated onto the fine mesh with :data:`WARM_START_IPOPT` (the same unique optimum in a third of the
    CPU; a cold solve if that fails or there is none). Variable damping: candidates are
    (1) the fine-mesh QP at D_min adopted as is (feasible; for iVVEA it *is*
    the fine SEA solution, so iVVEA <= SEA holds exactly on the fine mesh) and
    (2) one warm-started polish of the coarse multi-start optimum interpolated
    onto the fine mesh (a cold-option retry only if that fails). Best wins.
    """
    fm = case.fine_mesh
    fs = _solver(fm, case.ipopt_options)
    fw = _solver(fm, tuple(sorted({**dict(case.ipopt_options), **WARM_START_IPOPT}.items())))
    A, T = case.A_rad, case.T_s
    fcase = RestToRestCase(A, T, case.settings, fm, case.starts, case.ipopt_options,
                           regularisation=case.regularisation)
    crow = {r.setting: r for r in coarse_rows}
    qp_cache: dict[tuple, OcpResult] = {}

    def const_solve(act: Actuator) -> OcpResult:
        key = (act.K_Nm_per_rad, act.D_min_Nms_per_rad, act.B_kgm2, act.M_kgm2, act.tau_m_max_Nm)
        if key not in qp_cache:
            const = act.with_(D_max_Nms_per_rad=act.D_min_Nms_per_rad)
            start = (coarse_qps or {}).get(("const",) + key)
            r = None
            if start is not None and start.success and np.all(np.isfinite(start.w)):
                r = fw.solve(const, A, T, w0=fw.guess_from_other_mesh(start, const, A, T),
                             regularisation=case.regularisation)
            if r is None or not r.success:  # no coarse optimum, or the warm start failed: cold, default options
                cold = fs.solve(const, A, T, regularisation=case.regularisation)
                if r is not None:  # the failed warm solve's time counts
                    cold.seconds += r.seconds
                    cold.extra["cpu_seconds"] = cold.extra.get("cpu_seconds", 0.0) + r.extra.get("cpu_seconds", 0.0)
                r = cold
            qp_cache[key] = r
        return qp_cache[key]

    rows, best = [], {}
    cN = case.mesh.n_intervals
    for act in case.settings:
        cr = crow[act.name]
        secs, cpu, iters = float(cr.seconds), float(cr.cpu_seconds), int(cr.iterations)
        obj = {f"N{cN} {k}": v for k, v in json.loads(cr.start_objectives).items()}
        obj = {k: (float("nan") if v is None else v) for k, v in obj.items()}
        cand: dict[str, OcpResult] = {}
        qp = const_solve(act)
        secs += qp.seconds
        cpu += qp.extra.get("cpu_seconds", 0.0)
        iters += max(qp.iterations, 0)
        if not act.variable_damping:
            cand["qp"] = qp
        else:
            cand["const-Dmin (adopted)"] = fw.evaluate_as(qp, act, A, T, status=qp.status)  # J only: no cold build
            cb = coarse_best.get(act.name)
            if cb is not None and cb.success:
                lab = f"polish:{cr.start}"
                r = fw.solve(act, A, T, w0=fw.guess_from_other_mesh(cb, act, A, T), regularisation=case.regularisation)
                if not r.success:  # retry with the default options from the same start
                    secs, cpu, iters = secs + r.seconds, cpu + r.extra.get("cpu_seconds", 0.0), iters + max(r.iterations, 0)
                    obj[lab + " (warm)"] = float("nan")
                    r = fs.solve(act, A, T, w0=fs.guess_from_other_mesh(cb, act, A, T), regularisation=case.regularisation)
                secs += r.seconds
                cpu += r.extra.get("cpu_seconds", 0.0)
                iters += max(r.iterations, 0)
                cand[lab] = r
        for k, r in cand.items():
            obj[k] = r.objective if r.success else float("nan")
        label = _pick_label(cand)
        b = cand[label] if label else None
        best[act.name] = b
        status = None
        if label is None:
            first = next(iter(cand.values()), None)
            status = first.status if first is not None else "no start tried"
        row = _row(fcase, act, b, label or "", len(cand), secs, iters, obj, fs, status=status, cpu=cpu)
        rows.append(replace(row, coarse_mesh_N=cN, coarse_rmse=cr.rmse))
    return rows, best


def _solve_case_one_mesh(case: RestToRestCase, neighbour: dict[str, OcpResult], options: tuple | None = None,
                         qps_out: dict | None = None, warm: bool = False) -> tuple[list[CaseRow], dict[str, OcpResult]]:
    """Multi-start on ``case.mesh`` only (``neighbour``: the neighbouring case's optima by setting name;
    ``options``: the IPOPT options, default the case's own; ``qps_out`` gets the constant-damping QP optima by
    their numbers, the fine polish's starts; ``warm``: the starts of :data:`MULTISTART_WARM_STARTS` with
    :data:`MULTISTART_WARM_IPOPT`, when that is set)."""
    opts = case.ipopt_options if options is None else options
    s = _solver(case.mesh, opts)
    # the NLPs with a start point: IPOPT starts at it (MULTISTART_WARM_IPOPT; the case's own options win)
    sw = (_solver(case.mesh, tuple(sorted({**MULTISTART_WARM_IPOPT, **dict(opts)}.items())))
          if warm and MULTISTART_WARM_IPOPT else s)

    def sw_(start: str) -> RestToRestSolver:
        return sw if start in MULTISTART_WARM_STARTS else s
    A, T = case.A_rad, case.T_s
    dt = s.interval_seconds(T)
    unknown = set(case.starts) - _ALL_STARTS
    if unknown:
        raise ValueError(f"unknown start(s) {sorted(unknown)}; choose from {sorted(_ALL_STARTS)}")
    rows: dict[str, CaseRow] = {}
    best: dict[str, OcpResult] = {}
    info: dict[str, dict] = {}
    qp_cache: dict[tuple, OcpResult] = {} if qps_out is None else qps_out
    cpu = {a.name: 0.0 for a in case.settings}  # CPU seconds of each setting's solves

    def const_solve(act: Actuator) -> OcpResult:
        key = ("const", act.K_Nm_per_rad, act.D_min_Nms_per_rad, act.B_kgm2, act.M_kgm2, act.tau_m_max_Nm)
        if key not in qp_cache:
            qp_cache[key] = s.solve(act.with_(D_max_Nms_per_rad=act.D_min_Nms_per_rad), A, T,
                                    regularisation=case.regularisation)
        return qp_cache[key]

    # constant-damping settings: one convex QP each
    for act in case.settings:
        if not act.variable_damping:
            r = const_solve(act)
            cpu[act.name] += r.extra.get("cpu_seconds", 0.0)
            best[act.name] = r
            info[act.name] = dict(start="qp", n=1, secs=r.seconds, iters=r.iterations, obj={"qp": r.objective})
    variable = [a for a in case.settings if a.variable_damping]
    # variable damping: starts from feasible QP solutions, cold, then cross starts
    for act in variable:
        cand: dict[str, OcpResult] = {}
        secs, iters = 0.0, 0
        inf = dict(obj={})

        def attempt(label: str, r: OcpResult) -> None:
            nonlocal secs, iters
            secs += r.seconds
            cpu[act.name] += r.extra.get("cpu_seconds", 0.0)
            iters += max(r.iterations, 0)
            inf["obj"][label] = r.objective if r.success else float("nan")
            cand[label] = r

        if "const-Dmin" in case.starts:
            qp = const_solve(act)
            secs += qp.seconds
            cpu[act.name] += qp.extra.get("cpu_seconds", 0.0)
            attempt("const-Dmin (adopted)", s.evaluate_as(qp, act, A, T, status=qp.status))
            attempt("const-Dmin", sw_("const-Dmin").solve(act, A, T, w0=s.guess_from(qp, act, A, T),
                                                          regularisation=case.regularisation))
        if "ramp" in case.starts:
            prof = ramp_u_d_profile(act, dt, act.D_max_Nms_per_rad)
            rq = s.solve(act, A, T, u_d_fixed=prof, regularisation=case.regularisation)
            attempt("ramp (adopted)", rq)
            if rq.success:
                attempt("ramp", sw_("ramp").solve(act, A, T, w0=s.guess_from(rq, act, A, T),
                                                  regularisation=case.regularisation))
        if "cold" in case.starts:
            attempt("cold", s.solve(act, A, T, regularisation=case.regularisation))
        nb = neighbour.get(act.name) if "neighbour" in case.starts else None
        if nb is not None and nb.success and len(nb.w) == s.cols[True].nw and np.all(np.isfinite(nb.w)):
            attempt("neighbour", sw_("neighbour").solve(act, A, T, w0=nb.w,
                                                        regularisation=case.regularisation))
        info[act.name] = dict(cand=cand, secs=secs, iters=iters, obj=inf["obj"])
    if "cross" in case.starts and len(variable) > 1:
        for act in variable:
            for other in variable:
                if other is act:
                    continue
                ob = _pick(info[other.name]["cand"])
                if ob is None:
                    continue
                r = sw_("cross").solve(act, A, T, w0=s.guess_from(ob, act, A, T), regularisation=case.regularisation)
                inf = info[act.name]
                inf["secs"] += r.seconds
                cpu[act.name] += r.extra.get("cpu_seconds", 0.0)
                inf["iters"] += max(r.iterations, 0)
                label = f"cross:{other.name}"
                inf["obj"][label] = r.objective if r.success else float("nan")
                inf["cand"][label] = r
    for act in variable:
        inf = info[act.name]
        label = _pick_label(inf["cand"])
        best[act.name] = inf["cand"][label] if label else None
        inf["start"] = label or ""
        inf["n"] = len(inf["cand"])
        if label is None:  # every start failed: record the first failure's status
            first = next(iter(inf["cand"].values()), None)
            inf["status"] = first.status if first is not None else "no start tried"
    for act in case.settings:
        inf = info[act.name]
        rows[act.name] = _row(case, act, best.get(act.name), inf["start"], inf["n"], inf["secs"], inf["iters"],
                              inf["obj"], s, status=inf.get("status"), cpu=cpu[act.name])
    return [rows[a.name] for a in case.settings], best


#: Starts whose objectives agree to this relative tolerance count as a tie;
#: a tie goes to the earlier start (so "won" means "first to reach the best").
TIE_RTOL = 1e-6


def _pick_label(cand: dict[str, OcpResult]) -> str | None:
    ok = {k: r.objective for k, r in cand.items() if r.success and np.isfinite(r.objective)}
    if not ok:
        return None
    fbest = min(ok.values())
    for k, f in ok.items():  # insertion order
        if f <= fbest + TIE_RTOL * abs(fbest) + 1e-15:
            return k
    return None  # pragma: no cover


def _pick(cand: dict[str, OcpResult]) -> OcpResult | None:
    lab = _pick_label(cand)
    return cand[lab] if lab else None


_KEPT = threading.local()  # per thread: where solve_case also puts its best results (keep_results)


@contextlib.contextmanager
def keep_results() -> Iterator[list]:
    """Inside the block, :func:`solve_case` (in this thread) also hands over its best results.

    The sweep uses it to draw its trajectory figure from the worker's own solution instead of
    solving that case once more; :func:`solve_case`'s return value is unchanged.

    Yields
    ------
    list
        Gets ``(case, best)`` for every case that :func:`solve_case` solved without an error inside
        the block, in call order; ``best`` maps setting names to their OcpResult (or None).
    """
    kept: list = []
    previous = getattr(_KEPT, "sink", None)
    _KEPT.sink = kept
    try:
        yield kept
    finally:
        _KEPT.sink = previous


def _case_or_error(case: RestToRestCase, neighbour: dict[str, OcpResult] | None,
                   ) -> tuple[list[CaseRow], dict[str, OcpResult]]:
    """:func:`solve_case_results`, or error rows (and no results) for any exception in it."""
    t0 = time.perf_counter()
    try:
        return solve_case_results(case, neighbour)
    except Exception as exc:  # noqa: BLE001 - a sweep must never stop on one case
        msg = f"error: {type(exc).__name__}: {exc}".splitlines()[0][:200]
        return [_row(case, act, None, "", 0, time.perf_counter() - t0, 0, {}, None, status=msg)
                for act in case.settings], {}


def solve_case(case: RestToRestCase) -> list[CaseRow]:
    """Rows for one (A, T) case on its own (no neighbour start); never raises.

    Any exception becomes rows with ``status = "error: ..."`` and no result.
    Inside :func:`keep_results` the best results are handed over too.

    Parameters
    ----------
    case
        Amplitude (rad), period (s), settings, mesh(es), starts, regularisation.

    Returns
    -------
    list of CaseRow
        One ``results.csv`` row per setting (SI units; ``to_dict()`` gives the CSV row).
    """
    rows, best = _case_or_error(case, None)
    sink = getattr(_KEPT, "sink", None)
    if sink is not None and best:
        sink.append((case, best))
    return rows


def solve_chain(cases: Sequence[RestToRestCase], keep: RestToRestCase | None = None,
                ) -> tuple[list[list[CaseRow]], dict[str, OcpResult] | None]:
    """Work function of the sweeps: the cases of one chain in order, each starting from its predecessor's optima.

    Every case but the first gets the ``neighbour`` start (when among its starts): the multi-start optimum of
    the same setting at the case before. Deterministic for a given chain; never raises (a case that fails
    becomes error rows, and the next case has no neighbour start).

    Parameters
    ----------
    cases
        The chain's cases (one amplitude in rad, its periods in s in order; see :func:`chains`).
    keep
        A case of the chain whose best results to hand back (the trajectory figure's), or None.

    Returns
    -------
    (list of list of CaseRow, dict or None)
        The rows of each case in order (SI units), and the best results by setting name of ``keep`` (None
        when ``keep`` is not in the chain or failed).
    """
    out, kept, neighbour = [], None, None
    for case in cases:
        rows, best = _case_or_error(case, neighbour)
        out.append(rows)
        if keep is not None and case == keep:
            kept = best or None
        neighbour = {k: r.extra.get("multistart") for k, r in best.items()
                     if r is not None and r.extra.get("multistart") is not None} or None
    return out, kept


def chains(cases: Sequence[RestToRestCase]) -> list[list[RestToRestCase]]:
    """The sweep's cases grouped into chains: consecutive cases of one amplitude, when they use the neighbour start.

    Parameters
    ----------
    cases
        The sweep's cases, amplitude-major (as :meth:`~vvea_design.actuator.rest_to_rest.Grid.cases` gives them).

    Returns
    -------
    list of list of RestToRestCase
        One chain per amplitude (its periods in the grid's order) for cases whose starts include ``neighbour``;
        every other case is a chain of its own.
    """
    out: list[list[RestToRestCase]] = []
    for c in cases:
        if ("neighbour" in c.starts and out and out[-1][-1].A_rad == c.A_rad and "neighbour" in out[-1][-1].starts
                and out[-1][-1].settings == c.settings):
            out[-1].append(c)
        else:
            out.append([c])
    return out


def _chain_item(item: tuple) -> tuple[list[list[CaseRow]], dict | None]:
    """Work function of :func:`~vvea_design.actuator.rest_to_rest.run_rest_to_rest`: ``item = (solve, cases,
    keep)``, ``solve`` being the sweep's :func:`solve_chain` (passed along, so a worker imports this light
    module only, not the sweep's figures and statistics)."""
    solve, cases, keep = item
    return solve(cases, keep)


@dataclass(frozen=True)
class SingleSolve:
    """One setting at one (A, T) on one mesh, single start (:func:`solve_single`)."""

    mesh_N: int  #: intervals of the mesh
    mesh_degree: int  #: Radau degree of the mesh
    setting: str  #: setting name
    A_rad: float  #: reference amplitude, rad
    T_s: float  #: reference period, s
    rmse: float  #: tracking rmse, rad (NaN when IPOPT failed)
    status: str  #: IPOPT status
    seconds: float  #: solver wall time, s

    def to_dict(self) -> dict:
        """Plain-JSON dictionary (a table row).

        Returns
        -------
        dict
            Field name to value: ``mesh_N``, ``mesh_degree`` (counts), ``setting``, ``A_rad`` (rad),
            ``T_s`` (s), ``rmse`` (rad), ``status`` and ``seconds`` (s).
        """
        return asdict(self)


def solve_single(item: tuple[Mesh, Actuator, float, float]) -> SingleSolve:
    """Work function: one setting at one (A, T) on one mesh, single start (for QP convergence checks).

    Parameters
    ----------
    item
        ``(mesh, actuator, A_rad, T_s)``: amplitude in rad, period in s.

    Returns
    -------
    SingleSolve
        Mesh, setting, A (rad), T (s), ``rmse`` (rad), IPOPT status, wall ``seconds``.
    """
    mesh, act, A, T = item
    r = _solver(mesh, ()).solve(act, A, T)
    return SingleSolve(mesh.n_intervals, mesh.degree, act.name, A, T,
                       r.extra["rmse_rad"] if r.success else float("nan"), r.status, r.seconds)
