"""Valve backlash: the valve stops short of its command, on the side it was approached from.

Physics
-------
The servo closes its position loop on its own output shaft; the rotary valve follows through a
coupling with play, and the servo stops inside its dead band. The valve therefore rests half the
combined backlash short of the command, on the side it came from:
``γ = γ_cmd - (b/2) sign(γ_cmd - γ_prev)``; when the command does not change, the valve does not
move. With the run order shuffled, the same nominal angle is reached from above in some
experiments and from below in others — and near 105–112° the laminar damping changes by tens of
percent per degree.

Ranges
------
- ``backlash_deg`` 0.4–1.2°: a hobby servo's dead band (≈ 0.2–0.5°) plus the play of a pinned
  coupling (≈ 0.2–0.7°).
"""

from __future__ import annotations

import numpy as np

from ..spec import MechanismSpec, Range


def actual_angles_deg(commands, backlash):
    """Valve angles reached for a sequence of commands.

    Parameters
    ----------
    commands : sequence of float
        Commanded angles in run order, degree.
    backlash : float
        Combined backlash, degree.

    Returns
    -------
    list of float
        Actual angles, degree (the first command is approached from below, from the servo's
        parking position at 0°).
    """
    out, prev_cmd, prev = [], None, 0.0
    for c in commands:
        if prev_cmd is not None and c == prev_cmd:
            out.append(prev)
            continue
        prev = float(c - 0.5 * backlash * np.sign(c - prev))
        prev_cmd = c
        out.append(prev)
    return out


def apply(params, ctx, mods) -> None:
    """Move every experiment's valve to where the backlash leaves it.

    Parameters
    ----------
    params : dict
        ``backlash_deg`` (degree).
    ctx : CampaignContext
        The campaign (its run order).
    mods : list of ExperimentMods
        Edited in place.
    """
    actual = actual_angles_deg([p.valve_deg for p in ctx.plans], params["backlash_deg"])
    for m, a in zip(mods, actual):
        m.claim("valve_deg", SPEC.name)
        m.valve_deg = a


SPEC = MechanismSpec(
    name="valve_backlash",
    domain="actuation",
    description="the valve rests half its backlash short of the command, on the side it came from: the "
                "damping at one nominal angle depends on the previous experiment's valve",
    states=("valve", "history", "velocity"),
    ranges={"backlash_deg": Range(0.4, 1.2, "deg", "servo dead band plus coupling play")},
    apply=apply,
)
