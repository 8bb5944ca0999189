"""
Diagnose a bench campaign
=========================

A campaign of tension tests (``../shared/recordings/campaign_c.csv``, beside the repository)
that the paper's model, eq. 14, does not fit: ``vd.diagnose`` finds where model and bench
disagree, names the physics the model left out, fits it, and shows the error falling on
experiments it was not fitted to. ``vvea diagnose FILE --out DIR`` does the same on the command
line.
"""

# %%
# The recordings
# --------------
# One row per sample, many experiments per file (the exchange format). At the test suite's size
# the example takes a 50-experiment subset of the 135: the lowest and highest charge, every other
# valve position, all speeds.
import os
import tempfile
from pathlib import Path

import matplotlib.pyplot as plt
import pandas as pd

import vvea_design as vd

SMALL = os.environ.get("VVEA_EXAMPLES_SMALL") == "1"
try:
    HERE = Path(__file__).resolve().parent
except NameError:  # sphinx-gallery runs the example in its own folder, without __file__
    HERE = Path.cwd()
campaign = HERE.parent.parent / "shared" / "recordings" / "campaign_c.csv"
out = Path(tempfile.mkdtemp(prefix="vvea_example_"))

if SMALL:
    table = pd.read_csv(campaign)
    first = table.groupby("experiment").first()
    valves = sorted(first.valve_deg.unique())
    keep = first.index[first.p2_MPa.isin([1, 4]) & first.valve_deg.isin(valves[::2])]
    campaign = out / "campaign_c_subset.csv"
    table[table.experiment.isin(keep)].to_csv(campaign, index=False)
print(f"{campaign.name}: {pd.read_csv(campaign).experiment.nunique()} experiments")

# %%
# Diagnose
# --------
# The job fits eq. 14, estimates the noise floor, selects effects by cross-validation (whole
# experiments left out), refits, and checks the final model on held-out experiments. It writes
# ``report.json``, ``summary.md``, ``final_model.json`` and the figures into ``out``. At the small
# size it skips the flexible-learner check for leftover structure (``learner=False``).
run = vd.diagnose(campaign, learner=not SMALL, out=out / "diagnosis")
report = run.diagnosis.report  # the typed report: report.json is its to_dict()
print("accepted:", ", ".join(e.id for e in report.accepted) or "nothing")
print(f"held-out RMS: eq. 14 {report.heldout.baseline_N:.1f} N -> final {report.heldout.final_N:.1f} N "
      f"(noise floor {report.noise_floor_N:.1f} N)")
for effect in report.accepted:
    print(f"  {effect.id}: {effect.explanation}")

# %%
# The held-out error after each accepted term
# -------------------------------------------
# The diagnosis's own figure: eq. 14 alone, then each accepted term, on experiments that took
# no part in selecting or fitting them.
fig, ax = plt.subplots(figsize=(8, 5))
ax.imshow(plt.imread(out / "diagnosis" / "heldout_per_effect.png"))
ax.set_axis_off()
plt.show()

# %%
# Use the fitted model
# --------------------
# ``final_model.json`` is eq. 14 plus the accepted terms; it predicts new motions of the same unit.
model = vd.load_final_model(out / "diagnosis" / "final_model.json")
print(model.model)
