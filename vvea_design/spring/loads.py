"""The load cases every pressure-bearing piece is sized for, and the closed-form stresses they cause.

A load case gives the pressure on each kind of face: **chamber-1 gas**, **chamber-2 gas** and **fluid** (the
oil under the piston, in the base's channels up to the throttle and the relief valve; the oil in the bladder
and the support ring's channels sits at chamber-2 pressure). Pressures in MPa (gauge, as the charges), forces N.
:func:`load_cases` builds them from the peak pressures (arrays over a population):

``gas_full_stroke``
    x = travel, a fast (``fixed.wall_sizing_n``, adiabatic) stroke: chamber 2 at its peak, chamber 1 at its
    lowest, the fluid at chamber-2 pressure (no flow).
``gas_rest``
    x = 0: both chambers at their charge (chamber 1 at its highest), the fluid at chamber-2 pressure.
``retraction``
    a fast retraction cavitates the fluid under the piston (0 MPa; the paper's Remark 1): the envelope of the
    chamber pressures (each at its highest) with the fluid at 0.
``relief``
    the relief (blow-off) valve open: the fluid at the peak chamber-2 pressure plus the relief's pressure drop
    ``fixed.relief_force_N / A2``; chamber 1 at its lowest (x = travel).
``damping``
    the largest damping force the actuator can ask of the throttle: its motor's ``|tau_m| <= 100 N m``
    through the tendon pulley, ``fixed.max_motor_torque_Nm / fixed.pulley_radius_mm`` (all of it on one unit,
    conservatively), or the relief force if that is lower (:attr:`Loads.damping_bounded_by_motor` says which);
    the fluid at the peak chamber-2 pressure plus that force over A2.
``proof``
    the proof test: every face at ``fixed.proof_pressure_factor`` (1.5, ISO 10100's proof pressure of a
    hydraulic cylinder) times its highest working pressure over the cases above, no external force, held to
    ``fixed.proof_safety_factor`` (1.05 on yield: EN 13445-3's test condition ``f_test = R_p0.2 / 1.05``).

The working cases are held to ``fixed.wall_safety_factor`` on yield. Each case also carries the external
(tendon) force on the unit, ``A2 fluid - A1 chamber_1`` (> 0 tension), which the top cap's joint carries on top
of the pressure. Since every stress here is proportional to the load, a piece sized for the largest of
``load(case) x SF(case) / SF_ref`` (:meth:`Loads.effective`) meets every case's safety factor at once.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any, Callable

import numpy as np

from .geometry import Array, Pressures
from .parameters import FixedParameters
from .records import Record

__all__ = ["LoadCase", "Loads", "PieceLoad", "CASE_NAMES", "WORKING_CASES", "FACES", "load_cases",
           "lame_tresca_MPa", "plate_centre_moment_per_MPa"]

#: Every load case, in the order the design file lists them.
CASE_NAMES = ("gas_full_stroke", "gas_rest", "retraction", "relief", "damping", "proof")
#: The working (not test) cases.
WORKING_CASES = CASE_NAMES[:-1]
#: The kinds of face a pressure acts on.
FACES = ("chamber_1", "chamber_2", "fluid")

_WHAT = {
    "gas_full_stroke": "x = travel, fast stroke (wall-sizing exponent): chamber 2 at its peak, chamber 1 at its "
                       "lowest, fluid at chamber-2 pressure",
    "gas_rest": "x = 0: chambers at their charge (chamber 1 highest), fluid at chamber-2 pressure",
    "retraction": "fast retraction, the fluid under the piston cavitating (0 MPa); chamber pressures at their highest",
    "relief": "relief valve open: fluid at peak chamber-2 pressure + relief force / A2; chamber 1 at its lowest",
    "damping": "largest damping force the actuator asks (motor torque through the pulley, or the relief force)",
    "proof": "proof test: each face at the proof factor times its highest working pressure, no external force",
}
_STANDARD = {name: "working load, safety on yield (min_wall_safety_factor)" for name in WORKING_CASES}
_STANDARD["proof"] = "ISO 10100 proof pressure (1.5 x rated); EN 13445-3 test stress R_p0.2 / 1.05"


@dataclass(frozen=True)
class LoadCase(Record):
    """One load case: the pressure on each kind of face (MPa), the external force (N), the safety asked."""

    name: str  #: one of :data:`CASE_NAMES`
    what: str  #: the state it describes
    chamber_1_MPa: Array  #: chamber-1 gas pressure, MPa
    chamber_2_MPa: Array  #: chamber-2 gas pressure (and the bladder's fluid), MPa
    fluid_MPa: Array  #: fluid under the piston, in the base's channels up to the valves, MPa
    external_force_N: Array  #: tension on the unit's eyes, ``A2 fluid - A1 chamber_1`` (0 in the proof test), N
    required_safety_factor: float  #: on yield, dimensionless
    standard: str  #: where the case and its safety factor come from


@dataclass(frozen=True)
class Loads:
    """Every load case of a design or a population (arrays broadcast), and what set the damper's cases."""

    cases: tuple[LoadCase, ...]
    reference_safety_factor: float  #: ``fixed.wall_safety_factor``: what :meth:`effective` normalises to
    relief_pressure_MPa: Array  #: relief valve's pressure drop, ``fixed.relief_force_N / A2``, MPa
    damping_force_N: Array  #: the ``damping`` case's force on the piston, N
    motor_force_N: float  #: ``fixed.max_motor_torque_Nm / fixed.pulley_radius_mm``, N
    relief_force_N: float  #: ``fixed.relief_force_N``, N

    @property
    def damping_bounded_by_motor(self) -> bool:
        """True when the motor (not the relief valve) bounds the damping force the actuator can ask."""
        return self.motor_force_N < self.relief_force_N

    def case(self, name: str) -> LoadCase:
        """The load case called ``name``.

        Parameters
        ----------
        name : str
            One of :data:`CASE_NAMES`.

        Returns
        -------
        LoadCase
            Its pressures (MPa) and force (N).
        """
        for c in self.cases:
            if c.name == name:
                return c
        raise KeyError(f"no load case {name!r}; known: {[c.name for c in self.cases]}")

    def per_case(self, load: Callable[[LoadCase], Array]) -> dict[str, Array]:
        """A load evaluated in every case.

        Parameters
        ----------
        load : callable
            ``load(case)`` -> array (a pressure in MPa, a force in N ...).

        Returns
        -------
        dict of str to ndarray
            Case name -> the load, in its unit.
        """
        return {c.name: load(c) for c in self.cases}

    def effective(self, load: Callable[[LoadCase], Array], stacked: bool = True) -> Array:
        """The load a piece is sized for: the largest of ``load(case) x SF(case) / SF_ref`` over the cases.

        Parameters
        ----------
        load : callable
            ``load(case)`` -> a non-negative array (MPa or N) to which the piece's stress is proportional.
        stacked : bool
            Evaluate ``load`` once on every case stacked along a leading axis (:attr:`stacked`; ``load`` must
            broadcast over it); else once per case.

        Returns
        -------
        ndarray
            The effective load, in the unit of ``load``: sized with ``reference_safety_factor`` it meets every
            case's own safety factor.
        """
        ratio = np.array([c.required_safety_factor for c in self.cases]) / self.reference_safety_factor
        if stacked:
            v = np.asarray(load(self.stacked), dtype=float)
            return np.max(v * ratio.reshape((-1,) + (1,) * (v.ndim - 1)), axis=0)
        out = None
        for c, k in zip(self.cases, ratio):
            v = np.asarray(load(c), dtype=float) * k
            out = v if out is None else np.fmax(out, v)
        return out

    @property
    def stacked(self) -> LoadCase:
        """Every case in one: each field an array with the cases on a leading axis (MPa, N)."""
        st = self.__dict__.get("_stacked")
        if st is None:
            cs = self.cases
            st = LoadCase("stacked", "every case", *(np.array(np.broadcast_arrays(*[getattr(c, k) for c in cs]))
                                                    for k in ("chamber_1_MPa", "chamber_2_MPa", "fluid_MPa",
                                                              "external_force_N")),
                          np.array([c.required_safety_factor for c in cs]), "")
            object.__setattr__(self, "_stacked", st)
        return st

    @property
    def chamber_difference_MPa(self) -> Array:
        """Effective pressure between the two chambers, ``|chamber 2 - chamber 1|`` (the bulkhead's, the collar's), MPa."""
        return self.effective(lambda c: np.abs(c.chamber_2_MPa - c.chamber_1_MPa))

    @property
    def piston_floor_difference_MPa(self) -> Array:
        """Effective pressure across the piston's floor, ``|fluid - chamber 1|``, MPa."""
        return self.effective(lambda c: np.abs(c.fluid_MPa - c.chamber_1_MPa))

    def to_dict(self) -> dict[str, Any]:
        """JSON-ready content (one design: floats).

        Returns
        -------
        dict
            ``cases`` (name -> the case's fields: MPa, N), ``relief_pressure_MPa``, ``damping_force_N``,
            ``motor_force_N``, ``relief_force_N`` and ``damping_bounded_by`` (``"motor"`` or ``"relief"``).
        """
        return {"cases": {c.name: c.to_dict() for c in self.cases},
                "relief_pressure_MPa": self.relief_pressure_MPa, "damping_force_N": self.damping_force_N,
                "motor_force_N": self.motor_force_N, "relief_force_N": self.relief_force_N,
                "damping_bounded_by": "motor" if self.damping_bounded_by_motor else "relief"}


