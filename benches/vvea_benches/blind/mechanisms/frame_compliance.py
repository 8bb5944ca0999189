"""Compliant load train: the tester's frame, load cell and clevises in series with the unit.

Physics
-------
The displacement channel reads the crosshead, not the piston. Between them sit the frame, the
load cell, the clevis pins and the unit's rod eyes, together a spring ``K_f``. The piston is at
``x_p = x_meas - F/K_f``: the spring looks softer (by about ``k/K_f``, so more at high charge), and
at the closed valves, where the damper is stiff, ``K_f`` and the throttle form a Maxwell element —
the damping force builds up with the time constant ``L(γ)/K_f`` after the start and the reversal;
at the reversal the frame unloads by twice the friction before the piston moves back.

Ranges
------
- ``K_N_per_mm`` 4000–15000 N/mm: a table-top 5–10 kN frame (10–20 kN/mm), its load cell
  (20–50 kN/mm) and two clevis-pin joints with their play taken up (10–30 kN/mm each), in series.
"""

from __future__ import annotations

from ..spec import MechanismSpec, Range


def apply(params, ctx, mods) -> None:
    """Put the compliant load train in series with every experiment.

    Parameters
    ----------
    params : dict
        ``K_N_per_mm`` (N/mm).
    ctx : CampaignContext
        The campaign.
    mods : list of ExperimentMods
        Edited in place.
    """
    for m in mods:
        m.claim("frame_K_N_per_mm", SPEC.name)
        m.frame_K_N_per_mm = params["K_N_per_mm"]


SPEC = MechanismSpec(
    name="frame_compliance",
    domain="rig",
    description="the load train (frame, load cell, clevises) is a spring in series: the piston lags "
                "the crosshead by F/K",
    states=("position", "charge", "velocity", "valve", "since_reversal"),
    ranges={"K_N_per_mm": Range(4000.0, 15000.0, "N/mm", "frame, load cell and clevis joints in series")},
    apply=apply,
)
