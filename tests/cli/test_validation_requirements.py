"""Requirements no real unit can have are refused naming the key, and the file is read safely (issue 24, campaign A
family ``req``): :class:`Requirements`, :func:`load_requirements` and ``vvea optimise/design/pareto --spec``."""

from __future__ import annotations

import os

import pytest

from vvea_design.plausibility import LIMITS
from vvea_design.spring.requirements import REQUIREMENT_LIMITS, Requirements, SpecError, load_requirements

ABSURD = [  # (campaign A case, key, value, words)
    ("req-06/35", "max_charge_MPa", 1e-12, ("max_charge_MPa", ">= 0.01")),
    ("req-07", "max_charge_MPa", 1e9, ("max_charge_MPa", "<= 20 MPa")),
    ("req-08", "max_mass_g", 1.0, ("max_mass_g", "servo")),
    ("req-09", "travel_mm", 1e-300, ("travel_mm", ">= 0.5")),
    ("req-10", "travel_mm", 1e6, ("travel_mm",)),
    ("req-12", "min_wall_safety_factor", 1e6, ("min_wall_safety_factor", "<= 20")),
    ("req-13", "min_wall_safety_factor", 0.1, ("min_wall_safety_factor", "yield")),
]


@pytest.mark.parametrize("case, key, value, words", ABSURD, ids=[c for c, *_ in ABSURD])
def test_an_absurd_requirement_is_refused_naming_it(tmp_path, case, key, value, words):
    with pytest.raises(SpecError) as exc:
        Requirements(**{key: value})
    for w in words:
        assert w in str(exc.value), str(exc.value)
    f = tmp_path / "req.toml"
    f.write_text(f"{key} = {value!r}\n")
    with pytest.raises(SpecError, match=f"req.toml: .*{key}"):
        load_requirements(f)


def test_every_numeric_requirement_has_a_plausible_range():
    numeric = [f for f, t in Requirements.__annotations__.items() if "float" in str(t) and "tuple" not in str(t)]
    limited = set(REQUIREMENT_LIMITS) | {"setpoint_x0_mm", "min_gas_fraction_at_full_stroke", "n_polytropic",
                                         "min_mean_stiffness_N_per_mm",  # a target: unreachable = infeasible (3)
                                         "max_bladder_strain", "max_linearity_adiabatic"}
    assert set(numeric) <= limited, set(numeric) - limited
    assert all(k in LIMITS for k in REQUIREMENT_LIMITS.values())


def test_a_5000_digit_number_names_the_line_and_key(tmp_path):
    """req-20: used to be a ValueError traceback (Python's 4300-digit limit)."""
    f = tmp_path / "req.toml"
    f.write_text("travel_mm = 40.0\nmax_housing_length_mm = 1" + "0" * 5000 + "\n")
    with pytest.raises(SpecError, match=r"req\.toml: line 2: max_housing_length_mm: a number of 5001 digits"):
        load_requirements(f)


@pytest.mark.parametrize("enc", ["utf-16", "utf-16-le", "utf-16-be"])
def test_utf16_is_named(tmp_path, enc):
    """req-21/22: used to be 'not UTF-8: byte 0xff' or 'not valid TOML: Expected ='."""
    f = tmp_path / "req.toml"
    f.write_bytes("max_outer_diameter_mm = 59.5\n".encode(enc))
    with pytest.raises(SpecError, match=r"req\.toml: is UTF-16 text .*save it as UTF-8"):
        load_requirements(f)


def test_non_regular_files_and_absurd_sizes_are_refused_before_reading(tmp_path):
    """size-05/06/07: /dev/zero and a FIFO were 'does not exist' (or hung), a 20 GB file a MemoryError."""
    with pytest.raises(SpecError, match="/dev/zero: is a character device, not a regular file"):
        load_requirements("/dev/zero")
    os.mkfifo(tmp_path / "req.toml")
    with pytest.raises(SpecError, match=r"req\.toml: is a FIFO \(named pipe\), not a regular file"):
        load_requirements(tmp_path / "req.toml")
    big = tmp_path / "big.toml"
    with open(big, "wb") as fh:
        fh.truncate(20 * 2**30)
    with pytest.raises(SpecError, match=r"big\.toml: is 20\.0 GiB .* larger than any requirements file"):
        load_requirements(big)
    (tmp_path / "dir.toml").mkdir()
    with pytest.raises(SpecError, match=r"dir\.toml: is a folder, not a file"):
        load_requirements(tmp_path / "dir.toml")
