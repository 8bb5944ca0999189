"""The FE check of a unit's pressure-bearing pieces: every piece of the CAD model, meshed from its meridian
section, solved under every load case; per wall of the design the governing case, its peak stress and where,
the safety factor on yield, pass or fail at the case's required factor; and a picture of each piece's stress.

The peak includes the concentrations at grooves, shoulders and edges the CAD draws (internal corners drawn
sharp get the drawing's root radii, :meth:`~vvea_design.cad.layout.Layout.corner_radius_mm`: R1 at steps and
shoulders, the ISO 3601 gland's radius at O-ring groove roots, R1.5 at the rod's shoulder); the nominal (membrane plus
bending, linearised on a stress-classification line) is reported beside it with the closed form the sizing
uses, so that "the FE and the sizing agree away from the features" and "the features take the factor" are
both visible. The check is stricter than a design-by-analysis check to EN 13445-3 annex B (which limits the
membrane and bending stress and leaves the peak to the fatigue check): the peak must keep the factor.

Lengths mm, stresses and pressures MPa, forces N, times s.
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from ..cad.assembly import CadModel
from ..materials.structural import get_material
from .evaluate import Nominal, Peak, linearise, peak_in
from .loads import LoadCase, default_load_cases
from .meshing import MeshSpec, element_size_mm
from .model import CaseSolution, PieceModel
from .pieces import PieceSpec, build_piece, piece_specs
from ..cad.layout import ROD_SHOULDER_RADIUS_MM, ROOT_RADIUS_MM
from .section import outline_polygon

__all__ = ["CaseCheck", "WallCheck", "PieceCheck", "StructureResult", "check_structure", "CRITERIA"]

#: The equivalent stresses a check can be made on.
CRITERIA = ("tresca", "von_mises")


@dataclass(frozen=True)
class CaseCheck:
    """One wall under one load case."""

    case: str
    required_safety: float
    peak: Peak
    nominal: Nominal | None  #: the most stressed stress-classification line (None: the wall has none)
    safety: float  #: yield over the peak (the check's criterion)
    nominal_safety: float  #: yield over the nominal membrane plus bending (nan: no line)
    sizing_stress_MPa: float = math.nan  #: the spring sizing's stress of the wall in this case (nan: none)

    @property
    def peak_over_sizing(self) -> float:
        """FE peak over the sizing's closed-form stress (the concentration the sizing must learn; nan: none)."""
        return self.peak.tresca_MPa / self.sizing_stress_MPa if self.sizing_stress_MPa > 0 else math.nan

    @property
    def passes(self) -> bool:
        """The peak keeps the required factor."""
        return self.safety >= self.required_safety

    def to_dict(self) -> dict[str, Any]:
        """JSON-ready content.

        Returns
        -------
        dict
            Case name, required and achieved safety factors, the peak (MPa, mm) and the nominal (MPa).
        """
        n = self.nominal
        return {"case": self.case, "required_safety": self.required_safety, "safety": self.safety,
                "passes": self.passes, "nominal_safety": _num(self.nominal_safety),
                "sizing_stress_MPa": _num(self.sizing_stress_MPa), "peak_over_sizing": _num(self.peak_over_sizing),
                "peak_von_mises_MPa": self.peak.von_mises_MPa, "peak_tresca_MPa": self.peak.tresca_MPa,
                "peak_r_mm": self.peak.r_mm, "peak_z_mm": self.peak.z_mm, "feature": self.peak.feature,
                "corner_radius_mm": _num(self.peak.corner_radius_mm),
                "nominal": None if n is None else {
                    "line": n.line, "membrane_von_mises_MPa": n.membrane_von_mises_MPa,
                    "membrane_bending_von_mises_MPa": n.membrane_bending_von_mises_MPa,
                    "membrane_bending_tresca_MPa": n.membrane_bending_tresca_MPa,
                    "closed_form_MPa": _num(n.closed_form_MPa), "fe_comparable_MPa": _num(n.fe_comparable_MPa),
                    "closed_form": n.closed_form_what}}


