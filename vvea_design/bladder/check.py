"""The bladder check: strain of the silicone sleeve over the stroke, and its radial room.

The bladder is a silicone sleeve cast as a straight cylinder (mid radius
``R``, wall ``H``) and clamped at both ends, a free length ``L`` apart, in the
annulus between the inner tube and the outer-tube bore (see
:mod:`vvea_design.spring.design`). The piston pushes fluid into it and draws it
out again; relative to the cast shape the fluid volume changes by
``design.bladder_volume_change_mm3`` = {"compressed" (x = 0, < 0),
"expanded" (x = travel, > 0)}.

For each stroke end :func:`check_membrane` solves the axisymmetric
hyperelastic membrane (:mod:`vvea_design.bladder.membrane`) at that prescribed
volume change, with the tension-field relaxation where the sleeve wrinkles,
and reports

* the largest tensile principal strain of the membrane (wrinkles relaxed),
* the pressure difference that holds the shape (fluid minus gas),
* where the membrane is wrinkled or slack,
* the radial gaps to the inner tube and the outer bore (the FE has no
  contact: a negative gap means the bladder would touch, and the strain
  beyond that point is not physical),
* a **bending bound** at the clamped ends. The membrane meets the clamp at
  an angle ``dphi`` to the axis; the real wall is built in, so it turns
  through ``dphi`` in a boundary layer whose decay rate ``s`` solves
  ``D s^4 - T s^2 + (E h / R^2) = 0`` (a tensioned cylindrical shell:
  bending stiffness ``D = mu h^3 / 3`` for an incompressible sheet,
  meridional tension ``T``, hoop stiffness ``E h / R^2 = 3 mu h / R^2``).
  Every root has ``|s|^2 <= T / D + 2 beta^2`` with ``beta^4 = 2.25 / (R h)^2``,
  so the surface bending strain is bounded by
  ``eps_b = (h / 2) dphi sqrt(T / D + 2 beta^2)``. The strain bound of a stroke end
  is ``max(max membrane strain, clamp meridional strain + eps_b)``.

:func:`strain_bound` is the same check on a coarser mesh, for the
optimiser: two coarse meshes (48 and 24 elements), Richardson-extrapolated
and multiplied by :data:`SURROGATE_FACTOR`; about 0.1 s per design after
the first call (``studies/bench_bladder.py``). The tests check it stays above
the fine check.

Units: mm, mm³, MPa; strains are engineering strains as fractions.
"""

from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np

from .membrane import (
    TAUT,
    MembraneError,
    MembraneSolution,
    MooneyRivlin,
    sleeve_meridian,
    solve_volume,
)
from ..materials.silicones import Silicone, StrainCriterion, get_criterion, get_silicone
from ..messages import show
from ..plausibility import LIMITS
from .result import DEFAULT_ELEMENTS, ENDS, BladderReport, BladderResult, StrokeEnd

__all__ = [
    "BladderError",
    "BladderResult",
    "BladderReport",
    "StrokeEnd",
    "check_membrane",
    "check_bladder",
    "strain_bound",
    "write_bladder_report",
    "plot_bladder",
    "bending_strain",
    "DEFAULT_MATERIAL",
    "DEFAULT_ELEMENTS",
    "SURROGATE_ELEMENTS",
    "SURROGATE_FACTOR",
    "PAPER_BLADDER",
]

DEFAULT_MATERIAL = "dragon-skin-20"
SURROGATE_ELEMENTS = 48  #: elements of the fast :func:`strain_bound` (Richardson with half as many)
SURROGATE_FACTOR = 1.05  #: safety factor of the fast bound over its extrapolated coarse meshes

#: The paper's bladder, reconstructed (docs/bladder.md gives the reasoning): 59.5 mm housing with
#: 1.5 mm walls (bore radius 28.25 mm), 30 mm piston in a 1.5 mm inner tube (16.5 mm), 132.5 mm
#: long with 8 + 14 mm end caps and 5 mm clamps (free length 100.5 mm), 1.5 mm wall cast at
#: mid-stroke with the chamber-2 gas of mid-stroke (V2 = 73 400 mm³ at x = 0 minus half the
#: stroke, about 59 300 mm³) outside it; full stroke pi/4 30² 40 = 28 274 mm³, split evenly.
PAPER_BLADDER = {
    "inner_tube_outer_radius_mm": 16.5,
    "outer_bore_radius_mm": 28.25,
    "free_length_mm": 100.5,
    "thickness_mm": 1.5,
    "mid_radius_mm": round(math.sqrt(28.25**2 - (73400.0 - math.pi / 8 * 30**2 * 40) / (math.pi * 100.5)) - 0.75, 3),
    "stroke_volume_mm3": math.pi / 4 * 30**2 * 40,
}


