"""Wheelset creepages: analytic values without yaw, yaw creepage, mirror symmetry of the two wheels."""

import math

import numpy as np
import pytest

from contact.wheel_rail.kinematics import contact_frame, creepages
from contact.wheel_rail.track_geometry import WheelsetPose, axle_direction

V, R0 = 2000.0, 460.0


def _right_point(gamma, r=455.0, s=745.0):
    n = np.array([0.0, -math.sin(gamma), math.cos(gamma)])
    return np.array([0.0, s, -r]), n


def test_no_yaw_analytic():
    gamma = 0.3
    P, n = _right_point(gamma)
    k = creepages(P, n, np.zeros(3), axle_direction(WheelsetPose()), V, V / R0)
    assert k.vx == pytest.approx(1.0 - 455.0 / R0, rel=1e-12)
    assert k.vy == pytest.approx(0.0, abs=1e-15)
    assert k.phi_per_mm == pytest.approx(-math.sin(gamma) / R0, rel=1e-12)


def test_contact_frame_right_handed():
    for n in (np.array([0, -0.3, 0.954]), np.array([0, 0.94, 0.34])):
        x, y, z = contact_frame(n / np.linalg.norm(n))
        assert np.allclose(np.cross(x, y), z)
        assert y[1] > 0


def test_yaw_lateral_creepage_and_mirror():
    psi, gamma = 0.01, 0.05
    pose = WheelsetPose(0.0, psi, 0.0)
    a = axle_direction(pose)
    P, n = _right_point(gamma, r=R0)
    P = np.array([-R0 * 0.0, 0.0, 0.0]) + 745.0 * a + np.array([0.0, 0.0, -R0])
    k = creepages(P, n, np.zeros(3), a, V, V / R0)
    assert k.vy == pytest.approx(-math.sin(psi) * math.cos(gamma), rel=1e-6)
    # the left wheel: mirror image of the right one at the opposite yaw; vx equal, vy and spin opposite
    Pl = P * np.array([1, -1, 1])
    nl = n * np.array([1, -1, 1])
    al = axle_direction(WheelsetPose(0.0, -psi, 0.0))
    kl = creepages(Pl, nl, np.zeros(3), al, V, V / R0)
    assert kl.vx == pytest.approx(k.vx, abs=1e-15)
    assert kl.vy == pytest.approx(-k.vy, rel=1e-12)
    assert kl.phi_per_mm == pytest.approx(-k.phi_per_mm, rel=1e-12)
