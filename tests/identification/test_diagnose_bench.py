"""A small benchmark on the unit-test bench (`testbench`, the candidates' own formulas: it checks the
machinery, not the method): every catalogue effect at a clear SNR, and null campaigns. The proof on the
independent simulator is `studies/diagnosis_benchmark.py` (tests/identification/test_diagnosis_benchmark.py at small size)."""

from __future__ import annotations

import pytest

import numpy as np

from vvea_benches.testbench import BenchmarkCase, case_spec, run_case, simulate, summarise_benchmark
from vvea_design.identification.effects import EFFECT_IDS

SMALL_CASES = [BenchmarkCase("single", (eid,), (5.0,), 1000 + k, "small") for k, eid in enumerate(EFFECT_IDS)]
SMALL_CASES[EFFECT_IDS.index("relief_valve")] = BenchmarkCase("single", ("relief_valve",), (4.0,), 123, "small")
NULL_CASES = [BenchmarkCase("null", (), (), 2000 + k, "small") for k in range(3)]


def test_case_spec_is_deterministic():
    c = BenchmarkCase("single", ("stiction",), (3.0,), 77, "small")
    a, b = case_spec(c), case_spec(c)
    assert a == b
    np.testing.assert_array_equal(simulate(a).frame["force_N"], simulate(b).frame["force_N"])


@pytest.fixture(scope="module")
def small_bench():
    return [run_case(c) for c in SMALL_CASES + NULL_CASES]


def test_small_benchmark_detects_each_effect(small_bench):
    for r in small_bench[: len(SMALL_CASES)]:
        (eid,) = r["effects"]
        assert r["snr"][eid] == pytest.approx(5.0 if eid != "relief_valve" else 4.0, rel=0.05)
        assert r["detected"][eid], f"{eid} not detected: accepted {r['accepted']}"
        assert not r["false_positives"], f"{eid}: spurious {r['false_positives']}"
        gap = r["heldout_baseline_N"] - r["heldout_true_N"]
        if gap > 0.2:
            assert r["heldout_baseline_N"] - r["heldout_final_N"] >= 0.5 * gap, eid


def test_small_benchmark_null_campaigns_accept_nothing(small_bench):
    nulls = small_bench[len(SMALL_CASES) :]
    assert all(r["accepted"] == [] and r["discovered"] == [] for r in nulls)
    assert all(r["heldout_final_N"] == r["heldout_baseline_N"] for r in nulls)
    s = summarise_benchmark(small_bench)
    assert s["null"]["false_positive_rate"] == 0.0
    assert set(s["per_effect"]) == set(EFFECT_IDS)


