"""The FE as a job (:func:`vvea_design.jobs.structure.check_structure`): options checked first, the pictures
land whole in ``out``, the result names them there."""

from pathlib import Path

import pytest

from tests.cad.cases import REFERENCE
from tests.structure.test_check import _model
from vvea_design.jobs.common import OptionError
from vvea_design.jobs.structure import check_structure


@pytest.mark.parametrize("option", ["corner_radius_mm", "elements_per_wall"])
def test_bad_options_are_named_before_any_work(option, tmp_path):
    with pytest.raises(OptionError, match=option):
        check_structure(REFERENCE, out=tmp_path / "fe", **{option: 0.0})
    assert not (tmp_path / "fe").exists()


def test_the_job_writes_each_pieces_picture_into_out(tmp_path):
    out = tmp_path / "structure"
    res = check_structure(_model(REFERENCE), out=out)
    figures = [Path(p.figure) for p in res.pieces]
    assert {f.parent for f in figures} == {out} and all(f.is_file() for f in figures)
    assert {f.name for f in figures} == {f"fe_{p.piece}.png" for p in res.pieces}
    assert res.cpu_seconds > 0 and res.to_dict()["cpu_seconds"] == res.cpu_seconds
    assert res.passes == all(w.passes for w in res.walls)
