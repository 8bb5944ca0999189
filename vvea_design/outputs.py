"""Outputs written whole or not at all.

Every command that writes files goes through this module, so that a bad
``--out``, a failed computation, Ctrl-C or a crash never leaves a mix of old
and new files:

* :func:`check_output_dir` / :func:`check_output_file` validate the location
  *before* the computation: ``--out`` that is an existing file (or folder,
  for a file output), a path under a file, or a folder nobody may write in
  (a real write probe, so read-only mounts count too) is an
  :class:`OutputError` naming the path.
* :func:`output_dir` (a folder of results) and :func:`output_files` (single
  files such as ``design.json``) hand out a temporary folder/file *beside*
  the target (same file system) and move it into place only when the block
  ends without an exception. An exception or Ctrl-C inside the block removes
  the temporary and leaves the target exactly as it was. SIGINT/SIGTERM/SIGHUP
  are held back during the final renames (a few microseconds) and take effect
  right after them.

What happens to an existing target folder (``output_dir``):

* it does not exist -> the temporary folder is renamed to it;
* it holds only what the same command wrote there last time (listed in the
  hidden ``.vvea-<command>.json`` it leaves in every folder it writes), or
  nothing -> the whole folder is **replaced atomically** (Linux
  ``renameat2(RENAME_EXCHANGE)``; elsewhere two renames, between which the
  folder is briefly absent but never mixed), so files of the earlier run that
  this run did not write are gone;
* it also holds anything else (the design JSON the command read, files of
  other commands, your own notes, ``--out .``) -> those are **never
  touched**: each entry this run wrote replaces its namesake with a rename,
  and the entries the same command wrote last time but not this time are
  removed.

Temporaries are named ``.<name>.vvea-tmp-<pid>-<random>`` (and
``.vvea-old-`` for replaced entries); one left behind by a killed process
(SIGKILL cannot be caught) is removed by the next command writing there once
its process is gone.

Nested results: an :func:`output_dir` whose target lies inside (or is) the
temporary folder of an :func:`output_dir` still open in the same thread of
execution writes straight into that target (created), with no temporary and
no marker of its own: the enclosing block already lands the whole tree at
once. This is how :func:`vvea_design.pipeline.design_unit` runs the jobs of
its steps (CAD set, bladder check, ...) into the one unit folder it writes.
"""

from __future__ import annotations

import contextlib
import contextvars
import ctypes
import errno
import json
import os
import re
import secrets
import shutil
import signal
import threading
from collections.abc import Iterator
from pathlib import Path

__all__ = ["OutputError", "check_output_dir", "check_output_file", "output_dir", "output_files", "write_text_atomic",
           "MARKER_PREFIX", "check_not_input", "io_failure"]

#: Every output folder gets ``.vvea-<command>.json`` listing what the command wrote there.
MARKER_PREFIX = ".vvea-"
_TEMP = re.compile(r"\.vvea-(?:tmp|old)-(\d+)-[0-9a-f]+")
#: The temporary folders of the :func:`output_dir` blocks open in this context (innermost last).
_OPEN: contextvars.ContextVar[tuple[Path, ...]] = contextvars.ContextVar("vvea_open_output_dirs", default=())


class OutputError(ValueError):
    """An output location that cannot be written (names the path and why).

    Parameters
    ----------
    message : str
        The whole message.
    path : Path, optional
        The location refused before any work (with ``reason``): :meth:`named` words the message for the
        option that gave it.
    reason : str, optional
        Why ``path`` cannot be written.
    """

    def __init__(self, message: str, path: Path | None = None, reason: str | None = None):
        super().__init__(message)
        self.path = path
        self.reason = reason

    def named(self, option: str) -> str:
        """The message naming the option that gave the location (``--out /x: is an existing file...``).

        Parameters
        ----------
        option : str
            The option (``"--out"``); ``""`` for none.

        Returns
        -------
        str
            The message; one not about a refused location (a failed write or move) as it is.
        """
        if self.path is None or self.reason is None:
            return str(self)
        return f"{_label(self.path, option)}: {self.reason}"


