"""The FE check of a unit's pieces (the main job's step): every layout, the typed result, the pictures."""

import json
import math

from dataclasses import replace

import pytest

from tests.cad.cases import BULKHEAD, JOINTS, OTHERS, POCKET
from vvea_design.cad.assembly import CadModel
from vvea_design.cad.layout import BULKHEAD_ROOT_RADIUS_MM, Layout
from vvea_design.cad.parts import piston
from vvea_design.cad.registry import PartContext
from vvea_design.materials.structural import get_material
from vvea_design.structure import check_structure, default_load_cases
from vvea_design.spring.design import Design
from vvea_design.structure.closed_form import lame
from vvea_design.structure.pieces import _end_bearings

#: The cupped-piston optimum as the CAD of this branch draws it (its walls from the gas-only rules it was made with).
GAS_ONLY_POCKET = replace(POCKET, fixed=replace(POCKET.fixed, sizing_rules="gas_only"))


def _model(design) -> CadModel:
    """The machined pieces and the piston only (what the FE reads), without the rest of the CAD set."""
    lay = Layout(design)
    ctx = PartContext(lay)
    solids = {**ctx.housing_pieces, "piston": piston(lay, 0.0)}
    return CadModel(design, lay, solids, {}, None)


@pytest.fixture(scope="module")
def reference(tmp_path_factory):
    out = tmp_path_factory.mktemp("fe")
    return check_structure(_model(BULKHEAD), out_dir=out), out


def test_every_piece_and_wall_of_the_bulkhead_unit(reference):
    res, out = reference
    assert [p.piece for p in res.pieces] == ["housing_outer_tube", "housing_inner_tube", "housing_top_cap",
                                             "housing_base", "piston"]
    assert {w.wall for w in res.walls} == {"outer_tube", "inner_tube", "bulkhead", "top_cap", "base", "piston"}
    names = {c.name for c in BULKHEAD.load_cases.cases}
    assert names >= {"gas_full_stroke", "gas_rest", "retraction", "relief", "damping", "proof"}
    for w in res.walls:
        assert {c.case for c in w.cases} == names
        g = w.governing
        assert g.safety == pytest.approx(get_material(BULKHEAD.fixed.rod_material if w.wall == "piston" else
                                                      BULKHEAD.fixed.housing_material).yield_MPa / g.peak.tresca_MPa)
        assert w.passes == all(c.safety >= c.required_safety for c in w.cases)
    assert res.passes == all(w.passes for w in res.walls)
    for p in res.pieces:  # the joints' reactions balance the pressures: the pin carries nothing
        assert p.elements > 100 and p.element_size_mm > 0
        assert p.figure and (out / f"fe_{p.piece}.png").is_file()
    base = next(p for p in res.pieces if p.piece == "housing_base")
    assert base.volume_fraction < 0.99  # the valve bores are not in the axisymmetric model (and say so)
    assert any("housing_base" in n for n in res.notes)


def test_the_outer_tube_agrees_with_lame_away_from_its_ends(reference):
    res, _ = reference
    w = res.wall("outer_tube")
    case = next(c for c in default_load_cases(BULKHEAD) if c.name == "gas_rest")  # no end load from the cap? see below
    p = case.chamber_2_MPa
    rb, ro = BULKHEAD.outer_bore_radius_mm, BULKHEAD.outer_diameter_mm / 2
    nom = next(c for c in w.cases if c.case == "gas_rest").nominal
    assert nom.closed_form_MPa == pytest.approx(float(lame(rb, rb, ro, p)["s_tt"]))
    assert nom.fe_comparable_MPa == pytest.approx(nom.closed_form_MPa, rel=0.02)
    tresca_lame = float(lame(rb, rb, ro, p)["s_tt"]) + p  # hoop minus radial (-p) at the bore (closed ends too)
    assert nom.membrane_bending_tresca_MPa == pytest.approx(tresca_lame, rel=0.04)  # linearised over the wall
    # the threaded joint makes it a closed-ended tube: the cap's load (the seal circle's pressure) in its wall
    sol_axial = float(lame(rb, rb, ro, p)["s_zz_closed"])
    assert sol_axial > 0
    with pytest.raises(KeyError, match="checked:"):
        res.wall("collar")


