"""Tests of the recordings reader: format, validation errors, velocity estimate."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pandas as pd
import pytest

from vvea_benches.testbench import simulate, small_spec
from vvea_design.identification.recordings import (
    MIN_SAMPLES_PER_EXPERIMENT,
    RecordingsError,
    read_recordings,
    recordings_from_frame,
    trapezoid_profile,
)

from tests.helpers import SHARED_RECORDINGS  # noqa: E402

SHARED = SHARED_RECORDINGS


@pytest.fixture(scope="module")
def small_frame() -> pd.DataFrame:
    return simulate(small_spec(seed=3)).frame


@pytest.fixture(scope="module")
def small_csv(tmp_path_factory, small_frame) -> Path:
    p = tmp_path_factory.mktemp("rec") / "small.csv"
    small_frame.to_csv(p, index=False)
    return p


def test_reads_shared_campaign():
    rec = read_recordings(SHARED / "campaign_a.csv")
    d = rec.data
    assert rec.n_experiments == 135
    assert rec.rows_read == len(d) == 40635
    # every experiment: start, turning point and end are the rest samples
    assert (d.groupby("experiment")["at_rest"].sum() == 3).all()
    assert rec.n_savgol == 0
    # in the cruise phase the estimated speed equals the nominal label
    cruise = d[(d["displacement_mm"] > 5) & (d["displacement_mm"] < 35)]
    rel = np.abs(np.abs(cruise["velocity_mm_s"]) - cruise["speed_mm_s"]) / cruise["speed_mm_s"]
    assert rel.max() < 0.01
    # the direction flips exactly once per experiment
    flips = d[~d["at_rest"]].groupby("experiment")["direction"].apply(lambda s: int((np.diff(s.to_numpy()) != 0).sum()))
    assert (flips == 1).all()


def test_velocity_matches_truth_on_simulated(small_frame):
    rec = recordings_from_frame(small_frame, "sim")
    spec = small_spec(seed=3)
    err = []
    for e, g in rec.data.groupby("experiment", sort=False):
        s = g["speed_mm_s"].iloc[0]
        ta = min(spec.accel_time_s, 0.25 * spec.travel_mm / s)
        t = g["time_s"].to_numpy()
        _, v_true = trapezoid_profile(t, s, s / ta, spec.travel_mm / s + ta)
        err.append(np.sqrt(np.mean((g["velocity_mm_s"].to_numpy() - v_true) ** 2)) / s)
    # displacement noise is 2 µm; a finite difference would be off by ~1e-1 mm/s at 12 mm/s
    assert np.max(err) < 0.01


def test_profile_jacobian_matches_finite_differences():
    """The analytic Jacobian the profile fit uses equals central differences away from the kinks."""
    from vvea_design.identification.recordings import _trapezoid_jac, _trapezoid_x

    rng = np.random.default_rng(7)
    for _ in range(40):
        v = rng.uniform(0.1, 15.0)
        t_rev = rng.uniform(0.5, 50.0)
        ta = rng.uniform(0.02, 0.45) * t_rev
        p = np.array([v, v / ta, t_rev, rng.uniform(-5.0, 5.0)])
        t = np.sort(rng.uniform(-0.1 * t_rev, 2.2 * t_rev, 400))  # before the start and after the end too

        def x_of(q):
            return q[3] + _trapezoid_x(t, q[0], q[1], q[2])[2]

        jac = _trapezoid_jac(t, p[0], p[1], p[2])
        fd = np.empty_like(jac)
        for j in range(4):
            h = 1e-6 * abs(p[j]) + 1e-9
            e = np.zeros(4)
            e[j] = h
            fd[:, j] = (x_of(p + e) - x_of(p - e)) / (2 * h)
        mirrored = np.minimum(t, 2 * t_rev - t)
        tm = np.clip(mirrored, 0.0, None)
        gap = 1e-3 * t_rev  # keep clear of the branch changes, the turning point and the clip at rest
        ok = (
            (np.abs(tm - ta) > gap) & (np.abs(tm - (t_rev - ta)) > gap)
            & (np.abs(t - t_rev) > gap) & (np.abs(mirrored) > gap)
        )
        assert ok.sum() > 300
        for j in range(4):  # d/dv mm s/mm, d/da mm s²/mm, d/dt_rev mm/s, d/dx0 1
            np.testing.assert_allclose(jac[ok, j], fd[ok, j], rtol=1e-5, atol=1e-6 * np.abs(fd[:, j]).max())


def _time_since_reversal_loop(t, v):
    """The definition, sample by sample: the reader's former loop."""
    sgn = np.sign(np.where(np.abs(v) > 1e-9, v, 0.0))
    out = np.zeros(len(t))
    last, prev = t[0], 0.0
    for i in range(len(t)):
        if sgn[i] != 0 and sgn[i] != prev:
            last = t[i - 1] if i > 0 else t[0]
            prev = sgn[i]
        out[i] = t[i] - last
    return out


