"""The features of the inner tube's seats (:mod:`vvea_design.cad.tube_seats`) on the end pieces' and the inner tube's
sheets: the seat's spigot (the O-ring's groove in it, its diameter in the tube's bore), the seat's bore and depth,
the tube's ends and lead-ins, the fill tube's neck and the cap's bore and groove round it. Model mm, sheet frame
(u across the axis, z along it); see :mod:`vvea_design.cad.features`.
"""

from __future__ import annotations

from .drafting import Dim, Leader
from .feature_base import SPIGOT_FIT, Feature, groove_feature, lead_in_feature, symmetric
from .feature_base import fit_text as _fit

__all__ = ["seat_features", "tube_end_features"]


def seat_features(lay, part: str) -> list[Feature]:
    """The seat of the inner tube's end in an end piece (``housing_base`` or ``housing_top_cap``), and in the top cap
    of ``bulkhead`` the fill tube's neck bore with its O-ring groove.

    Parameters
    ----------
    lay : Layout
        Radii and levels of the design, mm.
    part : str
        ``housing_base`` or ``housing_top_cap``.

    Returns
    -------
    list of Feature
        Empty without seats (the gas-only rules) or, in ``annulus_top``, on the top cap.
    """
    s = lay.seats
    if s is None:
        return []
    rp, ri = lay.r_piston, lay.r_inner_tube
    if part == "housing_base":
        g, (g0, g1), z_face, z_end, name = s.base, s.z_base_groove, lay.z_base_top, s.z_base_floor, "base"
    else:
        if s.top is None:
            return []
        g, (g0, g1), z_face, z_end, name = s.top, s.z_top_groove, lay.z_cap, s.z_top_end, "top cap"
    sp, sp_tol = _fit(2 * rp, SPIGOT_FIT)
    sb, sb_tol = _fit(2 * ri, "H9")
    depth = abs(z_end - z_face)
    out = [Feature("seat_spigot", "diameter", "seat spigot (in the inner tube's bore)", sp, sp_tol,
                   Dim("u", (-rp, z_face), (rp, z_face), "inside", f"{sp} {sp_tol} (seat spigot)"),
                   u_edges=symmetric(rp), standard="ISO 286, ISO 3601-2"),
           Feature("seat_bore", "diameter", "seat bore (the inner tube's end)", sb, sb_tol,
                   Leader((ri, 0.5 * (z_face + z_end)), f"inner tube's seat {sb} {sb_tol} x {depth:.2f} deep "
                          f"(the tube's end; floor flat, Ra 1.6)", "right"),
                   u_edges=symmetric(ri), z_edges=(z_end,), probe=(0.0, 0.5 * (rp + ri), 0.5 * (z_face + z_end)),
                   finish="Ra 1.6"),
           *groove_feature("tube_seal", g, g0, g1, z_face, f"the {name}'s face", "left", -1.0)]
    if part == "housing_top_cap" and s.fill is not None:
        rn, f = s.neck_radius_mm, s.fill
        nb, nb_tol = _fit(2 * rn, "H8")
        out += [Feature("neck_bore", "hole", "bore for the fill tube's neck", nb, nb_tol,
                        Leader((rn, s.z_neck_top - 0.3), f"fill tube neck bore {nb} {nb_tol} x "
                               f"{s.z_neck_top - lay.z_cap:.2f} deep, Ra 0.8", "right"),
                        u_edges=symmetric(rn), z_edges=(s.z_neck_top,), finish="Ra 0.8",
                        probe=(0.0, 0.5 * (lay.r_fill_tube_bore + rn), s.z_neck_top - 0.3)),
                *groove_feature("neck_seal", f, *s.z_neck_groove, lay.z_cap, "the cap's underside", "right")]
    return out


def tube_end_features(lay) -> list[Feature]:
    """The inner tube's ends in the seats: the top end's lead-in (the bottom end's is the piston bore's), and in
    ``bulkhead`` the fill tube's neck with its lead-in.

    Parameters
    ----------
    lay : Layout
        Radii and levels of the design, mm.

    Returns
    -------
    list of Feature
        Empty without seats.
    """
    s = lay.seats
    if s is None:
        return []
    out = []
    if s.top is not None:
        out.append(lead_in_feature("lead_in_top", "piston bore, top end", s.lead_in_top, lay.r_piston, s.z_top_end,
                                   True, False, "right", s.top))
    if s.fill is not None:
        rn, z1 = s.neck_radius_mm, lay.z_cap
        nd, nd_tol = _fit(2 * rn, "f7")
        out += [Feature("fill_neck", "diameter", "fill tube's neck (in the top cap)", nd, nd_tol,
                        Leader((-rn, 0.5 * (z1 + s.z_neck_top)), f"neck {nd} {nd_tol} x {s.z_neck_top - z1:.2f} long "
                               f"(O-ring {s.fill.oring.code} seals on it), Ra 0.8", "left"),
                        u_edges=symmetric(rn), z_edges=(z1, s.z_neck_top), finish="Ra 0.8",
                        probe=(0.0, rn + 0.05, 0.5 * (z1 + s.z_neck_top))),
                lead_in_feature("lead_in_neck", "fill tube's neck end", s.lead_in_neck, rn, s.z_neck_top, False, False,
                                "left", s.fill)]
    return out
