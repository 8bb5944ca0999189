"""The actuator tests keep the built CasADi solvers in a temporary cache (not the user's ~/.cache)."""

from __future__ import annotations

import os

import pytest


@pytest.fixture(scope="session", autouse=True)
def _solver_cache_in_a_temporary_folder(tmp_path_factory):
    """``VVEA_CACHE_DIR`` for this session (worker processes inherit it); restored afterwards."""
    old = os.environ.get("VVEA_CACHE_DIR")
    os.environ["VVEA_CACHE_DIR"] = str(tmp_path_factory.mktemp("solver_cache"))
    yield
    if old is None:
        os.environ.pop("VVEA_CACHE_DIR", None)
    else:
        os.environ["VVEA_CACHE_DIR"] = old
