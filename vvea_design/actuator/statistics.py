"""Table 5 statistics of a rest-to-rest results table (paper section 5)."""

from __future__ import annotations

import pandas as pd

__all__ = ["PAPER_TABLE5", "table5_statistics"]


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


def table5_statistics(df, outperform_rtol: float = 1e-3) -> dict:
    """Table 5 statistics from a results table (pandas DataFrame of results.csv).

    For every pair (X, Y) of settings with X variable-damping: the fraction of
    cases where ``rmse_X < (1 - rtol) rmse_Y`` and ``mean(rmse_Y)/mean(rmse_X)``,
    over (a) ``all``: the cases both solved, and (b) ``valid``: the cases where
    both trajectories are valid (the link reaches 95 % of A in both
    up-phases). A result whose trajectory did not pass the re-simulation
    check (column ``verified``, :mod:`vvea_design.actuator.verify`) counts as
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
    dict
        JSON-ready statistics (fractions dimensionless, rmse in rad, times in s).
    """
    df = df.copy()

    def _bool(col: str) -> pd.Series:
        return df[col].astype(str).str.lower().isin(["true", "1"])

    df["success"] = _bool("success")
    df["valid"] = _bool("valid")
    df["verified"] = _bool("verified") if "verified" in df else df["success"]
    unverified = df[df.success & ~df.verified]
    df.loc[~df.verified, "rmse"] = float("nan")  # an unverified trajectory is no result
    df["usable"] = df.valid & df.verified & df.success
    one = df.drop_duplicates(["case_id", "setting"], keep="last")
    piv = one.pivot(index="case_id", columns="setting", values="rmse").astype(float)
    valid = one.pivot(index="case_id", columns="setting", values="usable").fillna(False).astype(bool)
    any_valid = valid.any(axis=1)
    settings = list(dict.fromkeys(df["setting"]))
    varset = sorted({s for s in settings if (df.loc[df.setting == s, "D_max_Nms_per_rad"]
                                           > df.loc[df.setting == s, "D_min_Nms_per_rad"]).any()},
                    key=settings.index)
    pairs = {}
    for X in varset:
        for Y in settings:
            if Y == X:
                continue
            both_valid = valid[X] & valid[Y]
            for scope, mask in (("all", pd.Series(True, index=piv.index)), ("valid", both_valid)):
                sub = piv.loc[mask.reindex(piv.index, fill_value=False), [X, Y]].dropna()
                n = len(sub)
                beats = int((sub[X] < (1 - outperform_rtol) * sub[Y]).sum()) if n else 0
                worse = int((sub[X] > (1 + outperform_rtol) * sub[Y]).sum()) if n else 0
                pairs[f"{X}_vs_{Y}_{scope}"] = {
                    "n_cases": n,
                    "X_beats_Y": beats,
                    "fraction_X_beats_Y": beats / n if n else None,
                    "X_worse_than_Y": worse,
                    "meanrmse_Y_over_X": float(sub[Y].mean() / sub[X].mean()) if n else None,
                    "n_excluded": int(piv.shape[0] - n),
                }
    guarantee = {}
    if "iVVEA" in settings and "SEA" in settings:
        sub = piv[["iVVEA", "SEA"]].dropna()
        diff = sub["iVVEA"] - sub["SEA"]
        guarantee = {
            "n_cases": len(sub),
            "iVVEA_worse_than_SEA_cases": int((diff > 0).sum()),
            "max_rmse_iVVEA_minus_SEA_rad": float(diff.max()) if len(sub) else None,
        }
    wins = {}
    for X in varset:
        wins[X] = {str(k): int(v) for k, v in df.loc[(df.setting == X) & df.success, "start"]
                   .fillna("").astype(str).str.replace(r"^cross:.*", "cross", regex=True).value_counts().items()}
    failures = df.loc[~df.success, ["case_id", "setting", "status"]]
    best_counts = {}
    for scope_sets in ([s for s in settings if s not in varset or s == v] for v in varset):
        cols = [c for c in scope_sets if c in piv.columns]
        label = "+".join(cols)
        rm = piv[cols].where(valid[cols])
        winner = rm.apply(lambda r: r.dropna().idxmin() if r.notna().any() else "none-valid", axis=1)
        best_counts[label] = {str(k): int(v) for k, v in winner.value_counts().items()}
    return {
        "outperform_rtol": outperform_rtol,
        "n_cases": int(piv.shape[0]),
        "n_cases_any_valid": int(any_valid.sum()),
        "valid_cases_per_setting": {s: int(valid[s].sum()) for s in valid.columns},
        "mean_rmse_rad": {s: float(piv[s].mean()) for s in piv.columns},
        "pairs": pairs,
        "ivvea_vs_sea_guarantee": guarantee,
        "winning_starts": wins,
        "best_valid_setting_counts": best_counts,
        "unverified": {"count": int(len(unverified)),
                       "by_setting": {str(k): int(v) for k, v in unverified["setting"].value_counts().items()},
                       "cases": [f"{r.case_id} {r.setting}" for r in unverified.itertuples()]},
        "solver_failures": {"count": int(len(failures)),
                            "by_status": {str(k): int(v) for k, v in failures["status"].value_counts().items()}},
        "paper_table5": PAPER_TABLE5,
        "seconds_per_setting": {s: float(df.loc[df.setting == s, "seconds"].mean()) for s in settings},
    }


