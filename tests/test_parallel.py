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
