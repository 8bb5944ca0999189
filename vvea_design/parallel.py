"""The one parallel map every sweep goes through.

Local processes by default (all cores), a Dask distributed cluster when a
scheduler address is given, or serial in-process for ``workers=1``.  Results
are handed to ``on_result`` as they complete so callers can write them case
by case (resumable sweeps); the returned list is always in input order.

Worker processes end with their parent: each worker asks the kernel for
SIGTERM when its parent dies (Linux ``PR_SET_PDEATHSIG``; elsewhere a
watchdog thread polls the parent id), so even ``kill -9`` of the parent leaves
no orphan computing. While a map runs, SIGTERM to the parent raises
:class:`Terminated` in it (the finished results are already handed over);
on Ctrl-C or SIGTERM the parent cancels the queued items and stops the running
ones at once.

Example
-------
>>> from vvea_design.parallel import parallel_map
>>> parallel_map(abs, [-1, -2, 3], workers=1, progress=False)
[1, 2, 3]
"""

from __future__ import annotations

import contextlib
import multiprocessing
import os
import signal
import sys
import threading
import time
from collections.abc import Callable, Iterable, Iterator, Sequence
from concurrent.futures import ProcessPoolExecutor, as_completed
from concurrent.futures.process import BrokenProcessPool
from typing import Any, TypeVar

from .plausibility import check_count
from .progress import progress_bar

T = TypeVar("T")
R = TypeVar("R")

__all__ = ["parallel_map", "default_workers", "Terminated", "WorkerLost", "SchedulerUnreachable", "check_scheduler",
           "note_interrupt", "interrupt_noted", "clean_workers", "WorkersHandle"]

#: Set by the command line's SIGINT handler: a solver that swallows the KeyboardInterrupt its signal check raised
#: (CasADi's IPOPT returns ``NonIpopt_Exception_Thrown``) can still tell that the user pressed Ctrl-C.
_INTERRUPT = {"noted": False}


def note_interrupt(noted: bool = True) -> None:
    """Remember (or forget, ``noted=False``) that SIGINT arrived.

    Parameters
    ----------
    noted : bool
        True when the handler saw SIGINT; False to reset at the start of a command.
    """
    _INTERRUPT["noted"] = bool(noted)


def interrupt_noted() -> bool:
    """Whether SIGINT arrived since the last reset (:func:`note_interrupt`).

    Returns
    -------
    bool
        True after Ctrl-C.
    """
    return _INTERRUPT["noted"]


class Terminated(BaseException):
    """Raised in the parent when it receives SIGTERM during :func:`parallel_map`.

    A BaseException (like KeyboardInterrupt), so ``except Exception`` blocks
    do not swallow it; the exit status for it is 143 (128 + SIGTERM).
    """


class WorkerLost(RuntimeError):
    """A worker process ended without returning its result (killed by a signal, or it exited).

    The message names the lost worker (its process id and how it ended) and the peak memory a worker
    reached, measured; memory is named as the likely cause only when that peak was most of the machine's.

    The results finished before it were handed to ``on_result``; the exit status for it is 4 (a failed
    computation).
    """


class SchedulerUnreachable(ValueError):
    """The Dask scheduler address given cannot be reached (names the address and why)."""


def _lost_workers(pool: ProcessPoolExecutor) -> list[tuple[int, int | None]]:
    """(pid, exit code) of the pool's workers that ended on their own (not the pool's SIGTERM to the rest)."""
    procs = dict(getattr(pool, "_processes", None) or {})
    deadline = time.monotonic() + 2.0  # the pool broke because a worker ended: its exit code may lag a moment
    while True:
        ended = [(pid, p.exitcode) for pid, p in procs.items() if p.exitcode not in (None, 0)]
        if ended or not procs or time.monotonic() > deadline:
            break
        time.sleep(0.05)
    first = [w for w in ended if w[1] != -signal.SIGTERM]
    return first or ended


def _memory_total_bytes() -> int | None:
    try:
        with open("/proc/meminfo", encoding="ascii") as fh:
            for line in fh:
                if line.startswith("MemTotal:"):
                    return int(line.split()[1]) * 1024
    except (OSError, ValueError):
        return None
    return None


