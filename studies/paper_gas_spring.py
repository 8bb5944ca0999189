"""Reproduce the paper's gas-spring figures (Figs 3, 4, 5) and the 1.86 % reference.

    python studies/paper_gas_spring.py [--out DIR]

Writes fig3_setpoints.{csv,png}, fig4_pressures.{csv,png}, fig5_volumes.{csv,png}
and reference.json (our numbers next to the paper's) into
studies/results/paper_gas_spring/ by default.
"""

from __future__ import annotations

import argparse
import csv
import json
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

from vvea_design.spring import paper  # noqa: E402
from vvea_design.spring.gas_spring import least_squares_line  # noqa: E402
from vvea_design.spring.plots import save_figure  # noqa: E402

HERE = Path(__file__).resolve().parent


def _write_csv(path: Path, rows: list[dict]) -> None:
    with open(path, "w", newline="") as fh:
        w = csv.DictWriter(fh, fieldnames=list(rows[0]))
        w.writeheader()
        for r in rows:
            w.writerow({k: (f"{v:.6g}" if isinstance(v, float) else v) for k, v in r.items()})


def main(out: Path) -> dict:
    out.mkdir(parents=True, exist_ok=True)
    summary: dict = {}

    springs, rows = paper.fig3_setpoints()
    _write_csv(out / "fig3_setpoints.csv", rows)
    fig, ax = plt.subplots(figsize=(7, 4.5))
    x = np.linspace(-5, 40, 181)
    for x0, s in springs.items():
        ax.plot(x, s.force_N(x), label=f"x0 = {x0:+g} mm (p1 = {s.p1_MPa:.3f} MPa)")
        ax.plot([x0], [0], "ko", ms=4)
    ax.axhline(0, color="k", lw=0.5)
    ax.set(xlabel="displacement x [mm]", ylabel="force [N]", title="Fig. 3: setpoint shift by p1 (eq. 6), p2 fixed")
    ax.legend(fontsize=8)
    ax.grid(alpha=0.3)
    save_figure(fig, out / "fig3_setpoints.png")
    summary["fig3"] = {f"{x0:+g}": {"p1_MPa": s.p1_MPa, "force_at_x0_N": float(s.force_N(x0))} for x0, s in springs.items()}

    springs, rows = paper.fig4_pressures()
    _write_csv(out / "fig4_pressures.csv", rows)
    fig, ax = plt.subplots(figsize=(7, 4.5))
    x = paper.PAPER_FIG5.x_mm(161)
    fig4 = {}
    for p2, s in springs.items():
        k = s.mean_stiffness_N_per_mm()
        fig4[f"{p2:g}"] = {"mean_stiffness_N_per_mm": k, "stiffness_per_MPa": k / p2, "linearity_error": s.linearity_error()}
        ax.plot(x, s.force_N(x), label=f"p2 = {p2:g} MPa: {k:.1f} N/mm")
    ax.set(xlabel="displacement x [mm]", ylabel="force [N]", title="Fig. 4: stiffness scales with p2 (p1/p2 fixed)")
    ax.legend(fontsize=8)
    ax.grid(alpha=0.3)
    save_figure(fig, out / "fig4_pressures.png")
    summary["fig4"] = fig4

    springs, rows = paper.fig5_volumes()
    _write_csv(out / "fig5_volumes.csv", rows)
    fig, (ax, ax2) = plt.subplots(1, 2, figsize=(12, 4.5))
    fig5 = {}
    for V2, s in springs.items():
        F = s.force_N(x)
        lin = s.linearity_error()  # exact metric
        fig5[f"{V2:.4g}"] = {"linearity_error": s.linearity_error(), "max_force_N": float(F.max())}
        line = ax.plot(x, F, label=f"V2 = {V2:.3g} mm³: {100 * lin:.2f} %")[0]
        k, b = least_squares_line(x, F)
        if abs(V2 - 7.34e4) < 1:
            ax.plot(x, k * x + b, "--", color=line.get_color(), lw=1, label="linear fit of V2 = 7.34e4")
        ax2.plot(x, F - (k * x + b), color=line.get_color())
    ax.set(xlabel="displacement x [mm]", ylabel="force [N]", title="Fig. 5: progression with V2")
    ax.legend(fontsize=8)
    ax.grid(alpha=0.3)
    ax2.set(xlabel="displacement x [mm]", ylabel="F − least-squares line [N]", title="deviation from the linear fit")
    ax2.grid(alpha=0.3)
    save_figure(fig, out / "fig5_volumes.png")
    summary["fig5"] = fig5

    ref = paper.reference_summary()
    ref_401 = paper.reference_summary(num=401)
    ref_fine = paper.reference_summary(num=4001)
    eq = paper.reference_summary(paper.equal_area_variant())
    summary["reference"] = {
        "configuration": "PAPER_FIG5: A2 = pi/4 30^2 (piston), A1 = pi/4 57.1^2 (outer-tube bore), "
                         "V1 = 1.22e5 mm3, V2 = 7.34e4 mm3, F(0) = 0, p2 = 2.3866 MPa",
        "ours_exact": ref.to_dict(),
        "ours_401_samples": ref_401.to_dict(),
        "ours_4001_samples": ref_fine.to_dict(),
        "equal_area_reading_A1_eq_A2": eq.to_dict(),
    }
    (out / "reference.json").write_text(json.dumps(summary, indent=2, sort_keys=True) + "\n")
    print(f"reference (exact metric): linearity {100 * ref.linearity_error:.3f} % ({ref.deviation_N:.2f} N at "
          f"{ref.max_force_N:.0f} N); paper 1.86 % (33.98 N at 1827 N); "
          f"equal-area reading {100 * eq.linearity_error:.2f} %")
    print(f"wrote {out}")
    return summary


if __name__ == "__main__":
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--out", type=Path, default=HERE / "results" / "paper_gas_spring")
    main(ap.parse_args().out)
