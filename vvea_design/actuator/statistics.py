"""Table 5 statistics of a rest-to-rest results table (paper section 5).

:func:`table5_statistics` turns a ``results.csv`` table into a typed :class:`Table5Statistics` (one
:class:`PairStatistics` per pair of settings and scope); ``to_dict()`` gives the JSON of
``summary.json``.
"""

from __future__ import annotations

from dataclasses import asdict, dataclass, fields

import pandas as pd

__all__ = ["PAPER_TABLE5", "PairStatistics", "CountedPair", "Table5Statistics", "table5_statistics", "counted_pair"]


#: Table 5 of the paper (fractions and ratios).
PAPER_TABLE5 = {
    "VVEA_beats_SEA": 0.291,
    "VVEA_beats_LWR": 0.892,
    "iVVEA_beats_SEA": 0.896,
    "iVVEA_beats_LWR": 0.908,
    "meanrmse_SEA_over_VVEA": 0.934,
    "meanrmse_LWR_over_VVEA": 1.104,
    "meanrmse_SEA_over_iVVEA": 1.243,
    "meanrmse_LWR_over_iVVEA": 1.521,
}


@dataclass(frozen=True)
class PairStatistics:
    """A variable-damping setting X against another setting Y over one scope of cases (Table 5 row)."""

    n_cases: int  #: cases compared (both solved; for the ``valid`` scope also both valid and verified)
    X_beats_Y: int  #: cases with rmse_X < (1 - rtol) rmse_Y
    fraction_X_beats_Y: float | None  #: X_beats_Y / n_cases (None without cases)
    X_worse_than_Y: int  #: cases with rmse_X > (1 + rtol) rmse_Y
    meanrmse_Y_over_X: float | None  #: mean rmse of Y over mean rmse of X (None without cases)
    n_excluded: int  #: cases of the table left out of this comparison

    def to_dict(self) -> dict:
        """Plain-JSON dictionary.

        Returns
        -------
        dict
            JSON-ready fields by name: the case counts ``n_cases``, ``X_beats_Y``, ``X_worse_than_Y``,
            ``n_excluded``, the fraction ``fraction_X_beats_Y`` (dimensionless) and the ratio
            ``meanrmse_Y_over_X`` (dimensionless); ``None`` where not defined.
        """
        return asdict(self)


@dataclass(frozen=True)
class CountedPair:
    """X against Y over *every* case of the table: a case where only one of them is usable goes to that one.

    "Usable" is solved, verified by re-simulation and valid (the link reaches 95 % of A in both up-phases).
    Nothing is left out: ``X_beats_Y + X_worse_than_Y + ties + neither_usable == n_cases``.
    """

    n_cases: int  #: every case of the table
    X_beats_Y: int  #: both usable and rmse_X < (1 - rtol) rmse_Y, plus the cases where only X is usable
    X_worse_than_Y: int  #: both usable and rmse_X > (1 + rtol) rmse_Y, plus the cases where only Y is usable
    ties: int  #: both usable, within rtol
    only_X_usable: int  #: X usable, Y not (counted as a win of X)
    only_Y_usable: int  #: Y usable, X not (counted as a loss of X)
    neither_usable: int  #: neither usable (its own column: no winner)
    fraction_X_beats_Y: float | None  #: X_beats_Y / n_cases (None without cases)
    fraction_X_worse_than_Y: float | None  #: X_worse_than_Y / n_cases (None without cases)
    n_both_usable: int  #: cases where both are usable (the mean ratio's cases)
    meanrmse_Y_over_X: float | None  #: mean rmse of Y over mean rmse of X over the both-usable cases

    def to_dict(self) -> dict:
        """Plain-JSON dictionary.

        Returns
        -------
        dict
            JSON-ready fields by name: case counts, fractions (dimensionless) and the mean rmse ratio
            (dimensionless); ``None`` where not defined.
        """
        return asdict(self)


