"""Campaign generator: the paper's campaign on the simulated unit, with mechanisms switched on.

A campaign is named by a :class:`CampaignSpec` (kind, mechanisms, seed) and is deterministic from
it: the base unit, the run order, the mechanisms' parameters and the noise all come from
generators seeded by the seed and the campaign's id. :func:`build_campaign` returns the recordings
(the exchange format of ``shared/specs/recordings.md``) and a truth record (mechanisms,
parameters, the states they depend on, the true noise, the catalogue ids a diagnosis should name).

Kinds:

- ``null``: linear gas law (eq. 14 holds exactly) and noise — a diagnosis must accept nothing;
- ``catalogue``: the chambers' base (``gas_nonlinearity``) plus one catalogue form;
- ``mechanism`` / ``pair``: the chambers' base plus one / two mechanisms outside the catalogue.
"""

from __future__ import annotations

from dataclasses import asdict, dataclass, replace
from pathlib import Path

import numpy as np
import pandas as pd

from .motion import Motion, plan_campaign
from .registry import BLIND, CATALOGUE, DEV, PAIRS, half_of_mechanism, half_of_seed, lookup
from .simulate import ExperimentMods, simulate_experiment
from .spec import CampaignContext, stable_seed
from .unit import BaseUnit, sample_base

__all__ = ["CampaignSpec", "Campaign", "campaign_specs", "build_campaign", "write_campaign", "X_NOISE_MM",
           "COLUMNS"]

#: Displacement noise of the crosshead encoder, mm.
X_NOISE_MM = 0.002
#: Columns of the exchange format, in order.
COLUMNS = ("experiment", "time_s", "displacement_mm", "force_N", "p2_MPa", "valve_deg", "speed_mm_s")
KINDS = ("null", "catalogue", "mechanism", "pair")


@dataclass(frozen=True)
class CampaignSpec:
    """What one campaign holds; the campaign is deterministic from it."""

    campaign_id: str  #: unique name (also part of the seed)
    kind: str  #: "null", "catalogue", "mechanism" or "pair"
    mechanisms: tuple[str, ...]  #: switched-on mechanisms / catalogue forms
    seed: int  #: seed
    half: str  #: "dev" or "blind"
    gas_law: str = "chambers"  #: base gas law
    noise: str = "auto"  #: "white", "ar" (AR(1) correlated) or "auto" (either, by the seed)
    n_per_ramp: int = 200  #: sample intervals per ramp

    def __post_init__(self) -> None:
        if self.kind not in KINDS:
            raise ValueError(f"CampaignSpec.kind must be one of {KINDS}, got {self.kind!r}")
        if self.half not in ("dev", "blind"):
            raise ValueError(f"CampaignSpec.half must be 'dev' or 'blind', got {self.half!r}")
        if self.noise not in ("white", "ar", "auto"):
            raise ValueError(f"CampaignSpec.noise must be 'white', 'ar' or 'auto', got {self.noise!r}")
        for name in self.mechanisms:
            lookup(name)

    def to_dict(self) -> dict:
        """Plain-JSON form.

        Returns
        -------
        dict
            The fields.
        """
        d = asdict(self)
        d["mechanisms"] = list(self.mechanisms)
        return d


@dataclass(frozen=True)
class Campaign:
    """Recordings and their truth."""

    spec: CampaignSpec  #: what was asked for
    recordings: pd.DataFrame  #: the exchange-format table
    truth: dict  #: mechanisms, parameters, states, noise, expected catalogue ids

    def to_dict(self) -> dict:
        """The truth record (the recordings are written separately).

        Returns
        -------
        dict
            The truth.
        """
        return dict(self.truth)


