"""The optimisation problem: a design, or a whole population of decision vectors, evaluated against the
requirements (performance, constraint margins, feasibility).

The requirements themselves (the spec, its TOML file) are :mod:`vvea_design.spring.requirements`; the
search over this problem is :mod:`vvea_design.spring.optimise`. :func:`evaluate_design` evaluates one
:class:`~vvea_design.spring.design.Design`; :func:`evaluate_population` evaluates ``S`` decision vectors of
one layout in one numpy call with the same formulas (:func:`~vvea_design.spring.derive.derive`) — what the
optimiser calls. Margins are scaled and dimensionless, positive where a constraint is met.
"""

from __future__ import annotations

from dataclasses import dataclass, replace

import numpy as np

from .derive import Derived, derive
from .design import Design
from .gas_spring import linearity_exact
from .layouts import LayoutVariant, get_layout
from .parameters import CHANNEL_GAP_MM
from .ports import (MIN_FILL_PORT_MM, MIN_PISTON_SEAL_FIT_MM, MIN_VALVE_REACH_MM, piston_seal_fit_mm,
                    valve_bore_reach_mm)
from .requirements import REPORTED_N, Requirements

__all__ = [
    "Evaluation",
    "evaluate_design",
    "constraint_margins",
    "constraint_names",
    "evaluate_population",
    "design_from_vector",
    "binding_bounds",
]


@dataclass(frozen=True)
class Evaluation:
    """A design's performance and its constraint margins (positive = satisfied)."""

    design: Design
    linearity_error: float  #: fraction, exact (continuous) metric at the nominal n_polytropic
    mean_stiffness_N_per_mm: float  #: continuous least-squares slope at the design's charge (nominal n)
    max_force_N: float
    peak_pressure_MPa: float  #: highest chamber pressure the walls are sized for
    mass_g: float
    margins: dict[str, float]  #: dimensionless, positive = satisfied
    details: dict[str, dict[str, float | str]]  #: value, limit and unit of each constraint
    linearity_isothermal: float = float("nan")  #: n = 1, fraction
    linearity_adiabatic: float = float("nan")  #: n = 1.4, fraction
    mean_stiffness_adiabatic_N_per_mm: float = float("nan")  #: n = 1.4, at the design's charge
    objective: float = float("nan")  #: what the optimiser minimised (worst linearity over its exponents)
    objective_exponents: tuple[float, ...] = (1.0,)

    @property
    def feasible(self) -> bool:
        """Every margin >= 0 (to 1e-9)."""
        return all(m >= -1e-9 for m in self.margins.values())

    def binding(self, tol: float = 1e-3) -> list[str]:
        """Constraints at (or beyond) their limit.

        Parameters
        ----------
        tol : float
            A constraint binds when its margin (scaled, dimensionless) is below this.

        Returns
        -------
        list of str
            Names of the binding or violated constraints, in the order of :attr:`margins`.
        """
        return [k for k, m in self.margins.items() if m < tol]

    def performance(self) -> dict[str, float]:
        """The design's performance figures (the ``performance`` block of the design JSON).

        Returns
        -------
        dict
            Linearity errors (fraction: nominal, n = 1, n = 1.4, objective) with the objective's
            exponents, mean stiffness (N/mm, nominal and n = 1.4), stiffness per MPa of charge,
            ``max_force_N``, ``mass_g``, ``peak_pressure_MPa``, ``p1_MPa``, ``housing_length_mm``,
            ``total_gas_mm3`` and ``layout``.
        """
        return {
            "linearity_error": self.linearity_error,
            "linearity_error_isothermal": self.linearity_isothermal,
            "linearity_error_adiabatic": self.linearity_adiabatic,
            "objective": self.objective,
            "objective_exponents": list(self.objective_exponents),
            "mean_stiffness_N_per_mm": self.mean_stiffness_N_per_mm,
            "mean_stiffness_adiabatic_N_per_mm": self.mean_stiffness_adiabatic_N_per_mm,
            "stiffness_per_charge_N_per_mm_per_MPa": self.mean_stiffness_N_per_mm / self.design.p2_MPa,
            "max_force_N": self.max_force_N,
            "mass_g": self.mass_g,
            "peak_pressure_MPa": self.peak_pressure_MPa,
            "p1_MPa": self.design.p1_MPa,
            "housing_length_mm": self.design.housing_length_mm,
            "total_gas_mm3": self.design.V1_mm3 + self.design.V2_mm3,
            "layout": self.design.layout,
        }

    def to_dict(self) -> dict:
        """JSON-ready content.

        Returns
        -------
        dict
            ``performance`` (:meth:`performance`), ``constraints`` (name -> scaled margin,
            dimensionless, > 0 met) and ``constraint_details`` (name -> value, limit, unit, kind).
        """
        return {"performance": self.performance(), "constraints": dict(self.margins),
                "constraint_details": {k: dict(v) for k, v in self.details.items()}}


