"""Discovered family: dynamics of the force reading (sensor or amplifier), the whole model lagged.

``force_lag`` (first order) and one second-order filter (``force_filter_lag``,
its shape the lag ``2 ζ/ω_n``); the accepted filter's damping ratio is fitted
over :data:`ZETA_RANGE` (a general second-order sensor, not a list of
standard filter types); a filter whose damping ratio was fitted is made from its id
(:func:`filter_id`, e.g. ``force_filter_lag_z0733``) on first lookup.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..signals import filter_design
from .base import Effect, Param, fmt_estimate, register, register_maker

__all__ = ["ZETA_RANGE", "filter_id", "fitted_filter"]

#: Place of this module's effects among the candidates (see :mod:`vvea_design.identification.effects`).
RANK = 110


@dataclass(frozen=True)
class ForceLag(Effect):
    def grid(self, D, ctx):
        return np.geomspace(0.003, 3.0, 13)

    def columns(self, D, tau, ctx):
        return np.zeros((D.n, 0))

    def transform(self, D, X, tau, ctx, out=None, eq14_first=False):
        # the reading is the unit's force through a first-order lag: every column of the model is lagged
        # (exact and still linear in the amplitudes); the sensor starts from the unit at rest before the
        # motion (zero force state: every column of the model vanishes at rest at x = 0)
        def ba(dt):
            q = np.exp(-dt / tau)
            return [1.0 - q], [1.0, -q]

        return filter_design(D, X, ba, out, eq14_first)

    def describe(self, values, errors, tau, se):
        return (
            f"The force reading lags the motion by tau = {fmt_estimate(tau, se, 's')} (first-order lag of the whole force): "
            "sensor or amplifier dynamics, not the spring or damper."
        )


def _bilinear_2nd_order(wn: float, zeta: float, fs: float):
    """``scipy.signal.bilinear([wn²], [1, 2 ζ wn, wn²], fs)`` in closed form (the same digital filter, without its polynomial overhead).

    Parameters: natural frequency ``wn`` (rad/s), damping ratio ``zeta`` (-), sampling rate ``fs`` (Hz).
    Returns the numerator and denominator coefficients (descending powers of z, ``a[0] = 1``).
    """
    K = 2.0 * fs
    a0 = K * K + 2.0 * zeta * wn * K + wn * wn
    b = (wn * wn / a0) * np.array([1.0, 2.0, 1.0])
    a = np.array([1.0, 2.0 * (wn * wn - K * K) / a0, (K * K - 2.0 * zeta * wn * K + wn * wn) / a0])
    return b, a


@dataclass(frozen=True)
class ForceFilter(ForceLag):
    """Second-order low-pass of the force reading (damping ratio ``zeta`` of a standard filter type); shape = its lag 2 zeta / omega_n."""

    zeta: float = 0.7071
    kind: str = "Butterworth"

    def grid(self, D, ctx):
        # the filter types compete on this grid, so it is fine around the lag the residual shows: a lag
        # tau leaves residual ~ -tau df/dt of the model force f (first order in tau)
        r, f = ctx.get("residual_N"), ctx.get("model_force_N")
        coarse = np.geomspace(0.003, 3.0, 13)
        if r is None or f is None or D.n_exp == 0:
            return coarse
        fd = np.zeros(D.n)
        for e in range(D.n_exp):
            a, b = D.bounds[e], D.bounds[e + 1]
            if b - a > 2:
                fd[a:b] = np.gradient(f[a:b], D.t[a:b])
        m = (r != 0) & np.isfinite(fd)
        den = float(np.sum(fd[m] ** 2))
        tau = -float(np.sum(r[m] * fd[m])) / den if den > 0 else np.nan
        if not np.isfinite(tau) or tau <= 0.003:
            return coarse
        return np.clip(tau, 0.003, 3.0) * np.geomspace(0.6, 2.5, 9)

    def transform(self, D, X, lag, ctx, out=None, eq14_first=False):
        wn = 2 * self.zeta / lag

        def ba(dt):
            # bilinear (Tustin) discretisation of wn^2/(s^2 + 2 zeta wn s + wn^2), in closed form; from rest (see ForceLag)
            return _bilinear_2nd_order(wn, self.zeta, 1.0 / dt)

        return filter_design(D, X, ba, out, eq14_first)

    def describe(self, values, errors, lag, se):
        fn = 2 * self.zeta / lag / (2 * np.pi)
        kind = f"damping ratio {self.zeta:.3g}, fitted" if self.kind.startswith("fitted") else f"{self.kind}, damping ratio {self.zeta:.3g}"
        return (
            f"The force reading passes a second-order filter ({kind}, natural frequency {fn:.3g} Hz, "
            f"lag {fmt_estimate(lag, se, 's')}): sensor or amplifier dynamics, not the spring or damper."
        )


#: id of a second-order force filter with a fitted damping ratio: ``force_filter_lag_z`` + 1000 zeta (4 digits)
_FILTER_ID = r"force_filter_lag_z(\d{4})"
ZETA_RANGE = (0.4, 1.6)  #: damping ratios a fitted sensor filter may take (underdamped amplifier .. nearly first order)


def filter_id(zeta: float) -> str:
    """Effect id of the second-order force filter with damping ratio ``zeta`` (rounded to 0.001).

    Parameters
    ----------
    zeta : float
        Damping ratio (dimensionless), within :data:`ZETA_RANGE`.

    Returns
    -------
    str
        ``force_filter_lag_z`` + 1000 zeta on 4 digits (``force_filter_lag_z0733`` for 0.733).

    Raises
    ------
    ValueError
        If ``zeta`` lies outside :data:`ZETA_RANGE`.
    """
    z = float(zeta)
    if not (ZETA_RANGE[0] - 1e-9 <= z <= ZETA_RANGE[1] + 1e-9):
        raise ValueError(f"filter damping ratio zeta = {z:g} outside {ZETA_RANGE}")
    return f"force_filter_lag_z{int(round(1000 * z)):04d}"


def fitted_filter(zeta: float) -> "ForceFilter":
    """The second-order force-reading filter with a fitted damping ratio (not registered: made from its id).

    Parameters
    ----------
    zeta : float
        Damping ratio (dimensionless), within :data:`ZETA_RANGE`; rounded to 0.001.

    Returns
    -------
    ForceFilter
        The filter effect, id :func:`filter_id` (``zeta``), its shape the lag 2 zeta/omega_n in s.
    """
    z = round(float(zeta), 3)
    return ForceFilter(filter_id(z), "second-order force-reading filter (fitted damping ratio)",
                       "The measured force is the unit's force through a second-order filter.",
                       f"f_meas = H(s) f,  H = wn^2/(s^2 + 2 zeta wn s + wn^2),  zeta = {z:.3f} (fitted),  lag = 2 zeta/wn", (),
                       Param("lag", "s", 0.0, np.inf, "filter lag 2 zeta/omega_n"), catalogue=False, zeta=z,
                       kind="fitted damping ratio")


register(ForceLag("force_lag", "force-reading lag", "The measured force is a lagged copy of the force the unit makes.",
                  "f_meas = lowpass_tau(f),  tau df_meas/dt = f - f_meas   (the whole model lagged)", (),
                  Param("tau", "s", 0.0, np.inf, "lag time constant"), catalogue=False))


# one second-order filter is a candidate (a Butterworth start); the damping ratio of the accepted one is fitted
# over ZETA_RANGE (selection.refine_filter_damping), not chosen from a list of standard types
register(ForceFilter("force_filter_lag", "second-order force-reading filter", "The measured force is the unit's force through a second-order filter.",
                     "f_meas = H(s) f,  H = wn^2/(s^2 + 2 zeta wn s + wn^2),  zeta fitted (starts at 0.707),  lag = 2 zeta/wn", (),
                     Param("lag", "s", 0.0, np.inf, "filter lag 2 zeta/omega_n"), catalogue=False, zeta=0.7071, kind="Butterworth"))


register_maker(_FILTER_ID, lambda m: fitted_filter(int(m.group(1)) / 1000.0))
