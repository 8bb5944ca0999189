"""The `vvea` command line: each command parses its options, calls one job and prints its result.

Spring side (this module): ``optimise``, ``spring``, ``check``, ``pareto``,
``map`` (the jobs of :mod:`vvea_design.jobs.spring`) and ``design`` (the main
job, :func:`vvea_design.pipeline.design_unit`). Other topics register their
commands from their own modules (``cli/*.py``). Results and tables go to
stdout, progress and logs to stderr.
"""

from __future__ import annotations

import sys
from pathlib import Path
from typing import Optional

import typer
from rich.table import Table

from .common import fail as _fail
from .common import job_errors
from .errors import VveaGroup, set_debug, strip_debug
from .outputs import check_out, out_dir
from ..messages import show_margin
from ..progress import console
from ..progress import out as stdout

app = typer.Typer(
    cls=VveaGroup,  # every command: one-line errors, the documented exit codes, --debug for traces (cli/errors.py)
    add_completion=False,
    no_args_is_help=True,
    pretty_exceptions_enable=False,
    help="vvea-design: design the pneumatic spring–damper unit of a variable visco-elastic actuator.",
)

out_console = stdout  # results and tables on stdout; progress and logs on stderr (``console``)


def _version(value: bool) -> None:
    if value:
        from .. import __version__

        stdout.print(f"vvea-design {__version__}", highlight=False)
        raise typer.Exit()


@app.callback()
def _root(
    version: bool = typer.Option(False, "--version", "-V", callback=_version, is_eager=True,
                                 help="print the version and exit"),
    debug: bool = typer.Option(False, "--debug", help="show the full trace of an unexpected error"),
) -> None:
    """vvea-design: design the pneumatic spring–damper unit of a variable visco-elastic actuator.

    Exit codes: 0 done, 1 a check failed (or an internal error), 2 bad input, 3 infeasible requirements,
    4 a computation failed, 130 interrupted, 143 terminated.
    """
    import matplotlib

    set_debug(debug)
    matplotlib.use("Agg")  # the command line draws off-screen; the library never selects a backend


def _print_evaluation(ev, title: str, bounds=()) -> None:
    perf = ev.performance()
    t = Table(title=title, show_header=True)
    t.add_column("quantity")
    t.add_column("value", justify="right")
    t.add_row("layout", str(perf["layout"]))
    for key in ("linearity_error", "linearity_error_isothermal", "linearity_error_adiabatic", "mean_stiffness_N_per_mm",
                "max_force_N", "mass_g", "peak_pressure_MPa", "p1_MPa", "housing_length_mm"):
        v = perf[key]
        t.add_row(key, f"{100 * v:.3f} %" if key.startswith("linearity_error") else f"{v:.4g}")
    for name in ("piston_diameter_mm", "outer_diameter_mm", "V1_mm3", "V2_mm3", "V2_top_mm3", "V1_annulus_mm3", "A1_mm2", "A2_mm2"):
        t.add_row(name, f"{getattr(ev.design, name):.5g}")
    for wall, t_mm in ev.design.walls_mm().items():
        t.add_row(f"wall {wall} [mm]", f"{t_mm:.3g}")
    stdout.print(t)
    c = Table(title="constraints (margin > 0 = satisfied)")
    c.add_column("constraint")
    c.add_column("value", justify="right")
    c.add_column("limit", justify="right")
    c.add_column("margin", justify="right")
    for name, m in ev.margins.items():
        d = ev.details[name]
        style = "red" if m < -1e-9 else ("yellow" if m < 1e-3 else "green")
        rel = "<=" if d["kind"] == "max" else ">="
        c.add_row(name, f"{show_margin(d['value'])} {d['unit']}", f"{rel} {float(d['limit']):.4g}",
                  f"[{style}]{show_margin(m, '+.4f')}[/]")  # round-off of a binding constraint reads 0
    for b in bounds:  # a search bound the optimum sits on limits it like a constraint
        c.add_row(f"{b['name']} [search bound]", f"{b['value']:.6g}",
                  f"{'<=' if b['end'] == 'high' else '>='} {b['bound']:.6g}", "[yellow]0[/]")
    stdout.print(c)


