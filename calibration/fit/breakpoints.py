"""The break points of the piecewise-linear characteristic fit (paper Fig. 2, eqs. 4-8): the least-squares optimum
found exactly by enumerating the data intervals, with a bounded Nelder-Mead search where the enumeration would be
too large. Units mm, MPa.

The fitted displacement is ``u(p) = c_0 p + sum_i d_i max(p - q_i, 0)`` (:mod:`calibration.fit.characteristic_fit`).
Between two neighbouring data pressures B_k < B_{k+1} there is no data point, so a break point q inside that
interval changes the fitted values only through

    d max(p_j - q, 0) = d (p_j - B_{k+1}) + w   for p_j >= B_{k+1} (0 below),   w = d (B_{k+1} - q),

which is linear in (d, w); a break point at a data pressure is a fixed hinge with a free d. For every assignment of
the free break points to distinct intervals or data pressures the best fit is therefore a linear least-squares
problem, and it is admissible when every d >= d_min and every q lies in its interval. The global optimum (all
d > d_min) is the least-squares solution of its own assignment, so it is the best admissible solution over all
assignments: no local minima, no starting points. Assignments the data cannot tell apart are left out (an
interval together with one of its end points, the last interval that holds only p_max, the first one beside a
fixed kink at its lower end).

Optional weights w_j (> 0) make every problem a weighted least-squares problem (rows and right-hand side times
w_j): the same argument holds, the optimum is that of the weighted cost sum_j (w_j r_j)^2.
"""

from __future__ import annotations

import itertools
import math
from functools import lru_cache

import numpy as np
from scipy.optimize import minimize, nnls

#: Largest number of assignments enumerated; beyond it (many segments on many points) the Nelder-Mead search runs.
MAX_ASSIGNMENTS = 150000
#: Assignments solved at once (bounds the batch's memory to some 50 MB on 25 points and 8 segments).
CHUNK = 20000
#: Ridge added to the assignments' normal matrices (columns scaled to unit length) (-).
RIDGE = 1e-13
#: Nelder-Mead restarts from the best start's result (at most; they stop when the cost no longer falls).
POLISH_RESTARTS = 20
#: Seeded random starts added to the systematic ones of the Nelder-Mead search.
RANDOM_STARTS = 12


def hinge_matrix(p: np.ndarray, q: np.ndarray, with_c0: bool) -> np.ndarray:
    """Columns p (with ``with_c0``) and max(p - q_i, 0) of the fitted displacement (mm/MPa)."""
    cols = ([p] if with_c0 else []) + [np.maximum(p - qi, 0.0) for qi in q]
    return np.column_stack(cols) if cols else np.zeros((p.size, 0))


def solve_linear(p, u, q, c0_fixed, d_min, weights=None):
    """Best (c0, d) >= d_min for break points q (bounded least squares, rows weighted by ``weights`` when given):
    (c0, d, unweighted residual vector)."""
    with_c0 = c0_fixed is None
    A = hinge_matrix(p, q, with_c0)
    rhs = u - (0.0 if with_c0 else c0_fixed * p)
    if A.shape[1] == 0:
        return c0_fixed, np.zeros(0), -rhs
    w = np.ones_like(p) if weights is None else np.asarray(weights, dtype=float)
    lb = np.full(A.shape[1], d_min)
    y, _ = nnls(A * w[:, None], (rhs - A @ lb) * w)
    x = lb + y
    c0 = x[0] if with_c0 else c0_fixed
    d = x[1:] if with_c0 else x
    return c0, d, A @ x - rhs


@lru_cache(maxsize=64)
def _assignments(n_options: int, n_free: int, first: int) -> np.ndarray:
    """Index rows of ``n_free`` options out of ``first..n_options-1`` (interval k = 2k, data pressure B_{k+1} =
    2k + 1), no two neighbouring (an interval and its end point look alike on the data)."""
    rows = [c for c in itertools.combinations(range(first, n_options), n_free)
            if all(b - a >= 2 for a, b in zip(c, c[1:]))]
    return np.array(rows, dtype=int).reshape(len(rows), n_free)


@lru_cache(maxsize=64)
def _point_assignments(n_options: int, n_free: int, first: int) -> np.ndarray:
    """Index rows of ``n_free`` data pressures (the odd options 2k + 1) out of ``first..n_options-1``, neighbours
    allowed (break points at the data pressures only)."""
    points = [o for o in range(first, n_options) if o % 2 == 1]
    rows = list(itertools.combinations(points, n_free))
    return np.array(rows, dtype=int).reshape(len(rows), n_free)


