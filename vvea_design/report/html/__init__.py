"""One self-contained ``report.html`` that opens offline.

Everything is inline: figures as SVG (matplotlib, no pyplot, so no backend
is touched), pictures as base64 PNG, the 3-D view as base64 mesh arrays
drawn by three.js (MIT, vendored as package data in ``report/vendor``; the
page makes no network request).

A report is built from sections (:class:`Section`, :class:`HtmlReport`, in
:mod:`~vvea_design.report.html.page`), so any wing can make one:
:func:`unit_report` for ``vvea design`` (:mod:`~vvea_design.report.html.unit`),
:func:`folder_report` for a command's result folder (``vvea study``,
``vvea diagnose``; :mod:`~vvea_design.report.html.folder`); the 3-D view is
:mod:`~vvea_design.report.html.viewer`.
"""

from .folder import folder_report, recorded_text, write_folder_report
from .page import (MAX_REPORT_BYTES, HtmlReport, Section, figure_svg, image, paragraph, pass_fail, preformatted,
                   table, verdict)
from .unit import MAX_INLINE_DRAWINGS_BYTES, UnitResult, unit_report
from .viewer import ViewerPart, viewer, viewer_parts_from_cad

__all__ = [
    "Section", "HtmlReport", "ViewerPart", "table", "paragraph", "verdict", "figure_svg", "image",
    "preformatted", "viewer", "viewer_parts_from_cad", "unit_report", "folder_report", "write_folder_report",
    "recorded_text", "pass_fail", "UnitResult",
    "MAX_REPORT_BYTES", "MAX_INLINE_DRAWINGS_BYTES",
]
