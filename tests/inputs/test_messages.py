"""Issue 24, second pass, class 6: the weak messages. A killed worker is named with how it ended and the
measured peak memory (memory called the cause only when the peak was most of the machine's); an error about a
huge grid or value stays a few lines."""

from __future__ import annotations

import os
import signal
import time

import pytest
from typer.testing import CliRunner

from vvea_design.cli.main import app
from vvea_design.messages import show
from vvea_design.parallel import WorkerLost, lost_worker_message, parallel_map


def _dies_on_two(i: int) -> int:
    if i == 2:
        os.kill(os.getpid(), signal.SIGKILL)
    time.sleep(0.1)
    return i


def test_a_killed_worker_is_named_with_its_signal_and_the_measured_peak():
    with pytest.raises(WorkerLost) as exc:
        parallel_map(_dies_on_two, range(5), workers=2, progress=False, description="demo sweep")
    msg = str(exc.value)
    assert msg.startswith("demo sweep: worker process ") and "SIGKILL" in msg, msg
    assert "peak memory of a worker" in msg and "MiB" in msg and "item(s) finished and were kept" in msg, msg
    assert "out of memory" not in msg and "memory the likely cause" not in msg, msg
    assert "\n" not in msg


def test_memory_is_named_only_when_it_was_the_measured_cause(monkeypatch):
    import vvea_design.parallel as par

    monkeypatch.setattr(par, "_memory_total_bytes", lambda: 1024)  # a peak above half the machine's memory
    msg = lost_worker_message("demo", [(123, -9)], 1, 4)
    assert "worker process 123 was killed by SIGKILL" in msg and "memory the likely cause" in msg, msg
    msg = lost_worker_message("demo", [(7, 3)], 0, 2)
    assert "worker process 7 exited with status 3" in msg


def test_a_huge_grid_is_refused_in_a_few_lines():
    grid = ",".join(f"{0.001 * (i + 1):.3f}" for i in range(3000)) + ":1"
    res = CliRunner().invoke(app, ["study", "rest-to-rest", "-o", "/tmp/r24-never-written", "--grid", grid],
                             env={"COLUMNS": "100"})
    assert res.exit_code == 2
    # the message itself, without the panel's frame and padding (its width follows the terminal the test sees)
    lines = [" ".join(line.strip(" │╭╮╰╯─").split()) for line in res.output.splitlines()]
    text = "\n".join(line for line in lines if line)
    assert len(text) < 1500 and len(text.splitlines()) <= 12, text
    assert "2500" in text and "3000 amplitudes" in text


def test_degrees_in_the_grid_and_radians_in_the_throttle_range_are_named():
    res = CliRunner().invoke(app, ["study", "rest-to-rest", "-o", "/tmp/r24-never-written", "--grid", "30,60:1"],
                             env={"COLUMNS": "400"})
    assert res.exit_code == 2 and "degrees" in res.output, res.output
    from vvea_design.jobs.common import OptionError
    from vvea_design.jobs.studies import _check_mapping

    with pytest.raises(OptionError, match="radians"):
        _check_mapping(None, None, 0.87, 2.09)
    _check_mapping(None, None, 50.0, 120.0)


def test_show_keeps_long_values_short():
    assert len(show(tuple(range(3000)))) < 80 and "3000 values" in show(list(range(3000)))
    assert "5000 characters" in show(b"x" * 4997) and show([1, 2]) == "[1, 2]"