def counted_pair(rmse_X, rmse_Y, usable_X, usable_Y, rtol: float = 1e-3) -> CountedPair:
    """Count X against Y over every case (see :class:`CountedPair`).

    Parameters
    ----------
    rmse_X, rmse_Y
        Tracking rmse of X and Y per case, rad (NaN where not solved).
    usable_X, usable_Y
        Per case: the result is solved, verified and valid.
    rtol
        Relative margin of "X beats Y" (fraction, dimensionless).

    Returns
    -------
    CountedPair
        Wins, losses, ties and the one-sided cases (counts), fractions of every case, mean rmse ratio.
    """
    import numpy as np

    x, y = np.asarray(rmse_X, float), np.asarray(rmse_Y, float)
    ux = np.asarray(usable_X, bool) & np.isfinite(x)
    uy = np.asarray(usable_Y, bool) & np.isfinite(y)
    both = ux & uy
    better = both & (x < (1 - rtol) * y)
    worse = both & (x > (1 + rtol) * y)
    only_x, only_y = ux & ~uy, uy & ~ux
    n = len(x)
    wins, losses = int(better.sum() + only_x.sum()), int(worse.sum() + only_y.sum())
    nb = int(both.sum())
    return CountedPair(
        n_cases=n, X_beats_Y=wins, X_worse_than_Y=losses, ties=int((both & ~better & ~worse).sum()),
        only_X_usable=int(only_x.sum()), only_Y_usable=int(only_y.sum()), neither_usable=int((~ux & ~uy).sum()),
        fraction_X_beats_Y=wins / n if n else None, fraction_X_worse_than_Y=losses / n if n else None,
        n_both_usable=nb, meanrmse_Y_over_X=float(y[both].mean() / x[both].mean()) if nb else None)


@dataclass(frozen=True)
class Table5Statistics:
    """Table 5 statistics of one results table (what ``summary.json`` holds besides the run record).

    Fractions and ratios dimensionless, rmse in rad, times in s.
    """

    outperform_rtol: float  #: relative margin of "X beats Y" (fraction)
    n_cases: int  #: (A, T) cases in the table
    n_cases_any_valid: int  #: cases where at least one setting is usable (valid and verified)
    valid_cases_per_setting: dict[str, int]  #: usable cases by setting name
    mean_rmse_rad: dict[str, float]  #: mean rmse (rad) by setting over its solved, verified cases
    pairs: dict[str, PairStatistics]  #: ``"<X>_vs_<Y>_<all|valid>"`` to the comparison
    #: ``"<X>_vs_<Y>"`` to X against Y over every case (a case only one of them makes usable goes to it)
    counted: dict[str, CountedPair]
    ivvea_vs_sea_guarantee: dict  #: iVVEA against SEA case by case (empty without both settings)
    winning_starts: dict[str, dict[str, int]]  #: per variable-damping setting: start label to cases it won
    best_valid_setting_counts: dict[str, dict[str, int]]  #: per group of settings: best usable setting to cases
    unverified: dict  #: results left out because their trajectory did not verify (count, by setting, cases)
    solver_failures: dict  #: results IPOPT did not solve (count, by status)
    paper_table5: dict[str, float]  #: the paper's Table 5 (context)
    seconds_per_setting: dict[str, float]  #: mean solver wall time per result (s) by setting

    def pair(self, X: str, Y: str, scope: str = "valid") -> PairStatistics | None:
        """The comparison of ``X`` with ``Y`` over ``scope``.

        Parameters
        ----------
        X : str
            Name of the variable-damping setting.
        Y : str
            Name of the other setting.
        scope : str
            ``"valid"`` (both trajectories valid and verified) or ``"all"`` (both solved).

        Returns
        -------
        PairStatistics or None
            None when the table has no such pair (X has constant damping, or a name is not in it).
        """
        return self.pairs.get(f"{X}_vs_{Y}_{scope}")

    def counted_pair(self, X: str, Y: str) -> CountedPair | None:
        """X against Y over every case (:class:`CountedPair`).

        Parameters
        ----------
        X : str
            Name of the variable-damping setting.
        Y : str
            Name of the other setting.

        Returns
        -------
        CountedPair or None
            None when the table has no such pair.
        """
        return self.counted.get(f"{X}_vs_{Y}")

    def to_dict(self) -> dict:
        """Plain-JSON dictionary, in the key order of ``summary.json``.

        Returns
        -------
        dict
            JSON-ready: every field by name, ``pairs`` as name to :meth:`PairStatistics.to_dict`
            (fractions and ratios dimensionless, rmse in rad, times in s).
        """
        d = {f.name: getattr(self, f.name) for f in fields(self)}
        d["pairs"] = {k: p.to_dict() for k, p in self.pairs.items()}
        d["counted"] = {k: p.to_dict() for k, p in self.counted.items()}
        return d


