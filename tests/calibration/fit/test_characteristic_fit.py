"""The piecewise-linear concave fitter: exact recovery, noise, constraints, and the Prandtl-element round trip."""

import numpy as np
import pytest

from calibration.fit.characteristic_fit import fit_characteristic
from wrlayer.characteristic import Characteristic
from wrlayer.errors import InputError

KNOWN = Characteristic(np.array([0.0, 0.01, 0.03, 0.08]), np.array([0.0, 800.0, 1200.0, 1500.0]))


def _points(ch, n=41):
    p = np.linspace(0.0, ch.p_MPa[-1], n)
    return p, ch.displacement(p)


@pytest.mark.parametrize("pinned", [False, True])
def test_recovers_a_known_characteristic_exactly(pinned):
    p, u = _points(KNOWN)
    kw = dict(s1_N_per_mm3=KNOWN.initial_stiffness, p2_MPa=800.0) if pinned else {}
    fit = fit_characteristic(p, u, 3, **kw)
    np.testing.assert_allclose(fit.characteristic.p_MPa, KNOWN.p_MPa, rtol=1e-7, atol=1e-6)
    np.testing.assert_allclose(fit.characteristic.u_mm, KNOWN.u_mm, rtol=1e-7, atol=1e-10)
    assert fit.max_error_mm < 1e-9
    par, ref = fit.parameters, KNOWN.to_parameters()
    np.testing.assert_allclose(par.k_N_per_mm3, ref.k_N_per_mm3, rtol=1e-6)
    np.testing.assert_allclose(par.T0_MPa, ref.T0_MPa, rtol=1e-6)


def test_noisy_points_are_fitted_within_the_noise():
    p, u = _points(KNOWN, 81)
    sigma = 2e-4
    noisy = u + np.random.default_rng(1).normal(0.0, sigma, u.size)
    fit = fit_characteristic(p, noisy, 3)
    # the fit is as close to the data as the truth is (least squares) and close to the truth
    assert fit.rms_error_mm <= np.sqrt(np.mean((noisy - u) ** 2)) * (1 + 1e-9)
    assert np.max(np.abs(fit.characteristic.displacement(p) - u)) < 3 * sigma
    assert np.all(np.diff(fit.characteristic.slopes) < 0) and np.all(fit.characteristic.slopes > 0)


def test_more_segments_never_fit_worse_and_parameters_are_physical():
    p = np.linspace(0, 1600, 60)
    u = 1e-3 * p / 800 + 2e-7 * np.maximum(p - 700, 0) ** 2  # smooth convex u(p): elastic then plastic
    errors = []
    for n in range(2, 5):
        fit = fit_characteristic(p, u, n, s1_N_per_mm3=800e3, p2_MPa=700.0, max_relative_error=1.0)
        assert np.all(fit.parameters.k_N_per_mm3 > 0) and np.all(fit.parameters.T0_MPa > 0)
        assert fit.characteristic.elastic_limit_MPa == pytest.approx(700.0)
        errors.append(fit.rms_error_mm)
    assert all(b <= a * (1 + 1e-6) for a, b in zip(errors, errors[1:]))


@pytest.mark.parametrize("n", [0, 17, 2.5, True])
def test_segment_count_out_of_range(n):
    p, u = _points(KNOWN)
    with pytest.raises(InputError, match="number of segments"):
        fit_characteristic(p, u, n, what="rail y = 0 mm")


def test_decreasing_displacement_cannot_be_fitted_and_names_the_position():
    p = np.linspace(0, 1000, 11)
    u = 1e-5 * p
    u[6] = 0.5 * u[4]
    with pytest.raises(InputError, match="rail y = 5 mm: displacement decreases"):
        fit_characteristic(p, u, 2, what="rail y = 5 mm", max_relative_error=0.05)


def test_stiffening_data_cannot_be_fitted_with_decreasing_slopes():
    p = np.linspace(0, 1000, 30)
    u = 1e-4 * np.sqrt(p)  # concave u(p): the slopes of p(u) would increase
    with pytest.raises(InputError, match="wheel y = -3 mm: no concave characteristic"):
        fit_characteristic(p, u, 3, what="wheel y = -3 mm", max_relative_error=0.01)


class PrandtlElement:
    """Independent time-stepping of the Prandtl element (paper eqs. 1-3): N springs, 1..N-1 with sliders."""

    def __init__(self, k, t0):
        self.k, self.t0 = np.asarray(k, float), np.asarray(t0, float)
        self.slip = np.zeros(self.k.size)

    def stress(self, u):
        """Total stress for displacement u after return mapping of each slider (|k_i (u - s_i)| <= T_0i)."""
        force = self.k * (u - self.slip)
        for i in range(self.k.size - 1):
            if abs(force[i]) > self.t0[i]:
                self.slip[i] = u - np.sign(force[i]) * self.t0[i] / self.k[i]
                force[i] = self.k[i] * (u - self.slip[i])
        return force.sum()

    def displacement_for(self, p, u_guess):
        """Solve stress(u) = p by bisection (monotone in u), without committing the slider state."""
        lo, hi = u_guess - 1.0, u_guess + 1.0
        for _ in range(80):
            mid = 0.5 * (lo + hi)
            saved = self.slip.copy()
            s = self.stress(mid)
            self.slip = saved
            lo, hi = (mid, hi) if s < p else (lo, mid)
        return 0.5 * (lo + hi)


def test_round_trip_parameters_element_monotonic_and_unloading():
    p, u = _points(KNOWN)
    fit = fit_characteristic(p, u, 3)
    par = fit.parameters
    back = Characteristic.from_parameters(par, u_end_mm=KNOWN.u_mm[-1])
    np.testing.assert_allclose(back.p_MPa, KNOWN.p_MPa, rtol=1e-6, atol=1e-6)
    p2 = KNOWN.elastic_limit_MPa
    for p0 in (500.0, 1000.0, 1400.0, 1600.0, 1700.0, 2100.0):
        el = PrandtlElement(par.k_N_per_mm3, par.T0_MPa)
        u_now = 0.0
        for pk in np.linspace(0, p0, 25)[1:]:  # monotonic loading in small steps
            u_now = el.displacement_for(pk, u_now)
            el.stress(u_now)
        assert u_now == pytest.approx(float(KNOWN.displacement(p0)), rel=1e-6, abs=1e-12)
        for pk in np.linspace(p0, 0, 25)[1:]:  # unloading to zero stress
            u_now = el.displacement_for(pk, u_now)
            el.stress(u_now)
        if p0 <= 2 * p2:  # eq. (8): unloading parallel to the first segment
            expected = float(KNOWN.residual_displacement(p0))
        else:  # beyond 2 p_2 the element slips back (Masing): u(p0) - 2 u(p0/2) < eq. (8)
            expected = float(KNOWN.displacement(p0) - 2 * KNOWN.displacement(p0 / 2))
            assert expected < float(KNOWN.residual_displacement(p0))
        assert u_now == pytest.approx(expected, rel=1e-6, abs=1e-9)
