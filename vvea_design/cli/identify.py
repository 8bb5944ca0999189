"""``vvea identify`` and ``vvea diagnose``: thin commands over the library.

The lead wires them into the main app with ``register(app)``.
"""

from __future__ import annotations

from pathlib import Path

import typer
from rich.table import Table

from .common import fail
from .outputs import check_out, out_dir
from ..progress import console, progress_bar

__all__ = ["register"]


def _read(file: Path):
    from ..identification.recordings import RecordingsError, read_recordings

    try:
        with progress_bar(f"reading {file.name} (velocity from the motion profile)", total=None):
            return read_recordings(file)
    except RecordingsError as exc:
        fail(str(exc))


def identify_cmd(
    file: Path = typer.Argument(..., help="recordings file (CSV or Parquet, shared/specs/recordings.md)"),
    out: Path = typer.Option(Path("identification"), "--out", help="output folder"),
) -> None:
    """Fit the paper's eq. 14 (g, C, one L per valve) with uncertainties; Table 3, Figs 10 and 11."""
    from ..identification.identify import PAPER_ERROR_BAND_PCT, write_identification

    check_out(out)
    rec = _read(file)
    with progress_bar("fitting eq. 14 and drawing Figs 10/11", total=None), out_dir(out, "identify") as tmp:
        summary = write_identification(rec, tmp)
    t = Table(title=f"Table 3 — identified parameters of {file.name}")
    for c in ("Parameter", "Unit", "Value", "± s.e.", "Paper"):
        t.add_column(c, justify="right" if c not in ("Parameter", "Unit") else "left")
    for name, p in summary["parameters"].items():
        paper = "" if p["paper"] is None else f"{p['paper']:.2f}"
        t.add_row(name, p["unit"], f"{p['value']:.2f}", f"{p['std_error']:.2f}", paper)
    typer.echo("")
    console.print(t)
    band = summary["error_band_pct"]["ours"]
    typer.echo(
        f"RMS error {summary['rmse_N']:.1f} N; error band {band[0]:+.1f} % ... {band[1]:+.1f} % of nominal force "
        f"(paper: {PAPER_ERROR_BAND_PCT[0]:+.1f} % ... {PAPER_ERROR_BAND_PCT[1]:+.1f} %)."
    )
    typer.echo(
        f"{summary['rows_read']} rows read, {summary['rows_left_out']} left out ({summary['rows_left_out_reason']}); "
        f"{summary['velocity_fallback_experiments']} experiments used the Savitzky-Golay velocity fallback."
    )
    typer.echo(f"wrote {', '.join(summary['files'])} to {out}")


def diagnose_cmd(
    file: Path = typer.Argument(..., help="recordings file (CSV or Parquet)"),
    out: Path = typer.Option(Path("diagnosis"), "--out", help="output folder"),
    seed: int = typer.Option(0, help="seed of the held-out and cross-validation splits"),
    learner: bool = typer.Option(True, "--learner/--no-learner", help="run the flexible-learner check for leftover structure"),
) -> None:
    """Locate where eq. 14 and the recordings disagree, name and fit the left-out physics, show held-out improvement."""
    from ..identification.diagnose import DiagnoseSettings, diagnose, format_summary, write_diagnosis

    check_out(out)
    rec = _read(file)
    msgs = []
    from rich.progress import Progress, SpinnerColumn, TextColumn, TimeElapsedColumn

    with Progress(SpinnerColumn(), TextColumn("[bold]{task.description}"), TimeElapsedColumn(), console=console) as prog:
        task = prog.add_task("diagnosing", total=None)

        def say(msg: str) -> None:
            msgs.append(msg)
            prog.update(task, description=f"diagnosing: {msg}")

        diag = diagnose(rec, DiagnoseSettings(seed=seed, learner=learner), progress=say)
        with out_dir(out, "diagnose") as tmp:
            files = write_diagnosis(diag, tmp)
    typer.echo(format_summary(diag.report))
    typer.echo(f"wrote {', '.join(files)} to {out} ({diag.report['runtime_s']:.1f} s)")


def register(app: typer.Typer) -> None:
    """Add the ``identify`` and ``diagnose`` commands to ``app``."""
    app.command("identify")(identify_cmd)
    app.command("diagnose")(diagnose_cmd)