def lost_worker_message(description: str, lost: list[tuple[int, int | None]], done: int, total: int) -> str:
    """One line for a worker that died: which one, how it ended, the measured peak memory, what was kept.

    Parameters
    ----------
    description : str
        What the workers computed (the progress bar's label).
    lost : list of (int, int or None)
        Process id and exit code of each worker that ended on its own (negative: the signal number).
    done, total : int
        Items finished (kept) and items in all.

    Returns
    -------
    str
        ``"actuator study: worker process 1234 was killed by signal SIGKILL (kill -9, a job scheduler or the
        system) before returning its result; peak memory of a worker 161 MiB of 15.6 GiB; 3 of 16 item(s)
        finished and were kept"``. Memory is called the likely cause only when the measured peak was more than
        half of the machine's memory.
    """
    try:
        import resource

        peak = resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss * 1024  # bytes (Linux: KiB)
    except (ImportError, OSError):  # pragma: no cover - not Linux
        peak = 0
    mem = _memory_total_bytes()
    mib = f"{peak / 2**20:.0f} MiB" + (f" of {mem / 2**30:.1f} GiB" if mem else "")
    if lost:
        pid, code = lost[0]
        if code is not None and code < 0:
            try:
                name = signal.Signals(-code).name
            except ValueError:
                name = f"signal {-code}"
            how = f"was killed by {name}" + (" (kill -9, a job scheduler or the system)" if name == "SIGKILL" else "")
        else:
            how = f"exited with status {code}"
        who = f"worker process {pid}" + (f" (and {len(lost) - 1} more)" if len(lost) > 1 else "")
    else:
        who, how = "a worker process", "ended"
    cause = ""
    if peak and mem and peak > 0.5 * mem:
        cause = f"; its memory peak ({mib}) makes memory the likely cause: lower --workers or the problem size"
    return (f"{description}: {who} {how} before returning its result; peak memory of a worker {mib}{cause}; "
            f"{done} of {total} item(s) finished and were kept")


def check_scheduler(address: str, timeout_s: float = 5.0) -> str:
    """Raise :class:`SchedulerUnreachable` unless a TCP connection to ``address`` opens within ``timeout_s``.

    Parameters
    ----------
    address : str
        ``tcp://host:port`` (or ``host:port``).
    timeout_s : float
        Seconds to wait for the connection.

    Returns
    -------
    str
        ``address`` unchanged.

    Raises
    ------
    SchedulerUnreachable
        The address is malformed or nothing answers there.
    """
    import socket
    from urllib.parse import urlsplit

    parts = urlsplit(address if "://" in address else f"tcp://{address}")
    try:
        host, port = parts.hostname, parts.port
    except ValueError:
        host = port = None
    if parts.scheme not in ("tcp", "tls") or not host or not port:
        raise SchedulerUnreachable(f"scheduler {address!r}: expected an address tcp://host:port")
    try:
        with socket.create_connection((host, port), timeout=timeout_s):
            pass
    except OSError as exc:
        raise SchedulerUnreachable(f"scheduler {address}: cannot connect within {timeout_s:g} s "
                                   f"({exc.strerror or exc}); is a Dask scheduler running there?") from None
    return address


_LOCAL = threading.local()  # per thread: the handle of its :func:`clean_workers` block


class WorkersHandle:
    """What :func:`clean_workers` hands its block: :meth:`cancel` stops the pools started inside it from another
    thread."""

    def __init__(self) -> None:
        self.context = multiprocessing.get_context("forkserver")
        self.pools: list[ProcessPoolExecutor] = []
        self.cancelled = threading.Event()
        self._lock = threading.Lock()

    def add(self, pool: ProcessPoolExecutor) -> None:
        """Register a pool started in the block (stopped at once if the block was cancelled).

        Parameters
        ----------
        pool : ProcessPoolExecutor
            The pool just started.

        Returns
        -------
        None
        """
        with self._lock:
            self.pools.append(pool)
            cancelled = self.cancelled.is_set()
        if cancelled:
            _stop_now(pool)

    def cancel(self) -> None:
        """Stop the block's work: its running pools' workers end now (inside the block every map runs in a pool).

        Returns
        -------
        None
        """
        with self._lock:
            self.cancelled.set()
            pools = list(self.pools)
        for pool in pools:
            _stop_now(pool)


