"""One vocabulary: a quantity has one name in the design file, the Design, the derivation and the CAD's Layout.

The design file's keys are the reference (the file stays as it is). A name that is a design quantity means that
quantity everywhere; a Layout radius of a diameter is its ``*_radius_mm``; a CAD feature or a level of the CAD's
frame that happens to equal a design quantity is listed below with the reason.
"""

import inspect
import math
from dataclasses import fields

import pytest

from vvea_design.cad.layout import DEPRECATED_NAMES, Layout
from vvea_design.spring.derive import Derived
from vvea_design.spring.design import Design, FixedParameters
from vvea_design.spring.design_file import design_to_dict
from vvea_design.spring.layouts import all_walls
from vvea_design.spring.problem import evaluate_design
from vvea_design.spring.requirements import Requirements

#: The gas-only rules (tests/spring/rules.py): these designs were sized by them, and the CAD draws them.
GAS_ONLY = FixedParameters(sizing_rules="gas_only")
POCKET = FixedParameters(piston_pocket=True, sizing_rules="gas_only")
DESIGNS = {
    "inner_tube": Design(35.18, 59.5, 47107.0, 99735.0, fixed=GAS_ONLY),
    "bulkhead": Design(35.4, 59.5, 48800.0, 102000.0, layout="bulkhead", V2_top_mm3=3800.0, fixed=GAS_ONLY),
    "annulus_top": Design(34.0, 59.5, 52000.0, 80000.0, layout="annulus_top", V1_annulus_mm3=9000.0, fixed=GAS_ONLY),
    "bulkhead, piston pocket": Design(35.4, 59.5, 48800.0, 102000.0, layout="bulkhead", V2_top_mm3=3800.0,
                                      fixed=POCKET),
    # the buildability rules (the default): a thread joint, the damper's loads, the tolerances
    "bulkhead, buildable": Design(33.155, 59.33, 33650.0, 80180.0, layout="bulkhead", V2_top_mm3=658.0),
    "inner_tube, buildable, ring": Design(33.0, 59.3, 33000.0, 65000.0, joint="ring_top"),
}

#: The wall thickness attribute of each wall (the design file's ``fixed.min_<attribute>`` is its minimum).
WALL_ATTRIBUTES = {"outer_tube": "outer_wall_mm", "inner_tube": "inner_tube_wall_mm", "top_cap": "top_cap_mm",
                   "base": "base_mm", "bulkhead": "bulkhead_mm", "collar": "collar_mm",
                   "piston_floor": "piston_floor_mm"}

#: Layout values that equal a design quantity without being it: levels of the CAD's frame (z = 0 at the base's
#: underside) and CAD features sized from one.
NOT_DESIGN_QUANTITIES = {
    "z_base_top": "a level of the CAD's frame: the base's top face, base_mm above z = 0",
    "z_top": "a level of the CAD's frame: the top face, housing_length_mm above z = 0",
    "cross_port_d": "a CAD feature: the top cap's cross port, at most 1.5 mm (a round number like several)",
    "cuff": "a CAD feature: cad.clamp_groove_fraction of the clamp, 3 mm (a round number like several)",
    "bead_length": "a CAD feature: the sealing bead, at most cad.bead_length_mm = 1.5 mm",
    "z_cap_face": "a level of the CAD's frame: the top cap's outside face (the housing's top, or the ring plug's top)",
    "z_lead_in_bottom": "a level of the CAD's frame: where the outer tube's bottom lead-in starts (the base's top "
                        "face when the tube has no thread)",
    "z_lead_in_top": "a level of the CAD's frame: where the outer tube's top lead-in ends (the housing's top when "
                     "the tube has no thread at that end)",
    "y_port1": "a CAD feature: the chamber-1 valve's offset on the top face (0 on the axis in the bulkhead layout)",
    "relief_seat_d": "a CAD feature: the relief seat drilling, fixed.relief_seat_mm capped by the relief bore",
    "base_own_mm": "a section quantity of the buildability rules (the base below its joint zone, which holds the "
                   "valve bores); under the gas-only rules there is no joint zone and it is the whole base_mm",
}


#: Numbers of the design file that are counts or standard grades, not quantities (a level of the CAD's frame may
#: equal one by chance).
COUNTS_AND_GRADES = {"bore_tolerance_grade", "outside_tolerance_grade", "ring_channels"}


def _file(design: Design) -> dict:
    req = Requirements(fixed=design.fixed)
    return design_to_dict(evaluate_design(design, req), req)


def _design_quantities(design: Design) -> dict[str, float]:
    """Every number of the design file by its key (parameters, fixed, geometry; walls by their attribute)."""
    data = _file(design)
    q = {**data["parameters"], **data["fixed"], **{k: v for k, v in data["geometry"].items() if k != "walls_mm"}}
    q.update({WALL_ATTRIBUTES[w]: t for w, t in data["geometry"]["walls_mm"].items()})
    return {k: v for k, v in q.items() if isinstance(v, (int, float)) and not isinstance(v, bool)
            and k not in COUNTS_AND_GRADES}


def _numbers(obj, names) -> dict[str, float]:
    out = {}
    for name in names:
        try:
            v = getattr(obj, name)
        except AttributeError:  # a feature of another layout (the collar's seal groove in annulus_top only)
            continue
        if isinstance(v, (int, float)) and not isinstance(v, bool):
            out[name] = float(v)
    return out


