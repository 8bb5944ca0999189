"""Benchmark of ``diagnose`` on the independent physics bench (issue 10 item 8).

Campaigns come from :mod:`vvea_benches.physbench`, a simulator
written from the physics (chamber energy balance, regime-dependent orifice
flow, relief valve, LuGre friction, leak, sensor filter, ripples) that
shares no formula with the effect catalogue. For every catalogue effect
(``gas_nonlinearity, thermal, quadratic_damping, relief_valve, stiction,
pressure_friction, leakage``), every effect outside the catalogue
(``force_lag, position_ripple, time_ripple, hysteresis, direction_stiffness``)
and for null campaigns (nothing beyond eq. 14), ``--per-effect`` campaigns
with parameters drawn from their own seed are written as CSV in the exchange
format, read back with ``read_recordings`` and diagnosed blind through the
library. The diagnosis is consumed in its JSON form only
(``effects[].id/accepted/catalogue``, ``heldout_rmse_N``, ``noise_floor_N``
if present, ``unexplained_structure``).

Scores, per effect:

- **recall**: share of its campaigns in which it was found. A catalogue
  effect must be accepted under its id; an effect outside the catalogue must
  be modelled by an accepted ``"catalogue": false`` effect whose id names it
  (:data:`SIGNATURE_WORDS`), and is *misnamed* when a catalogue effect is
  accepted instead.
- **precision**: of all campaigns in which the id was accepted (for an
  effect outside the catalogue: a discovered id naming it), the share in
  which it was really present.
- **false positives on nulls**: effects accepted on null campaigns.
- **held-out RMS after / noise**: ``heldout_rmse_N.final`` over the bench's
  true noise RMS (target <= 2) and over the tool's own ``noise_floor_N``.

Nothing here is tuned to the diagnosis: the bench's parameter ranges are
those documented in ``physbench.PARAMETER_RANGES``.

Writes into ``--out`` (default ``studies/results/diagnosis_benchmark``):
``cases.csv`` (one row per campaign), ``summary.json`` and
``benchmark.png``.

Usage::

    python studies/diagnosis_benchmark.py [--quick] [--per-effect 4] [--null 8]
        [--seed 0] [--workers N] [--scheduler tcp://host:port] [--out DIR]
"""

from __future__ import annotations

import argparse
import json
import sys
import tempfile
import time
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import pandas as pd

HERE = Path(__file__).resolve().parent
sys.path[:0] = [str(HERE.parent), str(HERE.parent / "benches")]  # the checkout and its benches, as scripts/install.sh test installs them

from vvea_design.figure_layout import tight_layout_once  # noqa: E402
from vvea_benches import physbench as pb  # noqa: E402

#: Words an accepted non-catalogue effect id must contain to count as naming
#: the out-of-catalogue physics (lower case, any one suffices).
SIGNATURE_WORDS: dict[str, tuple[str, ...]] = {
    "force_lag": ("lag", "filter", "delay"),
    "position_ripple": ("position", "spindle", "pitch", "displacement_periodic"),
    "time_ripple": ("time_ripple", "time_periodic", "frequency", "temporal"),
    "hysteresis": ("hysteresis", "presliding", "pre_sliding", "play", "backlash"),
    "direction_stiffness": ("direction",),
}

#: The reduced campaign of ``--quick`` (and the tests): 2 pressures x 4 valves x 3 speeds.
QUICK_GRID = pb.CampaignGrid(
    pressures_MPa=(1.0, 4.0), valves_deg=(50.0, 104.0, 110.0, 120.0), speeds_mm_s=(0.1, 4.0, 12.0), samples=151
)


@dataclass(frozen=True)
class Case:
    """One benchmark campaign."""

    kind: str  #: "catalogue", "other" or "null"
    effect: str  #: the effect switched on ("" for null)
    seed: int
    grid: pb.CampaignGrid = pb.CampaignGrid()


