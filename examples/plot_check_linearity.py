"""
Guard linearity in your own tests
=================================

A design file is a product: when something upstream changes, a test should fail if the spring
got less linear. ``vd.assert_linearity`` is that test's assertion (``vvea check`` is the same
gate on the command line). This example checks the repository's reference design, shows the
message a regression gives, and runs a small pytest file that uses it.
"""

# %%
# The design and its linearity
# ----------------------------
# ``cad/design.json`` is the reference design: the buildable optimum of the paper's requirements,
# an ``inner_tube`` unit with M56x1.5 threaded joints (its seals sit clear of the threads, which
# costs linearity: 2.34 %, where the paper's gas-only sizing reached about 1.3 %). The check computes the linearity from the file's ``parameters`` alone (paper eq. 5, the exact
# metric), so an edited or stale ``performance`` block cannot fool it.
import re
import subprocess
import sys
import tempfile
import textwrap
from pathlib import Path

import matplotlib.pyplot as plt

import vvea_design as vd
from vvea_design.spring.plots import plot_spring

try:
    HERE = Path(__file__).resolve().parent
except NameError:  # sphinx-gallery runs the example in its own folder, without __file__
    HERE = Path.cwd()
design_file = HERE.parent / "cad" / "design.json"

design = vd.load_design(design_file)
lin = design.gas_spring.linearity_error()
print(f"{design_file.name}: {design.layout} layout, linearity error {100 * lin:.4f} %")

# %%
# A limit it meets, and one it misses
# -----------------------------------
# Take the design's own error plus a margin as the limit: 2.40 % over the reference's 2.34 %
# leaves room for round-off, not for a regression. A limit below the error, 2.30 %, shows what a
# regression looks like: the assertion fails with a message that names the design, its error, the
# limit and the force span — what pytest shows.
vd.assert_linearity(design_file, max_linearity=0.0240)
print("limit 2.40 %: passes")
try:
    vd.assert_linearity(design_file, max_linearity=0.0230)
except AssertionError as exc:
    print(f"limit 2.30 %: fails -> {exc}")
else:
    raise SystemExit("the tight limit should have failed")

# %%
# In your own pytest file
# -----------------------
# The same two lines in a test module, run by pytest as your CI would run it.
tests = Path(tempfile.mkdtemp(prefix="vvea_example_"))
(tests / "test_my_unit.py").write_text(textwrap.dedent(f"""
    import vvea_design as vd

    def test_unit_stays_linear():
        vd.assert_linearity({str(design_file)!r}, max_linearity=0.0240)
"""))
run = subprocess.run([sys.executable, "-m", "pytest", "-q", "-p", "no:cacheprovider", str(tests)],
                     capture_output=True, text=True, cwd=tests)
print(re.sub(r" in [0-9.]+s", "", run.stdout.strip().splitlines()[-1]))  # e.g. "1 passed"
assert run.returncode == 0, run.stdout + run.stderr

# %%
# What the limit guards
# ---------------------
# The deviation of the force from its least-squares line (second panel): the linearity error is
# its largest absolute value divided by the force span.
fig = plt.figure(figsize=(11, 7))  # plot_spring draws into a pyplot figure (the gallery shows those)
plot_spring(design.gas_spring, title=f"reference design: linearity {100 * lin:.3f} %", fig=fig)
plt.show()
