"""Break points of the operating-range fit by dynamic programming: the polygon through a subset of the points that
is closest to all of them in the largest weighted deviation, for every number of segments at once. Units mm, MPa.

The loaded branch of a calibration is fitted on the FEM's loading curve read every 0.05 p_2
(:func:`calibration.fit.operating_range.densified`): 40-60 points, on which the exhaustive placement of
:mod:`calibration.fit.breakpoints` no longer fits its budget and its Nelder-Mead search lands in local minima
(measured on a synthetic (p/p_2 - 1)^1.8 curve: 8 segments 4.8 % off the curve, 6-20 s). Restricting the break
points to the points themselves turns the placement into a shortest-path problem: with e(i, k) the largest
weighted deviation of the chord from point i to point k over the points between them, the best polygon with m
segments from the first point to point k is

    E_m(k) = min over i < k of max(E_{m-1}(i), e(i, k)),      E_1(k) = e(0, k)

(O(m M^2) after the O(M^3) table e; milliseconds for M = 60). The polygon's break points are then used by the
least-squares solve of the element's slopes (:func:`calibration.fit.breakpoints.solve_linear`), which moves the
element from the chords (one-sided on a convex curve) to the least-squares line through each segment's points.
On a convex curve the chord error bounds the fit's: the same curve, 8 segments: 2.2 % off, in milliseconds.
"""

from __future__ import annotations

import numpy as np


def chord_deviations(p: np.ndarray, u: np.ndarray, w: np.ndarray) -> np.ndarray:
    """e[i, k] (i < k): the largest w_j |chord_ik(p_j) - u_j| over i < j < k (-; 0 on and below the diagonal).
    p strictly increasing (MPa), u the values (mm), w the weights (1/mm)."""
    m = p.size
    e = np.zeros((m, m))
    j = np.arange(m)
    for i in range(m - 2):
        k = np.arange(i + 2, m)
        t = (p[None, :] - p[i]) / (p[k, None] - p[i])
        dev = np.abs(u[i] + t * (u[k, None] - u[i]) - u[None, :]) * w[None, :]
        between = (j[None, :] > i) & (j[None, :] < k[:, None])
        e[i, k] = np.where(between, dev, 0.0).max(axis=1)
    return e


def chord_knots(p: np.ndarray, u: np.ndarray, w: np.ndarray, max_segments: int) -> dict[int, np.ndarray]:
    """{m: indices of the polygon's vertices (first and last point included)} of the best polygon with m segments,
    m = 1 .. min(max_segments, number of points - 1) (module docstring)."""
    n = p.size
    m_max = min(max_segments, n - 1)
    e = chord_deviations(p, u, w)
    best = np.full((m_max + 1, n), np.inf)
    came = np.zeros((m_max + 1, n), dtype=int)
    best[1, 1:] = e[0, 1:]
    for m in range(2, m_max + 1):
        for k in range(m, n):
            cost = np.maximum(best[m - 1, :k], e[:k, k])
            came[m, k] = int(np.argmin(cost))
            best[m, k] = cost[came[m, k]]
    out = {}
    for m in range(1, m_max + 1):
        idx, k = [n - 1], n - 1
        for level in range(m, 1, -1):
            k = came[level, k]
            idx.append(k)
        out[m] = np.array(sorted(idx + [0]))
    return out


__all__ = ["chord_deviations", "chord_knots"]
