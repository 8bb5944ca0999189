"""The FE check of a unit's pieces (the main job's step): every layout, the typed result, the pictures."""

import json
import math

import pytest

from tests.cad.cases import OTHERS, POCKET, REFERENCE
from vvea_design.cad.assembly import CadModel
from vvea_design.cad.layout import Layout
from vvea_design.cad.parts import piston
from vvea_design.cad.registry import PartContext
from vvea_design.materials.structural import get_material
from vvea_design.structure import check_structure, default_load_cases
from vvea_design.structure.closed_form import lame
from vvea_design.structure.loads import P_ATM_MPa


def _model(design) -> CadModel:
    """The machined pieces and the piston only (what the FE reads), without the rest of the CAD set."""
    lay = Layout(design)
    ctx = PartContext(lay)
    solids = {**ctx.housing_pieces, "piston": piston(lay, 0.0)}
    return CadModel(design, lay, solids, {}, None)


@pytest.fixture(scope="module")
def reference(tmp_path_factory):
    out = tmp_path_factory.mktemp("fe")
    return check_structure(_model(REFERENCE), out_dir=out), out


def test_every_piece_and_wall_of_the_bulkhead_unit(reference):
    res, out = reference
    assert [p.piece for p in res.pieces] == ["housing_outer_tube", "housing_inner_tube", "housing_top_cap",
                                             "housing_base", "piston"]
    assert {w.wall for w in res.walls} == {"outer_tube", "inner_tube", "bulkhead", "top_cap", "base", "piston"}
    for w in res.walls:
        assert {c.case for c in w.cases} == {"gas_peak", "gas_charge", "fluid_relief"}
        g = w.governing
        assert g.safety == pytest.approx(get_material(REFERENCE.fixed.rod_material if w.wall == "piston" else
                                                      REFERENCE.fixed.housing_material).yield_MPa / g.peak.tresca_MPa)
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
    case = next(c for c in default_load_cases(REFERENCE) if c.name == "gas_peak")
    p = case.chamber_2_MPa - P_ATM_MPa
    rb, ro = REFERENCE.outer_bore_radius_mm, REFERENCE.outer_diameter_mm / 2
    nom = next(c for c in w.cases if c.case == "gas_peak").nominal
    assert nom.closed_form_MPa == pytest.approx(float(lame(rb, rb, ro, p)["s_tt"]))
    assert nom.fe_comparable_MPa == pytest.approx(nom.closed_form_MPa, rel=0.02)
    tresca_lame = float(lame(rb, rb, ro, p)["s_tt"]) + p  # hoop minus radial (-p) at the bore, open ends
    assert nom.membrane_bending_tresca_MPa == pytest.approx(tresca_lame, rel=0.04)  # linearised over the wall
    with pytest.raises(KeyError, match="checked:"):
        res.wall("collar")


def test_the_result_is_json_and_names_the_governing_case(reference):
    res, _ = reference
    d = json.loads(json.dumps(res.to_dict()))
    assert set(d["walls"]) == {w.wall for w in res.walls}
    wall = d["walls"]["bulkhead"]
    assert wall["governing_case"] in {"gas_peak", "gas_charge", "fluid_relief"}
    assert wall["location"]["feature"] in {"groove root", "shoulder", "edge", "plain wall"}
    assert wall["safety"] == pytest.approx(wall["yield_MPa"] / wall["peak_tresca_MPa"])
    assert d["criterion"] == "tresca" and len(d["cases"]) == 3 and d["notes"]


def test_the_sharp_bulkhead_root_is_found():
    """The bulkhead's root in the bore is drawn sharp: at the default R0.2 its peak is several times the
    plate's nominal stress; rounded more generously it drops."""
    res = check_structure(_model(REFERENCE), cases=default_load_cases(REFERENCE)[:1])
    sharp = res.wall("bulkhead").governing
    assert sharp.peak.feature == "shoulder" and res.wall("bulkhead").concentration > 2.5
    rounder = check_structure(_model(REFERENCE), cases=default_load_cases(REFERENCE)[:1], corner_radius_mm=0.8)
    assert rounder.wall("bulkhead").governing.peak.tresca_MPa < 0.8 * sharp.peak.tresca_MPa


@pytest.mark.parametrize("name, design, wall", [("annulus_top", OTHERS["annulus_top_short"], "collar"),
                                                ("pocket", POCKET, "piston_floor")])
def test_the_other_layouts_walls(name, design, wall):
    res = check_structure(_model(design), cases=default_load_cases(design)[:1])
    w = res.wall(wall)
    g = w.governing
    assert g.nominal is not None and math.isfinite(g.nominal.closed_form_MPa) and g.nominal.closed_form_MPa > 0
    assert g.peak.tresca_MPa >= g.nominal.membrane_bending_tresca_MPa * 0.99
    assert w.piece == ("housing_inner_tube" if wall == "collar" else "piston")


def test_bad_criterion():
    with pytest.raises(ValueError, match="criterion"):
        check_structure(_model(REFERENCE), criterion="rankine")
