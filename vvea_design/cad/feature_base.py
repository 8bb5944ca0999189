"""The feature record of a machined part (:class:`Feature`), the drawing conventions it is written in (the
general tolerance, the fits of the housing's diameters, the groove width tolerance) and the features every part
shares (lead-in chamfers, O-ring grooves). :mod:`vvea_design.cad.features` (the parts' lists) and
:mod:`vvea_design.cad.joint_features` (the joint's) build on it; see :mod:`vvea_design.cad.features` for what a
feature is and how the tests check it.
"""

from __future__ import annotations

from dataclasses import dataclass

from .drafting import Dim, Leader, fit_tolerance
from .seals import Gland, LeadIn

__all__ = ["Feature", "FEATURE_KINDS", "DETAIL_KEYS", "GENERAL", "GROOVE_WIDTH_TOL", "THREAD_CLASS", "TUBE_OD_FIT",
           "SEAL_BORE_FIT", "SPIGOT_FIT", "feature_texts", "sheet_plane", "lead_in_feature", "groove_feature",
           "fit_text", "symmetric"]

#: What a feature is.
FEATURE_KINDS = ("length", "diameter", "groove", "hole", "thread", "chamfer", "slot", "radius")
#: The general tolerance (ISO 2768-m) of a feature without its own.
GENERAL = "ISO 2768-m"
#: Width tolerance of an O-ring groove (bd_warehouse's gland width tolerance), mm.
GROOVE_WIDTH_TOL = "+0.13/0"
#: Tolerance class of the internal threads (ISO 965-1).
THREAD_CLASS = "6H"
#: Drawn tolerances of the housing's diameters (ISO 286): the tubes' outside diameters, the bores the O-rings seal
#: on (H8) and the spigots that enter them (g7: the largest clearance stays under the gland's extrusion gap).
TUBE_OD_FIT, SEAL_BORE_FIT, SPIGOT_FIT = "h9", "H8", "g7"
#: The features whose dimension a part's sheet draws in its detail view instead of the main view.
DETAIL_KEYS = frozenset({"groove_width"})

Point = tuple[float, float]


@dataclass(frozen=True)
class Feature:
    """One feature of a machined part (model mm): what it is, its size and tolerance as the sheet writes them,
    the annotation that gives it, the section edges it makes and a point of the material it removes."""

    key: str  #: unique within the part
    kind: str  #: one of :data:`FEATURE_KINDS`
    title: str  #: human name
    size: str  #: the size as written on the sheet, e.g. ``Ø35.42``, ``2.41``, ``M5x0.8``
    tolerance: str  #: the tolerance as written (fit, deviation, thread class) or :data:`GENERAL`
    show: Dim | Leader | str  #: how the sheet gives it: a dimension, a leader note or a numbered note
    u_edges: tuple[float, ...] = ()  #: signed u of the vertical section edges it makes (sheet plane), mm
    z_edges: tuple[float, ...] = ()  #: z of the horizontal section edges it makes, mm
    slants: tuple[tuple[Point, Point], ...] = ()  #: the slanted section edges (chamfers) it makes, end points, mm
    probe: tuple[float, float, float] | None = None  #: a point (x, y, z) in the material it removes, mm
    finish: str = ""  #: surface roughness, e.g. ``Ra 0.4``
    standard: str = ""  #: the standard behind it

    def __post_init__(self) -> None:
        if self.kind not in FEATURE_KINDS:
            raise ValueError(f"feature {self.key!r}: kind must be one of {FEATURE_KINDS}, got {self.kind!r}")
        if not self.size or not self.tolerance:
            raise ValueError(f"feature {self.key!r}: size and tolerance are required")

    @property
    def text(self) -> str:
        """The text of its annotation (the dimension's label, the leader's or the note's text)."""
        if isinstance(self.show, Dim):
            return self.show.label()
        if isinstance(self.show, Leader):
            return self.show.text
        return self.show

    def to_dict(self) -> dict:
        """JSON-ready summary (the manifest's feature list).

        Returns
        -------
        dict
            ``key``, ``kind``, ``title``, ``size``, ``tolerance``, ``finish``, ``standard``.
        """
        return {"key": self.key, "kind": self.kind, "title": self.title, "size": self.size,
                "tolerance": self.tolerance, "finish": self.finish, "standard": self.standard}


def feature_texts(features) -> list[str]:
    """The annotation texts of ``features`` (for a sheet's search).

    Parameters
    ----------
    features : iterable of Feature
        The features.

    Returns
    -------
    list of str
        Each feature's :attr:`Feature.text`.
    """
    return [f.text for f in features]


def sheet_plane(part: str) -> str:
    """The section plane a part's sheet shows: the port plane (x = 0) for the top cap, else the valve plane.

    Parameters
    ----------
    part : str
        Part name.

    Returns
    -------
    str
        ``"yz"`` or ``"xz"``.
    """
    return "yz" if part == "housing_top_cap" else "xz"


