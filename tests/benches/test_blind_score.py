"""The scorer on hand-made reports."""

import numpy as np
import pytest

from vvea_benches.blind.score import named_states, score_campaign, summarise


def truth(kind, expected, mechanisms=(), states=(), half="dev", sigma=3.0):
    return {"campaign_id": f"{kind}-x", "kind": kind, "half": half, "seed": 0, "expected_catalogue": list(expected),
            "mechanisms": [{"name": m, "effect_over_noise": 5.0} for m in mechanisms], "states": list(states),
            "noise": {"sigma_N": sigma}}


def report(accepted=(), final=3.0, baseline=10.0, flagged=False, where=(), learner=None):
    effects = [{"id": i, "catalogue": c, "accepted": True} for i, c in accepted]
    effects.append({"id": "thermal", "catalogue": True, "accepted": False})
    return {"effects": effects, "heldout_rmse_N": {"baseline": baseline, "final": final},
            "unexplained_structure": flagged, "unexplained_where": list(where), "learner": learner or {"flag": False},
            "noise_floor_N": 3.1, "runtime_s": 10.0}


def test_null_with_an_acceptance_is_a_false_accept():
    r = score_campaign(truth("null", []), report([("leakage", True)], final=3.0, baseline=3.0))
    assert r["outcome"] == "false_accept" and r["n_accepted"] == 1 and r["extra_catalogue"] == "leakage"
    assert score_campaign(truth("null", []), report(final=3.0, baseline=3.0))["outcome"] == "clean"


def test_out_of_catalogue_modelled_misnamed_flagged_missed():
    t = truth("mechanism", ["gas_nonlinearity"], ["sticky_band"], ["position", "direction"])
    ok = score_campaign(t, report([("gas_nonlinearity", True), ("friction_along_stroke", False)], final=5.9))
    assert ok["outcome"] == "modelled" and ok["modelled"] and not ok["named_as_catalogue"]
    assert ok["accepted_outside"] == "friction_along_stroke"
    bad = score_campaign(t, report([("gas_nonlinearity", True), ("stiction", True)], final=6.1, flagged=True,
                                   where=["displacement 20-25 mm: residual RMS 9 N", "along campaign_time (50 %)",
                                          "held-out RMS after the fit 8 N > 2 x noise"]))
    assert not bad["modelled"] and bad["named_as_catalogue"] and bad["outcome"] == "misnamed+flagged"
    assert bad["states_named"] == "campaign_order position" and bad["states_hit"] == "position"
    assert bad["states_recall"] == pytest.approx(0.5)
    missed = score_campaign(t, report([("gas_nonlinearity", True)], final=30.0))
    assert missed["outcome"] == "missed"
    worse = score_campaign(t, report(final=11.0, baseline=10.0))
    assert worse["final_gt_baseline"]


def test_states_from_the_learner_and_dicts():
    s, unknown = named_states({"unexplained_where": [{"feature": "valve"}, "speed 8 mm/s: x", "mystery 3: y"],
                               "learner": {"flag": True, "where": [{"feature": "time_since_reversal"}]}})
    assert s == ["since_reversal", "valve", "velocity"] and unknown == ["mystery"]
    s, _ = named_states({"unexplained_where": [], "learner": {"flag": False, "where": [{"feature": "p2"}]}})
    assert s == []


def test_summary_precision_recall_per_half():
    rows = [
        score_campaign(truth("catalogue", ["gas_nonlinearity", "stiction"]),
                       report([("gas_nonlinearity", True), ("stiction", True)])),
        score_campaign(truth("catalogue", ["gas_nonlinearity", "leakage"]), report([("gas_nonlinearity", True)])),
        score_campaign(truth("mechanism", ["gas_nonlinearity"], ["m"], ["charge"]),
                       report([("gas_nonlinearity", True), ("leakage", True)], final=4.0)),
        score_campaign(truth("null", [], half="blind"), report([("thermal", True)], final=3.0, baseline=3.0)),
    ]
    s = summarise(rows)
    dev = s["dev"]
    assert dev["catalogue"]["per_id"]["gas_nonlinearity"] == {"tp": 3, "fp": 0, "fn": 0, "precision": 1.0, "recall": 1.0}
    lk = dev["catalogue"]["per_id"]["leakage"]
    assert (lk["tp"], lk["fp"], lk["fn"]) == (0, 1, 1) and lk["precision"] == 0.0 and lk["recall"] == 0.0
    assert dev["catalogue"]["precision"] == pytest.approx(4 / 5) and dev["catalogue"]["recall"] == pytest.approx(4 / 5)
    assert dev["outside"]["campaigns"] == 1 and dev["outside"]["named_as_catalogue"] == 1
    assert dev["outside"]["outcomes"]["modelled+misnamed"] == 1
    assert s["blind"]["null"] == {"campaigns": 1, "accepted_effects": 1, "campaigns_with_acceptance": 1}
    assert s["all"]["campaigns"] == 4 and np.isnan(rows[0]["states_recall"])


def test_states_precision_and_the_tables():
    from vvea_benches.blind.tables import markdown

    t = truth("mechanism", ["gas_nonlinearity"], ["m"], ["valve", "history"])
    r = score_campaign(t, report([("gas_nonlinearity", True)], final=30.0, flagged=True,
                                 where=["valve 108 deg: x", "p2 4 MPa: x", "speed 8 mm/s: x", "direction extending: x"]))
    assert r["states_recall"] == pytest.approx(0.5) and r["states_precision"] == pytest.approx(0.25)
    s = summarise([r])
    assert s["dev"]["outside"]["flagged_states_precision_mean"] == pytest.approx(0.25)
    md = markdown(s, None, [r], [])
    assert "| mechanism-x | flagged |" in md and "BLIND" not in md.split("### DEV")[0].split("\n")[2]


def test_write_tables_into_a_page(tmp_path):
    import json

    from vvea_benches.blind.tables import write_tables

    r = score_campaign(truth("null", []), report(final=3.0, baseline=3.0))
    (tmp_path / "dev").mkdir()
    (tmp_path / "dev" / "scores.json").write_text(json.dumps({"campaigns": [r]}))
    (tmp_path / "summary.json").write_text(json.dumps({"run": {"campaigns_scored": 1, "campaigns_planned": 2},
                                                       **summarise([r])}))
    page = tmp_path / "page.md"
    page.write_text("# P\n\n<!-- untuned:start -->\nold\n<!-- untuned:end -->\ntail\n")
    write_tables(tmp_path, page)
    text = page.read_text()
    assert "old" not in text and "Campaigns scored: 1 of 2" in text and "| null-x | clean |" in text
    assert text.endswith("<!-- untuned:end -->\ntail\n")
    with pytest.raises(ValueError, match="marker"):
        write_tables(tmp_path, tmp_path / "dev" / "scores.json")
