"""The contact ends of a coarse grid's loaded lines (mm): where each line's pressure meets zero between cells.

Used by the coarse-grid solver (:mod:`contact.normal.coarse_exact`) for a line's extent along x and a run's extent
along y, and by the exact tangential theory's grid (:mod:`contact.normal.coarse_tangential`). Units: mm, MPa.
"""

from __future__ import annotations

import numpy as np

from wrlayer.jit import kernel

__all__ = ["line_ends"]


def line_ends(values: np.ndarray, coords: np.ndarray, step: float, power: int) -> tuple[np.ndarray, np.ndarray]:
    """(low ends, high ends) (mm) of the positive run of each row of ``values`` (rows, cells at ``coords``): at each
    end the parabola through the outer three values^power (Hertz: p^2 is exactly quadratic; with a layer p is
    linear near the edge) meets zero within 1.5 cells beyond the outer cell; else (fewer cells, no such root) the
    exact solver's rule (:func:`contact.normal.exact.line_extent`) at that end. One compiled loop over the rows."""
    values = np.ascontiguousarray(values, dtype=float)
    return _row_ends(values, np.ascontiguousarray(coords, dtype=float), float(step), int(power))


@kernel()
def _parabola_end(q, outer, sign, n):
    """Steps t in [0, 1.5] beyond cell ``outer`` (outwards: ``sign``) where the parabola through q at the outer
    three cells meets zero (the smallest root; a straight line when it has no curvature); inf when none."""
    i0 = outer
    i1 = min(max(outer - sign, 0), n - 1)
    i2 = min(max(outer - 2 * sign, 0), n - 1)
    q0, q1, q2 = q[i0], q[i1], q[i2]
    c = 0.5 * (q0 - 2.0 * q1 + q2)            # q(t) = q0 + b t + c t^2 through t = 0, -1, -2 (t outward)
    b = q0 - q1 + c
    best = np.inf
    if c != 0.0:
        disc = b * b - 4.0 * c * q0
        if disc >= 0.0:
            sq = np.sqrt(disc)
            for r in ((-b - sq) / (2.0 * c), (-b + sq) / (2.0 * c)):
                if np.isfinite(r) and 0.0 <= r <= 1.5 and r < best:
                    best = r
    elif b != 0.0:
        r = -q0 / b
        if np.isfinite(r) and 0.0 <= r <= 1.5:
            best = r
    return best


@kernel()
def _row_ends(values, coords, step, power):
    rows, n = values.shape
    lo = np.empty(rows)
    hi = np.empty(rows)
    q = np.empty(n)
    for k in range(rows):
        first, last = -1, -1
        for i in range(n):
            q[i] = values[k, i] ** power
            if values[k, i] > 0.0:
                if first < 0:
                    first = i
                last = i
        lo[k] = coords[first] - step * _parabola_end(q, first, -1, n)
        hi[k] = coords[last] + step * _parabola_end(q, last, 1, n)
        few = last - first < 2
        if few or not np.isfinite(lo[k]):      # the exact solver's rule (line_extent, _edge_extension)
            inner = values[k, first + 1] if first + 1 <= last else 0.0
            lo[k] = coords[first] - _edge(values[k, first], inner, step, power)
        if few or not np.isfinite(hi[k]):
            inner = values[k, last - 1] if last - 1 >= first else 0.0
            hi[k] = coords[last] + _edge(values[k, last], inner, step, power)
    return lo, hi


@kernel()
def _edge(outer, inner, step, power):
    """:func:`contact.normal.exact._edge_extension`, compiled."""
    if inner > outer > 0.0:
        qo, qi = outer ** power, inner ** power
        return min(step, step * qo / (qi - qo))
    return 0.5 * step
