"""Rail placement (gauge point, cant, top) and the wheel's contact locus (exact surface-of-revolution checks)."""

import math

import numpy as np
import pytest

from contact.wheel_rail.track_geometry import TrackLayout, WheelsetPose, axle_direction, place_rail, wheel_locus
from wrlayer.errors import InputError


def test_rail_gauge_point_and_top(placed, layout):
    # the gauge point sits at gauge/2, gauge_depth below the top; the top is the highest point at Z = 0
    assert placed.gauge_point[0] == pytest.approx(layout.gauge_mm / 2, abs=1e-9)
    assert placed.gauge_point[1] == pytest.approx(-layout.gauge_depth_mm, abs=1e-9)
    assert placed.Z_mm.max() == pytest.approx(0.0, abs=1e-6)
    assert placed.point(placed.top_q_mm)[1] == pytest.approx(0.0, abs=1e-12)
    # no point of the head within the 14 mm band lies further inward than the gauge point
    band = placed.Z_mm >= -layout.gauge_depth_mm
    assert placed.Y_mm[band].min() >= layout.gauge_mm / 2 - 1e-6
    # canted 1:40 towards the track centre: the top lies on the field side of the crown, where the slope is -1/40
    assert placed.top_q_mm > 0
    assert placed.profile.dz(placed.top_q_mm) == pytest.approx(-1 / 40, rel=1e-9)


def test_rail_normal_is_rotated_profile_normal(placed):
    q = np.array([-30.0, -10.0, 0.0, 20.0])
    n = placed.normal(q)
    a = placed.angle_rad
    n0 = placed.profile.normal(q)
    assert np.allclose(n[:, 0], math.cos(a) * n0[:, 0] - math.sin(a) * n0[:, 1])
    # q_at inverts point
    Y = placed.point(q)[:, 0]
    assert np.allclose(placed.q_at(Y), q, atol=1e-9)


def test_impossible_gauge_and_short_profile(rail60):
    with pytest.raises(InputError, match="gauge_mm.*impossible gauge"):
        TrackLayout(gauge_mm=1300.0)
    with pytest.raises(InputError, match="gauge_depth_mm"):
        place_rail(rail60, TrackLayout(gauge_depth_mm=40.0))


@pytest.mark.parametrize("pose", [WheelsetPose(0, 0, 0), WheelsetPose(3.0, 0.02, 0.004), WheelsetPose(-5, -0.015, 0.01)])
def test_wheel_locus_lies_on_the_wheel_with_normal_across_x(s1002, layout, pose):
    y = np.linspace(-60, 50, 23)
    loc = wheel_locus(s1002, layout, pose, y)
    a = axle_direction(pose)
    centre = np.array([0.0, pose.lateral_mm, 0.0])
    rel = np.column_stack([loc.X_mm, loc.Y_mm, loc.Z_mm]) - centre
    axial = rel @ a
    radial = np.linalg.norm(rel - axial[:, None] * a, axis=1)
    assert np.allclose(axial, layout.taping_line_mm + y, atol=1e-9)          # on the right circle
    assert np.allclose(radial, layout.nominal_radius_mm - s1002.z(y), atol=1e-9)
    assert np.allclose(loc.normal[:, 0], 0.0, atol=1e-12)                   # contact locus: n_X = 0
    assert np.all(loc.normal[:, 2] < 0)                                     # pointing down, out of the wheel
    if pose.yaw_rad == 0 and pose.roll_rad == 0:
        assert np.allclose(loc.X_mm, 0.0)
        assert np.allclose(loc.Z_mm, -(layout.nominal_radius_mm - s1002.z(y)))


def test_mirrored_pose():
    p = WheelsetPose(2.0, 0.01, -0.003).for_side("left")
    assert (p.lateral_mm, p.yaw_rad, p.roll_rad) == (-2.0, -0.01, 0.003)
    with pytest.raises(InputError, match="side"):
        WheelsetPose().for_side("middle")


def test_cross3_is_numpy_cross_bit_for_bit():
    from contact.wheel_rail.track_geometry import cross3

    rng = np.random.default_rng(3)
    a, b = rng.normal(size=3), rng.normal(size=(7, 3))
    assert np.array_equal(cross3(a, b), np.cross(a, b))
    assert np.array_equal(cross3(b, a), np.cross(b, a))
    assert np.array_equal(cross3(a, b[0]), np.cross(a, b[0]))
    assert cross3(a, b).shape == (7, 3) and cross3(a, b[0]).shape == (3,)
