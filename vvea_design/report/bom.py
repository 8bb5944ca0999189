"""Bill of materials of one built CAD model: every part with its material and
mass (CAD volume x density), the O-rings the grooves were sized for, the
bought parts the CAD has seats for, the hydraulic fluid and the bladder
silicone with its cast volume.

:func:`bill_of_materials` returns a typed :class:`BillOfMaterials`
(``to_dict()`` for JSON / the HTML report); :func:`write_bom` also writes
``bom.csv``. Masses of made parts come from the solids' volumes
(:data:`~vvea_design.cad.registry.PARTS` gives material and process);
bought parts the CAD does not model carry no mass except the lumped
servo-and-valve mass of the design (``fixed.servo_and_valve_mass_g``).
"""

from __future__ import annotations

import csv
import io
from dataclasses import dataclass
from pathlib import Path

from ..cad.assembly import CadModel, mould_void
from ..cad.registry import all_parts
from ..materials.silicones import get_silicone
from ..materials.structural import DENSITY_HYDRAULIC_OIL_g_per_mm3, DENSITY_SILICONE_g_per_mm3

__all__ = ["BomLine", "BillOfMaterials", "bill_of_materials", "write_bom", "CSV_COLUMNS", "POUR_ALLOWANCE"]

#: Extra silicone mixed over the mould's void (cup and mixer losses), fraction.
POUR_ALLOWANCE = 0.15

#: Column order of ``bom.csv``.
CSV_COLUMNS = ("item", "part", "description", "category", "material", "standard", "size", "quantity",
               "unit_volume_mm3", "unit_mass_g", "total_mass_g", "in_unit", "file", "note")


@dataclass(frozen=True)
class BomLine:
    """One line of the bill of materials (mm³, g)."""

    item: int
    part: str  #: part name (file stem for made parts)
    description: str
    category: str  #: machined, turned, printed, cast, seal, bought, fluid, tooling
    material: str
    standard: str  #: standard the item is ordered to ("" for made parts)
    size: str  #: order size ("" if the drawing defines it)
    quantity: int
    unit_volume_mm3: float | None
    unit_mass_g: float | None
    in_unit: bool  #: counts towards the unit's mass (tooling does not)
    file: str = ""
    note: str = ""

    @property
    def total_mass_g(self) -> float | None:
        return None if self.unit_mass_g is None else self.unit_mass_g * self.quantity

    def to_dict(self) -> dict:
        """Plain-JSON dictionary of the line (the keys of :data:`CSV_COLUMNS`).

        Returns
        -------
        dict
            JSON-ready: ``item``, ``part``, ``description``, ``category``, ``material``, ``standard``,
            ``size``, ``quantity`` (count), ``unit_volume_mm3`` (mm³), ``unit_mass_g`` and
            ``total_mass_g`` (g; ``None`` when unknown), ``in_unit``, ``file`` and ``note``.
        """
        return {"item": self.item, "part": self.part, "description": self.description, "category": self.category,
                "material": self.material, "standard": self.standard, "size": self.size,
                "quantity": self.quantity, "unit_volume_mm3": self.unit_volume_mm3,
                "unit_mass_g": self.unit_mass_g, "total_mass_g": self.total_mass_g, "in_unit": self.in_unit,
                "file": self.file, "note": self.note}


