"""Speed and memory of identification and diagnosis: one campaign, ten at once, the slowest benchmark campaigns.

Prints (and writes ``timings.json`` under ``--out``, default
``studies/results/diagnosis_bench/``):

- the shared ``campaign_c`` (135 experiments): read (incl. the motion-profile
  velocity fit), Table 3 fit (eq. 14), full ``diagnose`` -- target <= 15 s on
  this 2-core machine;
- ten copies of it concatenated as one campaign (1,350 experiments, ~406,000
  rows; experiment ids made distinct): ``diagnose`` time and peak memory
  against one campaign -- targets <= 10 x the time and <= 600 MB peak;
  for both sizes the peak resident memory per stage of ``diagnose``
  (baseline and noise floor, selection -- with the round and candidate
  where it peaked --, final fits, learner check), sampled from a thread;
- ``--cases``: campaigns of the independent physics bench that were the
  slowest of ``studies/diagnosis_benchmark.py`` (effect:seed, the benchmark's
  own seeds), each a full 135-experiment diagnosis -- target <= 15 s.

How it measures: each run is its own process, so its peak resident memory
(``ru_maxrss``: the whole process -- interpreter, libraries, the recordings
table and every numpy buffer) is its own; wall time and the process's CPU
time of ``diagnose`` are both printed (CPU time is less sensitive to the
load of a shared machine; the machine load is printed with the result).
A second run of each campaign size under ``tracemalloc`` gives the peak of
the Python/numpy heap during ``diagnose`` alone (what the diagnosis itself
allocates on top of the process; skip with ``--no-tracemalloc``).

Usage::

    python studies/bench_diagnose.py [--out DIR] [--copies 10] [--no-learner]
        [--cases force_lag:22,thermal:3,hysteresis:32] [--no-tracemalloc]
"""

from __future__ import annotations

import argparse
import json
import os
import resource
import subprocess
import sys
import time
import tracemalloc
from pathlib import Path

HERE = Path(__file__).resolve().parent


class _RssByStage:
    """Peak resident memory (``VmRSS`` from ``/proc/self/status``, MB) per stage of ``diagnose``, sampled by a thread every 20 ms.

    The stage is the last progress message of ``diagnose`` (baseline, each
    selection round's candidate, final fits, learner); Linux only (elsewhere
    nothing is recorded).
    """

    def __init__(self):
        import threading

        self.stage, self.peaks, self._stop = "before diagnose", {}, threading.Event()
        self._ok = Path("/proc/self/status").exists()
        self._t = threading.Thread(target=self._run, daemon=True)
        self._t.start()

    def _rss(self) -> float:
        for line in open("/proc/self/status"):
            if line.startswith("VmRSS"):
                return int(line.split()[1]) / 1024.0
        return float("nan")

    def _run(self):
        while self._ok and not self._stop.is_set():
            r = self._rss()
            if r > self.peaks.get(self.stage, 0.0):
                self.peaks[self.stage] = r
            self._stop.wait(0.02)

    def say(self, msg: str) -> None:
        self.stage = msg

    def stop(self) -> dict:
        self._stop.set()
        self._t.join()
        return self.peaks


def _stage_summary(peaks: dict) -> dict:
    """Peak RSS (MB) per stage group (selection rounds as one, with the candidate where the peak was)."""
    out: dict = {}
    for st, r in peaks.items():
        grp = "selection" if st.startswith("round ") or st == "selection" else st
        if r > out.get(grp, (0.0, ""))[0]:
            out[grp] = (r, st)
    return {k: dict(peak_rss_MB=v[0], at=v[1]) for k, v in out.items()}


def _one(path: str, copies: int, learner: bool, trace: bool = False) -> dict:
    """Run in a child process: read ``copies`` concatenated copies of ``path``, fit eq. 14, diagnose."""
    import pandas as pd

    from vvea_design.identification.diagnose import diagnose
    from vvea_design.identification.fit_data import FitData
    from vvea_design.identification.fitting import fit_model
    from vvea_design.identification.recordings import read_recordings, recordings_from_frame
    from vvea_design.identification.settings import DiagnoseSettings

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
        del one, frames
    t1 = time.perf_counter()
    rss_read = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024.0
    D = FitData.from_recordings(rec)
    fit_model(D, ())
    del D
    t2 = time.perf_counter()
    if trace:
        tracemalloc.start()
    stages = None if trace else _RssByStage()
    c2 = time.process_time()
    d = diagnose(rec, DiagnoseSettings(learner=learner), progress=None if stages is None else stages.say)
    c3 = time.process_time()
    t3 = time.perf_counter()
    if stages is not None:
        stages.say("after diagnose")
        stages = _stage_summary(stages.stop())
    heap = tracemalloc.get_traced_memory()[1] / 2**20 if trace else None
    return dict(
        copies=copies,
        n_experiments=rec.n_experiments,
        rows=rec.rows_read,
        read_s=t1 - t0,
        table3_fit_s=t2 - t1,
        diagnose_s=t3 - t2,
        diagnose_cpu_s=c3 - c2,
        peak_rss_after_read_MB=rss_read,
        peak_rss_MB=resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024.0,
        diagnose_heap_peak_MB=heap,
        peak_rss_by_stage=stages,
        accepted=[e.id for e in d.report.accepted],
        heldout_rmse_N=[d.report.heldout.baseline_N, d.report.heldout.final_N],
        noise_floor_N=d.report.noise_floor_N,
    )


