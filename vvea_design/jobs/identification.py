"""The identification side's jobs: ``vvea identify`` (eq. 14, Table 3, Figs 10/11) and ``vvea diagnose``
(where eq. 14 and the recordings disagree, the left-out physics named and fitted) as functions."""

from __future__ import annotations

import contextlib
import tempfile
from collections.abc import Callable, Iterable, Iterator, Mapping
from dataclasses import dataclass, field, replace
from pathlib import Path
from typing import TYPE_CHECKING, Any

from .common import (OptionError, PathLike, check_option, check_out, design_of, folder, inputs_kept, lazy_errors,
                     moved)

if TYPE_CHECKING:
    from ..identification.identify import Identification
    from ..identification.recordings import Recordings
    from ..identification.report import Diagnosis, DiagnosisReport
    from ..spring.design import Design
    from ..spring.gas_spring import GasSpring

__all__ = ["identify", "DiagnosisRun", "diagnose", "RecordingsError", "DesignFileError"]

#: The errors these jobs raise, imported on first use.
__getattr__ = lazy_errors(__name__, ("RecordingsError", "DesignFileError"))


def _reference(design: Design | GasSpring | PathLike | None, progress: bool) -> tuple[GasSpring, Any]:
    """The unit on the bench, said on stderr: its spring, and what the recordings are checked against.

    A design file is rebuilt from its decision variables (:func:`~vvea_design.jobs.common.design_of`); the
    second value is that design (its travel, g per MPa and wall capacity bound the recordings), the spring
    given, or None for the paper's Fig. 5 unit.
    """
    from ..identification.fit_data import REFERENCE_NOTE
    from ..progress import console
    from ..spring.gas_spring import GasSpring
    from ..spring.paper import PAPER_FIG5

    if design is None:
        text, ref, unit = f"note: {REFERENCE_NOTE}", PAPER_FIG5, None
    else:
        unit = design if isinstance(design, GasSpring) else design_of(design)
        ref = unit if isinstance(unit, GasSpring) else unit.gas_spring
        text = (f"unit from {design if isinstance(design, (str, Path)) else 'the design given'}: A1 = "
                f"{ref.A1_mm2:.0f} mm^2, A2 = {ref.A2_mm2:.0f} mm^2, V1 = {ref.V1_mm3:.4g} mm^3, V2 = "
                f"{ref.V2_mm3:.4g} mm^3, travel {ref.travel_mm:g} mm")
    if progress:
        console.print(text, markup=False, highlight=False, soft_wrap=True)
    return ref, unit


def _recordings(recordings: Recordings | PathLike, progress: bool, units: Mapping[str, str] | None = None,
                negate: Iterable[str] = (), unit: Any = None) -> Recordings:
    """The campaign, read from its file (a spinner on stderr) unless given, checked against ``unit``."""
    from ..identification.recordings import Recordings, read_recordings
    from ..progress import progress_bar

    if isinstance(recordings, Recordings):
        return recordings
    path = Path(recordings)
    with progress_bar(f"reading {path.name} (velocity from the motion profile)", total=None, enabled=progress):
        return read_recordings(path, units=units, negate=tuple(negate), reference=unit)


def _within_rating(rec: Recordings, design: Any, allow_over_rating: bool) -> Recordings:
    """Refuse recordings charged above the ``design``'s rating unless asked for; then their notes say so.

    The rating is :func:`vvea_design.jobs.rating.charge_rating` (the ``max_charge_MPa`` the design was optimised
    for, or the charge its walls are sized for); without a design (the paper's unit) or for a bare gas spring
    there is none.
    """
    from ..spring.gas_spring import GasSpring

    if design is None or isinstance(design, GasSpring) or "p2_MPa" not in rec.data:
        return rec
    from ..identification.recordings import RecordingsError
    from .rating import check_charge

    p = float(rec.data["p2_MPa"].max())
    try:
        label = check_charge(design, p, allow_over_rating=allow_over_rating)
    except OptionError as exc:
        raise RecordingsError(f"{rec.source}: column p2_MPa: the highest charge p2 {exc.reason}") from None
    return replace(rec, notes=tuple(rec.notes) + (label,)) if label else rec