@pytest.mark.parametrize("label", list(DESIGNS))
def test_the_design_speaks_the_design_files_names(label):
    design = DESIGNS[label]
    data = _file(design)
    for key in (*data["parameters"], *data["geometry"]):
        if key == "walls_mm":
            continue
        owner = design if hasattr(design, key) else design.fixed
        assert hasattr(owner, key), f"the design file's {key} is no attribute of Design"
        v, want = getattr(owner, key), data["parameters"].get(key, data["geometry"].get(key))
        assert v == (want if isinstance(want, str) else pytest.approx(want, rel=1e-12)), key
    # the walls: by wall name in the file, each thickness an attribute whose minimum is fixed.min_<attribute>
    assert set(WALL_ATTRIBUTES) == set(all_walls())
    for wall, t in data["geometry"]["walls_mm"].items():
        attr = WALL_ATTRIBUTES[wall]
        assert f"min_{attr}" in data["fixed"] and getattr(design, attr) == pytest.approx(t, rel=1e-12)
    assert data["geometry"]["walls_mm"] == design.walls_mm() == data["performance"]["walls_mm"]


@pytest.mark.parametrize("label", list(DESIGNS))
def test_the_derivation_speaks_the_designs_names(label):
    """A derived quantity the Design (or its fixed parameters) shows has the same name there; the layout's own
    quantities too; the rest are the derivation's intermediates, listed."""
    design = DESIGNS[label]
    g = design.derived
    intermediates = {"layout", "peak_chamber_1_MPa", "peak_chamber_2_MPa", "chamber_difference_MPa",
                     "inner_tube_net_pressure_MPa", "wall_capacity_value_MPa", "wall_capacity_limit_MPa",
                     "bladder_shift_compressed_mm", "bladder_shift_expanded_mm", "bladder_clearance_compressed_mm",
                     "bladder_clearance_expanded_mm", "bladder_cast_gap_mm", "buildable", "inner_tube_buckling_MPa",
                     "inner_tube_cut_mm3",
                     # the buildability rules' intermediates: the sized section, the checks per case, the flow path
                     "section", "check", "governing", "hydraulic_path",
                     # the room the CAD needs for the chamber-2 fill port (the chamber2_port_room constraint's value)
                     "chamber2_port_room_mm"}
    for f in fields(Derived):
        v = getattr(g, f.name)
        if f.name in intermediates or isinstance(v, dict) or v is None:
            continue
        owner = design if hasattr(design, f.name) else design.fixed
        assert hasattr(owner, f.name), f"Derived.{f.name} is not a Design quantity: name it as the Design does"
        assert getattr(owner, f.name) == v, f.name
    for name, v in g.layout_quantities.items():
        assert getattr(design, name) == v, name
    assert g.walls_mm == design.walls_mm() and g.masses_g == design.mass_breakdown_g()
    assert g.stresses_MPa == design.wall_stresses_MPa() and g.safety_factors == design.wall_safety_factors()


def _layout_problems(lay: Layout, design: Design) -> list[str]:
    """Where ``lay`` (a CAD Layout) names a design quantity otherwise than the design does."""
    problems = []
    quantities = _design_quantities(design)
    quantities.update(_numbers(design, [n for n, v in inspect.getmembers(Design) if isinstance(v, property)
                                        and not n.startswith("_")]))
    names = [n for n, v in inspect.getmembers(type(lay)) if isinstance(v, property) and not n.startswith("_")]
    values = _numbers(lay, [n for n in names if n not in DEPRECATED_NAMES])
    for name, v in values.items():
        if name in COUNTS_AND_GRADES:  # a count named as the design file names it (ring_channels), not a length
            continue
        if name in quantities:  # the design's name: the design's value
            if not math.isclose(v, quantities[name], rel_tol=1e-12, abs_tol=1e-12):
                problems.append(f"Layout.{name} = {v} but the design's {name} = {quantities[name]}")
            continue
        if name.endswith("_radius_mm"):  # half a diameter of the design, named after it
            stem = name[: -len("_radius_mm")]
            diameter = quantities.get(f"{stem}_diameter_mm", quantities.get(f"{stem}_mm"))
            if diameter is None or not math.isclose(v, diameter / 2, rel_tol=1e-12):
                problems.append(f"Layout.{name}: not half of the design's {stem}_diameter_mm (or {stem}_mm)")
            continue
        same = sorted(k for k, q in quantities.items() if math.isclose(v, q, rel_tol=1e-12, abs_tol=1e-12)
                      or (k.endswith(("_diameter_mm", "_outer_mm", "_bore_mm"))
                          and math.isclose(v, q / 2, rel_tol=1e-12)))
        if same and name not in NOT_DESIGN_QUANTITIES:
            problems.append(f"Layout.{name} = {v} is the design's {same}: name it as the design file does "
                            "(or list why it is not)")
    for old, new in DEPRECATED_NAMES.items():  # the old names still answer, with the new names' values
        if getattr(lay, old) != getattr(lay, new) or new not in values:
            problems.append(f"deprecated Layout.{old} is not Layout.{new}")
    return problems


@pytest.mark.parametrize("label", list(DESIGNS))
def test_every_cad_layout_quantity_of_the_design_has_the_design_files_name(label):
    design = DESIGNS[label]
    assert _layout_problems(Layout(design), design) == []


def test_the_vocabulary_check_catches_a_second_name():
    """A Layout property that mirrors a design quantity under another name fails the check above."""
    class Renamed(Layout):
        @property
        def bore_radius(self):  # the design file's outer_bore_radius_mm under another name
            return self.design.outer_bore_radius_mm

    design = DESIGNS["inner_tube"]
    problems = _layout_problems(Renamed(design), design)
    assert len(problems) == 1 and "Layout.bore_radius" in problems[0] and "outer_bore_radius_mm" in problems[0]
