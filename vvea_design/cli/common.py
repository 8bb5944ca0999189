"""What every `vvea` command module shares: failing with a clear message, loading a design."""

from __future__ import annotations

from pathlib import Path
from typing import NoReturn

import typer

from ..progress import print_error

__all__ = ["fail", "load_design_or_exit"]


def fail(msg: str, code: int = 2) -> NoReturn:
    """Print ``error: msg`` on stderr (literally, no markup) and exit with ``code``.

    Parameters
    ----------
    msg : str
        What is wrong, naming the file, field or option.
    code : int
        Exit status: 2 = bad input (default), 3 = infeasible requirements, 1 = a check failed.

    Raises
    ------
    typer.Exit
        Always.
    """
    print_error(msg)
    raise typer.Exit(code)


def load_design_or_exit(path: Path):
    """The frozen design of a design JSON; a bad file exits 2 with the loader's message (it names the file).

    Parameters
    ----------
    path : Path
        Design JSON (``vvea optimise`` / ``vvea design`` output).

    Returns
    -------
    vvea_design.spring.design.Design
        The frozen design (mm, mm³, MPa).
    """
    from ..spring.design_file import DesignFileError, load_design

    try:
        return load_design(path)
    except DesignFileError as exc:
        fail(str(exc))
