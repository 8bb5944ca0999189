"""How a mechanism is described: its parameter ranges, the states it depends on, how it edits a campaign.

Every mechanism module (``mechanisms/<name>.py``, ``catalogue/<id>.py``) defines one
:class:`MechanismSpec` named ``SPEC``. Its ``apply(params, ctx, mods)`` edits the per-experiment
:class:`~.simulate.ExperimentMods` records of a campaign; ``ctx`` (:class:`CampaignContext`)
gives it the unit, the run plan and a random source of its own.
"""

from __future__ import annotations

import zlib
from collections.abc import Callable
from dataclasses import dataclass, field

import numpy as np

from .motion import ExperimentPlan, Motion
from .unit import BaseUnit

__all__ = ["STATES", "DOMAINS", "Range", "Choice", "MechanismSpec", "CampaignContext", "stable_seed"]

#: The vocabulary of states a mechanism's force may depend on (the truth names these).
STATES = (
    "position",  # piston displacement x
    "velocity",  # speed |ẋ| (magnitude)
    "direction",  # extending or retracting (sign of ẋ)
    "charge",  # the preset p2
    "valve",  # the valve angle γ
    "time_in_experiment",  # time since the start of the experiment
    "since_reversal",  # time or travel since the last reversal of the motion
    "campaign_order",  # time on the campaign clock / place in the run order
    "history",  # the settings of earlier experiments (previous preset, previous valve)
    "experiment",  # a random value per experiment (not predictable from any state)
)
DOMAINS = ("fluid", "thermal", "friction", "structural", "actuation", "sensing", "rig", "gas")


def stable_seed(*parts) -> int:
    """A seed that depends only on ``parts`` (their text), stable across runs and platforms.

    Parameters
    ----------
    *parts
        Anything with a ``str``.

    Returns
    -------
    int
        CRC32 of the parts joined by ``|``.
    """
    return zlib.crc32("|".join(str(p) for p in parts).encode())


@dataclass(frozen=True)
class Range:
    """A continuous parameter range with its unit and its physical reason."""

    lo: float  #: lower bound
    hi: float  #: upper bound
    unit: str  #: unit of the value
    why: str  #: the physical reason for the range
    scale: str = "lin"  #: "lin" (uniform) or "log" (log-uniform)

    def draw(self, rng: np.random.Generator) -> float:
        """One value from the range.

        Parameters
        ----------
        rng : numpy.random.Generator
            Source of randomness.

        Returns
        -------
        float
            A value in [lo, hi] (uniform, or log-uniform for ``scale="log"``).
        """
        if self.scale == "log":
            return float(np.exp(rng.uniform(np.log(self.lo), np.log(self.hi))))
        return float(rng.uniform(self.lo, self.hi))


@dataclass(frozen=True)
class Choice:
    """A discrete parameter with its options and its physical reason."""

    options: tuple  #: the values
    unit: str  #: unit of the value
    why: str  #: the physical reason

    def draw(self, rng: np.random.Generator):
        """One of the options, uniformly.

        Parameters
        ----------
        rng : numpy.random.Generator
            Source of randomness.

        Returns
        -------
        object
            One option.
        """
        return self.options[int(rng.integers(len(self.options)))]


@dataclass(frozen=True)
class CampaignContext:
    """What a mechanism sees of the campaign it is applied to."""

    base: BaseUnit  #: the unit
    plans: tuple[ExperimentPlan, ...]  #: the run plan, in run order
    motions: tuple[Motion, ...]  #: each experiment's crosshead motion
    seed: int  #: the campaign's seed

    def rng_for(self, name: str) -> np.random.Generator:
        """A random source private to one mechanism (the same draws whenever it is applied).

        Parameters
        ----------
        name : str
            The mechanism's name.

        Returns
        -------
        numpy.random.Generator
            Seeded by the campaign's seed and the name.
        """
        return np.random.default_rng([self.seed, stable_seed("mechanism", name)])


@dataclass(frozen=True)
class MechanismSpec:
    """One mechanism: what it is, which states its force depends on, its ranges and how it acts."""

    name: str  #: identifier
    domain: str  #: one of DOMAINS
    description: str  #: one plain-words sentence
    states: tuple[str, ...]  #: states from STATES the force depends on
    ranges: dict  #: parameter name -> Range or Choice
    apply: Callable = field(repr=False)  #: apply(params, ctx, mods) edits the mods in place
    catalogue_id: str | None = None  #: the catalogue id this mechanism is a form of, or None

    def __post_init__(self) -> None:
        bad = [s for s in self.states if s not in STATES]
        if bad:
            raise ValueError(f"mechanism {self.name!r}: unknown states {bad} (known: {STATES})")
        if self.domain not in DOMAINS:
            raise ValueError(f"mechanism {self.name!r}: unknown domain {self.domain!r}")

    def sample(self, rng: np.random.Generator) -> dict:
        """Draw one parameter set from the ranges.

        Parameters
        ----------
        rng : numpy.random.Generator
            Source of randomness.

        Returns
        -------
        dict
            Parameter name -> value.
        """
        return {k: r.draw(rng) for k, r in self.ranges.items()}

    def describe(self) -> dict:
        """Plain-JSON description (ranges with their units and reasons).

        Returns
        -------
        dict
            name, domain, description, states, catalogue_id and ranges.
        """
        rng = {}
        for k, r in self.ranges.items():
            if isinstance(r, Range):
                rng[k] = {"lo": r.lo, "hi": r.hi, "unit": r.unit, "scale": r.scale, "why": r.why}
            else:
                rng[k] = {"options": list(r.options), "unit": r.unit, "why": r.why}
        return {"name": self.name, "domain": self.domain, "description": self.description,
                "states": list(self.states), "catalogue_id": self.catalogue_id, "ranges": rng}
