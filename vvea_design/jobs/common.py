"""What every job shares: the option error, reading its inputs, writing its folder whole or not at all.

* :class:`OptionError` - a job option with a value the job cannot use. Its message names the option as the
  Python keyword (``silicone``); :meth:`OptionError.named` words it for another name (the command line's
  ``--silicone``), so each check lives in the job and the command line only renames.
* :func:`requirements_of`, :func:`design_of`, :func:`spring_of` - a job's input given as an object or as the
  file that holds it.
* :func:`folder` / :func:`files` - where a job writes: nothing when ``out`` is None, else through
  :func:`vvea_design.outputs.output_dir` / :func:`~vvea_design.outputs.output_files` (whole or not at all).
"""

from __future__ import annotations

import contextlib
import importlib
from collections.abc import Callable, Iterator
from pathlib import Path
from typing import TYPE_CHECKING, Any

from ..outputs import check_output_dir, check_output_file, output_dir, output_files

if TYPE_CHECKING:
    from ..spring.design import Design
    from ..spring.gas_spring import GasSpring
    from ..spring.requirements import Requirements

__all__ = ["OptionError", "requirements_of", "design_of", "spring_of", "check_out", "folder", "files", "moved",
           "PathLike", "ERRORS", "lazy_errors", "check_option", "check_scheduler_option", "inputs_kept"]

#: The errors a job may raise (besides :class:`OptionError` and :class:`~vvea_design.outputs.OutputError`), by
#: name: the module of this package that defines each. A job module re-exports the ones its jobs raise
#: (:func:`lazy_errors`), so a caller catches them without reaching into the wings.
ERRORS = {
    "SpecError": "spring.requirements",
    "DesignFileError": "spring.design_file",
    "Infeasible": "spring.optimise",
    "NoBuildableDesign": "spring.optimise",
    "LinearityRegression": "testing",
    "CadError": "cad.layout",
    "BladderError": "bladder.check",
    "RecordingsError": "identification.recordings",
    "PlausibilityError": "plausibility",
    "DesignError": "spring.parameters",
    "WorkerLost": "parallel",
    "SchedulerUnreachable": "parallel",
    "Terminated": "parallel",
}

#: A file or folder given as text or as a path.
PathLike = str | Path


def lazy_errors(module: str, names: tuple[str, ...]) -> Callable[[str], Any]:
    """A module ``__getattr__`` that imports each of ``names`` (keys of :data:`ERRORS`) on first use.

    A job module stays light to import (no CAD kernel, no optimiser) and still offers its errors by name.

    Parameters
    ----------
    module : str
        The job module's ``__name__`` (named in the error for an unknown attribute).
    names : tuple of str
        The errors it re-exports.

    Returns
    -------
    callable
        ``__getattr__(name)``: the error class; AttributeError for another name.
    """
    def __getattr__(name: str) -> Any:
        if name in names:
            return getattr(importlib.import_module(f"vvea_design.{ERRORS[name]}"), name)
        raise AttributeError(f"module {module!r} has no attribute {name!r}")

    return __getattr__


class OptionError(ValueError):
    """A job option with a value the job cannot use; the message names the option and why.

    Parameters
    ----------
    option : str
        The job's keyword (``"silicone"``, ``"mesh_n"``).
    reason : str
        What is wrong with the value (shows the value).
    template : str
        How the message reads, with ``{option}`` and ``{reason}`` in it.
    """

    def __init__(self, option: str, reason: str, template: str = "{option}: {reason}"):
        self.option = option
        self.reason = reason
        self.template = template
        super().__init__(template.format(option=option, reason=reason))

    def named(self, name: str) -> str:
        """The message with the option called ``name`` (e.g. the command line's ``--silicone``).

        Parameters
        ----------
        name : str
            How the caller calls the option.

        Returns
        -------
        str
            The message.
        """
        return self.template.format(option=name, reason=self.reason)

    def renamed(self, option: str) -> "OptionError":
        """The same error for an option of another name (a job that passes its option on to another job).

        Parameters
        ----------
        option : str
            The caller's keyword.

        Returns
        -------
        OptionError
            The error, ``option`` in its message.
        """
        return OptionError(option, self.reason, self.template)


def requirements_of(requirements: Requirements | PathLike | None) -> tuple[Requirements, str | None]:
    """Requirements and where they came from.

    Parameters
    ----------
    requirements : Requirements, path-like or None
        The requirements, a requirements TOML file, or None for the built-in defaults (the paper's unit).

    Returns
    -------
    (Requirements, str or None)
        The validated requirements and the file they were read from (None: given as an object, or the
        defaults).

    Raises
    ------
    SpecError
        A file that cannot be read or holds a wrong value (names file, key and problem).
    """
    from ..spring.requirements import Requirements, load_requirements

    if isinstance(requirements, Requirements):
        return requirements, None
    return load_requirements(requirements), None if requirements is None else str(requirements)


def design_of(design: Design | PathLike) -> Design:
    """The frozen design, given or read from a design JSON.

    Parameters
    ----------
    design : Design or path-like
        A :class:`~vvea_design.spring.design.Design` (mm, mm³, MPa) or a design JSON (``vvea optimise`` /
        ``vvea design`` output).

    Returns
    -------
    Design
        The design.

    Raises
    ------
    DesignFileError
        A file that is missing, malformed or incomplete (names the file and key).
    """
    from ..spring.design import Design
    from ..spring.design_file import load_design

    return design if isinstance(design, Design) else load_design(design)


