"""One self-contained ``report.html`` that opens offline.

Everything is inline: figures as SVG (matplotlib, no pyplot, so no backend
is touched), pictures as base64 PNG, the 3-D view as base64 mesh arrays
drawn by three.js (MIT, vendored as package data in ``report/vendor``; the
page makes no network request).

A report is built from sections (:class:`Section`, :class:`HtmlReport`), so
any wing can make one: :func:`unit_report` for ``vvea design``,
:func:`folder_report` for a command's result folder (``vvea study``,
``vvea diagnose``).
"""

from __future__ import annotations

import base64
import hashlib
import html
import io
import json
import platform
import sys
from collections.abc import Callable, Iterable, Sequence
from dataclasses import dataclass, field
from importlib import resources
from pathlib import Path
from typing import TYPE_CHECKING, Any, Protocol

import numpy as np

from .. import __version__

if TYPE_CHECKING:  # pragma: no cover
    from matplotlib.figure import Figure

    from ..actuator.design_study import DesignStudy
    from ..actuator.model import Actuator
    from ..bladder.check import BladderResult
    from ..cad.manifest import CadManifest
    from ..spring.curve import SpringCurve
    from ..spring.optimise import OptimisationResult
    from ..spring.requirements import Requirements
    from .bom import BillOfMaterials
    from .drawing import DrawingSet

