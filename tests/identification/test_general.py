"""Tests of names from evidence (a catalogue name must beat general terms on its states), the noise bound,
the numerical guard of the candidate fits and the backward step's protection of a catalogue form."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import pytest

from vvea_benches.testbench import simulate, small_spec
from vvea_design.identification.effects import REGISTRY, Effect, Param
from vvea_design.identification.fit_data import FitData
from vvea_design.identification.fitting import fit_model
from vvea_design.identification.general import general_sse, fold_residuals, name_evidence, noise_upper_bound
from vvea_design.identification.last_stage import FEATURES
from vvea_design.identification.least_squares import blocks
from vvea_design.identification.design import assemble
from vvea_design.identification.noise import noise_floor_N
from vvea_design.identification.recordings import recordings_from_frame
from vvea_design.identification.selection import _cv_current, _score_safely, plan_split
from vvea_design.identification.settings import DiagnoseSettings

S = DiagnoseSettings()


def _data(frame):
    return FitData.from_recordings(recordings_from_frame(frame, "general"))


def _frame(noise_N=3.0, seed=11):
    return simulate(small_spec(seed=seed, noise_N=noise_N)).frame.copy()


# ------------------------------------------------------------------ name_evidence (pure)
def _sse(n=30, level=100.0, seed=0):
    return level * (1.0 + 0.05 * np.random.default_rng(seed).standard_normal(n))


def test_a_formula_whose_states_carry_little_of_the_structure_is_not_named():
    base = _sse(level=100.0)
    allst = _sse(level=10.0, seed=1)  # trees on all states remove 90 %
    same = _sse(level=90.0, seed=2)  # trees on the formula's states only 10 %
    cat = _sse(level=92.0, seed=3)
    ne = name_evidence(base, cat, same, allst, np.arange(30), ("velocity", "valve"), S)
    assert not ne.ok and "does not depend on the states" in ne.reason
    assert ne.states_share == pytest.approx(10 / 90, rel=0.2)


def test_a_formula_beaten_by_a_general_function_of_its_states_is_not_named():
    base = _sse(level=100.0)
    allst = _sse(level=10.0, seed=1)
    same = _sse(level=12.0, seed=2)  # the same states carry nearly all of it
    cat = _sse(level=60.0, seed=3)  # the formula removes less than half of it
    ne = name_evidence(base, cat, same, allst, np.arange(30), ("charge", "position"), S)
    assert not ne.ok and "a general function of the same states" in ne.reason
    assert ne.general_t > S.name_t


def test_a_formula_as_good_as_the_general_function_keeps_its_name():
    base = _sse(level=100.0)
    allst = _sse(level=10.0, seed=1)
    same = _sse(level=11.0, seed=2)
    cat = _sse(level=11.5, seed=3)
    ne = name_evidence(base, cat, same, allst, np.arange(30), ("charge", "position"), S)
    assert ne.ok and ne.reason == ""
    assert ne.general_share == pytest.approx((100 - 11.5) / (100 - 11.0), rel=0.05)


def test_non_finite_errors_give_no_verdict():
    base = _sse()
    cat = base.copy()
    cat[3] = np.nan
    assert name_evidence(base, cat, base, base, np.arange(30), ("velocity",), S).ok


# ------------------------------------------------------------------ general terms on a campaign
@pytest.fixture(scope="module")
def offset_campaign():
    """eq. 14 + a force proportional to the charge (independent of motion): the charge carries it, the velocity not."""
    frame = _frame()
    frame["force_N"] += 30.0 * frame["p2_MPa"]
    D = _data(frame)
    return D, plan_split(D, S)


def test_general_terms_find_the_structure_along_the_right_states(offset_campaign):
    D, plan = offset_campaign
    cur = fit_model(D, (), experiments=plan.train)
    _, X0, blk, base_sse = _cv_current(D, cur, plan)
    res = fold_residuals(D, X0, blk, plan)
    tr = plan.train
    # eq. 14's refitted spring takes part of the offset: what is left is a function of the charge and the position
    charge = general_sse(D, plan, res, ("charge", "position"))
    velocity = general_sse(D, plan, res, ("velocity", "valve"))
    everything = general_sse(D, plan, res, tuple(FEATURES))
    gain = lambda z: 1.0 - z[tr].sum() / base_sse[tr].sum()  # noqa: E731
    assert gain(charge) > 0.9 and gain(everything) > 0.9
    assert gain(velocity) < 0.2 * gain(charge)
    assert np.all(np.isnan(charge[plan.test]))  # only the training experiments are scored
    # a damping law fitted to it would not be named: its states carry little of what all states carry
    ne = name_evidence(base_sse, base_sse * 0.9, velocity, everything, tr, ("velocity", "valve"), S)
    assert not ne.ok


def test_noise_bound_sees_through_a_friction_band():
    """A friction step over a band of the stroke inflates the periodogram floor; the trees' held-out RMS bounds it."""
    frame = _frame(noise_N=2.0, seed=13)
    x = frame["displacement_mm"].to_numpy()
    dx = frame.groupby("experiment")["displacement_mm"].diff().bfill().to_numpy()
    band = (x > 0.3 * x.max()) & (x < 0.5 * x.max())
    frame["force_N"] += 60.0 * band * np.sign(dx)
    D = _data(frame)
    plan = plan_split(D, S)
    floor = noise_floor_N(D, D.y - fit_model(D, (), experiments=plan.train).predict(D))
    bound = noise_upper_bound(D, plan)
    assert np.isfinite(bound) and bound < floor
    assert bound < 4.0 * 2.0  # within a few times the true 2 N


# ------------------------------------------------------------------ numerical guard
@dataclass(frozen=True)
class _Overflows(Effect):
    def columns(self, D, _, ctx):
        return np.column_stack([D.x * 1e200, D.x * 1e200 * (1.0 + 1e-16)])


@dataclass(frozen=True)
class _NotFinite(Effect):
    def columns(self, D, _, ctx):
        c = D.p2.copy()
        c[::7] = np.nan
        return c[:, None]


@pytest.mark.parametrize("cls", [_Overflows, _NotFinite])
def test_a_candidate_whose_fit_blows_up_is_rejected_without_a_gain(monkeypatch, cls):
    eff = cls(f"blowup_test_{cls.__name__.lower()}", "test", "A test effect.", "f += a c",
              tuple(Param(f"a{i}", "N", -np.inf, np.inf) for i in range(2 if cls is _Overflows else 1)), catalogue=False)
    monkeypatch.setitem(REGISTRY, eff.id, eff)
    D = _data(_frame(seed=17))
    plan = plan_split(D, S)
    cur = fit_model(D, (), experiments=plan.train)
    ctx, X0, blk, base_sse = _cv_current(D, cur, plan)
    tri = _score_safely(D, cur, eff.id, ctx, plan, base_sse, blk, X0, 3.0, S, 1)
    ev = tri.evidence
    assert ev is not None and ev.passes is False
    assert not np.isfinite(ev.cv_gain) or ev.cv_gain > -10.0  # never a gain like -1e19
    assert any("numerically" in r for r in ev.reasons)
