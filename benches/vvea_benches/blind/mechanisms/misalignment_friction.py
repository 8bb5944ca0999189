"""Misaligned grips: a side load on the rod guide makes friction grow with the transmitted force.

Physics
-------
When the tester's clevises are offset or tilted against the unit's axis, the axial force ``F``
through the unit comes with a side load ``F e / l`` on the rod guide (offset ``e``, guide length
``l``), and the guide's friction ``μ F e / l`` adds to the seal friction against the motion. It
therefore grows with the spring force (with x and the charge) and with the damping force, and is
nil when the unit carries no load.

Ranges
------
- ``mu_eff`` 0.01–0.03: guide friction μ 0.1–0.2 (bronze/PTFE) times an offset-to-length ratio of
  0.05–0.15 (1–3 mm over a 15–20 mm guide).
"""

from __future__ import annotations

import numpy as np

from ..spec import MechanismSpec, Range


def apply(params, ctx, mods) -> None:
    """Add the guide's load-proportional friction to every experiment.

    Parameters
    ----------
    params : dict
        ``mu_eff`` (dimensionless).
    ctx : CampaignContext
        The campaign.
    mods : list of ExperimentMods
        Edited in place.
    """
    for m in mods:
        m.friction_terms.append(lambda s: params["mu_eff"] * np.abs(s.F_gas + s.F_thr))


SPEC = MechanismSpec(
    name="misalignment_friction",
    domain="rig",
    description="misaligned grips load the rod guide sideways: friction grows in proportion to the force "
                "the unit carries",
    states=("position", "charge", "direction", "velocity", "valve"),
    ranges={"mu_eff": Range(0.01, 0.03, "1", "guide friction times offset over guide length")},
    apply=apply,
)
