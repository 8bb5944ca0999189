"""Charge-dependent load-cell zero: the charging hose pulls on the load train.

Physics
-------
The unit is charged through a hose from the bench's charging panel. Between charging and the run
only the isolation valve at the unit is closed, so the hose stays at the preset pressure. The hose
is led along the machine's load train (clamped to the upper clevis); a pressurised hose loop tries
to straighten (Bourdon effect) and its fittings carry the pressure's end force, so the load cell
reads an extra force proportional to the hose pressure: ``f_meas = f + s k p2``. It does not depend
on the motion, the valve or the campaign time — only on the charge.

Ranges
------
- ``k_N_per_MPa`` 6–20 N/MPa: a 4 mm bore hose has an end-force area of 12.6 mm² (12.6 N/MPa);
  a loop's straightening force adds or subtracts a similar amount depending on how it is led.
- ``sign`` ±1: whether the hose pulls in tension or pushes depends on its routing.
"""

from __future__ import annotations

from ..spec import Choice, MechanismSpec, Range


def apply(params, ctx, mods) -> None:
    """Add the hose force to every experiment's load-cell reading.

    Parameters
    ----------
    params : dict
        ``k_N_per_MPa`` (N/MPa) and ``sign`` (±1).
    ctx : CampaignContext
        The campaign (its plan gives each experiment's preset).
    mods : list of ExperimentMods
        Edited in place.
    """
    for m, plan in zip(mods, ctx.plans):
        m.sensor_offset_N += params["sign"] * params["k_N_per_MPa"] * plan.p2_MPa


SPEC = MechanismSpec(
    name="charge_zero_offset",
    domain="sensing",
    description="the load cell's zero shifts in proportion to the charge (pressurised charging hose "
                "on the load train), whatever the motion",
    states=("charge",),
    ranges={
        "k_N_per_MPa": Range(6.0, 20.0, "N/MPa", "end-force area of a 4 mm hose bore (12.6 mm²) ± loop force"),
        "sign": Choice((-1.0, 1.0), "1", "routing of the hose decides pull or push"),
    },
    apply=apply,
)
