"""Benchmark: the test command's time against an earlier commit, on this machine, back to back.

Issue 9 asks that the default suite (``python3 -m pytest -n 2``) be "not worse
than" the suite of the commit before its restructure (``ce0ed94``). Machine
speed moves between days (2.7 x on 2026-11-25), so both are measured in one
sitting. The earlier commit is checked out into a temporary git worktree (with
``shared/`` linked beside it, as CI clones it) and imported through
``PYTHONPATH``; this checkout runs as it is. Four runs:

- ``full``: each tree's whole default suite;
- ``common``: only the tests whose node id exists in both trees (the earlier
  capabilities under the same names, as they are tested today).

Prints wall and CPU (user + system of the test processes) per run with the load
before each, and writes ``studies/results/bench_suite.json``.

Usage::

    python studies/bench_suite.py [--base ce0ed94] [--common-only]
"""

from __future__ import annotations

import argparse
import json
import os
import resource
import shutil
import subprocess
import sys
import tempfile
import time
from pathlib import Path

HERE = Path(__file__).resolve().parent
ROOT = HERE.parent
OUT = HERE / "results" / "bench_suite.json"
PYTEST = [sys.executable, "-m", "pytest", "-p", "no:cacheprovider"]


def _env(tree: Path) -> dict:
    env = {**os.environ, "VTK_DEFAULT_OPENGL_WINDOW": "vtkEGLRenderWindow"}
    if tree != ROOT:
        env["PYTHONPATH"] = str(tree)  # the earlier code wins over the editable install of this checkout
    return env


def _ids(tree: Path) -> list[str]:
    res = subprocess.run([*PYTEST, "--collect-only", "-q", "-n", "0"], cwd=tree, env=_env(tree),
                         capture_output=True, text=True)
    ids = [line for line in res.stdout.splitlines() if "::" in line]
    if not ids:
        raise SystemExit(f"no tests collected in {tree}:\n{res.stdout[-2000:]}\n{res.stderr[-2000:]}")
    return ids


def _run(tree: Path, args: list[str]) -> dict:
    load = os.getloadavg()[0]
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    t0 = time.perf_counter()
    res = subprocess.run([*PYTEST, "-n", "2", "-q", *args], cwd=tree, env=_env(tree), capture_output=True, text=True)
    wall = time.perf_counter() - t0
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    summary = [line for line in res.stdout.splitlines() if " passed" in line or " failed" in line]
    return dict(wall_s=round(wall, 1), cpu_s=round(after.ru_utime - before.ru_utime + after.ru_stime - before.ru_stime, 1),
                load_before=round(load, 2), exit_code=res.returncode, summary=summary[-1] if summary else res.stdout[-500:])


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--base", default="ce0ed94", help="the earlier commit (default: before issue 9's restructure)")
    ap.add_argument("--common-only", action="store_true", help="skip the two full-suite runs")
    a = ap.parse_args(argv)
    tmp = Path(tempfile.mkdtemp(prefix="vvea_bench_suite_"))
    base = tmp / "base"
    shared = ROOT.parent / "shared"
    try:
        subprocess.run(["git", "worktree", "add", "-q", "--detach", str(base), a.base], cwd=ROOT, check=True)
        if shared.exists():
            (tmp / "shared").symlink_to(shared)  # the tests find ../shared beside the checkout
        common = sorted(set(_ids(base)) & set(_ids(ROOT)))
        ids_file = tmp / "common_ids.txt"
        ids_file.write_text("\n".join(common) + "\n")
        rows = {}
        for name, tree in (("base", base), ("this", ROOT)):
            if not a.common_only:
                rows[f"{name}_full"] = _run(tree, [])
                print(f"{name} full:   {rows[f'{name}_full']}", flush=True)
            rows[f"{name}_common"] = _run(tree, [f"@{ids_file}"])
            print(f"{name} common: {rows[f'{name}_common']}", flush=True)
        head = subprocess.run(["git", "rev-parse", "--short", "HEAD"], cwd=ROOT, capture_output=True, text=True).stdout.strip()
        result = dict(base=a.base, this=head, common_tests=len(common), date=time.strftime("%Y-%m-%d %H:%M"),
                      cpus=os.cpu_count(), runs=rows)
        OUT.parent.mkdir(parents=True, exist_ok=True)
        OUT.write_text(json.dumps(result, indent=2) + "\n")
        print(f"{len(common)} tests in both trees; written {OUT.relative_to(ROOT)}")
        bad = [k for k, r in rows.items() if r["exit_code"] != 0]
        if bad:
            print(f"runs that did not pass: {bad}", file=sys.stderr)
        return 1 if bad else 0
    finally:
        subprocess.run(["git", "worktree", "remove", "--force", str(base)], cwd=ROOT, capture_output=True)
        shutil.rmtree(tmp, ignore_errors=True)


if __name__ == "__main__":
    raise SystemExit(main())
