"""Analytic profiles: S1002 checks from profiles.md, rail-head construction, generic geometry."""

import itertools

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy.interpolate import CubicSpline
from scipy.optimize import brentq

from wrlayer.errors import InputError
from meshes.meshing.gmsh_session import gmsh_session
from meshes.profiles.base import check_closed, outline_area
from meshes.profiles import (
    S1002,
    Arc,
    Line,
    PointCurve,
    Rail54E1,
    Rail60E1,
    SplineProfile,
    get_profile,
)
from meshes.profiles.s1002 import BOUNDS, section_pieces_raw


@pytest.fixture(scope="module")
def wheel():
    return S1002()


@pytest.fixture(scope="module", params=["60E1", "54E1"])
def rail(request):
    return get_profile(request.param)


# ---------------------------------------------------------------- S1002 (profiles.md checks)
def test_s1002_flange_height_and_taping_line(wheel):
    assert wheel.F(-55.0) == pytest.approx(28.0, abs=1e-9)
    assert wheel.F(0.0) == pytest.approx(0.0, abs=1e-12)
    assert wheel.radius(0.0) == pytest.approx(460.0)
    assert S1002(r0=500.0).radius(-55.0) == pytest.approx(528.0)


def test_s1002_sections_join(wheel):
    pieces = list(section_pieces_raw().values())
    for a, b in itertools.pairwise(pieces):
        assert a.yb == b.ya
        assert abs(float(a.z(a.yb)) - float(b.z(b.ya))) < 1.5e-4   # profiles.md: "about 1e-4 mm"
        assert abs(float(a.dz(a.yb)) - float(b.dz(b.ya))) < 1e-5   # tangent joins


def test_s1002_flange_face_slope(wheel):
    y = np.linspace(BOUNDS[3], BOUNDS[4], 7)
    assert np.allclose(wheel.dz(y), np.tan(np.radians(70.0)), atol=1e-4)   # F' = -tan 70 deg


def test_s1002_flange_thickness(wheel):
    s_flange_face = brentq(lambda s: wheel.F(s) - 10.0, -45.0, -30.0)
    assert s_flange_face - (-70.0) == pytest.approx(32.5, abs=5e-3)


def test_s1002_flange_back_is_vertical(wheel):
    assert wheel.dz(-70.0) == -np.inf
    assert np.allclose(wheel.normal(-70.0), [-1.0, 0.0])           # out of the flange back
    assert wheel.curvature(-70.0) == pytest.approx(1 / 20.5)
    assert np.isfinite(S1002(y_min=-69.9).dz(-69.9))


def test_s1002_normal_points_out_of_wheel(wheel):
    n = wheel.normal(np.array([-55.0, 0.0, 50.0]))
    assert np.all(n[:, 1] < 0)                     # towards the rail (down)
    assert np.allclose(np.hypot(n[:, 0], n[:, 1]), 1.0)


def test_s1002_point_curves_within_1e4_mm(wheel):
    """A cubic spline and Gmsh's Catmull-Rom spline through the points follow the polynomials."""
    with gmsh_session("point-curve-check") as gmsh:
        for seg in wheel.surface_segments():
            if not isinstance(seg, PointCurve):
                continue
            p = seg.points
            t = np.r_[0.0, np.cumsum(np.hypot(*np.diff(p, axis=0).T))]
            q = CubicSpline(t, p)(np.linspace(0.0, t[-1], 4001))
            d, _ = wheel.signed_distance(q)
            # at the C/D join the standard's own sections differ by 1.18e-4 mm (see test above)
            assert np.abs(d).max() < 1.2e-4
            inner = (q[:, 0] > p[0, 0] + 0.5) & (q[:, 0] < p[-1, 0] - 0.5)
            assert np.abs(d[inner]).max() < 1e-5
            curve = gmsh.model.geo.addSpline([gmsh.model.geo.addPoint(y, z, 0.0) for y, z in p])
            gmsh.model.geo.synchronize()
            lo, hi = gmsh.model.getParametrizationBounds(1, curve)
            xyz = np.reshape(gmsh.model.getValue(1, curve, np.linspace(lo[0], hi[0], 4001)), (-1, 3))
            d, _ = wheel.signed_distance(xyz[:, :2])
            inner = (xyz[:, 0] > p[0, 0] + 0.5) & (xyz[:, 0] < p[-1, 0] - 0.5)
            assert np.abs(d).max() < 1.2e-4 and np.abs(d[inner]).max() < 1e-4