class BladderError(ValueError):
    """A bladder that cannot be checked: bad dimensions, unknown material, a volume change it cannot take."""


# -------------------------------------------------------------------- checks
def _positive(name: str, v) -> float:
    if isinstance(v, bool) or not isinstance(v, (int, float, np.floating)) or not math.isfinite(v) or v <= 0:
        raise BladderError(f"{name} must be a positive number, got {show(v)}")
    return float(v)


def bending_strain(solution: MembraneSolution, end: int) -> tuple[float, float]:
    """Bending bound at a clamped end (``end`` 0 = first node, -1 = last).

    Parameters
    ----------
    solution : MembraneSolution
        A solved membrane (:func:`vvea_design.bladder.membrane.solve_volume`): deformed meridian
        (mm), element thickness (mm), meridional tension (N/mm) and stretches.
    end : int
        Which clamp: 0 the first node (lower clamp), -1 the last (upper clamp).

    Returns
    -------
    bending_strain : float
        ``(h/2) dphi sqrt(T/D + 2 beta^2)``, fraction.
    clamp_strain : float
        That plus the tensile meridional membrane strain at the clamp, fraction.
        Angle, tension, thickness and strain are extrapolated from the first
        two elements to the clamp node (linearly in arc length).
    """
    ref = solution.meridian
    f = solution.fields
    r, z = solution.r_mm, solution.z_mm
    # angle to the clamp direction (the reference meridian there) of the first two elements, extrapolated
    # linearly in arc length to the clamp node: O(h^2), where the first chord alone is O(h)
    idx = [0, 1, 2] if end == 0 else [-1, -2, -3]
    tR, tZ = ref.r_mm[idx[1]] - ref.r_mm[idx[0]], ref.z_mm[idx[1]] - ref.z_mm[idx[0]]
    ang, s_mid, s = [], [], 0.0
    for a, b in ((idx[0], idx[1]), (idx[1], idx[2])):
        dr, dz = r[b] - r[a], z[b] - z[a]
        ang.append(math.atan2(tR * dz - tZ * dr, tR * dr + tZ * dz))
        ds = math.hypot(dr, dz)
        s_mid.append(s + ds / 2)
        s += ds
    w = s_mid[0] / (s_mid[1] - s_mid[0])

    def at_clamp(v0: float, v1: float) -> float:
        return v0 - (v1 - v0) * w

    e0, e1 = (0, 1) if end == 0 else (ref.n_elements - 1, ref.n_elements - 2)
    dphi = abs(at_clamp(*ang))
    h = at_clamp(float(f["thickness_mm"][e0]), float(f["thickness_mm"][e1]))
    mu = solution.material.shear_modulus_MPa
    D = mu * h**3 / 3.0
    T = max(at_clamp(float(f["T1_N_per_mm"][e0]), float(f["T1_N_per_mm"][e1])), 0.0)
    R = float(r[idx[0]])
    beta2 = 1.5 / (R * h)
    eps_b = 0.5 * h * dphi * math.sqrt(T / D + 2 * beta2)
    eps_m = max(at_clamp(float(f["l1_eff"][e0]), float(f["l1_eff"][e1])) - 1.0, 0.0)
    return eps_b, eps_m + eps_b


def _slack_intervals(ref_z: np.ndarray, state: np.ndarray) -> list[list[float]]:
    out: list[list[float]] = []
    for e, s in enumerate(state):
        if s == TAUT:
            continue
        z0, z1 = float(ref_z[e]), float(ref_z[e + 1])
        if out and abs(out[-1][1] - z0) < 1e-9:
            out[-1][1] = z1
        else:
            out.append([z0, z1])
    return [[round(a, 3), round(b, 3)] for a, b in out]


