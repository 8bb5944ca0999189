"""Bladder mould: two halves split on the meridian plane y = 0, a core,
registration pins, a sprue to the lowest point and vents at the highest.

Mould frame: the cavity's axis is Z (vertical when casting), centred on
``z = 0``; the parting plane is ``y = 0``.

* **Cavity** = the cast bladder scaled by ``1 + cad.mould_shrinkage`` about
  its centre, so the cured part shrinks to the drawn bladder:
  ``V_cavity = V_bladder * (1 + s)**3``.
* **Core** (``mould_core``): a tube (wall ``cad.mould_core_wall_mm``) filling the cavity's inner outline,
  sticking out ``cad.mould_core_spigot_mm`` at both ends to locate it in the
  halves' end walls and to pull it out; the bladder is stretched off it.
* **Halves** (``mould_half_a`` at y >= 0 with four pins, ``mould_half_b``
  at y <= 0 with the pin holes, ``cad.pin_clearance_mm`` radial clearance):
  a block around the cavity. A surface of revolution split on a meridian
  plane has no undercut in the opening direction (±y), so the halves need no
  draft; the draft sits where parts slide axially: the sprue funnel.
* **Sprue**: a vertical channel on the parting plane at +x from the top face,
  with a tapered funnel entry, turning into a horizontal runner that enters
  the cavity's lowest point (the underside of the lower bead).
* **Vents**: ``cad.vents`` vertical holes from the cavity's highest face
  (top of the upper bead) to the top face, away from the sprue.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from build123d import Location, Solid

from ._shapes import bar, cone, cut, cylinder, fuse, revolved, ring, single_solid
from .bladder import bladder_profile
from .layout import Layout

__all__ = ["Mould", "mould", "box", "mould_core_volume_mm3"]


def box(x0: float, x1: float, y0: float, y1: float, z0: float, z1: float) -> Solid:
    """Axis-aligned box between the given limits.

    Parameters
    ----------
    x0, x1 : float
        Lower and upper x limits, mm (x0 < x1).
    y0, y1 : float
        Lower and upper y limits, mm (y0 < y1).
    z0, z1 : float
        Lower and upper z limits, mm (z0 < z1).

    Returns
    -------
    Solid
        The box, mm.
    """
    b = Solid.make_box(x1 - x0, y1 - y0, z1 - z0)
    return b.moved(Location((x0, y0, z0)))


@dataclass(frozen=True)
class Mould:
    """The mould's solids (mould frame, mm) and the numbers the tests check."""

    half_a: Solid
    half_b: Solid
    core: Solid
    cavity: Solid  #: the cavity as a solid (= scaled bladder), for checks and renders
    block_mm: tuple[float, float, float, float, float, float]  #: x0, x1, y0, y1, z0, z1 of the halves
    shrinkage: float
    sprue_top_mm: tuple[float, float, float]  #: centre of the sprue's opening in the top face
    vent_tops_mm: tuple[tuple[float, float, float], ...]  #: centres of the vent openings

    def parts(self) -> dict[str, Solid]:
        """The mould parts by file name stem.

        Returns
        -------
        dict of str to Solid
            ``mould_half_a``, ``mould_half_b`` and ``mould_core``, mould frame, mm.
        """
        return {"mould_half_a": self.half_a, "mould_half_b": self.half_b, "mould_core": self.core}


def _cavity_profile(lay: Layout) -> list[tuple[float, float]]:
    """The bladder outline scaled by ``1 + shrinkage`` about its centre (mould frame), mm."""
    s = 1.0 + lay.cad.mould_shrinkage
    zmid = 0.5 * (lay.z_bladder0 + lay.z_bladder1)
    return [(r * s, (z - zmid) * s) for r, z in bladder_profile(lay)]


def _core_dims(lay: Layout) -> tuple[float, ...]:
    """Core radii and levels: r_in_min (at the beads), r_in, r_max, zc0, zc1, bead length,
    block z0, z1 and the core's bore radius (mould frame), mm."""
    c = lay.cad
    s = 1.0 + c.mould_shrinkage
    prof = _cavity_profile(lay)
    r_in_min = (lay.r_bladder_in - lay.bead_mm) * s  # core at the beads
    r_in = lay.r_bladder_in * s
    r_max = (lay.r_bladder_out + lay.bead_mm) * s
    zc0, zc1 = prof[0][1], prof[6][1]
    lb = lay.bead_length * s
    z0, z1 = zc0 - c.mould_wall_mm, zc1 + c.mould_wall_mm
    r_bore = max(r_in_min - c.mould_core_wall_mm, 0.0)
    return r_in_min, r_in, r_max, zc0, zc1, lb, z0, z1, r_bore


