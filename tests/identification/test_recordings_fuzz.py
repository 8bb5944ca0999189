"""Fuzz the recordings reader (issue 11): any file gives a Recordings or a RecordingsError, never a traceback."""

from __future__ import annotations

import numpy as np
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from vvea_benches import physbench as pb
from vvea_design.identification.recordings import Recordings, RecordingsError, read_recordings

_GRID = pb.CampaignGrid(pressures_MPa=(2.0,), valves_deg=(100.0, 110.0), speeds_mm_s=(4.0,), samples=25)
VALID = pb.simulate_campaign(pb.random_parameters((), seed=11, grid=_GRID)).frame.to_csv(index=False).encode()
LINES = VALID.decode().splitlines()

_TOKENS = ["", "nan", "inf", "-inf", "1e309", "abc", "1,5", ";", ",", '"', "\t", "0", "-1", "1e-300", "E000", "E001", " "]


def _check(tmp_path_factory, data: bytes, suffix: str = ".csv") -> None:
    p = tmp_path_factory.mktemp("fuzz") / f"f{suffix}"
    p.write_bytes(data)
    try:
        rec = read_recordings(p)
    except RecordingsError as exc:
        assert str(p) in str(exc) or p.name in str(exc)
        return
    assert isinstance(rec, Recordings)
    assert np.isfinite(rec.data["velocity_mm_s"]).all()


@settings(max_examples=60, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture])
@given(st.binary(max_size=400))
def test_random_bytes(tmp_path_factory, data):
    _check(tmp_path_factory, data)
    _check(tmp_path_factory, data, ".parquet")


@settings(max_examples=80, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture])
@given(
    st.lists(
        st.tuples(
            st.sampled_from(["field", "delete_line", "dup_line", "truncate", "byte"]),
            st.integers(0, len(LINES) - 1),
            st.integers(0, 7),
            st.sampled_from(_TOKENS),
            st.integers(0, 255),
        ),
        min_size=1,
        max_size=4,
    )
)
def test_csv_mutations(tmp_path_factory, edits):
    lines = list(LINES)
    raw_byte = None
    for kind, i, j, tok, b in edits:
        i = min(i, len(lines) - 1)
        if kind == "field" and lines:
            parts = lines[i].split(",")
            parts[min(j, len(parts) - 1)] = tok
            lines[i] = ",".join(parts)
        elif kind == "delete_line" and len(lines) > 1:
            del lines[i]
        elif kind == "dup_line":
            lines.insert(i, lines[i])
        elif kind == "truncate":
            lines = lines[: max(i, 1)]
        elif kind == "byte":
            raw_byte = (i, b)
    data = ("\n".join(lines) + "\n").encode()
    if raw_byte is not None:
        k = raw_byte[0] * 7 % max(len(data), 1)
        data = data[:k] + bytes([raw_byte[1]]) + data[k + 1 :]
    _check(tmp_path_factory, data)
