"""Placement of profile points: order of operations, inverse, mirror, cant sign, wheel radius."""

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from wrlayer.errors import InputError
from meshes.profiles.placement import (
    Placement,
    mirror,
    place,
    rail_inclination,
    unplace,
    wheel_at_radius,
)
from meshes.profiles import S1002, Rail60E1

finite = st.floats(-100.0, 100.0)


@settings(max_examples=50, deadline=None)
@given(st.floats(-3.0, 3.0), finite, finite, st.booleans())
def test_place_unplace_and_mirror(angle, dy, dz, flip):
    p = Placement(angle, dy, dz, flip)
    pts = np.array([[1.0, 2.0], [-3.0, 0.5], [0.0, -7.0]])
    assert np.allclose(unplace(place(pts, p), p), pts)
    assert np.allclose(place(pts, mirror(p)), place(pts, p) * [-1.0, 1.0])
    # distances are preserved
    q = place(pts, p)
    assert np.allclose(np.linalg.norm(q[0] - q[1]), np.linalg.norm(pts[0] - pts[1]))


def test_order_mirror_rotate_shift():
    q = place([[1.0, 0.0]], Placement(np.pi / 2, 10.0, 20.0, mirror=True))
    assert np.allclose(q, [[10.0, 19.0]])      # (1,0) -> (-1,0) -> (0,-1) -> (10,19)


def test_rail_cant_tilts_top_to_gauge_side():
    rail = Rail60E1()
    a = rail_inclination(40)
    assert a == pytest.approx(np.arctan(1 / 40))
    canted = place(np.column_stack(rail.sample(0.1)), Placement(a))
    top = canted[np.argmax(canted[:, 1])]
    # the highest point moves to the field side (+y) by 300 sin a while the head leans to -y (gauge)
    assert top[0] == pytest.approx(300 * np.sin(a), abs=0.05)
    axis = place([[0.0, -100.0], [0.0, 0.0]], Placement(a))
    assert axis[1, 0] < axis[0, 0]
    with pytest.raises(InputError):
        rail_inclination(0)


def test_wheel_at_radius():
    wheel = S1002(r0=460.0)
    p = wheel_at_radius(460.0, y_taping=750.0)
    q = place(np.array([[0.0, 0.0], [-55.0, float(wheel.z(-55.0))]]), p)
    assert np.allclose(q[0], [750.0, -460.0])
    assert -q[1, 1] == pytest.approx(wheel.radius(-55.0))   # distance below the axle = radius
    with pytest.raises(InputError):
        wheel_at_radius(-1.0)
