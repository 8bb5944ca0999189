"""The page of a report: :class:`Section`, :class:`HtmlReport` (one self-contained HTML5 document, its CSS)
and the block helpers every section is made of (tables, paragraphs, verdicts, inline figures).
"""

from __future__ import annotations

import base64
import html
import io
import re
from collections.abc import Iterable, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

if TYPE_CHECKING:  # pragma: no cover
    from matplotlib.figure import Figure

__all__ = ["Section", "HtmlReport", "table", "paragraph", "verdict", "pass_fail", "figure_svg", "image",
           "preformatted", "MAX_REPORT_BYTES"]

#: The size a report must stay under (bytes): 5 MB.
MAX_REPORT_BYTES = 5_000_000


# ----------------------------------------------------------------- structure
@dataclass(frozen=True)
class Section:
    """One titled part of a report; ``body`` is HTML made with the block helpers of this module."""

    title: str  #: heading
    body: str  #: HTML content (already escaped)
    anchor: str = ""  #: id for the table of contents (default: from the title)

    @property
    def id(self) -> str:
        """The HTML id of the section.

        Returns
        -------
        str
            ``anchor`` or a slug of ``title``.
        """
        if self.anchor:
            return self.anchor
        return "".join(c if c.isalnum() else "-" for c in self.title.lower()).strip("-")


@dataclass(frozen=True)
class HtmlReport:
    """A whole page: title, sections, inline scripts."""

    title: str  #: page title and top heading
    sections: tuple[Section, ...]  #: in order
    subtitle: str = ""  #: one line under the title (HTML)
    scripts: tuple[str, ...] = field(default=())  #: inline JavaScript, in order, after the content

    def render(self) -> str:
        """The page as one HTML string.

        Returns
        -------
        str
            A complete HTML5 document with no external reference.
        """
        toc = "".join(f'<li><a href="#{s.id}">{html.escape(s.title)}</a></li>' for s in self.sections)
        body = "".join(f'<section id="{s.id}"><h2>{html.escape(s.title)}</h2>{s.body}</section>'
                       for s in self.sections)
        scripts = "".join(f"<script>{_script_safe(js)}</script>" for js in self.scripts)
        return (
            "<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\">"
            "<meta name=\"viewport\" content=\"width=device-width, initial-scale=1\">"
            # a data: favicon keeps the browser from asking for /favicon.ico
            "<link rel=\"icon\" href=\"data:,\">"
            f"<title>{html.escape(self.title)}</title><style>{_CSS}</style></head><body>"
            f"<header><h1>{html.escape(self.title)}</h1><p class=\"sub\">{self.subtitle}</p>"
            f"<nav><ul>{toc}</ul></nav></header><main>{body}</main>{scripts}</body></html>\n"
        )

    def write(self, path: str | Path) -> Path:
        """Write the page (UTF-8) and return its path.

        Parameters
        ----------
        path : path-like
            File to write; its folder is created.

        Returns
        -------
        Path
            ``path``.

        Raises
        ------
        ValueError
            The page would exceed :data:`MAX_REPORT_BYTES`.
        """
        data = self.render().encode("utf-8")
        if len(data) > MAX_REPORT_BYTES:
            raise ValueError(f"report {path} would be {len(data) / 1e6:.1f} MB, over the "
                             f"{MAX_REPORT_BYTES / 1e6:.0f} MB limit")
        path = Path(path)
        path.parent.mkdir(parents=True, exist_ok=True)
        path.write_bytes(data)
        return path


def _script_safe(js: str) -> str:
    return js.replace("</script", "<\\/script")


