"""Contact search of S1002 on 60E1 at 1:40: known geometry, separation function, KP radius, bad input."""

import math

import numpy as np
import pytest

from contact.wheel_rail import contact_search
from contact.wheel_rail.contact_search import first_contact_radius, search_contacts
from contact.wheel_rail.track_geometry import TrackLayout, WheelsetPose, place_rail, wheel_locus
from wrlayer.errors import InputError


def test_centred_contact_near_crown_and_taping_line(placed, s1002, layout):
    res = search_contacts(placed, s1002, layout, WheelsetPose(0.0))
    c = res.candidates[0]
    assert c.vertical_gap_mm == pytest.approx(0.0, abs=1e-12)
    # rail: near the head centre line (crown), on the gauge side of the canted rail's highest point (q ~ +7.5)
    assert abs(c.y_rail_mm) < 3.0
    assert 3.0 < placed.top_q_mm - c.y_rail_mm < 10.0
    # wheel: near the taping line; contact angle close to the cant (tread conicity ~ 1:40)
    assert abs(c.y_wheel_mm) < 5.0
    assert 0.5 < math.degrees(c.contact_angle_rad) < 3.0


def test_contact_moves_to_flange_root_then_flange(placed, s1002, layout):
    rows = []
    for d in np.arange(0.0, 10.01, 0.5):
        res = search_contacts(placed, s1002, layout, WheelsetPose(float(d)))
        first = min(res.candidates, key=lambda c: c.vertical_gap_mm)
        rows.append((d, first.y_rail_mm, first.y_wheel_mm, math.degrees(first.contact_angle_rad)))
    rows = np.array(rows)
    # towards the gauge side on both profiles and with steeper contact angles as the wheelset moves to this rail
    assert np.all(np.diff(rows[1:, 1]) < 0.5)
    assert rows[2, 1] < -5 and rows[2, 2] < -5                # already jumped towards the gauge corner
    assert np.any((rows[:, 2] < -25) & (rows[:, 3] > 15))     # flange root
    assert rows[-1, 3] > 55 and rows[-1, 2] < -38             # flange
    # the jump: somewhere the rail contact point moves by more than 8 mm in one 0.5 mm step
    assert np.max(np.abs(np.diff(rows[:, 1]))) > 8.0


def test_two_candidates_near_the_jump(placed, s1002, layout):
    res = search_contacts(placed, s1002, layout, WheelsetPose(5.0))
    assert len(res.candidates) >= 2
    angles = sorted(math.degrees(c.contact_angle_rad) for c in res.candidates)
    assert angles[0] < 10 and angles[-1] > 14


def test_separation_function_lies_between_the_profiles(placed, s1002, layout):
    pose = WheelsetPose(6.0, 0.01, 0.001)
    res = search_contacts(placed, s1002, layout, pose)
    for c in res.candidates:
        assert c.f_mm.min() == pytest.approx(c.normal_gap_mm, abs=1e-12)
        P = np.array([c.Y_mm, c.Z_mm])
        t, n = c.lateral[1:], c.normal[1:]
        sel = np.linspace(0, c.eta_mm.size - 1, 15).astype(int)
        eta, f = c.eta_mm[sel], c.f_mm[sel]
        # the rail point on each normal line lies on the rail profile (independent check via signed_distance)
        q = c.rail_coordinate(eta)
        rp = placed.point(q)
        zeta_r = (rp - P) @ n
        assert np.allclose((rp - P) @ t, eta, atol=2e-6)
        unplaced_angle = -placed.angle_rad
        rel = rp - np.array([placed.dy_mm, placed.dz_mm])
        cs, sn = math.cos(unplaced_angle), math.sin(unplaced_angle)
        prof_pts = np.column_stack([cs * rel[:, 0] - sn * rel[:, 1], sn * rel[:, 0] + cs * rel[:, 1]])
        d, _ = placed.profile.signed_distance(prof_pts)
        assert np.max(np.abs(d)) < 1e-8
        # the wheel point at zeta_r + f on the same line is on the wheel's contact locus (at rigid contact height)
        wp = P + eta[:, None] * t + (zeta_r + f)[:, None] * n
        yw = c.wheel_coordinate(eta)
        loc = wheel_locus(s1002, layout, pose, yw)
        assert np.allclose(loc.Y_mm, wp[:, 0], atol=1e-6)
        assert np.allclose(loc.Z_mm + res.wheel_height_mm, wp[:, 1], atol=1e-6)


