"""Which input field sets each constraint: an infeasible result named by what the user can edit.

A constraint the least-violating design misses (``mean_stiffness``), or one that holds it back (``charge_p2`` at
its limit), is a derived quantity; the user edits requirements and ``[fixed]`` fields. :data:`CONSTRAINT_FIELDS`
traces each constraint back to the fields that set its limit or its value, and :func:`explain_infeasible` words
it: the field, its value, what the best design found reaches (the value that field would have to take), and the
fields of the constraints that hold the design back.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from ..messages import show

if TYPE_CHECKING:
    from .problem import Evaluation
    from .requirements import Requirements

__all__ = ["CONSTRAINT_FIELDS", "LIMIT_FIELD", "fields_of", "explain_infeasible"]

#: constraint (or its prefix) -> the requirements / ``[fixed]`` fields that set it (``fixed.`` = a ``[fixed]`` field).
CONSTRAINT_FIELDS: dict[str, tuple[str, ...]] = {
    "outer_diameter": ("max_outer_diameter_mm",),
    "housing_length": ("max_housing_length_mm", "travel_mm", "fixed.min_top_cap_mm", "fixed.min_base_mm",
                       "fixed.piston_height_mm", "fixed.fluid_clearance_mm"),
    "charge_p1": ("max_charge_MPa", "setpoint_x0_mm"),
    "charge_p2": ("max_charge_MPa",),
    "mean_stiffness": ("min_mean_stiffness_N_per_mm", "max_charge_MPa", "travel_mm"),
    "gas_left_at_full_stroke": ("min_gas_fraction_at_full_stroke", "travel_mm"),
    "bladder_room": ("fixed.bladder_thickness_mm", "fixed.bladder_min_gap_mm", "fixed.bladder_bulge_factor"),
    "bladder_channel_room": ("fixed.ring_channel_mm", "fixed.bladder_thickness_mm"),
    "chamber2_port_room": ("max_outer_diameter_mm", "fixed.bladder_thickness_mm", "fixed.joint_seal_cross_section_mm"),
    "piston_seal_fit": ("bounds.piston_diameter_mm",),
    "valve_bore_reach": ("fixed.rod_diameter_mm", "fixed.fluid_channel_mm", "bounds.piston_diameter_mm"),
    "wall_capacity": ("max_charge_MPa", "min_wall_safety_factor", "fixed.housing_material", "fixed.wall_sizing_n"),
    "wall_safety": ("min_wall_safety_factor", "max_charge_MPa", "fixed.housing_material"),
    "joint_capacity": ("joints", "fixed.tie_rod_property_class", "max_charge_MPa"),
    "piston_floor_room": ("fixed.piston_pocket", "fixed.min_piston_floor_mm"),
    "cross_slot_room": ("fixed.cross_slot_mm", "fixed.cross_slot_fraction", "layouts"),
    "parasitic_damping": ("max_parasitic_damping_N_s_per_mm", "fixed.fluid_channel_mm", "fixed.throttle_bore_mm",
                          "fixed.ring_channel_mm", "fixed.oil", "fixed.oil_temperature_C"),
    "mass": ("max_mass_g", "fixed.servo_and_valve_mass_g"),
    "linearity_adiabatic": ("max_linearity_adiabatic",),
    "bladder_strain": ("max_bladder_strain", "bladder_material"),
}

#: constraint -> the requirement that *is* its limit (the best design's value is what that field would accept).
LIMIT_FIELD: dict[str, str] = {
    "outer_diameter": "max_outer_diameter_mm", "housing_length": "max_housing_length_mm",
    "mean_stiffness": "min_mean_stiffness_N_per_mm", "gas_left_at_full_stroke": "min_gas_fraction_at_full_stroke",
    "parasitic_damping": "max_parasitic_damping_N_s_per_mm", "mass": "max_mass_g",
    "linearity_adiabatic": "max_linearity_adiabatic", "bladder_strain": "max_bladder_strain",
}


def fields_of(constraint: str) -> tuple[str, ...]:
    """The fields that set ``constraint`` (``wall_safety_base`` -> those of ``wall_safety``); () if unknown.

    Parameters
    ----------
    constraint : str
        A constraint name of :func:`~vvea_design.spring.problem.constraint_names`.

    Returns
    -------
    tuple of str
        Requirement names, ``fixed.<name>`` fields and ``bounds.<name>`` search ranges, the limit's own field first.
    """
    if constraint in CONSTRAINT_FIELDS:
        return CONSTRAINT_FIELDS[constraint]
    for prefix, names in CONSTRAINT_FIELDS.items():
        if constraint.startswith(prefix):
            return names
    return ()


def _value(req: Requirements, name: str) -> str:
    if name.startswith("bounds."):  # a search range: the user's [bounds] entry, else it follows the requirements
        key = name[7:]
        given = req.bounds.get(key)
        return f"[bounds] {key} = {show(list(given)) if given is not None else '(not set: follows the envelope)'}"
    obj, key = (req.fixed, name[6:]) if name.startswith("fixed.") else (req, name)
    v = getattr(obj, key, None)
    label = f"[fixed] {key}" if name.startswith("fixed.") else key
    return f"{label} = {show(list(v) if isinstance(v, tuple) else v)}"


def explain_infeasible(ev: Evaluation, req: Requirements, tol: float = 1e-3) -> list[str]:
    """Lines naming the fields behind each missed constraint and behind what holds the best design back.

    Parameters
    ----------
    ev : Evaluation
        The least-violating design, evaluated.
    req : Requirements
        The requirements it was searched for.
    tol : float
        Margin (scaled, dimensionless) at or below which a satisfied constraint counts as holding it back.

    Returns
    -------
    list of str
        Per missed constraint: ``"  <constraint> is set by <field> = <value>, ...; the best design found reaches
        <value>: <field> <=/>= that would accept it"``; then one line naming the constraints at their limit
        (and their fields) that keep the design from doing better.
    """
    lines = []
    for name, m in sorted(ev.margins.items(), key=lambda kv: kv[1]):
        if m >= -1e-9:
            continue
        names = fields_of(name)
        if not names:
            continue
        d = ev.details[name]
        line = f"  {name} is set by " + ", ".join(_value(req, n) for n in names)
        limit = LIMIT_FIELD.get(name)
        if limit is not None and getattr(req, limit, None) is not None:
            rel = "<=" if d["kind"] == "max" else ">="
            near = float(d["value"])
            line += (f"; the best design found reaches {near:.4g} {d['unit']}: {limit} {'>=' if rel == '<=' else '<='} "
                     f"{near:.4g} would accept it (with the other misses fixed)")
        lines.append(line)
    held = [n for n, m in ev.margins.items() if -1e-9 <= m <= tol and fields_of(n)]
    if held:
        lines.append("  what holds it back (at its limit): " + "; ".join(
            f"{n} ({', '.join(_value(req, f) for f in fields_of(n)[:3])})" for n in held))
    return lines
