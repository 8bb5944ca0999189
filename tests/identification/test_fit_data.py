"""Tests of the fit data's cache: every entry counts against its byte budget, and eviction moves no bit."""

from __future__ import annotations

import numpy as np

from vvea_design.identification import fit_data, signals
from vvea_design.identification.effects import REGISTRY, effect_columns


def test_cache_budget_counts_every_entry_and_eviction_moves_no_bit(D, monkeypatch):
    """Every entry of a FitData's cache (columns, fine grids, velocity gaps, ...) counts against its byte budget, and
    what an evicted entry is rebuilt into is bit for bit what the roomy cache held (memory on large campaigns)."""
    import dataclasses

    from scipy.signal import lfilter

    def run(Dc):
        op = lambda seg, dt: lfilter([1.0 - np.exp(-dt / 0.05)], [1.0, -np.exp(-dt / 0.05)], seg, axis=1)  # noqa: E731
        out = []
        for _ in range(2):  # the second pass reads what survived in the cache (or rebuilds it)
            out.append(signals._velocity_correction(Dc, op))
            out.append(REGISTRY["force_filter_lag"].transform(Dc, np.column_stack([Dc.x, np.ones(Dc.n)]), 0.05, {}))
            out += [effect_columns(Dc, REGISTRY[e], s, {}) for e, s in (("stiction", 2.0), ("quadratic_damping", 1.6), ("thermal", 3.0))]
            out.append(signals.travel_since_reversal(Dc))
            sizes = [fit_data._nbytes(v) for v in Dc._cache.values()]
            assert sum(sizes) <= fit_data.CACHE_BYTES or len(sizes) == 1
        return out

    roomy = run(dataclasses.replace(D, _cache={}))
    monkeypatch.setattr(fit_data, "CACHE_BYTES", 3 * 8 * D.n)  # three columns' worth: most entries are evicted and rebuilt
    tight = run(dataclasses.replace(D, _cache={}))
    for a, b in zip(roomy, tight):
        np.testing.assert_array_equal(a.view(np.int64), b.view(np.int64))
