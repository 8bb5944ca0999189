"""Tests of the effects package: the registry (its order, its discovery of effect modules, the structure rule
that only effects key on effect ids), and the effects' columns and transforms (small sizes, exact references)."""

from __future__ import annotations

import json
import os
import shutil
import subprocess
import sys

import numpy as np
import pytest
from scipy.signal import bilinear
from tests.helpers import REPO

from vvea_benches.testbench import simulate, small_spec
from vvea_design.identification import effects as fx
from vvea_design.identification.diagnose import diagnose
from vvea_design.identification.effects import CATALOGUE, DISCOVERY, DISCOVERY_IDS, EFFECT_IDS, REGISTRY, Effect, Param
from vvea_design.identification.effects.force_lag import _bilinear_2nd_order, filter_id
from vvea_design.identification.recordings import recordings_from_frame
from vvea_design.identification.settings import DiagnoseSettings

SPEC_IDS = {"gas_nonlinearity", "thermal", "quadratic_damping", "relief_valve", "stiction", "pressure_friction", "leakage"}


def test_registry_covers_the_spec_and_is_signed():
    assert SPEC_IDS <= set(EFFECT_IDS)
    assert set(CATALOGUE) | set(DISCOVERY) == set(REGISTRY)
    for e in REGISTRY.values():
        assert e.physics and e.equation and e.title
        assert isinstance(e, Effect)
    for e in CATALOGUE.values():
        for p in e.amplitudes:
            assert p.lower >= 0.0, f"{e.id}.{p.name} must carry its physical sign"


def test_no_if_chains_on_effect_ids_outside_the_registry():
    """fitting, selection, report and the bench call effect methods; no code outside the effects package keys on an
    effect id."""
    src = REPO / "vvea_design" / "identification"
    files = [p for p in sorted(src.rglob("*.py")) if "effects" not in p.relative_to(src).parts]
    files.append(REPO / "benches" / "vvea_benches" / "testbench.py")
    assert {p.name for p in files} >= {"identify.py", "diagnose.py", "selection.py", "fitting.py", "report.py", "testbench.py"}
    for path in files:
        text = path.read_text()
        for eid in REGISTRY:
            assert f'== "{eid}"' not in text and f'"{eid}" in ' not in text, (path.name, eid)


def test_the_candidates_keep_their_order():
    """The effect modules' ranks give the registry the order the selection tests the candidates in (a tie in a
    round goes to the first)."""
    assert EFFECT_IDS == ("gas_nonlinearity", "thermal", "quadratic_damping", "relief_valve", "stiction", "pressure_friction",
                          "leakage")
    assert DISCOVERY_IDS == ("force_lag", "force_filter_lag", "damping_lag", "motion_memory", "presliding_hysteresis", "position_ripple",
                             "time_ripple", "direction_stiffness", "spring_polynomial", "charge_curvature", "pressure_damping",
                             "friction_along_stroke", "campaign_trend")
    assert tuple(REGISTRY) == EFFECT_IDS + DISCOVERY_IDS
    assert DiagnoseSettings().candidates == EFFECT_IDS and DiagnoseSettings().discovery == DISCOVERY_IDS
    ranks = [sys.modules[m].RANK for m in fx.discover()]
    assert ranks == sorted(ranks)


_NEW_EFFECT = """
from dataclasses import dataclass

import numpy as np

from .base import Effect, Param, register


@dataclass(frozen=True)
class CubicFriction(Effect):
    def columns(self, D, _, ctx):
        return (D.s * (D.x / 40.0) ** 3)[:, None]


register(CubicFriction("cubic_friction", "cubic friction", "Friction growing along the stroke.", "f += b sign(xdot) (x/40)^3",
                       (Param("b", "N", 0.0, np.inf),), catalogue={catalogue}))
"""


@pytest.mark.parametrize("catalogue", [False, True])
def test_a_new_effect_module_registers_itself(tmp_path, catalogue):
    """Adding an effect touches one file: a module dropped into the effects package (a copy of the package here) is
    found on import, registered, ranked after the others and offered to the selection -- no other file edited."""
    pkg = tmp_path / "vvea_design"
    shutil.copytree(REPO / "vvea_design", pkg, ignore=shutil.ignore_patterns("__pycache__", "vendor"))
    (pkg / "identification" / "effects" / "cubic_friction.py").write_text(_NEW_EFFECT.replace("{catalogue}", str(catalogue)))
    code = ("import json; from vvea_design.identification import effects as fx; "
            "from vvea_design.identification.settings import DiagnoseSettings; s = DiagnoseSettings(); "
            "print(json.dumps(dict(file=fx.__file__, ids=list(fx.REGISTRY), catalogue=list(fx.EFFECT_IDS), "
            "discovery=list(fx.DISCOVERY_IDS), candidates=list(s.candidates) + list(s.discovery), "
            "modules=list(fx.discover()))))")
    env = dict(os.environ, PYTHONPATH=str(tmp_path))
    r = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, env=env, cwd=tmp_path, timeout=300)
    assert r.returncode == 0, r.stderr
    got = json.loads(r.stdout.strip().splitlines()[-1])
    assert got["file"].startswith(str(tmp_path))  # the copy was imported, not the checkout
    assert got["ids"] == list(REGISTRY) + ["cubic_friction"]  # the others keep their order; unranked comes last
    assert ("cubic_friction" in got["catalogue"]) == catalogue and ("cubic_friction" in got["discovery"]) != catalogue
    assert "cubic_friction" in got["candidates"]
    assert got["modules"][-1].endswith(".cubic_friction")


