"""Discovered family: periodic forces -- in displacement (pitch from a periodogram of the residual) and in time
(phase fitted per experiment).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..signals import periodogram_peaks
from .base import FREE, Effect, Param, fmt_estimate, register

__all__: list[str] = []  # its effects are reached through the registry

#: Place of this module's effects among the candidates (see :mod:`vvea_design.identification.effects`).
RANK = 140


@dataclass(frozen=True)
class PositionRipple(Effect):
    def grid(self, D, ctx):
        periods = np.geomspace(0.3, max(D.travel_mm / 2.5, 0.6), 400)
        return periodogram_peaks(D.x, ctx["residual_N"], periods)

    def columns(self, D, pitch, ctx):
        w = 2 * np.pi * D.x / pitch
        return np.column_stack([np.sin(w), np.cos(w)])

    def describe(self, values, errors, pitch, se):
        A = float(np.hypot(values["a_s"], values["a_c"]))
        return (
            f"A {A:.3g} N periodic force with {fmt_estimate(pitch, se, 'mm')} pitch in displacement, the same in every experiment: "
            "spindle or lead-screw ripple of the drive (or a periodic bore/seal track), not the gas spring."
        )


@dataclass(frozen=True)
class TimeRipple(Effect):
    """A force periodic in time whose phase is not tied to the motion: the phase is fitted per experiment.

    The period and the amplitude are shared by all experiments; each
    experiment's phase is a nuisance parameter set from its own residual
    (``residual_all_N``), so the term cannot be predicted for a new motion
    without measuring it (:meth:`columns` gives zeros without a residual).
    """

    nuisance_per_experiment: int = 2
    shape_xtol: float = 1e-7

    def _fast_rows(self, D):
        dts = D.per_exp_dt()
        keep = dts <= np.median(dts) + 1e-12
        return np.repeat(keep, D.n_per_exp), float(np.max(dts[keep])) if keep.any() else 1.0

    def _power(self, D, r, periods, rows):
        """Per-experiment-phase periodogram: sum over experiments of the power at each period."""
        pw = np.zeros(len(periods))
        w = 2 * np.pi / periods
        trig, kept = {}, 0  # cos and sin of the phases per distinct sampling (experiments share a few), up to 32 MB
        for e in range(D.n_exp):
            a, b = D.bounds[e], D.bounds[e + 1]
            if not rows[a]:
                continue
            key = D.t[a:b].tobytes()
            cs = trig.get(key)
            if cs is None:
                ph = np.outer(D.t[a:b], w)
                cs = (np.cos(ph), np.sin(ph))
                if kept + 2 * ph.nbytes <= 32e6:
                    trig[key] = cs
                    kept += 2 * ph.nbytes
            re = r[a:b] - r[a:b].mean()
            pw += (re @ cs[0]) ** 2 + (re @ cs[1]) ** 2
        return pw

    def grid(self, D, ctx):
        rows, dt = self._fast_rows(D)
        r = ctx["residual_N"]
        periods = np.geomspace(3 * dt, 40.0, 330)
        pw = self._power(D, r, periods, rows & (r != 0))
        if not np.any(pw):
            return np.array([])
        k = int(np.argmax(pw))
        if pw[k] < 5.0 * np.median(pw):  # no line stands out of the noise: nothing periodic to test
            return np.array([])
        best = float(periods[k])
        # the fast experiments are short against a slow ripple: the frequency is resolved by every experiment
        # sampled at least 2.5 times per period (no aliasing), the longest ones most finely: scanned over the
        # coarse estimate's uncertainty (+-15 %) at an eighth of their resolution; then over +-3 of those
        # steps by all experiments (aliasing puts no other line that close) at an eighth of theirs
        dts = D.per_exp_dt()
        live = r != 0
        ok = np.repeat(dts <= best / 2.5, D.n_per_exp) & live
        if ok.any():
            span = max(float(np.max(D.t[ok]) - np.min(D.t[ok])), best)
            f0, df = 1.0 / best, 1.0 / (8.0 * span)
            half = min(0.15 * f0, 400 * df)
            freqs = f0 + np.arange(-half, half + 0.5 * df, df)
            freqs = freqs[freqs > 0]
            best = float(1.0 / freqs[int(np.argmax(self._power(D, r, 1.0 / freqs, ok)))])
        else:
            df = 0.05 / best
        span_all = max(float(np.max(D.t[live]) - np.min(D.t[live])), best) if live.any() else best
        f0, df2 = 1.0 / best, min(1.0 / (8.0 * span_all), df)
        freqs = f0 + np.arange(-3 * df, 3 * df + 0.5 * df2, df2)
        freqs = freqs[freqs > 0]
        best = float(1.0 / freqs[int(np.argmax(self._power(D, r, 1.0 / freqs, live)))])
        step = best * best * df2
        return np.array([best - step, best, best + step])

    def columns(self, D, period, ctx):
        r = ctx.get("residual_all_N")
        if r is None:
            return np.zeros((D.n, 1))
        w = 2 * np.pi / period
        sn, cs = np.sin(w * D.t), np.cos(w * D.t)
        # the phase from a least-squares fit of sine, cosine and an offset to each experiment's residual
        # (an experiment shorter than the period leaves sine and cosine far from orthogonal): the 3 x 3
        # normal equations of all experiments at once
        B = [sn, cs, np.ones(D.n)]
        starts = D.bounds[:-1]
        G = np.empty((D.n_exp, 3, 3))
        rhs = np.empty((D.n_exp, 3))
        for i in range(3):
            rhs[:, i] = np.add.reduceat(B[i] * r, starts) if D.n else 0.0
            for j in range(i, 3):
                G[:, i, j] = G[:, j, i] = np.add.reduceat(B[i] * B[j], starts) if D.n else 0.0
        ok = D.n_per_exp >= 3
        coef = np.zeros((D.n_exp, 3))
        if ok.any():
            G[ok] += 1e-12 * np.trace(G[ok], axis1=1, axis2=2)[:, None, None] * np.eye(3)  # a period much longer than an experiment
            coef[ok] = np.linalg.solve(G[ok], rhs[ok][..., None])[..., 0]
        phi = np.repeat(np.arctan2(coef[:, 1], coef[:, 0]), D.n_per_exp)
        col = np.sin(w * D.t + phi)
        return col[:, None]

    def describe(self, values, errors, period, se):
        return (
            f"A {fmt_estimate(values['A'], errors.get('A'), 'N')} periodic force at {1 / period:.4g} Hz (period {fmt_estimate(period, se, 's')}), "
            "independent of position and speed, its phase not tied to the start of the motion: vibration of the "
            "test machine or a periodic disturbance in the force chain (phase fitted per experiment)."
        )


register(PositionRipple("position_ripple", "periodic force in displacement", "A force periodic in x.",
                        "f += a_s sin(2 pi x/P) + a_c cos(2 pi x/P)",
                        (Param("a_s", "N", *FREE, "sine amplitude"), Param("a_c", "N", *FREE, "cosine amplitude")),
                        Param("P", "mm", 0.0, np.inf, "pitch"), catalogue=False, needs=("residual_N",)))


register(TimeRipple("time_ripple", "periodic force in time", "A force periodic in time.",
                    "f += A sin(2 pi t/T + phi_e)   (phi_e fitted per experiment from its residual)",
                    (Param("A", "N", 0.0, np.inf, "amplitude"),),
                    Param("T", "s", 0.0, np.inf, "period"), catalogue=False, needs=("residual_N",)))
