"""Units of the recordings: columns recorded in another unit, converted on request, refused when only guessed.

The exchange format fixes the units (N, mm, MPa, s, degree, mm/s; ``shared/specs/recordings.md``). A file
exported in other units is the commonest silent error of an identification: a force in kN fits g = 0.02
N/mm/MPa with an RMS error of 0.0 N, a displacement in metres fits g = 23,000. So the reader
(:func:`vvea_design.identification.recordings.recordings_from_frame`) checks every campaign against what a
real bench and the unit on it can give (:mod:`vvea_design.plausibility`), in this order:

1. **force** — a force column that never changes is no recording;
2. **one experiment** holding more than 20 times the median number of samples (and > 20,000) would outweigh
   all the others in the fit: refused, naming it;
3. **displacement** — the largest span of an experiment must lie between 0.5 mm and 1000 mm, and within the
   unit's travel (+10 %) when its design is given; running mostly negative is a flipped sign;
4. **pressure** — p2 between 0.01 and 20 MPa, and below what the design's walls carry;
5. **valve** — angles within a full turn; angles all below 2π and not whole look like radians;
6. **time and speed** — the motion's speed (span over half the cycle) against the ``speed_mm_s`` label, the
   cycle's length against a day, the bench's slowest speed;
7. **force scale and sign** — the slope of force against displacement of each experiment against the
   reference unit's g·p2 (g = mean stiffness per MPa of the ``--design`` unit, else of the paper's Fig. 5
   unit): its median must be positive and within a factor 3 (with a design; 50 without, and outside 1/3 ... 3
   not within 35 % of a force unit's factor: lbf, kgf, daN, kN); the ``speed_mm_s`` labels a length factor
   (10, 25.4) above the motion name a displacement in cm or inches;
8. **one experiment unlike the others** — after the campaign passed as a whole, each experiment is compared
   with the others: its force slope (a sign flipped, or a factor a force unit explains: kN, daN, kgf, lbf),
   its displacement span (a factor of m, in, µm), its p2 (bar, kPa, psi among MPa), its time base (ms: the
   ``speed_mm_s`` label against its own motion, relative to the others'); the offending experiment is named.

Also (3b) the **displacement's zero**: the format's x runs from 0 (the stroke end where the force is set) to
the travel; an experiment running well below 0 (a zero at mid-stroke) or, with ``--design``, beyond the
unit's travel is refused naming the experiment and the offset.

A column whose scale points to another unit is refused with a message naming the column, the likely unit
(:func:`vvea_design.plausibility.likely_unit`) and the override: ``units={"force_N": "kN"}`` in Python,
``--force-unit kN`` on the command line, which converts the column and skips its check (``"N"`` accepts it
as it is). A flipped sign is fixed with ``negate=("force_N",)`` / ``--negate force_N``.
"""

from __future__ import annotations

import math
from collections.abc import Iterable, Mapping

import numpy as np
import pandas as pd

from ..plausibility import LIMITS, TOOL_UNIT, likely_unit, unit_factor, unit_label
from ..messages import show

__all__ = ["COLUMN_QUANTITY", "COLUMN_OPTION", "apply_units", "check_scale", "Reference", "DOMINANT_FACTOR",
           "DOMINANT_MIN_ROWS"]

#: Which quantity each numeric column of the format is (its tool unit in :data:`~vvea_design.plausibility.TOOL_UNIT`).
COLUMN_QUANTITY: dict[str, str] = {"force_N": "force", "displacement_mm": "length", "time_s": "time",
                                   "p2_MPa": "pressure", "valve_deg": "angle", "speed_mm_s": "speed"}
#: The command-line option that gives each column's unit (``vvea identify`` / ``vvea diagnose``).
COLUMN_OPTION: dict[str, str] = {"force_N": "--force-unit", "displacement_mm": "--displacement-unit",
                                 "time_s": "--time-unit", "p2_MPa": "--pressure-unit", "valve_deg": "--valve-unit",
                                 "speed_mm_s": "--speed-unit"}
#: An experiment with more than this many times the median samples per experiment (and more than
#: :data:`DOMINANT_MIN_ROWS`) would outweigh the others in a fit over samples.
DOMINANT_FACTOR = 20.0
DOMINANT_MIN_ROWS = 20_000


