"""Fit data: a campaign's samples as arrays ready for fitting, and the cache of what is computed from them.

:class:`FitData` is made from :class:`~vvea_design.identification.recordings.Recordings`
(the reader's table) and carries the unit's gas spring (``reference``) the gas
terms are shaped with. Everything that is a function of the campaign alone
(design columns, filter grids, ramps) is cached on it by :func:`cached`,
within a byte budget (:data:`CACHE_COLUMNS`, :data:`CACHE_BYTES`).
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from ..spring.gas_spring import GasSpring
from ..spring.paper import PAPER_FIG5
from .recordings import Recordings

__all__ = ["FitData", "REFERENCE_NOTE", "REST_REASON", "CACHE_COLUMNS", "CACHE_BYTES", "cached"]

#: What the tool assumes when no design file is given.
REFERENCE_NOTE = (
    "no --design given: the gas terms use the paper's Fig. 5 unit (vvea_design.spring.paper.PAPER_FIG5: "
    f"A1 = {PAPER_FIG5.A1_mm2:.0f} mm^2, A2 = {PAPER_FIG5.A2_mm2:.0f} mm^2, V1 = {PAPER_FIG5.V1_mm3:.3g} mm^3, "
    f"V2 = {PAPER_FIG5.V2_mm3:.3g} mm^3, travel {PAPER_FIG5.travel_mm:g} mm)"
)
#: Why :meth:`FitData.from_recordings` leaves samples out (``drop_rest``).
REST_REASON = "samples at rest (start, turning point, end): friction is set-valued there"



@dataclass(frozen=True)
class FitData:
    """Numeric arrays of a campaign, ready for fitting (one entry per sample).

    Attributes (units): ``x`` mm, ``v`` mm/s (estimated), ``p2`` MPa,
    ``valve`` degree, ``valve_idx`` index into ``valves``, ``t`` s within the
    experiment, ``tsr`` s since last reversal, ``ctime`` s of campaign time,
    ``exp`` experiment index (0..n_exp-1, run order), ``y`` measured force N,
    ``bounds`` row offsets of the experiments, ``reference`` the unit's gas
    spring (areas, V1, V2 and travel used by the gas terms; the design
    file's, or the paper's Fig. 5 unit).
    """

    x: np.ndarray
    v: np.ndarray
    p2: np.ndarray
    valve: np.ndarray
    valve_idx: np.ndarray
    valves: tuple
    t: np.ndarray
    tsr: np.ndarray
    ctime: np.ndarray
    exp: np.ndarray
    y: np.ndarray
    bounds: np.ndarray
    reference: GasSpring = PAPER_FIG5
    rows_left_out: int = 0
    speed: np.ndarray | None = None  #: nominal speed label per sample (mm/s)
    _cache: dict = field(default_factory=dict, compare=False, repr=False)
    _cache_nbytes: dict = field(default_factory=dict, compare=False, repr=False)  #: (entry, its bytes) per _cache key

    @property
    def n(self) -> int:
        return len(self.y)

    @property
    def n_exp(self) -> int:
        return len(self.bounds) - 1

    @property
    def n_per_exp(self) -> np.ndarray:
        """Samples per experiment."""
        return np.diff(self.bounds)

    @property
    def s(self) -> np.ndarray:
        """sign(ẋ)."""
        return np.sign(self.v)

    @property
    def travel_mm(self) -> float:
        """The unit's travel (from the reference design)."""
        return float(self.reference.travel_mm)

    @classmethod
    def from_recordings(cls, rec: Recordings, reference: GasSpring = PAPER_FIG5, drop_rest: bool = True) -> "FitData":
        """Arrays of a :class:`~vvea_design.identification.recordings.Recordings` campaign.

        With ``drop_rest`` the samples at rest (start, turning point, end:
        ``at_rest``) are left out, because friction is set-valued there;
        :attr:`rows_left_out` counts them. ``reference`` is the unit's gas
        spring (its chamber areas, V1, V2 and travel shape the gas terms).

        Parameters
        ----------
        rec : Recordings
            The campaign as read (mm, mm/s, N, MPa, deg, s columns).
        reference : GasSpring
            The unit the gas terms are shaped with (default: the paper's Fig. 5 unit).
        drop_rest : bool
            Leave out the samples at rest.

        Returns
        -------
        FitData
            Samples in run order, experiments renumbered 0..n-1 (``bounds`` are their row ranges).
        """
        d = rec.data[~rec.data["at_rest"].to_numpy()] if drop_rest else rec.data
        valve = d["valve_deg"].to_numpy(float)
        valves = tuple(np.unique(valve))
        exp = d["exp_index"].to_numpy(int)
        # renumber experiments 0..n-1 in run order (an experiment can lose all rows only if it never moves)
        _, exp = np.unique(exp, return_inverse=True)
        starts = np.flatnonzero(np.r_[True, exp[1:] != exp[:-1]])
        return cls(
            x=d["displacement_mm"].to_numpy(float),
            v=d["velocity_mm_s"].to_numpy(float),
            p2=d["p2_MPa"].to_numpy(float),
            valve=valve,
            valve_idx=np.searchsorted(np.array(valves), valve),
            valves=valves,
            t=d["time_s"].to_numpy(float),
            tsr=d["time_since_reversal_s"].to_numpy(float),
            ctime=d["campaign_time_s"].to_numpy(float),
            exp=exp,
            y=d["force_N"].to_numpy(float),
            bounds=np.r_[starts, len(d)],
            reference=reference,
            rows_left_out=int(len(rec.data) - len(d)) + rec.rows_left_out,
            speed=d["speed_mm_s"].to_numpy(float),
        )

    def per_exp_dt(self) -> np.ndarray:
        """Median sample spacing of each experiment (cached).

        Returns
        -------
        numpy.ndarray
            ``(n_exp,)`` spacing in s (1 s for an experiment with a single sample).
        """
        key = ("dt",)
        if key not in self._cache:
            dt = np.ones(self.n_exp)
            for e in range(self.n_exp):
                t = self.t[self.bounds[e] : self.bounds[e + 1]]
                if len(t) > 1:
                    dt[e] = float(np.median(np.diff(t)))
            self._cache[key] = dt
        return self._cache[key]


