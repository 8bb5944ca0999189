"""Helpers the tests import (``from tests.helpers import ...``): the repository's paths, a typer app with one
topic's commands, a build shared by the pytest-xdist workers, and process probes read from ``/proc``."""

from __future__ import annotations

import time
from pathlib import Path

import typer

#: The repository root.
REPO = Path(__file__).resolve().parents[1]

#: The shared example campaigns (CI clones the repository with shared/ beside it).
SHARED_RECORDINGS = REPO.parent / "shared" / "recordings"


def make_app(register) -> typer.Typer:
    """A typer app with one topic module's commands registered, as `vvea` would have them.

    The empty callback keeps typer from collapsing a single command into the app itself.
    """
    app = typer.Typer()

    @app.callback()
    def _main():  # pragma: no cover - typer needs a callback to keep sub-commands
        pass

    register(app)
    return app


def shared_once(tmp_path_factory, name: str, build):
    """Run ``build(folder)`` once per test session, across pytest-xdist workers, and return
    ``(folder, info)`` where ``info`` is the JSON-able value ``build`` returned.

    The first worker that asks builds into ``<session basetemp>/<name>`` under an exclusive
    ``flock``; the others wait for it and read the result. A failed build leaves no marker,
    so the next caller builds again (and fails the same way, visibly).
    """
    import fcntl
    import json
    import os
    import shutil

    root = tmp_path_factory.getbasetemp()
    if os.environ.get("PYTEST_XDIST_WORKER"):
        root = root.parent  # the controller's basetemp, shared by the workers
    folder = root / name
    with open(root / f"{name}.lock", "w") as lock:
        fcntl.flock(lock, fcntl.LOCK_EX)
        try:
            done = root / f"{name}.done.json"
            if not done.exists():
                shutil.rmtree(folder, ignore_errors=True)
                folder.mkdir()
                done.write_text(json.dumps(build(folder) or {}))
            return folder, json.loads(done.read_text())
        finally:
            fcntl.flock(lock, fcntl.LOCK_UN)


def children(pid: int) -> list[int]:
    """Live (non-zombie) child processes of ``pid``, from /proc."""
    out = []
    for d in Path("/proc").iterdir():
        if d.name.isdigit():
            try:
                fields = (d / "stat").read_text().rsplit(")", 1)[1].split()
            except OSError:
                continue
            if int(fields[1]) == pid and fields[0] != "Z":
                out.append(int(d.name))
    return out


def alive(pid: int) -> bool:
    """Whether process ``pid`` exists and is not a zombie."""
    try:
        state = Path(f"/proc/{pid}/stat").read_text().rsplit(")", 1)[1].split()[0]
    except OSError:
        return False
    return state != "Z"


def wait_until(cond, timeout: float) -> bool:
    """Poll ``cond()`` every 0.2 s until it is true or ``timeout`` seconds have passed; its last value."""
    t0 = time.monotonic()
    while time.monotonic() - t0 < timeout:
        if cond():
            return True
        time.sleep(0.2)
    return cond()
