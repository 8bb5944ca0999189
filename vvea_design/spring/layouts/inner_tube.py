"""``inner_tube``: the paper's layout. Chamber 1 fills the inner tube from the piston to the top cap, so V1
sets the housing length (``docs/layout.md``). It adds nothing to the shared unit: the base class's hooks."""

from __future__ import annotations

from .base import LayoutVariant, register

__all__ = ["InnerTube"]


@register
class InnerTube(LayoutVariant):
    """Chamber 1 is the bore column above the piston; chamber 2 the annulus around the bladder."""

    name = "inner_tube"
    summary = "chamber 1 fills the inner tube from the piston to the top cap; V1 sets the housing length"
    order = 0