@pytest.mark.parametrize(
    "signs",
    [
        [0, 0, 1, 1, 1, 0, -1, -1, 0, 0],  # start at rest, out and back through a rest sample
        [1, 1, 0, 0, 1, 1, -1, -1, -1, 1],  # moving from the first sample, a pause without reversal, two reversals
        [0, 0, 0, 0, 0, 0, 0, 0],  # never moves
        [-1, 1, -1, 1, 0, 1e-12, -1e-12, 0],  # reversal at every sample, then speeds below the rest threshold
        [0, 1, 0, -1, 0, 1, 0, -1],  # every move separated by rest
    ],
)
def test_time_since_reversal_equals_its_definition(signs):
    from vvea_design.identification.recordings import _time_since_reversal

    rng = np.random.default_rng(len(signs))
    t = 3.0 + np.cumsum(rng.uniform(0.01, 0.05, len(signs)))  # uneven steps, not starting at 0
    v = np.asarray(signs, float) * rng.uniform(0.5, 2.0, len(signs))
    np.testing.assert_array_equal(_time_since_reversal(t, v), _time_since_reversal_loop(t, v))


@pytest.mark.parametrize(
    "tokens",
    [
        ["0.33667", "384.19", "-1.1494", "4", "1e-3", "+2.5E+02", ".5", "1.", "+19e39", "0.1234567890123456789"],
        ["1", "2", "-0", "3"],  # integers with a negative zero: pandas reads 0
        ["-0.0", "1.5"],  # a negative zero pandas keeps
        ["-0", "1", "2", "0.5"],  # ... also written as an integer, once one entry is not
        ["-0.0000", "0.0012", "-0.0003"],  # as displacement columns have it
        ["0.5", "1.5", None, "inf", "-Infinity", "nan", "1e400"],  # missing, non-finite: left to the checks
        ["1.5", "12,5", "abc", " 2", "1_000", "0x10"],  # text Arrow refuses: pandas decides, as before
    ],
)
def test_text_columns_parse_as_pandas_does(tokens):
    from vvea_design.identification.recordings import _to_numeric

    col = pd.Series(tokens, dtype="str")
    got = _to_numeric(col).to_numpy(float)
    want = pd.to_numeric(col, errors="coerce").to_numpy(float)
    same = (got.view(np.int64) == want.view(np.int64)) | (np.isnan(got) & np.isnan(want))
    # one exception: pandas reads 19e39 one unit in the last place off; Arrow rounds correctly
    off = np.array([x == "+19e39" for x in tokens])
    assert np.all(same[~off])
    assert np.all(got[off] == 19e39) and np.all(np.abs(got[off] - want[off]) <= np.spacing(19e39))


def test_csv_and_parquet_agree(tmp_path, small_frame, small_csv):
    pq = tmp_path / "small.parquet"
    small_frame.to_parquet(pq)
    a = read_recordings(small_csv)
    b = read_recordings(pq)
    assert a.n_experiments == b.n_experiments
    np.testing.assert_allclose(a.data["velocity_mm_s"], b.data["velocity_mm_s"], atol=1e-6)
    # extra columns are kept and ignored
    assert "force_true_N" in a.data.columns


def test_savgol_fallback_for_other_motions():
    t = np.linspace(0, 10, 201)
    x = 20 * (1 - np.cos(np.pi * t / 5))  # 0 -> 40 -> 0, sinusoidal, not a trapezoid
    # a spring's force (a constant force column is refused: no load cell connected)
    df = pd.DataFrame(dict(experiment="S", time_s=t, displacement_mm=x, force_N=46.6 * x, p2_MPa=2.0, valve_deg=100.0))
    rec = recordings_from_frame(df, "sine")
    assert rec.n_savgol == 1
    v_true = 20 * np.pi / 5 * np.sin(np.pi * t / 5)
    inner = slice(10, -10)
    assert np.max(np.abs(rec.data["velocity_mm_s"].to_numpy()[inner] - v_true[inner])) < 0.05


def _bad(frame: pd.DataFrame, kind: str) -> pd.DataFrame:
    f = frame.copy()
    if kind == "missing":
        return f.drop(columns=["force_N"])
    if kind == "non_numeric":
        f["force_N"] = f["force_N"].astype(object)
        f.loc[7, "force_N"] = "12,5"
        return f
    if kind == "nan":
        f.loc[9, "displacement_mm"] = np.nan
        return f
    if kind == "time":
        f.loc[20, "time_s"] = f.loc[18, "time_s"]
        return f
    if kind == "few":
        first = f["experiment"].iloc[0]
        keep = f.index[f["experiment"] == first][: MIN_SAMPLES_PER_EXPERIMENT - 2]
        return pd.concat([f.loc[keep], f[f["experiment"] != first]])
    if kind == "two_pressures":
        f.loc[30, "p2_MPa"] = 3.0
        return f
    if kind == "split":
        first = f[f["experiment"] == f["experiment"].iloc[0]]
        return pd.concat([first.iloc[:50], f[f["experiment"] != first["experiment"].iloc[0]], first.iloc[50:]])
    raise AssertionError(kind)