def mould_core_volume_mm3(lay: Layout) -> float:
    """Closed-form volume of the mould core (tube with spigots + the land between the beads).

    Parameters
    ----------
    lay : Layout
        Radii and axial levels of the design, mm (z = 0 under the base).

    Returns
    -------
    float
        Volume, mm³.
    """
    r_in_min, r_in, _, zc0, zc1, lb, z0, z1, r_bore = _core_dims(lay)
    sp = lay.cad.mould_core_spigot_mm
    return (math.pi * (r_in_min**2 - r_bore**2) * (z1 - z0 + 2 * sp)
            + math.pi * (r_in**2 - r_in_min**2) * (zc1 - zc0 - 2 * lb))


def mould(lay: Layout) -> Mould:
    """Build the bladder mould of one layout: two halves, core, sprue, runner, vents, pins.

    Parameters
    ----------
    lay : Layout
        Radii and axial levels of the design, mm (z = 0 under the base).
        The mould's feature sizes come from ``lay.cad`` (shrinkage, walls, sprue, vents, pins).

    Returns
    -------
    Mould
        The halves, core and cavity (mould frame: axis Z centred on z = 0, parting plane y = 0, mm),
        the block limits, the shrinkage (fraction) and where the sprue and vents open (mm).
    """
    c = lay.cad
    prof = _cavity_profile(lay)
    cavity = revolved(prof)
    r_in_min, r_in, r_max, zc0, zc1, lb, z0, z1, r_bore = _core_dims(lay)
    x_half = r_max + c.mould_side_mm
    y_half = r_max + c.mould_wall_mm
    core = fuse(ring(r_bore, r_in_min, z0 - c.mould_core_spigot_mm, z1 + c.mould_core_spigot_mm),
                ring(r_bore, r_in, zc0 + lb, zc1 - lb))
    core_envelope = fuse(cylinder(r_in_min, z0 - 1.0, z1 + 1.0), ring(0.5 * r_in_min, r_in, zc0 + lb, zc1 - lb))
    block = box(-x_half, x_half, -y_half, y_half, z0, z1)
    # sprue on the parting plane, funnel at the top, runner into the lowest point
    xs = r_max + 0.3 * c.mould_side_mm
    funnel = min(c.sprue_funnel_mm, 0.5 * c.mould_side_mm)
    rs, rr = c.sprue_mm / 2, c.runner_mm / 2
    z_run = zc0 + rr
    sprue = [
        cylinder(rs, z_run, z1 + 1.0, x=xs),
        cone(rs, funnel / 2 * 1.2, (xs, 0, z1 - 0.5 * c.mould_wall_mm), (0, 0, 1), 0.6 * c.mould_wall_mm),
        bar(rr, (xs, 0, z_run), (-1, 0, 0), xs - (r_max - 0.2)),
        Solid.make_sphere(rs).moved(Location((xs, 0, z_run))),
    ]
    # the runner's bottom must reach the cavity floor: flatten it with a box below its axis
    sprue.append(box(r_max - 0.2, xs, -rr, rr, zc0, z_run))
    # vents at the top of the upper bead, away from the sprue (angles from 90 deg)
    rv = 0.5 * (r_in_min + r_max)
    vd = min(c.vent_mm, 0.8 * (r_max - r_in_min))
    vents, vent_tops = [], []
    for k in range(c.vents):
        a = math.pi / 2 + math.pi * k / max(c.vents - 1, 1) if c.vents > 1 else math.pi
        p = (rv * math.cos(a), rv * math.sin(a))
        vents.append(cylinder(vd / 2, zc1 - 0.2, z1 + 1.0, x=p[0], y=p[1]))
        vent_tops.append((round(p[0], 6), round(p[1], 6), z1))
    body = cut(block, core_envelope, cavity, *sprue, *vents)
    half_a = single_solid(body.intersect(box(-x_half - 1, x_half + 1, 0, y_half + 1, z0 - 1, z1 + 1)))
    half_b = single_solid(body.intersect(box(-x_half - 1, x_half + 1, -y_half - 1, 0, z0 - 1, z1 + 1)))
    # registration pins on half A (pointing -y), holes in half B
    xp = r_max + 0.75 * c.mould_side_mm
    zl = 0.5 * (z1 - z0) * 0.6
    pins, holes = [], []
    for px in (-xp, xp):
        for pz in (-zl, zl):
            pins.append(bar(c.pin_mm / 2, (px, 0.01, pz), (0, -1, 0), c.pin_length_mm + 0.01))
            holes.append(bar(c.pin_mm / 2 + c.pin_clearance_mm, (px, 0.01, pz), (0, -1, 0), c.pin_length_mm + 0.5))
    half_a = fuse(half_a, *pins)
    half_b = cut(half_b, *holes)
    return Mould(
        half_a=half_a, half_b=half_b, core=core, cavity=cavity,
        block_mm=(-x_half, x_half, -y_half, y_half, z0, z1), shrinkage=c.mould_shrinkage,
        sprue_top_mm=(xs, 0.0, z1), vent_tops_mm=tuple(vent_tops),
    )
