"""Small campaigns for the blind bench's tests (few samples per ramp: fast)."""

import numpy as np
import pytest

from vvea_benches.blind.motion import Motion, plan_campaign
from vvea_benches.blind.simulate import ExperimentMods, simulate_experiment
from vvea_benches.blind.spec import CampaignContext
from vvea_benches.blind.unit import sample_base

N_PER_RAMP = 40


def make_ctx(seed=3, gas_law="chambers", n_per_ramp=N_PER_RAMP):
    rng = np.random.default_rng(seed)
    base = sample_base(rng, gas_law)
    plans = tuple(plan_campaign(rng, n_per_ramp))
    motions = tuple(Motion(p.speed_mm_s, n_per_ramp=n_per_ramp) for p in plans)
    return CampaignContext(base, plans, motions, seed)


def simulate(ctx, mechanisms=(), indices=None):
    """Noise-free simulation of the selected experiments with the given (spec, params) pairs applied."""
    mods = [ExperimentMods(valve_deg=p.valve_deg) for p in ctx.plans]
    for spec, params in mechanisms:
        spec.apply(params, ctx, mods)
    idx = range(len(ctx.plans)) if indices is None else indices
    return {i: simulate_experiment(ctx.base, ctx.plans[i], mods[i], ctx.motions[i]) for i in idx}, mods


def find(ctx, p2=None, valve=None, speed=None):
    """Index of the first experiment with these settings."""
    for i, p in enumerate(ctx.plans):
        if (p2 is None or p.p2_MPa == p2) and (valve is None or p.valve_deg == valve) and (
                speed is None or p.speed_mm_s == speed):
            return i
    raise LookupError((p2, valve, speed))


@pytest.fixture(scope="module")
def ctx():
    return make_ctx()


class _Bench:
    make_ctx = staticmethod(make_ctx)
    simulate = staticmethod(simulate)
    find = staticmethod(find)


@pytest.fixture(scope="session")
def bench():
    """The helpers above: ``bench.make_ctx``, ``bench.simulate``, ``bench.find``."""
    return _Bench()