def _stroke_end(sol: MembraneSolution, r_in: float | None, r_out: float | None) -> StrokeEnd:
    f = sol.fields
    b0, c0 = bending_strain(sol, 0)
    b1, c1 = bending_strain(sol, -1)
    geo = min(float(np.min(f["l1"])), float(np.min(f["l2"]))) - 1.0
    # node thickness: mean of the adjacent elements
    h = f["thickness_mm"]
    hn = np.concatenate([[h[0]], 0.5 * (h[1:] + h[:-1]), [h[-1]]])
    gap_in = float(np.min(sol.r_mm - hn / 2) - r_in) if r_in is not None else None
    gap_out = float(r_out - np.max(sol.r_mm + hn / 2)) if r_out is not None else None
    mps = sol.max_principal_strain
    return StrokeEnd(
        solution=sol,
        max_principal_strain=mps,
        min_geometric_strain=geo,
        bending_strain=max(b0, b1),
        clamp_strain=max(c0, c1),
        strain_bound=max(mps, c0, c1),
        wrinkled_fraction=sol.wrinkled_fraction,
        slack_z_mm=_slack_intervals(sol.meridian.z_mm, sol.state),
        gap_inner_tube_mm=gap_in,
        gap_outer_bore_mm=gap_out,
    )


def check_membrane(mid_radius_mm: float, free_length_mm: float, thickness_mm: float,
                   volume_change_mm3: dict, material: str | Silicone = DEFAULT_MATERIAL,
                   criterion: str | StrainCriterion | float | None = None, *,
                   inner_tube_outer_radius_mm: float | None = None, outer_bore_radius_mm: float | None = None,
                   n_elements: int = DEFAULT_ELEMENTS, relaxed: bool = True) -> BladderResult:
    """Check a clamped sleeve from plain numbers (the design-free core of :func:`check_bladder`).

    Parameters
    ----------
    mid_radius_mm, free_length_mm, thickness_mm : float
        Cast sleeve: mid-surface radius, length between the clamps, wall, mm.
    volume_change_mm3 : dict
        ``{"expanded": dV >= 0, "compressed": dV <= 0}`` — fluid volume
        relative to the cast shape at the two stroke ends, mm³.
    material : str or Silicone
        Key of :data:`vvea_design.materials.silicones.SILICONES` or a :class:`Silicone`.
    criterion : str, StrainCriterion, float or None
        Allowable-strain criterion (``None`` = ``"cyclic"``), or the allowable
        strain itself as a fraction.
    inner_tube_outer_radius_mm, outer_bore_radius_mm : float, optional
        Radial room; when given, volume changes that would push the sleeve
        through them are refused and the gaps are reported.
    n_elements : int
        Elements along the meridian.
    relaxed : bool
        Tension-field relaxation (wrinkling); ``False`` only for comparisons.

    Returns
    -------
    BladderResult
        Both stroke ends (strains as fractions, pressure in MPa, gaps in mm), the allowable strain
        (fraction) and the verdicts.

    Raises
    ------
    BladderError
        Non-positive dimensions, unknown material or criterion, a volume
        change of the wrong sign or one the sleeve cannot take.
    """
    from ..materials.silicones import allowable_strain

    LIMITS["bladder_elements"].check(n_elements, "n_elements", BladderError)
    R = _positive("mid_radius_mm", mid_radius_mm)
    L = _positive("free_length_mm", free_length_mm)
    H = _positive("thickness_mm", thickness_mm)
    if H >= R:
        raise BladderError(f"thickness_mm ({H:g}) must be smaller than mid_radius_mm ({R:g})")
    try:
        sil = get_silicone(material)
        numeric = isinstance(criterion, (int, float)) and not isinstance(criterion, bool)
        crit = None if numeric else get_criterion(criterion)
        allow = allowable_strain(sil, criterion)
    except ValueError as exc:
        raise BladderError(str(exc)) from None
    if not isinstance(volume_change_mm3, dict) or set(volume_change_mm3) != set(ENDS):
        raise BladderError(f"volume_change_mm3 must be a dict with keys {ENDS}, got {volume_change_mm3!r}")
    dv = {k: float(volume_change_mm3[k]) for k in ENDS}
    for k, v in dv.items():
        if not math.isfinite(v):
            raise BladderError(f"volume_change_mm3[{k!r}] must be finite, got {show(v)}")
    if dv["expanded"] < 0:
        raise BladderError(f"volume_change_mm3['expanded'] must be >= 0 (fluid in), got {dv['expanded']:g}")
    if dv["compressed"] > 0:
        raise BladderError(f"volume_change_mm3['compressed'] must be <= 0 (fluid out), got {dv['compressed']:g}")
    r_in = None if inner_tube_outer_radius_mm is None else _positive("inner_tube_outer_radius_mm", inner_tube_outer_radius_mm)
    r_out = None if outer_bore_radius_mm is None else _positive("outer_bore_radius_mm", outer_bore_radius_mm)
    # the fluid can at most empty the space between tube and sleeve, the gas the space outside it
    fluid_max = math.pi * (R**2 - (r_in or 0.0) ** 2) * L
    if r_in is not None and R - H / 2 <= r_in:
        raise BladderError(f"the sleeve (inner radius {R - H / 2:.3f} mm) does not clear the inner tube "
                           f"(outer radius {r_in:.3f} mm)")
    if -dv["compressed"] >= fluid_max:
        raise BladderError(
            f"volume_change_mm3['compressed'] = {dv['compressed']:.0f} mm³: the sleeve cannot give up more than "
            f"the {fluid_max:.0f} mm³ it encloses{' above the inner tube' if r_in else ''}")
    if r_out is not None:
        if R + H / 2 >= r_out:
            raise BladderError(f"the sleeve (outer radius {R + H / 2:.3f} mm) does not fit the bore "
                               f"(radius {r_out:.3f} mm)")
        gas_max = math.pi * (r_out**2 - R**2) * L
        if dv["expanded"] >= gas_max:
            raise BladderError(
                f"volume_change_mm3['expanded'] = {dv['expanded']:.0f} mm³: the sleeve cannot take more than the "
                f"{gas_max:.0f} mm³ between it and the bore")
    try:
        mat = MooneyRivlin.neo_hookean(sil.shear_modulus_MPa)
        ref = sleeve_meridian(R, L, H, int(n_elements))
        ends = {}
        for k in ENDS:
            sol = solve_volume(ref, mat, dv[k], relaxed=relaxed)
            ends[k] = _stroke_end(sol, r_in, r_out)
    except MembraneError as exc:
        raise BladderError(str(exc)) from None
    key = material if isinstance(material, str) else sil.name
    return BladderResult(R, L, H, key, sil, crit, allow, dv, ends, r_in, r_out, int(n_elements))


