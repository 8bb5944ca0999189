"""Drawn tolerances of the dimensions that set a wall's thickness, and their least-material condition.

A wall is sized for its load at its **least-material condition** (LMC): the thinnest the drawing allows. The
diameters that bound a wall carry ISO 286-1 fits (a bore ``H``: 0 .. +IT, an outside ``h``: -IT .. 0, the IT
grade a field of :class:`~vvea_design.spring.parameters.FixedParameters`); the axial thicknesses of the end
caps, the bulkhead, the collar and the piston floor carry the ISO 2768-1 general tolerance of the class
``fixed.thickness_tolerance_class`` (``f`` fine by default), symmetric. The CAD draws these same tolerances
(:func:`drawn_tolerances` lists them per design), so the sizing and the drawing agree on the thinnest wall.

Every function takes numpy arrays (a population) or floats; lengths in mm.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .records import Record

__all__ = ["DrawnTolerance", "it_tolerance_mm", "general_tolerance_mm", "hole_max_mm", "shaft_min_mm",
           "thickness_allowance_mm", "IT_GRADES", "GENERAL_CLASSES"]

#: ISO 286-1:2010 Table 1, upper bound of each nominal-size step, mm (the steps are ``<= 3``, ``> 3 .. 6``, ...).
_STEP_UPPER_MM = np.array([3.0, 6.0, 10.0, 18.0, 30.0, 50.0, 80.0, 120.0, 180.0, 250.0])
#: ISO 286-1:2010 Table 1, standard tolerance grades IT6 .. IT11 per step, µm.
_IT_UM = {
    6: (6, 8, 9, 11, 13, 16, 19, 22, 25, 29),
    7: (10, 12, 15, 18, 21, 25, 30, 35, 40, 46),
    8: (14, 18, 22, 27, 33, 39, 46, 54, 63, 72),
    9: (25, 30, 36, 43, 52, 62, 74, 87, 100, 115),
    10: (40, 48, 58, 70, 84, 100, 120, 140, 160, 185),
    11: (60, 75, 90, 110, 130, 160, 190, 220, 250, 290),
}
#: The IT grades this module knows (ISO 286-1).
IT_GRADES = tuple(_IT_UM)

#: ISO 2768-1:1989 Table 1, linear dimensions: upper bound of each range, mm (``0.5 .. 3``, ``> 3 .. 6``, ...).
_GENERAL_UPPER_MM = np.array([3.0, 6.0, 30.0, 120.0, 400.0, 1000.0])
#: ISO 2768-1 permissible deviations (±) per tolerance class and range, mm.
_GENERAL_MM = {
    "f": (0.05, 0.05, 0.1, 0.15, 0.2, 0.3),
    "m": (0.1, 0.1, 0.2, 0.3, 0.5, 0.8),
    "c": (0.2, 0.3, 0.5, 0.8, 1.2, 2.0),
}
#: The ISO 2768-1 tolerance classes this module knows.
GENERAL_CLASSES = tuple(_GENERAL_MM)


def it_tolerance_mm(nominal_mm, grade: int):
    """The ISO 286-1 standard tolerance ``IT<grade>`` of a nominal size, mm.

    Parameters
    ----------
    nominal_mm : float or array
        Nominal size (a diameter), mm; 0 < size <= 250.
    grade : int
        IT grade, one of :data:`IT_GRADES` (6 .. 11).

    Returns
    -------
    float or ndarray
        The tolerance (the width of the band), mm.

    Raises
    ------
    ValueError
        For an unknown grade.
    """
    if grade not in _IT_UM:
        raise ValueError(f"IT grade must be one of {IT_GRADES}, got {grade!r}")
    d = np.asarray(nominal_mm, dtype=float)
    i = np.clip(np.searchsorted(_STEP_UPPER_MM, d, side="left"), 0, len(_STEP_UPPER_MM) - 1)
    out = np.asarray(_IT_UM[grade], dtype=float)[i] * 1e-3
    return out if out.ndim else float(out)


def general_tolerance_mm(nominal_mm, tolerance_class: str):
    """The ISO 2768-1 permissible deviation (±) of a linear dimension, mm.

    Parameters
    ----------
    nominal_mm : float or array
        Nominal length, mm (values below 0.5 mm take the first range).
    tolerance_class : str
        ``"f"``, ``"m"`` or ``"c"`` (:data:`GENERAL_CLASSES`).

    Returns
    -------
    float or ndarray
        The deviation each way, mm.

    Raises
    ------
    ValueError
        For an unknown class.
    """
    if tolerance_class not in _GENERAL_MM:
        raise ValueError(f"ISO 2768-1 class must be one of {GENERAL_CLASSES}, got {tolerance_class!r}")
    d = np.asarray(nominal_mm, dtype=float)
    i = np.clip(np.searchsorted(_GENERAL_UPPER_MM, d, side="left"), 0, len(_GENERAL_UPPER_MM) - 1)
    out = np.asarray(_GENERAL_MM[tolerance_class], dtype=float)[i]
    return out if out.ndim else float(out)


def hole_max_mm(nominal_mm, grade: int):
    """Largest size of a bore toleranced ``H<grade>`` (0 .. +IT): its least-material size, mm.

    Parameters
    ----------
    nominal_mm : float or array
        Nominal diameter, mm.
    grade : int
        IT grade (ISO 286-1).

    Returns
    -------
    float or ndarray
        ``nominal + IT``, mm.
    """
    return nominal_mm + it_tolerance_mm(nominal_mm, grade)


def shaft_min_mm(nominal_mm, grade: int):
    """Smallest size of an outside diameter toleranced ``h<grade>`` (-IT .. 0): its least-material size, mm.

    Parameters
    ----------
    nominal_mm : float or array
        Nominal diameter, mm.
    grade : int
        IT grade (ISO 286-1).

    Returns
    -------
    float or ndarray
        ``nominal - IT``, mm.
    """
    return nominal_mm - it_tolerance_mm(nominal_mm, grade)


def thickness_allowance_mm(required_mm, tolerance_class: str):
    """What a sized thickness adds to its required least-material value so that its lower limit still holds, mm.

    The nominal is ``required + a`` with ``a`` the ISO 2768-1 deviation of the range ``required + 0.5`` falls in:
    the deviations grow with the size and stay below 0.5 mm up to 400 mm, so the nominal's own deviation is at
    most ``a`` and ``nominal - deviation >= required``.

    Parameters
    ----------
    required_mm : float or array
        Thickness the load needs at the least-material condition, mm.
    tolerance_class : str
        ISO 2768-1 class (``"f"``, ``"m"``, ``"c"``).

    Returns
    -------
    float or ndarray
        The allowance ``a``, mm.
    """
    return general_tolerance_mm(np.asarray(required_mm, dtype=float) + 0.5, tolerance_class)


@dataclass(frozen=True)
class DrawnTolerance(Record):
    """One toleranced dimension of a sized wall, as the drawing carries it (mm)."""

    feature: str  #: what is dimensioned (``outer_tube_bore``, ``top_cap_thickness`` ...)
    part: str  #: the part it is on (``housing_outer_tube`` ..., the CAD's part names)
    nominal_mm: float  #: nominal size, mm
    designation: str  #: as written on the drawing (``Ø56.32 H8``, ``8.00 ±0.10``)
    upper_deviation_mm: float  #: upper deviation from nominal, mm
    lower_deviation_mm: float  #: lower deviation from nominal (negative or 0), mm
    least_material_mm: float  #: the size at the least-material condition (what the sizing took), mm
    standard: str  #: ISO 286-1 (fit) or ISO 2768-1 (general tolerance class)

    @classmethod
    def bore(cls, feature: str, part: str, nominal_mm: float, grade: int) -> "DrawnTolerance":
        """A bore toleranced ``H<grade>``.

        Parameters
        ----------
        feature, part : str
            What is dimensioned and on which part.
        nominal_mm : float
            Nominal diameter, mm.
        grade : int
            IT grade (ISO 286-1).

        Returns
        -------
        DrawnTolerance
            0 .. +IT; least material at the largest bore, mm.
        """
        it = it_tolerance_mm(nominal_mm, grade)
        return cls(feature, part, float(nominal_mm), f"Ø{nominal_mm:.3f} H{grade}", it, 0.0, nominal_mm + it,
                   "ISO 286-1")

    @classmethod
    def outside(cls, feature: str, part: str, nominal_mm: float, grade: int) -> "DrawnTolerance":
        """An outside diameter toleranced ``h<grade>``.

        Parameters
        ----------
        feature, part : str
            What is dimensioned and on which part.
        nominal_mm : float
            Nominal diameter, mm.
        grade : int
            IT grade (ISO 286-1).

        Returns
        -------
        DrawnTolerance
            -IT .. 0; least material at the smallest diameter, mm.
        """
        it = it_tolerance_mm(nominal_mm, grade)
        return cls(feature, part, float(nominal_mm), f"Ø{nominal_mm:.3f} h{grade}", 0.0, -it, nominal_mm - it,
                   "ISO 286-1")

    @classmethod
    def thickness(cls, feature: str, part: str, nominal_mm: float, tolerance_class: str) -> "DrawnTolerance":
        """An axial thickness with the ISO 2768-1 general tolerance of ``tolerance_class``.

        Parameters
        ----------
        feature, part : str
            What is dimensioned and on which part.
        nominal_mm : float
            Nominal thickness, mm.
        tolerance_class : str
            ISO 2768-1 class (``"f"``, ``"m"``, ``"c"``).

        Returns
        -------
        DrawnTolerance
            ± the class's deviation; least material at the thinnest, mm.
        """
        a = general_tolerance_mm(nominal_mm, tolerance_class)
        return cls(feature, part, float(nominal_mm), f"{nominal_mm:.2f} ±{a:g}", a, -a, nominal_mm - a,
                   f"ISO 2768-1 {tolerance_class}")
