"""Oil warming: the damping falls over the campaign as the oil warms (viscosity ~ exp(-b ΔT)).

Physics
-------
The throttle is laminar: its damping is proportional to the oil's viscosity, which falls
exponentially with temperature (``μ = μ0 exp(-b ΔT)``, the Reynolds/Andrade law near room
temperature). The oil warms two ways: the room warms over the day (``ΔT_room (1 - e^{-t/τ_room})``)
and every experiment dissipates its damping and friction work in the unit, which stores it
(thermal mass ``C_th``) and sheds it to the air (resistance ``R_th``)::

    C_th dT/dt = P_diss(t) - (T - T_room(t)) / R_th

``P_diss`` is the experiment's work ``2 stroke (L v + C)`` spread over its duration. The damping
of every experiment is ``L(γ) exp(-b (T(t) - T(0)))``: it falls over the campaign and dips after
the strongly damped fast runs. The spring and the friction are unchanged.

Ranges
------
- ``b_per_K`` 0.02–0.045 1/K: mineral hydraulic oils (ISO VG 22–46) halve their viscosity every
  15–20 K (b ≈ 0.035–0.045); silicone oils are flatter (b ≈ 0.02).
- ``dT_room_K`` 2–6 K and ``tau_room_h`` 1–3 h: room warming over a working day.
- ``C_th_J_per_K`` 500–900 J/K: 0.64 kg of aluminium and steel (≈ 0.55 kJ/K) plus 40–80 g of oil.
- ``R_th_K_per_W`` 2–6 K/W: natural convection from ≈ 0.025 m² (h ≈ 10 W/m²K) plus conduction
  into the clevises.
"""

from __future__ import annotations

import math

import numpy as np

from ..spec import MechanismSpec, Range
from ..unit import STROKE_MM


def oil_temperature_K(params, ctx, dt_s: float = 1.0):
    """Oil temperature rise on the campaign clock.

    Parameters
    ----------
    params : dict
        The mechanism's parameters (see the module docstring).
    ctx : CampaignContext
        The campaign.
    dt_s : float
        Integration step, s.

    Returns
    -------
    t_s, dT_K : numpy.ndarray
        Campaign clock, s, and the oil's temperature rise above its start, K.
    """
    end = ctx.plans[-1].t_start_s + ctx.plans[-1].duration_s
    t = np.arange(0.0, end + 2 * dt_s, dt_s)
    P = np.zeros_like(t)
    for plan in ctx.plans:
        L = float(ctx.base.damping_N_s_per_mm(plan.valve_deg))
        work_J = 2.0 * STROKE_MM * (L * plan.speed_mm_s + ctx.base.C_N) * 1e-3
        sel = (t >= plan.t_start_s) & (t < plan.t_start_s + plan.duration_s)
        P[sel] += work_J / plan.duration_s
    room = params["dT_room_K"] * (1.0 - np.exp(-t / (3600.0 * params["tau_room_h"])))
    C, R = params["C_th_J_per_K"], params["R_th_K_per_W"]
    decay = math.exp(-dt_s / (R * C))
    T = np.zeros_like(t)
    for k in range(1, len(t)):
        target = room[k] + R * P[k - 1]
        T[k] = target + (T[k - 1] - target) * decay
    return t, T


def apply(params, ctx, mods) -> None:
    """Scale every experiment's laminar damping by the oil's viscosity ratio along its run.

    Parameters
    ----------
    params : dict
        ``b_per_K``, ``dT_room_K``, ``tau_room_h``, ``C_th_J_per_K``, ``R_th_K_per_W``.
    ctx : CampaignContext
        The campaign.
    mods : list of ExperimentMods
        Edited in place.
    """
    tc, T = oil_temperature_K(params, ctx)
    b = params["b_per_K"]
    for m, plan in zip(mods, ctx.plans):
        m.damping.append(lambda t, s=plan.t_start_s: np.exp(-b * np.interp(s + np.asarray(t), tc, T)))


SPEC = MechanismSpec(
    name="oil_warming",
    domain="thermal",
    description="the damping falls over the campaign (and after strongly damped runs) as the oil warms "
                "and its viscosity drops exponentially",
    states=("velocity", "valve", "campaign_order", "history"),
    ranges={
        "b_per_K": Range(0.02, 0.045, "1/K", "viscosity-temperature slope of hydraulic and silicone oils"),
        "dT_room_K": Range(2.0, 6.0, "K", "room warming over a working day"),
        "tau_room_h": Range(1.0, 3.0, "h", "time constant of the room"),
        "C_th_J_per_K": Range(500.0, 900.0, "J/K", "0.64 kg of metal plus 40-80 g of oil"),
        "R_th_K_per_W": Range(2.0, 6.0, "K/W", "natural convection from 0.025 m² plus the clevises"),
    },
    apply=apply,
)