__all__ = [
    "Section", "HtmlReport", "ViewerPart", "table", "paragraph", "verdict", "figure_svg", "image",
    "preformatted", "viewer", "viewer_parts_from_cad", "unit_report", "folder_report", "write_folder_report",
    "recorded_text", "pass_fail", "UnitResult",
    "MAX_REPORT_BYTES",
]

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
figure img{max-width:min(100%,1000px)}
pre{background:#f6f8fa;padding:8px;overflow:auto;font-size:.8em;max-height:420px}
.viewer-wrap{position:relative;width:100%;max-width:1000px}
#viewer{width:100%;height:520px;display:block;border:1px solid #d5dbe3;background:#f4f6f8;touch-action:none}
.viewer-tools{margin:6px 0;display:flex;gap:6px;flex-wrap:wrap}
.viewer-tools button{font:inherit;font-size:.85em;padding:3px 10px;border:1px solid #9aa8ba;background:#fff;
border-radius:3px;cursor:pointer} .viewer-tools button.on{background:#1f3a5f;color:#fff}
.legend span{display:inline-block;margin-right:14px;font-size:.85em}
.legend i{display:inline-block;width:11px;height:11px;margin-right:4px;vertical-align:-1px;border:1px solid #0003}
.note{font-size:.9em;color:#4a5566}
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


def table(header: Sequence[str], rows: Iterable[Sequence[Any]], *, raw_columns: Sequence[int] = ()) -> str:
    """An HTML table; numbers right-aligned with 4 significant digits.

    Parameters
    ----------
    header : sequence of str
        Column titles (put the unit in the title).
    rows : iterable of sequences
        Cells; floats are formatted, everything else shown as ``str``.
    raw_columns : sequence of int
        Columns whose cells are HTML already (not escaped).

    Returns
    -------
    str
        The ``<table>`` element.
    """
    head = "".join(f"<th>{html.escape(str(h))}</th>" for h in header)
    body = []
    for row in rows:
        cells = []
        for i, v in enumerate(row):
            num = isinstance(v, (int, float, np.number)) and not isinstance(v, bool)
            text = str(v) if i in raw_columns else html.escape(_fmt(v))
            cells.append(f'<td class="num">{text}</td>' if num else f"<td>{text}</td>")
        body.append("<tr>" + "".join(cells) + "</tr>")
    return f'<div class="tw"><table><thead><tr>{head}</tr></thead><tbody>{"".join(body)}</tbody></table></div>'


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


# ------------------------------------------------------------------ 3-D view
@dataclass(frozen=True, eq=False)
class ViewerPart:
    """One triangle mesh of the 3-D view (mm, CAD frame: z along the unit's axis)."""

    name: str  #: part name shown in the legend
    group: str  #: view it belongs to: "assembly" or "mould"
    color: str  #: CSS hex colour "#rrggbb"
    vertices_mm: np.ndarray  #: (n, 3) vertex positions, mm
    faces: np.ndarray  #: (m, 3) vertex indices
    opacity: float = 1.0  #: 1 opaque ... 0 invisible
    visible: bool = True  #: shown when the page opens

    def to_json(self) -> dict[str, Any]:
        """The part as the viewer script reads it (base64 float32 positions and uint32 indices).

        Returns
        -------
        dict
            name, group, color, opacity, visible, positions (base64), indices (base64).
        """
        pos = np.ascontiguousarray(self.vertices_mm, dtype="<f4")
        idx = np.ascontiguousarray(self.faces, dtype="<u4")
        return {"name": self.name, "group": self.group, "color": self.color, "opacity": float(self.opacity),
                "visible": bool(self.visible),
                "positions": base64.b64encode(pos.tobytes()).decode("ascii"),
                "indices": base64.b64encode(idx.tobytes()).decode("ascii")}


#: Colour, view, opacity, shown-at-start of each CAD file the 3-D view uses (mould parts opened apart).
_CAD_VIEW = {
    "housing": ("#a9b4c2", "assembly", 1.0, True),
    "piston": ("#5d6d7e", "assembly", 1.0, True),
    "bladder": ("#e07b39", "assembly", 1.0, True),
    "support_ring": ("#3b8f5a", "assembly", 1.0, True),
    "gas_chamber_1": ("#4f8fe0", "assembly", 0.35, False),
    "gas_chamber_2": ("#6fc3e8", "assembly", 0.35, False),
    "mould_half_a": ("#c9a227", "mould", 1.0, True),
    "mould_half_b": ("#d9b84a", "mould", 1.0, True),
    "mould_core": ("#8a6bb0", "mould", 1.0, True),
}
#: How far each mould part is moved to show the mould opened (mm, CAD frame).
_MOULD_OPEN_MM = {"mould_half_a": (0.0, 35.0, 0.0), "mould_half_b": (0.0, -35.0, 0.0)}


def viewer_parts_from_cad(cad_dir: str | Path) -> list[ViewerPart]:
    """The 3-D view's parts from a CAD folder's STL files (``vvea cad`` output).

    Parameters
    ----------
    cad_dir : path-like
        Folder holding ``housing.stl``, ``piston.stl``, ... (missing files are skipped).

    Returns
    -------
    list of ViewerPart
        Assembly at x = 0 and the opened mould, in mm.
    """
    import trimesh

    parts = []
    for name, (color, group, opacity, visible) in _CAD_VIEW.items():
        path = Path(cad_dir) / f"{name}.stl"
        if not path.exists():
            continue
        mesh = trimesh.load_mesh(path, file_type="stl", process=True)
        v = np.asarray(mesh.vertices, float) + np.asarray(_MOULD_OPEN_MM.get(name, (0.0, 0.0, 0.0)))
        parts.append(ViewerPart(name, group, color, v, np.asarray(mesh.faces), opacity, visible))
    return parts


def _vendored_three() -> str:
    return resources.files("vvea_design.report").joinpath("vendor/three.min.js").read_text(encoding="utf-8")


def viewer(parts: Sequence[ViewerPart], caption: str = "") -> tuple[str, tuple[str, ...]]:
    """An interactive, rotatable 3-D view (three.js, inlined) of the given parts.

    Parameters
    ----------
    parts : sequence of ViewerPart
        Meshes in mm; ``group`` picks the view ("assembly" or "mould").
    caption : str
        Plain-text caption.

    Returns
    -------
    (str, tuple of str)
        The HTML block and the inline scripts the page must carry (three.js, the viewer).
    """
    data = json.dumps({"parts": [p.to_json() for p in parts]}, separators=(",", ":"))
    groups = list(dict.fromkeys(p.group for p in parts))
    buttons = "".join(f'<button data-group="{g}" class="{"on" if i == 0 else ""}">{html.escape(g)}</button>'
                      for i, g in enumerate(groups))
    legend = "".join(f'<span data-part="{html.escape(p.name)}" data-group="{p.group}"><i style="background:{p.color}">'
                     f'</i>{html.escape(p.name)}</span>' for p in parts)
    cap = f"<figcaption>{html.escape(caption)}</figcaption>" if caption else ""
    block = (
        '<figure class="viewer-wrap"><div class="viewer-tools">' + buttons +
        '<button id="viewer-cut" class="on">cut-away</button><button id="viewer-gas">gas chambers</button>'
        '<button id="viewer-reset">reset view</button></div>'
        '<canvas id="viewer" aria-label="3-D view: drag to rotate, wheel to zoom"></canvas>'
        f'<div class="legend" id="viewer-legend">{legend}</div>{cap}'
        f'<script type="application/json" id="viewer-data">{_script_safe(data)}</script></figure>'
    )
    return block, (_vendored_three(), _VIEWER_JS)


_VIEWER_JS = r"""
(function () {
  var canvas = document.getElementById('viewer');
  if (!canvas) return;
  var data = JSON.parse(document.getElementById('viewer-data').textContent);
  function arr(s, T) {
    var bin = atob(s), u = new Uint8Array(bin.length);
    for (var i = 0; i < bin.length; i++) u[i] = bin.charCodeAt(i);
    return new T(u.buffer);
  }
  var renderer;
  try {
    renderer = new THREE.WebGLRenderer({canvas: canvas, antialias: true, preserveDrawingBuffer: true});
  } catch (e) {
    canvas.insertAdjacentHTML('afterend', '<p class="note">This browser cannot show WebGL: the 3-D view is off.</p>');
    window.vveaViewer = {ready: false, error: String(e)};
    return;
  }
  renderer.localClippingEnabled = true;
  renderer.setPixelRatio(window.devicePixelRatio || 1);
  var scene = new THREE.Scene();
  scene.background = new THREE.Color(0xf4f6f8);
  var camera = new THREE.PerspectiveCamera(30, 1, 1, 10000);
  scene.add(new THREE.HemisphereLight(0xffffff, 0x556677, 0.75));
  var key = new THREE.DirectionalLight(0xffffff, 0.75);
  key.position.set(0.6, 0.8, 1.0);
  camera.add(key);
  scene.add(camera);
  var cut = new THREE.Plane(new THREE.Vector3(0, 0, -1), 0);
  var groups = {}, gas = [];
  data.parts.forEach(function (p) {
    var g = new THREE.BufferGeometry();
    g.setAttribute('position', new THREE.BufferAttribute(arr(p.positions, Float32Array), 3));
    g.setIndex(new THREE.BufferAttribute(arr(p.indices, Uint32Array), 1));
    g.computeVertexNormals();
    var m = new THREE.MeshStandardMaterial({color: p.color, metalness: 0.15, roughness: 0.6,
      side: THREE.DoubleSide, transparent: p.opacity < 1, opacity: p.opacity, depthWrite: p.opacity >= 1});
    var mesh = new THREE.Mesh(g, m);
    mesh.name = p.name;
    mesh.visible = p.visible;
    if (p.name.indexOf('gas_chamber') === 0) gas.push(mesh);
    if (!groups[p.group]) { groups[p.group] = new THREE.Group(); groups[p.group].rotation.x = -Math.PI / 2; scene.add(groups[p.group]); }
    groups[p.group].add(mesh);
  });
  var names = Object.keys(groups), current = names[0], cutOn = true;
  var orbit = {theta: 0.65, phi: 1.2, radius: 1, target: new THREE.Vector3()};
  function frame() {
    var box = new THREE.Box3().setFromObject(groups[current]);
    var size = box.getSize(new THREE.Vector3()), c = box.getCenter(new THREE.Vector3());
    orbit.target.copy(c);
    orbit.radius = 0.62 * Math.max(size.x, size.y, size.z) / Math.tan(camera.fov * Math.PI / 360);
    cut.constant = c.z;
  }
  function setClip() {
    Object.keys(groups).forEach(function (k) {
      groups[k].traverse(function (o) { if (o.material) { o.material.clippingPlanes = (cutOn && k === 'assembly') ? [cut] : []; o.material.needsUpdate = true; } });
    });
  }
  function show(name) {
    current = name;
    names.forEach(function (k) { groups[k].visible = (k === name); });
    document.querySelectorAll('.viewer-tools button[data-group]').forEach(function (b) { b.classList.toggle('on', b.dataset.group === name); });
    document.querySelectorAll('#viewer-legend span').forEach(function (s) { s.style.display = s.dataset.group === name ? '' : 'none'; });
    frame(); draw();
  }
  function resize() {
    var w = canvas.clientWidth, h = canvas.clientHeight;
    renderer.setSize(w, h, false);
    camera.aspect = w / h;
    camera.updateProjectionMatrix();
  }
  function draw() {
    var r = orbit.radius, t = orbit.theta, p = orbit.phi;
    camera.position.set(orbit.target.x + r * Math.sin(p) * Math.sin(t), orbit.target.y + r * Math.cos(p),
                        orbit.target.z + r * Math.sin(p) * Math.cos(t));
    camera.lookAt(orbit.target);
    renderer.render(scene, camera);
  }
  var drag = null;
  canvas.addEventListener('pointerdown', function (e) { drag = {x: e.clientX, y: e.clientY}; canvas.setPointerCapture(e.pointerId); });
  canvas.addEventListener('pointerup', function () { drag = null; });
  canvas.addEventListener('pointermove', function (e) {
    if (!drag) return;
    orbit.theta -= (e.clientX - drag.x) * 0.01;
    orbit.phi = Math.min(Math.PI - 0.05, Math.max(0.05, orbit.phi - (e.clientY - drag.y) * 0.01));
    drag = {x: e.clientX, y: e.clientY};
    draw();
  });
  canvas.addEventListener('wheel', function (e) { e.preventDefault(); orbit.radius *= Math.exp(e.deltaY * 0.001); draw(); }, {passive: false});
  document.querySelectorAll('.viewer-tools button[data-group]').forEach(function (b) {
    b.addEventListener('click', function () { show(b.dataset.group); });
  });
  document.getElementById('viewer-cut').addEventListener('click', function (e) {
    cutOn = !cutOn; e.target.classList.toggle('on', cutOn); setClip(); draw();
  });
  document.getElementById('viewer-gas').addEventListener('click', function (e) {
    var on = !(gas.length && gas[0].visible);
    gas.forEach(function (m) { m.visible = on; }); e.target.classList.toggle('on', on); draw();
  });
  document.getElementById('viewer-reset').addEventListener('click', function () { orbit.theta = 0.65; orbit.phi = 1.2; show(current); });
  window.addEventListener('resize', function () { resize(); draw(); });
  resize(); setClip(); show(current);
  window.vveaViewer = {ready: true, parts: data.parts.length, rotate: function (d) { orbit.theta += d; draw(); }};
})();
"""


# ------------------------------------------------------------- unit report
class UnitResult(Protocol):
    """What :func:`unit_report` reads of a designed unit.

    The main job's result (``UnitDesign`` of the pipeline module, which sits above this
    one and calls it) has every member; the report states the shape it needs
    instead of importing its caller. Read-only members, units as in the result.
    """

    @property
    def requirements(self) -> Requirements:
        """What was asked for."""

    @property
    def optimisation(self) -> OptimisationResult:
        """The optimised design, evaluated (margins, performance)."""

    @property
    def spring(self) -> SpringCurve:
        """Isothermal and adiabatic force curves (N), deviations (N), pressures (MPa) over x (mm)."""

    @property
    def bladder(self) -> BladderResult:
        """The bladder check with the requirements' silicone."""

    @property
    def actuator(self) -> Actuator:
        """Joint-level K, D range of the unit (SI)."""

    @property
    def cad_manifest(self) -> CadManifest | None:
        """The CAD set's manifest (None when CAD was skipped)."""

    @property
    def bom(self) -> BillOfMaterials | None:
        """Bill of materials (None: no CAD)."""

    @property
    def drawings(self) -> DrawingSet | None:
        """Dimensioned drawings (None: no CAD)."""

    @property
    def actuator_study(self) -> DesignStudy | None:
        """The design's rest-to-rest and torque-step study (None when skipped)."""

    @property
    def out_dir(self) -> Path:
        """The folder written."""

    @property
    def files(self) -> dict[str, Path]:
        """What was written, by role."""

    @property
    def seconds(self) -> dict[str, float]:
        """Wall time of each step (s)."""

    @property
    def seed(self) -> int:
        """Seed of the optimiser."""

    @property
    def version(self) -> str:
        """vvea-design version that made it."""

    @property
    def spec_path(self) -> str | None:
        """Requirements file (None: the built-in defaults)."""

    @property
    def passes(self) -> bool:
        """Every constraint met and the bladder check passed."""


def _spring_figure(unit: UnitResult) -> "Figure":
    from matplotlib.figure import Figure

    c = unit.spring
    x = c.x_mm
    fig = Figure(figsize=(12.5, 3.9))
    a, b, p = fig.subplots(1, 3)
    a.plot(x, c.force_isothermal_N, color="C0", lw=2, label=f"isothermal (n = 1), {c.stiffness_isothermal_N_per_mm:.1f} N/mm")
    a.plot(x, c.force_adiabatic_N, color="C3", lw=1.5, ls="--",
           label=f"adiabatic (n = 1.4), {c.stiffness_adiabatic_N_per_mm:.1f} N/mm")
    a.set(xlabel="displacement x (mm), x > 0 extends", ylabel="force F (N), tension > 0")
    a.set_title("force over the stroke", y=1.0)  # placed, not searched for at the draw (no offset text here)
    a.legend(fontsize=8, loc="upper left")
    a.grid(alpha=0.3)
    b.plot(x, c.deviation_isothermal_N, color="C0", lw=2, label=f"isothermal: {100 * c.linearity_isothermal:.2f} %")
    b.plot(x, c.deviation_adiabatic_N, color="C3", lw=1.5, ls="--", label=f"adiabatic: {100 * c.linearity_adiabatic:.2f} %")
    b.axhline(0, color="k", lw=0.6)
    b.set(xlabel="displacement x (mm)", ylabel="F − least-squares line (N)")
    b.set_title("deviation from the straight line (linearity error)", y=1.0)
    b.legend(fontsize=8, loc="best")
    b.grid(alpha=0.3)
    p.plot(x, c.P1_isothermal_MPa, color="C2", lw=2, label="chamber 1, isothermal")
    p.plot(x, c.P2_isothermal_MPa, color="C4", lw=2, label="chamber 2, isothermal")
    p.plot(x, c.P1_adiabatic_MPa, color="C2", lw=1.2, ls="--", label="chamber 1, adiabatic")
    p.plot(x, c.P2_adiabatic_MPa, color="C4", lw=1.2, ls="--", label="chamber 2, adiabatic")
    p.set(xlabel="displacement x (mm)", ylabel="gas pressure (MPa)")
    p.set_title("chamber pressures", y=1.0)
    p.legend(fontsize=8, loc="best")
    p.grid(alpha=0.3)
    # margins in inches as a constrained layout set them, without the second draw it costs: fixed room for
    # the titles and axis labels, and left of each panel the room of its widest y tick label
    from ..figure_layout import place_row_in, ytick_label_width_in

    place_row_in(fig, (a, b, p), left=0.365 + ytick_label_width_in(a), right=0.042, bottom=0.477, top=0.255,
                 gaps=[0.39 + ytick_label_width_in(ax) for ax in (b, p)])
    return fig


def _bladder_figure(unit: UnitResult) -> "Figure":
    from matplotlib.figure import Figure

    bl = unit.bladder
    ends = list(bl.ends)
    fig = Figure(figsize=(7.5, 3.2))
    ax = fig.subplots()
    kinds = [("membrane max principal", [bl.ends[k].max_principal_strain for k in ends]),
             ("clamp (membrane + bending)", [bl.ends[k].clamp_strain for k in ends])]
    w = 0.35
    for i, (label, vals) in enumerate(kinds):
        ax.bar(np.arange(len(ends)) + (i - 0.5) * w, 100 * np.asarray(vals), w, label=label)
    ax.axhline(100 * bl.allowable_strain, color="#b00020", lw=1.5, ls="--",
               label=f"allowable {100 * bl.allowable_strain:.1f} % ({bl.silicone.name})")
    ax.set_xticks(np.arange(len(ends)), [f"{k}\n(ΔV = {bl.volume_change_mm3[k]:+.0f} mm³)" for k in ends])
    ax.set_ylabel("strain (%)")
    ax.set_ylim(0, 100 * max(bl.allowable_strain, bl.strain_bound) * 1.35)
    ax.set_title(f"bladder strain bound {100 * bl.strain_bound:.1f} % vs allowable {100 * bl.allowable_strain:.1f} %", y=1.0)
    ax.legend(fontsize=8, loc="upper left", ncols=3)
    ax.grid(axis="y", alpha=0.3)
    from ..figure_layout import set_margins_in, ytick_label_width_in

    # as a constrained layout set them (without its second draw); the y tick labels' room measured
    set_margins_in(fig, left=0.351 + ytick_label_width_in(ax), bottom=0.481, right=0.289, top=0.255)
    return fig


def _requirements_section(unit: UnitResult) -> Section:
    from dataclasses import fields

    req = unit.requirements
    rows = []
    for f in fields(req):
        if f.name in ("bounds", "fixed"):
            continue
        rows.append((f.name, getattr(req, f.name)))
    bounds = table(("decision variable (unit in the name)", "search low", "search high"),
                   [(k, v[0], v[1]) for k, v in req.bounds.items()])
    src = unit.spec_path or "built-in defaults (the paper's unit)"
    return Section("Requirements", paragraph(f"source: {src}") +
                   table(("requirement (unit in the name)", "value"), rows) + bounds)


def _margins_section(unit: UnitResult) -> Section:
    ev = unit.optimisation.evaluation
    rows = []
    for name, m in ev.margins.items():
        d = ev.details[name]
        rel = "≤" if d["kind"] == "max" else "≥"
        unit_s = d["unit"] if d["unit"] != "-" else ""
        rows.append((name, f"{float(d['value']):.4g} {unit_s}".strip(), f"{rel} {float(d['limit']):.4g} {unit_s}".strip(),
                     float(m), pass_fail(m >= -1e-9)))
    perf = ev.performance()
    prow = [("linearity error (isothermal)", f"{100 * perf['linearity_error']:.3f} %"),
            ("mean stiffness at the charge", f"{perf['mean_stiffness_N_per_mm']:.2f} N/mm"),
            ("largest force over the stroke", f"{perf['max_force_N']:.1f} N"),
            ("charge p1 / p2", f"{perf['p1_MPa']:.3f} / {ev.design.p2_MPa:.3f} MPa"),
            ("peak pressure", f"{perf['peak_pressure_MPa']:.2f} MPa"),
            ("mass", f"{perf['mass_g']:.0f} g"),
            ("housing length", f"{perf['housing_length_mm']:.1f} mm"),
            ("piston diameter", f"{ev.design.piston_diameter_mm:.2f} mm"),
            ("outer diameter", f"{ev.design.outer_diameter_mm:.2f} mm"),
            ("V1 / V2", f"{ev.design.V1_mm3:.0f} / {ev.design.V2_mm3:.0f} mm³")]
    body = (verdict(ev.feasible, "every constraint met" if ev.feasible else "a constraint is violated") +
            table(("quantity", "value"), prow) +
            table(("constraint", "value", "limit", "margin (> 0 met, scaled)", "verdict"), rows, raw_columns=(4,)) +
            paragraph(f"binding (margin < 0.001): {', '.join(ev.binding()) or 'none'}; optimiser: "
                      f"{unit.optimisation.evaluations} evaluations in {unit.optimisation.seconds:.1f} s, seed "
                      f"{unit.seed}.", "note"))
    return Section("Design and constraint margins", body)


def _bladder_section(unit: UnitResult) -> Section:
    bl = unit.bladder
    rows = []
    for k, e in bl.ends.items():
        rows.append((k, float(bl.volume_change_mm3[k]), e.pressure_MPa, 100 * e.max_principal_strain,
                     100 * e.clamp_strain, 100 * e.strain_bound, 100 * e.wrinkled_fraction, e.gap_inner_tube_mm,
                     e.gap_outer_bore_mm))
    body = (verdict(bl.passes, f"strain bound {100 * bl.strain_bound:.2f} % vs allowable "
                               f"{100 * bl.allowable_strain:.2f} % ({bl.silicone.name}); radial room "
                               f"{'ok' if bl.passes_room else 'the bladder touches'}") +
            figure_svg(_bladder_figure(unit), "FE membrane strain at both stroke ends against the silicone's "
                                              "allowable strain (dashed).") +
            table(("stroke end", "ΔV (mm³)", "fluid − gas (MPa)", "membrane strain (%)", "clamp strain (%)",
                   "strain bound (%)", "wrinkled area (%)", "gap to inner tube (mm)", "gap to outer bore (mm)"), rows))
    png = unit.files.get("bladder_png")
    if png and Path(png).exists():
        body += image(png, "Deformed meridian at both stroke ends, coloured by strain.")
    return Section("Bladder", body)


def _actuator_section(unit: UnitResult) -> Section:
    from ..actuator.model import PAPER_SETTINGS

    a = unit.actuator
    rows = [(s.name, s.K_Nm_per_rad, s.D_min_Nms_per_rad, s.D_max_Nms_per_rad, s.eigenfrequency_Hz)
            for s in [a, *PAPER_SETTINGS.values()]]
    body = (paragraph("Joint-level parameters of the unit (two pre-loaded units on the tendon pulley, paper "
                      "section 3.4) beside the paper's Table 4 settings.") +
            table(("setting", "K (N m/rad)", "D_min (N m s/rad)", "D_max (N m s/rad)", "eigenfrequency (Hz)"), rows))
    study = unit.actuator_study
    if study is None:
        body += paragraph("The design's own rest-to-rest and safety study was not run in this job "
                          "(--no-actuator-study); `vvea study rest-to-rest --design design.json` runs it.", "note")
    else:
        body += _design_study_blocks(study)
    return Section("Actuator", body)


def _design_study_blocks(study: "DesignStudy") -> str:
    """The design's actuator study (:class:`vvea_design.actuator.design_study.DesignStudy`): Table 5, map, safety."""
    grid = study.grid
    out = paragraph(f"Rest-to-rest optimal control (paper section 5) on {len(grid.A_rad)} × {len(grid.T_s)} cases "
                    f"(A = {', '.join(f'{v:g}' for v in grid.A_rad)} rad; T = {', '.join(f'{v:g}' for v in grid.T_s)} s), "
                    f"{study.mesh.n_intervals} collocation intervals (Radau degree {study.mesh.degree}); "
                    "only trajectories that are valid (95 % of A reached) and verified by re-simulation count.")
    rows = []
    for c in study.comparisons:
        rows.append((f"design vs {c.other}", c.n_cases, c.n_excluded,
                     None if c.fraction_design_beats is None else 100 * c.fraction_design_beats,
                     c.meanrmse_other_over_design,
                     None if c.paper_vvea_beats is None else 100 * c.paper_vvea_beats,
                     c.paper_meanrmse_other_over_vvea))
    out += "<h3>Table 5 for the design</h3>" + table(
        ("comparison", "cases compared", "cases left out", "design beats (%)", "mean rmse other / design",
         "paper: VVEA beats (%)", "paper: rmse other / VVEA"), rows)
    srows = [(s.name, s.K_Nm_per_rad, s.D_min_Nms_per_rad, s.D_max_Nms_per_rad, s.n_cases, s.n_solved, s.n_valid,
              s.n_unverified, s.mean_rmse_rad) for s in study.settings]
    out += table(("setting", "K (N m/rad)", "D_min (N m s/rad)", "D_max (N m s/rad)", "cases", "solved", "valid",
                  "unverified (left out)", "mean rmse (rad)"), srows)
    f = study.files
    if getattr(f, "map_png", None) and Path(f.map_png).exists():
        out += image(f.map_png, "Actuator comparison map: which setting tracks best in each (A, T) case.")
    if getattr(f, "trajectory_png", None) and Path(f.trajectory_png).exists():
        out += image(f.trajectory_png, "Optimal trajectories of one case.")
    cases = list(study.safety_design.cases) + [study.safety_reference.variable]
    out += "<h3>Safety: 50 N m torque step (paper section 6)</h3>" + table(
        ("case", "mean D (N m s/rad)", "max D (N m s/rad)", "t95 (ms)", "status"),
        [(c.name, c.mean_D_Nms_per_rad, c.max_D_Nms_per_rad, 1e3 * c.t95_s, c.status) for c in cases])
    if getattr(f, "safety_png", None) and Path(f.safety_png).exists():
        out += image(f.safety_png, "Torque step of the design and of the paper's VVEA.")
    t = study.timing
    out += paragraph(f"study time {t.total_s:.1f} s on {t.workers} worker(s); {study.n_left_out} result(s) left out "
                     "because their trajectory did not verify.", "note")
    return out


def _cad_section(unit: UnitResult) -> tuple[Section, tuple[str, ...]] | None:
    cad_dir = unit.out_dir / "cad"
    if unit.cad_manifest is None or not cad_dir.exists():
        return None
    parts = viewer_parts_from_cad(cad_dir)
    block, scripts = viewer(parts, "Drag to rotate, wheel to zoom. Assembly at x = 0 (cut-away: the half towards "
                                   "you removed); mould: the two halves opened apart around the core. Units: mm.")
    m = unit.cad_manifest
    meas = [(k, v.cad, v.design, v.rel_error) for k, v in m.measured.items()]
    body = block + table(("quantity", "CAD", "design", "relative error"), meas)
    for name in ("assembly_cutaway.png", "mould_open.png"):
        if (cad_dir / name).exists():
            body += image(cad_dir / name, f"render: {name[:-4].replace('_', ' ')}")
    return Section("3-D model", body, anchor="model"), scripts


def _bom_section(unit: UnitResult) -> Section | None:
    bom = unit.bom
    if bom is None:
        return None
    rows = [(ln.item, ln.part, ln.description, ln.category, ln.material, ln.standard, ln.size, ln.quantity,
             ln.unit_volume_mm3, ln.unit_mass_g, ln.total_mass_g, ln.in_unit) for ln in bom.lines]
    body = (table(("item", "part", "description", "category", "material", "standard", "size", "qty",
                   "volume each (mm³)", "mass each (g)", "mass (g)", "in the unit"), rows) +
            table(("total", "value"), [("unit mass (g)", bom.unit_mass_g), ("bladder silicone", bom.silicone),
                                       ("cured bladder volume (mm³)", bom.bladder_volume_mm3),
                                       ("mould void incl. sprue, runner, vents (mm³)", bom.mould_void_mm3),
                                       ("silicone to mix (mm³)", bom.silicone_to_mix_mm3),
                                       ("silicone to mix (g)", bom.silicone_to_mix_g)]) +
            paragraph("Also in cad/bom.csv. Made parts: CAD volume × density; bought parts as listed.", "note"))
    return Section("Bill of materials", body)


#: Largest total size of drawing SVGs inlined in the report (bytes); beyond it only links are given.
MAX_INLINE_DRAWINGS_BYTES = 1_500_000


def _drawings_section(unit: UnitResult) -> Section | None:
    ds = unit.drawings
    if ds is None:
        return None
    body = paragraph("Dimensioned drawings made from the CAD solids (SVG per sheet and one PDF in cad/): "
                     + ", ".join(ds.sheets) + ".")
    used = 0
    for name, svg_path, scale in zip(ds.sheets, ds.svg, ds.scales):
        p = Path(svg_path)
        if not p.exists():
            continue
        size = p.stat().st_size
        if used + size > MAX_INLINE_DRAWINGS_BYTES:
            body += paragraph(f"sheet {name}: cad/{p.name} (not inlined: the report stays small)", "note")
            continue
        used += size
        svg = p.read_text(encoding="utf-8")
        svg = svg[svg.index("<svg"):]
        body += f"<figure>{svg}<figcaption>{html.escape(f'sheet {name}, scale {_scale(scale)}')}</figcaption></figure>"
    return Section("Drawings", body)


def _scale(s: float) -> str:
    return f"{s:g}:1" if s >= 1 else f"1:{1 / s:g}"


def _files_section(unit: UnitResult) -> Section:
    rows = []
    for role, p in unit.files.items():
        p = Path(p)
        try:
            rel = p.relative_to(unit.out_dir)
        except ValueError:
            rel = p
        rows.append((role, str(rel)))
    return Section("Files", table(("what", "path (in the output folder)"), rows))


def _provenance_section(unit: UnitResult) -> Section:
    spec_hash = ""
    if unit.spec_path and Path(unit.spec_path).exists():
        spec_hash = hashlib.sha256(Path(unit.spec_path).read_bytes()).hexdigest()
    rows = [("vvea-design version", unit.version), ("seed", unit.seed),
            ("requirements file", unit.spec_path or "none (built-in defaults)"),
            ("requirements sha256", spec_hash or "–"),
            ("Python", platform.python_version()), ("platform", f"{sys.platform} {platform.machine()}")]
    rows += [(f"time: {k} (s)", v) for k, v in unit.seconds.items()]
    return Section("Provenance", table(("item", "value"), rows) +
                   "<h3>Requirements as read</h3>" +
                   preformatted(json.dumps(unit.requirements.to_dict(), indent=2, default=str)))


def unit_report(unit: UnitResult) -> HtmlReport:
    """The report of one designed unit (what ``vvea design`` writes as ``report.html``).

    Parameters
    ----------
    unit : UnitResult
        The main job's result (``design_unit`` of the pipeline module returns one).

    Returns
    -------
    HtmlReport
        Call ``.write(path)``.
    """
    ev = unit.optimisation.evaluation
    sections: list[Section] = [_margins_section(unit), _requirements_section(unit)]
    sections.append(Section("Force curve", figure_svg(
        _spring_figure(unit),
        "Isothermal (slow motion, n = 1) and adiabatic (fast motion, n = 1.4) force from the same charge at x = 0; "
        "deviation = force minus its least-squares line; chamber pressures.") +
        table(("gas law", "linearity error (%)", "mean stiffness (N/mm)", "F at full stroke (N)"),
              [("isothermal n = 1", 100 * unit.spring.linearity_isothermal, unit.spring.stiffness_isothermal_N_per_mm,
                float(unit.spring.force_isothermal_N[-1])),
               ("adiabatic n = 1.4", 100 * unit.spring.linearity_adiabatic, unit.spring.stiffness_adiabatic_N_per_mm,
                float(unit.spring.force_adiabatic_N[-1]))]), anchor="force"))
    scripts: tuple[str, ...] = ()
    cad = _cad_section(unit)
    if cad is not None:
        sec, scripts = cad
        sections.append(sec)
    sections.append(_bladder_section(unit))
    sections.append(_actuator_section(unit))
    for extra in (_drawings_section(unit), _bom_section(unit)):
        if extra is not None:
            sections.append(extra)
    sections += [_files_section(unit), _provenance_section(unit)]
    ok = unit.passes
    sub = (f'linearity error {100 * ev.linearity_error:.2f} %, stiffness {ev.mean_stiffness_N_per_mm:.1f} N/mm, '
           f'bladder {100 * unit.bladder.strain_bound:.1f} % of {100 * unit.bladder.allowable_strain:.0f} % — '
           f'<b>{"all checks pass" if ok else "a check fails"}</b> · vvea-design {html.escape(unit.version)}, '
           f'seed {unit.seed}')
    return HtmlReport("vvea design: spring–damper unit", tuple(sections), sub, scripts)


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