@dataclass(frozen=True)
class PieceLoad(Record):
    """A pressure-bearing piece under its load cases: the governing one, its stress and safety factor."""

    piece: str  #: outer_tube, inner_tube, top_cap, base, bulkhead, collar, piston_floor
    part: str  #: the CAD part it belongs to
    faces: str  #: which faces load it (e.g. ``chamber_2 inside``)
    method: str  #: how the stress is computed (formula and standard)
    governing_case: str  #: the case with the smallest safety factor relative to the one it asks
    stress_MPa: float  #: peak stress at the least-material condition in the governing case, MPa
    safety_factor: float  #: yield / that stress (the inner tube: also buckling), dimensionless
    required_safety_factor: float  #: what the governing case asks, dimensionless
    safety_factor_per_case: dict  #: case name -> safety factor, dimensionless


def load_cases(pressures: Pressures, p2_MPa, A1_mm2, A2_mm2, fixed: FixedParameters) -> Loads:
    """Every load case of a design (arrays broadcast over a population).

    Parameters
    ----------
    pressures : Pressures
        The charge of chamber 1 and the peaks of a fast stroke, MPa.
    p2_MPa : float or array
        Chamber-2 charge, MPa.
    A1_mm2, A2_mm2 : float or array
        Piston face and annulus under it, mm².
    fixed : FixedParameters
        Relief force (N), motor torque (N m), pulley radius (mm), proof factors, safety factor.

    Returns
    -------
    Loads
        The cases of :data:`CASE_NAMES` with their pressures (MPa) and external forces (N).
    """
    f = fixed
    p1, P2, P1min = pressures.p1_MPa, pressures.peak_chamber_2_MPa, pressures.min_chamber_1_MPa
    p2 = np.asarray(p2_MPa, dtype=float) * np.ones_like(P2)
    A1, A2 = A1_mm2, A2_mm2
    sf = f.wall_safety_factor
    motor = f.max_motor_torque_Nm / (f.pulley_radius_mm * 1e-3)
    damp = min(motor, f.relief_force_N)
    with np.errstate(divide="ignore", invalid="ignore"):
        dp_relief = f.relief_force_N / A2
        dp_damp = damp / A2
    zero = np.zeros_like(P2)
    states = {
        "gas_full_stroke": (P1min, P2, P2),
        "gas_rest": (p1 * np.ones_like(P2), p2, p2),
        "retraction": (p1 * np.ones_like(P2), P2, zero),
        "relief": (P1min, P2, P2 + dp_relief),
        "damping": (P1min, P2, P2 + dp_damp),
    }
    cases = [LoadCase(name, _WHAT[name], c1, c2, fl, A2 * fl - A1 * c1, sf, _STANDARD[name])
             for name, (c1, c2, fl) in states.items()]
    k = f.proof_pressure_factor
    proof = [k * np.max([getattr(c, face) for c in cases], axis=0)
             for face in ("chamber_1_MPa", "chamber_2_MPa", "fluid_MPa")]
    cases.append(LoadCase("proof", _WHAT["proof"], *proof, zero, f.proof_safety_factor, _STANDARD["proof"]))
    return Loads(tuple(cases), sf, dp_relief, np.full_like(P2, damp), motor, f.relief_force_N)


