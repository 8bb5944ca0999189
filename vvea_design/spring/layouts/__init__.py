"""The layout variants of the unit, one module each (``docs/layout.md`` draws them).

Every module of this package but :mod:`~vvea_design.spring.layouts.base` holds one layout: a subclass of
:class:`~vvea_design.spring.layouts.base.LayoutVariant` decorated with
:func:`~vvea_design.spring.layouts.base.register`. The package imports them all (:func:`discover`), so
adding a layout is adding a module here: its decision variables, walls, volumes, constraints and design-file
lines are its own, and the optimiser, the requirements, the design file and the schema list it.
"""

from __future__ import annotations

import importlib
import pkgutil

from ..parameters import DesignError
from .base import (COMMON_BOUNDS, COMMON_WALLS, DECISION_VARIABLES, LAYOUTS, BudgetShare, LayoutStack,
                   LayoutVariable, LayoutVariant, register)

__all__ = ["LAYOUTS", "LayoutVariant", "LayoutVariable", "LayoutStack", "BudgetShare", "register", "get_layout",
           "discover", "layout_variables", "all_walls", "DECISION_VARIABLES", "COMMON_WALLS", "COMMON_BOUNDS"]


def discover() -> dict[str, LayoutVariant]:
    """Import every layout module of this package (each registers itself).

    Modules already imported are not imported again; a module added to the package's path since the
    last call is.

    Returns
    -------
    dict of str to LayoutVariant
        :data:`LAYOUTS`: every registered layout by name, in their declared order.
    """
    for info in pkgutil.iter_modules(__path__):
        if info.name != "base" and not info.name.startswith("_"):
            importlib.import_module(f"{__name__}.{info.name}")
    return LAYOUTS


def get_layout(name) -> LayoutVariant:
    """The layout variant called ``name``.

    Parameters
    ----------
    name : str or LayoutVariant
        A key of :data:`LAYOUTS` (``"inner_tube"``, ``"bulkhead"``, ``"annulus_top"`` ...), or a layout
        itself (returned as it is).

    Returns
    -------
    LayoutVariant
        Its name, summary, decision variables, walls and hooks.

    Raises
    ------
    DesignError
        For an unknown name (the message lists the known ones).
    """
    if isinstance(name, LayoutVariant):
        return name
    try:
        return LAYOUTS[name]
    except (KeyError, TypeError):
        raise DesignError(f"unknown layout {name!r}; known: {', '.join(LAYOUTS)}") from None


def layout_variables() -> dict[str, tuple[str, LayoutVariable]]:
    """Every layout's own decision variables, in the order of :data:`LAYOUTS`.

    Returns
    -------
    dict of str to tuple
        Variable name (unit in the name, mm³) -> (name of the layout that owns it, its :class:`LayoutVariable`).
    """
    return {v.name: (lay.name, v) for lay in LAYOUTS.values() for v in lay.own_variables}


def all_walls() -> tuple[str, ...]:
    """Every pressure wall any layout sizes: the shared ones, each layout's own, the piston pocket's floor.

    Returns
    -------
    tuple of str
        Wall names, in the order :meth:`~vvea_design.spring.design.Design.walls_mm` lists them.
    """
    return COMMON_WALLS + tuple(w for lay in LAYOUTS.values() for w in lay.own_walls) + ("piston_floor",)


discover()
