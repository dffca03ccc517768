"""The secant root finder of the wheel–rail load balance (scalar, bounded steps)."""

from __future__ import annotations

import math
from collections.abc import Callable

from wrlayer.errors import ConvergenceError


def secant(fun: Callable[[float], float], x0: float, x1: float, xtol: float, maxiter: int, what: str,
           f0: float | None = None, bounds: tuple[float | None, float | None] = (None, None),
           ftol: float = 0.0) -> float:
    """Root of a smooth monotone scalar function by the secant method, steps kept inside ``bounds`` (halfway to a
    bound when a step would leave them); stops when a step is below ``xtol`` or |f| <= ``ftol``. ``f0``: fun(x0)
    when already known. ConvergenceError naming ``what`` after ``maxiter`` steps."""
    lo, hi = bounds
    f0 = fun(x0) if f0 is None else f0
    if abs(f0) <= ftol:
        return x0
    f1 = fun(x1)
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
    raise ConvergenceError(f"{what}: the secant iteration did not converge (last step {x1 - x0:.3g}, residual "
                           f"{f1:.3g})")


__all__ = ["secant"]
