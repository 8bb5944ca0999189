"""``quadratic_damping``: a sharp-edged orifice in series with the laminar throttle channel.

Physics
-------
The valve's window is a sharp-edged orifice of area ``A_o(γ)``; the flow ``Q = A2 ẋ`` through it
loses ``ρ Q²/(2 Cd² A_o²)`` (Bernoulli with a discharge coefficient) on top of the laminar channel's
loss, so the throttle force is ``L(γ) ẋ + K(γ) ẋ|ẋ|`` with ``K = ρ A2³/(2 Cd² A_o²)``. The window
closes linearly from fully open at 95° to shut at ``γ_c``; a bypass clearance ``A_b`` stays open::

    A_o(γ) = A_b + A_w clip((γ_c - γ)/(γ_c - 95°), 0, 1)

The quadratic part matters most where the window is small (closed valves) and at the open valves,
where the laminar part is tiny.

Ranges
------
- ``A_w_mm2`` 1.5–4 mm²: the rectangular window of a rotary valve in a 30 mm unit.
- ``A_b_mm2`` 0.15–0.4 mm²: radial clearance of the valve's cylinder.
- ``gamma_c_deg`` 111–114°: where the window shuts (Table 3's damping rises steeply there).
- ``Cd`` 0.6–0.75: sharp-edged orifice.
"""

from __future__ import annotations

import numpy as np

from ..simulate import RHO_OIL_KG_MM3
from ..spec import MechanismSpec, Range

GAMMA_FULL_DEG = 95.0


def orifice_K_N_s2_per_mm2(valve_deg, params, A2_mm2):
    """Orifice coefficient at a valve angle, N s²/mm².

    Parameters
    ----------
    valve_deg : float
        Actual valve angle, degree.
    params : dict
        ``A_w_mm2``, ``A_b_mm2``, ``gamma_c_deg``, ``Cd``.
    A2_mm2 : float
        Working piston area, mm².

    Returns
    -------
    float
        ``K = ρ A2³ / (2 Cd² A_o²)`` (kg/mm → N s²/mm² with the factor 1e-3).
    """
    open_share = np.clip((params["gamma_c_deg"] - valve_deg) / (params["gamma_c_deg"] - GAMMA_FULL_DEG), 0.0, 1.0)
    A_o = params["A_b_mm2"] + params["A_w_mm2"] * open_share
    return float(1e-3 * RHO_OIL_KG_MM3 * A2_mm2**3 / (2.0 * params["Cd"] ** 2 * A_o**2))


def apply(params, ctx, mods) -> None:
    """Give every experiment the orifice term of its valve angle.

    Parameters
    ----------
    params : dict
        ``A_w_mm2``, ``A_b_mm2``, ``gamma_c_deg``, ``Cd``.
    ctx : CampaignContext
        The campaign.
    mods : list of ExperimentMods
        Edited in place (uses each experiment's actual valve angle).
    """
    for m in mods:
        m.claim("turbulent_K_N_s2_mm2", SPEC.name)
        m.turbulent_K_N_s2_mm2 = orifice_K_N_s2_per_mm2(m.valve_deg, params, ctx.base.A2_mm2)


SPEC = MechanismSpec(
    name="quadratic_damping",
    domain="fluid",
    description="the valve window is a sharp-edged orifice: a throttle force growing with velocity "
                "squared on top of the laminar one",
    states=("velocity", "direction", "valve"),
    ranges={
        "A_w_mm2": Range(1.5, 4.0, "mm²", "rectangular window of a rotary valve"),
        "A_b_mm2": Range(0.15, 0.4, "mm²", "radial clearance of the valve cylinder"),
        "gamma_c_deg": Range(111.0, 114.0, "deg", "the window shuts where Table 3 rises steeply"),
        "Cd": Range(0.6, 0.75, "1", "sharp-edged orifice"),
    },
    apply=apply,
    catalogue_id="quadratic_damping",
)
