"""One palette (vvea_design.palette) for every figure, render and the report's 3-D view; margins that are
round-off of zero read 0 (vvea_design.messages.show_margin)."""

import ast
import re
from types import SimpleNamespace

import numpy as np
import pytest
from matplotlib.colors import to_hex, to_rgb

from tests.helpers import REPO
from vvea_design import palette
from vvea_design.messages import MARGIN_TOL, show_margin


# ------------------------------------------------------------------ the palette itself
def test_the_cad_part_table_colours_the_files_as_the_palette_draws_them():
    """STEP and glTF colours come from the CAD part table; every picture from the palette: the same values."""
    from vvea_design.cad.registry import FLUID_COLOUR, PARTS

    for p in PARTS:
        assert palette.part_colour(p.name) == pytest.approx(p.colour), p.name
    assert palette.part_colour("fluid") == pytest.approx(FLUID_COLOUR)
    assert set(palette.PART_LABELS) == set(palette.PART_COLOURS)


def test_one_colour_means_one_thing():
    settings = set(palette.SETTING_COLOURS.values())
    assert len(settings) == len(palette.SETTING_COLOURS)  # one colour per setting
    others = set(palette.OTHER_COLOURS)
    laws = {s["color"] for s in palette.GAS_LAW_STYLES.values()}
    parts = {to_hex(c) for c in palette.PART_COLOURS.values()}
    for a, b in ((settings, others), (settings, laws), (others, laws), (settings, parts), (laws, parts),
                 (others, parts), ({palette.LIMIT_COLOUR}, settings | others | laws | parts)):
        assert not a & b
    assert palette.part_colour("gas_chamber_1") != palette.part_colour("gas_chamber_2")
    assert palette.part_hex("gas_chamber_2") == "#f24033"  # red, as the cut-away (the paper's Fig. 2)
    assert to_rgb(palette.part_hex("bladder")) == pytest.approx(palette.part_colour("bladder"), abs=1 / 255)
    assert palette.setting_colour("design") == "#d62728" and palette.setting_colour("mine", 1) == palette.OTHER_COLOURS[1]
    assert [palette.gas_law(n) for n in (1.0, 1.4, 1.2)] == ["isothermal", "adiabatic", "polytropic"]
    assert palette.gas_law_label(1.4) == "adiabatic (n = 1.4)"
    with pytest.raises(KeyError, match="parts"):
        palette.part_colour("flux capacitor")


#: Modules that draw settings, parts or gas laws: their colours come from the palette, none is written out.
DRAWING_MODULES = ["vvea_design/actuator/figures.py", "vvea_design/spring/plots.py", "vvea_design/cad/render.py",
                   "vvea_design/report/html/unit.py", "vvea_design/report/html/viewer.py"]
_COLOUR_STRING = re.compile(r"^(#[0-9a-fA-F]{6}|tab:\w+|C\d|red|green|blue|orange|purple|brown|pink|cyan|magenta)$")
_FORMAT_STRING = re.compile(r"^[rgbcmy][-.:ox*+sd^v]{0,3}$")  # "r*", "g--", "b": a plot format with a colour
_COLOUR_KEYWORDS = {"color", "colors", "colour", "c", "facecolor", "edgecolor", "mfc", "mec", "shape_color"}