def make_cases(per_effect: int = 4, n_null: int = 8, seed: int = 0, grid: pb.CampaignGrid | None = None,
               effects: tuple | None = None) -> list[Case]:
    """Campaigns: ``per_effect`` per effect (catalogue and other) and ``n_null`` null ones."""
    grid = grid or pb.CampaignGrid()
    effects = tuple(effects or pb.EFFECTS)
    cases, k = [], 0
    for e in effects:
        kind = "catalogue" if e in pb.CATALOGUE_EFFECTS else "other"
        for _ in range(per_effect):
            cases.append(Case(kind, e, seed * 100000 + k, grid))
            k += 1
    for _ in range(n_null):
        cases.append(Case("null", "", seed * 100000 + k, grid))
        k += 1
    return cases


def report_json(diag) -> dict:
    """The diagnosis in its JSON form, whatever object ``diagnose`` returns."""
    if isinstance(diag, dict):
        rep = diag
    elif hasattr(diag, "to_dict"):
        rep = diag.to_dict()
    elif hasattr(diag, "report"):
        rep = diag.report
        rep = rep.to_dict() if hasattr(rep, "to_dict") else rep
    else:  # pragma: no cover - unknown API
        raise TypeError(f"cannot read a report from {type(diag).__name__}")
    return json.loads(json.dumps(rep, default=lambda o: o.tolist() if hasattr(o, "tolist") else str(o)))


def _noise_floor(rep: dict):
    v = rep.get("noise_floor_N")
    if v is None and isinstance(rep.get("noise_N"), dict):
        v = rep["noise_N"].get("value")
    if isinstance(v, dict):
        v = v.get("value")
    return None if v is None else float(v)


def _is_catalogue(eff: dict) -> bool:
    return bool(eff.get("catalogue", eff.get("id") in pb.CATALOGUE_EFFECTS))


def score(case: Case, rep: dict, truth: pb.BenchTruth) -> dict:
    """Score one diagnosis report (JSON form) against the bench's truth."""
    accepted = [e for e in rep.get("effects", []) if e.get("accepted")]
    acc_cat = [e["id"] for e in accepted if _is_catalogue(e)]
    acc_new = [e["id"] for e in accepted if not _is_catalogue(e)]
    if case.kind == "catalogue":
        found = case.effect in acc_cat
        misnamed = False
    elif case.kind == "other":
        words = SIGNATURE_WORDS[case.effect]
        found = any(any(w in i.lower() for w in words) for i in acc_new)
        misnamed = bool(acc_cat)
    else:
        found, misnamed = False, False
    wrong_cat = [i for i in acc_cat if i != case.effect]
    held = rep.get("heldout_rmse_N", {}) or {}
    floor = _noise_floor(rep)
    fin = held.get("final")
    return dict(
        kind=case.kind,
        effect=case.effect,
        seed=case.seed,
        n_experiments=int(truth.run_order.shape[0]),
        accepted_catalogue=acc_cat,
        accepted_discovered=acc_new,
        found=bool(found),
        misnamed_as_catalogue=bool(misnamed),
        false_positive_catalogue=wrong_cat,
        unexplained_structure=bool(rep.get("unexplained_structure", False)),
        heldout_baseline_N=held.get("baseline"),
        heldout_final_N=fin,
        noise_true_N=truth.noise_N,
        noise_floor_N=floor,
        final_over_noise=(None if fin is None else float(fin) / truth.noise_N),
        final_over_floor=(None if fin is None or not floor else float(fin) / floor),
        effect_parameters=truth.to_dict()["effect_parameters"],
    )


