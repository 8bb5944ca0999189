"""Messages show numbers as numbers (issue 11 item 11): never ``np.float64(…)``.

The values below come from numpy, as they do in practice (a CSV column, a
computed stiffness): the message must read ``1.2``, not ``np.float64(1.2)``.
"""

from __future__ import annotations

import numpy as np
import pandas as pd
import pytest

from vvea_design.messages import show


def _assert_plain(msg: str) -> None:
    assert "np." not in msg and "float64" not in msg and "int64" not in msg, msg


@pytest.mark.parametrize(
    "value, text",
    [
        (np.float64(3.25), "3.25"),
        (np.float32(0.5), "0.5"),
        (np.int64(7), "7"),
        (np.float64("nan"), "nan"),
        (-np.inf, "-inf"),
        ((np.float64(5.0), np.float64(1.0)), "[5, 1]"),
        (np.array([1.5, 2.0]), "[1.5, 2]"),
        (123456789.0, "1.23457e+08"),
        ("wood", "'wood'"),
        (True, "True"),
        (None, "None"),
    ],
)
def test_show(value, text):
    assert show(value) == text


def _frame(**change):
    n = 12
    d = {
        "experiment": ["e1"] * n,
        "time_s": np.linspace(0.0, 1.1, n),
        "displacement_mm": np.concatenate([np.linspace(0, 40, n // 2), np.linspace(40, 0, n // 2)]),
        "force_N": np.linspace(0, 100, n),
        "p2_MPa": np.full(n, 2.0),
        "valve_deg": np.full(n, 90.0),
    }
    for k, (i, v) in change.items():
        d[k] = np.array(d[k], dtype=float)
        d[k][i] = v
    return pd.DataFrame(d)


@pytest.mark.parametrize(
    "change, match",
    [
        ({"time_s": (5, 0.1)}, r"time_s does not increase .*\(0.4 then 0.1\)"),
        ({"p2_MPa": (4, 3.0)}, r"two pressures in column p2_MPa \(2 and 3\)"),
        ({"valve_deg": (4, 60.0)}, r"two valve positions in column valve_deg \(90 and 60\)"),
    ],
)
def test_recordings_errors_show_plain_numbers(change, match):
    from vvea_design.identification.recordings import RecordingsError, recordings_from_frame

    with pytest.raises(RecordingsError, match=match) as exc:
        recordings_from_frame(_frame(**change), source="rec.csv")
    _assert_plain(str(exc.value))


def test_actuator_and_bladder_errors_show_plain_numbers():
    from vvea_design.actuator.model import pulley_radius_for_stiffness_m
    from vvea_design.bladder.check import BladderError, _positive

    with pytest.raises(ValueError) as exc:
        pulley_radius_for_stiffness_m(np.float64(-2.0), 100.0)
    _assert_plain(str(exc.value))
    assert "got -2" in str(exc.value)
    with pytest.raises(BladderError) as exc:
        _positive("thickness_mm", np.float64(-1.5))
    _assert_plain(str(exc.value))
    assert "got -1.5" in str(exc.value)