@dataclass(frozen=True)
class WallCheck:
    """A wall of the design checked by FE under every case; the governing one (lowest margin) named."""

    wall: str  #: the design's wall name (``outer_tube``, ``bulkhead``, ``piston_floor`` ...)
    piece: str  #: the CAD part it is in
    material: str
    yield_MPa: float
    criterion: str  #: "tresca" or "von_mises"
    cases: tuple[CaseCheck, ...]

    @property
    def governing(self) -> CaseCheck:
        """The case with the smallest safety over its required factor."""
        return min(self.cases, key=lambda c: c.safety / c.required_safety)

    @property
    def passes(self) -> bool:
        """Every case keeps its required factor."""
        return all(c.passes for c in self.cases)

    @property
    def concentration(self) -> float:
        """Peak over nominal (the criterion's stress) in the governing case (nan: no nominal)."""
        g = self.governing
        if g.nominal is None:
            return math.nan
        nom = g.nominal.membrane_bending_tresca_MPa if self.criterion == "tresca" else \
            g.nominal.membrane_bending_von_mises_MPa
        peak = g.peak.tresca_MPa if self.criterion == "tresca" else g.peak.von_mises_MPa
        return peak / nom if nom > 0 else math.nan

    @property
    def peak_over_sizing(self) -> float:
        """The largest FE peak (Tresca) over the spring sizing's stress of the same case (nan: no sizing)."""
        vals = [c.peak_over_sizing for c in self.cases if math.isfinite(c.peak_over_sizing)]
        return max(vals) if vals else math.nan

    def to_dict(self) -> dict[str, Any]:
        """JSON-ready content.

        Returns
        -------
        dict
            The wall, its piece and material, the governing case's numbers at the top (safety, peak in MPa,
            where in mm, the feature), the concentration, and every case.
        """
        g = self.governing
        return {"wall": self.wall, "piece": self.piece, "material": self.material, "yield_MPa": self.yield_MPa,
                "criterion": self.criterion, "passes": self.passes, "governing_case": g.case,
                "safety": g.safety, "required_safety": g.required_safety,
                "peak_MPa": g.peak.tresca_MPa if self.criterion == "tresca" else g.peak.von_mises_MPa,
                "peak_von_mises_MPa": g.peak.von_mises_MPa, "peak_tresca_MPa": g.peak.tresca_MPa,
                "location": {"r_mm": g.peak.r_mm, "z_mm": g.peak.z_mm, "feature": g.peak.feature,
                             "corner_radius_mm": _num(g.peak.corner_radius_mm)},
                "nominal_safety": _num(g.nominal_safety), "concentration": _num(self.concentration),
                "peak_over_sizing": _num(self.peak_over_sizing),
                "cases": [c.to_dict() for c in self.cases]}


@dataclass(frozen=True)
class PieceCheck:
    """A piece's model: its section, mesh, joint, and the picture of its governing stress field."""

    piece: str
    title: str
    material: str
    section_angle_deg: float  #: half-plane the CAD solid was cut at
    volume_fraction: float  #: CAD volume / revolved section (what the axisymmetric model leaves out)
    elements: int
    nodes: int
    element_size_mm: float  #: median element edge
    corners: int  #: re-entrant corners (rounded to at least the default radius)
    joint: str  #: how its axial load reaches its joint
    reactions_N: dict[str, float]  #: the joint's axial reaction per case, N
    figure: str | None = None  #: stress-field PNG (None: not drawn)
    bearings: dict[str, str] = field(default_factory=dict)  #: the joint face each case's reaction went to
    not_drawn: tuple[str, ...] = ()  #: joint faces the section does not have (replaced by the next listed)

    def to_dict(self) -> dict[str, Any]:
        """JSON-ready content.

        Returns
        -------
        dict
            Every field (angle in degrees, sizes in mm, reactions in N, the PNG's path).
        """
        return {"piece": self.piece, "title": self.title, "material": self.material,
                "section_angle_deg": _num(self.section_angle_deg), "volume_fraction": _num(self.volume_fraction),
                "elements": self.elements, "nodes": self.nodes, "element_size_mm": self.element_size_mm,
                "corners": self.corners, "joint": self.joint, "reactions_N": dict(self.reactions_N),
                "bearings": dict(self.bearings), "not_drawn": list(self.not_drawn), "figure": self.figure}


