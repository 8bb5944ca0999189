"""The layout variants are a registry: one module each, found by the package; a new module is a new layout."""

import math
import sys
import textwrap

import numpy as np
import pytest

import vvea_design.spring.layouts as layouts
from vvea_design.spring.derive import Derived, derive
from vvea_design.spring.design import Design, DesignError, FixedParameters
from vvea_design.spring.layouts import LAYOUTS, DECISION_VARIABLES, discover, get_layout
from vvea_design.spring.layouts.base import LayoutVariant, register
from vvea_design.spring.problem import constraint_names, evaluate_design, evaluate_population
from vvea_design.spring.requirements import DEFAULT_BOUNDS, Requirements

#: A layout in a module of its own: the plain unit with a chamber-1 port volume in the top cap (its own gas,
#: taken from the bore column, and its own quantity). Nothing else is edited to add it.
PROBE = textwrap.dedent('''
    """probe_port: the inner tube with 500 mm³ of chamber-1 gas in a port in the top cap (a test layout)."""
    import numpy as np

    from vvea_design.spring.layouts.base import LayoutStack, LayoutVariant, register

    PORT_MM3 = 500.0


    @register
    class ProbePort(LayoutVariant):
        """Chamber 1 in the bore and in a port in the top cap."""

        name = "probe_port"
        summary = "inner_tube with a chamber-1 port in the top cap"
        order = 50
        chamber1_note = " plus the top-cap port"

        def stack(self, section, variables, fixed):
            port = PORT_MM3 * np.ones_like(section.A1_mm2)
            return LayoutStack(chamber1_elsewhere_mm3=(port,), quantities={"port_volume_mm3": port})
''')


@pytest.fixture()
def probe_layout(tmp_path, monkeypatch):
    """A layout module dropped into the package's search path (not into the source tree), then removed."""
    (tmp_path / "probe_port.py").write_text(PROBE)
    monkeypatch.setattr(layouts, "__path__", [*layouts.__path__, str(tmp_path)])
    yield "probe_port"
    LAYOUTS.pop("probe_port", None)
    sys.modules.pop("vvea_design.spring.layouts.probe_port", None)


def test_the_package_registers_its_layout_modules_in_their_order():
    assert list(LAYOUTS) == ["inner_tube", "bulkhead", "annulus_top"]
    assert all(isinstance(lay, LayoutVariant) and lay.name == name for name, lay in LAYOUTS.items())
    assert get_layout("bulkhead").decision_variables == DECISION_VARIABLES + ("V2_top_mm3",)
    assert get_layout("annulus_top").walls == ("outer_tube", "inner_tube", "top_cap", "base", "collar")
    assert get_layout(LAYOUTS["bulkhead"]) is LAYOUTS["bulkhead"]
    with pytest.raises(DesignError, match="unknown layout 'sideways'; known: inner_tube, bulkhead, annulus_top"):
        get_layout("sideways")
    # each layout's own variable has its default bounds from its module; the order is the layouts'
    assert list(DEFAULT_BOUNDS) == ["piston_diameter_mm", "outer_diameter_mm", "V1_mm3", "V2_mm3", "V2_top_mm3",
                                    "V1_annulus_mm3", "bladder_cast_fill"]


