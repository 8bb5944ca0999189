"""O-ring seals: the ISO 3601-1 class A sizes and the glands that hold them,
from bd_warehouse's data (:mod:`bd_warehouse.o_rings`), so the drawing, the
bill of materials and the solids name the same ring.

What comes from where:

* **sizes** (inner diameter, cross-section and their tolerances): ISO 3601-1
  class A (= AS568 dash numbers), bd_warehouse's ``o-ring_parameters.csv``;
  this unit uses the 1.78 mm and 2.62 mm series (:data:`SERIES`);
* **glands** (radial depth window, squeeze window, groove width without
  back-up ring, groove root radius, largest extrusion gap): bd_warehouse's
  ``o-ring_static_gland_parameters.csv`` (static, radial squeeze) and
  ``o-ring_dynamic_gland_parameters.csv`` (reciprocating) -- the seal makers'
  design-guide values bd_warehouse states (Apple Rubber); initial design
  values, not a verification against ISO 3601-2;
* **lead-in chamfers** (kept here, bd_warehouse has none): ISO 3601-2's rule
  that every edge an O-ring passes on assembly has a 15 ... 20 deg chamfer
  whose radial depth exceeds the ring's protrusion (free ring with its
  cross-section tolerance, beyond the surface it seals on); the length is at
  least the installation-chamfer length of the seal makers' guides
  (:data:`LEAD_IN_MIN_LENGTH_MM`, 15 deg);
* **surface finish** (kept here): ISO 3601-2's roughness for pulsating
  pressure (:data:`FINISH_RA_UM`): the chambers see a pressure cycle every
  stroke;
* **compound**: NBR 70 IRHD, the ISO 3601-5 class for mineral hydraulic oil
  (ISO 6743-4 HM) and nitrogen (:data:`COMPOUND`).

Selection (:func:`piston_gland`, :func:`rod_gland`, :func:`static_male_gland`,
:func:`static_female_gland`):

* male gland (groove in the inner part: piston, spigots): groove root
  diameter = bore - 2 x depth; the ring's inner diameter is stretched onto
  the root by 0 ... 5 % (the size closest to 2 % is taken);
* female gland (groove in the outer part: the rod seal in the base): groove
  outer diameter = shaft + 2 x depth; the ring's inner diameter sits on the
  shaft with 0 ... 5 % stretch (closest to 1 %).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from functools import lru_cache

from bd_warehouse.o_rings import ORing as _BdORing

from ..spring.joints import LEAD_IN_MIN_LENGTH_MM as _LEAD_IN_MIN_LENGTH_MM

__all__ = ["ORing", "Gland", "GlandSpec", "LeadIn", "ORING_SIZES", "DYNAMIC_GLANDS", "STATIC_GLANDS", "SERIES",
           "LEAD_IN_MIN_LENGTH_MM", "FINISH_RA_UM", "COMPOUND", "ORING_STANDARD", "get_oring", "gland_spec", "piston_gland",
           "rod_gland", "static_male_gland", "static_female_gland", "lead_in", "SealError"]


class SealError(ValueError):
    """No standard O-ring fits (names the diameter and cross-section)."""


#: The O-ring cross-sections this unit uses (mm): ISO 3601-1 class A, 1.78 mm (sizes 004-050) and 2.62 mm
#: (102-...). The preferred one is ``CadParameters.oring_cross_section_mm``; the other is tried when none fits.
SERIES = (1.78, 2.62)
#: The standard the rings are ordered to.
ORING_STANDARD = "ISO 3601-1 class A (= AS568)"
#: The ring compound for mineral hydraulic oil (ISO 6743-4 HM, ISO VG 32) and nitrogen: ISO 3601-5 NBR, 70 IRHD
#: (-30 ... +100 degC). FKM for oil above 100 degC.
COMPOUND = "NBR 70 IRHD (ISO 3601-5; mineral oil HM and nitrogen, -30...+100 °C)"
#: Shortest lead-in chamfer (mm along the axis) at 15 deg by cross-section (mm): the installation chamfers of the
#: seal makers' design guides; ISO 3601-2's rule (radial depth > the ring's protrusion) may ask more
#: (:func:`lead_in`). The spring side's table (the joints' seal zones reserve this room).
LEAD_IN_MIN_LENGTH_MM = _LEAD_IN_MIN_LENGTH_MM
#: ISO 3601-2 surface roughness Ra (µm) for pulsating pressure: the counter-surface the ring seals on and the
#: groove's flanks and root, static and dynamic (reciprocating) glands.
FINISH_RA_UM = {"static": {"counter": 0.8, "groove": 1.6}, "dynamic": {"counter": 0.4, "groove": 1.6}}


def _o_ring_class():
    """bd_warehouse's ORing class (its CSVs are read once, at its import)."""
    return _BdORing