@dataclass(frozen=True)
class StructureResult:
    """The FE check of every pressure-bearing piece of a unit."""

    walls: tuple[WallCheck, ...]
    pieces: tuple[PieceCheck, ...]
    cases: tuple[LoadCase, ...]
    mesh: MeshSpec
    corner_radius_mm: float | None  #: one radius given to every sharp internal corner (None: the drawing's)
    criterion: str
    seconds: float
    notes: tuple[str, ...] = field(default=())
    cpu_seconds: float = math.nan  #: CPU time of the check (this process), s

    @property
    def passes(self) -> bool:
        """Every wall keeps its required factor under every case."""
        return all(w.passes for w in self.walls)

    def wall(self, name: str) -> WallCheck:
        """The check of one wall.

        Parameters
        ----------
        name : str
            The design's wall name.

        Returns
        -------
        WallCheck
            Its check.

        Raises
        ------
        KeyError
            If no piece holds that wall (the message lists those checked).
        """
        for w in self.walls:
            if w.wall == name:
                return w
        raise KeyError(f"no FE check of wall {name!r}; checked: {', '.join(w.wall for w in self.walls)}")

    def to_dict(self) -> dict[str, Any]:
        """JSON-ready content (what ``unit.json`` holds under ``structure``).

        Returns
        -------
        dict
            Verdict, criterion, the cases (MPa, mm), every wall's check, every piece's model, the mesh, time (s).
        """
        return {"passes": self.passes, "criterion": self.criterion,
                "walls": {w.wall: w.to_dict() for w in self.walls},
                "pieces": {p.piece: p.to_dict() for p in self.pieces},
                "cases": [c.to_dict() for c in self.cases],
                "mesh": {"elements_per_wall": self.mesh.elements_per_wall,
                         "elements_per_radius": self.mesh.elements_per_radius, "growth": self.mesh.growth,
                         "max_size_mm": self.mesh.max_size_mm},
                "corner_radius_mm": self.corner_radius_mm, "root_radii": "drawing" if self.corner_radius_mm is None
                else "uniform", "seconds": self.seconds,
                "cpu_seconds": _num(self.cpu_seconds), "notes": list(self.notes)}


def _num(v: float) -> float | None:
    return None if v is None or (isinstance(v, float) and math.isnan(v)) else float(v)


def _sizing_stresses(design) -> dict[str, dict[str, float]]:
    """The spring sizing's stress per wall and case (yield over its safety factor per case), MPa."""
    try:
        loads = design.piece_loads()
    except AttributeError:  # a design without the buildability records
        return {}
    out = {}
    for wall, pl in loads.items():
        mat = get_material(design.fixed.rod_material if wall == "piston_floor" else design.fixed.housing_material)
        out[wall] = {c: (mat.yield_MPa / sf if sf and math.isfinite(sf) and sf > 0 else math.nan)
                     for c, sf in pl.safety_factor_per_case.items()}
    return out


