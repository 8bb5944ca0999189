"""Tests of the held-out guard (a term stays only if it lowers the held-out error and passes its own checks)
and of naming from dependence (a catalogue name needs the catalogue effect's dependence on the states)."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import pytest

from vvea_benches.testbench import simulate, small_spec
from vvea_design.identification.dependence import dependence_profile, describe_dependence, main_states, per_charge_share
from vvea_design.identification.effects import REGISTRY, Check, Effect, Param
from vvea_design.identification.fit_data import FitData
from vvea_design.identification.guard import heldout_guard, heldout_rmse
from vvea_design.identification.recordings import recordings_from_frame
from vvea_design.identification.selection import _Trial, plan_split
from vvea_design.identification.fitting import fit_model
from vvea_design.identification.report import Evidence
from vvea_design.identification.settings import DiagnoseSettings


#: A force proportional to the charge plus a constant: a candidate of the state library (made from its id).
OFFSET = "states[p|1]"


def _frame():
    return simulate(small_spec(seed=7, noise_N=3.0)).frame.copy()


def _data(frame):
    return FitData.from_recordings(recordings_from_frame(frame, "guard"))


def _evidence():
    return Evidence(1, 0.5, 10.0, 5, 5, 0, 1.0, 10.0, 3.0, True, None, True, ())


@pytest.fixture(scope="module")
def split_offset():
    """A charge offset on the training experiments only: fitted on them, it makes the held-out experiments worse."""
    frame = _frame()
    D0 = _data(frame)
    plan = plan_split(D0, DiagnoseSettings())
    names = frame["experiment"].drop_duplicates().to_numpy()
    train_names = set(names[plan.train])
    on = frame["experiment"].isin(train_names).to_numpy()
    frame.loc[on, "force_N"] += 25.0 * frame.loc[on, "p2_MPa"]
    D = _data(frame)
    return D, plan_split(D, DiagnoseSettings())


def test_guard_removes_a_term_that_raises_the_heldout_error(split_offset):
    D, plan = split_offset
    assert len(plan.test) > 0
    trials = {OFFSET: _Trial(OFFSET, None, np.nan, _evidence(), None)}
    kept, removed = heldout_guard(D, plan, [OFFSET], {}, trials)
    assert kept == []
    assert "does not lower the error on the held-out experiments" in removed[OFFSET]
    ev = trials[OFFSET].evidence
    assert ev.passes is False and "held-out guard" in ev.reasons[-1]
    # with the term the held-out error is indeed worse than eq. 14's
    base = heldout_rmse(D, fit_model(D, (), experiments=plan.train), plan.test)
    with_term = heldout_rmse(D, fit_model(D, (OFFSET,), experiments=plan.train), plan.test)
    assert with_term > base


def test_guard_keeps_a_term_that_lowers_the_heldout_error():
    frame = _frame()
    frame["force_N"] += 25.0 * frame["p2_MPa"]  # the same offset on every experiment
    D = _data(frame)
    plan = plan_split(D, DiagnoseSettings())
    kept, removed = heldout_guard(D, plan, [OFFSET], {}, {})
    assert kept == [OFFSET] and removed == {}


@dataclass(frozen=True)
class _AlwaysFails(Effect):
    def columns(self, D, _, ctx):
        return D.p2[:, None]

    def signature(self, D, values, shape, contribution):
        return [Check("never holds", False, "a check that always fails")]


def test_a_failed_signature_unaccepts_its_term(monkeypatch):
    eff = _AlwaysFails("always_fails_test", "test", "A test effect.", "f += a p2", (Param("a", "N/MPa", 0.0, np.inf),))
    monkeypatch.setitem(REGISTRY, eff.id, eff)
    frame = _frame()
    frame["force_N"] += 25.0 * frame["p2_MPa"]
    D = _data(frame)
    plan = plan_split(D, DiagnoseSettings())
    trials = {eff.id: _Trial(eff.id, None, np.nan, _evidence(), None)}
    kept, removed = heldout_guard(D, plan, [eff.id], {}, trials)
    assert kept == []
    assert "signature check fails" in removed[eff.id] and "always fails" in removed[eff.id]
    assert trials[eff.id].evidence.passes is False


@pytest.fixture(scope="module")
def D():
    return _data(_frame())


def test_dependence_names_the_charge_for_a_charge_offset(D):
    prof = dependence_profile(D, 30.0 * D.p2)
    assert main_states(prof)[0] == "charge"
    txt = describe_dependence(prof)
    assert "charge" in txt and "independent of motion and position" in txt
    assert per_charge_share(D, 30.0 * D.p2) == pytest.approx(1.0)


def test_dependence_names_the_position_for_a_band(D):
    band = 40.0 * D.s * ((D.x > 10) & (D.x < 15))
    ms = main_states(dependence_profile(D, band))
    assert "position" in ms or "direction" in ms
    assert "charge" not in ms and "campaign_order" not in ms


def _leak_checks(D, values, contribution):
    return {c.name: c.passed for c in REGISTRY["leakage"].signature(D, values, np.nan, contribution)}


def test_leakage_name_needs_a_falling_charge_that_changes_over_the_campaign(D):
    th = D.ctime / 3600.0
    zero = dict(q0=0.0, q=0.0, q2=0.0, q1=0.0, c0=0.0, c=0.0)
    leak = dict(zero, q=2.0)
    ok = _leak_checks(D, leak, -2.0 * D.p2 * D.x * th)
    assert all(ok.values()), ok
    # a charge that rises at the end of the campaign (the t^2 term outgrows the loss) is not a leak
    T = float(th.max())
    rising = dict(zero, q=2.0, c=4.0 / T)
    got = _leak_checks(D, rising, D.p2 * D.x * (-2.0 * th + (4.0 / T) * th**2))
    assert got["the charge falls throughout the campaign"] is False
    # an offset that follows the charge and not the campaign order is not a leak
    got = _leak_checks(D, leak, -20.0 * D.p2)
    assert got["changes with campaign order, not with the charge alone"] is False


def test_a_stiffness_equal_in_both_directions_is_not_called_direction_dependent():
    eff = REGISTRY["direction_stiffness"]
    same = eff.describe(dict(k_ext=2.12, k_ret=2.17, dk_p=0.0), dict(k_ext=0.05, k_ret=0.05, dk_p=0.01), np.nan, np.nan)
    assert "same in both directions" in same and "not a direction-dependent" in same
    diff = eff.describe(dict(k_ext=2.0, k_ret=-1.0, dk_p=0.0), dict(k_ext=0.05, k_ret=0.05, dk_p=0.01), np.nan, np.nan)
    assert "differs between extension and retraction" in diff
