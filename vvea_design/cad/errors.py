"""The CAD's error: a design or a CAD parameter that cannot be drawn (re-exported by
:mod:`vvea_design.cad.layout`, where the CAD's modules take it from)."""

from __future__ import annotations

from ..spring.design import DesignError

__all__ = ["CadError"]


class CadError(DesignError):
    """A design or a CAD parameter that cannot be drawn (names the field)."""
