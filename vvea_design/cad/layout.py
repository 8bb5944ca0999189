"""Derived CAD dimensions: one place that turns a frozen :class:`Design` into the radii and axial levels every
part is drawn from. Frame (all parts, assembly): axis = global Z, ``z = 0`` at the underside of the base, the top
cap's top face at ``z = housing_length_mm``. ``x > 0`` (extension) moves the piston *down*, towards the base.

The numbers the design does not fix (feature sizes: seal grooves, ports, valve bores, mould walls, shrinkage) are
:class:`CadParameters`; they never change a volume or an area the optimiser saw. All lengths in mm.
"""

from __future__ import annotations

import math
from dataclasses import asdict, dataclass, fields, replace
from functools import cached_property

from ..spring.design import Design
from ..spring.joints import LEAD_IN_GAP_MM as _LEAD_IN_GAP_MM, seal_lead_in_land_mm
from ..spring.ports import VALVE_ROD_WALL_MM, bead_height_mm, chamber2_port_room_mm
from .errors import CadError
from .joints import JointGeometry, joint_geometry
from .layout_checks import COLLAR_SEAL_LAND_MM, SPIGOT_LAND_MM, check_layout
from .seals import Gland, LeadIn, SealError, lead_in, piston_gland, rod_gland, static_male_gland
from .tube_seats import TubeSeats, tube_seats

#: The damper's sizes the design owns (``fixed.*``): :class:`CadParameters` keeps them only as aliases of the
#: defaults; the CAD draws the design's values.
HYDRAULIC_FIELDS = ("throttle_bore_mm", "relief_bore_mm", "relief_seat_mm", "fluid_channel_mm", "ring_channel_mm",
                    "ring_channels")
#: Axial gap between the end of a lead-in chamfer and the seal groove's flank at the installed position, mm (the
#: spring side's: the joints' seal zones reserve it, :func:`~vvea_design.spring.joints.seal_lead_in_land_mm`).
LEAD_IN_GAP_MM = _LEAD_IN_GAP_MM
#: Where the chamfer-angle room for a lead-in stops: the piston's lower ring must never run onto the inner tube's
#: bottom chamfer at full stroke (axial gap, mm).
PISTON_LEAD_IN_GAP_MM = 0.3

#: Root radius of the machined pieces' internal corners (steps, shoulders, the roots of plates in tubes) where
#: the drawing states no other ("internal corners R1 unless stated"; at most 0.45 of the shorter edge meeting
#: there), mm. The FE check of the pieces (:mod:`vvea_design.structure`) rounds the drawn corners with the same
#: radii (:meth:`Layout.corner_radius_mm`).
ROOT_RADIUS_MM = 1.0
#: Root radius of the rod's shoulder into the piston (the rod carries the piston's whole load: the largest
#: concentration of the steel part), mm.
ROD_SHOULDER_RADIUS_MM = 1.5
#: Root radius of the bulkhead's web in the inner tube's bore, both faces (the thin tube wall takes the web's
#: edge moment there: a thicker web alone barely lowers the root's peak), mm. Chamber 1 keeps the piston tens of
#: mm below it.
BULKHEAD_ROOT_RADIUS_MM = 3.0

__all__ = ["CadParameters", "Layout", "CadError", "DEPRECATED_NAMES", "ROOT_RADIUS_MM", "ROD_SHOULDER_RADIUS_MM",
           "BULKHEAD_ROOT_RADIUS_MM"]

#: Old names of :class:`Layout`'s radii and sizes -> their names, the design's (one vocabulary); the old ones
#: remain as read-only aliases while the CAD's modules move over.
DEPRECATED_NAMES = {"r_outer": "outer_radius_mm", "r_bore": "outer_bore_radius_mm", "r_piston": "piston_radius_mm",
                    "r_inner_tube": "inner_tube_outer_radius_mm", "r_rod": "rod_radius_mm",
                    "r_bladder_in": "bladder_inner_radius_mm", "r_bladder_out": "bladder_outer_radius_mm",
                    "r_pocket": "piston_pocket_radius_mm", "r_fill_tube_out": "fill_tube_outer_radius_mm",
                    "r_fill_tube_bore": "fill_tube_bore_radius_mm", "slot_height": "cross_slot_mm",
                    "clamp": "bladder_clamp_mm"}


def _deprecated(name: str) -> property:
    """A read-only alias of the property ``name`` (a deprecated old name)."""
    return property(lambda self: getattr(self, name), doc=f"Deprecated: :attr:`{name}`.")