def lame_tresca_MPa(p_inside_MPa, p_outside_MPa, r_inside_mm, r_outside_mm, sigma_axial_MPa=0.0):
    """Largest Tresca stress (``max |sigma_i - sigma_j|``) of a thick-walled tube (Lamé), MPa.

    ``sigma_r = A - B/r^2``, ``sigma_theta = A + B/r^2`` with ``A = (p_i ri^2 - p_o ro^2)/(ro^2 - ri^2)`` and
    ``B = (p_i - p_o) ri^2 ro^2/(ro^2 - ri^2)``; at the bore, where ``|sigma_theta|`` and ``|sigma_theta -
    sigma_r|`` are largest (``B/r^2`` falls outward), with the given axial stress.

    Parameters
    ----------
    p_inside_MPa, p_outside_MPa : float or array
        Pressure on the bore and on the outside, MPa.
    r_inside_mm, r_outside_mm : float or array
        Bore and outside radius, mm.
    sigma_axial_MPa : float or array
        Axial stress (uniform over the section), MPa.

    Returns
    -------
    float or ndarray
        The Tresca equivalent stress, MPa.
    """
    pi_, po, ri, ro, sz = (np.asarray(v, dtype=float) for v in (p_inside_MPa, p_outside_MPa, r_inside_mm,
                                                                 r_outside_mm, sigma_axial_MPa))
    with np.errstate(divide="ignore", invalid="ignore"):
        den = ro**2 - ri**2
        st = (pi_ * (ri**2 + ro**2) - 2 * po * ro**2) / den  # sigma_theta at the bore
        sr = -pi_
        return np.fmax(np.fmax(np.abs(st - sr), np.abs(st - sz)), np.abs(sr - sz))


