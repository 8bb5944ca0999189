"""Every mechanism of the blind bench, and the split into a DEV half and a BLIND half.

The method's developer sees the DEV half's campaigns and scores only; the BLIND half judges the
method on mechanisms it was never tuned on (``docs/diagnosis-protocol.md``). Catalogue and null
campaigns are split by seed: even seeds DEV, odd seeds BLIND.
"""

from __future__ import annotations

from .catalogue import (gas_nonlinearity, leakage, pressure_friction, quadratic_damping, relief_valve,
                        stiction, thermal)
from .mechanisms import (bladder_contact, bladder_membrane, cavitation, charge_zero_offset, entrained_air,
                         frame_compliance, gas_dissolution, misalignment_friction, oil_warming, room_warming,
                         seal_heating, start_transient, sticky_band, valve_backlash, zero_position_scatter)
from .spec import MechanismSpec

__all__ = ["MECHANISMS", "CATALOGUE", "ALL", "DEV", "BLIND", "PAIRS", "half_of_mechanism", "half_of_seed",
           "lookup"]

#: Mechanisms outside the catalogue, by name.
MECHANISMS: dict[str, MechanismSpec] = {m.SPEC.name: m.SPEC for m in (
    charge_zero_offset, room_warming, oil_warming, sticky_band, bladder_membrane, start_transient,
    entrained_air, zero_position_scatter, seal_heating, misalignment_friction, bladder_contact,
    frame_compliance, gas_dissolution, cavitation, valve_backlash)}
#: The bench's own forms of the catalogue effects, by catalogue id.
CATALOGUE: dict[str, MechanismSpec] = {m.SPEC.name: m.SPEC for m in (
    gas_nonlinearity, thermal, quadratic_damping, relief_valve, stiction, pressure_friction, leakage)}
ALL: dict[str, MechanismSpec] = {**MECHANISMS, **CATALOGUE}

#: The developer's half (names may be shown to the method's developer).
DEV = ("charge_zero_offset", "room_warming", "oil_warming", "sticky_band", "bladder_membrane",
       "start_transient", "entrained_air")
#: The judge's half (never shown to the method's developer).
BLIND = ("zero_position_scatter", "seal_heating", "misalignment_friction", "bladder_contact",
         "frame_compliance", "gas_dissolution", "cavitation", "valve_backlash")
#: Campaigns with two mechanisms at once, per half.
PAIRS = {
    "dev": (("charge_zero_offset", "oil_warming"), ("sticky_band", "entrained_air")),
    "blind": (("bladder_contact", "valve_backlash"), ("seal_heating", "gas_dissolution")),
}

if set(DEV) & set(BLIND) or set(DEV) | set(BLIND) != set(MECHANISMS):
    raise RuntimeError("DEV and BLIND must split MECHANISMS exactly")


def half_of_mechanism(name: str) -> str:
    """The half a mechanism outside the catalogue belongs to.

    Parameters
    ----------
    name : str
        Mechanism name.

    Returns
    -------
    str
        "dev" or "blind".

    Raises
    ------
    KeyError
        If the name is not a mechanism outside the catalogue.
    """
    if name in DEV:
        return "dev"
    if name in BLIND:
        return "blind"
    raise KeyError(f"{name!r} is not a mechanism outside the catalogue (known: {sorted(MECHANISMS)})")


def half_of_seed(seed: int) -> str:
    """The half a catalogue or null campaign of this seed belongs to.

    Parameters
    ----------
    seed : int
        Campaign seed.

    Returns
    -------
    str
        "dev" for even seeds, "blind" for odd ones.
    """
    return "dev" if seed % 2 == 0 else "blind"


def lookup(name: str) -> MechanismSpec:
    """A mechanism or catalogue form by name.

    Parameters
    ----------
    name : str
        Mechanism name or catalogue id.

    Returns
    -------
    MechanismSpec
        Its spec.

    Raises
    ------
    KeyError
        If the name is unknown.
    """
    try:
        return ALL[name]
    except KeyError:
        raise KeyError(f"unknown mechanism {name!r} (known: {sorted(ALL)})") from None
