"""The diagnosis benchmark on the independent bench, at small size."""

import importlib.util
import sys
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import pytest  # noqa: E402

from vvea_benches import physbench as pb  # noqa: E402
from tests.helpers import REPO

_spec = importlib.util.spec_from_file_location(
    "diagnosis_benchmark", REPO / "studies" / "diagnosis_benchmark.py"
)
bench = importlib.util.module_from_spec(_spec)
sys.modules["diagnosis_benchmark"] = bench  # dataclasses look their module up
_spec.loader.exec_module(bench)


def test_cases_cover_every_effect_and_nulls():
    cases = bench.make_cases(per_effect=2, n_null=3)
    assert {c.effect for c in cases if c.kind != "null"} == set(pb.EFFECTS)
    assert sum(c.kind == "null" for c in cases) == 3
    assert len({c.seed for c in cases}) == len(cases)


def _truth(effect):
    grid = pb.CampaignGrid(pressures_MPa=(2.0,), valves_deg=(100.0,), speeds_mm_s=(4.0,), samples=21)
    return pb.simulate_campaign(pb.random_parameters((effect,) if effect else (), seed=1, grid=grid)).truth


def test_scoring_rules():
    rep = {
        "effects": [
            {"id": "thermal", "accepted": True, "catalogue": True},
            {"id": "stiction", "accepted": False, "catalogue": True},
            {"id": "force_lag", "accepted": True, "catalogue": False},
        ],
        "heldout_rmse_N": {"baseline": 40.0, "final": 6.0},
        "noise_floor_N": 3.0,
        "unexplained_structure": False,
    }
    s = bench.score(bench.Case("catalogue", "thermal", 1), rep, _truth("thermal"))
    assert s["found"] and s["false_positive_catalogue"] == [] and s["final_over_floor"] == pytest.approx(2.0)
    s = bench.score(bench.Case("other", "force_lag", 1), rep, _truth("force_lag"))
    assert s["found"] and s["misnamed_as_catalogue"]  # modelled, but a catalogue effect was accepted beside it
    s = bench.score(bench.Case("null", "", 1), rep, _truth(""))
    assert not s["found"] and s["false_positive_catalogue"] == ["thermal"]
    summ = bench.summarise([dict(s, simulate_s=0.1, diagnose_s=1.0, error="")])
    assert summ["null"]["campaigns_with_false_positive"] == 1


def test_one_small_campaign_end_to_end(tmp_path):
    grid = pb.CampaignGrid(pressures_MPa=(1.0, 4.0), valves_deg=(50.0, 104.0, 110.0), speeds_mm_s=(0.1, 4.0, 12.0),
                           samples=61)
    r = bench.run_case(bench.Case("catalogue", "thermal", 3, grid))
    assert r["n_experiments"] == 18
    # either the diagnosis ran and was scored from its JSON report, or its crash was recorded
    assert r["error"] or (r["heldout_final_N"] is not None and isinstance(r["found"], bool))
    summ = bench.summarise([r])
    fig = bench.plot(summ)
    fig.savefig(tmp_path / "b.png")
    assert (tmp_path / "b.png").stat().st_size > 10000
    frame = bench.cases_frame([r])
    assert list(frame["effect"]) == ["thermal"]
    frame.to_csv(tmp_path / "cases.csv", index=False)
    back = bench.results_from_cases(tmp_path / "cases.csv")
    assert bench.summarise(back)["per_effect"] == summ["per_effect"]
