"""Discovered family: a sparse sum of terms from a library of the measured states and their histories.

Physics outside the catalogue is not searched for among look-alikes of any simulator's effects: the
candidate is built, in every selection round, from a general library of the states a bench records --

- position ``x/travel``, and its square, the charge ``p2``, the direction ``sign(xdot)``, the speed
  ``|xdot|``, a constant;
- the campaign time ``t_c`` (campaign order, h) and its square;
- first-order histories: ``exp(-t/tau)`` of the time within the experiment (tau 0.1, 0.3, 1 s) and
  ``exp(-d/r)`` of the distance travelled since the last reversal (r 0.2, 1, 3 mm);
- eq. 14's own spring ``p2 x`` and throttle ``L(gamma) xdot`` forces (their changes with the states);

-- and their pairwise products (:func:`library_terms`). :func:`select_terms` keeps a sparse subset by
sequentially thresholded least squares (STLSQ) on the current residual, its threshold chosen by
grouped cross-validation (whole experiments held out); the kept terms are one candidate
(:class:`StateTerms`, id ``states[p|p*tc|...]``, made from its id) that the forward selection then
scores like every other candidate, and the held-out guard judges. Its report says in plain words
what the force depends on ("a force proportional to the charge, independent of motion and position";
"the throttle force changing with campaign time"; "a force over the first 0.3 s of each experiment").
"""

from __future__ import annotations

import re
from dataclasses import dataclass
from itertools import combinations

import numpy as np

from ..fit_data import FitData, cached
from .base import FREE, Effect, Param, register_maker

__all__ = ["BASES", "library_terms", "term_columns", "select_terms", "states_id", "StateTerms", "MAX_TERMS"]

#: Place of this module's effects among the candidates (see :mod:`vvea_design.identification.effects`).
RANK = 160

#: At most this many terms in one library candidate.
MAX_TERMS = 6

#: Base name -> (words, unit, states it depends on). A term is a base or the product of two.
BASES: dict = {
    "1": ("a constant", "", ()),
    "x": ("the position x/travel", "", ("position",)),
    "x2": ("the position squared (x/travel)^2", "", ("position",)),
    "p": ("the charge p2", "MPa", ("charge",)),
    "dir": ("the direction of motion", "", ("direction",)),
    "speed": ("the speed |xdot|", "mm/s", ("speed",)),
    "tc": ("the campaign time (campaign order)", "h", ("campaign_order",)),
    "tc2": ("the campaign time squared", "h^2", ("campaign_order",)),
    "start0.1": ("a decay over the first 0.1 s of each experiment", "", ("time_in_experiment",)),
    "start0.3": ("a decay over the first 0.3 s of each experiment", "", ("time_in_experiment",)),
    "start1": ("a decay over the first 1 s of each experiment", "", ("time_in_experiment",)),
    "rev0.2": ("a decay over the first 0.2 mm after each reversal", "", ("since_reversal",)),
    "rev1": ("a decay over the first 1 mm after each reversal", "", ("since_reversal",)),
    "rev3": ("a decay over the first 3 mm after each reversal", "", ("since_reversal",)),
    "spring": ("eq. 14's spring column p2 x", "MPa mm", ("charge", "position")),
    "damp": ("the throttle force L(gamma) xdot", "N", ("valve", "speed", "direction")),
}

_FAMILY = {"tc": "tc", "tc2": "tc", "start0.1": "start", "start0.3": "start", "start1": "start", "rev0.2": "rev", "rev1": "rev", "rev3": "rev", "x": "x", "x2": "x"}
#: Terms that eq. 14 already holds (or a sum of its columns): never library terms.
_IN_EQ14 = {"dir", "spring", "damp", "p*x", "dir*speed"}
#: The charge-borne curvature of the spring (charge x position products): the gas law's own family, which the
#: catalogue's ``gas_nonlinearity`` (with the unit's geometry) and the ``charge_curvature`` operator fit.
_GAS_FAMILY = {"x*p", "x2*p", "x*spring", "x2*spring", "p*spring"}
#: A force that is a polynomial of the position alone (a spring outside the gas chambers): the ``spring_polynomial``
#: operator's own family. Left out so that a library candidate does not bundle an ever-present spring curvature with the
#: term that answers the round's question (a bundle would out-score, and so out-name, a catalogue effect on its own).
_SPRING_FAMILY = {"x", "x2", "x*x2"}


