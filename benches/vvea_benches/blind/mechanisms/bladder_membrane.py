"""The bladder's own elasticity: a small nonlinear force of the silicone membrane, with a loss loop.

Physics
-------
The silicone bladder takes up the oil the piston displaces; stretching it costs a pressure of its
own, ``Δp_b`` (paper Fig. 7: from -0.03 MPa compressed to +0.03 MPa expanded over the stroke),
which adds to the oil pressure on the working piston: ``f += A2 Δp_b``. The membrane stiffens at
large strain (``s(u) = a u + (1 - a) u³`` with ``u`` the stroke position about the bladder's
relaxed point) and, being an elastomer, loses energy: the loading and unloading branches differ by
a loss ``±η`` that builds up over a few millimetres after each reversal (a rate-independent loop,
integrated along the path: ``dh/dx = (η sign(ẋ) - h)/x_h``). The force does not depend on the
charge: the same few tens of newtons at 1 MPa as at 4 MPa.

Ranges
------
- ``p_b_MPa`` 0.015–0.04 MPa: the paper's FE result (±0.03 MPa) with a spread for the cast wall.
- ``x_n_mm`` 15–25 mm: the bladder is cast near its mid-stroke shape.
- ``a`` 0.4–0.9: share of the linear part of the pressure–volume curve.
- ``eta`` 0.1–0.3: silicone loss (tan δ ≈ 0.1–0.3) as a share of ``p_b``.
- ``x_h_mm`` 1–4 mm: travel after a reversal over which the loop closes.
"""

from __future__ import annotations

import numpy as np

from ..spec import MechanismSpec, Range

HALF_STROKE_MM = 20.0


def loss_state(x, v, eta, x_h):
    """Path-integrated loss state ``h`` (dimensionless), starting on the unloading branch.

    Parameters
    ----------
    x, v : numpy.ndarray
        Piston position (mm) and velocity (mm/s) per sample.
    eta : float
        Loss share, dimensionless.
    x_h : float
        Travel over which ``h`` settles after a reversal, mm.

    Returns
    -------
    numpy.ndarray
        ``h`` per sample, in [-eta, eta].
    """
    h = np.empty_like(x)
    h[0] = -eta
    for k in range(1, len(x)):
        dx = x[k] - x[k - 1]
        s = np.sign(dx) if dx != 0 else np.sign(v[k])
        h[k] = eta * s + (h[k - 1] - eta * s) * np.exp(-abs(dx) / x_h)
    return h


def apply(params, ctx, mods) -> None:
    """Add the membrane force to every experiment.

    Parameters
    ----------
    params : dict
        ``p_b_MPa``, ``x_n_mm``, ``a``, ``eta``, ``x_h_mm``.
    ctx : CampaignContext
        The campaign.
    mods : list of ExperimentMods
        Edited in place.
    """
    A2 = ctx.base.A2_mm2

    def term(s):
        u = (s.x - params["x_n_mm"]) / HALF_STROKE_MM
        shape = params["a"] * u + (1.0 - params["a"]) * u**3
        return A2 * params["p_b_MPa"] * (shape + loss_state(s.x, s.v, params["eta"], params["x_h_mm"]))

    for m in mods:
        m.force_terms.append(term)


SPEC = MechanismSpec(
    name="bladder_membrane",
    domain="structural",
    description="the silicone bladder's own elastic pressure adds a small nonlinear force, the same at "
                "every charge, with a loss loop that closes a few mm after each reversal",
    states=("position", "direction", "since_reversal"),
    ranges={
        "p_b_MPa": Range(0.015, 0.04, "MPa", "paper Fig. 7: ±0.03 MPa over the stroke"),
        "x_n_mm": Range(15.0, 25.0, "mm", "bladder cast near its mid-stroke shape"),
        "a": Range(0.4, 0.9, "1", "share of the linear part of the membrane's p-V curve"),
        "eta": Range(0.1, 0.3, "1", "silicone loss factor tan δ"),
        "x_h_mm": Range(1.0, 4.0, "mm", "travel over which the loss loop closes"),
    },
    apply=apply,
)
