"""``vvea study ...`` commands: rest-to-rest sweep and safety study (the jobs
:func:`vvea_design.jobs.studies.run_rest_to_rest` and :func:`~vvea_design.jobs.studies.run_safety`).

Wire it in with ``register(app)``.
"""

from __future__ import annotations

from pathlib import Path
from typing import Optional

import typer

from .errors import INTERRUPT_REPORTED

__all__ = ["register", "study_app"]

study_app = typer.Typer(help="Actuator studies: rest-to-rest optimal control (paper §5) and safety (§6).",
                        no_args_is_help=True)


def _failed_solves(count: int, total: int, what: str, where: Path) -> None:
    """Exit 4 after the results are written when a solve failed: a failed solve never exits 0."""
    if count:
        from ..progress import print_error

        print_error(f"{count} of {total} {what} failed to solve (see the status column); the results in {where} "
                    "are written but incomplete")
        raise typer.Exit(4)


def _check_mesh_n(option: str, n: int, allow_off: bool = False) -> None:
    if n == 0 or (allow_off and n == -1):
        return
    if n < 4 or n % 4:
        off = ", -1 = none" if allow_off else ""
        raise typer.BadParameter(f"{option} must be a multiple of 4 (>= 4; 0 = study default{off}), got {n}")


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
    gamma_min_deg: Optional[float] = typer.Option(None, "--gamma-min-deg",
                                                  help="Lowest throttle angle used (deg; default: the mapping's 50)."),
    gamma_max_deg: Optional[float] = typer.Option(None, "--gamma-max-deg",
                                                  help="Highest throttle angle used (deg; default: the mapping's 120)."),
    restart: bool = typer.Option(False, "--restart", help="Discard existing results instead of resuming."),
    no_progress: bool = typer.Option(False, "--no-progress", help="Hide the progress bar."),
) -> None:
    """Rest-to-rest optimal control sweep for VVEA, iVVEA, SEA, LWR (+ your design).

    Resumes an interrupted sweep in the same --out folder.
    """
    from ..jobs.studies import Terminated, cases_saved, run_rest_to_rest
    from ..progress import console
    from .common import job_errors

    # every option is checked before anything is solved
    _check_mesh_n("--mesh-n", mesh_n)
    _check_mesh_n("--fine-mesh-n", fine_mesh_n, allow_off=True)
    if workers is not None and workers < 1:
        raise typer.BadParameter(f"--workers must be >= 1, got {workers}")
    if design is None and (pulley_radius_m is not None or p2_mpa is not None):
        raise typer.BadParameter("--pulley-radius-m and --p2-mpa apply to --design only")
    # the gamma range is checked with or without --design (the job says they apply to a design only)
    mapping = dict(pulley_radius_m=pulley_radius_m, p2_MPa=p2_mpa, gamma_min_deg=gamma_min_deg,
                   gamma_max_deg=gamma_max_deg)
    try:
        with job_errors({"p2_MPa": "--p2-mpa"}, bad_parameter=True, errors=(ValueError,)):
            run = run_rest_to_rest(out, grid=grid, design=design, **mapping, mesh_n=mesh_n or None,
                                   fine_mesh_n={0: "auto", -1: None}.get(fine_mesh_n, fine_mesh_n),
                                   workers=workers, scheduler=scheduler, restart=restart, progress=not no_progress)
    except (KeyboardInterrupt, Terminated) as exc:
        code = 130 if isinstance(exc, KeyboardInterrupt) else 143
        what = "interrupted (Ctrl-C)" if code == 130 else "terminated (SIGTERM): the sweep is interrupted"
        console.print(f"\n[bold yellow]{what}[/]: {cases_saved(out)} "
                      f"finished case(s) are saved in {out / 'results.csv'}. Run the same command again to resume "
                      f"the sweep (add --restart to start over).", soft_wrap=True)
        INTERRUPT_REPORTED["done"] = True
        raise typer.Exit(code) from None
    typer.echo(run.summary_text)
    console.print(f"wrote {', '.join(str(f) for f in run.files.values())}")
    _failed_solves(run.solver_failures, run.summary.run.ocps, "optimal-control problems", out)


@study_app.command("safety")
def safety(
    out: Path = typer.Option(..., "--out", "-o", help="Output folder (safety.json, safety_trajectories.csv, safety.png)."),
    mesh_n: Optional[int] = typer.Option(None, "--mesh-n", help="Collocation intervals over the 0.5 s horizon "
                                                               "(default: the study's 200)."),
    tau_ref_nm: Optional[float] = typer.Option(None, "--tau-ref-nm", help="Torque step height (N m; default: the "
                                                                          "paper's 50)."),
    link_inertia_kgm2: Optional[float] = typer.Option(None, "--link-inertia-kgm2",
                                                      help="Link inertia M (kg m²; default: the paper's 1e4)."),
) -> None:
    """Torque step (paper §6, Table 6): variable damping vs fixed D = 31 and D = 200."""
    from ..jobs.studies import run_safety
    from ..progress import console
    from .common import job_errors

    with job_errors({"tau_ref_Nm": "--tau-ref-nm", "M_kgm2": "--link-inertia-kgm2"}, bad_parameter=True,
                    errors=(ValueError,)):
        run = run_safety(out, mesh_n=mesh_n, tau_ref_Nm=tau_ref_nm, M_kgm2=link_inertia_kgm2)
    typer.echo(run.summary_text)
    console.print(f"wrote {', '.join(str(f) for f in run.files.values())}")
    _failed_solves(run.solver_failures, len(run.study.cases), "torque-step cases", out)


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
