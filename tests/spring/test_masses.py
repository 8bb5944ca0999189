"""One mass: the closed-form volume of every made part equals the CAD's solid, part by part (to 0.5 %), each
part weighed in its own material (the steel piston at steel density), the joint's parts, the oil and the servo
listed beside them.

A gas-only design is drawn with its pieces split by planes: the closed form is compared in that drawing
(``spec = "today"``). A buildable design is drawn with its joint (threads, run-outs, the ring's plug and groove, the
tie rods' holes): the closed form with the joint's zones (:func:`part_masses_g`) is compared. Every joint of every
layout is drawn (the default run one per joint, the slow run the rest)."""

import math
from dataclasses import replace

import numpy as np
import pytest

from vvea_design.materials.structural import get_material
from vvea_design.spring.derive import _mass_geometry
from vvea_design.spring.design import Design, FixedParameters
from vvea_design.spring.hydraulics import BEAD_HEIGHT_MM, COLLECTOR_DEPTH_MAX_MM
from vvea_design.spring.masses import CAD_FEATURES, dynamic_gland_mm, overlap_mm3, part_volumes_mm3

GAS_ONLY = FixedParameters(sizing_rules="gas_only")
#: a 70 mm envelope sealed with the 2.62 mm series (no 1.78 mm ring fits its tie rods' tube bore)
WIDE = FixedParameters(joint_seal_cross_section_mm=2.62)
DRAWN = {
    "bulkhead, gas-only": Design(35.4, 59.5, 48800.0, 102000.0, layout="bulkhead", V2_top_mm3=3800.0, fixed=GAS_ONLY),
    "inner_tube, buildable, ring": Design(33.0, 59.3, 33000.0, 65000.0, joint="ring_top"),
    # the buildable joints of every layout (issue 23: one mass, the optimiser's = the CAD's, part by part)
    "bulkhead, buildable, thread": Design(33.155, 59.33, 33650.0, 80180.0, layout="bulkhead", V2_top_mm3=658.0),
    "inner_tube, buildable, tie rods": Design(30.0, 70.0, 33000.0, 80000.0, joint="tie_rods", fixed=WIDE),
    "annulus_top, buildable, thread": Design(32.0, 59.3, 30000.0, 60000.0, layout="annulus_top",
                                             V1_annulus_mm3=4000.0),
}
SLOW = {
    "annulus_top, gas-only": Design(34.373592304325015, 65.0, 45706.09615792426, 108669.22305813522,
                                    layout="annulus_top", V1_annulus_mm3=12516.61122629605,
                                    fixed=FixedParameters(travel_mm=50.0, sizing_rules="gas_only")),
    "bulkhead, pocket, gas-only": Design(36.25872487311745, 59.5, 55396.278750715785, 111402.24160741588,
                                         layout="bulkhead", V2_top_mm3=9391.457271224454,
                                         fixed=FixedParameters(piston_pocket=True, fluid_clearance_mm=0.5,
                                                               min_base_mm=11.0, sizing_rules="gas_only",
                                                               bladder_cast_fill=0.14958958987549847)),
    "bulkhead, buildable, pocket": Design(33.0, 59.3, 33000.0, 75000.0, layout="bulkhead", V2_top_mm3=500.0,
                                          fixed=FixedParameters(piston_pocket=True)),
    "inner_tube, buildable, thread": Design(33.0, 59.3, 33000.0, 75000.0, joint="thread"),
    # (bulkhead with ring_top is not built: spring.joints.EXCLUDED_PAIRS)
    "bulkhead, buildable, tie rods": Design(30.0, 70.0, 33000.0, 80000.0, layout="bulkhead", V2_top_mm3=658.0,
                                            joint="tie_rods", fixed=WIDE),
    "annulus_top, buildable, ring": Design(32.0, 59.3, 30000.0, 60000.0, layout="annulus_top",
                                           V1_annulus_mm3=4000.0, joint="ring_top"),
    "annulus_top, buildable, tie rods": Design(30.0, 70.0, 50000.0, 80000.0, layout="annulus_top",
                                               V1_annulus_mm3=4000.0, joint="tie_rods",
                                               fixed=replace(WIDE, min_collar_mm=5.1)),  # the collar's 2.62 ring
}


