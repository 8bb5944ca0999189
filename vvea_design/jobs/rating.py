"""A design's charge rating: the highest chamber-2 charge a job may evaluate it at without being asked.

The rating is the lower of the requirements' ``max_charge_MPa`` the design was optimised for (a design file's
``spec``) and the design's own charge ``p2_MPa`` (the charge its walls are sized for, at their safety factor
and ``fixed.wall_sizing_n``). A job that takes a charge (``vvea spring --p2``, ``vvea study rest-to-rest
--p2-mpa``) refuses one above the rating unless the caller asks for it (``allow_over_rating=True``,
``--allow-over-rating``); then every output it writes says so (:data:`OVER_RATING_LABEL`). A charge at which
the walls yield (the rating times the smallest wall safety factor) stays refused either way.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path
from typing import Any

from .common import OptionError

__all__ = ["ChargeRating", "charge_rating", "check_charge", "OVER_RATING_LABEL"]

#: The first words of every output computed above the rating (figure titles, CSV comment, printed line).
OVER_RATING_LABEL = "OVER RATING"


@dataclass(frozen=True)
class ChargeRating:
    """A design's rating (MPa) and where it was read (``"d.json: spec.max_charge_MPa"``)."""

    rated_MPa: float  #: highest charge without ``allow_over_rating``, MPa
    source: str  #: which field of which input sets it

    def to_dict(self) -> dict[str, Any]:
        """JSON-ready.

        Returns
        -------
        dict
            ``rated_MPa`` (MPa) and ``source``.
        """
        return {"rated_MPa": self.rated_MPa, "source": self.source}


def _number(v: Any) -> float | None:
    return float(v) if isinstance(v, (int, float)) and not isinstance(v, bool) else None


def charge_rating(design: Any) -> ChargeRating | None:
    """The charge rating of a design, a design file or its parsed content.

    Parameters
    ----------
    design : Design, path-like, dict or GasSpring
        The design (its ``p2_MPa``), a design JSON or its content (``spec.max_charge_MPa`` and
        ``parameters.p2_MPa``); a bare gas spring has no walls and no rating.

    Returns
    -------
    ChargeRating or None
        The lower of the two charges (MPa) naming its field; None for a bare gas spring.
    """
    from ..spring.design import Design
    from ..spring.design_file import read_design_json

    if isinstance(design, Design):
        return ChargeRating(float(design.p2_MPa), "the design's p2_MPa (the charge its walls are sized for)")
    if isinstance(design, (str, Path)):
        data, name = read_design_json(design), f"{design}: "
    elif isinstance(design, dict):
        data, name = design, ""
    else:
        return None
    spec = data.get("spec") if isinstance(data.get("spec"), dict) else {}
    params = data.get("parameters") if isinstance(data.get("parameters"), dict) else {}
    found = [(v, f"{name}{what}") for v, what in (
        (_number(spec.get("max_charge_MPa")), "spec.max_charge_MPa (the requirement it was optimised for)"),
        (_number(params.get("p2_MPa")), "parameters.p2_MPa (the charge its walls are sized for)")) if v is not None]
    if not found:
        return None
    rated, source = min(found, key=lambda f: f[0])
    return ChargeRating(rated, source)


def check_charge(design: Any, p2_MPa: float, *, allow_over_rating: bool = False,
                 option: str = "p2_MPa") -> str:
    """Refuse a charge above the design's rating unless asked for; the label of a charge allowed over it.

    Parameters
    ----------
    design : Design, path-like, dict or GasSpring
        What :func:`charge_rating` reads.
    p2_MPa : float
        The charge asked for, MPa.
    allow_over_rating : bool
        Compute above the rating (the outputs then carry the returned label).
    option : str
        The job's keyword the error names (the command line renames it: ``--p2``).

    Returns
    -------
    str
        ``""`` at or below the rating; else the label every output must carry
        (``"OVER RATING: p2 = 5 MPa above ..."``).

    Raises
    ------
    OptionError
        ``p2_MPa`` above the rating without ``allow_over_rating``.
    """
    rating = charge_rating(design)
    if rating is None or p2_MPa <= rating.rated_MPa * (1 + 1e-9):
        return ""
    what = f"the design's rating {rating.rated_MPa:g} MPa ({rating.source})"
    if not allow_over_rating:
        raise OptionError(option, f"= {p2_MPa:g} MPa is above {what}: a unit charged above its rating is not the "
                          "unit that was designed and built; charge at most to the rating, optimise a design for "
                          "the higher charge (max_charge_MPa), or ask for it explicitly (allow_over_rating=True, "
                          "--allow-over-rating) and every output is labelled", "{option} {reason}")
    return f"{OVER_RATING_LABEL}: p2 = {p2_MPa:g} MPa above {what}"
