"""Score a diagnosis report against a campaign's truth, and summarise many campaigns.

The report is read as the contract of ``shared/specs/diagnosis-report.md`` describes it (``effects``
with ``id``/``accepted``/``catalogue``, ``heldout_rmse_N``, ``unexplained_structure``,
``unexplained_where``, ``learner``); nothing else of the diagnosis is used.

Per campaign (:func:`score_campaign`):

- catalogue: which expected ids were accepted, which accepted catalogue ids were not expected
  (named as catalogue — for a campaign whose extra physics is outside the catalogue, a wrong name);
- null campaigns: how many effects were accepted (must be 0);
- out-of-catalogue campaigns: *modelled* when the final held-out RMS is at most twice the TRUE
  noise RMS; *flagged* when ``unexplained_structure`` is true, with the states the report names
  compared with the truth's;
- every campaign: whether the final held-out RMS exceeds the baseline's.
"""

from __future__ import annotations

import re

import numpy as np

__all__ = ["FEATURE_STATES", "CATALOGUE_IDS", "named_states", "score_campaign", "summarise", "MODELLED_FACTOR"]

#: The ids of the diagnosis catalogue (shared/specs/diagnosis-report.md).
CATALOGUE_IDS = ("gas_nonlinearity", "thermal", "quadratic_damping", "relief_valve", "stiction",
                 "pressure_friction", "leakage")
#: Final held-out RMS at most this many times the true noise counts as modelled.
MODELLED_FACTOR = 2.0
#: How the report's feature words map to the truth's states.
FEATURE_STATES = {
    "displacement": ("position",), "position": ("position",), "x": ("position",), "stroke": ("position",),
    "speed": ("velocity",), "velocity": ("velocity", "direction"), "xdot": ("velocity", "direction"),
    "direction": ("direction",), "extending": ("direction",), "retracting": ("direction",),
    "p2": ("charge",), "pressure": ("charge",), "charge": ("charge",),
    "valve": ("valve",), "gamma": ("valve",),
    "time_since_reversal": ("since_reversal",), "since_reversal": ("since_reversal",),
    "time_in_experiment": ("time_in_experiment",), "time": ("time_in_experiment",),
    "time_since_start": ("time_in_experiment",),
    "campaign_time": ("campaign_order",), "campaign_order": ("campaign_order",), "campaign": ("campaign_order",),
    "run_order": ("campaign_order",),
    "experiment": ("experiment",), "previous_valve": ("history",), "previous_p2": ("history",),
}
_WORD = re.compile(r"^\s*(?:along\s+)?([A-Za-z_][A-Za-z0-9_]*)")


def named_states(report: dict) -> tuple[list[str], list[str]]:
    """States the report names where structure remains.

    Reads the first word of each ``unexplained_where`` entry (a sentence such as ``"valve 108 deg:
    residual RMS ..."`` or ``"along campaign_time (...)"``, or a dict with a ``feature``), and the
    learner's ``where`` features when the learner flagged structure.

    Parameters
    ----------
    report : dict
        The diagnosis report.

    Returns
    -------
    states : list of str
        Truth-vocabulary states named (sorted).
    unknown : list of str
        Feature words that map to no state (sorted).
    """
    words = []
    for w in report.get("unexplained_where") or []:
        if isinstance(w, dict):
            words.append(str(w.get("feature") or w.get("state") or ""))
        else:
            m = _WORD.match(str(w))
            if m:
                words.append(m.group(1))
    learner = report.get("learner") or {}
    if learner.get("flag"):
        words += [str(w.get("feature", "")) for w in learner.get("where") or [] if isinstance(w, dict)]
    states, unknown = set(), set()
    for w in words:
        key = w.lower()
        if key in FEATURE_STATES:
            states.update(FEATURE_STATES[key])
        elif key and key not in ("held", "heldout", "no"):
            unknown.add(key)
    return sorted(states), sorted(unknown)


def _outcome(kind, modelled, misnamed, flagged, missed_cat, extra_cat, n_accepted):
    if kind == "null":
        return "clean" if n_accepted == 0 else "false_accept"
    if kind == "catalogue":
        if not missed_cat and not extra_cat:
            return "found" if modelled else "found_not_modelled"
        return "missed" if missed_cat and not extra_cat else ("extra" if not missed_cat else "missed+extra")
    if modelled:
        return "modelled+misnamed" if misnamed else "modelled"
    if misnamed:
        return "misnamed+flagged" if flagged else "misnamed"
    return "flagged" if flagged else "missed"


