"""Physical plausibility: the ranges a real unit and a real bench can have, and the unit a number is likely in.

A number can be valid (finite, positive) and still impossible: a 1e9 MPa charge, a 1e-300 mm travel, a valve
at 1,100°, a recording whose displacement spans 0.04 "mm" on a 40 mm unit. This module holds, in one table
each, what the toolkit accepts as real:

* :data:`LIMITS` — the range of every physical quantity and of every size a user can ask for (a map's grid,
  a mesh, a study's cases, worker processes). Each :class:`Limit` knows its unit and *why* its ends are
  where they are, and says so in the message (:meth:`Limit.check`). The requirements, the design file, the
  recordings and the command-line numbers all check against the same entries, and so do the library's
  public functions: a user calling the library gets the checks the ``vvea`` command makes.
* :data:`UNITS` — the units each quantity is commonly recorded in, with their factor to the toolkit's unit
  (N, mm, MPa, s, degree, mm/s). :func:`likely_unit` names the unit a number whose scale is off by a factor
  is probably in, so a message can say "force_N looks like kN" and name the override.

The checks that need a design (charge against the walls' capacity, travel against the housing) or the
recordings (force scale against g·p2·x) are made by their input kind's loader
(:mod:`vvea_design.spring.requirements`, :mod:`vvea_design.spring.design_file`,
:mod:`vvea_design.identification.units`) with these ranges; ``docs/reliability.md`` lists them all.
This module imports nothing of the toolkit but :mod:`vvea_design.messages` (floor 0).
"""

from __future__ import annotations

import math
import numbers
from dataclasses import dataclass

from .messages import show

__all__ = ["Limit", "LIMITS", "UNITS", "TOOL_UNIT", "UNIT_NAMES", "unit_factor", "unit_label", "likely_unit",
           "check_limit", "check_count", "PlausibilityError"]


class PlausibilityError(ValueError):
    """A number outside what a real unit, bench or computer can have (names it, its range and why)."""


@dataclass(frozen=True)
class Limit:
    """The range a quantity can have, in its unit, and why."""

    low: float  #: smallest accepted value (inclusive unless ``open_low``)
    high: float  #: largest accepted value (inclusive)
    unit: str  #: the unit of ``low``/``high`` ("" for a count or a fraction)
    why: str  #: what the ends mean physically (or in memory and time), for the message
    integer: bool = False  #: a whole number (a count)
    open_low: bool = False  #: ``low`` itself is not accepted (a fraction > 0)

    def problem(self, value) -> str | None:
        """What is wrong with ``value`` (None when it is in range).

        Parameters
        ----------
        value : Any
            The number (Python or numpy), in :attr:`unit`.

        Returns
        -------
        str or None
            ``"must be a number"``, ``"must be a whole number >= 2 and <= 401 points per axis"`` (for 2.5) or
            ``"must be >= 0.01 and <= 20 MPa"`` (the range it leaves); None when ``value`` is a real number
            in range.
        """
        if isinstance(value, bool) or not isinstance(value, numbers.Real):
            return "must be a number"
        v = float(value)
        if not math.isfinite(v) or v < self.low or (self.open_low and v == self.low) or v > self.high:
            return f"must be {self.range_text()}"
        if self.integer and v != int(v):
            return f"must be a whole number {self.range_text()}"
        return None

    def range_text(self) -> str:
        """``">= 0.01 and <= 20 MPa"``: the accepted range with its unit.

        Returns
        -------
        str
            The range as a message shows it.
        """
        u = f" {self.unit}" if self.unit else ""
        lo = f"> {show(self.low)}" if self.open_low else f">= {show(self.low)}"
        return f"{lo} and <= {show(self.high)}{u}"

    def check(self, value, label: str, error: type[Exception] = PlausibilityError, hint: str = ""):
        """Return ``value`` when it is in range, else raise ``error`` naming ``label``, the range and why.

        Parameters
        ----------
        value : Any
            The number, in :attr:`unit`.
        label : str
            What the user called it (``"--n"``, ``"parameters.p2_MPa"``, ``"max_charge_MPa"``).
        error : type of Exception
            The error class raised (the caller's input kind).
        hint : str
            Appended to the message (a likely cause, e.g. "did you mean a fraction?").

        Returns
        -------
        Any
            ``value`` unchanged.

        Raises
        ------
        error
            ``value`` is not a finite real number in range: ``"--n must be >= 2 and <= 401 points per axis,
            got 100000 (a map of n x n designs: ...)"``.
        """
        why = self.problem(value)
        if why is not None:
            real = isinstance(value, numbers.Real) and not isinstance(value, bool)
            unit = f" {self.unit}" if self.unit and real and self.unit.split()[0] in ("MPa", "mm", "m", "g", "N/mm",
                                                                                      "deg", "N", "kg", "s", "mm/s") else ""
            raise error(f"{label} {why}, got {show(value)}{unit}" + (f" ({self.why})" if real else "")
                        + (f"; {hint}" if hint else ""))
        return value


