"""Every example in examples/ runs as a script at its small size (``VVEA_EXAMPLES_SMALL=1``) and prints
what it claims. The same scripts are the documentation's gallery (sphinx-gallery)."""

from __future__ import annotations

import os
import subprocess
import sys

import pytest

from tests.helpers import REPO, SHARED_RECORDINGS

EXAMPLES = REPO / "examples"

#: What each example must print (a line of its result), at the small size.
EXPECT = {
    "plot_paper_spring.py": ["linearity error: exact 1.866 %, on 401 samples 1.854 %"],
    "plot_check_linearity.py": ["limit 2.40 %: passes", "limit 2.30 %: fails", "1 passed"],
    "plot_design_from_toml.py": ["layout inner_tube: linearity 2.306 % (isothermal)", "wrote "],
    "plot_design_unit.py": ["inner_tube layout: linearity 2.306 % (isothermal)", "every check passes: True"],
    "plot_diagnose_campaign.py": ["50 experiments", "accepted: gas_nonlinearity, stiction"],
}


def test_every_example_is_checked():
    assert sorted(p.name for p in EXAMPLES.glob("*.py")) == sorted(EXPECT)


@pytest.mark.parametrize("name", sorted(EXPECT))
def test_example_runs(name, tmp_path):
    if name == "plot_diagnose_campaign.py" and not (SHARED_RECORDINGS / "campaign_c.csv").is_file():
        pytest.fail(f"{SHARED_RECORDINGS / 'campaign_c.csv'} is missing (the shared recordings beside the repository)")
    env = {**os.environ, "VVEA_EXAMPLES_SMALL": "1", "MPLBACKEND": "Agg", "TMPDIR": str(tmp_path),
           "PYTHONPATH": os.pathsep.join([str(REPO), os.environ.get("PYTHONPATH", "")])}
    res = subprocess.run([sys.executable, str(EXAMPLES / name)], capture_output=True, text=True, cwd=tmp_path,
                         env=env, timeout=900)
    assert res.returncode == 0, f"{name} failed:\n{res.stdout[-3000:]}\n{res.stderr[-3000:]}"
    for line in EXPECT[name]:
        assert line in res.stdout, f"{name} did not print {line!r}:\n{res.stdout[-3000:]}"
