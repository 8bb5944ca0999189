"""Tension-test recordings: reader, validation and velocity estimate.

Reads the exchange format of ``shared/specs/recordings.md`` (CSV or Parquet):
one tidy table, one row per sample, many experiments per file, columns
``experiment, time_s, displacement_mm, force_N, p2_MPa, valve_deg`` and the
optional label ``speed_mm_s`` and the optional absolute time ``clock_s`` (s, the
tensile tester's clock: with it the campaign time keeps the pauses between runs).
Other columns are kept and ignored.

Velocity is derived from ``time_s`` and ``displacement_mm`` only. A naive
finite difference is useless here: 2 µm of displacement noise at 20 ms
sampling is 0.1 mm/s, i.e. 100 N at a damping of 1000 N s/mm. The reader
therefore fits, per experiment, the test machine's motion profile (constant
acceleration to a cruise speed, cruise, a constant-deceleration reversal,
cruise back, constant deceleration to rest) to the displacement by least
squares and differentiates the fitted profile analytically. Where that
profile does not describe an experiment (fit error well above the
displacement noise) the velocity falls back to a Savitzky-Golay derivative
on each monotone segment; the number of such experiments is reported.

Example
-------
>>> from vvea_design.identification.recordings import read_recordings
>>> rec = read_recordings("../shared/recordings/campaign_a.csv")  # doctest: +SKIP
>>> rec.n_experiments, rec.data["velocity_mm_s"].abs().max()        # doctest: +SKIP
"""

from __future__ import annotations

from collections.abc import Iterable, Mapping
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
import pandas as pd
from scipy.optimize import least_squares
from scipy.signal import savgol_filter

from ..inputs import check_input_file, decode_text, read_input_bytes
from ..messages import show
from ..spring.gas_spring import PAPER_FIG5
from .units import Reference, apply_units, check_scale

__all__ = [
    "RecordingsError",
    "Recordings",
    "REQUIRED_COLUMNS",
    "MIN_SAMPLES_PER_EXPERIMENT",
    "REST_FRACTION",
    "read_recordings",
    "recordings_from_frame",
    "trapezoid_profile",
]

#: Columns every file must hold (name -> meaning, unit).
REQUIRED_COLUMNS: dict[str, str] = {
    "experiment": "identifier of one test run (text)",
    "time_s": "time since the start of the experiment (s)",
    "displacement_mm": "piston displacement x, + = extension (mm)",
    "force_N": "measured external force, + = tension (N)",
    "p2_MPa": "pressure preset of the positive chamber (MPa)",
    "valve_deg": "throttle valve position gamma (degree)",
}
#: A sample is "at rest" when its speed is below this fraction of the cruise
#: speed (start, turning point, end): friction is set-valued there (anything
#: between -C and +C), so models of sign(ẋ) leave these samples out.
REST_FRACTION = 0.02
#: An experiment with fewer samples than this is rejected.
MIN_SAMPLES_PER_EXPERIMENT = 8

_NUMERIC = ("time_s", "displacement_mm", "force_N", "p2_MPa", "valve_deg")
_OPTIONAL = ("speed_mm_s", "clock_s")  #: optional numeric columns: the speed label (mm/s), the absolute time (s)


class RecordingsError(ValueError):
    """A recordings file that does not follow the exchange format."""


