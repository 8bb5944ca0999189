"""O-ring seals: the size table against an independent copy of ISO 3601-1, the
gland rules, and the CAD grooves measured on the solids against the chosen ring."""

from __future__ import annotations

import sys
from pathlib import Path

import pytest
from build123d import GeomType


from tests.cad.cases import DESIGNS, SLOW  # noqa: E402

from vvea_design.cad import CadError, CadParameters, Layout, housing, piston  # noqa: E402
from vvea_design.cad.seals import (  # noqa: E402
    DYNAMIC_GLANDS,
    ORING_SIZES,
    SealError,
    get_oring,
    piston_gland,
    rod_gland,
)

ALL = {**DESIGNS, **SLOW}


#: An independent copy of ISO 3601-1 class A (the 1.78 mm and 2.62 mm series), typed from the standard before
#: the CAD read bd_warehouse's data: code -> inner diameter, mm.
ISO_3601_1 = {
    **dict(zip([f"{k:03d}" for k in range(4, 51)],
               [1.78, 2.57, 2.90, 3.68, 4.47, 5.28, 6.07, 7.65, 9.25, 10.82, 12.42, 14.00, 15.60, 17.17, 18.77, 20.35,
                21.95, 23.52, 25.12, 26.70, 28.30, 29.87, 31.47, 33.05, 34.65, 37.82, 41.00, 44.17, 47.35, 50.52,
                53.70, 56.87, 60.05, 63.22, 66.40, 69.57, 72.75, 75.92, 82.27, 88.62, 94.97, 101.32, 107.67, 114.02,
                120.37, 126.72, 133.07], strict=True)),
    **dict(zip([f"{k:03d}" for k in range(102, 151)],
               [1.24, 2.06, 2.84, 3.63, 4.42, 5.23, 6.02, 7.59, 9.19, 10.77, 12.37, 13.94, 15.54, 17.12, 18.72, 20.29,
                21.89, 23.47, 25.07, 26.64, 28.24, 29.82, 31.42, 32.99, 34.59, 36.17, 37.77, 39.34, 40.94, 42.52,
                44.12, 45.69, 47.29, 48.90, 50.47, 52.07, 53.64, 55.25, 56.82, 58.42, 59.99, 61.60, 63.17, 64.77,
                66.34, 67.95, 69.52, 71.12, 72.69], strict=True)),
}


def test_size_table_matches_bd_warehouse():
    """The sizes the CAD uses (bd_warehouse's ISO 3601-1 data) equal an independent copy of the standard, and
    the gland rows are bd_warehouse's (issue 23: the CAD reads bd_warehouse instead of hand-typed tables)."""
    o_rings = pytest.importorskip("bd_warehouse.o_rings")
    for code, d in ISO_3601_1.items():
        w = 1.78 if int(code) < 100 else 2.62
        assert ORING_SIZES[code] == (d, w), code
    for code, (d, w) in ORING_SIZES.items():
        p = o_rings.ORing.parameters(code)
        assert (p["id"], p["w"]) == (d, w), code
    for w, (dmin, dmax, width, sq_lo, sq_hi) in DYNAMIC_GLANDS.items():
        ref = o_rings.ORing.o_ring_dynamic_gland_data[f"{w:g}"]
        assert (ref["d_min"], ref["d_max"], ref["g_w_0"], ref["sq_p_min"], ref["sq_p_max"]) == (dmin, dmax, width,
                                                                                              sq_lo, sq_hi)
    # the dynamic rows are the values the CAD sized its piston and rod glands with before (behaviour kept)
    assert DYNAMIC_GLANDS[1.78] == (1.40, 1.45, 2.41, 15.0, 25.0)
    assert DYNAMIC_GLANDS[2.62] == (2.21, 2.29, 3.68, 10.0, 18.0)


def test_static_glands_lead_ins_and_finish():
    """Static glands from bd_warehouse's static table; the lead-in chamfer's radial depth exceeds the free ring's
    protrusion (ISO 3601-2), its angle is 15...20 deg; roughness per ISO 3601-2 for pulsating pressure."""
    from vvea_design.cad.seals import FINISH_RA_UM, STATIC_GLANDS, lead_in, static_female_gland, static_male_gland

    g = static_male_gland(56.32)
    lo, hi = STATIC_GLANDS[1.78][3:]
    assert g.application == "static" and g.is_male and lo / 100 <= g.squeeze <= hi / 100 and 0 <= g.stretch <= 0.05
    assert g.width_mm == STATIC_GLANDS[1.78][2] and 0.13 <= g.radius_mm <= 0.38
    f = static_female_gland(8.0)
    assert not f.is_male and f.groove_diameter_mm > 8.0 and 0 <= f.stretch <= 0.05
    for gl in (g, f, piston_gland(35.42), rod_gland(8.0)):
        li = gl.lead_in()
        assert 15.0 <= li.angle_deg <= 20.0
        assert li.depth_mm > gl.protrusion_mm + gl.oring.cross_section_tolerance_mm
        assert li.length_mm * __import__("math").tan(__import__("math").radians(li.angle_deg)) == \
            pytest.approx(li.depth_mm, abs=0.01)
        assert str(FINISH_RA_UM[gl.application]["counter"]) in gl.finish_text
    short = g.lead_in(max_length_mm=1.9)
    assert short.angle_deg > 15.0 and short.length_mm <= 1.9
    with pytest.raises(SealError, match="lead-in"):
        lead_in(g.oring, g.protrusion_mm, max_length_mm=1.0)


def test_size_table_is_monotonic_per_series():
    for w in DYNAMIC_GLANDS:
        ids = [d for d, ww in ORING_SIZES.values() if ww == w]
        assert ids == sorted(ids) and len(ids) > 40


