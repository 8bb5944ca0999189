"""Benchmark: time to build and export the whole CAD set of one design.

Prints the import time and then, after import, the time of each phase
(build all solids; checks + STEP/STL/manifest; off-screen renders) and the
total -- target < 10 s after import. Run::

    python studies/bench_cad.py [design.json] [--repeat N] [--no-renders]

Without a design JSON it uses the reference design
``Design(35.18, 59.5, 47107.0, 99735.0)``.
"""

from __future__ import annotations

import argparse
import tempfile
import time

t0 = time.perf_counter()
from vvea_design.cad import build_cad, write_cad  # noqa: E402
from vvea_design.cad.export import export_files  # noqa: E402
from vvea_design.cad.render import render_assembly_cutaway, render_mould_open  # noqa: E402
from vvea_design.spring.design import Design  # noqa: E402

T_IMPORT = time.perf_counter() - t0


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("design_json", nargs="?", help="design JSON (default: the reference design)")
    ap.add_argument("--repeat", type=int, default=1, help="repeat the timing N times (best and mean printed)")
    ap.add_argument("--no-renders", action="store_true", help="skip the PNG renders")
    args = ap.parse_args()
    if args.design_json:
        from vvea_design.spring.design_file import load_design

        design = load_design(args.design_json)
    else:
        design = Design(35.18, 59.5, 47107.0, 99735.0)
    print(f"import vvea_design.cad (build123d, OCP, trimesh, pyvista): {T_IMPORT:.2f} s")
    totals = []
    for k in range(args.repeat):
        with tempfile.TemporaryDirectory() as tmp:
            from pathlib import Path

            t = time.perf_counter()
            model = build_cad(design)
            t_build = time.perf_counter() - t
            t = time.perf_counter()
            _, meshes = export_files(model, Path(tmp))
            t_export = time.perf_counter() - t
            t, c = time.perf_counter(), time.process_time()
            from vvea_design.report.bom import bill_of_materials
            from vvea_design.report.drawing import write_drawings

            write_drawings(model, Path(tmp) / "drw")
            bill_of_materials(model)
            t_draw, c_draw = time.perf_counter() - t, time.process_time() - c
            t = time.perf_counter()
            if not args.no_renders:
                render_assembly_cutaway(model, meshes)
                render_mould_open(model, meshes)
            t_render = time.perf_counter() - t
            t, c = time.perf_counter(), time.process_time()
            write_cad(design, tmp, renders=not args.no_renders, show_progress=False)
            t_all, c_all = time.perf_counter() - t, time.process_time() - c
        totals.append(t_all)
        print(f"run {k + 1}: build {t_build:.2f} s | checks + STEP/STL/manifest {t_export:.2f} s | renders "
              f"{t_render:.2f} s | write_cad end to end {t_all:.2f} s wall, {c_all:.2f} s CPU | drawings + BOM "
              f"{t_draw:.2f} s wall, {c_draw:.2f} s CPU")
    import os

    print(f"load average {os.getloadavg()[0]:.1f} on {os.cpu_count()} cores (wall time grows with other jobs)")
    print(f"write_cad (whole set, one design, after import): best {min(totals):.2f} s, "
          f"mean {sum(totals) / len(totals):.2f} s over {len(totals)} run(s); target < 10 s")


if __name__ == "__main__":
    main()
