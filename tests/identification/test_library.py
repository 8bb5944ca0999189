"""Tests of the state library (general discovery): its terms, the sparse selection with grouped CV, the made
effect ``states[...]`` and its description by the states it follows; and of the selection's rule that a
candidate which explained nothing is not tested again."""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import pytest

from vvea_benches.testbench import simulate, small_spec
from vvea_design.identification.design import assemble
from vvea_design.identification.effects import REGISTRY, is_effect_id
from vvea_design.identification.effects.library import (BASES, MAX_TERMS, StateTerms, library_terms, select_terms, states_id,
                                                        term_columns, term_states)
from vvea_design.identification.fit_data import FitData
from vvea_design.identification.fitting import fit_model
from vvea_design.identification.recordings import recordings_from_frame
from vvea_design.identification.report import Evidence
from vvea_design.identification.selection import _round_context, _settles, _Trial, plan_split
from vvea_design.identification.settings import DiagnoseSettings


@pytest.fixture(scope="module")
def D():
    return FitData.from_recordings(recordings_from_frame(simulate(small_spec(seed=7, noise_N=3.0)).frame, "library"))


def _with(D, extra):
    return replace(D, y=D.y + extra, _cache={}, _cache_nbytes={})


def _selected(D):
    plan = plan_split(D, DiagnoseSettings())
    cur = fit_model(D, (), experiments=plan.train)
    ctx = _round_context(D, cur, plan)
    X0 = assemble(D, cur.effects, cur.shapes, ctx)[0]
    return select_terms(D, ctx, plan.folds, X0)


def test_library_holds_the_states_their_histories_and_products_but_not_eq14_or_the_gas_curve():
    terms = library_terms()
    assert len(terms) == len(set(terms)) == 102
    for t in ("1", "p", "x*dir", "x*tc", "speed", "tc", "tc2", "tc2*damp", "start0.3", "rev1", "tc*damp", "tc*spring", "p*tc", "dir*rev0.2", "x*dir"):
        assert t in terms
    # eq. 14's own columns (or sums of them) and the charge-borne curvature of the gas spring are not library terms
    for t in ("dir", "spring", "damp", "x*p", "dir*speed", "x2*p", "x*spring", "x2*spring", "p*spring", "x", "x2", "x*x2"):
        assert t not in terms
    # no product within one history family (two decays of the same clock)
    assert not any(t.split("*")[0][:3] == t.split("*")[-1][:3] and "*" in t and t != "x*x2" for t in terms)
    assert all(b in BASES for t in terms for b in t.split("*"))


def test_term_columns_are_the_products_of_the_states(D):
    ctx = {"damping_force_N": np.linspace(-1.0, 1.0, D.n)}
    F = term_columns(D, ("p", "p*tc", "tc*damp", "1"), ctx)
    assert F.shape == (D.n, 4)
    np.testing.assert_allclose(F[:, 0], D.p2)
    np.testing.assert_allclose(F[:, 1], D.p2 * D.ctime / 3600.0)
    np.testing.assert_allclose(F[:, 2], ctx["damping_force_N"] * D.ctime / 3600.0)
    np.testing.assert_allclose(F[:, 3], 1.0)


def test_a_charge_offset_is_found_as_the_charge_alone(D):
    terms = _selected(_with(D, 25.0 * D.p2))
    assert terms and terms[0] == "p"
    assert len(terms) <= 2  # sparse: the charge (and at most a constant)


def test_a_force_at_the_start_of_each_experiment_is_found_by_the_time_within_the_experiment(D):
    terms = _selected(_with(D, 40.0 * np.exp(-D.t / 3.0)))  # (the small bench samples its slow runs seconds apart)
    assert terms and "time_in_experiment" in term_states(terms[0])


def test_a_term_the_current_model_already_holds_is_not_a_library_term(D):
    # pressure friction p2 sign(xdot) in the model: the library's p*dir is no new term beside it
    D2 = _with(D, 3.0 * D.p2 * D.s + 20.0 * D.p2)
    plan = plan_split(D2, DiagnoseSettings())
    cur = fit_model(D2, ("pressure_friction",), experiments=plan.train)
    ctx = _round_context(D2, cur, plan)
    terms = select_terms(D2, ctx, plan.folds, assemble(D2, cur.effects, cur.shapes, ctx)[0])
    assert "p*dir" not in terms and terms and terms[0] == "p"


def test_clean_data_gives_no_or_few_library_terms(D):
    assert len(_selected(D)) <= 1


def test_at_most_max_terms_are_kept(D):
    extra = 20 * D.p2 + 30 * np.exp(-D.t / 3.0) + 10 * D.s * np.exp(-np.abs(D.x) / 3.0) + 0.5 * np.abs(D.v) + 15 * D.s * D.x / D.travel_mm
    assert 1 <= len(_selected(_with(D, extra))) <= MAX_TERMS


def test_made_effect_reads_back_from_its_id_and_rejects_unknown_terms():
    e = REGISTRY["states[p|1]"]
    assert isinstance(e, StateTerms) and e.id == "states[p|1]" and e.terms == ("p", "1") and not e.catalogue
    assert [q.unit for q in e.params(None)] == ["N/MPa", "N"]
    assert "states[p|1]" not in list(REGISTRY)  # made, not listed among the candidates
    assert is_effect_id(states_id(("tc*damp",))) and REGISTRY[states_id(("tc*damp",))].needs == ("damping_force_N",)
    assert [q.unit for q in REGISTRY["states[tc*damp]"].params(None)] == ["1/h"]
    assert not is_effect_id("states[nonsense]") and not is_effect_id("states[]")


def test_made_effect_describes_the_states_it_follows():
    e = REGISTRY["states[p|1]"]
    txt = e.describe({"c[p]": 10.9, "c[1]": 0.03}, {}, np.nan, np.nan)
    assert "the charge p2" in txt and "independent of motion and position" in txt and "+10.9 N/MPa" in txt
    txt = REGISTRY["states[tc*damp]"].describe({"c[tc*damp]": 0.02}, {}, np.nan, np.nan)
    assert "campaign" in txt and "throttle force" in txt and "independent of motion" not in txt


def _trial(gain, t, sse=True):
    ev = Evidence(1, gain, t, 0, 5, 0, 0.0, 0.0, 1.0, True, None, False, ())
    return _Trial("x", np.zeros(3) if sse else None, np.nan, ev, None)


def test_a_candidate_that_explained_nothing_is_not_tested_again():
    assert _settles(_trial(-0.001, -1.0))
    assert _settles(_trial(0.0, 0.0))
    assert _settles(_trial(0.5, 3.0, sse=False))  # could not be fitted
    assert not _settles(_trial(0.001, -1.0))  # some gain: tested again
    assert not _settles(_trial(-0.001, 0.5))  # consistent over experiments: tested again
