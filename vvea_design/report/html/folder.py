"""The report of a command's result folder (``vvea study``, ``vvea diagnose``): :func:`folder_report`."""

from __future__ import annotations

import html
import io
import json
from collections.abc import Callable, Sequence
from pathlib import Path
from typing import Any

from ... import __version__
from .page import HtmlReport, Section, image, preformatted, table

__all__ = ["folder_report", "recorded_text", "write_folder_report"]


# ------------------------------------------------------------ folder report
def folder_report(title: str, folder: str | Path, *, summary_text: str = "",
                  tables: Sequence[tuple[str, Sequence[str], Sequence[Sequence[Any]]]] = (),
                  data: dict | None = None, provenance: dict | None = None, label: str | None = None) -> HtmlReport:
    """A report of a command's result folder: its summary, tables, every PNG in it, its data.

    Parameters
    ----------
    title : str
        Page title.
    folder : path-like
        The result folder; every ``*.png`` in it (sorted, not recursive) is inlined.
    summary_text : str
        The command's text summary (shown monospaced).
    tables : sequence of (title, header, rows)
        Tables to show (put units in the headers).
    data : dict, optional
        The result as JSON (shown last, pretty-printed).
    provenance : dict, optional
        Inputs, settings and seed; the version is added.
    label : str, optional
        How the folder is named on the page (default: its path; commands that write into a temporary
        folder moved into place at the end pass the final path).

    Returns
    -------
    HtmlReport
        Call ``.write(path)``.
    """
    folder = Path(folder)
    sections = []
    if summary_text:
        sections.append(Section("Summary", preformatted(summary_text)))
    for t_title, header, rows in tables:
        sections.append(Section(t_title, table(header, rows)))
    pngs = sorted(folder.glob("*.png"))
    if pngs:
        sections.append(Section("Figures", "".join(image(p, p.stem.replace("_", " ")) for p in pngs)))
    prov = {"vvea-design version": __version__, **(provenance or {})}
    sections.append(Section("Provenance", table(("item", "value"), [(k, str(v)) for k, v in prov.items()])))
    if data is not None:
        text = json.dumps(data, indent=2, default=str)
        if len(text) > 400_000:
            text = text[:400_000] + "\n... (cut; the full result is in the folder's JSON)"
        sections.append(Section("Result data", preformatted(text)))
    return HtmlReport(title, tuple(sections), html.escape(str(folder) if label is None else label))


def recorded_text(print_to: "Callable[[Any], None]") -> str:
    """Plain text of what ``print_to(console)`` prints on a rich console (tables included), unwrapped.

    Parameters
    ----------
    print_to : callable
        Called with a recording :class:`rich.console.Console`.

    Returns
    -------
    str
        The text, no colour codes.
    """
    from rich.console import Console

    rec = Console(record=True, width=200, file=io.StringIO(), color_system=None)
    print_to(rec)
    return rec.export_text().rstrip("\n")


def write_folder_report(title: str, folder: str | Path, **kwargs: Any) -> Path:
    """Write ``report.html`` into ``folder`` (see :func:`folder_report`).

    Parameters
    ----------
    title : str
        Page title.
    folder : path-like
        The result folder.
    **kwargs
        Passed to :func:`folder_report`.

    Returns
    -------
    Path
        ``folder / "report.html"``.
    """
    return folder_report(title, folder, **kwargs).write(Path(folder) / "report.html")
