"""The `vvea` command line: a thin layer over the library.

Spring side (this module): ``optimise``, ``spring``, ``check``, ``pareto``,
``map`` and ``design`` (the main job: everything into one folder). Other
topics register their commands from their own modules (``cli_*.py``).
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
from ..progress import console

app = typer.Typer(
    add_completion=False,
    no_args_is_help=True,
    help="vvea-design: design the pneumatic spring–damper unit of a variable visco-elastic actuator.",
)

out_console = console  # status and tables on stderr; data files on disk


def _print_evaluation(ev, title: str) -> None:
    perf = ev.performance()
    t = Table(title=title, show_header=True)
    t.add_column("quantity")
    t.add_column("value", justify="right")
    for key in ("linearity_error", "mean_stiffness_N_per_mm", "max_force_N", "mass_g", "peak_pressure_MPa",
                "p1_MPa", "housing_length_mm"):
        v = perf[key]
        t.add_row(key, f"{100 * v:.3f} %" if key == "linearity_error" else f"{v:.4g}")
    for name in ("piston_diameter_mm", "outer_diameter_mm", "V1_mm3", "V2_mm3", "A1_mm2", "A2_mm2"):
        t.add_row(name, f"{getattr(ev.design, name):.5g}")
    console.print(t)
    c = Table(title="constraints (margin > 0 = satisfied)")
    c.add_column("constraint")
    c.add_column("value", justify="right")
    c.add_column("limit", justify="right")
    c.add_column("margin", justify="right")
    for name, m in ev.margins.items():
        d = ev.details[name]
        style = "red" if m < -1e-9 else ("yellow" if m < 1e-3 else "green")
        rel = "<=" if d["kind"] == "max" else ">="
        c.add_row(name, f"{float(d['value']):.4g} {d['unit']}", f"{rel} {float(d['limit']):.4g}", f"[{style}]{m:+.4f}[/]")
    console.print(c)


def _optimise_to(spec: Optional[Path], seed: int, out: Path):
    from ..spring.design_file import save_design
    from ..spring.optimise import Infeasible, NoBuildableDesign, optimise
    from ..spring.plots import plot_spring
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
        plot_spring(res.design.gas_spring, tmp_png, extra_charges_MPa=(1.0, 2.0),
                    title=f"optimised design: linearity {100 * res.evaluation.linearity_error:.2f} %")
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


def _write_spring(gs, folder: Path) -> Path:
    """spring.csv and spring.png of ``gs`` into ``folder``; return the PNG path."""
    from ..spring.plots import plot_spring

    x = gs.x_mm(81)
    F = gs.force_N(x)
    k = gs.stiffness_N_per_mm(x)
    P1, P2 = gs.pressures_MPa(x)
    with open(folder / "spring.csv", "w", newline="") as fh:
        w = csv.writer(fh)
        w.writerow(["x_mm", "force_N", "stiffness_N_per_mm", "P1_MPa", "P2_MPa"])
        for row in zip(x, F, k, P1, P2):
            w.writerow([f"{v:.6g}" for v in row])
    return plot_spring(gs, folder / "spring.png", extra_charges_MPa=(1.0, 2.0, 4.0))


@app.command()
def spring(
    design: Path = typer.Argument(..., help="design JSON"),
    out: Optional[Path] = typer.Option(None, "--out", "-o", help="folder for spring.csv and spring.png (default: beside the design)"),
    p2: Optional[float] = typer.Option(None, "--p2", help="evaluate at this chamber-2 charge [MPa] (p1 from eq. 7)"),
) -> None:
    """Force curve, stiffness and linearity of a design (from its parameters alone)."""
    from ..spring.design_file import DesignFileError, spring_from_json
    from ..spring.gas_spring import linearity_error, mean_stiffness_N_per_mm

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
        png = _write_spring(gs, tmp)
    png = out / png.name
    xf = gs.x_mm(401)
    Ff = gs.force_N(xf)
    console.print(f"linearity error {100 * float(linearity_error(xf, Ff)):.3f} %, mean stiffness "
                  f"{float(mean_stiffness_N_per_mm(xf, Ff)):.2f} N/mm at p2 = {gs.p2_MPa:.3g} MPa, "
                  f"F({gs.travel_mm:g}) = {float(Ff[-1]):.1f} N")
    console.print(f"wrote {out / 'spring.csv'} and {png}")


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
        console.print("[bold red]FAIL[/]", end=" ")
        console.print(str(exc), markup=False, highlight=False, soft_wrap=True)
        raise typer.Exit(1)
    console.print(f"[green]OK[/] {design}: linearity error {100 * lin:.3f} % <= {100 * max_linearity:.3f} %")


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
    from ..spring.optimise import PARETO_AXES, pareto_front, save_pareto
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
        console.print(f"{field} = {r[field]:g}: {lin}")
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
    from ..spring.optimise import linearity_map
    from ..spring.plots import plot_linearity_map

    check_out(out)
    try:
        d = load_design_or_exit(design)
        req = load_requirements_from_design(design)
        m = linearity_map(d, req, x, y, n=n)
    except (DesignFileError, ValueError) as exc:
        _fail(str(exc))
    with out_dir(out, "map") as tmp:
        plot_linearity_map(m, tmp / f"map_{x}_{y}.png", optimum=(getattr(d, x), getattr(d, y)))
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
    seed: int = typer.Option(0, "--seed"),
    renders: bool = typer.Option(True, "--renders/--no-renders", help="make the CAD PNG renders"),
) -> None:
    """The main job: optimise, then spring curve, CAD and bladder check, all into one folder."""
    with out_dir(out, "design") as tmp:  # the whole job lands in `out` only when every step succeeded
        design_json = tmp / "design.json"
        _optimise_to(spec, seed, design_json)
        for step in DESIGN_STEPS:
            step(design_json, tmp, renders)
    console.print(f"[bold green]done[/]: everything is in {out}/")


def _step_spring(design_json: Path, out: Path, renders: bool) -> None:
    spring(design_json, out=out / "spring", p2=None)


from . import bladder as cli_bladder  # noqa: E402
from . import cad as cli_cad  # noqa: E402
from . import identify as cli_identify  # noqa: E402
from . import study as cli_study  # noqa: E402  (topic modules register their commands)

for _module in (cli_cad, cli_bladder, cli_identify, cli_study):
    _module.register(app)

#: Steps of ``vvea design`` after the optimisation: f(design_json, out_dir, renders).
DESIGN_STEPS = [_step_spring, cli_cad.design_step, cli_bladder.design_step]


def main() -> None:  # console-script entry point
    try:
        app()
    except KeyboardInterrupt:  # pragma: no cover
        console.print("interrupted")
        sys.exit(130)


__all__ = ["app", "main", "DESIGN_STEPS"]