def _candidates(p, rhs, fixed, bounds, rows, w):
    """Weighted least-squares solution of every assignment in ``rows``: (coefficients, break points, cost, lower
    interval ends, in-interval flags)."""
    up = bounds[rows // 2 + 1]  # (G, f): the upper end of each interval / the data pressure itself
    low = bounds[rows // 2]
    inside = rows % 2 == 0
    hinge = np.maximum(p[None, None, :] - up[..., None], 0.0)
    step = (p[None, None, :] >= up[..., None]) * inside[..., None]
    g = rows.shape[0]
    A = np.concatenate([np.broadcast_to(fixed.T, (g,) + fixed.T.shape), hinge, step], axis=1) * w  # (G, m, n)
    rhs = rhs * w
    norm = np.sqrt(np.sum(A * A, axis=2))
    empty = norm == 0  # the step column of a break point at a data pressure
    norm[empty] = 1.0
    As = A / norm[..., None]
    N = As @ As.transpose(0, 2, 1)
    # a tiny ridge keeps the assignments the data cannot tell apart solvable (their solutions are real
    # placements with their real cost, just not unique); the chosen one is solved again exactly
    N[:, np.arange(N.shape[1]), np.arange(N.shape[1])] += empty + RIDGE
    x = np.linalg.solve(N, (As @ rhs)[..., None])[..., 0] / norm
    nf = fixed.shape[1]
    f = rows.shape[1]
    d, w = x[:, nf:nf + f], x[:, nf + f:]
    with np.errstate(divide="ignore", invalid="ignore"):
        q = np.where(inside, up - w / d, up)
    return x, q, np.sum(((x[:, None, :] @ A)[:, 0, :] - rhs) ** 2, axis=1), low, inside


def exact_breakpoints(p: np.ndarray, u: np.ndarray, pinned: list[float], n_free: int, c0_fixed: float | None,
                      d_min: float, weights=None, at_points: bool = False) -> np.ndarray | None:
    """The optimal break points (MPa; the pinned ones first, then the free ones ascending) by enumeration; None
    when there are more than :data:`MAX_ASSIGNMENTS` assignments or none is admissible. ``at_points``: the free
    break points only at data pressures (the optimum over those placements; far fewer assignments)."""
    p_max = float(p[-1])
    lo = pinned[0] if pinned else 0.0
    bounds = np.unique(np.concatenate([[lo], p[(p > lo) & (p < p_max)], [p_max]]))
    n_options = 2 * (bounds.size - 1) - 2  # without the last interval (it holds p_max alone)
    # the first interval cannot be told from a fixed kink at lo (the pinned hinge, or c_0 p with a free c_0)
    first = 1 if (pinned or c0_fixed is None) else 0
    if at_points:
        n_points = len([o for o in range(first, n_options) if o % 2 == 1])
        if n_points < n_free or math.comb(n_points, n_free) > MAX_ASSIGNMENTS:
            return None
        rows = _point_assignments(n_options, n_free, first)
    elif n_options - first < n_free or _count(n_options - first, n_free) > MAX_ASSIGNMENTS:
        return None
    else:
        rows = _assignments(n_options, n_free, first)
    if rows.shape[0] == 0:
        return None
    fixed = hinge_matrix(p, np.asarray(pinned, dtype=float), c0_fixed is None)
    rhs = u - (0.0 if c0_fixed is None else c0_fixed * p)
    w = np.ones_like(p) if weights is None else np.asarray(weights, dtype=float)
    nf = fixed.shape[1]
    best_cost, best_row, best_q = np.inf, None, None
    for start in range(0, rows.shape[0], CHUNK):
        chunk = rows[start:start + CHUNK]
        x, q, cost, low, inside = _candidates(p, rhs, fixed, bounds, chunk, w)
        ok = np.all(x[:, :nf + n_free] >= d_min, axis=1)
        ok &= np.all(~inside | ((q >= low) & (q <= bounds[chunk // 2 + 1])), axis=1)
        cost = np.where(ok, cost, np.inf)
        i = int(np.argmin(cost))
        if cost[i] < best_cost:
            best_cost, best_row, best_q = float(cost[i]), chunk[i], q[i]
    if best_row is None:
        return None
    q_best = _polished(p, rhs, fixed, bounds, best_row, w)
    if q_best is None:  # an assignment the data cannot tell apart: its ridge solution
        q_best = best_q
    return np.array(list(pinned) + sorted(q_best.tolist()))


def _count(n: int, k: int) -> int:
    """Number of ways to choose k of n options in a row, no two neighbouring."""
    return 0 if n - k + 1 < k else int(np.prod([(n - k + 1 - i) / (i + 1) for i in range(k)]).round())


def _polished(p, rhs, fixed, bounds, row, w) -> np.ndarray | None:
    """The free break points of one assignment, solved again by orthogonal least squares (the batched normal
    equations lose digits on close columns); None when its columns are linearly dependent."""
    up = bounds[row // 2 + 1]
    inside = row % 2 == 0
    cols = [fixed] + [np.maximum(p - b, 0.0)[:, None] for b in up]
    cols += [(p >= b).astype(float)[:, None] for b in up[inside]]
    A = np.hstack(cols) * w[:, None]
    x, _, rank, _ = np.linalg.lstsq(A, rhs * w, rcond=None)
    if rank < A.shape[1]:
        return None
    nf, f = fixed.shape[1], row.size
    q = up.copy()
    q[inside] = up[inside] - x[nf + f:] / x[nf:nf + f][inside]
    return q


def searched_breakpoints(p: np.ndarray, u: np.ndarray, pinned: list[float], n_free: int,
                         c0_fixed: float | None, d_min: float, n_starts: int = 6, weights=None,
                         starts: list[np.ndarray] | None = None) -> np.ndarray:
    """The break points (MPa; the pinned ones first) minimising the squared fit error: bounded Nelder-Mead from
    systematic and seeded random starts, the best one polished by restarts (a local search: used where
    :func:`exact_breakpoints` has too many assignments)."""
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

    w = np.ones_like(p) if weights is None else np.asarray(weights, dtype=float)

    def cost(z):
        return float(np.sum((w * solve_linear(p, u, breakpoints(z), c0_fixed, d_min, w)[2]) ** 2))

    options = dict(xatol=1e-9, fatol=1e-24 * float(np.sum((w * u) ** 2)), maxiter=300 * n_free, maxfev=400 * n_free,
                   adaptive=n_free > 2)
    best = None
    for q0 in (_starts(p, u, lo, span, n_free, n_starts) if starts is None else starts):
        res = minimize(cost, to_z(np.asarray(q0, dtype=float)), method="Nelder-Mead", options=options)
        if best is None or res.fun < best.fun:
            best = res
    # polish the best start: Nelder-Mead restarted from its own result (a fresh simplex) until the cost stops falling
    for _ in range(POLISH_RESTARTS):
        res = minimize(cost, best.x, method="Nelder-Mead", options=options)
        improved = res.fun < best.fun * (1.0 - 1e-9)
        if res.fun < best.fun:
            best = res
        if not improved:
            break
    return breakpoints(best.x)


def _starts(p, u, lo, span, n_free, n_starts) -> list[np.ndarray]:
    """Starting break points of the Nelder-Mead search: even in p, at quantiles of the data, at equal steps of u,
    geometric, and :data:`RANDOM_STARTS` seeded uniform draws (the same inputs give the same fit)."""
    p_max = float(p[-1])
    inner = p[(p > lo) & (p < p_max)]
    starts = [lo + span * np.arange(1, n_free + 1) / (n_free + 1)]
    if inner.size >= n_free:
        starts.append(np.quantile(inner, np.arange(1, n_free + 1) / (n_free + 1)))
    u_lo = np.interp(lo, p, u)
    starts.append(np.interp(u_lo + (u[-1] - u_lo) * np.arange(1, n_free + 1) / (n_free + 1), u, p))
    for f in np.linspace(0.2, 0.8, max(0, n_starts - len(starts))):
        starts.append(lo + span * (1.0 - (1.0 - f) ** np.arange(1, n_free + 1)))
    rng = np.random.default_rng(20261124)
    return starts + [lo + span * np.sort(rng.uniform(0.02, 0.98, n_free)) for _ in range(RANDOM_STARTS)]


def best_breakpoints(p: np.ndarray, u: np.ndarray, pinned: list[float], n_free: int, c0_fixed: float | None,
                     d_min: float, n_starts: int = 6, weights=None, at_points: bool = False) -> np.ndarray:
    """The (weighted) least-squares break points: exact by enumeration (``at_points``: among the data pressures),
    else by the Nelder-Mead search."""
    q = exact_breakpoints(p, u, pinned, n_free, c0_fixed, d_min, weights, at_points)
    if q is not None:
        return q
    # too many placements: the optimum among the data pressures, polished between them (a local search), when
    # those are few enough, else the Nelder-Mead search from its systematic starts
    q = None if at_points else exact_breakpoints(p, u, pinned, n_free, c0_fixed, d_min, weights, True)
    starts = None if q is None else [q[len(pinned):]]
    return searched_breakpoints(p, u, pinned, n_free, c0_fixed, d_min, n_starts, weights, starts)


__all__ = ["MAX_ASSIGNMENTS", "best_breakpoints", "exact_breakpoints", "hinge_matrix", "searched_breakpoints",
           "solve_linear"]