def _today(design: Design) -> dict:
    """The closed form of the drawing today's CAD makes of ``design``."""
    g = design.derived
    sec = g.section
    from vvea_design.spring.derive import Stack

    stack = Stack(g.chamber1_length_mm, g.fluid_column_mm, g.inner_length_mm, g.housing_length_mm,
                  g.bladder_free_length_mm, g.rod_length_mm, None)
    bl = {"bladder_inner_radius_mm": g.bladder_inner_radius_mm, "bladder_outer_radius_mm": g.bladder_outer_radius_mm}
    geo = _mass_geometry(sec, stack, bl, g.layout_quantities, design.fixed)
    geo["base_own"] = geo["base"]
    return {k: float(v) for k, v in part_volumes_mm3({k: np.asarray(v, dtype=float) for k, v in geo.items()},
                                                     design.fixed, design.variant, "today").items()}


def _with_joint(design: Design) -> dict:
    """The closed form of the drawing the CAD makes of a design with a joint (the joint's zones drawn), mm³."""
    from vvea_design.materials.structural import DENSITY_SILICONE_g_per_mm3

    m = design.mass_breakdown_g()
    f = design.fixed
    rho = {"piston": get_material(f.rod_material).density_g_per_mm3, "bladder": DENSITY_SILICONE_g_per_mm3,
           "support_ring": get_material(f.support_ring_material).density_g_per_mm3}
    parts = ("housing_base", "housing_outer_tube", "housing_inner_tube", "housing_top_cap", "piston", "bladder",
             "support_ring")
    return {k: m[k] / rho.get(k, get_material(f.housing_material).density_g_per_mm3) for k in parts}


def _compare(design: Design):
    """The CAD's solids against the closed form of what it draws, every made part: the plain split for a gas-only
    design, the joint's zones for a buildable one (the CAD draws them). The issue asks 0.5 %; the closed form keeps
    every part within 0.25 % (the O-ring sizes the CAD picks per bore are mirrored by nominal gland depths)."""
    from vvea_design.cad import build_cad

    model = build_cad(design)
    cad = {k: float(s.volume) for k, s in {**model.parts, **model.housing_pieces}.items()}
    buildable = design.fixed.sizing_rules != "gas_only"
    closed = _with_joint(design) if buildable else _today(design)
    assert set(closed) == {"housing_base", "housing_outer_tube", "housing_inner_tube", "housing_top_cap", "piston",
                           "bladder", "support_ring"}
    for part, v in closed.items():
        assert v == pytest.approx(cad[part], rel=2.5e-3), part
    for part in ("bladder", "support_ring"):  # drawn the same way by both: exact
        assert closed[part] == pytest.approx(cad[part], rel=1e-9), part
    return closed


@pytest.mark.parametrize("label", list(DRAWN))
def test_closed_form_volumes_are_the_cads_part_by_part(label):
    _compare(DRAWN[label])


@pytest.mark.slow
@pytest.mark.parametrize("label", list(SLOW))
def test_closed_form_volumes_are_the_cads_part_by_part_slow(label):
    _compare(SLOW[label])


def test_each_part_in_its_own_material_and_the_sum_is_the_mass():
    d = DRAWN["inner_tube, buildable, ring"]
    m = d.mass_breakdown_g()
    assert {"housing_base", "housing_outer_tube", "housing_inner_tube", "housing_top_cap", "piston", "bladder",
            "support_ring", "retaining_ring", "fluid", "servo_and_valve"} <= set(m)
    assert sum(m.values()) == pytest.approx(d.mass_g)
    # the piston and its rod are one turned part in the rod's steel (not the housing's aluminium)
    g = d.derived
    rp, rr = d.piston_diameter_mm / 2, d.fixed.rod_diameter_mm / 2
    dep, wid = dynamic_gland_mm(1.78)
    # the rod end's lead-in for the rod seal (ISO 3601-2): radial depth over the ring's protrusion + its tolerance
    # + 0.1, the makers' 2.10 mm at 15 deg or the depth at 15 deg; a triangle revolved at its centroid
    li_depth = round(1.78 - dep + 0.08 + 0.1, 2)
    li_length = max(2.10, li_depth / math.tan(math.radians(15.0)))
    lead_in = 2 * math.pi * (rr - li_depth / 3) * 0.5 * li_depth * li_length
    v = (math.pi * rp**2 * d.fixed.piston_height_mm + math.pi * rr**2 * g.rod_length_mm
         - 2 * math.pi * (rp**2 - (rp - dep) ** 2) * wid - math.pi * 2.1**2 * 10.0 - lead_in)
    assert m["piston"] == pytest.approx(v * get_material("steel-42crmo4").density_g_per_mm3)
    assert m["retaining_ring"] == pytest.approx([j for j in d.joints() if j.kind == "ring_top"][0].mass_g)


