"""Stress-concentration factors: the FE per kind, the fit, and the data file the spring sizing reads."""

import json

import numpy as np
import pytest

from tests.helpers import REPO
from vvea_design.spring.buildability import PIECE_PARTS
from vvea_design.spring.concentration import FORMAT as SPRING_FORMAT
from vvea_design.spring.concentration import concentration_factors
from vvea_design.structure.concentration import FORMAT, FORMAT_VERSION, KINDS, KtPoint, evaluate_kt, fit_kt, kt_point
from vvea_design.structure.meshing import MeshSpec

DATA = REPO / "vvea_design" / "spring" / "data" / "stress_concentration.json"


@pytest.mark.parametrize("kind, x1, x2, lo, hi", [
    ("oring_groove_root", 5.0, 0.4, 1.0, 1.4),
    ("thread_relief", 4.0, 0.3, 2.5, 4.5),
    ("ring_groove", 3.0, 0.3, 3.0, 9.0),
    ("shoulder_fillet", 20.0, 2.0, 2.3, 3.2),  # FE above Peterson's 2.4 (his round-bar charts run low)
    ("web_root", 10.0, 0.6, 1.8, 3.0),
])
def test_each_kind_concentrates(kind, x1, x2, lo, hi):
    p = kt_point(kind, x1, x2, MeshSpec(elements_per_radius=2.0))
    assert p.kind == kind and p.x1 == pytest.approx(x1, rel=1e-6) and p.x2 == x2
    assert lo < p.kt_tresca < hi
    assert p.kt_von_mises <= p.kt_tresca * 1.05  # Tresca is the larger equivalent stress, bar round-off


def test_unknown_kind():
    with pytest.raises(ValueError, match="unknown feature kind"):
        kt_point("keyway", 1.0, 1.0)


def test_the_fit_recovers_a_known_law():
    pts = [KtPoint("web_root", a, b, 1.5 * a**0.4 * b**-0.3, 1.4 * a**0.4 * b**-0.3)
           for a in (2.0, 5.0, 10.0) for b in (0.3, 0.6, 1.2)]
    f = fit_kt(pts, "tresca")
    assert f.coefficients == pytest.approx((np.log(1.5), 0.4, -0.3, 0.0), abs=1e-9)
    assert f.max_relative_error < 1e-9
    assert f(100.0, 0.1) == pytest.approx(f(10.0, 0.3))  # clamped into the fitted range
    with pytest.raises(ValueError, match="one kind"):
        fit_kt(pts + [KtPoint("ring_groove", 1, 1, 2, 2)], "tresca")


def test_the_shipped_data_file_holds_every_kind():
    data = json.loads(DATA.read_text())
    assert data["format"] == FORMAT == SPRING_FORMAT and data["format_version"] == FORMAT_VERSION == 1
    assert "exp(c0" in data["model"]
    concentration_factors.cache_clear()
    read = concentration_factors()  # the spring side's reader takes it: every piece, each its largest factor
    assert set(read) == set(PIECE_PARTS) and all(k >= 1.0 for k in read.values())
    assert read == {p: max(f.values()) for p, f in data["factors"].items()}
    assert set(data["kinds"]) == set(KINDS)
    for kind, d in data["kinds"].items():
        assert d["x1"] == KINDS[kind]["x1"] and d["nominal"] == KINDS[kind]["nominal"]
        for crit in ("tresca", "von_mises"):
            c = d[crit]["coefficients"]
            assert len(c) == 4 and d[crit]["max_relative_error"] < 0.25
            # the file's law reproduces its own points within the stated error
            for p in d["points"]:
                kt = evaluate_kt(c, p[d["x1"]], p[d["x2"]], d["x1_range"], d["x2_range"])
                assert abs(kt / p[f"kt_{crit}"] - 1) <= d[crit]["max_relative_error"] + 1e-9