def run_case(case: Case) -> dict:
    """Simulate, write, read, diagnose blind and score one campaign (picklable for ``parallel_map``)."""
    from vvea_design.identification.diagnose import diagnose
    from vvea_design.identification.recordings import read_recordings

    t0 = time.perf_counter()
    camp = pb.simulate_campaign(pb.random_parameters((case.effect,) if case.effect else (), seed=case.seed, grid=case.grid))
    with tempfile.TemporaryDirectory(prefix="vvea-bench-") as tmp:
        path = pb.write_campaign(camp, Path(tmp) / f"campaign_{case.seed}.csv")
        rec = read_recordings(path)
    t1 = time.perf_counter()
    try:
        rep = report_json(diagnose(rec))
        error = ""
    except Exception as exc:  # a crash is a result of the benchmark, not a reason to stop it
        rep, error = {}, f"{type(exc).__name__}: {exc}"
    t2 = time.perf_counter()
    out = score(case, rep, camp.truth)
    out.update(simulate_s=t1 - t0, diagnose_s=t2 - t1, error=error)
    return out


def _rate(v):
    return None if not v else float(np.mean(v))


def summarise(results: list[dict]) -> dict:
    """Recall, precision, misnaming, false positives on nulls and held-out RMS / noise, per effect."""
    out: dict = {"n_campaigns": len(results), "per_effect": {}}
    for e in pb.EFFECTS:
        rows = [r for r in results if r["effect"] == e]
        if not rows:
            continue
        ratio = [r["final_over_noise"] for r in rows if r["final_over_noise"] is not None]
        rfl = [r["final_over_floor"] for r in rows if r["final_over_floor"] is not None]
        d = dict(
            catalogue=e in pb.CATALOGUE_EFFECTS,
            n=len(rows),
            recall=_rate([r["found"] for r in rows]),
            heldout_final_over_noise_median=float(np.median(ratio)) if ratio else None,
            share_final_le_2x_noise=_rate([q <= 2.0 for q in ratio]),
            heldout_final_over_floor_median=float(np.median(rfl)) if rfl else None,
            unexplained_flag_rate=_rate([r["unexplained_structure"] for r in rows]),
            errors=sum(bool(r["error"]) for r in rows),
        )
        if e in pb.CATALOGUE_EFFECTS:
            acc = [r for r in results if e in r["accepted_catalogue"]]
            d["precision"] = _rate([r["effect"] == e for r in acc])
            d["accepted_in_campaigns"] = len(acc)
            d["other_catalogue_ids_accepted"] = sorted({i for r in rows for i in r["false_positive_catalogue"]})
        else:
            words = SIGNATURE_WORDS[e]
            acc = [r for r in results if any(any(w in i.lower() for w in words) for i in r["accepted_discovered"])]
            d["precision"] = _rate([r["effect"] == e for r in acc])
            d["accepted_in_campaigns"] = len(acc)
            d["misnamed_as_catalogue_rate"] = _rate([r["misnamed_as_catalogue"] for r in rows])
            d["catalogue_ids_accepted"] = sorted({i for r in rows for i in r["accepted_catalogue"]})
            d["discovered_ids_accepted"] = sorted({i for r in rows for i in r["accepted_discovered"]})
        out["per_effect"][e] = d
    nulls = [r for r in results if r["kind"] == "null"]
    if nulls:
        ratio = [r["final_over_noise"] for r in nulls if r["final_over_noise"] is not None]
        out["null"] = dict(
            n=len(nulls),
            campaigns_with_false_positive=int(sum(bool(r["accepted_catalogue"] or r["accepted_discovered"]) for r in nulls)),
            accepted=[r["accepted_catalogue"] + r["accepted_discovered"] for r in nulls if r["accepted_catalogue"] or r["accepted_discovered"]],
            heldout_final_over_noise_median=float(np.median(ratio)) if ratio else None,
            unexplained_flag_rate=_rate([r["unexplained_structure"] for r in nulls]),
        )
    cat = [r for r in results if r["kind"] == "catalogue"]
    if cat:
        out["catalogue_overall"] = dict(
            recall=_rate([r["found"] for r in cat]),
            share_final_le_2x_noise=_rate([r["final_over_noise"] <= 2 for r in cat if r["final_over_noise"] is not None]),
        )
    out["diagnose_s"] = dict(median=float(np.median([r["diagnose_s"] for r in results])),
                             max=float(np.max([r["diagnose_s"] for r in results])))
    out["errors"] = [dict(effect=r["effect"], seed=r["seed"], error=r["error"]) for r in results if r["error"]]
    return out