@contextlib.contextmanager
def clean_workers(handle: WorkersHandle | None = None) -> Iterator[WorkersHandle]:
    """Worker pools this thread starts inside the block start their workers from a fork server.

    A worker forked from a process in which another thread is busy (the main job builds the CAD while the actuator
    study runs beside it) inherits that thread's locks held at the moment of the fork, and may hang on one. The
    fork server is a clean, single-threaded process; its workers import what they run.

    Parameters
    ----------
    handle : WorkersHandle, optional
        The handle another thread keeps to cancel the block's work (None: a new one).

    Returns
    -------
    Iterator[WorkersHandle]
        (a context manager) the handle: ``handle.cancel()`` from another thread stops the block's pools.
    """
    old = getattr(_LOCAL, "handle", None)
    _LOCAL.handle = handle = handle or WorkersHandle()
    try:
        yield handle
    finally:
        _LOCAL.handle = old


def _die_with_parent(parent_pid: int | None) -> None:
    """Worker initializer: end this worker when the parent process dies.

    A forked worker also inherits the parent's SIGTERM handler of :func:`_sigterm_raises` (the pool
    starts its workers on the first submit, inside it); the worker would catch the resulting
    exception as a failed item and go on, so :func:`_stop_now` waited 5 s per worker before killing
    it. The worker gets the default action back: SIGTERM ends it at once.
    """
    signal.signal(signal.SIGTERM, signal.SIG_DFL)
    if sys.platform.startswith("linux"):
        try:
            import ctypes

            libc = ctypes.CDLL("libc.so.6", use_errno=True)
            PR_SET_PDEATHSIG = 1
            libc.prctl(PR_SET_PDEATHSIG, signal.SIGTERM, 0, 0, 0)
        except OSError:  # pragma: no cover - no libc: the watchdog below still works
            pass
    if parent_pid is None:  # started by a fork server (:func:`clean_workers`): the death signal follows it
        parent_pid = os.getppid()
    if os.getppid() != parent_pid:  # the parent died before we got here
        os._exit(1)

    def watchdog() -> None:
        while True:
            time.sleep(1.0)
            if os.getppid() != parent_pid:
                os._exit(1)

    threading.Thread(target=watchdog, name="vvea-parent-watchdog", daemon=True).start()


@contextlib.contextmanager
def _sigterm_raises() -> Iterator[None]:
    """While active (main thread only), SIGTERM raises :class:`Terminated` in the parent."""
    if threading.current_thread() is not threading.main_thread():
        yield
        return

    def handler(signum, frame):
        raise Terminated(f"received signal {signum}")

    old = signal.signal(signal.SIGTERM, handler)
    try:
        yield
    finally:
        signal.signal(signal.SIGTERM, old)


def _stop_now(pool: ProcessPoolExecutor) -> None:
    """Cancel queued items and end the running workers without waiting for them."""
    procs = list(getattr(pool, "_processes", {}).values())  # no public API for the worker processes
    pool.shutdown(wait=False, cancel_futures=True)
    for p in procs:
        if p.is_alive():
            p.terminate()
    for p in procs:
        p.join(timeout=5)
        if p.is_alive():  # pragma: no cover - a worker that ignores SIGTERM
            p.kill()


def default_workers() -> int:
    """Number of local worker processes: all cores (``VVEA_WORKERS`` overrides).

    Returns
    -------
    int
        Number of worker processes, >= 1: the value of the ``VVEA_WORKERS``
        environment variable if set, otherwise the number of CPU cores.

    Raises
    ------
    ValueError
        If ``VVEA_WORKERS`` is not a whole number >= 1.
    """
    env = os.environ.get("VVEA_WORKERS")
    if env:
        try:
            n = int(env)
        except ValueError as exc:  # pragma: no cover - user error path
            raise ValueError(f"VVEA_WORKERS must be a whole number, got {env!r}") from exc
        if n < 1:
            raise ValueError(f"VVEA_WORKERS must be >= 1, got {n}")
        return n
    return max(1, os.cpu_count() or 1)


