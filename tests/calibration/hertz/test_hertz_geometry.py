"""Hertz ellipse from curvatures: closed-form circle, Boussinesq integration of the elliptic pressure, mating."""

import math

import pytest
from scipy.integrate import quad

from calibration.hertz.geometry import (combined_modulus_MPa, halfspace_centre_compliance_mm_per_MPa,
                                        hertz_ellipse, local_geometry, mating_position)
from wrlayer.errors import InputError
from meshes.profiles import get_profile

E, NU = 210000.0, 0.3


def test_sphere_on_flat_matches_the_closed_form():
    R, N = 100.0, 1000.0
    Es = combined_modulus_MPa(E, NU)
    h = hertz_ellipse(1 / (2 * R), 1 / (2 * R), N, Es)
    a = (3 * N * R / (4 * Es)) ** (1 / 3)
    assert h.a_mm == pytest.approx(a, rel=1e-10) and h.b_mm == pytest.approx(a, rel=1e-10)
    assert h.p0_MPa == pytest.approx(3 * N / (2 * math.pi * a * a), rel=1e-10)
    assert h.approach_mm == pytest.approx(a * a / R, rel=1e-10)


def _boussinesq(x0, y0, a, b, p0, Es):
    """Normal displacement (both bodies) at (x0, y0) of p0 sqrt(1 - x^2/a^2 - y^2/b^2): polar integration around
    the point, u = 1/(pi E*) int int p dr dtheta."""

    def ray(theta):
        c, s = math.cos(theta), math.sin(theta)
        A = (c / a) ** 2 + (s / b) ** 2
        B = 2 * (x0 * c / a ** 2 + y0 * s / b ** 2)
        C = (x0 / a) ** 2 + (y0 / b) ** 2 - 1
        r_end = (-B + math.sqrt(B * B - 4 * A * C)) / (2 * A)
        f = lambda r: p0 * math.sqrt(max(0.0, 1 - ((x0 + r * c) / a) ** 2 - ((y0 + r * s) / b) ** 2))
        return quad(f, 0, r_end, epsabs=1e-12, epsrel=1e-9, limit=100)[0]

    return quad(ray, 0, 2 * math.pi, epsabs=1e-11, epsrel=1e-8, limit=100)[0] / (math.pi * Es)


@pytest.mark.parametrize("A,B", [(1 / 920, 1 / 600), (1 / 920, 1 / 26), (1 / 40, 1 / 2000)])
def test_ellipse_reproduces_the_gap_by_boussinesq_integration(A, B):
    Es = combined_modulus_MPa(E, NU)
    h = hertz_ellipse(A, B, 50000.0, Es)
    assert 2 / 3 * math.pi * h.a_mm * h.b_mm * h.p0_MPa == pytest.approx(50000.0, rel=1e-12)
    u0 = _boussinesq(0, 0, h.a_mm, h.b_mm, h.p0_MPa, Es)
    assert u0 == pytest.approx(h.approach_mm, rel=1e-6)
    x1, y1 = 0.5 * h.a_mm, 0.5 * h.b_mm
    assert _boussinesq(x1, 0, h.a_mm, h.b_mm, h.p0_MPa, Es) == pytest.approx(h.approach_mm - A * x1 ** 2, rel=1e-6)
    assert _boussinesq(0, y1, h.a_mm, h.b_mm, h.p0_MPa, Es) == pytest.approx(h.approach_mm - B * y1 ** 2, rel=1e-6)
    # one body's centre displacement is half the approach for equal materials
    c = halfspace_centre_compliance_mm_per_MPa(h.a_mm, h.b_mm, E, NU)
    assert 2 * c * h.p0_MPa == pytest.approx(h.approach_mm, rel=1e-10)


def test_non_positive_curvature_sum_is_an_input_error():
    with pytest.raises(InputError, match="curvature sums"):
        hertz_ellipse(1e-3, -1e-3, 1000.0, 1e5)


def test_rail_crown_mates_with_the_wheel_tread_near_the_taping_line():
    rail, wheel = get_profile("60E1"), get_profile("S1002")
    y, rule = mating_position(rail, 0.0, wheel)
    assert rule == "tangent" and abs(y) < 10
    # tangent: equal track-frame slopes (rail canted by 1:40)
    assert math.atan(wheel.dz(y)) == pytest.approx(math.atan(rail.dz(0.0)) + math.atan(1 / 40), abs=1e-9)
    g = local_geometry(rail, -15.0, wheel, 100000.0, E, NU)
    assert g.a_mm > 0 and g.b_mm > 0 and g.p0_ref_MPa > 0 and g.k_x_per_mm == 0.0
    assert g.k_x_mate_per_mm == pytest.approx(1 / float(wheel.radius(g.y_mate_mm)))


def test_position_outside_the_profile_names_it():
    with pytest.raises(InputError, match="y = 80 mm"):
        local_geometry(get_profile("60E1"), 80.0, get_profile("S1002"), 1e5, E, NU)