def _say_bounds(bounds) -> None:
    """One line per search bound the optimum sits on: it limits the design; say how to lift it."""
    for b in bounds:
        console.print(f"note: {b['variable']} = {b['value']:.6g} sits on the {b['end']} end of its search bound "
                      f"({b['bound']:.6g}): the bound limits the optimum like a constraint; widen [bounds] "
                      f"{b['variable']} in the requirements file (or leave it out: the default follows the envelope)",
                      soft_wrap=True, markup=False, highlight=False)


def _infeasible(exc, spec: Optional[Path]) -> None:
    """Exit 3 for requirements no design meets: the least-violating design's table, then why."""
    from ..jobs.spring import Infeasible

    if isinstance(exc, Infeasible):
        _print_evaluation(exc.result.evaluation, "least-violating design", exc.result.binding_bounds)
    _fail(f"{spec or 'the default requirements'}: {exc}", code=3)  # the file whose fields the message names


@app.command()
def optimise(
    out: Path = typer.Option(Path("design.json"), "--out", "-o", help="design JSON to write (a _force.png goes beside it)"),
    spec: Optional[Path] = typer.Option(None, "--spec", "-s", help="requirements TOML (default: the paper's unit)"),
    seed: int = typer.Option(0, "--seed", help="seed of the global search (same seed, same design)"),
) -> None:
    """Find the most linear spring that meets the requirements; write design.json and its force plot."""
    from ..jobs.spring import Infeasible, NoBuildableDesign, SpecError, force_plot_path
    from ..jobs.spring import optimise as optimise_job

    try:
        with job_errors(errors=(SpecError,)):
            res = optimise_job(spec, seed=seed, out=out)
    except (Infeasible, NoBuildableDesign) as exc:
        _infeasible(exc, spec)
    _print_evaluation(res.evaluation, f"optimised design (seed {seed})", res.binding_bounds)
    console.print(f"{res.evaluations} model evaluations in {res.seconds:.1f} s "
                  f"({res.evaluations_per_second:.0f}/s); binding: {', '.join(res.binding()) or 'none'}")
    _say_bounds(res.binding_bounds)
    console.print(f"wrote {out} and {force_plot_path(out)}")


@app.command()
def spring(
    design: Path = typer.Argument(..., help="design JSON"),
    out: Optional[Path] = typer.Option(None, "--out", "-o", help="folder for spring.csv and spring.png (default: beside the design)"),
    p2: Optional[float] = typer.Option(None, "--p2", help="evaluate at this chamber-2 charge [MPa] (p1 from eq. 7)"),
    allow_over_rating: bool = typer.Option(False, "--allow-over-rating",
                                           help="accept a --p2 above the design's rating (its max_charge_MPa); "
                                                "every output is then labelled OVER RATING"),
) -> None:
    """Force curve, stiffness and linearity of a design (rebuilt from its decision variables)."""
    from ..jobs.spring import DesignFileError, spring_report

    with job_errors({"p2_MPa": "--p2", "allow_over_rating": "--allow-over-rating"}, errors=(DesignFileError,)):
        rep = spring_report(design, p2_MPa=p2, allow_over_rating=allow_over_rating, out=out or design.parent)
    gs = rep.spring
    if rep.over_rating:
        console.print(f"warning: {rep.over_rating}", markup=False, highlight=False, soft_wrap=True)
    stdout.print(("OVER RATING: " if rep.over_rating else "")
                 + f"linearity error {100 * rep.linearity_error:.3f} % (n = {gs.n_polytropic:g}; "
                 f"{100 * rep.linearity_error_adiabatic:.3f} % at n = 1.4), mean stiffness "
                 f"{rep.mean_stiffness_N_per_mm:.2f} N/mm at p2 = {gs.p2_MPa:.3g} MPa, "
                 f"F({gs.travel_mm:g}) = {rep.force_at_travel_N:.1f} N")
    console.print(f"wrote {rep.files['csv']} and {rep.files['png']}")


@app.command()
def check(
    design: Path = typer.Argument(..., help="design JSON"),
    max_linearity: float = typer.Option(..., "--max-linearity", help="largest acceptable linearity error (fraction, 0.015 = 1.5 %)"),
) -> None:
    """Fail (exit 1) when a design's linearity error exceeds the limit: a regression gate."""
    from ..jobs.spring import DesignFileError, check_design

    with job_errors(errors=(DesignFileError,)):
        res = check_design(design, max_linearity)
    if not res.passes:
        stdout.print("[bold red]FAIL[/]", end=" ")
        stdout.print(res.message, markup=False, highlight=False, soft_wrap=True)
        raise typer.Exit(1)
    stdout.print(f"[green]OK[/] {design}: linearity error {100 * res.linearity_error:.3f} % <= {100 * max_linearity:.3f} %")


