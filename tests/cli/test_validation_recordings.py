"""Recordings in another unit, sign or shape are refused naming the column, the likely unit and the override
(issue 24, campaign A family ``rec``): the library (:func:`recordings_from_frame`, :func:`read_recordings`)
and the commands (``vvea identify`` / ``vvea diagnose``) alike. The unit-scaled property test is derandomised
with a bounded count."""

from __future__ import annotations

import math

import numpy as np
import pandas as pd
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from typer.testing import CliRunner

from tests.helpers import REPO, SHARED_RECORDINGS
from vvea_benches import physbench as pb
from vvea_design.identification.recordings import RecordingsError, read_recordings, recordings_from_frame
from vvea_design.plausibility import UNITS

_GRID = pb.CampaignGrid(pressures_MPa=(2.0, 4.0), valves_deg=(100.0, 110.0), speeds_mm_s=(4.0,), samples=40)
SMALL = pb.simulate_campaign(pb.random_parameters((), seed=11, grid=_GRID)).frame  # 4 experiments, the paper's unit
CAMPAIGN = SHARED_RECORDINGS / "campaign_a.csv"


@pytest.fixture(scope="module")
def rec18() -> pd.DataFrame:
    """The first 18 experiments of the shared campaign A (what the hostile campaign uses)."""
    df = pd.read_csv(CAMPAIGN)
    return df[df["experiment"].isin({f"E{i:03d}" for i in range(18)})].reset_index(drop=True)


@pytest.fixture(scope="module")
def design():
    from vvea_design.spring.design_file import load_design

    return load_design(REPO / "cad" / "design.json")


def _scaled(df: pd.DataFrame, column: str, factor: float) -> pd.DataFrame:
    out = df.copy()
    out[column] = out[column] * factor
    return out


# -- every unit case of campaign A: refused naming the column and the unit, with the override --------------------
UNIT_CASES = [  # (column, multiply by, words the message must hold) — campaign A rec-01 ... rec-15
    ("force_N", 1e-3, ("force_N", "kN", "--force-unit kN")),
    ("p2_MPa", 1e6, ("p2_MPa", "Pa", "--pressure-unit Pa")),
    ("time_s", 1e3, ("time_s", "ms", "--time-unit ms")),
    ("displacement_mm", 1e-3, ("displacement_mm", "metres", "--displacement-unit m")),
    ("displacement_mm", 1e3, ("displacement_mm", "micrometres", "--displacement-unit um")),
    ("p2_MPa", 10.0, ("p2_MPa", "bar", "--pressure-unit bar")),
    ("valve_deg", math.pi / 180, ("valve_deg", "radians", "--valve-unit rad")),
    ("speed_mm_s", 1e-3, ("speed_mm_s", "m/s", "--speed-unit m/s")),
]


@pytest.mark.parametrize("column, factor, words", UNIT_CASES, ids=[f"{c}x{f:g}" for c, f, _ in UNIT_CASES])
@pytest.mark.parametrize("with_design", [False, True])
def test_a_column_in_another_unit_is_refused_naming_it(rec18, design, column, factor, words, with_design):
    with pytest.raises(RecordingsError) as exc:
        recordings_from_frame(_scaled(rec18, column, factor), "rec.csv", reference=design if with_design else None)
    msg = str(exc.value)
    for w in words:
        assert w in msg, msg
    assert "rec.csv" in msg


def test_displacement_in_metres_is_named_against_the_designs_travel(rec18, design):
    """rec-11: 0 ... 0.04 'mm' on a 40 mm unit."""
    with pytest.raises(RecordingsError, match=r"displacement_mm.*strokes 40 mm \(its travel\).*metres"):
        recordings_from_frame(_scaled(rec18, "displacement_mm", 1e-3), "rec.csv", reference=design)


def test_valve_beyond_a_full_turn(rec18):
    """rec-13: valve_deg + 1000."""
    df = rec18.copy()
    df["valve_deg"] += 1000
    with pytest.raises(RecordingsError, match=r"valve_deg ranges 1050 \.\.\. 1120 deg: a throttle valve turns"):
        recordings_from_frame(df, "rec.csv")


@pytest.mark.parametrize("column, words", [("force_N", ("force_N", "sign", "--negate force_N")),
                                           ("displacement_mm", ("displacement_mm", "sign", "negative",
                                                                "--negate displacement_mm"))])
def test_a_flipped_sign_is_refused_with_the_override(rec18, column, words):
    """rec-16, rec-17."""
    with pytest.raises(RecordingsError) as exc:
        recordings_from_frame(_scaled(rec18, column, -1.0), "rec.csv")
    for w in words:
        assert w in str(exc.value)


