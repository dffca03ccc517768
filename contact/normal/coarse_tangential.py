"""The grid the exact tangential theory solves a coarse-grid normal solution on (units mm, MPa).

The coarse solver's pressure (:class:`contact.normal.solution.GridPressure`, 12 cells along x by default) is too
coarse along x for the rolling slip's tractions, which vary along x more than the pressure does and across y less:
with spin alone, on the normal grid's 12 cells along x F_y and M_z of a flange patch were 17 % of mu N and 25 % of
mu N a off the converged solution; on 48 cells and 16 lines 4.1 % and 3.4 %, every force of the 30-patch set at six
creepages within 4.1 %, at 0.8 times the time of 48 cells on 32 lines (``benchmarks/bench_fast_normal.py``). So
each cell is cut into :data:`TANGENTIAL_X_REFINE` along x and every :data:`TANGENTIAL_Y_MERGE` lines are merged.
"""

from __future__ import annotations

import numpy as np

from contact.normal.coarse_ends import line_ends
from contact.normal.solution import GridPressure
from wrlayer.jit import kernel

__all__ = ["TANGENTIAL_X_REFINE", "TANGENTIAL_Y_MERGE", "refined_along_x", "tangential_grid"]

#: Cells of the exact tangential theory's grid per cell of the normal grid along x (:func:`tangential_grid`).
TANGENTIAL_X_REFINE = 4
#: Lines of the coarse grid merged into one line of the exact tangential theory's grid (:func:`tangential_grid`).
TANGENTIAL_Y_MERGE = 2


def tangential_grid(on: GridPressure) -> GridPressure:
    """The grid the exact tangential theory solves a coarse solution's pressure ``on`` on: each cell cut into
    :data:`TANGENTIAL_X_REFINE` along x (:func:`refined_along_x`) and every :data:`TANGENTIAL_Y_MERGE` lines merged
    into one (their mean pressure over their width: the same force). Built only when that theory runs."""
    x, fine = refined_along_x(on.x_mm, on.p_MPa, on.edge_power, TANGENTIAL_X_REFINE)
    m = TANGENTIAL_Y_MERGE
    n = on.y_mm.size
    full = np.zeros((-(-n // m) * m, x.size))
    full[:n] = fine
    dy = float(on.y_mm[1] - on.y_mm[0]) if n > 1 else 0.0
    y = on.y_mm[0] + np.arange(full.shape[0]) * dy
    return GridPressure(x, y.reshape(-1, m).mean(axis=1), full.reshape(-1, m, x.size).mean(axis=1), on.edge_power)


def refined_along_x(xs: np.ndarray, p: np.ndarray, power: int, factor: int) -> tuple[np.ndarray, np.ndarray]:
    """(x (nx factor,), p (lines, nx factor)): every cell of the uniform cells ``xs`` (mm) cut into ``factor``
    along x; on each loaded line p^power interpolated linearly between the cell centres and to zero at the line's
    contact ends (:func:`contact.normal.coarse_ends.line_ends`: Hertz's p^2 is quadratic in x, a layer's p linear
    near the edge), then scaled so that the line keeps its force (MPa mm). One compiled loop over the lines."""
    xs = np.ascontiguousarray(xs, dtype=float)
    p = np.ascontiguousarray(p, dtype=float)
    dx = float(xs[1] - xs[0]) if xs.size > 1 else 1.0
    x = xs[0] - 0.5 * dx + (np.arange(xs.size * factor) + 0.5) * (dx / factor)
    fine = np.zeros((p.shape[0], x.size))
    loaded = np.flatnonzero(p.max(axis=1) > 0)
    if loaded.size == 0:
        return x, fine
    lo, hi = line_ends(p[loaded], xs, dx, power)
    _refine_lines(p, xs, x, loaded, lo, hi, int(power), int(factor), fine)
    return x, fine


@kernel()
def _refine_lines(p, xs, x, loaded, lo, hi, power, factor, fine):
    """Fills ``fine`` (lines, x.size) on the ``loaded`` lines: knots at the line's ends (value 0) and at the cell
    centres inside them or loaded, linear in p^power between knots (as numpy.interp), zero at and beyond the ends,
    scaled to the line's force."""
    n = xs.size
    at = np.empty(n + 2)
    q = np.empty(n + 2)
    for k in range(loaded.size):
        row = loaded[k]
        a, b = lo[k], hi[k]
        at[0], q[0] = a, 0.0
        m = 1
        force = 0.0
        for i in range(n):
            v = p[row, i]
            force += v
            if (a < xs[i] < b) or v > 0.0:
                at[m], q[m] = xs[i], v ** power
                m += 1
        at[m], q[m] = b, 0.0
        m += 1
        j = 0
        total = 0.0
        for i in range(x.size):
            xi = x[i]
            if xi <= a or xi >= b:
                fine[row, i] = 0.0
                continue
            while j + 1 < m - 1 and at[j + 1] <= xi:
                j += 1
            t = (q[j + 1] - q[j]) / (at[j + 1] - at[j]) * (xi - at[j]) + q[j]
            value = t ** (1.0 / power) if t > 0.0 else 0.0
            fine[row, i] = value
            total += value
        if total > 0.0:
            scale = factor * force / total
            for i in range(x.size):
                fine[row, i] *= scale
        else:
            for i in range(x.size):
                fine[row, i] = 0.0