@lru_cache(maxsize=1)
def _sizes() -> dict[str, tuple[float, float]]:
    data = _o_ring_class().o_ring_parameters["iso3601"]
    return {code: (float(p["id"]), float(p["w"])) for code, p in sorted(data.items()) if float(p["w"]) in SERIES}


@dataclass(frozen=True)
class GlandSpec:
    """One row of bd_warehouse's gland tables (mm, %): radial depth and squeeze windows, groove width without
    back-up ring, groove root radius, largest diametral clearance (extrusion gap)."""

    depth_min_mm: float
    depth_max_mm: float
    width_mm: float
    squeeze_min_pct: float
    squeeze_max_pct: float
    radius_min_mm: float
    radius_max_mm: float
    clearance_max_mm: float

    def as_tuple(self) -> tuple[float, float, float, float, float]:
        """The first five numbers, as the old hand-typed table held them.

        Returns
        -------
        tuple of float
            depth min, depth max, groove width (mm), squeeze min, squeeze max (%).
        """
        return (self.depth_min_mm, self.depth_max_mm, self.width_mm, self.squeeze_min_pct, self.squeeze_max_pct)


@lru_cache(maxsize=1)
def _glands() -> tuple[dict[float, GlandSpec], dict[float, GlandSpec]]:
    cls = _o_ring_class()
    dyn, sta = {}, {}
    for w in SERIES:
        d = cls.o_ring_dynamic_gland_data[f"{w:g}"]
        dyn[w] = GlandSpec(d["d_min"], d["d_max"], d["g_w_0"], d["sq_p_min"], d["sq_p_max"], d["g_r_min"],
                           d["g_r_max"], d["clr_max"])
        s = cls.o_ring_static_gland_data[f"{w:g}"]
        sta[w] = GlandSpec(s["d_r_min"], s["d_r_max"], s["g_w_0"], s["sq_r_p_min"], s["sq_r_p_max"], s["g_r_min"],
                           s["g_r_max"], s["clr_max"])
    return dyn, sta


#: ISO 3601-1 sizes of :data:`SERIES`: code -> (inner diameter, cross-section), mm (bd_warehouse's data).
ORING_SIZES: dict[str, tuple[float, float]] = _sizes()
#: Dynamic (reciprocating) gland without back-up ring per cross-section (mm, %): depth min, depth max, groove
#: width, squeeze min %, squeeze max % (bd_warehouse's data; the groove depth may leave [depth min, depth max] to
#: seat a standard ring, never the squeeze window).
DYNAMIC_GLANDS: dict[float, tuple[float, float, float, float, float]] = {
    w: g.as_tuple() for w, g in _glands()[0].items()}
#: Static gland (radial squeeze) without back-up ring per cross-section: the same columns (bd_warehouse's data).
STATIC_GLANDS: dict[float, tuple[float, float, float, float, float]] = {
    w: g.as_tuple() for w, g in _glands()[1].items()}


def gland_spec(cross_section_mm: float, application: str) -> GlandSpec:
    """The full gland row (radius and clearance included) of a cross-section.

    Parameters
    ----------
    cross_section_mm : float
        O-ring cross-section, mm (one of :data:`SERIES`).
    application : str
        ``"static"`` or ``"dynamic"``.

    Returns
    -------
    GlandSpec
        Depth, squeeze, width, root radius and clearance limits (mm, %).

    Raises
    ------
    SealError
        For another cross-section or application.
    """
    dyn, sta = _glands()
    table = {"static": sta, "dynamic": dyn}.get(application)
    if table is None:
        raise SealError(f"application must be 'static' or 'dynamic', got {application!r}")
    if cross_section_mm not in table:
        raise SealError(f"no {application} gland data for an O-ring cross-section of {cross_section_mm:g} mm; "
                        f"known: {', '.join(f'{w:g}' for w in SERIES)} mm")
    return table[cross_section_mm]


