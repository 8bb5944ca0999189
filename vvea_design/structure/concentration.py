"""Stress-concentration factors of the unit's feature kinds, from FE over a range of geometries, and their fit.

Each feature kind has a canonical axisymmetric geometry, a load, and a *nominal* stress: the closed form a
sizing computes without the feature (stated per kind in :data:`KINDS`). The factor is the FE peak over that
nominal, for the Tresca and for the von Mises stress:

* ``oring_groove_root``: a rectangular O-ring gland (width 1.7 x depth, ISO 3601 proportions) turned in the
  outside of a tube under internal pressure; nominal: Lamé at the bore of the full wall (the groove's factor
  on the wall the sizing draws; the peak is the largest near the groove, at its root or at the bore under it);
* ``thread_relief``: a thread relief / undercut (width 2 x depth) turned in the outside of a tube carrying
  an axial load (a threaded joint's end load); nominal: the axial stress on the net section;
* ``ring_groove``: a DIN 472 retaining-ring groove (width 2.2 x depth) in a bore, the ring bearing on the
  groove's flank and the tube carrying that load to its other end; nominal: the axial stress on the net
  section outside the groove;
* ``shoulder_fillet``: a shoulder of a bar in tension (the rod into the piston; the large part long, loaded
  far from the shoulder: Peterson's stepped bar); nominal: the bar's axial stress;
* ``web_root``: a plate (bulkhead, cap web) in a tube's bore under pressure on one side, its root corners
  rounded; nominal: the bending stress of a clamped plate's edge, ``3 q a^2 / (4 t^2)``.

The fit is ``ln Kt = c0 + c1 ln x1 + c2 ln x2 + c3 ln x1 ln x2`` in the kind's two dimensionless variables
(:data:`KINDS`), by least squares (a factor may fall below 1 where the closed form's nominal is conservative,
e.g. a shallow gland in a thick wall); ``x1`` is taken with the root radius the geometry really got; the study ``studies/fe_stress_concentration.py`` runs the grid, fits, and writes
the data file the spring sizing reads (:func:`write_factors`; format in :data:`FORMAT`). Lengths mm, stresses
MPa.
"""

from __future__ import annotations

import json
import math
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from .elasticity import AxiProblem, AxiSolution
from .meshing import MeshSpec, mesh_section
from .model import boundary_facets, nearest_vertex
from .section import section_from_outline, with_corner_radii

__all__ = ["KINDS", "FORMAT", "FORMAT_VERSION", "KtPoint", "KtFit", "kt_point", "fit_kt", "write_factors", "evaluate_kt"]

#: Identifier of the data file's format and its version (the spring side's reader,
#: :mod:`vvea_design.spring.concentration`, checks both).
FORMAT = "vvea-stress-concentration"
FORMAT_VERSION = 1

#: Feature kinds: what they are, their variables ``x1``, ``x2`` and the nominal stress their factor is over.
KINDS: dict[str, dict[str, str]] = {
    "oring_groove_root": {
        "what": "O-ring gland (rectangular groove, width 1.7 x depth) in a wall under internal pressure",
        "x1": "depth_over_radius", "x2": "depth_over_wall",
        "nominal": "Lamé at the bore of the full wall (a bore, b outside): Tresca 2 p b^2/(b^2 - a^2)"},
    "thread_relief": {
        "what": "thread relief / undercut (width 2 x depth) in a wall carrying the joint's axial load",
        "x1": "depth_over_radius", "x2": "depth_over_wall",
        "nominal": "axial stress on the net section under the relief: F / (pi (b_root^2 - a^2))"},
    "ring_groove": {
        "what": "DIN 472 retaining-ring groove (width 2.2 x depth) in a bore, the ring bearing on its flank",
        "x1": "depth_over_radius", "x2": "depth_over_wall",
        "nominal": "axial stress on the net section outside the groove: F / (pi (b^2 - a_root^2))"},
    "shoulder_fillet": {
        "what": "shoulder of a bar (diameter d) into a larger one (D), in tension (the rod into the piston)",
        "x1": "diameter_over_radius", "x2": "large_over_small_diameter",
        "nominal": "axial stress in the bar: F / (pi d^2 / 4)"},
    "web_root": {
        "what": "root of a plate (bulkhead, cap web) in a tube's bore, pressure on one side",
        "x1": "thickness_over_radius", "x2": "wall_over_thickness",
        "nominal": "bending stress at a clamped plate's edge: 3 q a^2 / (4 t^2) (a: the bore's radius)"},
}