def _refused(path: Path, option: str, reason: str) -> OutputError:
    """The error for a location refused before any work: ``<option> <path>: <reason>``."""
    return OutputError(f"{_label(path, option)}: {reason}", path, reason)


# ---------------------------------------------------------------------------
# validation before the computation
# ---------------------------------------------------------------------------

def _label(path: Path, option: str) -> str:
    return f"{option} {path}" if option else str(path)


def _nearest_existing(path: Path, option: str) -> Path:
    """The nearest existing ancestor of ``path``; it must be a folder (not a file the path runs through)."""
    anc = path.parent
    while not os.path.lexists(anc) and anc != anc.parent:
        anc = anc.parent
    if not anc.is_dir():
        raise _refused(path, option, f"{anc} is a file, so nothing can be written under it; give a path in a folder")
    return anc


def _writable(folder: Path) -> OSError | None:
    """Create and remove a folder in ``folder``: a real test (root ignores permission bits, not read-only mounts)."""
    name = folder / f".vvea-probe-{os.getpid()}-{secrets.token_hex(4)}"
    try:
        os.mkdir(name)
        os.rmdir(name)
    except OSError as exc:
        return exc
    return None


def _fail_unwritable(folder: Path, path: Path, option: str, exc: OSError) -> None:
    raise _refused(path, option, f"cannot write in {folder} ({exc.strerror or exc})") from None


def _not_a_windows_path(path: str | os.PathLike, option: str) -> None:
    """A drive letter or backslashes on a system whose separator is '/': a path meant for Windows."""
    text = os.fspath(path)
    if os.sep == "/" and (re.match(r"^[A-Za-z]:[\\/]", text) or "\\" in text):
        raise _refused(Path(text), option, "looks like a Windows path (a drive letter or backslashes); this system "
                       "separates folders with '/' and would make a file named with backslashes — write it as "
                       "e.g. designs/d.json")


def check_not_input(outputs, inputs, option: str = "--out") -> None:
    """Raise :class:`OutputError` when an output would be one of the inputs (the same file, or a link to it).

    Call it before any work, with every file the command writes and every file it reads: ``vvea optimise
    --spec req.toml -o req.toml`` (or ``-o`` a link to it, or a hard link) is refused, never overwrites the
    requirements.

    Parameters
    ----------
    outputs : iterable of path-like
        Files (or folders) the command writes.
    inputs : iterable of path-like or None
        Files it reads (None entries are skipped).
    option : str
        The option named in the message.

    Raises
    ------
    OutputError
        An output resolves to an input (symbolic links followed, hard links by inode).
    """
    ins = []
    for i in inputs:
        if i is None:
            continue
        real = os.path.realpath(i)
        try:
            st = os.stat(real)
            ident = (st.st_dev, st.st_ino)
        except OSError:
            ident = None
        ins.append((Path(i), real, ident))
    for o in outputs:
        real = os.path.realpath(o)
        try:
            st = os.stat(real)
            ident = (st.st_dev, st.st_ino)
        except OSError:
            ident = None
        for given, r, i_ident in ins:
            if real == r or (ident is not None and ident == i_ident):
                how = "" if os.path.abspath(o) == os.path.abspath(given) else f" (it resolves to {r})"
                raise _refused(Path(o), option, f"is the input {given}{how}; writing it would destroy the input "
                               "— give another output path")


def io_failure(exc: OSError, target) -> str:
    """One line for a write that failed (a full disk, a quota, a read-only or vanished file system).

    Parameters
    ----------
    exc : OSError
        The error raised while writing.
    target : path-like
        The output the command was writing.

    Returns
    -------
    str
        ``could not write <target>: no space left on device (the disk is full; nothing was changed there)``
        and the like.
    """
    why = (exc.strerror or str(exc)).rstrip(".")
    extra = {errno.ENOSPC: "the disk is full", errno.EDQUOT: "the disk quota is used up",
             errno.EFBIG: "a file size limit is reached", errno.EROFS: "the file system is read-only"}.get(exc.errno)
    return (f"could not write {target}: {why[:1].lower() + why[1:]} ({extra + '; ' if extra else ''}nothing was changed "
            "there)")