def design_from_vector(v, req: Requirements, layout: str = "inner_tube", joint: str = "thread") -> Design:
    """A design of ``layout`` from its decision vector, charged to the highest allowed pressure.

    Parameters
    ----------
    v : array_like
        Values of :meth:`Requirements.decision_variables` of the layout in their order and units
        (mm, mm³; ``bladder_cast_fill`` a fraction, clipped to [0, 1]).
    req : Requirements
        Gives the charge p2 (``max_charge_MPa``), the set point (mm) and the fixed parameters.
    layout : str
        Layout variant, a name of :data:`vvea_design.spring.layouts.LAYOUTS` (``"inner_tube"``,
        ``"bulkhead"`` or ``"annulus_top"``).
    joint : str
        The joint (:data:`~vvea_design.spring.joints.JOINTS`).

    Returns
    -------
    Design
        The design, charged to p2 = ``req.max_charge_MPa`` with p1 from the set point.

    Raises
    ------
    DesignError
        If the layout is unknown or the geometry cannot be drawn.
    """
    kw = {name: float(val) for name, val in zip(req.decision_variables(layout), v)}
    fixed = req.fixed
    if "bladder_cast_fill" in kw:
        fixed = replace(fixed, bladder_cast_fill=min(max(kw.pop("bladder_cast_fill"), 0.0), 1.0))
    return Design(**kw, p2_MPa=req.max_charge_MPa, setpoint_x0_mm=req.setpoint_x0_mm, fixed=fixed, layout=layout,
                  joint=joint)


def binding_bounds(design: Design, req: Requirements, tol: float = 1e-6) -> list[dict]:
    """The search bounds the design sits on: a bound that limits the optimum, reported like a constraint.

    The outer diameter's high end at the envelope (``max_outer_diameter_mm``) is not listed: the
    envelope's own constraint ``outer_diameter`` reports it.

    Parameters
    ----------
    design : Design
        The design (its layout's decision variables; the cast fill from ``fixed`` when optimised).
    req : Requirements
        Its requirements: the search ranges (:meth:`Requirements.search_bounds`).
    tol : float
        A variable is on a bound when within this fraction of the bound (or of its range) of it.

    Returns
    -------
    list of dict
        One per bound reached: ``variable`` (unit in the name), ``end`` ("low"/"high"), ``bound`` and
        ``value`` in the variable's unit, and ``name``: ``"bound <variable> (<end> end)"``.
    """
    out = []
    for name, (lo, hi) in zip(req.decision_variables(design.layout), req.search_bounds(design.layout)):
        v = float(design.fixed.bladder_cast_fill if name == "bladder_cast_fill" else getattr(design, name))
        for end, b in (("low", lo), ("high", hi)):
            if abs(v - b) > tol * max(abs(b), hi - lo):
                continue
            if name == "outer_diameter_mm" and end == "high" and b == req.max_outer_diameter_mm:
                continue
            out.append({"name": f"bound {name} ({end} end)", "variable": name, "end": end, "bound": float(b),
                        "value": v})
    return out


def _exponents(req: Requirements, report: bool = True) -> list[float]:
    extra = REPORTED_N.values() if report else ()
    cap = (REPORTED_N["adiabatic"],) if req.max_linearity_adiabatic is not None else ()
    return sorted({float(req.n_polytropic), *extra, *cap, *req.objective_exponents})


