"""Warming charging panel: every charge comes out higher as the room warms over the campaign.

Physics
-------
The presets are set on the bench's charging panel by dome-loaded regulators: each regulator's
outlet follows the pressure of its dome, a closed gas volume set once at the start of the
campaign. As the laboratory warms over the day (heating, sun, the tester's drive), the dome's gas
warms and its pressure rises as ``T/T0`` (ideal gas, fixed volume), so every charge delivered to
the unit — chamber 2 and chamber 1 alike — is higher than its label by the same factor:
``p_actual = p2 (T0 + ΔT(t))/T0`` with ``ΔT(t) = dT (1 - exp(-t/τ))`` on the campaign clock.
The spring force grows with the charge, so the error grows with x and p2 and with the campaign.

Ranges
------
- ``dT_K`` 3–9 K: a laboratory warming over a working day (heating in the morning, sun on the
  panel); 9 K gives a 3 % higher charge.
- ``tau_h`` 1–4 h: time constant of a room and of a steel panel following it.
"""

from __future__ import annotations

import numpy as np

from ..spec import MechanismSpec, Range

T0_K = 293.15


def apply(params, ctx, mods) -> None:
    """Scale both chambers' charges by the dome's temperature ratio at each experiment's charging.

    Parameters
    ----------
    params : dict
        ``dT_K`` (K) and ``tau_h`` (h).
    ctx : CampaignContext
        The campaign (its plan gives each experiment's start time, s).
    mods : list of ExperimentMods
        Edited in place.
    """
    for m, plan in zip(mods, ctx.plans):
        dT = params["dT_K"] * (1.0 - np.exp(-plan.t_start_s / (3600.0 * params["tau_h"])))
        f = (T0_K + dT) / T0_K
        m.charge2.append(lambda t, f=f: f)
        m.charge1.append(lambda t, f=f: f)


SPEC = MechanismSpec(
    name="room_warming",
    domain="thermal",
    description="the charge rises over the campaign as the room (and the regulators' gas domes) warm",
    states=("position", "charge", "campaign_order"),
    ranges={
        "dT_K": Range(3.0, 9.0, "K", "a laboratory warming over a working day"),
        "tau_h": Range(1.0, 4.0, "h", "time constant of a room and a steel panel"),
    },
    apply=apply,
)