def identify(recordings: Recordings | PathLike, *, design: Design | GasSpring | PathLike | None = None,
             units: Mapping[str, str] | None = None, negate: Iterable[str] = (), out: PathLike | None = None,
             progress: bool = True, allow_over_rating: bool = False) -> Identification:
    """Fit the paper's eq. 14 (g, C, one L per valve) with uncertainties; Table 3, Figs 10 and 11 (``vvea identify``).

    Parameters
    ----------
    recordings : Recordings or path-like
        The campaign, or its file (CSV or Parquet, ``shared/specs/recordings.md``).
    design : Design, GasSpring or path-like, optional
        The unit on the bench (eq. 14 has no gas-law term: it is named so the user knows which one is
        assumed; a recording whose travel, force scale or charge cannot be this unit's is refused); None:
        the paper's Fig. 5 unit.
    units : mapping of str to str, optional
        Column -> the unit it was recorded in (``{"force_N": "kN", "displacement_mm": "m"}``), converted to
        the format's unit; a column given a unit is not questioned for its scale (a file only).
    negate : iterable of str
        Columns recorded with the opposite sign convention (``("force_N",)``), negated (a file only).
    out : path-like, optional
        Folder for ``table3.csv``, ``identification.json`` and the figures; None: numbers only (no figures).
    progress : bool
        Say which unit is assumed and show spinners on stderr.
    allow_over_rating : bool
        Fit recordings charged above the ``design``'s rating (:mod:`vvea_design.jobs.rating`); their notes (and
        ``identification.json``) then carry the label.

    Returns
    -------
    Identification
        Table 3 (values in their units), the RMS error (N), the error band (% of nominal force),
        identifiability, notes and the names of the files written (none without ``out``).

    Raises
    ------
    OutputError
        ``out`` cannot be written (before any work).
    DesignFileError
        A design file that is missing or incomplete.
    RecordingsError
        A recordings file that cannot be read (names the file, row and column), or charged above the
        ``design``'s rating without ``allow_over_rating``.
    """
    from ..identification.identify import write_identification
    from ..progress import progress_bar

    check_out(out)
    inputs_kept((out,), (recordings, design))
    _, unit = _reference(design, progress)
    rec = _within_rating(_recordings(recordings, progress, units, negate, unit), design, allow_over_rating)
    with progress_bar("fitting eq. 14 and drawing Figs 10/11", total=None, enabled=progress), \
            folder(out, "identify", names=("table3.csv", "identification.json")) as tmp:
        if tmp is not None:
            return write_identification(rec, tmp)
        with tempfile.TemporaryDirectory() as scratch:
            return replace(write_identification(rec, scratch, figures=False), files=())


@dataclass(frozen=True)
class DiagnosisRun:
    """What :func:`diagnose` found: the diagnosis, its text summary and the files written."""

    diagnosis: Diagnosis  #: the typed report and the fitted models
    summary_text: str  #: the summary printed by ``vvea diagnose`` (also ``summary.md``)
    files: dict[str, Path] = field(default_factory=dict)  #: by file name, ``report.html`` last (empty: none)

    @property
    def report(self) -> DiagnosisReport:
        """The typed report (:meth:`DiagnosisReport.to_dict` is ``report.json``)."""
        return self.diagnosis.report

    def to_dict(self) -> dict[str, Any]:
        """JSON-ready.

        Returns
        -------
        dict
            ``report`` (the ``report.json`` content: forces in N, run time in s), ``summary_text`` and
            ``files`` (paths as text).
        """
        return {"report": self.report.to_dict(), "summary_text": self.summary_text,
                "files": {k: str(v) for k, v in self.files.items()}}


