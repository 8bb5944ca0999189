"""``stiction``: Stribeck friction — breakaway above the Coulomb level, decaying with sliding speed.

Physics
-------
At rest the seal's lip squeezes the lubricant film out and sticks; at low sliding speed it runs in
mixed lubrication, and only as the speed rises does a full film carry it. The friction magnitude
follows the Stribeck curve ``C + (F_s - C) exp(-(|ẋ|/v_s)^δ)``: breakaway ``F_s`` at start and at
the reversal, the Coulomb level ``C`` once sliding faster than ``v_s``.

Ranges
------
- ``Fs_over_C`` 1.3–1.9: breakaway of elastomer seals 30–90 % above their sliding friction.
- ``v_s_mm_s`` 0.05–0.4 mm/s: Stribeck velocity of lubricated elastomer seals.
- ``delta`` 0.8–2: shape exponent (1 exponential, 2 Gaussian).
"""

from __future__ import annotations

from ..spec import MechanismSpec, Range


def apply(params, ctx, mods) -> None:
    """Give every experiment the Stribeck curve.

    Parameters
    ----------
    params : dict
        ``Fs_over_C``, ``v_s_mm_s`` (mm/s), ``delta``.
    ctx : CampaignContext
        The campaign.
    mods : list of ExperimentMods
        Edited in place.
    """
    for m in mods:
        m.claim("stribeck", SPEC.name)
        m.stribeck = dict(params)


SPEC = MechanismSpec(
    name="stiction",
    domain="friction",
    description="breakaway friction above the Coulomb level at start and reversal, decaying with sliding "
                "speed (Stribeck)",
    states=("velocity", "direction", "since_reversal"),
    ranges={
        "Fs_over_C": Range(1.3, 1.9, "1", "breakaway of elastomer seals"),
        "v_s_mm_s": Range(0.05, 0.4, "mm/s", "Stribeck velocity of lubricated seals"),
        "delta": Range(0.8, 2.0, "1", "shape exponent"),
    },
    apply=apply,
    catalogue_id="stiction",
)