class Reference:
    """What the recordings are checked against: the unit on the bench (its g per MPa, travel, wall capacity).

    Parameters
    ----------
    spring : GasSpring-like
        ``mean_stiffness_N_per_mm()``, ``p2_MPa`` and ``travel_mm`` (mm, MPa).
    label : str
        How messages name it (``"the --design unit"``, ``"the paper's Fig. 5 unit"``).
    design_given : bool
        True when it is the user's own unit (tighter bands: travel, force scale within a factor 3).
    max_charge_MPa : float or None
        Highest p2 its walls carry before they yield (MPa); None: only the general range.
    """

    def __init__(self, spring, label: str, design_given: bool, max_charge_MPa: float | None = None):
        self.g = float(spring.mean_stiffness_N_per_mm()) / float(spring.p2_MPa)  #: N/mm per MPa
        self.travel_mm = float(spring.travel_mm)
        self.label = label
        self.design_given = design_given
        self.max_charge_MPa = max_charge_MPa


def apply_units(d: pd.DataFrame, units: Mapping[str, str] | None, negate: Iterable[str], source: str,
                error: type[Exception]) -> set[str]:
    """Convert the columns given a unit to the format's units, and negate the ones asked for (in place).

    Parameters
    ----------
    d : pandas.DataFrame
        The numeric columns of the campaign (changed in place).
    units : mapping or None
        Column -> the unit it was recorded in (``{"force_N": "kN"}``).
    negate : iterable of str
        Columns whose sign is flipped (``("force_N",)``: compression was recorded positive).
    source : str
        The file, named in messages.
    error : type of Exception
        The error class raised (the recordings' own).

    Returns
    -------
    set of str
        The columns given a unit: their scale is the user's word, not checked.

    Raises
    ------
    error
        An unknown column or unit.
    """
    given = set()
    for col, unit in (units or {}).items():
        if col not in COLUMN_QUANTITY:
            raise error(f"{source}: units: unknown column {col!r}; columns with a unit: {', '.join(COLUMN_QUANTITY)}")
        if col not in d.columns:
            continue
        try:
            factor = unit_factor(COLUMN_QUANTITY[col], str(unit))
        except ValueError as exc:
            raise error(f"{source}: {COLUMN_OPTION[col]} / units[{col!r}]: {exc}") from None
        if factor != 1.0:
            d[col] = d[col] * factor
        given.add(col)
    for col in negate or ():
        if col not in ("force_N", "displacement_mm"):
            raise error(f"{source}: negate: only force_N and displacement_mm have a sign convention, got {col!r}")
        d[col] = -d[col]
        given.add(f"sign:{col}")
    return given


def _override(col: str, unit: str) -> str:
    return (f"pass {COLUMN_OPTION[col]} {unit} (units={{'{col}': '{unit}'}} in Python) or convert the column to "
            f"{TOOL_UNIT[COLUMN_QUANTITY[col]]}")


def _per_experiment(d: pd.DataFrame, starts: np.ndarray) -> dict[str, np.ndarray]:
    """Span of displacement, duration, sample count and force-displacement slope of every experiment."""
    x, t, F = (d[c].to_numpy(float) for c in ("displacement_mm", "time_s", "force_N"))
    n = np.diff(np.r_[starts, len(d)])
    xmax, xmin = np.maximum.reduceat(x, starts), np.minimum.reduceat(x, starts)
    tend = t[np.r_[starts[1:], len(d)] - 1]
    sx, sy = np.add.reduceat(x, starts), np.add.reduceat(F, starts)
    sxx, sxy = np.add.reduceat(x * x, starts), np.add.reduceat(x * F, starts)
    with np.errstate(divide="ignore", invalid="ignore"):
        slope = (n * sxy - sx * sy) / (n * sxx - sx * sx)
    return {"n": n, "span": xmax - xmin, "xmax": xmax, "xmin": xmin, "duration": tend - t[starts], "slope": slope,
            "p2": d["p2_MPa"].to_numpy(float)[starts]}


def check_scale(d: pd.DataFrame, starts: np.ndarray, names, source: str, reference: Reference,
                given: set[str]) -> tuple[str | None, list[str]]:
    """The first sign that a column is in another unit or sign convention, and notes short of an error.

    Parameters
    ----------
    d : pandas.DataFrame
        The campaign, numeric columns in the format's units (after :func:`apply_units`).
    starts : numpy.ndarray
        Row index of each experiment's first sample.
    names : sequence of str
        The experiments' identifiers, in order.
    source : str
        The file, named in messages.
    reference : Reference
        The unit the recordings are checked against.
    given : set of str
        Columns whose unit the user gave (not checked), ``"sign:<column>"`` for negated ones.

    Returns
    -------
    problem : str or None
        The message of the first problem (names the column, what it looks like and the override).
    notes : list of str
        Remarks that are not errors (a speed label off by a factor that is no unit).
    """
    e = _per_experiment(d, starts)
    F = d["force_N"].to_numpy(float)
    checks = (_force_constant, _dominant, _displacement, _offset, _pressure, _valve, _time_and_speed, _force,
              _odd_experiment)
    notes: list[str] = []
    for check in checks:
        msg = check(d, e, F, np.asarray(names), source, reference, given, notes)
        if msg:
            return msg, notes
    return None, notes


