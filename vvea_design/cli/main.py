"""The `vvea` command line: a thin layer over the library.

Spring side (this module): ``optimise``, ``spring``, ``check``, ``pareto``,
``map`` and ``design`` (the main job, :func:`vvea_design.pipeline.design_unit`).
Other topics register their commands from their own modules (``cli/*.py``).
Results and tables go to stdout, progress and logs to stderr.
"""

from __future__ import annotations

import csv
import sys
from pathlib import Path
from typing import Optional

import typer
from rich.table import Table

from .common import fail as _fail
from .common import load_design_or_exit
from .outputs import check_out, out_dir, out_files
from ..messages import show_margin
from ..progress import console
from ..progress import out as stdout

app = typer.Typer(
    add_completion=False,
    no_args_is_help=True,
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
) -> None:
    """vvea-design: design the pneumatic spring–damper unit of a variable visco-elastic actuator."""
    import matplotlib

    matplotlib.use("Agg")  # the command line draws off-screen; the library never selects a backend


def _print_evaluation(ev, title: str) -> None:
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
    stdout.print(c)


def _optimise_to(spec: Optional[Path], seed: int, out: Path):
    from ..spring.design_file import save_design
    from ..spring.optimise import Infeasible, NoBuildableDesign, optimise
    from ..spring.plots import plot_spring, save_figure
    from ..spring.requirements import SpecError, load_requirements

    png = out.with_name(out.stem + "_force.png")
    check_out(out, "file")
    check_out(png, "file")
    try:
        req = load_requirements(spec)
    except SpecError as exc:
        _fail(str(exc))
    strain_fn = None
    if req.max_bladder_strain is not None:
        from functools import partial

        from ..bladder.check import strain_bound

        strain_fn = partial(strain_bound, material=req.bladder_material)
    try:
        res = optimise(req, seed=seed, bladder_strain_fn=strain_fn)
    except Infeasible as exc:
        _print_evaluation(exc.result.evaluation, "least-violating design")
        _fail(str(exc), code=3)
    except NoBuildableDesign as exc:
        _fail(f"{spec or 'the default requirements'}: {exc}", code=3)
    with out_files(out, png) as (tmp_json, tmp_png):  # both files whole, or neither
        save_design(tmp_json, res.evaluation, req, optimiser=res.summary())
        save_figure(plot_spring(res.design.gas_spring, extra_charges_MPa=(1.0, 2.0),
                                title=f"optimised design ({res.layout} layout): linearity "
                                      f"{100 * res.evaluation.linearity_error:.2f} %"),
                    tmp_png)
    _print_evaluation(res.evaluation, f"optimised design (seed {seed})")
    console.print(f"{res.evaluations} model evaluations in {res.seconds:.1f} s "
                  f"({res.evaluations_per_second:.0f}/s); binding: {', '.join(res.evaluation.binding()) or 'none'}")
    console.print(f"wrote {out} and {png}")
    return res, req


@app.command()
def optimise(
    out: Path = typer.Option(Path("design.json"), "--out", "-o", help="design JSON to write (a _force.png goes beside it)"),
    spec: Optional[Path] = typer.Option(None, "--spec", "-s", help="requirements TOML (default: the paper's unit)"),
    seed: int = typer.Option(0, "--seed", help="seed of the global search (same seed, same design)"),
) -> None:
    """Find the most linear spring that meets the requirements; write design.json and its force plot."""
    _optimise_to(spec, seed, out)