def test_s1002_section_outline_closed_ccw(wheel):
    out = wheel.section_outline(40.0)
    check_closed(out)
    assert {s.tag for s in out} == {"surface", "side", "fixed"}
    assert [s.tag for s in out[-3:]] == ["side", "fixed", "side"]
    assert out[-2].start[1] == out[-2].end[1] == 40.0
    # area against a direct integral of (40 - z) over y
    y = np.linspace(-70.0, 60.0, 200001)
    direct = np.trapezoid(40.0 - wheel.z(y), y)
    assert wheel.section_area(40.0) == pytest.approx(direct, rel=1e-6)
    with pytest.raises(InputError, match="depth_mm"):
        wheel.section_outline(1.0)


# ---------------------------------------------------------------- rail heads
def test_head_widths():
    assert Rail60E1().head_width == pytest.approx(72.0, abs=1e-3)
    assert Rail54E1().head_width == pytest.approx(70.0, abs=1e-3)


def test_60e1_arc_centres_match_notes():
    g = Rail60E1().geometry
    assert np.allclose(g.c_mid, [7.5005, -80.1279], atol=1e-4)
    assert np.allclose(g.c_corner, [23.0160, -14.9491], atol=1e-4)
    assert np.allclose(g.p_flank_top, [36.0, -14.3], atol=1e-3)


def test_rail_tangent_at_every_joint(rail):
    out = rail.section_outline(70.0)
    check_closed(out)

    def tangents(seg):
        if isinstance(seg, Line):
            t = np.subtract(seg.end, seg.start)
            return t, t
        c = np.array(seg.centre)
        r0, r1 = np.subtract(seg.start, c), np.subtract(seg.end, c)
        s = np.sign(seg.sweep())
        return s * np.array([-r0[1], r0[0]]), s * np.array([-r1[1], r1[0]])

    corners = []
    for a, b in zip(out, out[1:] + out[:1]):
        ta, tb = tangents(a)[1], tangents(b)[0]
        cross = (ta[0] * tb[1] - ta[1] * tb[0]) / (np.linalg.norm(ta) * np.linalg.norm(tb))
        if abs(cross) > 1e-9:
            corners.append(a.end)
        else:
            assert np.dot(ta, tb) > 0
    # the only sharp corners: web/cut (2) and web/underside (2), all on |y| = 8.25
    assert len(corners) == 4
    assert np.allclose(np.abs([c[0] for c in corners]), 8.25)


def test_rail_curvatures(rail):
    c = rail.curvature
    assert c(0.0) == pytest.approx(-1 / 300)     # z'' < 0: the crown bends down
    g = rail.geometry
    y80 = 0.5 * (g.p_crown_end[0] + g.p_mid_end[0])
    y13 = 0.5 * (g.p_mid_end[0] + g.p_flank_top[0])
    assert c(y80) == pytest.approx(-1 / 80) and c(-y80) == pytest.approx(-1 / 80)
    assert c(y13) == pytest.approx(-1 / 13) and c(-y13) == pytest.approx(-1 / 13)
    assert rail.dz(rail.y_max) == pytest.approx(-20.0)    # R13 meets the 1:20 flank
    assert rail.z(-7.0) == pytest.approx(rail.z(7.0))
    assert np.allclose(rail.normal(0.0), [0.0, 1.0])


def test_rail_section_area_against_polygon(rail):
    out = rail.section_outline(80.0)
    pts = []
    for seg in out:
        if isinstance(seg, Arc):
            c, r = np.array(seg.centre), seg.radius
            a0 = np.arctan2(seg.start[1] - c[1], seg.start[0] - c[0])
            a = a0 + np.linspace(0.0, seg.sweep(), 20001)[:-1]
            pts.append(c + r * np.column_stack([np.cos(a), np.sin(a)]))
        else:
            pts.append(np.array([seg.start]))
    p = np.vstack(pts)
    polygon = 0.5 * np.sum(p[:, 0] * np.roll(p[:, 1], -1) - np.roll(p[:, 0], -1) * p[:, 1])
    assert rail.section_area(80.0) == pytest.approx(polygon, rel=1e-8)
    assert rail.section_area(80.0) > 0
    # a deeper cut adds exactly the web strip
    assert rail.section_area(90.0) - rail.section_area(80.0) == pytest.approx(10.0 * 16.5)


