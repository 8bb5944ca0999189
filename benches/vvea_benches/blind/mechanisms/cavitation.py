"""Cavitation on retraction: the oil side cannot be pulled below its gas-release pressure.

Physics
-------
While retracting, oil flows back from the bladder through the throttle into the inner chamber;
the inner chamber's pressure is the chamber-2 gas pressure minus the throttle's pressure drop,
``P2(x) - F_thr/A2``. It cannot fall below the pressure at which the dissolved air comes out
(gaseous cavitation, ``p_cav``): there the oil column breaks and the damping force is capped at
``A2 (P2(x) - p_cav)``. The cap is low at 1 MPa and grows with the charge and with x; it bites at
the closed valves and the high speeds, only while retracting.

Ranges
------
- ``p_cav_MPa`` 0.05–0.3 MPa (absolute): air comes out of mineral oil well above its vapour
  pressure, at some tenths of a bar to a few bar depending on its air content.
"""

from __future__ import annotations

from ..spec import MechanismSpec, Range


def apply(params, ctx, mods) -> None:
    """Give every experiment its cavitation pressure.

    Parameters
    ----------
    params : dict
        ``p_cav_MPa`` (MPa, absolute).
    ctx : CampaignContext
        The campaign.
    mods : list of ExperimentMods
        Edited in place.
    """
    for m in mods:
        m.claim("cavitation_p_MPa", SPEC.name)
        m.cavitation_p_MPa = params["p_cav_MPa"]


SPEC = MechanismSpec(
    name="cavitation",
    domain="fluid",
    description="while retracting the oil side cavitates at closed valves and high speed: the damping "
                "force is capped at the charge's pressure times the piston area",
    states=("direction", "velocity", "valve", "charge", "position"),
    ranges={"p_cav_MPa": Range(0.05, 0.3, "MPa", "gas release pressure of mineral oil")},
    apply=apply,
)