def _performance(A1, A2, V1, V2, p1, p2, req: Requirements, report: bool = True) -> dict[str, np.ndarray]:
    """Linearity (exact metric) at every exponent needed, stiffness, force; arrays like the inputs."""
    T = req.fixed.travel_mm
    out: dict[str, np.ndarray] = {}
    for n in _exponents(req, report):
        r = linearity_exact(A1, A2, V1, V2, p1, p2, T, n)
        out[f"lin_{n:g}"] = r.linearity_error
        out[f"k_{n:g}"] = r.mean_stiffness_N_per_mm
        if n in req.objective_exponents or (n == REPORTED_N["adiabatic"] and req.max_linearity_adiabatic is not None):
            with np.errstate(divide="ignore", invalid="ignore"):
                out[f"ext_{n:g}"] = r.signed_extremes_N / r.force_span_N[..., None]
        if n == req.n_polytropic:
            with np.errstate(divide="ignore", invalid="ignore"):
                F0 = A2 * p2 - A1 * p1
                FT = A2 * p2 * (V2 / (V2 - A2 * T)) ** n - A1 * p1 * (V1 / (V1 + A1 * T)) ** n
            out["max_force_N"] = np.maximum(np.abs(F0), np.abs(FT))
    with np.errstate(invalid="ignore"):
        out["objective"] = np.max([out[f"lin_{n:g}"] for n in req.objective_exponents], axis=0)
    return out


def _details(g: Derived, perf: dict, req: Requirements, values: dict, layout: LayoutVariant,
             strain=None, search: bool = False) -> dict[str, dict]:
    """Every constraint's value, limit, unit and kind (values are arrays or floats like ``g``); with ``search``
    not the wall safety factors (not searched: the sized walls meet them whenever ``wall_capacity`` does).
    ``values``: the charges ``p1_MPa``, ``p2_MPa``, ``V2_mm3`` and ``outer_diameter_mm`` as evaluated."""
    p1, p2, V2 = values["p1_MPa"], values["p2_MPa"], values["V2_mm3"]
    with np.errstate(divide="ignore", invalid="ignore"):
        scale_to_max = req.max_charge_MPa / np.maximum(p2, p1)
        k = perf[f"k_{req.n_polytropic:g}"] * scale_to_max
        gas_left = (V2 - g.displaced_volume_mm3) / V2
    t_bl = req.fixed.bladder_thickness_mm
    d: dict[str, dict] = {
        "outer_diameter": {"value": values["outer_diameter_mm"], "limit": req.max_outer_diameter_mm, "unit": "mm", "kind": "max"},
        "housing_length": {"value": g.housing_length_mm, "limit": req.max_housing_length_mm, "unit": "mm", "kind": "max"},
        "charge_p1": {"value": p1, "limit": req.max_charge_MPa, "unit": "MPa", "kind": "max"},
        "charge_p2": {"value": p2, "limit": req.max_charge_MPa, "unit": "MPa", "kind": "max"},
        "mean_stiffness": {"value": k, "limit": req.min_mean_stiffness_N_per_mm, "unit": "N/mm", "kind": "min"},
        "gas_left_at_full_stroke": {"value": gas_left, "limit": req.min_gas_fraction_at_full_stroke, "unit": "-", "kind": "min"},
        "bladder_room_compressed": {"value": g.bladder_clearance_compressed_mm, "limit": 0.0, "unit": "mm", "kind": "min", "scale": t_bl},
        "bladder_room_expanded": {"value": g.bladder_clearance_expanded_mm, "limit": 0.0, "unit": "mm", "kind": "min", "scale": t_bl},
        "bladder_channel_room": {"value": g.bladder_cast_gap_mm, "limit": CHANNEL_GAP_MM, "unit": "mm", "kind": "min",
                                 "scale": t_bl},
        "chamber2_port_room": {"value": g.chamber2_port_room_mm, "limit": MIN_FILL_PORT_MM, "unit": "mm", "kind": "min",
                               "scale": 1.0},
        "piston_seal_fit": {"value": piston_seal_fit_mm(g.piston_diameter_mm), "limit": MIN_PISTON_SEAL_FIT_MM,
                            "unit": "mm", "kind": "min", "scale": 1.0},
        "valve_bore_reach": {"value": valve_bore_reach_mm(g.piston_diameter_mm, req.fixed.rod_diameter_mm,
                                                          req.fixed.fluid_channel_mm),
                             "limit": MIN_VALVE_REACH_MM, "unit": "mm", "kind": "min", "scale": 1.0},
        "wall_capacity": {"value": g.wall_capacity_value_MPa, "limit": g.wall_capacity_limit_MPa, "unit": "MPa", "kind": "max"},
        **layout.constraint_details(g),
    }
    if req.buildable:
        d["joint_capacity"] = {"value": g.joint_utilisation, "limit": 1.0, "unit": "-", "kind": "max"}
        if req.fixed.piston_pocket:
            d["piston_floor_room"] = {"value": g.section.piston_floor_room_mm, "limit": 0.0, "unit": "mm", "kind": "min",
                                      "scale": 1.0}
        if req.max_parasitic_damping_N_s_per_mm is not None:
            d["parasitic_damping"] = {"value": g.parasitic_damping_N_s_per_mm,
                                      "limit": req.max_parasitic_damping_N_s_per_mm, "unit": "N s/mm", "kind": "max"}
    for wall in () if search else _walls(layout, req.fixed):
        limit = g.required_safety_factors[wall] if req.buildable else req.min_wall_safety_factor
        d[f"wall_safety_{wall}"] = {"value": g.safety_factors[wall], "limit": limit, "unit": "-", "kind": "min"}
    if req.max_mass_g is not None:
        d["mass"] = {"value": g.mass_g, "limit": req.max_mass_g, "unit": "g", "kind": "max"}
    if req.max_linearity_adiabatic is not None:
        d["linearity_adiabatic"] = {"value": perf[f"lin_{REPORTED_N['adiabatic']:g}"],
                                    "limit": req.max_linearity_adiabatic, "unit": "-", "kind": "max"}
    if req.max_bladder_strain is not None:
        if strain is None:
            raise ValueError("req.max_bladder_strain is set: pass the design's bladder_strain to evaluate_design")
        d["bladder_strain"] = {"value": strain, "limit": req.max_bladder_strain, "unit": "-", "kind": "max"}
    return d


