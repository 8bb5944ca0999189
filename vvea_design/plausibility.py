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

__all__ = ["Limit", "LIMITS", "FIELD_LIMITS", "UNITS", "TOOL_UNIT", "UNIT_NAMES", "unit_factor", "unit_label",
           "likely_unit", "check_limit", "check_field", "check_count", "PlausibilityError"]


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
    #: the quantity (a key of :data:`UNITS`) whose other units a value out of range is tried in, so the message
    #: can name the unit it was likely typed in ("" : none)
    quantity: str = ""
    typical: float | None = None  #: a typical value, in :attr:`unit`: of two units that fit, the nearer one is named
    zero_ok: bool = False  #: 0 itself is accepted (a feature that is absent), any other value must be in range

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
        if self.zero_ok and v == 0.0:
            return None
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
        zero = "0 or " if self.zero_ok else ""
        return f"{zero}{lo} and <= {show(self.high)}{u}"

    def unit_hint(self, value) -> str:
        """``"it looks like m (metres): 0.008 m is 8 mm"`` when ``value`` fits this range in another unit, else "".

        Parameters
        ----------
        value : Any
            A number out of range, as typed (in what should be :attr:`unit`).

        Returns
        -------
        str
            The unit of :data:`UNITS` [:attr:`quantity`] whose factor brings ``value`` into range (of several,
            the one nearest :attr:`typical`, else the range's middle), with the converted value; "" when no
            unit does or the limit has no quantity.
        """
        if not self.quantity or isinstance(value, bool) or not isinstance(value, numbers.Real):
            return ""
        v = float(value)
        if not math.isfinite(v) or v == 0.0:
            return ""
        aim = self.typical if self.typical else (math.sqrt(self.low * self.high) if self.low > 0 else self.high / 2)
        best, dist = None, math.inf
        for unit, factor in UNITS[self.quantity].items():
            w = v * factor
            if factor == 1.0 or self.problem(w) is not None or w == 0.0:
                continue
            d = abs(math.log(abs(w) / aim)) if aim > 0 else 0.0
            if d < dist:
                best, dist = unit, d
        if best is None:
            return ""
        converted = f"{show(v * UNITS[self.quantity][best])} {self.unit}".rstrip()
        if best == "%":
            return f"it looks like a percentage: {show(v)} % is {converted} (give a fraction)"
        return f"it looks like {unit_label(best)}: {show(v)} {best} is {converted}; give it in {self.unit}"

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
            unit = f" {self.unit}" if self.unit and real and self.unit.split()[0] in (
                "MPa", "mm", "m", "g", "N/mm", "deg", "N", "kg", "s", "mm/s", "mm³", "rad", "°C") else ""
            hint = hint or self.unit_hint(value)
            raise error(f"{label} {why}, got {show(value)}{unit}" + (f" ({self.why})" if real else "")
                        + (f"; {hint}" if hint else ""))
        return value


