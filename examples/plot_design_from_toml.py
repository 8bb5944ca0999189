"""
Design a spring from a requirements file
========================================

The first step of the main job on its own: read a requirements TOML, find the most linear spring
that meets it, and look at the result — its layout, its linearity for slow and fast strokes,
every constraint's margin and its force curve. ``vvea optimise --spec FILE`` does the same on the
command line.
"""

# %%
# Read the requirements
# ---------------------
# ``examples/my_requirements.toml`` asks for a unit smaller than the paper's: 50 mm × 150 mm,
# 30 mm of travel, 60 N/mm at 3 MPa. Every key it leaves out keeps its default
# (``examples/requirements.toml`` lists them all).
import dataclasses
import os
import tempfile
from pathlib import Path

import matplotlib.pyplot as plt

import vvea_design as vd
from vvea_design.spring.plots import plot_spring

SMALL = os.environ.get("VVEA_EXAMPLES_SMALL") == "1"  # the test suite's size: one layout instead of three
try:
    HERE = Path(__file__).resolve().parent
except NameError:  # sphinx-gallery runs the example in its own folder, without __file__
    HERE = Path.cwd()

requirements = vd.load_requirements(HERE / "my_requirements.toml")
if SMALL:
    requirements = dataclasses.replace(requirements, layouts=("inner_tube",))
print(f"travel {requirements.travel_mm:g} mm, envelope {requirements.max_outer_diameter_mm:g} × "
      f"{requirements.max_housing_length_mm:g} mm, ≥ {requirements.min_mean_stiffness_N_per_mm:g} N/mm "
      f"at ≤ {requirements.max_charge_MPa:g} MPa; layouts tried: {', '.join(requirements.layouts)}")

# %%
# Optimise
# --------
# The search is seeded: the same seed gives the same design. ``out`` is the design file the job
# writes (with its force plot beside it): the file every other command and job reads.
out = Path(tempfile.mkdtemp(prefix="vvea_example_")) / "design.json"
result = vd.optimise(requirements, seed=0, out=out)
ev = result.evaluation
print(f"layout {ev.design.layout}: linearity {100 * ev.linearity_isothermal:.3f} % (isothermal), "
      f"{100 * ev.linearity_adiabatic:.3f} % (adiabatic); {ev.mean_stiffness_N_per_mm:.1f} N/mm, "
      f"{ev.mass_g:.0f} g")
print(f"wrote {out}")

# %%
# Every constraint's margin
# -------------------------
# A margin ≥ 0 is met; the ones near 0 bind — they are what stops the linearity from getting better.
for name, margin in ev.margins.items():
    print(f"  {name:26s} {margin:+.4f}{'   binds' if abs(margin) < 1e-3 else ''}")
assert all(m >= -1e-9 for m in ev.margins.values()), "every constraint is met"

# %%
# The force curve
# ---------------
# At the design's charge and at 1 and 2 MPa (the stiffness follows the charge; the shape does not),
# dashed: the same hardware with adiabatic gas (fast strokes).
fig = plt.figure(figsize=(11, 7))  # plot_spring draws into a pyplot figure (the gallery shows those)
plot_spring(ev.design.gas_spring, extra_charges_MPa=(1.0, 2.0),
            title=f"{ev.design.layout} layout: linearity {100 * ev.linearity_error:.2f} %", fig=fig)
plt.show()
