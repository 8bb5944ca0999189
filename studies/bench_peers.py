"""Peers beside ``vvea diagnose``: SINDy and eq. 14 + gradient-boosted trees on the same held-out experiments.

Reads a run folder of ``studies/blind_diagnosis.py`` (its campaigns, each campaign's
``diagnose/<id>/report.json`` with ``heldout.test_experiments``, and its scores), fits the peers of
``vvea_benches.blind.peers`` on the training experiments of every campaign and scores them on the
experiments the diagnosis held out, with two velocities (``np.gradient`` and a fitted trapezoid).
Writes per half ``OUT/<half>/peers.csv`` and ``peers.png`` and ``OUT/peers_summary.json`` (how often
a peer's held-out RMS is below the diagnosis's final one, with the machine load and times).

Usage::

    PYTHONPATH=$PWD:$PWD/benches python studies/bench_peers.py --run studies/results/blind_diagnosis/run \
        --half all --workers 2

It may run while the diagnosis run is still going (it takes the campaigns scored so far);
``--resume`` keeps the campaigns already done in ``RUN/peers_rows.jsonl``.
"""

from __future__ import annotations

import argparse
import json
import os
import time
from datetime import datetime, timezone
from pathlib import Path

import numpy as np
import pandas as pd

from vvea_benches.blind.peers import peer_heldout_rmse
from vvea_benches.blind.plots import plot_peers
from vvea_benches.blind.runlog import RunLog
from vvea_design.parallel import parallel_map
from vvea_design.progress import console

HERE = Path(__file__).resolve().parent
DEFAULT_RUN = HERE / "results" / "blind_diagnosis" / "run"
PEERS = ("sindy_gradient_N", "trees_gradient_N", "sindy_fitted_N", "trees_fitted_N")
#: A peer "beats" the tool by a margin when its held-out RMS is below this share of the tool's.
MARGIN = 0.95


def peer_row(item: dict) -> dict:
    """Peers on one campaign (never raises).

    Parameters
    ----------
    item : dict
        ``row`` (the campaign's score row) and ``run`` (the run folder).

    Returns
    -------
    dict
        Campaign ids, the diagnosis's baseline and final held-out RMS, each peer's held-out RMS
        (N), the best peer and whether it beats the diagnosis; ``error`` on a failure.
    """
    row, run = item["row"], Path(item["run"])
    cid = row["campaign_id"]
    head = {k: row[k] for k in ("campaign_id", "kind", "half", "seed", "mechanisms")}
    try:
        t0 = time.perf_counter()
        report = json.loads((run / "diagnose" / cid / "report.json").read_text())
        test = report["heldout"]["test_experiments"]
        p = peer_heldout_rmse(run / "campaigns" / f"{cid}.csv", test, seed=int(row["seed"]))
        final = float(report["heldout_rmse_N"]["final"])
        best = min(PEERS, key=lambda k: p[k])
        return {**head, "true_noise_N": row["true_noise_N"], "diagnose_baseline_N": report["heldout_rmse_N"]["baseline"],
                "diagnose_final_N": final, "n_test_experiments": len(test), **p,
                "best_peer": best.removesuffix("_N"), "best_peer_N": p[best],
                "peer_beats_tool": bool(p[best] < final), "peer_beats_tool_by_5pct": bool(p[best] < MARGIN * final),
                "peer_s": time.perf_counter() - t0}
    except Exception as exc:  # a failed campaign is data
        return {**head, "error": f"{type(exc).__name__}: {exc}"}


def _scored_rows(run: Path, half: str) -> list[dict]:
    """Scored campaigns of a run: ``RUN/rows.jsonl`` (also while the run is still going), else ``RUN/<half>/scores.json``."""
    halves = ("dev", "blind") if half == "all" else (half,)
    if (run / "rows.jsonl").exists():
        rows = [json.loads(line) for line in (run / "rows.jsonl").read_text().splitlines()]
    else:
        rows = []
        for h in halves:
            f = run / h / "scores.json"
            if f.exists():
                rows += json.loads(f.read_text())["campaigns"]
    return [r for r in rows if "error" not in r and r["half"] in halves]


