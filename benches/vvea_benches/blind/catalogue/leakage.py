"""``leakage``: the charge drifts down over the campaign.

Physics
-------
Every experiment's charge comes from the bench's charging panel, whose dome-loaded regulators
deliver the pressure of their gas domes (set once at the campaign's start). A dome that leaks
through its fitting loses pressure as ``exp(-t/τ_dome)`` on the campaign clock, so every later
charge — chamber 2 and chamber 1 alike — falls short of its label by the same factor. On top, the
unit's chamber 2 leaks past its seal during each run, ``exp(-t/τ_seal)`` since its charging
(the leak rate is proportional to the pressure: laminar flow through the seal's micro-channels).

Ranges
------
- ``tau_dome_h`` 60–200 h: a dome losing 4–14 % over a 9-hour campaign — a visibly leaky fitting.
- ``tau_seal_h`` 20–100 h: a chamber losing 0.2–1 % during an 800 s slow run.
"""

from __future__ import annotations

import numpy as np

from ..spec import MechanismSpec, Range


def apply(params, ctx, mods) -> None:
    """Scale the charges by the dome's leak and chamber 2 by its seal leak.

    Parameters
    ----------
    params : dict
        ``tau_dome_h`` (h), ``tau_seal_h`` (h).
    ctx : CampaignContext
        The campaign (start times on the campaign clock).
    mods : list of ExperimentMods
        Edited in place.
    """
    for m, plan in zip(mods, ctx.plans):
        f = float(np.exp(-plan.t_start_s / (3600.0 * params["tau_dome_h"])))
        m.charge1.append(lambda t, f=f: f)
        m.charge2.append(lambda t, f=f: f * np.exp(-np.asarray(t) / (3600.0 * params["tau_seal_h"])))


SPEC = MechanismSpec(
    name="leakage",
    domain="gas",
    description="the charge drifts down over the campaign (a leaking charge supply and chamber seal)",
    states=("position", "charge", "campaign_order"),
    ranges={
        "tau_dome_h": Range(60.0, 200.0, "h", "a dome losing 4-14 % over a campaign"),
        "tau_seal_h": Range(20.0, 100.0, "h", "a chamber losing 0.2-1 % in a slow run"),
    },
    apply=apply,
    catalogue_id="leakage",
)