#: Every range the toolkit accepts (key -> :class:`Limit`); ``docs/reliability.md`` has the table.
LIMITS: dict[str, Limit] = {
    # the unit -----------------------------------------------------------------------------------------
    "charge_MPa": Limit(0.01, 20.0, "MPa", "a pneumatic unit is charged between 0.1 bar and 200 bar (absolute); "
                        "below, nothing is left to make a force, above, no gas spring of this kind is built"),
    "travel_mm": Limit(0.5, 1000.0, "mm", "a spring-damper unit strokes between half a millimetre and a metre"),
    "diameter_mm": Limit(2.0, 1000.0, "mm", "the unit's diameters lie between 2 mm and a metre"),
    "length_mm": Limit(2.0, 5000.0, "mm", "the unit's housing is between 2 mm and 5 m long"),
    "wall_safety_factor": Limit(1.0, 20.0, "", "below 1 the walls are designed to yield; above 20 no wall this "
                                "thin can be sized"),
    "mass_g": Limit(1e-3, 1e6, "g", "a unit weighs between a milligram and a tonne"),
    "strain_fraction": Limit(0.0, 10.0, "", "a strain is a fraction (0.25 = 25 %); no silicone stretches "
                             "beyond 1000 %", open_low=True),
    "linearity_fraction": Limit(0.0, 1.0, "", "a linearity error is a fraction of the force span "
                                "(0.015 = 1.5 %)", open_low=True),
    # the bench ----------------------------------------------------------------------------------------
    "valve_deg": Limit(0.0, 360.0, "deg", "a throttle valve turns at most a full turn"),
    "bench_speed_mm_s": Limit(1e-3, 5000.0, "mm/s", "a test machine moves between 1 µm/s and 5 m/s"),
    "sample_interval_s": Limit(1e-6, 60.0, "s", "a bench samples between every microsecond and every minute"),
    "experiment_duration_s": Limit(1e-3, 86400.0, "s", "one loading-unloading cycle lasts less than a day"),
    # the actuator -------------------------------------------------------------------------------------
    "pulley_radius_m": Limit(1e-3, 1.0, "m", "a tendon pulley has a radius between 1 mm and 1 m"),
    "torque_step_Nm": Limit(0.0, 100.0, "N m", "the motor delivers at most 100 N m (paper eq. 13); a larger "
                            "step cannot be tracked", open_low=True),
    "link_inertia_kgm2": Limit(1e-6, 1e6, "kg m²", "a robot link's inertia lies between 1e-6 and 1e6 kg m²"),
    # sizes a user can ask for (memory and time) -------------------------------------------------------
    "map_points": Limit(2, 401, "points per axis", "a map of n x n designs: 401 x 401 = 160,801 evaluations is "
                        "already minutes and hundreds of MB", integer=True),
    "bladder_elements": Limit(4, 4000, "elements", "the bladder FE converges long before 4000 elements along "
                              "the meridian (96 is the default)", integer=True),
    "mesh_intervals": Limit(4, 4096, "intervals", "a collocation mesh beyond 4096 intervals takes hours and "
                            "gigabytes per solve (64 is the default)", integer=True),
    "grid_cases": Limit(1, 2500, "cases", "each case is several optimal-control solves: 2500 cases is already "
                        "days of computing (the paper's grid has 150)", integer=True),
    "workers": Limit(1, 1024, "processes", "worker processes: at least 1, at most 1024", integer=True),
    "pareto_points": Limit(1, 500, "points", "each point is one full optimisation", integer=True),
    "seed": Limit(0, 2**32 - 1, "", "the search's random generator takes seeds 0 .. 2**32 - 1", integer=True),
}

#: The toolkit's unit of each quantity.
TOOL_UNIT: dict[str, str] = {"length": "mm", "force": "N", "pressure": "MPa", "time": "s", "angle": "deg",
                             "speed": "mm/s"}

#: Units each quantity is commonly recorded in: name -> factor to the toolkit's unit (value in tool unit =
#: value in that unit x factor).
UNITS: dict[str, dict[str, float]] = {
    "length": {"mm": 1.0, "m": 1e3, "cm": 10.0, "um": 1e-3, "µm": 1e-3, "in": 25.4},
    "force": {"N": 1.0, "kN": 1e3, "daN": 10.0, "mN": 1e-3, "lbf": 4.4482216152605},
    "pressure": {"MPa": 1.0, "bar": 0.1, "kPa": 1e-3, "Pa": 1e-6, "psi": 6.894757293168361e-3, "GPa": 1e3},
    "time": {"s": 1.0, "ms": 1e-3, "us": 1e-6, "µs": 1e-6, "min": 60.0},
    "angle": {"deg": 1.0, "rad": 180.0 / math.pi},
    "speed": {"mm/s": 1.0, "m/s": 1e3, "cm/s": 10.0, "mm/min": 1.0 / 60.0, "um/s": 1e-3, "µm/s": 1e-3},
}