def test_a_new_layout_module_is_found_without_editing_another_file(probe_layout):
    assert probe_layout not in LAYOUTS
    discover()
    assert list(LAYOUTS)[-1] == probe_layout  # its declared order: after the three
    lay = get_layout(probe_layout)
    assert lay.decision_variables == DECISION_VARIABLES and lay.walls == LAYOUTS["inner_tube"].walls
    # the requirements, the design, the problem and the schema take it
    req = Requirements(layouts=("inner_tube", probe_layout))
    assert req.decision_variables(probe_layout) == DECISION_VARIABLES
    plain = Design(31.5, 59.3, 26000.0, 65000.0)  # feasible under the buildability rules
    d = Design(31.5, 59.3, 26000.0, 65000.0, layout=probe_layout)
    assert d.chamber1_length_mm == pytest.approx(plain.chamber1_length_mm - 500.0 / d.A1_mm2, rel=1e-12)
    assert d.housing_length_mm == pytest.approx(plain.housing_length_mm - 500.0 / d.A1_mm2, rel=1e-12)
    assert d.derived.layout_quantities["port_volume_mm3"] == 500.0
    assert d.walls_mm() == plain.walls_mm() and set(d.volume_budget_mm3()) == set(plain.volume_budget_mm3())
    X = np.array([plain.decision_vector() * s for s in (0.97, 1.0, 1.03)])
    obj, mar, ok = evaluate_population(X, req, probe_layout)
    ev = evaluate_design(d.with_charge(req.max_charge_MPa), req)
    assert ok[1] and obj[1] == pytest.approx(ev.objective, rel=1e-12)
    np.testing.assert_allclose(mar[:, 1], [ev.margins[n] for n in constraint_names(req, probe_layout, search=True)],
                               rtol=1e-10, atol=1e-12)
    from vvea_design.schema import design_schema

    assert probe_layout in design_schema()["properties"]["parameters"]["properties"]["layout"]["enum"]
    with pytest.raises(DesignError, match="plus the top-cap port"):
        Design(35.18, 59.5, 400.0, 99735.0, layout=probe_layout)


def test_a_layout_cannot_take_another_layouts_name_or_variables():
    class Impostor(LayoutVariant):
        name = "bulkhead"

    with pytest.raises(DesignError, match="registered twice"):
        register(Impostor)

    class Thief(LayoutVariant):
        name = "thief"
        own_variables = LAYOUTS["bulkhead"].own_variables

    with pytest.raises(DesignError, match="claims"):
        register(Thief)
    assert "thief" not in LAYOUTS and type(LAYOUTS["bulkhead"]).__name__ == "Bulkhead"
    with pytest.raises(DesignError, match="not a named LayoutVariant"):
        register(int)


def test_derive_is_typed_frozen_and_broadcast():
    f = FixedParameters()
    X = {"piston_diameter_mm": np.array([35.0, 35.4]), "outer_diameter_mm": 59.5, "V1_mm3": np.array([48e3, 49e3]),
         "V2_mm3": 102e3, "V2_top_mm3": np.array([3800.0, 0.0])}
    g = derive(X, 4.0, 0.0, f, "bulkhead")
    assert isinstance(g, Derived) and g.layout == "bulkhead"
    assert g.housing_length_mm.shape == (2,) and g.walls_mm["bulkhead"].shape == (2,)
    with pytest.raises(AttributeError):
        g.housing_length_mm = 0.0  # frozen
    d = g.to_dict()
    assert d["housing_length_mm"] is g.housing_length_mm and set(d["walls_mm"]) == set(get_layout("bulkhead").walls)
    one = Design(35.4, 59.5, 49e3, 102e3, layout="bulkhead", V2_top_mm3=0.0)
    assert one.derived.housing_length_mm == g.housing_length_mm[1] and isinstance(one.derived.housing_length_mm, float)
    assert one.derived.layout_quantities["top_space_length_mm"] == 0.0
    # the search leaves out what it does not read; the rest is the same
    lean = derive(X, 4.0, 0.0, f, "bulkhead", stresses=False, masses=False)
    assert lean.stresses_MPa is None and lean.masses_g is None and lean.mass_g is None
    np.testing.assert_array_equal(lean.housing_length_mm, g.housing_length_mm)
    with pytest.raises(DesignError, match="needs V2_top_mm3"):
        derive({k: v for k, v in X.items() if k != "V2_top_mm3"}, 4.0, 0.0, f, "bulkhead")
    assert math.isinf(Design(35.18, 59.5, 47107.0, 99735.0).cross_slot_room_mm)
