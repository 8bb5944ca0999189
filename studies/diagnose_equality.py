"""Before/after check of a change that must not move a diagnosis: dump the reports of a few campaigns, compare two dumps.

A speed-up of ``diagnose`` must leave its results alone. Run ``dump`` on the
code before the change and on the code after it (e.g. two worktrees or two
commits), then ``compare``:

- **results** (the exit code): the accepted effects, their parameters and
  shape values, the held-out RMS per step, the noise floor, the final
  model -- equal to ``--rtol`` (default 1e-6 relative);
- **other fields** (printed, not judged): the evidence of rejected
  candidates and the flexible-learner check. A candidate whose held-out gain
  is zero to rounding (1e-11 of the mean square) can count a fold as
  improved or not by the last bit, and the gradient-boosted trees of the
  learner split on residuals that moved by rounding; neither changes what
  the diagnosis concludes.

The campaigns: ``campaign_c`` (``--recordings``) and physics-bench campaigns
``effect:seed`` with the diagnosis benchmark's own seeds (the slowest types
of ``studies/diagnosis_benchmark.py``: thermal, force_lag, hysteresis).
Each case also prints its wall and CPU time and the machine load.

Usage::

    python studies/diagnose_equality.py dump DIR [--cases campaign_c,thermal:5,force_lag:23,hysteresis:31]
    python studies/diagnose_equality.py compare DIR_BEFORE DIR_AFTER [--rtol 1e-6]
"""

from __future__ import annotations

import argparse
import json
import math
import os
import sys
import tempfile
import time
from pathlib import Path

HERE = Path(__file__).resolve().parent
DEFAULT_CASES = "campaign_c,thermal:5,force_lag:23,hysteresis:31"
#: report fields that are results (judged); everything else is printed only
RESULT_KEYS = ("effects[].accepted", "effects[].parameters", "heldout", "noise_floor_N", "final_model", "baseline_parameters",
               "baseline_rmse_N", "unexplained_structure")


def _recordings(spec: str, recordings: Path):
    from vvea_benches import physbench as pb
    from vvea_design.identification.recordings import read_recordings

    if ":" not in spec:
        return read_recordings(recordings / f"{spec}.csv")
    effect, seed = spec.split(":")
    camp = pb.simulate_campaign(pb.random_parameters((effect,) if effect != "null" else (), seed=int(seed), grid=pb.CampaignGrid()))
    with tempfile.TemporaryDirectory(prefix="vvea-eq-") as tmp:
        return read_recordings(pb.write_campaign(camp, Path(tmp) / f"{effect}_{seed}.csv"))


def dump(out: Path, cases: list[str], recordings: Path) -> None:
    from vvea_design.identification.diagnose import diagnose
    from vvea_design.identification.settings import DiagnoseSettings

    out.mkdir(parents=True, exist_ok=True)
    for spec in cases:
        rec = _recordings(spec, recordings)
        load0 = os.getloadavg()[0]
        t0, c0 = time.perf_counter(), time.process_time()
        d = diagnose(rec, DiagnoseSettings())
        wall, cpu = time.perf_counter() - t0, time.process_time() - c0
        rep = d.report.to_dict()
        rep.pop("runtime_s", None)
        (out / f"{spec.replace(':', '_')}.json").write_text(json.dumps(rep, indent=1, default=str))
        print(f"{spec}: diagnose {wall:.1f} s ({cpu:.1f} s CPU), 1-min load {load0:.1f} -> {os.getloadavg()[0]:.1f}; "
              f"accepted {', '.join(e.id for e in d.report.accepted) or 'none'}; held-out {d.report.heldout.final_N}", flush=True)


def _diff(x, y, path: str, rtol: float, out: list) -> None:
    if isinstance(x, dict) and isinstance(y, dict):
        for k in sorted(set(x) | set(y)):
            if k not in x or k not in y:
                out.append((f"{path}.{k}", "missing on one side", ""))
            else:
                _diff(x[k], y[k], f"{path}.{k}", rtol, out)
    elif isinstance(x, list) and isinstance(y, list):
        if len(x) != len(y):
            out.append((path, f"{len(x)} items", f"{len(y)} items"))
            return
        for i, (u, v) in enumerate(zip(x, y)):
            _diff(u, v, f"{path}[{i}]", rtol, out)
    elif isinstance(x, float) and isinstance(y, (int, float)) and not isinstance(y, bool):
        same = x == y or (math.isnan(x) and math.isnan(float(y))) or abs(x - y) <= rtol * max(abs(x), abs(y))
        if not same:
            out.append((path, x, y))
    elif x != y:
        out.append((path, x, y))


def _is_result(path: str, report: dict) -> bool:
    if path.startswith(".effects["):
        i = int(path[len(".effects[") : path.index("]")])
        eff = report["effects"][i]
        rest = path[path.index("]") + 1 :]
        return bool(eff.get("accepted")) and not rest.startswith(".evidence") or rest in (".accepted", ".id")
    return any(path.startswith("." + k) for k in RESULT_KEYS if not k.startswith("effects"))


def compare(a: Path, b: Path, rtol: float) -> int:
    bad = 0
    for f in sorted(a.glob("*.json")):
        g = b / f.name
        if not g.exists():
            print(f"{f.stem}: not in {b}")
            continue
        ra, rb = json.loads(f.read_text()), json.loads(g.read_text())
        ra.pop("source", None)  # where the file was read from
        rb.pop("source", None)
        diffs: list = []
        _diff(ra, rb, "", rtol, diffs)
        res = [d for d in diffs if _is_result(d[0], ra)]
        other = [d for d in diffs if not _is_result(d[0], ra)]
        print(f"{f.stem}: results {'SAME' if not res else f'{len(res)} DIFFERENCES'} (rtol {rtol:g}); "
              f"{len(other)} other fields differ (rejected candidates' evidence, learner)")
        for d in res[:20] + other[:8]:
            print("   ", *d)
        bad += bool(res)
    return bad


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    sub = ap.add_subparsers(dest="cmd", required=True)
    d = sub.add_parser("dump")
    d.add_argument("out", type=Path)
    d.add_argument("--cases", default=DEFAULT_CASES)
    d.add_argument("--recordings", type=Path, default=HERE.parents[1] / "shared" / "recordings")
    c = sub.add_parser("compare")
    c.add_argument("before", type=Path)
    c.add_argument("after", type=Path)
    c.add_argument("--rtol", type=float, default=1e-6)
    args = ap.parse_args(argv)
    if args.cmd == "dump":
        dump(args.out, [s.strip() for s in args.cases.split(",") if s.strip()], args.recordings)
        return 0
    return compare(args.before, args.after, args.rtol)


if __name__ == "__main__":
    sys.exit(main())