def _design_sleeve(design) -> dict:
    """Sleeve numbers of a :class:`~vvea_design.spring.design.Design`, with checks naming the design field."""
    f = design.fixed
    L = design.bladder_free_length_mm
    if not L > 0:
        raise BladderError(f"bladder_free_length_mm is {L:.3f} mm: the clamps (fixed.bladder_clamp_mm) take the "
                           f"whole inner length; increase V1_mm3")
    if design.bladder_inner_radius_mm <= design.inner_tube_outer_radius_mm:
        raise BladderError(
            f"V2_mm3 ({design.V2_mm3:.0f}) leaves no room for the cast bladder: its inner radius "
            f"{design.bladder_inner_radius_mm:.3f} mm is inside the inner tube ({design.inner_tube_outer_radius_mm:.3f} mm)")
    if design.bladder_outer_radius_mm >= design.outer_bore_radius_mm:
        raise BladderError(
            f"V2_mm3 ({design.V2_mm3:.0f}) is too small: the cast bladder (outer radius "
            f"{design.bladder_outer_radius_mm:.3f} mm) does not fit the bore ({design.outer_bore_radius_mm:.3f} mm)")
    return dict(mid_radius_mm=design.bladder_mid_radius_mm, free_length_mm=L, thickness_mm=f.bladder_thickness_mm,
                volume_change_mm3=dict(design.bladder_volume_change_mm3),
                inner_tube_outer_radius_mm=design.inner_tube_outer_radius_mm,
                outer_bore_radius_mm=design.outer_bore_radius_mm)


