"""
The main job from Python
========================

``vd.design_unit`` is what ``vvea design`` runs: optimise the spring, draw its curve, build and
check the CAD set, check the bladder in the requirements' silicone, map the unit to an actuator,
run the design's own actuator study and write ``report.html`` — all into one folder, returning a
typed result. At the test suite's size the CAD set and the actuator study are left out.
"""

# %%
# Run it
# ------
import os
import tempfile
from pathlib import Path

import matplotlib.pyplot as plt

import vvea_design as vd

SMALL = os.environ.get("VVEA_EXAMPLES_SMALL") == "1"
try:
    HERE = Path(__file__).resolve().parent
except NameError:  # sphinx-gallery runs the example in its own folder, without __file__
    HERE = Path.cwd()

requirements = vd.load_requirements(HERE / "my_requirements.toml")
out = Path(tempfile.mkdtemp(prefix="vvea_example_")) / "my_unit"
unit = vd.design_unit(requirements, out=out, cad=not SMALL, actuator_study=not SMALL)

# %%
# What it found
# -------------
# ``unit`` is a frozen :class:`~vvea_design.pipeline.UnitDesign`; ``unit.to_dict()`` is what
# ``unit.json`` holds.
ev = unit.optimisation.evaluation
print(f"{ev.design.layout} layout: linearity {100 * ev.linearity_isothermal:.3f} % (isothermal), "
      f"{100 * ev.linearity_adiabatic:.3f} % (adiabatic), {ev.mass_g:.0f} g")
print(f"bladder ({unit.bladder.silicone.name}): strain bound {100 * unit.bladder.strain_bound:.2f} % "
      f"against {100 * unit.bladder.allowable_strain:.0f} % -> {'passes' if unit.bladder.passes else 'FAILS'}")
print(f"actuator: K = {unit.actuator.K_Nm_per_rad:.1f} N m/rad, "
      f"D = {unit.actuator.D_min_Nms_per_rad:.3g} … {unit.actuator.D_max_Nms_per_rad:.4g} N m s/rad")
print("every check passes:", unit.passes)
assert unit.passes

# %%
# What it wrote
# -------------
for role, path in sorted(unit.files.items()):
    print(f"  {role:20s} {Path(path).relative_to(out) if Path(path).is_absolute() else path}")

# %%
# The force curve it drew
# -----------------------
fig, ax = plt.subplots(figsize=(8, 6))
ax.imshow(plt.imread(out / "design_force.png"))
ax.set_axis_off()
plt.show()
