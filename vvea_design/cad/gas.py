"""Gas domains at x = 0 as solids: what the optimiser's V1 and V2 look like.

* **Chamber 1** (A1/V1, grows with x): the inner-tube bore above the piston,
  radius ``piston_diameter_mm / 2`` from the piston top to the top cap,
  volume ``A1 * chamber1_length_mm = V1 - fixed.dead_volume_1_mm3``.
* **Chamber 2** (A2/V2, shrinks with x): the annulus between the outer-tube
  bore and the *equal-volume straight sleeve* of radius
  ``design.bladder_equivalent_outer_radius_mm(0)`` over the bladder's free
  length, volume ``V2 - fixed.dead_volume_2_mm3``. The real bladder at x = 0
  is the cast sleeve deflated inwards (and bulging between its clamps); this
  domain has its volume, not its shape, and so overlaps the cast bladder drawing.

In the ``bulkhead`` layout chamber 1 ends at the bulkhead and includes the
fill tube's bore up to the top cap (it is charged through it); chamber 2
also fills the inner-tube bore above the bulkhead, outside the fill tube
(``V2_top_mm3``), so its domain is two solids (joined through the top cap's
ports, which are not drawn). In the ``annulus_top`` layout chamber 1 is the
bore above the piston, the slots in the inner tube's top end and the annulus
above the collar (``V1_annulus_mm3``): one solid. With ``fixed.piston_pocket``
chamber 1 also fills the pocket in the piston crown (every layout). The dead
volumes (ports, default 0) are not drawn.
"""

from __future__ import annotations

from build123d import Compound, Solid

from ._shapes import cylinder, fuse, ring
from .layout import Layout
from .parts import cross_slots

__all__ = ["gas_chamber_1", "gas_chamber_2", "fluid_column"]


def gas_chamber_1(lay: Layout, x_mm: float = 0.0) -> Solid:
    """Chamber-1 gas at displacement ``x_mm`` (the bore above the piston; with a bulkhead, up to it
    plus the fill tube's bore).

    Parameters
    ----------
    lay : Layout
        Radii and axial levels of the design, mm (z = 0 under the base).
    x_mm : float
        Piston displacement, mm (x > 0 extends the spring and moves the piston down, towards the base).

    Returns
    -------
    Solid
        The gas domain in the assembly frame, mm; its volume is ``V1 - dead_volume_1 + A1 x`` (mm³).
    """
    zt = lay.z_piston_top(x_mm)
    pocket = [cylinder(lay.r_pocket, zt - lay.design.piston_pocket_depth_mm, zt + 0.01)] if lay.has_piston_pocket else []
    if lay.has_top_annulus:
        return fuse(cylinder(lay.r_piston, zt, lay.z_cap),
                    ring(lay.r_inner_tube, lay.r_bore, lay.z_collar1, lay.z_cap),
                    *cross_slots(lay, lay.r_piston, lay.r_inner_tube), *pocket)
    if not lay.has_bulkhead:
        column = cylinder(lay.r_piston, zt, lay.z_cap)
        return fuse(column, *pocket) if pocket else column
    return fuse(cylinder(lay.r_piston, zt, lay.z_bulkhead0),
                cylinder(lay.r_fill_tube_bore, lay.z_bulkhead0, lay.z_cap), *pocket)


def gas_chamber_2(lay: Layout, x_mm: float = 0.0) -> Solid:
    """Chamber-2 gas at displacement ``x_mm`` (outside the equal-volume straight sleeve).

    Parameters
    ----------
    lay : Layout
        Radii and axial levels of the design, mm (z = 0 under the base).
    x_mm : float
        Piston displacement, mm (x > 0 extends the spring and moves the piston down, towards the base).

    Returns
    -------
    Solid or Compound
        The gas domain in the assembly frame, mm: the annulus between the equal-volume sleeve and the
        outer-tube bore over the bladder's free length, plus (bulkhead layout with ``V2_top_mm3`` > 0)
        the annulus above the bulkhead outside the fill tube, as a two-solid compound.
    """
    r_in = lay.r_gas2_inner if x_mm == 0 else lay.design.bladder_equivalent_outer_radius_mm(x_mm)
    annulus = ring(r_in, lay.r_bore, lay.z_free0, lay.z_free1)
    if not lay.has_bulkhead or lay.design.V2_top_mm3 <= 0:
        return annulus
    return Compound([annulus, ring(lay.r_fill_tube_out, lay.r_piston, lay.z_bulkhead1, lay.z_cap)])


def fluid_column(lay: Layout, x_mm: float = 0.0) -> Solid:
    """The fluid column at displacement ``x_mm``: the annulus between rod and bore from the base to the piston's
    underside (its channels not drawn). Drawn on the unit's section; not a part of the table.

    Parameters
    ----------
    lay : Layout
        Radii and axial levels of the design, mm (z = 0 under the base).
    x_mm : float
        Piston displacement, mm (x > 0 extends the spring and moves the piston down, towards the base).

    Returns
    -------
    Solid
        The fluid column in the assembly frame, mm; its volume is ``A2`` times the piston's height over the base, mm³.
    """
    return ring(lay.r_rod, lay.r_piston, lay.z_base_top, lay.z_piston_bottom(x_mm))
