"""Linearity regression helpers for designers' own test suites.

Example (in your project's tests)::

    from vvea_design.testing import assert_linearity

    def test_my_unit_stays_linear():
        assert_linearity("designs/my_unit.json", max_linearity=0.015)

The design file is rebuilt from its decision variables and checked like every
command reads it (:func:`vvea_design.spring.design_file.load_design`): a stored
area, pressure, wall or figure that disagrees with the design is an error
(:class:`~vvea_design.spring.design_file.DesignFileError`), never a judgement
of a stale copy; its spring is then evaluated with paper eq. 5.
"""

from __future__ import annotations

from pathlib import Path

from .plausibility import LIMITS
from .spring.design_file import spring_from_json
from .spring.gas_spring import GasSpring

__all__ = ["LinearityRegression", "check_linearity", "assert_linearity"]


class LinearityRegression(AssertionError):
    """A design's linearity error exceeds the agreed limit."""


def check_linearity(design: str | Path | dict | GasSpring, max_linearity: float, num: int | None = None) -> float:
    """Return the design's linearity error; raise :class:`LinearityRegression` above ``max_linearity``.

    Parameters
    ----------
    design : str, Path, dict or GasSpring
        A design JSON path, its parsed content (rebuilt and checked as
        :func:`~vvea_design.spring.design_file.load_design_dict` does), or a
        :class:`~vvea_design.spring.gas_spring.GasSpring` (paper eq. 5).
    max_linearity : float
        Largest acceptable linearity error, a fraction (0.015 = 1.5 %).
    num : int or None
        ``None`` (default): the exact metric over the continuous travel (what
        the optimiser and the design file report); an int: on that many samples.

    Returns
    -------
    float
        The linearity error, a fraction of the force span.

    Raises
    ------
    LinearityRegression
        The error exceeds ``max_linearity``.
    vvea_design.spring.design_file.DesignFileError
        The design file is unreadable, incomplete or disagrees with itself.
    vvea_design.plausibility.PlausibilityError
        ``max_linearity`` is not a fraction in (0, 1].
    """
    LIMITS["linearity_fraction"].check(max_linearity, "max_linearity")
    gs = design if isinstance(design, GasSpring) else spring_from_json(design)
    lin = gs.linearity_error(num)
    if lin > max_linearity:
        span = float(gs.force_N(gs.travel_mm) - gs.force_N(0.0))
        raise LinearityRegression(
            f"{design if not isinstance(design, dict) else 'design'}: linearity error {100 * lin:.3f} % exceeds the "
            f"limit {100 * max_linearity:.3f} % (force span {span:.1f} N over "
            f"0–{gs.travel_mm:g} mm)"
        )
    return lin


def assert_linearity(design: str | Path | dict | GasSpring, max_linearity: float) -> None:
    """pytest-friendly assertion: fails with a readable message when the design regresses.

    Parameters
    ----------
    design : str, Path, dict or GasSpring
        As for :func:`check_linearity`.
    max_linearity : float
        Largest acceptable linearity error, a fraction (0.015 = 1.5 %).
    """
    check_linearity(design, max_linearity)
