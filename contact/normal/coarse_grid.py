"""The coarse grid of :mod:`contact.normal.coarse_exact`: lines on a lattice over the contact regions, cells along x.

Units: mm, MPa. :class:`CoarseGrid` places about n lines (y) on one lattice of spacing dy over a list of y intervals
(no lines in the gaps between separated regions) and n_x cells (x) over an x interval; :func:`loaded_spans` gives
the intervals of a solution's loaded cells plus :data:`MARGIN`; :func:`influence_table` the half-space's influence
coefficients of the lattice's cell offsets; :func:`separation_at` the separation at the lines; :func:`resample` a
pressure of one grid on another (a warm start).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from contact.normal.boussinesq import corner_antiderivative
from contact.normal.coarse_cg import influence_columns
from contact.normal.problem import NormalProblem
from wrlayer.jit import kernel

__all__ = ["MARGIN", "CoarseGrid", "GridTables", "grid_tables", "influence_table", "loaded_spans", "merged",
           "resample", "separation_at"]

#: Margin of the fitted grid around the loaded cells of a solution (relative to their extent).
MARGIN = 0.12


@dataclass
class CoarseGrid:
    """The coarse grid: lines y (ny,) on a lattice of spacing dy (``rows``: their lattice indices, increasing; gaps
    between contact regions carry no lines), cell centres x (nx,) spacing dx (mm); ``clipped``: whether the first /
    last line interval ends at the strip grid's end."""

    y: np.ndarray
    rows: np.ndarray
    x: np.ndarray
    dy: float
    dx: float
    box_delta: float
    clipped: tuple = (False, False)
    #: The tables of :func:`grid_tables` once built (the grid's solves share them; a warm start reuses them).
    tables: "GridTables | None" = field(default=None, repr=False, compare=False)
    #: :meth:`spans` once computed (every solve on a kept grid asks for them).
    _spans: list | None = field(default=None, repr=False, compare=False)

    @classmethod
    def over_box(cls, prob: NormalProblem, delta: float, shape: tuple) -> "CoarseGrid":
        """shape = (lines, cells) over {f < delta} (one strip more each side, within the table)."""
        f = prob.separation_on_grid_mm
        ys = prob.strip_y_mm
        on = np.flatnonzero(f < delta)
        y_lo, y_hi = ys[max(on[0] - 1, 0)], ys[min(on[-1] + 1, ys.size - 1)]   # f is linear between strips
        x_hi = math.sqrt(2.0 * prob.rolling_radius_mm * delta)
        return cls.over(prob, [(y_lo, y_hi)], (-x_hi, x_hi), shape, delta)

    @classmethod
    def over(cls, prob: NormalProblem, spans: list, x_span: tuple, shape: tuple, box_delta: float) -> "CoarseGrid":
        """About shape[0] lines over the y intervals ``spans`` (sorted, disjoint; clipped to the strip grid) on one
        lattice, shape[1] cells over ``x_span`` (mm)."""
        n, nx = shape
        ys = prob.strip_y_mm
        clipped = (bool(spans[0][0] <= ys[0]), bool(spans[-1][1] >= ys[-1]))
        spans = [(max(lo, ys[0]), min(hi, ys[-1])) for lo, hi in spans]
        dy = sum(hi - lo for lo, hi in spans) / n
        y0 = spans[0][0]
        runs = [np.arange(int(math.floor((lo - y0) / dy + 1e-9)), int(math.ceil((hi - y0) / dy - 1e-9)))
                for lo, hi in spans]
        rows = runs[0] if len(runs) == 1 else np.unique(np.concatenate(runs))   # one span: sorted and unique
        dx = (x_span[1] - x_span[0]) / nx
        return cls(y0 + (rows + 0.5) * dy, rows, x_span[0] + (np.arange(nx) + 0.5) * dx, float(dy), float(dx),
                   box_delta, clipped)

    def spans(self) -> list[tuple[np.ndarray, float, float]]:
        """(line indices, y_lo, y_hi) of each interval of consecutive lattice lines."""
        if self._spans is None:
            cut = np.flatnonzero(np.diff(self.rows) > 1) + 1
            self._spans = [(k, float(self.y[k[0]] - 0.5 * self.dy), float(self.y[k[-1]] + 0.5 * self.dy))
                           for k in np.split(np.arange(self.y.size), cut)]
        return self._spans


@dataclass(frozen=True)
class GridTables:
    """What every solve on one grid of one problem needs: the separation f (ny, nx) at the cells (mm), the
    influence table k (:func:`influence_table`, mm/MPa) and its expanded columns (:func:`influence_columns`)."""

    f: np.ndarray
    k: np.ndarray
    cols: np.ndarray


def grid_tables(prob: NormalProblem, grid: CoarseGrid, factor: float) -> GridTables:
    """The grid's :class:`GridTables` for ``prob`` (built once per grid; f does not depend on the force, so a grid
    kept for another force of the same separation keeps them)."""
    if grid.tables is None:
        f = separation_at(prob, grid.y)[:, None] + (grid.x * grid.x)[None, :] / (2.0 * prob.rolling_radius_mm)
        k = influence_table(grid, factor)
        grid.tables = GridTables(f, k, influence_columns(k, grid.rows))
    return grid.tables


