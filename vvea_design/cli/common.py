"""What every `vvea` command module shares: failing with a clear message, turning a job's errors into exits."""

from __future__ import annotations

import contextlib
from collections.abc import Iterator, Mapping
from typing import NoReturn

import typer

from ..jobs.common import OptionError
from ..outputs import OutputError
from ..progress import print_error

__all__ = ["fail", "job_errors", "flag"]


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


def flag(option: str, flags: Mapping[str, str] | None = None) -> str:
    """The command-line flag of a job's option: ``flags[option]``, else ``--`` and the option with dashes.

    Parameters
    ----------
    option : str
        The job's keyword (``"max_linearity"``).
    flags : mapping, optional
        Keywords whose flag is spelt otherwise (``{"p2_MPa": "--p2"}``).

    Returns
    -------
    str
        The flag (``"--max-linearity"``).
    """
    return (flags or {}).get(option) or "--" + option.replace("_", "-")


@contextlib.contextmanager
def job_errors(flags: Mapping[str, str] | None = None, *, bad_parameter: bool = False,
               errors: tuple[type[BaseException], ...] = ()) -> Iterator[None]:
    """Run a job: a bad output location or option, or one of ``errors``, exits 2 with its message.

    Parameters
    ----------
    flags : mapping, optional
        Job keywords whose flag is not ``--`` plus the keyword with dashes.
    bad_parameter : bool
        Report a bad option as typer does (``Invalid value: ...``, exit 2) instead of ``error: ...``.
    errors : tuple of exception types
        The job's input errors (a design or requirements file, recordings) shown as they read (as typer's
        ``Invalid value`` with ``bad_parameter``).

    Returns
    -------
    Iterator[None]
        (a context manager) around the job call.
    """
    try:
        yield
    except OutputError as exc:
        fail(exc.named("--out"))
    except OptionError as exc:
        msg = exc.named(flag(exc.option, flags))
        if bad_parameter:
            raise typer.BadParameter(msg) from None
        fail(msg)
    except errors as exc:
        if bad_parameter:
            raise typer.BadParameter(str(exc)) from exc
        fail(str(exc))
