"""Deterministic STEP / STL export of the CAD set and its manifest.

* STEP: OCCT's writer with a fixed header timestamp (:data:`STEP_TIMESTAMP`);
  the assembly's ``NEXT_ASSEMBLY_USAGE_OCCURRENCE`` ids (a process-global
  counter in OCCT) are renumbered 1, 2, ... so the bytes depend on the
  design only.
* STL: binary, from one tessellation (``cad.stl_tolerance_mm``,
  ``cad.stl_angular_tolerance_rad``) merged into a watertight
  :class:`trimesh.Trimesh`; the same mesh is checked and rendered.
* ``manifest.json``: every file with its size, sha256, volume, bounding box
  and material, plus the CAD-measured chamber volumes and piston areas
  next to the design's, the interference and mould checks.
"""

from __future__ import annotations

import hashlib
import io
import json
import re
from pathlib import Path

import numpy as np
import trimesh
from build123d import Shape, export_step

from ..spring.design import Design
from .assembly import part_materials, CadModel, assembly, build_cad, interference_mm3, mould_void
from .layout import CadParameters

__all__ = ["STEP_TIMESTAMP", "step_bytes", "to_mesh", "stl_bytes", "write_cad", "bbox_mm"]

#: Fixed STEP header timestamp (byte-stable exports).
STEP_TIMESTAMP = "2000-01-01T00:00:00"

_NAUO = re.compile(rb"NEXT_ASSEMBLY_USAGE_OCCURRENCE\('\d+'")


def step_bytes(shape: Shape) -> bytes:
    """STEP (AP214, mm) of ``shape`` or a labelled assembly, byte-stable."""
    buf = io.BytesIO()
    export_step(shape, buf, timestamp=STEP_TIMESTAMP)
    data = buf.getvalue()
    counter = iter(range(1, 1 << 30))
    return _NAUO.sub(lambda m: b"NEXT_ASSEMBLY_USAGE_OCCURRENCE('%d'" % next(counter), data)


def to_mesh(shape: Shape, tolerance_mm: float = 0.05, angular_tolerance_rad: float = 0.25) -> trimesh.Trimesh:
    """Tessellate ``shape`` into a merged triangle mesh (mm)."""
    verts, tris = shape.tessellate(tolerance_mm, angular_tolerance_rad)
    v = np.array([(p.X, p.Y, p.Z) for p in verts], dtype=np.float64)
    f = np.array(tris, dtype=np.int64).reshape(-1, 3)
    mesh = trimesh.Trimesh(v, f, process=False)
    mesh.merge_vertices(digits_vertex=6)
    mesh.update_faces(mesh.nondegenerate_faces())
    mesh.remove_unreferenced_vertices()
    return mesh


def stl_bytes(mesh: trimesh.Trimesh) -> bytes:
    """Binary STL of ``mesh`` (float32, fixed header)."""
    tri = np.asarray(mesh.triangles, dtype=np.float64)
    normals = np.asarray(mesh.face_normals, dtype=np.float32)
    rec = np.zeros(len(tri), dtype=[("n", "<f4", (3,)), ("v", "<f4", (3, 3)), ("a", "<u2")])
    rec["n"] = normals
    rec["v"] = tri.astype(np.float32)
    header = b"vvea_design binary STL".ljust(80, b" ")
    return header + np.uint32(len(tri)).tobytes() + rec.tobytes()


def bbox_mm(shape: Shape) -> list[list[float]]:
    """Bounding box ``[[xmin, ymin, zmin], [xmax, ymax, zmax]]`` rounded to 1 µm, mm."""
    bb = shape.bounding_box()
    return [[_r(bb.min.X), _r(bb.min.Y), _r(bb.min.Z)], [_r(bb.max.X), _r(bb.max.Y), _r(bb.max.Z)]]


def _r(v: float, nd: int = 3) -> float:
    """Round for the manifest (and turn -0.0 into 0.0)."""
    return float(round(v, nd)) + 0.0


def _write(path: Path, data: bytes) -> dict:
    path.write_bytes(data)
    return {"bytes": len(data), "sha256": hashlib.sha256(data).hexdigest()}


def write_cad(design: Design, out_dir, renders: bool = True, cad: CadParameters | None = None,
              show_progress: bool = True) -> dict:
    """Build every part of ``design`` and write the CAD set into ``out_dir``.

    Files: ``<part>.step`` and ``<part>.stl`` for housing (united),
    housing_base, housing_outer_tube, housing_inner_tube, housing_top_cap
    (its machined parts), piston, bladder, support_ring, mould_half_a,
    mould_half_b, mould_core;
    ``assembly.step`` (named parts, x = 0); ``gas_chamber_1.stl``,
    ``gas_chamber_2.stl`` (x = 0); ``assembly_cutaway.png`` and
    ``mould_open.png`` (if ``renders``); ``manifest.json``.

    Parameters
    ----------
    design : Design
        The frozen design (mm, mm³).
    out_dir : path-like
        Output folder (created).
    renders : bool
        Also write the PNG renders (off-screen pyvista).
    cad : CadParameters, optional
        Feature sizes (default ``CadParameters()``).
    show_progress : bool
        Show the rich progress bar.

    Returns
    -------
    dict
        The manifest (also written as ``manifest.json``).

    Raises
    ------
    CadError
        For a design or parameter that cannot be drawn, before any geometry.
    """
    from ..progress import progress_bar
    from .layout import Layout

    cad = cad or CadParameters()
    Layout(design, cad)  # validate first: a clear error before any file or solid
    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    n_steps = 7 + 15 + (2 if renders else 0)  # build 7, export 15, renders 2
    with progress_bar("CAD: build, check, export", n_steps, enabled=show_progress) as advance:
        model = build_cad(design, cad, progress=advance)
        manifest = _export(model, out, advance)
        if renders:
            from .render import render_assembly_cutaway, render_mould_open

            for name, fn in (("assembly_cutaway.png", render_assembly_cutaway), ("mould_open.png", render_mould_open)):
                data = fn(model, manifest["_meshes"])
                manifest["files"][name] = {**_write(out / name, data), "kind": "render"}
                advance()
    manifest.pop("_meshes")
    manifest["files"] = dict(sorted(manifest["files"].items()))
    (out / "manifest.json").write_text(json.dumps(manifest, indent=2, sort_keys=False) + "\n")
    return manifest


