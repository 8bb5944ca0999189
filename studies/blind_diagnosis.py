"""Blind protocol for ``vvea diagnose``: generate campaigns, run the command as a black box, score it.

For every campaign of the chosen half and seeds (``vvea_benches.blind.campaign.campaign_specs``)
this script

1. generates the recordings and their truth (``OUT/campaigns/<id>.csv``, ``<id>.truth.json``;
   git-ignored),
2. runs ``vvea diagnose <id>.csv --out OUT/diagnose/<id>`` in a subprocess (git-ignored),
3. scores its ``report.json`` against the truth (``vvea_benches.blind.score``),

and writes, per half, ``OUT/<half>/scores.csv``, ``scores.json`` and ``scores.png`` (held-out RMS
over the true noise per campaign, coloured by outcome), and ``OUT/summary.json`` (aggregates per
half, the run's machine load and times). The BLIND half's per-campaign files name its mechanisms:
the method's developer reads ``OUT/dev/`` and the aggregates only.

Usage::

    PYTHONPATH=$PWD:$PWD/benches python studies/blind_diagnosis.py --half dev --seeds 0 1 --workers 2 \
        --out studies/results/blind_diagnosis/run

``--resume`` keeps campaigns already scored in ``OUT/rows.jsonl``; ``--no-run`` only rescores
and rewrites; ``--doc docs/diagnosis-protocol.md`` also writes the tables into that page (after
``studies/bench_peers.py``, with the peers' columns).
"""

from __future__ import annotations

import argparse
import json
import os
import platform
import shutil
import subprocess
import sys
import time
from datetime import datetime, timezone
from pathlib import Path

import pandas as pd

from vvea_benches.blind.campaign import CampaignSpec, build_campaign, campaign_specs, write_campaign
from vvea_benches.blind.plots import plot_scores
from vvea_benches.blind.runlog import RunLog
from vvea_benches.blind.tables import write_tables
from vvea_benches.blind.score import score_campaign, summarise
from vvea_design.parallel import parallel_map
from vvea_design.progress import console

HERE = Path(__file__).resolve().parent
REPO = HERE.parent
DEFAULT_OUT = HERE / "results" / "blind_diagnosis" / "run"


def vvea_command() -> list[str]:
    """The ``vvea`` command next to this interpreter, or on the PATH.

    Returns
    -------
    list of str
        The command's argv prefix.
    """
    here = Path(sys.executable).parent / "vvea"
    if here.exists():
        return [str(here)]
    found = shutil.which("vvea")
    if found:
        return [found]
    return [sys.executable, "-m", "vvea_design"]


def run_one(item: dict) -> dict:
    """Generate one campaign, diagnose it in a subprocess and score it (never raises).

    Parameters
    ----------
    item : dict
        ``spec`` (CampaignSpec as dict), ``out`` (run folder), ``vvea`` (command prefix),
        ``timeout_s``.

    Returns
    -------
    dict
        The score row (``score.score_campaign``) plus ``generate_s`` and ``diagnose_wall_s``; on a
        failure a row with ``error`` and ``outcome="error"``.
    """
    spec = CampaignSpec(**{**item["spec"], "mechanisms": tuple(item["spec"]["mechanisms"])})
    out = Path(item["out"])
    head = {"campaign_id": spec.campaign_id, "kind": spec.kind, "half": spec.half, "seed": spec.seed,
            "mechanisms": "+".join(spec.mechanisms)}
    try:
        t0 = time.perf_counter()
        csv, truth_path = write_campaign(build_campaign(spec), out / "campaigns")
        t1 = time.perf_counter()
        dest = out / "diagnose" / spec.campaign_id
        cmd = item["vvea"] + ["diagnose", str(csv), "--out", str(dest)]
        proc = subprocess.run(cmd, capture_output=True, text=True, timeout=item["timeout_s"])
        t2 = time.perf_counter()
        (out / "diagnose").mkdir(parents=True, exist_ok=True)
        (out / "diagnose" / f"{spec.campaign_id}.log").write_text(proc.stdout[-20000:] + proc.stderr[-20000:])
        if proc.returncode != 0:
            raise RuntimeError(f"vvea diagnose exited {proc.returncode}: {proc.stderr.strip()[-400:]}")
        report = json.loads((dest / "report.json").read_text())
        row = score_campaign(json.loads(truth_path.read_text()), report)
        row.update(generate_s=t1 - t0, diagnose_wall_s=t2 - t1, loadavg_1min_after=os.getloadavg()[0])
        return row
    except Exception as exc:  # a failed campaign is data, not the end of the sweep
        return {**head, "error": f"{type(exc).__name__}: {exc}", "outcome": "error"}


