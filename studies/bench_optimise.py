"""Benchmark of the linearity optimiser: time to optimum and model evaluations per second.

    python studies/bench_optimise.py [--seeds 0 1 2]

Prints, per seed, the wall time of `optimise()` on the default requirements,
its model evaluations, evaluations per second and the linearity reached; and
the cost of one design evaluation (timeit).
"""

from __future__ import annotations

import argparse
import timeit

from vvea_design.spring.design import Design
from vvea_design.spring.optimise import optimise
from vvea_design.spring.requirements import Requirements, evaluate_design


def main(seeds: list[int]) -> None:
    req = Requirements()
    d = Design(34.5, 59.5, 41500.0, 90000.0)
    n = 2000
    t = timeit.timeit(lambda: evaluate_design(d, req), number=n) / n
    print(f"one design evaluation (geometry + 401-point curve + all constraints): {1e6 * t:.0f} µs "
          f"({1 / t:.0f} per second)")
    print(f"{'seed':>4} {'seconds':>8} {'evaluations':>11} {'eval/s':>8} {'linearity %':>11}  binding")
    for s in seeds:
        r = optimise(req, seed=s, progress=False)
        print(f"{s:>4} {r.seconds:>8.2f} {r.evaluations:>11d} {r.evaluations_per_second:>8.0f} "
              f"{100 * r.evaluation.linearity_error:>11.4f}  {', '.join(r.evaluation.binding())}")


if __name__ == "__main__":
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--seeds", type=int, nargs="+", default=[0, 1, 2])
    main(ap.parse_args().seeds)
