"""The part table owns each part's drawing and bill-of-materials data (issue 22): every entry with a sheet
carries its drawing hook, every entry its BOM hook or the reason it is not on the bill, and the report
only iterates over the table."""

from __future__ import annotations

import inspect

import pytest

from tests.cad.cases import REFERENCE
from tests.helpers import REPO
from vvea_design.cad import PARTS, BomLine, SheetContent, registry
from vvea_design.cad.bill import BOUGHT_ITEMS, SECTIONS, BomContext
from vvea_design.materials.silicones import get_silicone

#: The parts that get a dimensioned sheet of their own (the committed cad/drawing_<part>.svg files).
DRAWN = ("housing_base", "housing_outer_tube", "housing_inner_tube", "housing_top_cap", "piston")


def test_every_part_has_its_bom_hook_or_a_reason():
    for p in PARTS:
        assert (p.bom is not None) != bool(p.not_on_bom), p.name
        if p.bom is not None:
            assert callable(p.bom) and len(inspect.signature(p.bom).parameters) == 2, p.name
        else:
            assert len(p.not_on_bom) > 10, p.name  # a reason a reader understands, not a flag
    assert {p.name for p in PARTS if p.bom is None} == {"housing", "gas_chamber_1", "gas_chamber_2"}


def test_every_drawn_part_has_its_drawing_hook():
    """The sheets committed in cad/ are exactly the parts whose entry carries a drawing hook, plus the two sheets of
    the whole unit: its section and the exploded assembly order (issue 23, item 7), which no part entry owns."""
    from vvea_design.report.assembly_sheet import SHEET_NAME

    drawn = [p.name for p in PARTS if p.drawing is not None]
    assert drawn == list(DRAWN)
    assert SHEET_NAME == "assembly_order" and SHEET_NAME not in {p.name for p in PARTS}
    committed = sorted(f.stem.removeprefix("drawing_") for f in (REPO / "cad").glob("drawing_*.svg"))
    assert committed == sorted([*DRAWN, "unit_section", SHEET_NAME])
    for p in PARTS:
        assert p.drawing is None or callable(p.drawing), p.name
        assert p.hatch in registry.HATCHES, p.name
    assert all(p.hatch is None for p in registry.parts_in("gas"))


def test_hooks_give_the_part_its_lines_and_sheet(reference_model):
    """Called on the built reference model, each hook answers for its own part."""
    model = reference_model
    assert model.design == REFERENCE
    ctx = BomContext(model.layout, model.solids, get_silicone("dragon-skin-20"))
    for p in PARTS:
        if p.bom is not None:
            lines = p.bom(p, ctx)
            assert lines and all(isinstance(ln, BomLine) and ln.part == p.name and ln.item == 0 for ln in lines)
            assert all(ln.file == f"{p.name}.step" for ln in lines)
            assert {ln.section for ln in lines} == ({"tooling"} if p.group == "mould" else {"made"}), p.name
        if p.drawing is not None:
            content = p.drawing(model.layout, model.solids[p.name])
            assert isinstance(content, SheetContent) and content.dims and content.notes, p.name
            assert content.notes[0].startswith("All dimensions in mm"), p.name
    sections = [ln.section for hook in BOUGHT_ITEMS for ln in hook(ctx)]
    assert sections == sorted(sections, key=SECTIONS.index) and set(sections) == {"seal", "bought", "fluid"}


def test_a_part_must_say_how_it_is_billed():
    def build(ctx):
        return None

    mat = registry.fixed_material("pla", "printed")
    with pytest.raises(ValueError, match="neither"):
        registry.Part("x", "x", "assembly", build, mat, (0, 0, 0), bom=None)
    with pytest.raises(ValueError, match="both"):
        registry.Part("x", "x", "assembly", build, mat, (0, 0, 0), not_on_bom="not bought")
    with pytest.raises(ValueError, match="hatch"):
        registry.Part("x", "x", "assembly", build, mat, (0, 0, 0), hatch="tartan")
    assert registry.Part("x", "x", "assembly", build, mat, (0, 0, 0)).bom is registry.made_part


def test_sheet_content_names_its_plane():
    with pytest.raises(ValueError, match="plane"):
        SheetContent((), (), (), plane="xy")