def _export(model: CadModel, out: Path, advance) -> dict:
    d, cad = model.design, model.layout.cad
    mats = part_materials(d)
    files: dict[str, dict] = {}
    meshes: dict[str, trimesh.Trimesh] = {}
    for name, solid in model.export_solids().items():
        mesh = to_mesh(solid, cad.stl_tolerance_mm, cad.stl_angular_tolerance_rad)
        meshes[name] = mesh
        info = {"part": name, "material": mats[name], "volume_mm3": _r(solid.volume), "bbox_mm": bbox_mm(solid)}
        files[f"{name}.step"] = {**_write(out / f"{name}.step", step_bytes(solid)), **info, "kind": "step"}
        files[f"{name}.stl"] = {**_write(out / f"{name}.stl", stl_bytes(mesh)), **info,
                                "kind": "stl", "triangles": int(len(mesh.faces)),
                                "mesh_volume_mm3": _r(mesh.volume), "watertight": bool(mesh.is_watertight)}
        advance()
    asm = assembly(model, 0.0)
    files["assembly.step"] = {**_write(out / "assembly.step", step_bytes(asm)), "kind": "step",
                              "part": "assembly", "parts": [c.label for c in asm.children],
                              "material": "see parts", "volume_mm3": _r(asm.volume), "bbox_mm": bbox_mm(asm)}
    advance()
    for name, solid in model.gas.items():
        mesh = to_mesh(solid, cad.stl_tolerance_mm, cad.stl_angular_tolerance_rad)
        meshes[name] = mesh
        files[f"{name}.stl"] = {**_write(out / f"{name}.stl", stl_bytes(mesh)), "kind": "stl", "part": name,
                                "material": mats[name], "volume_mm3": _r(solid.volume), "bbox_mm": bbox_mm(solid),
                                "triangles": int(len(mesh.faces)), "mesh_volume_mm3": _r(mesh.volume),
                                "watertight": bool(mesh.is_watertight)}
    advance()
    meshes["piston_at_travel"] = to_mesh(model.piston_at_travel, cad.stl_tolerance_mm, cad.stl_angular_tolerance_rad)
    meas = model.measured()
    design_vals = {"chamber_1_volume_mm3": d.V1_mm3 - d.fixed.dead_volume_1_mm3,
                   "chamber_2_volume_mm3": d.V2_mm3 - d.fixed.dead_volume_2_mm3,
                   "piston_area_A1_mm2": d.A1_mm2, "piston_area_A2_mm2": d.A2_mm2}
    checks = {k: {"cad": _r(meas[k]), "design": _r(design_vals[k]),
                  "rel_error": float(f"{(meas[k] - design_vals[k]) / design_vals[k]:.3e}")} for k in meas}
    inter = {f"x_{x:g}_mm": {k: _r(v) for k, v in interference_mm3(model.parts_at(x)).items()}
             for x in (0.0, d.fixed.travel_mm)}
    advance()
    void = mould_void(model.mould)
    advance()
    walls_min = d.minimum_walls_mm()
    walls_drawn = {k: v for k, v in d.walls_mm().items() if k != "bulkhead"}
    manifest = {
        "generator": "vvea_design.cad.write_cad",
        "design": _design_dict(d),
        "cad_parameters": cad.to_dict(),
        "frame": "axis Z, z = 0 at the base underside, x > 0 moves the piston towards the base; "
                 "mould parts in the mould frame (cavity centred on z = 0, parting plane y = 0)",
        "measured": checks,
        "interference_mm3": inter,
        "walls_mm": {k: {"drawn": _r(walls_drawn[k]), "minimum": _r(walls_min[k])} for k in walls_min},
        "envelope_mm": {"outer_diameter_mm": _r(d.outer_diameter_mm), "housing_length_mm": _r(d.housing_length_mm),
                        "housing_bbox_mm": files["housing.step"]["bbox_mm"]},
        "mould": {"shrinkage": cad.mould_shrinkage,
                  "cavity_volume_mm3": _r(void["cavity_volume_mm3"]),
                  "bladder_volume_mm3": _r(model.parts["bladder"].volume),
                  "expected_cavity_volume_mm3": _r(model.closed_form_mm3["mould_cavity"]),
                  "sprue_open": void["sprue_open"], "vents_open": void["vents_open"]},
        "files": files,
        "_meshes": meshes,
    }
    return manifest


def _design_dict(d: Design) -> dict:
    from dataclasses import asdict

    out = asdict(d)
    return json.loads(json.dumps(out))