def colour_literals(source: str) -> list[str]:
    """Colour specs written into ``source``: colour strings (hex, ``tab:``, ``C0``, chromatic names) anywhere,
    one-letter colours and plot format strings with a colour letter given to a colour keyword or a plot call,
    and RGB tuples of unequal channels given to a colour keyword. Black, white and greys are allowed (they
    draw no setting, part or gas law)."""
    found = []
    for node in ast.walk(ast.parse(source)):
        if isinstance(node, ast.Constant) and isinstance(node.value, str) and _COLOUR_STRING.match(node.value):
            found.append(f"line {node.lineno}: {node.value!r}")
        elif isinstance(node, ast.Call):
            name = getattr(node.func, "attr", getattr(node.func, "id", ""))
            args = node.args[1:] if name in ("plot", "step", "loglog", "semilogy", "semilogx") else []
            for a in args:
                if isinstance(a, ast.Constant) and isinstance(a.value, str) and _FORMAT_STRING.match(a.value):
                    found.append(f"line {a.lineno}: {a.value!r}")
            for kw in node.keywords:
                if kw.arg not in _COLOUR_KEYWORDS:
                    continue
                v = kw.value
                if isinstance(v, ast.Constant) and isinstance(v.value, str) and _FORMAT_STRING.match(v.value):
                    found.append(f"line {v.lineno}: {v.value!r}")
                elif isinstance(v, ast.Tuple):
                    vals = [e.value for e in v.elts if isinstance(e, ast.Constant)]
                    if len(vals) >= 3 and len(set(vals[:3])) > 1:
                        found.append(f"line {v.lineno}: {tuple(vals)}")
    return found


def test_the_scan_finds_written_out_colours():
    src = 'ax.plot(x, y, color="tab:red")\nax.plot(x, y, "r*")\nax.bar(x, y, color=(0.9, 0.1, 0.1))\n' \
          'ax.plot(x, y, color="k", ls="--")\nax.plot(x, y, color="0.5")\nm = palette.part_colour("bladder")\n' \
          'label = f"{x:g} mm"\nax.grid(axis="y")\n'  # neutral colours, format specs and axis names are no colours
    assert sorted(f.split(":")[0] for f in colour_literals(src)) == ["line 1", "line 2", "line 3"]


@pytest.mark.parametrize("module", DRAWING_MODULES)
def test_drawing_modules_take_their_colours_from_the_palette(module):
    source = (REPO / module).read_text()
    assert colour_literals(source) == [], f"{module} writes colours out instead of taking the palette's"
    assert "palette" in source


# ------------------------------------------------------------------ figures drawn in the palette's colours
def _trajectory(name, A=0.5, T=0.8, n=16):
    t = np.linspace(0, 2 * T, n + 1)
    return SimpleNamespace(t_s=t, q_rad=A * (t > T / 2), tau_m_Nm=np.full(n, 10.0), D_Nms_per_rad=np.full(n + 1, 12.1),
                           tau_Nm=50 * (1 - np.exp(-t / 0.01)), extra={"rmse_rad": 0.05, "mean_D_Nms_per_rad": 20.0,
                                                                       "t95_s": 0.005})


def _line_colours(ax):
    return {ln.get_label(): to_hex(ln.get_color()) for ln in ax.get_lines() if not ln.get_label().startswith("_")}


def test_trajectory_figure_colours_and_a_legend_that_covers_no_trace():
    from matplotlib.backends.backend_agg import FigureCanvasAgg

    from vvea_design.actuator.figures import plot_trajectory

    best = {n: _trajectory(n) for n in ("design", "VVEA", "SEA", "LWR")}
    fig = plot_trajectory(best, 0.5, 0.8, highlight="design")
    got = _line_colours(fig.axes[0])
    for n in best:
        assert got[f"{n} (rmse 0.0500 rad)"] == palette.SETTING_COLOURS[n]
    FigureCanvasAgg(fig).draw()
    r = fig.canvas.get_renderer()
    legend = fig.axes[0].get_legend().get_window_extent(r)
    for ax in fig.axes:  # right of every panel: it hides no trace (it covered SEA's)
        assert legend.x0 >= ax.get_window_extent(r).x1
    assert legend.x1 <= fig.bbox.x1 + 1  # and inside the picture


