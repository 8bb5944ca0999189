"""Deterministic STEP / STL export of the CAD set and its manifest.

* STEP: OCCT's writer with a fixed header timestamp (:data:`STEP_TIMESTAMP`);
  every file's product carries the part's name from the part table; the
  assembly's ``NEXT_ASSEMBLY_USAGE_OCCURRENCE`` ids (a process-global
  counter in OCCT) are renumbered 1, 2, ... so the bytes depend on the
  design only.
* STL: binary, from one tessellation (``cad.stl_tolerance_mm``,
  ``cad.stl_angular_tolerance_rad``) merged into a watertight
  :class:`trimesh.Trimesh`; the same mesh is checked, rendered and put in the GLB.
* the manifest (:class:`~vvea_design.cad.manifest.CadManifest`,
  ``manifest.json``): every file with its size, sha256, volume, bounding box
  and material, every part's closed-form volume next to the drawn one, the
  CAD-measured chamber volumes and piston areas next to the design's, the
  interference and mould checks.

The files each part gets come from :data:`~vvea_design.cad.registry.PARTS`;
:func:`~vvea_design.cad.write.write_cad` drives this module and the renders.
"""

from __future__ import annotations

import hashlib
import io
import re
from pathlib import Path

import trimesh
from build123d import Shape, export_step

from .assembly import CadModel, assembly, interference_mm3, mould_void
from .bill import glands
from .fill import gas_charges, oil_fill_mm3
from .leaks import leak_paths
from .manifest import BBox, CadManifest, Envelope, FileRecord, MeasuredCheck, MouldCheck, PartRecord, WallCheck
from .mesh import to_mesh
from .registry import all_parts

__all__ = ["STEP_TIMESTAMP", "step_bytes", "to_mesh", "stl_bytes", "bbox_mm", "export_files", "export_steps",
           "write_file"]

#: Fixed STEP header timestamp (byte-stable exports).
STEP_TIMESTAMP = "2000-01-01T00:00:00"

_NAUO = re.compile(rb"NEXT_ASSEMBLY_USAGE_OCCURRENCE\('\d+'")


def step_bytes(shape: Shape) -> bytes:
    """STEP (AP214, mm) of ``shape`` or a labelled assembly, byte-stable.

    The product name is ``shape.label`` (every part of the table is labelled
    by :func:`~vvea_design.cad.assembly.build_cad`); the header timestamp is
    :data:`STEP_TIMESTAMP` and the assembly-usage ids are renumbered from 1.

    Parameters
    ----------
    shape : Shape
        A labelled solid or a labelled assembly compound, mm.

    Returns
    -------
    bytes
        The STEP file content; the same shape gives the same bytes in every run.
    """
    buf = io.BytesIO()
    export_step(shape, buf, timestamp=STEP_TIMESTAMP)
    data = buf.getvalue()
    counter = iter(range(1, 1 << 30))
    return _NAUO.sub(lambda m: b"NEXT_ASSEMBLY_USAGE_OCCURRENCE('%d'" % next(counter), data)


def stl_bytes(mesh: trimesh.Trimesh) -> bytes:
    """Binary STL of ``mesh`` (float32, fixed header).

    Parameters
    ----------
    mesh : trimesh.Trimesh
        Triangle mesh, mm.

    Returns
    -------
    bytes
        80-byte header, triangle count, one record per triangle (normal and vertices as float32, mm).
    """
    import numpy as np

    tri = np.asarray(mesh.triangles, dtype=np.float64)
    normals = np.asarray(mesh.face_normals, dtype=np.float32)
    rec = np.zeros(len(tri), dtype=[("n", "<f4", (3,)), ("v", "<f4", (3, 3)), ("a", "<u2")])
    rec["n"] = normals
    rec["v"] = tri.astype(np.float32)
    header = b"vvea_design binary STL".ljust(80, b" ")
    return header + np.uint32(len(tri)).tobytes() + rec.tobytes()


def bbox_mm(shape: Shape) -> BBox:
    """Axis-aligned bounding box of ``shape`` for the manifest.

    Parameters
    ----------
    shape : Shape
        A solid or compound, mm.

    Returns
    -------
    tuple of tuple of float
        ``((xmin, ymin, zmin), (xmax, ymax, zmax))`` rounded to 1 µm, mm.
    """
    bb = shape.bounding_box()
    return (_r(bb.min.X), _r(bb.min.Y), _r(bb.min.Z)), (_r(bb.max.X), _r(bb.max.Y), _r(bb.max.Z))


def _r(v: float, nd: int = 3) -> float:
    """Round for the manifest (and turn -0.0 into 0.0)."""
    return float(round(v, nd)) + 0.0


def write_file(path: Path, data: bytes, kind: str, **about) -> FileRecord:
    """Write ``data`` to ``path``; return its record for the manifest.

    Parameters
    ----------
    path : Path
        File to write (its folder must exist); an existing file is replaced.
    data : bytes
        The content.
    kind : str
        ``"step"``, ``"stl"``, ``"glb"`` or ``"render"``.
    **about
        The other fields of :class:`~vvea_design.cad.manifest.FileRecord` (part, material, volume in mm³, ...).

    Returns
    -------
    FileRecord
        Size (count of bytes), sha256 (hex digest), ``kind`` and ``about``.
    """
    path.write_bytes(data)
    return FileRecord(len(data), hashlib.sha256(data).hexdigest(), kind, **about)


