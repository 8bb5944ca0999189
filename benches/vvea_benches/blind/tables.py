"""Markdown tables of a run's scores (for docs/diagnosis-protocol.md): per half, per catalogue id, per DEV campaign.

Only aggregates are given for the BLIND half; the per-campaign table is the DEV half's.
"""

from __future__ import annotations

__all__ = ["summary_table", "catalogue_table", "dev_campaign_table", "markdown", "write_tables"]


def _f(x, digits=2):
    if x is None:
        return "–"
    if isinstance(x, float):
        return f"{x:.{digits}f}"
    return str(x)


def summary_table(summary: dict, peers: dict | None) -> str:
    """One column per half: the headline numbers.

    Parameters
    ----------
    summary : dict
        ``summary.json`` of a run (``score.summarise`` per half).
    peers : dict or None
        ``peers_summary.json`` of the run, if the peers ran.

    Returns
    -------
    str
        A markdown table.
    """
    halves = [h for h in ("dev", "blind", "all") if summary.get(h, {}).get("campaigns")]
    lines = ["| | " + " | ".join(h.upper() for h in halves) + " |", "| --- |" + " --- |" * len(halves)]

    def row(label, fn):
        lines.append(f"| {label} | " + " | ".join(fn(h) for h in halves) + " |")

    row("campaigns scored (failed)", lambda h: f"{summary[h]['campaigns']} ({summary[h]['failed']})")
    row("catalogue precision (all campaigns)", lambda h: _f(summary[h]["catalogue"]["precision"]))
    row("catalogue recall (all campaigns)", lambda h: _f(summary[h]["catalogue"]["recall"]))
    row("catalogue campaigns named exactly", lambda h: f"{summary[h]['catalogue']['catalogue_campaigns_found']} of "
                                                       f"{summary[h]['catalogue']['catalogue_campaigns']}")
    row("null campaigns: effects accepted", lambda h: f"{summary[h]['null']['accepted_effects']} in "
                                                      f"{summary[h]['null']['campaigns']}")
    o = {h: summary[h]["outside"] for h in halves}
    row("out-of-catalogue campaigns", lambda h: str(o[h]["campaigns"]))
    row("… modelled (final ≤ 2 × true noise)", lambda h: f"{o[h]['modelled']} ({_f(o[h]['modelled_fraction'])})")
    row("… named as a catalogue effect (wrong)", lambda h: str(o[h]["named_as_catalogue"]))
    row("… not modelled but flagged", lambda h: str(o[h]["flagged_not_modelled"]))
    row("… … flagged with a true state", lambda h: str(o[h]["flagged_with_a_true_state"]))
    row("… … states named: recall / precision (mean)",
        lambda h: f"{_f(o[h].get('flagged_states_recall_mean'))} / {_f(o[h].get('flagged_states_precision_mean'))}")
    row("… missed (not modelled, not flagged, no wrong name)", lambda h: str(o[h]["missed"]))
    row("final held-out RMS > baseline", lambda h: str(summary[h]["final_gt_baseline"]))
    if peers:
        row("campaigns with peers", lambda h: str(peers.get(h, {}).get("campaigns", "–")))
        row("… a peer beats diagnose's final RMS (by > 5 %)",
            lambda h: f"{peers[h]['any_peer_beats_tool']} ({peers[h]['any_peer_beats_tool_by_5pct']})"
            if h in peers else "–")
        row("… per peer: SINDy ∇ / SINDy fit / trees ∇ / trees fit",
            lambda h: " / ".join(str(v) for v in peers[h]["per_peer_beats_tool"].values()) if h in peers else "–")
        row("… modelled ≤ 2 × noise: diagnose vs best peer",
            lambda h: f"{peers[h]['tool_modelled_2x_noise']} vs {max(peers[h]['peer_modelled_2x_noise'].values())}"
            if h in peers else "–")
    return "\n".join(lines)


def catalogue_table(summary: dict) -> str:
    """Catalogue precision and recall per id and half.

    Parameters
    ----------
    summary : dict
        ``summary.json`` of a run.

    Returns
    -------
    str
        A markdown table (tp/fp/fn, precision, recall per half).
    """
    halves = [h for h in ("dev", "blind") if summary.get(h, {}).get("campaigns")]
    head = "| id | " + " | ".join(f"{h.upper()} tp/fp/fn | {h.upper()} precision | {h.upper()} recall" for h in halves)
    lines = [head + " |", "| --- |" + " --- | --- | --- |" * len(halves)]
    for cid in summary[halves[0]]["catalogue"]["per_id"]:
        cells = []
        for h in halves:
            v = summary[h]["catalogue"]["per_id"][cid]
            cells += [f"{v['tp']}/{v['fp']}/{v['fn']}", _f(v["precision"]), _f(v["recall"])]
        lines.append(f"| `{cid}` | " + " | ".join(cells) + " |")
    return "\n".join(lines)


