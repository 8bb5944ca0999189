"""Identify and diagnose the three shared campaigns (``shared/recordings``).

For each of ``campaign_a/b/c.csv`` writes, under ``--out`` (default
``studies/results/shared_campaigns/``), a folder ``campaign_X/`` with

- ``identify/``  Table 3 (``table3.csv``), ``identification.json``, Figs 10 and 11
- ``diagnose/``  ``report.json``, ``summary.md``, ``residual_maps.png``, ``worst_experiments.png``

and one overview ``shared_campaigns.json`` + ``shared_campaigns.csv``: the
effects accepted against those the README names, held-out RMSE before and
after, run times.

Usage::

    python studies/shared_campaigns.py [--out DIR] [--recordings DIR]
"""

from __future__ import annotations

import argparse
import json
import time
from pathlib import Path

import pandas as pd

from vvea_design.identification.diagnose import diagnose, write_diagnosis
from vvea_design.identification.identify import write_identification
from vvea_design.progress import console, progress_bar
from vvea_design.identification.recordings import read_recordings
from vvea_design.identification.settings import DiagnoseSettings

HERE = Path(__file__).resolve().parent
#: What the shared README says each campaign holds beyond eq. 14.
EXPECTED = {"campaign_a": [], "campaign_b": ["quadratic_damping"], "campaign_c": ["gas_nonlinearity", "stiction"]}


def main(argv=None) -> list[dict]:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--out", type=Path, default=HERE / "results" / "shared_campaigns")
    ap.add_argument("--recordings", type=Path, default=HERE.parents[1] / "shared" / "recordings")
    args = ap.parse_args(argv)
    import matplotlib

    matplotlib.use("Agg")  # a study draws into files
    rows = []
    with progress_bar("shared campaigns", total=len(EXPECTED)) as advance:
        for name, expected in EXPECTED.items():
            t0 = time.perf_counter()
            rec = read_recordings(args.recordings / f"{name}.csv")
            t1 = time.perf_counter()
            ident = write_identification(rec, args.out / name / "identify").to_dict()
            t2 = time.perf_counter()
            diag = diagnose(rec, DiagnoseSettings())
            write_diagnosis(diag, args.out / name / "diagnose")
            t3 = time.perf_counter()
            rep = diag.report
            accepted = [e.id for e in rep.accepted]
            fm = {p.name: p.value for p in rep.final_model.parameters}
            rows.append(
                dict(
                    campaign=name,
                    expected="+".join(expected) or "none",
                    accepted="+".join(accepted) or "none",
                    correct=sorted(accepted) == sorted(expected),
                    heldout_baseline_N=rep.heldout.baseline_N,
                    heldout_final_N=rep.heldout.final_N,
                    noise_floor_N=rep.noise_floor_N,
                    unexplained_structure=rep.unexplained_structure,
                    eq14_g=ident["parameters"]["g"]["value"],
                    eq14_C=ident["parameters"]["B (=C)"]["value"],
                    eq14_rmse_N=ident["rmse_N"],
                    eq14_error_band_lo_pct=ident["error_band_pct"]["ours"][0],
                    eq14_error_band_hi_pct=ident["error_band_pct"]["ours"][1],
                    final_g=fm["g"],
                    final_C=fm["C"],
                    read_s=t1 - t0,
                    identify_s=t2 - t1,
                    diagnose_s=t3 - t2,
                )
            )
            advance()
    args.out.mkdir(parents=True, exist_ok=True)
    pd.DataFrame(rows).to_csv(args.out / "shared_campaigns.csv", index=False)
    (args.out / "shared_campaigns.json").write_text(json.dumps(rows, indent=1))
    for r in rows:
        console.print(
            f"{r['campaign']}: expected {r['expected']:<28} accepted {r['accepted']:<28} "
            f"{'OK' if r['correct'] else 'WRONG'}  held-out {r['heldout_baseline_N']:.1f} -> {r['heldout_final_N']:.1f} N "
            f"(noise floor {r['noise_floor_N']:.1f} N)"
        )
    return rows


if __name__ == "__main__":
    main()