def library_terms() -> tuple:
    """Every term of the library: each base (but eq. 14's own) and each product of two bases of different families.

    Returns
    -------
    tuple of str
        Term names, ``"p"`` or ``"p*tc"`` (base names of :data:`BASES`, joined by ``*``).
    """
    names = [b for b in BASES if b != "1"]
    out = ["1"] + [b for b in names if b not in _IN_EQ14 | _SPRING_FAMILY]
    for a, b in combinations(names, 2):
        if _FAMILY.get(a, a) == _FAMILY.get(b, b) and (a, b) != ("x", "x2"):
            continue
        if {f"{a}*{b}", f"{b}*{a}"} & (_IN_EQ14 | _GAS_FAMILY | _SPRING_FAMILY):
            continue
        out.append(f"{a}*{b}")
    return tuple(out)


def _distance_since_reversal(D: FitData) -> np.ndarray:
    """Distance travelled since the last reversal (or the start of the experiment), mm."""
    s = D.s
    new = np.ones(D.n, bool)
    new[1:] = (s[1:] != s[:-1]) | (D.exp[1:] != D.exp[:-1])
    seg = np.cumsum(new) - 1
    return np.abs(D.x - D.x[np.flatnonzero(new)][seg])


def _bases(D: FitData) -> np.ndarray:
    """The context-free bases per sample, ``(n, len(BASES))`` (the throttle-force column left zero), cached on ``D``."""

    def make():
        d = _distance_since_reversal(D)
        u = D.x / D.travel_mm
        cols = {"1": np.ones(D.n), "x": u, "x2": u * u, "p": D.p2, "dir": D.s, "speed": np.abs(D.v), "tc": D.ctime / 3600.0, "tc2": (D.ctime / 3600.0) ** 2,
                "start0.1": np.exp(-D.t / 0.1), "start0.3": np.exp(-D.t / 0.3), "start1": np.exp(-D.t / 1.0),
                "rev0.2": np.exp(-d / 0.2), "rev1": np.exp(-d / 1.0), "rev3": np.exp(-d / 3.0), "spring": D.p2 * D.x,
                "damp": np.zeros(D.n)}
        return np.column_stack([cols[k] for k in BASES])

    return cached(D, ("library_bases",), make)


def _pairs(terms) -> tuple[np.ndarray, np.ndarray]:
    keys = list(BASES)
    i, j = [], []
    for t in terms:
        a, _, b = t.partition("*")
        i.append(keys.index(a))
        j.append(keys.index(b or "1"))
    return np.array(i, int), np.array(j, int)


def _needs_damping(terms) -> bool:
    return any("damp" in t.split("*") for t in terms)


def term_columns(D: FitData, terms, ctx: dict, rows: slice = slice(None)) -> np.ndarray:
    """The library terms ``terms`` per sample (of ``rows``), each in the product of its bases' units.

    Parameters
    ----------
    D : FitData
        The campaign (x in mm, xdot in mm/s, p2 in MPa, times in s).
    terms : sequence of str
        Term names (:func:`library_terms`).
    ctx : dict
        ``damping_force_N`` (N per sample) when a term uses the throttle force ``damp``.
    rows : slice
        Samples to compute (default all).

    Returns
    -------
    numpy.ndarray, shape (samples, len(terms))
        Columns in their units (e.g. MPa for ``p``, MPa h for ``p*tc``, N h for ``damp*tc``).
    """
    B = _bases(D)[rows]
    if _needs_damping(terms):
        B = B.copy()
        B[:, list(BASES).index("damp")] = np.asarray(ctx["damping_force_N"], float)[rows]
    i, j = _pairs(terms)
    return B[:, i] * B[:, j]


def _stlsq(G: np.ndarray, b: np.ndarray, lam: float, fixed: int = 0, iters: int = 10) -> np.ndarray:
    """Sequentially thresholded least squares on the normal equations (columns scaled to unit RMS): coefficients in N.

    The first ``fixed`` columns (the current model's) are always kept; the others are dropped while their
    coefficient (the force RMS they carry, N) is below ``lam``.
    """
    p = len(b)
    act = np.ones(p, bool)
    th = np.zeros(p)
    ridge = 1e-6 * max(float(np.trace(G)) / max(p, 1), 1e-300)  # columns scaled alike: keeps near-collinear terms finite
    for _ in range(iters):
        th = np.zeros(p)
        idx = np.flatnonzero(act)
        th[idx] = np.linalg.solve(G[np.ix_(idx, idx)] + ridge * np.eye(len(idx)), b[idx])
        small = act & (np.abs(th) < lam)
        small[:fixed] = False
        if not small.any():
            break
        act &= ~small
    return th