@app.command()
def spring(
    design: Path = typer.Argument(..., help="design JSON"),
    out: Optional[Path] = typer.Option(None, "--out", "-o", help="folder for spring.csv and spring.png (default: beside the design)"),
    p2: Optional[float] = typer.Option(None, "--p2", help="evaluate at this chamber-2 charge [MPa] (p1 from eq. 7)"),
) -> None:
    """Force curve, stiffness and linearity of a design (from its parameters alone)."""
    from ..pipeline import write_spring_files
    from ..spring.design_file import DesignFileError, spring_from_json

    check_out(out or design.parent)
    try:
        gs = spring_from_json(design)
    except DesignFileError as exc:
        _fail(str(exc))
    if p2 is not None:
        if p2 <= 0:
            _fail(f"--p2 must be > 0 MPa, got {p2}")
        gs = gs.with_pressures(p2)
    out = out or design.parent
    with out_dir(out, "spring") as tmp:
        files = {k: out / Path(v).name for k, v in write_spring_files(gs, tmp).items()}
    stdout.print(f"linearity error {100 * gs.linearity_error():.3f} % (n = {gs.n_polytropic:g}; "
                 f"{100 * gs.with_polytropic(1.4).linearity_error():.3f} % at n = 1.4), mean stiffness "
                 f"{gs.mean_stiffness_N_per_mm():.2f} N/mm at p2 = {gs.p2_MPa:.3g} MPa, "
                 f"F({gs.travel_mm:g}) = {float(gs.force_N(gs.travel_mm)):.1f} N")
    console.print(f"wrote {files['csv']} and {files['png']}")


@app.command()
def check(
    design: Path = typer.Argument(..., help="design JSON"),
    max_linearity: float = typer.Option(..., "--max-linearity", help="largest acceptable linearity error (fraction, 0.015 = 1.5 %)"),
) -> None:
    """Fail (exit 1) when a design's linearity error exceeds the limit: a regression gate."""
    from ..spring.design_file import DesignFileError
    from ..testing import LinearityRegression, check_linearity

    if not 0 < max_linearity < 1:
        _fail(f"--max-linearity is a fraction in (0, 1), got {max_linearity}")
    try:
        lin = check_linearity(design, max_linearity)
    except DesignFileError as exc:
        _fail(str(exc))
    except LinearityRegression as exc:
        stdout.print("[bold red]FAIL[/]", end=" ")
        stdout.print(str(exc), markup=False, highlight=False, soft_wrap=True)
        raise typer.Exit(1)
    stdout.print(f"[green]OK[/] {design}: linearity error {100 * lin:.3f} % <= {100 * max_linearity:.3f} %")


@app.command()
def pareto(
    axis: str = typer.Option("stiffness", "--axis", help="swept requirement: stiffness | outer_diameter | mass"),
    values: str = typer.Option(..., "--values", help="comma-separated values of the swept requirement"),
    spec: Optional[Path] = typer.Option(None, "--spec", "-s", help="requirements TOML"),
    out: Path = typer.Option(Path("pareto"), "--out", "-o", help="output folder"),
    seed: int = typer.Option(0, "--seed"),
    scheduler: Optional[str] = typer.Option(None, "--scheduler", help="Dask scheduler address (tcp://host:port)"),
) -> None:
    """Pareto front: best linearity against stiffness, outer diameter or mass (CSV + PNG)."""
    from ..spring.studies import PARETO_AXES, pareto_front, save_pareto
    from ..spring.requirements import SpecError, load_requirements

    if axis not in PARETO_AXES:
        _fail(f"--axis must be one of {sorted(PARETO_AXES)}, got {axis!r}")
    try:
        vals = [float(v) for v in values.split(",") if v.strip()]
    except ValueError:
        _fail(f"--values must be comma-separated numbers, got {values!r}")
    if not vals:
        _fail("--values is empty")
    check_out(out)
    try:
        req = load_requirements(spec)
    except SpecError as exc:
        _fail(str(exc))
    rows = pareto_front(req, axis, vals, seed=seed, scheduler=scheduler)
    with out_dir(out, "pareto") as tmp:
        csv_path, png = (out / Path(f).name for f in save_pareto(rows, axis, tmp))
    field = PARETO_AXES[axis][0]
    for r in rows:
        lin = f"{100 * r['linearity_error']:.3f} %" if r.get("feasible") else "infeasible"
        stdout.print(f"{field} = {r[field]:g}: {lin}")
    console.print(f"wrote {csv_path} and {png}")