def test_torque_step_draws_each_setting_in_its_colour_and_fixed_damping_dashed():
    from vvea_design.actuator.figures import plot_safety

    res = {"design, variable D": _trajectory("d"), "VVEA, variable D": _trajectory("v"),
           "design, fixed D 31": _trajectory("f")}
    fig = plot_safety(res, 50.0)
    lines = {ln.get_label(): ln for ln in fig.axes[4].get_lines()}  # damping panel, full horizon
    assert to_hex(lines["design, variable D"].get_color()) == palette.SETTING_COLOURS["design"]
    assert to_hex(lines["VVEA, variable D"].get_color()) == palette.SETTING_COLOURS["VVEA"]
    fixed = lines["design, fixed D 31"]
    assert to_hex(fixed.get_color()) == palette.OTHER_COLOURS[0] and fixed.get_linestyle() == "--"
    # the paper's study: names without a setting are the base setting's
    fig = plot_safety({"variable D 12.1-200": _trajectory("v"), "fixed D 31": _trajectory("f"),
                       "fixed D 200": _trajectory("g")}, 50.0, base_setting="VVEA")
    lines = {ln.get_label(): ln for ln in fig.axes[4].get_lines()}
    assert to_hex(lines["variable D 12.1-200"].get_color()) == palette.SETTING_COLOURS["VVEA"]
    assert to_hex(lines["fixed D 31"].get_color()) == palette.OTHER_COLOURS[0]  # as in the design's figure
    assert lines["fixed D 31"].get_linestyle() != lines["fixed D 200"].get_linestyle()


def test_design_map_bars_in_the_settings_colours():
    import pandas as pd

    from vvea_design.actuator.figures import plot_design_map
    from vvea_design.actuator.model import PAPER_SETTINGS

    rows = []
    for s, v in dict(design=0.9, VVEA=1.0, SEA=2.0).items():
        a = PAPER_SETTINGS.get(s, PAPER_SETTINGS["VVEA"])
        rows.append(dict(case_id="c1", setting=s, A_rad=1.0, T_s=1.0, rmse=v, valid=True, success=True, verified=True,
                         D_min_Nms_per_rad=a.D_min_Nms_per_rad, D_max_Nms_per_rad=a.D_max_Nms_per_rad))
    fig = plot_design_map(pd.DataFrame(rows), "design", ["VVEA", "SEA"])
    bars = fig.axes[1].patches
    assert [to_hex(b.get_facecolor()) for b in bars] == [palette.SETTING_COLOURS[n] for n in ("design", "VVEA", "SEA")]


def test_spring_figure_gas_laws_chambers_and_recharges_told_apart():
    from vvea_design.spring.gas_spring import PAPER_FIG5
    from vvea_design.spring.plots import plot_spring

    own = PAPER_FIG5.p2_MPa
    fig = plot_spring(PAPER_FIG5, extra_charges_MPa=(1.0, 2.0, own), layout="inner_tube")
    force, pressures = fig.axes[0], fig.axes[3]
    lines = {ln.get_label(): ln for ln in force.get_lines() if not ln.get_label().startswith("_")}
    iso = next(ln for lab, ln in lines.items() if lab.startswith("F(x), isothermal (n = 1)"))
    adi = next(ln for lab, ln in lines.items() if lab.startswith("F(x), adiabatic (n = 1.4)"))
    assert to_hex(iso.get_color()) == palette.GAS_LAW_STYLES["isothermal"]["color"] and iso.get_linestyle() == "-"
    assert to_hex(adi.get_color()) == palette.GAS_LAW_STYLES["adiabatic"]["color"] and adi.get_linestyle() == "--"
    assert f"charge p2 = {own:g} MPa" in iso.get_label()  # the own charge is the nominal curve, drawn once
    recharged = [ln for lab, ln in lines.items() if lab.startswith("recharged")]
    assert len(recharged) == 2  # 1 and 2 MPa; not the own charge again
    greys = {to_hex(ln.get_color()) for ln in recharged}
    assert len(greys) == 2 and not greys & {to_hex(iso.get_color()), to_hex(adi.get_color())}
    assert all(ln.get_linestyle() != "-" for ln in recharged)  # none looks like the nominal curve
    assert {t.get_text() for t in force.texts} >= {"p2 = 1 MPa", "p2 = 2 MPa"}  # labelled at their ends
    chambers = _line_colours(pressures)
    assert chambers["chamber 1 (expands), isothermal (n = 1)"] == palette.part_hex("gas_chamber_1")
    assert chambers["chamber 2 (compressed), adiabatic (n = 1.4)"] == palette.part_hex("gas_chamber_2")
    assert "inner_tube layout" in fig._suptitle.get_text() and "isothermal" in fig._suptitle.get_text()


