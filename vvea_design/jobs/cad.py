"""The CAD set as one job (``vvea cad``): build -> write (STEP, STL, GLB, renders, manifest) -> drawings -> BOM.

:func:`build_cad` is the only place this sequence exists; :func:`vvea_design.pipeline.design_unit` runs it
for its ``cad/`` folder. The CAD kernel (build123d) is imported when the job runs, not with this module.
"""

from __future__ import annotations

import tempfile
from dataclasses import dataclass, replace
from pathlib import Path
from typing import TYPE_CHECKING, Any

from .common import OptionError, PathLike, check_out, design_of, folder, lazy_errors, moved

if TYPE_CHECKING:
    from ..cad import CadManifest
    from ..report.bom import BillOfMaterials
    from ..report.drawing import DrawingSet
    from ..spring.design import Design

__all__ = ["CadSet", "build_cad", "CadError", "DesignFileError"]


#: The errors this job raises, imported on first use (``CadError`` loads the CAD kernel).
__getattr__ = lazy_errors(__name__, ("CadError", "DesignFileError"))


@dataclass(frozen=True)
class CadSet:
    """What :func:`build_cad` made: the checked CAD set, its drawings and bill of materials."""

    manifest: CadManifest  #: every file and part, CAD-measured volumes (mm³) and areas (mm²), the checks
    drawings: DrawingSet | None  #: the dimensioned sheets (None: not drawn, or nothing written)
    bom: BillOfMaterials | None  #: the bill of materials (None: not asked for)
    out_dir: Path | None  #: the folder written (None: nothing kept)

    def to_dict(self) -> dict[str, Any]:
        """JSON-ready.

        Returns
        -------
        dict
            ``manifest`` (the ``manifest.json`` content: mm, mm³, mm², fractions), ``drawings`` (sheets,
            files, scales), ``bom`` (lines, masses in g, volumes in mm³) and ``out_dir``; None where absent.
        """
        return {"manifest": self.manifest.to_dict(),
                "drawings": None if self.drawings is None else self.drawings.to_dict(),
                "bom": None if self.bom is None else self.bom.to_dict(),
                "out_dir": None if self.out_dir is None else str(self.out_dir)}


def build_cad(design: Design | PathLike, *, out: PathLike | None = None, renders: bool = True,
              drawings: bool = True, silicone: str | None = None, progress: bool = True) -> CadSet:
    """Build, check and write the CAD set of a design, with its drawings and bill of materials (``vvea cad``).

    Housing, piston, bladder, support ring, bladder mould and gas domains as STEP, STL and GLB, checked
    against the design (chamber volumes, piston areas, interference, walls, watertightness, mould);
    ``manifest.json``; with ``drawings`` the dimensioned sheets (SVG each, ``drawings.pdf``) and
    ``bom.csv`` / ``bom.json``.

    Parameters
    ----------
    design : Design or path-like
        The design (mm, mm³), or its design JSON.
    out : path-like, optional
        Folder for the set; None: built and checked in a temporary folder that is removed (no drawings).
    renders : bool
        Write the off-screen PNG renders.
    drawings : bool
        Write the drawings and the bill of materials.
    silicone : str, optional
        Key of the bladder's casting silicone for the bill of materials; None: the bladder check's default.
    progress : bool
        Show a progress bar on stderr.

    Returns
    -------
    CadSet
        The manifest, drawings and bill of materials.

    Raises
    ------
    OptionError
        An unknown ``silicone``.
    OutputError
        ``out`` cannot be written (before the CAD kernel is loaded).
    DesignFileError
        A design file that is missing or incomplete.
    CadError
        A design that cannot be drawn (names the field), before any file is written.
    """
    from ..bladder.check import DEFAULT_MATERIAL
    from ..materials.silicones import SILICONES

    silicone = DEFAULT_MATERIAL if silicone is None else silicone
    if silicone not in SILICONES:
        raise OptionError("silicone", f"{silicone!r}; known: {', '.join(sorted(SILICONES))}", "unknown {option} {reason}")
    check_out(out)
    d = design_of(design)
    from ..cad import build_cad as build, write_cad

    model = build(d)
    if out is None:
        from ..report.bom import bill_of_materials

        with tempfile.TemporaryDirectory() as tmp:
            manifest = write_cad(d, tmp, renders=renders, show_progress=progress, model=model)
        return CadSet(manifest, None, bill_of_materials(model, silicone) if drawings else None, None)
    sheets = bom = None
    with folder(out, "cad") as tmp:  # the CAD set, drawings and BOM land whole, or the old ones stay
        manifest = write_cad(d, tmp, renders=renders, show_progress=progress, model=model)
        if drawings:
            from ..report.bom import write_bom
            from ..report.drawing import write_drawings

            sheets = write_drawings(model, tmp)
            bom = write_bom(model, tmp, silicone)
    if sheets is not None:
        sheets = replace(sheets, svg=tuple(moved(Path(p), tmp, Path(out)) for p in sheets.svg),
                         pdf=moved(Path(sheets.pdf), tmp, Path(out)))
    return CadSet(manifest, sheets, bom, Path(out))
