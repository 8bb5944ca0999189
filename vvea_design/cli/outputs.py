"""The commands' side of :mod:`vvea_design.outputs`: a bad output location exits 2 with a clear message.

Every command that writes calls :func:`check_out` right after reading its
arguments (before any computation) and writes through :func:`out_dir` /
:func:`out_files`, so its results land whole or not at all.
"""

from __future__ import annotations

import contextlib
from collections.abc import Iterator
from pathlib import Path

from ..outputs import OutputError, check_not_input, check_output_dir, check_output_file, output_dir, output_files
from .common import fail

__all__ = ["check_out", "out_dir", "out_files", "check_inputs_kept"]


def check_inputs_kept(outputs, inputs, option: str = "--out") -> None:
    """Exit 2 (naming both) when an output file would be one of the inputs, before any work.

    Parameters
    ----------
    outputs : iterable of Path
        The files the command writes.
    inputs : iterable of Path or None
        The files it reads (None skipped).
    option : str
        The option named in the message.
    """
    try:
        check_not_input(outputs, inputs, option)
    except OutputError as exc:
        fail(str(exc))


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


@contextlib.contextmanager
def out_files(*paths: Path, option: str = "--out") -> Iterator[list[Path]]:
    """:func:`vvea_design.outputs.output_files` that exits 2 on a location it cannot write.

    Parameters
    ----------
    *paths : Path
        The result files.
    option : str
        The option named in messages.

    Returns
    -------
    Iterator[list[Path]]
        (a context manager) the temporary paths, in order.
    """
    try:
        with output_files(*paths, option=option) as tmps:
            yield tmps
    except OutputError as exc:
        fail(str(exc))