_IO_ERRNOS = {errno.ENOSPC, errno.EDQUOT, errno.EFBIG, errno.EROFS, errno.EIO}


def check_output_dir(path: str | os.PathLike, option: str = "--out") -> Path:
    """Raise :class:`OutputError` unless a result folder can be written at ``path``.

    Call it before the computation. An existing folder must be writable
    itself; a new one needs its nearest existing ancestor writable.

    Parameters
    ----------
    path : path-like
        The result folder (need not exist).
    option : str
        The command-line option named in the message (``""`` for none).

    Returns
    -------
    Path
        ``path`` made absolute, symbolic links resolved.

    Raises
    ------
    OutputError
        ``path`` is an existing file, lies under a file, cannot be written, or is a Windows path.
    """
    _not_a_windows_path(path, option)
    p = Path(os.path.realpath(path))
    if p.exists() and not p.is_dir():
        raise _refused(p, option, "is an existing file, not a folder; give a folder path")
    folder = p if p.is_dir() else _nearest_existing(p, option)
    err = _writable(folder)
    if err is not None:
        _fail_unwritable(folder, p, option, err)
    return p


def check_output_file(path: str | os.PathLike, option: str = "--out") -> Path:
    """Raise :class:`OutputError` unless a file can be written at ``path``.

    Parameters
    ----------
    path : path-like
        The result file (need not exist).
    option : str
        The command-line option named in the message (``""`` for none).

    Returns
    -------
    Path
        ``path`` made absolute, symbolic links resolved.

    Raises
    ------
    OutputError
        ``path`` is an existing folder, lies under a file, its folder cannot be written, or it is a
        Windows path.
    """
    _not_a_windows_path(path, option)
    p = Path(os.path.realpath(path))
    if p.is_dir():
        raise _refused(p, option, f"is an existing folder; give a file path (e.g. {p / 'design.json'})")
    folder = _nearest_existing(p, option)
    err = _writable(folder)
    if err is not None:
        _fail_unwritable(folder, p, option, err)
    return p


# ---------------------------------------------------------------------------
# helpers
# ---------------------------------------------------------------------------

def _temp_name(target: Path, kind: str = "tmp") -> Path:
    return target.with_name(f".{target.stem}.vvea-{kind}-{os.getpid()}-{secrets.token_hex(4)}{target.suffix}")


def _alive(pid: int) -> bool:
    if pid == os.getpid():
        return True
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except PermissionError:
        return True
    return True


def _remove_orphans(folder: Path) -> None:
    """Remove temporaries in ``folder`` left by processes that no longer run (killed with SIGKILL)."""
    try:
        entries = list(os.scandir(folder))
    except OSError:
        return
    for e in entries:
        m = _TEMP.search(e.name)
        if m and e.name.startswith(".") and not _alive(int(m.group(1))):
            _remove(Path(e.path))


def _remove(path: Path) -> None:
    if path.is_dir() and not path.is_symlink():
        shutil.rmtree(path, ignore_errors=True)
    else:
        with contextlib.suppress(FileNotFoundError):
            path.unlink()


def _make_parents(folder: Path) -> list[Path]:
    """``mkdir -p folder``; return the folders created (deepest last) so a failure can remove them."""
    missing = []
    p = folder
    while not p.exists():
        missing.append(p)
        p = p.parent
    for m in reversed(missing):
        os.mkdir(m)
    return list(reversed(missing))


def _remove_created(created: list[Path]) -> None:
    for d in reversed(created):
        with contextlib.suppress(OSError):
            os.rmdir(d)  # only if still empty