def summarise_peers(rows: list[dict]) -> dict:
    """Counts of campaigns where a peer beats the diagnosis, per half.

    Parameters
    ----------
    rows : list of dict
        Rows of :func:`peer_row`.

    Returns
    -------
    dict
        Per half and over all: campaigns, failures, how many campaigns any peer beats the tool
        (strictly and by more than 5 %), per peer, and the median peer / tool RMS ratio.
    """
    out = {}
    for half in ("dev", "blind", "all"):
        rs = [r for r in rows if half == "all" or r["half"] == half]
        ok = [r for r in rs if "error" not in r]
        out[half] = {
            "campaigns": len(rs), "failed": len(rs) - len(ok),
            "any_peer_beats_tool": sum(r["peer_beats_tool"] for r in ok),
            "any_peer_beats_tool_by_5pct": sum(r["peer_beats_tool_by_5pct"] for r in ok),
            "per_peer_beats_tool": {k.removesuffix("_N"): sum(r[k] < r["diagnose_final_N"] for r in ok) for k in PEERS},
            "median_ratio_to_tool": {k.removesuffix("_N"): (float(np.median([r[k] / r["diagnose_final_N"] for r in ok]))
                                                             if ok else None) for k in PEERS},
            "peer_modelled_2x_noise": {k.removesuffix("_N"): sum(r[k] <= 2.0 * r["true_noise_N"] for r in ok) for k in PEERS},
            "tool_modelled_2x_noise": sum(r["diagnose_final_N"] <= 2.0 * r["true_noise_N"] for r in ok),
        }
    return out


def main(argv=None) -> dict:
    """Run the peers on a blind_diagnosis run (see the module docstring).

    Parameters
    ----------
    argv : list of str or None
        Command-line arguments.

    Returns
    -------
    dict
        The summary written to ``OUT/peers_summary.json``.
    """
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--run", type=Path, default=DEFAULT_RUN, help="run folder of studies/blind_diagnosis.py")
    ap.add_argument("--half", choices=("dev", "blind", "all"), default="dev")
    ap.add_argument("--seeds", type=int, nargs="*", default=None, help="only these seeds (default: all in the run)")
    ap.add_argument("--workers", type=int, default=2)
    ap.add_argument("--resume", action="store_true", help="keep campaigns already done in RUN/peers_rows.jsonl")
    ap.add_argument("--no-run", action="store_true", help="fit nothing: write what RUN/peers_rows.jsonl holds")
    args = ap.parse_args(argv)
    run = args.run.resolve()
    rows = _scored_rows(run, args.half)
    if args.seeds is not None:
        rows = [r for r in rows if int(r["seed"]) in set(args.seeds)]
    if not rows:
        raise SystemExit(f"no scored campaigns in {run} for half {args.half}: run studies/blind_diagnosis.py first")
    log = RunLog(run / "peers_rows.jsonl", args.resume or args.no_run)
    todo = [] if args.no_run else [r for r in rows if r["campaign_id"] not in log.done]
    load0, t0 = os.getloadavg(), time.time()
    console.print(f"peers on {len(rows)} campaigns ({len(todo)} to run), {args.workers} workers, load {load0[0]:.1f}")

    new = parallel_map(peer_row, [{"row": r, "run": str(run)} for r in todo], workers=args.workers,
                       description="peers", on_result=log.append)
    res = log.merged([r["campaign_id"] for r in rows], new)
    for half in ("dev", "blind"):
        rs = [r for r in res if r["half"] == half and "error" not in r]
        if rs:
            every = [r for r in res if r["half"] == half]
            (run / half).mkdir(parents=True, exist_ok=True)
            pd.DataFrame(every).sort_values(["kind", "campaign_id"]).to_csv(run / half / "peers.csv", index=False)
            plot_peers(rs, run / half / "peers.png",
                       f"{half.upper()} half: held-out RMS / true noise, vvea diagnose (bars) and peers (markers)")
    summary = {"run": {"started_utc": datetime.fromtimestamp(t0, timezone.utc).isoformat(timespec="seconds"),
                       "wall_s": time.time() - t0, "loadavg_start": list(load0), "loadavg_end": list(os.getloadavg()),
                       "cpu_count": os.cpu_count(), "workers": args.workers,
                       "peer_s_total": sum(r.get("peer_s", 0.0) for r in res),
                       "errors": {r["campaign_id"]: r["error"] for r in res if "error" in r}},
               **summarise_peers(res)}
    (run / "peers_summary.json").write_text(json.dumps(summary, indent=1, default=str))
    for half in ("dev", "blind"):
        s = summary[half]
        if s["campaigns"]:
            console.print(f"[bold]{half}[/]: a peer beats the tool in {s['any_peer_beats_tool']} of {s['campaigns']} "
                          f"campaigns ({s['any_peer_beats_tool_by_5pct']} by > 5 %); per peer {s['per_peer_beats_tool']}")
    return summary


if __name__ == "__main__":
    main()
