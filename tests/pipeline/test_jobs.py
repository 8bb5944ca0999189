"""Each command's job called from Python gives what the command gives (issue 22 item 3): the same files, the same
numbers in what it prints. Small inputs throughout (tiny search budgets, coarse meshes, a short campaign); the
main job's twin is in test_pipeline.py (it shares that module's `vvea design` run)."""

from __future__ import annotations

import io
import json
import re
from pathlib import Path

import pytest
from typer.testing import CliRunner

import vvea_design as vd
from tests.helpers import REPO
from vvea_design.cli.main import app

runner = CliRunner()
#: Keys whose values are wall or CPU times (they differ between any two runs).
TIMING = {"seconds", "evaluations_per_second", "wall_seconds", "wall_seconds_this_run", "solver_seconds",
          "solver_seconds_total", "solver_cpu_seconds_total", "cpu_seconds", "runtime_s", "timing", "wall_s", "cpu_s",
          "seconds_per_setting"}


def tree(folder: Path) -> dict[str, bytes]:
    """Every file under ``folder`` with its bytes (the hidden marker of the writing command left out)."""
    return {str(p.relative_to(folder)): p.read_bytes() for p in sorted(folder.rglob("*"))
            if p.is_file() and not p.name.startswith(".vvea-")}


def untimed(value):
    """``value`` (parsed JSON) without its timings."""
    if isinstance(value, dict):
        return {k: untimed(v) for k, v in value.items() if k not in TIMING}
    if isinstance(value, list):
        return [untimed(v) for v in value]
    return value


def same_files(a: Path, b: Path, timed: tuple[str, ...] = (), csv_timed: dict[str, list[str]] | None = None,
               named: tuple[str, ...] = ()) -> None:
    """The folders hold the same files, byte for byte; JSON files in ``timed`` compared without their timings,
    CSV files in ``csv_timed`` without the named columns, files in ``named`` (a report naming its folder) only
    present in both."""
    import pandas as pd

    ta, tb = tree(a), tree(b)
    assert set(ta) == set(tb)
    for name in ta:
        if name in timed:
            assert untimed(json.loads(ta[name])) == untimed(json.loads(tb[name])), name
        elif name in (csv_timed or {}):
            pd.testing.assert_frame_equal(*(pd.read_csv(io.BytesIO(t[name])).drop(columns=csv_timed[name])
                                            for t in (ta, tb)), obj=name)
        elif name not in named:
            assert ta[name] == tb[name], name


def numbers(text: str) -> list[str]:
    """The numbers in a printed text, in order."""
    return re.findall(r"[-+]?\d+\.?\d*(?:e[-+]?\d+)?", text)


@pytest.fixture()
def design_json(tmp_path):
    from vvea_design.spring.design import Design
    from vvea_design.spring.design_file import save_design
    from vvea_design.spring.problem import evaluate_design
    from vvea_design.spring.requirements import Requirements

    req = Requirements()
    return save_design(tmp_path / "design.json", evaluate_design(Design(34.5, 59.5, 41500.0, 90000.0), req), req)


@pytest.fixture()
def tiny_search(monkeypatch):
    """The optimiser on a few dozen evaluations (the point is the job against the command, not the optimum)."""
    import vvea_design.spring.optimise as opt
    import vvea_design.spring.studies as studies

    real = opt.optimise

    def tiny(req, **kw):
        return real(req, **{**kw, "popsize": 5, "maxiter": 30, "progress": False})  # 15: no feasible design now

    monkeypatch.setattr(opt, "optimise", tiny)
    monkeypatch.setattr(studies, "optimise", tiny)


def test_optimise(tmp_path, tiny_search):
    spec = tmp_path / "req.toml"
    spec.write_text('layouts = ["inner_tube"]\n')
    res = vd.optimise(spec, seed=3, out=tmp_path / "job" / "design.json")
    cli = runner.invoke(app, ["optimise", "--spec", str(spec), "--seed", "3", "--out", str(tmp_path / "cli" / "design.json")])
    assert cli.exit_code == 0, cli.output
    same_files(tmp_path / "job", tmp_path / "cli", timed=("design.json",))
    assert set(tree(tmp_path / "job")) == {"design.json", "design_force.png"}
    assert f"{100 * res.evaluation.linearity_error:.3f} %" in cli.stdout
    assert f"{res.evaluation.performance()['mass_g']:.4g}" in cli.stdout
    assert json.loads((tmp_path / "job" / "design.json").read_text())["optimiser"]["seed"] == 3