def _force_constant(d, e, F, names, source, ref, given, notes):
    if F.size and np.ptp(F) == 0:
        return (f"{source}: column force_N is {show(F[0] + 0.0)} N in every row: no force was recorded (a load cell not "
                "connected, or the wrong column exported)")
    return None


def _dominant(d, e, F, names, source, ref, given, notes):
    n = e["n"]
    if len(n) < 2:
        return None
    med = float(np.median(n))
    k = int(np.argmax(n))
    if n[k] > DOMINANT_FACTOR * med and n[k] > DOMINANT_MIN_ROWS:
        return (f"{source}: experiment {names[k]!r} has {int(n[k]):,} samples, {n[k] / med:,.0f} times the median "
                f"of the {len(n)} experiments ({med:,.0f}): a fit over samples would weigh it as much as "
                f"{n[k] / med:,.0f} experiments and move every parameter towards it; resample it to the others' rate "
                "(e.g. keep every k-th sample) or leave it out")
    return None


def _displacement(d, e, F, names, source, ref, given, notes):
    span = float(np.max(e["span"])) if len(e["span"]) else 0.0
    x = d["displacement_mm"].to_numpy(float)
    T, what = ref.travel_mm, ref.label
    if "displacement_mm" not in given:
        low, high = LIMITS["travel_mm"].low, (1.1 * T + 0.5 if ref.design_given else LIMITS["travel_mm"].high)
        if span > 0 and not low <= span <= high:
            unit = likely_unit("length", span / T, tolerance=3.0)
            head = (f"{source}: column displacement_mm spans at most {show(span)} mm in an experiment; "
                    + (f"{what} strokes {show(T)} mm (its travel)" if ref.design_given else
                       f"a bench stroke lies between {show(low)} and {show(high)} mm"))
            if unit:
                f = unit_factor("length", unit)
                return (f"{head}: it looks like {unit_label(unit)}: x {show(f)} gives {show(span * f)} mm; "
                        + _override("displacement_mm", unit))
            return head + "; check the column and its unit (pass --displacement-unit mm to use it as it is)"
    if "sign:displacement_mm" not in given and "displacement_mm" not in given:
        lo, hi = float(np.min(x)), float(np.max(x))
        if lo < -0.5 * span and hi < 0.25 * abs(lo):
            return (f"{source}: column displacement_mm runs from {show(hi)} to {show(lo)} mm, mostly negative: the "
                    "format's x > 0 is extension of the pull spring (tension +); the displacement's sign looks "
                    "flipped; pass --negate displacement_mm (negate=('displacement_mm',) in Python) or flip the column"
                    " (pass --displacement-unit mm to use it as it is)")
    return None


def _offset(d, e, F, names, source, ref, given, notes):
    """An experiment whose displacement zero is not at the stroke end (x from 0 to the travel)."""
    if "displacement_mm" in given or "sign:displacement_mm" in given:
        return None
    span, xmin, xmax = e["span"], e["xmin"], e["xmax"]
    low = -(0.05 * span + 0.5)
    bad = np.flatnonzero(xmin < low)
    if ref.design_given:
        bad = np.union1d(bad, np.flatnonzero(xmax > 1.1 * ref.travel_mm + 0.5))
    if not bad.size:
        return None
    k = int(bad[0])
    more = f" (and {bad.size - 1} more experiment(s))" if bad.size > 1 else ""
    limit = f"0 ... {show(ref.travel_mm)} mm, the travel of {ref.label}" if ref.design_given else "0 ... its span"
    return (f"{source}: experiment {names[k]!r} runs x = {show(xmin[k])} ... {show(xmax[k])} mm{more}: the format's "
            f"displacement runs from 0 (one stroke end) to the travel ({limit}); its zero looks offset by "
            f"{show(xmin[k])} mm" + (" (a zero at mid-stroke?)" if xmin[k] < 0 else "")
            + ": subtract the offset from displacement_mm of that experiment (--displacement-unit mm uses the file "
            "as it is)")


