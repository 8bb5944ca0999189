"""Dimensioned drawings and the bill of materials of the reference design."""

from __future__ import annotations

import csv
import io
import sys
import xml.etree.ElementTree as ET
from itertools import combinations
from pathlib import Path

import pytest


from tests.cad.cases import REFERENCE  # noqa: E402

from vvea_design.cad import PARTS, build_cad  # noqa: E402
from vvea_design.report.bom import bill_of_materials, write_bom  # noqa: E402
from vvea_design.report.drawing import (  # noqa: E402
    SHEET_MM,
    check_anchors,
    fit_deviations_um,
    sheet_figure,
    sheet_specs,
    write_drawings,
)


@pytest.fixture(scope="module")
def model(reference_model):
    assert reference_model.design == REFERENCE
    return reference_model


@pytest.fixture(scope="module")
def specs(model):
    return sheet_specs(model)


def test_one_sheet_per_machined_piece(specs):
    assert [s.name for s in specs] == ["unit_section"] + [p.name for p in PARTS if p.drawing]
    assert {"housing_base", "housing_outer_tube", "housing_inner_tube", "housing_top_cap", "piston"} <= {
        s.name for s in specs}


def test_sheets_by_name(model, specs):
    """``sheet_specs(model, names)`` makes only the named sheets, the same as in the full set."""
    (piston,) = sheet_specs(model, ["piston"])
    full = next(s for s in specs if s.name == "piston")
    assert piston.dims == full.dims and piston.notes == full.notes and piston.leaders == full.leaders
    with pytest.raises(ValueError, match="no sheet named"):
        sheet_specs(model, ["housing", "nope"])


def test_dimensions_sit_on_the_drawn_outline(specs):
    """Every dimension anchor (except feature axes) lies on the section of the build123d solid."""
    for spec in specs:
        assert spec.dims, spec.name
        assert check_anchors(spec) == [], spec.name


def test_anchor_check_catches_a_wrong_dimension(specs):
    from dataclasses import replace

    from vvea_design.report.drawing import Dim

    spec = specs[0]
    bad = replace(spec, dims=[Dim("z", (-5.0, 3.3), (-5.0, 40.0), "left")])
    assert len(check_anchors(bad)) == 2


def test_fits_iso286():
    assert fit_deviations_um(34.37, "H8") == (39.0, 0.0)
    assert fit_deviations_um(34.37, "f7") == (-25.0, -50.0)
    assert fit_deviations_um(8.0, "H8") == (22.0, 0.0)
    assert fit_deviations_um(8.0, "f7") == (-13.0, -28.0)
    with pytest.raises(ValueError, match="ISO 286"):
        fit_deviations_um(8.0, "k6")
    # the fits the housing's seals add (issue 23): static seal bores H8 with g7 spigots, tubes h9, plug bores H11
    assert fit_deviations_um(56.32, "g7") == (-10.0, -40.0)
    assert fit_deviations_um(59.5, "h9") == (0.0, -74.0)
    assert fit_deviations_um(3.0, "H11") == (60.0, 0.0)
    with pytest.raises(ValueError, match="outside"):
        fit_deviations_um(500.0, "H8")


def test_sheet_content(model, specs):
    lay = model.layout
    unit = specs[0]
    text = " ".join([d.label() for d in unit.dims] + [lead.text for lead in unit.leaders] + unit.notes)
    for must in ("ISO 2768-m", "H8", "f7", lay.piston_seal.oring.code, lay.rod_seal.oring.code, "stroke",
                 "fill port", "relief valve", "wall"):
        assert must in text, must
    piston = next(s for s in specs if s.name == "piston")
    assert piston.detail is not None
    widths = [d for d in piston.detail.dims if d.label().startswith(f"{lay.piston_seal.width_mm:.2f}")]
    assert len(widths) == 2
    for d in widths:
        assert d.value_mm == pytest.approx(lay.piston_seal.width_mm, abs=1e-9)