def test_the_result_is_json_and_names_the_governing_case(reference):
    res, _ = reference
    d = json.loads(json.dumps(res.to_dict()))
    assert set(d["walls"]) == {w.wall for w in res.walls}
    wall = d["walls"]["bulkhead"]
    assert wall["governing_case"] in {c.name for c in BULKHEAD.load_cases.cases}
    assert wall["location"]["feature"] in {"groove root", "shoulder", "edge", "plain wall"}
    assert wall["safety"] == pytest.approx(wall["yield_MPa"] / wall["peak_tresca_MPa"])
    assert d["criterion"] == "tresca" and len(d["cases"]) == len(BULKHEAD.load_cases.cases) and d["notes"]
    assert wall["peak_over_sizing"] > 0  # (> 1 at a sharp root: test_the_sharp_bulkhead_root_is_found)
    w = res.wall("bulkhead")
    assert wall["peak_over_sizing"] == pytest.approx(max(c.peak.tresca_MPa / c.sizing_stress_MPa for c in w.cases))
    cap = d["pieces"]["housing_top_cap"]
    assert set(cap["bearings"]) == {c.name for c in BULKHEAD.load_cases.cases}


def test_the_sharp_bulkhead_root_is_found():
    """The bulkhead's root in the bore is drawn sharp: at a turning tool's least nose radius (R0.2) its peak is
    several times the plate's nominal stress; with the drawing's root radius (R3, the default) it drops."""
    first = default_load_cases(BULKHEAD)[:1]
    res = check_structure(_model(BULKHEAD), cases=first, corner_radius_mm=0.2)
    sharp = res.wall("bulkhead").governing
    assert sharp.peak.feature == "shoulder" and res.wall("bulkhead").concentration > 2.5
    assert res.wall("bulkhead").peak_over_sizing > 1  # the sharp root: the sizing's plate formula misses it
    rounder = check_structure(_model(BULKHEAD), cases=first)
    assert rounder.corner_radius_mm is None
    g = rounder.wall("bulkhead").governing
    assert g.peak.corner_radius_mm == pytest.approx(BULKHEAD_ROOT_RADIUS_MM, abs=0.01)
    assert g.peak.tresca_MPa < 0.8 * sharp.peak.tresca_MPa


@pytest.mark.parametrize("name, design, wall", [("annulus_top", OTHERS["annulus_top_short"], "collar"),
                                                ("pocket", GAS_ONLY_POCKET, "piston_floor")])
def test_the_other_layouts_walls(name, design, wall):
    res = check_structure(_model(design), cases=default_load_cases(design)[:1])
    w = res.wall(wall)
    g = w.governing
    assert g.nominal is not None and math.isfinite(g.nominal.closed_form_MPa) and g.nominal.closed_form_MPa > 0
    assert g.peak.tresca_MPa >= g.nominal.membrane_bending_tresca_MPa * 0.99
    assert w.piece == ("housing_inner_tube" if wall == "collar" else "piston")


def test_the_threaded_tube_carries_the_caps_load():
    """With the thread joint the outer tube is closed-ended: its axial membrane stress is the cap's load over
    its wall; with tie rods the end pieces bear on the nuts' ring and the tube carries only the rods' clamp force."""
    threaded = JOINTS["thread_inner_tube"]  # the CAD draws its threads (the gas-only bulkhead has none)
    case = default_load_cases(threaded)[:1]
    res = check_structure(_model(threaded), cases=case)
    tube = next(p for p in res.pieces if p.piece == "housing_outer_tube")
    cap = next(p for p in res.pieces if p.piece == "housing_top_cap")
    name = case[0].name
    assert "thread" in cap.bearings[name] and not cap.not_drawn
    assert "thread" in next(p for p in res.pieces if p.piece == "housing_base").bearings[name]
    assert "thread" in tube.bearings[name]
    assert tube.reactions_N[name] == pytest.approx(-(abs(cap.reactions_N[name]) + max(case[0].external_force_N, 0)),
                                                   rel=1e-6)
    # tie rods (a buildable design's joint record; the CAD draws the gas-only bulkhead's section)
    rods = next(j for j in Design(28.0, 58.6, 20000.0, 50000.0, layout="bulkhead", V2_top_mm3=402.0,
                                  joint="tie_rods").joints() if j.kind == "tie_rods")
    lay = Layout(BULKHEAD)
    for end, push in (("top_cap", -1), ("base", +1)):
        first, fallback = _end_bearings(lay, rods, end)
        assert "nuts" in first.what and first.pushes == push
        assert first.r_mm[0] == pytest.approx(rods.rod_circle_radius_mm - rods.nut_width_across_flats_mm / 2)
        assert "not drawn" in fallback.what and fallback.r_mm == (lay.outer_bore_radius_mm, lay.outer_radius_mm)


def test_bad_criterion():
    with pytest.raises(ValueError, match="criterion"):
        check_structure(_model(BULKHEAD), criterion="rankine")