def test_an_all_zero_force_column_is_refused(rec18):
    """rec-19/20: used to write NaN into identification.json / crash diagnose."""
    with pytest.raises(RecordingsError, match="force_N is 0 N in every row"):
        recordings_from_frame(_scaled(rec18, "force_N", 0.0), "rec.csv")


def test_one_experiment_that_would_outweigh_the_others_is_refused(rec18):
    """rec-18: one experiment with 1e6 rows moved B and L(50) without a word."""
    e = rec18[rec18["experiment"] == "E017"]
    n = 30_000
    t = np.linspace(e["time_s"].iloc[0], e["time_s"].iloc[-1], n)
    big = pd.DataFrame({"experiment": "E017", "time_s": t,
                        "displacement_mm": np.interp(t, e["time_s"], e["displacement_mm"]),
                        "force_N": np.interp(t, e["time_s"], e["force_N"]), "p2_MPa": e["p2_MPa"].iloc[0],
                        "valve_deg": e["valve_deg"].iloc[0], "speed_mm_s": e["speed_mm_s"].iloc[0]})
    df = pd.concat([rec18[rec18["experiment"] != "E017"], big], ignore_index=True)
    with pytest.raises(RecordingsError, match=r"experiment 'E017' has 30,000 samples.*resample"):
        recordings_from_frame(df, "rec.csv")


def test_the_override_converts_and_reads_like_the_plain_file():
    plain = recordings_from_frame(SMALL, "small")
    kn = recordings_from_frame(_scaled(SMALL, "force_N", 1e-3), "small", units={"force_N": "kN"})
    assert np.allclose(kn.data["force_N"], plain.data["force_N"])
    flipped = recordings_from_frame(_scaled(SMALL, "force_N", -1.0), "small", negate=("force_N",))
    assert np.allclose(flipped.data["force_N"], plain.data["force_N"])
    with pytest.raises(RecordingsError, match=r"unknown force unit 'kg'"):
        recordings_from_frame(SMALL, "small", units={"force_N": "kg"})
    with pytest.raises(RecordingsError, match="unknown column"):
        recordings_from_frame(SMALL, "small", units={"pressure": "bar"})


# -- the property: a column recorded in a detectable other unit is refused; given that unit it reads as the plain -
DETECTABLE = [("force_N", u) for u in ("kN", "mN")] + [("displacement_mm", u) for u in ("m", "um")] + \
    [("p2_MPa", u) for u in ("bar", "kPa", "Pa", "psi", "GPa")] + [("time_s", u) for u in ("ms", "us")] + \
    [("valve_deg", "rad"), ("speed_mm_s", "m/s"), ("speed_mm_s", "mm/min")]
QUANTITY = {"force_N": "force", "displacement_mm": "length", "p2_MPa": "pressure", "time_s": "time",
            "valve_deg": "angle", "speed_mm_s": "speed"}


@settings(max_examples=25, deadline=None, derandomize=True, suppress_health_check=[HealthCheck.too_slow])
@given(case=st.sampled_from(DETECTABLE), jitter=st.floats(0.8, 1.25))
def test_property_a_unit_scaled_column_is_refused_and_its_override_restores_it(case, jitter):
    column, unit = case
    factor = UNITS[QUANTITY[column]][unit]
    frame = SMALL.copy()
    frame["force_N"] = frame["force_N"] * jitter  # a unit a little stiffer or softer than the paper's
    recorded = _scaled(frame, column, 1.0 / factor)  # what a file in that unit holds
    with pytest.raises(RecordingsError) as exc:
        recordings_from_frame(recorded, "rec.csv")
    assert column in str(exc.value) and unit in str(exc.value), str(exc.value)
    back = recordings_from_frame(recorded, "rec.csv", units={column: unit})
    assert np.allclose(back.data[column], frame[column], rtol=1e-9, atol=1e-9)


def test_read_recordings_refuses_non_regular_files_and_names_utf16(tmp_path):
    with pytest.raises(RecordingsError, match="/dev/zero: is a character device, not a regular file"):
        read_recordings("/dev/zero")
    import os

    os.mkfifo(tmp_path / "fifo.csv")
    with pytest.raises(RecordingsError, match="FIFO"):
        read_recordings(tmp_path / "fifo.csv")
    sparse = tmp_path / "big.csv"
    with open(sparse, "wb") as fh:
        fh.truncate(3 * 2**30)
    with pytest.raises(RecordingsError, match=r"big\.csv: is 3\.0 GiB"):
        read_recordings(sparse)
    for enc in ("utf-16", "utf-16-le"):
        p = tmp_path / f"{enc}.csv"
        p.write_bytes(SMALL.head(20).to_csv(index=False).encode(enc))
        with pytest.raises(RecordingsError, match="UTF-16"):
            read_recordings(p)
    (tmp_path / "folder.csv").mkdir()
    with pytest.raises(RecordingsError, match="is a folder"):
        read_recordings(tmp_path / "folder.csv")
