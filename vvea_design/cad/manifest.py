"""The CAD set's manifest as typed records: :class:`CadManifest` is what
:func:`~vvea_design.cad.write.write_cad` returns; its ``to_dict()`` is the
content of ``manifest.json`` (key order included: the file is byte-stable).

Lengths in mm, areas in mm², volumes in mm³; relative errors as fractions.
"""

from __future__ import annotations

import json
from collections.abc import Mapping
from dataclasses import asdict, dataclass

from ..spring.design import Design
from .layout import CadParameters

__all__ = ["FileRecord", "PartRecord", "MeasuredCheck", "WallCheck", "Envelope", "MouldCheck", "CadManifest",
           "GENERATOR", "FRAME"]

#: The manifest's ``generator``.
GENERATOR = "vvea_design.cad.write_cad"
#: The manifest's ``frame``: the coordinate frames of the parts.
FRAME = ("axis Z, z = 0 at the base underside, x > 0 moves the piston towards the base; "
         "mould parts in the mould frame (cavity centred on z = 0, parting plane y = 0)")

BBox = tuple[tuple[float, float, float], tuple[float, float, float]]


def _bbox_list(bb: BBox | None) -> list[list[float]] | None:
    return None if bb is None else [list(bb[0]), list(bb[1])]


@dataclass(frozen=True)
class FileRecord:
    """One file of the CAD set: its size and digest, its kind and what it holds.

    A part's own file (STEP or STL) names the part, its material, volume (mm³) and bounding box (mm); an STL
    also its triangle count, mesh volume (mm³) and watertightness. A file of several parts (``assembly.step``,
    a GLB scene) lists them; a render is just a picture.
    """

    size_bytes: int  #: file size, count of bytes
    sha256: str  #: hex digest of the content
    kind: str  #: "step", "stl", "glb" or "render"
    part: str | None = None  #: the part it holds (``"assembly"`` for assembly.step)
    parts: tuple[str, ...] | None = None  #: the parts of an assembly or scene
    material: str | None = None
    volume_mm3: float | None = None
    bbox_mm: BBox | None = None  #: ((xmin, ymin, zmin), (xmax, ymax, zmax)), mm
    triangles: int | None = None  #: STL triangle count
    mesh_volume_mm3: float | None = None  #: STL mesh volume, mm³
    watertight: bool | None = None  #: STL mesh closed
    about: str | None = None  #: what a scene shows (frame, units)

    @property
    def is_part_file(self) -> bool:
        """A single part's STEP or STL (not an assembly, scene or render)."""
        return self.parts is None and self.part is not None

    def to_dict(self) -> dict:
        """The file's entry of ``manifest.json``.

        Returns
        -------
        dict
            ``bytes`` (count) and ``sha256``; then for a part's own file ``part``, ``material``,
            ``volume_mm3`` (mm³), ``bbox_mm`` (mm), ``kind`` and for an STL ``triangles`` (count),
            ``mesh_volume_mm3`` (mm³), ``watertight``; for any other file ``kind`` first, then those of
            ``part``, ``parts``, ``material``, ``volume_mm3``, ``bbox_mm``, ``about`` it has.
        """
        out: dict = {"bytes": self.size_bytes, "sha256": self.sha256}
        if self.is_part_file:
            out.update(part=self.part, material=self.material, volume_mm3=self.volume_mm3,
                       bbox_mm=_bbox_list(self.bbox_mm), kind=self.kind)
            if self.triangles is not None:
                out.update(triangles=self.triangles, mesh_volume_mm3=self.mesh_volume_mm3, watertight=self.watertight)
            return out
        out["kind"] = self.kind
        extra = {"part": self.part, "parts": None if self.parts is None else list(self.parts),
                 "material": self.material, "volume_mm3": self.volume_mm3, "bbox_mm": _bbox_list(self.bbox_mm),
                 "about": self.about}
        out.update({k: v for k, v in extra.items() if v is not None})
        return out


