"""Piecewise-linear concave fit of a monotonic layer characteristic (paper Fig. 2, eqs. 4–8). Units mm, MPa.

The fitted displacement is convex in p, written with hinge functions::

    u(p) = c_0 p + sum_{i=1}^{N-1} d_i max(p - q_i, 0),     c_0 = 1/S_1 > 0,  d_i > 0

so that p(u) is piecewise linear with N strictly decreasing positive slopes S_i = 1/(c_0 + d_1 + ... + d_{i-1})
and break points p_{i+1} = q_i: exactly the element of eqs. (4)–(6) (k_i > 0, T_0i > 0). For fixed break points
the best (least-squares in u) c_0, d is a bounded linear least-squares problem (scipy.optimize.nnls); the
break points are the exact least-squares optimum over all placements (:mod:`calibration.fit.breakpoints`).
Optionally S_1 is fixed and p_2 = q_1 is pinned (the calibration pins p_2 to the FEM first-yield pressure).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from calibration.fit.breakpoints import best_breakpoints, hinge_matrix, solve_linear
from wrlayer.characteristic import Characteristic, PrandtlParameters
from wrlayer.errors import InputError, require
from wrlayer.layer_table import MAX_SEGMENTS

#: Allowed numbers of segments (at most what a layer table stores).
N_SEGMENTS_RANGE = (1, MAX_SEGMENTS)
#: Smallest hinge increment d_i relative to the mean compliance u_max/p_max (keeps slopes strictly decreasing).
D_MIN_REL = 1e-6


@dataclass(frozen=True)
class CharacteristicFit:
    """A fitted characteristic with its element parameters and fit errors (mm) over the fitted points."""

    characteristic: Characteristic
    parameters: PrandtlParameters
    n_segments: int
    max_error_mm: float
    rms_error_mm: float

    def to_dict(self) -> dict:
        return {"n_segments": self.n_segments, **self.characteristic.to_dict(),
                "k_N_per_mm3": self.parameters.k_N_per_mm3.tolist(), "T0_MPa": self.parameters.T0_MPa.tolist(),
                "slopes_N_per_mm3": self.characteristic.slopes.tolist(),
                "max_error_mm": self.max_error_mm, "rms_error_mm": self.rms_error_mm}


def _checked_points(p_MPa, u_mm, n_segments, what: str, max_relative_error: float) -> tuple[np.ndarray, np.ndarray]:
    """The points sorted by p as float arrays; InputError naming ``what`` when they cannot be fitted."""
    require(isinstance(n_segments, (int, np.integer)) and not isinstance(n_segments, bool)
            and N_SEGMENTS_RANGE[0] <= n_segments <= N_SEGMENTS_RANGE[1], what,
            f"number of segments must be an integer in {list(N_SEGMENTS_RANGE)}, got {n_segments!r}")
    p = np.asarray(p_MPa, dtype=float).ravel()
    u = np.asarray(u_mm, dtype=float).ravel()
    require(p.size == u.size and p.size >= 2, what, f"needs >= 2 (p, u) points of equal count, got {p.size}, {u.size}")
    require(bool(np.all(np.isfinite(p)) and np.all(np.isfinite(u))), what, "points contain NaN or infinite values")
    order = np.argsort(p)
    p, u = p[order], u[order]
    require(bool(p[0] >= 0 and p[-1] > 0), what, "pressures must be >= 0 with a positive maximum")
    u_max = float(np.max(np.abs(u)))
    require(u_max > 0, what, "all displacements are zero")
    drop = np.maximum.accumulate(u) - u  # decrease below an earlier point (noise up to max_relative_error)
    if np.any(drop > max_relative_error * u_max):
        j = int(np.argmax(drop > max_relative_error * u_max)) - 1
        raise InputError(what, f"displacement decreases from p = {p[j]:.6g} to {p[j + 1]:.6g} MPa: cannot be "
                               "fitted with positive slopes")
    return p, u


def fit_characteristic(p_MPa, u_mm, n_segments: int, s1_N_per_mm3: float | None = None,
                       p2_MPa: float | None = None, what: str = "characteristic",
                       max_relative_error: float = 0.05, n_starts: int = 6, weights=None,
                       reverse_factor: float = 1.0, breakpoints_MPa=None) -> CharacteristicFit:
    """Fit N segments to the points (p_MPa, u_mm) (u at pressure p on monotonic loading).

    weights: per point (> 0, same order as the points; None: all 1), the least-squares weights of the fit.
    reverse_factor: the element's reverse slider threshold factor rho carried by the fitted characteristic.

    s1_N_per_mm3: fix the first slope S_1; p2_MPa: pin the first break point (elastic limit; needs N >= 2).
    breakpoints_MPa: the N - 1 break points given (increasing, the first one p2_MPa when that is given): only the
    slopes are fitted (:mod:`calibration.fit.chord_knots` places them).
    InputError naming ``what`` if the points are unusable (non-finite, not increasing) or if no concave
    characteristic with positive decreasing slopes fits them within ``max_relative_error`` of max(u).
    """
    w = None
    if weights is not None:
        w = np.asarray(weights, dtype=float).ravel()
        require(w.size == np.size(p_MPa) and bool(np.all(np.isfinite(w) & (w > 0))), what,
                "weights must be positive and finite, one per point")
        w = w[np.argsort(np.asarray(p_MPa, dtype=float).ravel())]
    p, u = _checked_points(p_MPa, u_mm, n_segments, what, max_relative_error)
    p_max, u_max = float(p[-1]), float(np.max(np.abs(u)))
    c0_fixed = None
    if s1_N_per_mm3 is not None:
        require(np.isfinite(s1_N_per_mm3) and s1_N_per_mm3 > 0, what, f"S_1 must be positive, got {s1_N_per_mm3!r}")
        c0_fixed = 1.0 / float(s1_N_per_mm3)
    pinned = []
    if p2_MPa is not None:
        require(n_segments >= 2, what, "pinning p_2 needs at least 2 segments")
        require(np.isfinite(p2_MPa) and 0 < p2_MPa < p_max, what,
                f"p_2 = {p2_MPa!r} MPa must lie inside (0, {p_max:.6g}) MPa, the range of the points")
        pinned = [float(p2_MPa)]
    d_min = D_MIN_REL * u_max / p_max
    n_free = n_segments - 1 - len(pinned)
    if breakpoints_MPa is not None:
        q = np.asarray(breakpoints_MPa, dtype=float)
        require(q.size == n_segments - 1 and bool(np.all(np.diff(q) > 0)) and (not pinned or q[0] == pinned[0]),
                what, f"{n_segments} segments need {n_segments - 1} increasing break points starting at p_2")
    elif n_free > 0:
        q = best_breakpoints(p, u, pinned, n_free, c0_fixed, d_min, n_starts, w)
    else:
        q = np.array(pinned)
    c0, d, r = solve_linear(p, u, q, c0_fixed, d_min, w)
    # drop break points that coincide or fall outside the data (degenerate segments)
    p_pts = np.concatenate([[0.0], q, [p_max]])
    if np.any(np.diff(p_pts) <= 1e-9 * p_max):
        raise InputError(what, f"{n_segments} segments leave a segment of zero length; use fewer segments")
    u_pts = c0 * p_pts + hinge_matrix(p_pts, q, False) @ d if q.size else c0 * p_pts
    max_err = float(np.max(np.abs(r)))
    rms_err = float(np.sqrt(np.mean(r ** 2)))
    if max_err > max_relative_error * u_max:
        raise InputError(what, f"no concave characteristic with positive decreasing slopes fits the points: "
                               f"max error {max_err:.3g} mm > {max_relative_error:g} of max u = {u_max:.3g} mm "
                               f"(wrong curvature, or too few segments: N = {n_segments})")
    ch = Characteristic(u_pts, p_pts, what, reverse_factor)
    return CharacteristicFit(ch, ch.to_parameters(), int(n_segments), max_err, rms_err)
