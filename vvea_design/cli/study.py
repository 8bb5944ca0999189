"""``vvea study ...`` commands: rest-to-rest sweep and safety study (thin layer over
:mod:`vvea_design.actuator`).

Wire it in with ``register(app)``.
"""

from __future__ import annotations

import json
from pathlib import Path
from typing import Optional

import typer

from .errors import INTERRUPT_REPORTED

__all__ = ["register", "study_app"]

study_app = typer.Typer(help="Actuator studies: rest-to-rest optimal control (paper §5) and safety (§6).",
                        no_args_is_help=True)


def _grid(spec: str):
    from ..actuator.rest_to_rest import GRIDS, Grid

    if spec in GRIDS:
        return spec
    # "A1,A2,...:T1,T2,..." custom grid
    try:
        a, t = spec.split(":")
        return Grid(tuple(float(x) for x in a.split(",")), tuple(float(x) for x in t.split(",")))
    except ValueError as exc:
        raise typer.BadParameter(
            f"--grid must be one of {sorted(GRIDS)} or 'A1,A2,..:T1,T2,..' (rad:s), got {spec!r} ({exc})"
        ) from exc


def _check_mesh_n(option: str, n: int, allow_off: bool = False) -> None:
    from ..plausibility import LIMITS

    if n == 0 or (allow_off and n == -1):
        return
    if n < 4 or n % 4:
        off = ", -1 = none" if allow_off else ""
        raise typer.BadParameter(f"{option} must be a multiple of 4 (>= 4; 0 = study default{off}), got {n}")
    why = LIMITS["mesh_intervals"].problem(n)
    if why:
        raise typer.BadParameter(f"{option} {why}, got {n} ({LIMITS['mesh_intervals'].why})")


def _check_limit(key: str, value, option: str) -> None:
    """typer's Invalid value (exit 2) naming ``option`` unless ``value`` lies in the toolkit's range."""
    from ..plausibility import LIMITS, PlausibilityError

    if value is None:
        return
    try:
        LIMITS[key].check(value, option, PlausibilityError)
    except PlausibilityError as exc:
        raise typer.BadParameter(str(exc)) from None


def _failed_solves(count: int, total: int, what: str, where: Path) -> None:
    """Exit 4 after the results are written when a solve failed: a failed solve never exits 0."""
    if count:
        from ..progress import print_error

        print_error(f"{count} of {total} {what} failed to solve (see the status column); the results in {where} "
                    "are written but incomplete")
        raise typer.Exit(4)


def _cases_saved(out: Path) -> int:
    """Number of complete cases in ``out/results.csv`` (0 if none)."""
    import csv

    res = out / "results.csv"
    if not res.exists():
        return 0
    from ..actuator.multistart import RESULT_COLUMNS

    by_case: dict[str, set] = {}
    settings: set = set()
    with res.open(newline="") as fh:
        for row in csv.DictReader(fh):
            if None in row or any(row.get(c) is None for c in RESULT_COLUMNS):
                continue
            by_case.setdefault(row["case_id"], set()).add(row["setting"])
            settings.add(row["setting"])
    return sum(1 for s in by_case.values() if s == settings)


