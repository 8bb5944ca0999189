"""The effect object, its parameters and checks, and the registry every effect module adds to.

An :class:`Effect` is everything the tool knows about one piece of physics
that the paper's eq. 14 (``f = g p2 x + L(γ) ẋ + C sign(ẋ)``) leaves out:
its fit columns (linear amplitudes with physical bounds, at most one *shape*
parameter searched on a grid), the context it needs from the current model,
its equation and an engineer's sentence, its physical signature checks and,
for the unit-test bench (``vvea_benches.testbench``), the force it adds to a
simulated bench. Each effect module of this package registers its effects
with :func:`register` where it defines them; :data:`REGISTRY` holds them by
id, and identification, diagnosis and the unit-test bench only call their
methods.

Some effects are made from their id on first lookup instead of being listed
(a sensor filter whose damping ratio was fitted, ``force_filter_lag_z0733``):
the module that defines them adds an id pattern with :func:`register_maker`.

Residual sign convention everywhere: residual = measurement − model (N).
"""

from __future__ import annotations

import re
from dataclasses import dataclass

import numpy as np

from ..fit_data import FitData, cached

__all__ = ["Param", "Check", "Effect", "REGISTRY", "FREE", "register", "register_maker", "is_effect_id", "effect_columns",
           "fmt_estimate"]


@dataclass(frozen=True)
class Param:
    """A model parameter: name, unit, physical bounds, meaning."""

    name: str
    unit: str
    lower: float
    upper: float
    meaning: str = ""


@dataclass(frozen=True)
class Check:
    """One physical signature check of a fitted effect."""

    name: str
    passed: bool
    detail: str

    def to_dict(self) -> dict:
        """The check as JSON.

        Returns
        -------
        dict
            ``name``, ``passed`` (bool) and ``detail`` (the numbers behind the verdict, as text).
        """
        return dict(name=self.name, passed=bool(self.passed), detail=self.detail)


_NAN = np.array([np.nan])
#: Bounds of an amplitude that may take either sign.
FREE = (-np.inf, np.inf)