def plot(summary: dict):
    """Recall/precision per effect and held-out RMS after the fit over the noise; returns the Figure."""
    import matplotlib.pyplot as plt

    pe = summary["per_effect"]
    names = list(pe)
    fig, (ax, ax2) = plt.subplots(2, 1, figsize=(11, 8.5), sharex=True)
    xs = np.arange(len(names))
    rec = [pe[n]["recall"] or 0.0 for n in names]
    prec = [pe[n].get("precision") for n in names]
    mis = [pe[n].get("misnamed_as_catalogue_rate") for n in names]
    lab = lambda vals: ["" if v is None else f"{v:.2f}" for v in vals]  # noqa: E731
    c1 = ax.bar(xs - 0.25, rec, 0.25, label="recall (found / named right)", color="C0")
    c2 = ax.bar(xs, [p if p is not None else 0 for p in prec], 0.25, label="precision", color="C2")
    c3 = ax.bar(xs + 0.25, [m if m is not None else 0 for m in mis], 0.25, label="named as a catalogue effect (wrong)",
                color="C3")
    for c, vals in ((c1, rec), (c2, prec), (c3, mis)):
        ax.bar_label(c, labels=lab(vals), fontsize=6.5, padding=1, rotation=90)
    ax.axhline(0.95, color="k", ls="--", lw=0.8, label="target 0.95")
    ax.set_ylim(0, 1.32)
    ax.set_ylabel("share of campaigns [-]")
    nul = summary.get("null", {})
    ax.set_title(
        f"diagnose on the independent physics bench ({summary['n_campaigns']} campaigns); "
        f"null campaigns with an accepted effect: {nul.get('campaigns_with_false_positive', 'n/a')} of {nul.get('n', 0)}"
    )
    ax.legend(fontsize=8, loc="upper right", ncol=2)
    ratio = [pe[n]["heldout_final_over_noise_median"] for n in names]
    c4 = ax2.bar(xs, [r if r is not None else 0 for r in ratio], 0.5,
                 color=["C0" if pe[n]["catalogue"] else "C1" for n in names])
    ax2.bar_label(c4, labels=lab(ratio), fontsize=7, padding=1)
    ax2.axhline(2.0, color="k", ls="--", lw=0.8, label="target: 2 x noise")
    ax2.set_yscale("log")
    ax2.set_ylabel("held-out RMS after fit / true noise RMS [-]\n(median over campaigns)")
    ax2.set_xticks(xs)
    ax2.set_xticklabels([f"{n}\n(n={pe[n]['n']})" for n in names], rotation=30, ha="right")
    ax2.legend(handles=[plt.Rectangle((0, 0), 1, 1, color="C0", label="catalogue effect"),
                        plt.Rectangle((0, 0), 1, 1, color="C1", label="outside the catalogue"),
                        plt.Line2D([], [], color="k", ls="--", lw=0.8, label="target: 2 x noise")], fontsize=8)
    tight_layout_once(fig)
    return fig


def cases_frame(results: list[dict]) -> pd.DataFrame:
    rows = []
    for r in results:
        q = {k: v for k, v in r.items() if k != "effect_parameters"}
        for k in ("accepted_catalogue", "accepted_discovered", "false_positive_catalogue"):
            q[k] = "+".join(q[k])
        q["effect_parameters"] = json.dumps(r["effect_parameters"])
        rows.append(q)
    return pd.DataFrame(rows)