@study_app.command("rest-to-rest")
def rest_to_rest(
    out: Path = typer.Option(..., "--out", "-o", help="Output folder (results.csv, summary.json, PNGs)."),
    design: Optional[Path] = typer.Option(None, "--design", help="Design JSON: adds its actuator as setting 'design'."),
    grid: str = typer.Option("paper", "--grid", help="paper | coarse | 'A1,A2:T1,T2' (rad:s)."),
    scheduler: Optional[str] = typer.Option(None, "--scheduler", help="Dask scheduler address tcp://host:port."),
    workers: Optional[int] = typer.Option(None, "--workers", help="Local worker processes (default all cores)."),
    mesh_n: int = typer.Option(0, "--mesh-n", help="Collocation intervals of the multi-start (multiple of 4; 0 = study default 64)."),
    fine_mesh_n: int = typer.Option(
        0, "--fine-mesh-n",
        help="Intervals of the mesh the results are reported on: one polish per setting from the multi-start "
             "optimum (multiple of 4; 0 = study default: 192 with the default --mesh-n, none otherwise; -1 = none)."),
    pulley_radius_m: Optional[float] = typer.Option(None, "--pulley-radius-m", help="Pulley radius r for --design (m)."),
    p2_mpa: Optional[float] = typer.Option(None, "--p2-mpa", help="Recharge the design spring to p2 (MPa)."),
    gamma_min_deg: float = typer.Option(50.0, "--gamma-min-deg", help="Lowest throttle angle used (deg)."),
    gamma_max_deg: float = typer.Option(120.0, "--gamma-max-deg", help="Highest throttle angle used (deg)."),
    restart: bool = typer.Option(False, "--restart", help="Discard existing results instead of resuming."),
    no_progress: bool = typer.Option(False, "--no-progress", help="Hide the progress bar."),
) -> None:
    """Rest-to-rest optimal control sweep for VVEA, iVVEA, SEA, LWR (+ your design).

    Resumes an interrupted sweep in the same --out folder.
    """
    from ..actuator.model import PAPER_SETTINGS, from_design_json
    from ..actuator.multistart import DEFAULT_MESH
    from ..actuator.ocp import Mesh
    from ..actuator.rest_to_rest import run_rest_to_rest
    from ..parallel import Terminated
    from ..progress import console
    from .outputs import check_out

    # every option is checked before anything is solved
    check_out(out)  # resumable: results.csv grows case by case in --out itself, so only validated up front
    _check_mesh_n("--mesh-n", mesh_n)
    _check_mesh_n("--fine-mesh-n", fine_mesh_n, allow_off=True)
    if workers is not None and workers < 1:
        raise typer.BadParameter(f"--workers must be >= 1, got {workers}")
    _check_limit("workers", workers, "--workers")
    if design is None and (pulley_radius_m is not None or p2_mpa is not None):
        raise typer.BadParameter("--pulley-radius-m and --p2-mpa apply to --design only")
    for option, g in (("--gamma-min-deg", gamma_min_deg), ("--gamma-max-deg", gamma_max_deg)):
        _check_limit("valve_deg", g, option)
    if gamma_min_deg > gamma_max_deg:
        raise typer.BadParameter(f"--gamma-min-deg ({gamma_min_deg:g}) must not exceed --gamma-max-deg "
                                 f"({gamma_max_deg:g})" + ("" if design is not None else
                                                            "; they apply to --design only"))
    _check_limit("pulley_radius_m", pulley_radius_m, "--pulley-radius-m")
    _check_limit("charge_MPa", p2_mpa, "--p2-mpa")
    if scheduler is not None:
        from ..parallel import SchedulerUnreachable, check_scheduler

        try:
            check_scheduler(scheduler)
        except SchedulerUnreachable as exc:
            raise typer.BadParameter(f"--scheduler: {exc}") from None
    grid_spec = _grid(grid)
    settings = list(PAPER_SETTINGS.values())
    if design is not None:
        if not design.exists():
            raise typer.BadParameter(f"--design: file {design} does not exist")
        kw = dict(gamma_min_deg=gamma_min_deg, gamma_max_deg=gamma_max_deg, p2_MPa=p2_mpa)
        if pulley_radius_m is not None:
            kw["pulley_radius_m"] = pulley_radius_m
        try:
            settings.append(from_design_json(design, **kw))
        except ValueError as exc:
            raise typer.BadParameter(f"--design {design}: {exc}") from exc
    mesh = DEFAULT_MESH if mesh_n == 0 else Mesh(mesh_n, DEFAULT_MESH.degree)
    fine = "auto" if fine_mesh_n == 0 else (None if fine_mesh_n < 0 else Mesh(fine_mesh_n, DEFAULT_MESH.degree))
    try:
        summary = run_rest_to_rest(out, grid=grid_spec, settings=settings, mesh=mesh, fine_mesh=fine, workers=workers,
                                   scheduler=scheduler, restart=restart, progress=not no_progress)
    except ValueError as exc:
        raise typer.BadParameter(str(exc)) from exc
    except (KeyboardInterrupt, Terminated) as exc:
        code = 130 if isinstance(exc, KeyboardInterrupt) else 143
        console.print(f"\n[bold yellow]{'interrupted' if code == 130 else 'terminated'}[/]: {_cases_saved(out)} "
                      f"finished case(s) are saved in {out / 'results.csv'}. Run the same command again to resume "
                      f"the sweep (add --restart to start over).", soft_wrap=True)
        INTERRUPT_REPORTED["done"] = True
        raise typer.Exit(code) from None
    from ..outputs import output_files
    from ..report.html import folder_report, recorded_text

    text = recorded_text(lambda c: _print_summary(summary, c))  # results to stdout, and into the report
    typer.echo(text)
    with output_files(out / "report.html", option="") as (tmp_report,):  # whole or not at all
        folder_report("vvea study rest-to-rest", out, summary_text=text, data=summary.to_dict(),
                      provenance={"grid": grid, "design": design, "mesh_n": mesh_n, "fine_mesh_n": fine_mesh_n}
                      ).write(tmp_report)
    console.print(f"wrote {out / 'results.csv'}, {out / 'summary.json'}, {out / 'best_map.png'}, "
                  f"{out / 'trajectory.png'}, {out / 'report.html'}")
    fails = summary.statistics.solver_failures
    _failed_solves(int(fails.get("count", 0)), summary.run.ocps, "optimal-control problems", out)