_E, _NU = 68.9e3, 0.33


@dataclass(frozen=True)
class KtPoint:
    """One FE of a feature kind: its variables and the factors."""

    kind: str
    x1: float
    x2: float
    kt_tresca: float
    kt_von_mises: float

    def to_dict(self) -> dict:
        """JSON-ready content.

        Returns
        -------
        dict
            Kind, the two variables, the two factors.
        """
        k = KINDS[self.kind]
        return {k["x1"]: self.x1, k["x2"]: self.x2, "kt_tresca": self.kt_tresca, "kt_von_mises": self.kt_von_mises}


@dataclass(frozen=True)
class KtFit:
    """``ln Kt = c0 + c1 ln x1 + c2 ln x2 + c3 ln x1 ln x2`` for one kind and criterion, its range and error."""

    kind: str
    criterion: str
    coefficients: tuple[float, float, float, float]
    x1_range: tuple[float, float]
    x2_range: tuple[float, float]
    max_relative_error: float  #: of the fit over the FE points

    def __call__(self, x1, x2=1.0):
        """The fitted factor (variables clamped into the fitted range).

        Parameters
        ----------
        x1, x2 : float or array
            The kind's variables.

        Returns
        -------
        float or ndarray
            Kt (dimensionless).
        """
        return evaluate_kt(self.coefficients, x1, x2, self.x1_range, self.x2_range)


def evaluate_kt(coefficients, x1, x2, x1_range, x2_range):
    """``exp(c0 + c1 ln x1 + c2 ln x2 + c3 ln x1 ln x2)`` with the variables clamped into their ranges (the data
    file's model).

    Parameters
    ----------
    coefficients : sequence of 4 float
        ``c0 .. c3``, dimensionless.
    x1, x2 : float or array
        Variables (ratios of lengths), dimensionless.
    x1_range, x2_range : tuple of float
        Fitted ranges, dimensionless.

    Returns
    -------
    float or ndarray
        Kt.
    """
    c0, c1, c2, c3 = coefficients
    u = np.log(np.clip(np.asarray(x1, dtype=float), *x1_range))
    v = np.log(np.clip(np.asarray(x2, dtype=float), *x2_range))
    return np.exp(c0 + c1 * u + c2 * v + c3 * u * v)


def _solve(outline, radius, spec, loads, pin_at, clamp=None) -> tuple[AxiSolution, object]:
    """Mesh an outline (its re-entrant corners rounded), apply ``loads(mid, n) -> (p, tz)``, solve."""
    sec = with_corner_radii(section_from_outline(outline, "kt"), radius)
    mesh = mesh_section(sec, spec)
    bf, mid, n, _ = boundary_facets(mesh)
    p, tz = loads(mid, n)
    pin = None
    if clamp is None:
        pin = nearest_vertex(mesh, *pin_at)
    cl = None if clamp is None else bf[clamp(mid, n)]
    prob = AxiProblem(mesh, _E, _NU, pin, clamped_facets=cl)
    return prob.solve(prob.load_vector(bf, p, tz)), sec


def _balanced_ends(mid, n, a_mm, b_mm, L, F, ring=None):
    """Axial traction totalling F on the top end face (r in a..b), -F on the bottom end (or on ``ring``)."""
    top = (np.abs(mid[1] - L) < 1e-9) & (np.abs(n[1]) > 0.9)
    bot = (np.abs(mid[1]) < 1e-9) & (np.abs(n[1]) > 0.9)
    tz = np.zeros(mid.shape[1])
    tz[bot] = -F / (math.pi * (b_mm**2 - a_mm**2))
    if ring is None:
        tz[top] = F / (math.pi * (b_mm**2 - a_mm**2))
    else:
        sel, area = ring
        tz[sel(mid, n)] = F / area
    return tz


def _radius(sec) -> float:
    """The root radius the geometry really got (the least of its corners'; a fillet is limited by its edges)."""
    r = min(c.radius_mm for c in sec.corners)
    if r <= 0:
        raise ValueError("a corner of the feature could not be rounded")
    return r


