"""The one parallel map: order, callbacks, errors, serial and process paths."""

import pytest

from vvea_design.parallel import default_workers, parallel_map


def square(x):
    return x * x


def boom(x):
    if x == 3:
        raise ValueError("bad item 3")
    return x


@pytest.mark.parametrize("workers", [1, 2])
def test_results_in_input_order_and_callback_sees_every_item(workers):
    seen = {}
    out = parallel_map(square, range(10), workers=workers, progress=False, on_result=lambda i, r: seen.__setitem__(i, r))
    assert out == [i * i for i in range(10)]
    assert seen == {i: i * i for i in range(10)}


@pytest.mark.parametrize("workers", [1, 2])
def test_errors_propagate_after_finished_results_were_handed_over(workers):
    seen = []
    with pytest.raises(ValueError, match="bad item 3"):
        parallel_map(boom, range(6), workers=workers, progress=False, on_result=lambda i, r: seen.append(i))
    if workers == 1:
        assert seen == [0, 1, 2]


def test_empty_and_worker_settings(monkeypatch):
    assert parallel_map(square, [], progress=False) == []
    monkeypatch.setenv("VVEA_WORKERS", "3")
    assert default_workers() == 3
    monkeypatch.setenv("VVEA_WORKERS", "0")
    with pytest.raises(ValueError, match="VVEA_WORKERS"):
        default_workers()
    with pytest.raises(ValueError, match="workers must be >= 1"):
        parallel_map(square, [1, 2], workers=0, progress=False)


# -- workers end with their parent (issue 11 item 6) ---------------------------------------------------
import os  # noqa: E402
import signal  # noqa: E402
import subprocess  # noqa: E402
import sys  # noqa: E402
import textwrap  # noqa: E402
import time  # noqa: E402
from pathlib import Path  # noqa: E402

from tests.helpers import REPO, alive as _alive, children as _children, wait_until as _wait  # noqa: E402

ROOT = str(REPO)


def _start_parent(tmp_path) -> tuple[subprocess.Popen, list[int]]:
    script = tmp_path / "parent.py"
    script.write_text(textwrap.dedent(f"""
        import sys, time
        sys.path.insert(0, {ROOT!r})
        from vvea_design.parallel import parallel_map

        def work(i):
            time.sleep(300)
            return i

        if __name__ == "__main__":
            parallel_map(work, range(6), workers=2, progress=False)
    """))
    # SIGINT back to its default in the child: a suite started in the background by a shell without job
    # control inherits SIGINT ignored, and a parent ignoring Ctrl-C would not be the case under test
    proc = subprocess.Popen([sys.executable, str(script)], stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                            preexec_fn=lambda: signal.signal(signal.SIGINT, signal.SIG_DFL))
    assert _wait(lambda: len(_children(proc.pid)) >= 2, 60), "workers did not start"
    return proc, _children(proc.pid)


@pytest.mark.skipif(not sys.platform.startswith("linux"), reason="reads /proc")
@pytest.mark.parametrize("sig", [signal.SIGTERM, signal.SIGKILL, signal.SIGINT])
def test_killing_the_parent_ends_its_workers(tmp_path, sig):
    proc, workers = _start_parent(tmp_path)
    try:
        os.kill(proc.pid, sig)
        proc.wait(timeout=120)  # generous: only a failure waits this long (the suite may run under load)
        assert _wait(lambda: not any(_alive(w) for w in workers), 15), \
            f"workers {[w for w in workers if _alive(w)]} outlived their parent ({sig.name})"
    finally:
        for w in workers + [proc.pid]:
            if _alive(w):
                os.kill(w, signal.SIGKILL)
    if sig == signal.SIGTERM:
        assert b"Terminated" in proc.stderr.read()
