"""Bill-of-materials lines of the CAD set: the line type, what a BOM hook is
given, and the items the unit needs that the CAD has seats for but does not
model (O-rings, servo and valve, screws, relief ball, fill valves, fluid).

Each part of :data:`~vvea_design.cad.registry.PARTS` owns its line through its
BOM hook (``part.bom(part, ctx)``); :data:`BOUGHT_ITEMS` holds the hooks of the
other items, one function each, in bill order. :func:`vvea_design.report.bom.bill_of_materials`
collects every hook's lines, orders them by :data:`SECTIONS` (made parts, seals,
bought parts, fluid, tooling; table order inside a section) and numbers them.
Masses: made parts CAD volume x density; bought parts carry no mass except the
lumped servo-and-valve mass of the design (``fixed.servo_and_valve_mass_g``).
"""

from __future__ import annotations

from collections.abc import Callable, Mapping
from dataclasses import dataclass

from build123d import Solid

from ..materials.silicones import Silicone
from ..materials.structural import DENSITY_HYDRAULIC_OIL_g_per_mm3
from ..spring.design import Design
from .layout import Layout

__all__ = ["BomLine", "BomContext", "SECTIONS", "BOUGHT_ITEMS", "bought_items", "o_rings", "servo_and_valve",
           "servo_screws", "relief_ball", "fill_valves", "hydraulic_fluid"]

#: The sections of the bill, in order: ``made`` (machined, turned, printed, cast parts), then seals, bought
#: parts, fluid and tooling (not part of the unit).
SECTIONS = ("made", "seal", "bought", "fluid", "tooling")


@dataclass(frozen=True)
class BomLine:
    """One line of the bill of materials (mm³, g)."""

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
    item: int = 0  #: position in the bill, 1, 2, ... (0 until the bill numbers its lines)

    @property
    def total_mass_g(self) -> float | None:
        """Mass of the line's quantity, g (None when the unit mass is unknown)."""
        return None if self.unit_mass_g is None else self.unit_mass_g * self.quantity

    @property
    def section(self) -> str:
        """The section of the bill the line belongs to (one of :data:`SECTIONS`, from its category)."""
        return self.category if self.category in SECTIONS else "made"

    def to_dict(self) -> dict:
        """Plain-JSON dictionary of the line (the columns of ``bom.csv``).

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


@dataclass(frozen=True, eq=False)
class BomContext:
    """What a BOM hook is given: the built solids of one design and the bladder's casting silicone."""

    layout: Layout  #: radii, levels, glands and CAD parameters of the design, mm
    solids: Mapping[str, Solid]  #: every part's solid by name (x = 0), mm
    silicone: Silicone  #: the silicone the bladder is cast in

    @property
    def design(self) -> Design:
        """The design the solids were built from."""
        return self.layout.design


def o_rings(ctx: BomContext) -> tuple[BomLine, ...]:
    """The O-rings the grooves were sized for: piston (2), rod, and the collar's static seal if there is one.

    Parameters
    ----------
    ctx : BomContext
        The design's layout (its glands, mm).

    Returns
    -------
    tuple of BomLine
        One ``seal`` line per gland: ISO 3601 size, quantity, groove (mm), stretch and squeeze (%).
    """
    lay = ctx.layout
    glands = [(lay.piston_seal, 2, "piston seal"), (lay.rod_seal, 1, "rod seal (base)")]
    if lay.collar_seal is not None:
        glands.append((lay.collar_seal, 1, "collar to outer-tube bore (static)"))
    return tuple(
        BomLine(part=f"oring_{gland.kind}", description=f"O-ring, {where}", category="seal",
                material="NBR 70 Shore A (or FKM)", standard="ISO 3601-1 class A / AS568", size=gland.oring.name,
                quantity=qty, unit_volume_mm3=None, unit_mass_g=None, in_unit=True,
                note=f"groove {gland.groove_diameter_mm:.2f} x {gland.width_mm:.2f} mm; stretch "
                     f"{100 * gland.stretch:.1f} %, squeeze {100 * gland.squeeze:.0f} %")
        for gland, qty, where in glands)


