"""The exact solver's pressure field on its grid, and the cell pressures and strip centres FASTSIM takes from it.

:func:`contact.normal.exact.solve_exact` keeps its field in ``NormalSolution.field``; the tangential solve of a
scene or a wheel-rail patch passes :func:`fastsim_pressure` and :func:`strip_centres` to FASTSIM instead of the
semi-elliptic strips of Kik-Piotrowski. Units: mm, MPa.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from contact.normal.solution import NormalSolution
from wrlayer.jit import kernel

__all__ = ["ExactField", "fastsim_pressure", "strip_centres"]


@dataclass(frozen=True, repr=False)
class ExactField:
    """The exact solution on its grid: x_mm (nx,) cell centres, y_mm (ny,) lines (= strips ``lines`` of the
    problem's strip grid), p_MPa (ny, nx), u_layer_mm (ny, nx) layer displacement under load, separation_mm
    (ny, nx) f(x, y), dx_mm, dy_mm; x_extent_mm (ny, 2): refined trailing and leading contact ends of each line
    (NaN where unloaded); kp_delta_mm, kp_slope: approach (mm) and d log N / d log delta of the Kik–Piotrowski solve
    that placed the grid (a later solve started from this one starts its KP solve there)."""

    x_mm: np.ndarray
    y_mm: np.ndarray
    lines: np.ndarray
    p_MPa: np.ndarray
    u_layer_mm: np.ndarray
    separation_mm: np.ndarray
    dx_mm: float
    dy_mm: float
    x_extent_mm: np.ndarray = None
    kp_delta_mm: float | None = None
    kp_slope: float | None = None

    def __repr__(self) -> str:
        return (f"ExactField({self.y_mm.size} lines x {self.x_mm.size} cells, dx={self.dx_mm:.4g} mm, "
                f"dy={self.dy_mm:.4g} mm, p_max={float(np.max(self.p_MPa)):.6g} MPa)")


def fastsim_pressure(solution: NormalSolution, region: int, nx: int) -> np.ndarray:
    """The exact pressure of patch ``region`` as FASTSIM cell pressures (n_strips, nx) (MPa): each line's
    refined contact extent [x_t, x_l] is cut into nx equal cells from the leading edge, the pressure is
    interpolated linearly between the cell centres of the exact grid (0 at the refined ends) and scaled so that
    the strip keeps its exact force. Pass :func:`strip_centres` to FASTSIM as well: in rolling mode the lines'
    extents are shifted towards the leading edge. The lines in one compiled loop (:func:`_line_pressures`: the same
    values as ``np.interp`` line by line)."""
    fld: ExactField = solution.field
    reg = solution.regions[region]
    rows = np.searchsorted(fld.lines, reg.strips)
    lo, hi = fld.x_extent_mm[rows, 0], fld.x_extent_mm[rows, 1]
    frac = (np.arange(nx) + 0.5) / nx
    at = hi[:, None] - frac[None, :] * (hi - lo)[:, None]
    pc = _line_pressures(np.ascontiguousarray(fld.p_MPa), np.ascontiguousarray(fld.x_mm, dtype=float),
                         rows.astype(np.int64), np.ascontiguousarray(lo), np.ascontiguousarray(hi), at)
    force = fld.p_MPa[rows].sum(axis=1) * fld.dx_mm
    total = pc.sum(axis=1) * (hi - lo) / nx
    out = np.zeros((rows.size, nx))
    ok = total > 0
    out[ok] = pc[ok] * (force[ok] / total[ok])[:, None]
    return out


@kernel()
def _line_pressures(p, x, rows, lo, hi, at):  # pragma: no cover - compiled
    """Per line r = rows[k]: the pressure through (lo[k], 0), the loaded cells (x, p[r]) and (hi[k], 0) (sorted by x,
    ties in that order, as a stable argsort) interpolated linearly at at[k] (np.interp)."""
    out = np.empty(at.shape)
    xs = np.empty(p.shape[1] + 2)
    ps = np.empty(p.shape[1] + 2)
    for k in range(rows.size):
        r = rows[k]
        xs[0], ps[0] = lo[k], 0.0
        m = 1
        for i in range(p.shape[1]):
            if p[r, i] > 0:
                xs[m], ps[m] = x[i], p[r, i]
                m += 1
        xs[m], ps[m] = hi[k], 0.0
        m += 1
        for i in range(1, m):                       # stable insertion sort by x
            xv, pv, j = xs[i], ps[i], i - 1
            while j >= 0 and xs[j] > xv:
                xs[j + 1], ps[j + 1] = xs[j], ps[j]
                j -= 1
            xs[j + 1], ps[j + 1] = xv, pv
        out[k] = np.interp(at[k], xs[:m], ps[:m])
    return out


def strip_centres(solution: NormalSolution, region: int) -> np.ndarray:
    """x (mm) of the centre of each line's refined contact extent [x_t, x_l] in patch ``region`` (the frame of the
    exact grid, x = 0 at the separation's reference point): 0 up to discretisation in indentation mode, shifted
    towards the leading edge (+x) in rolling mode. FASTSIM's ``strip_centre_mm``."""
    fld: ExactField = solution.field
    rows = np.searchsorted(fld.lines, solution.regions[region].strips)
    return 0.5 * (fld.x_extent_mm[rows, 0] + fld.x_extent_mm[rows, 1])