#: Every range the toolkit accepts (key -> :class:`Limit`); ``docs/reliability.md`` has the table.
LIMITS: dict[str, Limit] = {
    # the unit -----------------------------------------------------------------------------------------
    "charge_MPa": Limit(0.01, 20.0, "MPa", "a pneumatic unit is charged between 0.1 bar and 200 bar (absolute); "
                        "below, nothing is left to make a force, above, no gas spring of this kind is built",
                        quantity="pressure", typical=2.0),
    "travel_mm": Limit(0.5, 1000.0, "mm", "a spring-damper unit strokes between half a millimetre and a metre",
                       quantity="length", typical=40.0),
    "diameter_mm": Limit(2.0, 1000.0, "mm", "the unit's diameters lie between 2 mm and a metre", quantity="length",
                         typical=40.0),
    "length_mm": Limit(2.0, 5000.0, "mm", "the unit's housing is between 2 mm and 5 m long", quantity="length",
                       typical=130.0),
    "thin_mm": Limit(0.1, 100.0, "mm", "a wall, gap, sleeve, seal, land or bore of the unit is between 0.1 mm and "
                     "100 mm", quantity="length", typical=2.0),
    "gap_mm": Limit(0.05, 100.0, "mm", "a radial clearance is 0 (none) or between 0.05 mm and 100 mm",
                    quantity="length", typical=0.5, zero_ok=True),
    "axial_mm": Limit(1.0, 1000.0, "mm", "an end cap, base, piston or clamp is between 1 mm and a metre long",
                      quantity="length", typical=8.0),
    "pulley_radius_mm": Limit(5.0, 1000.0, "mm", "a tendon pulley has a radius between 5 mm and 1 m",
                              quantity="length", typical=60.0),
    "gas_volume_mm3": Limit(10.0, 1e10, "mm³", "a chamber holds between 10 mm³ and 10 m³ of gas",
                            quantity="volume", typical=3e4),
    "extra_volume_mm3": Limit(0.0, 1e10, "mm³", "an extra gas volume is 0 (absent) ... 10 m³", quantity="volume",
                              typical=1e4),
    "stiffness_N_per_mm": Limit(1e-3, 2e4, "N/mm", "a gas spring's stiffness lies between 0.001 and 20,000 N/mm",
                                quantity="stiffness", typical=100.0),
    "force_N": Limit(0.1, 1e6, "N", "a force on the unit lies between 0.1 N and 1 MN", quantity="force",
                     typical=1000.0),
    "motor_torque_Nm": Limit(0.01, 1e4, "N m", "a motor delivers between 0.01 and 10,000 N m"),
    "wall_safety_factor": Limit(1.0, 20.0, "", "below 1 the walls are designed to yield; above 20 no wall this "
                                "thin can be sized"),
    "proof_factor": Limit(1.0, 10.0, "", "a proof or safety factor is at least 1 and at most 10"),
    "bulge_factor": Limit(1.0, 5.0, "", "the bladder's peak / mean radial shift is between 1 (uniform) and 5"),
    "polytropic_n": Limit(1.0, 1.4, "", "a diatomic gas such as N2 or air is compressed between isothermally "
                          "(n = 1) and adiabatically (n = 1.4)"),
    "wall_sizing_n": Limit(1.0, 1.67, "", "the walls' polytropic exponent lies between 1 (isothermal) and 1.67 "
                           "(a monatomic gas, adiabatic)"),
    "mass_g": Limit(1e-3, 1e6, "g", "a unit weighs between a milligram and a tonne", quantity="mass", typical=300.0),
    "part_mass_g": Limit(0.5, 1e5, "g", "a part weighs 0 (none) or between 0.5 g and 100 kg", quantity="mass",
                         typical=40.0, zero_ok=True),
    "linear_damping_N_s_per_mm": Limit(1e-4, 1e4, "N s/mm", "a spring-damper unit's linear damping lies between "
                                       "1e-4 N s/mm (a free piston) and 1e4 N s/mm (a closed valve)"),
    "strain_fraction": Limit(0.0, 10.0, "", "a strain is a fraction (0.25 = 25 %); no silicone stretches "
                             "beyond 1000 %", open_low=True, quantity="fraction", typical=0.25),
    "strain_limit_fraction": Limit(0.0, 2.0, "", "a strain limit is a fraction (0.25 = 25 %); no silicone "
                                   "bladder survives repeated strokes beyond 200 %", open_low=True,
                                   quantity="fraction", typical=0.25),
    "linearity_fraction": Limit(0.0, 1.0, "", "a linearity error is a fraction of the force span "
                                "(0.015 = 1.5 %)", open_low=True, quantity="fraction", typical=0.02),
    "linearity_limit_fraction": Limit(0.0, 0.2, "", "a linearity limit is a fraction of the force span "
                                      "(0.015 = 1.5 %); above 20 % the spring is no linear spring",
                                      open_low=True, quantity="fraction", typical=0.02),
    "share_fraction": Limit(0.0, 0.99, "", "a share is a fraction (0.2 = 20 %) below 1", quantity="fraction",
                            typical=0.2),
    "open_fraction": Limit(0.0, 1.0, "", "a fraction (0.5 = 50 %) between 0 and 1", quantity="fraction",
                           typical=0.5),
    "temperature_C": Limit(-20.0, 100.0, "°C", "the oil's data cover -20 ... 100 °C"),
    # the bench ----------------------------------------------------------------------------------------
    "valve_deg": Limit(0.0, 360.0, "deg", "a throttle valve turns at most a full turn"),
    "bench_speed_mm_s": Limit(1e-3, 5000.0, "mm/s", "a test machine moves between 1 µm/s and 5 m/s"),
    "sample_interval_s": Limit(1e-6, 60.0, "s", "a bench samples between every microsecond and every minute"),
    "experiment_duration_s": Limit(1e-3, 86400.0, "s", "one loading-unloading cycle lasts less than a day"),
    # the actuator -------------------------------------------------------------------------------------
    "pulley_radius_m": Limit(1e-3, 1.0, "m", "a tendon pulley has a radius between 1 mm and 1 m",
                             quantity="length_m", typical=0.06),
    "torque_step_Nm": Limit(0.0, 100.0, "N m", "the motor delivers at most 100 N m (paper eq. 13); a larger "
                            "step cannot be tracked", open_low=True),
    "link_inertia_kgm2": Limit(1e-6, 1e6, "kg m²", "a robot link's inertia lies between 1e-6 and 1e6 kg m²"),
    "amplitude_rad": Limit(0.0, math.pi, "rad", "a joint's rest-to-rest swing is more than 0 and at most half a "
                           "turn (pi rad)", open_low=True, quantity="angle_rad", typical=0.5),
    "period_s": Limit(1e-3, 60.0, "s", "a rest-to-rest motion lasts between a millisecond and a minute",
                      quantity="time", typical=1.0),
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

#: The range (a key of :data:`LIMITS`) of every numeric field a user can type: the requirements' top level, the
#: ``[fixed]`` table (and a design file's ``fixed``), the decision variables of a design file's ``parameters``
#: and of ``[bounds]`` (both ends). One table: the requirements, the fixed parameters, the design file and the
#: bounds all check against it, and ``docs/reliability.md`` lists it (a test keeps the two in sync).
FIELD_LIMITS: dict[str, str] = {
    # requirements
    "travel_mm": "travel_mm",
    "max_outer_diameter_mm": "diameter_mm",
    "max_housing_length_mm": "length_mm",
    "max_charge_MPa": "charge_MPa",
    "min_mean_stiffness_N_per_mm": "stiffness_N_per_mm",
    "min_wall_safety_factor": "wall_safety_factor",
    "min_gas_fraction_at_full_stroke": "share_fraction",
    "max_mass_g": "mass_g",
    "max_bladder_strain": "strain_limit_fraction",
    "n_polytropic": "polytropic_n",
    "max_linearity_adiabatic": "linearity_limit_fraction",
    "max_parasitic_damping_N_s_per_mm": "linear_damping_N_s_per_mm",
    # decision variables (a design file's parameters, [bounds])
    "piston_diameter_mm": "diameter_mm",
    "outer_diameter_mm": "diameter_mm",
    "V1_mm3": "gas_volume_mm3",
    "V2_mm3": "gas_volume_mm3",
    "V2_top_mm3": "extra_volume_mm3",
    "V1_annulus_mm3": "extra_volume_mm3",
    "p2_MPa": "charge_MPa",
    "bladder_cast_fill": "open_fraction",
    # [fixed]
    "rod_diameter_mm": "diameter_mm",
    "min_outer_wall_mm": "thin_mm",
    "min_inner_tube_wall_mm": "thin_mm",
    "min_top_cap_mm": "axial_mm",
    "min_base_mm": "axial_mm",
    "min_bulkhead_mm": "thin_mm",
    "fill_tube_outer_mm": "thin_mm",
    "fill_tube_bore_mm": "thin_mm",
    "min_collar_mm": "thin_mm",
    "cross_slot_mm": "thin_mm",
    "cross_slot_fraction": "open_fraction",
    "wall_safety_factor": "wall_safety_factor",
    "wall_sizing_n": "wall_sizing_n",
    "piston_height_mm": "axial_mm",
    "piston_pocket_wall_mm": "thin_mm",
    "min_piston_floor_mm": "thin_mm",
    "fluid_clearance_mm": "thin_mm",
    "bladder_thickness_mm": "thin_mm",
    "bladder_clamp_mm": "axial_mm",
    "bladder_min_gap_mm": "gap_mm",
    "bladder_bulge_factor": "bulge_factor",
    "dead_volume_1_mm3": "extra_volume_mm3",
    "dead_volume_2_mm3": "extra_volume_mm3",
    "servo_and_valve_mass_g": "part_mass_g",
    "relief_force_N": "force_N",
    "max_motor_torque_Nm": "motor_torque_Nm",
    "pulley_radius_mm": "pulley_radius_mm",
    "proof_pressure_factor": "proof_factor",
    "proof_safety_factor": "proof_factor",
    "joint_seal_cross_section_mm": "thin_mm",
    "seal_land_mm": "thin_mm",
    "throttle_bore_mm": "thin_mm",
    "relief_bore_mm": "thin_mm",
    "relief_seat_mm": "thin_mm",
    "fluid_channel_mm": "thin_mm",
    "ring_channel_mm": "thin_mm",
    "oil_temperature_C": "temperature_C",
}

#: The toolkit's unit of each quantity.
TOOL_UNIT: dict[str, str] = {"length": "mm", "force": "N", "pressure": "MPa", "time": "s", "angle": "deg",
                             "speed": "mm/s"}

#: Units each quantity is commonly recorded in: name -> factor to the toolkit's unit (value in tool unit =
#: value in that unit x factor).
UNITS: dict[str, dict[str, float]] = {
    "length": {"mm": 1.0, "m": 1e3, "cm": 10.0, "um": 1e-3, "µm": 1e-3, "in": 25.4},
    "force": {"N": 1.0, "kN": 1e3, "daN": 10.0, "kgf": 9.80665, "mN": 1e-3, "lbf": 4.4482216152605},
    "pressure": {"MPa": 1.0, "bar": 0.1, "kPa": 1e-3, "Pa": 1e-6, "psi": 6.894757293168361e-3, "GPa": 1e3},
    "time": {"s": 1.0, "ms": 1e-3, "us": 1e-6, "µs": 1e-6, "min": 60.0},
    "angle": {"deg": 1.0, "rad": 180.0 / math.pi},
    "speed": {"mm/s": 1.0, "m/s": 1e3, "cm/s": 10.0, "mm/min": 1.0 / 60.0, "um/s": 1e-3, "µm/s": 1e-3},
    # quantities of the requirements and fixed parameters (their tool unit first)
    "length_m": {"m": 1.0, "mm": 1e-3, "cm": 1e-2, "in": 0.0254},
    "volume": {"mm³": 1.0, "cm³": 1e3, "l": 1e6, "m³": 1e9},
    "stiffness": {"N/mm": 1.0, "N/m": 1e-3, "kN/m": 1.0, "lbf/in": 0.17512685},
    "mass": {"g": 1.0, "kg": 1e3, "mg": 1e-3, "lb": 453.59237},
    "fraction": {"": 1.0, "%": 0.01},
    "angle_rad": {"rad": 1.0, "deg": math.pi / 180.0},
}


#: How a unit is named in a message ("kN (kilonewtons)").
UNIT_NAMES: dict[str, str] = {
    "m": "metres", "cm": "centimetres", "um": "micrometres", "µm": "micrometres", "in": "inches",
    "kN": "kilonewtons", "daN": "decanewtons", "kgf": "kilogram-force", "mN": "millinewtons", "lbf": "pound-force",
    "bar": "bar", "kPa": "kilopascals", "Pa": "pascals", "psi": "pounds per square inch", "GPa": "gigapascals",
    "ms": "milliseconds", "us": "microseconds", "µs": "microseconds", "min": "minutes",
    "rad": "radians", "m/s": "metres per second", "cm/s": "centimetres per second", "mm/min": "millimetres per minute",
    "um/s": "micrometres per second", "µm/s": "micrometres per second",
    "cm³": "cubic centimetres", "l": "litres", "m³": "cubic metres", "N/m": "newtons per metre",
    "lbf/in": "pound-force per inch", "kg": "kilograms", "mg": "milligrams", "lb": "pounds", "%": "percent",
    "deg": "degrees", "mm": "millimetres",
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


def check_field(name: str, value, label: str | None = None, error: type[Exception] = PlausibilityError):
    """Check a typed field (a requirement, a fixed parameter, a decision variable) against :data:`FIELD_LIMITS`.

    Parameters
    ----------
    name : str
        The field's name (``"rod_diameter_mm"``); a name not in :data:`FIELD_LIMITS` is not checked.
    value : Any
        Its value, in the unit its name carries (None: an optional field left out, not checked).
    label : str or None
        What the message calls it (``"fixed.rod_diameter_mm"``); None: ``name``.
    error : type of Exception
        The error class raised.

    Returns
    -------
    Any
        ``value`` unchanged.

    Raises
    ------
    error
        ``value`` out of its range: one line naming the field, the range, why, and the unit it was likely
        typed in (``fixed.rod_diameter_mm must be >= 2 and <= 1000 mm, got 0.008 mm (...); it looks like m
        (metres): 0.008 m is 8 mm``).
    """
    key = FIELD_LIMITS.get(name)
    if key is None or value is None:
        return value
    return LIMITS[key].check(value, label or name, error)


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
