"""Load-train seating at each start: a short force pulse in the first few tenths of a second.

Physics
-------
Between experiments the unit hangs unloaded in the tester; its rod eyes sit on the clevis pins
with some play and the wedge grips relax. When the crosshead starts, the joints slip and seat under
the first load: friction in the pin joints and the grip wedges adds a short tension pulse that
rises and decays within a few tenths of a second (an alpha-function ``A (t/τ) e^{1 - t/τ}``, peak
``A`` at ``t = τ``). Only the time since the start matters — not the speed, the charge or the valve.

Ranges
------
- ``A_N`` 25–80 N: pin friction (μ ≈ 0.15) times the first few hundred newtons of load.
- ``tau_s`` 0.04–0.12 s: a seating slip of a few hundredths of a millimetre.
"""

from __future__ import annotations

import numpy as np

from ..spec import MechanismSpec, Range


def pulse(t, A, tau):
    """The seating pulse, N.

    Parameters
    ----------
    t : array_like
        Time since the start, s.
    A : float
        Peak force, N.
    tau : float
        Time of the peak, s.

    Returns
    -------
    numpy.ndarray
        ``A (t/τ) exp(1 - t/τ)``.
    """
    r = np.asarray(t, dtype=float) / tau
    return A * r * np.exp(1.0 - r)


def apply(params, ctx, mods) -> None:
    """Add the seating pulse to every experiment.

    Parameters
    ----------
    params : dict
        ``A_N`` (N) and ``tau_s`` (s).
    ctx : CampaignContext
        The campaign.
    mods : list of ExperimentMods
        Edited in place.
    """
    for m in mods:
        m.force_terms.append(lambda s: pulse(s.t, params["A_N"], params["tau_s"]))


SPEC = MechanismSpec(
    name="start_transient",
    domain="rig",
    description="the load train seats at each start: a tension pulse within the first ~0.3 s of every "
                "experiment",
    states=("time_in_experiment",),
    ranges={
        "A_N": Range(25.0, 80.0, "N", "pin friction times the first few hundred newtons"),
        "tau_s": Range(0.04, 0.12, "s", "a seating slip of a few hundredths of a millimetre"),
    },
    apply=apply,
)