@pytest.mark.parametrize("index", range(6))
def test_text_does_not_overlap_and_stays_on_the_sheet(specs, index):
    """Render the sheet and check that no two labels overlap and all lie inside the border."""
    from matplotlib.backends.backend_agg import FigureCanvasAgg

    spec = specs[index]
    fig = sheet_figure(spec, index + 1, len(specs), "test")
    FigureCanvasAgg(fig)
    renderer = fig.canvas.get_renderer()
    ax = fig.axes[0]
    boxes = [(t.get_text(), t.get_window_extent(renderer)) for t in ax.texts if t.get_text().strip()]
    w_px, h_px = fig.get_size_inches() * fig.dpi
    px_per_mm = w_px / SHEET_MM[0]
    for text, bb in boxes:
        assert bb.x0 >= 10 * px_per_mm - 1 and bb.x1 <= w_px - 10 * px_per_mm + 1, (spec.name, text)
        assert bb.y0 >= 10 * px_per_mm - 1 and bb.y1 <= h_px - 10 * px_per_mm + 1, (spec.name, text)
    for (ta, a), (tb, b) in combinations(boxes, 2):
        a2 = a.expanded(0.98, 0.9)
        b2 = b.expanded(0.98, 0.9)
        assert not a2.overlaps(b2), (spec.name, ta, tb)
    assert fig._vvea_scale in (5.0, 2.0, 1.0, 0.5)


def test_write_drawings_files(reference_cad_run):
    """The sheets `vvea cad` writes (the session's shared run): one SVG per sheet at the sheet size and a
    multi-page PDF. Byte stability across processes: tests/cad/test_cad_sync.py compares them with cad/."""
    out, exit_code, output = reference_cad_run
    assert exit_code == 0, output
    svg = sorted(out.glob("drawing_*.svg"))
    # the unit's section, one sheet per drawn part, and the exploded assembly order (issue 23, item 7)
    drawn = [p.name for p in PARTS if p.drawing is not None]
    assert sorted(p.stem.removeprefix("drawing_") for p in svg) == sorted(["unit_section", *drawn, "assembly_order"])
    assert len(svg) == 7
    pdf = (out / "drawings.pdf").read_bytes()
    assert pdf.startswith(b"%PDF") and pdf.count(b"/Type /Page\n") + pdf.count(b"/Type /Page ") >= 7
    assert "assembly order" in (out / "drawing_assembly_order.svg").read_text()
    for p in svg:
        root = ET.fromstring(p.read_bytes())
        assert root.tag.endswith("svg")
        assert float(root.get("width").rstrip("pt")) == pytest.approx(SHEET_MM[0] / 25.4 * 72, rel=1e-3)
        assert "ISO 2768-m" in p.read_text()


# ------------------------------------------------------------------ bill of materials
def test_bom_lines(model):
    bom = bill_of_materials(model, "ecoflex-00-30")
    by_part = {line.part: line for line in bom.lines}
    for p in PARTS:
        if p.bom:
            line = by_part[p.name]
            mat = p.material(model.design)
            assert line.unit_volume_mm3 == pytest.approx(model.solids[p.name].volume, rel=1e-12)
            assert line.unit_mass_g == pytest.approx(line.unit_volume_mm3 * mat.density_g_per_mm3, rel=1e-12)
            assert line.in_unit == (p.group != "mould")
        else:
            assert p.name not in by_part
    assert "Ecoflex 00-30" in by_part["bladder"].material
    lay = model.layout
    assert by_part["oring_piston"].quantity == 2 and lay.piston_seal.oring.name == by_part["oring_piston"].size
    assert by_part["oring_rod"].size == lay.rod_seal.oring.name
    assert [line.item for line in bom.lines] == list(range(1, len(bom.lines) + 1))
    in_unit = sum(line.total_mass_g or 0.0 for line in bom.lines if line.in_unit)
    assert bom.unit_mass_g == pytest.approx(in_unit)
    assert bom.mould_void_mm3 > model.closed_form_mm3["mould_cavity"] > bom.bladder_volume_mm3
    assert bom.silicone_to_mix_mm3 > bom.mould_void_mm3
    d = bom.to_dict()
    assert d["lines"][0]["part"] == bom.lines[0].part and d["unit_mass_g"] == bom.unit_mass_g


