"""Boussinesq integral of the Kik–Piotrowski method on the square grid (paper eq. 13): I2 = II sqrt(x_l^2-x^2)/r.

The patch is a set of strips of width h (lateral centres at offsets dj*h from the reference point, dj integer) with
leading edges x_l(y). Along x the strip is cut into cells of width h_x = h/m (m = ``x_subdivision``; m = 1: the
paper's square elements) centred at i*h_x, so that the singular point (0, 0) is the centre of cell (0, 0).

Per cell: the kernel 1/r is integrated EXACTLY over the cell (closed form, corner formula of
F(x, y) = x asinh(y/x) + y asinh(x/y), also on the cell containing the singular point), and the pressure factor
sqrt(x_l^2 - x^2) is integrated EXACTLY along x over the part of the cell inside the strip; their product / h_x is
the cell's contribution (the pressure factor enters as its cell mean). The sum of the pressure factors is therefore
exactly I1 = sum (pi/2) x_l^2 h; the only approximation is the cell-mean product (error O(h^2), measured in
``benchmarks/bench_contact.py`` and ``tests/contact/test_kik_piotrowski.py``). Units: mm.
"""

from __future__ import annotations

import functools

import numba
import numpy as np


def _corner_antiderivative(x, y):
    """Signed F(x, y) = II_{[0,x]x[0,y]} 1/sqrt(s^2 + t^2) ds dt = x asinh(y/x) + y asinh(x/y) (mm); F(0, y) = 0."""
    ax, ay = np.abs(x), np.abs(y)
    with np.errstate(divide="ignore", invalid="ignore"):
        f = np.where(ax > 0, ax * np.arcsinh(ay / np.where(ax > 0, ax, 1.0)), 0.0) \
            + np.where(ay > 0, ay * np.arcsinh(ax / np.where(ay > 0, ay, 1.0)), 0.0)
    return np.sign(x) * np.sign(y) * f


def rectangle_kernel_integral(x1, x2, y1, y2):
    """Exact II_{[x1,x2]x[y1,y2]} 1/sqrt(x^2 + y^2) dx dy (mm), vectorised; finite also around (0, 0)."""
    f = _corner_antiderivative
    return f(x2, y2) - f(x1, y2) - f(x2, y1) + f(x1, y1)


@functools.lru_cache(maxsize=16)
def _kernel_table(h: float, m: int, ni: int, nj: int) -> np.ndarray:
    """(ni, nj): exact kernel integral over the cell (x centre i h/m, width h/m; y centre j h, width h) / (h/m)."""
    hx = h / m
    xc = np.arange(ni)[:, None] * hx
    yc = np.arange(nj)[None, :] * h
    table = rectangle_kernel_integral(xc - hx / 2, xc + hx / 2, yc - h / 2, yc + h / 2) / hx
    table.setflags(write=False)
    return table


def _table(h: float, m: int, ni: int, nj: int) -> np.ndarray:
    """Cached table at least (ni, nj), sizes rounded up to powers of two so that few tables are built."""
    ri = 1 << max(int(ni - 1).bit_length(), 4)
    rj = 1 << max(int(nj - 1).bit_length(), 4)
    return _kernel_table(float(h), int(m), ri, rj)


@numba.njit(cache=True)
def _weighted_sum(a, dj, table, hx):
    """sum over strips s and cells i of (exact II_cell sqrt(a_s^2 - x^2) dx) * table[i, dj_s], cells +-i."""
    total = 0.0
    for s in range(a.size):
        aa = a[s]
        a2 = aa * aa
        row = dj[s]
        g_prev = 0.0
        i = 0
        while True:
            xe = (i + 0.5) * hx
            inside = xe < aa
            if not inside:
                xe = aa
            g = 0.5 * (xe * np.sqrt(max(a2 - xe * xe, 0.0)) + a2 * np.arcsin(min(xe / aa, 1.0)))
            w = 2.0 * (g - g_prev)          # cell i = 0: [-hx/2, hx/2] = 2 * [0, hx/2]; cells i > 0: +-i
            total += w * table[i, row]
            g_prev = g
            if not inside:
                break
            i += 1
    return total


def boussinesq_integral(x_lead_mm, strip_offset: np.ndarray, grid_mm: float, x_subdivision: int = 1) -> float:
    """I2 = II sqrt(x_l(y)^2 - x^2) / sqrt(x^2 + y^2) dx dy over the strips (mm^2), reference point at (0, 0).

    x_lead_mm: (ns,) x_l of each strip (> 0); strip_offset: (ns,) integer offsets dj of the strip centres from the
    reference point in units of ``grid_mm``; x_subdivision: cells per h along x.
    """
    a = np.ascontiguousarray(x_lead_mm, dtype=float)
    dj = np.abs(np.asarray(strip_offset, dtype=np.int64))
    hx = grid_mm / x_subdivision
    ni = int(np.ceil(a.max() / hx + 0.5)) + 1
    table = _table(grid_mm, x_subdivision, ni, int(dj.max()) + 1)
    return float(_weighted_sum(a, dj, table, hx))


def elliptic_patch_integral(a_mm: float, b_mm: float) -> float:
    """I2 of the ellipsoidal (Hertz) pressure factor on an elliptic patch, semi-axes a (x) and b (y), exactly:
    II a sqrt(1 - x^2/a^2 - y^2/b^2) / r dx dy = pi a b' K(e) with b' = min(a, b), e^2 = 1 - (b'/a')^2 (mm^2)."""
    from scipy.special import ellipk
    big, small = max(a_mm, b_mm), min(a_mm, b_mm)
    return float(np.pi * a_mm * small * ellipk(1.0 - (small / big) ** 2))