def test_kp_radius_without_yaw_is_r_over_cos(placed, s1002, layout):
    for d in (0.0, 3.0, 8.0):
        for c in search_contacts(placed, s1002, layout, WheelsetPose(d)).candidates:
            assert c.rolling_radius_kp_mm == pytest.approx(c.wheel_radius_mm / math.cos(c.wheel_contact_angle_rad),
                                                           rel=1e-9)


@pytest.mark.parametrize("pose", [WheelsetPose(6.0, 0.03, 0.002), WheelsetPose(8.0, -0.05, 0.0),
                                  WheelsetPose(1.0, 0.04, -0.003)])
def test_kp_radius_with_yaw_matches_the_wheel_surface(placed, s1002, layout, pose):
    """Independent check of Euler's formula: intersect the exact wheel surface of revolution with the lines
    P + X e_X + zeta n and fit zeta = X^2 / (2 R)."""
    from scipy.optimize import brentq

    from contact.wheel_rail.track_geometry import axle_direction

    res = search_contacts(placed, s1002, layout, pose)
    a = axle_direction(pose)
    centre = np.array([0.0, pose.lateral_mm, res.wheel_height_mm])

    def surface(p):  # distance from the axle minus the profile radius at the point's axial position
        rel = p - centre
        s = rel @ a
        return np.linalg.norm(rel - s * a) - (layout.nominal_radius_mm - s1002.z(s - layout.taping_line_mm))

    for c in res.candidates:
        n = c.normal
        xs = np.array([-2.0, -1.0, 1.0, 2.0])
        starts = [c.wheel_point + x * np.array([1.0, 0.0, 0.0]) for x in xs]
        zeta = [brentq(lambda z, p0=p0, n=n: surface(p0 + z * n), -0.2, 0.2, xtol=1e-14) for p0 in starts]
        coeff = np.polyfit(xs, zeta, 2)
        assert 1.0 / (2.0 * coeff[0]) == pytest.approx(c.rolling_radius_kp_mm, rel=2e-3)


def test_bad_geometry_names_the_case(placed, s1002, layout, rail60):
    with pytest.raises(InputError, match="case A: flange through the rail"):
        search_contacts(placed, s1002, layout, WheelsetPose(25.0), case="case A")
    wide = TrackLayout(gauge_mm=1620.0)
    with pytest.raises(InputError, match="case B: the profiles do not meet"):
        search_contacts(place_rail(rail60, wide), s1002, wide, WheelsetPose(0.0), case="case B")
    with pytest.raises(InputError, match="wheel profile"):
        search_contacts(placed, rail60, layout, WheelsetPose(0.0))


def test_first_contact_radius_is_the_searched_first_contacts(placed, s1002, layout, monkeypatch):
    """The rolling radius without the candidates' separation functions is the radius of the candidate with the
    smallest normal gap, bit for bit, across the jump to the flange (two candidates at 5 mm); within the tie
    distance of the two lowest minima the candidates decide (forced here by a tie distance larger than any gap)."""
    def searched(d):
        res = search_contacts(placed, s1002, layout, WheelsetPose(float(d)))
        return min(res.candidates, key=lambda c: c.normal_gap_mm).wheel_radius_mm, len(res.candidates)

    displacements = np.arange(-4.0, 10.01, 0.5)
    expected = [searched(d) for d in displacements]
    assert max(n for _, n in expected) >= 2
    got = [first_contact_radius(placed, s1002, layout, WheelsetPose(float(d))) for d in displacements]
    assert got == [r for r, _ in expected]
    calls = []
    monkeypatch.setattr(contact_search, "FIRST_CONTACT_TIE_MM", 10.0)
    monkeypatch.setattr(contact_search, "search_contacts", lambda *a, **k: calls.append(1) or search_contacts(*a, **k))
    assert first_contact_radius(placed, s1002, layout, WheelsetPose(5.0)) == searched(5.0)[0] and calls
