"""The features the design's joint (:mod:`vvea_design.cad.joints`) gives the outer tube, the base and the top cap:
the threads (ISO 261 fine, ISO 965-1 class, drawn at their pitch diameter), the run-out undercuts (DIN 76-1), the
retaining ring's counterbore, plug and groove (DIN 472), the tie rods' holes (ISO 273) and the pieces' new lengths
and shoulders. :mod:`vvea_design.cad.features` calls these for a design with a joint (``Layout.has_joint``); the
sheets draw them as they draw every feature. Model mm, sheet coordinates ``(u, z)``.
"""

from __future__ import annotations

import math

from .drafting import Dim, Leader, fit_tolerance
from .feature_base import SEAL_BORE_FIT, SPIGOT_FIT, TUBE_OD_FIT, Feature, groove_feature, lead_in_feature, symmetric
from .layout import Layout

__all__ = ["outer_tube_joint_features", "base_joint_features", "top_cap_joint_features", "thread_classes"]

#: General tolerance (ISO 2768-m), as :data:`vvea_design.cad.features.GENERAL`.
_GENERAL = "ISO 2768-m"


_feature = Feature
_sym = symmetric


def thread_classes(designation: str) -> tuple[str, str, str]:
    """Split a thread designation ``M56x1.5-5H/5g6g`` into its size and its internal and external classes.

    Parameters
    ----------
    designation : str
        ISO 965-1 designation of the fit.

    Returns
    -------
    tuple of str
        ``(size, internal class, external class)``, e.g. ``("M56x1.5", "5H", "5g6g")``.
    """
    size, _, cls = designation.partition("-")
    internal, _, external = cls.partition("/")
    return size, internal or "6H", external or "6g"


def _thread(key: str, t, internal: bool, side: str, where: str) -> list:
    """A thread (its step at the thread's inner end) and, on the external one, its run-out undercut."""
    size, ci, ce = thread_classes(t.designation)
    cls = ci if internal else ce
    r2, r3 = t.pitch_diameter_mm / 2, t.external_minor_mm / 2
    z_mid = 0.5 * sum(t.thread)
    z_step = t.thread[1] if t.end == "base" else t.thread[0]
    kind = "internal" if internal else "external"
    txt = (f"{where}: {kind} thread {size}-{cls}, engaged length {t.engagement_mm:.2f} (drawn at its pitch "
           f"Ø{2 * r2:.3f}), ISO 261 / ISO 965-1")
    out = [_feature(key, "thread", f"{kind} thread ({where})", size, cls, Leader((r2, z_mid), txt, side),
                    u_edges=_sym(r2), z_edges=(z_step,), standard="ISO 261, ISO 965-1")]
    if internal and t.relief[1] > t.relief[0]:  # the tube's run-out at the minor bore, then the step to the bore
        r1 = t.internal_minor_mm / 2
        run = t.relief[1] - t.relief[0]
        z_run = t.relief[1] if t.end == "base" else t.relief[0]
        txt = (f"{where}: internal thread run-out Ø{2 * r1:.3f} {cls} (D1) x {run:.2f} (DIN 76-1 short); the O-rings "
               "pass it clear of the crests (ISO 3601-2)")
        out.append(_feature(f"{key}_runout", "groove", f"internal thread run-out ({where})", f"Ø{2 * r1:.3f}", cls,
                            Leader((r1, 0.5 * sum(t.relief)), txt, side), u_edges=_sym(r1), z_edges=(z_run,),
                            standard="DIN 76-1"))
    if not internal:
        z_run = t.runout[1] if t.end == "base" else t.runout[0]
        run = t.runout[1] - t.runout[0]
        txt = (f"{where}: thread run-out undercut Ø{2 * r3:.2f} h12 x {run:.2f} (DIN 76-1 short), R0.4 at its "
               "root")
        out.append(_feature(f"{key}_runout", "groove", f"thread run-out ({where})", f"Ø{2 * r3:.2f}", "h12",
                            Leader((-r3, 0.5 * sum(t.runout)), txt, "left"), u_edges=_sym(r3), z_edges=(z_run,),
                            probe=(0.5 * (r2 + r3), 0.0, 0.5 * sum(t.runout)), standard="DIN 76-1"))
    return out


