"""Contact geometry against hand-worked cases: a conical wheel (Delta r = 2 lambda y, gamma_e = lambda at every
amplitude, roll parameter = lambda), a circular wheel on a circular rail head (closed-form contact angle, contact
positions and rolling radii), and jumps."""

import math

import numpy as np
import pytest

from contact.geometry import WheelsetProfiles, contact_geometry
from contact.geometry.jumps import contact_jumps, jump_steps
from contact.geometry.sweep import lateral_positions, lateral_sweep
from contact.wheel_rail.track_geometry import TrackLayout
from meshes.profiles import Profile, Rail60E1
from meshes.profiles.pieces import ArcPiece, line_piece
from wrlayer.errors import InputError


def cone(slope: float) -> Profile:
    """A conical wheel z = slope * y (the radius r = r0 - z grows towards the flange side, -y)."""
    return Profile(f"cone {slope:g}", "wheel", [line_piece(-60.0, 60.0, -60.0 * slope, slope)])


@pytest.mark.parametrize("slope", [0.025, 0.15])
def test_cone_on_a_round_head_without_roll_is_exact(slope):
    """By hand: the rail contact stays where the rail's slope equals the cone's, the wheel contact moves by y:
    Delta r = 2 slope y exactly, and both conicity methods give the slope at every amplitude 0.5..10 mm."""
    got = contact_geometry(WheelsetProfiles(Rail60E1(), cone(slope)), TrackLayout(), step_mm=0.25, with_roll=False)
    y = got.sweep.lateral_mm
    assert np.max(np.abs(got.sweep.delta_r_mm - 2.0 * slope * y)) < 1e-8  # mm
    assert np.allclose(got.conicity.equivalent_conicity, slope, rtol=1e-8)
    assert np.allclose(got.conicity.harmonic_conicity, slope, rtol=1e-9)
    assert np.allclose(got.sweep.right.y_rail_mm, got.sweep.right.y_rail_mm[0], atol=1e-6)
    assert not got.jumps


def test_cone_with_roll_against_the_first_order_hand_value():
    """Rolled so that both wheels touch (upright rails). By hand, to first order in the roll phi: the right wheel's
    surface slope in the track becomes slope + phi, so the rail contact moves by -R phi on a rail head arc of radius
    R, and the tilted radius moves the wheel point by r0 phi: the wheel contact coordinate shifts by -(R + r0) phi,
    r_right = r_n + slope (y + (R + r0) phi) and the left side mirrored. With phi = Delta r / (2 e0):
    Delta r = 2 slope y / (1 - slope (R + r0) / e0) and the roll parameter e0 phi / y = Delta r e0 / (2 e0 y).
    Here the contact lies on 60E1's R80 arc (rail coordinate -11.5 mm): factor 1.0378 (5.3 % on the R300 crown
    with a 1:40 cant). Measured agreement: Delta r 2e-5, roll parameter 0.6 % (phi = Delta r / (2 e0) neglects the
    contact angles)."""
    slope = 0.05
    got = contact_geometry(WheelsetProfiles(Rail60E1(), cone(slope)), TrackLayout(inclination_rad=0.0), step_mm=0.25)
    s = got.sweep
    y = s.lateral_mm
    nz = y != 0.0
    assert np.all(np.abs(np.abs(s.right.y_rail_mm) - 11.5) < 0.3)       # on the R80 arc (10.2 < |q| < 20)
    factor = 1.0 / (1.0 - slope * (80.0 + s.r0_mm) / s.e0_mm)
    assert factor == pytest.approx(1.0378, abs=1e-4)
    assert np.max(np.abs(s.delta_r_mm[nz] / (2.0 * slope * y[nz]) / factor - 1.0)) < 5e-4
    assert np.allclose(s.roll_parameter[nz], slope * factor, rtol=1e-2)
    assert np.allclose(got.conicity.equivalent_conicity, slope * factor, rtol=5e-4)
    assert math.isnan(s.roll_parameter[~nz][0])


# circular wheel tread (radius RW, centre (C, -RW) in the wheel frame) on a circular rail head (radius RR, centre
# (0, -RR), crown at 0), upright rails: the centres lie on the common normal at distance RW - RR
RW, RR, C = 300.0, 100.0, 28.53


def circular_pair() -> tuple[Profile, Profile]:
    rail = Profile("arc rail", "rail", [ArcPiece(-55.0, 55.0, (0.0, -RR), RR, True)])
    wheel = Profile("arc wheel", "wheel", [ArcPiece(-60.0, 60.0, (C, -RW), RW, True)])
    return rail, wheel