def _peak(sol: AxiSolution, box) -> tuple[float, float]:
    r0, r1, z0, z1 = box
    m = (sol.nodes_mm[0] >= r0) & (sol.nodes_mm[0] <= r1) & (sol.nodes_mm[1] >= z0) & (sol.nodes_mm[1] <= z1)
    return float(sol.tresca_MPa[m].max()), float(sol.von_mises_MPa[m].max())


def kt_point(kind: str, x1: float, x2: float, spec: MeshSpec = MeshSpec(elements_per_radius=3.0)) -> KtPoint:
    """The FE factor of one geometry of a feature kind.

    Parameters
    ----------
    kind : str
        A key of :data:`KINDS`.
    x1, x2 : float
        Its variables (e.g. depth / root radius and depth / wall).
    spec : MeshSpec
        Mesh sizes (the corner refined to resolve the root radius).

    Returns
    -------
    KtPoint
        Peak over nominal, Tresca and von Mises.

    Raises
    ------
    ValueError
        For an unknown kind.
    """
    if kind not in KINDS:
        raise ValueError(f"unknown feature kind {kind!r}; known: {', '.join(KINDS)}")
    return {"oring_groove_root": _oring, "thread_relief": _relief, "ring_groove": _ring,
            "shoulder_fillet": _shoulder, "web_root": _web}[kind](x1, x2, spec)


def _oring(x1, x2, spec) -> KtPoint:
    t, a, p = 2.0, 20.0, 10.0
    d = x2 * t
    rho, w, b = d / x1, 1.7 * d, a + t
    L = 8 * t + w
    z0, z1 = 0.5 * (L - w), 0.5 * (L + w)
    outline = [(a, 0), (b, 0), (b, z0), (b - d, z0), (b - d, z1), (b, z1), (b, L), (a, L)]

    def loads(mid, n):
        return np.where(np.abs(mid[0] - a) < 1e-9, p, 0.0), np.zeros(mid.shape[1])

    sol, sec = _solve(outline, rho, spec, loads, (a, 0.0))
    tr, vm = _peak(sol, (a, b, z0 - 2 * rho - t, z1 + 2 * rho + t))
    x1 = d / _radius(sec)
    st = p * (b**2 + a**2) / (b**2 - a**2)
    nom_tr = st + p
    nom_vm = math.sqrt(0.5 * ((st + p) ** 2 + p**2 + st**2))
    return KtPoint("oring_groove_root", x1, x2, tr / nom_tr, vm / nom_vm)


def _relief(x1, x2, spec) -> KtPoint:
    t, a, F = 2.0, 20.0, 1000.0
    d = x2 * t
    rho, w, b = d / x1, 2.0 * d, a + t
    L = 8 * t + w
    z0, z1 = 0.5 * (L - w), 0.5 * (L + w)
    outline = [(a, 0), (b, 0), (b, z0), (b - d, z0), (b - d, z1), (b, z1), (b, L), (a, L)]

    def loads(mid, n):
        return np.zeros(mid.shape[1]), _balanced_ends(mid, n, a, b, L, F)

    sol, sec = _solve(outline, rho, spec, loads, (a, 0.0))
    tr, vm = _peak(sol, (b - d - 0.5 * t, b, z0 - 2 * rho, z1 + 2 * rho))
    x1 = d / _radius(sec)
    nom = F / (math.pi * ((b - d) ** 2 - a**2))
    return KtPoint("thread_relief", x1, x2, tr / nom, vm / nom)


def _ring(x1, x2, spec) -> KtPoint:
    t, a, F = 2.0, 20.0, 1000.0
    d = x2 * t
    rho, w, b = d / x1, 2.2 * d, a + t
    L = 8 * t + w
    z0, z1 = L - 3 * t - w, L - 3 * t
    outline = [(a, 0), (b, 0), (b, L), (a, L), (a, z1), (a + d, z1), (a + d, z0), (a, z0)]
    area = math.pi * ((a + d) ** 2 - a**2)

    def flank(mid, n):  # the groove's upper flank (the ring pushes it towards the open end, +z)
        return (np.abs(mid[1] - z1) < 1e-9) & (mid[0] > a) & (mid[0] < a + d) & (n[1] < -0.9)

    def loads(mid, n):
        return np.zeros(mid.shape[1]), _balanced_ends(mid, n, a, b, L, F, ring=(flank, area))

    sol, sec = _solve(outline, rho, spec, loads, (b, 0.0))
    tr, vm = _peak(sol, (a, a + d + 0.5 * t, z0 - 2 * rho, z1 + 2 * rho))
    x1 = d / _radius(sec)
    nom = F / (math.pi * (b**2 - (a + d) ** 2))
    return KtPoint("ring_groove", x1, x2, tr / nom, vm / nom)