def dev_campaign_table(rows: list[dict], peers: dict) -> str:
    """Per DEV campaign: outcome, held-out RMS over the noise, names, states, the best peer.

    Parameters
    ----------
    rows : list of dict
        DEV score rows.
    peers : dict
        Peer rows by campaign id (may be empty).

    Returns
    -------
    str
        A markdown table.
    """
    lines = ["| campaign | outcome | baseline / noise | final / noise | best peer / noise | wrong catalogue names | "
             "states named (true) |", "| --- | --- | --- | --- | --- | --- | --- |"]
    for r in sorted(rows, key=lambda r: (r["kind"], r["campaign_id"])):
        if "error" in r:
            lines.append(f"| {r['campaign_id']} | error | | | | | |")
            continue
        p = peers.get(r["campaign_id"])
        best = _f(p["best_peer_N"] / r["true_noise_N"]) if p and "best_peer_N" in p else "–"
        named = r["states_named"] or "–"
        lines.append(f"| {r['campaign_id']} | {r['outcome']} | {_f(r['heldout_baseline_N'] / r['true_noise_N'])} | "
                     f"{_f(r['final_over_noise'])} | {best} | {r['extra_catalogue'] or '–'} | "
                     f"{named} ({r['states_truth'] or '–'}) |")
    return "\n".join(lines)


def markdown(summary: dict, peers_summary: dict | None, dev_rows: list[dict], peer_rows: list[dict]) -> str:
    """All tables of a run, for the protocol page.

    Parameters
    ----------
    summary : dict
        ``summary.json``.
    peers_summary : dict or None
        ``peers_summary.json``.
    dev_rows : list of dict
        DEV score rows.
    peer_rows : list of dict
        Peer rows (any half; only the DEV ones are shown).

    Returns
    -------
    str
        Markdown.
    """
    peers = {r["campaign_id"]: r for r in peer_rows if r.get("half") == "dev" and "error" not in r}
    return "\n\n".join([
        "### Per half\n\n" + summary_table(summary, peers_summary),
        "### Catalogue ids per half (over every campaign of the half)\n\n" + catalogue_table(summary),
        "### DEV campaigns\n\n" + dev_campaign_table(dev_rows, peers),
    ])


def write_tables(run, doc=None) -> str:
    """Write ``RUN/tables.md`` from a run folder and, if ``doc`` is given, put it between the doc's
    ``<!-- untuned:start -->`` and ``<!-- untuned:end -->`` markers.

    Parameters
    ----------
    run : path-like
        Run folder of ``studies/blind_diagnosis.py`` (``summary.json``, ``dev/scores.json``,
        optionally ``peers_summary.json`` and ``peers_rows.jsonl``).
    doc : path-like or None
        Markdown page to update.

    Returns
    -------
    str
        The markdown written.
    """
    import json
    import re
    from pathlib import Path

    run = Path(run)
    summary = json.loads((run / "summary.json").read_text())
    peers_path, prow_path = run / "peers_summary.json", run / "peers_rows.jsonl"
    peers = json.loads(peers_path.read_text()) if peers_path.exists() else None
    prow = [json.loads(line) for line in prow_path.read_text().splitlines()] if prow_path.exists() else []
    dev_path = run / "dev" / "scores.json"
    dev = json.loads(dev_path.read_text())["campaigns"] if dev_path.exists() else []
    n_s, n_p = summary["run"].get("campaigns_scored"), summary["run"].get("campaigns_planned")
    head = f"Campaigns scored: {n_s} of {n_p}"
    if n_s != n_p:
        head += " — the sweep had not finished when these tables were written; `--resume` completes it"
    head += f"; peers on {peers['all']['campaigns'] if peers else 0} of them.\n\n"
    md = head + markdown(summary, peers, dev, prow) + "\n"
    (run / "tables.md").write_text(md)
    if doc is not None:
        doc = Path(doc)
        text = doc.read_text()
        if "<!-- untuned:start -->" not in text:
            raise ValueError(f"{doc}: no '<!-- untuned:start -->' marker to write the tables at")
        text = re.sub(r"<!-- untuned:start -->.*<!-- untuned:end -->",
                      lambda _m: "<!-- untuned:start -->\n" + md + "<!-- untuned:end -->", text, flags=re.S)
        doc.write_text(text)
    return md
