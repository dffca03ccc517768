"""Rolling-radius difference: a conical wheel on a round rail head, computed by hand."""

import numpy as np
import pytest

from contact.wear.conicity import radius_difference, rolling_radius
from contact.wheel_rail.track_geometry import TrackLayout
from meshes.profiles import S1002, Rail60E1, SplineProfile


def _cone(slope):
    """A conical tread z = slope * y (wheel frame: the radius r = r0 - z falls towards the field side)."""
    y = np.linspace(-40.0, 40.0, 81)
    return SplineProfile(y, slope * y, name=f"cone {slope:g}", body="wheel")


@pytest.mark.parametrize("slope", [0.025, 1.0 / 15.0])
@pytest.mark.parametrize("amplitude", [1.0, 3.0])
def test_cone_on_a_round_head_gives_its_slope(slope, amplitude):
    """By hand: on the rail's crown arc the contact stays where the rail's slope equals the cone's, so the wheel's
    contact point moves by the lateral displacement a and the rolling radius by slope x a, towards the flange on
    the wheel the wheelset moves towards: r_right(a) - r_left(a) = 2 slope a, quasi-conicity = slope."""
    wheel, rail, layout = _cone(slope), Rail60E1(), TrackLayout()
    got = radius_difference({"right": {"rail": rail, "wheel": wheel}}, layout, amplitude)
    assert got.delta_r_mm == pytest.approx(2.0 * slope * amplitude, rel=1e-7)
    assert got.quasi_conicity == pytest.approx(slope, rel=1e-7)
    centre = rolling_radius(rail, wheel, layout, "right", 0.0)
    assert got.r_right_mm - centre == pytest.approx(slope * amplitude, rel=1e-7)
    assert centre - got.r_left_mm == pytest.approx(slope * amplitude, rel=1e-7)


def test_one_side_stands_for_both_and_the_sides_are_used_as_given():
    """A side not simulated takes the other's profiles (mirror-symmetric wheelset); two sides: each its own."""
    layout = TrackLayout()
    s1002 = {"rail": Rail60E1(), "wheel": S1002()}
    right_only = radius_difference({"right": s1002}, layout, 3.0)
    both = radius_difference({"right": s1002, "left": dict(s1002)}, layout, 3.0)
    left_only = radius_difference({"left": s1002}, layout, 3.0)
    assert right_only == both == left_only
    assert right_only.delta_r_mm > 0  # S1002: the radius grows towards the flange
    cone = radius_difference({"right": s1002, "left": {"rail": Rail60E1(), "wheel": _cone(0.025)}}, layout, 3.0)
    assert cone.r_right_mm == right_only.r_right_mm
    assert cone.r_left_mm == pytest.approx(rolling_radius(Rail60E1(), _cone(0.025), layout, "left", 3.0))