def test_3d_view_parts_take_the_palettes_colours_and_names(tmp_path):
    import trimesh

    from vvea_design.report.html import viewer, viewer_parts_from_cad

    for name in ("housing", "gas_chamber_2", "mould_half_a", "mould_half_b", "mould_core"):
        trimesh.creation.box(extents=(1, 2, 3)).export(tmp_path / f"{name}.stl")
    parts = {p.name: p for p in viewer_parts_from_cad(tmp_path)}
    assert set(parts) == {"housing", "gas_chamber_2", "mould_half_a", "mould_half_b", "mould_core"}
    for name, p in parts.items():
        assert p.color == palette.part_hex(name) and p.label == palette.PART_LABELS[name]
    assert parts["mould_half_a"].callout and not parts["housing"].callout  # the halves share a colour: named in view
    block, _ = viewer(list(parts.values()))
    assert 'id="viewer-labels"' in block
    for name in ("mould_half_a", "mould_half_b", "mould_core"):  # the mould view's legend
        assert f'data-group="mould"><i style="background:{palette.part_hex(name)}"></i>' \
               f'{palette.PART_LABELS[name]}' in block.replace("&#x27;", "'")


def test_the_cutaway_and_mould_renders_take_the_palettes_colours(monkeypatch):
    """The renders ask the palette for every colour they draw (recorded, no CAD built)."""
    import vvea_design.cad.render as render

    asked = []
    monkeypatch.setattr(render, "part_colour", lambda name: asked.append(name) or palette.part_colour(name))

    class Poly:
        bounds = (0.0, 1.0, 0.0, 1.0, 0.0, 1.0)

        def translate(self, *a, **k):
            return self

        def rotate_z(self, *a, **k):
            return self

    class Plotter:
        def __init__(self, **k):
            self.renderer = SimpleNamespace(SetWorldPoint=lambda *a: None, WorldToDisplay=lambda: None,
                                            GetDisplayPoint=lambda: (10.0, 10.0, 0.0))

        def add_mesh(self, poly, color=None, **k):
            assert color is not None

        def __getattr__(self, name):
            return lambda *a, **k: np.zeros((900, 1400, 3), dtype=np.uint8)

    monkeypatch.setattr(render, "_pv", lambda: SimpleNamespace(Plotter=Plotter))
    monkeypatch.setattr(render, "_poly", lambda mesh: Poly())
    monkeypatch.setattr("vvea_design.cad.mesh.to_mesh", lambda *a: None)
    model = SimpleNamespace(mould=SimpleNamespace(block_mm=(0.0, 10.0), cavity=None))
    png = render.render_mould_open(model, {"mould_half_a": 0, "mould_half_b": 0, "mould_core": 0})
    assert png[:4] == b"\x89PNG"
    assert {"mould_half_a", "mould_half_b", "mould_core", "bladder"} <= set(asked)


# ------------------------------------------------------------------ margins: round-off reads 0
def test_show_margin_writes_round_off_as_zero():
    assert show_margin(-4.29e-16) == "0" and show_margin(3.2e-15, "+.4f") == "0"
    assert show_margin(-2e-16, "+.4f") == "0"  # not "-0.0000"
    assert show_margin(0.05102) == "0.05102" and show_margin(-0.25, "+.4f") == "-0.2500"
    assert show_margin(-2 * MARGIN_TOL, "+.1e") == "-2.0e-09"  # a real violation keeps its sign
    assert show_margin(float("nan")) == "nan" and show_margin(np.float64(1e-10)) == "0"