_CSS = """
body{font-family:system-ui,-apple-system,'Segoe UI',Roboto,'DejaVu Sans',sans-serif;margin:0;color:#1d2430;
background:#fff;line-height:1.4}
header{background:#1f3a5f;color:#fff;padding:14px 28px}
header h1{margin:0;font-size:1.5em} .sub{margin:4px 0 8px 0;opacity:.9}
nav ul{list-style:none;padding:0;margin:0;display:flex;flex-wrap:wrap;gap:4px 16px;font-size:.9em}
nav a{color:#cfe1ff;text-decoration:none}
main{padding:8px 28px 40px 28px;max-width:1250px}
section{margin-top:22px;border-top:1px solid #dde3ea;padding-top:6px}
h2{font-size:1.2em;color:#1f3a5f}
table{border-collapse:collapse;margin:6px 0 12px 0;font-size:.9em}
th,td{border:1px solid #d5dbe3;padding:3px 8px;text-align:left}
td.num{text-align:right;font-variant-numeric:tabular-nums;white-space:nowrap}
.tw{max-width:100%;overflow-x:auto}
th{background:#eef2f7;white-space:normal;vertical-align:bottom}
.pass{color:#106b21;font-weight:600} .fail{color:#b00020;font-weight:600} .warn{color:#8a5a00;font-weight:600}
.verdict{font-size:1.1em;padding:8px 12px;border-radius:4px;display:inline-block;margin:6px 0}
.verdict.pass{background:#e3f4e6} .verdict.fail{background:#fbe4e7}
figure{margin:8px 0 16px 0} figcaption{font-size:.85em;color:#4a5566;max-width:1000px}
figure svg,figure img{max-width:100%;height:auto;border:1px solid #eef0f3}
figure img{max-width:min(100%,1000px)} figure svg,figure img,#viewer{box-sizing:border-box}
pre{background:#f6f8fa;padding:8px;overflow:auto;font-size:.8em;max-height:420px}
.viewer-wrap{position:relative;width:100%;max-width:1000px}
#viewer{width:100%;height:520px;display:block;border:1px solid #d5dbe3;background:#f4f6f8;touch-action:none}
.viewer-tools{margin:6px 0;display:flex;gap:6px;flex-wrap:wrap}
.viewer-tools button{font:inherit;font-size:.85em;padding:3px 10px;border:1px solid #9aa8ba;background:#fff;
border-radius:3px;cursor:pointer} .viewer-tools button.on{background:#1f3a5f;color:#fff}
.viewer-stage{position:relative}
.viewer-labels{position:absolute;inset:0;pointer-events:none;overflow:hidden}
.viewer-labels span{position:absolute;transform:translate(-50%,-50%);background:#fffd;border:1px solid #9aa8ba;
border-radius:3px;padding:1px 6px;font-size:.8em;white-space:nowrap}
.legend span{display:inline-block;margin-right:14px;font-size:.85em}
.legend i{display:inline-block;width:11px;height:11px;margin-right:4px;vertical-align:-1px;border:1px solid #0003}
.note{font-size:.9em;color:#4a5566}
.swatches span{display:inline-block;margin-right:14px;font-size:.85em;white-space:nowrap}
.swatches i{display:inline-block;width:22px;height:0;margin-right:5px;vertical-align:3px;border-top-width:3px}
a.sheet{display:block;color:inherit}
td{overflow-wrap:break-word}
@media (max-width:640px){
header{padding:10px 12px} main{padding:4px 12px 30px 12px}
table{font-size:.82em} th,td{padding:2px 5px}
table.wide,table.wide tbody,table.wide tr,table.wide td{display:block}
table.wide thead{display:none}
table.wide tr{border:1px solid #d5dbe3;margin:0 0 8px 0}
table.wide td{border:0;border-bottom:1px solid #eef0f3;text-align:left;white-space:normal}
table.wide td::before{content:attr(data-label);display:inline-block;width:46%;margin-right:4%;font-weight:600;
color:#4a5566;vertical-align:top}
}
"""


# -------------------------------------------------------------- block helpers
def _fmt(v: Any) -> str:
    if isinstance(v, bool):
        return "yes" if v else "no"
    if isinstance(v, (float, np.floating)):
        if not np.isfinite(v):
            return "–"
        return f"{float(v):.4g}"
    if v is None:
        return "–"
    return str(v)


_LONG_RUN = re.compile(r"[A-Za-z0-9]{20,}")


def _breakable(text: str) -> str:
    """Escaped cell text with line-break opportunities for a narrow screen: after each underscore and slash
    (constraint names, paths) and every 12 characters of a long run of letters and digits (a hash)."""
    text = text.replace("_", "_<wbr>").replace("/", "/<wbr>")
    return _LONG_RUN.sub(lambda m: "<wbr>".join(m.group(0)[k:k + 12] for k in range(0, len(m.group(0)), 12)), text)


#: Tables with this many columns or more are shown one row per card on a narrow screen (phone).
WIDE_TABLE_COLUMNS = 6


