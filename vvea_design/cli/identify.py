"""``vvea identify`` and ``vvea diagnose``: the jobs :func:`vvea_design.jobs.identification.identify` and
:func:`~vvea_design.jobs.identification.diagnose`, their results printed.

The lead wires them into the main app with ``register(app)``.
"""

from __future__ import annotations

from pathlib import Path

import typer
from rich.table import Table

from .common import job_errors
from ..progress import console
from ..progress import out as stdout

__all__ = ["register"]

def _units(force: str | None, displacement: str | None, time: str | None, pressure: str | None,
           valve: str | None, speed: str | None) -> dict:
    """The columns given a unit on the command line (the others keep the format's)."""
    given = {"force_N": force, "displacement_mm": displacement, "time_s": time, "p2_MPa": pressure,
             "valve_deg": valve, "speed_mm_s": speed}
    return {k: v for k, v in given.items() if v is not None}


_UNIT_HELP = "unit the {} column was recorded in ({}; default {}): converted, and its scale not questioned"
FORCE_UNIT = typer.Option(None, "--force-unit", help=_UNIT_HELP.format("force_N", "N, kN, daN, mN, lbf", "N"))
DISPLACEMENT_UNIT = typer.Option(None, "--displacement-unit",
                                 help=_UNIT_HELP.format("displacement_mm", "mm, m, cm, um, in", "mm"))
TIME_UNIT = typer.Option(None, "--time-unit", help=_UNIT_HELP.format("time_s", "s, ms, us, min", "s"))
PRESSURE_UNIT = typer.Option(None, "--pressure-unit",
                             help=_UNIT_HELP.format("p2_MPa", "MPa, bar, kPa, Pa, psi", "MPa"))
VALVE_UNIT = typer.Option(None, "--valve-unit", help=_UNIT_HELP.format("valve_deg", "deg, rad", "deg"))
SPEED_UNIT = typer.Option(None, "--speed-unit", help=_UNIT_HELP.format("speed_mm_s", "mm/s, m/s, mm/min", "mm/s"))
NEGATE = typer.Option(None, "--negate", help="a column recorded with the opposite sign (force_N: compression "
                                             "positive; displacement_mm: x < 0 extending); repeat for both")

OVER_RATING = typer.Option(False, "--allow-over-rating", help="accept recordings charged above the --design unit's "
                           "rating (its max_charge_MPa); the outputs then say OVER RATING")

_DESIGN_HELP = "design JSON of the unit on the bench (its chamber areas, V1, V2 and travel shape the gas terms); default: the paper's Fig. 5 unit"


def identify_cmd(
    file: Path = typer.Argument(..., help="recordings file (CSV or Parquet, shared/specs/recordings.md)"),
    out: Path = typer.Option(Path("identification"), "--out", "-o", help="output folder"),
    design: Path = typer.Option(None, "--design", help=_DESIGN_HELP),
    force_unit: str = FORCE_UNIT, displacement_unit: str = DISPLACEMENT_UNIT, time_unit: str = TIME_UNIT,
    pressure_unit: str = PRESSURE_UNIT, valve_unit: str = VALVE_UNIT, speed_unit: str = SPEED_UNIT,
    negate: list[str] = NEGATE, allow_over_rating: bool = OVER_RATING,
) -> None:
    """Fit the paper's eq. 14 (g, C, one L per valve) with uncertainties; Table 3, Figs 10 and 11."""
    from ..jobs.identification import DesignFileError, RecordingsError, identify

    with job_errors(errors=(DesignFileError, RecordingsError)):
        summary = identify(file, design=design, out=out, negate=negate or (), allow_over_rating=allow_over_rating,
                           units=_units(force_unit, displacement_unit, time_unit, pressure_unit, valve_unit,
                                        speed_unit)).to_dict()
    t = Table(title=f"Table 3 — identified parameters of {file.name}")
    for c in ("Parameter", "Unit", "Value", "± s.e.", "Paper"):
        t.add_column(c, justify="right" if c not in ("Parameter", "Unit") else "left")
    for name, p in summary["parameters"].items():
        paper = "" if p["paper"] is None else f"{p['paper']:.2f}"
        se = "not determined" if p["std_error"] is None else f"{p['std_error']:.2f}"
        t.add_row(name, p["unit"], f"{p['value']:.2f}", se, paper)
    typer.echo("")
    stdout.print(t)
    band, paper_band = summary["error_band_pct"]["ours"], summary["error_band_pct"]["paper"]
    typer.echo(
        f"RMS error {summary['rmse_N']:.1f} N; error band {band[0]:+.1f} % ... {band[1]:+.1f} % of nominal force "
        f"(paper: {paper_band[0]:+.1f} % ... {paper_band[1]:+.1f} %)."
    )
    typer.echo(
        f"{summary['rows_read']} rows read, {summary['rows_left_out']} left out ({summary['rows_left_out_reason']}); "
        f"{summary['velocity_fallback_experiments']} experiments used the Savitzky-Golay velocity fallback."
    )
    for note in summary.get("notes", []):
        typer.echo(f"note: {note}")
    typer.echo(f"wrote {', '.join(summary['files'])} to {out}")


def diagnose_cmd(
    file: Path = typer.Argument(..., help="recordings file (CSV or Parquet)"),
    out: Path = typer.Option(Path("diagnosis"), "--out", "-o", help="output folder"),
    seed: int = typer.Option(0, help="seed of the held-out and cross-validation splits"),
    learner: bool = typer.Option(True, "--learner/--no-learner", help="run the flexible-learner check for leftover structure"),
    design: Path = typer.Option(None, "--design", help=_DESIGN_HELP),
    force_unit: str = FORCE_UNIT, displacement_unit: str = DISPLACEMENT_UNIT, time_unit: str = TIME_UNIT,
    pressure_unit: str = PRESSURE_UNIT, valve_unit: str = VALVE_UNIT, speed_unit: str = SPEED_UNIT,
    negate: list[str] = NEGATE, allow_over_rating: bool = OVER_RATING,
) -> None:
    """Locate where eq. 14 and the recordings disagree, name and fit the left-out physics, show held-out improvement."""
    from ..jobs.identification import DesignFileError, RecordingsError, diagnose

    import matplotlib

    matplotlib.use("Agg")  # the command draws into files
    with job_errors(errors=(DesignFileError, RecordingsError)):
        run = diagnose(file, design=design, seed=seed, learner=learner, out=out, negate=negate or (),
                       allow_over_rating=allow_over_rating,
                       units=_units(force_unit, displacement_unit, time_unit, pressure_unit, valve_unit, speed_unit))
    typer.echo(run.summary_text)
    console.print(f"wrote {', '.join(run.files)} to {out} ({run.report.runtime_s:.1f} s)")


def register(app: typer.Typer) -> None:
    """Add the ``identify`` and ``diagnose`` commands to ``app``.

    Parameters
    ----------
    app : typer.Typer
        The main ``vvea`` application; it is changed in place.

    Returns
    -------
    None
    """
    app.command("identify")(identify_cmd)
    app.command("diagnose")(diagnose_cmd)
