"""Every feature of every machined part is on its sheet with a dimension and a tolerance (issue 23).

The features come from the part's definition (the part table's feature hook, from the layout the solids are
built from), not from the sheet; each is checked against the solid both ways:

* it is in the solid: the edges it makes are edges of the part's section, the material it removes is not
  in the solid;
* nothing is left out: every edge of the part's section is made by a listed feature;

and found on the part's sheet: its annotation's text gives its size and its tolerance (or the general
tolerance ISO 2768-m the sheet states), its dimensions' anchors lie on the drawn outline. For every machined
part of every layout: bulkhead (the reference, the bladder cast near x = 0, the cupped piston), inner_tube and
annulus_top, and every joint the buildability rules size (thread, ring_top, tie_rods).
"""

from __future__ import annotations

import pytest
from build123d import Vector

from tests.cad.cases import DESIGNS, JOINTS, POCKET, REFERENCE, SLOW
from vvea_design.cad import PARTS, build_cad
from vvea_design.cad.drafting import Dim, Leader
from vvea_design.cad.features import GENERAL, Feature, missing_edges, sheet_plane, unexplained_edges
from vvea_design.cad.section import section_loops
from vvea_design.report.drawing import check_anchors, sheet_specs

#: One design per layout (and the cupped piston): the part lists differ per layout.
CASES = {"reference": REFERENCE, "cast_fill_free": DESIGNS["cast_fill_free"],
         "annulus_top_short": DESIGNS["annulus_top_short"], "inner_tube_k50": SLOW["pareto_k50"],
         "cupped_piston": POCKET, **JOINTS}
DRAWN = [p for p in PARTS if p.drawing is not None]


@pytest.fixture(scope="module", params=list(CASES), ids=list(CASES))
def case(request):
    """(name, model, sheets by part name) of one design."""
    d = CASES[request.param]
    model = request.getfixturevalue("reference_model") if request.param == "reference" else build_cad(d)
    assert model.design == d
    return request.param, model, {s.name: s for s in sheet_specs(model)}


def _loops(model, part):
    solid = model.solids[part.name]
    bb = solid.bounding_box()
    r = max(abs(bb.min.X), abs(bb.max.X), abs(bb.min.Y), abs(bb.max.Y)) + 5.0
    return section_loops(solid, sheet_plane(part.name), -r, r)


def _texts(spec) -> list[str]:
    dims = [*spec.dims, *(spec.detail.dims if spec.detail else [])]
    leaders = [*spec.leaders, *(spec.detail.leaders if spec.detail else [])]
    return [d.label() for d in dims] + [lead.text for lead in leaders] + list(spec.notes)


def test_every_drawn_part_lists_its_features():
    assert {p.name for p in DRAWN} == {"housing_base", "housing_outer_tube", "housing_inner_tube", "housing_top_cap",
                                       "piston"}
    for p in DRAWN:
        assert callable(p.features), p.name


@pytest.mark.parametrize("part", DRAWN, ids=[p.name for p in DRAWN])
def test_every_feature_is_on_its_sheet_with_a_tolerance(case, part):
    name, model, sheets = case
    feats = part.features(model.layout)
    assert feats and all(isinstance(f, Feature) for f in feats)
    assert len({f.key for f in feats}) == len(feats), [f.key for f in feats]
    spec = sheets[part.name]
    texts = _texts(spec)
    general = any(GENERAL in n for n in spec.notes)
    for f in feats:
        assert f.text in texts, (name, part.name, f.key, f.text)
        assert f.size in f.text, (name, part.name, f.key)
        assert f.tolerance in f.text or (f.tolerance == GENERAL and general), (name, part.name, f.key, f.tolerance)
        if isinstance(f.show, Dim):
            assert f.show in [*spec.dims, *(spec.detail.dims if spec.detail else [])]
        elif isinstance(f.show, Leader):
            assert f.show in spec.leaders
    assert check_anchors(spec) == [], name
    kinds = {f.kind for f in feats}
    assert {"length", "diameter"} <= kinds, (name, part.name, kinds)
    if part.name in ("housing_outer_tube", "housing_inner_tube", "piston"):  # an O-ring passes an edge of each
        assert "chamfer" in kinds, (name, part.name)


@pytest.mark.parametrize("part", DRAWN, ids=[p.name for p in DRAWN])
def test_the_features_are_the_solid(case, part):
    """Both ways: every feature's edges are in the section and its material is gone; every section edge is a
    feature's."""
    name, model, _ = case
    feats = part.features(model.layout)
    loops = _loops(model, part)
    assert unexplained_edges(loops, feats) == [], (name, part.name)
    assert missing_edges(loops, feats) == [], (name, part.name)
    solid = model.solids[part.name]
    for f in feats:
        if f.probe is not None:
            assert not solid.is_inside(Vector(*f.probe)), (name, part.name, f.key, f.probe)


def test_a_forgotten_feature_is_found(reference_model):
    """Negative control: drop the top cap's seal groove (or any feature that makes edges) from the list and the
    section has edges no feature explains; claim a groove the solid lacks and its edges are missing."""
    part = next(p for p in PARTS if p.name == "housing_top_cap")
    feats = part.features(reference_model.layout)
    loops = _loops(reference_model, part)
    for f in feats:
        if f.u_edges or f.z_edges or f.slants:
            rest = [g for g in feats if g.key != f.key]
            if any(abs(u - v) < 1e-5 for g in rest for u in f.u_edges for v in g.u_edges) \
                    or any(abs(u - v) < 1e-5 for g in rest for u in f.z_edges for v in g.z_edges):
                continue  # its edges are shared with another feature's (e.g. the thread's tap drill bottom)
            assert unexplained_edges(loops, rest), f.key
    ghost = Feature("ghost", "groove", "groove that is not there", "Ø10.00", GENERAL, "ghost", u_edges=(-5.0, 5.0),
                    z_edges=(-3.0,))
    assert len(missing_edges(loops, [*feats, ghost])) == 3


def test_ports_follow_the_layout(case):
    """The chamber-1 port is on the axis in the bulkhead layout (the fill tube's bore), over the piston in the
    others; the top cap's sheet says so, and the solid has the hole there."""
    name, model, sheets = case
    lay = model.layout
    cap = model.solids["housing_top_cap"]
    z = lay.z_cap + 0.5
    texts = " ".join(_texts(sheets["housing_top_cap"]))
    port1 = next(f for f in model.solids and next(p for p in PARTS if p.name == "housing_top_cap").features(lay)
                 if f.key == "port1")
    if lay.has_bulkhead:
        assert not cap.is_inside(Vector(0.0, 0.0, z))
        assert port1.u_edges == (-lay.r_fill_tube_bore, lay.r_fill_tube_bore)  # on the axis, not at r_port1
        assert "on the axis" in port1.text and port1.text in texts
    else:
        assert not cap.is_inside(Vector(0.0, lay.r_port1, z))
        assert cap.is_inside(Vector(0.0, 0.0, z))