@dataclass(frozen=True)
class CadParameters:
    """Feature sizes the optimiser does not see (mm, except ``shrinkage``).

    Every field is validated in ``__post_init__``; a bad value raises
    :class:`CadError` naming the field before any geometry is built.
    """

    oring_cross_section_mm: float = 1.78  #: O-ring series of the piston and rod seals (ISO 3601-1: 1.78 or 2.62)
    rod_thread_core_mm: float = 4.2  #: tapped hole (M5 core) in the rod end for the bottom eye
    rod_thread_depth_mm: float = 10.0  #: depth of that tapped hole
    fill_port_mm: float = 2.0  #: gas fill-port drilling (largest; shrinks to fit between bladder and seal)
    fill_port_counterbore_mm: float = 4.2  #: tap drill of the charging valves' M5x0.8 thread (ISO 261)
    fill_port_counterbore_depth_mm: float = 4.0  #: depth of that tapped hole from the face
    valve_spot_face_mm: float = 9.0  #: flat seat of a charging valve's seal around its M5 hole (diameter)
    plug_bore_mm: float = 3.0  #: bore of the expander plug that closes a cross port at the outside
    plug_depth_mm: float = 3.0  #: its depth from the outside
    throttle_bore_mm: float = 6.0  #: deprecated: the design's ``fixed.throttle_bore_mm`` is drawn
    relief_bore_mm: float = 5.0  #: deprecated: the design's ``fixed.relief_bore_mm`` is drawn
    relief_seat_mm: float = 2.5  #: deprecated: the design's ``fixed.relief_seat_mm`` is drawn
    fluid_channel_mm: float = 3.0  #: deprecated: the design's ``fixed.fluid_channel_mm`` is drawn
    servo_screw_core_mm: float = 2.5  #: M3 core of the two servo-mount screws
    servo_screw_depth_mm: float = 6.0  #: their depth
    ring_channel_mm: float = 2.0  #: deprecated: the design's ``fixed.ring_channel_mm`` is drawn
    ring_channels: int = 6  #: deprecated: the design's ``fixed.ring_channels`` is drawn
    clamp_groove_fraction: float = 0.6  #: bladder cuff depth as a fraction of ``fixed.bladder_clamp_mm``
    bead_height_mm: float = 0.4  #: radial height of the sealing beads (largest; shrinks to fit)
    bead_length_mm: float = 1.5  #: axial length of a sealing bead
    mould_shrinkage: float = 0.001  #: linear shrinkage of the silicone; cavity = bladder x (1 + s)
    mould_wall_mm: float = 6.0  #: mould wall around the cavity (y and z)
    mould_side_mm: float = 16.0  #: mould wall in x (holds sprue and registration pins)
    mould_core_wall_mm: float = 3.0  #: wall of the hollow core
    mould_core_spigot_mm: float = 5.0  #: core length sticking out of each mould end
    sprue_mm: float = 4.0  #: sprue diameter
    sprue_funnel_mm: float = 8.0  #: sprue funnel diameter at the top (the drafted entry)
    runner_mm: float = 3.0  #: horizontal runner from the sprue into the lowest point of the cavity
    vent_mm: float = 1.5  #: vent diameter
    vents: int = 3  #: number of vents at the top of the cavity
    pin_mm: float = 3.0  #: registration pin diameter
    pin_length_mm: float = 4.0  #: registration pin length past the parting plane
    pin_clearance_mm: float = 0.1  #: radial clearance of the pin holes
    stl_tolerance_mm: float = 0.05  #: STL linear deflection
    stl_angular_tolerance_rad: float = 0.1  #: STL angular deflection
    cross_slots: int = 4  #: slots in the inner tube's top end (``annulus_top``; they share ``fixed.cross_slot_fraction``)
    min_pocket_root_wall_mm: float = 1.5  #: thinnest wall between the piston pocket (``fixed.piston_pocket``) and a seal groove's root

    def __post_init__(self) -> None:
        for f in fields(self):
            v = getattr(self, f.name)
            if f.name in ("ring_channels", "vents", "cross_slots"):
                if isinstance(v, bool) or not isinstance(v, int) or v < 1:
                    raise CadError(f"cad.{f.name} must be an integer >= 1, got {v!r}")
                continue
            if isinstance(v, bool) or not isinstance(v, (int, float)) or not math.isfinite(v):
                raise CadError(f"cad.{f.name} must be a finite number, got {v!r}")
            if f.name == "mould_shrinkage":
                if not 0.0 <= v < 0.1:
                    raise CadError(f"cad.mould_shrinkage must be in [0, 0.1), got {v!r}")
            elif v <= 0:
                raise CadError(f"cad.{f.name} must be > 0, got {v!r}")
        if not 0.2 <= self.clamp_groove_fraction <= 0.8:
            raise CadError(f"cad.clamp_groove_fraction must be in [0.2, 0.8], got {self.clamp_groove_fraction!r}")
        if self.sprue_funnel_mm < self.sprue_mm:
            raise CadError("cad.sprue_funnel_mm must be >= cad.sprue_mm")
        from .seals import DYNAMIC_GLANDS

        if self.oring_cross_section_mm not in DYNAMIC_GLANDS:
            raise CadError(f"cad.oring_cross_section_mm must be one of "
                           f"{', '.join(f'{w:g}' for w in DYNAMIC_GLANDS)} mm, got {self.oring_cross_section_mm!r}")

    def to_dict(self) -> dict:
        """JSON-ready content.

        Returns
        -------
        dict
            Every feature size by name (mm; ``mould_shrinkage`` a fraction, counts integers).
        """
        return asdict(self)


