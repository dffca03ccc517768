"""Rail and wheel surfaces and patches in track coordinates: points lie on the bodies' surfaces, the patch's centre
is the contact point found by the contact search (both sides, yawed and rolled wheelset), a depth moves the points
into the body along its normal."""

import numpy as np
import pytest

from contact.wheel_rail.contact_search import search_contacts
from contact.wheel_rail.track_geometry import TrackLayout, WheelsetPose, place_rail
from contact.wheel_rail.track_surfaces import (patch_on_rail, patch_on_wheel, quads, rail_points,
                                               wheel_points)
from meshes.profiles import get_profile

LAYOUT = TrackLayout(gauge_mm=1435.0, gauge_depth_mm=14.0, inclination_rad=np.arctan(1 / 40),
                     back_to_back_mm=1360.0, flange_back_y_mm=-70.0, nominal_radius_mm=460.0)


@pytest.fixture(scope="module")
def bodies():
    rail, wheel = get_profile("60E1"), get_profile("S1002")
    return place_rail(rail, LAYOUT), wheel


@pytest.mark.parametrize("side", ["right", "left"])
@pytest.mark.parametrize("pose", [WheelsetPose(0.0, 0.0, 0.0), WheelsetPose(5.0, 0.012, 0.002)])
def test_patch_centre_is_the_contact_point_and_grid_lies_on_both_surfaces(bodies, side, pose):
    placed, wheel = bodies
    sign, side_pose = (1 if side == "right" else -1), pose.for_side(side)
    found = search_contacts(placed, wheel, LAYOUT, side_pose)
    touching = [c for c in found.candidates if abs(c.normal_gap_mm) < 1e-6]
    assert touching
    x, eta = np.linspace(-4.0, 4.0, 9), np.linspace(-3.0, 3.0, 7)
    for cand in touching:
        centre = np.array([cand.X_mm, sign * cand.Y_mm, cand.Z_mm])
        on_rail = patch_on_rail(placed, cand, sign, x, eta)
        on_wheel = patch_on_wheel(wheel, LAYOUT, side_pose, found.wheel_height_mm, cand, sign, x, eta)
        assert np.allclose(on_rail[4, 3], centre, atol=1e-6) and np.allclose(on_wheel[4, 3], centre, atol=1e-6)
        # on the rail surface: Z of the placed rail at the point's lateral position (side frame)
        assert np.allclose(on_rail[..., 2], placed.Z_at(sign * on_rail[..., 1]), atol=1e-9)
        assert np.allclose(on_rail[..., 0], cand.X_mm + x[:, None])
        # on the wheel surface: the strip's circle about the axle (axial position s(y), radius r(y))
        y = cand.wheel_coordinate(eta)
        pts = on_wheel.copy()
        pts[..., 1] *= sign
        a = np.array([-np.sin(side_pose.yaw_rad) * np.cos(side_pose.roll_rad),
                      np.cos(side_pose.yaw_rad) * np.cos(side_pose.roll_rad), np.sin(side_pose.roll_rad)])
        rel = pts - np.array([0.0, side_pose.lateral_mm, found.wheel_height_mm])
        axial = rel @ a
        radial = np.linalg.norm(rel - axial[..., None] * a, axis=-1)
        assert np.allclose(axial, LAYOUT.taping_line_mm + y[None, :], atol=1e-9)
        assert np.allclose(radial, LAYOUT.nominal_radius_mm - wheel.z(y)[None, :], atol=1e-9)
        # the patch follows the rolling direction on the wheel too (arc length x along each circle)
        assert np.allclose(np.diff(on_wheel[:, 3, 0]), 1.0, atol=2e-3)


def test_surfaces_and_depth(bodies):
    placed, wheel = bodies
    q = np.linspace(-30.0, 30.0, 61)
    X = np.linspace(-10.0, 10.0, 5)
    right, left = rail_points(placed, 1, X, q), rail_points(placed, -1, X, q)
    assert np.allclose(left[..., 1], -right[..., 1]) and np.all(right[..., 1] > 650.0)
    dented = rail_points(placed, 1, X, q, depth_mm=np.full((5, 61), 0.01))
    assert np.allclose(np.linalg.norm(dented - right, axis=-1), 0.01)
    assert np.all(dented[..., 2] <= right[..., 2] + 1e-12)                  # into the rail, below its surface
    phi, y = np.linspace(-0.02, 0.02, 5), np.linspace(-30.0, 30.0, 31)
    top = wheel_points(wheel, LAYOUT, WheelsetPose(), 460.0, 1, phi, y)
    dented = wheel_points(wheel, LAYOUT, WheelsetPose(), 460.0, 1, phi, y, depth_mm=np.full((5, 31), 0.01))
    assert np.allclose(np.linalg.norm(dented - top, axis=-1), 0.01)
    assert np.all(dented[2, :, 2] >= top[2, :, 2])                          # into the wheel, above its tread
    cells = quads(5, 31)
    assert cells.shape == (4 * 30, 4) and cells.max() == 5 * 31 - 1