def _check_case(pm: PieceModel, spec: PieceSpec, cs: CaseSolution, criterion: str,
                sizing: dict[str, dict[str, float]]) -> dict[str, CaseCheck]:
    """Each wall of a piece under one solved case."""
    out = {}
    mat = pm.material
    for reg in spec.regions:
        pk = peak_in(cs.solution, reg, spec.section, criterion)
        if pk is None:
            continue
        noms = [linearise(cs.solution, line, cs.case.gauge_MPa(), cs.case.x_mm) for line in reg.lines]
        key = (lambda n: n.membrane_bending_tresca_MPa) if criterion == "tresca" else \
            (lambda n: n.membrane_bending_von_mises_MPa)
        nom = max(noms, key=key) if noms else None
        peak = pk.tresca_MPa if criterion == "tresca" else pk.von_mises_MPa
        safety = mat.yield_MPa / peak if peak > 0 else math.inf
        nsafe = (mat.yield_MPa / key(nom) if key(nom) > 0 else math.inf) if nom is not None else math.nan
        out[reg.wall] = CaseCheck(cs.case.name, cs.case.required_safety, pk, nom, safety, nsafe,
                                  sizing.get(reg.wall, {}).get(cs.case.name, math.nan))
    return out


def check_structure(model: CadModel, cases: tuple[LoadCase, ...] | None = None, *, mesh: MeshSpec = MeshSpec(),
                    criterion: str = "tresca", corner_radius_mm: float | None = None,
                    out_dir: str | Path | None = None, progress=None) -> StructureResult:
    """FE check of every pressure-bearing piece of a unit under its load cases.

    Parameters
    ----------
    model : CadModel
        The unit's CAD (its machined pieces and piston at x = 0), mm.
    cases : tuple of LoadCase, optional
        Load cases (absolute pressures, MPa); default :func:`~vvea_design.structure.loads.default_load_cases`.
    mesh : MeshSpec
        Mesh sizes (the coarse default is the main job's; ``studies/fe_convergence.py`` measures its error).
    criterion : str
        ``"tresca"`` (default) or ``"von_mises"``: the stress the safety factor is taken on.
    corner_radius_mm : float, optional
        Radius given to every internal corner the CAD draws sharp, mm; None (default): the drawing's root radii
        (:meth:`~vvea_design.cad.layout.Layout.corner_radius_mm`).
    out_dir : path-like, optional
        Folder for a stress-field PNG per piece (None: no pictures).
    progress : callable, optional
        ``progress(piece_name, index, total)`` before each piece.

    Returns
    -------
    StructureResult
        Per wall the governing case, peak stress (MPa) and location (mm), safety factor and verdict; per piece
        its model; the cases; the time (s).

    Raises
    ------
    ValueError
        If ``criterion`` is unknown or a piece's pressures cannot be reacted by its joint.
    """
    if criterion not in CRITERIA:
        raise ValueError(f"criterion must be one of {CRITERIA}, got {criterion!r}")
    t0, c0 = time.perf_counter(), time.process_time()
    cases = tuple(cases) if cases is not None else default_load_cases(model.design)
    specs = piece_specs(model, corner_radius_mm)
    outlines = {s.part: outline_polygon(s.section.face) for s in specs if s.part != "piston"}
    sizing = _sizing_stresses(model.design)
    walls: dict[str, dict[str, CaseCheck]] = {}
    wall_piece: dict[str, PieceSpec] = {}
    pieces: dict[str, PieceCheck] = {}
    reactions: dict[str, dict[str, float]] = {}
    # the end pieces first: the outer tube carries their joints' loads
    order = sorted(specs, key=lambda sp: sp.part not in ("housing_top_cap", "housing_base"))
    for i, spec in enumerate(order):
        if progress is not None:
            progress(spec.part, i, len(specs))
        pm = build_piece(spec, model, outlines, mesh)
        solved = [pm.solve(c, _applied(pm, spec, c, reactions)) for c in cases]
        reactions[spec.part] = {cs.case.name: cs.reaction_N for cs in solved}
        for cs in solved:
            for wall, cc in _check_case(pm, spec, cs, criterion, sizing).items():
                walls.setdefault(wall, {})[cs.case.name] = cc
                wall_piece[wall] = spec
        fig = None
        if out_dir is not None:
            from .figures import piece_figure

            gov = _governing_solution(spec, solved, walls, criterion)
            fig = str(piece_figure(pm, spec, gov, criterion, Path(out_dir) / f"fe_{spec.part}.png"))
        pieces[spec.part] = PieceCheck(
            spec.part, spec.title, get_material(spec.material_key).name, spec.section.angle_deg,
            spec.section.volume_fraction, pm.mesh.t.shape[1], pm.mesh.doflocs.shape[1], element_size_mm(pm.mesh),
            len(spec.section.corners), spec.joint, reactions[spec.part], fig,
            {cs.case.name: ("none (no net axial load)" if cs.bearing is None else cs.bearing.what) for cs in solved},
            tuple(b.what for b in pm.missing_bearings))
    pieces = {s.part: pieces[s.part] for s in specs}  # in the specs' order
    checks = []
    for wall, by_case in walls.items():
        spec = wall_piece[wall]
        mat = get_material(spec.material_key)
        checks.append(WallCheck(wall, spec.part, mat.name, mat.yield_MPa, criterion,
                                tuple(by_case[c.name] for c in cases if c.name in by_case)))
    notes = _notes(list(pieces.values()), corner_radius_mm)
    return StructureResult(tuple(checks), tuple(pieces.values()), cases, mesh, corner_radius_mm, criterion,
                           time.perf_counter() - t0, notes, time.process_time() - c0)


