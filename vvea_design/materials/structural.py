"""Structural materials for the housing, rod and printed parts.

Values are typical handbook minima (yield) and densities; a requirements
file may name any key of :data:`STRUCTURAL` or give its own values.
Silicone casting compounds for the bladder live in :mod:`vvea_design.materials.silicones`
(bladder check).
"""

from __future__ import annotations

from dataclasses import dataclass

__all__ = ["Material", "STRUCTURAL", "get_material"]


@dataclass(frozen=True)
class Material:
    name: str
    density_g_per_mm3: float  #: g/mm³ (aluminium 2.70e-3)
    yield_MPa: float  #: 0.2 % proof stress, MPa
    youngs_modulus_MPa: float
    poisson: float
    source: str = ""


#: Keys usable in the requirements file (``[materials] housing = "..."``).
STRUCTURAL: dict[str, Material] = {
    "al-6061-t6": Material("Aluminium 6061-T6", 2.70e-3, 276.0, 68.9e3, 0.33, "ASM Handbook / MatWeb, 6061-T6 typical"),
    "al-7075-t6": Material("Aluminium 7075-T6", 2.81e-3, 503.0, 71.7e3, 0.33, "ASM Handbook / MatWeb, 7075-T6 typical"),
    "steel-1.4305": Material("Stainless steel 1.4305 (303)", 7.90e-3, 190.0, 193e3, 0.29, "EN 10088-3, annealed min."),
    "steel-42crmo4": Material("Steel 42CrMo4 QT", 7.85e-3, 650.0, 210e3, 0.29, "EN 10083-3, QT, d<=16 mm"),
    "pa12-sls": Material("PA12 (SLS printed)", 1.01e-3, 48.0, 1.7e3, 0.40, "EOS PA 2200 datasheet, tensile strength"),
    "pla": Material("PLA (FDM printed)", 1.24e-3, 50.0, 3.5e3, 0.36, "typical FDM PLA datasheet"),
}

#: Densities of non-structural media, g/mm³.
DENSITY_SILICONE_g_per_mm3 = 1.10e-3
DENSITY_HYDRAULIC_OIL_g_per_mm3 = 0.87e-3


def get_material(key: str) -> Material:
    """Look a structural material up by key, with a clear error for unknown keys.

    Parameters
    ----------
    key : str
        A key of :data:`STRUCTURAL`, e.g. ``"al-6061-t6"``.

    Returns
    -------
    Material
        The material (density in g/mm³, yield stress and Young's modulus in MPa).

    Raises
    ------
    ValueError
        If ``key`` is unknown; the message lists the known keys.
    """
    try:
        return STRUCTURAL[key]
    except KeyError:
        raise ValueError(
            f"unknown material {key!r}; known: {', '.join(sorted(STRUCTURAL))}"
        ) from None
