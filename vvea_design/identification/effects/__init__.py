"""The effects the paper's eq. 14 leaves out: one module per effect or family, each registering itself.

The baseline is the paper's identification model (eq. 14)::

    f = g p2 x + L(γ) ẋ + C sign(ẋ)

:mod:`.base` holds the :class:`~.base.Effect` object (fit columns, shape
grid, signature checks, sentence, bench force), its :class:`~.base.Param`
and :class:`~.base.Check`, and the :data:`REGISTRY`. Every other module of
this package is found on import (:func:`pkgutil.iter_modules`) and registers
its effects where it defines them, so **adding an effect touches one file**:
a new module here. Its module-level ``RANK`` places its effects among the
candidates (lower first; a module without one comes after the ranked ones,
by name); the candidates are tested in that order.

Two kinds of effects live in the registry:

- **catalogue** effects (``catalogue=True``): named physics of the unit
  (``shared/specs/diagnosis-report.md``). Each fits a *family* of physical
  forms, not one formula, so that the real form of the effect is followed:

  ===================  ======================================================
  id                   added force (N)
  ===================  ======================================================
  gas_nonlinearity     p2 (a2 r2(x; V2) + a1 r1(x)): eq. 5's two chamber
                       forces of the unit's geometry, each minus its straight
                       line; V2 free (an effective, polytropic volume)
  thermal              p2 (k_i f_i h_i + s_i f_i h_i² + k h),  ḣ_i = u̇_i - h_i/τ  (wall heat
                       exchange per chamber, chamber 1 at τ/2, τ, 2τ; second order)
  quadratic_damping    K(γ) ẋ|ẋ|^(m-1)   (orifice flow, exponent m fitted)
  relief_valve         soft knee: above F_open the throttle force follows
                       c F_open + r (L ẋ - F_open), c near 1
  stiction             sign(ẋ) (S1 e^(-|ẋ|/v_s) + S2 e^(-(|ẋ|/v_s)²))  (Stribeck
                       shape between exponential and Gaussian)
  pressure_friction    c_p p2 sign(ẋ)
  leakage              -p2 t_c (q0 + q x + curvature) + p2 t_c² (c0 + c x)
                       (the charge, and all it carries, decays over campaign time)
  ===================  ======================================================

  one module each: :mod:`.gas_nonlinearity`, :mod:`.thermal`,
  :mod:`.quadratic_damping`, :mod:`.relief_valve`, :mod:`.stiction`,
  :mod:`.pressure_friction`, :mod:`.leakage`.

- **discovery operators** (``catalogue=False``): interpretable operators on the
  measured signals for physics nobody listed, one module per family: lags of
  the force reading (:mod:`.force_lag`); relaxing memory of the damping force
  and of the motion (:mod:`.memory`); play/stop hysteresis operators
  (:mod:`.hysteresis`); Fourier terms in displacement and in time, pitch or
  frequency found by a periodogram of the residual (:mod:`.ripple`);
  direction-dependent stiffness and state polynomials (:mod:`.polynomials`);
  campaign-time trends (:mod:`.trend`). Each translates its fitted
  parameters into a physical signature and a sentence. Beside them, each
  selection round offers a sparse sum of terms of a general library of the
  measured states and their histories (:mod:`.library`, ids ``states[...]``
  made on lookup), described by the states it follows.

Residual sign convention everywhere: residual = measurement − model (N).
"""

from __future__ import annotations

import importlib
import math
import pkgutil
import sys

from .base import REGISTRY, Check, Effect, Param, effect_columns, is_effect_id, register

__all__ = ["REGISTRY", "CATALOGUE", "DISCOVERY", "EFFECT_IDS", "DISCOVERY_IDS", "Effect", "Param", "Check", "register",
           "is_effect_id", "effect_columns", "discover"]


def discover() -> tuple[str, ...]:
    """Import every effect module of this package (all but :mod:`.base` and private ones) and order the registry.

    Importing a module registers its effects (a module already imported is not run again). The registry is
    then ordered by the ``RANK`` of the module that defines each effect's class (lower first, unranked
    modules last by name), registration order within a module: the order the selection tests the
    candidates in. Runs once on import of this package.

    Returns
    -------
    tuple of str
        Dotted names of the effect modules, lowest ``RANK`` first.
    """
    names = sorted(m.name for m in pkgutil.iter_modules(__path__) if m.name != "base" and not m.name.startswith("_"))
    for name in names:
        importlib.import_module(f"{__name__}.{name}")

    def rank(module: str) -> tuple:
        return (getattr(sys.modules.get(module), "RANK", math.inf), module)

    seq = {k: i for i, k in enumerate(REGISTRY)}
    ordered = sorted(REGISTRY.items(), key=lambda kv: (rank(type(kv[1]).__module__), seq[kv[0]]))
    REGISTRY.clear()
    REGISTRY.update(ordered)
    return tuple(sorted((f"{__name__}.{n}" for n in names), key=rank))


discover()

#: Catalogue effects (named physics of the unit), in registry order.
CATALOGUE: dict[str, Effect] = {k: e for k, e in REGISTRY.items() if e.catalogue}
#: Discovery operators, in registry order.
DISCOVERY: dict[str, Effect] = {k: e for k, e in REGISTRY.items() if not e.catalogue}
#: The catalogue's effect ids.
EFFECT_IDS: tuple[str, ...] = tuple(CATALOGUE)
#: The discovery operators' ids.
DISCOVERY_IDS: tuple[str, ...] = tuple(DISCOVERY)