# ---------------------------------------------------------------- generic geometry
@pytest.mark.parametrize("name", ["S1002", "60E1", "54E1"])
def test_sample_and_arc_length_round_trip(name):
    prof = get_profile(name)
    y, z = prof.sample(0.5)
    assert y[0] == prof.y_min and y[-1] == prof.y_max
    s = prof.arc_length(y)
    assert np.all(np.diff(s) <= 0.5 + 1e-9) and np.all(np.diff(s) > 0)
    assert np.all(np.hypot(np.diff(y), np.diff(z)) <= 0.5 + 1e-9)
    assert np.allclose(prof.y_at_arc_length(s), y, atol=1e-9)
    # arc length against the polygon length of a fine sample
    yf, zf = prof.sample(0.01)
    assert prof.length == pytest.approx(np.sum(np.hypot(np.diff(yf), np.diff(zf))), rel=1e-6)


@settings(max_examples=60, deadline=None)
@given(st.sampled_from(["S1002", "60E1"]), st.floats(0.0, 1.0))
def test_arc_length_inverse_property(name, frac):
    prof = get_profile(name)
    s = frac * prof.length
    # y is a poor coordinate at the vertical flange back (y = -70 + s^2 / 2R): there s(y(s)) is
    # only good to sqrt(2 R eps |y|) ~ 1e-6 mm; elsewhere to round-off
    assert prof.arc_length(prof.y_at_arc_length(s)) == pytest.approx(s, abs=2e-6)


def test_curvature_and_normal_consistent_with_derivatives(wheel):
    y = np.linspace(-60.0, 55.0, 301)
    z1, z2 = wheel.dz(y), wheel.d2z(y)
    assert np.allclose(wheel.curvature(y), z2 / (1 + z1**2) ** 1.5)
    n = wheel.normal(y)
    assert np.allclose(n[:, 0] * 1.0 + n[:, 1] * z1, 0.0)          # normal is perpendicular
    h = 1e-5                                                          # slope by finite differences
    assert np.allclose((wheel.z(y + h) - wheel.z(y - h)) / (2 * h), z1, atol=1e-5)


def test_out_of_range_raises(wheel):
    with pytest.raises(InputError, match=r"outside the profile's valid range \[-70, 60\] mm"):
        wheel.z(61.0)
    with pytest.raises(InputError, match="contact y"):
        wheel.check_y([0.0, -80.0], "contact y")
    with pytest.raises(InputError, match="s"):
        wheel.y_at_arc_length(-1.0)


@pytest.mark.parametrize("name", ["S1002", "60E1"])
def test_one_point_is_the_array_value(name):
    """A single point (float, 0-d or 1-element array) is evaluated on its own path: the same piece and the same
    value, bit for bit, as inside an array, at every joint of the pieces, at the ends and within round-off beyond
    them; the result's shape follows the input's."""
    prof = get_profile(name)
    joints = [p.yb for p in prof._pieces[:-1]]
    ys = np.array(sorted(joints + [prof.y_min, prof.y_max, prof.y_min - 5e-10, prof.y_max + 5e-10, 0.3]
                         + [j + d for j in joints for d in (-1e-9, 1e-9)]))
    for method, trailing in (("z", ()), ("dz", ()), ("d2z", ()), ("curvature", ()), ("normal", (2,))):
        many = getattr(prof, method)(ys)
        for k, y in enumerate(ys):
            one, arr, zero_d = (getattr(prof, method)(v) for v in (float(y), np.array([y]), np.array(y)))
            assert np.shape(one) == np.shape(zero_d) == trailing and np.shape(arr) == (1,) + trailing
            for v in (one, arr.reshape(trailing), zero_d):
                assert np.array_equal(v, many[k])
    with pytest.raises(InputError, match="outside the profile's valid range"):
        prof.z(np.array([prof.y_max + 1e-6]))
    with pytest.raises(InputError, match="outside the profile's valid range"):
        prof.z(float("nan"))


