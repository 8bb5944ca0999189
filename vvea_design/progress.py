"""Progress display (rich) shared by every long job."""

from __future__ import annotations

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

#: Console for progress and status messages (stderr, so stdout stays data).
console = Console(stderr=True)


def print_error(message: str) -> None:
    """Print ``error: <message>`` on stderr; the message is shown literally (no rich markup)."""
    console.print("[bold red]error:[/]", end=" ")
    console.print(str(message), markup=False, highlight=False, soft_wrap=True)


@contextmanager
def progress_bar(description: str, total: int | None, enabled: bool = True) -> Iterator[Callable[..., None]]:
    """Context manager yielding ``advance(n=1)``; shows done/total and time left.

    With ``total=None`` a spinner is shown instead of a bar. Disabled (a no-op)
    when ``enabled`` is false.
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
