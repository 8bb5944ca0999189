"""The FE check of a unit's pressure-bearing pieces as one job: the CAD's meridian sections -> gmsh meshes ->
axisymmetric linear-elastic FE (scikit-fem) under the design's load cases -> peak stress and safety factor per
wall, a stress-field picture per piece.

:func:`check_structure` is what :func:`vvea_design.pipeline.design_unit` runs after the CAD (the coarse
mesh: ``studies/fe_convergence.py`` measures its error against the converged one). The FE room and the CAD
kernel are imported when the job runs, not with this module.
"""

from __future__ import annotations

from pathlib import Path
from typing import TYPE_CHECKING, Any

from .common import OptionError, PathLike, check_out, design_of, folder, lazy_errors, moved

if TYPE_CHECKING:
    from ..spring.design import Design
    from ..structure.check import StructureResult
    from .cad import CadSet

__all__ = ["check_structure", "CadError", "DesignFileError"]

#: The errors this job raises, imported on first use (``CadError`` loads the CAD kernel).
__getattr__ = lazy_errors(__name__, ("CadError", "DesignFileError"))


def check_structure(unit: Design | CadSet | Any | PathLike, *, out: PathLike | None = None,
                    corner_radius_mm: float | None = None, elements_per_wall: float | None = None,
                    progress: Any = None) -> StructureResult:
    """FE check of every pressure-bearing piece of a unit under its governing load cases.

    Tubes, caps, base, bulkhead or collar and the piston (cupped or not) are meshed from the CAD's meridian
    sections (their grooves, steps and re-entrant corners rounded with the drawing's root radii, or
    ``corner_radius_mm``, where drawn sharp), loaded by each load case of the design (chamber gases, the fluid at the relief setting and at the
    largest damping force, the proof pressure; the joints' reactions on their faces) and checked against the
    yield stress of their material with the criterion's equivalent stress (Tresca).

    Parameters
    ----------
    unit : Design, CadSet, CadModel or path-like
        The design (mm, mm³) or its design JSON (its CAD is built), a CAD set of :func:`~.cad.build_cad`
        that kept its model, or the CAD model itself.
    out : path-like, optional
        Folder for a stress-field PNG per piece (written whole); None: no pictures.
    corner_radius_mm : float, optional
        Radius given to every internal corner the CAD draws sharp, mm (None: the drawing's root radii, R1 at
        steps, the ISO 3601 gland's at O-ring grooves, R1.5 at the rod's shoulder).
    elements_per_wall : float, optional
        Quadratic elements across the thinnest wall (None: the main job's coarse mesh).
    progress : callable, optional
        ``progress(piece, index, total)`` before each piece.

    Returns
    -------
    StructureResult
        Per wall the governing case, peak stress (MPa), its place (mm), safety factor and verdict; per piece
        its mesh, joint and pictures; wall-clock and CPU time (s).

    Raises
    ------
    OptionError
        ``corner_radius_mm`` or ``elements_per_wall`` not positive, before any work.
    OutputError
        ``out`` cannot be written (before any work).
    DesignFileError
        A design file that is missing or incomplete.
    CadError
        A design that cannot be drawn.
    """
    for name, v in (("corner_radius_mm", corner_radius_mm), ("elements_per_wall", elements_per_wall)):
        if v is not None and not v > 0:
            raise OptionError(name, f"must be > 0, got {v!r}")
    check_out(out)
    from ..structure import check_structure as check
    from ..structure.meshing import MeshSpec

    model = _model_of(unit)
    kw = {"corner_radius_mm": corner_radius_mm,
          "mesh": MeshSpec() if elements_per_wall is None else MeshSpec(elements_per_wall=elements_per_wall),
          "progress": progress}
    if out is None:
        return check(model, **kw)
    with folder(out, "structure") as tmp:
        res = check(model, out_dir=tmp, **kw)
    from dataclasses import replace

    return replace(res, pieces=tuple(replace(p, figure=None if p.figure is None else str(moved(Path(p.figure), tmp,
                                                                                              Path(out))))
                                     for p in res.pieces))


def _model_of(unit: Any) -> Any:
    """The CAD model of a design, design file, CAD set or model."""
    if getattr(unit, "solids", None) is not None and getattr(unit, "layout", None) is not None:
        return unit  # a CadModel
    model = getattr(unit, "model", None)
    if model is not None:
        return model  # a CadSet that kept its model
    from ..cad import build_cad

    return build_cad(design_of(unit))