def plate_centre_moment_per_MPa(load_radius_mm, support_radius_mm, poisson: float):
    """Bending moment at the centre of a simply supported circular plate per unit pressure, N·mm/mm per MPa.

    The pressure acts on a central circle of radius ``c`` (the seal), the plate is supported at ``a >= c``
    (the joint): ``M = c^2/16 [4 - (1 - nu) c^2/a^2 + 4 (1 + nu) ln(a/c)]`` (Timoshenko & Woinowsky-Krieger,
    *Theory of Plates and Shells*, the central circular load); at ``c = a`` the uniform plate's
    ``(3 + nu) a^2/16``. The peak stress is ``6 M p / t^2``.

    Parameters
    ----------
    load_radius_mm, support_radius_mm : float or array
        ``c`` and ``a``, mm.
    poisson : float
        Poisson's ratio of the plate, dimensionless.

    Returns
    -------
    float or ndarray
        ``M / p``, mm² (N·mm/mm per N/mm²).
    """
    c = np.asarray(load_radius_mm, dtype=float)
    a = np.fmax(np.asarray(support_radius_mm, dtype=float), c)
    nu = float(poisson)
    return c**2 / 16 * (4 - (1 - nu) * c**2 / a**2 + 4 * (1 + nu) * np.log(a / c))