def _bool(series: pd.Series) -> pd.Series:
    return series.astype(str).str.lower().isin(["true", "1"])


def _variable_settings(df: pd.DataFrame, settings: list[str]) -> list[str]:
    """Settings whose damping range is not a single value (variable damping), in table order."""
    return sorted({s for s in settings if (df.loc[df.setting == s, "D_max_Nms_per_rad"]
                                         > df.loc[df.setting == s, "D_min_Nms_per_rad"]).any()},
                  key=settings.index)


def _pairs(piv: pd.DataFrame, valid: pd.DataFrame, varset: list[str], settings: list[str],
           rtol: float) -> dict[str, PairStatistics]:
    """Every (X variable, Y other) comparison over both scopes."""
    pairs = {}
    for X in varset:
        for Y in settings:
            if Y == X:
                continue
            both_valid = valid[X] & valid[Y]
            for scope, mask in (("all", pd.Series(True, index=piv.index)), ("valid", both_valid)):
                sub = piv.loc[mask.reindex(piv.index, fill_value=False), [X, Y]].dropna()
                n = len(sub)
                beats = int((sub[X] < (1 - rtol) * sub[Y]).sum()) if n else 0
                worse = int((sub[X] > (1 + rtol) * sub[Y]).sum()) if n else 0
                pairs[f"{X}_vs_{Y}_{scope}"] = PairStatistics(
                    n_cases=n, X_beats_Y=beats, fraction_X_beats_Y=beats / n if n else None, X_worse_than_Y=worse,
                    meanrmse_Y_over_X=float(sub[Y].mean() / sub[X].mean()) if n else None,
                    n_excluded=int(piv.shape[0] - n))
    return pairs


def _counted(piv: pd.DataFrame, valid: pd.DataFrame, varset: list[str], settings: list[str],
             rtol: float) -> dict[str, CountedPair]:
    """Every (X variable, Y other) comparison over every case of the table."""
    out = {}
    for X in varset:
        for Y in settings:
            if Y != X:
                out[f"{X}_vs_{Y}"] = counted_pair(piv[X], piv[Y], valid[X], valid[Y], rtol)
    return out


def _guarantee(piv: pd.DataFrame, settings: list[str]) -> dict:
    """iVVEA against SEA case by case (the multi-start's guarantee: iVVEA never worse)."""
    if "iVVEA" not in settings or "SEA" not in settings:
        return {}
    sub = piv[["iVVEA", "SEA"]].dropna()
    diff = sub["iVVEA"] - sub["SEA"]
    return {
        "n_cases": len(sub),
        "iVVEA_worse_than_SEA_cases": int((diff > 0).sum()),
        "max_rmse_iVVEA_minus_SEA_rad": float(diff.max()) if len(sub) else None,
    }


def _best_counts(piv: pd.DataFrame, valid: pd.DataFrame, varset: list[str], settings: list[str]) -> dict:
    """Per variable-damping setting with the constant ones: which usable setting tracks best, case count."""
    best_counts = {}
    for scope_sets in ([s for s in settings if s not in varset or s == v] for v in varset):
        cols = [c for c in scope_sets if c in piv.columns]
        label = "+".join(cols)
        rm = piv[cols].where(valid[cols])
        winner = rm.apply(lambda r: r.dropna().idxmin() if r.notna().any() else "none-valid", axis=1)
        best_counts[label] = {str(k): int(v) for k, v in winner.value_counts().items()}
    return best_counts