def test_the_joints_zones_move_volume_between_the_pieces_and_keep_the_sum():
    """A thread joint moves the ring outside its spigot from the end piece to the tube; the sum of the housing's
    pieces changes only by the undercut, the seal grooves and (ring) the space above the plug."""
    d = Design(33.155, 59.33, 33650.0, 80180.0, layout="bulkhead", V2_top_mm3=658.0)
    m = d.mass_breakdown_g()
    housing = sum(m[k] for k in ("housing_base", "housing_outer_tube", "housing_inner_tube", "housing_top_cap"))
    rho = get_material("al-6061-t6").density_g_per_mm3
    today = _today(d)
    plain = sum(today[k] for k in ("housing_base", "housing_outer_tube", "housing_inner_tube", "housing_top_cap"))
    assert housing < plain * rho and housing > 0.97 * plain * rho
    assert m["housing_outer_tube"] > today["housing_outer_tube"] * rho  # the tube runs over both spigots


def test_the_mirrored_cad_features_are_the_cads():
    from vvea_design.cad.layout import CadParameters

    c = CadParameters()
    for k, v in CAD_FEATURES.items():
        assert getattr(c, k) == v, k
    assert c.bead_height_mm == BEAD_HEIGHT_MM
    f = FixedParameters()
    for k in ("throttle_bore_mm", "relief_bore_mm", "relief_seat_mm", "fluid_channel_mm", "ring_channel_mm",
              "ring_channels"):
        assert getattr(c, k) == getattr(f, k), k  # the hydraulics' sizes: the CAD's defaults (it should read ours)
    assert COLLECTOR_DEPTH_MAX_MM == 1.0


def test_overlap_of_crossing_drillings_by_hand():
    # a drilling of radius a << R starting on the axis of a bore: about pi a^2 R
    assert float(overlap_mm3(0.1, 3.0)) == pytest.approx(math.pi * 0.01 * 3.0, rel=2e-3)
    # equal radii: 16 a^3 / 3 / 2 (half the Steinmetz solid)
    assert float(overlap_mm3(1.0, 1.0)) == pytest.approx(16 / 3 / 2, rel=1e-6)
    assert float(overlap_mm3(1.5, 1.25)) == pytest.approx(float(overlap_mm3(1.25, 1.5)), rel=1e-9)


def test_replaced_fixed_keep_the_mass_model_consistent():
    d = DRAWN["inner_tube, buildable, ring"]
    heavy = replace(d, fixed=replace(d.fixed, housing_material="al-7075-t6"))
    assert heavy.mass_breakdown_g()["piston"] == pytest.approx(d.mass_breakdown_g()["piston"], rel=0.05)


def test_the_ring_series_the_closed_form_expects_is_the_cads():
    """The closed form mirrors which O-ring series the CAD seats in a static male gland per bore (ISO 3601-1 sizes,
    the static squeeze window, 0-5 % stretch): both agree over the bores of the envelopes, and the 2.62 mm series
    takes over where no 1.78 mm ring fits."""
    from vvea_design.cad.seals import SERIES, SealError, static_male_gland
    from vvea_design.spring.joints import SERIES_MM, static_male_cross_section_mm

    assert tuple(SERIES) == SERIES_MM
    bores = np.round(np.arange(40.0, 80.0, 0.07), 3)
    ours = static_male_cross_section_mm(bores, 1.78)
    seen = set()
    for bore, cs in zip(bores, ours):
        try:
            cad = static_male_gland(float(bore), 1.78).oring.cross_section_mm
        except SealError:
            continue
        assert cad == cs, bore
        seen.add(float(cs))
    assert seen == {1.78, 2.62}