@dataclass(frozen=True)
class Recordings:
    """A validated campaign with derived kinematics.

    Attributes
    ----------
    data : pandas.DataFrame
        One row per sample, in file order, with the format's columns plus
        ``velocity_mm_s`` (estimated ẋ, mm/s), ``direction`` (+1 extending,
        -1 retracting, 0 at rest), ``time_since_reversal_s`` (s since the
        last start or reversal of motion), ``campaign_time_s`` (s since the
        start of the first experiment, experiments laid end to end in file
        order) and ``exp_index`` (0-based experiment number in run order).
    experiments : pandas.DataFrame
        One row per experiment: ``experiment, p2_MPa, valve_deg, speed_mm_s``
        (nominal label, or the fitted cruise speed when absent),
        ``n_samples``, ``velocity_method`` ("profile" or "savgol"),
        ``profile_rms_mm`` (displacement misfit of the motion profile).
    source : str
        File the campaign was read from (or ``"<frame>"``).
    rows_read : int
        Rows in the file.
    rows_left_out : int
        Rows the reader left out (the reader leaves none out; the field is
        carried so that every consumer can report it).
    displacement_noise_mm : float
        Robust estimate of the displacement measurement noise (mm).
    """

    data: pd.DataFrame
    experiments: pd.DataFrame
    source: str
    rows_read: int
    rows_left_out: int = 0
    displacement_noise_mm: float = 0.0
    notes: tuple[str, ...] = field(default_factory=tuple)

    @property
    def n_experiments(self) -> int:
        """Number of experiments in the campaign."""
        return len(self.experiments)

    @property
    def n_savgol(self) -> int:
        """Experiments whose velocity came from the Savitzky-Golay fallback."""
        return int((self.experiments["velocity_method"] == "savgol").sum())

    def subset(self, experiment_ids) -> "Recordings":
        """The campaign restricted to the given experiment identifiers (run order kept).

        Parameters
        ----------
        experiment_ids : iterable
            Experiment identifiers (compared as text with the ``experiment`` column); an identifier that
            is not in the campaign selects nothing.

        Returns
        -------
        Recordings
            A new campaign with the samples and experiment rows of those experiments, in their original
            order, ``rows_read`` set to its number of samples and ``rows_left_out`` to 0; the derived
            columns (``exp_index``, ``campaign_time_s``, ...), the displacement noise (mm) and the notes
            are those of the full campaign, not recomputed.
        """
        keep = set(map(str, experiment_ids))
        d = self.data[self.data["experiment"].isin(keep)].reset_index(drop=True)
        e = self.experiments[self.experiments["experiment"].isin(keep)].reset_index(drop=True)
        return Recordings(d, e, self.source, len(d), 0, self.displacement_noise_mm, self.notes)


# ---------------------------------------------------------------- reading
def read_recordings(path: str | Path, *, units: Mapping[str, str] | None = None, negate: Iterable[str] = (),
                    reference=None) -> Recordings:
    """Read and validate a recordings file (``.csv`` or ``.parquet``).

    Parameters
    ----------
    path
        CSV (comma separated, header line, ``.`` decimal point) or Parquet
        file with the exchange-format columns. A CSV exported with ``;`` as
        delimiter and ``,`` as decimal mark (spreadsheet programs in many
        locales) is read too; :attr:`Recordings.notes` says so.
    units
        Column -> the unit it was recorded in (``{"force_N": "kN"}``), converted to the format's unit
        (:data:`vvea_design.plausibility.UNITS`); a column given a unit is not checked for its scale.
    negate
        Columns recorded with the opposite sign convention (``("force_N",)``), negated.
    reference
        The unit on the bench the recordings are checked against (:mod:`vvea_design.identification.units`):
        a :class:`~vvea_design.spring.design.Design` (its travel, g per MPa and the charge its walls
        carry), a :class:`~vvea_design.spring.gas_spring.GasSpring`, or None: the paper's Fig. 5 unit.

    Returns
    -------
    Recordings
        The validated campaign with estimated velocity.

    Raises
    ------
    RecordingsError
        Naming the file, the column or line and what is wrong. Line numbers
        are those of the file (blank lines counted). Also before reading: a
        path that is a folder, a FIFO or a device, a file over 2 GiB; and
        after: a column whose scale or sign points to another unit or
        convention (naming the likely unit and the override).
    """
    path = Path(path)
    check_input_file(path, "recordings file", RecordingsError)
    suffix = path.suffix.lower()
    notes: list[str] = []
    lines = None
    line_offset = 0
    if suffix in (".parquet", ".pq"):
        try:
            frame = pd.read_parquet(path)
        except Exception as exc:
            raise RecordingsError(f"{path}: cannot be read as Parquet: {_short(exc)}") from None
    else:
        frame, lines, notes = _read_csv(path)
        line_offset = 2
    return recordings_from_frame(frame, source=str(path), line_offset=line_offset, line_numbers=lines,
                                 notes=tuple(notes), units=units, negate=negate, reference=reference)


def _short(exc: Exception) -> str:
    msg = str(exc).strip().splitlines()
    return (msg[0] if msg else type(exc).__name__)[:300]


