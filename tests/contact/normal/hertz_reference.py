"""Analytic Hertz solution of an elliptic contact (Johnson, Contact Mechanics, sec. 4.2), for the exact-solver tests.

Units: mm, N, MPa. Separation f = x^2/(2 Rx) + y^2/(2 Ry) between two bodies of modulus E and Poisson's ratio nu
(combined E* = E / (2 (1 - nu^2))). Returns the semi-axes a (along x), b (along y), p0, the approach and the area.
"""

from __future__ import annotations

import numpy as np
from scipy.optimize import brentq
from scipy.special import ellipe, ellipk


def hertz(N: float, Rx: float, Ry: float, E: float, nu: float) -> dict:
    e_star = E / (2.0 * (1.0 - nu ** 2))
    A, B = 1.0 / (2.0 * Rx), 1.0 / (2.0 * Ry)
    small, big = min(A, B), max(A, B)        # the long semi-axis lies along the direction of smaller curvature

    def ratio(m):                            # B/A as a function of m = e^2 (long axis along the small curvature)
        K, Ek = ellipk(m), ellipe(m)
        return (Ek / (1.0 - m) - K) / (K - Ek)

    m = 0.0 if big == small else brentq(lambda m: ratio(m) - big / small, 1e-12, 1.0 - 1e-14, xtol=1e-15)
    K, Ek = ellipk(m), ellipe(m)
    if m == 0.0:
        long_ = (3.0 * N * Rx / (4.0 * e_star)) ** (1.0 / 3.0)
    else:
        long_ = (3.0 * N * (K - Ek) / (2.0 * np.pi * e_star * m * small)) ** (1.0 / 3.0)
    short = long_ * np.sqrt(1.0 - m)
    p0 = 3.0 * N / (2.0 * np.pi * long_ * short)
    delta = p0 * short * K / e_star
    a, b = (long_, short) if A <= B else (short, long_)
    return {"a_mm": a, "b_mm": b, "p0_MPa": p0, "delta_mm": delta, "area_mm2": np.pi * a * b}