@dataclass(frozen=True)
class Effect:
    """One effect: fit columns, context, equation and sentence, signature checks, bench force.

    Subclasses override :meth:`columns` (always), and where needed
    :meth:`params`, :meth:`grid`, :meth:`damping_mask`, :meth:`signature`,
    :meth:`describe` and the ``bench_*`` methods.

    Attributes
    ----------
    id : str
        Identifier (``shared/specs/diagnosis-report.md``; discovery operators
        name what they are, e.g. ``force_lag``).
    title, physics, equation : str
        Short name; a sentence a mechanical engineer would accept; the added term.
    amplitudes : tuple[Param]
        Linear amplitude parameters (bounds carry the physical sign).
    shape : Param or None
        The one shape parameter searched on :meth:`grid` and refined.
    catalogue : bool
        Named physics of the unit (True) or a discovery operator (False).
    needs : tuple[str]
        Context keys the columns need from the current model:
        ``damping_force_N`` (L(γ)ẋ), ``model_force_N`` (the current model's
        force), ``residual_N`` (measurement − current model).
    log_shape : bool
        Refine the shape in log space.
    """

    id: str
    title: str
    physics: str
    equation: str
    amplitudes: tuple = ()
    shape: Param | None = None
    catalogue: bool = True
    needs: tuple = ()
    log_shape: bool = True
    shape_xtol: float = 1e-3  #: tolerance of the shape refinement (log units when log_shape)
    #: parameters fitted per experiment on that experiment's own data (held-out error is charged for them)
    nuisance_per_experiment: int = 0
    #: (class attribute, not a field) the measured states the formula's force depends on
    #: (:data:`~vvea_design.identification.last_stage.FEATURES` names): a catalogue name must beat a general
    #: function of exactly these states (:mod:`~vvea_design.identification.general`); empty: not compared
    depends_on = ()

    # -- fitting ---------------------------------------------------------
    def params(self, D: FitData) -> tuple:
        """Amplitude parameters for campaign ``D`` (per valve for some effects).

        Parameters
        ----------
        D : FitData
            The campaign.

        Returns
        -------
        tuple of Param
            One per design column of :meth:`columns`, in that order (units in ``Param.unit``).
        """
        return self.amplitudes

    def grid(self, D: FitData, ctx: dict) -> np.ndarray:
        """Shape-parameter values to search (``[nan]`` without a shape).

        Parameters
        ----------
        D : FitData
            The campaign.
        ctx : dict
            The context of the current model (keys in :attr:`needs`: forces in N).

        Returns
        -------
        numpy.ndarray
            Values of the shape parameter in its own unit, ``shape.unit`` (e.g. s for a time constant, mm for
            a pitch).
        """
        return _NAN

    def columns(self, D: FitData, shape: float, ctx: dict) -> np.ndarray:
        """Design columns ``(n, k)`` of the amplitudes at shape value ``shape``.

        Parameters
        ----------
        D : FitData
            The campaign.
        shape : float
            The shape parameter in its own unit, ``shape.unit`` (e.g. s for a time constant, mm for a pitch;
            nan without one).
        ctx : dict
            The context of the current model (keys in :attr:`needs`: forces in N).

        Returns
        -------
        numpy.ndarray
            ``(D.n, k)``: force in N per unit of each amplitude (the amplitudes' units cancel), one column per
            :meth:`params` entry.
        """
        raise NotImplementedError

    def damping_mask(self, D: FitData, shape: float, ctx: dict) -> np.ndarray | None:
        """Samples whose linear damping column this effect replaces (None: none).

        Parameters
        ----------
        D : FitData
            The campaign.
        shape : float
            The shape parameter in its own unit, ``shape.unit`` (e.g. s for a time constant, mm for a pitch;
            nan without one).
        ctx : dict
            The context of the current model (forces in N).

        Returns
        -------
        numpy.ndarray or None
            ``(D.n,)`` bool, True where eq. 14's ``L(γ)ẋ`` column is zeroed (e.g. the relief valve open).
        """
        return None

    def transform(self, D: FitData, X: np.ndarray, shape: float, ctx: dict, out: np.ndarray | None = None) -> np.ndarray:
        """The whole design matrix as the effect changes it (sensor dynamics); identity by default.

        Parameters
        ----------
        D : FitData
            The campaign.
        X : numpy.ndarray
            ``(D.n, p)`` design columns (N per unit amplitude).
        shape : float
            The shape parameter, in ``shape.unit`` (e.g. a lag in s).
        ctx : dict
            The context of the current model (forces in N).
        out : numpy.ndarray, optional
            Where to write the result, N per unit amplitude (may be ``X`` itself: the design is then transformed in place,
            without a second copy); a new array when None.

        Returns
        -------
        numpy.ndarray
            ``(D.n, p)`` transformed design (N per unit amplitude); ``X`` itself for the identity.
        """
        return X

    @property
    def replaces_damping(self) -> bool:
        """True when the effect replaces linear damping columns (not nested in eq. 14)."""
        return type(self).damping_mask is not Effect.damping_mask

    @property
    def transforms_design(self) -> bool:
        """True when the effect acts on the whole design (e.g. a lag of the force reading)."""
        return type(self).transform is not Effect.transform

    @property
    def nested(self) -> bool:
        """True when the effect only adds columns (eq. 14 + others is the effect at zero amplitude)."""
        return not (self.replaces_damping or self.transforms_design)

    # -- meaning -----------------------------------------------------------
    def signature(self, D: FitData, values: dict, shape: float, contribution: np.ndarray) -> list[Check]:
        """Physical signature checks of a fitted instance (catalogue effects).

        Parameters
        ----------
        D : FitData
            The campaign.
        values : dict
            Fitted amplitudes by parameter name (their units in :meth:`params`).
        shape : float
            The fitted shape parameter in its own unit, ``shape.unit`` (e.g. s for a time constant).
        contribution : numpy.ndarray
            ``(D.n,)`` the effect's fitted force at the samples (N).

        Returns
        -------
        list of Check
            Empty for effects without checks (discovery operators).
        """
        return []

    def describe(self, values: dict, errors: dict, shape: float, shape_se: float) -> str:
        """The fitted effect in one sentence with its numbers.

        Parameters
        ----------
        values, errors : dict
            Fitted amplitudes and their standard errors by parameter name (units in :meth:`params`).
        shape, shape_se : float
            The fitted shape parameter and its standard error in its own unit, ``shape.unit`` (e.g. s for a
            time constant, mm for a pitch).

        Returns
        -------
        str
            The sentence an engineer reads in the report (units written out).
        """
        return self.physics

    # -- unit-test bench ---------------------------------------------------
    #: key of the strength parameter in :meth:`bench_random`'s params, and how SNR follows it
    bench_strength: str = ""
    bench_snr_rises: bool = True
    bench_linear: bool = True

    def bench_force(self, P: dict, cols: dict, spec) -> np.ndarray:
        """Force this effect adds to eq. 14 on the unit-test bench (``vvea_benches.testbench``, not the proof's simulator).

        Parameters
        ----------
        P : dict
            The effect's bench parameters (:meth:`bench_random`, units in their keys).
        cols : dict
            Bench signals: ``x`` (mm), ``v`` (mm/s), ``p2`` (MPa), ``valve`` (deg), ``ctime_h`` (h), ``exp``
            (index), ``t`` (s).
        spec : CampaignSpec
            The bench campaign (its reference unit and grid).

        Returns
        -------
        numpy.ndarray
            The added force per sample (N).
        """
        raise NotImplementedError(f"{self.id} has no bench force")

    def bench_random(self, rng: np.random.Generator, spec) -> dict:
        """Random bench parameters of strength 1.

        Parameters
        ----------
        rng : numpy.random.Generator
            The seeded generator of the case.
        spec : CampaignSpec
            The bench campaign.

        Returns
        -------
        dict
            Parameters for :meth:`bench_force`, units in their keys; ``bench_strength`` names the one scaled
            to reach a target SNR.
        """
        raise NotImplementedError(f"{self.id} has no bench force")

    def bench_strength_range(self, cols: dict, spec) -> tuple[float, float]:
        """Bisection range of the strength (effects not linear in strength).

        Parameters
        ----------
        cols : dict
            Bench signals (see :meth:`bench_force`).
        spec : CampaignSpec
            The bench campaign.

        Returns
        -------
        tuple of float
            Lowest and highest strength searched, in the unit of the ``bench_strength`` parameter (e.g. N, MPa
            or s: its key names it).
        """
        return (1e-6, 10.0)

    def bench_with_strength(self, P: dict, s: float) -> dict:
        """Bench parameters with the strength set.

        Parameters
        ----------
        P : dict
            Bench parameters (:meth:`bench_random`).
        s : float
            The strength, in the unit of the ``bench_strength`` parameter (e.g. N, MPa or s: its key names it).

        Returns
        -------
        dict
            A copy of ``P`` with ``P[bench_strength] = s``.
        """
        P = dict(P)
        P[self.bench_strength] = s
        return P