def _read_csv(path: Path):
    """Parse a CSV; returns (frame, file line number of every data row, notes)."""
    import csv
    import io

    raw = read_input_bytes(path, "recordings file", RecordingsError)
    text = decode_text(raw, path, "recordings file", RecordingsError, "CSV (or use a .parquet file)")
    del raw
    file_lines = text.splitlines()
    nonblank = [i + 1 for i, ln in enumerate(file_lines) if ln.strip()]
    if not nonblank:
        raise RecordingsError(f"{path}: the file is empty (expected a header line and data rows)")
    header = file_lines[nonblank[0] - 1]
    sep = ","
    notes: list[str] = []
    if ";" in header and "," not in header:
        sep = ";"
    elif "\t" in header and "," not in header:
        sep = "\t"
    try:
        frame = pd.read_csv(
            io.StringIO(text), sep=sep, dtype=str, skip_blank_lines=True,
            quoting=csv.QUOTE_MINIMAL, engine="c",
        )
    except pd.errors.ParserError as exc:
        msg = _short(exc)
        import re

        m = re.search(r"Expected (\d+) fields in line (\d+), saw (\d+)", msg)
        if m:
            ln = int(m.group(2))  # the C parser counts the file's lines, blank ones included
            raise RecordingsError(
                f"{path}: line {ln}: {m.group(3)} fields where the header has {m.group(1)} "
                f"(delimiter {sep!r}{'; is the decimal mark a comma in a comma-separated file?' if sep == ',' else ''})"
            ) from None
        raise RecordingsError(f"{path}: cannot be read as CSV: {msg}") from None
    except (ValueError, csv.Error, UnicodeError, MemoryError) as exc:
        raise RecordingsError(f"{path}: cannot be read as CSV: {_short(exc)}") from None
    frame.columns = [str(c).strip() for c in frame.columns]
    lines = np.asarray(nonblank[1:], dtype=int) if len(nonblank) - 1 == len(frame) else None
    if sep != ",":
        notes.append(f"read as {'semicolon' if sep == ';' else 'tab'}-separated")
    decimal_comma = False
    for c in _NUMERIC + _OPTIONAL:
        if c in frame.columns:
            col = frame[c].str.strip()
            if sep != "," and col.str.contains(",", regex=False).any() and not col.str.contains(".", regex=False).any():
                col = col.str.replace(",", ".", regex=False)
                decimal_comma = True
            frame[c] = col
    if decimal_comma:
        notes.append("decimal comma read as decimal point")
    if notes:
        notes = [f"{path.name}: " + " with ".join(notes) + " (the exchange format is comma-separated with '.' decimals)"]
    return frame, lines, notes


def _where(source: str, idx: int, line_offset: int, lines=None) -> str:
    if lines is not None and 0 <= idx < len(lines):
        return f"{source}: line {int(lines[idx])}"
    return f"{source}: line {idx + line_offset}" if line_offset else f"{source}: row {idx}"


def _numeric_columns(d: pd.DataFrame, source: str, line_offset: int, line_numbers) -> None:
    """The numeric columns of ``d`` as floats (in place); a non-numeric, empty or infinite cell names its line."""
    cols = list(_NUMERIC) + [c for c in _OPTIONAL if c in d.columns]
    for c in cols:
        num = _to_numeric(d[c])
        bad = num.isna() & d[c].notna()
        if bad.any():
            i = int(np.flatnonzero(bad.to_numpy())[0])
            raise RecordingsError(
                f"{_where(source, i, line_offset, line_numbers)}: column {c} holds a non-numeric value {show(d[c].iloc[i])}"
            )
        nan = num.isna() | ~np.isfinite(num.astype(float))
        if nan.any():
            i = int(np.flatnonzero(nan.to_numpy())[0])
            raise RecordingsError(f"{_where(source, i, line_offset, line_numbers)}: column {c} is NaN/empty or infinite")
        d[c] = num.astype(float)