@pytest.mark.parametrize("bore", [24.0, 28.7, 31.08, 34.37, 38.0, 44.0, 60.0])
def test_piston_gland_rules(bore):
    g = piston_gland(bore)
    lo, hi = DYNAMIC_GLANDS[g.oring.cross_section_mm][3:]
    assert 0.0 <= g.stretch <= 0.05 + 1e-12
    assert lo / 100 - 1e-9 <= g.squeeze <= hi / 100 + 1e-9
    assert g.groove_diameter_mm == pytest.approx(bore - 2 * g.depth_mm)
    assert g.fill < 0.9
    assert g.oring.name.startswith(f"ISO 3601-1 {g.oring.code} (AS568-{g.oring.code})")


def test_rod_gland_rules():
    g = rod_gland(8.0)
    assert g.oring.code == "011" and 0.0 <= g.stretch <= 0.05
    assert g.groove_diameter_mm == pytest.approx(8.0 + 2 * 1.425)


def test_seal_errors():
    with pytest.raises(SealError, match="unknown O-ring size"):
        get_oring("999")
    with pytest.raises(SealError, match="cross-section of 3 mm"):
        piston_gland(30.0, 3.0)
    with pytest.raises(SealError, match="Ø0.50 mm rod"):
        rod_gland(0.5)
    with pytest.raises(CadError, match="cad.oring_cross_section_mm"):
        CadParameters(oring_cross_section_mm=2.0)


def _cyl_radii(solid, z0, z1):
    out = []
    for f in solid.faces():
        if f.geom_type == GeomType.CYLINDER:
            bb = f.bounding_box()
            if bb.min.Z >= z0 - 1e-6 and bb.max.Z <= z1 + 1e-6:
                out.append((round(f.radius, 6), round(bb.min.Z, 6), round(bb.max.Z, 6)))
    return out


@pytest.mark.parametrize("key", list(DESIGNS))
def test_cad_piston_grooves_match_the_oring(key):
    """Two grooves on the piston: root Ø and width as the gland of the chosen ring."""
    lay = Layout(ALL[key])
    g = lay.piston_seal
    s = piston(lay, 0.0)
    roots = [c for c in _cyl_radii(s, lay.z_piston_bottom(), lay.z_piston_top()) if c[0] < lay.r_piston - 1e-3
             and c[0] > lay.r_rod + 1e-3]
    assert len(roots) == 2
    for r, z0, z1 in roots:
        assert 2 * r == pytest.approx(g.groove_diameter_mm, abs=1e-6)
        assert z1 - z0 == pytest.approx(g.width_mm, abs=1e-6)
    # the ring seats with 0-5 % stretch on the measured root
    assert 0.0 <= 2 * roots[0][0] / g.oring.inner_diameter_mm - 1 <= 0.05 + 1e-9


def test_cad_rod_groove_matches_the_oring():
    lay = Layout(DESIGNS["reference"])
    g = lay.rod_seal
    h = housing(lay)
    cyl = [c for c in _cyl_radii(h, 0.0, lay.z_base_top) if abs(2 * c[0] - g.groove_diameter_mm) < 1e-6]
    assert len(cyl) == 1
    r, z0, z1 = cyl[0]
    assert (z0, z1) == pytest.approx(lay.z_rod_seal, abs=1e-6)
    assert z1 - z0 == pytest.approx(g.width_mm, abs=1e-6)
    assert 0.0 <= g.sliding_diameter_mm / g.oring.inner_diameter_mm - 1 <= 0.05


def test_cad_collar_groove_matches_its_oring_and_is_checked():
    """annulus_top: the collar's static seal to the outer bore is a groove in its rim, centred in the collar
    plate, with the ring stretched 0-5 % and squeezed inside the gland window; a collar too short for it
    (fixed.min_collar_mm) is a clear CadError; the other layouts have no collar seal."""
    from dataclasses import replace

    assert Layout(DESIGNS["reference"]).collar_seal is None
    d = DESIGNS["annulus_top_short"]
    lay = Layout(d)
    g = lay.collar_seal
    assert g.kind == "collar" and g.sliding_diameter_mm == pytest.approx(2 * lay.r_bore)
    assert 0.0 <= g.stretch <= 0.05 and 0.15 - 1e-9 <= g.squeeze <= 0.25 + 1e-9
    assert g.application == "static"  # a static seal: the static gland table (issue 23)
    assert g.to_dict()["kind"] == "collar"
    h = housing(lay)
    cyl = [c for c in _cyl_radii(h, lay.z_free1, lay.z_collar1 + 0.01)
           if abs(2 * c[0] - g.groove_diameter_mm) < 1e-6]
    assert len(cyl) == 1
    _, z0, z1 = cyl[0]
    assert (z0, z1) == pytest.approx(lay.z_collar_seal, abs=1e-6)
    assert z0 >= lay.z_collar1 - d.collar_mm + 0.75 - 1e-9 and z1 <= lay.z_collar1 - 0.75 + 1e-9
    # at a 1 MPa charge the pressure alone would allow a 2.85 mm collar: too short for the 2.41 mm groove
    short = replace(d, p2_MPa=1.0, fixed=replace(d.fixed, min_collar_mm=1.0))
    assert short.collar_mm < g.width_mm + 1.5
    with pytest.raises(CadError, match="fixed.min_collar_mm"):
        Layout(short)
    assert Layout(replace(d, p2_MPa=1.0)).design.collar_mm == pytest.approx(4.0)  # the default minimum holds it
    # the design's own minimum leaves the groove room at any pressure
    assert d.fixed.min_collar_mm >= g.width_mm + 1.5
