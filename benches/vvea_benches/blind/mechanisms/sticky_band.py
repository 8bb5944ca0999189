"""A sticky band of the bore: the seal rubs harder over one stretch of the stroke.

Physics
-------
A score, a dry patch (the oil film wiped off) or a slightly undersized stretch of the working
piston's bore raises the seal's friction where the seal lip passes over it. The extra friction
``ΔC`` acts against the motion in both directions, only while the seal is inside the band
``[x_a, x_a + w]``, with edges as wide as the seal's contact band (≈ 0.5 mm). It does not depend
on the charge, the valve or the speed.

Ranges
------
- ``x_start_mm`` 5–28 mm and ``width_mm`` 3–10 mm: a local defect, away from the stroke ends.
- ``dC_N`` 30–90 N: 25–70 % of the Coulomb level; a dry stretch roughly doubles a lubricated
  elastomer seal's friction, a score raises it less.
"""

from __future__ import annotations

import numpy as np

from ..spec import MechanismSpec, Range

EDGE_MM = 0.5


def band(x, x_start, width, edge=EDGE_MM):
    """Smooth indicator of the band, dimensionless, in [0, 1].

    Parameters
    ----------
    x : array_like
        Piston position, mm.
    x_start, width : float
        Start and width of the band, mm.
    edge : float
        Width of the smooth edges, mm.

    Returns
    -------
    numpy.ndarray
        About 1 inside the band, 0 outside.
    """
    x = np.asarray(x, dtype=float)
    return 1.0 / (1.0 + np.exp(-(x - x_start) / (edge / 4))) / (1.0 + np.exp((x - x_start - width) / (edge / 4)))


def apply(params, ctx, mods) -> None:
    """Add the band's friction to every experiment.

    Parameters
    ----------
    params : dict
        ``x_start_mm``, ``width_mm`` (mm) and ``dC_N`` (N).
    ctx : CampaignContext
        The campaign.
    mods : list of ExperimentMods
        Edited in place.
    """
    def term(s):
        return params["dC_N"] * band(s.x, params["x_start_mm"], params["width_mm"])

    for m in mods:
        m.friction_terms.append(term)


SPEC = MechanismSpec(
    name="sticky_band",
    domain="friction",
    description="the seal rubs harder over one band of the stroke (a score or dry patch of the bore), "
                "in both directions",
    states=("position", "direction"),
    ranges={
        "x_start_mm": Range(5.0, 28.0, "mm", "a local defect away from the stroke ends"),
        "width_mm": Range(3.0, 10.0, "mm", "a local defect away from the stroke ends"),
        "dC_N": Range(30.0, 90.0, "N", "a dry stretch up to doubles a lubricated seal's friction"),
    },
    apply=apply,
)