@dataclass(frozen=True)
class PartRecord:
    """One part of the table as drawn: title, group, material, colour, drawn and closed-form volume, files."""

    title: str
    group: str
    material: str
    colour_rgb: tuple[float, float, float]  #: RGB 0..1, rounded to 0.001
    volume_mm3: float  #: of the solid, mm³
    closed_form_volume_mm3: float | None  #: the closed form, mm³ (None: the part has none)
    files: tuple[str, ...]  #: its file names

    def to_dict(self) -> dict:
        """The part's entry of ``manifest.json``.

        Returns
        -------
        dict
            ``title``, ``group``, ``material``, ``colour_rgb`` (0..1), ``volume_mm3`` and
            ``closed_form_volume_mm3`` (mm³, None without a closed form), ``files``.
        """
        return {"title": self.title, "group": self.group, "material": self.material,
                "colour_rgb": list(self.colour_rgb), "volume_mm3": self.volume_mm3,
                "closed_form_volume_mm3": self.closed_form_volume_mm3, "files": list(self.files)}


@dataclass(frozen=True)
class MeasuredCheck:
    """A quantity measured on the solids next to the design's value (same unit as its name says)."""

    cad: float  #: measured on the solids
    design: float  #: the design's value
    rel_error: float  #: (cad - design) / design, fraction (three significant digits)

    def to_dict(self) -> dict:
        """The entry of ``manifest.json``'s ``measured``.

        Returns
        -------
        dict
            ``cad``, ``design`` (the quantity's unit, mm³ or mm²) and ``rel_error`` (fraction).
        """
        return {"cad": self.cad, "design": self.design, "rel_error": self.rel_error}


@dataclass(frozen=True)
class WallCheck:
    """A wall as drawn next to the minimum its hoop stress needs, mm."""

    drawn: float  #: mm
    minimum: float  #: mm

    def to_dict(self) -> dict:
        """The entry of ``manifest.json``'s ``walls_mm``.

        Returns
        -------
        dict
            ``drawn`` and ``minimum``, mm.
        """
        return {"drawn": self.drawn, "minimum": self.minimum}


@dataclass(frozen=True)
class Envelope:
    """The unit's envelope: the design's outer diameter and housing length, the housing's bounding box, mm."""

    outer_diameter_mm: float
    housing_length_mm: float
    housing_bbox_mm: BBox  #: of the united housing, mm

    def to_dict(self) -> dict:
        """``manifest.json``'s ``envelope_mm``.

        Returns
        -------
        dict
            ``outer_diameter_mm``, ``housing_length_mm`` and ``housing_bbox_mm``, mm.
        """
        return {"outer_diameter_mm": self.outer_diameter_mm, "housing_length_mm": self.housing_length_mm,
                "housing_bbox_mm": _bbox_list(self.housing_bbox_mm)}


@dataclass(frozen=True)
class MouldCheck:
    """The bladder mould's checks: cavity measured as the closed mould's void, openings reached."""

    shrinkage: float  #: silicone shrinkage the cavity is scaled by, fraction
    cavity_volume_mm3: float  #: measured, mm³
    bladder_volume_mm3: float  #: of the drawn bladder, mm³
    expected_cavity_volume_mm3: float  #: bladder x (1 + shrinkage)³, closed form, mm³
    sprue_open: bool  #: the void reaches the sprue's opening
    vents_open: tuple[bool, ...]  #: the void reaches each vent's opening

    def to_dict(self) -> dict:
        """``manifest.json``'s ``mould``.

        Returns
        -------
        dict
            ``shrinkage`` (fraction), ``cavity_volume_mm3``, ``bladder_volume_mm3``,
            ``expected_cavity_volume_mm3`` (mm³), ``sprue_open`` and ``vents_open``.
        """
        return {"shrinkage": self.shrinkage, "cavity_volume_mm3": self.cavity_volume_mm3,
                "bladder_volume_mm3": self.bladder_volume_mm3,
                "expected_cavity_volume_mm3": self.expected_cavity_volume_mm3, "sprue_open": self.sprue_open,
                "vents_open": list(self.vents_open)}