@contextlib.contextmanager
def _spinner(enabled: bool) -> Iterator[Callable[[str], None]]:
    """``say(message)``: a spinner on stderr reading ``diagnosing: <message>``."""
    if not enabled:
        yield lambda msg: None
        return
    from rich.progress import Progress, SpinnerColumn, TextColumn, TimeElapsedColumn

    from ..progress import console

    with Progress(SpinnerColumn(), TextColumn("[bold]{task.description}"), TimeElapsedColumn(), console=console) as prog:
        task = prog.add_task("diagnosing", total=None)
        yield lambda msg: prog.update(task, description=f"diagnosing: {msg}")


def diagnose(recordings: Recordings | PathLike, *, design: Design | GasSpring | PathLike | None = None, seed: int = 0,
             learner: bool = True, units: Mapping[str, str] | None = None, negate: Iterable[str] = (),
             out: PathLike | None = None, progress: bool = True, allow_over_rating: bool = False) -> DiagnosisRun:
    """Locate where eq. 14 and the recordings disagree, name and fit the left-out physics (``vvea diagnose``).

    Parameters
    ----------
    recordings : Recordings or path-like
        The campaign, or its file (CSV or Parquet).
    design : Design, GasSpring or path-like, optional
        The unit on the bench: its areas, V1, V2 and travel shape the gas terms; None: the paper's
        Fig. 5 unit.
    seed : int
        Seed of the held-out and cross-validation splits.
    learner : bool
        Run the flexible-learner check for leftover structure.
    units : mapping of str to str, optional
        Column -> the unit it was recorded in, converted (a file only; see :func:`identify`).
    negate : iterable of str
        Columns recorded with the opposite sign convention, negated (a file only).
    out : path-like, optional
        Folder for ``report.json``, ``final_model.json``, ``summary.md``, the figures and ``report.html``.
    progress : bool
        Say which unit is assumed and show a spinner with the current stage on stderr.
    allow_over_rating : bool
        Diagnose recordings charged above the ``design``'s rating; the summary (and ``report.html``) then
        starts with the label.

    Returns
    -------
    DiagnosisRun
        The diagnosis (RMS errors in N), its text summary and the files written.

    Raises
    ------
    OutputError
        ``out`` cannot be written (before any work).
    DesignFileError
        A design file that is missing or incomplete.
    RecordingsError
        A recordings file that cannot be read, or charged above the ``design``'s rating without
        ``allow_over_rating``.
    """
    from ..identification.diagnose import DiagnoseSettings, diagnose as run, format_summary, write_diagnosis
    from ..report.html import write_folder_report

    check_option("seed", seed, "seed")
    check_out(out)
    inputs_kept((out,), (recordings, design))
    reference, unit = _reference(design, progress)
    rec = _within_rating(_recordings(recordings, progress, units, negate, unit), design, allow_over_rating)
    with _spinner(progress) as say:
        diag = run(rec, DiagnoseSettings(seed=seed, learner=learner), progress=say, reference=reference)
    text = format_summary(diag.report)
    over = [n for n in rec.notes if n.startswith("OVER RATING")]
    if over:  # every output of a campaign charged above the rating says so
        text = "\n".join([*over, text])
    written: dict[str, Path] = {}
    with folder(out, "diagnose") as tmp:  # the report and its figures land together
        if tmp is not None:
            written = {name: tmp / name for name in write_diagnosis(diag, tmp)}
            name = Path(recordings).name if isinstance(recordings, (str, Path)) else Path(rec.source).name
            html = write_folder_report(f"vvea diagnose: {name}", tmp, summary_text=text, data=diag.report.to_dict(),
                                       label=str(out), provenance={"recordings": recordings, "design": design,
                                                                   "seed": seed, "learner": learner})
            written[html.name] = html
    if out is not None:
        written = {k: moved(v, tmp, Path(out)) for k, v in written.items()}
    return DiagnosisRun(diag, text, written)