def _odd_experiment(d, e, F, names, source, ref, given, notes):
    """One experiment unlike the others: a sign, a force, length, pressure or time unit of its own."""
    n_exp = len(e["n"])
    if n_exp < 3:
        return None
    med_span = float(np.median(e["span"]))
    if "displacement_mm" not in given and med_span > 0:
        for k in range(n_exp):
            ratio = float(e["span"][k]) / med_span
            unit = likely_unit("length", ratio * 1.0, tolerance=1.5) if ratio > 0 else None
            if unit and abs(math.log(ratio)) > math.log(20.0):
                return (f"{source}: experiment {names[k]!r} spans {show(e['span'][k])} mm where the others span "
                        f"{show(med_span)} mm (median): its displacement looks like {unit_label(unit)}; convert that "
                        "experiment to mm or leave it out (--displacement-unit mm uses the file as it is)")
    msg = _odd_pressure(e, names, source, given)
    if msg:
        return msg
    with np.errstate(divide="ignore", invalid="ignore"):
        r = e["slope"] / (ref.g * e["p2"])
    ok = np.isfinite(r)
    if ok.sum() >= 3 and "force_N" not in given:
        r0 = float(np.median(r[ok]))
        if r0 > 0:
            for k in np.flatnonzero(ok):
                if r[k] < 0 and "sign:force_N" not in given:
                    return (f"{source}: experiment {names[k]!r}: force_N falls as displacement_mm grows while it rises "
                            f"in the others (slope {show(r[k] / r0)} times theirs): its force's sign looks flipped; "
                            "flip that experiment's force or leave it out (--force-unit N uses the file as it is)")
                unit = likely_unit("force", r[k] / r0, tolerance=1.5)
                if unit and abs(math.log(r[k] / r0)) > math.log(2.5):
                    return (f"{source}: experiment {names[k]!r}: its force rises {show(r[k] / r0)} times as steeply "
                            f"as in the others (per MPa of p2): it looks like {_force_label(unit)}; convert that "
                            "experiment's force_N to N or leave it out (--force-unit N uses the file as it is)")
    return _odd_time(d, e, names, source, given)


def _odd_pressure(e, names, source, given):
    """One experiment's p2 in another pressure unit than the others' (bar among MPa)."""
    if "p2_MPa" in given:
        return None
    p = e["p2"]
    if len(p) < 3 or not np.all(p > 0):
        return None
    for k in range(len(p)):
        others = np.delete(p, k)
        lo, hi, med = float(np.min(others)), float(np.max(others)), float(np.median(others))
        if lo / 2 <= p[k] <= 2 * hi:
            continue
        best, dist = None, math.inf
        for unit, f in _candidates("pressure"):
            if lo / 1.2 <= p[k] * f <= 1.2 * hi and abs(math.log(p[k] * f / med)) < dist:
                best, dist = unit, abs(math.log(p[k] * f / med))
        if best:
            return (f"{source}: experiment {names[k]!r} is charged to p2 = {show(p[k])} where the others lie in "
                    f"{show(lo)} ... {show(hi)} MPa: its p2 looks like {unit_label(best)} (x "
                    f"{show(unit_factor('pressure', best))} gives {show(p[k] * unit_factor('pressure', best))} MPa); "
                    "convert that experiment's p2_MPa or leave it out (--pressure-unit MPa uses the file as it is)")
    return None


def _odd_time(d, e, names, source, given):
    """One experiment on another time base (ms): its speed label against its own motion, relative to the others'."""
    if "speed_mm_s" not in d.columns or "time_s" in given or "speed_mm_s" in given:
        return None
    with np.errstate(divide="ignore", invalid="ignore"):
        motion = e["span"] / (0.5 * e["duration"])
        R = d["speed_mm_s"].to_numpy(float)[np.r_[0, np.cumsum(e["n"])[:-1]]] / motion
    ok = np.isfinite(R) & (R > 0)
    if ok.sum() < 3:
        return None
    R0 = float(np.median(R[ok]))
    for k in np.flatnonzero(ok):
        unit = likely_unit("time", R[k] / R0, tolerance=1.5)
        if unit and abs(math.log(R[k] / R0)) > math.log(20.0):
            return (f"{source}: experiment {names[k]!r} lasts {show(e['duration'][k])} s for a {show(e['span'][k])} "
                    f"mm stroke at its speed label {show(R[k] * motion[k])} mm/s, {show(R[k] / R0)} times off the "
                    f"others: its time_s looks like {unit_label(unit)}; convert that experiment's time or leave it out "
                    "(--time-unit s uses the file as it is)")
    return None