def recordings_from_frame(
    frame: pd.DataFrame,
    source: str = "<frame>",
    line_offset: int = 0,
    line_numbers=None,
    notes: tuple = (),
    *,
    units: Mapping[str, str] | None = None,
    negate: Iterable[str] = (),
    reference=None,
) -> Recordings:
    """Validate a table in the exchange format and derive the kinematics.

    Parameters
    ----------
    frame
        The table (columns as in the file).
    source
        Name used in error messages.
    line_offset
        Added to a 0-based row index to name the line in error messages
        (2 for a CSV with a header line, 0 for "row" numbering).
    line_numbers
        File line of every row (overrides ``line_offset``; blank lines in a
        CSV shift them).
    notes
        Remarks about how the file was read, kept in :attr:`Recordings.notes`.
    units, negate, reference
        As for :func:`read_recordings`: columns' units to convert, columns to negate, and the unit the
        scale of the columns is checked against (None: the paper's Fig. 5 unit).

    Returns
    -------
    Recordings
        The validated campaign with estimated velocity.

    Raises
    ------
    RecordingsError
        Missing column, non-numeric value, NaN, time not increasing inside
        an experiment, too few samples, an experiment with two pressures or
        two valve positions, an experiment split into non-contiguous blocks;
        a column whose scale or sign points to another unit or convention,
        a force that never changes, one experiment that would outweigh all
        the others (:func:`vvea_design.identification.units.check_scale`).
    """
    frame = frame.reset_index(drop=True)
    missing = [c for c in REQUIRED_COLUMNS if c not in frame.columns]
    if missing:
        raise RecordingsError(
            f"{source}: missing required column(s) {', '.join(missing)} "
            f"(found: {', '.join(map(str, frame.columns))})"
        )
    if len(frame) == 0:
        raise RecordingsError(f"{source}: no data rows")
    d = frame.copy()
    d["experiment"] = d["experiment"].astype(object)
    bad_id = d["experiment"].isna()
    if bad_id.any():
        i = int(np.flatnonzero(bad_id.to_numpy())[0])
        raise RecordingsError(f"{_where(source, i, line_offset, line_numbers)}: column experiment is empty (NaN)")
    d["experiment"] = d["experiment"].astype(str)
    _numeric_columns(d, source, line_offset, line_numbers)
    given = apply_units(d, units, negate, source, RecordingsError)

    exp = d["experiment"].to_numpy()
    starts = np.r_[True, exp[1:] != exp[:-1]]
    block_ids = exp[starts]
    if len(set(block_ids)) != len(block_ids):
        seen: set[str] = set()
        for i in np.flatnonzero(starts):
            if exp[i] in seen:
                raise RecordingsError(
                    f"{_where(source, int(i), line_offset, line_numbers)}: rows of experiment {exp[i]!r} are not contiguous "
                    "(it appears again after another experiment)"
                )
            seen.add(exp[i])
    bounds = np.r_[np.flatnonzero(starts), len(d)]
    t = d["time_s"].to_numpy()
    held = {c: d[c].to_numpy() for c in ("p2_MPa", "valve_deg")}  # columns once, not per experiment
    for k in range(len(block_ids)):
        a, b = bounds[k], bounds[k + 1]
        name = block_ids[k]
        if b - a < MIN_SAMPLES_PER_EXPERIMENT:
            raise RecordingsError(
                f"{_where(source, int(a), line_offset, line_numbers)}: experiment {name!r} has only {b - a} samples "
                f"(at least {MIN_SAMPLES_PER_EXPERIMENT} needed)"
            )
        dt = np.diff(t[a:b])
        if np.any(dt <= 0):
            i = int(a + 1 + np.flatnonzero(dt <= 0)[0])
            raise RecordingsError(
                f"{_where(source, i, line_offset, line_numbers)}: time_s does not increase inside experiment {name!r} "
                f"({show(t[i - 1])} then {show(t[i])})"
            )
        for c in ("p2_MPa", "valve_deg"):
            vals = held[c][a:b]
            if np.any(vals != vals[0]):
                i = int(a + np.flatnonzero(vals != vals[0])[0])
                what = "pressures" if c == "p2_MPa" else "valve positions"
                raise RecordingsError(
                    f"{_where(source, i, line_offset, line_numbers)}: experiment {name!r} has two {what} in column {c} "
                    f"({show(vals[0])} and {show(vals[i - a])})"
                )
        if held["p2_MPa"][a] <= 0:
            raise RecordingsError(
                f"{_where(source, int(a), line_offset, line_numbers)}: experiment {name!r}: p2_MPa must be > 0, got {show(held['p2_MPa'][a])}"
            )
    problem, more = check_scale(d, bounds[:-1], block_ids, source, _reference(reference), given)
    if problem:
        raise RecordingsError(problem)
    return _derive(d, bounds, block_ids, source, tuple(notes) + tuple(more), line_offset, line_numbers)