def test_spline_profile():
    y = np.linspace(-20.0, 20.0, 81)
    prof = SplineProfile(y, 300.0 - np.sqrt(300.0**2 - y**2) * 1.0 - 0.0, "bowl", "wheel")
    assert prof.curvature(0.0) == pytest.approx(1 / 300, rel=1e-4)
    assert np.allclose(prof.normal(0.0), [0.0, -1.0])
    (seg,) = prof.surface_segments()
    assert isinstance(seg, PointCurve) and seg.start == (-20.0, prof.z(-20.0))
    with pytest.raises(InputError, match="strictly increasing"):
        SplineProfile([0, 1, 1, 2], [0, 0, 0, 0], "bad", "rail")
    with pytest.raises(InputError, match="at least 4"):
        SplineProfile([0, 1, 2], [0, 0, 0], "bad", "rail")


def test_get_profile_names():
    assert isinstance(get_profile("uic60"), Rail60E1)
    assert isinstance(get_profile("UIC54"), Rail54E1)
    assert get_profile("S1002", r0=430.0).r0 == 430.0
    with pytest.raises(InputError, match="'R65'.*S1002, 60E1, UIC60, 54E1, UIC54"):
        get_profile("R65")
    with pytest.raises(InputError, match=r"60E1 does not take option\(s\) \['r0'\]"):
        get_profile("60E1", r0=460.0)


def test_outline_area_of_unit_square_with_arc():
    # square [0,1]^2 with the top edge replaced by a half-disc bump of radius 0.5: arcs < 180 deg
    quarter = [Arc((1.0, 1.0), (0.5, 1.5), (0.5, 1.0)), Arc((0.5, 1.5), (0.0, 1.0), (0.5, 1.0))]
    loop = [Line((0.0, 0.0), (1.0, 0.0)), Line((1.0, 0.0), (1.0, 1.0))] + quarter + [Line((0.0, 1.0), (0.0, 0.0))]
    assert outline_area(loop) == pytest.approx(1.0 + np.pi * 0.25 / 2)


@pytest.mark.parametrize("name", ["S1002", "60E1"])
def test_signed_distance_along_normals(name):
    prof = get_profile(name)
    y = np.r_[np.linspace(prof.y_min + 0.01, prof.y_max - 0.01, 97), prof.y_max - 1e-3]
    d = np.resize([0.4, -0.3, 0.0, 0.05], y.size)
    pts = np.column_stack([y, prof.z(y)]) + d[:, None] * prof.normal(y)
    dist, foot = prof.signed_distance(pts)
    assert np.allclose(dist, d, atol=1e-9)
    assert np.allclose(foot, y, atol=1e-7)
    # beyond the end: distance to the end point
    end = np.array([prof.y_max, prof.z(prof.y_max)])
    dist, foot = prof.signed_distance([end + 2.0 * prof.normal(prof.y_max)])
    assert foot[0] == prof.y_max and dist[0] == pytest.approx(2.0)


def test_block_section_of_a_spline_rail():
    y = np.linspace(-30.0, 30.0, 121)
    prof = SplineProfile(y, -(y**2) / 600.0, "parabola", "rail")
    out = prof.section_outline(20.0)
    check_closed(out)
    assert [s.tag for s in out] == ["fixed", "side", "surface", "side"]
    exact = 60.0 * 20.0 - 2 * 30.0**3 / 3 / 600.0        # integral of (z + 20) over y
    assert prof.section_area(20.0) == pytest.approx(exact, rel=1e-10)
    with pytest.raises(InputError, match="depth_mm"):
        prof.section_outline(1.0)


@pytest.mark.parametrize("name", ["S1002", "60E1"])
def test_profiles_pickle(name):
    import pickle

    prof = get_profile(name)
    y = np.linspace(prof.y_min, prof.y_max, 11)
    for p in (prof, SplineProfile(y, prof.z(y), "s", prof.body)):
        copy = pickle.loads(pickle.dumps(p))
        assert np.array_equal(copy.z(y), p.z(y)) and copy.length == p.length