def influence_table(grid: CoarseGrid, factor: float) -> np.ndarray:
    """(lattice rows spanned, 2 nx - 1) displacement at the centre of a cell (mm/MPa) per unit pressure on the cell
    at the offset (dj >= 0, di; column nx - 1 + di) (Love's closed form, :mod:`contact.normal.halfspace`;
    symmetric in the sign of dj)."""
    ny, nx = int(grid.rows[-1] - grid.rows[0]) + 1, grid.x.size
    xe = (np.arange(nx + 1) - 0.5) * grid.dx
    ye = (np.arange(ny + 1) - 0.5) * grid.dy
    f = corner_antiderivative(xe[None, :], ye[:, None])
    k = factor * (f[1:, 1:] - f[:-1, 1:] - f[1:, :-1] + f[:-1, :-1])
    return np.ascontiguousarray(np.concatenate([k[:, :0:-1], k], axis=1))     # x offsets -(nx-1)..(nx-1)


def resample(p: np.ndarray, old: CoarseGrid, new: CoarseGrid) -> np.ndarray:
    """A pressure of ``old`` on ``new``: bilinear in the cell centres, 0 outside (the CG's warm start)."""
    return _interp_rows(new.y, old.y, _interp_rows(new.x, old.x, p).T).T


def _interp_rows(x: np.ndarray, xp: np.ndarray, fp: np.ndarray) -> np.ndarray:
    """``np.interp(x, xp, row, left=0, right=0)`` of every row of fp (rows, xp.size) at once, with numpy's
    arithmetic (slope (f[j+1] - f[j]) / (xp[j+1] - xp[j]) times (x - xp[j]) plus f[j]; f[-1] at xp[-1]): the same
    values, in one compiled loop (a cold solve resamples five or six times)."""
    if xp.size < 2:
        return np.array([np.interp(x, xp, row, left=0.0, right=0.0) for row in fp]).reshape(fp.shape[0], x.size)
    return _interp_kernel(np.ascontiguousarray(x, dtype=float), np.ascontiguousarray(xp, dtype=float),
                          np.ascontiguousarray(fp, dtype=float))


@kernel()
def _interp_kernel(x, xp, fp):  # pragma: no cover - compiled
    rows, m, n = fp.shape[0], xp.size, x.size
    out = np.zeros((rows, n))
    for i in range(n):
        xi = x[i]
        if xi < xp[0] or xi > xp[m - 1]:
            continue
        j = np.searchsorted(xp, xi, side="right") - 1
        j = min(max(j, 0), m - 2)
        for r in range(rows):
            if xi == xp[m - 1]:
                out[r, i] = fp[r, m - 1]
            else:
                out[r, i] = (fp[r, j + 1] - fp[r, j]) / (xp[j + 1] - xp[j]) * (xi - xp[j]) + fp[r, j]
    return out


def separation_at(prob: NormalProblem, y: np.ndarray) -> np.ndarray:
    """f(y) at the lines (mm): the separation table interpolated as the problem does onto its strips (linear or
    PCHIP; straight from the table, so that lines between strips see no kinks), plus the strips' offset (dents,
    linear between strips), shifted as the strip grid (its minimum 0). The PCHIP interpolant of the last table
    is kept (a solve evaluates it on every grid; the problems of one table at other forces share its arrays)."""
    if prob.interpolation == "linear":
        f = np.interp(y, prob.y_mm, prob.f_mm)
    else:
        if _LAST_PCHIP[0] is not prob.y_mm or _LAST_PCHIP[1] is not prob.f_mm:
            from scipy.interpolate import PchipInterpolator   # here: slow to import, only "pchip" needs it
            _LAST_PCHIP[:] = [prob.y_mm, prob.f_mm, PchipInterpolator(prob.y_mm, prob.f_mm)]
        f = _LAST_PCHIP[2](y)
    if prob.f_offset_mm is not None:
        f = f + np.interp(y, prob.strip_y_mm, prob.f_offset_mm)
    return f - prob.separation_unshifted_on_grid_mm.min()


_LAST_PCHIP: list = [None, None, None]


def loaded_spans(grid: CoarseGrid, p: np.ndarray) -> tuple[list, tuple]:
    """The y intervals of the runs of loaded lattice lines and the x interval of the loaded cells, each with
    :data:`MARGIN` of its extent added each side (overlapping intervals merged): (y spans, x span) (mm)."""
    on = np.flatnonzero(p.max(axis=1) > 0)
    runs = np.split(on, np.flatnonzero(np.diff(grid.rows[on]) > 1) + 1)
    spans = []
    for run in runs:
        lo, hi = grid.y[run[0]] - 0.5 * grid.dy, grid.y[run[-1]] + 0.5 * grid.dy
        lo, hi = lo - MARGIN * (hi - lo), hi + MARGIN * (hi - lo)
        if spans and lo <= spans[-1][1]:
            spans[-1] = (spans[-1][0], hi)
        else:
            spans.append((lo, hi))
    cols = np.flatnonzero(p.max(axis=0) > 0)
    lo, hi = grid.x[cols[0]] - 0.5 * grid.dx, grid.x[cols[-1]] + 0.5 * grid.dx
    return spans, (lo - MARGIN * (hi - lo), hi + MARGIN * (hi - lo))


def merged(spans: list) -> list:
    """The y intervals ``spans`` ((lo, hi) mm) sorted, overlapping ones joined."""
    out = []
    for lo, hi in sorted(spans):
        if out and lo <= out[-1][1]:
            out[-1] = (out[-1][0], max(hi, out[-1][1]))
        else:
            out.append((lo, hi))
    return out