@dataclass(frozen=True)
class ORing:
    """One standard O-ring (mm)."""

    code: str  #: ISO 3601-1 size code (= AS568 dash number)
    inner_diameter_mm: float
    cross_section_mm: float

    @property
    def name(self) -> str:
        """Order name, e.g. ``ISO 3601-1 026 (AS568-026), 31.47 x 1.78 mm``."""
        return (f"ISO 3601-1 {self.code} (AS568-{self.code}), "
                f"{self.inner_diameter_mm:.2f} x {self.cross_section_mm:.2f} mm")

    @property
    def cross_section_tolerance_mm(self) -> float:
        """± tolerance of the cross-section (ISO 3601-1 class A, bd_warehouse's data), mm."""
        return float(_o_ring_class().parameters(self.code)["w_tol"])

    @property
    def inner_diameter_tolerance_mm(self) -> float:
        """± tolerance of the inner diameter (ISO 3601-1 class A), mm."""
        return float(_o_ring_class().parameters(self.code)["id_tol"])

    def to_dict(self) -> dict:
        """Plain-JSON dictionary of the ring.

        Returns
        -------
        dict
            JSON-ready: ``name`` (order name), ``code`` (ISO 3601-1 / AS568 size code),
            ``inner_diameter_mm`` and ``cross_section_mm`` (mm) and ``standard``.
        """
        return {"name": self.name, "code": self.code, "inner_diameter_mm": self.inner_diameter_mm,
                "cross_section_mm": self.cross_section_mm, "standard": "ISO 3601-1 class A / AS568"}


@dataclass(frozen=True)
class LeadIn:
    """A lead-in chamfer on the edge an O-ring passes on assembly (ISO 3601-2): angle to the axis, axial
    length and radial depth (mm)."""

    angle_deg: float
    length_mm: float
    depth_mm: float

    def text(self) -> str:
        """As written on a drawing, e.g. ``lead-in 2.10 x 15°``.

        Returns
        -------
        str
            Axial length (mm) and angle to the axis (deg).
        """
        return f"lead-in {self.length_mm:.2f} x {self.angle_deg:g}°"


def lead_in(ring: ORing, protrusion_mm: float, max_length_mm: float | None = None) -> LeadIn:
    """The lead-in chamfer of an edge ``ring`` passes on assembly (ISO 3601-2, 15 ... 20 deg).

    Radial depth: the ring's largest protrusion beyond the surface it seals on (its cross-section tolerance
    included) + 0.1 mm, so the ring only meets the chamfer; length: at least :data:`LEAD_IN_MIN_LENGTH_MM` at
    15 deg. When ``max_length_mm`` is shorter, the angle is raised towards 20 deg.

    Parameters
    ----------
    ring : ORing
        The O-ring that passes the edge.
    protrusion_mm : float
        Nominal protrusion of the free ring beyond the sealing surface (cross-section - gland depth), mm.
    max_length_mm : float, optional
        Longest chamfer the part has room for along the axis, mm.

    Returns
    -------
    LeadIn
        Angle (deg), axial length and radial depth (mm).

    Raises
    ------
    SealError
        If even a 20 deg chamfer does not fit in ``max_length_mm``.
    """
    w = ring.cross_section_mm
    depth = round(protrusion_mm + ring.cross_section_tolerance_mm + 0.1, 2)
    length = max(LEAD_IN_MIN_LENGTH_MM.get(w, 0.0), depth / math.tan(math.radians(15.0)))
    if max_length_mm is None or length <= max_length_mm + 1e-9:
        return LeadIn(15.0, round(length, 2), round(length * math.tan(math.radians(15.0)), 3))
    steep = depth / math.tan(math.radians(20.0))
    if steep > max_length_mm + 1e-9:
        raise SealError(f"no room for the lead-in chamfer of O-ring {ring.code}: needs {steep:.2f} mm at 20° "
                        f"(radial depth {depth:.2f} mm), has {max_length_mm:.2f} mm")
    ang = math.degrees(math.atan(depth / max_length_mm))
    ang = max(15.0, math.ceil(ang * 10) / 10)
    return LeadIn(ang, round(depth / math.tan(math.radians(ang)), 2), depth)