def test_a_new_effect_is_one_registered_object(monkeypatch):
    """Adding a term touches one place: an Effect object in the registry, found by the selection."""

    class CubicFriction(Effect):
        def columns(self, D, _, ctx):
            return (D.s * (D.x / 40.0) ** 3)[:, None]

    eff = CubicFriction("cubic_test", "cubic friction", "Friction growing along the stroke.", "f += b sign(xdot) (x/40)^3",
                        (Param("b", "N", 0.0, np.inf),), catalogue=False)
    monkeypatch.setitem(REGISTRY, eff.id, eff)
    frame = simulate(small_spec(seed=5)).frame.copy()
    v = np.gradient(frame["displacement_mm"].to_numpy())
    frame["force_N"] += 40.0 * np.sign(v) * (frame["displacement_mm"] / 40.0) ** 3
    d = diagnose(recordings_from_frame(frame, "cubic"), DiagnoseSettings(learner=False, discovery=("cubic_test",)))
    assert [e.id for e in d.report.accepted] == ["cubic_test"]


def test_fitted_filter_ids_are_made_on_lookup_and_checked():
    from vvea_design.identification.effects import is_effect_id

    assert filter_id(0.7334) == "force_filter_lag_z0733"
    e = REGISTRY["force_filter_lag_z0733"]
    assert e.zeta == 0.733 and not e.catalogue
    assert "force_filter_lag_z0733" not in REGISTRY  # made, not listed among the candidates
    assert is_effect_id("force_filter_lag_z0733") and not is_effect_id("force_filter_lag_zz")
    with pytest.raises(KeyError):
        REGISTRY["no_such_effect"]
    with pytest.raises(ValueError, match="zeta"):
        filter_id(3.0)


def test_second_order_filter_coefficients_equal_scipy_bilinear():
    for lag in (0.003, 0.05, 0.7, 3.0):
        for dt in (0.001, 0.02, 0.5):
            wn = 2 * 0.7071 / lag
            b, a = _bilinear_2nd_order(wn, 0.7071, 1.0 / dt)
            br, ar = bilinear([wn**2], [1.0, 2 * 0.7071 * wn, wn**2], fs=1.0 / dt)
            np.testing.assert_allclose(b, br, rtol=1e-13)
            np.testing.assert_allclose(a, ar, rtol=1e-13, atol=1e-15)


@pytest.mark.parametrize("eid", [e.id for e in REGISTRY.values() if e.transforms_design])
def test_sensor_transforms_in_place_equal_the_copying_ones(D, eid):
    """``transform(..., out=X)`` (assemble filters the design in place) equals the transform into a new array."""
    eff = REGISTRY[eid]
    X = np.column_stack([D.x, np.sin(3 * D.t), np.ones(D.n)])
    shape = float(np.median(eff.grid(D, {})))
    ref = eff.transform(D, X.copy(), shape, {})
    Xi = X.copy()
    got = eff.transform(D, Xi, shape, {}, out=Xi)
    assert got is Xi
    np.testing.assert_allclose(got, ref, rtol=0, atol=1e-12 * np.abs(ref).max())


def test_time_ripple_scan_reuses_the_phases_of_shared_samplings_exactly(D):
    """Experiments sampled alike share one cos/sin table: the periodogram is the direct one, bit for bit."""
    r = np.random.default_rng(0).normal(size=D.n)
    periods = np.geomspace(0.05, 20.0, 50)
    rows = np.ones(D.n, bool)
    w = 2 * np.pi / periods
    ref = np.zeros(len(periods))
    for e in range(D.n_exp):
        a, b = D.bounds[e], D.bounds[e + 1]
        ph = np.outer(D.t[a:b], w)
        re = r[a:b] - r[a:b].mean()
        ref += (re @ np.cos(ph)) ** 2 + (re @ np.sin(ph)) ** 2
    assert len({D.t[D.bounds[e] : D.bounds[e + 1]].tobytes() for e in range(D.n_exp)}) < D.n_exp  # shared samplings exist
    np.testing.assert_array_equal(REGISTRY["time_ripple"]._power(D, r, periods, rows), ref)


@pytest.mark.parametrize("eid", [e.id for e in REGISTRY.values() if not e.needs])
def test_columns_of_effects_without_needs_do_not_read_the_context(D, eid):
    """``effect_columns`` caches the columns of effects without ``needs`` per shape: they must not depend on the context."""
    eff = REGISTRY[eid]
    rng = np.random.default_rng(1)
    ctx = {k: rng.normal(size=D.n) * 50 for k in ("damping_force_N", "model_force_N", "residual_N", "residual_all_N")}
    grid = np.asarray(eff.grid(D, ctx), float) if eff.shape is not None else np.array([np.nan])
    if len(grid) == 0:
        pytest.skip("no grid on this campaign")
    shape = float(grid[len(grid) // 2])
    ref = eff.columns(D, shape, ctx)
    np.testing.assert_array_equal(eff.columns(D, shape, {}), ref)
    got = fx.effect_columns(D, eff, shape, ctx)
    np.testing.assert_array_equal(got, ref)
    assert fx.effect_columns(D, eff, shape, {}) is got  # the second call is the cached array


def test_quadratic_damping_columns_put_each_sample_on_its_valve(D):
    """K(gamma) columns: xdot |xdot|^(m-1) in the column of the sample's valve, zero in the others."""
    m = 1.7
    X = REGISTRY["quadratic_damping"].columns(D, m, {})
    assert X.shape == (D.n, len(D.valves))
    q = D.v * np.abs(D.v) ** (m - 1.0)
    for j, g in enumerate(D.valves):
        on = D.valve == g
        np.testing.assert_array_equal(X[on, j], q[on])
        assert not np.any(X[~on, j])