def _force_label(unit: str) -> str:
    """A force unit for a message; daN and kgf (2 % apart) cannot be told from the scale: both are named."""
    if unit in ("daN", "kgf"):
        return f"{unit_label('daN')} or {unit_label('kgf')} (2 % apart; the scale cannot tell them)"
    return unit_label(unit)


def _force_ratio(e, ref) -> float:
    """Median over experiments of (force-displacement slope) / (g p2): about 1 for a right file."""
    with np.errstate(divide="ignore", invalid="ignore"):
        r = e["slope"] / (ref.g * e["p2"])
    r = r[np.isfinite(r)]
    return float(np.median(r)) if r.size else float("nan")


def _pressure(d, e, F, names, source, ref, given, notes):
    if "p2_MPa" in given:
        return None
    p = e["p2"]
    lim = LIMITS["charge_MPa"]
    cap = lim.high if ref.max_charge_MPa is None else min(lim.high, ref.max_charge_MPa)
    pmax, pmin = float(np.max(p)), float(np.min(p))
    if lim.low <= pmin and pmax <= cap:
        return None
    inside = (p >= lim.low) & (p <= cap)
    if inside.sum() > len(p) / 2:  # most experiments are fine: name the one(s) in another unit, not the column
        msg = _odd_pressure(e, names, source, given)
        if msg:
            return msg
    r0 = _force_ratio(e, ref)
    best, score = None, math.inf
    for unit, f in _candidates("pressure"):
        if lim.low <= pmin * f and pmax * f <= cap:
            s = abs(math.log(r0 / f)) if r0 > 0 and math.isfinite(r0) else abs(math.log(pmax * f / 4.0))
            if s < score:
                best, score = unit, s
    why = (f"above {show(cap)} MPa, where the walls of {ref.label} yield" if ref.max_charge_MPa is not None and pmax > cap
           else f"a bench charge lies between {show(lim.low)} and {show(lim.high)} MPa")
    head = f"{source}: column p2_MPa ranges {show(pmin)} ... {show(pmax)}: {why}"
    if best:
        f = unit_factor("pressure", best)
        return (f"{head}; it looks like {unit_label(best)}: x {show(f)} gives {show(pmin * f)} ... {show(pmax * f)} MPa; "
                + _override("p2_MPa", best))
    return head + "; check the column and its unit (pass --pressure-unit MPa to use it as it is)"


def _candidates(quantity: str):
    from ..plausibility import UNITS

    return [(u, f) for u, f in UNITS[quantity].items() if f != 1.0]


def _valve(d, e, F, names, source, ref, given, notes):
    if "valve_deg" in given:
        return None
    v = d["valve_deg"].to_numpy(float)
    lo, hi = float(np.min(v)), float(np.max(v))
    lim = LIMITS["valve_deg"]
    if lo < lim.low or hi > lim.high:
        return (f"{source}: column valve_deg ranges {show(lo)} ... {show(hi)} deg: {lim.why} (0 ... 360 deg); is an "
                "offset added, or another column exported? (pass --valve-unit deg to use it as it is)")
    if hi <= 2 * math.pi + 1e-6 and np.any(np.abs(v - np.round(v)) > 1e-6):
        f = unit_factor("angle", "rad")
        return (f"{source}: column valve_deg ranges {show(lo)} ... {show(hi)}: no throttle works in a few degrees, "
                f"it looks like {unit_label('rad')}: x {show(f)} gives {show(lo * f)} ... {show(hi * f)} deg; "
                + _override("valve_deg", "rad"))
    return None