def _print_summary(summary, console) -> None:
    from rich.table import Table

    st = summary.statistics
    tab = Table(title="Table 5: ours (all solved cases / cases where both trajectories are valid) vs paper")
    for c in ("statistic", "ours (all)", "ours (both valid)", "paper"):
        tab.add_column(c)
    paper = st.paper_table5
    xs = list(dict.fromkeys(k.split("_vs_")[0] for k in st.pairs))
    for X in xs:
        for Y in ("SEA", "LWR"):
            a, v = st.pair(X, Y, "all"), st.pair(X, Y, "valid")
            if not a:
                continue
            fa = a.fraction_X_beats_Y
            fv = v.fraction_X_beats_Y if v else None
            pb = paper.get(f"{X}_beats_{Y}")
            tab.add_row(f"{X} beats {Y}", f"{fa:.1%}" if fa is not None else "-",
                        f"{fv:.1%}" if fv is not None else "-", f"{pb:.1%}" if pb is not None else "-")
            ra, rv = a.meanrmse_Y_over_X, v.meanrmse_Y_over_X if v else None
            pr = paper.get(f"meanrmse_{Y}_over_{X}")
            tab.add_row(f"mean rmse {Y} / {X}", f"{ra:.3f}" if ra else "-", f"{rv:.3f}" if rv else "-",
                        f"{pr:.3f}" if pr is not None else "-")
    console.print(tab)
    g = st.ivvea_vs_sea_guarantee
    if g:
        console.print(f"iVVEA worse than SEA in {g['iVVEA_worse_than_SEA_cases']} of {g['n_cases']} cases")
    console.print(f"winning starts: {json.dumps(st.winning_starts)}")
    console.print(f"solver failures: {st.solver_failures['count']}")
    unv = st.unverified
    if unv.get("count"):
        console.print(f"left out of every statistic, trajectory not reproduced by re-simulation: {unv['count']} "
                      f"({', '.join(unv['cases'][:8])}{' ...' if unv['count'] > 8 else ''})")
    else:
        console.print("every solved trajectory was reproduced by re-simulation")


@study_app.command("safety")
def safety(
    out: Path = typer.Option(..., "--out", "-o", help="Output folder (safety.json, safety_trajectories.csv, safety.png)."),
    mesh_n: int = typer.Option(200, "--mesh-n", help="Collocation intervals over the 0.5 s horizon."),
    tau_ref_nm: float = typer.Option(50.0, "--tau-ref-nm", help="Torque step height (N m)."),
    link_inertia_kgm2: float = typer.Option(1e4, "--link-inertia-kgm2", help="Link inertia M (kg m²)."),
) -> None:
    """Torque step (paper §6, Table 6): variable damping vs fixed D = 31 and D = 200."""
    import math

    from ..actuator.ocp import Mesh
    from ..actuator.safety import run_safety
    from ..progress import console
    from .outputs import check_out, out_dir

    check_out(out)
    if mesh_n < 4:
        raise typer.BadParameter(f"--mesh-n must be >= 4 intervals, got {mesh_n}")
    _check_limit("mesh_intervals", mesh_n, "--mesh-n")
    if not (math.isfinite(tau_ref_nm) and tau_ref_nm != 0):
        raise typer.BadParameter(f"--tau-ref-nm must be a non-zero torque in N m, got {tau_ref_nm}")
    _check_limit("torque_step_Nm", abs(tau_ref_nm), "|--tau-ref-nm|")
    if not (math.isfinite(link_inertia_kgm2) and link_inertia_kgm2 > 0):
        raise typer.BadParameter(f"--link-inertia-kgm2 must be > 0, got {link_inertia_kgm2}")
    _check_limit("link_inertia_kgm2", link_inertia_kgm2, "--link-inertia-kgm2")
    from rich.table import Table

    from ..report.html import recorded_text, write_folder_report

    with out_dir(out, "safety") as tmp:  # results, figure and report land together
        try:
            s = run_safety(tmp, mesh=Mesh(mesh_n, 3, grading=0.8), tau_ref_Nm=tau_ref_nm, M_kgm2=link_inertia_kgm2)
        except ValueError as exc:
            raise typer.BadParameter(str(exc)) from exc
        tab = Table(title=f"{tau_ref_nm:g} N m torque step")
        for c in ("case", "mean D (N m s/rad)", "max D", "t95 (ms)", "status"):
            tab.add_column(c)
        for c in s.cases:
            tab.add_row(c.name, f"{c.mean_D_Nms_per_rad:.1f}", f"{c.max_D_Nms_per_rad:.1f}",
                        f"{c.t95_s * 1e3:.1f}", c.status)
        text = recorded_text(lambda c: c.print(tab))
        write_folder_report("vvea study safety", tmp, summary_text=text, data=s.to_dict(), label=str(out),
                            provenance={"tau_ref_Nm": tau_ref_nm, "mesh_n": mesh_n,
                                        "link_inertia_kgm2": link_inertia_kgm2})
    typer.echo(text)
    console.print(f"wrote {out / 'safety.json'}, {out / 'safety_trajectories.csv'}, {out / 'safety.png'}, "
                  f"{out / 'report.html'}")
    _failed_solves(sum(1 for c in s.cases if not c.success), len(s.cases), "torque-step cases", out)


def register(app: typer.Typer) -> None:
    """Add the ``study`` sub-app to the main ``vvea`` app.

    Parameters
    ----------
    app : typer.Typer
        The main ``vvea`` application; it is changed in place.

    Returns
    -------
    None
    """
    app.add_typer(study_app, name="study")
