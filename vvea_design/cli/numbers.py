"""Numbers on the command line: checked against the toolkit's ranges before any work, the option named.

The ranges are :data:`vvea_design.plausibility.LIMITS`, the ones the library's functions check too, so
``vvea map --n 100000`` and ``linearity_map(..., n=100000)`` refuse the same value with the same reason; the
command line only names its option (``--n``) and exits 2 before anything is computed or allocated.
"""

from __future__ import annotations

from ..plausibility import LIMITS, PlausibilityError
from .common import fail

__all__ = ["check_number", "check_seed"]


def check_number(key: str, value, option: str, hint: str = ""):
    """Exit 2 naming ``option`` unless ``value`` lies in ``LIMITS[key]``; return it.

    Parameters
    ----------
    key : str
        A key of :data:`vvea_design.plausibility.LIMITS`.
    value : Any
        The option's value (None: not given, accepted).
    option : str
        The option as the user typed it (``"--n"``).
    hint : str
        A likely cause added to the message.

    Returns
    -------
    Any
        ``value``.
    """
    if value is None:
        return value
    try:
        return LIMITS[key].check(value, option, PlausibilityError, hint)
    except PlausibilityError as exc:
        fail(str(exc))


def check_seed(seed: int) -> int:
    """Exit 2 unless ``--seed`` is a seed the search's random generator takes (0 ... 2**32 - 1).

    Parameters
    ----------
    seed : int
        The ``--seed`` value.

    Returns
    -------
    int
        ``seed``.
    """
    return check_number("seed", seed, "--seed")
