"""Axisymmetric hyperelastic membrane finite elements, loaded by enclosed volume.

One concept per section, as in scikit-fem: the reference **meridian** (the
curve a surface of revolution is swept from, with its clamped nodes), the
**material** (incompressible Mooney-Rivlin, neo-Hookean when ``C01 = 0``, and
its tension-field relaxation), the **element** quantities (stretches of
two-node meridian elements), the **volume** of revolution, and the
**solver** (constrained energy minimisation).

Model
-----
A thin incompressible sheet of reference thickness ``H`` is swept about the
z axis by the meridian ``(R(S), Z(S))``. Deformed, a point goes to
``(r, z)``; the principal stretches are the meridional ``l1 = ds/dS``, the
hoop ``l2 = r/R`` and the thickness ``l3 = 1/(l1 l2)``. The meridian is cut
into two-node straight elements (cone frustums): ``l1`` is the chord ratio,
``l2`` is taken at the element midpoint (one-point quadrature), so the
discretisation error is O(h^2).

The strain energy density per reference volume is Mooney-Rivlin,

    W = C10 (I1 - 3) + C01 (I2 - 3),  shear modulus mu = 2 (C10 + C01),

with ``I1 = l1^2 + l2^2 + l3^2`` and ``I2 = l1^-2 + l2^-2 + l3^-2``. A
membrane cannot carry compression: it wrinkles. The **relaxed energy**
(Pipkin's tension-field theory) replaces ``W`` where a principal tension
would be negative by ``W`` at the *natural width* ``l2 = l1^-1/2`` (uniaxial
tension, true for any isotropic incompressible material), and by 0 where the
sheet is slack in both directions (``l1 <= 1`` and ``l2 <= 1``):

* taut      : ``l1^4 l2^2 >= 1`` and ``l2^4 l1^2 >= 1``  -> ``W(l1, l2)``
* wrinkled  : tension along the meridian only              -> ``W(l1, l1^-1/2)``
              or along the hoop only                       -> ``W(l2^-1/2, l2)``
* slack     : ``l1 <= 1`` and ``l2 <= 1``                  -> 0

The load is a prescribed **enclosed volume** ``V = pi int r^2 dz`` (exact for
the polygonal meridian), not a pressure: the total energy is minimised
subject to ``V = V_ref + dV`` and the **pressure is the Lagrange multiplier**
(``dPi = p dV``). Volume control follows the pressure-volume curve through
its limit point, where a pressure-driven solve would jump.

The constrained problem is solved with IPOPT through CasADi, with exact
(automatic-differentiation) gradients and Hessians. The solver is built once
per element count and cached; the geometry, thickness, material and target
volume are parameters, so a design check only solves. A deflated, wrinkled
sleeve is nearly a mechanism (zero stiffness in the slack directions); when
the direct solve does not converge, a homotopy blends in a fading fraction
``eta`` of the unrelaxed energy (1e-2 ... 0). If the pure relaxed problem
still fails, the solution with the smallest ``eta <= 1e-3`` that converged is
returned and ``eta`` is reported as ``MembraneSolution.regularisation``.

Units: mm, MPa (N/mm²), N/mm (membrane tension), mm³.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from functools import lru_cache

import casadi as ca
import numpy as np

__all__ = [
    "Meridian",
    "MooneyRivlin",
    "MembraneSolution",
    "MembraneError",
    "sleeve_meridian",
    "sphere_meridian",
    "enclosed_volume_mm3",
    "element_stretches",
    "relaxed_energy_density",
    "solve_volume",
    "solve_volume_path",
    "TAUT",
    "WRINKLED",
    "SLACK",
]

#: Element states of the tension-field model.
TAUT, WRINKLED, SLACK = 0, 1, 2
_PRINT_LEVEL = 0  # IPOPT verbosity (debugging)


class MembraneError(ValueError):
    """Bad membrane input, or a volume change the membrane cannot take."""


# --------------------------------------------------------------------- meridian
@dataclass(frozen=True, eq=False)
class Meridian:
    """Reference meridian of a membrane of revolution.

    Attributes
    ----------
    r_mm, z_mm : ndarray, shape (n + 1,)
        Node coordinates of the stress-free (cast) shape, mm; ``r >= 0``.
    thickness_mm : float
        Reference wall thickness ``H``, mm.
    fixed_r, fixed_z : ndarray of bool, shape (n + 1,)
        Nodes whose radial / axial coordinate is held (clamps, poles, one
        node against rigid axial translation).
    name : str
        What the curve is (``"sleeve"``, ``"sphere"``).
    """

    r_mm: np.ndarray
    z_mm: np.ndarray
    thickness_mm: float
    fixed_r: np.ndarray
    fixed_z: np.ndarray
    name: str = "meridian"

    def __post_init__(self) -> None:
        r, z = np.asarray(self.r_mm, float), np.asarray(self.z_mm, float)
        if r.ndim != 1 or r.shape != z.shape or r.size < 3:
            raise MembraneError("meridian needs r_mm and z_mm of the same length, at least 3 nodes")
        if not (np.all(np.isfinite(r)) and np.all(np.isfinite(z))):
            raise MembraneError("meridian coordinates must be finite")
        if np.any(r < 0):
            raise MembraneError("meridian radii r_mm must be >= 0")
        if not (math.isfinite(self.thickness_mm) and self.thickness_mm > 0):
            raise MembraneError(f"thickness_mm must be > 0, got {self.thickness_mm!r}")
        if np.any(np.hypot(np.diff(r), np.diff(z)) <= 0):
            raise MembraneError("meridian has zero-length elements")
        if np.any(0.5 * (r[1:] + r[:-1]) <= 0):
            raise MembraneError("meridian elements must not lie on the axis")
        object.__setattr__(self, "r_mm", r)
        object.__setattr__(self, "z_mm", z)
        object.__setattr__(self, "fixed_r", np.asarray(self.fixed_r, bool))
        object.__setattr__(self, "fixed_z", np.asarray(self.fixed_z, bool))

    @property
    def n_elements(self) -> int:
        return self.r_mm.size - 1

    @property
    def element_length_mm(self) -> np.ndarray:
        return np.hypot(np.diff(self.r_mm), np.diff(self.z_mm))

    @property
    def element_mid_radius_mm(self) -> np.ndarray:
        return 0.5 * (self.r_mm[1:] + self.r_mm[:-1])

    @property
    def area_mm2(self) -> float:
        """Reference mid-surface area (midpoint rule, as the energy), mm²."""
        return float(np.sum(2 * math.pi * self.element_mid_radius_mm * self.element_length_mm))

    @property
    def volume_mm3(self) -> float:
        """Volume of revolution enclosed by the reference meridian, mm³."""
        return enclosed_volume_mm3(self.r_mm, self.z_mm)


def sleeve_meridian(radius_mm: float, length_mm: float, thickness_mm: float, n_elements: int = 60,
                    grading: float = 0.9) -> Meridian:
    """A straight cylindrical sleeve clamped (r and z held) at both ends.

    Parameters
    ----------
    radius_mm, length_mm, thickness_mm : float
        Mid-surface radius, free length between the clamps and wall thickness, mm.
    n_elements : int
        Elements along the meridian.
    grading : float
        0 uniform ... 1 cosine spacing (finer at the clamps, where the
        meridian turns most). The default 0.9 puts the first element at
        about 1/(4 n) of the uniform size plus a little; the clamp strain then
        converges from 96 elements to within 0.1 %. Dimensionless.

    Returns
    -------
    Meridian
        The reference meridian (coordinates in mm), both end nodes held in r and z.

    Raises
    ------
    MembraneError
        If a size is not a positive number, ``n_elements < 2`` or ``grading`` is outside [0, 1].
    """
    for name, v in (("radius_mm", radius_mm), ("length_mm", length_mm), ("thickness_mm", thickness_mm)):
        if isinstance(v, bool) or not isinstance(v, (int, float, np.floating)) or not math.isfinite(v) or v <= 0:
            raise MembraneError(f"{name} must be a positive number, got {v!r}")
    if int(n_elements) < 2:
        raise MembraneError(f"n_elements must be >= 2, got {n_elements!r}")
    if not 0 <= grading <= 1:
        raise MembraneError(f"grading must be in [0, 1], got {grading!r}")
    s = np.linspace(0.0, 1.0, int(n_elements) + 1)
    z = length_mm * ((1 - grading) * s + grading * 0.5 * (1 - np.cos(math.pi * s)))
    r = np.full_like(z, float(radius_mm))
    ends = np.zeros(z.size, bool)
    ends[[0, -1]] = True
    return Meridian(r, z, float(thickness_mm), ends, ends.copy(), "sleeve")


def sphere_meridian(radius_mm: float, thickness_mm: float, n_elements: int = 64) -> Meridian:
    """A closed sphere (balloon): meridian from pole to pole, equal angles.

    The poles stay on the axis (r held); the south pole's z is held against
    rigid translation.

    Parameters
    ----------
    radius_mm : float
        Mid-surface radius of the sphere, mm.
    thickness_mm : float
        Wall thickness, mm.
    n_elements : int
        Elements along the meridian from pole to pole (>= 4).

    Returns
    -------
    Meridian
        The reference meridian (coordinates in mm), centred on the origin.

    Raises
    ------
    MembraneError
        If a size is not a positive number or ``n_elements < 4``.
    """
    for name, v in (("radius_mm", radius_mm), ("thickness_mm", thickness_mm)):
        if not math.isfinite(v) or v <= 0:
            raise MembraneError(f"{name} must be a positive number, got {v!r}")
    if int(n_elements) < 4:
        raise MembraneError(f"n_elements must be >= 4, got {n_elements!r}")
    th = np.linspace(0.0, math.pi, int(n_elements) + 1)
    r = radius_mm * np.sin(th)
    r[[0, -1]] = 0.0
    z = -radius_mm * np.cos(th)
    fr = np.zeros(th.size, bool)
    fr[[0, -1]] = True
    fz = np.zeros(th.size, bool)
    fz[0] = True
    return Meridian(r, z, float(thickness_mm), fr, fz, "sphere")


def enclosed_volume_mm3(r_mm, z_mm) -> float:
    """Volume of revolution ``pi int r^2 dz`` of a polygonal meridian (exact for cone frustums), mm³.

    Parameters
    ----------
    r_mm, z_mm : array_like, shape (n + 1,)
        Radius and axial coordinate of the meridian nodes, in order, mm.

    Returns
    -------
    float
        Enclosed volume, mm³ (positive when z increases along the meridian).
    """
    r, z = np.asarray(r_mm, float), np.asarray(z_mm, float)
    return float(math.pi / 3 * np.sum(np.diff(z) * (r[:-1] ** 2 + r[:-1] * r[1:] + r[1:] ** 2)))


# --------------------------------------------------------------------- material
@dataclass(frozen=True)
class MooneyRivlin:
    """Incompressible Mooney-Rivlin solid, ``W = C10 (I1 - 3) + C01 (I2 - 3)`` (MPa).

    ``C01 = 0`` is neo-Hookean with shear modulus ``2 C10``.
    """

    C10_MPa: float
    C01_MPa: float = 0.0

    def __post_init__(self) -> None:
        if not (math.isfinite(self.C10_MPa) and self.C10_MPa > 0):
            raise MembraneError(f"C10_MPa must be > 0, got {self.C10_MPa!r}")
        if not (math.isfinite(self.C01_MPa) and self.C01_MPa >= 0):
            raise MembraneError(f"C01_MPa must be >= 0, got {self.C01_MPa!r}")

    @classmethod
    def neo_hookean(cls, shear_modulus_MPa: float) -> "MooneyRivlin":
        """The neo-Hookean solid of a given shear modulus (``C10 = G/2``, ``C01 = 0``).

        Parameters
        ----------
        shear_modulus_MPa : float
            Small-strain shear modulus G, MPa.

        Returns
        -------
        MooneyRivlin
            The material with ``C10_MPa = shear_modulus_MPa / 2`` and ``C01_MPa = 0``.

        Raises
        ------
        MembraneError
            When ``shear_modulus_MPa`` is not a finite number > 0.
        """
        return cls(0.5 * shear_modulus_MPa, 0.0)

    @property
    def shear_modulus_MPa(self) -> float:
        return 2.0 * (self.C10_MPa + self.C01_MPa)


def _W(l1, l2, c10, c01):
    """Membrane energy density at stretches (l1, l2), incompressible (works on numpy and CasADi)."""
    l3 = 1.0 / (l1 * l2)
    return c10 * (l1**2 + l2**2 + l3**2 - 3) + c01 * (l1**-2 + l2**-2 + l3**-2 - 3)


def _dW(l1, l2, c10, c01):
    """(dW/dl1, dW/dl2) of :func:`_W`, numpy."""
    d1 = 2 * c10 * (l1 - l1**-3 * l2**-2) + 2 * c01 * (-(l1**-3) + l1 * l2**2)
    d2 = 2 * c10 * (l2 - l2**-3 * l1**-2) + 2 * c01 * (-(l2**-3) + l2 * l1**2)
    return d1, d2


def _relaxed_W_casadi(l1, l2, c10, c01):
    taut = ca.logic_and(l1**4 * l2**2 >= 1, l2**4 * l1**2 >= 1)
    w_mer = ca.logic_and(l1 > 1, l2**4 * l1**2 < 1)  # tension along the meridian only
    w_hoop = ca.logic_and(l2 > 1, l1**4 * l2**2 < 1)  # tension along the hoop only
    # guard the arguments of the inactive branches so they stay finite
    l1s = ca.fmax(l1, 1e-3)
    l2s = ca.fmax(l2, 1e-3)
    return ca.if_else(taut, _W(l1s, l2s, c10, c01),
                      ca.if_else(w_mer, _W(l1s, l1s**-0.5, c10, c01),
                                 ca.if_else(w_hoop, _W(l2s**-0.5, l2s, c10, c01), 0.0)))


def relaxed_energy_density(l1, l2, material: MooneyRivlin, relaxed: bool = True) -> np.ndarray:
    """Strain energy per reference volume at stretches (l1, l2), tension-field relaxed, MPa (N mm / mm³).

    Parameters
    ----------
    l1, l2 : array_like
        Meridional and hoop stretch (deformed / reference length), dimensionless;
        broadcast against each other.
    material : MooneyRivlin
        Material constants ``C10_MPa``, ``C01_MPa``.
    relaxed : bool
        ``True``: tension-field energy (zero in slack, uniaxial in wrinkled
        states); ``False``: the plain incompressible energy, compression carried.

    Returns
    -------
    numpy.ndarray
        Energy density at each pair of stretches, MPa (N mm / mm³).
    """
    l1 = np.asarray(l1, float)
    l2 = np.asarray(l2, float)
    c10, c01 = material.C10_MPa, material.C01_MPa
    if not relaxed:
        return _W(l1, l2, c10, c01)
    taut = (l1**4 * l2**2 >= 1) & (l2**4 * l1**2 >= 1)
    w_mer = ~taut & (l1 > 1) & (l2**4 * l1**2 < 1)
    w_hoop = ~taut & ~w_mer & (l2 > 1) & (l1**4 * l2**2 < 1)
    out = np.zeros(np.broadcast(l1, l2).shape)
    l1b, l2b = np.broadcast_arrays(l1, l2)
    out[taut] = _W(l1b[taut], l2b[taut], c10, c01)
    out[w_mer] = _W(l1b[w_mer], l1b[w_mer] ** -0.5, c10, c01)
    out[w_hoop] = _W(l2b[w_hoop] ** -0.5, l2b[w_hoop], c10, c01)
    return out


def element_stretches(ref: Meridian, r_mm, z_mm, material: MooneyRivlin | None = None,
                      relaxed: bool = True) -> dict[str, np.ndarray]:
    """Per-element stretches, tension-field state and membrane tensions of a deformed meridian.

    Parameters
    ----------
    ref : Meridian
        Reference (undeformed) meridian.
    r_mm, z_mm : array_like, shape (n + 1,)
        Deformed node coordinates, mm.
    material : MooneyRivlin, optional
        If given, the membrane tensions are computed too.
    relaxed : bool
        ``True``: classify elements as taut / wrinkled / slack (tension field);
        ``False``: every element counts as taut.

    Returns
    -------
    dict
        ``l1``, ``l2`` geometric meridional / hoop stretch; ``state`` (TAUT,
        WRINKLED, SLACK); ``l1_eff``, ``l2_eff``, ``l3_eff`` the stretches of
        the material itself (in a wrinkled direction the natural width, which
        the wrinkles take up; in slack elements 1); ``T1_N_per_mm``,
        ``T2_N_per_mm`` meridional / hoop tension per deformed length (if a
        material is given); ``thickness_mm`` deformed wall.
    """
    r, z = np.asarray(r_mm, float), np.asarray(z_mm, float)
    l1 = np.hypot(np.diff(r), np.diff(z)) / ref.element_length_mm
    l2 = (0.5 * (r[1:] + r[:-1])) / ref.element_mid_radius_mm
    taut = (l1**4 * l2**2 >= 1) & (l2**4 * l1**2 >= 1)
    if not relaxed:  # the membrane carries compression: every element counts as taut
        taut = np.ones_like(l1, bool)
    w_mer = ~taut & (l1 > 1) & (l2**4 * l1**2 < 1)
    w_hoop = ~taut & ~w_mer & (l2 > 1) & (l1**4 * l2**2 < 1)
    slack = ~(taut | w_mer | w_hoop)
    state = np.where(taut, TAUT, np.where(slack, SLACK, WRINKLED))
    l1e = np.where(taut | w_mer, l1, np.where(w_hoop, l2 ** -0.5, 1.0))
    l2e = np.where(taut | w_hoop, l2, np.where(w_mer, l1 ** -0.5, 1.0))
    l3e = 1.0 / (l1e * l2e)
    out = {"l1": l1, "l2": l2, "state": state, "l1_eff": l1e, "l2_eff": l2e, "l3_eff": l3e,
           "thickness_mm": ref.thickness_mm * l3e}
    if material is not None:
        d1, d2 = _dW(l1e, l2e, material.C10_MPa, material.C01_MPa)
        H = ref.thickness_mm
        out["T1_N_per_mm"] = np.where(slack, 0.0, H * d1 / l2e)
        out["T2_N_per_mm"] = np.where(slack, 0.0, H * d2 / l1e)
    return out


# ----------------------------------------------------------------------- solver
@dataclass(frozen=True, eq=False)
class MembraneSolution:
    """Equilibrium of a membrane at a prescribed enclosed-volume change.

    Attributes
    ----------
    meridian : Meridian
        The reference (cast) geometry.
    material : MooneyRivlin
    r_mm, z_mm : ndarray
        Deformed node coordinates, mm.
    volume_change_mm3 : float
        Enclosed volume minus the reference one, mm³ (the prescribed load).
    pressure_MPa : float
        Pressure difference across the membrane that holds it there
        (inside minus outside, the Lagrange multiplier), MPa.
    iterations : int
        IPOPT iterations.
    """

    meridian: Meridian
    material: MooneyRivlin
    r_mm: np.ndarray
    z_mm: np.ndarray
    volume_change_mm3: float
    pressure_MPa: float
    iterations: int
    fields: dict = field(repr=False, default_factory=dict)
    relaxed: bool = True  #: solved with the tension-field (wrinkling) relaxation
    regularisation: float = 0.0  #: weight of the unrelaxed energy blended in (0 = pure tension field)

    @property
    def principal_strains(self) -> np.ndarray:
        """Engineering principal strains of the material per element, shape (n, 3): meridian, hoop, thickness."""
        f = self.fields
        return np.column_stack([f["l1_eff"], f["l2_eff"], f["l3_eff"]]) - 1.0

    @property
    def element_max_principal_strain(self) -> np.ndarray:
        return self.principal_strains.max(axis=1)

    @property
    def max_principal_strain(self) -> float:
        """Largest tensile engineering principal strain over the membrane (wrinkles relaxed)."""
        return float(self.element_max_principal_strain.max())

    @property
    def energy_N_mm(self) -> float:
        """Stored (relaxed) strain energy of the membrane, N mm."""
        ref = self.meridian
        w = relaxed_energy_density(self.fields["l1"], self.fields["l2"], self.material, self.relaxed)
        return float(np.sum(2 * math.pi * ref.element_mid_radius_mm * ref.element_length_mm * ref.thickness_mm * w))

    @property
    def state(self) -> np.ndarray:
        return self.fields["state"]

    @property
    def wrinkled_fraction(self) -> float:
        """Fraction of the reference area that is wrinkled or slack."""
        a = self.meridian.element_mid_radius_mm * self.meridian.element_length_mm
        return float(np.sum(a[self.state != TAUT]) / np.sum(a))


@lru_cache(maxsize=32)
def _solver(n_nodes: int, relaxed: bool, max_iter: int = 300):
    """IPOPT solver for ``n_nodes`` meridian nodes, built once (parameters: geometry, material, target)."""
    n = n_nodes
    u = ca.SX.sym("u", 2 * n)  # [u_r (n), u_z (n)] displacements, mm
    R = ca.SX.sym("R", n)
    Z = ca.SX.sym("Z", n)
    c10, c01, H, e_scale, v_scale, eta = (ca.SX.sym(s) for s in ("c10", "c01", "H", "e_scale", "v_scale", "eta"))
    r = R + u[:n]
    z = Z + u[n:]
    dR, dZ = R[1:] - R[:-1], Z[1:] - Z[:-1]
    dr, dz = r[1:] - r[:-1], z[1:] - z[:-1]
    L0 = ca.sqrt(dR**2 + dZ**2)
    Rm = 0.5 * (R[1:] + R[:-1])
    l1 = ca.sqrt(dr**2 + dz**2) / L0
    l2 = 0.5 * (r[1:] + r[:-1]) / Rm
    w_full = _W(l1, l2, c10, c01)
    # eta > 0 blends in the unrelaxed energy: a homotopy that removes the zero-stiffness (slack) directions
    w = (1 - eta) * _relaxed_W_casadi(l1, l2, c10, c01) + eta * w_full if relaxed else w_full
    energy = ca.sum1(2 * math.pi * Rm * L0 * H * w)
    vol = math.pi / 3 * ca.sum1(dz * (r[:-1] ** 2 + r[:-1] * r[1:] + r[1:] ** 2))
    vol0 = math.pi / 3 * ca.sum1(dZ * (R[:-1] ** 2 + R[:-1] * R[1:] + R[1:] ** 2))
    p = ca.vertcat(R, Z, c10, c01, H, e_scale, v_scale, eta)
    nlp = {"x": u, "p": p, "f": energy / e_scale, "g": (vol - vol0) / v_scale}
    opts = {
        "print_time": False,
        "ipopt": {"print_level": _PRINT_LEVEL, "sb": "yes", "tol": 1e-10, "acceptable_tol": 1e-7,
                  "acceptable_iter": 5, "max_iter": int(max_iter), "mu_strategy": "monotone", "nlp_scaling_method": "none"},
    }
    energy_fn = ca.Function("energy", [u, p], [energy])
    return ca.nlpsol("membrane", "ipopt", nlp, opts), energy_fn


def solve_volume(ref: Meridian, material: MooneyRivlin, volume_change_mm3: float, *,
                 initial: MembraneSolution | None = None, relaxed: bool = True) -> MembraneSolution:
    """Equilibrium shape at an enclosed volume ``V_ref + volume_change_mm3``.

    Parameters
    ----------
    ref : Meridian
        Reference geometry and boundary conditions.
    material : MooneyRivlin
        Membrane material (``C10_MPa``, ``C01_MPa``).
    volume_change_mm3 : float
        Prescribed change of enclosed volume, mm³ (negative = deflate).
    initial : MembraneSolution, optional
        Warm start (a neighbouring solution on the same meridian).
    relaxed : bool
        Use the tension-field (wrinkling) relaxed energy; ``False`` lets the
        membrane carry compression (for comparisons only).

    Returns
    -------
    MembraneSolution
        Deformed shape (mm), pressure difference (MPa), per-element stretches
        and tensions; ``regularisation`` > 0 when the pure relaxed problem did
        not converge and a lightly regularised solution is returned.

    Raises
    ------
    MembraneError
        When the solver does not converge (a volume change the membrane
        cannot take in this setting).
    """
    if not math.isfinite(volume_change_mm3):
        raise MembraneError(f"volume_change_mm3 must be finite, got {volume_change_mm3!r}")
    if ref.name == "sphere" and ref.volume_mm3 + volume_change_mm3 <= 0:
        raise MembraneError(f"volume_change_mm3 {volume_change_mm3:g} would leave no enclosed volume")
    if volume_change_mm3 == 0.0:
        # no load: the stress-free reference shape is the exact solution (the solver's energy scaling
        # degenerates at zero energy, so it is not asked)
        r, z = ref.r_mm.copy(), ref.z_mm.copy()
        return MembraneSolution(ref, material, r, z, 0.0, 0.0, 0, element_stretches(ref, r, z, material, relaxed),
                                relaxed, 0.0)
    if initial is not None:
        x0 = np.concatenate([initial.r_mm - ref.r_mm, initial.z_mm - ref.z_mm])
    else:
        x0 = _initial_guess(ref, volume_change_mm3)
    try:
        # a direct attempt that succeeds takes < 40 iterations; give up early and take the homotopy
        return _solve(ref, material, volume_change_mm3, x0, relaxed, 0.0, max_iter=_DIRECT_ITER if relaxed else 300)
    except MembraneError:
        if not relaxed:
            raise
    # homotopy: blend in the unrelaxed (compression-carrying) energy and fade it out. A long deflated
    # sleeve is nearly a mechanism (strains ~1e-5); if the pure relaxed problem still does not
    # converge, the last regularised solution is returned with its weight in ``regularisation``.
    # Its strains are above the unregularised ones (they fall monotonically with the weight).
    x = _initial_guess(ref, volume_change_mm3)
    sol = None
    for eta in _HOMOTOPY:
        try:
            sol = _solve(ref, material, volume_change_mm3, x, True, eta, max_iter=_MAX_ITER if eta > 0 else _DIRECT_ITER)
        except MembraneError:
            if sol is None or sol.regularisation > _MAX_REGULARISATION:
                raise
            return sol
        x = np.concatenate([sol.r_mm - ref.r_mm, sol.z_mm - ref.z_mm])
    return sol


#: Weights of the unrelaxed energy in the fallback homotopy (ends at the pure relaxed energy).
_HOMOTOPY = (1e-2, 1e-3, 1e-4, 1e-5, 0.0)
#: IPOPT iteration caps: regularised homotopy steps; solves of the pure relaxed problem (those that
#: converge take < 30 iterations; a nearly slack sleeve that does not, would wander for hundreds).
_MAX_ITER = 80
_DIRECT_ITER = 40
#: Largest weight of the unrelaxed energy accepted as a solution when the pure relaxed one fails.
_MAX_REGULARISATION = 1e-3


def _solve(ref: Meridian, material: MooneyRivlin, volume_change_mm3: float, x0: np.ndarray,
           relaxed: bool, eta: float, max_iter: int = 300) -> MembraneSolution:
    n = ref.r_mm.size
    solver, energy_fn = _solver(n, bool(relaxed), int(max_iter))
    area = ref.area_mm2
    v_scale = area * 1.0  # volume change / v_scale = mean normal displacement, mm
    # scale the energy to O(1) at the start point, so that it is not swamped by the barrier of the
    # radius bounds when the strains are tiny (a wrinkled, deflated sleeve stores almost nothing)
    e_unit = material.shear_modulus_MPa * ref.thickness_mm * area  # N mm per unit strain^2
    p = np.concatenate([ref.r_mm, ref.z_mm,
                        [material.C10_MPa, material.C01_MPa, ref.thickness_mm, 1.0, v_scale, eta]])
    e0 = float(energy_fn(x0, p))
    e_scale = min(max(e0, 1e-10 * e_unit), e_unit)
    p[-3] = e_scale
    lbx = np.full(2 * n, -np.inf)
    ubx = np.full(2 * n, np.inf)
    fixed = np.concatenate([ref.fixed_r, ref.fixed_z])
    lbx[fixed] = 0.0
    ubx[fixed] = 0.0
    # keep radii positive (r = 0 only where held)
    lbx[:n][~ref.fixed_r] = -ref.r_mm[~ref.fixed_r] + 1e-6 * max(ref.r_mm.max(), 1.0)
    g = volume_change_mm3 / v_scale
    sol = solver(x0=x0, p=p, lbx=lbx, ubx=ubx, lbg=g, ubg=g)
    stats = solver.stats()
    if not stats["success"] and stats["return_status"] not in ("Solved_To_Acceptable_Level",):
        raise MembraneError(
            f"membrane solve did not converge at volume change {volume_change_mm3:.6g} mm³ "
            f"({stats['return_status']}); the membrane cannot take this volume change"
        )
    x = np.asarray(sol["x"]).ravel()
    r, z = ref.r_mm + x[:n], ref.z_mm + x[n:]
    if np.any(0.5 * (r[1:] + r[:-1]) <= 0):
        raise MembraneError(f"at volume change {volume_change_mm3:.6g} mm³ the membrane collapses onto the axis")
    pressure = -float(np.asarray(sol["lam_g"]).ravel()[0]) * e_scale / v_scale
    dv = enclosed_volume_mm3(r, z) - ref.volume_mm3
    return MembraneSolution(ref, material, r, z, float(dv), pressure, int(stats["iter_count"]),
                            element_stretches(ref, r, z, material, relaxed), relaxed, float(eta) if relaxed else 0.0)


def _initial_guess(ref: Meridian, dv: float) -> np.ndarray:
    """A displacement along the reference normal, shaped to the free nodes, with the right volume."""
    n = ref.r_mm.size
    free = ~(ref.fixed_r & ref.fixed_z)
    if ref.name == "sphere":
        scale = ((ref.volume_mm3 + dv) / ref.volume_mm3) ** (1 / 3)
        return np.concatenate([ref.r_mm * (scale - 1), (ref.z_mm - ref.z_mm[0]) * (scale - 1)])
    # bubble between clamps: sin shape of the arc-length coordinate, radial
    s = np.concatenate([[0.0], np.cumsum(ref.element_length_mm)])
    shape = np.sin(math.pi * s / s[-1]) * free
    if dv == 0:
        return np.zeros(2 * n)
    # amplitude from the linearised volume change of a radial bubble
    dvda = (enclosed_volume_mm3(ref.r_mm + 1e-3 * shape, ref.z_mm) - ref.volume_mm3) / 1e-3
    a = dv / dvda
    return np.concatenate([a * shape, np.zeros(n)])


def solve_volume_path(ref: Meridian, material: MooneyRivlin, volume_changes_mm3, *,
                      relaxed: bool = True) -> list[MembraneSolution]:
    """Solutions along a sequence of volume changes, each warm-started from the previous one.

    Parameters
    ----------
    ref : Meridian
        Reference geometry and boundary conditions.
    material : MooneyRivlin
        Membrane material (``C10_MPa``, ``C01_MPa``).
    volume_changes_mm3 : iterable of float
        Prescribed changes of enclosed volume, mm³, in the order to solve them
        (small steps help the warm start).
    relaxed : bool
        Use the tension-field (wrinkling) relaxed energy (see :func:`solve_volume`).

    Returns
    -------
    list of MembraneSolution
        One solution per volume change, in the same order.

    Raises
    ------
    MembraneError
        When a step does not converge (see :func:`solve_volume`).
    """
    out: list[MembraneSolution] = []
    prev = None
    for dv in volume_changes_mm3:
        prev = solve_volume(ref, material, float(dv), initial=prev, relaxed=relaxed)
        out.append(prev)
    return out