def _case(spec: str, learner: bool) -> dict:
    """Run in a child process: simulate one benchmark campaign (``effect:seed``), read it back, diagnose it."""
    import tempfile

    from vvea_benches import physbench as pb
    from vvea_design.identification.diagnose import diagnose
    from vvea_design.identification.recordings import read_recordings
    from vvea_design.identification.settings import DiagnoseSettings

    effect, seed = spec.split(":")
    camp = pb.simulate_campaign(pb.random_parameters((effect,) if effect != "null" else (), seed=int(seed), grid=pb.CampaignGrid()))
    with tempfile.TemporaryDirectory(prefix="vvea-bench-") as tmp:
        rec = read_recordings(pb.write_campaign(camp, Path(tmp) / f"{effect}_{seed}.csv"))
    t0, c0 = time.perf_counter(), time.process_time()
    d = diagnose(rec, DiagnoseSettings(learner=learner))
    return dict(case=spec, n_experiments=rec.n_experiments, diagnose_s=time.perf_counter() - t0, diagnose_cpu_s=time.process_time() - c0,
                peak_rss_MB=resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024.0, accepted=[e.id for e in d.report.accepted])


def _child(args: list[str]) -> dict:
    out = subprocess.run([sys.executable, __file__] + args, capture_output=True, text=True)
    if out.returncode != 0:
        sys.exit(f"the run {' '.join(args)} failed:\n{out.stderr}")
    return json.loads(out.stdout.strip().splitlines()[-1])


def main(argv=None) -> dict:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--out", type=Path, default=HERE / "results" / "diagnosis_bench")
    ap.add_argument("--recordings", type=Path, default=HERE.parents[1] / "shared" / "recordings")
    ap.add_argument("--copies", type=int, default=10)
    ap.add_argument("--no-learner", action="store_true")
    ap.add_argument("--cases", default="force_lag:22,thermal:3,hysteresis:32",
                    help="benchmark campaigns effect:seed (comma-separated; empty: none)")
    ap.add_argument("--no-tracemalloc", action="store_true")
    ap.add_argument("--child", type=int, default=0, help=argparse.SUPPRESS)
    ap.add_argument("--trace", action="store_true", help=argparse.SUPPRESS)
    ap.add_argument("--case-child", default="", help=argparse.SUPPRESS)
    args = ap.parse_args(argv)
    path = str(args.recordings / "campaign_c.csv")
    learner = ["--no-learner"] if args.no_learner else []
    if args.child:
        print(json.dumps(_one(path, args.child, not args.no_learner, args.trace)))
        return {}
    if args.case_child:
        print(json.dumps(_case(args.case_child, not args.no_learner)))
        return {}
    res = {"cpu_count": os.cpu_count(), "load_avg_1min_before": os.getloadavg()[0]}
    for n in (1, args.copies):
        res[f"x{n}"] = _child(["--child", str(n), "--recordings", str(args.recordings)] + learner)
        if not args.no_tracemalloc:
            res[f"x{n}"]["diagnose_heap_peak_MB"] = _child(["--child", str(n), "--trace", "--recordings", str(args.recordings)] + learner)[
                "diagnose_heap_peak_MB"]
    res["cases"] = [_child(["--case-child", c] + learner) for c in args.cases.split(",") if c.strip()]
    res["load_avg_1min_after"] = os.getloadavg()[0]
    one, ten = res["x1"], res[f"x{args.copies}"]
    res["time_ratio"] = ten["diagnose_s"] / one["diagnose_s"]
    res["cpu_time_ratio"] = ten["diagnose_cpu_s"] / one["diagnose_cpu_s"]
    args.out.mkdir(parents=True, exist_ok=True)
    (args.out / "timings.json").write_text(json.dumps(res, indent=1))
    print(f"machine: {res['cpu_count']} cores, 1-min load {res['load_avg_1min_before']:.1f} before, {res['load_avg_1min_after']:.1f} after")
    for r in (one, ten):
        heap = "" if r.get("diagnose_heap_peak_MB") is None else f", diagnose's own heap peak {r['diagnose_heap_peak_MB']:.0f} MB (tracemalloc)"
        print(
            f"{r['copies']:>2} x campaign_c: {r['n_experiments']} experiments / {r['rows']} rows: read {r['read_s']:.1f} s, "
            f"Table 3 fit {r['table3_fit_s']:.2f} s, diagnose {r['diagnose_s']:.1f} s ({r['diagnose_cpu_s']:.1f} s CPU), "
            f"peak RSS {r['peak_rss_after_read_MB']:.0f} MB after reading, {r['peak_rss_MB']:.0f} MB in all{heap} "
            f"-> {', '.join(r['accepted']) or 'none'}"
        )
        if r.get("peak_rss_by_stage"):
            print("    peak RSS by stage of diagnose: " + "; ".join(
                f"{k} {v['peak_rss_MB']:.0f} MB" + (f" ({v['at']})" if v["at"] != k else "") for k, v in r["peak_rss_by_stage"].items()))
    for c in res["cases"]:
        print(f"benchmark campaign {c['case']} ({c['n_experiments']} experiments): diagnose {c['diagnose_s']:.1f} s "
              f"({c['diagnose_cpu_s']:.1f} s CPU), peak RSS {c['peak_rss_MB']:.0f} MB -> {', '.join(c['accepted']) or 'none'}")
    slow = max([one["diagnose_s"]] + [c["diagnose_s"] for c in res["cases"]])
    print(
        f"diagnose: {one['diagnose_s']:.1f} s for 135 experiments, slowest 135-experiment campaign {slow:.1f} s (target <= 15 s); "
        f"{args.copies} campaigns take {res['time_ratio']:.1f} x one in wall time, {res['cpu_time_ratio']:.1f} x in CPU time "
        f"(target <= {args.copies}) at {ten['peak_rss_MB']:.0f} MB peak RSS (target <= 600 MB)"
    )
    return res


if __name__ == "__main__":
    main()
