"""Fixtures of the identification tests: a small simulated campaign as fit data."""

from __future__ import annotations

import pytest

from vvea_benches.testbench import simulate, small_spec
from vvea_design.identification.fit_data import FitData
from vvea_design.identification.recordings import recordings_from_frame


@pytest.fixture(scope="module")
def D():
    """30 experiments of the unit-test bench (2 pressures x 5 valves x 3 speeds, 151 samples), eq. 14 plus AR(1) noise."""
    spec = small_spec(seed=5, g_N_per_mm_MPa=21.0, C_N=140.0, noise_N=4.0, noise_rho=0.8)
    return FitData.from_recordings(recordings_from_frame(simulate(spec).frame, "sim"))