@dataclass(frozen=True)
class Gland:
    """A seal groove and its O-ring (mm): where it sits, how much the ring is squeezed, the groove's radius,
    finish and the lead-in chamfer of the edge the ring passes on assembly."""

    kind: str  #: what it seals: "piston", "rod", "collar", "cap", "base", ... (names the BOM line)
    oring: ORing
    depth_mm: float  #: radial groove depth (from the sealing diameter)
    width_mm: float  #: axial groove width
    sliding_diameter_mm: float  #: the diameter the ring seals on: bore (male gland) or shaft (female gland)
    groove_diameter_mm: float  #: root diameter (male gland) or outer diameter (female gland)
    application: str = "dynamic"  #: "dynamic" (reciprocating) or "static" (radial squeeze)
    male: bool | None = None  #: groove in the inner part (None: from ``kind``: piston/collar male, rod female)
    where: str = ""  #: human description (BOM, drawings)
    spec: GlandSpec | None = field(default=None, compare=False, repr=False)  #: the table row the gland came from

    @property
    def is_male(self) -> bool:
        """Groove in the inner part (the ring seats on the groove root and seals on a bore)."""
        return self.male if self.male is not None else self.kind in ("piston", "collar")

    @property
    def stretch(self) -> float:
        """Installed inner-diameter stretch of the ring (fraction)."""
        seat = self.groove_diameter_mm if self.is_male else self.sliding_diameter_mm
        return seat / self.oring.inner_diameter_mm - 1.0

    @property
    def squeeze(self) -> float:
        """Nominal radial squeeze (cross-section - gland depth) / cross-section, fraction."""
        return (self.oring.cross_section_mm - self.depth_mm) / self.oring.cross_section_mm

    @property
    def fill(self) -> float:
        """Groove fill: ring cross-section area / groove area (fraction, < 0.9 wanted)."""
        return math.pi / 4 * self.oring.cross_section_mm**2 / (self.depth_mm * self.width_mm)

    @property
    def _spec(self) -> GlandSpec:
        return self.spec or gland_spec(self.oring.cross_section_mm, self.application)

    @property
    def radius_mm(self) -> float:
        """Nominal groove root radius (mid of the table's window), mm."""
        s = self._spec
        return round(0.5 * (s.radius_min_mm + s.radius_max_mm), 3)

    @property
    def radius_range_mm(self) -> tuple[float, float]:
        """The groove root radius window of the gland table, mm."""
        return self._spec.radius_min_mm, self._spec.radius_max_mm

    @property
    def clearance_max_mm(self) -> float:
        """Largest diametral clearance (extrusion gap) the gland table allows, mm."""
        return self._spec.clearance_max_mm

    @property
    def protrusion_mm(self) -> float:
        """Nominal protrusion of the free ring beyond the sealing surface (cross-section - depth), mm."""
        return self.oring.cross_section_mm - self.depth_mm

    @property
    def free_sealing_radius_mm(self) -> float:
        """Where the free (uninstalled-side) ring reaches: largest radius of a male gland's ring, smallest of a
        female gland's, cross-section tolerance included, mm."""
        t = self.oring.cross_section_tolerance_mm
        if self.is_male:
            return self.sliding_diameter_mm / 2 + self.protrusion_mm + t
        return self.sliding_diameter_mm / 2 - self.protrusion_mm - t

    def lead_in(self, max_length_mm: float | None = None) -> LeadIn:
        """The lead-in chamfer of the edge this ring passes on assembly (:func:`lead_in`).

        Parameters
        ----------
        max_length_mm : float, optional
            Longest chamfer the part has room for along the axis, mm.

        Returns
        -------
        LeadIn
            Angle (deg), axial length and radial depth (mm).
        """
        return lead_in(self.oring, self.protrusion_mm, max_length_mm)

    @property
    def finish_text(self) -> str:
        """ISO 3601-2 roughness of the sealing surface and the groove, e.g. ``Ra 0.4 (bore), Ra 1.6 (groove)``."""
        f = FINISH_RA_UM[self.application]
        surface = "bore" if self.is_male else "shaft"
        return f"Ra {f['counter']:g} ({surface}), Ra {f['groove']:g} (groove)"

    @property
    def groove_fit(self) -> str:
        """The groove diameter's tolerance class: h9 (male root), H9 (female outer diameter)."""
        return "h9" if self.is_male else "H9"

    def to_dict(self) -> dict:
        """Plain-JSON dictionary of the gland, its ring and its fit.

        Returns
        -------
        dict
            JSON-ready: ``kind``, ``application``, ``male``, ``oring`` (:meth:`ORing.to_dict`), ``depth_mm``,
            ``width_mm``, ``sliding_diameter_mm``, ``groove_diameter_mm``, ``radius_mm`` (mm), the fractions
            ``stretch``, ``squeeze`` and ``fill``, ``lead_in`` (angle in deg, length and depth in mm),
            ``finish`` and ``compound``.
        """
        li = self.lead_in()
        return {"kind": self.kind, "application": self.application, "male": self.is_male,
                "oring": self.oring.to_dict(), "depth_mm": self.depth_mm, "width_mm": self.width_mm,
                "sliding_diameter_mm": self.sliding_diameter_mm, "groove_diameter_mm": self.groove_diameter_mm,
                "radius_mm": self.radius_mm, "stretch": self.stretch, "squeeze": self.squeeze, "fill": self.fill,
                "lead_in": {"angle_deg": li.angle_deg, "length_mm": li.length_mm, "depth_mm": li.depth_mm},
                "finish": self.finish_text, "compound": COMPOUND}


