"""The commands' side of :mod:`vvea_design.outputs`: a bad output location exits 2 with a clear message.

The jobs check their output location themselves before any work and write whole or not at all
(:mod:`vvea_design.jobs`); a command turns their :class:`~vvea_design.outputs.OutputError` into an exit
(:func:`vvea_design.cli.common.job_errors`). ``vvea design`` also holds the unit's folder open around the
main job (:func:`out_dir`), so that whatever the job writes lands whole.
"""

from __future__ import annotations

import contextlib
from collections.abc import Iterator
from pathlib import Path

from ..outputs import OutputError, check_output_dir, check_output_file, output_dir
from .common import fail

__all__ = ["check_out", "out_dir"]


def check_out(path: Path, kind: str = "dir", option: str = "--out") -> None:
    """Exit 2 (the message names the path) unless ``path`` can take a result folder or file.

    Parameters
    ----------
    path : Path
        The ``--out`` value.
    kind : str
        ``"dir"`` for a result folder, ``"file"`` for a single file.
    option : str
        The option named in the message.
    """
    try:
        (check_output_dir if kind == "dir" else check_output_file)(path, option)
    except OutputError as exc:
        fail(str(exc))


@contextlib.contextmanager
def out_dir(path: Path, command: str, option: str = "--out") -> Iterator[Path]:
    """:func:`vvea_design.outputs.output_dir` that exits 2 on a location it cannot write.

    Parameters
    ----------
    path : Path
        The result folder.
    command : str
        The command's name (marker file ``.vvea-<command>.json``).
    option : str
        The option named in messages.

    Returns
    -------
    Iterator[Path]
        (a context manager) the temporary folder to write into.
    """
    try:
        with output_dir(path, command, option) as tmp:
            yield tmp
    except OutputError as exc:
        fail(str(exc))
