"""Air entrained in the oil: a compressible oil column makes the damping force lag.

Physics
-------
Undissolved air bubbles in the oil between the working piston and the throttle make that oil
column compressible. Its bulk modulus is the bubbles' and the oil's in series,
``1/K = (1 - α)/K_oil + α/P`` (isothermal air at pressure ``P``), and the bubbles' volume share
shrinks with pressure, ``α = α1 (1 MPa / p2)``. The column of volume ``V_in`` is a spring of
stiffness ``k = A2² K / V_in`` in series with the throttle (a Maxwell element)::

    dF/dt = k (ẋ - u(F)),   u(F): the velocity the throttle passes at force F

so the damping force builds up with the time constant ``L(γ)/k`` after the start and after the
reversal: long at the closed valve and at low charge, nil at the open valve.

Ranges
------
- ``alpha_at_1MPa`` 0.003–0.015: 0.3–1.5 % free air at 1 MPa in a bladder unit filled without
  vacuum (more would make the closed valve's force lag by seconds).
- ``V_in_mm3`` 2e4–4.5e4 mm³: the oil between piston and throttle (30 mm bore × 30–60 mm plus
  channels).
- ``K_oil_MPa`` 1400–1700 MPa: bulk modulus of mineral hydraulic oil.
"""

from __future__ import annotations

from ..spec import MechanismSpec, Range


def oil_stiffness_N_per_mm(params, A2_mm2: float, p2_MPa: float) -> float:
    """Hydraulic stiffness of the oil column at a charge, N/mm.

    Parameters
    ----------
    params : dict
        ``alpha_at_1MPa``, ``V_in_mm3``, ``K_oil_MPa``.
    A2_mm2 : float
        Working piston area, mm².
    p2_MPa : float
        Charge, MPa (the oil sits at about the chamber-2 pressure).

    Returns
    -------
    float
        ``A2² K_eff / V_in``, N/mm.
    """
    alpha = min(0.5, params["alpha_at_1MPa"] / p2_MPa)
    K = 1.0 / ((1.0 - alpha) / params["K_oil_MPa"] + alpha / p2_MPa)
    return A2_mm2**2 * K / params["V_in_mm3"]


def apply(params, ctx, mods) -> None:
    """Give every experiment its oil column's stiffness.

    Parameters
    ----------
    params : dict
        ``alpha_at_1MPa``, ``V_in_mm3``, ``K_oil_MPa``.
    ctx : CampaignContext
        The campaign.
    mods : list of ExperimentMods
        Edited in place.
    """
    for m, plan in zip(mods, ctx.plans):
        m.claim("oil_stiffness_N_per_mm", SPEC.name)
        m.oil_stiffness_N_per_mm = oil_stiffness_N_per_mm(params, ctx.base.A2_mm2, plan.p2_MPa)


SPEC = MechanismSpec(
    name="entrained_air",
    domain="fluid",
    description="air bubbles make the oil column compressible: the damping force lags the motion, more "
                "at closed valves and low charge",
    states=("velocity", "valve", "charge", "since_reversal", "time_in_experiment"),
    ranges={
        "alpha_at_1MPa": Range(0.003, 0.015, "1", "free air in a unit filled without vacuum"),
        "V_in_mm3": Range(2.0e4, 4.5e4, "mm³", "oil between the piston and the throttle"),
        "K_oil_MPa": Range(1400.0, 1700.0, "MPa", "bulk modulus of mineral oil"),
    },
    apply=apply,
)
