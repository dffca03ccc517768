"""The operating-range fit (calibration.fit.operating_range) on synthetic FEM curves: u_pl within the target over
the range, the number of segments chosen by the error it reaches, the reverse factor fitted to the residuals."""

import numpy as np
import pytest

from calibration.fit.operating_range import (TARGET_FLOOR, densified, error_scale_mm, fit_operating_range,
                                             level_weights)
from calibration.settings import FitSettings
from wrlayer.characteristic import Characteristic

P_Y = 800.0
#: A load path like the default calibration's (0.5 p_y, p_y, the unloading peaks, steps of 0.1 p_y up to 3 p_y).
LEVELS = np.round(np.concatenate([[0.0, 0.5, 1.0, 1.05, 1.15], np.arange(1.1, 3.0001, 0.1)]), 6)
LEVELS.sort()
PEAKS = np.array([1.05, 1.1, 1.15, 1.2, 1.3, 1.4, 1.5, 1.7, 2.0, 2.5, 3.0])
#: The levels of the former default path (steps up to 0.2 p_y, the unloading peaks).
SPARSE_LEVELS = np.array([0.0, 0.5, 1.0, 1.05, 1.1, 1.2, 1.3, 1.5, 1.7, 2.0, 2.25, 2.5, 2.75, 3.0])


def u_pl(x):
    """An FEM-like inelastic displacement (mm): zero up to first yield, then growing as (x - 1)^1.8."""
    return 0.012 * np.maximum(x - 1.0, 0.0) ** 1.8


def _fit(residual, target=0.02, max_segments=7, levels=LEVELS, floor=TARGET_FLOOR, curve=u_pl):
    p = levels * P_Y
    u = curve(levels)
    s1 = p[-1] / (0.01 * u[-1])
    return fit_operating_range(p, u, s1, P_Y, PEAKS * P_Y, residual, (1.0, 3.0), target, max_segments, 0.1, "t",
                               error_floor=floor)


def _between_levels_error(fit) -> float:
    """The element's largest scaled u_pl error against the curve itself on a fine grid over 1.1-2.5 p_y (-)."""
    ch = fit.characteristic
    x = np.linspace(1.1, 2.5, 281)
    e = (ch.displacement(x * P_Y) - x * P_Y / ch.initial_stiffness - u_pl(x)) / error_scale_mm(x * P_Y, u_pl(x), P_Y,
                                                                                           x * P_Y)
    return float(np.max(np.abs(e)))


def test_loaded_branch_meets_the_target_with_the_fewest_segments():
    loose, tight = _fit(u_pl(PEAKS), target=0.06), _fit(u_pl(PEAKS), target=0.03, max_segments=8)
    assert loose.fit.n_segments < tight.fit.n_segments <= 8
    assert _between_levels_error(tight) <= 0.03
    # the errors are those of the stored characteristic against the points
    ch = tight.characteristic
    s1 = ch.initial_stiffness
    x = np.asarray(tight.levels_over_p2)
    expected = (ch.displacement(x * P_Y) - x * P_Y / s1 - u_pl(x)) / error_scale_mm(LEVELS * P_Y, u_pl(LEVELS), P_Y,
                                                                                     x * P_Y)
    np.testing.assert_allclose(tight.u_pl_error, expected, atol=1e-12)
    assert ch.elastic_limit_MPa == pytest.approx(P_Y)


def test_the_element_follows_the_curve_between_the_fem_levels():
    """Fitted on the former path's points alone, break points between two levels let the element pass through every
    point and bend 9 % away from the curve between them; on the monotone cubic through the points read every
    0.025 p_y it stays within 5 % everywhere, and within 3 % on the default path's points."""
    sparse = _fit(u_pl(PEAKS), target=0.02, max_segments=8, levels=SPARSE_LEVELS)
    assert _between_levels_error(sparse) <= 0.05
    assert _between_levels_error(_fit(u_pl(PEAKS), target=0.02, max_segments=8)) <= 0.03
    p, u = densified(SPARSE_LEVELS * P_Y, u_pl(SPARSE_LEVELS), P_Y)
    assert np.all(np.diff(p) > 0) and set(SPARSE_LEVELS * P_Y) <= set(p)
    assert np.isclose(p, 1.45 * P_Y).any() and np.interp(1.45 * P_Y, p, u) == pytest.approx(u_pl(1.45), rel=0.02)


def test_elastic_unloading_fits_the_reverse_factor_to_the_highest_peak():
    """An FEM that unloads elastically (residual = u_pl): the smallest rho whose element unloads without reverse slip
    up to the highest peak, about 3 p_y / p_2 - 1 = 2; its residuals are the loaded branch's."""
    fit = _fit(u_pl(PEAKS))
    assert 1.6 <= fit.characteristic.reverse_factor <= 2.0 + 1e-9
    assert max(map(abs, fit.residual_error)) <= max(map(abs, fit.u_pl_error)) + 0.002


def test_masing_unloading_fits_the_paper_element():
    """An FEM whose dents are those of the paper's (Masing) element: rho = 1."""
    ch = _fit(u_pl(PEAKS)).characteristic
    masing = Characteristic(ch.u_mm, ch.p_MPa).unloading_residual(PEAKS * P_Y)
    assert _fit(masing).characteristic.reverse_factor == pytest.approx(1.0)


def test_weights_relative_inside_the_range_a_tenth_outside():
    p = LEVELS * P_Y
    w = level_weights(p, u_pl(LEVELS), P_Y, (1.0, 2.0), TARGET_FLOOR)
    ref = u_pl(1.5) / 3
    assert w[LEVELS == 2.5][0] == pytest.approx(0.1 / u_pl(2.5))
    assert w[LEVELS == 1.05][0] == pytest.approx(1.0 / ref)
    assert w[LEVELS == 1.7][0] == pytest.approx(1.0 / u_pl(1.7))


def steep_u_pl(x):
    """u_pl as steep as the default positions' FEM near first yield (mm): u_pl(1.1 p_y) / u_pl(1.5 p_y) = 0.04."""
    return 0.012 * np.maximum(x - 1.0, 0.0) ** 2


def test_the_default_floor_fits_relative_to_the_value_from_1_1_p_y():
    """With the target's floor (1/3 of the value at 1.5 p_y) the element meets the target in its measure and is
    still several % off the value itself at 1.1 p_y, where u_pl is 4 % of that at 1.5 p_y; with the default floor
    (1/30) it is within 2 % of the value at every level and residual peak from 1.1 p_y up, with more segments."""
    def relative(fit):
        ch = fit.characteristic
        x = np.array([v for v in fit.levels_over_p2 if 1.1 - 1e-9 <= v <= 2.5 + 1e-9])
        e_u = (ch.displacement(x * P_Y) - x * P_Y / ch.initial_stiffness - steep_u_pl(x)) / steep_u_pl(x)
        peaks = PEAKS[(PEAKS >= 1.1) & (PEAKS <= 2.5)]
        e_r = (ch.unloading_residual(peaks * P_Y) - steep_u_pl(peaks)) / steep_u_pl(peaks)
        return float(np.max(np.abs(np.concatenate([e_u, e_r]))))

    settings = FitSettings()
    old = _fit(steep_u_pl(PEAKS), max_segments=10, curve=steep_u_pl)
    new = _fit(steep_u_pl(PEAKS), max_segments=settings.max_segments, floor=settings.error_floor, curve=steep_u_pl)
    assert max(map(abs, old.u_pl_error)) <= 0.03 and relative(old) > 0.04
    assert relative(new) <= 0.02
    assert new.fit.n_segments > old.fit.n_segments