def check_bladder(design, material: str | Silicone = DEFAULT_MATERIAL,
                  criterion: str | StrainCriterion | float | None = None, *,
                  n_elements: int = DEFAULT_ELEMENTS) -> BladderResult:
    """Check the bladder of ``design`` over its stroke (FE membrane at both stroke ends).

    Parameters
    ----------
    design : vvea_design.spring.design.Design
        The design whose cast bladder (mid radius, free length, wall, mm) and stroke volume changes
        (mm³) are checked, in the room between its inner tube and outer bore.
    material : str or Silicone
        Casting silicone: a key of :data:`vvea_design.materials.silicones.SILICONES` (default
        ``"dragon-skin-20"``) or a :class:`Silicone` (shear modulus in MPa).
    criterion : str, StrainCriterion, float or None
        Allowable-strain criterion of the silicone (None = ``"cyclic"``), or the allowable strain
        itself as a fraction.
    n_elements : int
        Elements along the meridian (96: the strain bound within ~0.2 % of its converged value).

    Returns
    -------
    BladderResult
        ``to_dict()`` gives the ``bladder.json`` content. About 0.1-0.7 s per
        design (the first call in a process builds the solvers, ~0.5 s more).

    Raises
    ------
    BladderError
        A design whose bladder does not fit, an unknown material or
        criterion, a stroke the sleeve cannot take.
    """
    return check_membrane(**_design_sleeve(design), material=material, criterion=criterion, n_elements=n_elements)


