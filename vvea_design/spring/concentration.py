"""Stress-concentration factors the closed-form sizing applies per pressure-bearing piece, read from
``vvea_design/spring/data/stress_concentration.json`` (written by the FE study; the spring wing never imports the
FE room).

Format (``format = "vvea-stress-concentration"``, ``format_version = 1``)::

    {"format": "vvea-stress-concentration", "format_version": 1, "source": "<the study that wrote it>",
     "factors": {"<piece>": {"<feature>": K, ...}, ...}}

``<piece>`` is one of :data:`~vvea_design.spring.buildability.PIECE_PARTS`' keys (``outer_tube``,
``inner_tube``, ``top_cap``, ``base``, ``bulkhead``, ``collar``, ``piston_floor``); ``K >= 1`` is the FE peak over
the closed-form stress at a feature (a thread root, a groove, a step). The sizing takes each piece's largest
factor: its allowable stress is divided by it, its reported stress multiplied. A missing file, piece or feature
counts as 1.0 (the closed form as it is).
"""

from __future__ import annotations

import json
import math
from functools import lru_cache
from importlib import resources

__all__ = ["concentration_factor", "concentration_factors", "FORMAT"]

FORMAT = "vvea-stress-concentration"


@lru_cache(maxsize=None)
def concentration_factors() -> dict[str, float]:
    """Each piece's largest stress-concentration factor from the shipped file.

    Returns
    -------
    dict of str to float
        Piece -> factor (>= 1, dimensionless); empty when no file is shipped.

    Raises
    ------
    ValueError
        If the file is not a stress-concentration file of a known version, or a factor is below 1 or not finite.
    """
    res = resources.files("vvea_design.spring").joinpath("data", "stress_concentration.json")
    if not res.is_file():
        return {}
    data = json.loads(res.read_text(encoding="utf-8"))
    if data.get("format") != FORMAT or data.get("format_version") != 1:
        raise ValueError(f"spring/data/stress_concentration.json: expected format {FORMAT!r} version 1")
    out = {}
    for piece, feats in data.get("factors", {}).items():
        vals = [float(v) for v in feats.values()]
        if any(not math.isfinite(v) or v < 1.0 for v in vals):
            raise ValueError(f"spring/data/stress_concentration.json: factors of {piece!r} must be finite and >= 1")
        out[piece] = max(vals, default=1.0)
    return out


def concentration_factor(piece: str) -> float:
    """The largest stress-concentration factor of a piece (1.0 when none is shipped).

    Parameters
    ----------
    piece : str
        A pressure-bearing piece (``outer_tube``, ``top_cap`` ...).

    Returns
    -------
    float
        The factor, >= 1, dimensionless.
    """
    return concentration_factors().get(piece, 1.0)