def get_oring(code: str) -> ORing:
    """The O-ring of an ISO 3601-1 size.

    Parameters
    ----------
    code : str
        Size code (``"026"``, ``"-026"`` or ``"26"``).

    Returns
    -------
    ORing
        Inner diameter and cross-section in mm.

    Raises
    ------
    SealError
        For a code not in the table.
    """
    key = str(code).strip().lstrip("-").zfill(3)
    if key not in ORING_SIZES:
        raise SealError(f"unknown O-ring size {code!r}; known: {min(ORING_SIZES)} ... {max(ORING_SIZES)}")
    d, w = ORING_SIZES[key]
    return ORing(key, d, w)


def _series(preferred_mm: float) -> list[float]:
    if preferred_mm not in SERIES:
        raise SealError(f"no dynamic gland data for an O-ring cross-section of {preferred_mm:g} mm; "
                        f"known: {', '.join(f'{w:g}' for w in SERIES)} mm")
    return [preferred_mm] + [w for w in SERIES if w != preferred_mm]


def _male(bore_mm: float, cross_section_mm: float, application: str, kind: str) -> Gland:
    for w in _series(cross_section_mm):
        spec = gland_spec(w, application)
        d_nom = 0.5 * (spec.depth_min_mm + spec.depth_max_mm)
        depth_lo, depth_hi = w * (1 - spec.squeeze_max_pct / 100), w * (1 - spec.squeeze_min_pct / 100)
        best = None
        for code, (d_in, w_ring) in ORING_SIZES.items():
            if w_ring != w:
                continue
            root_lo, root_hi = max(d_in, bore_mm - 2 * depth_hi), min(1.05 * d_in, bore_mm - 2 * depth_lo)
            if root_lo > root_hi + 1e-12:
                continue
            root = min(max(bore_mm - 2 * d_nom, root_lo), root_hi)
            score = (round(abs((bore_mm - root) / 2 - d_nom), 6), abs(root / d_in - 1.02))
            if best is None or score < best[0]:
                best = (score, code, root)
        if best is not None:
            _, code, root = best
            return Gland(kind, get_oring(code), round((bore_mm - root) / 2, 6), spec.width_mm, bore_mm, root,
                         application, True, spec=spec)
    raise SealError(f"no ISO 3601-1 O-ring ({', '.join(f'{w:g}' for w in SERIES)} mm series) seals a "
                    f"{'piston' if kind == 'piston' else 'spigot'} in a Ø{bore_mm:.2f} mm bore with 0-5 % stretch "
                    f"inside the squeeze window")


