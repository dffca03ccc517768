"""Polonsky–Keer constrained conjugate gradients for the frictionless normal contact on a grid.

Units: mm, MPa, N. Unknown: the cell pressures p >= 0 (ny, nx). The deformed gap of cell c is

    g_c = f_c + (C * p)_c + c_c p_c + b_c - delta

with f the undeformed separation (mm), C * p the elastic half-space displacement (:class:`HalfSpace`), and
c_c p_c + b_c a per-cell linear (or linearised) surface-layer displacement in series (compliance c >= 0 in
mm/MPa, offset b in mm; zero without a layer). Contact conditions (complementarity):

    p_c > 0  =>  g_c = 0,        p_c = 0  =>  g_c >= 0,       and  sum p_c dA = N  (force prescribed)

The operator C + diag(c) is symmetric positive definite, so the problem is the minimisation of a convex
quadratic over p >= 0 with the force as a linear constraint; Polonsky & Keer (1999, Wear 231) solve it by
conjugate gradients restricted to the contact set, with the approach delta as the Lagrange multiplier
(delta = mean of f + u over the contact set), the overlap cells (p = 0 and g < 0) entering the contact set, and
the force restored by scaling after every step. With the approach prescribed instead, delta is fixed and the
force follows. Stops when the relative change of the pressure sum |p_new - p_old| / sum p is below ``tol``;
ConvergenceError after ``max_iter`` iterations. When a step clips no cell and adds no overlap cell, the new
pressure is scale (p - tau t), so its displacement is scale (C*p - tau C*t) from the two convolutions already
done: one convolution per iteration instead of two on those steps (a full one every 25 steps and at the end).
With ``cells_displacement`` given, a step that clips or adds at most ``LOCAL_CELLS`` cells is corrected the same
way: the displacement of the few changed cells' pressure added from the influence coefficients directly.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from wrlayer.errors import ConvergenceError

__all__ = ["CGResult", "constrained_cg", "LOCAL_CELLS"]

#: Clipped or added cells up to which a step's displacement is corrected cell by cell instead of by a convolution.
LOCAL_CELLS = 16


@dataclass(frozen=True)
class CGResult:
    """p_MPa (ny, nx); delta_mm: the approach; iterations; change: last relative pressure change; gap_mm: the
    largest |gap| on the contact set and the deepest overlap outside it (mm) at the end."""

    p_MPa: np.ndarray
    delta_mm: float
    iterations: int
    change: float
    gap_error_mm: float


def constrained_cg(displacement, f: np.ndarray, c: np.ndarray | float, b: np.ndarray | float, cell_area: float,
                   p_start: np.ndarray, force_N: float | None = None, approach_mm: float | None = None,
                   tol: float = 1e-8, max_iter: int = 1000, cells_displacement=None) -> CGResult:
    """Solve the contact problem of the module docstring by Polonsky–Keer CG.

    displacement: p (ny, nx) -> elastic displacement (mm); f: separation at the cell centres (mm); c, b: layer
    compliance (mm/MPa) and offset (mm) per cell (or scalars); cell_area: dx dy (mm^2); p_start: a starting
    pressure (its positive cells are the first contact set); exactly one of force_N / approach_mm;
    cells_displacement: (rows, cols, values) -> elastic displacement of a pressure on those cells only (optional).
    """
    if (force_N is None) == (approach_mm is None):
        raise ValueError("give exactly one of force_N and approach_mm")
    p = _start(p_start, f, cell_area, force_N)
    t = np.zeros_like(p)
    g_old = 1.0
    conj = False
    change = np.inf
    kp = displacement(p)                                     # elastic displacement of the current pressure
    since_full = 0
    for it in range(1, int(max_iter) + 1):
        s = p > 0
        n_s = int(s.sum())
        g = f + kp + c * p + b
        if force_N is not None:
            g = g - g[s].mean()
        else:
            g = g - approach_mm
        gs = g[s]
        g_norm = float(gs @ gs)
        if conj:
            t[s] = gs + (g_norm / g_old) * t[s]
        else:
            t[s] = gs
        t[~s] = 0.0
        g_old = g_norm
        kt = displacement(t)
        r = kt + c * t
        if force_N is not None:
            r = r - r[s].mean()
        rt = float(r[s] @ t[s])
        tau = float(gs @ t[s]) / rt if rt > 0 else 0.0
        p_old = p.copy()
        p_lin = p[s] - tau * t[s]
        clipped = p_lin < 0
        p[s] = np.maximum(p_lin, 0.0)
        overlap = (p == 0) & (g < 0)
        conj = not np.any(overlap)
        p[overlap] -= tau * g[overlap]
        total = float(p.sum())
        if total <= 0:
            if force_N is None:                            # the bodies do not touch at this approach
                return CGResult(p, float(approach_mm), it, 0.0, 0.0)
            raise ConvergenceError("exact normal solver: the pressure vanished during the CG iteration")
        scale = 1.0
        if force_N is not None:
            scale = force_N / (cell_area * total)
        since_full += 1
        moved = overlap.copy()                             # cells whose pressure is not p_old - tau t
        moved[s] |= clipped
        full = since_full >= 25 or (moved.any() and (cells_displacement is None or moved.sum() > LOCAL_CELLS))
        kp = _displacement_after_step(displacement, cells_displacement, full, p, scale, kp - tau * kt,
                                      moved, p_old - tau * t)
        p *= scale
        since_full = 0 if full else since_full
        if force_N is not None:
            total = force_N / cell_area
        change = float(np.abs(p - p_old).sum()) / total
        if change < tol and n_s > 0:
            break
    else:
        raise ConvergenceError(f"exact normal solver: constrained CG did not converge in {max_iter} iterations "
                               f"(relative pressure change {change:.3g}, tolerance {tol:g})")
    return _result(p, f + displacement(p) + c * p + b, approach_mm, it, change)


def _displacement_after_step(displacement, cells_displacement, full: bool, p: np.ndarray, scale: float,
                             linear_u: np.ndarray, moved: np.ndarray, linear_p: np.ndarray) -> np.ndarray:
    """Elastic displacement (mm) of the new pressure scale * p: a convolution when ``full``; else from the linear
    step's displacement ``linear_u`` (of ``linear_p`` = p_old - tau t, both unscaled) plus the displacement of the
    ``moved`` cells' difference p - linear_p (clipped to 0, or added from the overlap)."""
    if full:
        return displacement(scale * p)
    if moved.any():
        rows, cols = np.nonzero(moved)
        linear_u = linear_u + cells_displacement(rows, cols, p[rows, cols] - linear_p[rows, cols])
    return scale * linear_u


def _start(p_start: np.ndarray, f: np.ndarray, cell_area: float, force_N: float | None) -> np.ndarray:
    """The starting pressure (MPa): ``p_start`` clipped at 0, else 1 on the lowest cells of f; scaled to the force."""
    p = np.array(p_start, dtype=float)
    p[p < 0] = 0.0
    if not np.any(p > 0):                                   # start from the lowest cells
        p[f <= f.min() + 1e-12 * max(1.0, abs(f.min()))] = 1.0
    if force_N is not None:
        p *= force_N / (cell_area * p.sum())
    return p


def _result(p: np.ndarray, gap: np.ndarray, approach_mm: float | None, iterations: int, change: float) -> CGResult:
    """The converged result: the approach (the mean gap on the contact set when the force was prescribed) and the
    largest violation of the contact conditions (mm); ``gap``: f + u_E + u_L before subtracting the approach."""
    s = p > 0
    delta = float(gap[s].mean()) if approach_mm is None else float(approach_mm)
    gap = gap - delta
    err = max(float(np.abs(gap[s]).max(initial=0.0)), float(-gap[~s].min(initial=0.0)))
    return CGResult(p, delta, iterations, change, err)