def _shoulder(x1, x2, spec) -> KtPoint:
    rs, F = 4.0, 1000.0
    rho, R = 2 * rs / x1, x2 * rs
    L1, L2 = 4 * rs, 3 * R
    outline = [(0, 0), (rs, 0), (rs, L1), (R, L1), (R, L1 + L2), (0, L1 + L2)]

    def loads(mid, n):
        tz = np.zeros(mid.shape[1])
        tz[(np.abs(mid[1]) < 1e-9)] = -F / (math.pi * rs**2)
        tz[(np.abs(mid[1] - L1 - L2) < 1e-9)] = F / (math.pi * R**2)
        return np.zeros(mid.shape[1]), tz

    sol, sec = _solve(outline, rho, spec, loads, (0.0, L1 + L2))
    tr, vm = _peak(sol, (0.5 * rs, rs + 3 * rho + 0.5, L1 - 3 * rho - 0.5, L1 + 0.5))
    x1 = 2 * rs / _radius(sec)
    nom = F / (math.pi * rs**2)
    return KtPoint("shoulder_fillet", x1, x2, tr / nom, vm / nom)


def _web(x1, x2, spec) -> KtPoint:
    t, a, q = 2.0, 16.0, 1.0
    rho, tw = t / x1, x2 * t
    b = a + tw
    L = 10 * t + 6 * tw
    z0, z1 = 0.5 * (L - t), 0.5 * (L + t)
    outline = [(0, z0), (a, z0), (a, 0), (b, 0), (b, L), (a, L), (a, z1), (0, z1)]

    def loads(mid, n):  # pressure below the web: on its underside and the bore under it
        wet = ((np.abs(mid[1] - z0) < 1e-9) & (mid[0] < a)) | ((np.abs(mid[0] - a) < 1e-9) & (mid[1] < z0))
        p = np.where(wet, q, 0.0)
        tz = np.zeros(mid.shape[1])
        top = (np.abs(mid[1] - L) < 1e-9) & (np.abs(n[1]) > 0.9)
        tz[top] = -q * a**2 / (b**2 - a**2)  # the tube's end takes the web's load (pressure on pi a^2)
        return p, tz

    sol, sec = _solve(outline, rho, spec, loads, (b, L))
    tr, vm = _peak(sol, (a - 3 * rho - 0.5, a + 0.5 * tw, z0 - 3 * rho - 0.5, z1 + 3 * rho + 0.5))
    x1 = t / _radius(sec)
    nom = 3 * q * a**2 / (4 * t**2)
    return KtPoint("web_root", x1, x2, tr / nom, vm / nom)


def fit_kt(points: list[KtPoint], criterion: str) -> KtFit:
    """Least-squares fit of ``ln Kt = c0 + c1 ln x1 + c2 ln x2 + c3 ln x1 ln x2`` over one kind's points.

    Parameters
    ----------
    points : list of KtPoint
        FE points of one kind.
    criterion : str
        ``"tresca"`` or ``"von_mises"``.

    Returns
    -------
    KtFit
        Coefficients, ranges, the largest relative error of the fitted Kt over the points.

    Raises
    ------
    ValueError
        If the points mix kinds.
    """
    kinds = {p.kind for p in points}
    if len(kinds) != 1:
        raise ValueError(f"fit_kt: one kind at a time, got {sorted(kinds)}")
    kt = np.array([p.kt_tresca if criterion == "tresca" else p.kt_von_mises for p in points])
    u = np.log([p.x1 for p in points])
    v = np.log([p.x2 for p in points])
    cols = [np.ones_like(u), u, v, u * v] if np.ptp(v) > 0 else [np.ones_like(u), u]
    coef, *_ = np.linalg.lstsq(np.column_stack(cols), np.log(kt), rcond=None)
    c = tuple(float(x) for x in coef) + (0.0,) * (4 - len(coef))
    fit = KtFit(points[0].kind, criterion, c, (float(np.exp(u.min())), float(np.exp(u.max()))),
                (float(np.exp(v.min())), float(np.exp(v.max()))), 0.0)
    err = float(np.max(np.abs(fit(np.exp(u), np.exp(v)) - kt) / kt))
    return KtFit(fit.kind, criterion, c, fit.x1_range, fit.x2_range, err)


