"""Discovered family: drifts over campaign time (force offset and friction).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .base import FREE, Effect, Param, fmt_estimate, register

__all__: list[str] = []  # its effects are reached through the registry

#: Place of this module's effects among the candidates (see :mod:`vvea_design.identification.effects`).
RANK = 160


@dataclass(frozen=True)
class CampaignTrend(Effect):
    def columns(self, D, _, ctx):
        th = D.ctime / 3600.0
        return np.column_stack([th, D.s * th])

    def describe(self, values, errors, _, __):
        return (
            f"A drift over the campaign: force offset {fmt_estimate(values['d0'], errors.get('d0'), 'N/h')} and friction "
            f"{fmt_estimate(values['d1'], errors.get('d1'), 'N/h')}: sensor zero drift, warming up or seal wear."
        )


register(CampaignTrend("campaign_trend", "drift over the campaign", "Offset and friction drift over campaign time.",
                       "f += d0 t_c + d1 t_c sign(xdot)   (t_c in h)",
                       (Param("d0", "N/h", *FREE, "offset drift"), Param("d1", "N/h", *FREE, "friction drift")), catalogue=False))
