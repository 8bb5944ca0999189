"""Numbers in messages: what a user reads, never ``np.float64(3.2)``.

f-strings with ``!r`` print numpy scalars as ``np.float64(…)`` (numpy >= 2)
and tuples/lists of them likewise. Every error or notice that shows a value
the user gave or a number the code computed formats it with :func:`show`.
"""

from __future__ import annotations

import math
import numbers
from typing import Any

__all__ = ["show"]


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
        element by element; anything else as ``repr``.

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
        return "[" + ", ".join(show(v) for v in value) + "]"
    if hasattr(value, "tolist") and hasattr(value, "dtype"):  # numpy array / scalar of another kind
        return show(value.tolist())
    return repr(value)