def test_spring(tmp_path, design_json):
    rep = vd.spring_report(design_json, p2_MPa=2.0, out=tmp_path / "job")
    cli = runner.invoke(app, ["spring", str(design_json), "--p2", "2", "--out", str(tmp_path / "cli")])
    assert cli.exit_code == 0, cli.output
    same_files(tmp_path / "job", tmp_path / "cli")
    assert rep.files == {"csv": tmp_path / "job" / "spring.csv", "png": tmp_path / "job" / "spring.png"}
    assert numbers(cli.stdout) == numbers(
        f"linearity error {100 * rep.linearity_error:.3f} % (n = {rep.spring.n_polytropic:g}; "
        f"{100 * rep.linearity_error_adiabatic:.3f} % at n = 1.4), mean stiffness {rep.mean_stiffness_N_per_mm:.2f} "
        f"N/mm at p2 = {rep.spring.p2_MPa:.3g} MPa, F({rep.spring.travel_mm:g}) = {rep.force_at_travel_N:.1f} N")
    assert rep.spring.p2_MPa == 2.0 and rep.to_dict()["files"]["csv"].endswith("spring.csv")
    with pytest.raises(vd.OptionError, match="p2_MPa must be > 0 MPa"):
        vd.spring_report(design_json, p2_MPa=-1.0)


def test_check(design_json):
    from vvea_design.jobs.spring import check_design

    ok, bad = check_design(design_json, 0.02), check_design(design_json, 0.01)
    assert ok.passes and not bad.passes and ok.linearity_error == bad.linearity_error
    res = runner.invoke(app, ["check", str(design_json), "--max-linearity", "0.02"])
    assert res.exit_code == 0 and f"{100 * ok.linearity_error:.3f} %" in res.stdout
    res = runner.invoke(app, ["check", str(design_json), "--max-linearity", "0.01"])
    assert res.exit_code == 1 and " ".join(bad.message.split()) in " ".join(res.stdout.split())
    with pytest.raises(vd.OptionError, match=r"max_linearity is a fraction in \(0, 1\)"):
        check_design(design_json, 5.0)


def test_map(tmp_path, design_json):
    rep = vd.linearity_map(design_json, x="piston_diameter_mm", y="V1_mm3", n=5, out=tmp_path / "job")
    cli = runner.invoke(app, ["map", str(design_json), "--x", "piston_diameter_mm", "--y", "V1_mm3", "--n", "5",
                              "--out", str(tmp_path / "cli")])
    assert cli.exit_code == 0, cli.output
    same_files(tmp_path / "job", tmp_path / "cli")
    assert sorted(rep.files) == ["csv", "png"] and rep.files["csv"].name == "map_piston_diameter_mm_V1_mm3.csv"
    assert len(rep.to_dict()["linearity"]) == 5 and rep.map.linearity.shape == (5, 5)


def test_pareto(tmp_path, tiny_search):
    spec = tmp_path / "req.toml"
    spec.write_text('layouts = ["bulkhead"]\n')
    front = vd.pareto_front("outer_diameter", [55.0], requirements=spec, out=tmp_path / "job")
    cli = runner.invoke(app, ["pareto", "--axis", "outer_diameter", "--values", "55", "--spec", str(spec),
                              "--out", str(tmp_path / "cli")])
    assert cli.exit_code == 0, cli.output
    same_files(tmp_path / "job", tmp_path / "cli")
    p = front.points[0]
    assert cli.stdout.strip() == (f"max_outer_diameter_mm = 55: {100 * p.linearity_error:.3f} %" if p.feasible
                                  else "max_outer_diameter_mm = 55: infeasible")
    with pytest.raises(vd.OptionError, match="axis must be one of"):
        vd.pareto_front("colour", [1.0])


def test_cad(tmp_path, reference_cad_run):
    """The CAD set of the reference design: the job writes what `vvea cad` wrote (the session's shared run)."""
    cli_out, code, output = reference_cad_run
    assert code == 0, output
    cad = vd.build_cad(REPO / "cad" / "design.json", out=tmp_path / "job", progress=False)
    same_files(tmp_path / "job", cli_out)
    assert cad.out_dir == tmp_path / "job" and cad.drawings.pdf == tmp_path / "job" / "drawings.pdf"
    assert all(p.is_file() for p in cad.drawings.svg)
    assert f"wrote {len(cad.manifest.files)} files" in output
    assert f"unit mass {cad.bom.unit_mass_g:.1f} g" in output and f"{len(cad.drawings.sheets)} sheets" in output
    with pytest.raises(vd.OptionError, match="unknown silicone 'wood'"):
        vd.build_cad(REPO / "cad" / "design.json", silicone="wood")


def test_bladder(tmp_path):
    # the default optimum (its bladder takes the stroke; the fixture's design leaves the sleeve too little volume)
    design_json = REPO / "cad" / "design.json"
    rep = vd.check_bladder(design_json, elements=16, out=tmp_path / "job", progress=False)
    cli = runner.invoke(app, ["bladder", str(design_json), "--elements", "16", "--out", str(tmp_path / "cli")])
    assert cli.exit_code == 0, cli.output
    same_files(tmp_path / "job", tmp_path / "cli")
    assert f"strain bound {100 * rep.result.strain_bound:.2f} %" in cli.stdout
    assert rep.path("json") == tmp_path / "job" / "bladder.json"
    bare = vd.check_bladder(design_json, elements=16, progress=False)  # no out: the check alone
    assert bare.out_dir is None and not bare.files and bare.result.strain_bound == rep.result.strain_bound
    with pytest.raises(vd.OptionError, match="elements must be >= 8"):
        vd.check_bladder(design_json, elements=2)


