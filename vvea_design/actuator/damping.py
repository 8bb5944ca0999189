"""The damping range the design's actuator study uses, and where it comes from.

The built unit's own range (the spring wing's hydraulics, ``Design.damping_range_N_s_per_mm()``): ``D_min`` is
the throttle fully open (the parasitic damping of the flow path), ``D_max`` the throttle closed, capped by
the relief valve. Through the tendon pulley (section 3.4) a unit damping ``L`` (N s/mm) is the joint damping
``D = n_units r² L``. A design without that record (an :class:`~vvea_design.actuator.model.Actuator`, a bare
:class:`~vvea_design.spring.gas_spring.GasSpring`, or an explicit choice) uses the paper's Table 4 range
(VVEA: 12.1-200 N m s/rad), and the record says so.

The relief valve bounds the damper's *force*, not its damping: each unit's damping force stays below
``relief_force_N``, so the joint's damping torque ``|D (θ' - q')|`` below ``n_units r relief_force_N``.
The rest-to-rest model has linear damping only; :attr:`DampingRange.relief_torque_Nm` lets the study check
its optima against that cap.
"""

from __future__ import annotations

import math
from dataclasses import asdict, dataclass

from ..messages import show
from .model import PAPER_SETTINGS

__all__ = ["DampingRange", "TABLE4_SOURCE", "UNIT_SOURCE", "paper_table4_range", "unit_damping_range"]

#: Source label of the paper's Table 4 range.
TABLE4_SOURCE = "paper Table 4 (VVEA)"
#: Source label of the built unit's own range.
UNIT_SOURCE = "the unit's hydraulics (throttle open: parasitic D_min; closed: relief-capped D_max)"


@dataclass(frozen=True)
class DampingRange:
    """A joint damping range and its origin (SI at the joint, the unit's own values in N s/mm)."""

    D_min_Nms_per_rad: float  #: joint damping, throttle open
    D_max_Nms_per_rad: float  #: joint damping, throttle closed
    source: str  #: :data:`UNIT_SOURCE` or :data:`TABLE4_SOURCE` (or a caller's label)
    why: str  #: one sentence: why this range is the one used
    unit_D_min_N_s_per_mm: float | None = None  #: the unit's own D_min (None: not from the unit)
    unit_D_max_N_s_per_mm: float | None = None  #: the unit's own D_max (None: not from the unit)
    relief_torque_Nm: float | None = None  #: joint damping torque at which the relief valves open (None: unknown)

    def __post_init__(self) -> None:
        for name in ("D_min_Nms_per_rad", "D_max_Nms_per_rad"):
            v = getattr(self, name)
            if isinstance(v, bool) or not isinstance(v, (int, float)) or not math.isfinite(v) or v < 0:
                raise ValueError(f"DampingRange.{name} must be a finite number >= 0, got {show(v)}")
        if self.D_max_Nms_per_rad < self.D_min_Nms_per_rad:
            raise ValueError(f"DampingRange.D_max_Nms_per_rad ({self.D_max_Nms_per_rad:g}) must be >= D_min_Nms_per_rad "
                             f"({self.D_min_Nms_per_rad:g})")

    @property
    def from_unit(self) -> bool:
        """True when the range is the built unit's own (not the paper's)."""
        return self.unit_D_min_N_s_per_mm is not None

    def to_dict(self) -> dict:
        """Plain-JSON dictionary.

        Returns
        -------
        dict
            Field name to value (joint damping N m s/rad, unit damping N s/mm, torque N m, texts).
        """
        return asdict(self)


def paper_table4_range(why: str = "the design carries no hydraulic damping range") -> DampingRange:
    """The paper's Table 4 VVEA range, 12.1-200 N m s/rad.

    Parameters
    ----------
    why
        The reason it is used (said in reports).

    Returns
    -------
    DampingRange
        Table 4's range with ``source`` :data:`TABLE4_SOURCE`.
    """
    v = PAPER_SETTINGS["VVEA"]
    return DampingRange(v.D_min_Nms_per_rad, v.D_max_Nms_per_rad, TABLE4_SOURCE, why)


def unit_damping_range(design, *, pulley_radius_m: float, n_units: int = 2) -> DampingRange:
    """The built unit's damping range at the joint, or Table 4's when the design has none.

    Parameters
    ----------
    design
        A :class:`~vvea_design.spring.design.Design` (its ``damping_range_N_s_per_mm()`` is used) or
        anything else (then Table 4, with the reason).
    pulley_radius_m
        Tendon-pulley radius r, m.
    n_units
        Pre-loaded units on the pulley (count).

    Returns
    -------
    DampingRange
        ``D = n_units r² L`` of the unit's open and closed throttle (N m s/rad), the unit's own values
        (N s/mm) and the relief torque (N m) when known.

    Raises
    ------
    ValueError
        When the unit reports a damping range that is not finite, negative or reversed.
    """
    get = getattr(design, "damping_range_N_s_per_mm", None)
    if get is None:
        return paper_table4_range(f"{type(design).__name__} carries no hydraulic damping range")
    L_min, L_max = (float(v) for v in get())
    if not (math.isfinite(L_min) and math.isfinite(L_max) and 0 <= L_min <= L_max):
        raise ValueError(f"the unit's damping range must be 0 <= D_min <= D_max N s/mm, got {show(L_min)}, "
                         f"{show(L_max)}")
    r2n = n_units * pulley_radius_m**2 * 1e3
    relief = getattr(getattr(design, "fixed", None), "relief_force_N", None)
    return DampingRange(
        D_min_Nms_per_rad=r2n * L_min, D_max_Nms_per_rad=r2n * L_max, source=UNIT_SOURCE,
        why="the design's own throttle, channels and relief valve (Design.damping_range_N_s_per_mm)",
        unit_D_min_N_s_per_mm=L_min, unit_D_max_N_s_per_mm=L_max,
        relief_torque_Nm=None if relief is None else float(n_units * pulley_radius_m * relief))