def results_from_cases(path: Path) -> list[dict]:
    """Read back ``cases.csv`` (to re-summarise and re-plot without re-running)."""
    f = pd.read_csv(path, keep_default_na=False)
    out = []
    for r in f.to_dict("records"):
        for k in ("accepted_catalogue", "accepted_discovered", "false_positive_catalogue"):
            r[k] = [i for i in str(r[k]).split("+") if i]
        for k in ("found", "misnamed_as_catalogue", "unexplained_structure"):
            r[k] = str(r[k]) == "True"
        for k in ("heldout_baseline_N", "heldout_final_N", "noise_floor_N", "final_over_noise", "final_over_floor"):
            r[k] = None if r[k] == "" else float(r[k])
        r["effect"] = "" if r["kind"] == "null" else r["effect"]
        r["error"] = str(r["error"])
        r["effect_parameters"] = json.loads(r["effect_parameters"])
        out.append(r)
    return out


def main(argv=None) -> dict:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--out", type=Path, default=HERE / "results" / "diagnosis_benchmark")
    ap.add_argument("--per-effect", type=int, default=4, help="campaigns per effect")
    ap.add_argument("--null", type=int, default=8, help="campaigns with nothing beyond eq. 14")
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--quick", action="store_true", help="1 campaign per effect + 2 nulls on a 24-experiment grid")
    ap.add_argument("--effects", default=None, help="comma-separated subset of effects")
    ap.add_argument("--workers", type=int, default=None)
    ap.add_argument("--scheduler", default=None)
    ap.add_argument("--from-cases", type=Path, default=None, help="re-summarise and re-plot an earlier cases.csv")
    args = ap.parse_args(argv)
    import matplotlib

    matplotlib.use("Agg")
    from vvea_design.parallel import parallel_map
    from vvea_design.progress import console

    effects = tuple(args.effects.split(",")) if args.effects else None
    if args.quick:
        cases = make_cases(1, 2, args.seed, QUICK_GRID, effects)
    else:
        cases = make_cases(args.per_effect, args.null, args.seed, None, effects)
    t0 = time.perf_counter()
    if args.from_cases:
        results = results_from_cases(args.from_cases)
        prev = args.from_cases.parent / "summary.json"
        wall = json.loads(prev.read_text()).get("wall_s") if prev.exists() else None
    else:
        results = parallel_map(run_case, cases, workers=args.workers, scheduler=args.scheduler,
                               description="diagnosis benchmark")
        wall = time.perf_counter() - t0
    summary = summarise(results)
    summary["wall_s"] = wall
    summary["grid"] = cases[0].grid.to_dict()
    args.out.mkdir(parents=True, exist_ok=True)
    cases_frame(results).to_csv(args.out / "cases.csv", index=False)
    (args.out / "summary.json").write_text(json.dumps(summary, indent=1))
    fig = plot(summary)
    fig.savefig(args.out / "benchmark.png", dpi=110)
    console.print(f"[bold]diagnosis benchmark[/bold] (independent physics bench): {len(results)} campaigns, "
                  f"{summary['wall_s'] or 0:.0f} s -> {args.out}")
    for e, d in summary["per_effect"].items():
        pr = d.get("precision")
        extra = f"precision {'n/a' if pr is None else f'{pr:.2f}'}"
        if not d["catalogue"]:
            extra += f"  named as catalogue {d['misnamed_as_catalogue_rate']:.2f}"
        r2 = d["heldout_final_over_noise_median"]
        console.print(f"  {e:<20} recall {d['recall']:.2f}  {extra:<44} held-out/noise "
                      f"{'n/a' if r2 is None else f'{r2:6.2f}'}  errors {d['errors']}")
    if "null" in summary:
        n = summary["null"]
        console.print(f"  null campaigns with an accepted effect: {n['campaigns_with_false_positive']} of {n['n']} {n['accepted']}")
    return summary


if __name__ == "__main__":
    main()
