"""``pressure_friction``: the seal is energised by the pressure it seals.

Physics
-------
An elastomer seal presses on its counter-face with its own preload plus the pressure it seals
acting on its lip; its friction is ``C + c_p P`` (Coulomb plus a hydrostatic term). The working
piston's seal holds the oil at the chamber-2 pressure, which rises with the charge and, as the
chamber is compressed, along the stroke: ``P2(x) = p2 V2/(V2 - A2 x)``.

Ranges
------
- ``c_p_N_per_MPa`` 8–25 N/MPa: friction coefficient 0.1–0.2 times the lip's projected area
  (π × 30 mm × 0.8–1 mm ≈ 75–95 mm²).
"""

from __future__ import annotations

from ..spec import MechanismSpec, Range


def apply(params, ctx, mods) -> None:
    """Add the pressure-energised friction to every experiment.

    Parameters
    ----------
    params : dict
        ``c_p_N_per_MPa`` (N/MPa).
    ctx : CampaignContext
        The campaign.
    mods : list of ExperimentMods
        Edited in place.
    """
    for m in mods:
        m.friction_terms.append(lambda s: params["c_p_N_per_MPa"] * s.P2)


SPEC = MechanismSpec(
    name="pressure_friction",
    domain="friction",
    description="seal friction grows with the chamber pressure it seals (charge, and along the stroke)",
    states=("charge", "position", "direction"),
    ranges={"c_p_N_per_MPa": Range(8.0, 25.0, "N/MPa", "friction coefficient times the lip's area")},
    apply=apply,
    catalogue_id="pressure_friction",
)
