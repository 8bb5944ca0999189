"""Crosshead motion of one tension test and the run plan of a campaign.

One experiment moves the crosshead 0 → 40 mm → 0 at a constant nominal speed with a short
constant acceleration (about 40 mm/s², a tensile tester's default ramp) at the start, before and
after the reversal and at the end: two trapezoidal velocity ramps. The campaign runs the paper's
135 combinations (3 presets × 9 valves × 5 speeds) in shuffled order with a set-up pause before
each experiment (recharging, setting the valve: 40–150 s), so that every experiment has a start
time on the campaign clock, which the campaign-time mechanisms use.
"""

from __future__ import annotations

import itertools
from dataclasses import asdict, dataclass

import numpy as np

from .unit import PRESETS_MPA, SPEEDS_MM_S, STROKE_MM, VALVES_DEG

__all__ = ["Motion", "ExperimentPlan", "plan_campaign"]


@dataclass(frozen=True)
class Motion:
    """Trapezoidal out-and-back motion of the crosshead."""

    speed_mm_s: float  #: nominal speed, mm/s
    accel_mm_s2: float = 40.0  #: acceleration at start, reversal and end, mm/s²
    stroke_mm: float = STROKE_MM  #: turning point, mm
    n_per_ramp: int = 200  #: sample intervals per ramp

    def __post_init__(self) -> None:
        if self.speed_mm_s <= 0 or self.accel_mm_s2 <= 0:
            raise ValueError(f"Motion needs speed and acceleration > 0, got {self.speed_mm_s}, {self.accel_mm_s2}")
        if self.speed_mm_s**2 / self.accel_mm_s2 >= self.stroke_mm:
            raise ValueError(f"Motion: the speed {self.speed_mm_s} mm/s is not reached within the stroke")
        if self.n_per_ramp < 5:
            raise ValueError(f"Motion.n_per_ramp must be >= 5, got {self.n_per_ramp}")

    @property
    def ramp_s(self) -> float:
        """Duration of one ramp (0 → stroke), s."""
        return self.stroke_mm / self.speed_mm_s + self.speed_mm_s / self.accel_mm_s2

    @property
    def duration_s(self) -> float:
        """Duration of the whole cycle, s."""
        return 2.0 * self.ramp_s

    @property
    def t_s(self) -> np.ndarray:
        """Sample times, s: ``2 n_per_ramp + 1`` equally spaced points, the turning point among them."""
        return np.linspace(0.0, self.duration_s, 2 * self.n_per_ramp + 1)

    @property
    def turn_index(self) -> int:
        """Index of the sample at the turning point."""
        return self.n_per_ramp

    def _ramp(self, tau):
        v, a, T = self.speed_mm_s, self.accel_mm_s2, self.ramp_s
        ta = v / a
        tau = np.clip(tau, 0.0, T)
        s = np.where(tau < ta, 0.5 * a * tau**2, v * tau - 0.5 * v * ta)
        s = np.where(tau > T - ta, self.stroke_mm - 0.5 * a * (T - tau) ** 2, s)
        ds = np.where(tau < ta, a * tau, v)
        ds = np.where(tau > T - ta, a * (T - tau), ds)
        return s, ds

    def position_mm(self, t) -> np.ndarray:
        """Crosshead position at time ``t``, mm.

        Parameters
        ----------
        t : array_like
            Time since the start of the experiment, s.

        Returns
        -------
        numpy.ndarray
            Position, mm (0 at start and end, the stroke at the reversal).
        """
        t = np.asarray(t, dtype=float)
        out_s, _ = self._ramp(t)
        back_s, _ = self._ramp(t - self.ramp_s)
        return np.where(t <= self.ramp_s, out_s, self.stroke_mm - back_s)

    def velocity_mm_s(self, t) -> np.ndarray:
        """Crosshead velocity at time ``t``, mm/s (> 0 while extending).

        Parameters
        ----------
        t : array_like
            Time since the start of the experiment, s.

        Returns
        -------
        numpy.ndarray
            Velocity, mm/s.
        """
        t = np.asarray(t, dtype=float)
        _, out_v = self._ramp(t)
        _, back_v = self._ramp(t - self.ramp_s)
        return np.where(t <= self.ramp_s, out_v, -back_v)


@dataclass(frozen=True)
class ExperimentPlan:
    """One experiment of a campaign: its settings and its place on the campaign clock."""

    index: int  #: position in the run order (0-based)
    name: str  #: experiment identifier written to the CSV
    p2_MPa: float  #: chamber-2 preset, MPa
    valve_deg: float  #: commanded valve angle, degree
    speed_mm_s: float  #: nominal crosshead speed, mm/s
    pause_before_s: float  #: set-up pause before the start, s
    t_start_s: float  #: start time on the campaign clock, s
    duration_s: float  #: duration of the motion, s

    def to_dict(self) -> dict:
        """Plain-JSON form.

        Returns
        -------
        dict
            The fields.
        """
        return asdict(self)


def plan_campaign(rng: np.random.Generator, n_per_ramp: int = 200, accel_mm_s2: float = 40.0,
                  pause_s: tuple[float, float] = (40.0, 150.0)) -> list[ExperimentPlan]:
    """The paper's 135 experiments in shuffled run order, with set-up pauses.

    Parameters
    ----------
    rng : numpy.random.Generator
        Source of the run order and the pauses.
    n_per_ramp : int
        Sample intervals per ramp.
    accel_mm_s2 : float
        Acceleration at start, reversal and end, mm/s².
    pause_s : tuple of float
        Range of the set-up pause before each experiment, s (uniform).

    Returns
    -------
    list of ExperimentPlan
        In run order.
    """
    combos = list(itertools.product(PRESETS_MPA, VALVES_DEG, SPEEDS_MM_S))
    order = rng.permutation(len(combos))
    plans, clock = [], 0.0
    for i, k in enumerate(order):
        p2, valve, speed = combos[int(k)]
        pause = float(rng.uniform(*pause_s))
        clock += pause
        dur = Motion(speed, accel_mm_s2, STROKE_MM, n_per_ramp).duration_s
        plans.append(ExperimentPlan(i, f"E{i:03d}", p2, valve, speed, pause, clock, dur))
        clock += dur
    return plans