def servo_and_valve(ctx: BomContext) -> tuple[BomLine, ...]:
    """The servo with the rotary throttle core and fittings (the design's lumped mass).

    Parameters
    ----------
    ctx : BomContext
        The design (``fixed.servo_and_valve_mass_g``, g) and its throttle bore (mm).

    Returns
    -------
    tuple of BomLine
        One ``bought`` line with the lumped mass, g.
    """
    lay = ctx.layout
    return (BomLine(part="servo_and_valve", description="servo (BMS-390DMH class), rotary throttle core, fittings",
                    category="bought", material="-", standard="", size=f"throttle bore Ø{lay.throttle_d:g} mm",
                    quantity=1, unit_volume_mm3=None, unit_mass_g=ctx.design.fixed.servo_and_valve_mass_g,
                    in_unit=True, note="lumped mass from the design (fixed.servo_and_valve_mass_g)"),)


def servo_screws(ctx: BomContext) -> tuple[BomLine, ...]:
    """The two servo mount screws (the base's tapped holes).

    Parameters
    ----------
    ctx : BomContext
        The CAD parameters (tap drill and depth, mm).

    Returns
    -------
    tuple of BomLine
        One ``bought`` line, M3 ISO 4762, quantity 2.
    """
    c = ctx.layout.cad
    return (BomLine(part="servo_screws", description="servo mount screws", category="bought", material="steel 8.8",
                    standard="ISO 4762", size=f"M3 (tapped Ø{c.servo_screw_core_mm:g} x {c.servo_screw_depth_mm:g} deep)",
                    quantity=2, unit_volume_mm3=None, unit_mass_g=None, in_unit=True,
                    note="length to suit the servo bracket"),)


def relief_ball(ctx: BomContext) -> tuple[BomLine, ...]:
    """The relief valve's ball (the base's stepped relief bore).

    Parameters
    ----------
    ctx : BomContext
        The relief bore and seat diameters, mm.

    Returns
    -------
    tuple of BomLine
        One ``bought`` line, ISO 3290-1 ball, diameter in mm.
    """
    lay = ctx.layout
    seat = lay.cad.relief_seat_mm
    return (BomLine(part="relief_ball", description="relief valve ball", category="bought", material="steel 100Cr6",
                    standard="ISO 3290-1", size=f"Ø{min(lay.relief_d, 1.2 * seat):g} mm (seat Ø{seat:g})",
                    quantity=1, unit_volume_mm3=None, unit_mass_g=None, in_unit=True,
                    note="spring to suit the relief pressure"),)


def fill_valves(ctx: BomContext) -> tuple[BomLine, ...]:
    """The gas fill valves of chambers 1 and 2 (the M5 counterbores of the fill ports).

    Parameters
    ----------
    ctx : BomContext
        The CAD parameters (counterbore diameter, mm).

    Returns
    -------
    tuple of BomLine
        One ``bought`` line, M5, quantity 2.
    """
    c = ctx.layout.cad
    return (BomLine(part="fill_valves", description="gas fill valves, chambers 1 and 2", category="bought",
                    material="-", standard="", size=f"M5 (counterbore Ø{c.fill_port_counterbore_mm:g})", quantity=2,
                    unit_volume_mm3=None, unit_mass_g=None, in_unit=True, note="charge with nitrogen"),)


def hydraulic_fluid(ctx: BomContext) -> tuple[BomLine, ...]:
    """The hydraulic oil of the fluid column (the channels not counted).

    Parameters
    ----------
    ctx : BomContext
        The design (``fluid_volume_mm3``, mm³).

    Returns
    -------
    tuple of BomLine
        One ``fluid`` line: volume (mm³) and mass (g).
    """
    fluid = max(ctx.design.fluid_volume_mm3, 0.0)
    return (BomLine(part="hydraulic_fluid", description="fluid column and channels (column only counted)",
                    category="fluid", material="hydraulic oil", standard="ISO 6743-4 HM", size="ISO VG 32",
                    quantity=1, unit_volume_mm3=fluid, unit_mass_g=fluid * DENSITY_HYDRAULIC_OIL_g_per_mm3,
                    in_unit=True, note=f"mass = volume x {DENSITY_HYDRAULIC_OIL_g_per_mm3:g} g/mm³"),)


#: The BOM hooks of the items the CAD has seats for but does not model, in bill order.
BOUGHT_ITEMS: tuple[Callable[[BomContext], tuple[BomLine, ...]], ...] = (
    o_rings, servo_and_valve, servo_screws, relief_ball, fill_valves, hydraulic_fluid)


def bought_items() -> tuple[Callable[[BomContext], tuple[BomLine, ...]], ...]:
    """The bought items' BOM hooks, looked up at call time (the bill goes through this).

    Returns
    -------
    tuple of callable
        :data:`BOUGHT_ITEMS`: each ``hook(ctx) -> tuple of BomLine``, in bill order.
    """
    return BOUGHT_ITEMS
