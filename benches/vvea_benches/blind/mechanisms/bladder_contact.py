"""The bladder touches the outer tube near full extension and rubs on it.

Physics
-------
As x grows the displaced oil inflates the bladder. Near the end of the stroke its bulge reaches
the outer tube's wall: the wall stops the bladder's radial growth, so the oil pressure — and the
tension — rises by a contact force that grows like a Hertz contact, ``k_c (x - x_c)^1.5``, in
both directions of motion; the silicone rubbing on the wall adds friction ``μ_c`` times that
force against the motion. Below ``x_c`` nothing happens; the charge does not matter.

Ranges
------
- ``x_c_mm`` 31–37 mm: the bladder is designed to clear the wall; cast and assembly tolerances let
  it touch within the last 3–9 mm.
- ``F_end_N`` 30–120 N: contact force at full stroke (sets ``k_c``): the membrane's small
  pressure (≈ 0.03 MPa) over the touching area.
- ``mu_c`` 0.2–0.6: silicone on an anodised wall, partly wetted by oil.
"""

from __future__ import annotations

import numpy as np

from ..spec import MechanismSpec, Range
from ..unit import STROKE_MM


def contact_force_N(x, x_c, F_end):
    """Elastic contact force, N (0 below ``x_c``).

    Parameters
    ----------
    x : array_like
        Piston position, mm.
    x_c : float
        Position of first contact, mm.
    F_end : float
        Contact force at full stroke, N.

    Returns
    -------
    numpy.ndarray
        ``k_c (x - x_c)^1.5`` with ``k_c = F_end / (stroke - x_c)^1.5``.
    """
    d = np.maximum(np.asarray(x, dtype=float) - x_c, 0.0)
    return F_end * (d / (STROKE_MM - x_c)) ** 1.5


def apply(params, ctx, mods) -> None:
    """Add the contact force and its rubbing friction to every experiment.

    Parameters
    ----------
    params : dict
        ``x_c_mm`` (mm), ``F_end_N`` (N), ``mu_c`` (dimensionless).
    ctx : CampaignContext
        The campaign.
    mods : list of ExperimentMods
        Edited in place.
    """
    def elastic(s):
        return contact_force_N(s.x, params["x_c_mm"], params["F_end_N"])

    def rubbing(s):
        return params["mu_c"] * contact_force_N(s.x, params["x_c_mm"], params["F_end_N"])

    for m in mods:
        m.force_terms.append(elastic)
        m.friction_terms.append(rubbing)


SPEC = MechanismSpec(
    name="bladder_contact",
    domain="structural",
    description="near full extension the bladder touches the outer tube: an added stiffening force and "
                "rubbing friction over the last few mm of the stroke",
    states=("position", "direction"),
    ranges={
        "x_c_mm": Range(31.0, 37.0, "mm", "cast and assembly tolerances of the bladder's clearance"),
        "F_end_N": Range(30.0, 120.0, "N", "membrane pressure over the touching area"),
        "mu_c": Range(0.2, 0.6, "1", "silicone on an anodised wall, partly wetted"),
    },
    apply=apply,
)