def campaign_specs(half: str = "all", seeds=(0, 1), n_per_ramp: int = 200) -> list[CampaignSpec]:
    """The campaigns of one half (or both) for the given seeds.

    Per seed: one campaign per mechanism of the half and one per pair of the half; for seeds of
    the half (even: dev, odd: blind) also one per catalogue form and two null campaigns (white
    and AR(1) noise).

    Parameters
    ----------
    half : str
        "dev", "blind" or "all".
    seeds : iterable of int
        Seeds.
    n_per_ramp : int
        Sample intervals per ramp.

    Returns
    -------
    list of CampaignSpec
        In a stable order.
    """
    if half not in ("dev", "blind", "all"):
        raise ValueError(f"half must be 'dev', 'blind' or 'all', got {half!r}")
    halves = ("dev", "blind") if half == "all" else (half,)
    out = []
    for seed in seeds:
        seed = int(seed)
        for h in halves:
            for name in (DEV if h == "dev" else BLIND):
                out.append(CampaignSpec(f"mech-{name}-s{seed}", "mechanism", (name,), seed, h, n_per_ramp=n_per_ramp))
            for a, b in PAIRS[h]:
                out.append(CampaignSpec(f"pair-{a}+{b}-s{seed}", "pair", (a, b), seed, h, n_per_ramp=n_per_ramp))
        h = half_of_seed(seed)
        if h in halves:
            for cid in CATALOGUE:
                out.append(CampaignSpec(f"cat-{cid}-s{seed}", "catalogue", (cid,), seed, h, n_per_ramp=n_per_ramp))
            for noise in ("white", "ar"):
                out.append(CampaignSpec(f"null-{noise}-s{seed}", "null", (), seed, h, gas_law="linear",
                                        noise=noise, n_per_ramp=n_per_ramp))
    return out


def _mods_for(names, params, ctx) -> list[ExperimentMods]:
    mods = [ExperimentMods(valve_deg=p.valve_deg) for p in ctx.plans]
    # the valve's position first: other mechanisms read it
    for name in sorted(names, key=lambda n: n != "valve_backlash"):
        lookup(name).apply(params[name], ctx, mods)
    return mods


def _noise_free(ctx: CampaignContext, names, params) -> list[dict]:
    mods = _mods_for(names, params, ctx)
    return [simulate_experiment(ctx.base, p, m, mo) for p, m, mo in zip(ctx.plans, mods, ctx.motions)]


def _linearised(base: BaseUnit, ctx: CampaignContext) -> BaseUnit:
    """The same unit with the straight line g p2 x that fits its chambers best (least squares)."""
    num = den = 0.0
    for p, mo in zip(ctx.plans, ctx.motions):
        x = mo.position_mm(mo.t_s)
        F = base.gas_force_N(x, p.p2_MPa)
        num += float(np.sum(F * p.p2_MPa * x))
        den += float(np.sum((p.p2_MPa * x) ** 2))
    return replace(base, gas_law="linear", g_N_per_mm_MPa=num / den)


def _noise(rng: np.random.Generator, n: int, sigma: float, phi: float) -> np.ndarray:
    w = rng.normal(0.0, sigma, n)
    if phi == 0.0:
        return w
    e = np.empty(n)
    e[0] = w[0]
    c = np.sqrt(1.0 - phi * phi)
    for k in range(1, n):
        e[k] = phi * e[k - 1] + c * w[k]
    return e