def _walls(layout, fixed=None) -> tuple[str, ...]:
    """The pressure walls of a layout, plus the piston pocket's floor when ``fixed.piston_pocket``."""
    return get_layout(layout).walls + (("piston_floor",) if fixed is not None and fixed.piston_pocket else ())


def evaluate_design(design: Design, req: Requirements, bladder_strain: float | None = None) -> Evaluation:
    """Performance and margins of ``design`` against ``req``.

    The design is evaluated as charged (``design.p2_MPa``); the stiffness
    requirement is checked at the highest allowed charge, where p2 is
    ``req.max_charge_MPa`` unless p1 would exceed it (then p1 is the
    limiting chamber). Linearity is the exact (continuous) metric, at the
    nominal exponent and at n = 1 and n = 1.4.

    Parameters
    ----------
    design : Design
        The design as charged (geometry in mm, mm³; p1, p2 in MPa).
    req : Requirements
        The limits to check against.
    bladder_strain : float or None
        The design's bladder strain bound (fraction), required when ``req.max_bladder_strain``
        is set.

    Returns
    -------
    Evaluation
        Linearity (fraction), stiffness (N/mm), force (N), peak pressure (MPa), mass (g) and every
        constraint's margin (scaled, dimensionless, > 0 met) with its value, limit and unit.

    Raises
    ------
    ValueError
        If ``req.max_bladder_strain`` is set and ``bladder_strain`` is None.
    """
    g, d = design.derived, design
    perf = {k: float(v) for k, v in _performance(d.A1_mm2, d.A2_mm2, d.V1_mm3, d.V2_mm3, d.p1_MPa, d.p2_MPa,
                                                  req).items() if not k.startswith("ext_")}
    values = {"p1_MPa": d.p1_MPa, "p2_MPa": d.p2_MPa, "V2_mm3": d.V2_mm3, "outer_diameter_mm": d.outer_diameter_mm}
    details = _details(g, perf, req, values, design.variant, bladder_strain)
    details = {k: {kk: (float(vv) if not isinstance(vv, str) else vv) for kk, vv in v.items()} for k, v in details.items()}
    margins = {name: float(_margin(d)) for name, d in details.items()}
    n = req.n_polytropic
    return Evaluation(
        design=design,
        linearity_error=perf[f"lin_{n:g}"],
        mean_stiffness_N_per_mm=perf[f"k_{n:g}"],
        max_force_N=perf["max_force_N"],
        peak_pressure_MPa=max(design.peak_pressures_MPa().values()),
        mass_g=design.mass_g,
        margins=margins,
        details=details,
        linearity_isothermal=perf["lin_1"],
        linearity_adiabatic=perf["lin_1.4"],
        mean_stiffness_adiabatic_N_per_mm=perf["k_1.4"],
        objective=perf["objective"],
        objective_exponents=tuple(req.objective_exponents),
    )