def table5_statistics(df, outperform_rtol: float = 1e-3) -> Table5Statistics:
    """Table 5 statistics from a results table (pandas DataFrame of results.csv).

    For every pair (X, Y) of settings with X variable-damping: the fraction of
    cases where ``rmse_X < (1 - rtol) rmse_Y`` and ``mean(rmse_Y)/mean(rmse_X)``,
    over (a) ``all``: the cases both solved, and (b) ``valid``: the cases where
    both trajectories are valid (the link reaches 95 % of A in both
    up-phases); and (c) ``counted``: every case, a case where only one of the two is usable
    going to that one (:class:`CountedPair`: nothing is left out). A result whose trajectory did not pass the
    re-simulation check (column ``verified``, :mod:`vvea_design.actuator.verify`) counts as
    not solved; ``unverified`` and each pair's ``n_excluded`` say how many
    were left out. Also: iVVEA-worse-than-SEA count, the winning starts,
    solver failures, and the paper's numbers.

    Parameters
    ----------
    df
        ``results.csv`` as a pandas DataFrame (rmse in rad).
    outperform_rtol
        Relative margin of "X beats Y" (fraction, dimensionless).

    Returns
    -------
    Table5Statistics
        Typed statistics (fractions dimensionless, rmse in rad, times in s); ``to_dict()`` gives the JSON.
    """
    df = df.copy()
    df["success"] = _bool(df["success"])
    df["valid"] = _bool(df["valid"])
    df["verified"] = _bool(df["verified"]) if "verified" in df else df["success"]
    unverified = df[df.success & ~df.verified]
    df.loc[~df.verified, "rmse"] = float("nan")  # an unverified trajectory is no result
    df["usable"] = df.valid & df.verified & df.success
    one = df.drop_duplicates(["case_id", "setting"], keep="last")
    piv = one.pivot(index="case_id", columns="setting", values="rmse").astype(float)
    valid = one.pivot(index="case_id", columns="setting", values="usable").fillna(False).astype(bool)
    settings = list(dict.fromkeys(df["setting"]))
    varset = _variable_settings(df, settings)
    wins = {}
    for X in varset:
        wins[X] = {str(k): int(v) for k, v in df.loc[(df.setting == X) & df.success, "start"]
                   .fillna("").astype(str).str.replace(r"^cross:.*", "cross", regex=True).value_counts().items()}
    failures = df.loc[~df.success, ["case_id", "setting", "status"]]
    return Table5Statistics(
        outperform_rtol=outperform_rtol,
        n_cases=int(piv.shape[0]),
        n_cases_any_valid=int(valid.any(axis=1).sum()),
        valid_cases_per_setting={s: int(valid[s].sum()) for s in valid.columns},
        mean_rmse_rad={s: float(piv[s].mean()) for s in piv.columns},
        pairs=_pairs(piv, valid, varset, settings, outperform_rtol),
        counted=_counted(piv, valid.reindex(index=piv.index, columns=piv.columns, fill_value=False), varset, settings,
                         outperform_rtol),
        ivvea_vs_sea_guarantee=_guarantee(piv, settings),
        winning_starts=wins,
        best_valid_setting_counts=_best_counts(piv, valid, varset, settings),
        unverified={"count": int(len(unverified)),
                    "by_setting": {str(k): int(v) for k, v in unverified["setting"].value_counts().items()},
                    "cases": [f"{r.case_id} {r.setting}" for r in unverified.itertuples()]},
        solver_failures={"count": int(len(failures)),
                         "by_status": {str(k): int(v) for k, v in failures["status"].value_counts().items()}},
        paper_table5=PAPER_TABLE5,
        seconds_per_setting={s: float(df.loc[df.setting == s, "seconds"].mean()) for s in settings},
    )
