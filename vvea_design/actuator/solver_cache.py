"""A disk cache of the built CasADi solvers: a process loads them instead of deriving them again.

Building a parametric solver (the NLP's SX expressions, then IPOPT's exact Hessian and Jacobians) takes
0.5-3 s per mesh and structure, once per process; the design study's workers pay it in every ``vvea
design``. A built solver is written with CasADi's own serialisation (``Function.serialize``) and read back
with ``Function.deserialize`` (about 6 times faster; the solves are bit-identical, ``tests/actuator``).

The file name is a hash of everything the functions depend on: the problem's kind and options (mesh, IPOPT
options), the CasADi version and the source text of :mod:`~vvea_design.actuator.collocation` and
:mod:`~vvea_design.actuator.ocp` — a change to any of them is a new file, never a stale solver. Files are
written atomically (a temporary file renamed), so parallel workers may race harmlessly. A file that cannot
be read is rebuilt.

``VVEA_SOLVER_CACHE=0`` turns the cache off; ``VVEA_CACHE_DIR`` moves it (default
``$XDG_CACHE_HOME/vvea_design/casadi``, else ``~/.cache/vvea_design/casadi``).
"""

from __future__ import annotations

import hashlib
import os
import pickle
import tempfile
from collections.abc import Callable
from pathlib import Path

import casadi as ca

__all__ = ["cache_dir", "cache_enabled", "cached_functions"]


def cache_enabled() -> bool:
    """Whether solvers are cached on disk (``VVEA_SOLVER_CACHE`` is not ``0``/``false``/``no``/``off``).

    Returns
    -------
    bool
        True unless the environment switches the cache off.
    """
    return os.environ.get("VVEA_SOLVER_CACHE", "1").strip().lower() not in ("0", "false", "no", "off")


def cache_dir() -> Path:
    """The folder of the cached solvers.

    Returns
    -------
    Path
        ``VVEA_CACHE_DIR`` if set, else ``$XDG_CACHE_HOME/vvea_design/casadi`` or ``~/.cache/vvea_design/casadi``.
    """
    env = os.environ.get("VVEA_CACHE_DIR")
    if env:
        return Path(env)
    base = os.environ.get("XDG_CACHE_HOME") or str(Path.home() / ".cache")
    return Path(base) / "vvea_design" / "casadi"


def _source_fingerprint() -> str:
    """sha256 of the source text the solvers are built from (collocation.py, ocp.py) and the CasADi version."""
    h = hashlib.sha256(ca.__version__.encode())
    here = Path(__file__).resolve().parent
    for name in ("collocation.py", "ocp.py"):
        h.update((here / name).read_bytes())
    return h.hexdigest()


_FINGERPRINT: str | None = None


def cached_functions(kind: str, key: tuple, build: Callable[[], dict[str, ca.Function]]) -> dict[str, ca.Function]:
    """The CasADi functions ``build()`` returns, from the disk cache when they were built before.

    Parameters
    ----------
    kind
        Name of the problem (part of the file name, e.g. ``"rest_to_rest"``).
    key
        Everything else the functions depend on (mesh, structure, options): its ``repr`` is hashed.
    build
        Builds the functions (name to :class:`casadi.Function`); called on a miss.

    Returns
    -------
    dict of str to casadi.Function
        The functions by name (built, or read back from the cache).
    """
    if not cache_enabled():
        return build()
    global _FINGERPRINT
    if _FINGERPRINT is None:
        _FINGERPRINT = _source_fingerprint()
    digest = hashlib.sha256(f"{kind}|{key!r}|{_FINGERPRINT}".encode()).hexdigest()[:24]
    path = cache_dir() / f"{kind}-{digest}.pkl"
    if path.exists():
        try:
            with path.open("rb") as fh:
                data = pickle.load(fh)
            return {name: ca.Function.deserialize(text) for name, text in data.items()}
        except Exception:  # noqa: BLE001 - a damaged or foreign file: build again and replace it
            pass
    funcs = build()
    try:
        path.parent.mkdir(parents=True, exist_ok=True)
        fd, tmp = tempfile.mkstemp(dir=path.parent, prefix=path.name, suffix=".tmp")
        with os.fdopen(fd, "wb") as fh:
            pickle.dump({name: f.serialize() for name, f in funcs.items()}, fh, protocol=pickle.HIGHEST_PROTOCOL)
        os.replace(tmp, path)
    except OSError:  # a read-only or full disk: the solvers still work, only uncached
        pass
    return funcs
