"""What a fitted term depends on: the share of its force each measured state explains.

A term's name must follow from what its force depends on, not from the formula it was fitted with:
a term fitted with a catalogue formula is named from the catalogue only when its dependence on the
states matches the catalogue effect's; any other term is described by the states its force follows
("a force proportional to the charge, independent of motion and position").

For every state (charge, position, speed, direction, valve, time within the experiment, time since
reversal, campaign order) :func:`dependence_profile` gives the share of the term's variance explained
by the state alone (the correlation ratio eta^2 over quantile bins of the state, or its distinct
values), and :func:`describe_dependence` turns the profile into a sentence.
"""

from __future__ import annotations

import numpy as np

from .fit_data import FitData

__all__ = ["STATES", "dependence_profile", "main_states", "describe_dependence", "per_charge_share"]

#: State name -> (meaning, function of the campaign giving one value per sample).
STATES: dict = {
    "charge": ("the charge p2", lambda D: D.p2),
    "position": ("the position x", lambda D: D.x),
    "speed": ("the speed |xdot|", lambda D: np.abs(D.v)),
    "direction": ("the direction of motion", lambda D: D.s),
    "valve": ("the valve opening", lambda D: D.valve),
    "time_in_experiment": ("the time within each experiment", lambda D: D.t),
    "since_reversal": ("the time since the last reversal", lambda D: D.tsr),
    "campaign_order": ("the campaign order (campaign time)", lambda D: D.ctime),
}

#: States of the motion (a term independent of all of them is "independent of motion and position").
MOTION = ("position", "speed", "direction", "since_reversal")


def _eta2(z: np.ndarray, f: np.ndarray, n_bins: int = 10) -> float:
    """Share of the variance of ``f`` explained by the conditional mean of ``f`` on bins of ``z`` (0..1)."""
    var = float(np.var(f))
    if not np.isfinite(var) or var <= 0.0 or len(f) < 2:
        return 0.0
    u = np.unique(z)
    if len(u) <= n_bins:
        idx = np.searchsorted(u, z)
    else:
        edges = np.unique(np.quantile(z, np.linspace(0.0, 1.0, n_bins + 1)[1:-1]))
        idx = np.searchsorted(edges, z)
    cnt = np.bincount(idx)
    mean = np.bincount(idx, weights=f) / np.maximum(cnt, 1)
    between = float(np.sum(cnt * (mean - f.mean()) ** 2) / len(f))
    return float(np.clip(between / var, 0.0, 1.0))


def dependence_profile(D: FitData, force: np.ndarray, rows: np.ndarray | None = None) -> dict:
    """Share of a term's force variance each state explains alone (eta^2, 0..1).

    Parameters
    ----------
    D : FitData
        The campaign.
    force : numpy.ndarray
        ``(D.n,)`` the term's force, N.
    rows : numpy.ndarray of bool, optional
        ``(D.n,)`` mask of the samples to use (dimensionless; default: all).

    Returns
    -------
    dict
        State name (keys of :data:`STATES`) -> explained share (dimensionless).
    """
    m = np.ones(D.n, bool) if rows is None else np.asarray(rows, bool)
    f = np.asarray(force, float)[m]
    return {k: _eta2(np.asarray(fn(D), float)[m], f) for k, (_, fn) in STATES.items()}


def main_states(profile: dict, floor: float = 0.1, rel: float = 0.3) -> list:
    """The states a term depends on: explained share >= ``floor`` and >= ``rel`` x the largest share, largest first.

    Parameters
    ----------
    profile : dict
        Output of :func:`dependence_profile`.
    floor, rel : float
        Absolute and relative thresholds on the explained share (dimensionless).

    Returns
    -------
    list of str
        State names.
    """
    top = max(profile.values(), default=0.0)
    return [k for k, v in sorted(profile.items(), key=lambda kv: -kv[1]) if v >= floor and v >= rel * top]


def describe_dependence(profile: dict) -> str:
    """A sentence saying what a term's force depends on, from its profile.

    Parameters
    ----------
    profile : dict
        Output of :func:`dependence_profile`.

    Returns
    -------
    str
        E.g. "Its force depends on the charge p2 (explains 97 % of it alone); independent of motion and position."
    """
    ms = main_states(profile)
    if not ms:
        return "Its force follows no single state (it depends on several together)."
    parts = [f"{STATES[k][0]} ({100 * profile[k]:.0f} %)" for k in ms]
    s = "Its force depends on " + ", ".join(parts) + " (share of its variance each explains alone)"
    if not any(k in ms for k in MOTION):
        s += "; independent of motion and position"
    return s + "."


def per_charge_share(D: FitData, force: np.ndarray) -> float:
    """Share of a term's variance that a constant per charge level explains (1: the force depends on the charge only).

    Parameters
    ----------
    D : FitData
        The campaign.
    force : numpy.ndarray
        ``(D.n,)`` the term's force, N.

    Returns
    -------
    float
        eta^2 of the force on the charge levels (dimensionless, 0..1).
    """
    return _eta2(np.round(np.asarray(D.p2, float), 3), np.asarray(force, float), n_bins=50)
