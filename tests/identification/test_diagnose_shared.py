"""The shared example campaigns (../shared/recordings, made by a simulator that is not part of this
project): `diagnose` accepts exactly the effects the README names, and the fit comes down to the noise.

The default run diagnoses each campaign on a 50-experiment subset of its own recordings (p2 = 1 and
4 MPa, five of the nine valve positions, all five speeds: a quarter of the CPU time); the full
135-experiment campaigns, the README's runs, are `slow` (``pytest -m slow``). One class per campaign:
pytest-xdist's `--dist loadscope` schedules classes separately, so they spread over both workers.
"""

from __future__ import annotations

import pandas as pd
import pytest
from tests.helpers import SHARED_RECORDINGS

from vvea_design.identification.diagnose import diagnose
from vvea_design.identification.recordings import read_recordings, recordings_from_frame
from vvea_design.identification.settings import DiagnoseSettings


def _subset(name: str):
    """p2 in {1, 4} MPa x every other valve position x all speeds, from the campaign's own file."""
    path = SHARED_RECORDINGS / f"{name}.csv"
    df = pd.read_csv(path)
    first = df.groupby("experiment").first()
    valves = sorted(first.valve_deg.unique())
    keep = first.index[first.p2_MPa.isin([1, 4]) & first.valve_deg.isin(valves[::2])]
    assert len(keep) == 50, f"{path}: expected 2 pressures x 5 valves x 5 speeds in the subset, got {len(keep)}"
    return recordings_from_frame(df[df.experiment.isin(keep)], source=f"{path} (subset)")


def _check(rec, expected):
    r = diagnose(rec, DiagnoseSettings(learner=False)).report
    assert set(r.accepted_catalogue_ids) == expected
    assert [e.id for e in r.accepted if not e.catalogue] == []
    h = r.heldout
    assert h.final_N <= 2.0 * r.noise_floor_N
    if expected:
        assert h.final_N < 0.5 * h.baseline_N
    else:
        assert h.final_N == h.baseline_N


CASES = {"campaign_a": set(), "campaign_b": {"quadratic_damping"}, "campaign_c": {"gas_nonlinearity", "stiction"}}


class TestCampaignA:
    """Nothing beyond the simple model: no effect may be accepted."""

    def test_subset(self):
        _check(_subset("campaign_a"), CASES["campaign_a"])

    @pytest.mark.slow
    def test_full(self):
        _check(read_recordings(SHARED_RECORDINGS / "campaign_a.csv"), CASES["campaign_a"])


class TestCampaignB:
    """Turbulent throttle flow: quadratic damping."""

    def test_subset(self):
        _check(_subset("campaign_b"), CASES["campaign_b"])

    @pytest.mark.slow
    def test_full(self):
        _check(read_recordings(SHARED_RECORDINGS / "campaign_b.csv"), CASES["campaign_b"])


class TestCampaignC:
    """Antagonistic isothermal chambers and stiction."""

    def test_subset(self):
        _check(_subset("campaign_c"), CASES["campaign_c"])

    @pytest.mark.slow
    def test_full(self):
        _check(read_recordings(SHARED_RECORDINGS / "campaign_c.csv"), CASES["campaign_c"])