class _Registry(dict):
    """The effect registry: a dict by id, plus effects created from their id on first use.

    A sensor filter whose damping ratio was fitted is named by it
    (``force_filter_lag_z0733``: zeta = 0.733, see
    :func:`~vvea_design.identification.effects.force_lag.filter_id`); such an
    id is made on lookup (``REGISTRY[id]``) without being listed, so the
    registry's listing stays the set of candidates.
    """

    def __missing__(self, key):
        eff = _made_effect(key)
        if eff is None:
            raise KeyError(key)
        return eff


_MAKERS: list = []  #: (compiled id pattern, make(match) -> Effect), see register_maker
_MADE: dict = {}  #: effects made from their id


def _made_effect(key):
    for pattern, make in _MAKERS:
        m = pattern.fullmatch(str(key))
        if m is None:
            continue
        eff = _MADE.get(key)
        if eff is None:
            eff = _MADE[key] = make(m)
        return eff
    return None


def register_maker(pattern: str, make) -> None:
    """Let ``REGISTRY[id]`` make an effect from an id that matches ``pattern`` (not listed in the registry).

    Parameters
    ----------
    pattern : str
        Regular expression an id must match in full (e.g. ``r"force_filter_lag_z(\\d{4})"``).
    make : callable
        ``make(match)`` returns the effect of the matched id (its numbers read from the match groups, e.g. a
        damping ratio, dimensionless); called once per id, the effect is kept.

    Returns
    -------
    None
    """
    _MAKERS.append((re.compile(pattern), make))