def _reference(ref) -> Reference:
    """The :class:`~vvea_design.identification.units.Reference` of a Design, a GasSpring or None (the paper's unit)."""
    if isinstance(ref, Reference):
        return ref
    if ref is None:
        return Reference(PAPER_FIG5, "the paper's Fig. 5 unit (no --design given)", False)
    if hasattr(ref, "gas_spring") and hasattr(ref, "wall_safety_factors"):  # a Design
        sf = min(ref.wall_safety_factors().values())
        return Reference(ref.gas_spring, "the --design unit", True, float(ref.p2_MPa) * float(sf))
    return Reference(ref, "the given unit", True)


def _to_numeric(col: pd.Series) -> pd.Series:
    """``pd.to_numeric(col, errors="coerce")``, parsed by Arrow when the column is Arrow-backed text.

    A CSV read as text gives Arrow strings; Arrow's cast to float64 is a vectorised parse, far cheaper than
    pandas' per-element one, and gives the correctly rounded double (pandas' parser misses it by one unit in
    the last place for some long mantissas with large exponents). Arrow is stricter: a column
    it refuses (any text it cannot read as a number), or a column of integer literals holding ``-0``
    (which pandas reads as the integer 0, not -0.0), goes through :func:`pandas.to_numeric` as before, so
    what is rejected and the error messages do not change. Missing entries stay missing (NaN).
    """
    dtype = col.dtype
    if isinstance(dtype, pd.StringDtype) and dtype.storage == "pyarrow":
        try:
            vals = col.astype("float64[pyarrow]").to_numpy(dtype=float, na_value=np.nan)
        except (ValueError, TypeError, NotImplementedError):  # pyarrow.ArrowInvalid is a ValueError
            vals = None
        if vals is not None and (
            not np.any((vals == 0.0) & np.signbit(vals)) or col.str.contains(r"[^0-9+-]", regex=True).any()
        ):  # pandas keeps -0.0 unless every entry is an integer literal (then it reads integers: 0)
            return pd.Series(vals, index=col.index, name=col.name)
    return pd.to_numeric(col, errors="coerce")


# ---------------------------------------------------------------- kinematics
def trapezoid_profile(t: np.ndarray, v_mm_s: float, a_mm_s2: float, t_rev_s: float, x0_mm: float = 0.0):
    """Displacement and velocity of the test machine's out-and-back motion.

    Constant acceleration ``a`` from rest to the cruise speed ``v``, cruise,
    constant deceleration reaching the turning point at ``t_rev`` (velocity
    zero there), and the mirror image back to rest at ``2 t_rev``.

    Parameters
    ----------
    t : array, s
    v_mm_s : float
        Cruise speed (mm/s), > 0.
    a_mm_s2 : float
        Acceleration (mm/s²), > 0.
    t_rev_s : float
        Time of the turning point (s).
    x0_mm : float
        Displacement at rest (mm).

    Returns
    -------
    x_mm, v_mm_s : arrays
    """
    t = np.asarray(t, float)
    ta, tm, x = _trapezoid_x(t, v_mm_s, a_mm_s2, t_rev_s)
    vel = np.where(tm < ta, a_mm_s2 * tm, np.where(tm < t_rev_s - ta, v_mm_s, a_mm_s2 * np.clip(t_rev_s - tm, 0, None)))
    sign = np.where(t <= t_rev_s, 1.0, -1.0)
    vel = np.where((t < 0) | (t > 2 * t_rev_s), 0.0, vel * sign)
    return x0_mm + x, vel


