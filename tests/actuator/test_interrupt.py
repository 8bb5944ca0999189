"""Ctrl-C during an IPOPT solve is an interrupt, however CasADi reports it (campaign A int-04: a serial study
used to finish and exit 0 after Ctrl-C, because CasADi's signal check raised the KeyboardInterrupt inside the
solve and IPOPT returned ``NonIpopt_Exception_Thrown``, counted as one failed start)."""
from __future__ import annotations

from types import SimpleNamespace

import numpy as np
import pytest

from vvea_design.actuator.collocation import _Collocation
from vvea_design.parallel import interrupt_noted, note_interrupt


class _Solver:
    def __init__(self, status):
        self.status = status

    def __call__(self, **kw):
        return {"x": np.zeros(3), "f": 0.0}

    def stats(self):
        return {"return_status": self.status, "success": False, "iter_count": 1}


def _solve(status):
    col = SimpleNamespace(nw=3)
    z = np.zeros(3)
    return _Collocation.solve(col, _Solver(status), z, None, z - 1, z + 1)


@pytest.fixture(autouse=True)
def _reset():
    note_interrupt(False)
    yield
    note_interrupt(False)


def test_a_swallowed_keyboard_interrupt_after_sigint_is_an_interrupt():
    note_interrupt()
    assert interrupt_noted()
    with pytest.raises(KeyboardInterrupt):
        _solve("NonIpopt_Exception_Thrown")


def test_the_same_status_without_sigint_is_a_failed_solve():
    w, f, status, success, iters, secs = _solve("NonIpopt_Exception_Thrown")
    assert status == "NonIpopt_Exception_Thrown" and not success


def test_ipopts_own_stop_is_an_interrupt():
    with pytest.raises(KeyboardInterrupt):
        _solve("User_Requested_Stop")


def test_a_swallowed_interrupt_lands_no_output_folder(tmp_path):
    """Campaign A int-07: Ctrl-C during `vvea design` was raised inside a weakref callback, printed as
    'Exception ignored' and dropped; the job went on and replaced the old folder, exit 0. Now the landing refuses."""
    from vvea_design.outputs import output_dir, output_files

    old = tmp_path / "out"
    with output_dir(old, "design") as tmp:  # an earlier run's folder (its manifest names design.json as its own)
        (tmp / "design.json").write_text("old")
    note_interrupt()
    with pytest.raises(KeyboardInterrupt, match="nothing was written"):
        with output_dir(old, "design") as tmp:
            (tmp / "design.json").write_text("new")
    assert (old / "design.json").read_text() == "old"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["out"]  # no temporary folder left
    with pytest.raises(KeyboardInterrupt):
        with output_files(tmp_path / "d.json") as (tmp,):
            tmp.write_text("new")
    assert not (tmp_path / "d.json").exists()
    note_interrupt(False)
    with output_dir(old, "design") as tmp:
        (tmp / "design.json").write_text("new")
    assert (old / "design.json").read_text() == "new"


def test_the_main_job_stops_at_its_next_step_after_a_noted_interrupt():
    """int-07: the main job went on through every step after the dropped Ctrl-C; now the next step refuses."""
    from vvea_design.pipeline import _Steps

    steps = _Steps(None)
    with steps("optimise"):
        pass
    note_interrupt()
    with pytest.raises(KeyboardInterrupt, match="before the spring step"):
        with steps("spring"):
            pass


def test_a_dropped_interrupt_prints_no_trace(capsys):
    """The command line's hook keeps Python from printing 'Exception ignored ... KeyboardInterrupt'."""
    import sys

    from vvea_design.cli.errors import _signals

    seen = []
    before = sys.unraisablehook
    sys.unraisablehook = lambda u: seen.append(type(u.exc_value).__name__)
    try:
        with _signals():
            hook = sys.unraisablehook
            hook(SimpleNamespace(exc_value=KeyboardInterrupt(), exc_type=KeyboardInterrupt))
            hook(SimpleNamespace(exc_value=ValueError("x"), exc_type=ValueError))
        assert sys.unraisablehook is not hook
    finally:
        sys.unraisablehook = before
    assert seen == ["ValueError"]
