"""Shared test helpers."""

import atexit
import os
from pathlib import Path

import pytest

from tests.helpers import REPO, make_app, shared_once


def _worker_exit_now() -> None:  # pragma: no cover - runs at interpreter exit
    """Last exit handler of a pytest-xdist worker: flush the logs and the standard streams, then end the process.

    Every exit handler registered after this one (matplotlib, pyvista, dask, multiprocessing, ...) has run by
    now, and the worker has sent its reports and closed its channel; what is left is the interpreter's own
    teardown, which frees the session's heap object by object (CAD solids, IPOPT solvers, cached designs);
    the operating system frees it in one step.
    """
    import logging
    import sys

    logging.shutdown()
    for stream in (sys.stdout, sys.stderr):
        try:
            stream.flush()
        except Exception:
            pass
    os._exit(0)


if os.environ.get("PYTEST_XDIST_WORKER"):
    atexit.register(_worker_exit_now)  # registered early: runs after the handlers libraries register later


@pytest.fixture(scope="session")
def reference_cad_run(tmp_path_factory):
    """``vvea cad cad/design.json --out DIR`` (renders, drawings and BOM included), run once per
    test session and shared by the CAD, drawing, sync and CLI tests: ``(out_dir, exit_code, output)``."""

    def build(folder):
        from typer.testing import CliRunner

        from vvea_design.cli.cad import register

        res = CliRunner().invoke(make_app(register), ["cad", str(REPO / "cad" / "design.json"),
                                                      "--out", str(folder / "cad")])
        return {"exit_code": res.exit_code, "output": res.output}

    folder, info = shared_once(tmp_path_factory, "reference_cad_run", build)
    return folder / "cad", info["exit_code"], info["output"]


@pytest.fixture(scope="session")
def reference_model():
    """``build_cad`` of the reference design (cad/design.json), once per worker, shared read-only by the CAD,
    drawing and optimiser tests (a model builds its parts' solids once and hands out the same ones)."""
    from vvea_design.cad import build_cad
    from vvea_design.spring.design_file import load_design

    return build_cad(load_design(REPO / "cad" / "design.json"))


#: Test modules whose tests and module fixtures cost the most CPU (measured with ``--durations=0`` at idle),
#: most expensive first. They are handed out first (``--no-loadscope-reorder`` in pyproject's addopts keeps
#: this order; xdist's own reorder is by test count), so the two workers end together instead of one
#: finishing a long module alone. The modules that read the shared reference CAD run (test_cad_sync,
#: test_cad_drawing, test_cad_cli) are not listed: they come after test_cad has started building it.
HEAVY_FIRST = ("test_cad.py", "test_diagnose.py", "test_optimise.py", "test_pipeline.py", "test_study_actuator.py",
               "test_diagnose_families.py", "test_diagnose_bench.py", "test_bladder.py", "test_identify.py",
               "test_hygiene.py", "test_diagnose_shared.py", "test_design_study.py", "test_docs_build.py",
               "test_examples.py")


def pytest_collection_modifyitems(session, config, items):
    """Heavy modules first (a stable sort: the order inside a module is kept)."""
    rank = {name: i for i, name in enumerate(HEAVY_FIRST)}
    items.sort(key=lambda item: rank.get(item.path.name, len(rank)))


@pytest.hookimpl(hookwrapper=True)
def pytest_runtest_protocol(item, nextitem):
    """With ``VVEA_TEST_TIMELINE=DIR``, each worker appends ``start end nodeid`` (epoch s) per test to
    ``DIR/<worker>.txt``: where the two workers idle, to re-tune :data:`HEAVY_FIRST`."""
    import os
    import time

    folder = os.environ.get("VVEA_TEST_TIMELINE")
    t0 = time.time()
    yield
    if folder:
        worker = os.environ.get("PYTEST_XDIST_WORKER", "main")
        with open(Path(folder) / f"{worker}.txt", "a") as fh:
            fh.write(f"{t0:.3f} {time.time():.3f} {item.nodeid}\n")
