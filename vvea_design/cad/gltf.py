"""Compact binary glTF (GLB) scenes of the CAD set for an interactive 3-D view.

* ``assembly.glb`` -- the unit at x = 0 cut open on the meridian plane
  (the half y < 0 removed, cut faces capped and facing glTF +Z) so the chambers, piston and
  bladder are visible; gas chambers translucent. One node per part, named
  after it, coloured from the part table.
* ``mould.glb`` -- the mould opened along y (half A +y, half B -y) with the
  core and the cast bladder between.

glTF is metres and +Y up: the CAD's mm are scaled by 1e-3 and its +Z axis
turned to +Y. The meshes are the export tessellation (STL), so the view is
what the files hold; the bytes depend on the design only (vertex normals are
rounded to 1e-6, so the float noise of their averaging, which differs between
trimesh/numpy releases, does not reach the file).
"""

from __future__ import annotations

import numpy as np
import trimesh

from .mesh import to_mesh
from .registry import get_part

__all__ = ["glb_bytes", "assembly_scene", "mould_scene", "GLB_TO_METRES"]

#: mm -> m and CAD +Z up -> glTF +Y up.
GLB_TO_METRES = np.array([[1e-3, 0, 0, 0], [0, 0, 1e-3, 0], [0, -1e-3, 0, 0], [0, 0, 0, 1]], dtype=float)
#: Decimals the vertex normals keep (byte-stable GLB across trimesh/numpy releases).
NORMAL_DECIMALS = 6


def _material(rgb, alpha: float = 1.0):
    from trimesh.visual.material import PBRMaterial

    return PBRMaterial(baseColorFactor=[*(float(c) for c in rgb), float(alpha)], metallicFactor=0.1,
                       roughnessFactor=0.7, alphaMode="BLEND" if alpha < 1 else "OPAQUE", doubleSided=True)


def _half(solid, tolerance_mm: float, angular_tolerance_rad: float) -> trimesh.Trimesh:
    """Keep y >= 0 of ``solid`` (exact boolean, so the cut is capped; its face looks along glTF +Z,
    towards a default camera) and tessellate it (mm). The half may fall apart into several
    solids (a chamber ported through a riser off the meridian plane): all of them are kept."""
    from .mould import box

    bb = solid.bounding_box()
    if bb.min.Y >= -1e-9:
        half = solid
    else:
        half = solid.cut(box(bb.min.X - 1, bb.max.X + 1, bb.min.Y - 1, 0.0, bb.min.Z - 1, bb.max.Z + 1)).clean()
    return to_mesh(half, tolerance_mm, angular_tolerance_rad)


def _scene(nodes: list[tuple[str, trimesh.Trimesh, tuple, float]]) -> trimesh.Scene:
    scene = trimesh.Scene()
    for name, mesh, rgb, alpha in nodes:
        m = trimesh.Trimesh(np.asarray(mesh.vertices, dtype=np.float64), np.asarray(mesh.faces, dtype=np.int64),
                            process=False)
        m.apply_transform(GLB_TO_METRES)
        m.visual = trimesh.visual.TextureVisuals(material=_material(rgb, alpha))
        # Vertex normals rounded to 1e-6 (and -0.0 made 0.0): the averaging leaves float noise
        # (~1e-16 where a component is zero) that differs between trimesh/numpy releases, and
        # the file's bytes should depend on the design only.
        m.vertex_normals = np.round(np.asarray(m.vertex_normals, dtype=np.float64), NORMAL_DECIMALS) + 0.0
        scene.add_geometry(m, node_name=name, geom_name=name)
    return scene


def assembly_scene(solids: dict, tolerance_mm: float = 0.05, angular_tolerance_rad: float = 0.1) -> trimesh.Scene:
    """Part solids by name (assembly frame, mm) cut open on y = 0, as a glTF scene (m, +Y up).

    Parameters
    ----------
    solids : dict of str to Solid
        Parts of the table by name, mm; gas parts become translucent (alpha 0.35).
    tolerance_mm : float
        Tessellation linear deflection, mm.
    angular_tolerance_rad : float
        Tessellation angular deflection, rad.

    Returns
    -------
    trimesh.Scene
        One named node per part, coloured from the part table, in metres.
    """
    nodes = []
    for name, solid in solids.items():
        part = get_part(name)
        alpha = 0.35 if part.group == "gas" else 1.0
        nodes.append((name, _half(solid, tolerance_mm, angular_tolerance_rad), part.colour, alpha))
    return _scene(nodes)


def mould_scene(meshes: dict[str, trimesh.Trimesh], cavity: trimesh.Trimesh, gap_mm: float) -> trimesh.Scene:
    """The mould opened along y, core and cast bladder between, as a glTF scene (m, +Y up).

    Parameters
    ----------
    meshes : dict of str to trimesh.Trimesh
        Tessellated mould parts (``mould_half_a``, ``mould_half_b``, ``mould_core``), mould frame, mm.
    cavity : trimesh.Trimesh
        The cavity (= cast bladder) mesh, mould frame, mm.
    gap_mm : float
        How far each half moves away from the parting plane, mm.

    Returns
    -------
    trimesh.Scene
        Nodes ``mould_half_a``, ``mould_half_b``, ``mould_core``, ``bladder`` in metres.
    """
    a = meshes["mould_half_a"].copy()
    a.apply_translation([0, gap_mm, 0])
    b = meshes["mould_half_b"].copy()
    b.apply_translation([0, -gap_mm, 0])
    return _scene([("mould_half_a", a, get_part("mould_half_a").colour, 1.0),
                   ("mould_half_b", b, get_part("mould_half_b").colour, 1.0),
                   ("mould_core", meshes["mould_core"], get_part("mould_core").colour, 1.0),
                   ("bladder", cavity, get_part("bladder").colour, 1.0)])


def glb_bytes(scene: trimesh.Scene) -> bytes:
    """The scene as binary glTF 2.0.

    Parameters
    ----------
    scene : trimesh.Scene
        Scene to export (metres).

    Returns
    -------
    bytes
        GLB bytes (deterministic for a given scene).
    """
    # unitize_normals=False: the normals are unit and rounded already (_scene); trimesh >= 5
    # re-normalises by default, which would bring the float noise back.
    return trimesh.exchange.gltf.export_glb(scene, include_normals=True, unitize_normals=False)