def evaluate_population(X, req: Requirements, layout: str = "inner_tube", strain_fn=None, extremes: bool = False,
                        joint: str = "thread"):
    """Objective and constraint margins of many designs at once (what the optimiser calls).

    ``X`` has shape ``(S, N)``: ``S`` decision vectors of ``layout`` (its
    ``decision_variables``), each charged to ``req.max_charge_MPa``. Returns
    ``(objective (S,), margins (M, S), buildable (S,))`` with the margins in
    the order of ``constraint_names(req, layout, search=True)`` (the
    constraints a search can violate: not the p2 charge, which is the limit,
    nor the wall safety factors, which the sized walls meet whenever
    ``wall_capacity`` does); the same formulas as
    :func:`evaluate_design` (:func:`~vvea_design.spring.derive.derive`).
    ``strain_fn(g, cols) -> (S,)`` gives the bladder strain when
    ``req.max_bladder_strain`` is set (the optimiser's surrogate). With
    ``extremes`` a fourth array ``(4 E, S)`` holds the signed deviations
    over the force span (at both ends, interior max and min) for each of the
    ``E`` objective exponents: the objective is their largest magnitude, and
    they are smooth where the objective has kinks (the polish's epigraph).

    Parameters
    ----------
    X : array_like
        Decision vectors, shape ``(S, N)``, each in the order and units of
        ``req.decision_variables(layout)`` (mm, mm³; the cast fill a fraction).
    req : Requirements
        The limits; the charge is ``req.max_charge_MPa``.
    layout : str
        Layout variant, a name of :data:`vvea_design.spring.layouts.LAYOUTS` (``"inner_tube"``,
        ``"bulkhead"`` or ``"annulus_top"``).
    strain_fn : callable or None
        ``strain_fn(g, cols)``: bladder strain bound (fraction) of each design from the derived
        geometry ``g`` (a :class:`~vvea_design.spring.derive.Derived`) and the decision columns ``cols`` (name -> array); used only when
        ``req.max_bladder_strain`` is set (None then counts as zero strain).
    extremes : bool
        Also return the signed deviations.
    joint : str
        The joint (:data:`~vvea_design.spring.joints.JOINTS`; ignored under the gas-only rules).

    Returns
    -------
    objective : numpy.ndarray
        Shape ``(S,)``: worst linearity error over the objective exponents (fraction); 1.0 for an
        unbuildable design.
    margins : numpy.ndarray
        Shape ``(M, S)``: scaled, dimensionless margins (> 0 met); -1 for an unbuildable design.
    buildable : numpy.ndarray
        Shape ``(S,)``, bool: the geometry can be drawn and every value is finite.
    extremes : numpy.ndarray
        Only with ``extremes``: shape ``(4 E, S)``, signed deviations over the force span
        (fraction).

    Raises
    ------
    DesignError
        If ``layout`` is unknown.
    """
    X = np.atleast_2d(np.asarray(X, dtype=float))
    lay = get_layout(layout)
    cols = {name: X[:, i] for i, name in enumerate(req.decision_variables(layout))}
    S = X.shape[0]
    p2 = np.full(S, req.max_charge_MPa)
    # the walls' stresses (and the masses without a mass limit) are not searched: not derived, unless a strain
    # function that may read them is used (the surrogate declares it reads only the bladder's geometry)
    strained = strain_fn is not None and req.max_bladder_strain is not None
    lean = not strained or getattr(strain_fn, "reads_bladder_geometry_only", False)
    with np.errstate(all="ignore"):
        g = derive(cols, p2, req.setpoint_x0_mm, req.fixed, lay, joint=joint, stresses=not lean,
                   masses=not lean or req.max_mass_g is not None)
        perf = _performance(g.A1_mm2, g.A2_mm2, cols["V1_mm3"], cols["V2_mm3"], g.p1_MPa, p2, req, report=False)
        strain = strain_fn(g, cols) if strained else None
        values = {"p1_MPa": g.p1_MPa, "p2_MPa": p2, "V2_mm3": cols["V2_mm3"], "outer_diameter_mm": cols["outer_diameter_mm"]}
        details = _details(g, perf, req, values, lay,
                           strain if req.max_bladder_strain is None else (strain if strain is not None else np.zeros(S)),
                           search=lean)
        rows = []
        for k in constraint_names(req, layout, search=True):
            if k.startswith("linearity_adiabatic["):  # smooth pieces of max |deviation| <= limit (no kinks)
                i = int(k[len("linearity_adiabatic["):-1])
                e = perf[f"ext_{REPORTED_N['adiabatic']:g}"][:, i % 4]
                lim = req.max_linearity_adiabatic
                rows.append((lim - e) / lim if i < 4 else (lim + e) / lim)
            else:
                m = _margin(details[k])
                rows.append(m if np.shape(m) == (S,) else np.broadcast_to(m, (S,)))
        margins = np.array(rows, dtype=float)
    ok = g.buildable & np.all(np.isfinite(margins), axis=0) & np.isfinite(perf["objective"])
    obj = np.where(ok, perf["objective"], 1.0)
    margins = np.where(ok[None, :], margins, -1.0)
    if extremes:
        ext = np.concatenate([perf[f"ext_{n:g}"].T for n in req.objective_exponents], axis=0)
        ext = np.where(ok[None, :], ext, 1.0)
        return obj, margins, ok, ext
    return obj, margins, ok


