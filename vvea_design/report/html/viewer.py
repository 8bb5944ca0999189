"""The report's interactive 3-D view: three.js (vendored, inlined) drawing the CAD set's STL meshes."""

from __future__ import annotations

import base64
import html
import json
from collections.abc import Sequence
from dataclasses import dataclass
from importlib import resources
from pathlib import Path
from typing import Any

import numpy as np

from ...palette import PART_LABELS, part_hex
from .page import _script_safe

__all__ = ["ViewerPart", "viewer_parts_from_cad", "viewer"]


# ------------------------------------------------------------------ 3-D view
@dataclass(frozen=True, eq=False)
class ViewerPart:
    """One triangle mesh of the 3-D view (mm, CAD frame: z along the unit's axis)."""

    name: str  #: part name (CAD part table)
    group: str  #: view it belongs to: "assembly" or "mould"
    color: str  #: CSS hex colour "#rrggbb"
    vertices_mm: np.ndarray  #: (n, 3) vertex positions, mm
    faces: np.ndarray  #: (m, 3) vertex indices
    opacity: float = 1.0  #: 1 opaque ... 0 invisible
    visible: bool = True  #: shown when the page opens
    label: str = ""  #: how the legend names it (default: ``name``)
    callout: bool = False  #: also named in the view, above the part (parts of one colour told apart)

    def to_json(self) -> dict[str, Any]:
        """The part as the viewer script reads it (base64 float32 positions and uint32 indices).

        Returns
        -------
        dict
            name, label, group, color, opacity, visible, callout, positions (base64), indices (base64).
        """
        pos = np.ascontiguousarray(self.vertices_mm, dtype="<f4")
        idx = np.ascontiguousarray(self.faces, dtype="<u4")
        return {"name": self.name, "label": self.label or self.name, "group": self.group, "color": self.color,
                "opacity": float(self.opacity), "visible": bool(self.visible), "callout": bool(self.callout),
                "positions": base64.b64encode(pos.tobytes()).decode("ascii"),
                "indices": base64.b64encode(idx.tobytes()).decode("ascii")}


#: View, opacity, shown-at-start and named-in-the-view of each CAD file the 3-D view uses (mould parts opened
#: apart); the colours and legend names are the palette's (vvea_design.palette), as in every render.
_CAD_VIEW = {
    "housing": ("assembly", 1.0, True, False),
    "piston": ("assembly", 1.0, True, False),
    "bladder": ("assembly", 1.0, True, False),
    "support_ring": ("assembly", 1.0, True, False),
    "gas_chamber_1": ("assembly", 0.35, False, False),
    "gas_chamber_2": ("assembly", 0.35, False, False),
    "mould_half_a": ("mould", 1.0, True, True),  # both halves one colour: named in the view
    "mould_half_b": ("mould", 1.0, True, True),
    "mould_core": ("mould", 1.0, True, True),
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
    for name, (group, opacity, visible, callout) in _CAD_VIEW.items():
        path = Path(cad_dir) / f"{name}.stl"
        if not path.exists():
            continue
        mesh = trimesh.load_mesh(path, file_type="stl", process=True)
        v = np.asarray(mesh.vertices, float) + np.asarray(_MOULD_OPEN_MM.get(name, (0.0, 0.0, 0.0)))
        parts.append(ViewerPart(name, group, part_hex(name), v, np.asarray(mesh.faces), opacity, visible,
                                PART_LABELS.get(name, name), callout))
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
                     f'</i>{html.escape(p.label or p.name)}</span>' for p in parts)
    cap = f"<figcaption>{html.escape(caption)}</figcaption>" if caption else ""
    block = (
        '<figure class="viewer-wrap"><div class="viewer-tools">' + buttons +
        '<button id="viewer-cut" class="on">cut-away</button><button id="viewer-gas">gas chambers</button>'
        '<button id="viewer-reset">reset view</button></div>'
        '<div class="viewer-stage"><canvas id="viewer" aria-label="3-D view: drag to rotate, wheel to zoom"></canvas>'
        '<div class="viewer-labels" id="viewer-labels"></div></div>'
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
  var groups = {}, gas = [], callouts = [];
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
    if (p.callout) {
      var tag = document.createElement('span');
      tag.textContent = p.label;
      tag.dataset.part = p.name;
      document.getElementById('viewer-labels').appendChild(tag);
      callouts.push({mesh: mesh, tag: tag, group: p.group});
    }
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
    // the whole part in view, also in a portrait window (narrower than it is high)
    orbit.radius = 0.62 * Math.max(size.x, size.y, size.z) / Math.tan(camera.fov * Math.PI / 360) /
      Math.min(1, camera.aspect);
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
    var w = canvas.clientWidth, h = canvas.clientHeight;
    callouts.forEach(function (c) {  // each named part's label above its top, where the camera sees it
      var on = c.group === current && c.mesh.visible;
      if (on) {
        var box = new THREE.Box3().setFromObject(c.mesh), v = box.getCenter(new THREE.Vector3());
        v.y = box.max.y;
        v.project(camera);
        on = v.z < 1;
        c.tag.style.left = ((v.x + 1) / 2 * w) + 'px';
        c.tag.style.top = Math.max(12, (1 - v.y) / 2 * h - 12) + 'px';
      }
      c.tag.style.display = on ? '' : 'none';
    });
    var placed = [];  // a name that would cover another moves down below it
    callouts.forEach(function (c) {
      if (c.tag.style.display === 'none') return;
      var x = parseFloat(c.tag.style.left), y = parseFloat(c.tag.style.top);
      var hw = c.tag.offsetWidth / 2 + 2, hh = c.tag.offsetHeight / 2 + 2;
      for (var k = 0; k < placed.length; k++) {
        var p = placed[k];
        if (Math.abs(x - p.x) < hw + p.hw && Math.abs(y - p.y) < hh + p.hh) { y = p.y + hh + p.hh; k = -1; }
      }
      c.tag.style.top = y + 'px';
      placed.push({x: x, y: y, hw: hw, hh: hh});
    });
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
  window.vveaViewer = {ready: true, parts: data.parts.length, callouts: callouts.length,
                      rotate: function (d) { orbit.theta += d; draw(); }};
})();
"""
