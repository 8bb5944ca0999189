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


def test_size_table_matches_bd_warehouse():
    """Every size of our table equals bd_warehouse's ISO 3601-1 data (typed independently)."""
    o_rings = pytest.importorskip("bd_warehouse.o_rings")
    for code, (d, w) in ORING_SIZES.items():
        p = o_rings.ORing.parameters(code)
        assert (p["id"], p["w"]) == (d, w), code
    for w, (dmin, dmax, width, sq_lo, sq_hi) in DYNAMIC_GLANDS.items():
        ref = o_rings.ORing.o_ring_dynamic_gland_data[f"{w:g}"]
        assert (ref["d_min"], ref["d_max"], ref["g_w_0"], ref["sq_p_min"], ref["sq_p_max"]) == (dmin, dmax, width,
                                                                                              sq_lo, sq_hi)


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
