"""How the rest-to-rest results move with the collocation mesh.

Part 1: SEA and LWR (convex QPs, one global optimum each) on the whole paper grid for
N = 32 ... 256 intervals (Radau degree 3): per-case relative change of the rmse.
Part 2: the Table 5 statistics with every setting and the full multi-start on a 3 x 4 sub-grid
for N = 32, 64, 128.

    python studies/mesh_convergence.py        # -> studies/results/mesh_convergence/
    python studies/mesh_convergence.py --check-results studies/results/rest_to_rest
        # the reported (fine-mesh) SEA rmse of a finished sweep vs N = 256 (sea_lwr_rmse.csv) and a
        # fresh N = 384 QP, case by case -> fine_mesh_check.json
"""

from __future__ import annotations

import argparse
import json
import os
import time
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import pandas as pd  # noqa: E402

from vvea_design.actuator.model import PAPER_SETTINGS  # noqa: E402
from vvea_design.actuator.ocp import Mesh  # noqa: E402
from vvea_design.figure_layout import tight_layout_once  # noqa: E402
from vvea_design.parallel import parallel_map  # noqa: E402
from vvea_design.actuator.multistart import solve_single  # noqa: E402
from vvea_design.actuator.rest_to_rest import GRIDS, Grid, mesh_convergence  # noqa: E402

SUBGRID = Grid((0.3, 0.6, 0.9), (0.3, 0.7, 1.1, 1.5))


