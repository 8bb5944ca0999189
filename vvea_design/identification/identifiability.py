"""Identifiability: whether the recordings can separate the fitted parameters (rank and conditioning of the design)."""

from __future__ import annotations

from dataclasses import asdict, dataclass

import numpy as np

from .fit_data import FitData
from .fitting import ModelFit

__all__ = ["Identifiability", "identifiability"]


@dataclass(frozen=True)
class Identifiability:
    """Whether the recordings can separate the fitted parameters.

    Attributes
    ----------
    n_parameters, n_experiments : int
    condition_number : float
        Of the column-scaled design matrix (ratio of its extreme singular values).
    inseparable : list[list[str]]
        Groups of parameters the data cannot tell apart: a combination of
        their columns has less than ``tolerance`` of a column's norm.
    no_data : list[str]
        Parameters whose column is zero (e.g. a valve with no moving samples).
    errors_reliable : bool
        Cluster-robust standard errors need more experiments than parameters.
    messages : list[str]
        What to tell the user.
    """

    n_parameters: int
    n_experiments: int
    condition_number: float
    inseparable: list
    no_data: list
    errors_reliable: bool
    messages: list

    @property
    def unreliable_parameters(self) -> set:
        """Parameters whose value or uncertainty the data do not determine."""
        if not self.errors_reliable:
            return set()  # every error is unreliable; the values may still be fine
        return {n for grp in self.inseparable for n in grp} | set(self.no_data)

    def to_dict(self) -> dict:
        """Plain-JSON dictionary of the fields.

        Returns
        -------
        dict
            JSON-ready: ``n_parameters`` and ``n_experiments`` (counts), ``condition_number``
            (dimensionless), ``inseparable`` (groups of parameter names), ``no_data`` (parameter names),
            ``errors_reliable`` and ``messages``.
        """
        return asdict(self)


def identifiability(fit: ModelFit, D: FitData, tolerance: float = 0.1) -> Identifiability:
    """Check rank and conditioning of the fit's design on ``D`` (issue 11 item 10).

    The design's columns are scaled to unit norm; an eigenvector of the
    scaled normal matrix with eigenvalue below ``tolerance²`` is a
    combination of parameters the data cannot determine (its columns
    combine to less than ``tolerance`` = 10 % of a column's norm: the
    variance of that combination is inflated more than 100-fold against
    independent columns, the usual "severe collinearity" mark), and the
    parameters with a large share in it (|component| > 0.3) are reported
    together. With no more experiments than parameters the
    cluster-robust (experiments as clusters) standard errors are not
    available.

    Parameters
    ----------
    fit : ModelFit
        The fitted model.
    D : FitData
        The data it was fitted to.
    tolerance : float
        Smallest norm of a column combination, as a fraction of a column's norm.

    Returns
    -------
    Identifiability
        Condition number, inseparable groups, whether errors are reliable, messages.
    """
    X = fit.design(D)
    names = [q.name for q in fit.params]
    G = X.T @ X
    d = np.sqrt(np.clip(np.diag(G), 0, None))
    no_data = [names[j] for j in np.flatnonzero(d <= 1e-12 * max(d.max(), 1e-300))]
    keep = np.flatnonzero(d > 1e-12 * max(d.max(), 1e-300))
    Gs = G[np.ix_(keep, keep)] / np.outer(d[keep], d[keep])
    lam, V = np.linalg.eigh(Gs)
    lam = np.clip(lam, 0, None)
    cond = float(np.sqrt(lam.max() / lam.min())) if lam.min() > 0 else float("inf")
    groups = []
    for i in np.flatnonzero(lam < tolerance**2):
        grp = [names[keep[j]] for j in np.flatnonzero(np.abs(V[:, i]) > 0.3)]
        if grp and grp not in groups:
            groups.append(grp)
    ne = int(D.n_exp)
    reliable = ne > len(names)
    msgs = []
    for grp in groups:
        msgs.append(
            f"the recordings cannot separate {' and '.join(grp)}: a combination of them hardly changes the force "
            "(e.g. one speed per valve makes C sign(ẋ) and L ẋ alike; one pressure leaves g p2 x alone); "
            "their values are not determined and no uncertainty is given for them -- record more speeds, valves or pressures"
        )
    for n in no_data:
        msgs.append(f"no moving samples inform {n}: it is not identified")
    if not reliable:
        msgs.append(
            f"only {ne} experiment(s) for {len(names)} parameters: cluster-robust standard errors (experiments as "
            "clusters) need more experiments than parameters, so no uncertainties are given"
        )
    return Identifiability(len(names), ne, cond, groups, no_data, reliable, msgs)
