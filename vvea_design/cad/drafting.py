"""The drawing vocabulary of the CAD parts: what a sheet says about a part, before any layout.

A part's drawing hook (:attr:`~vvea_design.cad.registry.Part.drawing`)
returns a :class:`SheetContent`: the section plane, the dimensions
(:class:`Dim`, anchored on the outline of the section), the notes with
leader lines (:class:`Leader`), the numbered notes and an optional enlarged
:class:`Detail`. All coordinates are model mm in the section plane: ``u``
across the axis (x or y), ``z`` along it. :mod:`vvea_design.report.drawing`
cuts the solids, lays the sheet out at a true scale and writes SVG/PDF.

Tolerances written on the sheets: general tolerances ISO 2768-m; the
sliding fits are ISO 286 H8/f7 (piston in its bore, rod in the base), their
deviations from the ISO 286 table below (:func:`fit_deviations_um`); seal
grooves from the O-ring's gland (:mod:`vvea_design.cad.seals`).
"""

from __future__ import annotations

from dataclasses import dataclass, field

from build123d import Solid

from .layout import Layout
from .seals import COMPOUND

__all__ = ["Dim", "Leader", "Detail", "SheetContent", "fit_deviations_um", "fit_text", "fit_tolerance", "FITS",
           "general_notes", "part_notes", "Revision", "revision_date", "drawing_number", "FIXED_DATE",
           "radial_extent_mm", "PLANES"]

#: Section planes a sheet can show: ``"xz"`` (the valve plane y = 0, u = x), ``"yz"`` (the fill-port plane
#: x = 0, u = y) and ``"aligned"`` (section A-A: the left half in the valve plane, the right in the fill-port plane).
PLANES = ("xz", "yz", "aligned")

# ISO 286-1 standard tolerance grades IT6 ... IT11 (µm) and the fundamental deviations es of the shafts "f" and "g"
# (µm) by nominal size range (over, up to] in mm.
_ISO286 = (  # (over, up to, IT6, IT7, IT8, IT9, IT10, IT11, es of f, es of g)
    (0, 3, 6, 10, 14, 25, 40, 60, -6, -2), (3, 6, 8, 12, 18, 30, 48, 75, -10, -4),
    (6, 10, 9, 15, 22, 36, 58, 90, -13, -5), (10, 18, 11, 18, 27, 43, 70, 110, -16, -6),
    (18, 30, 13, 21, 33, 52, 84, 130, -20, -7), (30, 50, 16, 25, 39, 62, 100, 160, -25, -9),
    (50, 80, 19, 30, 46, 74, 120, 190, -30, -10), (80, 120, 22, 35, 54, 87, 140, 220, -36, -12),
)
#: The fits :func:`fit_deviations_um` knows: holes H6...H11, shafts h6...h11, f6...f11 and g6...g11 (ISO 286-2).
FITS = tuple(f"{letter}{grade}" for letter in "Hhfg" for grade in range(6, 12))


def fit_deviations_um(nominal_mm: float, fit: str) -> tuple[float, float]:
    """ISO 286 deviations of a hole (H) or a shaft (h, f, g) of tolerance grade 6 ... 11.

    Parameters
    ----------
    nominal_mm : float
        Nominal size, mm (0 ... 120).
    fit : str
        One of :data:`FITS`, e.g. ``"H8"``, ``"f7"``, ``"h9"``, ``"g7"``.

    Returns
    -------
    (float, float)
        Upper and lower deviation, µm.

    Raises
    ------
    ValueError
        For another fit or a size outside the table.
    """
    if fit not in FITS:
        raise ValueError(f"fit must be one of H6...H11, h6...h11, f6...f11, g6...g11 (ISO 286), got {fit!r}")
    letter, grade = fit[0], int(fit[1:])
    for lo, hi, *it, es_f, es_g in _ISO286:
        if lo < nominal_mm <= hi:
            t = float(it[grade - 6])
            if letter == "H":
                return t, 0.0
            es = {"h": 0.0, "f": float(es_f), "g": float(es_g)}[letter]
            return es, es - t
    raise ValueError(f"nominal size {nominal_mm:g} mm outside the ISO 286 table (0-120 mm)")


def fit_text(d_mm: float, fit: str) -> str:
    """The fit as written on a drawing: ``Ø34.37 H8 (+0.039/0)``.

    Parameters
    ----------
    d_mm : float
        Nominal diameter, mm.
    fit : str
        One of :data:`FITS`.

    Returns
    -------
    str
        Diameter (mm, two decimals), fit and its deviations in mm (a zero deviation written ``0``).
    """
    return f"Ø{d_mm:.2f} {fit_tolerance(d_mm, fit)}"


