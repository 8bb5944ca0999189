"""Casting silicones for the bladder and the allowable-strain criteria it is checked against.

Every compound carries its source. The datasheets give the hardness, the
tensile strength, the elongation at break and the *100 % modulus* (nominal
stress at 100 % elongation in the ASTM D412 test); the shear modulus of the
incompressible neo-Hookean model is fitted to that one point,

    P(lambda) = mu (lambda - lambda^-2)  ->  mu = P(2) / 1.75,

a secant fit over 0-100 % strain (the bladder sees well under 100 %). Where
a datasheet gives no 100 % modulus the value is a literature fit, named in
``source``.

Because the bladder is loaded by a prescribed volume, its neo-Hookean strain
field does not depend on the shear modulus at all; the modulus sets only
the pressure difference across it. The material matters through the
**allowable strain**, which is a named, overridable criterion:

* ``"cyclic"`` (default) — fatigue over millions of strokes:
  ``min(elongation_at_break / 10, 0.25)``;
* ``"static"`` — a single stroke: ``elongation_at_break / 3``.

Strains are engineering strains as fractions (0.25 = 25 %); moduli in MPa.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

__all__ = [
    "Silicone",
    "SILICONES",
    "get_silicone",
    "StrainCriterion",
    "CRITERIA",
    "DEFAULT_CRITERION",
    "get_criterion",
    "allowable_strain",
]

_PSI_MPa = 0.00689476


@dataclass(frozen=True)
class Silicone:
    """A casting silicone (incompressible, neo-Hookean fit)."""

    name: str
    shear_modulus_MPa: float  #: neo-Hookean mu, MPa (secant fit to the 100 % modulus)
    elongation_at_break: float  #: engineering strain at break, fraction (6.2 = 620 %)
    hardness: str  #: Shore hardness as on the datasheet
    tensile_strength_MPa: float  #: MPa
    source: str  #: where the numbers come from

    def __post_init__(self) -> None:
        for key in ("shear_modulus_MPa", "elongation_at_break", "tensile_strength_MPa"):
            v = getattr(self, key)
            if isinstance(v, bool) or not isinstance(v, (int, float)) or not math.isfinite(v) or v <= 0:
                raise ValueError(f"silicone {self.name!r}: {key} must be a positive number, got {v!r}")

    def to_dict(self) -> dict:
        """Plain-JSON dictionary of the datasheet values.

        Returns
        -------
        dict
            JSON-ready: ``name``, ``shear_modulus_MPa`` (MPa), ``elongation_at_break`` (fraction),
            ``hardness`` (Shore, as on the datasheet), ``tensile_strength_MPa`` (MPa) and ``source``.
        """
        return {
            "name": self.name,
            "shear_modulus_MPa": self.shear_modulus_MPa,
            "elongation_at_break": self.elongation_at_break,
            "hardness": self.hardness,
            "tensile_strength_MPa": self.tensile_strength_MPa,
            "source": self.source,
        }


def _smooth_on(name: str, hardness: str, tensile_psi: float, modulus100_psi: float, elong_pct: float) -> Silicone:
    return Silicone(
        name=name,
        shear_modulus_MPa=round(modulus100_psi * _PSI_MPa / 1.75, 4),
        elongation_at_break=elong_pct / 100.0,
        hardness=hardness,
        tensile_strength_MPa=round(tensile_psi * _PSI_MPa, 3),
        source=(f"Smooth-On technical bulletin ({name}): tensile {tensile_psi:g} psi, 100 % modulus "
                f"{modulus100_psi:g} psi, elongation {elong_pct:g} %; mu = 100 % modulus / 1.75"),
    )


#: Keys usable as ``material=`` (and ``bladder_material`` in the requirements file).
SILICONES: dict[str, Silicone] = {
    "ecoflex-00-30": _smooth_on("Ecoflex 00-30", "Shore 00-30", 200, 10, 900),
    "ecoflex-00-50": _smooth_on("Ecoflex 00-50", "Shore 00-50", 315, 12, 980),
    "dragon-skin-10": _smooth_on("Dragon Skin 10", "Shore 10A", 475, 22, 1000),
    "dragon-skin-20": _smooth_on("Dragon Skin 20", "Shore 20A", 550, 49, 620),
    "dragon-skin-30": _smooth_on("Dragon Skin 30", "Shore 30A", 500, 86, 364),
    "sylgard-184": Silicone(
        name="Sylgard 184 (10:1, room-temperature cure)",
        shear_modulus_MPa=0.45,
        elongation_at_break=1.0,
        hardness="Shore 43A",
        tensile_strength_MPa=6.7,
        source=("Dow Sylgard 184 datasheet (hardness, tensile strength); Johnston et al., J. Micromech. "
                "Microeng. 24 (2014) 035017: E = 1.32-2.97 MPa by cure, E = 1.35 MPa at 25 C -> mu = E/3; "
                "elongation ~100 % (lower end of the paper's 100-600 %)"),
    ),
}


def get_silicone(key: str | Silicone) -> Silicone:
    """A silicone by key (or pass a :class:`Silicone` through), with a clear error for unknown keys.

    Parameters
    ----------
    key : str or Silicone
        A key of :data:`SILICONES`, or a :class:`Silicone`, which is returned as is.

    Returns
    -------
    Silicone
        The casting silicone (shear modulus and tensile strength in MPa, elongation at break as a fraction).

    Raises
    ------
    ValueError
        If ``key`` is unknown; the message lists the known keys.
    """
    if isinstance(key, Silicone):
        return key
    try:
        return SILICONES[key]
    except (KeyError, TypeError):
        raise ValueError(f"unknown silicone {key!r}; known: {', '.join(sorted(SILICONES))}") from None


@dataclass(frozen=True)
class StrainCriterion:
    """Allowable strain ``min(elongation_at_break / divisor, cap)``.

    Attributes
    ----------
    name : str
    divisor : float
        Safety divisor on the elongation at break.
    cap : float
        Upper limit whatever the elongation (fatigue of elastomers is governed
        by the strain amplitude; tens of percent is where crack growth starts
        to matter), fraction. ``inf`` for none.
    """

    name: str
    divisor: float
    cap: float = math.inf

    def __post_init__(self) -> None:
        if not (math.isfinite(self.divisor) and self.divisor > 0):
            raise ValueError(f"criterion {self.name!r}: divisor must be > 0, got {self.divisor!r}")
        if not self.cap > 0:
            raise ValueError(f"criterion {self.name!r}: cap must be > 0, got {self.cap!r}")

    def allowable(self, silicone: Silicone) -> float:
        """Allowable engineering strain for ``silicone``, fraction.

        Parameters
        ----------
        silicone : Silicone
            The material; its ``elongation_at_break`` (fraction) is divided by :attr:`divisor`.

        Returns
        -------
        float
            ``min(elongation_at_break / divisor, cap)``, engineering strain as a fraction (0.5 = 50 %).
        """
        return min(silicone.elongation_at_break / self.divisor, self.cap)

    @property
    def formula(self) -> str:
        f = f"elongation_at_break / {self.divisor:g}"
        return f if math.isinf(self.cap) else f"min({f}, {self.cap:g})"

    def to_dict(self) -> dict:
        """Plain-JSON dictionary of the criterion.

        Returns
        -------
        dict of str to str
            ``name`` and ``formula`` (e.g. ``"min(elongation_at_break / 10, 0.25)"`` for ``cyclic``).
        """
        return {"name": self.name, "formula": self.formula}


#: Named criteria.
CRITERIA: dict[str, StrainCriterion] = {
    "cyclic": StrainCriterion("cyclic", divisor=10.0, cap=0.25),
    "static": StrainCriterion("static", divisor=3.0),
}
DEFAULT_CRITERION = "cyclic"


def get_criterion(criterion: str | StrainCriterion | None = None) -> StrainCriterion:
    """A criterion by name (``None`` -> the default, ``"cyclic"``) or passed through.

    Parameters
    ----------
    criterion : str or StrainCriterion or None
        A key of :data:`CRITERIA` (``"cyclic"`` or ``"static"``), a
        :class:`StrainCriterion` (returned as is), or ``None`` for the default.

    Returns
    -------
    StrainCriterion
        The criterion.

    Raises
    ------
    ValueError
        If ``criterion`` is an unknown name; the message lists the known ones.
    """
    if criterion is None:
        criterion = DEFAULT_CRITERION
    if isinstance(criterion, StrainCriterion):
        return criterion
    try:
        return CRITERIA[criterion]
    except (KeyError, TypeError):
        raise ValueError(f"unknown strain criterion {criterion!r}; known: {', '.join(sorted(CRITERIA))}") from None


def allowable_strain(material: str | Silicone, criterion: str | StrainCriterion | float | None = None) -> float:
    """Allowable engineering strain of ``material`` under ``criterion`` (a float is taken as the value), fraction.

    Parameters
    ----------
    material : str or Silicone
        The silicone, by key of :data:`SILICONES` or as a :class:`Silicone`.
        Not used when ``criterion`` is a number.
    criterion : str or StrainCriterion or float or None
        A criterion name or object (see :func:`get_criterion`; ``None`` is the
        default ``"cyclic"``), or the allowable strain itself as a positive
        fraction (0.25 = 25 %).

    Returns
    -------
    float
        Allowable engineering strain, fraction.

    Raises
    ------
    ValueError
        If a numeric ``criterion`` is not a finite positive number or exceeds the material's elongation
        at break (a percentage given for a fraction), or a name is unknown.
    """
    if isinstance(criterion, (int, float)) and not isinstance(criterion, bool):
        if not (math.isfinite(criterion) and criterion > 0):
            raise ValueError(f"allowable strain must be a positive fraction, got {criterion!r}")
        sil = get_silicone(material)
        if criterion > sil.elongation_at_break:
            raise ValueError(f"allowable strain {criterion:g} ({100 * criterion:g} %) is beyond {sil.name}'s elongation "
                             f"at break ({100 * sil.elongation_at_break:g} %): it is a fraction (0.25 = 25 %)")
        return float(criterion)
    return get_criterion(criterion).allowable(get_silicone(material))
