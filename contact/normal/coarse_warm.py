"""The warm start of the coarse-grid normal solver (:mod:`contact.normal.coarse_exact`) across the solves of one patch
at successive forces (units mm, N, MPa).

The wheel–rail balance solves each contact candidate at several normal forces of one separation. A cold coarse solve
places its grid by a locating solve and two or three refits (about five grid solves); the patch barely moves between
balance steps, so :class:`CoarseWarmStart` keeps the last solve's grid (with its separation and influence tables,
:class:`contact.normal.coarse_grid.GridTables`) and the pressure it was fitted with, and the next solve starts there.
"""

from __future__ import annotations

import numpy as np

from contact.normal.problem import NormalProblem

__all__ = ["CoarseWarmStart"]


class CoarseWarmStart:
    """The last solve of one patch by :func:`contact.normal.coarse_exact.solve_coarse_exact`, the start of its next
    solve at another force (the wheel–rail balance iteration of one contact candidate: the same separation, layer
    and options).

    Each solve given it reads it and leaves its own final grid (with the grid's tables), the (spans, x span) that
    grid was fitted to, and the pressure there. A solve of the same problem at another force starts on that grid,
    from that pressure, to the full tolerance, and keeps the grid when the solution's loaded cells still fit it
    (the cold fit's test, with :data:`contact.normal.coarse_exact.WARM_KEEP_CELLS` cells of slack); so the result
    is the kept grid's solution at the new force, not the one a cold solve's fit would have placed (the two differ
    within the grid's discretisation: up to 2 % in p_max and area on the A-2.2 sweep). ``solves``: solves started
    from it; ``kept``: of those, solved on the kept grid alone."""

    def __init__(self):
        self.state: tuple | None = None          # (problem, layer, options, grid, fitted spans, pressure)
        self.solves = 0
        self.kept = 0

    def start_for(self, prob: NormalProblem, layer, options) -> tuple | None:
        """(grid, fitted spans, pressure) when the last solve was of the same separation, layer and options."""
        if self.state is None:
            return None
        last, last_layer, last_options, grid, fitted, p = self.state
        same = (last_layer is layer and last_options == options and _same_separation(last, prob))
        return (grid, fitted, p) if same else None

    def keep(self, prob, layer, options, grid, fitted, p) -> None:
        """Keep a solve's grid and pressure; on a kept grid the pressure it was fitted with stays the start, so
        that the solves on one grid are one function of the force (a start from the last solve would add the CG's
        stopping noise, which stalls a secant iteration on the force)."""
        if self.state is None or self.state[3] is not grid:
            self.state = (prob, layer, options, grid, fitted, p)


def _same_separation(a: NormalProblem, b: NormalProblem) -> bool:
    """Whether two problems have the same separation, strip grid and material (the force may differ)."""
    if a is b:
        return True
    arrays = (a.y_mm is b.y_mm or np.array_equal(a.y_mm, b.y_mm)) and (a.f_mm is b.f_mm or np.array_equal(a.f_mm,
                                                                                                         b.f_mm))
    offsets = (a.f_offset_mm is None and b.f_offset_mm is None) or (
        a.f_offset_mm is not None and b.f_offset_mm is not None and np.array_equal(a.f_offset_mm, b.f_offset_mm))
    return bool(arrays and offsets and (a.rolling_radius_mm, a.E_MPa, a.poisson, a.grid_mm, a.interpolation)
                == (b.rolling_radius_mm, b.E_MPa, b.poisson, b.grid_mm, b.interpolation))