@contextlib.contextmanager
def _signals_held() -> Iterator[None]:
    """Hold SIGINT/SIGTERM/SIGHUP back while the renames run; they take effect right after.

    Python runs signal handlers in the main thread whichever thread the kernel
    picks, so the handlers are swapped for a recorder (a per-thread signal
    mask would not do in a threaded process) and the recorded signals are
    raised again, to the original handlers, once the block is done.
    """
    if threading.current_thread() is not threading.main_thread():
        yield  # handlers run in the main thread: this one is not interrupted
        return
    caught: list[int] = []
    previous = {}
    for sig in (signal.SIGINT, signal.SIGTERM, signal.SIGHUP):
        handler = signal.getsignal(sig)
        if handler is None:  # installed from C: leave it alone
            continue
        previous[sig] = handler
        signal.signal(sig, lambda num, frame: caught.append(num))
    try:
        yield
    finally:
        for sig, handler in previous.items():
            signal.signal(sig, handler)
        for num in dict.fromkeys(caught):
            signal.raise_signal(num)


_RENAME_EXCHANGE = 2
_AT_FDCWD = -100


def _exchange(a: Path, b: Path) -> bool:
    """Swap two paths atomically (Linux renameat2); False when the system or file system cannot."""
    try:
        fn = ctypes.CDLL(None, use_errno=True).renameat2
    except (AttributeError, OSError):
        return False
    fn.argtypes = [ctypes.c_int, ctypes.c_char_p, ctypes.c_int, ctypes.c_char_p, ctypes.c_uint]
    if fn(_AT_FDCWD, os.fsencode(a), _AT_FDCWD, os.fsencode(b), _RENAME_EXCHANGE) == 0:
        return True
    err = ctypes.get_errno()
    if err in (errno.EINVAL, errno.ENOSYS, errno.EOPNOTSUPP, errno.EXDEV):
        return False
    raise OSError(err, os.strerror(err), str(b))


def _replace_dir(new: Path, target: Path) -> None:
    """Put folder ``new`` at ``target`` (an existing folder), atomically where the system allows."""
    if _exchange(new, target):
        _remove(new)  # now holds the old content
        return
    old = _temp_name(target, "old")
    os.rename(target, old)
    try:
        os.rename(new, target)
    except OSError:
        os.rename(old, target)
        raise
    _remove(old)


def _inside_open(target: Path) -> bool:
    """``target`` (absolute, resolved) is the temporary folder of an open :func:`output_dir` block, or in one."""
    return any(target == t or t in target.parents for t in _OPEN.get())


def _marker(command: str) -> str:
    return f"{MARKER_PREFIX}{command}.json"


def _previous_entries(target: Path, command: str) -> set[str]:
    try:
        data = json.loads((target / _marker(command)).read_text(encoding="utf-8"))
        return {str(e) for e in data.get("entries", []) if "/" not in str(e) and str(e) not in ("", ".", "..")}
    except (OSError, ValueError, AttributeError):
        return set()


def _own_entries_only(target: Path, command: str) -> bool:
    """``target`` holds nothing but what ``command`` wrote there last time (or nothing)."""
    present = set(os.listdir(target)) - {_marker(command)}
    return present <= _previous_entries(target, command)


def _foreign_entries(tmp: Path, target: Path, command: str) -> list[str]:
    """Entries ``command`` is about to write into ``target`` that exist there but are not its own earlier output.

    Its own earlier output is what the manifest (``.vvea-<command>.json``) of its last run there names; anything
    else of the same name (a user's ``spring.csv`` beside the input, another command's file) is not replaced.
    """
    if not target.is_dir():
        return []
    previous = _previous_entries(target, command)
    return sorted(e for e in os.listdir(tmp) if e != _marker(command) and e not in previous
                  and os.path.lexists(target / e))


def _stop_if_interrupted() -> None:
    """Land nothing after a Ctrl-C that a library swallowed (a KeyboardInterrupt raised inside a weakref or
    solver callback is printed and dropped; the command line's handler noted it, :mod:`vvea_design.parallel`)."""
    from .parallel import interrupt_noted

    if interrupt_noted():
        raise KeyboardInterrupt("interrupted (Ctrl-C) while the results were made: nothing was written")


