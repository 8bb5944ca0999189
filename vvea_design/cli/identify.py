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

_DESIGN_HELP = "design JSON of the unit on the bench (its chamber areas, V1, V2 and travel shape the gas terms); default: the paper's Fig. 5 unit"


def identify_cmd(
    file: Path = typer.Argument(..., help="recordings file (CSV or Parquet, shared/specs/recordings.md)"),
    out: Path = typer.Option(Path("identification"), "--out", "-o", help="output folder"),
    design: Path = typer.Option(None, "--design", help=_DESIGN_HELP),
) -> None:
    """Fit the paper's eq. 14 (g, C, one L per valve) with uncertainties; Table 3, Figs 10 and 11."""
    from ..jobs.identification import DesignFileError, RecordingsError, identify

    with job_errors(errors=(DesignFileError, RecordingsError)):
        summary = identify(file, design=design, out=out).to_dict()
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
) -> None:
    """Locate where eq. 14 and the recordings disagree, name and fit the left-out physics, show held-out improvement."""
    from ..jobs.identification import DesignFileError, RecordingsError, diagnose

    import matplotlib

    matplotlib.use("Agg")  # the command draws into files
    with job_errors(errors=(DesignFileError, RecordingsError)):
        run = diagnose(file, design=design, seed=seed, learner=learner, out=out)
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
