"""Benchmark of the main job and its report: `vvea design` step by step, then report.html in headless Chromium.

    python studies/bench_report.py [--spec REQ.toml] [--out DIR] [--repeat 5] [--no-renders]

Prints the time of each step of :func:`vvea_design.pipeline.design_unit`, the
report's size, and the time headless Chromium takes to open it (navigation
start to the 3-D view drawn: the median of ``--repeat`` fresh pages). Writes
two screenshots of the report (the top of the page and the 3-D view) and
``bench_report.json`` to ``studies/results/report/``; the design folder
itself goes to ``--out`` (a temporary folder by default).
"""

from __future__ import annotations

import argparse
import json
import statistics
import sys
import tempfile
import time
from pathlib import Path

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE.parent))

from vvea_design.pipeline import STEPS, design_unit  # noqa: E402
from vvea_design.spring.requirements import load_requirements  # noqa: E402

CHROMIUM_ARGS = ["--no-sandbox", "--disable-gpu", "--disable-quic", "--no-first-run",
                 "--disable-background-networking", "--disable-component-update", "--disable-sync",
                 "--host-resolver-rules=MAP * ~NOTFOUND", "--use-angle=swiftshader", "--enable-unsafe-swiftshader"]


def open_times(report: Path, repeat: int, shots: Path | None) -> list[float]:
    """Seconds from navigation to the 3-D view drawn, one fresh page each time."""
    import shutil

    from playwright.sync_api import sync_playwright

    exe = shutil.which("chromium") or "/usr/bin/chromium"
    times = []
    with sync_playwright() as p:
        browser = p.chromium.launch(executable_path=exe, args=CHROMIUM_ARGS)
        for i in range(repeat):
            page = browser.new_page(viewport={"width": 1280, "height": 900})
            t = time.perf_counter()
            page.goto(report.resolve().as_uri(), wait_until="load")
            page.wait_for_function("window.vveaViewer !== undefined && window.vveaViewer.ready", timeout=60_000)
            times.append(time.perf_counter() - t)
            if shots is not None and i == 0:
                page.screenshot(path=str(shots / "report_top.png"))
                page.locator(".viewer-wrap").scroll_into_view_if_needed()
                page.locator(".viewer-wrap").screenshot(path=str(shots / "report_3d.png"))
                page.locator("#force").screenshot(path=str(shots / "report_force.png"))
            page.close()
        browser.close()
    return times


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--out", type=Path, default=None, help="design folder (default: a temporary folder)")
    ap.add_argument("--results", type=Path, default=HERE / "results" / "report", help="screenshots and JSON")
    ap.add_argument("--repeat", type=int, default=5, help="page openings to time")
    ap.add_argument("--no-renders", action="store_true", help="skip the CAD PNG renders")
    ap.add_argument("--spec", type=Path, default=None, help="requirements TOML (default: the built-in ones)")
    args = ap.parse_args()
    import matplotlib

    matplotlib.use("Agg")  # a study selects the backend, the library does not
    out = args.out or Path(tempfile.mkdtemp(prefix="vvea_bench_report_"))
    t0 = time.perf_counter()
    unit = design_unit(load_requirements(args.spec), out, renders=not args.no_renders, spec_path=args.spec)
    total = time.perf_counter() - t0
    report = unit.files["report"]
    size = report.stat().st_size
    args.results.mkdir(parents=True, exist_ok=True)
    times = open_times(report, args.repeat, args.results)
    summary = {"spec": None if args.spec is None else str(args.spec), "design_seconds_by_step": {k: round(unit.seconds.get(k, 0.0), 2) for k in STEPS},
               "design_seconds_total": round(total, 2), "report_bytes": size,
               "chromium_open_seconds": [round(t, 3) for t in times],
               "chromium_open_seconds_median": round(statistics.median(times), 3)}
    (args.results / "bench_report.json").write_text(json.dumps(summary, indent=2) + "\n")
    print("vvea design, seconds per step: " + ", ".join(f"{k} {v:.1f}" for k, v in
                                                         summary["design_seconds_by_step"].items()))
    print(f"vvea design total: {total:.1f} s; report.html {size / 1e6:.2f} MB")
    print(f"headless Chromium, open to 3-D view drawn: median {summary['chromium_open_seconds_median']:.2f} s "
          f"over {len(times)} ({', '.join(f'{t:.2f}' for t in times)})")
    print(f"wrote {args.results / 'report_top.png'}, {args.results / 'report_3d.png'}, "
          f"{args.results / 'bench_report.json'}; design folder {out}")


if __name__ == "__main__":
    main()