def outer_tube_joint_features(lay: Layout) -> tuple:
    """The outer tube's features with the design's joint: length between its ends, outside diameter, the sealing
    bore, the threaded ends (or the ring's counterbore and groove), the lead-ins the O-rings enter by.

    Parameters
    ----------
    lay : Layout
        Radii and levels of the design, mm (``lay.has_joint``).

    Returns
    -------
    tuple of Feature
        In sheet order.
    """
    j, rb = lay.joint, lay.r_bore
    ro, b0, zs = j.tube_outer_radius_mm, j.z_tube_bottom, j.z_tube_top
    od = f"Ø{2 * ro:.2f}"
    bd = f"Ø{2 * rb:.2f}"
    od_tol, bd_tol = fit_tolerance(2 * ro, TUBE_OD_FIT), fit_tolerance(2 * rb, SEAL_BORE_FIT)
    zm = 0.5 * (lay.z_base_top + lay.z_cap)
    f = [_feature("length", "length", "length", f"{zs - b0:.2f}", _GENERAL, Dim("z", (-ro, b0), (-ro, zs), "left"),
                  z_edges=(b0, zs)),
         _feature("outside", "diameter", "outside diameter", od, od_tol,
                  Dim("u", (-ro, zs), (ro, zs), "top", f"{od} {od_tol}"), u_edges=_sym(ro)),
         _feature("bore", "diameter", "bore (O-ring counter-surface)", bd, bd_tol,
                  Dim("u", (-rb, zm), (rb, zm), "bottom", f"{bd} {bd_tol}"), u_edges=_sym(rb), finish="Ra 0.8",
                  standard="ISO 3601-2"),
         lead_in_feature("lead_in_bottom", "bore, bottom end", lay.lead_in_outer_bottom, rb, lay.z_lead_in_bottom,
                          True, True, "right", lay.base_seal)]
    if j.base_thread is not None:
        f += _thread("thread_bottom", j.base_thread, True, "right", "bottom end")
    if j.cap_thread is not None:
        f += _thread("thread_top", j.cap_thread, True, "right", "top end")
        f.append(lead_in_feature("lead_in_top", "bore, top end", lay.lead_in_outer_top, rb, lay.z_lead_in_top,
                                  True, False, "right", lay.cap_seal))
    elif lay.lead_in_outer_top is not None:  # tie rods: a plain top end; ring_top: the counterbore's step
        f.append(lead_in_feature("lead_in_top", "bore, top end", lay.lead_in_outer_top, rb, lay.z_lead_in_top,
                                  True, False, "right", lay.cap_seal))
    if j.ring is not None:
        r = j.ring
        d1, d2 = r.bore_mm / 2, r.groove_diameter_mm / 2
        cb_tol = fit_tolerance(r.bore_mm, SEAL_BORE_FIT)
        zc = j.cap_seal[1]
        f += [_feature("counterbore", "diameter", "counterbore (the cap plug's seat)", f"Ø{r.bore_mm:.2f}",
                       cb_tol, Leader((d1, 0.5 * (zc + r.plug[1])),
                                      f"counterbore Ø{r.bore_mm:.2f} {cb_tol} x {zs - zc:.2f} deep from the top "
                                      "end (the cap's O-ring passes it clear, ISO 3601-2)", "right"),
                       u_edges=_sym(d1), z_edges=(zc,), standard="ISO 3601-2"),
              _feature("ring_groove", "groove", "retaining ring groove", f"Ø{r.groove_diameter_mm:.2f}", "H13",
                       Leader((d2, 0.5 * sum(r.groove)),
                              f"groove Ø{r.groove_diameter_mm:.2f} H13 x {r.groove_width_mm:.2f} H13, "
                              f"{zs - r.groove[1]:.2f} from the top end, for the ring {r.designation}", "left"),
                       u_edges=_sym(d2), z_edges=r.groove, probe=(0.5 * (d1 + d2), 0.0, 0.5 * sum(r.groove)),
                       standard="DIN 472"),
              lead_in_feature("lead_in_counterbore", "counterbore, top end", lay.lead_in_counterbore, d1, zs, True,
                               False, "right", lay.cap_seal)]
    return tuple(f)


def _rod_holes(lay: Layout, z0: float, z1: float, where: str) -> list:
    """The tie rods' clearance holes through an end piece between ``z0`` and ``z1`` (ISO 273 medium)."""
    r = lay.joint.rods
    if r is None:
        return []
    a = math.radians(r.angles_deg[0])
    angs = ", ".join(f"{v:g}" for v in r.angles_deg)
    txt = (f"{where}: {r.count}x Ø{r.hole_mm:g} through (ISO 273 medium, for {r.designation}) on "
           f"Ø{2 * r.circle_radius_mm:.2f} ±0.1, at {angs}° from the throttle's axis (+x)")
    return [_feature("rod_holes", "hole", "tie rods' holes", f"{r.count}x Ø{r.hole_mm:g}", "ISO 273 medium", txt,
                     probe=(r.circle_radius_mm * math.cos(a), r.circle_radius_mm * math.sin(a), 0.5 * (z0 + z1)),
                     standard="ISO 273")]