def spring_of(design: Design | GasSpring | PathLike | dict) -> tuple[GasSpring, str | None]:
    """The gas spring of a design and the design's layout.

    Parameters
    ----------
    design : Design, GasSpring, path-like or dict
        A design (its ``gas_spring``), a gas spring, or a design JSON / its parsed content (the spring of
        its ``parameters`` alone, paper eq. 5: an edited file is judged by what it says).

    Returns
    -------
    (GasSpring, str or None)
        The spring (mm, mm², mm³, MPa) and the layout (None when given as a spring or a file).

    Raises
    ------
    DesignFileError
        A file that is missing or whose parameters are incomplete (names the file and key).
    """
    from ..spring.design import Design
    from ..spring.design_file import spring_from_json
    from ..spring.gas_spring import GasSpring

    if isinstance(design, Design):
        return design.gas_spring, design.layout
    if isinstance(design, GasSpring):
        return design, None
    return spring_from_json(design), None


@contextlib.contextmanager
def folder(out: PathLike | None, command: str, names: tuple[str, ...] = ()) -> Iterator[Path | None]:
    """The folder a job writes into: None without ``out``, else a temporary that becomes ``out`` whole.

    Parameters
    ----------
    out : path-like or None
        The result folder (None: the job writes nothing).
    command : str
        The job's plain name (marker ``.vvea-<command>.json``, :func:`vvea_design.outputs.output_dir`).
    names : tuple of str
        The entries the job writes, when known: a file of that name in ``out`` that is not the job's own
        earlier output is refused before any work (never overwritten).

    Returns
    -------
    Iterator[Path or None]
        (a context manager) where to write.

    Raises
    ------
    OutputError
        ``out`` cannot be written (checked before the block), or the results could not be moved into place.
    """
    if out is None:
        yield None
        return
    with output_dir(out, command, option="", names=names) as tmp:
        yield tmp


@contextlib.contextmanager
def files(*paths: PathLike) -> Iterator[list[Path]]:
    """Temporary paths that replace ``paths`` together when the block ends without an exception.

    Parameters
    ----------
    *paths : path-like
        The result files.

    Returns
    -------
    Iterator[list[Path]]
        (a context manager) one temporary path per file, in order.

    Raises
    ------
    OutputError
        A location cannot be written, or the files could not be moved into place.
    """
    with output_files(*paths, option="") as tmps:
        yield tmps


def check_out(out: PathLike | None, kind: str = "dir") -> None:
    """Raise :class:`~vvea_design.outputs.OutputError` now, before any work, unless ``out`` can be written.

    Parameters
    ----------
    out : path-like or None
        The result folder (``kind="dir"``) or file (``kind="file"``); None: nothing is written.
    kind : str
        ``"dir"`` or ``"file"``.
    """
    if out is not None:
        (check_output_dir if kind == "dir" else check_output_file)(out, "")


def moved(value: Any, old: Path, new: Path) -> Any:
    """``value`` with a path inside ``old`` pointing to the same entry inside ``new`` (other values as they are).

    Parameters
    ----------
    value : object
        A path, or anything else.
    old, new : Path
        The temporary folder a job wrote into and the folder it became.

    Returns
    -------
    object
        The path moved, or ``value`` unchanged.
    """
    if isinstance(value, Path) and (value == old or old in value.parents):
        return new / value.relative_to(old)
    return value



def check_option(key: str, value: Any, option: str) -> Any:
    """Raise :class:`OptionError` naming ``option`` unless ``value`` lies in the toolkit's range ``key``.

    The ranges are :data:`vvea_design.plausibility.LIMITS` (what a real unit, bench or computer can have), so
    a job refuses an absurd number (a 1e9 MPa charge, a 100000-point map) before any work, naming the option
    and why.

    Parameters
    ----------
    key : str
        A key of :data:`vvea_design.plausibility.LIMITS` (``"charge_MPa"``, ``"map_points"``, ``"seed"``).
    value : Any
        The option's value, in the limit's unit (None: not given, accepted).
    option : str
        The job's keyword (``"p2_MPa"``, ``"n"``).

    Returns
    -------
    Any
        ``value`` unchanged.

    Raises
    ------
    OptionError
        ``value`` is not a finite number in the range (the message gives the range and why).
    """
    from ..plausibility import LIMITS

    if value is None:
        return value
    lim = LIMITS[key]
    why = lim.problem(value)
    if why is not None:
        from ..messages import show

        real = isinstance(value, (int, float)) and not isinstance(value, bool)
        hint = lim.unit_hint(value) if real else ""
        raise OptionError(option, f"{why}, got {show(value)}" + (f" ({lim.why})" if real else "")
                          + (f"; {hint}" if hint else ""), "{option} {reason}")
    return value


def check_scheduler_option(scheduler: str | None) -> None:
    """Raise :class:`OptionError` (option ``scheduler``) now, before any work, unless the Dask scheduler answers.

    Parameters
    ----------
    scheduler : str or None
        ``tcp://host:port``; None: local processes (nothing to check).

    Raises
    ------
    OptionError
        A malformed address, or no connection within a few seconds.
    """
    if scheduler is None:
        return
    from ..parallel import SchedulerUnreachable, check_scheduler

    try:
        check_scheduler(scheduler)
    except SchedulerUnreachable as exc:
        raise OptionError("scheduler", str(exc)) from None


def inputs_kept(outputs: Any, inputs: Any) -> None:
    """Raise :class:`~vvea_design.outputs.OutputError` before any work when an output is one of the inputs.

    ``optimise("req.toml", out="req.toml")`` (or ``out`` a link to it) is refused: no input is ever an output.

    Parameters
    ----------
    outputs : iterable of path-like or None
        The files and folders the job writes (None entries skipped).
    inputs : iterable of object
        What the job reads; the entries given as a path are compared (objects skipped).
    """
    from ..outputs import check_not_input

    outs = [o for o in outputs if o is not None]
    ins = [i for i in inputs if isinstance(i, (str, Path))]
    if outs and ins:
        check_not_input(outs, ins, option="")
