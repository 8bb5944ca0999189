"""Numbers in messages: what a user reads, never ``np.float64(3.2)``.

f-strings with ``!r`` print numpy scalars as ``np.float64(…)`` (numpy >= 2)
and tuples/lists of them likewise. Every error or notice that shows a value
the user gave or a number the code computed formats it with :func:`show`.
A constraint margin (or any number whose exact value is zero at the optimum)
is shown with :func:`show_margin`: round-off below the optimiser's tolerance
reads 0, not ``-4.3e-16`` or ``-0.0000``.
"""

from __future__ import annotations

import math
import numbers
from typing import Any

__all__ = ["show", "show_margin", "MARGIN_TOL"]

#: Feasibility tolerance of the optimiser: a constraint margin >= -MARGIN_TOL counts as met, and a margin
#: (or another scaled number) smaller than this in size is zero up to round-off (dimensionless).
MARGIN_TOL = 1e-9
#: Longest list :func:`show` writes out whole (values).
MAX_ITEMS = 12
#: Longest text :func:`show` writes out whole (characters).
MAX_CHARS = 200


def show(value: Any) -> str:
    """A value as a user should read it in a message.

    Parameters
    ----------
    value : Any
        A number (Python or numpy), string, list/tuple, numpy array, ...

    Returns
    -------
    str
        Real numbers with up to 6 significant digits (``inf``/``nan`` as
        such), integers whole, strings quoted, lists/tuples and numpy arrays
        element by element; anything else as ``repr``. A message stays a few lines: a list of more than
        :data:`MAX_ITEMS` values shows its first and last ones and its length, a string or ``repr`` of more
        than :data:`MAX_CHARS` characters its start and its length.

    >>> import numpy as np
    >>> show(np.float64(3.25)), show((np.float32(1), 2)), show("wood"), show(None)
    ('3.25', '[1, 2]', "'wood'", 'None')
    """
    if isinstance(value, bool) or value is None:
        return repr(value)
    if isinstance(value, numbers.Integral):
        return str(int(value))
    if isinstance(value, numbers.Real):
        v = float(value)
        return f"{v:.6g}" if math.isfinite(v) else str(v)
    if isinstance(value, (list, tuple)):
        if len(value) > MAX_ITEMS:
            return ("[" + ", ".join(show(v) for v in value[:5]) + ", ..., " + ", ".join(show(v) for v in value[-2:])
                    + f"] ({len(value)} values)")
        return "[" + ", ".join(show(v) for v in value) + "]"
    if hasattr(value, "tolist") and hasattr(value, "dtype"):  # numpy array / scalar of another kind
        return show(value.tolist())
    return _clip(repr(value))


def _clip(text: str) -> str:
    """``text``, or its first characters and its length when it is longer than :data:`MAX_CHARS`."""
    return text if len(text) <= MAX_CHARS else f"{text[:80]}... ({len(text)} characters)"


def show_margin(value: Any, spec: str = ".4g", tol: float = MARGIN_TOL) -> str:
    """A constraint margin (or an error that is zero at the optimum) as a user should read it.

    Parameters
    ----------
    value : Any
        The number (Python or numpy real, dimensionless or in the unit the caller states).
    spec : str
        Format spec of a number that is not zero, e.g. ``".4g"`` or ``"+.4f"``.
    tol : float
        Size below which the number is round-off of zero, in the unit of ``value`` (default
        :data:`MARGIN_TOL`, the optimiser's feasibility tolerance on the scaled margins).

    Returns
    -------
    str
        ``"0"`` when ``|value| < tol``, ``"nan"``/``"inf"`` as such, else ``format(value, spec)`` (a real
        margin keeps its sign, however small).

    >>> show_margin(-4.29e-16), show_margin(0.05102), show_margin(-2e-16, "+.4f"), show_margin(0.123456, "+.4f")
    ('0', '0.05102', '0', '+0.1235')
    """
    v = float(value)
    if not math.isfinite(v):
        return str(v)
    if abs(v) < tol:
        return "0"
    return format(v, spec)