def base_joint_features(lay: Layout, feats: tuple) -> tuple:
    """The base's features with the design's joint: its own part's outside and height to the shoulder, the
    spigot's thread and run-out (or the tie rods' holes); the rest as without a joint.

    Parameters
    ----------
    lay : Layout
        Radii and levels of the design, mm (``lay.has_joint``).
    feats : tuple of Feature
        The base's features without the joint.

    Returns
    -------
    tuple of Feature
        In sheet order.
    """
    j, R, rb, z0 = lay.joint, lay.r_outer, lay.r_bore, lay.z_base_top
    b0 = j.z_tube_bottom
    keep = [f for f in feats if f.key not in ("height", "outside")]
    f = [_feature("height", "length", "height (to the spigot's top face)", f"{z0:.2f}", _GENERAL,
                  Dim("z", (-R, 0.0), (-rb, z0), "left"), z_edges=(0.0, z0)),
         _feature("shoulder", "length", "shoulder (the tube's bottom end seats on it)", f"{b0:.2f}", _GENERAL,
                  Dim("z", (R, 0.0), (R, b0), "right"), z_edges=(b0,)),
         _feature("outside", "diameter", "outside diameter", f"Ø{2 * R:.2f}", _GENERAL,
                  Dim("u", (-R, b0), (R, b0), "top", f"Ø{2 * R:.2f}"), u_edges=_sym(R))]
    if j.base_thread is not None:
        f += _thread("thread", j.base_thread, False, "right", "spigot")
    f += _rod_holes(lay, 0.0, b0, "own part")
    return tuple(f + keep)


def top_cap_joint_features(lay: Layout, feats: tuple) -> tuple:
    """The top cap's features with the design's joint: the shoulder part above the tube (or the ring's plug), the
    spigot's length to the shoulder, its thread and run-out, the tie rods' holes; the rest as without a joint.

    Parameters
    ----------
    lay : Layout
        Radii and levels of the design, mm (``lay.has_joint``).
    feats : tuple of Feature
        The top cap's features without the joint.

    Returns
    -------
    tuple of Feature
        In sheet order.
    """
    j, R, z1, zf = lay.joint, lay.r_outer, lay.z_cap, lay.z_cap_face
    keep = [f for f in feats if f.key not in ("thickness", "outside")]
    if j.ring is not None:  # the cap is a plug in the tube's counterbore, its seal zone in the bore below
        r1, rb, zc = j.ring.bore_mm / 2, lay.r_bore, j.cap_seal[1]
        pd, pt = f"Ø{j.ring.bore_mm:.2f}", fit_tolerance(j.ring.bore_mm, SPIGOT_FIT)
        so, so_tol = f"Ø{2 * rb:.2f}", fit_tolerance(2 * rb, SPIGOT_FIT)
        f = [_feature("thickness", "length", "plug length", f"{zf - z1:.2f}", _GENERAL,
                      Dim("z", (-rb, z1), (-r1, zf), "left"), z_edges=(z1, zf)),
             _feature("outside", "diameter", "plug outside (in the tube's counterbore)", pd, pt,
                      Dim("u", (-r1, zf), (r1, zf), "top", f"{pd} {pt}"), u_edges=_sym(r1)),
             _feature("seal_spigot", "diameter", "seal spigot (in the outer-tube bore)", so, so_tol,
                      Leader((rb, 0.5 * (z1 + zc)), f"seal spigot {so} {so_tol} x {zc - z1:.2f}", "right"),
                      u_edges=_sym(rb), z_edges=(zc,))]
        if lay.has_top_annulus:
            f += groove_feature("cap_seal", lay.cap_seal, *lay.z_cap_seal, z1, "the spigot's end", "left", -1.0)
        return tuple(f + keep)
    zs = j.z_tube_top
    f = [_feature("thickness", "length", "thickness above the tube", f"{lay.z_top - zs:.2f}", _GENERAL,
                  Dim("z", (-R, zs), (-R, lay.z_top), "left"), z_edges=(zs, lay.z_top)),
         _feature("spigot_to_shoulder", "length", "spigot from the underside to the shoulder", f"{zs - z1:.2f}",
                  _GENERAL, Dim("z", (-lay.r_inner_tube, z1), (-R, zs), "left"), z_edges=(z1,)),
         _feature("outside", "diameter", "outside diameter", f"Ø{2 * R:.2f}", _GENERAL,
                  Dim("u", (-R, lay.z_top), (R, lay.z_top), "top", f"Ø{2 * R:.2f}"), u_edges=_sym(R))]
    if lay.has_top_annulus:  # the plain cap of annulus_top gets a spigot with its seal from the joint
        rb = lay.r_bore
        so, so_tol = f"Ø{2 * rb:.2f}", fit_tolerance(2 * rb, SPIGOT_FIT)
        f += [_feature("spigot_outside", "diameter", "spigot outside (in the outer-tube bore)", so, so_tol,
                       Dim("u", (-rb, z1), (rb, z1), "bottom", f"{so} {so_tol}"), u_edges=_sym(rb)),
              *groove_feature("cap_seal", lay.cap_seal, *lay.z_cap_seal, z1, "the spigot's end", "left", -1.0)]
    if j.cap_thread is not None:
        f += _thread("thread", j.cap_thread, False, "right", "spigot")
    f += _rod_holes(lay, zs, lay.z_top, "shoulder part")
    return tuple(f + keep)