#: The column cache of a FitData holds at most this many arrays of its length, and at most
#: CACHE_BYTES in all, every entry counted (columns, filter grids, velocity gaps). 40 MB is just above
#: what the column limit gives a 135-experiment campaign (~40,000 rows: 120 columns, 39 MB), so a
#: campaign of that size caches as before, and a larger one holds no more than that (a campaign ten
#: times the size: ~12 columns; at 64 MB the cache was the largest resident item of its diagnosis).
CACHE_COLUMNS = 120
CACHE_BYTES = 40e6


def _nbytes(v) -> int:
    if isinstance(v, np.ndarray):
        return v.nbytes
    if isinstance(v, (tuple, list)):
        return sum(_nbytes(q) for q in v)
    return 0


def cached(D: FitData, key, make):
    """``D._cache[key]``, computed by ``make()`` when missing; the least recently used entries go when over :data:`CACHE_COLUMNS`.

    Parameters
    ----------
    D : FitData
        The campaign the value is a function of (its cache holds it).
    key : hashable
        The entry's key: a tuple naming what is cached and its arguments (e.g. ``("stop", r_mm)``).
    make : callable
        ``make()`` computes the value when it is not cached (arrays in their own units, e.g. mm or N).

    Returns
    -------
    object
        The cached value, in the units ``make`` gives (do not modify it in place).
    """
    c = D._cache
    if key in c:
        c[key] = c.pop(key)  # most recently used last
        return c[key]
    val = make()
    c[key] = val
    limit = min(CACHE_COLUMNS * max(D.n, 1) * 8, CACHE_BYTES)
    total = sum(_entry_nbytes(D, k, v) for k, v in c.items())
    while total > limit:
        k0 = next(iter(c))
        if k0 == key:
            break
        total -= _entry_nbytes(D, k0, c.pop(k0))
        D._cache_nbytes.pop(k0, None)  # (it holds the entry: let the evicted arrays go)
    return val


def _entry_nbytes(D: FitData, key, val) -> int:
    """``_nbytes(val)``, remembered per cache entry (walking every cached array on each miss was ~1 % of a
    diagnosis). The size is tied to the object it was measured on, so an entry written into ``_cache``
    directly, or a size left by a copy of ``D`` that shares the dict, is measured afresh."""
    sizes = D._cache_nbytes
    got = sizes.get(key)
    if got is None or got[0] is not val:
        got = sizes[key] = (val, _nbytes(val))
    return got[1]
