"""The secant root finder of the wheel–rail load balance (scalar, bounded steps, a bracketing fallback)."""

from __future__ import annotations

import math
from collections.abc import Callable

from wrlayer.errors import ConvergenceError


def secant(fun: Callable[[float], float], x0: float, x1: float, xtol: float, maxiter: int, what: str,
           f0: float | None = None, bounds: tuple[float | None, float | None] = (None, None),
           ftol: float = 0.0, jump_ftol: float = 0.0) -> float:
    """Root of a smooth monotone scalar function by the secant method, steps kept inside ``bounds`` (halfway to a
    bound when a step would leave them); stops when a step is below ``xtol`` or |f| <= ``ftol``. ``f0``: fun(x0)
    when already known.

    Where the secant does not converge (it cycles when the function jumps across its root: the wheel–rail balance's
    force moves in steps where the tangential solver refits its grid), the closest pair of points with opposite
    signs is bisected (:func:`_bisected`) until |f| <= ``ftol`` or the pair is ``xtol`` apart; then the side
    with the smaller |f| is the root if that is within ``jump_ftol`` (the function's step there, accepted by the
    caller). ConvergenceError naming ``what`` otherwise."""
    lo, hi = bounds
    f0 = fun(x0) if f0 is None else f0
    if abs(f0) <= ftol:
        return x0
    f1 = fun(x1)
    seen = [(x0, f0), (x1, f1)]
    for _ in range(maxiter):
        if abs(f1) <= ftol or abs(x1 - x0) <= xtol:
            return x1
        if f1 == f0:
            break
        x2 = x1 - f1 * (x1 - x0) / (f1 - f0)
        if lo is not None and x2 <= lo:
            x2 = 0.5 * (x1 + lo)
        if hi is not None and x2 >= hi:
            x2 = 0.5 * (x1 + hi)
        if not math.isfinite(x2):
            break
        x0, f0, x1 = x1, f1, x2
        f1 = fun(x1)
        seen.append((x1, f1))
    root = _bisected(fun, seen, xtol, ftol, jump_ftol, maxiter)
    if root is not None:
        return root
    raise ConvergenceError(f"{what}: the secant iteration did not converge (last step {x1 - x0:.3g}, residual "
                           f"{f1:.3g})")


def _bisected(fun: Callable[[float], float], seen: list[tuple[float, float]], xtol: float, ftol: float,
              jump_ftol: float, maxiter: int) -> float | None:
    """The bisection of the closest pair of ``seen`` points (x, f) with opposite signs: a point with |f| <= ftol,
    or the side with the smaller |f| once the pair is ``xtol`` apart and that |f| <= ``jump_ftol``; None without
    such a pair or point within ``maxiter`` halvings."""
    pairs = [(abs(xn - xp), (xn, fn), (xp, fp)) for xn, fn in seen if fn < 0 for xp, fp in seen if fp > 0]
    if not pairs:
        return None
    _, neg, pos = min(pairs, key=lambda item: item[0])
    for _ in range(maxiter):
        if abs(pos[0] - neg[0]) <= xtol:
            x, f = min(neg, pos, key=lambda point: abs(point[1]))
            return x if abs(f) <= jump_ftol else None
        mid = 0.5 * (neg[0] + pos[0])
        f = fun(mid)
        if abs(f) <= ftol:
            return mid
        if f < 0:
            neg = (mid, f)
        else:
            pos = (mid, f)
    return None


__all__ = ["secant"]