def constraint_names(req: Requirements, layout: str = "inner_tube", search: bool = False) -> list[str]:
    """Names of the constraints :func:`evaluate_design` reports for ``req`` and ``layout``, in its order.

    Parameters
    ----------
    req : Requirements
        Optional limits (mass, adiabatic linearity, bladder strain) add their constraints.
    layout : str
        Layout variant, a name of :data:`vvea_design.spring.layouts.LAYOUTS` (``"inner_tube"``,
        ``"bulkhead"`` or ``"annulus_top"``).
    search : bool
        Only the constraints :func:`evaluate_population` returns (no p2 charge, no wall safety
        factors; the adiabatic linearity as its 8 smooth pieces).

    Returns
    -------
    list of str
        Constraint names in order.

    Raises
    ------
    DesignError
        If ``layout`` is unknown (only when ``search`` is false).
    """
    names = ["outer_diameter", "housing_length", "charge_p1", "charge_p2", "mean_stiffness",
             "gas_left_at_full_stroke", "bladder_room_compressed", "bladder_room_expanded", "bladder_channel_room",
             "chamber2_port_room", "piston_seal_fit", "valve_bore_reach", "wall_capacity"]
    names += get_layout(layout).own_constraints
    if req.buildable:
        names.append("joint_capacity")
        if req.fixed.piston_pocket:
            names.append("piston_floor_room")
        if req.max_parasitic_damping_N_s_per_mm is not None:
            names.append("parasitic_damping")
    if search:
        names.remove("charge_p2")
    else:
        names += [f"wall_safety_{w}" for w in _walls(layout, req.fixed)]
    if req.max_mass_g is not None:
        names.append("mass")
    if req.max_linearity_adiabatic is not None:
        names += [f"linearity_adiabatic[{i}]" for i in range(8)] if search else ["linearity_adiabatic"]
    if req.max_bladder_strain is not None:
        names.append("bladder_strain")
    return names


def _margin(d: dict):
    v, lim = d["value"], d["limit"]
    scale = d.get("scale")
    if scale is None:
        if isinstance(lim, (float, int)):  # a scalar limit (float64 arithmetic either way: the same values)
            scale = float(abs(lim)) if lim != 0 else 1.0
        else:
            scale = np.where(np.asarray(lim) != 0, np.abs(lim), 1.0)
    if d["kind"] == "max":
        return (lim - v) / scale
    return (v - lim) / scale


def constraint_margins(design: Design, req: Requirements) -> dict[str, float]:
    """Just the margins (positive = satisfied) of ``design`` against ``req``.

    Parameters
    ----------
    design : Design
        The design as charged.
    req : Requirements
        The limits (without ``max_bladder_strain``: this passes no strain).

    Returns
    -------
    dict of str to float
        Constraint name -> scaled margin, dimensionless (> 0 met).

    Raises
    ------
    ValueError
        If ``req.max_bladder_strain`` is set (use :func:`evaluate_design` with the strain).
    """
    return evaluate_design(design, req).margins
