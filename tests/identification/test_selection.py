"""Tests of the selection's machinery (the selection rules against the independent bench are in
test_diagnose_families.py)."""

from __future__ import annotations

import numpy as np
import pytest

from vvea_design.identification import selection
from vvea_design.identification.design import assemble
from vvea_design.identification.effects import REGISTRY


@pytest.mark.parametrize("eid", [e.id for e in REGISTRY.values() if e.transforms_design and not e.params(None)])
def test_filter_only_candidate_design_equals_the_assembled_one(D, eid):
    """The CV of a filter-only candidate filters the current design instead of rebuilding it: the same design, bit for bit."""
    base = ("stiction", "thermal")
    shapes = {"stiction": 8.0, "thermal": 1.5, eid: 0.05}
    X0, _, _ = assemble(D, base, shapes, {})
    X, _, _ = assemble(D, base + (eid,), shapes, {})
    np.testing.assert_array_equal(selection._filtered_design(D, REGISTRY[eid], X0, 0.05, {}), X)