def _commit_dir(tmp: Path, target: Path, command: str) -> None:
    """Move the finished temporary folder ``tmp`` into place as ``target`` (see the module doc)."""
    entries = sorted(e for e in os.listdir(tmp) if e != _marker(command))
    (tmp / _marker(command)).write_text(json.dumps({"command": command, "entries": entries}, indent=1) + "\n",
                                        encoding="utf-8")
    trash: list[Path] = []
    with _signals_held():
        if not target.exists():
            os.rename(tmp, target)
            return
        if tmp.parent != target and _own_entries_only(target, command):
            _replace_dir(tmp, target)  # only our own earlier output: replace the folder as a whole
            return
        # the folder holds entries we did not write: replace ours one by one, never touch the rest
        previous = _previous_entries(target, command)
        for name in [*entries, _marker(command)]:
            src, dst = tmp / name, target / name
            if os.path.lexists(dst):
                both_files = src.is_file() and dst.is_file() and not dst.is_symlink()
                if both_files:
                    os.replace(src, dst)
                    continue
                if src.is_dir() and dst.is_dir() and not dst.is_symlink() and _exchange(src, dst):
                    trash.append(src)
                    continue
                old = _temp_name(dst, "old")
                os.rename(dst, old)
                trash.append(old)
            os.rename(src, dst)
        for name in previous - set(entries):
            stale = target / name
            if os.path.lexists(stale):
                old = _temp_name(stale, "old")
                os.rename(stale, old)
                trash.append(old)
    for t in trash:
        _remove(t)
    _remove(tmp)


def _as_output_error(exc: OSError, tmp_paths: list[Path], target: Path) -> OutputError | None:
    """An OSError while writing into a temporary: a clear error naming the target."""
    name = str(getattr(exc, "filename", "") or "")
    if (name and any(name.startswith(str(t)) for t in tmp_paths)) or exc.errno in _IO_ERRNOS:
        return OutputError(io_failure(exc, target))
    return None


# ---------------------------------------------------------------------------
# the two context managers
# ---------------------------------------------------------------------------

@contextlib.contextmanager
def output_dir(path: str | os.PathLike, command: str, option: str = "--out", names: tuple[str, ...] = ()) -> Iterator[Path]:
    """Yield a temporary folder; when the block ends without an exception it becomes ``path`` (see the module doc).

    Validates the location first (:func:`check_output_dir`): enter the block
    before the computation. The temporary is beside ``path`` (whole-folder
    replacement) or, when ``path`` already holds entries of others or its
    parent is not writable, inside it (entry-by-entry replacement).

    Parameters
    ----------
    path : path-like
        The result folder.
    command : str
        Plain name of the writer; names the marker file ``.vvea-<command>.json``
        that tells a later run which entries are its own.
    option : str
        The command-line option named in messages (``""`` for none).
    names : tuple of str
        Entries the command will write, when known: one that ``path`` already holds and that is not the
        command's own earlier output (named by its manifest) is refused before the block, not after the work.

    Returns
    -------
    Iterator[Path]
        (a context manager) the temporary folder to write into.

    Raises
    ------
    OutputError
        The location cannot be written (before the block), it holds a file of the same name as an output
        that the command did not write (a user's ``spring.csv``: before the block when listed in ``names``,
        else when the results land; nothing is replaced), a write into the temporary failed, or the results
        could not be moved into place.
    """
    if not re.fullmatch(r"[A-Za-z0-9_-]+", command):
        raise ValueError(f"command must be a plain name, got {command!r}")
    target = check_output_dir(path, option)
    if names and target.is_dir() and not _inside_open(target):
        previous = _previous_entries(target, command)
        foreign = sorted(n for n in names if n not in previous and os.path.lexists(target / n))
        if foreign:
            raise _refused(target, option, f"already holds {', '.join(foreign)}, which this command did not write "
                           f"(no {_marker(command)} manifest of an earlier run names it); refusing to overwrite: "
                           "move it away or choose another output folder")
    if _inside_open(target):  # an enclosing block lands the whole tree: write in place
        target.mkdir(parents=True, exist_ok=True)
        yield target
        return
    try:
        created = _make_parents(target.parent)
    except OSError as exc:
        raise OutputError(io_failure(exc, target)) from exc
    _remove_orphans(target.parent)
    if target.is_dir():
        _remove_orphans(target)
        inside = not _own_entries_only(target, command) or _writable(target.parent) is not None
        tmp = _temp_name(target / "results") if inside else _temp_name(target)
    else:
        tmp = _temp_name(target)
    token = None
    try:
        try:
            os.mkdir(tmp)
        except OSError as exc:
            raise OutputError(io_failure(exc, target)) from exc
        token = _OPEN.set((*_OPEN.get(), Path(os.path.realpath(tmp))))
        yield tmp
        _stop_if_interrupted()
    except BaseException as exc:
        if token is not None:
            _OPEN.reset(token)
        _remove(tmp)
        _remove_created(created)
        if isinstance(exc, OSError):
            err = _as_output_error(exc, [tmp], target)
            if err is not None:
                raise err from exc
        raise
    _OPEN.reset(token)
    foreign = _foreign_entries(tmp, target, command)
    if foreign:  # no input, no file of the user's, is ever an output
        _remove(tmp)
        shown = ", ".join(foreign[:5]) + (f" and {len(foreign) - 5} more" if len(foreign) > 5 else "")
        raise _refused(target, option, f"already holds {shown}, which this command did not write (no "
                       f"{_marker(command)} manifest of an earlier run names it); refusing to overwrite: move "
                       "it away or choose another output folder")
    try:
        _commit_dir(tmp, target, command)
    except OSError as exc:
        _remove(tmp)
        raise OutputError(f"could not move the results into {target}: {exc.strerror or exc}"
                          + (" (the disk is full; nothing was changed there)" if exc.errno == errno.ENOSPC else "")
                          ) from exc