def export_steps() -> int:
    """Number of progress steps :func:`export_files` takes (one per part, assembly, checks, mould).

    Returns
    -------
    int
        Count of ``advance()`` calls: the number of parts in the table + 3.
    """
    return len(all_parts()) + 3


def export_files(model: CadModel, out: Path, advance=None) -> tuple[CadManifest, dict[str, trimesh.Trimesh]]:
    """Write every part's files (from the table), ``assembly.step`` and run the checks.

    Parameters
    ----------
    model : CadModel
        The built CAD set.
    out : Path
        Existing output folder.
    advance : callable, optional
        Progress callback, :func:`export_steps` calls.

    Returns
    -------
    (CadManifest, dict)
        The manifest (without the scenes and renders) and the tessellated meshes by part
        name (plus ``piston_at_travel``), mm.
    """
    advance = advance or (lambda n=1: None)
    cad = model.layout.cad
    files, parts, meshes = _export_parts(model, out, advance)
    asm = assembly(model, 0.0)
    files["assembly.step"] = write_file(out / "assembly.step", step_bytes(asm), "step", part="assembly",
                                        parts=tuple(c.label for c in asm.children), material="see parts",
                                        volume_mm3=_r(asm.volume), bbox_mm=bbox_mm(asm))
    advance()
    meshes["piston_at_travel"] = to_mesh(model.piston_at_travel, cad.stl_tolerance_mm, cad.stl_angular_tolerance_rad)
    d = model.design
    meas = model.measured()
    design_vals = {"chamber_1_volume_mm3": d.V1_mm3 - d.fixed.dead_volume_1_mm3,
                   "chamber_2_volume_mm3": d.V2_mm3 - d.fixed.dead_volume_2_mm3,
                   "piston_area_A1_mm2": d.A1_mm2, "piston_area_A2_mm2": d.A2_mm2}
    checks = {k: MeasuredCheck(_r(meas[k]), _r(design_vals[k]),
                               float(f"{(meas[k] - design_vals[k]) / design_vals[k]:.3e}")) for k in meas}
    inter = {f"x_{x:g}_mm": {k: _r(v) for k, v in interference_mm3(model.parts_at(x)).items()}
             for x in (0.0, d.fixed.travel_mm)}
    advance()
    void = mould_void(model.mould)
    advance()
    walls_min = d.minimum_walls_mm()
    walls_drawn = d.walls_mm()
    lay = model.layout
    check = model.assembly_check()
    seals = tuple({**g.to_dict(), "quantity": n, "where": where} for g, n, where in glands(lay))
    fill = {"oil_mm3": {k: _r(v) for k, v in oil_fill_mm3(lay).items()},
            "nitrogen": [{k: (_r(v, 4) if isinstance(v, float) else v) for k, v in g.to_dict().items()}
                         for g in gas_charges(lay)]}
    manifest = CadManifest(
        design=d, cad_parameters=cad, measured=checks, interference_mm3=inter,
        walls_mm={k: WallCheck(_r(walls_drawn[k]), _r(walls_min[k])) for k in walls_min},
        envelope_mm=Envelope(_r(d.outer_diameter_mm), _r(d.housing_length_mm), files["housing.step"].bbox_mm),
        mould=MouldCheck(cad.mould_shrinkage, _r(void.cavity_volume_mm3), _r(model.parts["bladder"].volume),
                         _r(model.closed_form_mm3["mould_cavity"]), void.sprue_open, void.vents_open),
        parts=parts, files=files, seals=seals, leak_paths=tuple(p.to_dict() for p in leak_paths(lay)), fill=fill,
        assembly=check.to_dict())
    return manifest, meshes


def _export_parts(model: CadModel, out: Path, advance) -> tuple[dict[str, FileRecord], dict[str, PartRecord],
                                                                 dict[str, trimesh.Trimesh]]:
    """Every part's STEP/STL (as the table lists) with its records and meshes; one ``advance()`` per part."""
    d, cad = model.design, model.layout.cad
    files: dict[str, FileRecord] = {}
    meshes: dict[str, trimesh.Trimesh] = {}
    parts: dict[str, PartRecord] = {}
    for part in all_parts():
        solid = model.solids[part.name]
        mesh = to_mesh(solid, cad.stl_tolerance_mm, cad.stl_angular_tolerance_rad)
        meshes[part.name] = mesh
        mat = part.material(d)
        info = {"part": part.name, "material": mat.name, "volume_mm3": _r(solid.volume), "bbox_mm": bbox_mm(solid)}
        closed = model.closed_form_mm3.get(part.name)
        parts[part.name] = PartRecord(part.title, part.group, mat.name, tuple(round(c, 3) for c in part.colour),
                                      _r(solid.volume), None if closed is None else _r(closed),
                                      tuple(f"{part.name}.{ext}" for ext in part.files))
        if "step" in part.files:
            files[f"{part.name}.step"] = write_file(out / f"{part.name}.step", step_bytes(solid), "step", **info)
        if "stl" in part.files:
            files[f"{part.name}.stl"] = write_file(out / f"{part.name}.stl", stl_bytes(mesh), "stl", **info,
                                                   triangles=int(len(mesh.faces)), mesh_volume_mm3=_r(mesh.volume),
                                                   watertight=bool(mesh.is_watertight))
        advance()
    return files, parts, meshes
