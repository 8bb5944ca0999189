"""Benchmark: ``identify`` on one campaign and on ten concatenated (issue 11 item 12).

Ten copies of a 135-experiment campaign with distinct experiment ids (1,350
experiments, ~406,000 rows, every test condition repeated ten times) are
written to one CSV; each size is then read, fitted (eq. 14) and written out
with its figures (``write_identification``) in a fresh process, so the peak
resident memory of each run is its own. Prints wall time per stage and the
peak memory; target: ten campaigns in <= 10 x the time of one and <= 600 MB.

The campaign is ``shared/recordings/campaign_a.csv`` when present, else a
campaign of the independent physics bench.

Usage::

    python studies/bench_identify_scale.py [--copies 10] [--campaign PATH] [--no-figures]
"""

from __future__ import annotations

import argparse
import json
import subprocess
import sys
import tempfile
from pathlib import Path

HERE = Path(__file__).resolve().parent
ROOT = HERE.parent

_CHILD = r"""
import json, resource, sys, time
t0 = time.perf_counter()
from vvea_design.identification.recordings import read_recordings
from vvea_design.identification.identify import write_identification
t1 = time.perf_counter()
rec = read_recordings(sys.argv[1])
t2 = time.perf_counter()
summary = write_identification(rec, sys.argv[2], figures=sys.argv[3] == "1")
t3 = time.perf_counter()
print(json.dumps(dict(rows=rec.rows_read, experiments=rec.n_experiments, import_s=t1 - t0, read_s=t2 - t1,
                      identify_s=t3 - t2, total_s=t3 - t1,
                      peak_MB=resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024.0,
                      files=list(summary.files), g=summary.parameters["g"].value)))
"""


def _campaign_frame(path: Path | None):
    import pandas as pd

    shared = ROOT.parent / "shared" / "recordings" / "campaign_a.csv"
    for cand in (path, shared, Path("/work/shared/recordings/campaign_a.csv")):
        if cand is not None and Path(cand).exists():
            return pd.read_csv(cand, dtype={"experiment": str}), str(cand)
    sys.path[:0] = [str(ROOT), str(ROOT / "benches")]  # the checkout, and its benches (scripts/install.sh test installs them)
    from vvea_benches import physbench as pb

    return pb.simulate_campaign(pb.random_parameters((), seed=0)).frame, "physbench seed 0 (null campaign)"


def main(argv=None) -> dict:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--copies", type=int, default=10)
    ap.add_argument("--campaign", type=Path, default=None)
    ap.add_argument("--no-figures", action="store_true")
    args = ap.parse_args(argv)
    import pandas as pd

    one, src = _campaign_frame(args.campaign)
    results = {}
    with tempfile.TemporaryDirectory(prefix="vvea-scale-") as tmp:
        tmp = Path(tmp)
        files = {1: tmp / "one.csv", args.copies: tmp / f"x{args.copies}.csv"}
        one.to_csv(files[1], index=False)
        many = pd.concat([one.assign(experiment=one["experiment"].astype(str) + f"_r{k}") for k in range(args.copies)])
        many.to_csv(files[args.copies], index=False)
        for n, f in files.items():
            env = dict(__import__("os").environ, PYTHONPATH=str(ROOT), MPLBACKEND="Agg")
            r = subprocess.run([sys.executable, "-c", _CHILD, str(f), str(tmp / f"out{n}"), "0" if args.no_figures else "1"],
                               capture_output=True, text=True, env=env)
            if r.returncode != 0:
                print(f"{n} campaign(s): FAILED\n{r.stderr[-2000:]}", file=sys.stderr)
                results[n] = dict(error=r.stderr[-2000:])
                continue
            results[n] = json.loads(r.stdout.strip().splitlines()[-1])
    print(f"identify scale benchmark on {src} (figures {'off' if args.no_figures else 'on'})")
    print(f"{'campaigns':>9} {'experiments':>11} {'rows':>8} {'read s':>8} {'identify s':>10} {'total s':>8} {'peak MB':>8}")
    for n, r in results.items():
        if "error" in r:
            print(f"{n:>9} failed")
            continue
        print(f"{n:>9} {r['experiments']:>11} {r['rows']:>8} {r['read_s']:>8.1f} {r['identify_s']:>10.1f} "
              f"{r['total_s']:>8.1f} {r['peak_MB']:>8.0f}")
    if all("error" not in r for r in results.values()) and len(results) == 2:
        a, b = results[1], results[args.copies]
        print(f"time ratio {b['total_s'] / a['total_s']:.1f} x for {args.copies} x the data (target <= {args.copies}); "
              f"peak {b['peak_MB']:.0f} MB (target <= 600)")
    return results


if __name__ == "__main__":
    main()