def _trapezoid_x(t: np.ndarray, v_mm_s: float, a_mm_s2: float, t_rev_s: float):
    """The displacement of :func:`trapezoid_profile` from rest (without ``x0``), with ``ta`` and the mirrored time ``tm`` it is built from.

    ``t`` a float array (s); the other arguments as for :func:`trapezoid_profile`. Returns ``(ta, tm, x)``.
    """
    ta = v_mm_s / a_mm_s2
    tm = np.minimum(t, 2 * t_rev_s - t)  # mirror about the turning point
    tm = np.clip(tm, 0.0, None)
    # outward ramp
    x = np.where(
        tm < ta,
        0.5 * a_mm_s2 * tm**2,
        np.where(
            tm < t_rev_s - ta,
            0.5 * a_mm_s2 * ta**2 + v_mm_s * (tm - ta),
            v_mm_s * (t_rev_s - ta) - 0.5 * a_mm_s2 * np.clip(t_rev_s - tm, 0, None) ** 2,
        ),
    )
    return ta, tm, x


def _trapezoid_jac(t: np.ndarray, v_mm_s: float, a_mm_s2: float, t_rev_s: float) -> np.ndarray:
    """Jacobian of ``x0 + _trapezoid_x(t, v, a, t_rev)[2]`` with respect to ``(v, a, t_rev, x0)``.

    ``t`` a float array (s); the other arguments as for :func:`trapezoid_profile`. Returns an array of shape
    ``(len(t), 4)``: columns in mm/(mm/s), mm/(mm/s²), mm/s and 1. Exact away from the kinks (branch changes,
    ``t == t_rev``, the clip of the mirrored time at 0), where it takes one one-sided derivative.

    With ``ta = v/a``, ``tm = max(min(t, 2 t_rev - t), 0)`` (``d tm/d t_rev`` is 2 where the mirror is taken
    and not clipped, else 0) and ``u = max(t_rev - tm, 0)``, the branches of :func:`_trapezoid_x` are
    ``a tm²/2`` (ramp), ``v tm - v²/(2a)`` (cruise) and ``v t_rev - v²/a - a u²/2`` (deceleration).
    """
    v, a, tr = v_mm_s, a_mm_s2, t_rev_s
    ta = v / a
    mir = 2 * tr - t
    tm = np.minimum(t, mir)
    dtm = np.where((t > mir) & (tm > 0.0), 2.0, 0.0)  # d tm / d t_rev
    tm = np.clip(tm, 0.0, None)
    ramp = tm < ta
    cruise = ~ramp & (tm < tr - ta)
    u = tr - tm
    du = np.where(u > 0.0, 1.0 - dtm, 0.0)
    u = np.clip(u, 0.0, None)
    jac = np.empty((len(t), 4))
    jac[:, 0] = np.where(ramp, 0.0, np.where(cruise, tm - ta, tr - 2 * ta))
    jac[:, 1] = np.where(ramp, 0.5 * tm**2, np.where(cruise, 0.5 * ta**2, ta**2 - 0.5 * u**2))
    jac[:, 2] = np.where(ramp, a * tm * dtm, np.where(cruise, v * dtm, v - a * u * du))
    jac[:, 3] = 1.0
    return jac


