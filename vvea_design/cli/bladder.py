"""``vvea bladder design.json --out DIR``: the bladder strain check (the job
:func:`vvea_design.jobs.bladder.check_bladder`).

Wire it in with ``register(app)``; ``vvea design`` runs the same job through
:func:`vvea_design.pipeline.design_unit`.
"""

from __future__ import annotations

from pathlib import Path
from typing import Optional

import typer

__all__ = ["register", "bladder", "print_bladder"]


def print_bladder(d: dict) -> None:
    """A table of the bladder.json content on the console (stdout), then the verdict line.

    Parameters
    ----------
    d : dict
        The ``bladder.json`` content (:meth:`vvea_design.bladder.check.BladderResult.to_dict`):
        per stroke end the volume change (mm³), pressure (MPa), strains and wrinkled area
        (fractions, printed in %) and gaps (mm); the strain bound and allowable strain
        (fractions) and the verdicts.
    """
    from rich.table import Table

    from ..progress import out as console  # results to stdout

    t = Table(title=f"bladder check — {d['material']['name']}, criterion {d['criterion']['name']} "
                    f"({d['criterion']['formula']})")
    t.add_column("quantity")
    t.add_column("expanded", justify="right")
    t.add_column("compressed", justify="right")

    def row(label, key, fmt):
        t.add_row(label, *(fmt(d[key][k]) for k in ("expanded", "compressed")))

    pct = lambda v: f"{100 * v:.2f} %"  # noqa: E731
    row("volume change (mm³)", "volume_change_mm3", lambda v: f"{v:+.0f}")
    row("pressure fluid - gas (MPa)", "pressure_MPa", lambda v: f"{v:+.5f}")
    row("max principal strain (membrane)", "max_principal_strain", pct)
    row("clamp strain (membrane + bending)", "clamp_strain", pct)
    row("wrinkled area", "wrinkled_area_fraction", lambda v: f"{100 * v:.0f} %")
    row("gap to inner tube (mm)", "gap_inner_tube_mm", lambda v: "-" if v is None else f"{v:.2f}")
    row("gap to outer bore (mm)", "gap_outer_bore_mm", lambda v: "-" if v is None else f"{v:.2f}")
    console.print(t)
    ok = "[bold green]PASSES[/]" if d["passes"] else "[bold red]FAILS[/]"
    console.print(f"strain bound {100 * d['strain_bound']:.2f} % vs allowable {100 * d['allowable_strain']:.2f} % "
                  f"({'ok' if d['passes_strain'] else 'too high'}); radial room "
                  f"{'ok' if d['passes_room'] else 'the bladder touches'} -> {ok}")


def bladder(
    design_json: Path = typer.Argument(..., help="design JSON (from `vvea optimise` / `vvea design`)"),
    out: Path = typer.Option(Path("bladder_out"), "--out", "-o", help="folder for bladder.json, CSV and PNG"),
    material: Optional[str] = typer.Option(None, "--material", "-m", help="casting silicone key (default: dragon-skin-20)"),
    criterion: Optional[str] = typer.Option(None, "--criterion", "-c",
                                            help="allowable-strain criterion: cyclic (default) | static"),
    allowable: Optional[float] = typer.Option(None, "--allowable", help="allowable strain as a fraction (overrides --criterion)"),
    elements: Optional[int] = typer.Option(None, "--elements", help="finite elements along the meridian (default 96)"),
) -> None:
    """Bladder check: FE membrane strain at both stroke ends, clamp bending bound, radial room."""
    from ..jobs.bladder import BladderError, DesignFileError, check_bladder
    from ..progress import console
    from .common import job_errors

    with job_errors(errors=(DesignFileError, BladderError)):
        report = check_bladder(design_json, material=material, criterion=criterion, allowable=allowable,
                               elements=elements, out=out)
    print_bladder(report.to_dict())
    console.print(f"wrote {', '.join(str(out / f) for f in report.files.values())}")


def register(app: typer.Typer) -> None:
    """Add the ``bladder`` command to ``app``.

    Parameters
    ----------
    app : typer.Typer
        The ``vvea`` application.
    """
    app.command("bladder")(bladder)