def score_campaign(truth: dict, report: dict) -> dict:
    """Score one diagnosis report against its campaign's truth.

    Parameters
    ----------
    truth : dict
        The campaign's truth record (``campaign.build_campaign``).
    report : dict
        The diagnosis's ``report.json``.

    Returns
    -------
    dict
        One flat row: ids, held-out RMS (N) before/after and over the true noise, the catalogue
        ids expected / accepted / missed / named wrongly, flags, states named vs true, outcome.
    """
    effects = report.get("effects") or []
    accepted = [e for e in effects if e.get("accepted")]
    acc_cat = sorted({e["id"] for e in accepted if e.get("catalogue")})
    acc_out = sorted({e["id"] for e in accepted if not e.get("catalogue")})
    expected = sorted(truth["expected_catalogue"])
    extra = sorted(set(acc_cat) - set(expected))
    missed = sorted(set(expected) - set(acc_cat))
    noise = float(truth["noise"]["sigma_N"])
    ho = report.get("heldout_rmse_N") or {}
    base, final = float(ho.get("baseline", np.nan)), float(ho.get("final", np.nan))
    modelled = bool(np.isfinite(final) and final <= MODELLED_FACTOR * noise)
    flagged = bool(report.get("unexplained_structure"))
    states, unknown = named_states(report)
    truth_states = sorted(truth.get("states") or [])
    hit = sorted(set(states) & set(truth_states))
    kind = truth["kind"]
    outside = kind in ("mechanism", "pair")
    misnamed = bool(outside and extra)
    eff = [m.get("effect_over_noise", np.nan) for m in truth["mechanisms"]]
    return {
        "campaign_id": truth["campaign_id"], "kind": kind, "half": truth["half"], "seed": truth["seed"],
        "mechanisms": "+".join(m["name"] for m in truth["mechanisms"]),
        "effect_over_noise": float(np.nanmax(eff)) if eff else 0.0,
        "true_noise_N": noise, "noise_floor_N": float(report.get("noise_floor_N", np.nan)),
        "heldout_baseline_N": base, "heldout_final_N": final, "final_over_noise": final / noise,
        "modelled": modelled, "final_gt_baseline": bool(final > base + 1e-9),
        "expected_catalogue": " ".join(expected), "accepted_catalogue": " ".join(acc_cat),
        "accepted_outside": " ".join(acc_out), "missed_catalogue": " ".join(missed),
        "extra_catalogue": " ".join(extra), "n_accepted": len(accepted),
        "named_as_catalogue": misnamed, "flagged": flagged,
        "states_named": " ".join(states), "states_unknown": " ".join(unknown),
        "states_truth": " ".join(truth_states), "states_hit": " ".join(hit),
        "states_recall": (len(hit) / len(truth_states)) if truth_states else np.nan,
        "states_precision": (len(hit) / len(states)) if states else np.nan,
        "outcome": _outcome(kind, modelled, misnamed, flagged, missed, extra, len(accepted)),
        "runtime_s": float(report.get("runtime_s", np.nan)),
    }


def _mean(values):
    v = [float(x) for x in values if x is not None and np.isfinite(float(x))]
    return float(np.mean(v)) if v else None


def _per_id(rows) -> dict:
    out = {}
    for cid in CATALOGUE_IDS:
        tp = fp = fn = 0
        for r in rows:
            exp, acc = set(r["expected_catalogue"].split()), set(r["accepted_catalogue"].split())
            tp += cid in exp and cid in acc
            fp += cid in acc and cid not in exp
            fn += cid in exp and cid not in acc
        out[cid] = {"tp": tp, "fp": fp, "fn": fn,
                    "precision": tp / (tp + fp) if tp + fp else None,
                    "recall": tp / (tp + fn) if tp + fn else None}
    return out


def summarise(rows: list[dict]) -> dict:
    """Summary of scored campaigns, per half and over all.

    Parameters
    ----------
    rows : list of dict
        Rows of :func:`score_campaign` (failed runs carry an ``error`` key and are counted apart).

    Returns
    -------
    dict
        For ``"dev"``, ``"blind"`` and ``"all"``: campaign counts, catalogue precision/recall per id
        (over every campaign of the half: a wrong name in an out-of-catalogue campaign is a false
        positive), null acceptances, the out-of-catalogue outcomes (modelled ≤ 2 × noise, named as
        catalogue, flagged, states), and how often the final held-out RMS exceeds the baseline's.
    """
    out = {}
    for half in ("dev", "blind", "all"):
        rs = [r for r in rows if half == "all" or r.get("half") == half]
        ok = [r for r in rs if "error" not in r]
        nulls = [r for r in ok if r["kind"] == "null"]
        outside = [r for r in ok if r["kind"] in ("mechanism", "pair")]
        cat = [r for r in ok if r["kind"] == "catalogue"]
        per_id = _per_id(ok)
        tp = sum(v["tp"] for v in per_id.values())
        fp = sum(v["fp"] for v in per_id.values())
        fn = sum(v["fn"] for v in per_id.values())
        flagged_not_modelled = [r for r in outside if r["flagged"] and not r["modelled"]]
        out[half] = {
            "campaigns": len(rs), "failed": len(rs) - len(ok),
            "catalogue": {"per_id": per_id, "precision": tp / (tp + fp) if tp + fp else None,
                          "recall": tp / (tp + fn) if tp + fn else None,
                          "catalogue_campaigns": len(cat),
                          "catalogue_campaigns_found": sum(r["outcome"] in ("found", "found_not_modelled") for r in cat)},
            "null": {"campaigns": len(nulls), "accepted_effects": sum(r["n_accepted"] for r in nulls),
                     "campaigns_with_acceptance": sum(r["n_accepted"] > 0 for r in nulls)},
            "outside": {
                "campaigns": len(outside),
                "modelled": sum(r["modelled"] for r in outside),
                "modelled_fraction": (sum(r["modelled"] for r in outside) / len(outside)) if outside else None,
                "named_as_catalogue": sum(r["named_as_catalogue"] for r in outside),
                "flagged": sum(r["flagged"] for r in outside),
                "flagged_not_modelled": len(flagged_not_modelled),
                "flagged_with_a_true_state": sum(bool(r["states_hit"]) for r in flagged_not_modelled),
                "flagged_states_recall_mean": _mean(r.get("states_recall") for r in flagged_not_modelled),
                "flagged_states_precision_mean": _mean(r.get("states_precision") for r in flagged_not_modelled),
                "missed": sum(r["outcome"] == "missed" for r in outside),
                "outcomes": {k: sum(r["outcome"] == k for r in outside)
                             for k in ("modelled", "modelled+misnamed", "flagged", "misnamed+flagged", "misnamed",
                                       "missed")},
            },
            "final_gt_baseline": sum(r["final_gt_baseline"] for r in ok),
        }
    return out
