"""``vvea cad design.json --out DIR``: the CAD set (the job :func:`vvea_design.jobs.cad.build_cad`).

Wire it in with ``register(app)``; ``vvea design`` runs the same job through
:func:`vvea_design.pipeline.design_unit`.
"""

from __future__ import annotations

from pathlib import Path
from typing import Optional

import typer

__all__ = ["register", "cad", "print_manifest"]


def print_manifest(manifest: dict) -> None:
    """The drawn-vs-optimised table and the check results on the console (stdout).

    Parameters
    ----------
    manifest : dict
        The CAD set's ``manifest.json`` content (:func:`vvea_design.cad.write_cad`): ``measured``
        (CAD vs design chamber volumes in mm³ and piston areas in mm², relative error as a
        fraction), ``mould`` (cavity volumes in mm³, sprue and vents open), ``interference_mm3``,
        ``walls_mm`` (drawn and minimum, mm) and ``files`` (watertightness of each STL).
    """
    from rich.table import Table

    from ..progress import out as console  # results to stdout

    t = Table(title="CAD vs design (what is drawn is what was optimised)")
    for col in ("quantity", "CAD", "design", "rel. error"):
        t.add_column(col, justify="right" if col != "quantity" else "left")
    for k, v in manifest["measured"].items():
        t.add_row(k, f"{v['cad']:.6g}", f"{v['design']:.6g}", f"{v['rel_error']:+.1e}")
    m = manifest["mould"]
    t.add_row("mould cavity_volume_mm3", f"{m['cavity_volume_mm3']:.6g}", f"{m['expected_cavity_volume_mm3']:.6g}",
              f"{(m['cavity_volume_mm3'] - m['expected_cavity_volume_mm3']) / m['expected_cavity_volume_mm3']:+.1e}")
    console.print(t)
    worst = max(v for pair in manifest["interference_mm3"].values() for v in pair.values())
    walls_ok = all(w["drawn"] >= w["minimum"] for w in manifest["walls_mm"].values())
    stl_ok = all(f.get("watertight", True) for f in manifest["files"].values())
    console.print(f"interference (max over pairs, both stroke ends): {worst:.3g} mm³; walls >= hoop-stress minimum: "
                  f"{'yes' if walls_ok else '[bold red]NO[/]'}; STL watertight: {'yes' if stl_ok else '[bold red]NO[/]'}; "
                  f"sprue/vents open: {m['sprue_open'] and all(m['vents_open'])}")


def cad(
    design_json: Path = typer.Argument(..., help="design JSON (from `vvea optimise` / `vvea design`)"),
    out: Path = typer.Option(Path("cad_out"), "--out", "-o", help="folder for STEP, STL, PNG and manifest.json"),
    renders: bool = typer.Option(True, "--renders/--no-renders", help="write the off-screen PNG renders"),
    drawings: bool = typer.Option(True, "--drawings/--no-drawings",
                                  help="write the dimensioned drawings (SVG per sheet, drawings.pdf) and bom.csv"),
    silicone: Optional[str] = typer.Option(None, "--silicone", help="bladder casting silicone for the bill of materials "
                                                                   "(default: the bladder check's, dragon-skin-20)"),
) -> None:
    """CAD: housing, piston, bladder, support ring, bladder mould and gas domains as STEP/STL/GLB, checked;
    dimensioned drawings and the bill of materials."""
    from ..jobs.cad import DesignFileError, build_cad
    from ..progress import console
    from .common import fail, job_errors

    try:
        with job_errors(errors=(DesignFileError,)):
            cad_set = build_cad(design_json, out=out, renders=renders, drawings=drawings, silicone=silicone)
    except Exception as exc:
        from ..jobs.cad import CadError  # the CAD kernel is loaded by now (the job ran)

        if not isinstance(exc, CadError):
            raise
        fail(f"{design_json}: {exc}")
    manifest = cad_set.manifest
    print_manifest(manifest.to_dict())
    console.print(f"wrote {len(manifest.files)} files and manifest.json to {out}/")
    if drawings:
        ds, bom = cad_set.drawings, cad_set.bom
        console.print(f"drawings: {len(ds.sheets)} sheets ({', '.join(ds.sheets)}) as SVG and {ds.pdf.name}; "
                      f"bom.csv: {len(bom.lines)} lines, unit mass {bom.unit_mass_g:.1f} g, "
                      f"silicone to mix {bom.silicone_to_mix_g:.1f} g ({bom.silicone})")


def register(app: typer.Typer) -> None:
    """Add the ``cad`` command to ``app``.

    Parameters
    ----------
    app : typer.Typer
        The ``vvea`` application.
    """
    app.command("cad")(cad)
