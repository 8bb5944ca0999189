"""What the study regularisation does: chatter and rmse, with and without it.

    python studies/regularisation_effect.py
        # one case (A = 1 rad, T = 1.6 s, N = 64 -> 192): motor-torque total variation, D switching, rmse
    git show 7cd3654:studies/results/rest_to_rest/results.csv > /tmp/unregularised.csv
    python studies/regularisation_effect.py --old /tmp/unregularised.csv
        # + per-case rmse change on the paper grid against the last unregularised committed run

Prints figures; asserts nothing.
"""

from __future__ import annotations

import argparse
from pathlib import Path

import numpy as np

from vvea_design.actuator.model import PAPER_SETTINGS
from vvea_design.actuator.multistart import (DEFAULT_FINE_MESH, DEFAULT_MESH, DEFAULT_REGULARISATION,
                                             RestToRestCase, solve_case_results)
from vvea_design.actuator.ocp import Regularisation


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--old", type=Path, default=None, help="results.csv of an unregularised paper-grid run")
    ap.add_argument("--new", type=Path, default=Path(__file__).parent / "results" / "rest_to_rest" / "results.csv")
    a = ap.parse_args()
    A, T = 1.0, 1.6
    settings = tuple(PAPER_SETTINGS.values())
    for label, reg in (("none", Regularisation()), ("default", DEFAULT_REGULARISATION)):
        _, best = solve_case_results(RestToRestCase(A, T, settings, DEFAULT_MESH, fine_mesh=DEFAULT_FINE_MESH,
                                                    regularisation=reg))
        for n in ("VVEA", "iVVEA", "SEA"):
            r = best[n]
            rest = r.t_s[:-1] < 0.5 * T  # first rest phase, q_des = 0
            tv = np.sum(np.abs(np.diff(r.tau_m_Nm)))
            tv_rest = np.sum(np.abs(np.diff(r.tau_m_Nm[rest])))
            D = r.D_Nms_per_rad
            cross = int(np.sum(np.diff(np.sign(D - 0.5 * (D.max() + D.min()))) != 0)) if D.max() > D.min() else 0
            print(f"{label:8s} {n:6s} rmse {r.extra['rmse_rad']:.5f} rad; total variation of tau_m {tv:6.0f} N m "
                  f"(first rest phase {tv_rest:5.0f} N m); D crosses mid-range {cross} times")
    if a.old is not None:
        import pandas as pd

        old, new = pd.read_csv(a.old), pd.read_csv(a.new)
        m = old.merge(new, on=["case_id", "setting"], suffixes=("_old", "_new"))
        m["rel_pct"] = 100 * (m.rmse_new / m.rmse_old - 1)
        print("\nper-case rmse change, regularised vs unregularised (%):")
        print(m.groupby("setting").rel_pct.describe()[["count", "mean", "min", "max"]].round(3).to_string())
        print(f"validity changed in {(m.valid_old.astype(str) != m.valid_new.astype(str)).sum()} of {len(m)} OCPs")
        print("mean IPOPT CPU per OCP (s), old -> new:")
        print(m.groupby("setting")[["cpu_seconds_old", "cpu_seconds_new"]].mean().round(3).to_string())


if __name__ == "__main__":
    main()
