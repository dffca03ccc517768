"""FaStrip: strip theory of rolling contact with Kalker-calibrated strip flexibilities, for any strip patch.

Units: mm, N, MPa, s; creepages vx, vy (-), spin phi (1/mm). Same sign conventions, inputs and output
(:class:`contact.tangential.fastsim.TangentialResult`) as FASTSIM (:mod:`contact.tangential.fastsim`): creepages
are body 1's rigid slip relative to body 2 over V, tractions act on body 1, the material enters each strip at its
leading edge x_c + x_l and leaves at x_c - x_l.

Idea (M. Sh. Sichani, R. Enblom, M. Berg 2016, "An alternative to FASTSIM for tangential solution of the
wheel–rail contact", *Vehicle System Dynamics* 54(6), FaStrip): combine Kalker's (1967) strip theory, in which every strip along the rolling
direction is a two-dimensional (Carter) rolling contact, with Kalker's creep coefficients so that the linear
theory is exact, and extend it for spin. The paper's closed forms were not at hand here; the strip problem below
is the same 2-D model solved exactly on the strip's cells instead of by its closed forms (identical to Carter's
for pure creepage, tested), derived as follows.

Strip model. Along a strip (length 2 x_l, pressure p(x)), the 2-D half-plane rolling problem (both bodies):

    u_k(x) = -(c_k / pi) Int t_k(x') ln|x - x'| dx'     (k = x, y),   slip / V  s = w - du/dx,
    w = (vx - phi y, vy + phi' (x - x_c)),   Coulomb |t| <= mu p, t = -mu p s/|s| where s != 0.

In full adhesion du/dx = w gives, with g(r) = sqrt((1 - r)/(1 + r)), r = (x - x_c)/x_l (airfoil inversion):
t_x = -(w_x / c_x) g(r) (Carter's creepage term) and, for the spin's linear lateral slip, t_y = -(phi' x_l / c_y)
sqrt(1 - r^2). Summing the strip forces over an ellipse (x_l = a sqrt(1 - y^2/b^2)) and equating them to Kalker's
linear theory Fx = -G a b C11 vx, Fy = -G a b (C22 vy + sqrt(ab) C23 phi) calibrates the flexibilities:

    c_x = pi^2 / (2 G C11),   c_y = pi^2 / (2 G C22),   phi' = phi c_y / c_phi,  c_phi = 2 pi sqrt(a/b) / (3 G C23)

with (a, b) the equivalent ellipse of the patch (Kik–Piotrowski: same area and length/width ratio, as FASTSIM's
flexibilities). The Coulomb problem of a strip is solved exactly on its ``nx`` cells: the log-kernel influence of
uniform traction on a cell (closed form), and the same nonlinear Gauss–Seidel march on the summed slip equation
as the exact solver (:mod:`contact.tangential.exact_rolling`), strip by strip (nx^2 work per sweep and strip).
Unlike FASTSIM's one flexibility per direction (traction rising linearly from the leading edge), the strip has the
elastic (Carter) traction shape: the slip zone and the saturation with spin follow the half-plane, and the
spin's lateral traction is not coupled to the longitudinal one through L1/L3 scalings.
"""

from __future__ import annotations

import functools
import math

import numba
import numpy as np

from contact.normal.patch import Patch
from contact.tangential.exact_rolling import coulomb_cell
from contact.tangential.fastsim import (
    W_PER_NMM_S,
    Creepage,
    TangentialResult,
    equivalent_ellipse,
    strip_cells,
)
from wrlayer.errors import ConvergenceError, require

__all__ = ["strip_flexibilities", "solve_fastrip"]

#: The log kernel is used as -ln(|z| / (SHIFT (nx + 1))) / pi in cell units: positive definite over a strip of
#: nx + 1 cells for SHIFT > 1/4 (an interval's logarithmic capacity is a quarter of its length); 0.5 gave the
#: fewest Gauss-Seidel sweeps (0.3: not converging, 1.0: 1.4x more sweeps, 4.0: 2.2x).
SHIFT = 0.5







def strip_flexibilities(a_mm: float, b_mm: float, C11: float, C22: float, C23: float, G_MPa: float
                        ) -> tuple[float, float, float]:
    """(c_x, c_y, phi'/phi) of the strip model (module docstring): the log-kernel compliances c_x, c_y (1/MPa)
    and the spin factor (-), from the equivalent ellipse (a, b in mm) and Kalker's coefficients."""
    cx = np.pi ** 2 / (2.0 * G_MPa * C11)
    cy = np.pi ** 2 / (2.0 * G_MPa * C22)
    c_phi = 2.0 * np.pi * np.sqrt(a_mm / b_mm) / (3.0 * G_MPa * C23)
    return float(cx), float(cy), float(cy / c_phi)


@functools.lru_cache(maxsize=16)
def _log_table(nx: int) -> np.ndarray:
    """kappa_m = -(1/pi) Int_{m-1/2}^{m+1/2} ln|z| dz for m = -(nx+1)..(nx+1) (index m + nx + 1): the log-kernel
    influence of a unit cell at offset m (in cell widths; the ln(dx) part is a uniform shift and cancels), shifted
    as below."""
    m = np.arange(-(nx + 1), nx + 2, dtype=float)

    def prim(z):
        az = np.abs(z)
        return np.where(az > 0, z * np.log(np.where(az > 0, az, 1.0)) - z, 0.0)

    # plus ln(SHIFT (nx + 1)) / pi: a uniform displacement (it cancels in the summed slip equation) that makes
    # the kernel positive definite over the strip, so that Gauss-Seidel converges
    table = (np.log(SHIFT * (nx + 1)) - (prim(m + 0.5) - prim(m - 0.5))) / np.pi
    table.setflags(write=False)
    return table