def test_circular_pair_against_the_closed_form():
    """By hand (no roll, no cant): the rail's gauge point at 14 mm below the top lies at q_g = -sqrt(RR^2 -
    (RR - 14)^2), so the rail is shifted by dy = gauge / 2 - q_g; a wheel displaced by y has its tread centre at
    Y = y + taping + C, and sin(gamma) = (dy - taping - C - y) / (RW - RR) for the right wheel (left: -y). Then the
    rail contact is at q = RR sin(gamma), the wheel's at C + RW sin(gamma), the rolling radius is
    r0 + RW (1 - cos(gamma)) and the contact angle (positive towards the gauge side) is -gamma."""
    rail, wheel = circular_pair()
    layout = TrackLayout(inclination_rad=0.0)
    s = lateral_sweep(WheelsetProfiles(rail, wheel), layout, lateral_positions(-8.0, 8.0, 0.5), with_roll=False)
    dy = 0.5 * layout.gauge_mm + math.sqrt(RR ** 2 - (RR - layout.gauge_depth_mm) ** 2)
    for side, sign in (("right", 1.0), ("left", -1.0)):
        sin_g = (dy - layout.taping_line_mm - C - sign * s.lateral_mm) / (RW - RR)
        g = np.arcsin(sin_g)
        got = getattr(s, side)
        assert np.max(np.abs(got.y_rail_mm - RR * sin_g)) < 5e-6        # measured 7e-7 mm
        assert np.max(np.abs(got.y_wheel_mm - (C + RW * sin_g))) < 5e-6
        radius = layout.nominal_radius_mm + RW * (1.0 - np.cos(g))
        assert np.max(np.abs(got.rolling_radius_mm - radius)) < 1e-6  # measured 6e-8 mm
        assert np.max(np.abs(got.contact_angle_rad + g)) < 1e-7  # 7e-9 rad
    closed = RW * (np.cos(np.arcsin((dy - layout.taping_line_mm - C + s.lateral_mm) / (RW - RR)))
                   - np.cos(np.arcsin((dy - layout.taping_line_mm - C - s.lateral_mm) / (RW - RR))))
    assert np.max(np.abs(s.delta_r_mm - closed)) < 2e-6


def test_jumps_are_steps_beyond_the_threshold():
    lateral = np.arange(6) * 0.1
    rail = np.array([0.0, 0.1, 0.2, 5.0, 5.1, 5.2])
    wheel = np.array([0.0, -0.1, -0.2, -0.3, -0.4, -3.0])
    assert jump_steps(rail, wheel, 1.0).tolist() == [False, False, False, True, False, True]
    jumps = contact_jumps("right", lateral, rail, wheel, 1.0)
    assert [(j.lateral_from_mm, j.lateral_to_mm) for j in jumps] == [(0.2, pytest.approx(0.3)), (0.4, 0.5)]
    with pytest.raises(InputError, match="jump_mm"):
        jump_steps(rail, wheel, 0.0)


@pytest.mark.parametrize("args, match", [((5.0, -5.0, 0.1), "lateral_max_mm"), ((-5.0, 5.0, 0.0), "step_mm"),
                                         ((-5.0, float("nan"), 0.1), "lateral_max_mm"),
                                         ((-5.0, 5.0, 1e-5), "at most 20001")])
def test_bad_lateral_range(args, match):
    with pytest.raises(InputError, match=match):
        lateral_positions(*args)


def test_different_left_wheel_shifts_the_equilibrium():
    """Right cone 0.15, left cone 0.05, level wheelset (hand): Delta r = d0 + (0.15 + 0.05) y with an offset d0 (the
    cones touch the rail at different points; 1.93 mm), so the oscillation is about y0 = -d0 / 0.2 (-9.6 mm) and both
    methods give (0.15 + 0.05) / 2 = 0.1 at every amplitude (the harmonic one about y = 0: the offset drops out)."""
    profiles = WheelsetProfiles(Rail60E1(), cone(0.15), left_wheel=cone(0.05))
    got = contact_geometry(profiles, TrackLayout(), -20.0, 11.0, 0.25, amplitudes_mm=[1.0, 3.0, 5.0], with_roll=False)
    y, dr = got.sweep.lateral_mm, got.sweep.delta_r_mm
    d0 = float(dr[y == 0.0][0])
    assert abs(d0) > 0.1
    assert np.max(np.abs(dr - d0 - 0.2 * y)) < 1e-8
    assert np.allclose(got.conicity.equivalent_conicity, 0.1, rtol=1e-8)
    assert np.allclose(got.conicity.harmonic_conicity, 0.1, rtol=1e-9)
