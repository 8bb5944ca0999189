"""Speed of identification and diagnosis on 135-experiment campaigns.

Prints (and writes ``timings.json`` under ``--out``, default
``studies/results/diagnosis_bench/``) the wall time of: reading a campaign
(including the motion-profile velocity fit), fitting Table 3 (eq. 14), and a
full ``diagnose`` (selection, final fits, learner check) -- on the shared
campaign_c and on one simulated campaign with two concealed effects. The
target is a 135-experiment campaign diagnosed in under 2 minutes and Table 3
identified in seconds.

Usage::

    python studies/bench_diagnose.py [--out DIR] [--repeat 1]
"""

from __future__ import annotations

import argparse
import json
import os
import time
from dataclasses import replace
from pathlib import Path

import numpy as np

from vvea_design.identification.diagnose import DiagnoseSettings, diagnose
from vvea_design.identification.effects import FitData
from vvea_design.identification.identify import fit_model
from vvea_design.progress import console
from vvea_design.identification.recordings import read_recordings, recordings_from_frame
from vvea_design.identification.testbench import CampaignSpec, random_effect, simulate

HERE = Path(__file__).resolve().parent


def _time(f, repeat):
    best, out = np.inf, None
    for _ in range(repeat):
        t = time.perf_counter()
        out = f()
        best = min(best, time.perf_counter() - t)
    return best, out


def main(argv=None) -> dict:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--out", type=Path, default=HERE / "results" / "diagnosis_bench")
    ap.add_argument("--recordings", type=Path, default=HERE.parents[1] / "shared" / "recordings")
    ap.add_argument("--repeat", type=int, default=1)
    args = ap.parse_args(argv)
    res = {"cpu_count": os.cpu_count(), "load_avg_1min": os.getloadavg()[0]}
    path = args.recordings / "campaign_c.csv"
    t_read, rec = _time(lambda: read_recordings(path), args.repeat)
    D = FitData.from_recordings(rec)
    t_fit, _ = _time(lambda: fit_model(D, ()), args.repeat)
    t_diag, dg = _time(lambda: diagnose(rec, DiagnoseSettings()), args.repeat)
    res["campaign_c"] = dict(
        n_experiments=rec.n_experiments, rows=rec.rows_read, read_s=t_read, table3_fit_s=t_fit, diagnose_s=t_diag,
        accepted=[e["id"] for e in dg.report["effects"] if e["accepted"]],
    )
    spec = CampaignSpec(seed=7)
    rng = np.random.default_rng(7)
    spec = replace(spec, effects=(random_effect("thermal", 3.0, spec, rng), random_effect("leakage", 3.0, spec, rng)))
    frame = simulate(spec).frame
    t_read2, rec2 = _time(lambda: recordings_from_frame(frame, "simulated"), args.repeat)
    t_diag2, dg2 = _time(lambda: diagnose(rec2, DiagnoseSettings()), args.repeat)
    res["simulated_thermal_leakage"] = dict(
        n_experiments=rec2.n_experiments, rows=rec2.rows_read, read_s=t_read2, diagnose_s=t_diag2,
        accepted=[e["id"] for e in dg2.report["effects"] if e["accepted"]],
    )
    args.out.mkdir(parents=True, exist_ok=True)
    (args.out / "timings.json").write_text(json.dumps(res, indent=1))
    console.print(f"machine: {res['cpu_count']} cores, load {res['load_avg_1min']:.1f}")
    for k in ("campaign_c", "simulated_thermal_leakage"):
        r = res[k]
        extra = f", Table 3 fit {r['table3_fit_s']:.3f} s" if "table3_fit_s" in r else ""
        console.print(
            f"{k}: {r['n_experiments']} experiments / {r['rows']} rows: read {r['read_s']:.1f} s{extra}, "
            f"diagnose {r['diagnose_s']:.1f} s (target < 120 s) -> {', '.join(r['accepted']) or 'none'}"
        )
    return res


if __name__ == "__main__":
    main()
