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
from tests.helpers import REPO

ROOT = REPO
CAD = Path(os.environ.get("VVEA_CAD_DIR", ROOT / "cad"))  #: override only to test this test
REGEN = "regenerate with: vvea cad cad/design.json --out cad"


@pytest.fixture(scope="module")
def fresh(reference_cad_run):
    """(committed manifest, today's manifest, today's folder): today's is the session's shared
    `vvea cad cad/design.json` run (tests/conftest.py)."""
    if not (CAD / "design.json").exists():
        pytest.skip("cad/design.json does not exist yet (the lead generates cad/ from the reference optimised design)")
    if not (CAD / "manifest.json").exists():
        pytest.fail(f"cad/design.json exists but cad/manifest.json does not; {REGEN}")
    out, exit_code, output = reference_cad_run
    assert exit_code == 0, output
    return json.loads((CAD / "manifest.json").read_text()), json.loads((out / "manifest.json").read_text()), out


def test_manifest_numbers_are_current(fresh):
    committed, new, _ = fresh
    for key in ("design", "cad_parameters", "measured", "interference_mm3", "walls_mm", "envelope_mm", "mould"):
        assert committed.get(key) == new[key], f"cad/manifest.json '{key}' is stale; {REGEN}"


def test_files_are_current(fresh):
    committed, new, _ = fresh
    for fname, info in new["files"].items():
        assert fname in committed["files"], f"cad/{fname} missing from the manifest; {REGEN}"
        path = CAD / fname
        assert path.is_file(), f"cad/{fname} missing; {REGEN}"
        import hashlib

        assert hashlib.sha256(path.read_bytes()).hexdigest() == info["sha256"], f"cad/{fname} is stale; {REGEN}"
        for k in ("volume_mm3", "bbox_mm", "material"):
            assert committed["files"][fname].get(k) == info.get(k), f"cad/{fname} {k} is stale; {REGEN}"


def test_drawings_and_bom_are_current(fresh):
    """cad/drawing_*.svg, cad/bom.csv and cad/bom.json are what `vvea cad` writes today (SVG text is byte-stable)."""
    import hashlib

    _, _, out = fresh
    made = sorted(out.glob("drawing_*.svg")) + [out / "bom.csv", out / "bom.json"]
    assert len(made) == 9  # 7 sheets (the assembly order included), bom.csv, bom.json
    for path in made:
        committed = CAD / path.name
        assert committed.is_file(), f"cad/{path.name} missing; {REGEN}"
        assert hashlib.sha256(committed.read_bytes()).hexdigest() == hashlib.sha256(path.read_bytes()).hexdigest(), \
            f"cad/{path.name} is stale; {REGEN}"
    assert sorted(p.name for p in CAD.glob("drawing_*.svg")) == [p.name for p in made[:-2]], f"stale sheets; {REGEN}"
    assert (CAD / "drawings.pdf").is_file()


def test_renders_exist(fresh):
    committed, _, _ = fresh
    for fname in ("assembly_cutaway.png", "mould_open.png"):
        assert (CAD / fname).is_file(), f"cad/{fname} missing; {REGEN}"
        assert fname in committed["files"]