def fit_tolerance(d_mm: float, fit: str) -> str:
    """The tolerance part of :func:`fit_text`: ``H8 (+0.039/0)``.

    Parameters
    ----------
    d_mm : float
        Nominal diameter, mm.
    fit : str
        One of :data:`FITS`.

    Returns
    -------
    str
        The fit and its deviations in mm (a zero deviation written ``0``).
    """
    up, lo = fit_deviations_um(d_mm, fit)
    return f"{fit} ({up / 1000:+.3f}/{lo / 1000:+.3f})".replace("+0.000", "0").replace("-0.000", "0")


@dataclass(frozen=True)
class Dim:
    """A linear dimension between two anchor points on the outline (model mm).

    ``axis`` "z": vertical (measures z1 - z0, line on ``side`` "left"/"right");
    ``axis`` "u": horizontal (measures u1 - u0, line on ``side`` "top"/"bottom").
    """

    axis: str
    a: tuple[float, float]  #: first anchor (u, z)
    b: tuple[float, float]  #: second anchor (u, z)
    side: str  #: left/right (axis z), top/bottom (axis u), or "inside": the line at the anchors' u, no extension
    text: str = ""  #: label; default the measured length with two decimals
    on_axis: bool = False  #: an anchor is a feature's axis (bore, channel), not a point of the outline

    @property
    def value_mm(self) -> float:
        """The measured length, mm."""
        return abs(self.b[1] - self.a[1]) if self.axis == "z" else abs(self.b[0] - self.a[0])

    def label(self) -> str:
        """The text written on the dimension line.

        Returns
        -------
        str
            :attr:`text` when set, else the measured length :attr:`value_mm` in mm with two decimals.
        """
        return self.text or f"{self.value_mm:.2f}"


@dataclass(frozen=True)
class Leader:
    """A note with a line to a point of the drawing (model mm)."""

    at: tuple[float, float]
    text: str
    side: str = "right"


@dataclass
class Detail:
    """An enlarged view of a window of the sheet's regions (model mm) with its own dimensions."""

    window: tuple[float, float, float, float]  #: u0, u1, z0, z1
    scale: float
    dims: list[Dim]
    leaders: list[Leader] = field(default_factory=list)
    label: str = "A"


@dataclass(frozen=True)
class SheetContent:
    """What one sheet says (model mm): its section plane, dimensions, leaders, notes and detail view.

    A part's sheet leaves ``title``, ``material``, ``view_note`` and ``extent`` empty: the drawing takes
    them from the part (title, material, mass) and its solid (bounding box). The unit's section sets them.
    """

    dims: tuple[Dim, ...]
    leaders: tuple[Leader, ...]
    notes: tuple[str, ...]
    plane: str = "xz"  #: one of :data:`PLANES`
    detail: Detail | None = None
    title: str = ""  #: "" for a part: its title
    material: str = ""  #: "" for a part: its material
    view_note: str = ""  #: "" for a part: which plane the section lies in
    extent: tuple[float, float, float, float] | None = None  #: u0, u1, z0, z1 (None for a part: its bounding box)

    def __post_init__(self) -> None:
        if self.plane not in PLANES:
            raise ValueError(f"sheet plane must be one of {PLANES}, got {self.plane!r}")


def general_notes(lay: Layout) -> tuple[str, ...]:
    """The general notes of the sheets: tolerances, the sliding fits, the piston and rod seals.

    Parameters
    ----------
    lay : Layout
        Radii and levels of the design (piston and rod diameters, glands), mm.

    Returns
    -------
    tuple of str
        Six notes: dimensions and general tolerances; the piston fit; the rod fit and surface finish;
        the piston seals' grooves; the rod seal's groove (sizes in mm, stretch and squeeze in %); the static
        seals and the compound.
    """
    ps, rs = lay.piston_seal, lay.rod_seal
    seats = lay.seats
    extra = (seats.base, seats.top, seats.fill) if seats is not None else ()
    static = [g for g in (lay.cap_seal, lay.base_seal, lay.collar_seal, *extra) if g is not None]
    return (
        "All dimensions in mm. General tolerances ISO 2768-m; ISO 8015. Edges ISO 13715 -0.2 unless stated.",
        f"Sliding fits ISO 286 H8/f7: piston bore {fit_text(2 * lay.r_piston, 'H8')}, "
        f"piston {fit_text(2 * lay.r_piston, 'f7')};",
        f"rod bore {fit_text(2 * lay.r_rod, 'H8')}, rod {fit_text(2 * lay.r_rod, 'f7')}. "
        "Seal running surfaces Ra 0.4.",
        f"Piston seals: 2x O-ring {ps.oring.name}; groove Ø{ps.groove_diameter_mm:.2f} h9 x {ps.width_mm:.2f} +0.13 "
        f"(stretch {100 * ps.stretch:.1f} %, squeeze {100 * ps.squeeze:.0f} %).",
        f"Rod seal: O-ring {rs.oring.name}; groove Ø{rs.groove_diameter_mm:.2f} H9 x {rs.width_mm:.2f} +0.13 "
        f"(stretch {100 * rs.stretch:.1f} %, squeeze {100 * rs.squeeze:.0f} %).",
        "Static seals: " + "; ".join(f"{g.kind} O-ring {g.oring.code} (squeeze {100 * g.squeeze:.0f} %)"
                                     for g in static) + f". Compound {COMPOUND}.",
    )