def write_factors(path: str | Path, points: dict[str, list[KtPoint]], fits: dict[str, dict[str, KtFit]],
                  provenance: dict, piece_factors: dict[str, dict[str, float]] | None = None,
                  pieces_source: str = "", pieces_provenance: dict | None = None) -> Path:
    """Write the data file the spring sizing reads (format :data:`FORMAT`, version :data:`FORMAT_VERSION`).

    ``factors`` (what :mod:`vvea_design.spring.concentration` reads): per pressure-bearing piece, per feature,
    the FE peak over the sizing's closed-form stress (>= 1; the sizing takes each piece's largest). ``kinds``:
    per feature kind, what it is, its variables, the nominal stress the factor multiplies, the model
    ``ln Kt = c0 + c1 ln x1 + c2 ln x2 + c3 ln x1 ln x2`` with the coefficients per criterion (``tresca``,
    ``von_mises``), the fitted ranges (evaluate with the variables clamped into them), the fit's largest
    error, and the FE points.

    Parameters
    ----------
    path : path-like
        The JSON file written.
    points : dict of str to list of KtPoint
        FE points per kind.
    fits : dict of str to dict of str to KtFit
        Per kind, per criterion.
    provenance : dict
        How the points were made (mesh, corner radii, command).
    piece_factors : dict of str to dict of str to float, optional
        Piece -> feature -> factor (dimensionless, clipped to >= 1); None: neutral 1.0 for every piece.
    pieces_source : str
        How the piece factors were found (the units checked).
    pieces_provenance : dict, optional
        Piece -> feature -> where each factor was measured (``studies/fe_concentration.py``), kept as
        ``factors_provenance``.

    Returns
    -------
    Path
        ``path``.
    """
    neutral = {"base": {"plate": 1.0}, "bulkhead": {"plate": 1.0}, "collar": {"root": 1.0},
               "inner_tube": {"wall": 1.0}, "outer_tube": {"wall": 1.0}, "piston_floor": {"root": 1.0},
               "top_cap": {"plate": 1.0}}
    factors = {k: dict(v) for k, v in neutral.items()}
    for piece, feats in (piece_factors or {}).items():
        factors[piece] = {f: round(max(1.0, float(v)), 4) for f, v in feats.items()}
    out = {"format": FORMAT, "format_version": FORMAT_VERSION,
           "source": pieces_source or "neutral piece factors (1.0); feature kinds fitted from FE",
           "factors": factors,
           "description": ("Stress-concentration factors. factors: per piece and feature, the FE peak (Tresca) over "
                           "the spring sizing's closed-form stress of the same load case (>= 1). kinds: per feature "
                           "kind, fitted from axisymmetric FE (vvea_design.structure.concentration): peak = Kt x "
                           "nominal, Kt = exp(c0 + c1 ln x1 + c2 ln x2 + c3 ln x1 ln x2) "
                           "with x1, x2 clamped into their fitted ranges; to stay on the safe side of the fit, multiply by "
                           "(1 + max_relative_error). The nominal stress of each "
                           "kind is stated with it."),
           "model": "Kt = exp(c0 + c1*ln(x1) + c2*ln(x2) + c3*ln(x1)*ln(x2))", "provenance": provenance, "kinds": {}}
    if pieces_provenance:
        out["factors_provenance"] = pieces_provenance
    for kind, fk in fits.items():
        k = KINDS[kind]
        any_fit = next(iter(fk.values()))
        out["kinds"][kind] = {
            "what": k["what"], "nominal": k["nominal"],
            "x1": k["x1"], "x2": k["x2"], "x1_range": list(any_fit.x1_range), "x2_range": list(any_fit.x2_range),
            **{c: {"coefficients": list(f.coefficients), "max_relative_error": f.max_relative_error}
               for c, f in fk.items()},
            "points": [p.to_dict() for p in points[kind]]}
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text(json.dumps(out, indent=1) + "\n")
    return path
