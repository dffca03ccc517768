"""Characteristic <-> Prandtl parameters (eqs. 4–6), residual displacement (eq. 8), series and interpolation."""

import numpy as np
import pytest
from hypothesis import given, settings, strategies as st

from wrlayer.characteristic import Characteristic, PrandtlParameters
from wrlayer.errors import InputError


def paper_like() -> Characteristic:
    # S1 = 5.9e4 N/mm^3, p2 = 1190 MPa (paper-notes inferences), then softer segments.
    return Characteristic([0.0, 0.02017, 0.03, 0.06], [0.0, 1190.0, 1450.0, 1700.0])


def test_equations_4_to_6_by_hand():
    c = Characteristic([0.0, 1.0, 3.0, 4.0], [0.0, 10.0, 16.0, 17.0])  # slopes 10, 3, 1
    par = c.to_parameters()
    np.testing.assert_allclose(par.k_N_per_mm3, [7.0, 2.0, 1.0])      # k1 = S1-S2, k2 = S2-S3, k3 = S3
    np.testing.assert_allclose(par.T0_MPa, [7.0 * 1.0, 2.0 * 3.0])     # T0i = k_i u_{i+1}
    np.testing.assert_allclose(par.break_displacements_mm, [1.0, 3.0])


def test_round_trip_parameters():
    c = paper_like()
    back = Characteristic.from_parameters(c.to_parameters(), u_end_mm=c.u_mm[-1])
    np.testing.assert_allclose(back.u_mm, c.u_mm, rtol=1e-12)
    np.testing.assert_allclose(back.p_MPa, c.p_MPa, rtol=1e-12)


def test_residual_matches_equation_8_segment_by_segment():
    c = paper_like()
    s = c.slopes
    for p0 in [500.0, 1190.0, 1300.0, 1456.0, 1600.0, 2000.0]:
        i = min(np.searchsorted(c.p_MPa, p0, side="right") - 1, c.n_segments - 1)
        eq8 = c.u_mm[i] + (p0 - c.p_MPa[i]) / s[i] - p0 / s[0]
        assert c.residual_displacement(p0) == pytest.approx(max(eq8, 0.0), abs=1e-15)
    assert c.residual_displacement(1000.0) == 0.0  # below p2: elastic


def test_pressure_displacement_inverse_and_secant():
    c = paper_like()
    u = np.linspace(0, 0.1, 57)
    np.testing.assert_allclose(c.displacement(c.pressure(u)), u, atol=1e-15)
    p = c.pressure(0.045)
    assert c.secant_stiffness(p) * 0.045 == pytest.approx(p)


@pytest.mark.parametrize("u,p,msg", [
    ([0, 1, 2], [0, 1, 3], "concave"),
    ([0, 1, 1], [0, 1, 2], "strictly increasing"),
    ([0, 1, 2], [0, 2, 1], "strictly increasing"),
    ([0.1, 1], [0, 1], "(0, 0)"),
    ([0, np.nan], [0, 1], "NaN"),
    ([0], [0], "at least 2"),
])
def test_invalid_characteristics_are_refused(u, p, msg):
    with pytest.raises(InputError, match=msg.replace("(", r"\(").replace(")", r"\)")):
        Characteristic(u, p, name="layer.rail")


def test_from_parameters_rejects_non_physical():
    with pytest.raises(InputError):
        Characteristic.from_parameters(PrandtlParameters(np.array([1.0, -1.0]), np.array([1.0])))
    with pytest.raises(InputError):  # break displacements not increasing
        Characteristic.from_parameters(PrandtlParameters(np.array([1.0, 1.0, 1.0]), np.array([2.0, 1.0])))


concave = st.lists(st.tuples(st.floats(1e-3, 1.0), st.floats(0.05, 0.95)), min_size=1, max_size=6).map(
    lambda segs: _build(segs))


def _build(segs):
    u, p, slope = [0.0], [0.0], 1e5
    for du, ratio in segs:
        u.append(u[-1] + du * 0.01)
        p.append(p[-1] + slope * du * 0.01)
        slope *= ratio
    return Characteristic(u, p)


@settings(max_examples=60, deadline=None)
@given(concave, concave, st.floats(0, 1))
def test_series_adds_displacements_and_interpolation_stays_physical(a, b, t):
    c = a.series(b)
    p = np.linspace(0, 0.99 * min(a.p_MPa[-1], b.p_MPa[-1]), 23)
    np.testing.assert_allclose(c.displacement(p), a.displacement(p) + b.displacement(p), rtol=1e-9, atol=1e-15)
    m = Characteristic.interpolate(a, b, t)
    u = np.linspace(0, max(a.u_mm[-1], b.u_mm[-1]), 31)
    np.testing.assert_allclose(m.pressure(u), (1 - t) * a.pressure(u) + t * b.pressure(u), rtol=1e-9)
    # residual never decreasing with peak pressure, never negative
    r = c.residual_displacement(np.linspace(0, 2 * c.p_MPa[-1], 40))
    assert np.all(r >= 0) and np.all(np.diff(r) >= -1e-15)


def test_reverse_factor_round_trip_interpolation_and_bounds():
    from wrlayer.characteristic import Characteristic as C

    a = C([0.0, 0.02, 0.03, 0.06], [0.0, 1190.0, 1456.0, 1900.0], "a", 2.0)
    assert C.from_dict(a.to_dict()).reverse_factor == 2.0
    assert "reverse_factor" not in C(a.u_mm, a.p_MPa).to_dict()  # the paper's element is written as before
    b = C(a.u_mm, a.p_MPa, "b")
    assert C.interpolate(a, b, 0.25).reverse_factor == pytest.approx(1.75)
    assert a.series(b).reverse_factor == 1.0
    assert a.with_points(a.u_mm * 2, a.p_MPa).reverse_factor == 2.0
    for bad in (0.0, -1.0, float("nan"), True, 1e4):
        with pytest.raises(InputError, match="reverse_factor"):
            C(a.u_mm, a.p_MPa, "x", bad)
