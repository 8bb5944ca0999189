"""The main job end to end: `vvea design` = pipeline.design_unit, with the requirements' silicone."""

import json
from dataclasses import replace

import numpy as np
import pytest
from typer.testing import CliRunner

from vvea_design.cli.main import app
from vvea_design.pipeline import STEPS, spring_curve
from vvea_design.spring.gas_spring import GasSpring

runner = CliRunner()


@pytest.fixture(scope="module")
def ecoflex_run(tmp_path_factory):
    """`vvea design --spec F` with bladder_material = "ecoflex-00-30", no renders (the whole chain, ~20 s)."""
    tmp = tmp_path_factory.mktemp("design")
    spec = tmp / "req.toml"
    spec.write_text('bladder_material = "ecoflex-00-30"\n')
    out = tmp / "out"
    res = runner.invoke(app, ["design", "--spec", str(spec), "-o", str(out), "--no-renders"])
    return res, out, spec


def test_design_checks_the_requirements_silicone(ecoflex_run):
    res, out, _ = ecoflex_run
    assert res.exit_code == 0, res.output
    bl = json.loads((out / "bladder" / "bladder.json").read_text())
    assert bl["material"]["key"] == "ecoflex-00-30"
    assert bl["material"]["name"] == "Ecoflex 00-30"
    unit = json.loads((out / "unit.json").read_text())
    assert unit["bladder"]["material"]["key"] == "ecoflex-00-30"
    assert unit["requirements"]["bladder_material"] == "ecoflex-00-30"
    assert "Ecoflex 00-30" in res.stdout  # the verdict line names the silicone


def test_design_writes_the_whole_folder(ecoflex_run):
    res, out, spec = ecoflex_run
    assert res.exit_code == 0, res.output
    for rel in ("design.json", "design_force.png", "spring/spring.csv", "spring/spring.png", "cad/manifest.json",
                "cad/housing.step", "cad/assembly.step", "bladder/bladder.json", "bladder/bladder.png",
                "actuator/actuator.json", "unit.json", "report.html"):
        assert (out / rel).is_file(), rel
    unit = json.loads((out / "unit.json").read_text())
    assert unit["spec"] == str(spec) and unit["seed"] == 0 and unit["version"]
    assert set(unit["seconds"]) == set(STEPS)
    assert unit["passes"] == (all(m >= -1e-9 for m in unit["constraint_margins"].values())
                              and unit["bladder"]["passes"])
    design = json.loads((out / "design.json").read_text())
    assert design["performance"]["linearity_error"] <= 0.0186  # better than the paper's hand-tuned 1.86 %
    assert all(m >= -1e-9 for m in design["constraints"].values())
    assert unit["performance"]["linearity_error"] == pytest.approx(design["performance"]["linearity_error"])
    # actuator parameters from the design: K = 2 r^2 k (SI), k from the design's own spring
    from vvea_design.actuator.model import PAPER_PULLEY_RADIUS_M

    k = design["performance"]["mean_stiffness_N_per_mm"]
    assert unit["actuator"]["K_Nm_per_rad"] == pytest.approx(2 * PAPER_PULLEY_RADIUS_M**2 * k * 1e3, rel=1e-6)
    size = (out / "report.html").stat().st_size
    assert 100_000 < size < 5_000_000


def test_design_streams_results_to_stdout_and_progress_to_stderr(ecoflex_run):
    res, out, _ = ecoflex_run
    assert "constraints (margin > 0 = satisfied)" in res.stdout
    assert "[1/7] optimise" in res.stderr and "done" in res.stderr
    assert "[1/7]" not in res.stdout


def test_spring_curve_matches_the_gas_law_by_hand():
    """Independent check of the isothermal and adiabatic curves: p V^n = const in each chamber."""
    gs = GasSpring(A1_mm2=900.0, A2_mm2=700.0, V1_mm3=40000.0, V2_mm3=90000.0, p1_MPa=3.0, p2_MPa=3.857142857)
    c = spring_curve(gs, num=41)
    x = c.x_mm
    for n, P1, P2, F in ((1.0, c.P1_isothermal_MPa, c.P2_isothermal_MPa, c.force_isothermal_N),
                         (1.4, c.P1_adiabatic_MPa, c.P2_adiabatic_MPa, c.force_adiabatic_N)):
        p1 = 3.0 * (40000.0 / (40000.0 + 900.0 * x)) ** n  # chamber 1 expands with x
        p2 = 3.857142857 * (90000.0 / (90000.0 - 700.0 * x)) ** n  # chamber 2 is compressed
        np.testing.assert_allclose(P1, p1, rtol=1e-12)
        np.testing.assert_allclose(P2, p2, rtol=1e-12)
        # tension > 0 as x grows: the force rises from 0 at x = 0 (charged for F(0) = 0)
        assert abs(F[0]) < 1e-6 * abs(F).max() and F[-1] > 0
        line = np.polyval(np.polyfit(x, F, 1), x)
        dev = F - line
        assert float(np.abs(dev).max() / (F.max() - F.min())) == pytest.approx(
            c.linearity_isothermal if n == 1.0 else c.linearity_adiabatic, rel=1e-9)
    assert c.stiffness_adiabatic_N_per_mm > c.stiffness_isothermal_N_per_mm  # gas stiffens when it cannot cool
    assert replace(gs, n_polytropic=1.4).force_N(x[-1]) == pytest.approx(c.force_adiabatic_N[-1])


def test_design_infeasible_spec_exits_3(tmp_path):
    spec = tmp_path / "r.toml"
    spec.write_text("max_outer_diameter_mm = 36.0\nmin_mean_stiffness_N_per_mm = 150.0\n")
    res = runner.invoke(app, ["design", "--spec", str(spec), "-o", str(tmp_path / "o")])
    assert res.exit_code == 3, res.output
    assert "no design meets the requirements" in res.output
    assert not (tmp_path / "o" / "report.html").exists()
