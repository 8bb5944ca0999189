"""``thermal``: each chamber's energy balance with heat exchange through its walls.

Physics
-------
Each gas chamber is a closed mass of ideal gas whose volume the piston changes. Its temperature
follows the first law with Newtonian heat exchange to the wall (wall at the charge temperature)::

    dT/dt = -(γ - 1) T V̇/V + (T_w - T)/τ,     P = P_charge (V_charge/V) (T/T_w)

with γ = 1.4 (air). Slow runs are isothermal (the paper's law); fast runs compress partly
adiabatically: the spring is stiffer and the loop opens (the gas is hotter while extending than
while retracting). Between experiments the gas returns to the wall temperature.

Ranges
------
- ``tau2_s`` 0.5–4 s: thermal time constant of a 50–80 cm³ gas chamber with aluminium walls
  (gas springs and small accumulators of this size: about a second).
- ``tau1_ratio`` 1.0–1.6: chamber 1 is larger (1.2e5 mm³) with less wall per volume.
"""

from __future__ import annotations

from ..spec import MechanismSpec, Range


def apply(params, ctx, mods) -> None:
    """Switch every experiment's gas to the energy balance.

    Parameters
    ----------
    params : dict
        ``tau2_s`` (s), ``tau1_ratio`` (dimensionless).
    ctx : CampaignContext
        The campaign.
    mods : list of ExperimentMods
        Edited in place.
    """
    th = {"tau2_s": params["tau2_s"], "tau1_s": params["tau2_s"] * params["tau1_ratio"]}
    for m in mods:
        m.claim("thermal", SPEC.name)
        m.thermal = dict(th)


SPEC = MechanismSpec(
    name="thermal",
    domain="thermal",
    description="the gas heats when compressed fast and exchanges heat with the walls: stiffness and "
                "loop width depend on speed",
    states=("position", "velocity", "direction", "charge", "since_reversal"),
    ranges={
        "tau2_s": Range(0.5, 4.0, "s", "thermal time constant of a 50-80 cm³ chamber"),
        "tau1_ratio": Range(1.0, 1.6, "1", "chamber 1 is larger, less wall per volume"),
    },
    apply=apply,
    catalogue_id="thermal",
)
