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

import math
from collections.abc import Callable, Mapping
from dataclasses import dataclass

from build123d import Solid

from ..materials.silicones import Silicone
from ..materials.structural import DENSITY_HYDRAULIC_OIL_g_per_mm3
from ..spring.design import Design
from .fill import NITROGEN, OIL, gas_charges, oil_fill_mm3
from .layout import Layout
from .seals import COMPOUND, ORING_STANDARD, Gland

__all__ = ["BomLine", "BomContext", "SECTIONS", "BOUGHT_ITEMS", "bought_items", "glands", "o_rings",
           "housing_joint", "servo_and_valve", "servo_screws", "relief_ball", "relief_ball_mm", "relief_spring_and_screw",
           "proof_pressure_MPa", "fill_valves", "cross_port_plug", "hydraulic_fluid", "gas_charge",
           "TIGHTENING_TORQUE_NM"]

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
    torque_Nm: float | None = None  #: tightening torque of a fastener, N m (None: not a fastener)

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
            ``total_mass_g`` (g; ``None`` when unknown), ``torque_Nm`` (N m; ``None`` unless a fastener),
            ``in_unit``, ``file`` and ``note``.
        """
        return {"item": self.item, "part": self.part, "description": self.description, "category": self.category,
                "material": self.material, "standard": self.standard, "size": self.size,
                "quantity": self.quantity, "unit_volume_mm3": self.unit_volume_mm3,
                "unit_mass_g": self.unit_mass_g, "total_mass_g": self.total_mass_g, "torque_Nm": self.torque_Nm,
                "in_unit": self.in_unit, "file": self.file, "note": self.note}


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


def glands(lay: Layout) -> tuple[tuple[Gland, int, str], ...]:
    """Every O-ring gland of the unit with its quantity and where it is.

    Parameters
    ----------
    lay : Layout
        The design's layout (its glands).

    Returns
    -------
    tuple of (Gland, int, str)
        Piston (2), rod, then the static ones: top cap, base, collar, the inner tube's seats in the base and the
        top cap, the fill tube's neck -- those the layout has.
    """
    out = [(lay.piston_seal, 2, "piston seal (dynamic)"), (lay.rod_seal, 1, "rod seal in the base (dynamic)")]
    seats = lay.seats
    extra = (seats.base, seats.top, seats.fill) if seats is not None else ()
    for g in (lay.cap_seal, lay.base_seal, lay.collar_seal, *extra):
        if g is not None:
            out.append((g, 1, g.where))
    return tuple(out)


def o_rings(ctx: BomContext) -> tuple[BomLine, ...]:
    """The O-rings the grooves were sized for: piston (2), rod, and the static ones (top cap, base, collar, the
    inner tube's seats, the fill tube's neck).

    Parameters
    ----------
    ctx : BomContext
        The design's layout (its glands, mm).

    Returns
    -------
    tuple of BomLine
        One ``seal`` line per gland: ISO 3601-1 size, compound (ISO 3601-5, for the oil and nitrogen), quantity,
        groove (mm), stretch and squeeze (%).
    """
    return tuple(
        BomLine(part=f"oring_{gland.kind}", description=f"O-ring, {where}", category="seal", material=COMPOUND,
                standard=f"{ORING_STANDARD}; ISO 3601-2 gland", size=gland.oring.name, quantity=qty,
                unit_volume_mm3=None, unit_mass_g=None, in_unit=True,
                note=f"{gland.application} gland: groove {gland.groove_diameter_mm:.2f} x {gland.width_mm:.2f} mm; "
                     f"stretch {100 * gland.stretch:.1f} %, squeeze {100 * gland.squeeze:.0f} %")
        for gland, qty, where in glands(ctx.layout))


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
                    in_unit=True, note="lumped mass from the design (fixed.servo_and_valve_mass_g); the core seals in "
                                       "its bore with its own O-ring (part of the assembly)"),)


#: Tightening torques (N m) of ISO 4762 socket head cap screws, property class 8.8 (ISO 898-1), µ_total = 0.12:
#: 90 % of the yield-limited assembly torque of VDI 2230-1's table A1, by thread.
TIGHTENING_TORQUE_NM = {"M3": 1.1, "M4": 2.6, "M5": 5.2, "M6": 9.0, "M8": 22.0, "M10": 43.0}


def servo_screws(ctx: BomContext) -> tuple[BomLine, ...]:
    """The two servo mount screws (the base's tapped holes).

    Parameters
    ----------
    ctx : BomContext
        The CAD parameters (tap drill and depth, mm).

    Returns
    -------
    tuple of BomLine
        One ``bought`` line, M3 ISO 4762 class 8.8, quantity 2, with its tightening torque (N m).
    """
    c = ctx.layout.cad
    return (BomLine(part="servo_screws", description="servo mount screws", category="bought",
                    material="steel, property class 8.8 (ISO 898-1), zinc flake", standard="ISO 4762",
                    size=f"M3 (tapped Ø{c.servo_screw_core_mm:g} x {c.servo_screw_depth_mm:g} deep)",
                    quantity=2, unit_volume_mm3=None, unit_mass_g=None, in_unit=True,
                    torque_Nm=TIGHTENING_TORQUE_NM["M3"],
                    note="length to suit the servo bracket (engagement >= 2 d in aluminium); torque: VDI 2230-1, "
                         "µ 0.12"),)


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
    seat = lay.relief_seat_d
    return (BomLine(part="relief_ball", description="relief valve ball", category="bought", material="steel 100Cr6",
                    standard="ISO 3290-1 grade G10", size=f"Ø{relief_ball_mm(lay):g} mm (seat Ø{seat:g})",
                    quantity=1, unit_volume_mm3=None, unit_mass_g=None, in_unit=True,
                    note="seated on the sharp seat edge of the drilling"),)


def relief_ball_mm(lay: Layout) -> float:
    """Diameter of the relief valve's ball: 1.2 x the seat drilling, at most the relief bore, mm.

    Parameters
    ----------
    lay : Layout
        The design's layout.

    Returns
    -------
    float
        Ball diameter, mm.
    """
    return min(lay.relief_d, 1.2 * lay.relief_seat_d)


def relief_spring_and_screw(ctx: BomContext) -> tuple[BomLine, ...]:
    """The relief valve's compression spring and the set screw that preloads it and closes the bore.

    Parameters
    ----------
    ctx : BomContext
        The relief bore, its thread and the seat (mm).

    Returns
    -------
    tuple of BomLine
        The spring (EN 13906-1) and the set screw (ISO 4026), ``bought``.
    """
    from .features import relief_thread, relief_thread_depth

    lay = ctx.layout
    seat = lay.relief_seat_d
    thread = relief_thread(lay).split("-")[0]
    area = math.pi * (seat / 2) ** 2
    return (BomLine(part="relief_spring", description="relief valve spring (helical compression)", category="bought",
                    material="spring steel wire EN 10270-1 SH", standard="EN 13906-1",
                    size=f"outer Ø <= {lay.relief_d - 0.4:.1f} mm, closes on the Ø{relief_ball_mm(lay):g} ball",
                    quantity=1, unit_volume_mm3=None, unit_mass_g=None, in_unit=True,
                    note=f"preload = relief setting x seat area ({area:.2f} mm²), N = MPa x mm²; "
                         "rate and free length to suit the relief setting of the damper's hydraulics"),
            BomLine(part="relief_set_screw", description="relief valve adjusting set screw (closes the bore)",
                    category="bought", material="steel 45H (ISO 898-5)", standard="ISO 4026",
                    size=f"{thread} x {relief_thread_depth(lay):.0f}", quantity=1, unit_volume_mm3=None,
                    unit_mass_g=None, in_unit=True,
                    note="sealed and locked with anaerobic hydraulic thread sealant (e.g. Loctite 542); set the "
                         "relief pressure, then seal"),)


def proof_pressure_MPa(lay: Layout) -> float:
    """The proof pressure the bought pressure parts are rated for: 1.5 x the highest gas pressure over a stroke
    (ISO 10100's proof test of hydraulic cylinders: 1.5 x the rated pressure), MPa.

    Parameters
    ----------
    lay : Layout
        The design's layout (its peak pressures).

    Returns
    -------
    float
        Proof pressure, MPa.
    """
    return 1.5 * max(lay.design.peak_pressures_MPa().values())


def fill_valves(ctx: BomContext) -> tuple[BomLine, ...]:
    """The gas charging valves of chambers 1 and 2 (the M5 tapped holes with their spot faces).

    Parameters
    ----------
    ctx : BomContext
        The CAD parameters and the design's pressures.

    Returns
    -------
    tuple of BomLine
        One ``bought`` line, quantity 2, rated for the proof pressure.
    """
    c = ctx.layout.cad
    proof = proof_pressure_MPa(ctx.layout)
    return (BomLine(part="fill_valves", description="gas charging valves, chambers 1 and 2: high-pressure "
                                                   "Schrader-type check valve with M5 stud (gas-spring charging valve)",
                    category="bought", material="brass or steel body, FKM/NBR core seal",
                    standard="thread ISO 261 M5x0.8; rated >= proof pressure (ISO 10100 practice)",
                    size=f"M5x0.8, seal on a Ø{c.valve_spot_face_mm:g} spot face, >= {proof:.1f} MPa",
                    quantity=2, unit_volume_mm3=None, unit_mass_g=None, in_unit=True, torque_Nm=1.5,
                    note="e.g. the charging valve of a nitrogen die gas spring (15 MPa class); charge with "
                         "nitrogen through it, cap it after charging"),)


def cross_port_plug(ctx: BomContext) -> tuple[BomLine, ...]:
    """The expander plug that closes the chamber-2 cross port where it was drilled from the outside.

    Parameters
    ----------
    ctx : BomContext
        The layout (whether it has a cross port; the plug bore, mm).

    Returns
    -------
    tuple of BomLine
        One ``bought`` line, or none without a cross port.
    """
    lay = ctx.layout
    if not lay.has_cross_port:
        return ()
    c = lay.cad
    where = "base" if lay.has_top_annulus else "top cap"
    return (BomLine(part="cross_port_plug", description=f"expander sealing plug, chamber-2 cross port ({where})",
                    category="bought", material="steel, zinc plated",
                    standard="press-in expander plug (SFC Koenig MB type), metal-to-metal seal",
                    size=f"for a Ø{c.plug_bore_mm:g} H11 x {c.plug_depth_mm:g} bore, >= "
                         f"{proof_pressure_MPa(lay):.1f} MPa in aluminium",
                    quantity=1, unit_volume_mm3=None, unit_mass_g=None, in_unit=True,
                    note="set with its setting tool after the bore is cleaned and dry"),)


def hydraulic_fluid(ctx: BomContext) -> tuple[BomLine, ...]:
    """The oil fill at x = 0: the fluid column, the inside of the bladder, the channels and the relief bore.

    Parameters
    ----------
    ctx : BomContext
        The layout (:func:`~vvea_design.cad.fill.oil_fill_mm3`, mm³).

    Returns
    -------
    tuple of BomLine
        One ``fluid`` line: volume (mm³) and mass (g), the spaces in the note.
    """
    fill = oil_fill_mm3(ctx.layout)
    parts = ", ".join(f"{k.replace('_', ' ')} {v:.0f}" for k, v in fill.items() if k != "total")
    return (BomLine(part="hydraulic_fluid", description="oil fill at x = 0 (column, bladder, channels)",
                    category="fluid", material=OIL, standard="ISO 6743-4 HM; ISO 3448 VG 32", size="ISO VG 32",
                    quantity=1, unit_volume_mm3=fill["total"],
                    unit_mass_g=fill["total"] * DENSITY_HYDRAULIC_OIL_g_per_mm3, in_unit=True,
                    note=f"mm³: {parts}; fill free of air with the piston at x = 0; mass = volume x "
                         f"{DENSITY_HYDRAULIC_OIL_g_per_mm3:g} g/mm³"),)


def gas_charge(ctx: BomContext) -> tuple[BomLine, ...]:
    """The nitrogen charge of each chamber at its charge pressure and 20 °C.

    Parameters
    ----------
    ctx : BomContext
        The layout (:func:`~vvea_design.cad.fill.gas_charges`).

    Returns
    -------
    tuple of BomLine
        One ``fluid`` line per chamber: volume (mm³) and nitrogen mass (g).
    """
    out = []
    for g in gas_charges(ctx.layout):
        n = g.chamber[-1]
        out.append(BomLine(part=f"nitrogen_{g.chamber}", description=f"gas charge, chamber {n}", category="fluid",
                           material=NITROGEN, standard="ISO 14175 N1",
                           size=f"{g.pressure_MPa:.3f} MPa (abs.) at 20 °C", quantity=1, unit_volume_mm3=g.volume_mm3,
                           unit_mass_g=g.mass_g, in_unit=True,
                           note=f"includes {g.dead_volume_mm3:.0f} mm³ of the drawn ports; mass = p V M / (Z R T), "
                                f"Z of nitrogen from its virial expansion"))
    return tuple(out)


def _joint_check(rec) -> str:
    """The joint's load case, end load and least safety factor, for its BOM note."""
    sf = min(rec.safety_factors.values()) if rec.safety_factors else float("nan")
    return (f"sized for {rec.end_load_N:.0f} N ({rec.governing_case}); least safety factor {sf:.2f} "
            f"(required {rec.required_safety_factor:.2f})")


def housing_joint(ctx: BomContext) -> tuple[BomLine, ...]:
    """The housing's joint (the design's, drawn by the CAD): each thread (cut on both parts, no separate item),
    the DIN 472 retaining ring, or the tie rods with their nuts, property class and tightening torque.

    Parameters
    ----------
    ctx : BomContext
        The design (its joint records; none under the gas-only rules).

    Returns
    -------
    tuple of BomLine
        ``bought`` lines with their standards (mass g, torque N m); empty without a joint.
    """
    if not ctx.layout.has_joint:
        return ()
    out = []
    for rec in ctx.design.joints():
        if rec.kind == "thread":
            where = "base" if rec.joint == "base" else "top cap"
            out.append(BomLine(part=f"thread_{rec.joint}", description=f"threaded joint, {where} into the outer tube "
                               "(cut on both parts, no separate item)", category="bought", material="-",
                               standard=rec.standard, size=f"{rec.designation}, engaged {rec.engagement_length_mm:.2f}",
                               quantity=1, unit_volume_mm3=None, unit_mass_g=None, in_unit=True,
                               note=f"screw home to the shoulder, O-ring greased; medium-strength anaerobic thread "
                                    f"locker; {_joint_check(rec)}"))
        elif rec.kind == "ring_top":
            out.append(BomLine(part="retaining_ring", description="internal retaining ring, top cap in the outer tube",
                               category="bought", material="spring steel C75S (DIN 472), phosphated",
                               standard=rec.standard, size=rec.designation, quantity=1, unit_volume_mm3=None,
                               unit_mass_g=rec.mass_g, in_unit=True,
                               note=f"fit with circlip pliers into the groove above the cap plug; {_joint_check(rec)}"))
        elif rec.kind == "tie_rods":
            rho = 7.85e-3  # steel, g/mm³
            d, s, m = rec.nominal_diameter_mm, rec.nut_width_across_flats_mm, rec.nut_height_mm
            rod_g = math.pi / 4 * d**2 * rec.rod_length_mm * rho
            nut_g = (math.sqrt(3) / 2 * s**2 - math.pi / 4 * d**2) * m * rho
            size = f"M{d:g}x{rec.pitch_mm:g} x {rec.rod_length_mm:.0f}"
            out += [BomLine(part="tie_rods", description="tie rods (threaded rods) clamping the end pieces",
                            category="bought", material=f"steel, property class {rec.property_class} (ISO 898-1)",
                            standard="DIN 976-1; ISO 898-1", size=size, quantity=int(rec.count), unit_volume_mm3=None,
                            unit_mass_g=rod_g, in_unit=True, torque_Nm=rec.tightening_torque_Nm,
                            note=f"preload {rec.preload_min_N:.0f}...{rec.preload_max_N:.0f} N (VDI 2230-1); "
                                 f"tighten crosswise in steps; {_joint_check(rec)}"),
                    BomLine(part="tie_rod_nuts", description="hexagon nuts of the tie rods", category="bought",
                            material="steel, property class 10 (ISO 898-2)", standard="ISO 4032",
                            size=f"M{d:g} (s {s:g}, m {m:g})", quantity=2 * int(rec.count), unit_volume_mm3=None,
                            unit_mass_g=nut_g, in_unit=True, torque_Nm=rec.tightening_torque_Nm,
                            note="washers under the nuts on aluminium (ISO 7089, 300 HV)")]
    return tuple(out)


#: The BOM hooks of the items the CAD has seats for but does not model, in bill order.
BOUGHT_ITEMS: tuple[Callable[[BomContext], tuple[BomLine, ...]], ...] = (
    o_rings, housing_joint, servo_and_valve, servo_screws, relief_ball, relief_spring_and_screw, fill_valves,
    cross_port_plug, hydraulic_fluid, gas_charge)


def bought_items() -> tuple[Callable[[BomContext], tuple[BomLine, ...]], ...]:
    """The bought items' BOM hooks, looked up at call time (the bill goes through this).

    Returns
    -------
    tuple of callable
        :data:`BOUGHT_ITEMS`: each ``hook(ctx) -> tuple of BomLine``, in bill order.
    """
    return BOUGHT_ITEMS
