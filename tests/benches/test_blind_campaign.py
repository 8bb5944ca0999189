"""The campaign generator: exchange format, truth, determinism, the split."""

import json

import numpy as np
import pandas as pd
import pytest

from vvea_benches.blind.campaign import COLUMNS, CampaignSpec, build_campaign, campaign_specs, write_campaign
from vvea_benches.blind.registry import BLIND, CATALOGUE, DEV, PAIRS

N = 10  # samples per ramp: small campaigns


@pytest.fixture(scope="module")
def sticky():
    return build_campaign(CampaignSpec("mech-sticky_band-s0", "mechanism", ("sticky_band",), 0, "dev", n_per_ramp=N))


def test_recordings_are_the_exchange_format(sticky, tmp_path):
    rec = sticky.recordings
    assert tuple(rec.columns) == COLUMNS
    assert rec["experiment"].nunique() == 135 and len(rec) == 135 * (2 * N + 1)
    for _, g in rec.groupby("experiment", sort=False):
        assert np.all(np.diff(g["time_s"].to_numpy()) > 0)
        assert g["p2_MPa"].nunique() == 1 and g["valve_deg"].nunique() == 1
        assert abs(g["displacement_mm"].max() - 40.0) < 0.02
    csv, truth = write_campaign(sticky, tmp_path)
    back = pd.read_csv(csv)
    assert list(back.columns) == list(COLUMNS) and len(back) == len(rec)
    assert json.loads(truth.read_text())["campaign_id"] == "mech-sticky_band-s0"


def test_truth_names_mechanisms_states_noise_and_expected_ids(sticky):
    t = sticky.truth
    assert t["expected_catalogue"] == ["gas_nonlinearity"] and t["out_of_catalogue"] == ["sticky_band"]
    assert t["states"] == ["direction", "position"]
    m = t["mechanisms"][0]
    assert m["half"] == "dev" and m["effect_rms_N"] > 0 and set(m["parameters"]) == {"x_start_mm", "width_mm", "dC_N"}
    assert 2.0 <= t["noise"]["sigma_N"] <= 5.0 and 0.0 <= t["noise"]["ar_phi"] < 0.7
    assert t["noise"]["rms_N"] == pytest.approx(t["noise"]["sigma_N"], rel=0.15)


def test_generator_is_deterministic_and_seeded(sticky):
    again = build_campaign(sticky.spec)
    pd.testing.assert_frame_equal(again.recordings, sticky.recordings)
    assert json.dumps(again.truth, sort_keys=True) == json.dumps(sticky.truth, sort_keys=True)
    other = build_campaign(CampaignSpec("mech-sticky_band-s1", "mechanism", ("sticky_band",), 1, "dev", n_per_ramp=N))
    assert not other.recordings["force_N"].equals(sticky.recordings["force_N"])


def test_null_campaign_is_eq14_plus_noise():
    c = build_campaign(CampaignSpec("null-white-s0", "null", (), 0, "dev", gas_law="linear", noise="white", n_per_ramp=N))
    t = c.truth
    assert t["expected_catalogue"] == [] and t["mechanisms"] == [] and t["noise"]["ar_phi"] == 0.0
    b = t["base"]
    rec = c.recordings
    # eq. 14 with the truth's parameters leaves only noise (the velocity is the trapezoid's, not fitted here)
    from vvea_benches.blind.motion import Motion

    res = []
    for (_, g), plan in zip(rec.groupby("experiment", sort=False), t["plan"]):
        m = Motion(plan["speed_mm_s"], n_per_ramp=N)
        x, v = m.position_mm(g["time_s"].to_numpy()), m.velocity_mm_s(g["time_s"].to_numpy())
        L = b["L_N_s_per_mm"][b["valves_deg"].index(plan["valve_deg"])]
        f = b["g_N_per_mm_MPa"] * plan["p2_MPa"] * x + L * v + b["C_N"] * np.tanh(v / 0.01)
        res.append(g["force_N"].to_numpy() - f)
    res = np.concatenate(res)
    assert np.sqrt(np.mean(res**2)) == pytest.approx(t["noise"]["sigma_N"], rel=0.15)


def test_ar_noise_is_correlated():
    c = build_campaign(CampaignSpec("null-ar-s0", "null", (), 0, "dev", gas_law="linear", noise="ar", n_per_ramp=N))
    assert 0.3 <= c.truth["noise"]["ar_phi"] <= 0.7


def test_specs_split_halves_and_seeds():
    dev = campaign_specs("dev", [0, 1])
    blind = campaign_specs("blind", [0, 1])
    both = campaign_specs("all", [0, 1])
    assert {s.campaign_id for s in both} == {s.campaign_id for s in dev} | {s.campaign_id for s in blind}
    mech_dev = {s.mechanisms[0] for s in dev if s.kind == "mechanism"}
    assert mech_dev == set(DEV) and not mech_dev & set(BLIND)
    assert all(s.seed == 0 for s in dev if s.kind in ("catalogue", "null"))  # even seeds: dev
    assert all(s.seed == 1 for s in blind if s.kind in ("catalogue", "null"))
    assert sum(s.kind == "null" for s in both) == 4
    for cid in CATALOGUE:
        assert sum(s.kind == "catalogue" and s.mechanisms == (cid,) for s in both) == 2
    assert sum(s.kind == "pair" for s in both) == 2 * (len(PAIRS["dev"]) + len(PAIRS["blind"]))
    with pytest.raises(ValueError, match="half"):
        campaign_specs("both", [0])
    with pytest.raises(KeyError, match="unknown mechanism"):
        CampaignSpec("x", "mechanism", ("no_such",), 0, "dev")
