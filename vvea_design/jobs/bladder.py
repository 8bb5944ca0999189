"""The bladder check as one job (``vvea bladder``): FE membrane strain at both stroke ends, clamp bending
bound, radial room; ``bladder.json``, ``bladder_profile.csv`` and ``bladder.png``."""

from __future__ import annotations

import contextlib
from dataclasses import replace
from pathlib import Path
from typing import TYPE_CHECKING

from .common import OptionError, PathLike, check_option, check_out, design_of, folder, inputs_kept, lazy_errors

if TYPE_CHECKING:
    from ..bladder.result import BladderReport
    from ..spring.design import Design

__all__ = ["check_bladder", "BladderError", "DesignFileError"]

#: The errors this job raises, imported on first use.
__getattr__ = lazy_errors(__name__, ("BladderError", "DesignFileError"))


def check_bladder(design: Design | PathLike, *, material: str | None = None, criterion: str | None = None,
                  allowable: float | None = None, elements: int | None = None, out: PathLike | None = None,
                  progress: bool = True) -> BladderReport:
    """Check a design's cast bladder over its stroke (``vvea bladder``).

    Parameters
    ----------
    design : Design or path-like
        The design (its bladder: mid radius, free length, wall in mm; stroke volume changes in mm³), or
        its design JSON.
    material : str, optional
        Casting silicone key (:data:`vvea_design.materials.silicones.SILICONES`); None: Dragon Skin 20.
    criterion : str, optional
        Allowable-strain criterion of the silicone: ``cyclic`` (None) or ``static``.
    allowable : float, optional
        Allowable strain as a fraction (overrides ``criterion``).
    elements : int, optional
        Finite elements along the meridian (at least 8); None: the check's default (96).
    out : path-like, optional
        Folder for ``bladder.json``, ``bladder_profile.csv`` and ``bladder.png``.
    progress : bool
        Show a spinner on stderr while the membrane is solved.

    Returns
    -------
    BladderReport
        The check (strains as fractions, pressures in MPa, gaps in mm, the verdicts) and the names of the
        files written (``out_dir`` None and no files without ``out``).

    Raises
    ------
    OptionError
        An unknown ``material`` or ``criterion``, ``elements`` outside 8 ... 4000, or an ``allowable`` strain
        that is no fraction the material can take.
    OutputError
        ``out`` cannot be written (before any work).
    DesignFileError
        A design file that is missing or incomplete.
    BladderError
        A bladder that does not fit or cannot take the stroke.
    """
    from ..bladder.check import DEFAULT_MATERIAL, check_bladder as solve, write_bladder_report
    from ..bladder.result import DEFAULT_ELEMENTS, BladderReport
    from ..materials.silicones import CRITERIA, SILICONES
    from ..progress import console

    material = DEFAULT_MATERIAL if material is None else material
    elements = DEFAULT_ELEMENTS if elements is None else elements
    if isinstance(material, str) and material not in SILICONES:
        raise OptionError("material", f"{material!r}; known: {', '.join(sorted(SILICONES))}", "unknown {option} {reason}")
    if criterion is not None and criterion not in CRITERIA:
        raise OptionError("criterion", f"{criterion!r}; known: {', '.join(sorted(CRITERIA))}", "unknown {option} {reason}")
    if elements < 8:
        raise OptionError("elements", f"must be >= 8, got {elements}", "{option} {reason}")
    check_option("bladder_elements", elements, "elements")
    if allowable is not None:
        from ..materials.silicones import allowable_strain

        try:
            allowable_strain(material, allowable)
        except ValueError as exc:
            raise OptionError("allowable", str(exc)) from None
    check_out(out)
    inputs_kept((out,), (design,))
    d = design_of(design)
    limit = allowable if allowable is not None else criterion
    shown = console.status("solving the bladder membrane at both stroke ends") if progress else contextlib.nullcontext()
    with shown, folder(out, "bladder") as tmp:
        if tmp is None:
            return BladderReport(solve(d, material, limit, n_elements=elements), None, {})
        report = write_bladder_report(d, tmp, material, limit, n_elements=elements)
    return replace(report, out_dir=Path(out))