@pytest.fixture(scope="module")
def campaign(tmp_path_factory):
    """A short simulated campaign with stiction (the bench of vvea_benches), as a Parquet file."""
    from vvea_benches.testbench import BenchmarkCase, case_spec, simulate

    f = tmp_path_factory.mktemp("campaign") / "rec.parquet"
    spec = case_spec(BenchmarkCase("single", ("stiction",), (5.0,), 5, "small"))
    simulate(spec).frame.drop(columns=["force_true_N"]).to_parquet(f)
    return f


def test_identify(tmp_path, campaign):
    ident = vd.identify(campaign, out=tmp_path / "job", progress=False)
    cli = runner.invoke(app, ["identify", str(campaign), "--out", str(tmp_path / "cli")])
    assert cli.exit_code == 0, cli.output
    same_files(tmp_path / "job", tmp_path / "cli")
    assert f"RMS error {ident.rmse_N:.1f} N" in cli.output
    for p in ident.parameters.values():
        assert f"{p.value:.2f}" in cli.output
    bare = vd.identify(campaign, progress=False)  # no out: the numbers alone
    assert bare.files == () and bare.rmse_N == ident.rmse_N


def test_diagnose(tmp_path, campaign):
    run = vd.diagnose(campaign, learner=False, out=tmp_path / "job", progress=False)
    cli = runner.invoke(app, ["diagnose", str(campaign), "--no-learner", "--out", str(tmp_path / "cli")])
    assert cli.exit_code == 0, cli.output
    assert run.summary_text in cli.output
    same_files(tmp_path / "job", tmp_path / "cli", timed=("report.json",), named=("report.html",))
    assert set(tree(tmp_path / "job")) == set(run.files)
    assert [e.id for e in run.report.accepted] == ["stiction"]


def test_safety(tmp_path):
    run = vd.run_safety(tmp_path / "job", mesh_n=24)
    cli = runner.invoke(app, ["study", "safety", "--mesh-n", "24", "--out", str(tmp_path / "cli")])
    assert cli.exit_code == 0, cli.output
    same_files(tmp_path / "job", tmp_path / "cli", timed=("safety.json",), named=("report.html",))
    assert set(tree(tmp_path / "job")) == {"safety.json", "safety_trajectories.csv", "safety.png", "report.html"}
    assert run.summary_text in cli.stdout
    assert run.study.setup["mesh"]["n_intervals"] == 24 and run.study.setup["tau_ref_Nm"] == 50.0
    with pytest.raises(vd.OptionError, match="M_kgm2 must be > 0"):
        vd.run_safety(M_kgm2=-1.0)


def test_rest_to_rest(tmp_path):
    run = vd.run_rest_to_rest(tmp_path / "job", grid="0.4:0.8", mesh_n=16, fine_mesh_n=None, workers=1,
                              progress=False)
    cli = runner.invoke(app, ["study", "rest-to-rest", "--grid", "0.4:0.8", "--mesh-n", "16", "--fine-mesh-n", "-1",
                              "--workers", "1", "--no-progress", "--out", str(tmp_path / "cli")])
    assert cli.exit_code == 0, cli.output
    same_files(tmp_path / "job", tmp_path / "cli", timed=("summary.json",),
               csv_timed={"results.csv": ["seconds", "cpu_seconds"]}, named=("report.html",))
    assert {"results.csv", "summary.json", "meta.json", "report.html"} <= set(tree(tmp_path / "job"))
    assert run.summary_text in cli.stdout
    assert run.files["results_csv"] == tmp_path / "job" / "results.csv"
    with pytest.raises(vd.OptionError, match="grid must be one of"):
        vd.run_rest_to_rest(tmp_path / "x", grid="huge")
    with pytest.raises(vd.OptionError, match="apply to a design only"):
        vd.run_rest_to_rest(tmp_path / "x", p2_MPa=3.0)
    assert not (tmp_path / "x").exists()


def test_design_study(tmp_path):
    """The design study of `vvea design` (tested whole against the command in test_pipeline.py): its options are
    checked before anything is solved, and it writes into ``out`` whole."""
    from vvea_design.spring.paper import PAPER_FIG5

    with pytest.raises(vd.OptionError, match="mesh_n: .*n_intervals"):
        vd.run_design_study(PAPER_FIG5, mesh_n=2, out=tmp_path / "x")
    with pytest.raises(vd.OptionError, match="must be 'A1,A2,..:T1,T2,..'"):
        vd.run_design_study(PAPER_FIG5, grid="0.2,-1:0.4", out=tmp_path / "x")
    assert not (tmp_path / "x").exists()
    study = vd.run_design_study(PAPER_FIG5, grid=((0.4,), (0.8,)), mesh_n=16, safety_mesh_n=24, workers=1,
                                out=tmp_path / "study")
    assert study.files.summary_json == tmp_path / "study" / "design_study.json"
    saved = json.loads(study.files.summary_json.read_text())
    assert saved["mesh"]["n_intervals"] == 16 and saved["files"]["results_csv"] == "results.csv"
    assert untimed(saved) == untimed(json.loads(json.dumps(study.to_dict(), default=str)))