@dataclass(frozen=True, eq=False)
class CadManifest:
    """Everything ``write_cad`` wrote and checked: the design and CAD parameters, the CAD-measured chamber
    volumes and piston areas next to the design's, interference, walls, envelope, mould, the seals and leak
    paths, the oil and gas fill, the assembly check, every part and every file. ``to_dict()`` is
    ``manifest.json``."""

    design: Design  #: the design drawn (mm, mm³)
    cad_parameters: CadParameters  #: the feature sizes drawn with
    measured: Mapping[str, MeasuredCheck]  #: by quantity (``chamber_1_volume_mm3``, ``piston_area_A1_mm2``, ...)
    interference_mm3: Mapping[str, Mapping[str, float]]  #: by displacement (``x_0_mm``), then pair ``a/b``, mm³
    walls_mm: Mapping[str, WallCheck]  #: by wall
    envelope_mm: Envelope
    mould: MouldCheck
    parts: Mapping[str, PartRecord]  #: by part name, in table order
    files: Mapping[str, FileRecord]  #: by file name
    generator: str = GENERATOR
    frame: str = FRAME
    seals: tuple[dict, ...] = ()  #: every O-ring gland (:meth:`~vvea_design.cad.seals.Gland.to_dict`, quantity)
    leak_paths: tuple[dict, ...] = ()  #: every joint and port and its seal (:class:`~vvea_design.cad.leaks.LeakPath`)
    fill: Mapping[str, object] | None = None  #: the oil fill (mm³) and the nitrogen charges (MPa, mm³, g)
    assembly: Mapping[str, object] | None = None  #: the assembly order checked (:class:`~vvea_design.cad.sequence.AssemblyCheck`)

    @property
    def assembly_passes(self) -> bool | None:
        """The assembly check's verdict (the parts go together in order, no O-ring over a thread or a sharp edge);
        None when it was not run."""
        return None if self.assembly is None else bool(self.assembly.get("passes"))

    @property
    def unsealed_paths(self) -> tuple[str, ...]:
        """Where a leak path of the audit has no seal (``where: between``); empty when every joint and port is
        sealed or the audit was not run."""
        return tuple(f"{p['where']}: {p['between']}" for p in self.leak_paths if not p.get("sealed"))

    def to_dict(self) -> dict:
        """The content of ``manifest.json`` (plain JSON types, units in the keys).

        Returns
        -------
        dict
            ``generator``, ``design``, ``cad_parameters``, ``frame``, ``measured`` (mm³, mm², fractions),
            ``interference_mm3`` (mm³), ``walls_mm`` (mm), ``envelope_mm`` (mm), ``mould`` (mm³),
            ``seals``, ``leak_paths``, ``fill``, ``assembly`` (those present), ``parts`` and ``files``, in this
            order.
        """
        extra = {"seals": list(self.seals), "leak_paths": list(self.leak_paths), "fill": self.fill,
                 "assembly": self.assembly}
        return {
            "generator": self.generator,
            "design": json.loads(json.dumps(asdict(self.design))),
            "cad_parameters": self.cad_parameters.to_dict(),
            "frame": self.frame,
            "measured": {k: v.to_dict() for k, v in self.measured.items()},
            "interference_mm3": {k: dict(v) for k, v in self.interference_mm3.items()},
            "walls_mm": {k: v.to_dict() for k, v in self.walls_mm.items()},
            "envelope_mm": self.envelope_mm.to_dict(),
            "mould": self.mould.to_dict(),
            **{k: v for k, v in extra.items() if v},
            "parts": {k: v.to_dict() for k, v in self.parts.items()},
            "files": {k: v.to_dict() for k, v in self.files.items()},
        }
