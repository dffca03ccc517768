"""The approach delta at which N(delta) equals the target force: log-log secant bracketing, Illinois regula falsi.

N(delta) is monotone; in log-log coordinates it is nearly a straight line (Hertz: N ~ delta^1.5). Units: mm, N.
"""

from __future__ import annotations

from typing import Protocol

import numpy as np

from wrlayer.errors import ConvergenceError

__all__ = ["ForceAtApproach", "find_delta"]

_MAX_BRACKET_STEPS = 60
_MAX_BRACKETED_ITERATIONS = 100


class ForceAtApproach(Protocol):
    """Anything with N(delta): e.g. :class:`contact.normal.regions.NormalForceEvaluator`."""

    def force_at(self, delta: float) -> float: ...


def find_delta(ev: ForceAtApproach, target: float, delta_guess: float, rtol: float,
               slope_guess: float = 1.5) -> tuple[float, int, int, float]:
    """Solve N(delta) = target (N increasing in delta). Returns (delta, bracketing steps, bracketed iterations,
    the last secant slope d log N / d log delta, or ``slope_guess`` when none was computed).

    In log-log coordinates N(delta) is nearly a straight line (Hertz: N ~ delta^1.5), so: secant steps in
    log-log (first step with exponent ``slope_guess``, step factor limited to [1/4, 4]) until the root is
    bracketed, then Illinois regula falsi in log-log on the bracket (guaranteed, superlinear). Stops at
    |N - target| <= rtol target or when the bracket is below 1e-14 delta; ConvergenceError after too many steps.
    """
    lt = np.log(target)
    pts: list[tuple[float, float]] = []             # (log delta, log N - log target)
    lo = hi = None
    d = delta_guess
    steps = 0
    last_slope = slope_guess
    while lo is None or hi is None:
        steps += 1
        if steps > _MAX_BRACKET_STEPS:
            raise ConvergenceError(f"normal approach delta: no bracket for N = {target:g} N after "
                                   f"{_MAX_BRACKET_STEPS} steps (last delta = {d:g} mm)")
        n = ev.force_at(d)
        if not (np.isfinite(n) and n >= 0):
            raise ConvergenceError(f"normal approach delta: N(delta = {d:g} mm) = {n!r}")
        if abs(n - target) <= rtol * target:
            return d, steps, 0, last_slope
        r = (np.log(n) if n > 0 else -np.inf) - lt
        pts.append((np.log(d), r))
        if r < 0:
            lo = pts[-1]
        else:
            hi = pts[-1]
        if lo is not None and hi is not None:
            break
        if len(pts) >= 2 and np.isfinite(pts[-2][1]) and np.isfinite(r) and pts[-1][1] != pts[-2][1]:
            slope = (pts[-1][1] - pts[-2][1]) / (pts[-1][0] - pts[-2][0])
            if slope > 0:
                last_slope = slope
            step = -r / slope if slope > 0 else (np.log(4.0) if r < 0 else -np.log(4.0))
        else:
            step = -r / last_slope if np.isfinite(r) else np.log(4.0)
        d = np.exp(pts[-1][0] + float(np.clip(step, -np.log(4.0), np.log(4.0))))
    side = 0
    n_at = [lo[1], hi[1]]                            # log(N / target) at the bracket ends (not Illinois-halved)
    for it in range(1, _MAX_BRACKETED_ITERATIONS + 1):
        (xa, fa), (xb, fb) = lo, hi
        if not np.isfinite(fa):                      # N = 0 at lo: bisect
            x = 0.5 * (xa + xb)
        else:
            x = xa - fa * (xb - xa) / (fb - fa)
            if not xa < x < xb:
                x = 0.5 * (xa + xb)
        d = float(np.exp(x))
        n = ev.force_at(d)
        if abs(n - target) <= rtol * target:
            return d, steps, it, last_slope
        if (xb - xa) < 1e-14:  # the bracket has collapsed onto a jump of N(delta)
            n_lo, n_hi = np.exp(lt + np.array(n_at))
            raise ConvergenceError(f"normal approach delta: N(delta) jumps across the target N = {target:g} N at "
                                   f"delta = {d:g} mm (from {n_lo:g} to {n_hi:g} N; a discontinuity of the region "
                                   "model, e.g. contact regions merging or separating): no approach gives this "
                                   "force")
        r = (np.log(n) if n > 0 else -np.inf) - lt
        if r < 0:
            n_at[0] = r
            lo = (x, r)
            if side == -1:
                hi = (hi[0], 0.5 * hi[1])            # Illinois: halve the stale end's residual
            side = -1
        else:
            n_at[1] = r
            hi = (x, r)
            if side == 1 and np.isfinite(lo[1]):
                lo = (lo[0], 0.5 * lo[1])
            side = 1
    raise ConvergenceError(f"normal approach delta: not converged after {_MAX_BRACKETED_ITERATIONS} iterations "
                           f"(bracket [{np.exp(lo[0]):g}, {np.exp(hi[0]):g}] mm)")
