"""Speed and memory of identification and diagnosis: one campaign, and ten at once.

Prints (and writes ``timings.json`` under ``--out``, default
``studies/results/diagnosis_bench/``):

- the shared ``campaign_c`` (135 experiments): read (incl. the motion-profile
  velocity fit), Table 3 fit (eq. 14), full ``diagnose`` -- target <= 15 s on
  this 2-core machine;
- ten copies of it concatenated as one campaign (1,350 experiments, ~406,000
  rows; experiment ids made distinct): ``diagnose`` time and peak memory
  against one campaign -- targets <= 10 x the time and <= 600 MB peak.

Each size runs in its own process so that its peak resident memory
(``ru_maxrss``) is its own. The machine load is printed with the result.

Usage::

    python studies/bench_diagnose.py [--out DIR] [--copies 10] [--no-learner]
"""

from __future__ import annotations

import argparse
import json
import os
import resource
import subprocess
import sys
import time
from pathlib import Path

HERE = Path(__file__).resolve().parent


def _one(path: str, copies: int, learner: bool) -> dict:
    """Run in a child process: read ``copies`` concatenated copies of ``path``, fit eq. 14, diagnose."""
    import pandas as pd

    from vvea_design.identification.diagnose import DiagnoseSettings, diagnose
    from vvea_design.identification.effects import FitData
    from vvea_design.identification.identify import fit_model
    from vvea_design.identification.recordings import read_recordings, recordings_from_frame

    t0 = time.perf_counter()
    if copies == 1:
        rec = read_recordings(path)
    else:
        one = pd.read_csv(path)
        frames = []
        for k in range(copies):
            f = one.copy()
            f["experiment"] = f["experiment"].astype(str) + f"_r{k}"
            frames.append(f)
        rec = recordings_from_frame(pd.concat(frames, ignore_index=True), f"{copies} x {Path(path).name}")
    t1 = time.perf_counter()
    rss_read = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024.0
    D = FitData.from_recordings(rec)
    fit_model(D, ())
    t2 = time.perf_counter()
    d = diagnose(rec, DiagnoseSettings(learner=learner))
    t3 = time.perf_counter()
    return dict(
        copies=copies,
        n_experiments=rec.n_experiments,
        rows=rec.rows_read,
        read_s=t1 - t0,
        table3_fit_s=t2 - t1,
        diagnose_s=t3 - t2,
        peak_rss_after_read_MB=rss_read,
        peak_rss_MB=resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024.0,
        accepted=[e.id for e in d.report.accepted],
        heldout_rmse_N=[d.report.heldout.baseline_N, d.report.heldout.final_N],
        noise_floor_N=d.report.noise_floor_N,
    )


def main(argv=None) -> dict:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--out", type=Path, default=HERE / "results" / "diagnosis_bench")
    ap.add_argument("--recordings", type=Path, default=HERE.parents[1] / "shared" / "recordings")
    ap.add_argument("--copies", type=int, default=10)
    ap.add_argument("--no-learner", action="store_true")
    ap.add_argument("--child", type=int, default=0, help=argparse.SUPPRESS)
    args = ap.parse_args(argv)
    path = str(args.recordings / "campaign_c.csv")
    if args.child:
        print(json.dumps(_one(path, args.child, not args.no_learner)))
        return {}
    res = {"cpu_count": os.cpu_count(), "load_avg_1min_before": os.getloadavg()[0]}
    for n in (1, args.copies):
        cmd = [sys.executable, __file__, "--child", str(n), "--recordings", str(args.recordings)] + (["--no-learner"] if args.no_learner else [])
        out = subprocess.run(cmd, capture_output=True, text=True)
        if out.returncode != 0:
            sys.exit(f"the {n}-campaign run failed:\n{out.stderr}")
        res[f"x{n}"] = json.loads(out.stdout.strip().splitlines()[-1])
    res["load_avg_1min_after"] = os.getloadavg()[0]
    one, ten = res["x1"], res[f"x{args.copies}"]
    res["time_ratio"] = ten["diagnose_s"] / one["diagnose_s"]
    args.out.mkdir(parents=True, exist_ok=True)
    (args.out / "timings.json").write_text(json.dumps(res, indent=1))
    print(f"machine: {res['cpu_count']} cores, 1-min load {res['load_avg_1min_before']:.1f} before, {res['load_avg_1min_after']:.1f} after")
    for r in (one, ten):
        print(
            f"{r['copies']:>2} x campaign_c: {r['n_experiments']} experiments / {r['rows']} rows: read {r['read_s']:.1f} s, "
            f"Table 3 fit {r['table3_fit_s']:.2f} s, diagnose {r['diagnose_s']:.1f} s, peak RSS {r['peak_rss_after_read_MB']:.0f} MB "
            f"after reading, {r['peak_rss_MB']:.0f} MB in all "
            f"-> {', '.join(r['accepted']) or 'none'}"
        )
    print(
        f"diagnose: {one['diagnose_s']:.1f} s for 135 experiments (target <= 15 s); {args.copies} campaigns take "
        f"{res['time_ratio']:.1f} x one (target <= {args.copies}) at {ten['peak_rss_MB']:.0f} MB peak (target <= 600 MB)"
    )
    return res


if __name__ == "__main__":
    main()