#: How a unit is named in a message ("kN (kilonewtons)").
UNIT_NAMES: dict[str, str] = {
    "m": "metres", "cm": "centimetres", "um": "micrometres", "µm": "micrometres", "in": "inches",
    "kN": "kilonewtons", "daN": "decanewtons", "mN": "millinewtons", "lbf": "pound-force",
    "bar": "bar", "kPa": "kilopascals", "Pa": "pascals", "psi": "pounds per square inch", "GPa": "gigapascals",
    "ms": "milliseconds", "us": "microseconds", "µs": "microseconds", "min": "minutes",
    "rad": "radians", "m/s": "metres per second", "cm/s": "centimetres per second", "mm/min": "millimetres per minute",
    "um/s": "micrometres per second", "µm/s": "micrometres per second",
}


def unit_label(unit: str) -> str:
    """``"kN (kilonewtons)"``: a unit with its name, for messages.

    Parameters
    ----------
    unit : str
        A unit of :data:`UNITS`.

    Returns
    -------
    str
        The unit, and its name in brackets when it has one in :data:`UNIT_NAMES`.
    """
    name = UNIT_NAMES.get(unit)
    return f"{unit} ({name})" if name and name != unit else unit


def unit_factor(quantity: str, unit: str) -> float:
    """Factor from ``unit`` to the toolkit's unit of ``quantity`` (value in tool unit = value x factor).

    Parameters
    ----------
    quantity : str
        A key of :data:`UNITS` (``"force"``, ``"length"``, ...).
    unit : str
        A unit of that quantity (``"kN"``, ``"m"``, ``"bar"`` ...).

    Returns
    -------
    float
        The factor (dimensionless: tool unit per given unit).

    Raises
    ------
    PlausibilityError
        An unknown quantity or unit (the message lists the known ones).
    """
    table = UNITS.get(quantity)
    if table is None:
        raise PlausibilityError(f"unknown quantity {quantity!r}; known: {', '.join(UNITS)}")
    if unit not in table:
        raise PlausibilityError(f"unknown {quantity} unit {unit!r}; known: {', '.join(table)}")
    return table[unit]


def likely_unit(quantity: str, ratio: float, tolerance: float = 3.0) -> str | None:
    """The unit a column is probably in when its numbers are ``ratio`` times what the toolkit's unit predicts.

    Parameters
    ----------
    quantity : str
        A key of :data:`UNITS`.
    ratio : float
        Observed / expected, both read in the toolkit's unit (dimensionless); e.g. 1e-3 for a force recorded
        in kN and read as N.
    tolerance : float
        The unit's factor must bring the ratio within this factor of 1 (dimensionless, > 1).

    Returns
    -------
    str or None
        The unit other than the toolkit's whose factor best explains ``ratio``, or None when none does.

    >>> likely_unit("force", 1.1e-3), likely_unit("length", 1000.0), likely_unit("force", 1.3)
    ('kN', 'um', None)
    """
    if not (isinstance(ratio, numbers.Real) and math.isfinite(ratio) and ratio > 0):
        return None
    best, dist = None, math.log(tolerance)
    for unit, factor in UNITS[quantity].items():
        if factor == 1.0:
            continue
        d = abs(math.log(ratio * factor))
        if d < dist:
            best, dist = unit, d
    return best


def check_limit(key: str, value, label: str, error: type[Exception] = PlausibilityError, hint: str = ""):
    """``LIMITS[key].check(value, label, error, hint)``: the value, or an error naming label, range and why.

    Parameters
    ----------
    key : str
        A key of :data:`LIMITS`.
    value : Any
        The number, in the limit's unit.
    label : str
        What the user called it (an option, a field).
    error : type of Exception
        The error class raised.
    hint : str
        A likely cause, appended to the message.

    Returns
    -------
    Any
        ``value`` unchanged.
    """
    return LIMITS[key].check(value, label, error, hint)


def check_count(key: str, value, label: str, error: type[Exception] = PlausibilityError) -> int:
    """A whole-number size (grid points, elements, intervals, workers) within :data:`LIMITS`, as an int.

    Parameters
    ----------
    key : str
        A key of :data:`LIMITS` whose limit is a count.
    value : Any
        The size asked for.
    label : str
        What the user called it (``"--n"``, ``"n_elements"``).
    error : type of Exception
        The error class raised.

    Returns
    -------
    int
        ``value`` as an int.
    """
    check_limit(key, value, label, error)
    return int(value)