@app.command()
def pareto(
    axis: str = typer.Option("stiffness", "--axis", help="swept requirement: stiffness | outer_diameter | mass | adiabatic"),
    values: str = typer.Option(..., "--values", help="comma-separated values of the swept requirement"),
    spec: Optional[Path] = typer.Option(None, "--spec", "-s", help="requirements TOML"),
    out: Path = typer.Option(Path("pareto"), "--out", "-o", help="output folder"),
    seed: int = typer.Option(0, "--seed"),
    scheduler: Optional[str] = typer.Option(None, "--scheduler", help="Dask scheduler address (tcp://host:port)"),
) -> None:
    """Pareto front: best linearity against stiffness, outer diameter or mass (CSV + PNG)."""
    from ..jobs.spring import SpecError, pareto_front

    try:
        vals = [float(v) for v in values.split(",") if v.strip()]
    except ValueError:
        _fail(f"--values must be comma-separated numbers, got {values!r}")
    with job_errors(errors=(SpecError,)):  # a value its requirement cannot take: --values, named by the job
        front = pareto_front(axis, vals, requirements=spec, seed=seed, scheduler=scheduler, out=out)
    for p in front.points:
        lin = f"{100 * p.linearity_error:.3f} %" if p.feasible else "infeasible"
        stdout.print(f"{front.swept} = {p.value:g}: {lin}")
    console.print(f"wrote {front.files['csv']} and {front.files['png']}")


@app.command("map")
def map_(
    design: Path = typer.Argument(..., help="design JSON (the other variables are held at its values)"),
    x: str = typer.Option("outer_diameter_mm", "--x", help="variable on the x axis"),
    y: str = typer.Option("V2_mm3", "--y", help="variable on the y axis"),
    n: int = typer.Option(61, "--n", help="grid points per axis"),
    out: Path = typer.Option(Path("map"), "--out", "-o", help="output folder"),
) -> None:
    """2-D map of linearity over any two design variables, infeasible region marked."""
    from ..jobs.spring import linearity_map

    with job_errors(errors=(ValueError,)):  # a bad design file, or a variable of another layout
        linearity_map(design, x=x, y=y, n=n, out=out)
    console.print(f"wrote {out / f'map_{x}_{y}.png'} and .csv")