def parallel_map(
    func: Callable[[T], R],
    items: Iterable[T],
    *,
    workers: int | None = None,
    scheduler: str | None = None,
    description: str = "working",
    on_result: Callable[[int, R], None] | None = None,
    progress: bool = True,
) -> list[R]:
    """Apply ``func`` to every item, in parallel, with a progress bar.

    Parameters
    ----------
    func
        A picklable top-level function of one argument.
    items
        The work items (materialised into a list).
    workers
        Local worker processes; ``None`` = all cores, ``1`` = serial in this
        process (deterministic, debuggable). Ignored when ``scheduler`` is set.
    scheduler
        Address of a Dask distributed scheduler (``tcp://host:port``); the
        map then runs on that cluster.
    description
        Label of the progress bar.
    on_result
        Called in the parent process as ``on_result(index, result)`` the
        moment each item completes (completion order), e.g. to append a row
        to a results file so an interrupted sweep loses nothing.
    progress
        Show a rich progress bar (cases done, elapsed, time left).

    Returns
    -------
    list
        Results in the order of ``items``. An exception raised by ``func``
        propagates (after the already finished results were handed to
        ``on_result``); functions that must never stop a sweep should catch
        their own failures and return them as data.

    Raises
    ------
    WorkerLost
        A worker process died without a result (names it, how it ended and the measured peak memory).
    SchedulerUnreachable
        ``scheduler`` is given and nothing answers there within 5 s.
    ValueError
        ``workers`` is not a whole number in 1 ... 1024.
    """
    work: Sequence[T] = list(items)
    results: list[Any] = [None] * len(work)
    if not work:
        return []

    with progress_bar(description, total=len(work), enabled=progress) as advance:

        def _done(i: int, r: R) -> None:
            results[i] = r
            if on_result is not None:
                on_result(i, r)
            advance()

        if scheduler:
            check_scheduler(scheduler)
            from distributed import Client, as_completed as dask_as_completed

            with Client(scheduler, timeout="10s") as client:
                futures = client.map(func, work, pure=False)
                index = {f.key: i for i, f in enumerate(futures)}
                for fut in dask_as_completed(futures):
                    _done(index[fut.key], fut.result())
        else:
            n = default_workers() if workers is None else check_count("workers", workers, "workers", ValueError)
            handle = getattr(_LOCAL, "handle", None)
            if handle is None and (n == 1 or len(work) == 1):  # beside a busy thread: always in a worker
                for i, item in enumerate(work):
                    _done(i, func(item))
            else:
                ctx = None if handle is None else handle.context
                pool = ProcessPoolExecutor(max_workers=min(n, len(work)), initializer=_die_with_parent,
                                           initargs=(None if ctx is not None else os.getpid(),), mp_context=ctx)
                if handle is not None:
                    handle.add(pool)
                with _sigterm_raises():
                    try:
                        futs = {pool.submit(func, item): i for i, item in enumerate(work)}
                        for fut in as_completed(futs):
                            _done(futs[fut], fut.result())
                    except (KeyboardInterrupt, Terminated):
                        # Ctrl-C or SIGTERM: stop everything now (finished results are already handed over)
                        _stop_now(pool)
                        raise
                    except BrokenProcessPool:
                        lost = _lost_workers(pool)
                        _stop_now(pool)
                        done = sum(1 for f in futs if f.done() and not f.cancelled() and f.exception() is None)
                        raise WorkerLost(lost_worker_message(description, lost, done, len(work))) from None
                    except BaseException:
                        # an error in one item: do not run (and then throw away) the queued items
                        pool.shutdown(wait=True, cancel_futures=True)
                        raise
                pool.shutdown(wait=True)
    return results
