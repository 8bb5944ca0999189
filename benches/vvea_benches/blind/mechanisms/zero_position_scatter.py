"""Displacement zero set anew at each mounting: the piston's zero scatters from run to run.

Physics
-------
Before each experiment the operator moves the crosshead until the unit hangs force-free and zeroes
the displacement channel there. The pin play of the rod eyes and the friction band of the seal
(± C around the gas force's zero) leave the piston a little off its true zero each time, so the
piston sits at ``x = x_meas + δ_e`` with ``δ_e`` drawn anew per experiment. The spring then reads
``k(p2) δ_e`` more or less all along the run: an offset that scales with the charge and is random
from experiment to experiment — no state of the recordings predicts it.

Ranges
------
- ``sigma_mm`` 0.05–0.25 mm: friction band ± C/k (≈ ±0.1 mm at 4 MPa, ±0.5 mm at 1 MPa, of
  which the operator's force-free criterion removes most) plus 0.05 mm pin play.
"""

from __future__ import annotations

from ..spec import MechanismSpec, Range


def apply(params, ctx, mods) -> None:
    """Shift every experiment's piston zero by a fresh draw.

    Parameters
    ----------
    params : dict
        ``sigma_mm`` (mm).
    ctx : CampaignContext
        The campaign (gives this mechanism's own random source).
    mods : list of ExperimentMods
        Edited in place.
    """
    rng = ctx.rng_for(SPEC.name)
    for m in mods:
        m.x_offset_mm += float(rng.normal(0.0, params["sigma_mm"]))


SPEC = MechanismSpec(
    name="zero_position_scatter",
    domain="sensing",
    description="the displacement zero is set anew at each mounting and scatters: a random spring "
                "offset per experiment, proportional to the charge",
    states=("experiment", "charge"),
    ranges={"sigma_mm": Range(0.05, 0.25, "mm", "seal friction band and pin play at zeroing")},
    apply=apply,
)
