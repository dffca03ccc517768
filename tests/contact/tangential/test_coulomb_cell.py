"""The per-cell Coulomb problem of the exact rolling solver (warm-started Newton on sigma = |s| in the power-mean
parametrisation) against a reference Newton iterated to round-off, and the two-component FFT displacement against
the direct sum (units mm, MPa; slips dimensionless)."""

import math

import numpy as np
import pytest

from contact.tangential.exact_influence import TractionHalfSpace
from contact.tangential.exact_rolling import coulomb_cell, coulomb_slip


def reference_cell(ssx, ssy, bx, by, bound):
    """The cell's traction by plain Newton on sigma from the cold start, to a step of 1e-15 of sigma + bound max b."""
    ax, ay = -ssx / bx, -ssy / by
    if ax * ax + ay * ay <= bound * bound:
        return ax, ay, False
    sig = max(math.hypot(ssx, ssy) - bound * max(bx, by), 0.0)
    for _ in range(200):
        dxx, dyy = sig + bound * bx, sig + bound * by
        h = ssx ** 2 / dxx ** 2 + ssy ** 2 / dyy ** 2 - 1.0
        dh = -2.0 * (ssx ** 2 / dxx ** 3 + ssy ** 2 / dyy ** 3)
        step = -h / dh
        sig += step
        if abs(step) <= 1e-15 * (sig + bound * max(bx, by)):
            break
    return -bound * ssx / (sig + bound * bx), -bound * ssy / (sig + bound * by), True


def random_cells(n, seed=3):
    rng = np.random.default_rng(seed)
    b = 10.0 ** rng.uniform(-5, -3, (n, 1)) * np.exp(rng.uniform(-1.0, 1.0, (n, 2)))  # anisotropy up to e^2
    bound = rng.uniform(1.0, 500.0, n)
    ss = rng.normal(size=(n, 2)) * bound[:, None] * b * 10.0 ** rng.uniform(-1.0, 1.5, (n, 1))
    return ss, b, bound


def test_cold_and_warm_coulomb_solves_equal_the_reference_newton():
    """Random cells (adhesion and slip, anisotropic self-influence): the cold solve and solves from guesses of
    sigma left of, right of, near and far from the root give the reference traction to 1e-12 of the bound."""
    ss, b, bound = random_cells(3000)
    slips = 0
    for (sx, sy), (bx, by), g in zip(ss, b, bound):
        want = reference_cell(sx, sy, bx, by, g)
        tx, ty, sl = coulomb_cell(sx, sy, bx, by, g)
        assert sl == want[2]
        assert abs(tx - want[0]) <= 1e-12 * g and abs(ty - want[1]) <= 1e-12 * g
        cold = coulomb_slip(sx, sy, bx, by, g, 0.0)
        assert (cold[2] > 0.0) == want[2]
        slips += want[2]
        for start in (cold[2] * (1 + 1e-9), cold[2] * 0.5, cold[2] * 1.7, cold[2] * 1e3, 1e-30):
            tx, ty, sig = coulomb_slip(sx, sy, bx, by, g, start)
            assert abs(tx - want[0]) <= 1e-12 * g and abs(ty - want[1]) <= 1e-12 * g
            assert sig == pytest.approx(cold[2], rel=1e-12, abs=1e-300)
    assert 500 < slips < 2500                  # both regimes exercised


def test_displacement_pair_equals_the_direct_sum():
    """u = A * t by the FFT (tractions narrower than the grid: the columns beyond carry none) against the direct
    sum over the near-field table."""
    ny, nx, m = 5, 7, 6
    hs = TractionHalfSpace(ny, nx, 0.3, 0.2, 80000.0, 0.28)
    t = np.random.default_rng(1).normal(size=(2, ny, m))
    u = hs.displacement_pair(t)
    want = np.zeros((2, ny, nx))
    for j in range(ny):
        for i in range(nx):
            for k in range(ny):
                for q in range(m):
                    axx, axy, ayy = hs.near[:, j - k + ny - 1, i - q + nx - 1]
                    want[0, j, i] += axx * t[0, k, q] + axy * t[1, k, q]
                    want[1, j, i] += axy * t[0, k, q] + ayy * t[1, k, q]
    np.testing.assert_allclose(u, want, rtol=1e-10, atol=1e-12 * np.abs(want).max())
