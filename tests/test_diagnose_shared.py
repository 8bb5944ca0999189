"""The shared example campaigns (../shared/recordings, made by a simulator that is not part of this
project): `diagnose` accepts exactly the effects the README names, and the fit comes down to the noise.

One class per campaign: pytest-xdist's `--dist loadscope` schedules classes separately, so the three
full-size diagnoses can run on both workers."""

from __future__ import annotations

from conftest import SHARED_RECORDINGS

from vvea_design.identification.diagnose import DiagnoseSettings, diagnose
from vvea_design.identification.recordings import read_recordings


def _check(name, expected):
    d = diagnose(read_recordings(SHARED_RECORDINGS / f"{name}.csv"), DiagnoseSettings(learner=False))
    r = d.report
    assert set(r.accepted_catalogue_ids) == expected
    assert [e.id for e in r.accepted if not e.catalogue] == []
    h = r.heldout
    assert h.final_N <= 2.0 * r.noise_floor_N
    if expected:
        assert h.final_N < 0.5 * h.baseline_N
    else:
        assert h.final_N == h.baseline_N


class TestCampaignA:
    def test_nothing_beyond_the_simple_model_is_accepted(self):
        _check("campaign_a", set())


class TestCampaignB:
    def test_turbulent_throttle_flow_is_quadratic_damping(self):
        _check("campaign_b", {"quadratic_damping"})


class TestCampaignC:
    def test_gas_nonlinearity_and_stiction(self):
        _check("campaign_c", {"gas_nonlinearity", "stiction"})
