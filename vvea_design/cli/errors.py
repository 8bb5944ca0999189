"""Exit codes and the one-line error of every `vvea` command, whatever goes wrong.

Every command runs inside :class:`VveaGroup` (the ``vvea`` app's group class), which maps what escapes it to an
exit code and **one** line on stderr (:data:`EXIT_CODES`; ``docs/reliability.md``)::

    0    done
    1    vvea check: the design misses the limit; or an unexpected internal error (a bug: run with --debug)
    2    bad input: a file, field, row, option or output location (named in the message); also an output
         that cannot be written (a full disk: "no space left on device", the old output kept)
    3    no design meets the requirements
    4    a computation failed: a solver failed, a worker process died
    130  interrupted (Ctrl-C / SIGINT)
    143  terminated (SIGTERM)

Full tracebacks only with ``vvea --debug ...`` (or ``VVEA_DEBUG=1``). Warnings the library raises for the user
(a design file written before the buildability rules,
:class:`~vvea_design.spring.design_file.LegacyDesignFile`) are printed as ``note: ...`` lines. The exceptions are matched by class name (:data:`ERROR_CODES`), so this module imports
none of the wings: a new input error slots in with one line.
"""

from __future__ import annotations

import contextlib
import errno
import os
import signal
import sys
import threading
import warnings
from collections.abc import Iterator

import typer
from typer.core import TyperGroup

from ..outputs import io_failure
from ..progress import console, print_error

__all__ = ["EXIT_CODES", "ERROR_CODES", "VveaGroup", "guarded", "set_debug", "strip_debug", "INTERRUPT_REPORTED"]

#: Exit status by meaning.
EXIT_CODES = {"ok": 0, "check_failed": 1, "internal_error": 1, "bad_input": 2, "infeasible": 3,
              "computation_failed": 4, "interrupted": 130, "terminated": 143}

#: Exit status of an error escaping a command, by the name of its class (or of a base class).
ERROR_CODES: dict[str, int] = {
    "OutputError": 2, "SpecError": 2, "DesignFileError": 2, "RecordingsError": 2, "PlausibilityError": 2,
    "BladderError": 2, "CadError": 2, "SchedulerUnreachable": 2, "OptionError": 2, "DesignError": 2,
    "Infeasible": 3, "NoBuildableDesign": 3,
    "WorkerLost": 4, "SolverFailed": 4,
    "LinearityRegression": 1,
}
_IO = {errno.ENOSPC, errno.EDQUOT, errno.EFBIG, errno.EROFS, errno.EIO}

_state = {"debug": bool(os.environ.get("VVEA_DEBUG")), "sigint": False}
#: Set by a command that printed its own message for an interrupt (the study says how to resume).
INTERRUPT_REPORTED = {"done": False}


def set_debug(on: bool) -> None:
    """Show full tracebacks (``vvea --debug``) instead of one-line errors.

    Parameters
    ----------
    on : bool
        True: every unexpected error is raised with its trace.
    """
    _state["debug"] = bool(on) or bool(os.environ.get("VVEA_DEBUG"))


def _names(exc: BaseException) -> set[str]:
    return {c.__name__ for c in type(exc).__mro__}


def _one_line(text: str) -> str:
    lines = [ln.rstrip() for ln in str(text).splitlines() if ln.strip()]
    return "\n".join(lines[:12]) if lines else type(text).__name__


def _interrupted(code: int, what: str) -> None:
    if not INTERRUPT_REPORTED["done"]:
        console.print(f"\n{what}: stopped; nothing was written, an earlier output is left as it was", soft_wrap=True,
                      markup=False, highlight=False)
    raise typer.Exit(code)


def _fail(code: int, message: str) -> None:
    print_error(message)
    raise typer.Exit(code)


def _report(exc: BaseException) -> None:
    """Map ``exc`` to a message and an exit code (raises typer.Exit); re-raise what is not an error of ours."""
    names = _names(exc)
    if isinstance(exc, KeyboardInterrupt) or (_state["sigint"] and isinstance(exc, ImportError)):
        _interrupted(130, "interrupted (Ctrl-C)")
    if "Terminated" in names:
        _interrupted(143, "terminated (SIGTERM)")
    for name, code in ERROR_CODES.items():
        if name in names:
            if name == "Infeasible":
                _fail(code, _one_line(exc))
            _fail(code, str(exc))
    if isinstance(exc, OSError) and exc.errno in _IO:
        _fail(2, io_failure(exc, exc.filename or "the output"))
    if isinstance(exc, MemoryError):
        _fail(2, "ran out of memory: an input or an option asks for more than this machine has (the message of the "
                 "limits is in docs/reliability.md); run with --debug for the trace")
    if isinstance(exc, Exception):
        text = str(exc).splitlines()[0][:300] if str(exc) else ""
        _fail(1, f"internal error: {type(exc).__name__}{': ' + text if text else ''} (a bug: please report it with "
                 "the output of `vvea --debug ...`)")
    raise exc