def _fit_profile(t: np.ndarray, x: np.ndarray):
    """Least-squares fit of :func:`trapezoid_profile`; returns (params, rms, x_fit, v_fit)."""
    k = int(np.argmax(x))
    t_rev0 = t[k]
    v0 = max((x[k] - x[0]) / max(t_rev0 - t[0], 1e-9), 1e-6)
    ta0 = min(0.2, 0.2 * t_rev0)
    p0 = np.array([v0, v0 / ta0, t_rev0, x[0]])
    # better start: straight lines through the cruise parts of both ramps
    span = x[k] - x[0]
    up = (np.arange(len(x)) < k) & (x > x[0] + 0.2 * span) & (x < x[0] + 0.8 * span)
    dn = (np.arange(len(x)) > k) & (x > x[0] + 0.2 * span) & (x < x[0] + 0.8 * span)
    if up.sum() >= 3 and dn.sum() >= 3:
        vu, bu = np.polyfit(t[up], x[up] - x[0], 1)
        vd, bd = np.polyfit(t[dn], x[dn] - x[0], 1)
        if vu > 0 and vd < 0:
            t1, t2 = -bu / vu, -bd / vd
            vv = 0.5 * (vu - vd)
            tr = 0.5 * (t1 + t2)
            ta = float(np.clip(2 * t1, 1e-3 * tr, 0.45 * tr))
            p0 = np.array([vv, vv / ta, tr, x[0]])

    tf = np.asarray(t, float)

    def res(p):  # trapezoid_profile(t, *p)[0] - x, without the velocity it would compute and drop
        return (p[3] + _trapezoid_x(tf, p[0], p[1], p[2])[2]) - x

    def jac(p):  # analytic: the profile is piecewise quadratic in (v, a, t_rev, x0)
        return _trapezoid_jac(tf, p[0], p[1], p[2])

    lo = [1e-9, 1e-9, t[0], -np.inf]
    hi = [np.inf, np.inf, t[-1], np.inf]
    best = None
    p0[2] = np.clip(p0[2], t[0], t[-1])
    for scale in (1.0, 0.3, 3.0):  # further acceleration guesses only if needed: the kink makes the cost non-smooth
        q0 = p0.copy()
        q0[1] = p0[1] * scale
        try:
            sol = least_squares(res, q0, jac=jac, bounds=(lo, hi), x_scale=np.abs(q0) + 1e-3, method="trf")
        except ValueError:
            continue
        if best is None or sol.cost < best.cost:
            best = sol
        noise = np.std(np.diff(x, 2)) / np.sqrt(6.0)
        if np.sqrt(2 * best.cost / len(x)) < 2.0 * noise:
            break
    if best is None:
        raise ValueError("the motion profile could not be fitted")
    p = best.x
    xf, vf = trapezoid_profile(t, *p)
    rms = float(np.sqrt(np.mean((xf - x) ** 2)))
    return p, rms, xf, vf


def _savgol_velocity(t: np.ndarray, x: np.ndarray) -> np.ndarray:
    """Savitzky-Golay derivative on each monotone segment (split at the turning sample)."""
    n = len(x)
    k = int(np.argmax(x))
    v = np.zeros(n)
    for a, b in ((0, k + 1), (k, n)):
        seg_t, seg_x = t[a:b], x[a:b]
        m = len(seg_x)
        if m < 3:
            continue
        w = min(11, m if m % 2 == 1 else m - 1)
        poly = min(2, w - 1)
        dt = float(np.median(np.diff(seg_t)))
        dv = savgol_filter(seg_x, w, poly, deriv=1, delta=dt, mode="interp")
        if a == 0:
            v[a:b] = dv
        else:
            v[k] = 0.5 * (v[k] + dv[0])
            v[k + 1 : b] = dv[1:]
    return v


def _time_since_reversal(t: np.ndarray, v: np.ndarray) -> np.ndarray:
    """Time since the last start or reversal of motion (s) at every sample of one experiment.

    ``t`` the sample times (s), ``v`` the velocity (mm/s); speeds up to 1e-9 mm/s count as rest. A start or
    reversal happens at a sample whose sign of ``v`` is non-zero and differs from the last non-zero sign
    before it (none before counts as 0); it is dated at the sample before (the first sample if it is the
    first). Before the first one the time counts from the first sample.
    """
    sgn = np.sign(np.where(np.abs(v) > 1e-9, v, 0.0))
    moving = np.flatnonzero(sgn != 0)
    s_moving = sgn[moving]
    events = moving[np.r_[True, s_moving[1:] != s_moving[:-1]]] if len(moving) else moving
    latest = np.full(len(t), -1)
    latest[events] = np.arange(len(events))
    latest = np.maximum.accumulate(latest)  # index into events of the last one at or before each sample
    event_time = np.r_[t[0], t[np.maximum(events - 1, 0)]]
    return t - event_time[latest + 1]


