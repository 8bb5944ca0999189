"""The committed `cad/` folder is what `vvea cad cad/design.json --out cad` writes today.

Fails when the CAD code or the design changed without regenerating::

    vvea cad cad/design.json --out cad

STEP, STL and manifest numbers must match byte for byte (sha256); the PNG
renders only need to exist (rasterisation differs between GL drivers).
"""

from __future__ import annotations

import json
import os
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
CAD = Path(os.environ.get("VVEA_CAD_DIR", ROOT / "cad"))  #: override only to test this test
REGEN = "regenerate with: vvea cad cad/design.json --out cad"


@pytest.fixture(scope="module")
def fresh(tmp_path_factory):
    if not (CAD / "design.json").exists():
        pytest.skip("cad/design.json does not exist yet (the lead generates cad/ from the reference optimised design)")
    from vvea_design.cad import write_cad
    from vvea_design.spring.design_file import load_design

    if not (CAD / "manifest.json").exists():
        pytest.fail(f"cad/design.json exists but cad/manifest.json does not; {REGEN}")
    out = tmp_path_factory.mktemp("cad_fresh")
    return json.loads((CAD / "manifest.json").read_text()), write_cad(load_design(CAD / "design.json"), out,
                                                                       renders=False, show_progress=False)


def test_manifest_numbers_are_current(fresh):
    committed, new = fresh
    for key in ("design", "cad_parameters", "measured", "interference_mm3", "walls_mm", "envelope_mm", "mould"):
        assert committed.get(key) == new[key], f"cad/manifest.json '{key}' is stale; {REGEN}"


def test_files_are_current(fresh):
    committed, new = fresh
    for fname, info in new["files"].items():
        assert fname in committed["files"], f"cad/{fname} missing from the manifest; {REGEN}"
        path = CAD / fname
        assert path.is_file(), f"cad/{fname} missing; {REGEN}"
        import hashlib

        assert hashlib.sha256(path.read_bytes()).hexdigest() == info["sha256"], f"cad/{fname} is stale; {REGEN}"
        for k in ("volume_mm3", "bbox_mm", "material"):
            assert committed["files"][fname].get(k) == info.get(k), f"cad/{fname} {k} is stale; {REGEN}"


def test_drawings_and_bom_are_current(tmp_path):
    """cad/drawing_*.svg and cad/bom.csv are what `vvea cad` writes today (SVG text is byte-stable)."""
    if not (CAD / "design.json").exists():
        pytest.skip("no cad/design.json")
    import hashlib

    from vvea_design.cad import build_cad
    from vvea_design.report.bom import write_bom
    from vvea_design.report.drawing import write_drawings
    from vvea_design.spring.design_file import load_design

    model = build_cad(load_design(CAD / "design.json"))
    ds = write_drawings(model, tmp_path)
    write_bom(model, tmp_path)
    for path in [*ds.svg, tmp_path / "bom.csv"]:
        committed = CAD / path.name
        assert committed.is_file(), f"cad/{path.name} missing; {REGEN}"
        assert hashlib.sha256(committed.read_bytes()).hexdigest() == hashlib.sha256(path.read_bytes()).hexdigest(), \
            f"cad/{path.name} is stale; {REGEN}"
    assert (CAD / "drawings.pdf").is_file()


def test_renders_exist(fresh):
    committed, _ = fresh
    for fname in ("assembly_cutaway.png", "mould_open.png"):
        assert (CAD / fname).is_file(), f"cad/{fname} missing; {REGEN}"
        assert fname in committed["files"]
