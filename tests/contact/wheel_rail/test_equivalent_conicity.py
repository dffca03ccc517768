"""Equivalent conicity (EN 15302) against closed forms: cones, a two-slope Delta r, the Klingel wavelength."""

import math

import numpy as np
import pytest

from contact.wheel_rail.equivalent_conicity import harmonic_conicity, sampled_delta_r, wavelength_conicity
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


def test_wavelength_of_a_cone_is_klingels():
    gamma, e0, r0 = 0.2, 750.0, 460.0
    g, lam = wavelength_conicity(lambda y: 2.0 * gamma * y, 3.0, e0, r0)
    assert lam == pytest.approx(2.0 * math.pi * math.sqrt(e0 * r0 / gamma), rel=1e-6)
    assert g == pytest.approx(gamma, rel=1e-6)


def test_methods_agree_closely_on_a_smooth_nonlinear_delta_r():
    f = lambda y: 2.0 * (0.05 * y + 0.004 * y ** 3)  # noqa: E731
    g_h = harmonic_conicity(f, 3.0)
    g_w, _ = wavelength_conicity(f, 3.0, 750.0, 460.0)
    # harmonic: 0.05 + 0.004 * 3/4 * 9 = 0.077 exactly
    assert g_h == pytest.approx(0.077, rel=1e-12)
    assert g_w == pytest.approx(g_h, rel=0.03)


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
