"""How much gas does a linearity need? The packing-free bound of eq. 5.

    python studies/linearity_bound.py [--out DIR]

For each total gas volume V1 + V2, the best linearity any layout could reach
under the default requirements (charges <= 4 MPa with F(0) = 0, stiffness
>= 93.2 N/mm, >= 20 % gas left at full stroke), ignoring where the gas goes.
Writes bound.csv and bound.png, and marks the optimiser's design.
"""

from __future__ import annotations

import argparse
import csv
import json
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

from vvea_design.spring.optimise import gas_volume_bound  # noqa: E402
from vvea_design.parallel import parallel_map  # noqa: E402
from vvea_design.spring.plots import save_figure  # noqa: E402

HERE = Path(__file__).resolve().parent
VOLUMES = [60e3, 80e3, 100e3, 130e3, 160e3, 200e3, 250e3, 300e3]


def main(out: Path) -> list[dict]:
    out.mkdir(parents=True, exist_ok=True)
    rows = parallel_map(gas_volume_bound, VOLUMES, description="bound per gas volume")
    with open(out / "bound.csv", "w", newline="") as fh:
        w = csv.DictWriter(fh, fieldnames=list(rows[0]))
        w.writeheader()
        w.writerows(rows)
    fig, ax = plt.subplots(figsize=(7, 4.5))
    ax.plot([r["total_gas_mm3"] / 1e3 for r in rows], [100 * r["linearity_error"] for r in rows], "o-",
            label="best any layout can do (eq. 5 only)")
    opt = HERE / "results" / "optimise" / "design.json"
    if opt.exists():
        d = json.loads(opt.read_text())
        p = d["parameters"]
        ax.plot([(p["V1_mm3"] + p["V2_mm3"]) / 1e3], [100 * d["performance"]["linearity_error"]], "r*", ms=14,
                label="our optimised unit (59.5 × 132.5 mm envelope)")
    ax.axhline(1.86, color="gray", ls="--", lw=1, label="paper, hand-tuned: 1.86 %")
    ax.axhline(1.0, color="gray", ls=":", lw=1, label="1 %")
    ax.set(xlabel="total gas volume V1 + V2 [10³ mm³]", ylabel="linearity error [%]",
           title="linearity needs gas: packing-free bound at 93.2 N/mm, 4 MPa")
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8)
    save_figure(fig, out / "bound.png")
    for r in rows:
        print(f"V1+V2 = {r['total_gas_mm3']:>8.0f} mm³: {100 * r['linearity_error']:.3f} %  (A1 {r['A1_mm2']:.0f}, "
              f"A2 {r['A2_mm2']:.0f} mm², V1 {r['V1_mm3']:.0f}, V2 {r['V2_mm3']:.0f} mm³)")
    return rows


if __name__ == "__main__":
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--out", type=Path, default=HERE / "results" / "linearity_bound")
    main(ap.parse_args().out)
