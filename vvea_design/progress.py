"""Consoles and progress display (rich) shared by every command.

Two consoles, one convention: results and tables go to :data:`out`
(stdout), progress, status and log lines to :data:`console` (stderr), so
``vvea optimise > result.txt`` captures the result and nothing else. Off a
terminal (a pipe, a file, CI) neither console wraps lines: "3844.0 N" is
never split.
"""

from __future__ import annotations

import sys
from collections.abc import Callable, Iterator
from contextlib import contextmanager

from rich.console import Console
from rich.progress import (
    BarColumn,
    MofNCompleteColumn,
    Progress,
    SpinnerColumn,
    TextColumn,
    TimeElapsedColumn,
    TimeRemainingColumn,
)

#: Line width used when the stream is not a terminal: wide enough that nothing wraps.
NO_WRAP_WIDTH = 10_000


def _console(stderr: bool) -> Console:
    stream = sys.stderr if stderr else sys.stdout
    try:
        tty = stream.isatty()
    except (AttributeError, ValueError):
        tty = False
    if tty:
        return Console(stderr=stderr)
    return Console(stderr=stderr, width=NO_WRAP_WIDTH, soft_wrap=True)


#: Console for progress, status and log messages (stderr).
console = _console(stderr=True)
#: Console for results and tables (stdout).
out = _console(stderr=False)


def print_error(message: str) -> None:
    """Print ``error: <message>`` on stderr; the message is shown literally (no rich markup).

    Parameters
    ----------
    message : str
        What went wrong (names the file, field or option).
    """
    console.print("[bold red]error:[/]", end=" ")
    console.print(str(message), markup=False, highlight=False, soft_wrap=True)


@contextmanager
def progress_bar(description: str, total: int | None, enabled: bool = True) -> Iterator[Callable[..., None]]:
    """Context manager yielding ``advance(n=1)``; shows done/total and time left on stderr.

    Parameters
    ----------
    description : str
        What is running.
    total : int or None
        Number of steps; ``None`` shows a spinner instead of a bar.
    enabled : bool
        False makes it a no-op.

    Yields
    ------
    callable
        ``advance(n=1)``: mark ``n`` more steps done.
    """
    if not enabled:
        yield lambda n=1: None
        return
    columns = [SpinnerColumn(), TextColumn("[bold]{task.description}")]
    if total is not None:
        columns += [BarColumn(), MofNCompleteColumn(), TimeElapsedColumn(), TextColumn("left"), TimeRemainingColumn()]
    else:
        columns += [TimeElapsedColumn()]
    with Progress(*columns, console=console, transient=False) as prog:
        task = prog.add_task(description, total=total)

        def advance(n: int = 1) -> None:
            prog.advance(task, n)

        yield advance