def _derive(d: pd.DataFrame, bounds: np.ndarray, names: np.ndarray, source: str, notes: tuple = (),
            line_offset: int = 0, line_numbers=None) -> Recordings:
    t_all = d["time_s"].to_numpy()
    x_all = d["displacement_mm"].to_numpy()
    p2_all, valve_all = d["p2_MPa"].to_numpy(), d["valve_deg"].to_numpy()
    speed_all = d["speed_mm_s"].to_numpy() if "speed_mm_s" in d.columns else None
    clock_all = d["clock_s"].to_numpy(float) if "clock_s" in d.columns else None
    if clock_all is not None and not np.all(np.isfinite(clock_all)):
        i = int(np.flatnonzero(~np.isfinite(clock_all))[0])
        raise RecordingsError(f"{_where(source, i, line_offset, line_numbers)}: column clock_s is not finite (the absolute time of every sample, s)")
    n = len(d)
    vel = np.zeros(n)
    tsr = np.zeros(n)
    ctime = np.zeros(n)
    exp_index = np.zeros(n, dtype=int)
    rows = []
    noise = []
    turning = np.zeros(n, dtype=bool)
    offset = 0.0
    for k in range(len(names)):
        a, b = bounds[k], bounds[k + 1]
        t, x = t_all[a:b], x_all[a:b]
        # displacement noise from second differences of the interior
        d2 = np.diff(x, 2)
        sig = float(1.4826 * np.median(np.abs(d2 - np.median(d2))) / np.sqrt(6.0))
        noise.append(sig)
        span = float(np.ptp(x))
        if not np.isfinite(span) or span <= max(20.0 * sig, 1e-6 * max(np.max(np.abs(x)), 1.0)):
            raise RecordingsError(
                f"{_where(source, int(a), line_offset, line_numbers)}: experiment {names[k]!r} does not move: its "
                f"displacement spans {span:.3g} mm (noise {sig:.2g} mm); every experiment must be a loading-unloading "
                "cycle -- remove the static recording or check the displacement column"
            )
        try:
            p, rms, _, vf = _fit_profile(t, x)
        except (ValueError, FloatingPointError, np.linalg.LinAlgError):
            p, rms, vf = None, np.inf, None
        tol = max(4.0 * sig, 1e-3 * max(np.ptp(x), 1e-9))
        if rms <= tol:
            v, method = vf, "profile"
        else:
            v, method = _savgol_velocity(t, x), "savgol"
        vel[a:b] = v
        if p is None:  # no profile: the cruise speed is the largest smoothed speed
            p = np.array([float(np.max(np.abs(v))) or 1e-9, np.nan, t[int(np.argmax(x))], x[0]])
        if method == "profile":
            # samples that fall on the start, the turning point or the end of
            # the motion (within a tenth of a sample step) are at rest
            dt_med = float(np.median(np.diff(t)))
            for tz in (0.0, p[2], 2 * p[2]):
                i = int(np.argmin(np.abs(t - tz)))
                if abs(t[i] - tz) < 0.1 * dt_med:
                    turning[a + i] = True
        tsr[a:b] = _time_since_reversal(t, v)
        ctime[a:b] = offset + (t - t[0]) if clock_all is None else clock_all[a:b] - clock_all.min()
        offset += (t[-1] - t[0]) + float(np.median(np.diff(t)))
        exp_index[a:b] = k
        speed = float(speed_all[a]) if speed_all is not None else float(p[0])
        rows.append(
            dict(
                experiment=names[k],
                p2_MPa=float(p2_all[a]),
                valve_deg=float(valve_all[a]),
                speed_mm_s=speed,
                n_samples=int(b - a),
                velocity_method=method,
                profile_rms_mm=rms,
                fitted_speed_mm_s=float(p[0]),
                fitted_accel_mm_s2=float(p[1]),
            )
        )
    out = d.copy()
    if "speed_mm_s" not in out.columns:
        out["speed_mm_s"] = np.repeat([r["speed_mm_s"] for r in rows], np.diff(bounds))
    out["velocity_mm_s"] = vel
    cruise = np.repeat([r["fitted_speed_mm_s"] for r in rows], np.diff(bounds))
    out["at_rest"] = (np.abs(vel) <= REST_FRACTION * np.abs(cruise)) | turning
    out["direction"] = np.where(out["at_rest"], 0, np.sign(vel)).astype(int)
    out["time_since_reversal_s"] = tsr
    out["campaign_time_s"] = ctime
    out["exp_index"] = exp_index
    experiments = pd.DataFrame(rows)
    return Recordings(
        data=out,
        experiments=experiments,
        source=source,
        rows_read=n,
        rows_left_out=0,
        displacement_noise_mm=float(np.median(noise)),
        notes=tuple(notes),
    )
