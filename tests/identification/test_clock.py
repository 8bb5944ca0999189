"""The optional absolute time column ``clock_s``: with it the campaign time keeps the pauses between runs."""

from __future__ import annotations

import numpy as np
import pytest

from vvea_benches.testbench import simulate, small_spec
from vvea_design.identification.diagnose import _clock_note
from vvea_design.identification.fit_data import FitData
from vvea_design.identification.recordings import RecordingsError, recordings_from_frame


@pytest.fixture(scope="module")
def frame():
    return simulate(small_spec(seed=3)).frame.copy()


def test_clock_column_keeps_the_pauses(frame):
    names = frame["experiment"].drop_duplicates().to_list()
    pause = 100.0
    start = {}
    t0 = 1000.0
    for k, n in enumerate(names):
        g = frame[frame["experiment"] == n]
        start[n] = t0
        t0 += float(g["time_s"].iloc[-1] - g["time_s"].iloc[0]) + pause
    f = frame.copy()
    f["clock_s"] = [start[e] + t for e, t in zip(f["experiment"], f["time_s"] - f.groupby("experiment")["time_s"].transform("min"))]
    rec = recordings_from_frame(f, "clock")
    D = FitData.from_recordings(rec)
    plain = FitData.from_recordings(recordings_from_frame(frame, "plain"))
    first, last = D.bounds[1:-1], D.bounds[1:-1] - 1
    # between two runs the clock's campaign time jumps by the pause (plus a sample or two), the plain one does not
    gap, gap_plain = D.ctime[first] - D.ctime[last], plain.ctime[first] - plain.ctime[last]
    assert np.all(gap >= pause) and np.all(gap < pause + 20.0)  # rest rows at the ends of a run are left out
    assert np.all(gap_plain < pause / 5)
    assert "pauses between runs are included" in _clock_note(rec)
    assert "no absolute time column" in _clock_note(recordings_from_frame(frame, "plain"))


def test_clock_column_must_be_finite(frame):
    f = frame.copy()
    f["clock_s"] = np.arange(len(f), dtype=float)
    f.loc[f.index[5], "clock_s"] = np.nan
    with pytest.raises(RecordingsError, match="clock_s"):
        recordings_from_frame(f, "bad")