# ----------------------------------------------------------------------------------------------- helpers
def fit_text(d_mm: float, fit: str) -> tuple[str, str]:
    """A diameter and its ISO 286 fit as a sheet writes them.

    Parameters
    ----------
    d_mm : float
        Nominal diameter, mm.
    fit : str
        ISO 286 fit, e.g. ``H8``.

    Returns
    -------
    tuple of str
        ``("Ø35.42", "H8 (+0.039/0)")``.
    """
    return f"Ø{d_mm:.2f}", fit_tolerance(d_mm, fit)


def symmetric(*r: float) -> tuple[float, ...]:
    """Both signs of each radius: the section edges of a cylinder on both halves of a sheet.

    Parameters
    ----------
    *r : float
        Radii, mm.

    Returns
    -------
    tuple of float
        ``(-r0, r0, -r1, r1, ...)``, mm.
    """
    return tuple(v for x in r for v in (-x, x))


def lead_in_feature(key: str, title: str, li: LeadIn, r: float, z: float, outward: bool, upward: bool,
                     side: str, gland: Gland) -> Feature:
    """A lead-in chamfer on the circular edge (r, z): slanted edges on both halves, a leader note.

    Parameters
    ----------
    key, title : str
        The feature's key and name.
    li : LeadIn
        The chamfer (angle, axial length, radial depth; mm, deg).
    r, z : float
        The chamfered edge: radius and level, mm.
    outward, upward : bool
        The chamfer reaches outwards (a bore) and upwards from the edge.
    side : str
        Side of the sheet the leader's text goes to (``left`` or ``right``).
    gland : Gland
        The O-ring's gland it leads into.

    Returns
    -------
    Feature
        A ``chamfer`` feature (ISO 3601-2).
    """
    rr = r + li.depth_mm if outward else r - li.depth_mm
    zz = z + li.length_mm if upward else z - li.length_mm
    slants = (((rr, z), (r, zz)), ((-rr, z), (-r, zz)))
    size = f"{li.length_mm:.2f} x {li.angle_deg:g}°"
    tol = "15°...20°, length min."
    txt = (f"{title}: lead-in {size} ({tol}; radial {li.depth_mm:.2f} > O-ring {gland.oring.code} protrusion), "
           "ISO 3601-2")
    at = (0.5 * (r + rr), 0.5 * (z + zz))
    return Feature(key, "chamfer", title, size, tol, Leader(at if side == "right" else (-at[0], at[1]), txt, side),
                   slants=slants, standard="ISO 3601-2")


def groove_feature(key: str, g: Gland, z0: float, z1: float, ref_z: float, ref: str, side: str,
                    u_sign: float = 1.0) -> list[Feature]:
    """An O-ring groove (root or outer diameter with its fit, width, position from a reference face) and its
    root radius, as one leader each.

    Parameters
    ----------
    key : str
        The groove's feature key (the radius gets ``<key>_radius``).
    g : Gland
        The gland (ISO 3601-2 from bd_warehouse), mm.
    z0, z1 : float
        The groove's axial extent, mm.
    ref_z : float
        The reference face its position is given from, mm.
    ref : str
        That face's name.
    side : str
        Side of the sheet the leader's text goes to.
    u_sign : float
        +1: the leader on the right half, -1: on the left (dimensionless).

    Returns
    -------
    list of Feature
        The ``groove`` and its root ``radius``.
    """
    d = g.groove_diameter_mm
    r_s = g.sliding_diameter_mm / 2
    size, tol = fit_text(d, g.groove_fit)
    pos = f"{min(abs(z0 - ref_z), abs(z1 - ref_z)):.2f} from {ref}"
    txt = (f"groove {size} {tol} x {g.width_mm:.2f} {GROOVE_WIDTH_TOL}, {pos}; O-ring {g.oring.code} "
           f"({g.oring.name}), {g.finish_text}")
    r_mid = 0.5 * (d / 2 + r_s)
    at = (u_sign * r_mid, 0.5 * (z0 + z1))
    probe = (u_sign * r_mid, 0.0, 0.5 * (z0 + z1))
    rad = g.radius_range_mm
    return [Feature(key, "groove", f"O-ring groove ({g.where or g.kind})", size, tol, Leader(at, txt, side),
                    u_edges=symmetric(d / 2), z_edges=(z0, z1), probe=probe, finish=g.finish_text,
                    standard="ISO 3601-2 (bd_warehouse gland data)"),
            Feature(f"{key}_radius", "radius", "groove root radius", f"R{g.radius_mm:.2f}",
                    f"R{rad[0]:.2f}...{rad[1]:.2f}", f"{g.application} O-ring grooves ({g.oring.cross_section_mm:g} mm "
                    f"rings): root radius R{g.radius_mm:.2f} (R{rad[0]:.2f}...{rad[1]:.2f}), edges of the groove "
                    "opening 0.1...0.2 rounded, burr-free",
                    standard="ISO 3601-2")]
