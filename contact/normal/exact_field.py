"""The exact solver's pressure field on its grid, and the cell pressures and strip centres FASTSIM takes from it.

:func:`contact.normal.exact.solve_exact` keeps its field in ``NormalSolution.field``; the tangential solve of a
scene or a wheel-rail patch passes :func:`fastsim_pressure` and :func:`strip_centres` to FASTSIM instead of the
semi-elliptic strips of Kik-Piotrowski. Units: mm, MPa.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from contact.normal.solution import NormalSolution

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
    extents are shifted towards the leading edge."""
    fld: ExactField = solution.field
    reg = solution.regions[region]
    rows = np.searchsorted(fld.lines, reg.strips)
    out = np.empty((rows.size, nx))
    frac = (np.arange(nx) + 0.5) / nx
    for k, r in enumerate(rows):
        lo, hi = fld.x_extent_mm[r]
        on = np.flatnonzero(fld.p_MPa[r] > 0)
        xs = np.concatenate([[lo], fld.x_mm[on], [hi]])
        ps = np.concatenate([[0.0], fld.p_MPa[r, on], [0.0]])
        order = np.argsort(xs, kind="stable")
        pc = np.interp(hi - frac * (hi - lo), xs[order], ps[order])
        force = fld.p_MPa[r].sum() * fld.dx_mm
        total = pc.sum() * (hi - lo) / nx
        out[k] = pc * (force / total) if total > 0 else 0.0
    return out


def strip_centres(solution: NormalSolution, region: int) -> np.ndarray:
    """x (mm) of the centre of each line's refined contact extent [x_t, x_l] in patch ``region`` (the frame of the
    exact grid, x = 0 at the separation's reference point): 0 up to discretisation in indentation mode, shifted
    towards the leading edge (+x) in rolling mode. FASTSIM's ``strip_centre_mm``."""
    fld: ExactField = solution.field
    rows = np.searchsorted(fld.lines, solution.regions[region].strips)
    return 0.5 * (fld.x_extent_mm[rows, 0] + fld.x_extent_mm[rows, 1])
