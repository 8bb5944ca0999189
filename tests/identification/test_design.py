"""Tests of the design matrix: one preallocated array equals eq. 14's columns with each effect's stacked, masked and
transformed."""

from __future__ import annotations

import numpy as np

from vvea_design.identification.design import assemble, baseline_columns
from vvea_design.identification.effects import REGISTRY
from vvea_design.identification.fitting import fit_model


def test_assemble_equals_the_stacked_columns(D):
    """One preallocated design equals eq. 14's columns, masked, with each effect's columns stacked and transformed."""
    base = fit_model(D, ())
    ctx = base.context(D)
    ctx["model_force_N"] = base.predict(D)
    ctx["residual_N"] = ctx["residual_all_N"] = D.y - ctx["model_force_N"]
    cases = [
        ((), {}),
        (("gas_nonlinearity", "stiction"), {"gas_nonlinearity": 3e5, "stiction": 0.3}),
        (("relief_valve", "thermal"), {"relief_valve": 400.0, "thermal": 2.0}),
        (("stiction", "force_lag"), {"stiction": 0.3, "force_lag": 0.05}),
    ]
    for effects, shapes in cases:
        X, params, groups = assemble(D, effects, shapes, ctx)
        X0 = baseline_columns(D)[0].copy()
        cols = [X0]
        for e in effects:
            m = REGISTRY[e].damping_mask(D, shapes[e], ctx)
            if m is not None:
                X0[m, 2:] = 0.0
            cols.append(REGISTRY[e].columns(D, shapes[e], ctx))
        ref = np.column_stack(cols)
        for e in effects:
            if REGISTRY[e].transforms_design:
                ref = REGISTRY[e].transform(D, ref, shapes[e], ctx, eq14_first=True)  # the whole design, eq. 14 first
        assert X.shape == ref.shape == (D.n, len(params))
        np.testing.assert_array_equal(X, ref)
        assert groups["eq14"] == slice(0, X0.shape[1])
