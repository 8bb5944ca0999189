"""Issue 24, second pass, class 4: a SINGLE experiment among normal ones in another unit, time base or sign, and
a displacement whose zero is offset, are refused naming the experiment (never fitted silently); the whole
campaign in another unit still names the column and the override."""

from __future__ import annotations

import numpy as np
import pandas as pd
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from typer.testing import CliRunner

from tests.helpers import REPO, SHARED_RECORDINGS
from vvea_design.cli.main import app
from vvea_design.identification.recordings import RecordingsError, recordings_from_frame
from vvea_design.spring.design_file import load_design

BASE = pd.read_csv(SHARED_RECORDINGS / "campaign_a.csv")
DESIGN_FILE = REPO / "cad" / "design.json"
DESIGN = load_design(DESIGN_FILE)
ONE = "E005"


def _one(col, fn, exp=ONE):
    d = BASE.copy()
    m = d.experiment == exp
    d.loc[m, col] = fn(d.loc[m, col])
    return d


ONE_EXPERIMENT = [
    ("force in kN", "force_N", lambda v: v / 1e3, "kN"),
    ("force in daN", "force_N", lambda v: v / 10.0, "daN"),
    ("force in kgf", "force_N", lambda v: v / 9.80665, "kgf"),
    ("force in lbf", "force_N", lambda v: v / 4.4482216152605, "lbf"),
    ("force sign flipped", "force_N", lambda v: -v, "sign looks flipped"),
    ("displacement in m", "displacement_mm", lambda v: v / 1e3, "metres"),
    ("displacement in inch", "displacement_mm", lambda v: v / 25.4, "inches"),
    ("time in ms", "time_s", lambda v: v * 1e3, "milliseconds"),
    ("p2 in bar", "p2_MPa", lambda v: v * 10.0, "bar"),
    ("p2 in kPa", "p2_MPa", lambda v: v * 1e3, "kilopascals"),
    ("zero at mid-stroke", "displacement_mm", lambda v: v - 20.0, "offset"),
]


@pytest.mark.parametrize("case, col, fn, word", ONE_EXPERIMENT, ids=[c[0] for c in ONE_EXPERIMENT])
@pytest.mark.parametrize("with_design", [False, True], ids=["no-design", "design"])
def test_one_odd_experiment_is_refused_naming_it(case, col, fn, word, with_design):
    with pytest.raises(RecordingsError) as exc:
        recordings_from_frame(_one(col, fn), "camp.csv", reference=DESIGN if with_design else None)
    msg = str(exc.value)
    assert "camp.csv" in msg and repr(ONE) in msg and word in msg, msg


def test_the_normal_campaign_is_accepted_with_and_without_design():
    assert recordings_from_frame(BASE.copy(), "camp.csv").n_experiments == BASE.experiment.nunique()
    recordings_from_frame(BASE.copy(), "camp.csv", reference=DESIGN)


def test_an_offset_beyond_the_designs_travel_is_refused():
    d = BASE.copy()
    d["displacement_mm"] += 10.0
    with pytest.raises(RecordingsError, match=r"the travel of the --design unit.*offset by 9\.9"):
        recordings_from_frame(d, "camp.csv", reference=DESIGN)


def test_the_column_override_takes_the_users_word():
    recordings_from_frame(_one("force_N", lambda v: v / 1e3), "camp.csv", units={"force_N": "N"})


def test_identify_refuses_one_experiment_in_kN_on_the_command_line(tmp_path):
    f = tmp_path / "rec.csv"
    _one("force_N", lambda v: v / 1e3).to_csv(f, index=False)
    res = CliRunner().invoke(app, ["identify", str(f), "--design", str(DESIGN_FILE), "-o", str(tmp_path / "id")],
                             env={"COLUMNS": "400"})
    text = " ".join(res.output.replace("│", " ").split())
    assert res.exit_code == 2 and "E005" in text and "kN" in text and "Traceback" not in text, text
    assert not (tmp_path / "id").exists()


# -- the property: any one experiment scaled by a unit factor of force, length or pressure (or its force negated)
# -- is refused naming it; the campaign as recorded is accepted (test above) ------------------------------------
SCALES = [("force_N", 1e-3), ("force_N", 0.1), ("force_N", 1 / 9.80665), ("force_N", 1 / 4.4482216152605),
          ("force_N", -1.0), ("displacement_mm", 1e-3), ("displacement_mm", 1 / 25.4), ("displacement_mm", 1e3),
          ("p2_MPa", 10.0), ("p2_MPa", 1e3), ("p2_MPa", 1e6), ("time_s", 1e3)]


@settings(max_examples=25, deadline=None, derandomize=True, suppress_health_check=[HealthCheck.too_slow])
@given(st.sampled_from(sorted(BASE.experiment.unique())), st.sampled_from(SCALES), st.floats(0.97, 1.03))
def test_property_one_unit_scaled_experiment_is_refused(exp, scale, jitter):
    col, factor = scale
    d = _one(col, lambda v: v * factor * (jitter if col != "p2_MPa" else 1.0), exp=exp)
    with pytest.raises(RecordingsError) as exc:
        recordings_from_frame(d, "camp.csv")
    assert "camp.csv" in str(exc.value)
    assert np.isfinite(d[col]).all()


WHOLE = [("lbf", "force_N", 1 / 4.4482216152605, "lbf"), ("daN", "force_N", 0.1, "daN"),
         ("kgf", "force_N", 1 / 9.80665, "kgf"), ("kN", "force_N", 1e-3, "kN"), ("cm", "displacement_mm", 0.1, "cm"),
         ("inch", "displacement_mm", 1 / 25.4, "inches"), ("m", "displacement_mm", 1e-3, "metres"),
         ("ms", "time_s", 1e3, "ms"), ("bar", "p2_MPa", 10.0, "bar"), ("Pa", "p2_MPa", 1e6, "Pa"),
         ("psi", "p2_MPa", 1 / 6.894757293168361e-3, "psi")]


@pytest.mark.parametrize("case, col, factor, word", WHOLE, ids=[w[0] for w in WHOLE])
def test_a_whole_campaign_in_another_unit_names_it_even_without_a_design(case, col, factor, word):
    d = BASE.copy()
    d[col] = d[col] * factor
    with pytest.raises(RecordingsError) as exc:
        recordings_from_frame(d, "camp.csv")
    msg = str(exc.value)
    assert word in msg and col in msg, msg
