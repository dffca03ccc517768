"""Piecewise-linear concave fit of a monotonic layer characteristic (paper Fig. 2, eqs. 4–8). Units mm, MPa.

The fitted displacement is convex in p, written with hinge functions::

    u(p) = c_0 p + sum_{i=1}^{N-1} d_i max(p - q_i, 0),     c_0 = 1/S_1 > 0,  d_i > 0

so that p(u) is piecewise linear with N strictly decreasing positive slopes S_i = 1/(c_0 + d_1 + ... + d_{i-1})
and break points p_{i+1} = q_i: exactly the element of eqs. (4)–(6) (k_i > 0, T_0i > 0). For fixed break points
the best (least-squares in u) c_0, d is a bounded linear least-squares problem (scipy.optimize.lsq_linear); the
break points are optimised by bounded Nelder–Mead from several deterministic starts. Optionally S_1 is fixed and
p_2 = q_1 is pinned (the calibration pins p_2 to the FEM first-yield pressure).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy.optimize import minimize, nnls

from wrlayer.characteristic import Characteristic, PrandtlParameters
from wrlayer.errors import InputError, require

#: Allowed numbers of segments.
N_SEGMENTS_RANGE = (1, 8)
#: Smallest hinge increment d_i relative to the mean compliance u_max/p_max (keeps slopes strictly decreasing).
_D_MIN_REL = 1e-6


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


def _hinge_matrix(p: np.ndarray, q: np.ndarray, with_c0: bool) -> np.ndarray:
    cols = ([p] if with_c0 else []) + [np.maximum(p - qi, 0.0) for qi in q]
    return np.column_stack(cols) if cols else np.zeros((p.size, 0))


def _solve_linear(p, u, q, c0_fixed, d_min):
    """Best (c0, d) for break points q: returns (c0, d, residual vector)."""
    with_c0 = c0_fixed is None
    A = _hinge_matrix(p, q, with_c0)
    rhs = u - (0.0 if with_c0 else c0_fixed * p)
    if A.shape[1] == 0:
        return c0_fixed, np.zeros(0), -rhs
    lb = np.full(A.shape[1], d_min)
    y, _ = nnls(A, rhs - A @ lb)
    x = lb + y
    c0 = x[0] if with_c0 else c0_fixed
    d = x[1:] if with_c0 else x
    return c0, d, A @ x - rhs


#: Nelder-Mead restarts from the best start's result (at most; they stop when the cost no longer falls).
POLISH_RESTARTS = 20
#: Seeded random starts added to the systematic ones (the breakpoint cost has several local minima).
RANDOM_STARTS = 12


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


def _best_breakpoints(p: np.ndarray, u: np.ndarray, pinned: list[float], n_free: int, c0_fixed: float | None,
                      d_min: float, n_starts: int) -> np.ndarray:
    """The break points (MPa; the pinned ones first) minimising the squared fit error: bounded Nelder-Mead from
    systematic and seeded random starts, the best one polished by restarts."""
    p_max = float(p[-1])
    lo = pinned[0] if pinned else 0.0
    span = p_max - lo
    gap_min = 1e-3 / (n_free + 1)

    def breakpoints(z):
        """Free break points from unconstrained z: ordered, inside (lo, p_max), gaps >= gap_min * span."""
        w = np.exp(np.concatenate([z, [0.0]]) - np.max(np.concatenate([z, [0.0]])))
        gaps = span * (gap_min + (1.0 - (n_free + 1) * gap_min) * w / w.sum())
        return np.array(pinned + (lo + np.cumsum(gaps[:-1])).tolist())

    def to_z(q_free):
        gaps = np.diff(np.concatenate([[lo], np.sort(q_free), [p_max]]))
        w = np.maximum(gaps / span - gap_min, 1e-12)
        return np.log(w[:-1] / w[-1])

    def cost(z):
        return float(np.sum(_solve_linear(p, u, breakpoints(z), c0_fixed, d_min)[2] ** 2))

    inner = p[(p > lo) & (p < p_max)]
    starts = [lo + span * np.arange(1, n_free + 1) / (n_free + 1)]
    if inner.size >= n_free:
        starts.append(np.quantile(inner, np.arange(1, n_free + 1) / (n_free + 1)))
    u_lo = np.interp(lo, p, u)
    targets = u_lo + (u[-1] - u_lo) * np.arange(1, n_free + 1) / (n_free + 1)  # equal steps of u
    starts.append(np.interp(targets, u, p))
    for f in np.linspace(0.2, 0.8, max(0, n_starts - len(starts))):
        starts.append(lo + span * (1.0 - (1.0 - f) ** np.arange(1, n_free + 1)))
    # and RANDOM_STARTS sorted uniform draws (fixed seed: the same inputs give the same fit)
    rng = np.random.default_rng(20261124)
    starts += [lo + span * np.sort(rng.uniform(0.02, 0.98, n_free)) for _ in range(RANDOM_STARTS)]
    best = None
    scale = float(np.sum(u ** 2))
    options = dict(xatol=1e-9, fatol=1e-24 * scale, maxiter=300 * n_free, maxfev=400 * n_free,
                   adaptive=n_free > 2)
    for q0 in starts:
        res = minimize(cost, to_z(np.asarray(q0, dtype=float)), method="Nelder-Mead", options=options)
        if best is None or res.fun < best.fun:
            best = res
    # polish the best start: Nelder-Mead restarted from its own result (a fresh simplex) until the cost stops
    # falling; without it the result hung on which start ran out of evaluations first, and FEM inputs that
    # differ in the 9th digit gave fits 2 % apart (measured on the wheel table)
    for _ in range(POLISH_RESTARTS):
        res = minimize(cost, best.x, method="Nelder-Mead", options=options)
        improved = res.fun < best.fun * (1.0 - 1e-9)
        if res.fun < best.fun:
            best = res
        if not improved:
            break
    return breakpoints(best.x)


def fit_characteristic(p_MPa, u_mm, n_segments: int, s1_N_per_mm3: float | None = None,
                       p2_MPa: float | None = None, what: str = "characteristic",
                       max_relative_error: float = 0.05, n_starts: int = 6) -> CharacteristicFit:
    """Fit N segments to the points (p_MPa, u_mm) (u at pressure p on monotonic loading).

    s1_N_per_mm3: fix the first slope S_1; p2_MPa: pin the first break point (elastic limit; needs N >= 2).
    InputError naming ``what`` if the points are unusable (non-finite, not increasing) or if no concave
    characteristic with positive decreasing slopes fits them within ``max_relative_error`` of max(u).
    """
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
    d_min = _D_MIN_REL * u_max / p_max
    n_free = n_segments - 1 - len(pinned)
    q = _best_breakpoints(p, u, pinned, n_free, c0_fixed, d_min, n_starts) if n_free > 0 else np.array(pinned)
    c0, d, r = _solve_linear(p, u, q, c0_fixed, d_min)
    # drop break points that coincide or fall outside the data (degenerate segments)
    p_pts = np.concatenate([[0.0], q, [p_max]])
    if np.any(np.diff(p_pts) <= 1e-9 * p_max):
        raise InputError(what, f"{n_segments} segments leave a segment of zero length; use fewer segments")
    u_pts = c0 * p_pts + _hinge_matrix(p_pts, q, False) @ d if q.size else c0 * p_pts
    max_err = float(np.max(np.abs(r)))
    rms_err = float(np.sqrt(np.mean(r ** 2)))
    if max_err > max_relative_error * u_max:
        raise InputError(what, f"no concave characteristic with positive decreasing slopes fits the points: "
                               f"max error {max_err:.3g} mm > {max_relative_error:g} of max u = {u_max:.3g} mm "
                               f"(wrong curvature, or too few segments: N = {n_segments})")
    ch = Characteristic(u_pts, p_pts, what)
    return CharacteristicFit(ch, ch.to_parameters(), int(n_segments), max_err, rms_err)