def check_results(results_dir: Path, out: Path, finer_N: int = 384, workers=None) -> dict:
    """Per-case relative change of the sweep's reported SEA rmse against finer meshes."""
    df = pd.read_csv(results_dir / "results.csv")
    sea = df[df.setting == "SEA"].set_index(["A_rad", "T_s"])
    N = int(sea.mesh_N.iloc[0])
    items = [(Mesh(finer_N, 3), PAPER_SETTINGS["SEA"], A, T) for A, T in sea.index]
    ref = {finer_N: pd.DataFrame([r.to_dict() for r in parallel_map(solve_single, items, workers=workers,
                                                                      progress=False)])
           .set_index(["A_rad", "T_s"]).rmse}
    qp_path = out / "sea_lwr_rmse.csv"
    if qp_path.exists():
        qp = pd.read_csv(qp_path)
        for n in sorted(set(qp.mesh_N)):
            if n > N:
                ref[n] = qp[(qp.setting == "SEA") & (qp.mesh_N == n)].set_index(["A_rad", "T_s"]).rmse
    res = {"results": str(results_dir), "reported_mesh_N": N, "n_cases": len(sea), "against": {}}
    for n, r in sorted(ref.items()):
        rel = (sea.rmse / r.reindex(sea.index) - 1).abs()
        i = rel.idxmax()
        res["against"][str(n)] = {"max_rel_change": float(rel.max()), "mean_rel_change": float(rel.mean()),
                                  "worst_case_A_T": [float(i[0]), float(i[1])],
                                  "cases_above_0.5_percent": int((rel > 0.005).sum())}
    (out / "fine_mesh_check.json").write_text(json.dumps(res, indent=2))
    print(json.dumps(res, indent=1))
    return res


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("--out", type=Path, default=Path(__file__).parent / "results" / "mesh_convergence")
    ap.add_argument("--qp-meshes", default="32,64,96,128,192,256")
    ap.add_argument("--stat-meshes", default="32,64,128")
    ap.add_argument("--workers", type=int, default=None)
    ap.add_argument("--check-results", type=Path, default=None,
                    help="only compare this finished sweep's SEA rmse with finer meshes")
    a = ap.parse_args()
    a.out.mkdir(parents=True, exist_ok=True)
    if a.check_results is not None:
        check_results(a.check_results, a.out, workers=a.workers)
        return
    t0 = time.perf_counter()
    qp_N = [int(x) for x in a.qp_meshes.split(",")]
    items = [(Mesh(N, 3), PAPER_SETTINGS[s], A, T) for N in qp_N for s in ("SEA", "LWR")
             for A, T in GRIDS["paper"].cases()]
    rows = parallel_map(solve_single, items, workers=a.workers, description="SEA/LWR QPs over meshes")
    qp = pd.DataFrame([r.to_dict() for r in rows])
    qp.to_csv(a.out / "sea_lwr_rmse.csv", index=False)
    conv = []
    for s in ("SEA", "LWR"):
        piv = qp[qp.setting == s].pivot_table(index=["A_rad", "T_s"], columns="mesh_N", values="rmse")
        for n0, n1 in zip(qp_N[:-1], qp_N[1:]):
            rel = (piv[n0] / piv[n1] - 1).abs()
            i = rel.idxmax()
            conv.append({"setting": s, "from_N": n0, "to_N": n1, "max_rel_change": float(rel.max()),
                         "mean_rel_change": float(rel.mean()), "worst_case_A_T": [float(i[0]), float(i[1])],
                         "mean_rmse_to": float(piv[n1].mean())})
    stat_N = [int(x) for x in a.stat_meshes.split(",")]
    res = mesh_convergence([Mesh(N, 3) for N in stat_N], grid=SUBGRID, workers=a.workers)
    stats = []
    for r in res:
        st = r.stats
        stats.append({"mesh_N": r.mesh.n_intervals, "wall_seconds": r.wall_seconds,
                      "solver_seconds": r.solver_seconds, "mean_rmse_rad": st.mean_rmse_rad,
                      "pairs": {k: {"fraction_X_beats_Y": v.fraction_X_beats_Y, "meanrmse_Y_over_X": v.meanrmse_Y_over_X}
                                for k, v in st.pairs.items() if k.endswith("_all")},
                      "ivvea_vs_sea": st.ivvea_vs_sea_guarantee, "winning_starts": st.winning_starts})
        r.df.assign(mesh_N=r.mesh.n_intervals).to_csv(a.out / f"subgrid_results_N{r.mesh.n_intervals}.csv",
                                                      index=False)
    out = {"qp_convergence": conv, "subgrid": {"A_rad": SUBGRID.A_rad, "T_s": SUBGRID.T_s}, "statistics": stats,
           "wall_seconds": round(time.perf_counter() - t0, 1), "loadavg_end": os.getloadavg()}
    (a.out / "mesh_convergence.json").write_text(json.dumps(out, indent=2))
    fig, ax = plt.subplots(1, 2, figsize=(10, 3.8))
    for s, m in (("SEA", "o-"), ("LWR", "s-")):
        c = [x for x in conv if x["setting"] == s]
        ax[0].loglog([x["to_N"] for x in c], [100 * x["max_rel_change"] for x in c], m, label=f"{s} max over grid")
        ax[0].loglog([x["to_N"] for x in c], [100 * x["mean_rel_change"] for x in c], m, mfc="none", ls="--",
                     label=f"{s} mean over grid")
    ax[0].axhline(0.5, color="k", lw=0.8, ls=":", label="0.5 %")
    ax[0].set_xlabel("intervals N (refined mesh of the pair)")
    ax[0].set_ylabel("|rmse change| on refinement (%)")
    ax[0].legend(fontsize=7)
    ax[0].set_title("QP settings, whole paper grid", fontsize=9)
    for key, lab in (("VVEA_vs_SEA_all", "VVEA beats SEA"), ("iVVEA_vs_SEA_all", "iVVEA beats SEA"),
                     ("VVEA_vs_LWR_all", "VVEA beats LWR"), ("iVVEA_vs_LWR_all", "iVVEA beats LWR")):
        ax[1].plot([x["mesh_N"] for x in stats], [100 * x["pairs"][key]["fraction_X_beats_Y"] for x in stats], "o-",
                   label=lab)
    ax[1].set_xlabel("intervals N")
    ax[1].set_ylabel("% of sub-grid cases")
    ax[1].set_title("Table 5 fractions on the 3 x 4 sub-grid", fontsize=9)
    ax[1].legend(fontsize=7)
    tight_layout_once(fig)
    fig.savefig(a.out / "mesh_convergence.png", dpi=130)
    print(json.dumps(out, indent=1))


if __name__ == "__main__":
    main()