def select_terms(D: FitData, ctx: dict, folds: np.ndarray, X0: np.ndarray | None = None, terms: tuple | None = None,
                 chunk: int = 40000) -> tuple:
    """The library terms kept by STLSQ beside the current model's design ``X0``, threshold by grouped cross-validation.

    The measured force is regressed on the current model's columns (always kept, refitted with the
    terms: a term is judged by what it adds to the whole model, not to a residual the model was fitted
    without it) and the library's. Every column is scaled to unit RMS over the training samples, so a
    coefficient is the force (N RMS) the term carries; STLSQ drops library terms below a threshold
    ``lam`` (0.02 .. 1 x the current residual RMS). For each ``lam`` the held-out squared error over
    the cross-validation folds (whole experiments) is computed from per-fold normal equations; the
    largest ``lam`` within one standard error of the smallest error is kept (the sparsest equally good
    sum), at most :data:`MAX_TERMS` terms (the largest forces).

    Parameters
    ----------
    D : FitData
        The campaign.
    ctx : dict
        ``residual_N`` (N per sample: the current model's residual, zero outside the training
        experiments) and ``damping_force_N`` (N).
    folds : numpy.ndarray of int
        Fold per experiment (-1: held out, not used).
    X0 : numpy.ndarray, shape (D.n, p0), optional
        The current model's design (columns in their units); None: the residual alone is regressed.
    terms : tuple of str, optional
        The library (default :func:`library_terms`).
    chunk : int
        Samples per block when the normal equations are summed (memory).

    Returns
    -------
    tuple of str
        The kept terms, largest force first (empty when none lowers the held-out error).
    """
    from threadpoolctl import threadpool_limits

    with threadpool_limits(limits=1):  # ~100 x 100 solves: threads only contend on a shared machine
        return _select_terms(D, ctx, folds, X0, library_terms() if terms is None else tuple(terms), chunk)


def _select_terms(D, ctx, folds, X0, terms, chunk) -> tuple:
    if "damping_force_N" not in ctx:
        terms = tuple(t for t in terms if "damp" not in t.split("*"))
    r = np.asarray(ctx["residual_N"], float)
    y_all = r if X0 is None else D.y
    p0 = 0 if X0 is None else X0.shape[1]
    fold_row = np.asarray(folds)[D.exp]
    ids = np.unique(fold_row[fold_row >= 0])
    if len(ids) < 2:
        return ()
    nf, p = len(ids), p0 + len(terms)
    G, b, yy = np.zeros((nf, p, p)), np.zeros((nf, p)), np.zeros(nf)
    code = np.searchsorted(ids, fold_row)
    for a in range(0, D.n, chunk):
        sl = slice(a, min(a + chunk, D.n))
        F, y, k = term_columns(D, terms, ctx, sl), y_all[sl], code[sl]
        if p0:
            F = np.column_stack([X0[sl], F])
        keep = fold_row[sl] >= 0
        for q in range(nf):
            m = keep & (k == q)
            if m.any():
                Fm = F[m]
                G[q] += Fm.T @ Fm
                b[q] += Fm.T @ y[m]
                yy[q] += y[m] @ y[m]
    Gt, bt = G.sum(0), b.sum(0)
    n_tr = int(np.sum(fold_row >= 0))
    scale = np.sqrt(np.maximum(np.diag(Gt), 0.0) / max(n_tr, 1))
    alive = scale > 0
    scale = np.where(alive, scale, 1.0)
    S = np.outer(scale, scale)
    if p0:  # a term the current model already holds (a catalogue effect's own column: p2 sign(xdot)) is no new term
        Gs = Gt / S
        A = Gs[:p0, :p0] + 1e-9 * np.trace(Gs[:p0, :p0]) / p0 * np.eye(p0)
        B = Gs[:p0, p0:]
        held = np.einsum("ij,ij->j", B, np.linalg.solve(A, B)) / np.maximum(np.diag(Gs)[p0:], 1e-300)
        alive[p0:] &= held < 0.999
    r_rms = float(np.sqrt(np.sum(r[fold_row >= 0] ** 2) / max(n_tr, 1)))
    lams = r_rms * np.array([0.02, 0.05, 0.1, 0.2, 0.3, 0.5, 0.7, 1.0, np.inf])  # inf: the current model alone
    cvf = np.zeros((len(lams), nf))  # held-out SSE per threshold and fold
    for i, lam in enumerate(lams):
        for q in range(nf):  # fit on the other folds (scaled: a coefficient is the term's force RMS, N), score on fold q
            Gq, bq = (Gt - G[q]) / S, (bt - b[q]) / scale
            if not np.isfinite(lam):
                w = np.zeros(p)
                if p0:
                    w[:p0] = _stlsq(Gq[:p0, :p0], bq[:p0], 0.0)
            else:
                w = _stlsq(Gq, bq, lam, p0)
            w = w * alive / scale
            cvf[i, q] = yy[q] - 2.0 * b[q] @ w + w @ G[q] @ w
    cv = cvf.sum(1)
    best = int(np.argmin(cv[:-1]))
    if cv[best] >= cv[-1]:  # nothing in the library lowers the held-out error
        return ()
    se = float(np.std(cvf[best] - cvf[-1], ddof=1) * np.sqrt(nf))  # one standard error of the held-out SSE (over the folds)
    lam = float(lams[np.flatnonzero(cv[:-1] <= cv[best] + se).max()])  # the sparsest sum within one standard error
    th = (_stlsq(Gt / S, bt / scale, lam, p0) * alive)[p0:]
    order = [int(j) for j in np.argsort(-np.abs(th)) if th[j] != 0.0][:MAX_TERMS]
    return tuple(terms[j] for j in order)


