"""CAD of the spring-damper unit from the frozen design (build123d solids,
trimesh checks, pyvista renders).

Data flow: :class:`~vvea_design.spring.design.Design` -> :class:`Layout` (derived
radii and levels, validated) -> the part table :data:`PARTS` (one entry per
part: builder, material, colour, closed-form volume, files, drawing hook,
BOM hook) -> :func:`build_cad` (every solid once, named and coloured) ->
:func:`write_cad` (STEP, STL, renders and the typed :class:`CadManifest`,
written as ``manifest.json``).

One module per concept: ``layout`` (dimensions and CAD parameters),
``parts`` (housing, piston with rod), ``bladder`` (bladder, support ring),
``gas`` (gas domains, fluid column), ``mould`` (bladder mould), ``registry``
(the part table), ``drafting`` (the drawing vocabulary: dimensions, leaders,
fits, sheet content), ``sheets`` (what each sheet dimensions: the parts'
drawing hooks and the unit's section), ``bill`` (bill-of-materials lines,
the bought items' hooks), ``assembly`` (the set, named assembly, checks),
``mesh`` (tessellation), ``export`` (deterministic files), ``manifest`` (the
typed manifest), ``render`` (off-screen pictures), ``write`` (``write_cad``,
the top of the package). Adding a part touches ``registry`` only (plus its
builder and hooks).
"""

from .assembly import CadModel, MouldVoid, assembly, build_cad, interference_mm3, mould_void
from .bill import BomContext, BomLine
from .bladder import bladder, bladder_volume_mm3, support_ring
from .drafting import Detail, Dim, Leader, SheetContent, fit_deviations_um
from .export import STEP_TIMESTAMP, step_bytes, stl_bytes
from .mesh import to_mesh
from .gas import fluid_column, gas_chamber_1, gas_chamber_2
from .layout import CadError, CadParameters, Layout
from .manifest import CadManifest, FileRecord, PartRecord
from .mould import Mould, mould
from .parts import housing, housing_pieces, piston, piston_faces_mm2, piston_head, piston_volume_mm3
from .registry import PARTS, Part, PartMaterial, get_part, parts_in
from .sheets import unit_section_sheet
from .write import write_cad

__all__ = [
    "CadError", "CadParameters", "Layout", "CadModel", "Mould", "MouldVoid", "CadManifest", "FileRecord", "PartRecord",
    "build_cad", "write_cad", "assembly", "interference_mm3", "mould_void",
    "housing", "housing_pieces", "piston", "piston_head", "piston_volume_mm3", "piston_faces_mm2",
    "bladder", "bladder_volume_mm3", "support_ring", "gas_chamber_1", "gas_chamber_2", "fluid_column", "mould",
    "STEP_TIMESTAMP", "step_bytes", "stl_bytes", "to_mesh",
    "PARTS", "Part", "PartMaterial", "get_part", "parts_in",
    "Dim", "Leader", "Detail", "SheetContent", "fit_deviations_um", "unit_section_sheet", "BomLine", "BomContext",
]
