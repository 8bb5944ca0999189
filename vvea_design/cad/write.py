"""``write_cad``: build the CAD set of one design and write it into a folder.

The top of the ``cad`` package: it drives :mod:`~vvea_design.cad.assembly`
(build), :mod:`~vvea_design.cad.export` (STEP, STL, manifest) and
:mod:`~vvea_design.cad.render` (PNG); none of those imports this module or
each other upwards, so there is no import cycle.
"""

from __future__ import annotations

import json
from dataclasses import replace
from pathlib import Path

from ..spring.design import Design
from .assembly import CadModel, build_cad
from .export import export_files, export_steps, write_file
from .layout import CadParameters, Layout
from .manifest import CadManifest, FileRecord
from .registry import all_parts

__all__ = ["write_cad", "RENDERS"]

#: The PNG renders ``write_cad`` writes (file name -> render function name in :mod:`.render`).
RENDERS = {"assembly_cutaway.png": "render_assembly_cutaway", "mould_open.png": "render_mould_open"}


def write_cad(design: Design, out_dir, renders: bool = True, cad: CadParameters | None = None,
              show_progress: bool = True, model: CadModel | None = None) -> CadManifest:
    """Build every part of ``design`` and write the CAD set into ``out_dir``.

    Files (one entry of :data:`~vvea_design.cad.registry.PARTS` each):
    ``<part>.step`` and ``<part>.stl`` for housing (united), housing_base,
    housing_outer_tube, housing_inner_tube, housing_top_cap (its machined
    pieces), piston, bladder, support_ring, mould_half_a, mould_half_b,
    mould_core; ``gas_chamber_1.stl``, ``gas_chamber_2.stl`` (x = 0);
    ``assembly.step`` (named parts, x = 0); ``assembly.glb`` and
    ``mould.glb`` (compact 3-D scenes for a viewer, see :mod:`.gltf`);
    ``assembly_cutaway.png`` and ``mould_open.png`` (if ``renders``);
    ``manifest.json``.

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
    model : CadModel, optional
        An already built model of ``design`` (skips the build).

    Returns
    -------
    CadManifest
        The manifest (its ``to_dict()`` is written as ``manifest.json``): every file and part, the
        CAD-measured volumes (mm³) and areas (mm²) next to the design's, the checks.

    Raises
    ------
    CadError
        For a design or parameter that cannot be drawn, before any geometry.
    """
    from ..progress import progress_bar

    cad = cad or CadParameters()
    Layout(design, cad)  # validate first: a clear error before any file or solid
    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    n_build = 0 if model is not None else len(all_parts()) + 1
    n_steps = n_build + export_steps() + 1 + (len(RENDERS) if renders else 0)
    with progress_bar("CAD: build, check, export", n_steps, enabled=show_progress) as advance:
        if model is None:
            model = build_cad(design, cad, progress=advance)
        manifest, meshes = export_files(model, out, advance)
        files = {**manifest.files, **_write_glb(model, meshes, out)}
        advance()
        if renders:
            from . import render

            for name, fn_name in RENDERS.items():
                data = getattr(render, fn_name)(model, meshes)
                files[name] = write_file(out / name, data, "render")
                advance()
    manifest = replace(manifest, files=dict(sorted(files.items())))
    (out / "manifest.json").write_text(json.dumps(manifest.to_dict(), indent=2, sort_keys=False) + "\n")
    return manifest


def _write_glb(model: CadModel, meshes: dict, out: Path) -> dict[str, FileRecord]:
    """``assembly.glb`` (assembly + gas parts, cut open) and ``mould.glb`` (opened mould), manifest records."""
    from .gltf import assembly_scene, glb_bytes, mould_scene
    from .mesh import to_mesh

    cad = model.layout.cad
    asm = glb_bytes(assembly_scene(model.group("assembly", "gas"), cad.stl_tolerance_mm,
                                   cad.stl_angular_tolerance_rad))
    x0, x1, y0, y1, _, _ = model.mould.block_mm
    cavity = to_mesh(model.mould.cavity, cad.stl_tolerance_mm, cad.stl_angular_tolerance_rad)
    mould = glb_bytes(mould_scene(meshes, cavity, gap_mm=0.6 * (y1 - y0)))
    return {
        "assembly.glb": write_file(out / "assembly.glb", asm, "glb", parts=tuple(model.group("assembly", "gas")),
                                   about="x = 0, cut open on y = 0 (y >= 0 kept), metres, +Y up"),
        "mould.glb": write_file(out / "mould.glb", mould, "glb",
                                parts=("mould_half_a", "mould_half_b", "mould_core", "bladder"),
                                about="mould frame opened along y, metres, +Y up"),
    }
