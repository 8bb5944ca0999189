"""``relief_valve``: a preloaded spring-ball valve bypassing the throttle.

Physics
-------
A ball on a seat of diameter ``d`` is held shut by a spring until the throttle's pressure drop
reaches the cracking pressure ``Δp_c`` (force ``F_c = A2 Δp_c`` on the piston). Above it the ball
lifts in proportion to the excess pressure (spring rate ``k_s``), opens a curtain area ``π d lift``
and passes ``Cd π d lift √(2 Δp/ρ)``. The throttle and the valve share the flow ``A2 ẋ``; the
force is the pressure drop that makes them pass it together (solved per sample). The force is
capped near ``F_c`` and rises only slowly above it; a pair of valves acts in both directions.

Ranges
------
- ``F_crack_N`` 1500–3000 N: set above the damping forces of the open and middle valves (≤ 1 kN)
  and below the closed valve's at a few mm/s, to protect the unit (paper section 2.1).
- ``d_seat_mm`` 1.5–3 mm: seat of a cartridge ball valve in this size of unit.
- ``k_spring_N_per_mm`` 10–60 N/mm: its spring.
"""

from __future__ import annotations

from ..spec import MechanismSpec, Range

CD_BALL = 0.65
LIFT_MAX_MM = 1.0


def apply(params, ctx, mods) -> None:
    """Fit every experiment's throttle with the relief valve.

    Parameters
    ----------
    params : dict
        ``F_crack_N`` (N), ``d_seat_mm`` (mm), ``k_spring_N_per_mm`` (N/mm).
    ctx : CampaignContext
        The campaign.
    mods : list of ExperimentMods
        Edited in place.
    """
    r = dict(params, Cd=CD_BALL, lift_max_mm=LIFT_MAX_MM, bidirectional=True)
    for m in mods:
        m.claim("relief", SPEC.name)
        m.relief = dict(r)


SPEC = MechanismSpec(
    name="relief_valve",
    domain="fluid",
    description="a spring-ball valve bypasses the throttle above its cracking pressure: the damping force "
                "is capped",
    states=("velocity", "direction", "valve"),
    ranges={
        "F_crack_N": Range(1500.0, 3000.0, "N", "above the middle valves' damping, below the closed valve's"),
        "d_seat_mm": Range(1.5, 3.0, "mm", "seat of a cartridge ball valve"),
        "k_spring_N_per_mm": Range(10.0, 60.0, "N/mm", "its spring"),
    },
    apply=apply,
    catalogue_id="relief_valve",
)