@dataclass(frozen=True)
class BillOfMaterials:
    """The whole list plus the totals a designer asks for first (g, mm³)."""

    lines: tuple[BomLine, ...]
    silicone: str  #: the bladder's casting silicone (name)
    bladder_volume_mm3: float  #: cured bladder (CAD)
    mould_void_mm3: float  #: what the closed mould takes: cavity + sprue + runner + vents
    silicone_to_mix_mm3: float  #: void x (1 + POUR_ALLOWANCE)
    silicone_to_mix_g: float

    @property
    def unit_mass_g(self) -> float:
        """Mass of the unit: every line in the unit with a mass (tooling excluded), g."""
        return float(sum(line.total_mass_g for line in self.lines if line.in_unit and line.total_mass_g is not None))

    def to_dict(self) -> dict:
        """Plain-JSON dictionary of the lines and the totals.

        Returns
        -------
        dict
            JSON-ready: ``lines`` (:meth:`BomLine.to_dict` each), ``silicone`` (name),
            ``bladder_volume_mm3``, ``mould_void_mm3`` and ``silicone_to_mix_mm3`` (mm³),
            ``silicone_to_mix_g`` (g), ``pour_allowance`` (fraction), ``unit_mass_g`` (g) and
            ``mass_source`` (how the masses were obtained).
        """
        return {"lines": [line.to_dict() for line in self.lines], "silicone": self.silicone,
                "bladder_volume_mm3": self.bladder_volume_mm3, "mould_void_mm3": self.mould_void_mm3,
                "silicone_to_mix_mm3": self.silicone_to_mix_mm3, "silicone_to_mix_g": self.silicone_to_mix_g,
                "pour_allowance": POUR_ALLOWANCE, "unit_mass_g": self.unit_mass_g,
                "mass_source": "made parts: CAD volume x density; bought parts: design's servo_and_valve_mass_g"}

    def csv_text(self) -> str:
        """The lines as CSV (columns :data:`CSV_COLUMNS`), volumes and masses rounded to 0.01.

        Returns
        -------
        str
            The CSV text: a header row, then one row per line; volumes in mm³ and masses in g with two
            decimals, ``None`` as an empty cell, booleans as ``true`` / ``false``; one newline after each row.
        """
        buf = io.StringIO()
        w = csv.writer(buf, lineterminator="\n")
        w.writerow(CSV_COLUMNS)
        for line in self.lines:
            d = line.to_dict()
            row = []
            for col in CSV_COLUMNS:
                v = d[col]
                row.append("" if v is None else f"{v:.2f}" if isinstance(v, float) else str(v).lower()
                           if isinstance(v, bool) else v)
            w.writerow(row)
        return buf.getvalue()


