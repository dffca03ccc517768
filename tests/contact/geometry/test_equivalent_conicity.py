"""Equivalent conicity (EN 15302) against closed forms: cones, a two-slope Delta r, the Klingel wavelength, an
asymmetric pair of cones."""

import math

import numpy as np
import pytest

from contact.geometry.conicity import (conicity_curve, equilibrium, harmonic_conicity, kinematic_oscillation,
                                      sampled_delta_r)
from wrlayer.errors import InputError


def two_slope(g1: float, g2: float, y1: float):
    """Delta r = 2 g1 y for |y| <= y1, slope 2 g2 beyond (a worn tread meeting the flange root)."""
    return lambda y: 2.0 * g2 * y + 2.0 * (g1 - g2) * np.clip(y, -y1, y1)


def test_cone_pair_gives_its_angle():
    assert harmonic_conicity(lambda y: 2.0 * 0.025 * y, 3.0) == pytest.approx(0.025, rel=1e-12)


def test_offset_drops_out():
    assert harmonic_conicity(lambda y: 0.4 + 2.0 * 0.1 * y, 3.0) == pytest.approx(0.1, rel=1e-12)


def test_two_slope_against_hand_computed_describing_function():
    # g1 = 0.05 up to 2 mm, g2 = 0.25 beyond, amplitude 3 mm: s = 2/3,
    # gamma_e = g2 + (g1 - g2) (2/pi) (asin s + s sqrt(1 - s^2)) = 0.25 - 0.2 * 0.78090 = 0.09382 (by hand)
    s = 2.0 / 3.0
    closed = 0.25 + (0.05 - 0.25) * (2.0 / math.pi) * (math.asin(s) + s * math.sqrt(1.0 - s * s))
    assert closed == pytest.approx(0.09382, abs=5e-6)
    f = two_slope(0.05, 0.25, 2.0)
    assert harmonic_conicity(f, 3.0, n_phi=20000) == pytest.approx(closed, rel=1e-6)
    assert harmonic_conicity(f, 3.0) == pytest.approx(closed, rel=5e-3)  # default 64 points, kinked Delta r


def test_below_the_kink_only_the_first_slope():
    assert harmonic_conicity(two_slope(0.05, 0.25, 2.0), 1.5) == pytest.approx(0.05, rel=1e-12)


Y = np.linspace(-12.0, 12.0, 241)


@pytest.mark.parametrize("amplitude", [0.5, 3.0, 10.0])
def test_wavelength_of_a_cone_is_klingels(amplitude):
    gamma, e0, r0 = 0.2, 750.0, 460.0
    got = kinematic_oscillation(Y, 2.0 * gamma * Y, amplitude, e0, r0)
    assert got.wavelength_mm == pytest.approx(2.0 * math.pi * math.sqrt(e0 * r0 / gamma), rel=1e-8)
    assert got.equivalent_conicity == pytest.approx(gamma, rel=1e-8)
    assert (got.peak_low_mm, got.peak_high_mm) == pytest.approx((-amplitude, amplitude), abs=1e-9)


def test_asymmetric_cones_give_the_two_half_oscillations():
    """Delta r = 2 g1 (y - y0) above y0 and 2 g2 (y - y0) below (by hand): each side is a harmonic half-oscillation,
    the peaks satisfy g1 a1^2 = g2 a2^2 with a1 + a2 = 2 y_hat, and the wavelength is the sum of the two half
    periods pi sqrt(e0 r0 / g), i.e. 1 / sqrt(gamma_e) = (1 / sqrt(g1) + 1 / sqrt(g2)) / 2."""
    g1, g2, y0, e0, r0, amp = 0.3, 0.05, 0.4, 745.0, 455.0, 4.0
    dr = np.where(Y > y0, 2.0 * g1 * (Y - y0), 2.0 * g2 * (Y - y0))
    assert equilibrium(Y, dr) == pytest.approx(y0, abs=1e-12)
    got = kinematic_oscillation(np.r_[Y[Y < y0], y0, Y[Y > y0]], np.r_[dr[Y < y0], 0.0, dr[Y > y0]], amp, e0, r0)
    a1 = 2.0 * amp / (1.0 + math.sqrt(g1 / g2))
    assert got.peak_high_mm - y0 == pytest.approx(a1, rel=1e-9)
    assert y0 - got.peak_low_mm == pytest.approx(2.0 * amp - a1, rel=1e-9)
    assert got.equivalent_conicity == pytest.approx(4.0 / (1.0 / math.sqrt(g1) + 1.0 / math.sqrt(g2)) ** 2, rel=1e-6)


def test_methods_agree_closely_on_a_smooth_nonlinear_delta_r():
    f = lambda y: 2.0 * (0.05 * y + 0.004 * y ** 3)  # noqa: E731
    g_h = harmonic_conicity(f, 3.0)
    g_w = kinematic_oscillation(Y, f(Y), 3.0, 750.0, 460.0).equivalent_conicity
    # harmonic: 0.05 + 0.004 * 3/4 * 9 = 0.077 exactly
    assert g_h == pytest.approx(0.077, rel=1e-12)
    assert g_w == pytest.approx(g_h, rel=0.03)
    assert g_w != pytest.approx(g_h, rel=1e-3)  # the methods differ for a nonlinear Delta r


def test_sampled_delta_r_interpolates_and_refuses_extrapolation():
    y = np.linspace(-10.0, 10.0, 201)
    f = sampled_delta_r(y, 2.0 * 0.03 * y)
    assert harmonic_conicity(f, 3.0) == pytest.approx(0.03, rel=1e-12)
    with pytest.raises(InputError, match="known on -10..10 mm only"):
        harmonic_conicity(f, 12.0)


@pytest.mark.parametrize("amp", [0.0, -1.0, float("nan")])
def test_bad_amplitude(amp):
    with pytest.raises(InputError, match="amplitude_mm"):
        harmonic_conicity(lambda y: y, amp)


def test_curve_refuses_an_amplitude_beyond_the_sweep_and_a_non_restoring_delta_r():
    with pytest.raises(InputError, match="leaves the lateral range"):
        conicity_curve(Y, 2.0 * 0.1 * Y, 750.0, 460.0, amplitudes_mm=[12.5])
    with pytest.raises(InputError, match="does not restore|no centred equilibrium"):
        conicity_curve(Y, -2.0 * 0.1 * Y, 750.0, 460.0)


def test_curve_of_a_cone_is_flat_over_en15302_amplitudes():
    curve = conicity_curve(Y, 2.0 * 0.05 * Y, 750.0, 460.0)
    assert curve.amplitude_mm[0] == 0.5 and curve.amplitude_mm[-1] == 10.0
    assert np.allclose(curve.equivalent_conicity, 0.05, rtol=1e-12)
    assert np.allclose(curve.harmonic_conicity, 0.05, rtol=1e-12)
    assert curve.at(3.0) == pytest.approx(0.05, rel=1e-12)


def test_a_second_equilibrium_within_the_oscillation_is_refused():
    """Delta r pointing away from the centre between 3 and 4 mm (e.g. a hollow-worn tread): the wheelset has
    several equilibria and the kinematic wavelength of an amplitude reaching them is not the simple oscillation's."""
    dr = np.where((np.abs(Y) > 3.05) & (np.abs(Y) < 3.95), -0.1 * np.sign(Y), 0.2 * Y)
    assert kinematic_oscillation(Y, dr, 2.5, 750.0, 460.0).equivalent_conicity == pytest.approx(0.1, rel=1e-8)
    with pytest.raises(InputError, match="several equilibria"):
        kinematic_oscillation(Y, dr, 6.0, 750.0, 460.0)