def rescore(row: dict, out: Path) -> dict:
    """Score a finished campaign again from its files (truth and report on disk), keeping its times.

    Parameters
    ----------
    row : dict
        The row logged when the campaign finished.
    out : pathlib.Path
        Run folder.

    Returns
    -------
    dict
        The row scored by the current scorer (the logged row if a file is missing or it had failed).
    """
    truth = out / "campaigns" / f"{row['campaign_id']}.truth.json"
    report = out / "diagnose" / row["campaign_id"] / "report.json"
    if "error" in row or not truth.exists() or not report.exists():
        return row
    new = score_campaign(json.loads(truth.read_text()), json.loads(report.read_text()))
    new.update({k: row[k] for k in ("generate_s", "diagnose_wall_s", "loadavg_1min_after") if k in row})
    return new


def _git_commit() -> str | None:
    try:
        return subprocess.run(["git", "-C", str(REPO), "rev-parse", "HEAD"], capture_output=True, text=True,
                              check=True).stdout.strip()
    except (OSError, subprocess.CalledProcessError):
        return None


def write_outputs(rows: list[dict], out: Path, run_info: dict) -> dict:
    """Write the per-half tables and figures and the summary.

    Parameters
    ----------
    rows : list of dict
        Scored campaigns.
    out : pathlib.Path
        Run folder.
    run_info : dict
        Machine load, times, command, versions (goes into ``summary.json``).

    Returns
    -------
    dict
        The summary (per half and over all, plus ``run``).
    """
    summary = summarise(rows)
    for half in ("dev", "blind"):
        rs = [r for r in rows if r.get("half") == half]
        if not rs:
            continue
        d = out / half
        d.mkdir(parents=True, exist_ok=True)
        pd.DataFrame(rs).sort_values(["kind", "campaign_id"]).to_csv(d / "scores.csv", index=False)
        (d / "scores.json").write_text(json.dumps({"summary": summary[half], "campaigns": rs}, indent=1, default=str))
        plot_scores(rs, d / "scores.png", f"vvea diagnose on the {half.upper()} half: final held-out RMS / true noise")
        if half == "blind":
            (d / "README.md").write_text("# BLIND half\n\nPer-campaign scores of the BLIND half. The method's "
                                         "developer does not read this folder.\n")
    result = {"run": run_info, **summary}
    (out / "summary.json").write_text(json.dumps(result, indent=1, default=str))
    return result