@app.command("map")
def map_(
    design: Path = typer.Argument(..., help="design JSON (the other variables are held at its values)"),
    x: str = typer.Option("outer_diameter_mm", "--x", help="variable on the x axis"),
    y: str = typer.Option("V2_mm3", "--y", help="variable on the y axis"),
    n: int = typer.Option(61, "--n", help="grid points per axis"),
    out: Path = typer.Option(Path("map"), "--out", "-o", help="output folder"),
) -> None:
    """2-D map of linearity over any two design variables, infeasible region marked."""
    import numpy as np

    from ..spring.design_file import DesignFileError, load_requirements_from_design
    from ..spring.studies import linearity_map
    from ..spring.plots import plot_linearity_map, save_figure

    check_out(out)
    try:
        d = load_design_or_exit(design)
        req = load_requirements_from_design(design)
        m = linearity_map(d, req, x, y, n=n)
    except (DesignFileError, ValueError) as exc:
        _fail(str(exc))
    with out_dir(out, "map") as tmp:
        save_figure(plot_linearity_map(m, optimum=(getattr(d, x), getattr(d, y))), tmp / f"map_{x}_{y}.png")
        with open(tmp / f"map_{x}_{y}.csv", "w", newline="") as fh:
            w = csv.writer(fh)
            w.writerow([x, y, "linearity_error", "feasible", "most_violated"])
            for iy, yv in enumerate(m["y"]):
                for ix, xv in enumerate(m["x"]):
                    lin = m["linearity"][iy, ix]
                    w.writerow([f"{xv:.6g}", f"{yv:.6g}", "" if np.isnan(lin) else f"{lin:.6g}",
                                int(m["feasible"][iy, ix]), m["worst"][iy, ix]])
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
                                                  "(rad:s); default 4 x 4 cases over the paper's grid"),
    study_mesh_n: Optional[int] = typer.Option(None, "--study-mesh-n",
                                               help="collocation intervals of each rest-to-rest case of the actuator "
                                                    "study (default 64)"),
    safety_mesh_n: Optional[int] = typer.Option(None, "--safety-mesh-n",
                                                help="collocation intervals of the torque steps of the actuator "
                                                     "study (default 100, clustered at the step)"),
    workers: Optional[int] = typer.Option(None, "--workers", help="worker processes of the actuator study "
                                                                  "(default: all cores)"),
    study_target_k: Optional[float] = typer.Option(None, "--study-target-k",
                                                   help="joint stiffness (N m/rad) at which the actuator study "
                                                        "compares the design with an SEA (default the paper's 362)"),
) -> None:
    """The main job: optimise, spring curve, CAD, bladder check, actuator, report.html — all into one folder."""
    from ..pipeline import STEPS, design_unit
    from ..spring.optimise import Infeasible, NoBuildableDesign
    from ..spring.requirements import SpecError, load_requirements

    check_out(out)
    try:
        req = load_requirements(spec)
    except SpecError as exc:
        _fail(str(exc))

    study_options: dict = {"workers": workers}
    if study_target_k is not None:
        if not (study_target_k > 0 and study_target_k < float("inf")):
            _fail(f"--study-target-k must be a positive stiffness in N m/rad, got {study_target_k!r}")
        study_options["target_K_Nm_per_rad"] = study_target_k
    if study_grid is not None:
        from ..actuator.rest_to_rest import Grid

        try:
            a, t = study_grid.split(":")
            study_options["grid"] = Grid(tuple(float(v) for v in a.split(",")), tuple(float(v) for v in t.split(",")))
        except ValueError as exc:
            _fail(f"--study-grid must be 'A1,A2,..:T1,T2,..' (rad:s), got {study_grid!r} ({exc})")
    if study_mesh_n is not None or safety_mesh_n is not None:
        from dataclasses import replace as _replace

        from ..actuator.design_study import DESIGN_MESH, DESIGN_SAFETY_MESH

        for flag, n, key, base in (("--study-mesh-n", study_mesh_n, "mesh", DESIGN_MESH),
                                   ("--safety-mesh-n", safety_mesh_n, "safety_mesh", DESIGN_SAFETY_MESH)):
            if n is None:
                continue
            try:
                study_options[key] = _replace(base, n_intervals=n)
            except ValueError as exc:
                _fail(f"{flag}: {exc}")

    def say(step: str, i: int, n: int) -> None:
        console.print(f"[{i + 1}/{n}] {step}")

    try:
        with out_dir(out, "design") as tmp:  # the whole unit lands in `out` only when every step succeeded
            unit = design_unit(req, tmp, seed=seed, renders=renders, actuator_study=actuator_study, spec_path=spec,
                               study_options=study_options, progress=say)
    except Infeasible as exc:
        _print_evaluation(exc.result.evaluation, "least-violating design")
        _fail(str(exc), code=3)
    except NoBuildableDesign as exc:
        _fail(f"{spec or 'the default requirements'}: {exc}", code=3)
    _print_evaluation(unit.optimisation.evaluation, f"optimised design (seed {seed})")
    bl = unit.bladder
    stdout.print(f"bladder ({bl.silicone.name}): strain bound {100 * bl.strain_bound:.2f} % vs allowable "
                 f"{100 * bl.allowable_strain:.2f} %, radial room {'ok' if bl.passes_room else 'touches'} -> "
                 f"{'PASSES' if bl.passes else 'FAILS'}")
    a = unit.actuator
    stdout.print(f"actuator: K = {a.K_Nm_per_rad:.1f} N m/rad, D = {a.D_min_Nms_per_rad:.3g} ... "
                 f"{a.D_max_Nms_per_rad:.4g} N m s/rad")
    if unit.actuator_study is not None:
        st = unit.actuator_study
        stdout.print(f"actuator study damping: D = {st.damping.D_min_Nms_per_rad:.3g} ... "
                     f"{st.damping.D_max_Nms_per_rad:.4g} N m s/rad from {st.damping.source} ({st.damping.why})")
        for r in st.runs:
            stdout.print(f"[{r.label}] " + (r.charge.describe() if r.charge is not None
                                            else f"K = {r.actuator.K_Nm_per_rad:.4g} N m/rad"))
            for c in (c for c in st.comparisons if c.run == r.label):
                beats = "-" if c.fraction_design_beats is None else f"{100 * c.fraction_design_beats:.1f} %"
                ratio = "-" if c.meanrmse_other_over_design is None else f"{c.meanrmse_other_over_design:.3f}"
                stdout.print(f"[{r.label}] {c.design} vs {c.other}: better in {c.design_beats} of {c.n_cases} "
                             f"cases ({beats}), worse in {c.design_worse} (of those, {c.only_other_valid} where only "
                             f"{c.other} is valid), {c.neither_valid} neither valid; mean rmse {c.other}/design "
                             f"{ratio} over the {c.n_both_valid} cases both are valid")
    console.print("time per step: " + ", ".join(f"{k} {unit.seconds.get(k, 0.0):.1f} s" for k in STEPS))
    console.print(f"[bold green]done[/]: everything is in {out}/ (open {out / ('report.html' if 'report' in unit.files else 'unit.json')})")


from . import bladder as cli_bladder  # noqa: E402
from . import cad as cli_cad  # noqa: E402
from . import identify as cli_identify  # noqa: E402
from . import study as cli_study  # noqa: E402  (topic modules register their commands)

for _module in (cli_cad, cli_bladder, cli_identify, cli_study):
    _module.register(app)


def main() -> None:
    """Run the ``vvea`` command (the console-script entry point); Ctrl-C exits 130 with a message."""
    try:
        app()
    except KeyboardInterrupt:  # pragma: no cover
        console.print("interrupted")
        sys.exit(130)


__all__ = ["app", "main"]
