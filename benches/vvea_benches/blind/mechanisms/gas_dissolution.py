"""Gas dissolving in the oil: after each recharge the charge drifts toward the oil's equilibrium.

Physics
-------
The silicone bladder is permeable to air, so chamber 2's gas exchanges with the oil, which holds
air in solution in proportion to the pressure (Henry's law; Ostwald coefficient ``λ``: volume of
gas dissolved per volume of oil at the same pressure). Let ``D`` be the pressure the dissolved air
is in equilibrium with; with gas volume ``V2`` and oil volume ``V_oil``::

    dD/dt = (P - D)/τ,     dP/dt = -ε (P - D)/τ,     ε = λ V_oil / V2

(the gas lost by the chamber is the gas the oil takes up). Before every experiment the unit is
recharged to its preset, but the oil still holds the previous charge's air: after a step from 1
to 4 MPa the chamber loses gas during the run, after a step down the oil gives gas back. The
charge therefore depends on the previous experiments' presets and on the time since the start;
the slow runs (800 s) show the full drift, the fast ones almost none.

Ranges
------
- ``ostwald`` 0.07–0.11: air in mineral oil near 20 °C (≈ 0.08–0.09).
- ``V_oil_mm3`` 3e4–6e4 mm³: oil in contact with the bladder.
- ``tau_s`` 100–600 s: permeation through the 1–2 mm silicone wall and diffusion into the oil
  film.
"""

from __future__ import annotations


import numpy as np

from ..spec import MechanismSpec, Range


def _evolve(P, D, eps, tau, t):
    """Closed-form exchange over time t: returns (P, D) (arrays if t is)."""
    Peq = (P + eps * D) / (1.0 + eps)
    e = np.exp(-(1.0 + eps) * np.asarray(t, dtype=float) / tau)
    return Peq + (P - Peq) * e, Peq + (D - Peq) * e


def apply(params, ctx, mods) -> None:
    """Make chamber 2's charge follow the exchange with the oil, experiment by experiment.

    Parameters
    ----------
    params : dict
        ``ostwald``, ``V_oil_mm3`` (mm³), ``tau_s`` (s).
    ctx : CampaignContext
        The campaign (run order, pauses, durations).
    mods : list of ExperimentMods
        Edited in place.
    """
    eps = params["ostwald"] * params["V_oil_mm3"] / ctx.base.V2_mm3
    tau = params["tau_s"]
    P_end, D = None, ctx.plans[0].p2_MPa  # the oil starts in equilibrium with the first charge
    for m, plan in zip(mods, ctx.plans):
        if P_end is not None:  # the pause: the previous charge keeps exchanging
            _, D = _evolve(P_end, D, eps, tau, plan.pause_before_s)
        P0, D0 = plan.p2_MPa, float(D)  # recharged to the preset
        m.charge2.append(lambda t, P0=P0, D0=D0: _evolve(P0, D0, eps, tau, t)[0] / P0)
        P_end, D = (float(a) for a in _evolve(P0, D0, eps, tau, plan.duration_s))
    return None


SPEC = MechanismSpec(
    name="gas_dissolution",
    domain="fluid",
    description="chamber 2's gas dissolves in (or comes out of) the oil through the bladder after each "
                "recharge, so the charge drifts within a run depending on the previous presets",
    states=("charge", "history", "time_in_experiment", "position"),
    ranges={
        "ostwald": Range(0.07, 0.11, "1", "Ostwald coefficient of air in mineral oil"),
        "V_oil_mm3": Range(3.0e4, 6.0e4, "mm³", "oil in contact with the bladder"),
        "tau_s": Range(100.0, 600.0, "s", "permeation through the silicone wall and into the oil"),
    },
    apply=apply,
)