@app.command()
def design(
    out: Path = typer.Option(Path("vvea_out"), "--out", "-o", help="folder for everything"),
    spec: Optional[Path] = typer.Option(None, "--spec", "-s", help="requirements TOML (default: the paper's unit)"),
    seed: int = typer.Option(0, "--seed", help="seed of the global search (same seed, same design)"),
    renders: bool = typer.Option(True, "--renders/--no-renders", help="make the CAD PNG renders"),
    actuator_study: bool = typer.Option(True, "--actuator-study/--no-actuator-study",
                                        help="run the design's own actuator study (rest-to-rest vs VVEA, SEA, LWR; "
                                             "torque step)"),
    study_grid: Optional[str] = typer.Option(None, "--study-grid",
                                             help="rest-to-rest grid of the actuator study: 'A1,A2,..:T1,T2,..' "
                                                  "(rad:s); default 3 x 3 cases over the paper's grid"),
    study_mesh_n: Optional[int] = typer.Option(None, "--study-mesh-n",
                                               help="collocation intervals of each rest-to-rest case of the actuator "
                                                    "study (default 64)"),
    safety_mesh_n: Optional[int] = typer.Option(None, "--safety-mesh-n",
                                                help="collocation intervals of the torque steps of the actuator "
                                                     "study (default 100, clustered at the step)"),
    workers: Optional[int] = typer.Option(None, "--workers", help="worker processes of the actuator study, which runs beside the CAD "
                                                                  "(default: all cores but one, at least 1)"),
    study_target_k: Optional[float] = typer.Option(None, "--study-target-k",
                                                   help="joint stiffness (N m/rad) at which the actuator study "
                                                        "compares the design with an SEA (default the paper's 362)"),
) -> None:
    """The main job: optimise, spring curve, CAD, bladder check, actuator, report.html — all into one folder."""
    from ..jobs.spring import Infeasible, NoBuildableDesign, SpecError
    from ..jobs.studies import design_study_lines
    from ..pipeline import STEPS, design_unit

    def say(step: str, i: int, n: int) -> None:
        console.print(f"[{i + 1}/{n}] {step}")

    check_out(out)
    try:
        with (job_errors({"study_target_K_Nm_per_rad": "--study-target-k"}, errors=(SpecError,)),
              out_dir(out, "design") as tmp):  # the unit lands whole, or not at all
            unit = design_unit(spec, tmp, seed=seed, renders=renders, actuator_study=actuator_study,
                               study_grid=study_grid, study_mesh_n=study_mesh_n, safety_mesh_n=safety_mesh_n,
                               workers=workers, study_target_K_Nm_per_rad=study_target_k, progress=say)
    except (Infeasible, NoBuildableDesign) as exc:
        _infeasible(exc, spec)
    _print_evaluation(unit.optimisation.evaluation, f"optimised design (seed {seed})",
                      unit.optimisation.binding_bounds)
    _say_bounds(unit.optimisation.binding_bounds)
    bl = unit.bladder
    stdout.print(f"bladder ({bl.silicone.name}): strain bound {100 * bl.strain_bound:.2f} % vs allowable "
                 f"{100 * bl.allowable_strain:.2f} %, radial room {'ok' if bl.passes_room else 'touches'} -> "
                 f"{'PASSES' if bl.passes else 'FAILS'}")
    fe = unit.structure
    if fe is not None:
        stdout.print(f"strength (FE, {fe.criterion} peak / yield): " + ", ".join(
            f"{w.wall} {w.governing.safety:.2f} (>= {w.governing.required_safety:g}, {w.governing.case})"
            for w in fe.walls) + f" -> {'PASSES' if fe.passes else 'FAILS'}", markup=False, highlight=False)
    if unit.cad_manifest is not None and unit.cad_manifest.assembly_passes is not None:
        stdout.print("assembly (in order along the axis; no O-ring over a thread or a sharp edge, ISO 3601-2) -> "
                     f"{'PASSES' if unit.cad_manifest.assembly_passes else 'FAILS'}", markup=False, highlight=False)
    if unit.cad_manifest is not None:
        open_paths = unit.cad_manifest.unsealed_paths
        stdout.print("seals (every joint and port, the CAD's leak audit) -> " + (
            "PASSES" if not open_paths else "FAILS, not sealed: " + "; ".join(open_paths)), markup=False,
            highlight=False)
    a = unit.actuator
    stdout.print(f"actuator: K = {a.K_Nm_per_rad:.1f} N m/rad, D = {a.D_min_Nms_per_rad:.3g} ... "
                 f"{a.D_max_Nms_per_rad:.4g} N m s/rad")
    if unit.actuator_study is not None:
        for line in design_study_lines(unit.actuator_study):  # '[equal stiffness]' is a label, not rich markup
            stdout.print(line, markup=False, highlight=False, soft_wrap=True)
    console.print("time per step: " + ", ".join(f"{k} {unit.seconds.get(k, 0.0):.1f} s" for k in STEPS))
    console.print(f"[bold green]done[/]: everything is in {out}/ (open {out / ('report.html' if 'report' in unit.files else 'unit.json')})")


from . import bladder as cli_bladder  # noqa: E402
from . import cad as cli_cad  # noqa: E402
from . import identify as cli_identify  # noqa: E402
from . import study as cli_study  # noqa: E402  (topic modules register their commands)

for _module in (cli_cad, cli_bladder, cli_identify, cli_study):
    _module.register(app)


def main() -> None:
    """Run the ``vvea`` command (the console-script entry point); exit codes and messages: :mod:`vvea_design.cli.errors`."""
    argv = strip_debug(sys.argv[1:])  # --debug anywhere on the line
    try:
        app(args=argv, prog_name="vvea")
    except KeyboardInterrupt:  # pragma: no cover - outside a command (while parsing)
        console.print("interrupted (Ctrl-C)")
        sys.exit(130)


__all__ = ["app", "main"]