@pytest.mark.parametrize(
    "kind, needle",
    [
        ("missing", "missing required column(s) force_N"),
        ("non_numeric", "column force_N holds a non-numeric value"),
        ("nan", "column displacement_mm is NaN"),
        ("time", "time_s does not increase"),
        ("few", "samples"),
        ("two_pressures", "two pressures"),
        ("split", "not contiguous"),
    ],
)
def test_bad_files_get_clear_errors(tmp_path, small_frame, kind, needle):
    p = tmp_path / f"bad_{kind}.csv"
    _bad(small_frame, kind).to_csv(p, index=False)
    with pytest.raises(RecordingsError) as exc:
        read_recordings(p)
    msg = str(exc.value)
    assert str(p) in msg  # names the file
    assert needle in msg
    if kind not in ("missing",):
        assert "line " in msg  # names the row


def test_missing_file(tmp_path):
    with pytest.raises(RecordingsError, match="not found"):
        read_recordings(tmp_path / "nope.csv")


# ---------------------------------------------------------------- issue 11: reader robustness
def _tiny_frame(n_exp: int = 3, samples: int = 41) -> pd.DataFrame:
    from vvea_benches import physbench as pb

    grid = pb.CampaignGrid(pressures_MPa=(2.0,), valves_deg=(100.0,), speeds_mm_s=(1.0, 4.0, 12.0)[:n_exp], samples=samples)
    return pb.simulate_campaign(pb.random_parameters((), seed=5, grid=grid)).frame


def test_experiment_without_motion_is_named(tmp_path):
    f = _tiny_frame()
    second = f["experiment"] == f["experiment"].unique()[1]
    f.loc[second, "displacement_mm"] = 0.0
    p = tmp_path / "static.csv"
    f.to_csv(p, index=False)
    first_line = int(np.flatnonzero(second.to_numpy())[0]) + 2
    with pytest.raises(RecordingsError, match=rf"{p}: line {first_line}: experiment 'E001' does not move"):
        read_recordings(p)


def test_semicolon_and_decimal_comma_are_read_and_said(tmp_path):
    f = _tiny_frame()
    p = tmp_path / "excel.csv"
    f.to_csv(p, index=False, sep=";", decimal=",")
    assert "," in p.read_text().splitlines()[1]
    rec = read_recordings(p)
    ref = recordings_from_frame(f, "ref")
    np.testing.assert_allclose(rec.data["force_N"], ref.data["force_N"])
    np.testing.assert_allclose(rec.data["velocity_mm_s"], ref.data["velocity_mm_s"])
    assert any("semicolon" in n and "decimal comma" in n for n in rec.notes)
    assert read_recordings(_write(tmp_path / "plain.csv", f)).notes == ()


def _write(p, f):
    f.to_csv(p, index=False)
    return p


def test_line_numbers_count_blank_lines(tmp_path):
    f = _tiny_frame().astype({"force_N": object})
    f.loc[50, "force_N"] = "oops"
    lines = f.to_csv(index=False).splitlines()
    lines.insert(3, "")  # blank lines after the header and inside the data
    lines.insert(10, "")
    lines.insert(11, "")
    p = tmp_path / "blank.csv"
    p.write_text("\n".join(lines) + "\n")
    want = [i + 1 for i, ln in enumerate(lines) if "oops" in ln][0]
    with pytest.raises(RecordingsError, match=rf"line {want}: column force_N holds a non-numeric value 'oops'"):
        read_recordings(p)


def test_wrong_field_count_names_the_file_line(tmp_path):
    f = _tiny_frame()
    lines = f.to_csv(index=False).splitlines()
    lines.insert(2, "")
    lines[20] = lines[20] + ",7,8"
    p = tmp_path / "fields.csv"
    p.write_text("\n".join(lines) + "\n")
    with pytest.raises(RecordingsError, match=r"line 21: 9 fields where the header has 7"):
        read_recordings(p)


@pytest.mark.parametrize(
    "content, needle",
    [
        (b"", "empty"),
        (b"\n\n  \n", "empty"),
        ("experiment,time_s\nä".encode("latin-1"), "not UTF-8"),
        (b"\x00\x01\x02PK", "not a text file"),
        (b"experiment;time_s;displacement_mm;force_N;p2_MPa;valve_deg\n", "no data rows"),
    ],
)
def test_unreadable_files(tmp_path, content, needle):
    p = tmp_path / "bad.csv"
    p.write_bytes(content)
    with pytest.raises(RecordingsError, match=needle):
        read_recordings(p)


def test_folder_and_bad_parquet(tmp_path):
    with pytest.raises(RecordingsError, match="is a folder"):
        read_recordings(tmp_path)
    q = tmp_path / "x.parquet"
    q.write_bytes(b"not parquet at all")
    with pytest.raises(RecordingsError, match="cannot be read as Parquet"):
        read_recordings(q)