def main(argv=None) -> dict:
    """Run the protocol (see the module docstring).

    Parameters
    ----------
    argv : list of str or None
        Command-line arguments.

    Returns
    -------
    dict
        The summary written to ``OUT/summary.json``.
    """
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--half", choices=("dev", "blind", "all"), default="dev")
    ap.add_argument("--seeds", type=int, nargs="+", default=[0, 1])
    ap.add_argument("--workers", type=int, default=2)
    ap.add_argument("--out", type=Path, default=DEFAULT_OUT)
    ap.add_argument("--n-per-ramp", type=int, default=200, help="sample intervals per ramp")
    ap.add_argument("--timeout", type=float, default=1800.0, help="seconds allowed for one diagnose run")
    ap.add_argument("--only", nargs="*", default=None, help="run only these campaign ids")
    ap.add_argument("--resume", action="store_true", help="keep campaigns already scored in OUT/rows.jsonl")
    ap.add_argument("--no-run", action="store_true", help="run nothing: score and write what OUT/rows.jsonl holds")
    ap.add_argument("--doc", type=Path, default=None,
                    help="also write the tables (with the peers', if bench_peers ran) into this page's untuned markers")
    ap.add_argument("--reverse", action="store_true", help="run the campaigns in reverse order (a second sweep "
                                                           "sharing the run folder from the other end)")
    args = ap.parse_args(argv)

    out = args.out.resolve()
    out.mkdir(parents=True, exist_ok=True)
    specs = campaign_specs(args.half, args.seeds, args.n_per_ramp)
    if args.only:
        specs = [s for s in specs if s.campaign_id in set(args.only)]
    log = RunLog(out / "rows.jsonl", args.resume or args.no_run)
    todo = [] if args.no_run else [s for s in specs if s.campaign_id not in log.done]
    if args.reverse:
        todo = todo[::-1]
    vvea = vvea_command()
    load0, t0, c0 = os.getloadavg(), time.time(), time.process_time()
    console.print(f"{len(specs)} campaigns ({len(todo)} to run), {args.workers} workers, "
                  f"load {load0[0]:.1f}; command: {' '.join(vvea)} diagnose")

    items = [{"spec": s.to_dict(), "out": str(out), "vvea": vvea, "timeout_s": args.timeout} for s in todo]
    new = parallel_map(run_one, items, workers=args.workers, description="blind diagnosis", on_result=log.append)
    rows = [rescore(r, out) for r in log.merged([s.campaign_id for s in specs], new)]
    ok = [r for r in rows if "error" not in r]
    run_info = {
        "started_utc": datetime.fromtimestamp(t0, timezone.utc).isoformat(timespec="seconds"),
        "mode": "score only (--no-run)" if args.no_run else "run", "campaigns_planned": len(specs),
        "campaigns_scored": len(ok),
        "wall_s": time.time() - t0, "parent_cpu_s": time.process_time() - c0,
        "loadavg_start": list(load0), "loadavg_end": list(os.getloadavg()), "cpu_count": os.cpu_count(),
        "workers": args.workers, "half": args.half, "seeds": args.seeds, "n_per_ramp": args.n_per_ramp,
        "command": vvea + ["diagnose", "CSV", "--out", "DIR"], "argv": sys.argv[1:] if argv is None else argv,
        "git_commit": _git_commit(), "python": platform.python_version(),
        "diagnose_wall_s_total": sum(r.get("diagnose_wall_s", 0.0) for r in ok),
        "diagnose_runtime_s_total": sum(r.get("runtime_s", 0.0) for r in ok),
        "generate_s_total": sum(r.get("generate_s", 0.0) for r in ok),
        "errors": {r["campaign_id"]: r["error"] for r in rows if "error" in r},
    }
    result = write_outputs(rows, out, run_info)
    if args.doc is not None:
        write_tables(out, args.doc)
    for half in ("dev", "blind"):
        s = result[half]
        if not s["campaigns"]:
            continue
        o, c, n = s["outside"], s["catalogue"], s["null"]
        console.print(f"[bold]{half}[/]: {s['campaigns']} campaigns ({s['failed']} failed); catalogue precision "
                      f"{c['precision']}, recall {c['recall']}; null acceptances {n['accepted_effects']} in "
                      f"{n['campaigns']}; outside: modelled {o['modelled']}/{o['campaigns']}, named as catalogue "
                      f"{o['named_as_catalogue']}, flagged {o['flagged']}; final > baseline {s['final_gt_baseline']}")
    return result


if __name__ == "__main__":
    main()