@numba.njit(cache=True)
def _strips(dx, wx, wy, bound, kappa, cx, cy, tol, max_sweeps):  # pragma: no cover - compiled
    """Every strip's 2-D rolling problem; cells k = 0 (leading) .. nx-1, the free pad ahead of cell 0.

    Returns tx, ty, sx, sy (ny, nx), slip flags and the largest sweep count (-1 when a strip did not converge)."""
    ny, nx = wx.shape
    tx = np.zeros((ny, nx))
    ty = np.zeros((ny, nx))
    sx = np.zeros((ny, nx))
    sy = np.zeros((ny, nx))
    slip = np.zeros((ny, nx), dtype=np.bool_)
    c0 = nx + 1                                  # kappa index of offset 0
    worst = 0
    for j in range(ny):
        h = dx[j]
        ux = np.zeros(nx + 1)                    # index 0: the pad; cell k at index k + 1
        uy = np.zeros(nx + 1)
        bx = cx * kappa[c0]                      # d s_k / d t_k: the cell's own log-kernel coefficient / dx
        by = cy * kappa[c0]
        scale = 0.0
        for k in range(nx):
            scale = max(scale, bound[j, k])
        if scale <= 0.0:
            continue
        done = False
        for sweep in range(1, max_sweeps + 1):
            big = 0.0
            acc_x = ux[0]
            acc_y = uy[0]
            for k in range(nx):
                g = bound[j, k]
                if g <= 0.0:
                    acc_x = ux[k + 1]
                    acc_y = uy[k + 1]
                    slip[j, k] = False
                    continue
                ssx = wx[j, k] + (ux[k + 1] - acc_x) / h - bx * tx[j, k]
                ssy = wy[j, k] + (uy[k + 1] - acc_y) / h - by * ty[j, k]
                nvx, nvy, sl = coulomb_cell(ssx, ssy, bx, by, g)
                slip[j, k] = sl
                sx[j, k] = ssx + bx * nvx if sl else 0.0
                sy[j, k] = ssy + by * nvy if sl else 0.0
                acc_x += (sx[j, k] - wx[j, k]) * h
                acc_y += (sy[j, k] - wy[j, k]) * h
                dtx = nvx - tx[j, k]
                dty = nvy - ty[j, k]
                if dtx == 0.0 and dty == 0.0:
                    continue
                big = max(big, math.sqrt(dtx * dtx + dty * dty))
                tx[j, k] = nvx
                ty[j, k] = nvy
                for q in range(nx + 1):          # displacement at index q (cell q - 1) from cell k (index k + 1)
                    kq = kappa[q - (k + 1) + c0] * h
                    ux[q] += cx * kq * dtx
                    uy[q] += cy * kq * dty
            tmax = 0.0
            for k in range(nx):
                tmax = max(tmax, math.sqrt(tx[j, k] ** 2 + ty[j, k] ** 2))
            if big <= tol * min(scale, max(tmax, 1e-300)):
                done = True
                worst = max(worst, sweep)
                break
        if not done:
            return tx, ty, sx, sy, slip, -1
    return tx, ty, sx, sy, slip, worst


def solve_fastrip(patch: Patch, creepage: Creepage, G_MPa: float, poisson: float, friction: float,
                  speed_mm_s: float = 1000.0, nx: int = 60, pressure_cells_MPa: np.ndarray | None = None,
                  strip_centre_mm: np.ndarray | None = None, tol: float = 1e-7, max_sweeps: int = 1000
                  ) -> TangentialResult:
    """FaStrip on the patch's strips; arguments as :func:`contact.tangential.fastsim.solve_tangential` (without
    ``flexibility``); tol, max_sweeps: the strip solver's stop (relative traction change) and limit.
    ConvergenceError when a strip does not converge."""
    cells = strip_cells(patch, creepage, G_MPa, poisson, friction, speed_mm_s, nx, pressure_cells_MPa,
                        strip_centre_mm)
    ell = equivalent_ellipse(patch, G_MPa, poisson)
    k = ell.coefficients
    cx, cy, spin_factor = strip_flexibilities(ell.a_mm, ell.b_mm, k.C11, k.C22, k.C23, G_MPa)
    y, x, xc, pn, dx = patch.y_mm, cells.x_mm, cells.centre_mm, cells.pn_MPa, cells.dx_mm
    wx = np.ascontiguousarray(np.broadcast_to((creepage.vx - creepage.phi_per_mm * y)[:, None], x.shape))
    wy = np.ascontiguousarray(creepage.vy + creepage.phi_per_mm * spin_factor * (x - xc[:, None]))
    tx, ty, sx, sy, slip, sweeps = _strips(dx, wx, wy, np.ascontiguousarray(friction * pn), _log_table(int(nx)),
                                           cx, cy, float(tol), int(max_sweeps))
    if sweeps < 0:
        raise ConvergenceError(f"FaStrip: a strip did not converge in {max_sweeps} sweeps (tolerance {tol:g})")
    # spin-scaled lateral slip is the strip model's; the reported slip is the model's slip
    speed = np.hypot(sx, sy)
    work = np.hypot(tx, ty) * speed * dx[:, None]                 # N/mm per cell and pass
    return cells.result(patch, tx, ty, slip, speed * speed_mm_s, work, ell, "fastrip", (cx, cy, spin_factor),
                        sweeps, 0.0)
