"""One palette for every picture the toolkit makes: figures, CAD renders and the report's 3-D view.

A colour means one thing everywhere:

* **settings** of the actuator studies (:data:`SETTING_COLOURS`): the design, the paper's VVEA,
  iVVEA, SEA and LWR; other settings or cases take :data:`OTHER_COLOURS` in order;
* **parts** of the unit and its mould (:data:`PART_COLOURS`): the housing pieces, piston, bladder,
  support ring, the gas of chamber 1 (blue) and chamber 2 (red, the paper's Fig. 2), the fluid
  column, the mould halves and the core; the CAD part table colours the STEP and glTF files with the
  same values;
* **gas laws** of the spring curves (:data:`GAS_LAW_STYLES`): isothermal (n = 1) solid, adiabatic
  (n = 1.4) dashed;
* **limits** (:data:`LIMIT_COLOUR`): an allowable value, a requirement no design meets.

Colours are matplotlib colour strings (``"#rrggbb"``) for settings and gas laws and RGB triples
(0..1) for parts; :func:`part_hex` gives a part's ``"#rrggbb"`` for HTML and three.js.
"""

from __future__ import annotations

__all__ = ["SETTING_COLOURS", "OTHER_COLOURS", "PART_COLOURS", "PART_LABELS", "GAS_LAW_STYLES",
           "FIXED_DAMPING_STYLES", "LIMIT_COLOUR", "setting_colour", "part_colour", "part_hex", "gas_law",
           "gas_law_label"]

#: Colour of each named actuator setting, in every actuator figure.
SETTING_COLOURS: dict[str, str] = {
    "design": "#d62728",  # red
    "VVEA": "#9467bd",  # purple
    "iVVEA": "#ff7f0e",  # orange
    "SEA": "#1f77b4",  # blue
    "LWR": "#7f7f7f",  # grey
}
#: Colours of settings or cases without a colour of their own (fixed-damping torque steps, user settings),
#: taken in order; none of them is a setting's, a part's or a gas law's colour.
OTHER_COLOURS: tuple[str, ...] = ("#2ca02c", "#17becf", "#bcbd22", "#e377c2", "#393b79")
#: Colour of a limit, an allowable value or a violation (a requirement no design meets), as the report's FAIL.
LIMIT_COLOUR = "#b00020"
#: Line styles of fixed-damping cases, in order (a variable-damping case is drawn solid).
FIXED_DAMPING_STYLES: tuple = ("--", "-.", (0, (1, 1.5)), (0, (5, 2, 1, 2, 1, 2)))

_HOUSING_GREY = (0.72, 0.74, 0.78)
_MOULD_BLUE = (0.55, 0.75, 0.95)

#: Colour (RGB 0..1) of each part of the unit and its mould, in every render and the 3-D view.
PART_COLOURS: dict[str, tuple[float, float, float]] = {
    "housing": _HOUSING_GREY,
    "housing_base": (0.66, 0.68, 0.72),
    "housing_outer_tube": (0.78, 0.80, 0.84),
    "housing_inner_tube": (0.60, 0.62, 0.66),
    "housing_top_cap": (0.70, 0.72, 0.76),
    "piston": (0.45, 0.47, 0.52),
    "bladder": (0.95, 0.75, 0.20),
    "support_ring": (0.15, 0.15, 0.15),
    "gas_chamber_1": (0.20, 0.40, 0.95),
    "gas_chamber_2": (0.95, 0.25, 0.20),
    "fluid": (0.25, 0.75, 0.35),
    "mould_half_a": _MOULD_BLUE,
    "mould_half_b": _MOULD_BLUE,
    "mould_core": (0.85, 0.85, 0.85),
}
#: How a part is named in legends and labels.
PART_LABELS: dict[str, str] = {
    "housing": "housing", "housing_base": "housing base", "housing_outer_tube": "outer tube",
    "housing_inner_tube": "inner tube", "housing_top_cap": "top cap", "piston": "piston with rod",
    "bladder": "bladder (silicone)", "support_ring": "support ring", "gas_chamber_1": "gas, chamber 1",
    "gas_chamber_2": "gas, chamber 2", "fluid": "fluid column", "mould_half_a": "mould half A (pins)",
    "mould_half_b": "mould half B (pin holes)", "mould_core": "mould core",
}

#: Colour and line style of each gas law in the spring figures.
GAS_LAW_STYLES: dict[str, dict[str, str]] = {
    "isothermal": {"color": "#1f3a5f", "ls": "-"},  # navy, solid
    "adiabatic": {"color": "#8c564b", "ls": "--"},  # brown, dashed
    "polytropic": {"color": "#6b6ecf", "ls": "-."},  # any other exponent
}


def setting_colour(name: str, i: int = 0) -> str:
    """The colour of an actuator setting.

    Parameters
    ----------
    name : str
        Setting name (``"design"``, ``"VVEA"``, ``"iVVEA"``, ``"SEA"``, ``"LWR"``, or any other).
    i : int
        Index of the setting among those without a colour of their own (count, from 0): picks
        :data:`OTHER_COLOURS` in turn.

    Returns
    -------
    str
        ``"#rrggbb"``.
    """
    return SETTING_COLOURS.get(name, OTHER_COLOURS[i % len(OTHER_COLOURS)])


def part_colour(name: str) -> tuple[float, float, float]:
    """The colour of a part of the unit or its mould.

    Parameters
    ----------
    name : str
        Part name as in the CAD part table (``"gas_chamber_2"``, ``"mould_core"``, ...) or ``"fluid"``.

    Returns
    -------
    tuple of float
        RGB, each 0..1 (dimensionless).

    Raises
    ------
    KeyError
        For a name the palette does not know (the message lists the names it knows).
    """
    try:
        return PART_COLOURS[name]
    except KeyError:
        raise KeyError(f"no palette colour for part {name!r}; parts: {sorted(PART_COLOURS)}") from None


def part_hex(name: str) -> str:
    """The colour of a part as ``"#rrggbb"`` (HTML, three.js).

    Parameters
    ----------
    name : str
        Part name, as for :func:`part_colour`.

    Returns
    -------
    str
        ``"#rrggbb"``, each channel rounded to the nearest of 0..255.
    """
    return "#" + "".join(f"{round(255 * c):02x}" for c in part_colour(name))


def gas_law(n_polytropic: float) -> str:
    """The gas law of a polytropic exponent.

    Parameters
    ----------
    n_polytropic : float
        Exponent n of p V^n = const (dimensionless).

    Returns
    -------
    str
        ``"isothermal"`` for n = 1, ``"adiabatic"`` for n = 1.4 (air, nitrogen), else ``"polytropic"``;
        a key of :data:`GAS_LAW_STYLES`.
    """
    if abs(n_polytropic - 1.0) < 1e-9:
        return "isothermal"
    if abs(n_polytropic - 1.4) < 1e-9:
        return "adiabatic"
    return "polytropic"


def gas_law_label(n_polytropic: float) -> str:
    """How a legend names the gas law of an exponent, e.g. ``"isothermal (n = 1)"``.

    Parameters
    ----------
    n_polytropic : float
        Exponent n of p V^n = const (dimensionless).

    Returns
    -------
    str
        ``"isothermal (n = 1)"``, ``"adiabatic (n = 1.4)"`` or ``"polytropic (n = 1.2)"``.
    """
    return f"{gas_law(n_polytropic)} (n = {n_polytropic:g})"