def strain_bound(design, material: str | Silicone = DEFAULT_MATERIAL, *,
                 n_elements: int = SURROGATE_ELEMENTS) -> float:
    """Fast strain bound of ``design``'s bladder for the optimiser (fraction).

    The check of :func:`check_bladder` on two coarse meshes (``n_elements``
    and half as many), Richardson-extrapolated for its O(h^2) convergence,
    times :data:`SURROGATE_FACTOR`. The tests and the verification study
    check it stays above the fine check. About 0.1 s per call on this
    machine (up to 0.6 s for a very long, nearly slack sleeve; the first
    call in a process builds the solvers, ~0.5 s more).
    Returns ``inf`` for a design whose bladder cannot take the stroke at
    all, so that an optimiser sees an infeasible point rather than an
    exception.

    Parameters
    ----------
    design : vvea_design.spring.design.Design
        The design whose cast bladder (mid radius, free length, wall, mm) and stroke volume changes
        (mm³) are checked, in the room between its inner tube and outer bore.
    material : str or Silicone
        Casting silicone: a key of :data:`vvea_design.materials.silicones.SILICONES` (default
        ``"dragon-skin-20"``) or a :class:`Silicone` (shear modulus in MPa).
    n_elements : int
        Elements of the finer of the two meshes (at least 8; the coarser has half as many).

    Returns
    -------
    float
        Strain bound (membrane and clamp bending, both stroke ends), fraction; ``inf`` when the
        bladder does not fit or cannot take the stroke.
    """
    n = max(int(n_elements), 8)
    try:
        sleeve = _design_sleeve(design)
    except BladderError:
        return math.inf
    key = _strain_key(sleeve, material, n)
    if key is not None and key in _STRAIN_BOUNDS:
        return _STRAIN_BOUNDS[key]
    try:
        fine = check_membrane(**sleeve, material=material, criterion=1.0, n_elements=n).strain_bound
        coarse = check_membrane(**sleeve, material=material, criterion=1.0, n_elements=n // 2).strain_bound
    except BladderError:
        value = math.inf
    else:
        value = SURROGATE_FACTOR * max(fine + (fine - coarse) / 3.0, fine)
    if key is not None:
        if len(_STRAIN_BOUNDS) >= 512:  # bounded: forget the oldest
            del _STRAIN_BOUNDS[next(iter(_STRAIN_BOUNDS))]
        _STRAIN_BOUNDS[key] = value
    return value


#: strain_bound's values by sleeve, material and mesh (a pure function of them: the same sleeve is not solved
#: again, e.g. the optimiser's final check and a caller's check of the returned design)
_STRAIN_BOUNDS: dict = {}


def _strain_key(sleeve: dict, material, n: int):
    key = tuple((k, tuple(sorted(v.items())) if isinstance(v, dict) else v) for k, v in sorted(sleeve.items()))
    try:
        hash(material)
    except TypeError:
        return None
    return key, material, n


# -------------------------------------------------------------------- report
def _surfaces(sol: MembraneSolution) -> tuple[np.ndarray, np.ndarray]:
    """Inner and outer wall surfaces (r, z) of the deformed membrane: the mid-surface offset by
    -/+ half the deformed thickness along its normal, mm."""
    pts = np.column_stack([sol.r_mm, sol.z_mm])
    h = np.asarray(sol.fields.get("thickness_mm", np.full(len(pts) - 1, sol.meridian.thickness_mm)), dtype=float)
    hn = np.concatenate([[h[0]], 0.5 * (h[1:] + h[:-1]), [h[-1]]])
    t = np.gradient(pts, axis=0)
    t /= np.maximum(np.linalg.norm(t, axis=1, keepdims=True), 1e-300)
    n = np.column_stack([t[:, 1], -t[:, 0]])  # points to +r for a meridian running up in z
    n *= np.sign(n[:, :1] + 1e-300)
    return pts - 0.5 * hn[:, None] * n, pts + 0.5 * hn[:, None] * n


def plot_bladder(result: BladderResult, fig=None, title: str = ""):
    """The bladder at both stroke ends and its strain against the allowable, with the verdict.

    Left two panels: the deformed wall (both surfaces, so the drawn gap is the
    reported one) coloured by the element's max principal strain, the cast
    wall dashed, the inner tube and the outer bore, the smallest gap marked.
    Right panel: max principal strain along the wall at both ends, the clamp
    strain bound and the allowable strain; the title gives PASS or FAIL.

    Parameters
    ----------
    result : BladderResult
        The check.
    fig : matplotlib.figure.Figure, optional
        Figure to draw into (a new 12 x 6.5 in one by default).
    title : str
        Prefix of the figure title.

    Returns
    -------
    matplotlib.figure.Figure
        Not saved (no backend is selected here).
    """
    import matplotlib
    from matplotlib.collections import PolyCollection
    from matplotlib.figure import Figure

    if fig is None:
        fig = Figure(figsize=(12, 6.5))
    axes = fig.subplots(1, 3, gridspec_kw={"width_ratios": [1, 1, 1.15]})
    # A figure handed in with its own layout engine keeps it; else the panels are placed at the end
    fixed = fig.get_layout_engine() is None
    cax = fig.add_axes([0.0, 0.0, 1.0, 1.0]) if fixed else None  # the colour bar's, placed at the end
    strains = [result.ends[k].solution.element_max_principal_strain for k in ENDS]
    vmax = max(max(float(s.max()) for s in strains), result.allowable_strain, 1e-6)
    norm = matplotlib.colors.Normalize(0.0, vmax)
    cmap = matplotlib.colormaps["viridis"]
    r_it, r_bo = result.inner_tube_outer_radius_mm, result.outer_bore_radius_mm
    pc = None
    for ax, k in zip(axes[:2], ENDS):
        e = result.ends[k]
        sol = e.solution
        ref = sol.meridian
        inner, outer = _surfaces(sol)
        quads = [np.array([inner[i], inner[i + 1], outer[i + 1], outer[i]]) for i in range(len(inner) - 1)]
        pc = PolyCollection(quads, array=sol.element_max_principal_strain, cmap=cmap, norm=norm,
                            edgecolors="face", linewidths=0.2)
        ax.add_collection(pc)
        ax.plot(inner[:, 0], inner[:, 1], color="black", lw=0.6)
        ax.plot(outer[:, 0], outer[:, 1], color="black", lw=0.6)
        t0 = ref.thickness_mm
        for sgn in (-1, 1):
            ax.plot(ref.r_mm + sgn * t0 / 2, ref.z_mm, "--", color="0.45", lw=0.8,
                    label="cast wall" if sgn < 0 else None)
        z0, z1 = float(min(ref.z_mm.min(), sol.z_mm.min())), float(max(ref.z_mm.max(), sol.z_mm.max()))
        lo = min(r_it if r_it is not None else inner[:, 0].min(), inner[:, 0].min()) - 1.0
        hi = max(r_bo if r_bo is not None else outer[:, 0].max(), outer[:, 0].max()) + 1.0
        if r_it is not None:
            ax.axvspan(lo, r_it, color="0.75", label="inner tube")
        if r_bo is not None:
            ax.axvspan(r_bo, hi, color="0.55", label="outer tube")
        wr = sol.state != TAUT
        if np.any(wr):
            mid = 0.5 * (sol.r_mm[:-1] + sol.r_mm[1:]), 0.5 * (sol.z_mm[:-1] + sol.z_mm[1:])
            every = np.zeros(wr.size, bool)
            every[:: max(1, wr.size // 25)] = True
            sel = wr & every
            ax.plot(mid[0][sel], mid[1][sel], "x", color="tab:red", ms=4, label="wrinkled / slack")
        # smallest gaps, drawn where they occur
        for gap, rad, surf in ((e.gap_inner_tube_mm, r_it, inner), (e.gap_outer_bore_mm, r_bo, outer)):
            if gap is None or rad is None:
                continue
            i = int(np.argmin(np.abs(surf[:, 0] - rad)))
            ax.annotate("", (rad, surf[i, 1]), (surf[i, 0], surf[i, 1]),
                        arrowprops=dict(arrowstyle="<->", color="tab:red", lw=1.0, shrinkA=0, shrinkB=0))
            ax.annotate(f"gap {gap:.2f} mm", (0.5 * (rad + surf[i, 0]), surf[i, 1]),
                        xytext=(0, -14 if surf[i, 1] > 0.5 * (z0 + z1) else 14), textcoords="offset points",
                        ha="center", va="center",
                        fontsize=8, color="tab:red", bbox=dict(facecolor="white", edgecolor="none", pad=0.5))
        touch = [n for n, t in e.touches.items() if t]
        ax.set_title(f"{k} (x = {'travel' if k == 'expanded' else '0'}): dV = {result.volume_change_mm3[k]:+.0f} mm³\n"
                     f"Δp = {e.pressure_MPa:+.3g} MPa, bound {100 * e.strain_bound:.1f} %"
                     + (f"\nTOUCHES {', '.join(touch)}" if touch else ""), fontsize=9, y=1.0)
        ax.set_xlim(lo, hi)
        ax.set_ylim(z0 - 1.0, z1 + 1.0)
        ax.set_xlabel("radius r (mm; radial scale exaggerated)")
        ax.legend(fontsize=7, loc="upper center", bbox_to_anchor=(0.5, -0.12), ncol=2, frameon=False)
    axes[0].set_ylabel("axial position z from the lower clamp (mm)")
    axes[1].sharey(axes[0])
    if fixed:
        fig.colorbar(pc, cax=cax, label="max principal strain (-)", orientation="horizontal")
    else:
        fig.colorbar(pc, ax=axes[:2], label="max principal strain (-)", location="bottom", shrink=0.6)
    # strain along the wall against the allowable
    ax = axes[2]
    for k, style in zip(ENDS, ("-", "--")):
        e = result.ends[k]
        sol = e.solution
        zm = 0.5 * (sol.meridian.z_mm[:-1] + sol.meridian.z_mm[1:])
        ax.plot(100 * sol.element_max_principal_strain, zm, style, color="tab:blue" if k == "expanded" else
                "tab:green", label=f"{k}: membrane max {100 * e.max_principal_strain:.1f} %")
        ax.plot([100 * e.clamp_strain] * 2, [zm[0], zm[-1]], ":", color="tab:blue" if k == "expanded" else
                "tab:green", lw=1.0, label=f"{k}: clamp + bending {100 * e.clamp_strain:.1f} %")
    ax.axvline(100 * result.allowable_strain, color="tab:red", lw=2,
               label=f"allowable {100 * result.allowable_strain:.1f} %")
    ax.set_xlim(0, 100 * vmax * 1.15)
    ax.set_xlabel("max principal strain (%)")
    ax.set_ylabel("reference z from the lower clamp (mm)")
    ax.legend(fontsize=7, loc="upper center", bbox_to_anchor=(0.5, -0.12), ncol=1, frameon=False)
    ok = result.passes
    verdict = "PASS" if ok else "FAIL"
    why = (f"bound {100 * result.strain_bound:.1f} % {'<=' if result.passes_strain else '>'} allowable "
           f"{100 * result.allowable_strain:.1f} %\n{'no contact with tube or bore' if result.passes_room else 'CONTACT'}")
    ax.set_title(f"{verdict}: {why}", fontsize=9, color="tab:green" if ok else "tab:red", weight="bold", y=1.0)
    fig.suptitle(f"{title + ': ' if title else ''}{result.silicone.name}, wall {result.thickness_mm:g} mm "
                 f"-> {verdict}", fontsize=11, color="black",
                 **({"y": 1 - 0.04 / fig.get_size_inches()[1]} if fixed else {}))  # where a constrained layout puts it
    if fixed:
        _place_panels(fig, axes, cax, result)
    return fig


def _place_panels(fig, axes, cax, result: BladderResult) -> None:
    """Panels and colour bar of :func:`plot_bladder` placed as a constrained layout placed them, in inches,
    without the extra draw it costs at savefig: the font sizes are fixed, so the room of the titles, axis
    labels, legends below and colour bar is known; the y tick labels' room is measured."""
    from ..figure_layout import place_row_in, ytick_label_width_in

    W, H = fig.get_size_inches()
    three = any(any(e.touches.values()) for e in result.ends.values())  # titles of three lines
    top, bottom, right = 0.62 + (0.15 if three else 0.0), 2.19, 0.04
    tw = [ytick_label_width_in(ax) for ax in axes]
    left, gaps = 0.36 + tw[0], (0.21 + tw[1], 0.40 + tw[2])  # the third panel has a y label
    edges = place_row_in(fig, axes, left, right, bottom, top, gaps, ratios=(1.0, 1.0, 1.15))
    # the colour bar: centred under the two wall panels, 0.6 of their span
    span = edges[1] - edges[0] + axes[1].get_position().width * W
    cax.set_position([(left + 0.2 * span) / W, 0.47 / H, 0.6 * span / W, 0.21 / H])


def _profile_rows(result: BladderResult) -> list[dict]:
    rows = []
    for k in ENDS:
        sol = result.ends[k].solution
        f = sol.fields
        ps = sol.principal_strains
        for e in range(sol.meridian.n_elements):
            rows.append({
                "stroke_end": k,
                "element": e,
                "z_ref_mm": 0.5 * (sol.meridian.z_mm[e] + sol.meridian.z_mm[e + 1]),
                "r_mm": 0.5 * (sol.r_mm[e] + sol.r_mm[e + 1]),
                "z_mm": 0.5 * (sol.z_mm[e] + sol.z_mm[e + 1]),
                "strain_meridional": ps[e, 0],
                "strain_hoop": ps[e, 1],
                "strain_thickness": ps[e, 2],
                "geometric_strain_meridional": f["l1"][e] - 1,
                "geometric_strain_hoop": f["l2"][e] - 1,
                "state": ["taut", "wrinkled", "slack"][int(f["state"][e])],
                "tension_meridional_N_per_mm": f["T1_N_per_mm"][e],
                "tension_hoop_N_per_mm": f["T2_N_per_mm"][e],
            })
    return rows


def write_bladder_report(design, out_dir: str | Path, material: str | Silicone = DEFAULT_MATERIAL,
                         criterion: str | StrainCriterion | float | None = None, *,
                         n_elements: int = DEFAULT_ELEMENTS, result: BladderResult | None = None) -> BladderReport:
    """Check ``design``'s bladder and write ``bladder.json``, ``bladder_profile.csv`` and ``bladder.png`` to ``out_dir``.

    Parameters
    ----------
    design : vvea_design.spring.design.Design
        The design whose cast bladder (mid radius, free length, wall, mm) and stroke volume changes
        (mm³) are checked, in the room between its inner tube and outer bore.
    out_dir : str or Path
        Folder to write into (created).
    material : str or Silicone
        Casting silicone: a key of :data:`vvea_design.materials.silicones.SILICONES` (default
        ``"dragon-skin-20"``) or a :class:`Silicone` (shear modulus in MPa).
    criterion : str, StrainCriterion, float or None
        Allowable-strain criterion of the silicone (None = ``"cyclic"``), or the allowable strain
        itself as a fraction.
    n_elements : int
        Elements along the meridian of the check.
    result : BladderResult or None
        The check of ``design`` already computed by :func:`check_bladder` with the same material,
        criterion and elements (written as it is, not solved again); None solves it here.

    Returns
    -------
    BladderReport
        The check and the names of the JSON, CSV and PNG written (relative to ``out_dir``); its
        ``to_dict()`` is the ``bladder.json`` content (units in the keys).

    Raises
    ------
    BladderError
        A design whose bladder does not fit, an unknown material or criterion, a stroke the sleeve
        cannot take.
    """
    import csv

    res = result if result is not None else check_bladder(design, material, criterion, n_elements=n_elements)
    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    png = out / "bladder.png"
    plot_bladder(res, title="bladder check").savefig(png, dpi=120)
    rows = _profile_rows(res)
    csv_path = out / "bladder_profile.csv"
    with csv_path.open("w", newline="") as fh:
        w = csv.DictWriter(fh, fieldnames=list(rows[0]))
        w.writeheader()
        w.writerows(rows)
    report = BladderReport(res, Path(out_dir), {"json": "bladder.json", "csv": csv_path.name, "png": png.name})
    (out / "bladder.json").write_text(json.dumps(report.to_dict(), indent=2))
    return report