def build_campaign(spec: CampaignSpec) -> Campaign:
    """Generate one campaign (deterministic from ``spec``).

    Parameters
    ----------
    spec : CampaignSpec
        What to generate.

    Returns
    -------
    Campaign
        Recordings (one row per sample, experiments in run order) and truth.
    """
    rng = np.random.default_rng([spec.seed, stable_seed("campaign", spec.campaign_id)])
    base = sample_base(rng, spec.gas_law)
    plans = tuple(plan_campaign(rng, spec.n_per_ramp))
    motions = tuple(Motion(p.speed_mm_s, n_per_ramp=spec.n_per_ramp) for p in plans)
    ctx = CampaignContext(base, plans, motions, stable_seed(spec.campaign_id, spec.seed))
    params = {n: lookup(n).sample(np.random.default_rng([spec.seed, stable_seed(spec.campaign_id, n)]))
              for n in spec.mechanisms}
    sigma = float(rng.uniform(2.0, 5.0))
    ar = spec.noise == "ar" or (spec.noise == "auto" and rng.random() < 0.5)
    phi = float(rng.uniform(0.3, 0.7)) if ar else 0.0

    sims = _noise_free(ctx, spec.mechanisms, params)
    f_all = np.concatenate([s["f_meas_N"] for s in sims])
    mech_rows = []
    for name in spec.mechanisms:
        if name == "gas_nonlinearity":
            ctx0 = replace(ctx, base=_linearised(base, ctx))
            others = [n for n in spec.mechanisms if n != name]
        else:
            ctx0, others = ctx, [n for n in spec.mechanisms if n != name]
        f0 = np.concatenate([s["f_meas_N"] for s in _noise_free(ctx0, others, params)])
        eff = float(np.sqrt(np.mean((f_all - f0) ** 2)))
        s = lookup(name)
        mech_rows.append({"name": name, "catalogue_id": s.catalogue_id, "domain": s.domain,
                          "description": s.description, "states": list(s.states),
                          "parameters": params[name], "effect_rms_N": eff, "effect_over_noise": eff / sigma,
                          "half": half_of_mechanism(name) if s.catalogue_id is None else spec.half})

    nrng = np.random.default_rng([spec.seed, stable_seed("noise", spec.campaign_id)])
    frames, noise_all = [], []
    for p, s in zip(plans, sims):
        n = len(s["t_s"])
        e = _noise(nrng, n, sigma, phi)
        noise_all.append(e)
        frames.append(pd.DataFrame({
            "experiment": p.name,
            "time_s": np.round(s["t_s"], 6),
            "displacement_mm": np.round(s["x_cross_mm"] + nrng.normal(0.0, X_NOISE_MM, n), 5),
            "force_N": np.round(s["f_meas_N"] + e, 3),
            "p2_MPa": p.p2_MPa, "valve_deg": p.valve_deg, "speed_mm_s": p.speed_mm_s}))
    rec = pd.concat(frames, ignore_index=True)[list(COLUMNS)]
    noise_all = np.concatenate(noise_all)

    expected = sorted({"gas_nonlinearity"} if spec.gas_law == "chambers" else set())
    expected = sorted(set(expected) | {r["catalogue_id"] for r in mech_rows if r["catalogue_id"]})
    outside = [r for r in mech_rows if r["catalogue_id"] is None]
    truth = {
        "campaign_id": spec.campaign_id, "kind": spec.kind, "half": spec.half, "seed": spec.seed,
        "spec": spec.to_dict(),
        "mechanisms": mech_rows,
        "expected_catalogue": expected,
        "out_of_catalogue": [r["name"] for r in outside],
        "states": sorted({st for r in outside for st in r["states"]}),
        "noise": {"sigma_N": sigma, "ar_phi": phi, "rms_N": float(np.sqrt(np.mean(noise_all**2))),
                  "x_sigma_mm": X_NOISE_MM},
        "base": base.to_dict(),
        "n_experiments": len(plans), "n_rows": int(len(rec)),
        "campaign_duration_h": (plans[-1].t_start_s + plans[-1].duration_s) / 3600.0,
        "plan": [p.to_dict() for p in plans],
    }
    return Campaign(spec, rec, truth)


def write_campaign(campaign: Campaign, folder: Path) -> tuple[Path, Path]:
    """Write ``<id>.csv`` (exchange format) and ``<id>.truth.json`` into ``folder``.

    Parameters
    ----------
    campaign : Campaign
        The campaign.
    folder : pathlib.Path
        Output folder (created).

    Returns
    -------
    csv_path, truth_path : pathlib.Path
        The two files.
    """
    import json

    folder = Path(folder)
    folder.mkdir(parents=True, exist_ok=True)
    cid = campaign.spec.campaign_id
    csv_path, truth_path = folder / f"{cid}.csv", folder / f"{cid}.truth.json"
    campaign.recordings.to_csv(csv_path, index=False)
    truth_path.write_text(json.dumps(campaign.truth, indent=1))
    return csv_path, truth_path
