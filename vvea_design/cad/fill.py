"""What the unit is filled with: the oil (every space the fluid fills at x = 0, from the drawn geometry) and the
nitrogen charge of each chamber (mass at its charge pressure and 20 °C).

Oil, at x = 0 (piston up): the fluid column under the piston; the inside of the bladder over its free length
(the annulus between the inner tube and the outer-tube bore, less the bladder and the chamber-2 gas, which is
exactly the design's ``V2_annulus_mm3`` at x = 0); the support ring's channels and collector groove; the base's
vertical channels; the relief valve's seat drilling and spring bore; the inner tube's bottom lead-in chamfer.
The rotary throttle's bore holds the bought throttle core; its free volume is the core's and not counted.

Nitrogen: m = p V M / (Z R T) at 20 °C, with the compressibility factor Z of nitrogen from its virial
expansion (second and third virial coefficients at 293.15 K, Dymond and Smith's compilation; Z = 0.995 at
4 MPa, the ideal gas is 0.5 % off). The volume is the design's chamber volume at x = 0 plus the drawn
ports' dead volume (holes the design's V1, V2 leave out unless ``fixed.dead_volume_*`` hold them).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from .layout import Layout

__all__ = ["oil_fill_mm3", "port_dead_volumes_mm3", "n2_density_kg_per_m3", "GasCharge", "gas_charges",
           "T_CHARGE_K", "OIL", "NITROGEN"]

#: Charge temperature, K (20 °C).
T_CHARGE_K = 293.15
#: Molar mass of nitrogen, kg/mol.
M_N2_KG_PER_MOL = 28.0134e-3
#: Second and third virial coefficients of nitrogen at 293.15 K, m³/mol and m⁶/mol².
B_N2, C_N2 = -5.6e-6, 1.4e-9
#: The gas constant, J/(mol K).
R_J_PER_MOL_K = 8.314462618
#: The oil: mineral hydraulic oil, ISO 6743-4 HM, viscosity grade ISO VG 32 (ISO 3448).
OIL = "mineral hydraulic oil ISO 6743-4 HM, ISO VG 32 (ISO 3448)"
#: The charge gas.
NITROGEN = "nitrogen >= 99.99 %, dry (ISO 14175 N1)"


def oil_fill_mm3(lay: Layout) -> dict[str, float]:
    """The oil the unit holds at x = 0, by space, mm³ (sum: ``total``).

    Parameters
    ----------
    lay : Layout
        Radii and levels of the design, mm.

    Returns
    -------
    dict of str to float
        ``column`` (under the piston), ``bladder`` (inside the bladder's free length), ``ring_channels``
        (support ring: channels and collector groove), ``base_channels`` (the four vertical channels),
        ``relief_bore`` (seat drilling and spring bore up to the adjusting thread), ``lead_in`` (the inner tube's
        bottom chamfer) and ``total``, mm³.
    """
    from .bladder import _collector_depth
    from .features import relief_thread_depth
    from .parts import lead_in_ring_mm3, tube_bottom_lead_in

    d, c = lay.design, lay.cad
    z0, zv = lay.z_base_top, lay.z_valve
    free = lay.z_free1 - lay.z_free0
    bladder = math.pi * (lay.r_bore**2 - lay.r_inner_tube**2) * free \
        - math.pi * (lay.r_bladder_out**2 - lay.r_bladder_in**2) * free - d.V2_annulus_mm3
    h, hg, dc, rc = lay.z_free0 - z0, _collector_depth(lay), lay.ring_channel_d, lay.r_ring_channel
    ring = lay.ring_channels * math.pi * (dc / 2) ** 2 * (h - hg) + math.pi * ((rc + 0.6 * dc) ** 2 - (rc - 0.6 * dc) ** 2) * hg
    ch, rch = lay.base_channel_d / 2, min(lay.base_channel_d, lay.ring_channel_d) / 2
    channels = 2 * math.pi * (ch**2 + rch**2) * (z0 - zv)  # from the valve axis up (half the bore's cross-section
    # below the axis is the bore's own)
    x_b = lay.r_ring_channel - lay.ring_channel_d / 2 - 0.5
    seat = lay.relief_seat_d / 2
    spring_len = max(lay.r_outer - relief_thread_depth(lay) - x_b, 0.0)
    relief = math.pi * seat**2 * (x_b - lay.x_valve_inner) + math.pi * (lay.relief_d / 2) ** 2 * spring_len
    li, _ = tube_bottom_lead_in(lay)
    out = {"column": d.A2_mm2 * d.fluid_column_mm, "bladder": bladder, "ring_channels": ring,
           "base_channels": channels, "relief_bore": relief,
           "lead_in": lead_in_ring_mm3(lay.r_piston, li.depth_mm, li.length_mm, outward=True)}
    out["total"] = sum(out.values())
    return out


def port_dead_volumes_mm3(lay: Layout) -> dict[str, float]:
    """Gas the drawn ports hold below the charging valves (tapped holes, ports, riser, cross port), by chamber,
    mm³: dead volume the design's ``V1_mm3``, ``V2_mm3`` include only through ``fixed.dead_volume_*_mm3``.

    Parameters
    ----------
    lay : Layout
        Radii and levels of the design, mm.

    Returns
    -------
    dict of str to float
        ``chamber_1`` and ``chamber_2``, mm³ (the valves' threads are taken as filled by the valves).
    """
    c = lay.cad
    a = lambda dia: math.pi * (dia / 2) ** 2  # noqa: E731 - area of a drilling, mm²
    below_valve = lay.design.top_cap_mm - c.fill_port_counterbore_depth_mm
    if lay.has_bulkhead:
        v1 = a(2 * lay.r_fill_tube_bore) * below_valve  # the fill tube's bore below the cap is chamber 1's own
    else:
        v1 = a(lay.fill_port_d) * below_valve
    if lay.has_top_annulus:
        v2 = a(lay.fill_port_d) * (lay.z_free0 - c.fill_port_counterbore_depth_mm)
    elif not lay.has_cross_port:
        v2 = a(lay.fill_port_d) * (lay.z_top - c.fill_port_counterbore_depth_mm - lay.z_free1)
    else:
        zc, dc = lay.z_cross_port, lay.cross_port_d
        v2 = a(lay.fill_port_d) * (zc - lay.z_free1) + a(dc) * (lay.r_outer - c.plug_depth_mm - lay.y_valve2)
        v2 += a(dc) * (lay.z_top - c.fill_port_counterbore_depth_mm - (lay.z_cap if lay.has_bulkhead else zc))
    return {"chamber_1": v1, "chamber_2": v2}


def n2_density_kg_per_m3(p_MPa: float, T_K: float = T_CHARGE_K) -> float:
    """Density of nitrogen from its virial expansion Z = 1 + B/Vm + C/Vm² (coefficients at 293.15 K).

    Parameters
    ----------
    p_MPa : float
        Absolute pressure, MPa (0 ... ~20; the virial series is good to a few 0.1 % there).
    T_K : float
        Temperature, K (the coefficients are the 293.15 K ones; keep it near 20 °C).

    Returns
    -------
    float
        Density, kg/m³.

    Raises
    ------
    ValueError
        For a negative pressure or a temperature far from 20 °C.
    """
    if p_MPa < 0 or not 273.0 <= T_K <= 313.0:
        raise ValueError(f"n2_density_kg_per_m3: p_MPa must be >= 0 and T_K 273...313 K, got {p_MPa}, {T_K}")
    p = p_MPa * 1e6
    vm = R_J_PER_MOL_K * T_K / p if p > 0 else math.inf
    for _ in range(50):  # fixed point on Vm = Z R T / p
        z = 1 + B_N2 / vm + C_N2 / vm**2
        vm_new = z * R_J_PER_MOL_K * T_K / p
        if abs(vm_new - vm) < 1e-15:
            break
        vm = vm_new
    return M_N2_KG_PER_MOL / vm if p > 0 else 0.0


@dataclass(frozen=True)
class GasCharge:
    """One chamber's nitrogen charge: pressure (MPa, absolute), volume (mm³) and mass (g) at 20 °C."""

    chamber: str
    pressure_MPa: float
    volume_mm3: float  #: the design's chamber volume at x = 0 plus the drawn ports' dead volume
    dead_volume_mm3: float  #: of which in the drawn ports
    mass_g: float

    def to_dict(self) -> dict:
        """JSON-ready content.

        Returns
        -------
        dict
            ``chamber``, ``pressure_MPa``, ``volume_mm3``, ``dead_volume_mm3`` and ``mass_g``.
        """
        return {"chamber": self.chamber, "pressure_MPa": self.pressure_MPa, "volume_mm3": self.volume_mm3,
                "dead_volume_mm3": self.dead_volume_mm3, "mass_g": self.mass_g}


def gas_charges(lay: Layout) -> tuple[GasCharge, GasCharge]:
    """The nitrogen charges of chambers 1 and 2 at x = 0 and 20 °C.

    Parameters
    ----------
    lay : Layout
        The design's layout (charge pressures, chamber volumes, ports).

    Returns
    -------
    tuple of GasCharge
        Chamber 1 (at ``p1``) and chamber 2 (at ``p2``).
    """
    d = lay.design
    dead = port_dead_volumes_mm3(lay)
    out = []
    for name, p, v in (("chamber_1", d.p1_MPa, d.V1_mm3), ("chamber_2", d.p2_MPa, d.V2_mm3)):
        vol = v + dead[name]
        out.append(GasCharge(name, p, vol, dead[name], n2_density_kg_per_m3(p) * vol * 1e-9 * 1e3))
    return out[0], out[1]
