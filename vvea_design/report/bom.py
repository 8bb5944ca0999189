"""Bill of materials of one built CAD model: every part with its material and
mass (CAD volume x density), the O-rings the grooves were sized for, the
bought parts the CAD has seats for, the hydraulic fluid and the bladder
silicone with its cast volume.

The lines come from their owners: every part of
:data:`~vvea_design.cad.registry.PARTS` gives its own through its BOM hook
(a part without one says why), the items the CAD has seats for but does not
model through :data:`~vvea_design.cad.bill.BOUGHT_ITEMS`; this module orders
them by section (:data:`~vvea_design.cad.bill.SECTIONS`), numbers them and adds
the casting totals. :func:`bill_of_materials` returns a typed
:class:`BillOfMaterials` (``to_dict()`` for JSON / the HTML report);
:func:`write_bom` also writes ``bom.csv``. Bought parts the CAD does not model
carry no mass except the lumped servo-and-valve mass of the design
(``fixed.servo_and_valve_mass_g``).
"""

from __future__ import annotations

import csv
import io
from dataclasses import dataclass, replace
from pathlib import Path

from ..cad.assembly import CadModel, mould_void
from ..cad.bill import SECTIONS, BomContext, BomLine, bought_items
from ..cad.registry import all_parts
from ..materials.silicones import get_silicone
from ..materials.structural import DENSITY_SILICONE_g_per_mm3

__all__ = ["BomLine", "BillOfMaterials", "bill_of_materials", "write_bom", "CSV_COLUMNS", "POUR_ALLOWANCE"]

#: Extra silicone mixed over the mould's void (cup and mixer losses), fraction.
POUR_ALLOWANCE = 0.15

#: Column order of ``bom.csv``.
CSV_COLUMNS = ("item", "part", "description", "category", "material", "standard", "size", "quantity",
               "unit_volume_mm3", "unit_mass_g", "total_mass_g", "torque_Nm", "in_unit", "file", "note")


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
        Lines in order: made parts (table order), seals, bought parts, fluid, tooling (table order),
        numbered from 1; masses in g, volumes in mm³.

    Raises
    ------
    ValueError
        For an unknown silicone key (names the known ones).
    """
    sil = get_silicone(silicone)
    ctx = BomContext(model.layout, model.solids, sil)
    found = [line for part in all_parts() if part.bom is not None for line in part.bom(part, ctx)]
    found += [line for hook in bought_items() for line in hook(ctx)]
    found.sort(key=lambda line: SECTIONS.index(line.section))  # stable: table order inside a section
    lines = tuple(replace(line, item=i) for i, line in enumerate(found, start=1))
    void = mould_void(model.mould).void_volume_mm3
    mix = void * (1 + POUR_ALLOWANCE)
    return BillOfMaterials(lines=lines, silicone=f"{sil.name} ({sil.hardness})",
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
