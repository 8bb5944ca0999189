"""From a solved piece to the numbers a designer signs: peak stress per wall and where, the nominal
(membrane and bending) stress on a stress-classification line, the concentration between them.

* **Peak**: the largest von Mises and Tresca stress over the nodes of a wall's region (:class:`Region`), with
  the feature it sits at: a groove's root (two re-entrant corners a groove's width apart on one face), a step
  or shoulder (one re-entrant corner), or the plain wall.
* **Nominal**: the stress linearised along a stress-classification line through the wall (EN 13445-3 annex C /
  ASME VIII-2 part 5 practice): membrane ``s_m = (1/t) ∫ s ds`` and bending ``s_b = (6/t^2) ∫ s (t/2 - s) ds``
  of the normal components (the shear is membrane only), the equivalent stress of ``s_m ± s_b`` at both ends;
  away from the concentrations this is what the closed forms give, so FE and closed form compare there.

Lengths mm, stresses MPa.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from .elasticity import AxiSolution, tresca, von_mises
from .section import MeridianSection

__all__ = ["StressLine", "Region", "Peak", "Nominal", "linearise", "peak_in", "feature_at"]

_COMPONENTS = ("s_rr", "s_zz", "s_tt", "s_rz")


@dataclass(frozen=True)
class StressLine:
    """A stress-classification line through a wall, from one surface to the other (mm), and the closed form
    the sizing uses for that wall (``closed_form(gauge_pressures, x_mm) -> MPa``, None: no closed form)."""

    what: str
    start_mm: tuple[float, float]
    end_mm: tuple[float, float]
    closed_form: object = None  #: callable (gauge pressures dict, x_mm) -> float, MPa
    closed_form_what: str = ""


@dataclass(frozen=True)
class Region:
    """A wall of the design inside a piece: the nodes in its boxes (``(r0, r1, z0, z1)``, mm) minus those in
    ``exclude``, and its stress-classification lines."""

    wall: str
    boxes: tuple[tuple[float, float, float, float], ...]
    lines: tuple[StressLine, ...] = ()
    exclude: tuple[tuple[float, float, float, float], ...] = ()

    def mask(self, nodes_mm: np.ndarray) -> np.ndarray:
        """Which nodes belong to the wall.

        Parameters
        ----------
        nodes_mm : ndarray
            ``(2, n)`` r, z of the nodes, mm.

        Returns
        -------
        ndarray of bool
            Nodes inside a box and outside every excluded box (dimensionless flags).
        """
        def inside(boxes):
            m = np.zeros(nodes_mm.shape[1], dtype=bool)
            for r0, r1, z0, z1 in boxes:
                m |= ((nodes_mm[0] >= r0) & (nodes_mm[0] <= r1) & (nodes_mm[1] >= z0) & (nodes_mm[1] <= z1))
            return m

        return inside(self.boxes) & ~inside(self.exclude)


@dataclass(frozen=True)
class Peak:
    """The largest stress of a wall and where it is."""

    von_mises_MPa: float
    tresca_MPa: float
    r_mm: float  #: where the larger of the criterion's stresses is
    z_mm: float
    feature: str  #: "groove root", "step", "plain wall"
    corner_radius_mm: float  #: radius at the feature (nan on a plain wall)


@dataclass(frozen=True)
class Nominal:
    """Linearised stress on a stress-classification line."""

    line: str
    membrane_von_mises_MPa: float
    membrane_bending_von_mises_MPa: float  #: the larger of both surfaces
    membrane_bending_tresca_MPa: float
    closed_form_MPa: float  #: the sizing's closed form for the same pressures (nan: none)
    fe_comparable_MPa: float  #: the FE's value of the quantity the closed form gives (nan: none)
    closed_form_what: str


def linearise(sol: AxiSolution, line: StressLine, gauge_MPa: dict[str, float], x_mm: float = 0.0,
              n: int = 41) -> Nominal:
    """Membrane and bending stress along a line, and the closed form's value beside the FE's.

    The FE's comparable value is the largest principal stress (by magnitude) of ``s_m ± s_b`` at the line's
    ends: hoop stress at a tube's bore, radial bending at a plate's surface, what the closed forms state.

    Parameters
    ----------
    sol : AxiSolution
        The solved piece.
    line : StressLine
        Through the wall, surface to surface, mm.
    gauge_MPa : dict of str to float
        The case's gauge pressures (for the closed form), MPa.
    x_mm : float
        The case's piston displacement (for the closed form: which space is where), mm.
    n : int
        Points along the line.

    Returns
    -------
    Nominal
        Membrane and membrane-plus-bending equivalent stresses (MPa) and the comparison.
    """
    (r0, z0), (r1, z1) = line.start_mm, line.end_mm
    t = math.hypot(r1 - r0, z1 - z0)
    s = np.linspace(0.0, 1.0, n)
    shrink = 1e-6  # stay a hair inside the section
    s_in = shrink + (1 - 2 * shrink) * s
    st = sol.stress_at(r0 + (r1 - r0) * s_in, z0 + (z1 - z0) * s_in)
    mem = {k: float(np.trapezoid(st[k], s)) for k in _COMPONENTS}
    ben = {k: float(6 * np.trapezoid(st[k] * (0.5 - s), s)) if k != "s_rz" else 0.0 for k in _COMPONENTS}
    ends = [{k: mem[k] + sign * ben[k] for k in _COMPONENTS} for sign in (1, -1)]
    vm_mb = max(float(von_mises(*(e[k] for k in _COMPONENTS))) for e in ends)
    tr_mb = max(float(tresca(*(e[k] for k in _COMPONENTS))) for e in ends)
    comparable = max((max((e["s_rr"], e["s_zz"], e["s_tt"]), key=abs) for e in ends), key=abs)
    cf = float(line.closed_form(gauge_MPa, x_mm)) if line.closed_form is not None else math.nan
    _ = t
    return Nominal(line.what, float(von_mises(*(mem[k] for k in _COMPONENTS))), vm_mb, tr_mb, cf,
                   float(abs(comparable)) if line.closed_form is not None else math.nan, line.closed_form_what)


def peak_in(sol: AxiSolution, region: Region, section: MeridianSection, criterion: str = "tresca") -> Peak | None:
    """The peak stress of a wall's region.

    Parameters
    ----------
    sol : AxiSolution
        The solved piece.
    region : Region
        The wall's nodes.
    section : MeridianSection
        The piece's section (to name the feature at the peak).
    criterion : str
        ``"tresca"`` or ``"von_mises"``: which stress locates the peak.

    Returns
    -------
    Peak or None
        None when no node lies in the region.
    """
    m = region.mask(sol.nodes_mm)
    if not m.any():
        return None
    vm, tr = sol.von_mises_MPa, sol.tresca_MPa
    crit = tr if criterion == "tresca" else vm
    idx = np.flatnonzero(m)
    i = idx[np.argmax(crit[idx])]
    r, z = float(sol.nodes_mm[0, i]), float(sol.nodes_mm[1, i])
    feature, rad = feature_at(r, z, section)
    return Peak(float(vm[idx].max()), float(tr[idx].max()), r, z, feature, rad)


def feature_at(r_mm: float, z_mm: float, section: MeridianSection, reach_mm: float = 0.6) -> tuple[str, float]:
    """Name the feature at a point of a section.

    * ``groove root``: a re-entrant corner with a second one on the same face line (same r or same z, within
      6 mm) and void between them (an O-ring gland, a ring groove, an undercut);
    * ``shoulder``: a re-entrant corner alone, or two with material between them (a step, a web's or a
      flange's root, the rod's shoulder);
    * ``edge``: a convex corner (the edge of a bore or a face);
    * ``plain wall``: none of these within reach.

    Parameters
    ----------
    r_mm, z_mm : float
        The point, mm.
    section : MeridianSection
        The section (its re-entrant corners, its outline).
    reach_mm : float
        How far from a corner (beyond its fillet) the point may be, mm.

    Returns
    -------
    tuple
        Feature name and the corner's radius (mm; nan on an edge or a plain wall).
    """
    corners = section.corners
    best, dist = None, math.inf
    for c in corners:
        d = math.hypot(c.r_mm - r_mm, c.z_mm - z_mm)
        if d < dist:
            best, dist = c, d
    if best is not None and dist <= reach_mm + 2 * best.radius_mm:
        for c in corners:
            if c is best:
                continue
            same_r = abs(c.r_mm - best.r_mm) < 1e-3 and abs(c.z_mm - best.z_mm) < 6.0
            same_z = abs(c.z_mm - best.z_mm) < 1e-3 and abs(c.r_mm - best.r_mm) < 6.0
            if not (same_r or same_z):
                continue
            qr, qz = 0.5 * (c.r_mm + best.r_mm), 0.5 * (c.z_mm + best.z_mm)
            dr, dz = (0.05, 0.0) if same_r else (0.0, 0.05)
            both = section.contains([qr - dr, qr + dr], [qz - dz, qz + dz])
            if not both.all():
                return "groove root", best.radius_mm
        return "shoulder", best.radius_mm
    for v in section.face.vertices():
        if math.hypot(v.X - r_mm, v.Y - z_mm) <= reach_mm:
            return "edge", math.nan
    return "plain wall", math.nan