def _applied(pm: PieceModel, spec: PieceSpec, case: LoadCase, reactions: dict) -> tuple:
    """The forces other pieces put on this one in a case: the top cap's joint load (its reaction plus the
    tendon's pull) on the tube's thread or groove, or a clamp force, N."""
    out = []
    for faces, source in spec.applied:
        face = pm.drawn(faces)
        if face is None:
            continue
        if source == "top_cap":
            force = abs(reactions.get("housing_top_cap", {}).get(case.name, 0.0)) + max(case.external_force_N, 0.0)
        else:
            force = float(source)
        out.append((face, force))
    return tuple(out)


def _governing_solution(spec: PieceSpec, solved: list[CaseSolution], walls, criterion: str) -> CaseSolution:
    """The piece's case with the smallest margin over all its walls."""
    best, margin = solved[0], math.inf
    for cs in solved:
        for reg in spec.regions:
            cc = walls.get(reg.wall, {}).get(cs.case.name)
            if cc is not None and cc.safety / cc.required_safety < margin:
                best, margin = cs, cc.safety / cc.required_safety
    return best


def _notes(pieces: list[PieceCheck], corner_radius_mm: float | None) -> tuple[str, ...]:
    out = [("internal corners drawn sharp are modelled with the drawing's root radii: "
            f"R{ROOT_RADIUS_MM:g} at steps and shoulders unless stated (at most 0.45 of the shorter edge meeting "
            f"there), R{ROD_SHOULDER_RADIUS_MM:g} at the rod's shoulder into the piston, the ISO 3601 gland's root "
            "radius at O-ring grooves" if corner_radius_mm is None else
            f"internal corners drawn sharp are modelled with R{corner_radius_mm:g} (a study's radius, not the "
            "drawing's)"),
           "threads are drawn as their pitch cylinders (ISO 6410-1) and the joint's load is smeared over the "
           "engaged flanks: the peak is taken outside a pitch round them, the thread itself is checked by ISO 965-1 "
           "(stripping, the wall under the root: the joint's safety factors)",
           "pressure enters the cylindrical fits of the joints up to their seal (the higher of the spaces they "
           "separate); the tendon's pull on the top cap's eye is carried by its joint (in the tube's end load), "
           "not applied to the cap (no eye is drawn)"]
    for p in pieces:
        if p.not_drawn:
            out.append(f"{p.piece}: joint face(s) not in the drawn section, the next listed used instead: "
                       + "; ".join(p.not_drawn))
    for p in pieces:
        if not math.isnan(p.volume_fraction) and p.volume_fraction < 0.995:
            out.append(f"{p.piece}: its non-axisymmetric holes (valve bores, ports) take "
                       f"{100 * (1 - p.volume_fraction):.1f} % of its volume and are not in the axisymmetric model")
    return tuple(out)


