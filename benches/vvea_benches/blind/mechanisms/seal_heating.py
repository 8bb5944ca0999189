"""Seal heating: the seal lip warms while sliding fast and its friction drops within the run.

Physics
-------
The friction power ``C |ẋ|`` heats the seal's contact band, a small thermal mass behind a poor
conductor (the elastomer). Its temperature rise follows ``τ dΔT/dt = R C |ẋ| - ΔT`` (steady rise
``R C |ẋ|``, time constant ``τ``); elastomer friction falls as the lip warms, ``C (1 - κ ΔT)``.
Between experiments (pauses of a minute or more) the lip cools back. Slow runs stay cold; in the
fast runs the friction sinks along the run, in both directions.

Ranges
------
- ``R_K_per_W`` 20–50 K/W: a contact band of ≈ 1 mm × 94 mm behind a 2 mm elastomer lip.
- ``tau_s`` 3–15 s: the lip's small heat capacity (≈ 0.3 J/K) times ``R``.
- ``kappa_per_K`` 0.003–0.008 1/K: elastomer friction falls 0.3–0.8 % per kelvin near room
  temperature.
"""

from __future__ import annotations

import numpy as np

from ..spec import MechanismSpec, Range

MIN_FACTOR = 0.4


def lip_temperature_K(t, v, C_N, R, tau):
    """Temperature rise of the seal lip along one run, K.

    Parameters
    ----------
    t, v : numpy.ndarray
        Time (s) and piston velocity (mm/s) per sample.
    C_N : float
        Coulomb friction, N.
    R : float
        Thermal resistance, K/W.
    tau : float
        Time constant, s.

    Returns
    -------
    numpy.ndarray
        ``ΔT`` per sample, K (0 at the start).
    """
    dT = np.zeros_like(t)
    P = C_N * np.abs(v) * 1e-3  # W
    for k in range(1, len(t)):
        target = R * 0.5 * (P[k] + P[k - 1])
        dT[k] = target + (dT[k - 1] - target) * np.exp(-(t[k] - t[k - 1]) / tau)
    return dT


def apply(params, ctx, mods) -> None:
    """Scale every experiment's Coulomb friction by the lip's warming.

    Parameters
    ----------
    params : dict
        ``R_K_per_W``, ``tau_s``, ``kappa_per_K``.
    ctx : CampaignContext
        The campaign.
    mods : list of ExperimentMods
        Edited in place.
    """
    def factor(s):
        dT = lip_temperature_K(s.t, s.v, s.base.C_N, params["R_K_per_W"], params["tau_s"])
        return np.maximum(MIN_FACTOR, 1.0 - params["kappa_per_K"] * dT)

    for m in mods:
        m.friction_factors.append(factor)


SPEC = MechanismSpec(
    name="seal_heating",
    domain="friction",
    description="the seal lip warms while sliding fast and its friction sinks along the run; it cools "
                "between runs",
    states=("velocity", "time_in_experiment", "direction"),
    ranges={
        "R_K_per_W": Range(20.0, 50.0, "K/W", "contact band behind a 2 mm elastomer lip"),
        "tau_s": Range(3.0, 15.0, "s", "small heat capacity of the lip times R"),
        "kappa_per_K": Range(0.003, 0.008, "1/K", "elastomer friction's temperature slope"),
    },
    apply=apply,
)