def states_id(terms) -> str:
    """The effect id of a library candidate of the terms ``terms``: ``states[p|p*tc]``.

    Parameters
    ----------
    terms : sequence of str
        Term names (:func:`library_terms`).

    Returns
    -------
    str
        The id (made into a :class:`StateTerms` effect on lookup in the registry).
    """
    return "states[" + "|".join(terms) + "]"


def _unit(term: str) -> str:
    us = [BASES[b][1] for b in term.split("*") if BASES[b][1]]
    head = "1" if "N" in us else "N"  # a term in the throttle force (N) has a dimensionless amplitude per its other units
    us = [u for u in us if u != "N"]
    return (head + "".join(f"/{u}" if " " not in u else f"/({u})" for u in us)) if us or head == "N" else "1"


def _words(term: str) -> str:
    return " x ".join(BASES[b][0] for b in term.split("*") if b != "1") or BASES["1"][0]


def term_states(term: str) -> tuple:
    """The states (names of :data:`vvea_design.identification.dependence.STATES`) a library term depends on.

    Parameters
    ----------
    term : str
        A term name (:func:`library_terms`).

    Returns
    -------
    tuple of str
        State names, without repeats.
    """
    out: list = []
    for b in term.split("*"):
        out += [s for s in BASES[b][2] if s not in out]
    return tuple(out)


_MOTION = ("position", "speed", "direction", "since_reversal")


@dataclass(frozen=True)
class StateTerms(Effect):
    """A sparse sum of library terms (made from its id ``states[...]``): a force described by the states it follows."""

    terms: tuple = ()

    def params(self, D):
        return tuple(Param(f"c[{t}]", _unit(t), *FREE, f"force per unit of {_words(t)}") for t in self.terms)

    def columns(self, D, shape, ctx):
        return term_columns(D, self.terms, ctx)

    def describe(self, values, errors, shape, shape_se):
        states: list = []
        for t in self.terms:
            states += [s for s in term_states(t) if s not in states]
        from ..dependence import STATES

        dep = ", ".join(STATES[s][0] for s in states) or "nothing measured"
        tail = "; independent of motion and position" if not any(s in _MOTION for s in states) else ""
        parts = [f"{values[f'c[{t}]']:+.3g} {_unit(t)} x {_words(t)}" for t in self.terms]
        return (f"A force outside the catalogue, found by sparse regression on a library of the measured states: it follows {dep}{tail}. "
                f"Terms: " + "; ".join(parts) + ".")


def _make(m: re.Match) -> StateTerms:
    keys = list(BASES)
    terms = tuple("*".join(sorted(t.split("*"), key=lambda b: keys.index(b) if b in keys else -1)) for t in m.group(1).split("|") if t)
    known = set(library_terms()) | {"dir", "spring", "damp"}
    bad = [t for t in terms if t not in known]
    if not terms or bad:
        raise KeyError(f"states[...]: unknown library term(s) {bad or '(none)'}")
    return StateTerms(m.group(0), "a sum of state terms", "A force that follows the measured states, outside the catalogue.",
                      "f += " + " + ".join(f"c[{t}] {t}" for t in terms), (), None, catalogue=False,
                      needs=("damping_force_N",) if _needs_damping(terms) else (), log_shape=False, terms=terms)


def _id_pattern() -> str:
    """The ids of library candidates: ``states[`` + known terms (either order of a product) joined by ``|`` + ``]``."""
    names = set(library_terms()) | {"dir", "spring", "damp"}
    names |= {"*".join(reversed(t.split("*"))) for t in names if "*" in t}
    term = "(?:" + "|".join(re.escape(t) for t in sorted(names, key=len, reverse=True)) + ")"
    return rf"states\[({term}(?:\|{term})*)\]"


register_maker(_id_pattern(), _make)
