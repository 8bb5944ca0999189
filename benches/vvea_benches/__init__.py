"""Bench simulators that judge the identification and the diagnosis of ``vvea_design``; not part of the library.

- ``physbench`` -- an independent tension-test bench simulated from physics (chamber thermodynamics,
  orifice and relief-valve flow, LuGre friction, leakage, load string and sensor): the proof of the
  diagnosis, sharing no formula with the effect catalogue;
- ``testbench`` -- a unit-test bench: eq. 14 plus the catalogue's effects (each effect's own bench
  force), with randomised parameters at a target signal-to-noise ratio, and the diagnosis benchmark.

``vvea_design`` never imports this package and its wheel does not ship it; the tests and the studies
do (``scripts/install.sh test`` installs it editable).
"""