@contextlib.contextmanager
def output_files(*paths: str | os.PathLike, option: str = "--out") -> Iterator[list[Path]]:
    """Yield one temporary path beside each of ``paths``; on success each replaces its target.

    Parameters
    ----------
    *paths : path-like
        The result files; every temporary must be written inside the block.
    option : str
        The command-line option named in messages (``""`` for none).

    Returns
    -------
    Iterator[list[Path]]
        (a context manager) the temporary paths, in order; each keeps the
        suffix of its target (``.json``, ``.png``), so writers that pick the
        format from the name work.

    Raises
    ------
    OutputError
        A location cannot be written, or the files could not be moved into place.
    """
    targets = [check_output_file(p, option) for p in paths]
    created: list[Path] = []
    for t in targets:
        try:
            created += _make_parents(t.parent)
        except OSError as exc:
            _remove_created(created)
            raise OutputError(io_failure(exc, t)) from exc
        _remove_orphans(t.parent)
    tmps = [_temp_name(t) for t in targets]
    try:
        yield tmps
        missing = [str(t) for t, tmp in zip(targets, tmps) if not tmp.exists()]
        if missing:
            raise RuntimeError(f"output_files: {', '.join(missing)} not written inside the block")
        _stop_if_interrupted()
    except BaseException as exc:
        for tmp in tmps:
            _remove(tmp)
        _remove_created(created)
        if isinstance(exc, OSError):
            err = _as_output_error(exc, tmps, targets[0])
            if err is not None:
                raise err from exc
        raise
    try:
        with _signals_held():
            for t, tmp in zip(targets, tmps):
                os.replace(tmp, t)
    except OSError as exc:
        for tmp in tmps:
            _remove(tmp)
        raise OutputError(f"could not move the results into {exc.filename or targets[0]}: {exc.strerror or exc}") from exc


def write_text_atomic(path: str | os.PathLike, text: str, encoding: str = "utf-8") -> Path:
    """Write a text file whole or not at all (temporary beside it, then ``os.replace``).

    Parameters
    ----------
    path : path-like
        The file.
    text : str
        Its content.
    encoding : str
        Text encoding.

    Returns
    -------
    Path
        ``path``, absolute.
    """
    with output_files(path, option="") as (tmp,):
        tmp.write_text(text, encoding=encoding)
    return Path(os.path.abspath(path))