def test_bom_csv(model, tmp_path):
    bom = write_bom(model, tmp_path)
    rows = list(csv.DictReader(io.StringIO((tmp_path / "bom.csv").read_text())))
    assert len(rows) == len(bom.lines)
    assert float(rows[0]["unit_mass_g"]) == pytest.approx(bom.lines[0].unit_mass_g, abs=0.01)
    assert (tmp_path / "bom.json").is_file()


def test_bom_unknown_silicone(model):
    with pytest.raises(ValueError, match="silicone"):
        bill_of_materials(model, "unobtainium")


def test_annulus_top_drawings_dimension_the_collar():
    """The annulus_top layout's sheets: every anchor on the outline, the collar dimensioned on the section and
    on the inner tube (it is part of it), a plain top cap, the chamber-2 port through the base noted."""
    from tests.cad.cases import OTHERS

    m = build_cad(OTHERS["annulus_top_short"])
    specs = {s.name: s for s in sheet_specs(m)}
    for spec in specs.values():
        assert spec.dims and check_anchors(spec) == [], spec.name
    for name in ("unit_section", "housing_inner_tube"):
        assert any("(collar)" in d.label() for d in specs[name].dims), name
    assert not any("clamp" in d.label() for d in specs["housing_top_cap"].dims)
    assert any("Chamber-2 fill port" in n for n in specs["housing_base"].notes)
    assert any("slots" in n for n in specs["housing_inner_tube"].notes)
    # the collar's static seal: its groove on the inner-tube sheet (anchored on the outline above), its ring
    # noted there and in the bill of materials
    seal = m.layout.collar_seal
    assert any(f"O-ring {seal.oring.code}" in lead.text for lead in specs["housing_inner_tube"].leaders)
    assert any("static seal, O-ring" in n and seal.oring.name in n for n in specs["housing_inner_tube"].notes)
    from vvea_design.report.bom import bill_of_materials

    lines = [ln for ln in bill_of_materials(m).lines if ln.part == "oring_collar"]
    assert len(lines) == 1 and lines[0].quantity == 1 and lines[0].size == seal.oring.name


def test_the_bill_comes_from_the_owners_hooks(model):
    """Every line is its owner's (a part's BOM hook or a bought item's), in section order, numbered; a part
    without a hook is not on the bill."""
    from vvea_design.cad.bill import BOUGHT_ITEMS, SECTIONS, BomContext
    from vvea_design.materials.silicones import get_silicone

    bom = bill_of_materials(model)
    ctx = BomContext(model.layout, model.solids, get_silicone("dragon-skin-20"))
    owned = [ln for p in PARTS if p.bom is not None for ln in p.bom(p, ctx)] + [ln for h in BOUGHT_ITEMS for ln in h(ctx)]
    assert sorted(ln.part for ln in bom.lines) == sorted(ln.part for ln in owned)
    sections = [ln.section for ln in bom.lines]
    assert sections == sorted(sections, key=SECTIONS.index)
    assert [ln.part for ln in bom.lines if ln.section == "made"] == [p.name for p in PARTS
                                                                    if p.bom is not None and p.group != "mould"]
    assert not {p.name for p in PARTS if p.bom is None} & {ln.part for ln in bom.lines}


def test_every_part_hatch_has_a_pattern():
    from vvea_design.cad.registry import HATCHES
    from vvea_design.report.sheet_spec import HATCH_PATTERNS

    assert set(HATCH_PATTERNS) == set(HATCHES)
