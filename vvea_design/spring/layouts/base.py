"""What every layout variant shares, and the registry the layout modules add themselves to.

A layout is a subclass of :class:`LayoutVariant` in its own module of :mod:`vvea_design.spring.layouts`,
decorated with :func:`register`. It owns what differs from the plain concentric unit: its own decision
variables (:class:`LayoutVariable`, with their search bounds), its own pressure walls (sizing, stress,
mass), the volumes and lengths it adds to or takes from the axial stack (:class:`LayoutStack`), its own
constraints, its lines of the design file's ``geometry`` and its items of the volume budget. The base
class's hooks are those of a layout that adds nothing (``inner_tube``).

Units: lengths mm, areas mm², volumes mm³, pressures and stresses MPa, masses g.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any, ClassVar

from ..geometry import Array, Pressures, Section
from ..parameters import DesignError, FixedParameters

# The hooks' "Stack", "Derived" and "Design" are :class:`~vvea_design.spring.derive.Stack`,
# :class:`~vvea_design.spring.derive.Derived` and :class:`~vvea_design.spring.design.Design`, named, not
# imported: they read their layout.

__all__ = ["LayoutVariant", "LayoutVariable", "LayoutStack", "BudgetShare", "register", "LAYOUTS",
           "DECISION_VARIABLES", "COMMON_WALLS", "COMMON_BOUNDS"]

#: The decision variables every layout has, in order, with their units in the name.
DECISION_VARIABLES = ("piston_diameter_mm", "outer_diameter_mm", "V1_mm3", "V2_mm3")

#: Default search range of each shared decision variable (mm, mm³).
COMMON_BOUNDS: dict[str, tuple[float, float]] = {
    "piston_diameter_mm": (12.0, 50.0),
    "outer_diameter_mm": (25.0, 59.5),
    "V1_mm3": (5.0e3, 3.0e5),
    "V2_mm3": (5.0e3, 3.0e5),
}

#: The pressure walls every layout has (sized by :func:`~vvea_design.spring.derive.derive`).
COMMON_WALLS = ("outer_tube", "inner_tube", "top_cap", "base")

#: The registered layouts by name, in their declared ``order`` (filled by :func:`register`; the package
#: imports every module of :mod:`vvea_design.spring.layouts`).
LAYOUTS: dict[str, "LayoutVariant"] = {}


@dataclass(frozen=True)
class LayoutVariable:
    """A decision variable a layout adds (a gas volume placed somewhere only that layout has)."""

    name: str  #: with its unit (``V2_top_mm3``); also the :class:`~vvea_design.spring.design.Design` field
    bounds: tuple[float, float]  #: default search range, in the variable's unit; the low end may be 0
    what: str  #: what it is, for messages ("chamber-2 gas above chamber 1")


@dataclass(frozen=True)
class LayoutStack:
    """What a layout adds to or takes from the axial stack and the gas accounting (arrays broadcast).

    The sequences are applied in order (each a subtraction or an addition of its own), so the sums are
    those of the formulas in ``docs/layout.md`` term by term.
    """

    chamber1_elsewhere_mm3: tuple = ()  #: chamber-1 gas outside the bore column above the piston, mm³
    inner_length_extra_mm: tuple = ()  #: inner-tube length above chamber 1 besides the column (a bulkhead), mm
    bladder_length_taken_mm: tuple = ()  #: inner length the bladder cannot use beyond its two clamps, mm
    chamber2_elsewhere_mm3: Array = 0.0  #: chamber-2 gas not around the bladder, mm³
    inner_tube_cut_mm3: Array = 0.0  #: inner-tube material the layout cuts away (and fills with gas), mm³
    buildable: Array = True  #: the layout's own quantities can be drawn (bool)
    quantities: dict[str, Array] = field(default_factory=dict)  #: the layout's own named quantities (unit in the name)


@dataclass(frozen=True)
class BudgetShare:
    """A layout's items of the volume budget at x = 0, mm³ (:meth:`~vvea_design.spring.design.Design.volume_budget_mm3`).

    ``walls`` are solids; ``chamber_1`` and ``chamber_2`` the gas of that chamber the layout holds outside the
    bore column and the annulus (subtracted from those items, so the budget still adds up).
    """

    walls: dict[str, float] = field(default_factory=dict)
    chamber_1: dict[str, float] = field(default_factory=dict)
    chamber_2: dict[str, float] = field(default_factory=dict)


def register(cls: type["LayoutVariant"]) -> type["LayoutVariant"]:
    """Class decorator: add an instance of a layout class to :data:`LAYOUTS` under its ``name``.

    Parameters
    ----------
    cls : type
        A subclass of :class:`LayoutVariant` with ``name``, ``summary`` and ``order`` set.

    Returns
    -------
    type
        ``cls`` itself.

    Raises
    ------
    DesignError
        If ``cls`` is not a layout class, has no name, or another module's layout has the same name or
        claims a variable or wall of another layout.
    """
    if not (isinstance(cls, type) and issubclass(cls, LayoutVariant)) or not cls.name:
        raise DesignError(f"register: {cls!r} is not a named LayoutVariant subclass")
    old = LAYOUTS.get(cls.name)
    if old is not None and (type(old).__module__, type(old).__qualname__) != (cls.__module__, cls.__qualname__):
        raise DesignError(f"layout {cls.name!r} is registered twice: by {type(old).__module__} and {cls.__module__}")
    for other in LAYOUTS.values():
        if other.name == cls.name:
            continue
        clash = ({v.name for v in other.own_variables} & {v.name for v in cls.own_variables}) | \
            (set(other.own_walls) & set(cls.own_walls))
        if clash:
            raise DesignError(f"layout {cls.name!r} claims {sorted(clash)} of layout {other.name!r}")
    LAYOUTS[cls.name] = cls()
    ordered = sorted(LAYOUTS.values(), key=lambda lay: (lay.order, lay.name))
    LAYOUTS.clear()
    LAYOUTS.update((lay.name, lay) for lay in ordered)
    return cls


class LayoutVariant:
    """A named geometry of the unit: where each gas volume goes (``docs/layout.md`` draws each).

    Subclasses set the class attributes and override the hooks that differ; the base class is the plain
    concentric unit (``inner_tube``): chamber 1 is the bore column above the piston, chamber 2 the annulus
    around the bladder, four walls.
    """

    name: ClassVar[str] = ""
    summary: ClassVar[str] = ""
    order: ClassVar[int] = 100  #: place in :data:`LAYOUTS` (and so in every listing of the layouts)
    own_variables: ClassVar[tuple[LayoutVariable, ...]] = ()
    own_walls: ClassVar[tuple[str, ...]] = ()
    #: the layout's constraints besides the shared ones (:meth:`constraint_details` gives their values)
    own_constraints: ClassVar[tuple[str, ...]] = ()
    #: the layout's items of the volume budget (their keys; :meth:`budget` their values)
    budget_items: ClassVar[BudgetShare] = BudgetShare()
    #: data for the CAD and the drawings: a bulkhead closes chamber 1; the inner-tube space above it is chamber-2 gas
    has_bulkhead: ClassVar[bool] = False
    #: data for the CAD and the drawings: chamber-1 gas also fills the annulus above a collar (the top bladder clamp)
    has_top_annulus: ClassVar[bool] = False
    #: what else V1 must exceed (in the message of a design whose chamber-1 column is empty)
    chamber1_note: ClassVar[str] = ""
    #: what else V2 must exceed (in the message of a design whose bladder holds no gas)
    chamber2_note: ClassVar[str] = ""
    #: what else takes the inner length (in the message of a design whose bladder has no free length)
    bladder_note: ClassVar[str] = ""

    def __repr__(self) -> str:
        return f"<layout {self.name!r}>"

    @property
    def decision_variables(self) -> tuple[str, ...]:
        """The layout's decision variables in the optimiser's order (the shared four, then its own)."""
        return DECISION_VARIABLES + tuple(v.name for v in self.own_variables)

    @property
    def walls(self) -> tuple[str, ...]:
        """The pressure walls :func:`~vvea_design.spring.derive.derive` sizes in this layout."""
        return COMMON_WALLS + self.own_walls

    # ------------------------------------------------------------------ derivation hooks
    def size_walls(self, section: Section, pressures: Pressures, fixed: FixedParameters) -> dict[str, Array]:
        """The layout's own walls, sized for their pressure (never below their minimum).

        Parameters
        ----------
        section : Section
            The cross-section with the shared walls sized (radii and thicknesses in mm).
        pressures : Pressures
            Charges and peaks, MPa.
        fixed : FixedParameters
            Minimums, safety factor, materials.

        Returns
        -------
        dict of str to ndarray
            Wall name (one of :attr:`own_walls`) -> thickness, mm.
        """
        return {}

    def stack(self, section: Section, variables: dict[str, Array], fixed: FixedParameters) -> LayoutStack:
        """What the layout adds to the axial stack and the gas accounting.

        Parameters
        ----------
        section : Section
            The cross-section with every wall sized (mm, mm²).
        variables : dict of str to ndarray
            The decision variables by name (mm, mm³), the layout's own among them.
        fixed : FixedParameters
            Fill tube, slots, clamps (mm).

        Returns
        -------
        LayoutStack
            Volumes (mm³) and lengths (mm) added or taken, and the layout's own quantities.
        """
        return LayoutStack()

    def rooms(self, stack: "Stack", fixed: FixedParameters) -> dict[str, Array]:
        """The layout's own quantities that need the finished axial stack (room left for its features).

        Parameters
        ----------
        stack : Stack
            The axial stack (:class:`~vvea_design.spring.derive.Stack`: lengths mm, the layout's quantities).
        fixed : FixedParameters
            Feature sizes (mm).

        Returns
        -------
        dict of str to ndarray
            Quantity name (unit in the name) -> value; merged into ``derived.layout_quantities``.
        """
        return {}

    def wall_stresses(self, section: Section, pressures: Pressures, fixed: FixedParameters) -> dict[str, Array]:
        """Peak stresses of the layout's own walls as drawn (their material: the housing's).

        Parameters
        ----------
        section : Section
            The cross-section with every wall sized (mm).
        pressures : Pressures
            Charges and peaks, MPa.
        fixed : FixedParameters
            Materials and sizes.

        Returns
        -------
        dict of str to ndarray
            Wall name -> peak stress, MPa.
        """
        return {}

    def part_masses(self, section: Section, quantities: dict[str, Array], fixed: FixedParameters,
                    density_g_per_mm3: float) -> dict[str, Array]:
        """Masses of the layout's own parts (housing material).

        Parameters
        ----------
        section : Section
            The cross-section with every wall sized (mm).
        quantities : dict of str to ndarray
            The layout's own quantities (:attr:`LayoutStack.quantities`; mm, mm³).
        fixed : FixedParameters
            Sizes (mm).
        density_g_per_mm3 : float
            Density of the housing material, g/mm³.

        Returns
        -------
        dict of str to ndarray
            Part name -> mass, g.
        """
        return {}

    def constraint_details(self, derived: "Derived") -> dict[str, dict[str, Any]]:
        """Value, limit, unit and kind of each of :attr:`own_constraints` (arrays like ``derived``).

        Parameters
        ----------
        derived : Derived
            The derived quantities of one design or a population (mm, mm³, MPa).

        Returns
        -------
        dict of str to dict
            Constraint name -> ``value``, ``limit``, ``unit``, ``kind`` (``min`` / ``max``), optional ``scale``.
        """
        return {}

    # ------------------------------------------------------------------ design hooks
    def geometry_summary(self, design: "Design") -> dict[str, float]:
        """The layout's own lines of the design file's ``geometry``.

        Parameters
        ----------
        design : Design
            A design of this layout.

        Returns
        -------
        dict of str to float
            Quantity name (unit in the name: mm, mm³) -> value.
        """
        return {}

    def budget(self, design: "Design") -> BudgetShare:
        """The layout's items of the volume budget at x = 0 (keys of :attr:`budget_items`).

        Parameters
        ----------
        design : Design
            A design of this layout.

        Returns
        -------
        BudgetShare
            Its solids and the gas it holds outside the bore column and the annulus, mm³.
        """
        return BudgetShare()