def _female(shaft_mm: float, cross_section_mm: float, application: str, kind: str) -> Gland:
    for w in _series(cross_section_mm):
        spec = gland_spec(w, application)
        depth = round(0.5 * (spec.depth_min_mm + spec.depth_max_mm), 6)
        best = None
        for code, (d_in, w_ring) in ORING_SIZES.items():
            s = shaft_mm / d_in - 1.0
            if w_ring == w and -1e-9 <= s <= 0.05 and (best is None or abs(s - 0.01) < best[0]):
                best = (abs(s - 0.01), code)
        if best is not None:
            return Gland(kind, get_oring(best[1]), depth, spec.width_mm, shaft_mm, shaft_mm + 2 * depth, application,
                         False, spec=spec)
    noun = "rod" if kind == "rod" else "shaft"
    raise SealError(f"no ISO 3601-1 O-ring seats on a Ø{shaft_mm:.2f} mm {noun} with 0-5 % stretch")


def piston_gland(bore_mm: float, cross_section_mm: float = 1.78) -> Gland:
    """Piston seal groove (male dynamic gland) and its O-ring.

    Takes the ring and groove root with the gland depth closest to the
    recommended one, inside the squeeze window, and 0 ... 5 % stretch (closest
    to 2 %); the preferred cross-section first, the other series if none fits.

    Parameters
    ----------
    bore_mm : float
        Bore the piston runs in, mm.
    cross_section_mm : float
        Preferred O-ring cross-section, mm (1.78 or 2.62).

    Returns
    -------
    Gland
        Ring, groove depth and width, root diameter (mm), stretch and squeeze.

    Raises
    ------
    SealError
        When no ring of either series fits.
    """
    return _male(bore_mm, cross_section_mm, "dynamic", "piston")


def rod_gland(rod_mm: float, cross_section_mm: float = 1.78) -> Gland:
    """Rod seal groove in the housing (female dynamic gland) and its O-ring.

    The ring's inner diameter sits on the rod with 0 ... 5 % stretch (closest
    to 1 %); the groove depth is the recommended one.

    Parameters
    ----------
    rod_mm : float
        Rod diameter, mm.
    cross_section_mm : float
        Preferred O-ring cross-section, mm (1.78 or 2.62).

    Returns
    -------
    Gland
        Ring, groove depth and width, groove outer diameter (mm), stretch and squeeze.

    Raises
    ------
    SealError
        When no ring of either series seats on the rod.
    """
    return _female(rod_mm, cross_section_mm, "dynamic", "rod")


def static_male_gland(bore_mm: float, cross_section_mm: float = 1.78, kind: str = "static") -> Gland:
    """Static seal groove in an inner part (a spigot or collar in a bore): radial squeeze, the static table.

    Parameters
    ----------
    bore_mm : float
        Bore the ring seals on, mm.
    cross_section_mm : float
        Preferred O-ring cross-section, mm (1.78 or 2.62).
    kind : str
        What it seals (names the gland's BOM line), e.g. ``"cap"``.

    Returns
    -------
    Gland
        Ring, groove depth and width, root diameter (mm), stretch and squeeze.

    Raises
    ------
    SealError
        When no ring of either series fits.
    """
    return _male(bore_mm, cross_section_mm, "static", kind)


def static_female_gland(shaft_mm: float, cross_section_mm: float = 1.78, kind: str = "static") -> Gland:
    """Static seal groove in an outer part around a shaft or tube: radial squeeze, the static table.

    Parameters
    ----------
    shaft_mm : float
        Diameter the ring seals on, mm.
    cross_section_mm : float
        Preferred O-ring cross-section, mm (1.78 or 2.62).
    kind : str
        What it seals (names the gland's BOM line).

    Returns
    -------
    Gland
        Ring, groove depth and width, groove outer diameter (mm), stretch and squeeze.

    Raises
    ------
    SealError
        When no ring of either series seats on the shaft.
    """
    return _female(shaft_mm, cross_section_mm, "static", kind)