def is_effect_id(key) -> bool:
    """True when ``key`` names a registered effect or one made from its id (a fitted sensor filter).

    Parameters
    ----------
    key : str
        An effect id (e.g. ``"thermal"`` or ``"force_filter_lag_z0733"``).

    Returns
    -------
    bool
        Whether ``REGISTRY[key]`` gives an effect.
    """
    return key in REGISTRY or _made_effect(key) is not None


#: Every effect (catalogue and discovery operators), by id.
REGISTRY: dict[str, Effect] = _Registry()


def register(effect: Effect) -> Effect:
    """Add ``effect`` to :data:`REGISTRY` (ids are unique).

    Parameters
    ----------
    effect : Effect
        The effect to register; its ``id`` must not be registered yet.

    Returns
    -------
    Effect
        ``effect`` itself (so it can be used as ``X = register(X(...))``).

    Raises
    ------
    ValueError
        If an effect with the same id is already registered.
    """
    if effect.id in REGISTRY:
        raise ValueError(f"effect id {effect.id!r} registered twice")
    REGISTRY[effect.id] = effect
    return effect


def effect_columns(D: FitData, eff: "Effect", shape: float, ctx: dict) -> np.ndarray:
    """``eff.columns(D, shape, ctx)``, cached per effect and shape value when the effect needs no context.

    The columns of an effect without ``needs`` are a function of the campaign
    and the shape alone (the same forces are rebuilt by every fold, round and
    refit); those that read the context are always rebuilt.

    Parameters
    ----------
    D : FitData
        The campaign (x in mm, ẋ in mm/s, p2 in MPa, t in s, ...).
    eff : Effect
        The effect whose columns are wanted.
    shape : float
        Its shape parameter, in the unit of ``eff.shape`` (e.g. s for a time
        constant, mm for a pitch); NaN for an effect without one.
    ctx : dict
        Context arrays per sample (``damping_force_N`` etc., N), read only by
        effects that declare them in ``needs``.

    Returns
    -------
    numpy.ndarray, shape (D.n, number of the effect's amplitudes)
        The effect's columns, each in the unit its amplitude multiplies (N per
        amplitude unit). Cached: do not modify it in place.
    """
    if eff.needs:
        return eff.columns(D, shape, ctx)
    sv = float(shape)
    return cached(D, ("columns", eff.id, sv if np.isfinite(sv) else None), lambda: eff.columns(D, shape, ctx))


def fmt_estimate(v: float, se: float | None = None, unit: str = "") -> str:
    """A fitted value for an effect's sentence: 3 significant digits, ``± se`` on 2 when finite, then the unit.

    Parameters
    ----------
    v : float
        The value, in the same unit as ``unit`` names (e.g. s, N).
    se : float, optional
        Its standard error, in the same unit (left out when None or not finite).
    unit : str
        The unit written after the number (e.g. ``"s"``, ``"N/MPa"``); empty for none.

    Returns
    -------
    str
        E.g. ``"0.05 ± 0.0031 s"``.
    """
    s = f"{v:.3g}"
    if se is not None and np.isfinite(se):
        s += f" ± {se:.2g}"
    return s + (f" {unit}" if unit else "")

