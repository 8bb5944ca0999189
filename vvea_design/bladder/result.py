"""Typed results of the bladder check: one stroke end (:class:`StrokeEnd`), the
check of one sleeve (:class:`BladderResult`, ``to_dict()`` = ``bladder.json``)
and the files written for it (:class:`BladderReport`).

Units: mm, mm³, MPa; strains are engineering strains as fractions.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field
from pathlib import Path

from ..materials.silicones import Silicone, StrainCriterion
from .membrane import MembraneSolution

__all__ = ["StrokeEnd", "BladderResult", "BladderReport", "ENDS", "DEFAULT_ELEMENTS"]

DEFAULT_ELEMENTS = 96  #: elements along the meridian of the full check
ENDS = ("expanded", "compressed")  #: the stroke ends checked: x = travel (expanded) and x = 0 (compressed)


@dataclass(frozen=True, eq=False)
class StrokeEnd:
    """The membrane at one end of the stroke."""

    solution: MembraneSolution
    max_principal_strain: float  #: largest tensile principal strain of the membrane, fraction
    min_geometric_strain: float  #: most negative meridian/hoop strain of the surface (taken up by wrinkles), fraction
    bending_strain: float  #: bending bound at the worse clamp, fraction
    clamp_strain: float  #: clamp meridional strain + bending bound, worse clamp, fraction
    strain_bound: float  #: max(max_principal_strain, clamp_strain), fraction
    wrinkled_fraction: float  #: wrinkled or slack share of the area
    slack_z_mm: list  #: reference z-intervals [z0, z1] (from the lower clamp) that are wrinkled or slack, mm
    gap_inner_tube_mm: float | None  #: smallest gap to the inner tube (negative = touches), mm
    gap_outer_bore_mm: float | None  #: smallest gap to the outer bore (negative = touches), mm

    @property
    def pressure_MPa(self) -> float:
        """Pressure difference that holds the shape, fluid minus gas, MPa."""
        return self.solution.pressure_MPa

    @property
    def touches(self) -> dict[str, bool]:
        """Whether the wall reaches ``inner_tube`` / ``outer_bore`` (gap < 0; False where not given)."""
        return {
            "inner_tube": self.gap_inner_tube_mm is not None and self.gap_inner_tube_mm < 0,
            "outer_bore": self.gap_outer_bore_mm is not None and self.gap_outer_bore_mm < 0,
        }


@dataclass(frozen=True, eq=False)
class BladderResult:
    """The bladder check of one sleeve (see :func:`check_membrane`)."""

    mid_radius_mm: float
    free_length_mm: float
    thickness_mm: float
    silicone_key: str
    silicone: Silicone
    criterion: StrainCriterion | None  #: None when the allowable strain was given as a number
    allowable_strain: float  #: fraction
    volume_change_mm3: dict  #: {"expanded", "compressed"}, mm³
    ends: dict  #: {"expanded": StrokeEnd, "compressed": StrokeEnd}
    inner_tube_outer_radius_mm: float | None = None
    outer_bore_radius_mm: float | None = None
    n_elements: int = DEFAULT_ELEMENTS
    extra: dict = field(default_factory=dict)

    @property
    def strain_bound(self) -> float:
        """Largest strain bound over both stroke ends (membrane + clamp bending), fraction."""
        return max(e.strain_bound for e in self.ends.values())

    @property
    def passes_strain(self) -> bool:
        """The strain bound is within the allowable strain."""
        return self.strain_bound <= self.allowable_strain

    @property
    def passes_room(self) -> bool:
        """The wall touches neither the inner tube nor the outer bore at either stroke end."""
        return not any(any(e.touches.values()) for e in self.ends.values())

    @property
    def passes(self) -> bool:
        """Strain bound within the allowable strain and no contact with inner tube or bore."""
        return self.passes_strain and self.passes_room

    def to_dict(self) -> dict:
        """The content of ``bladder.json`` (plain JSON types, units in the keys).

        Returns
        -------
        dict
            ``membrane`` (radius, length, wall in mm, shear modulus in MPa, model, elements),
            ``material``, ``criterion``, ``room`` (mm), ``volume_change_mm3``; per stroke end the
            strains (fractions), ``pressure_MPa``, wrinkled area (fraction) and z-intervals (mm),
            gaps (mm) and contact; the overall ``strain_bound`` and ``allowable_strain``
            (fractions) and the verdicts ``passes_strain``, ``passes_room``, ``passes``.
        """
        e = self.ends
        by_end = lambda f: {k: f(e[k]) for k in ENDS}  # noqa: E731
        return {
            "membrane": {
                "mid_radius_mm": self.mid_radius_mm,
                "free_length_mm": self.free_length_mm,
                "thickness_mm": self.thickness_mm,
                "shear_modulus_MPa": self.silicone.shear_modulus_MPa,
                "model": "incompressible neo-Hookean membrane, tension-field relaxed, clamped ends",
                "n_elements": self.n_elements,
            },
            "material": {"key": self.silicone_key, **self.silicone.to_dict()},
            "criterion": self.criterion.to_dict() if self.criterion else {"name": "given", "formula": "value"},
            "room": {
                "inner_tube_outer_radius_mm": self.inner_tube_outer_radius_mm,
                "outer_bore_radius_mm": self.outer_bore_radius_mm,
            },
            "volume_change_mm3": {k: float(self.volume_change_mm3[k]) for k in ENDS},
            "max_principal_strain": by_end(lambda s: s.max_principal_strain),
            "min_geometric_strain": by_end(lambda s: s.min_geometric_strain),
            "bending_strain": by_end(lambda s: s.bending_strain),
            "clamp_strain": by_end(lambda s: s.clamp_strain),
            "strain_bound_by_end": by_end(lambda s: s.strain_bound),
            "pressure_MPa": by_end(lambda s: s.pressure_MPa),
            "regularisation": by_end(lambda s: s.solution.regularisation),
            "wrinkled_area_fraction": by_end(lambda s: s.wrinkled_fraction),
            "wrinkled_z_mm": by_end(lambda s: s.slack_z_mm),
            "gap_inner_tube_mm": by_end(lambda s: s.gap_inner_tube_mm),
            "gap_outer_bore_mm": by_end(lambda s: s.gap_outer_bore_mm),
            "touches": by_end(lambda s: s.touches),
            "strain_bound": self.strain_bound,
            "allowable_strain": self.allowable_strain,
            "passes_strain": self.passes_strain,
            "passes_room": self.passes_room,
            "passes": self.passes,
            **self.extra,
        }


@dataclass(frozen=True, eq=False)
class BladderReport:
    """The bladder check of one design and the files written for it
    (:func:`~vvea_design.bladder.check.write_bladder_report`)."""

    result: BladderResult  #: the check written
    out_dir: Path | None  #: the folder written into (None: nothing written)
    files: Mapping[str, str]  #: by role (``json``, ``csv``, ``png``): file name in ``out_dir``

    def path(self, role: str) -> Path:
        """Where the file of ``role`` was written.

        Parameters
        ----------
        role : str
            ``"json"`` (bladder.json), ``"csv"`` (the profile along the meridian) or ``"png"`` (the figure).

        Returns
        -------
        Path
            ``out_dir / files[role]``.

        Raises
        ------
        KeyError
            For another role (the message lists the roles).
        """
        if role not in self.files:
            raise KeyError(f"no bladder file of role {role!r}; roles: {', '.join(self.files)}")
        return self.out_dir / self.files[role]

    def to_dict(self) -> dict:
        """The content of ``bladder.json``.

        Returns
        -------
        dict
            :meth:`BladderResult.to_dict` (units in the keys: mm, mm³, MPa, fractions) plus ``files``:
            the names of the JSON, CSV and PNG written, relative to ``out_dir``.
        """
        return {**self.result.to_dict(), "files": dict(self.files)}