def table(header: Sequence[str], rows: Iterable[Sequence[Any]], *, raw_columns: Sequence[int] = (),
          num_columns: Sequence[int] = (), cards: bool = False) -> str:
    """An HTML table; numbers right-aligned with 4 significant digits.

    On a narrow screen (under 640 px: a phone) every cell may wrap, and a table of
    :data:`WIDE_TABLE_COLUMNS` or more columns shows each row as a card of "header: value" lines,
    so no table runs off the page; put the column a reader needs first (a verdict) first.

    Parameters
    ----------
    header : sequence of str
        Column titles (put the unit in the title).
    rows : iterable of sequences
        Cells; floats are formatted, everything else shown as ``str``.
    raw_columns : sequence of int
        Columns whose cells are HTML already (not escaped).
    num_columns : sequence of int
        Columns of numbers given as text (already formatted): right-aligned like numbers.
    cards : bool
        Show each row as a card on a phone whatever the number of columns (for columns of long text).

    Returns
    -------
    str
        The ``<table>`` element.
    """
    labels = [html.escape(str(h), quote=True) for h in header]
    head = "".join(f"<th>{h}</th>" for h in labels)
    body = []
    for row in rows:
        cells = []
        for i, v in enumerate(row):
            num = (isinstance(v, (int, float, np.number)) and not isinstance(v, bool)) or i in num_columns
            text = str(v) if i in raw_columns else _breakable(html.escape(_fmt(v)))
            label = f' data-label="{labels[i]}"' if i < len(labels) else ""
            cells.append(f'<td class="num"{label}>{text}</td>' if num else f"<td{label}>{text}</td>")
        body.append("<tr>" + "".join(cells) + "</tr>")
    wide = ' class="wide"' if cards or len(labels) >= WIDE_TABLE_COLUMNS else ""
    return (f'<div class="tw"><table{wide}><thead><tr>{head}</tr></thead><tbody>{"".join(body)}</tbody></table>'
            "</div>")


def paragraph(text: str, cls: str = "") -> str:
    """A paragraph of plain text (escaped).

    Parameters
    ----------
    text : str
        The text.
    cls : str
        Optional CSS class (``note``, ``pass``, ``fail``).

    Returns
    -------
    str
        The ``<p>`` element.
    """
    c = f' class="{cls}"' if cls else ""
    return f"<p{c}>{html.escape(text)}</p>"


def verdict(ok: bool, text: str) -> str:
    """A coloured PASS/FAIL line.

    Parameters
    ----------
    ok : bool
        Passed.
    text : str
        What passed or failed (plain text).

    Returns
    -------
    str
        HTML.
    """
    cls = "pass" if ok else "fail"
    return f'<div class="verdict {cls}">{"PASS" if ok else "FAIL"}: {html.escape(text)}</div>'


def pass_fail(ok: bool) -> str:
    """``PASS`` / ``FAIL`` as coloured HTML (for a ``raw_columns`` table cell).

    Parameters
    ----------
    ok : bool
        Passed.

    Returns
    -------
    str
        HTML span.
    """
    return '<span class="pass">PASS</span>' if ok else '<span class="fail">FAIL</span>'


def figure_svg(fig: "Figure", caption: str = "") -> str:
    """A matplotlib Figure inlined as SVG (text as paths: same look in every browser).

    Parameters
    ----------
    fig : matplotlib.figure.Figure
        Made without pyplot (``Figure()``), so no backend is selected.
    caption : str
        Plain-text caption.

    Returns
    -------
    str
        ``<figure>`` with the ``<svg>`` inside.
    """
    import matplotlib

    buf = io.StringIO()
    with matplotlib.rc_context({"svg.hashsalt": "vvea-design", "svg.fonttype": "path"}):
        fig.savefig(buf, format="svg", metadata={"Date": None, "Creator": "vvea-design"})
    svg = buf.getvalue()
    svg = svg[svg.index("<svg"):]  # drop the XML prolog and DOCTYPE
    cap = f"<figcaption>{html.escape(caption)}</figcaption>" if caption else ""
    return f"<figure>{svg}{cap}</figure>"


def image(png: str | Path | bytes, caption: str = "", alt: str = "") -> str:
    """A PNG inlined as a base64 ``data:`` URL.

    Parameters
    ----------
    png : path-like or bytes
        The PNG file or its bytes.
    caption : str
        Plain-text caption.
    alt : str
        Alternative text.

    Returns
    -------
    str
        ``<figure>`` with the ``<img>``.
    """
    data = png if isinstance(png, bytes) else Path(png).read_bytes()
    b64 = base64.b64encode(data).decode("ascii")
    cap = f"<figcaption>{html.escape(caption)}</figcaption>" if caption else ""
    return f'<figure><img alt="{html.escape(alt or caption)}" src="data:image/png;base64,{b64}">{cap}</figure>'


def preformatted(text: str) -> str:
    """Monospaced text (escaped), e.g. a command's summary.

    Parameters
    ----------
    text : str
        The text.

    Returns
    -------
    str
        ``<pre>`` element.
    """
    return f"<pre>{html.escape(text)}</pre>"
