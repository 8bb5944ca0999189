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

__all__ = ["Dim", "Leader", "Detail", "SheetContent", "fit_deviations_um", "fit_text", "general_notes",
           "radial_extent_mm", "PLANES"]

#: Section planes a sheet can show: ``"xz"`` (the valve plane y = 0, u = x), ``"yz"`` (the fill-port plane
#: x = 0, u = y) and ``"aligned"`` (section A-A: the left half in the valve plane, the right in the fill-port plane).
PLANES = ("xz", "yz", "aligned")

# ISO 286-1 standard tolerance grades (µm) and the fundamental deviation of shafts "f" (µm) by nominal size
# range (over, up to] in mm.
_ISO286 = (  # (over, up to, IT7, IT8, es of f)
    (3, 6, 12, 18, -10), (6, 10, 15, 22, -13), (10, 18, 18, 27, -16), (18, 30, 21, 33, -20),
    (30, 50, 25, 39, -25), (50, 80, 30, 46, -30), (80, 120, 35, 54, -36),
)


def fit_deviations_um(nominal_mm: float, fit: str) -> tuple[float, float]:
    """ISO 286 deviations of an H8 hole or an f7 shaft.

    Parameters
    ----------
    nominal_mm : float
        Nominal size, mm (3 ... 120).
    fit : str
        ``"H8"`` or ``"f7"``.

    Returns
    -------
    (float, float)
        Upper and lower deviation, µm.

    Raises
    ------
    ValueError
        For another fit or a size outside the table.
    """
    for lo, hi, it7, it8, es_f in _ISO286:
        if lo < nominal_mm <= hi:
            if fit == "H8":
                return float(it8), 0.0
            if fit == "f7":
                return float(es_f), float(es_f - it7)
            raise ValueError(f"fit must be 'H8' or 'f7', got {fit!r}")
    raise ValueError(f"nominal size {nominal_mm:g} mm outside the ISO 286 table (3-120 mm)")


def fit_text(d_mm: float, fit: str) -> str:
    """The fit as written on a drawing: ``Ø34.37 H8 (+0.039/0)``.

    Parameters
    ----------
    d_mm : float
        Nominal diameter, mm.
    fit : str
        ``"H8"`` or ``"f7"``.

    Returns
    -------
    str
        Diameter (mm, two decimals), fit and its deviations in mm (a zero deviation written ``0``).
    """
    up, lo = fit_deviations_um(d_mm, fit)
    return f"Ø{d_mm:.2f} {fit} ({up / 1000:+.3f}/{lo / 1000:+.3f})".replace("+0.000", "0")


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
        Five notes: dimensions and general tolerances; the piston fit; the rod fit and surface finish;
        the piston seals' grooves; the rod seal's groove (sizes in mm, stretch and squeeze in %).
    """
    ps, rs = lay.piston_seal, lay.rod_seal
    return (
        "All dimensions in mm. General tolerances ISO 2768-m. Break sharp edges 0.2 x 45°.",
        f"Sliding fits ISO 286 H8/f7: piston bore {fit_text(2 * lay.r_piston, 'H8')}, "
        f"piston {fit_text(2 * lay.r_piston, 'f7')};",
        f"rod bore {fit_text(2 * lay.r_rod, 'H8')}, rod {fit_text(2 * lay.r_rod, 'f7')}. "
        "Seal running surfaces Ra 0.4.",
        f"Piston seals: 2x O-ring {ps.oring.name}; groove Ø{ps.groove_diameter_mm:.2f} h9 x {ps.width_mm:.2f} +0.1 "
        f"(stretch {100 * ps.stretch:.1f} %, squeeze {100 * ps.squeeze:.0f} %).",
        f"Rod seal: O-ring {rs.oring.name}; groove Ø{rs.groove_diameter_mm:.2f} H9 x {rs.width_mm:.2f} +0.1 "
        f"(stretch {100 * rs.stretch:.1f} %, squeeze {100 * rs.squeeze:.0f} %).",
    )


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