def _time_and_speed(d, e, F, names, source, ref, given, notes):
    with np.errstate(divide="ignore", invalid="ignore"):
        est = e["span"] / (0.5 * e["duration"])  # about the cruise speed of each experiment, mm/s
    ok = np.isfinite(est) & (est > 0)
    if not ok.any():
        return None
    v_med = float(np.median(est[ok]))
    time_free = "time_s" not in given
    speed = LIMITS["bench_speed_mm_s"]
    odd_speed = not (50 * speed.low <= v_med <= speed.high)  # the motion itself is implausibly slow or fast
    if "speed_mm_s" in d.columns and "speed_mm_s" not in given:
        with np.errstate(divide="ignore", invalid="ignore"):
            r = d["speed_mm_s"].to_numpy(float)[np.r_[0, np.cumsum(e["n"])[:-1]]] / est
        r = r[ok & np.isfinite(r) & (r > 0)]
        R = float(np.median(r)) if r.size else float("nan")  # label / motion
        if math.isfinite(R) and abs(math.log(R)) > math.log(3.0):
            t_unit = likely_unit("time", R, tolerance=1.5) if time_free else None
            s_unit = likely_unit("speed", R, tolerance=1.5)
            if t_unit and (odd_speed or not s_unit):
                return _time_message(source, e, v_med, t_unit, f"the speed_mm_s labels are {show(R)} times that")
            if s_unit:
                f = unit_factor("speed", s_unit)
                return (f"{source}: column speed_mm_s is {show(R)} times the speed of the motion (displacement over "
                        f"time, median {show(v_med)} mm/s): it looks like {unit_label(s_unit)}: x {show(f)} makes it "
                        "agree; " + _override("speed_mm_s", s_unit))
            l_unit = likely_unit("length", 1.0 / R, tolerance=1.5) if "displacement_mm" not in given else None
            if l_unit and R > 1:  # the motion is slower than its labels by a length factor: x in cm or inches
                f = unit_factor("length", l_unit)
                return (f"{source}: the speed_mm_s labels are {show(R)} times the speed of the motion (displacement "
                        f"over time, median {show(v_med)} mm/s): column displacement_mm looks like "
                        f"{unit_label(l_unit)}: x {show(f)} makes them agree; " + _override("displacement_mm", l_unit))
            notes.append(f"{source}: the speed_mm_s labels are {show(R)} times the speed of the motion (median "
                         f"{show(v_med)} mm/s); they are labels only (the velocity comes from time_s and "
                         "displacement_mm)")
    if time_free:
        dur = float(np.median(e["duration"]))
        if dur > LIMITS["experiment_duration_s"].high or (float(np.max(est[ok])) < 50 * speed.low and dur > 3600):
            return _time_message(source, e, v_med, "ms", "far longer and slower than a bench cycle")
    return None


def _time_message(source, e, v_med, unit, why) -> str:
    f = unit_factor("time", unit)
    dur = float(np.median(e["duration"]))
    return (f"{source}: column time_s makes a median cycle of {show(dur)} s ({show(dur / 3600)} h) with the piston at "
            f"{show(v_med)} mm/s, {why}; it looks like {unit_label(unit)}: "
            f"x {show(f)} gives {show(dur * f)} s at {show(v_med / f)} mm/s; " + _override("time_s", unit))


def _force(d, e, F, names, source, ref, given, notes):
    r0 = _force_ratio(e, ref)
    if not math.isfinite(r0):
        return None
    span = float(np.max(e["span"]))
    p = float(np.max(e["p2"]))
    predicted, peak = ref.g * p * span, float(np.max(np.abs(F)))
    src = f"g = {show(ref.g)} N/mm/MPa of {ref.label}"
    if r0 <= 0 and "sign:force_N" not in given and "force_N" not in given:
        return (f"{source}: column force_N falls as displacement_mm grows (median slope {show(r0)} of g·p2, {src}): "
                "the format's force is + in tension and a pull spring's force rises with x > 0; the force's sign "
                "looks flipped (compression recorded positive); pass --negate force_N (negate=('force_N',) in "
                "Python) or flip the column")
    if "force_N" in given or r0 <= 0:
        return None
    band = 3.0 if ref.design_given else 50.0
    close = likely_unit("force", r0, tolerance=1.35)  # r0 sits on a force unit's factor (lbf, kgf, daN, kN)
    if 1 / band <= r0 <= band and not (close and not 1 / 3 <= r0 <= 3):
        return None
    unit = likely_unit("force", r0, tolerance=3.0)
    head = (f"{source}: column force_N is {show(r0)} times what g·p2·x predicts: ~{show(predicted)} N at "
            f"{show(span)} mm and p2 = {show(p)} MPa ({src}), the file peaks at {show(peak)}")
    if unit:
        f = unit_factor("force", unit)
        return f"{head}; it looks like {_force_label(unit)}: " + _override("force_N", unit)
    return (head + "; is " + ("--design the unit on the bench" if ref.design_given else "the unit this far from the "
            "paper's (give its --design)") + ", or the column in another unit? (pass --force-unit N to use it as it is)")
