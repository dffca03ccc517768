"""Pure helpers of ``benchmarks/tamaas_reference.py`` (the Tamaas reference of the FEM validation benchmark).

These run without Tamaas: the load-step list, the plastic-zone extent on a depth grid, the closed-form axis stress
(Johnson 1985 eq. 3.45) against the project's first-yield value, and the grid checks of the settings.
"""

import numpy as np
import pytest

from benchmarks.tamaas_reference import TamaasSettings, hertz_axis_von_mises, load_steps, zone_extent
from calibration.fem.verification_meshes import hertz_axis_first_yield


def test_load_steps_follow_the_fem_path():
    steps = load_steps((2.0, 2.6, 3.0), 0.1, 1.5, (1.55, 1.65))
    assert steps[:5] == [1.5, 1.55, 1.6, 1.65, 1.7]
    assert steps[-1] == 3.0
    assert {2.0, 2.6, 3.0} <= set(steps)
    assert max(np.diff(steps)) <= 0.1 + 1e-12
    assert all(np.diff(steps) > 0)


def test_zone_extent_top_bottom_count():
    z = np.linspace(0.0, 2.0, 17)
    cum = np.zeros((17, 4, 4))
    assert np.isnan(zone_extent(cum, z, 0.0)[0]) and zone_extent(cum, z, 0.0)[2] == 0
    cum[3, 1, 2] = 1e-6
    cum[5:9, 2, 2] = 1e-3
    assert zone_extent(cum, z, 0.0) == (z[3], z[8], 5)
    assert zone_extent(cum, z, 1e-5) == (z[5], z[8], 4)


def test_axis_von_mises_matches_first_yield():
    fy, depth = hertz_axis_first_yield(0.3)
    zeta = np.linspace(0.01, 2.0, 20001)
    vm = hertz_axis_von_mises(zeta, 0.3)
    assert 1.0 / vm.max() == pytest.approx(fy, rel=1e-4)
    assert zeta[np.argmax(vm)] == pytest.approx(depth, abs=2e-3)
    # surface: sigma_z = -p0, sigma_r = -(1 + 2 nu) p0 / 2
    assert hertz_axis_von_mises(np.array([0.0]), 0.3)[0] == pytest.approx(1.0 - 0.8, abs=1e-9)


def test_settings_grid_sizes():
    s = TamaasSettings(period_a=8.0, dx_a=1 / 16, depth_a=2.5)
    assert (s.n_xy, s.n_z) == (128, 41)
    with pytest.raises(ValueError, match="even"):
        _ = TamaasSettings(period_a=8.0, dx_a=8 / 63).n_xy
    with pytest.raises(ValueError, match="integer"):
        _ = TamaasSettings(depth_a=2.05).n_z