#: The drawings' fixed issue date: the STEP files' header date (:data:`~vvea_design.cad.export.STEP_TIMESTAMP`), so
#: the files are byte-stable; ``SOURCE_DATE_EPOCH`` (the reproducible-builds variable) sets another one.
FIXED_DATE = "2000-01-01"


@dataclass(frozen=True)
class Revision:
    """A drawing set's revision for the title blocks: letter, date (ISO 8601) and a note."""

    letter: str = "A"
    date: str = ""  #: "" -> :func:`revision_date`
    note: str = "first issue"

    def __post_init__(self) -> None:
        if not self.date:
            object.__setattr__(self, "date", revision_date())


def revision_date() -> str:
    """The revision date: ``SOURCE_DATE_EPOCH`` (seconds since 1970, UTC) when set, else :data:`FIXED_DATE`.

    Returns
    -------
    str
        ``YYYY-MM-DD``.

    Raises
    ------
    ValueError
        If ``SOURCE_DATE_EPOCH`` is set but not an integer (names the variable).
    """
    import datetime
    import os

    epoch = os.environ.get("SOURCE_DATE_EPOCH")
    if not epoch:
        return FIXED_DATE
    try:
        return datetime.datetime.fromtimestamp(int(epoch), tz=datetime.timezone.utc).strftime("%Y-%m-%d")
    except ValueError:
        raise ValueError(f"SOURCE_DATE_EPOCH must be whole seconds since 1970, got {epoch!r}") from None


def drawing_number(design_id: str, sheet_no: int) -> str:
    """A sheet's drawing number: ``VVEA-<design id>-<sheet>``, e.g. ``VVEA-1a2b3c4d5e-03``.

    Parameters
    ----------
    design_id : str
        The design's short id (a digest of the design: another design, another number).
    sheet_no : int
        The sheet's number in the set, from 1.

    Returns
    -------
    str
        The drawing number.
    """
    return f"VVEA-{design_id or 'x'}-{sheet_no:02d}"


def part_notes() -> tuple[str, ...]:
    """The general notes of a part's sheet: units, general tolerances, edges and surface roughness.

    Returns
    -------
    tuple of str
        Three notes (ISO 2768-m, ISO 8015, ISO 13715 edges; Ra 3.2 unless stated; the internal corners' root
        radii that the FE check assumes, mm).
    """
    from .layout import BULKHEAD_ROOT_RADIUS_MM, ROD_SHOULDER_RADIUS_MM, ROOT_RADIUS_MM

    return ("All dimensions in mm. General tolerances ISO 2768-m; ISO 8015. Edges ISO 13715 -0.2 unless stated "
            "(burr-free).",
            "Surfaces Ra 3.2 unless stated; sealing surfaces free of scratches across the axis (ISO 3601-2).",
            f"Inside corners R{ROOT_RADIUS_MM:g} unless stated; rod shoulder R{ROD_SHOULDER_RADIUS_MM:g}; bulkhead "
            f"roots R{BULKHEAD_ROOT_RADIUS_MM:g} (the FE check assumes them).")


def radial_extent_mm(solid: Solid) -> tuple[float, float, float]:
    """How far a solid reaches from the axis, and its axial span, from its bounding box.

    Parameters
    ----------
    solid : build123d.Solid
        A part in the assembly frame, mm.

    Returns
    -------
    (float, float, float)
        ``R`` (largest |x| or |y| of the box), ``z0`` and ``z1`` (lowest and highest z), mm.
    """
    bb = solid.bounding_box()
    return max(abs(bb.min.X), abs(bb.max.X), abs(bb.min.Y), abs(bb.max.Y)), bb.min.Z, bb.max.Z