_default_showwarning = warnings.showwarning


def _show_note(message, category, filename, lineno, file=None, line=None) -> None:
    """The toolkit's own warnings as ``note: ...`` lines; other libraries' as Python shows them."""
    if getattr(category, "__module__", "").startswith("vvea_design"):
        console.print(f"note: {message}", markup=False, highlight=False, soft_wrap=True)
    else:
        _default_showwarning(message, category, filename, lineno, file, line)


@contextlib.contextmanager
def _signals() -> Iterator[None]:
    """SIGTERM raises ``Terminated`` (exit 143 with a message); SIGINT is remembered (an ImportError it causes
    inside a C extension's import is an interrupt, not a bug)."""
    if threading.current_thread() is not threading.main_thread():
        yield
        return
    from ..jobs.studies import Terminated, note_interrupt

    note_interrupt(False)

    def on_term(signum, frame):
        raise Terminated(f"received signal {signum}")

    def on_int(signum, frame):
        _state["sigint"] = True
        note_interrupt()  # a solver that swallows the KeyboardInterrupt below still learns of it
        raise KeyboardInterrupt

    old_hook = sys.unraisablehook

    def quiet_interrupt(unraisable):
        """A KeyboardInterrupt raised in a callback Python cannot propagate (a weakref's, during garbage
        collection) is noted above and stops the command at its next step or landing: no trace for it."""
        if not isinstance(unraisable.exc_value, KeyboardInterrupt):
            old_hook(unraisable)

    sys.unraisablehook = quiet_interrupt
    old = {s: signal.getsignal(s) for s in (signal.SIGTERM, signal.SIGINT)}
    if old[signal.SIGTERM] in (signal.SIG_DFL, None):
        signal.signal(signal.SIGTERM, on_term)
    if old[signal.SIGINT] is signal.default_int_handler:
        signal.signal(signal.SIGINT, on_int)
    try:
        yield
    finally:
        sys.unraisablehook = old_hook
        for s, h in old.items():
            if h is not None:
                signal.signal(s, h)


@contextlib.contextmanager
def guarded() -> Iterator[None]:
    """Run a command: what escapes becomes one line and an exit code (see the module doc); notes for warnings.

    Returns
    -------
    Iterator[None]
        (a context manager) around the command.
    """
    INTERRUPT_REPORTED["done"] = False
    _state["sigint"] = False
    with warnings.catch_warnings(), _signals():
        warnings.showwarning = _show_note
        try:
            yield
            if _state["sigint"]:  # a Ctrl-C that a library printed and dropped: still an interrupt (exit 130)
                raise KeyboardInterrupt("interrupted (Ctrl-C)")
        except (typer.Exit, typer.Abort, SystemExit):
            raise
        except BaseException as exc:
            if _names(exc) & {"ClickException", "Exit", "Abort"}:  # typer's own (a vendored click's) exits
                raise
            if _state["debug"]:
                raise
            _report(exc)


class VveaGroup(TyperGroup):
    """The ``vvea`` app's group: every command runs :func:`guarded`."""

    def invoke(self, ctx):
        """Run the command of ``ctx`` inside :func:`guarded` (click's hook).

        Parameters
        ----------
        ctx : click.Context
            The parsed command line.

        Returns
        -------
        Any
            What the command returns.
        """
        with guarded():
            return super().invoke(ctx)


def strip_debug(argv: list[str]) -> list[str]:
    """``argv`` without ``--debug`` (accepted anywhere on the line), which switches :func:`set_debug` on.

    Parameters
    ----------
    argv : list of str
        The command line after the program name.

    Returns
    -------
    list of str
        The same without ``--debug``.
    """
    if "--debug" in argv:
        set_debug(True)
        return [a for a in argv if a != "--debug"]
    return argv

