"""The main job runs the actuator study beside the CAD: its worker pools come from a fork server, its results
are those of a study run alone, and an error (or Ctrl-C) in the CAD's thread stops it at once."""

import time
from pathlib import Path

import pytest

from vvea_design.parallel import clean_workers, parallel_map
from vvea_design.pipeline import _beside


def _square(v: float) -> float:
    return v * v


def _slow(v: float) -> float:
    time.sleep(v)
    return v


def _map_squares(values, workers=2):
    return parallel_map(_square, values, workers=workers, progress=False)


def test_pools_started_beside_come_from_a_fork_server():
    with clean_workers() as handle:
        assert parallel_map(_square, [1.0, 2.0, 3.0], workers=2, progress=False) == [1.0, 4.0, 9.0]
    assert [p._mp_context.get_start_method() for p in handle.pools] == ["forkserver"]
    # outside the block the default start method is back (no pool registered)
    assert parallel_map(_square, [1.0, 2.0], workers=2, progress=False) == [1.0, 4.0]
    assert len(handle.pools) == 1


def test_beside_returns_the_result_and_its_own_time():
    with _beside(_map_squares, [1.0, 2.0, 3.0, 4.0]) as wait:
        result, seconds = wait()
    assert result == [1.0, 4.0, 9.0, 16.0] and seconds > 0


@pytest.mark.parametrize("workers", [1, 2])
def test_an_error_in_the_block_cancels_the_work_beside(workers):
    t = time.perf_counter()
    with pytest.raises(RuntimeError, match="the CAD failed"):
        with _beside(parallel_map, _slow, [0.2] * 400, workers=workers, progress=False):
            time.sleep(0.5)
            raise RuntimeError("the CAD failed")
    # 400 items of 0.2 s would take 40 s (80 s on one worker): the work was stopped, not waited for
    assert time.perf_counter() - t < 20


def test_the_study_beside_gives_the_study_alone(tmp_path):
    from vvea_design.jobs.studies import run_design_study
    from vvea_design.spring.design_file import load_design
    design = load_design(Path(__file__).resolve().parents[2] / "cad" / "design.json")
    opts = dict(grid="0.3,0.7:0.6,1.2", mesh_n=24, safety_mesh_n=30, workers=2)
    alone = run_design_study(design, out=tmp_path / "alone", **opts)
    with _beside(run_design_study, design, out=tmp_path / "beside", **opts) as wait:
        beside, _ = wait()

    def runs(study):  # every number of every run but the wall times
        def strip(v):
            if isinstance(v, dict):
                return {k: strip(x) for k, x in v.items() if "second" not in k and "timing" not in k}
            return [strip(x) for x in v] if isinstance(v, list) else v
        return [strip(r.to_dict()) for r in study.runs]

    assert runs(beside) == runs(alone)
    assert [c.to_dict() for c in beside.comparisons] == [c.to_dict() for c in alone.comparisons]
    assert beside.damping.to_dict() == alone.damping.to_dict()
