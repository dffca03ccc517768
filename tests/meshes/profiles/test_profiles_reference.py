"""Analytic profiles against the Manchester-benchmark SIMPACK files (read by meshes.profiles.io)."""

import numpy as np
import pytest
from scipy.optimize import least_squares

from meshes.profiles.placement import Placement, place, rail_inclination, unplace
from meshes.profiles.io import read_simpack
from meshes.profiles import S1002, Rail60E1


@pytest.fixture(scope="module")
def wheel_file(reference_dir):
    return read_simpack(reference_dir / "profiles" / "MBench_S1002_v3.prw")


@pytest.fixture(scope="module")
def rail_file(reference_dir):
    return read_simpack(reference_dir / "profiles" / "MBench_UIC60_v3.prr")


def test_s1002_against_file(wheel_file):
    wheel = S1002()
    assert wheel_file.body == "wheel"
    # the file's points (after mirror.y, inversion, z down -> up) lie on F(S): notes say ~2e-6 mm
    pts = wheel_file.points
    assert np.abs(pts[:, 1] - wheel.z(pts[:, 0])).max() < 1e-5
    # the file's spline between the points, in the normal direction
    y = np.linspace(wheel_file.y_min, wheel_file.y_max, 3001)
    d, _ = wheel.signed_distance(np.column_stack([y, wheel_file.z(y)]))
    assert np.abs(d).max() < 0.01                       # measured 0.0023 mm (near the flange back)
    flat = np.abs(wheel.dz(y)) < 1.0
    assert np.abs(wheel_file.z(y[flat]) - wheel.z(y[flat])).max() < 0.001   # measured 0.00025 mm


def _fit_cant(rail_file, rail):
    """Rotation angle and shift with file point = place(rail point, Placement(angle, dy, dz))."""
    pts = rail_file.points

    def residual(x):
        q = unplace(pts, Placement(*x))
        inside = np.abs(q[:, 0]) < 30.0
        return q[inside, 1] - rail.z(q[inside, 0])

    return least_squares(residual, [0.0, 0.0, 0.0]).x


def test_60e1_against_canted_file(rail_file):
    rail = Rail60E1()
    angle, dy, dz = _fit_cant(rail_file, rail)
    # 1:40 cant, counter-clockwise (top towards -y): the file's -y is the gauge side, +y the field side
    assert angle == pytest.approx(rail_inclination(40.0), abs=2e-5)
    # the file's origin is the highest point of the canted head: 300 sin(a) to the field side of
    # the crown, 300 (1 - cos a) = 0.094 mm above it
    assert dy == pytest.approx(-300.0 * np.sin(angle), abs=0.02)
    assert dz == pytest.approx(-300.0 * (1 - np.cos(angle)), abs=0.03)
    q = unplace(rail_file.points, Placement(angle, dy, dz))
    on_head = np.abs(q[:, 0]) <= rail.y_max
    d, _ = rail.signed_distance(q[on_head])
    assert np.abs(d).max() < 0.03                       # normal distance (measured 0.020 mm)
    flat = np.abs(rail.dz(q[on_head, 0])) < 1.0
    vertical = q[on_head, 1][flat] - rail.z(q[on_head, 0][flat])
    assert np.abs(vertical).max() < 0.03                # vertical distance (measured 0.020 mm)
    # the file covers the head symmetrically, down to the flanks (z = -37.5 mm)
    assert q[0, 0] == pytest.approx(-q[-1, 0], abs=1e-3)
    # placing the analytic head with the fitted placement reproduces the file's points
    p = place(q[on_head], Placement(angle, dy, dz))
    assert np.allclose(p, rail_file.points[on_head])
