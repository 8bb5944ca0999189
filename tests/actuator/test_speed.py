"""The speed-ups of the OCP studies give the results of the slower paths (within the solver's tolerance)."""

from __future__ import annotations

import pytest

import vvea_design.actuator.multistart as ms
import vvea_design.actuator.rest_to_rest as sa
from vvea_design.actuator.design_study import DESIGN_IPOPT, DESIGN_STARTS
from vvea_design.actuator.model import PAPER_SETTINGS
from vvea_design.actuator.multistart import RestToRestCase, chains
from vvea_design.actuator.ocp import Mesh, RestToRestSolver
from vvea_design.actuator.rest_to_rest import Grid

COARSE, FINE = Mesh(16, 3), Mesh(32, 3)
SETTINGS = (PAPER_SETTINGS["SEA"], PAPER_SETTINGS["LWR"], PAPER_SETTINGS["VVEA"])


@pytest.mark.parametrize("A, T", [(0.5, 0.8), (0.2, 0.3)])
def test_fine_qps_warm_started_from_the_coarse_qps_equal_the_cold_ones(A, T, monkeypatch):
    case = RestToRestCase(A, T, SETTINGS, COARSE, ("const-Dmin",), fine_mesh=FINE)
    qps: dict = {}
    rows, best = ms._solve_case_one_mesh(case, {}, None, qps)
    assert {k[0] for k in qps} == {"const"} and len(qps) == 3  # SEA, LWR and VVEA's D_min QP
    starts = []
    real = RestToRestSolver.guess_from_other_mesh
    monkeypatch.setattr(RestToRestSolver, "guess_from_other_mesh",
                        lambda self, other, act, A_, T_: starts.append(act.name) or real(self, other, act, A_, T_))
    warm, _ = ms._polish_on_fine_mesh(case, rows, best, qps)
    assert sorted(starts) == ["LWR", "SEA", "VVEA", "VVEA"]  # three QPs from their coarse optima + VVEA's polish
    starts.clear()
    cold, _ = ms._polish_on_fine_mesh(case, rows, best, None)
    assert starts == ["VVEA"]
    for w, c in zip(warm, cold):
        assert w.setting == c.setting and w.success and c.success
        assert w.mesh_N == c.mesh_N == FINE.n_intervals
        assert w.rmse == pytest.approx(c.rmse, rel=1e-5), w.setting
        assert w.valid == c.valid


def test_multistart_options_reach_the_coarse_mesh_only(monkeypatch, tmp_path):
    monkeypatch.setitem(ms.MULTISTART_IPOPT, "ipopt.mu_strategy", "monotone")
    monkeypatch.setattr(ms, "_SOLVERS", {})
    case = RestToRestCase(0.5, 0.8, SETTINGS, COARSE, ("const-Dmin",), fine_mesh=FINE)
    rows, _ = ms.solve_case_results(case)
    assert all(r.success and r.verified for r in rows)
    keys = set(ms._SOLVERS)
    assert (COARSE, (("ipopt.mu_strategy", "monotone"),)) in keys
    assert (FINE, ()) in keys  # the fine QPs' cold fallback / the fine solver keep the defaults
    assert all(m == COARSE for m, o in keys if ("ipopt.mu_strategy", "monotone") in o)
    # the sweep records them, so a sweep solved without them is not resumed with them
    meta = sa._meta(Grid((0.5,), (0.8,)), SETTINGS, COARSE, ("const-Dmin",), (), FINE)
    assert meta["multistart_ipopt_options"] == [["ipopt.mu_strategy", "monotone"]]
    monkeypatch.delitem(ms.MULTISTART_IPOPT, "ipopt.mu_strategy")
    assert "multistart_ipopt_options" not in sa._meta(Grid((0.5,), (0.8,)), SETTINGS, COARSE, ("const-Dmin",), (),
                                                      FINE)


def test_a_case_option_overrides_the_multistart_options(monkeypatch):
    monkeypatch.setitem(ms.MULTISTART_IPOPT, "ipopt.mu_strategy", "monotone")
    case = RestToRestCase(0.5, 0.8, SETTINGS, COARSE, ("const-Dmin",), (("ipopt.mu_strategy", "adaptive"),),
                          fine_mesh=FINE)
    assert dict(ms._coarse_options(case)) == {"ipopt.mu_strategy": "adaptive"}


def test_design_study_defaults_one_work_item_per_case_with_its_own_options():
    assert "neighbour" not in DESIGN_STARTS
    assert dict(DESIGN_IPOPT) == {"ipopt.mu_strategy": "monotone"}
    cases = [RestToRestCase(A, T, SETTINGS, COARSE, DESIGN_STARTS, DESIGN_IPOPT) for A in (0.2, 0.4)
             for T in (0.3, 0.6, 1.0)]
    assert [len(c) for c in chains(cases)] == [1] * len(cases)


def _warm(monkeypatch, options: dict) -> None:
    monkeypatch.setattr(ms, "MULTISTART_WARM_IPOPT", dict(options))
    monkeypatch.setattr(sa, "MULTISTART_WARM_IPOPT", ms.MULTISTART_WARM_IPOPT)


def test_warm_started_multistart_reaches_the_cold_optima_of_a_unimodal_setting(monkeypatch):
    """The multi-start NLPs started *at* their points (the option) land on VVEA's optimum of the cold options, on
    the coarse mesh only; a single-level case (the design study) keeps the cold options."""
    from vvea_design.actuator.ocp import WARM_START_IPOPT

    case = RestToRestCase(0.5, 0.8, SETTINGS, COARSE, ("const-Dmin", "ramp"), fine_mesh=FINE)
    rows = {}
    for label, options in (("cold", {}), ("warm", WARM_START_IPOPT)):
        _warm(monkeypatch, options)
        monkeypatch.setattr(ms, "_SOLVERS", {})
        rows[label] = {r.setting: r for r in ms.solve_case_results(case)[0]}
        keys = set(ms._SOLVERS)
        warm_keys = {(m, o) for m, o in keys if ("ipopt.warm_start_init_point", "yes") in o}
        # the fine polish's warm solver, and with the option the coarse mesh's one
        assert {m for m, _ in warm_keys} == ({FINE, COARSE} if options else {FINE})
        meta = sa._meta(Grid((0.5,), (0.8,)), SETTINGS, COARSE, ("const-Dmin",), (), FINE)
        assert ("multistart_warm_ipopt_options" in meta) == bool(options)  # a sweep records it (resume)
    for name in ("SEA", "LWR", "VVEA"):
        c, w = rows["cold"][name], rows["warm"][name]
        assert c.success and w.success and c.verified and w.verified
        assert w.rmse == pytest.approx(c.rmse, rel=1e-3), name
        assert w.valid == c.valid
    # single level (no fine mesh, as the design study): the option is not used
    _warm(monkeypatch, WARM_START_IPOPT)
    monkeypatch.setattr(ms, "_SOLVERS", {})
    ms.solve_case_results(RestToRestCase(0.5, 0.8, SETTINGS, COARSE, ("const-Dmin",)))
    assert not any(("ipopt.warm_start_init_point", "yes") in o for _, o in ms._SOLVERS)