def bill_of_materials(model: CadModel, silicone: str = "dragon-skin-20") -> BillOfMaterials:
    """The bill of materials of ``model`` with the bladder cast in ``silicone``.

    Parameters
    ----------
    model : CadModel
        The built CAD set (:func:`~vvea_design.cad.build_cad`).
    silicone : str
        Key of the casting silicone (:data:`~vvea_design.materials.silicones.SILICONES`).

    Returns
    -------
    BillOfMaterials
        Lines in order: made parts (table order), seals, bought parts, fluid, tooling; masses in g.

    Raises
    ------
    ValueError
        For an unknown silicone key (names the known ones).
    """
    d, lay = model.design, model.layout
    sil = get_silicone(silicone)
    lines: list[BomLine] = []

    def add(**kw) -> None:
        lines.append(BomLine(item=len(lines) + 1, **kw))

    for part in all_parts():
        if not part.bom or part.group == "mould":
            continue
        mat = part.material(d)
        vol = float(model.solids[part.name].volume)
        name = mat.name
        note = f"{mat.process}; mass = CAD volume x {mat.density_g_per_mm3:g} g/mm³"
        if part.name == "bladder":
            name = f"{sil.name} ({sil.hardness})"
            note = f"cast in the printed mould; mass = CAD volume x {DENSITY_SILICONE_g_per_mm3:g} g/mm³"
        add(part=part.name, description=part.title, category=mat.process, material=name, standard="", size="",
            quantity=1, unit_volume_mm3=vol, unit_mass_g=vol * mat.density_g_per_mm3, in_unit=True,
            file=f"{part.name}.step", note=note)
    glands = [(lay.piston_seal, 2, "piston seal"), (lay.rod_seal, 1, "rod seal (base)")]
    if lay.collar_seal is not None:
        glands.append((lay.collar_seal, 1, "collar to outer-tube bore (static)"))
    for gland, qty, where in glands:
        o = gland.oring
        add(part=f"oring_{gland.kind}", description=f"O-ring, {where}", category="seal",
            material="NBR 70 Shore A (or FKM)", standard="ISO 3601-1 class A / AS568", size=o.name, quantity=qty,
            unit_volume_mm3=None, unit_mass_g=None, in_unit=True,
            note=f"groove {gland.groove_diameter_mm:.2f} x {gland.width_mm:.2f} mm; stretch {100 * gland.stretch:.1f} %, "
                 f"squeeze {100 * gland.squeeze:.0f} %")
    f = d.fixed
    add(part="servo_and_valve", description="servo (BMS-390DMH class), rotary throttle core, fittings",
        category="bought", material="-", standard="", size=f"throttle bore Ø{lay.throttle_d:g} mm", quantity=1,
        unit_volume_mm3=None, unit_mass_g=f.servo_and_valve_mass_g, in_unit=True,
        note="lumped mass from the design (fixed.servo_and_valve_mass_g)")
    add(part="servo_screws", description="servo mount screws", category="bought", material="steel 8.8",
        standard="ISO 4762", size=f"M3 (tapped Ø{lay.cad.servo_screw_core_mm:g} x {lay.cad.servo_screw_depth_mm:g} deep)",
        quantity=2, unit_volume_mm3=None, unit_mass_g=None, in_unit=True, note="length to suit the servo bracket")
    add(part="relief_ball", description="relief valve ball", category="bought", material="steel 100Cr6",
        standard="ISO 3290-1", size=f"Ø{min(lay.relief_d, 1.2 * lay.cad.relief_seat_mm):g} mm (seat Ø{lay.cad.relief_seat_mm:g})",
        quantity=1, unit_volume_mm3=None, unit_mass_g=None, in_unit=True, note="spring to suit the relief pressure")
    add(part="fill_valves", description="gas fill valves, chambers 1 and 2", category="bought", material="-",
        standard="", size=f"M5 (counterbore Ø{lay.cad.fill_port_counterbore_mm:g})", quantity=2,
        unit_volume_mm3=None, unit_mass_g=None, in_unit=True, note="charge with nitrogen")
    fluid = max(d.fluid_volume_mm3, 0.0)
    add(part="hydraulic_fluid", description="fluid column and channels (column only counted)", category="fluid",
        material="hydraulic oil", standard="ISO 6743-4 HM", size="ISO VG 32", quantity=1, unit_volume_mm3=fluid,
        unit_mass_g=fluid * DENSITY_HYDRAULIC_OIL_g_per_mm3, in_unit=True,
        note=f"mass = volume x {DENSITY_HYDRAULIC_OIL_g_per_mm3:g} g/mm³")
    for part in all_parts():
        if part.group != "mould":
            continue
        mat = part.material(d)
        vol = float(model.solids[part.name].volume)
        add(part=part.name, description=part.title, category="tooling", material=mat.name, standard="", size="",
            quantity=1, unit_volume_mm3=vol, unit_mass_g=vol * mat.density_g_per_mm3, in_unit=False,
            file=f"{part.name}.step", note="bladder mould (not part of the unit); mass at 100 % infill")
    void = mould_void(model.mould)["void_volume_mm3"]
    mix = void * (1 + POUR_ALLOWANCE)
    return BillOfMaterials(lines=tuple(lines), silicone=f"{sil.name} ({sil.hardness})",
                           bladder_volume_mm3=float(model.solids["bladder"].volume), mould_void_mm3=float(void),
                           silicone_to_mix_mm3=float(mix), silicone_to_mix_g=float(mix * DENSITY_SILICONE_g_per_mm3))


def write_bom(model: CadModel, out_dir, silicone: str = "dragon-skin-20") -> BillOfMaterials:
    """Write ``bom.csv`` (and ``bom.json``) for ``model`` into ``out_dir``; return the typed BOM.

    Parameters
    ----------
    model : CadModel
        The built CAD set.
    out_dir : path-like
        Output folder (created).
    silicone : str
        Key of the bladder's casting silicone.

    Returns
    -------
    BillOfMaterials
        What was written.
    """
    import json

    bom = bill_of_materials(model, silicone)
    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    (out / "bom.csv").write_text(bom.csv_text())
    (out / "bom.json").write_text(json.dumps(bom.to_dict(), indent=2) + "\n")
    return bom
