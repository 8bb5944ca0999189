"""Benchmark of the bladder check: time per design of ``check_bladder`` and of the fast ``strain_bound``.

Run::

    python studies/bench_bladder.py [--repeat 5]

Prints a table and writes ``studies/results/bench_bladder.json``. The first
call in a process builds the CasADi/IPOPT solvers (reported separately as
"cold"); the optimiser and ``vvea design`` pay it once.
"""

from __future__ import annotations

import argparse
import json
import statistics
import subprocess
import sys
import time
from pathlib import Path

from rich.table import Table

from vvea_design.progress import console, progress_bar

sys.path.insert(0, str(Path(__file__).parent))
from bladder_verification import SURROGATE_DESIGNS  # noqa: E402

OUT = Path(__file__).parent / "results" / "bench_bladder.json"

_COLD = """
import time
t = time.perf_counter()
from vvea_design.spring.design import Design
from vvea_design.bladder.check import check_bladder
t1 = time.perf_counter()
check_bladder(Design(34.37, 59.5, 41342.0, 91473.0))
print(t1 - t, time.perf_counter() - t1)
"""


def main(argv=None) -> int:
    from vvea_design.bladder.check import DEFAULT_ELEMENTS, check_bladder, strain_bound

    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--repeat", type=int, default=5)
    a = ap.parse_args(argv)
    imp, cold = map(float, subprocess.run([sys.executable, "-c", _COLD], capture_output=True, text=True,
                                          check=True).stdout.split())
    rows = []
    with progress_bar("timing the bladder check", total=len(SURROGATE_DESIGNS)) as adv:
        for name, d in SURROGATE_DESIGNS.items():
            check_bladder(d), strain_bound(d)  # warm: solvers built for these sizes
            tc, ts = [], []
            for _ in range(a.repeat):
                t = time.perf_counter()
                check_bladder(d)
                tc.append(time.perf_counter() - t)
                t = time.perf_counter()
                strain_bound(d)
                ts.append(time.perf_counter() - t)
            rows.append({"design": name, "check_bladder_s": statistics.median(tc), "strain_bound_s": statistics.median(ts)})
            adv()
    t = Table(title=f"bladder check timing (median of {a.repeat}; {DEFAULT_ELEMENTS} elements; strain_bound 48+24)")
    t.add_column("design")
    t.add_column("check_bladder (s)", justify="right")
    t.add_column("strain_bound (s)", justify="right")
    for r in rows:
        t.add_row(r["design"], f"{r['check_bladder_s']:.3f}", f"{r['strain_bound_s']:.3f}")
    console.print(t)
    med_c = statistics.median(r["check_bladder_s"] for r in rows)
    max_c = max(r["check_bladder_s"] for r in rows)
    med_s = statistics.median(r["strain_bound_s"] for r in rows)
    console.print(f"cold first check in a fresh process: {cold:.2f} s (+ {imp:.2f} s imports); "
                  f"warm check: median {med_c:.3f} s, worst {max_c:.3f} s; strain_bound median {med_s * 1000:.0f} ms")
    OUT.parent.mkdir(parents=True, exist_ok=True)
    OUT.write_text(json.dumps({"designs": rows, "cold_first_check_s": cold, "import_s": imp,
                               "median_check_s": med_c, "worst_check_s": max_c, "median_strain_bound_s": med_s,
                               "elements": DEFAULT_ELEMENTS}, indent=2))
    print(json.dumps({"median_check_s": med_c, "worst_check_s": max_c, "median_strain_bound_s": med_s,
                      "cold_first_check_s": cold}))
    return 0


if __name__ == "__main__":
    sys.exit(main())