@dataclass(frozen=True)
class Layout:
    """Radii and axial levels (``z_*``) of one design, mm.

    Built from the design's public properties only, and checked: a layout
    whose features do not fit raises :class:`CadError` naming the field to
    change, before any solid is built. A radius or size that is a quantity of
    the design has the design's name (``outer_bore_radius_mm``, as in the
    design file; ``piston_radius_mm`` for half of ``piston_diameter_mm``);
    the CAD's own features (ports, channels, grooves: ``r_port1``,
    ``fill_port_d`` ...) and the levels of its frame keep short names. The
    old names of the design's quantities are deprecated aliases
    (:data:`DEPRECATED_NAMES`).
    """

    design: Design
    cad: CadParameters = CadParameters()

    def __post_init__(self) -> None:
        if not isinstance(self.design, Design):
            raise CadError(f"design must be a vvea_design.spring.design.Design, got {type(self.design).__name__}")
        if not isinstance(self.cad, CadParameters):
            raise CadError(f"cad must be CadParameters, got {type(self.cad).__name__}")
        for name in HYDRAULIC_FIELDS:  # the damper's sizes are the design's (fixed.*): the CAD draws those
            mine, theirs = getattr(self.cad, name), getattr(self.design.fixed, name)
            if mine != theirs and mine != getattr(CadParameters, name):
                raise CadError(f"cad.{name} = {mine!r} differs from the design's fixed.{name} = {theirs!r}: the CAD "
                               f"draws the design's (its hydraulics are sized with it); set fixed.{name} instead")
        self.check()

    # ----------------------------------------------------------- radii (the design's quantities, its names)
    @property
    def outer_radius_mm(self) -> float:
        """Outer tube outer radius = envelope radius (half ``outer_diameter_mm``), mm."""
        return self.design.outer_diameter_mm / 2

    @property
    def outer_bore_radius_mm(self) -> float:
        """Outer tube bore, mm."""
        return self.design.outer_bore_radius_mm

    @property
    def piston_radius_mm(self) -> float:
        """Inner tube bore = piston radius (half ``piston_diameter_mm``), mm."""
        return self.design.piston_diameter_mm / 2

    @property
    def inner_tube_outer_radius_mm(self) -> float:
        """Inner tube outer radius, mm."""
        return self.design.inner_tube_outer_radius_mm

    @property
    def rod_radius_mm(self) -> float:
        """Piston rod radius (half ``fixed.rod_diameter_mm``), mm."""
        return self.design.fixed.rod_diameter_mm / 2

    @property
    def bladder_inner_radius_mm(self) -> float:
        """Cast bladder sleeve, inner radius, mm."""
        return self.design.bladder_inner_radius_mm

    @property
    def bladder_outer_radius_mm(self) -> float:
        """Cast bladder sleeve, outer radius, mm."""
        return self.design.bladder_outer_radius_mm

    @cached_property
    def piston_seal(self) -> Gland:
        """Piston seal groove and its ISO 3601-1 O-ring (two per piston)."""
        try:
            return piston_gland(self.design.piston_diameter_mm, self.cad.oring_cross_section_mm)
        except SealError as exc:
            raise CadError(f"piston_diameter_mm: {exc}") from None

    @cached_property
    def rod_seal(self) -> Gland:
        """Rod seal groove in the base and its ISO 3601-1 O-ring."""
        try:
            return rod_gland(self.design.fixed.rod_diameter_mm, self.cad.oring_cross_section_mm)
        except SealError as exc:
            raise CadError(f"fixed.rod_diameter_mm: {exc}") from None

    def _static_seal(self, kind: str, where: str, field: str) -> Gland:
        """A static male gland against the outer-tube bore (``kind`` names it), or a CadError naming ``field``."""
        try:
            g = static_male_gland(2 * self.outer_bore_radius_mm, self.cad.oring_cross_section_mm, kind)
        except SealError as exc:
            raise CadError(f"{field} (the {where} to the Ø{2 * self.outer_bore_radius_mm:.2f} mm bore): {exc}") \
                from None
        return replace(g, where=where)

    @cached_property
    def collar_seal(self) -> Gland | None:
        """Static seal of the ``annulus_top`` collar to the outer-tube bore (it separates chamber 1's annulus
        from chamber 2): a male static gland (radial squeeze, ISO 3601 static table) in the collar plate's rim;
        ``None`` in the other layouts."""
        if not self.has_top_annulus:
            return None
        return self._static_seal("collar", "collar to outer-tube bore (static)", "outer_diameter_mm")

    @property
    def z_collar_seal(self) -> tuple[float, float]:
        """Axial extent of the collar's seal groove, centred in the collar plate (``annulus_top``), mm."""
        zc, w = self.z_collar1 - 0.5 * self.design.collar_mm, self.collar_seal.width_mm
        return zc - 0.5 * w, zc + 0.5 * w

    @property
    def z_rod_seal(self) -> tuple[float, float]:
        """Axial extent of the rod seal groove in the base (from the underside), mm."""
        return 1.5, 1.5 + self.rod_seal.width_mm

    def corner_radius_mm(self, part: str, r_mm: float, z_mm: float) -> float:
        """Root radius the drawing gives an internal corner of a machined part: an O-ring groove's root the
        largest of its ISO 3601 gland's window (bd_warehouse's table), the rod's shoulder
        :data:`ROD_SHOULDER_RADIUS_MM`, the bulkhead's roots in the bore :data:`BULKHEAD_ROOT_RADIUS_MM`, every
        other :data:`ROOT_RADIUS_MM`.

        Parameters
        ----------
        part : str
            The CAD part (``housing_base``, ``piston`` ...).
        r_mm, z_mm : float
            The corner, mm.

        Returns
        -------
        float
            The radius, mm.
        """
        glands = {"piston": (self.piston_seal,), "housing_base": (self.rod_seal, self.base_seal),
                  "housing_top_cap": (self.cap_seal,), "housing_inner_tube": (self.collar_seal,)}.get(part, ())
        for g in glands:
            if g is not None and g.spec is not None and abs(r_mm - g.groove_diameter_mm / 2) < 0.02:
                return g.spec.radius_max_mm
        if part == "piston" and abs(r_mm - self.rod_radius_mm) < 0.02:
            return ROD_SHOULDER_RADIUS_MM
        if (part == "housing_inner_tube" and self.has_bulkhead and abs(r_mm - self.piston_radius_mm) < 0.02
                and min(abs(z_mm - self.z_bulkhead0), abs(z_mm - self.z_bulkhead1)) < 0.02):
            return BULKHEAD_ROOT_RADIUS_MM
        return ROOT_RADIUS_MM

    @cached_property
    def joint(self) -> JointGeometry:
        """The housing's joint as drawn (:func:`~vvea_design.cad.joints.joint_geometry`; ``kind = "none"`` for a
        design sized by the gas-only rules)."""
        return joint_geometry(self.design, self.z_cap, self.z_top)

    @cached_property
    def seats(self) -> TubeSeats | None:
        """The inner tube's ends (and the fill tube's neck) seated and sealed in the end pieces
        (:func:`~vvea_design.cad.tube_seats.tube_seats`); None under the gas-only rules."""
        return tube_seats(self)

    @property
    def has_joint(self) -> bool:
        """The design sized a joint (threads, a retaining ring or tie rods) and the CAD draws it."""
        return self.joint.kind != "none"

    @property
    def cap_seal_bore_mm(self) -> float:
        """Diameter the top cap's static O-ring seals on: the outer bore (``ring_top`` too: the cap plug's seal
        zone lies below the tube's counterbore, so the ring passes the retaining ring's groove and the counterbore
        clear of their edges, ISO 3601-2), mm."""
        return 2 * self.outer_bore_radius_mm

    @cached_property
    def cap_seal(self) -> Gland | None:
        """Static seal of the top cap to the outer tube: a male static gland in the cap's joint seal zone (the
        design's joint), or without a joint in the top bladder clamp (the cap's spigot in the bore); ``None`` for
        the gas-only ``annulus_top``, whose plain cap has no spigot (an open path, the leak audit says so)."""
        if self.has_joint:
            try:
                g = static_male_gland(self.cap_seal_bore_mm, self.design.fixed.joint_seal_cross_section_mm, "cap")
            except SealError as exc:
                raise CadError(f"fixed.joint_seal_cross_section_mm (the top cap's seal): {exc}") from None
            return replace(g, where="top cap to outer tube, in the joint's seal zone (static)")
        if self.has_top_annulus:
            return None
        return self._static_seal("cap", "top cap spigot to outer-tube bore (static)", "outer_diameter_mm")

    @cached_property
    def base_seal(self) -> Gland:
        """Static seal of the base to the outer-tube bore: a male static gland in the base's joint seal zone,
        or without a joint in the base's spigot (which rises into the outer tube around the support ring)."""
        if self.has_joint:
            try:
                g = static_male_gland(2 * self.outer_bore_radius_mm, self.design.fixed.joint_seal_cross_section_mm,
                                      "base")
            except SealError as exc:
                raise CadError(f"fixed.joint_seal_cross_section_mm (the base's seal): {exc}") from None
            return replace(g, where="base to outer tube, in the joint's seal zone (static)")
        return self._static_seal("base", "base spigot to outer-tube bore (static)", "outer_diameter_mm")

    @property
    def r_base_spigot(self) -> float:
        """Inner radius of the base spigot where it holds the lower cuff's bead (the bead's outer radius), mm."""
        return self.bladder_outer_radius_mm + self.bead_mm

    @property
    def z_base_seal(self) -> tuple[float, float]:
        """Axial extent of the base seal's groove: in the joint's seal zone above the entry land the design reserves
        for the outer tube's lead-in (:attr:`seal_entry_land_mm`), or without a joint at the top of the CAD's spigot
        (land :data:`SPIGOT_LAND_MM`), so the outer tube's lead-in below it stays clear, mm."""
        w = self.base_seal.width_mm
        if self.has_joint:
            lo = self.joint.base_seal[0] + self.seal_entry_land_mm(self.base_seal)
            return lo, lo + w
        top = self.z_free0 - SPIGOT_LAND_MM
        return top - w, top

    @property
    def z_cap_seal(self) -> tuple[float, float]:
        """Axial extent of the cap seal's groove: in the joint's seal zone below the entry land the design reserves
        for the outer tube's top lead-in (:attr:`seal_entry_land_mm`), or without a joint at the bottom of the cap's
        spigot (land :data:`SPIGOT_LAND_MM`), so the outer tube's top lead-in above it stays clear, mm."""
        w = self.cap_seal.width_mm
        if self.has_joint:
            hi = self.joint.cap_seal[1] - self.seal_entry_land_mm(self.cap_seal)
            return hi - w, hi
        lo = self.z_free1 + SPIGOT_LAND_MM
        return lo, lo + w

    def seal_entry_land_mm(self, gland: Gland) -> float:
        """The joint's seal zone between its entry end (the thread's step or the tube's end, where the ring enters
        the bore) and the groove of ``gland``: the lead-in's room the design reserves for its ring (ISO 3601-2,
        :func:`~vvea_design.spring.joints.seal_lead_in_land_mm`).

        Parameters
        ----------
        gland : Gland
            The joint's static seal (its ring's cross-section sets the lead-in).

        Returns
        -------
        float
            Axial land, mm.
        """
        return seal_lead_in_land_mm(gland.oring.cross_section_mm, self.design.fixed.seal_land_mm)

    @cached_property
    def lead_in_piston(self) -> LeadIn:
        """Lead-in chamfer at the inner tube's bottom bore end: the piston's rings enter the bore there (every
        layout: in ``bulkhead`` the top is closed). Short enough that the lower ring never runs onto it at full
        stroke (ISO 3601-2: 15-20 deg, radial depth over the ring's protrusion)."""
        d, w = self.design, self.piston_seal.width_mm
        room = d.fluid_column_mm - d.fixed.travel_mm + 0.27 * d.fixed.piston_height_mm - w / 2 - PISTON_LEAD_IN_GAP_MM
        try:
            return self.piston_seal.lead_in(room)
        except SealError as exc:
            raise CadError(f"fixed.fluid_clearance_mm: {exc}") from None

    @cached_property
    def lead_in_rod(self) -> LeadIn:
        """Lead-in chamfer at the rod's end: it passes the rod seal in the base on assembly."""
        return self.rod_seal.lead_in(self.cad.rod_thread_depth_mm)

    @property
    def z_lead_in_bottom(self) -> float:
        """Where the outer tube's bottom lead-in starts: the tube's bottom end, or behind a threaded end the step
        from the thread's run-out (at its minor diameter, clear of the O-ring) to the bore, mm."""
        t = self.joint.base_thread
        return t.relief[1] if t is not None else self.joint.z_tube_bottom

    @property
    def z_lead_in_top(self) -> float:
        """Where the outer tube's top lead-in starts (its top end, the step behind its top thread's run-out, or
        ``ring_top`` the counterbore's step), mm."""
        t, j = self.joint.cap_thread, self.joint
        if t is not None:
            return t.relief[0]
        return j.cap_seal[1] if j.ring is not None else j.z_tube_top

    def _tube_lead_in(self, rings: list[Gland], room: float, where: str) -> LeadIn:
        """A lead-in (ISO 3601-2, 15 ... 20 deg) for the rings passing an end of the outer tube, in ``room`` mm.

        With a joint the design reserved the room (:attr:`seal_entry_land_mm`): a chamfer that does not fit is a
        :class:`CadError` naming ``fixed.seal_land_mm``. Under the gas-only rules the spigot is the bladder clamp,
        whose length the design fixes without the seal: a 20 deg chamfer may use the CAD's own clearance to the
        groove (:data:`LEAD_IN_GAP_MM`), ending at the groove's flank at most; else a :class:`CadError` naming
        ``fixed.bladder_clamp_mm``."""
        ring = max(rings, key=lambda g: g.protrusion_mm + g.oring.cross_section_tolerance_mm)
        try:
            return ring.lead_in(room)
        except SealError as exc:
            if self.has_joint:
                raise CadError(f"fixed.seal_land_mm ({where}, the joint's seal zone): {exc}") from None
            try:
                return ring.lead_in(room + LEAD_IN_GAP_MM)
            except SealError:
                raise CadError(f"fixed.bladder_clamp_mm ({where}): {exc}") from None

    @cached_property
    def lead_in_outer_bottom(self) -> LeadIn:
        """Lead-in chamfer at the outer tube's bottom bore end: the base seal's ring (and in ``annulus_top`` the
        collar's) enters the bore there. It ends :data:`LEAD_IN_GAP_MM` below the base seal's groove."""
        room = self.z_base_seal[0] - self.z_lead_in_bottom - LEAD_IN_GAP_MM
        rings = [self.base_seal] + ([self.collar_seal] if self.has_top_annulus else [])
        return self._tube_lead_in(rings, room, "the base spigot")

    @cached_property
    def lead_in_outer_top(self) -> LeadIn | None:
        """Lead-in chamfer at the outer tube's top bore end: the cap seal's ring enters the bore there (``None``
        without a cap seal; ``ring_top``: at the counterbore's step). It ends :data:`LEAD_IN_GAP_MM` above the cap
        seal's groove."""
        if self.cap_seal is None:
            return None
        room = self.z_lead_in_top - self.z_cap_seal[1] - LEAD_IN_GAP_MM
        return self._tube_lead_in([self.cap_seal], room, "the top cap's spigot")

    @cached_property
    def lead_in_counterbore(self) -> LeadIn | None:
        """``ring_top``: the chamfer at the mouth of the tube's top counterbore, where the cap plug enters (its ring
        passes it clear)."""
        if self.joint.ring is None:
            return None
        return self.cap_seal.lead_in(self.z_top - self.joint.ring.groove[1])

    @cached_property
    def bead_mm(self) -> float:
        """Radial height of the sealing beads (shrunk to a quarter of the free gap if needed)."""
        return float(bead_height_mm(self.inner_tube_outer_radius_mm, self.bladder_inner_radius_mm, self.outer_bore_radius_mm, self.bladder_outer_radius_mm, self.cad.bead_height_mm))

    @property
    def r_gas2_inner(self) -> float:
        """Inner radius of the chamber-2 gas domain at x = 0 (equal-volume straight sleeve)."""
        return self.design.bladder_equivalent_outer_radius_mm(0.0)

    @property
    def ring_channels(self) -> int:
        """Number of the support ring's axial fluid channels: ``fixed.ring_channels``."""
        return int(self.design.fixed.ring_channels)

    @cached_property
    def ring_channel_d(self) -> float:
        """Support-ring channel diameter: ``fixed.ring_channel_mm``, shrunk to the gap inside the bladder bead
        (the rule :mod:`vvea_design.spring.hydraulics` prices), mm."""
        return min(self.design.fixed.ring_channel_mm,
                   0.6 * (self.bladder_inner_radius_mm - self.bead_mm - self.inner_tube_outer_radius_mm))

    @property
    def r_ring_channel(self) -> float:
        """Radius of the support-ring channels (fluid side, inside the bladder)."""
        return 0.5 * (self.inner_tube_outer_radius_mm + self.bladder_inner_radius_mm - self.bead_mm)

    @property
    def _seal_root_near_port2(self) -> float:
        """Radius of the seal groove's root beside the chamber-2 port: the cap's spigot, or in ``annulus_top``
        the base's spigot (the port runs through it), mm."""
        g = self.base_seal if self.has_top_annulus else self.cap_seal
        return g.groove_diameter_mm / 2

    @cached_property
    def fill_port_d(self) -> float:
        """Chamber-2 port through the spigot, between the bead and the seal groove (:mod:`vvea_design.spring.ports`), mm."""
        room = chamber2_port_room_mm(self._seal_root_near_port2, self.bladder_outer_radius_mm, self.bead_mm)
        return min(self.cad.fill_port_mm, float(room))

    @property
    def _valve2_limit(self) -> float:
        """Largest radius of the chamber-2 valve whose spot face stays 0.8 mm inside the outer diameter, mm."""
        return self.outer_radius_mm - 0.5 * self.cad.valve_spot_face_mm - 0.8

    @property
    def r_port2(self) -> float:
        """Chamber-2 port radius: through the top clamp (or in ``annulus_top`` through the base and its spigot),
        midway between the bladder's bead and the root of the spigot's seal groove -- or further in, under the
        valve, when the valve's spot face does not fit over the midpoint but the port still clears the bead."""
        mid = 0.5 * (self.r_base_spigot + self._seal_root_near_port2)
        lim = self._valve2_limit
        if self.has_bulkhead or mid <= lim:
            return mid
        if lim >= self.r_base_spigot + self.fill_port_d / 2 + 0.3:
            return lim
        return mid

    @property
    def y_valve2(self) -> float:
        """Where the chamber-2 charging valve sits (+y, on the top face; in ``annulus_top`` on the base's
        underside): over the riser (``bulkhead``), else over the port where its spot face fits, else inboard,
        joined to the port by a cross port drilled from the outside and plugged, mm."""
        if self.has_bulkhead:
            return self.y_cross_riser
        return min(self.r_port2, self._valve2_limit)

    @property
    def has_cross_port(self) -> bool:
        """The chamber-2 valve is not over its port: a cross port joins them (and in ``bulkhead`` the riser)."""
        return self.has_bulkhead or self.y_valve2 < self.r_port2 - 1e-9

    @property
    def y_port1(self) -> float:
        """Where the chamber-1 charging valve sits (+y on the top face; 0 in ``bulkhead``: the fill tube's bore)."""
        return 0.0 if self.has_bulkhead else self.r_port1

    @property
    def r_port1(self) -> float:
        """Chamber-1 fill port radius (over the piston)."""
        return 0.6 * self.piston_radius_mm

    @cached_property
    def base_channel_d(self) -> float:
        return min(self.design.fixed.fluid_channel_mm, 0.5 * (self.piston_radius_mm - self.rod_radius_mm))

    @property
    def r_channel_a(self) -> float:
        """Base channel from the fluid column (inside the inner tube, outside the rod)."""
        return 0.5 * (self.rod_radius_mm + self.piston_radius_mm)

    @property
    def base_own_mm(self) -> float:
        """The base's own part, below its joint zone (the whole base under the gas-only rules): it holds the
        valve bores, mm."""
        if self.design.fixed.sizing_rules == "gas_only":
            return self.design.base_mm
        return float(self.design.derived.section.base_own_mm)

    @cached_property
    def throttle_d(self) -> float:
        """Rotary throttle bore: ``fixed.throttle_bore_mm``, shrunk to the base's own part (8 mm less), mm."""
        return min(self.design.fixed.throttle_bore_mm, self.base_own_mm - 8.0)

    @cached_property
    def relief_d(self) -> float:
        """Relief valve bore: ``fixed.relief_bore_mm``, at most the throttle bore, mm."""
        return min(self.design.fixed.relief_bore_mm, self.throttle_d)

    @property
    def relief_seat_d(self) -> float:
        """Relief valve seat drilling: ``fixed.relief_seat_mm``, at most the relief bore, mm."""
        return min(self.design.fixed.relief_seat_mm, self.relief_d)

    @property
    def x_valve_inner(self) -> float:
        """Inner end of the radial valve bores (keeps 1.5 mm of wall to the rod bore)."""
        return self.rod_radius_mm + VALVE_ROD_WALL_MM

    # ----------------------------------------------------------- levels
    @property
    def z_base_top(self) -> float:
        return self.design.base_mm

    @property
    def z_cap(self) -> float:
        """Underside of the top cap (top of both tubes)."""
        return self.design.base_mm + self.design.inner_length_mm

    @property
    def z_top(self) -> float:
        return self.design.housing_length_mm

    @property
    def z_cap_face(self) -> float:
        """The top cap's outside face, where its charging valves sit: the housing's top, or (``ring_top``) the
        plug's top inside the tube's counterbore, mm."""
        ring = self.joint.ring
        return ring.plug[1] if ring is not None else self.z_top

    def z_piston_bottom(self, x_mm: float = 0.0) -> float:
        """Piston underside at displacement ``x_mm`` (x > 0 moves it down).

        Parameters
        ----------
        x_mm : float
            Piston displacement, mm (x > 0 extends the spring).

        Returns
        -------
        float
            Height above the base's underside, mm.
        """
        return self.z_base_top + self.design.fluid_column_mm - x_mm

    def z_piston_top(self, x_mm: float = 0.0) -> float:
        """Piston top face (chamber 1's floor) at displacement ``x_mm``.

        Parameters
        ----------
        x_mm : float
            Piston displacement, mm (x > 0 extends the spring).

        Returns
        -------
        float
            Height above the base's underside, mm.
        """
        return self.z_piston_bottom(x_mm) + self.design.fixed.piston_height_mm

    # ----------------------------------------------------------- piston pocket
    @property
    def has_piston_pocket(self) -> bool:
        """Chamber-1 gas also in a pocket bored into the piston crown (``fixed.piston_pocket``)."""
        return self.design.piston_pocket_volume_mm3 > 0

    @property
    def piston_pocket_radius_mm(self) -> float:
        """Radius of the piston pocket (0 without one), mm."""
        return self.design.piston_pocket_radius_mm

    # ----------------------------------------------------------- bulkhead layout
    @property
    def has_bulkhead(self) -> bool:
        return self.design.variant.has_bulkhead

    @property
    def z_bulkhead0(self) -> float:
        """Underside of the bulkhead (top of chamber 1 at x = 0); the top cap's underside without one."""
        if not self.has_bulkhead:
            return self.z_cap
        return self.z_piston_top(0.0) + self.design.chamber1_length_mm

    @property
    def z_bulkhead1(self) -> float:
        """Top of the bulkhead (bottom of the chamber-2 space above it)."""
        return self.z_bulkhead0 + self.design.bulkhead_mm

    @property
    def fill_tube_outer_radius_mm(self) -> float:
        """Outer radius of the chamber-1 fill tube (half ``fixed.fill_tube_outer_mm``), mm."""
        return self.design.fixed.fill_tube_outer_mm / 2

    @property
    def fill_tube_bore_radius_mm(self) -> float:
        """Bore radius of the chamber-1 fill tube (half ``fixed.fill_tube_bore_mm``), mm."""
        return self.design.fixed.fill_tube_bore_mm / 2

    @property
    def cross_port_d(self) -> float:
        """Diameter of the cross port (and the riser) that joins the chamber-2 valve to its port, mm."""
        return min(self.fill_port_d, 1.5)

    @property
    def z_cross_port(self) -> float:
        """Axis height of the cross port: in the top cap between :attr:`z_cross_port_floor` and the valves' tapped
        holes, centred on the plug's bore; in ``annulus_top`` in the base above the valve's tapped hole."""
        c = self.cad
        if self.has_top_annulus:
            return c.fill_port_counterbore_depth_mm + 0.3 + 0.5 * c.plug_bore_mm
        return 0.5 * (self.z_cross_port_floor + self.z_cap_face - c.fill_port_counterbore_depth_mm - 0.3)

    @property
    def z_cross_port_floor(self) -> float:
        """Lowest level of the top cap's cross port and its plug: above the cap's underside, or with a joint above
        the outer tube's top end (the plug is fitted from the outside; a drilling through the tube would also be
        passed by the cap's O-ring), mm."""
        lo = self.z_cap + SPIGOT_LAND_MM
        if self.has_joint and self.joint.z_tube_top > self.z_cap:
            lo = max(lo, self.joint.z_tube_top + SPIGOT_LAND_MM)
        return lo

    @property
    def y_cross_riser(self) -> float:
        """Where the riser from the space above the bulkhead meets the cross port (+y): midway between the fill
        tube and the piston bore, or further out where the chamber-2 valve over it would touch the chamber-1
        valve's spot face on the axis (0.5 mm between the two), mm."""
        mid = 0.5 * (self.fill_tube_outer_radius_mm + self.piston_radius_mm)
        return max(mid, self.cad.valve_spot_face_mm + 0.5)

    # ----------------------------------------------------------- annulus_top layout
    @property
    def has_top_annulus(self) -> bool:
        """Chamber-1 gas also in the annulus above a collar on the inner tube (``annulus_top``)."""
        return self.design.variant.has_top_annulus

    @property
    def z_collar1(self) -> float:
        """Top of the collar (bottom of the chamber-1 annulus); the top cap's underside in the other layouts."""
        return self.z_cap - self.design.top_annulus_length_mm

    @property
    def cross_slot_mm(self) -> float:
        """Axial height of the slots in the inner tube's top end (``annulus_top``), mm."""
        return self.design.fixed.cross_slot_mm

    @property
    def slot_angle_rad(self) -> float:
        """Angle each slot takes of the inner tube's circumference, rad."""
        return 2 * math.pi * self.design.fixed.cross_slot_fraction / self.cad.cross_slots

    def slot_start_rad(self, k: int) -> float:
        """Start angle of slot ``k`` (slots centred at 45° + k 360°/n from +x: clear of the drawings' section
        planes x = 0 and y = 0, so the sections show the inner tube whole), rad.

        Parameters
        ----------
        k : int
            Slot number, 0 .. ``cad.cross_slots`` - 1.

        Returns
        -------
        float
            Angle from +x towards +y, rad.
        """
        return math.pi / 4 + 2 * math.pi * k / self.cad.cross_slots - self.slot_angle_rad / 2

    @property
    def bladder_clamp_mm(self) -> float:
        """Axial length of each clamped bladder end, mm."""
        return self.design.fixed.bladder_clamp_mm

    @property
    def cuff(self) -> float:
        """Axial depth of each bladder cuff in its clamp groove."""
        return self.cad.clamp_groove_fraction * self.bladder_clamp_mm

    @property
    def z_free0(self) -> float:
        """Bottom of the bladder's free length (top of the support ring)."""
        return self.z_base_top + self.bladder_clamp_mm

    @property
    def z_free1(self) -> float:
        """Top of the bladder's free length (underside of the top clamp; in ``annulus_top`` of the collar,
        which is the clamp plus the collar plate, below the chamber-1 annulus)."""
        if not self.has_top_annulus:
            return self.z_cap - self.bladder_clamp_mm
        return self.z_collar1 - self.design.collar_mm - self.bladder_clamp_mm

    @property
    def z_bladder0(self) -> float:
        return self.z_free0 - self.cuff

    @property
    def z_bladder1(self) -> float:
        return self.z_free1 + self.cuff

    @property
    def bead_length(self) -> float:
        return min(self.cad.bead_length_mm, 0.5 * self.cuff)

    @property
    def z_valve(self) -> float:
        """Axis height of the radial throttle and relief bores in the base."""
        return self.base_own_mm - 2.0 - self.throttle_d / 2

    # ----------------------------------------------------------- deprecated names
    # The CAD's modules and the drawings read these until they move to the names above (one vocabulary:
    # ``docs/layout.md``); :data:`DEPRECATED_NAMES` maps each to its name.
    r_outer = _deprecated("outer_radius_mm")
    r_bore = _deprecated("outer_bore_radius_mm")
    r_piston = _deprecated("piston_radius_mm")
    r_inner_tube = _deprecated("inner_tube_outer_radius_mm")
    r_rod = _deprecated("rod_radius_mm")
    r_bladder_in = _deprecated("bladder_inner_radius_mm")
    r_bladder_out = _deprecated("bladder_outer_radius_mm")
    r_pocket = _deprecated("piston_pocket_radius_mm")
    r_fill_tube_out = _deprecated("fill_tube_outer_radius_mm")
    r_fill_tube_bore = _deprecated("fill_tube_bore_radius_mm")
    slot_height = _deprecated("cross_slot_mm")
    clamp = _deprecated("bladder_clamp_mm")

    # ----------------------------------------------------------- checks
    def check(self) -> None:
        """Raise :class:`CadError` if a feature does not fit (:func:`~vvea_design.cad.layout_checks.check_layout`)."""
        check_layout(self)
