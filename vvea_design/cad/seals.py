"""O-ring seals: the ISO 3601-1 (= AS568) inch-series sizes and the dynamic
gland that holds them; the piston and rod seal grooves of the CAD are sized
here, so the drawing, the bill of materials and the solids name the same ring.

Sizes: ISO 3601-1 class A, cross-sections 1.78 mm (sizes 004-050) and
2.62 mm (102-150); inner diameters in mm as in the standard (AS568 dash
numbers are the same rings). Glands: reciprocating (dynamic) glands without
back-up ring, radial depth and axial width as recommended by the seal makers'
design guides (Apple Rubber Seal Design Guide; Parker O-Ring Handbook
ORD 5700 gives the same to 0.03 mm) -- initial design values, not a
verification against ISO 3601-2.

Selection (:func:`piston_gland`, :func:`rod_gland`):

* piston (male gland, groove in the piston): groove root diameter =
  bore - 2 x depth; the ring's inner diameter is stretched onto the root by
  0 ... 5 % (the size closest to 2 % is taken);
* rod (female gland, groove in the housing bore): groove outer diameter =
  rod + 2 x depth; the ring's inner diameter sits on the rod with 0 ... 5 %
  stretch (closest to 1 %).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

__all__ = ["ORing", "Gland", "ORING_SIZES", "DYNAMIC_GLANDS", "get_oring", "piston_gland", "rod_gland",
           "SealError"]


class SealError(ValueError):
    """No standard O-ring fits (names the diameter and cross-section)."""


#: ISO 3601-1 sizes: code -> (inner diameter, cross-section), mm.
ORING_SIZES: dict[str, tuple[float, float]] = {
    **{code: (d, 1.78) for code, d in zip(
        [f"{k:03d}" for k in range(4, 51)],
        [1.78, 2.57, 2.90, 3.68, 4.47, 5.28, 6.07, 7.65, 9.25, 10.82, 12.42, 14.00, 15.60, 17.17, 18.77, 20.35,
         21.95, 23.52, 25.12, 26.70, 28.30, 29.87, 31.47, 33.05, 34.65, 37.82, 41.00, 44.17, 47.35, 50.52, 53.70,
         56.87, 60.05, 63.22, 66.40, 69.57, 72.75, 75.92, 82.27, 88.62, 94.97, 101.32, 107.67, 114.02, 120.37,
         126.72, 133.07], strict=True)},
    **{code: (d, 2.62) for code, d in zip(
        [f"{k:03d}" for k in range(102, 151)],
        [1.24, 2.06, 2.84, 3.63, 4.42, 5.23, 6.02, 7.59, 9.19, 10.77, 12.37, 13.94, 15.54, 17.12, 18.72, 20.29,
         21.89, 23.47, 25.07, 26.64, 28.24, 29.82, 31.42, 32.99, 34.59, 36.17, 37.77, 39.34, 40.94, 42.52, 44.12,
         45.69, 47.29, 48.90, 50.47, 52.07, 53.64, 55.25, 56.82, 58.42, 59.99, 61.60, 63.17, 64.77, 66.34, 67.95,
         69.52, 71.12, 72.69], strict=True)},
}

#: Dynamic gland without back-up ring per cross-section (mm, %): depth min, depth max, groove width,
#: squeeze min %, squeeze max % (the groove depth may leave [depth min, depth max] to seat a standard
#: ring, never the squeeze window).
DYNAMIC_GLANDS: dict[float, tuple[float, float, float, float, float]] = {
    1.78: (1.40, 1.45, 2.41, 15.0, 25.0),
    2.62: (2.21, 2.29, 3.68, 10.0, 18.0),
}


@dataclass(frozen=True)
class ORing:
    """One standard O-ring (mm)."""

    code: str  #: ISO 3601-1 size code (= AS568 dash number)
    inner_diameter_mm: float
    cross_section_mm: float

    @property
    def name(self) -> str:
        """Order name, e.g. ``ISO 3601-1 026 (AS568-026), 31.47 x 1.78 mm``."""
        return (f"ISO 3601-1 {self.code} (AS568-{self.code}), "
                f"{self.inner_diameter_mm:.2f} x {self.cross_section_mm:.2f} mm")

    def to_dict(self) -> dict:
        """Plain-JSON dictionary of the ring.

        Returns
        -------
        dict
            JSON-ready: ``name`` (order name), ``code`` (ISO 3601-1 / AS568 size code),
            ``inner_diameter_mm`` and ``cross_section_mm`` (mm) and ``standard``.
        """
        return {"name": self.name, "code": self.code, "inner_diameter_mm": self.inner_diameter_mm,
                "cross_section_mm": self.cross_section_mm, "standard": "ISO 3601-1 class A / AS568"}


@dataclass(frozen=True)
class Gland:
    """A seal groove and its O-ring (mm): where it sits and how much the ring is squeezed."""

    kind: str  #: "piston" (groove in the piston), "rod" (groove in the housing bore) or "collar" (static, in the
    #: annulus_top collar's rim against the outer-tube bore: the piston's male gland rules)
    oring: ORing
    depth_mm: float  #: radial groove depth (from the sliding diameter)
    width_mm: float  #: axial groove width
    sliding_diameter_mm: float  #: bore (piston) or rod diameter the seal runs on
    groove_diameter_mm: float  #: root diameter (piston) or outer diameter (rod)

    @property
    def stretch(self) -> float:
        """Installed inner-diameter stretch of the ring (fraction)."""
        seat = self.groove_diameter_mm if self.kind in ("piston", "collar") else self.sliding_diameter_mm
        return seat / self.oring.inner_diameter_mm - 1.0

    @property
    def squeeze(self) -> float:
        """Nominal radial squeeze (cross-section - gland depth) / cross-section, fraction."""
        return (self.oring.cross_section_mm - self.depth_mm) / self.oring.cross_section_mm

    @property
    def fill(self) -> float:
        """Groove fill: ring cross-section area / groove area (fraction, < 0.9 wanted)."""
        return math.pi / 4 * self.oring.cross_section_mm**2 / (self.depth_mm * self.width_mm)

    def to_dict(self) -> dict:
        """Plain-JSON dictionary of the gland, its ring and its fit.

        Returns
        -------
        dict
            JSON-ready: ``kind`` (``"piston"``, ``"rod"`` or ``"collar"``), ``oring`` (:meth:`ORing.to_dict`),
            ``depth_mm``, ``width_mm``, ``sliding_diameter_mm``, ``groove_diameter_mm`` (mm) and the
            fractions ``stretch``, ``squeeze`` and ``fill``.
        """
        return {"kind": self.kind, "oring": self.oring.to_dict(), "depth_mm": self.depth_mm,
                "width_mm": self.width_mm, "sliding_diameter_mm": self.sliding_diameter_mm,
                "groove_diameter_mm": self.groove_diameter_mm, "stretch": self.stretch,
                "squeeze": self.squeeze, "fill": self.fill}


def get_oring(code: str) -> ORing:
    """The O-ring of an ISO 3601-1 size.

    Parameters
    ----------
    code : str
        Size code (``"026"``, ``"-026"`` or ``"26"``).

    Returns
    -------
    ORing
        Inner diameter and cross-section in mm.

    Raises
    ------
    SealError
        For a code not in the table.
    """
    key = str(code).strip().lstrip("-").zfill(3)
    if key not in ORING_SIZES:
        raise SealError(f"unknown O-ring size {code!r}; known: {min(ORING_SIZES)} ... {max(ORING_SIZES)}")
    d, w = ORING_SIZES[key]
    return ORing(key, d, w)


def _series(preferred_mm: float) -> list[float]:
    if preferred_mm not in DYNAMIC_GLANDS:
        raise SealError(f"no dynamic gland data for an O-ring cross-section of {preferred_mm:g} mm; "
                        f"known: {', '.join(f'{w:g}' for w in DYNAMIC_GLANDS)} mm")
    return [preferred_mm] + [w for w in DYNAMIC_GLANDS if w != preferred_mm]


def piston_gland(bore_mm: float, cross_section_mm: float = 1.78) -> Gland:
    """Piston seal groove (male dynamic gland) and its O-ring.

    Takes the ring and groove root with the gland depth closest to the
    recommended one, inside the squeeze window, and 0 ... 5 % stretch (closest
    to 2 %); the preferred cross-section first, the other series if none fits.

    Parameters
    ----------
    bore_mm : float
        Bore the piston runs in, mm.
    cross_section_mm : float
        Preferred O-ring cross-section, mm (1.78 or 2.62).

    Returns
    -------
    Gland
        Ring, groove depth and width, root diameter (mm), stretch and squeeze.

    Raises
    ------
    SealError
        When no ring of either series fits.
    """
    for w in _series(cross_section_mm):
        dmin, dmax, width, sq_lo, sq_hi = DYNAMIC_GLANDS[w]
        d_nom = 0.5 * (dmin + dmax)
        depth_lo, depth_hi = w * (1 - sq_hi / 100), w * (1 - sq_lo / 100)
        best = None
        for code, (d_in, w_ring) in ORING_SIZES.items():
            if w_ring != w:
                continue
            root_lo, root_hi = max(d_in, bore_mm - 2 * depth_hi), min(1.05 * d_in, bore_mm - 2 * depth_lo)
            if root_lo > root_hi + 1e-12:
                continue
            root = min(max(bore_mm - 2 * d_nom, root_lo), root_hi)
            score = (round(abs((bore_mm - root) / 2 - d_nom), 6), abs(root / d_in - 1.02))
            if best is None or score < best[0]:
                best = (score, code, root)
        if best is not None:
            _, code, root = best
            return Gland("piston", get_oring(code), round((bore_mm - root) / 2, 6), width, bore_mm, root)
    raise SealError(f"no ISO 3601-1 O-ring ({', '.join(f'{w:g}' for w in DYNAMIC_GLANDS)} mm series) seals a "
                    f"piston in a Ø{bore_mm:.2f} mm bore with 0-5 % stretch inside the squeeze window")


def rod_gland(rod_mm: float, cross_section_mm: float = 1.78) -> Gland:
    """Rod seal groove in the housing (female dynamic gland) and its O-ring.

    The ring's inner diameter sits on the rod with 0 ... 5 % stretch (closest
    to 1 %); the groove depth is the recommended one.

    Parameters
    ----------
    rod_mm : float
        Rod diameter, mm.
    cross_section_mm : float
        Preferred O-ring cross-section, mm (1.78 or 2.62).

    Returns
    -------
    Gland
        Ring, groove depth and width, groove outer diameter (mm), stretch and squeeze.

    Raises
    ------
    SealError
        When no ring of either series seats on the rod.
    """
    for w in _series(cross_section_mm):
        dmin, dmax, width, _, _ = DYNAMIC_GLANDS[w]
        depth = round(0.5 * (dmin + dmax), 6)
        best = None
        for code, (d_in, w_ring) in ORING_SIZES.items():
            s = rod_mm / d_in - 1.0
            if w_ring == w and -1e-9 <= s <= 0.05 and (best is None or abs(s - 0.01) < best[0]):
                best = (abs(s - 0.01), code)
        if best is not None:
            return Gland("rod", get_oring(best[1]), depth, width, rod_mm, rod_mm + 2 * depth)
    raise SealError(f"no ISO 3601-1 O-ring seats on a Ø{rod_mm:.2f} mm rod with 0-5 % stretch")
