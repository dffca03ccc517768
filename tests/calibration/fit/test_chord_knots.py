"""The break points by dynamic programming (calibration.fit.chord_knots): exact polygons are found, and the
placement is the best one an exhaustive search over the points finds."""

import itertools

import numpy as np

from calibration.fit.chord_knots import chord_deviations, chord_knots


def _worst(p, u, w, idx):
    return float(np.max(np.abs(np.interp(p, p[idx], u[idx]) - u) * w))


def test_a_polygon_through_the_points_is_found_exactly():
    p = np.linspace(0.0, 10.0, 41)
    u = np.interp(p, [0.0, 2.5, 6.0, 10.0], [0.0, 1.0, 5.0, 12.0])
    knots = chord_knots(p, u, np.ones_like(p), 5)
    np.testing.assert_allclose(p[knots[3]], [0.0, 2.5, 6.0, 10.0])
    assert _worst(p, u, np.ones_like(p), knots[3]) < 1e-12
    assert _worst(p, u, np.ones_like(p), knots[2]) > 0.1


def test_the_placement_is_the_exhaustive_optimum_and_improves_with_segments():
    rng = np.random.default_rng(3)
    p = np.sort(rng.uniform(0.0, 5.0, 12))
    u = np.maximum(p - 1.0, 0.0) ** 1.8 + 0.01 * rng.standard_normal(12)
    w = rng.uniform(0.5, 2.0, 12)
    knots = chord_knots(p, u, w, 4)
    errors = []
    for m in range(1, 5):
        brute = min(_worst(p, u, w, [0, *inner, 11]) for inner in itertools.combinations(range(1, 11), m - 1))
        errors.append(_worst(p, u, w, knots[m]))
        assert errors[-1] == brute and knots[m][0] == 0 and knots[m][-1] == 11 and len(knots[m]) == m + 1
    assert errors == sorted(errors, reverse=True)


def test_chord_deviation_of_neighbours_is_zero_and_weighted():
    p = np.array([0.0, 1.0, 2.0])
    e = chord_deviations(p, np.array([0.0, 0.0, 2.0]), np.array([1.0, 3.0, 1.0]))
    assert e[0, 1] == 0.0 and e[1, 2] == 0.0 and e[0, 2] == 3.0
