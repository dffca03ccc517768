"""Boussinesq integral of the Kik–Piotrowski method on the square grid (paper eq. 13): I2 = II sqrt(x_l^2-x^2)/r.

The patch is a set of strips of width h (lateral centres at offsets dj*h from the reference point, dj integer) with
leading edges x_l(y). Along x the strip is cut into cells of width h_x = h/m (m = ``x_subdivision``; m = 1: the
paper's square elements) centred at i*h_x, so that the singular point (0, 0) is the centre of cell (0, 0).

Per cell: the kernel 1/r is integrated EXACTLY over the cell (closed form, corner formula of
F(x, y) = x asinh(y/x) + y asinh(x/y), also on the cell containing the singular point), and the pressure factor
sqrt(x_l^2 - x^2) is integrated along x over the part of the cell inside the strip (exactly near the edge x_l, by a
4th-order cell-mean expansion with relative error < 1e-10 in the bulk, which avoids an arcsin per cell); their
product / h_x is the cell's contribution (the pressure factor enters as its cell mean). The sum of the pressure
factors is therefore I1 = sum (pi/2) x_l^2 h (to 1e-10); the only approximation is the cell-mean product (error
O(h^2), measured in ``benchmarks/bench_contact.py`` and ``tests/contact/test_kik_piotrowski.py``). Units: mm.
"""

from __future__ import annotations

import functools

import numpy as np

from wrlayer.errors import ConvergenceError
from wrlayer.jit import kernel


def corner_antiderivative(x, y):
    """Signed F(x, y) = II_{[0,x]x[0,y]} 1/sqrt(s^2 + t^2) ds dt = x asinh(y/x) + y asinh(x/y) (mm); F(0, y) = 0."""
    ax, ay = np.abs(x), np.abs(y)
    with np.errstate(divide="ignore", invalid="ignore"):
        f = np.where(ax > 0, ax * np.arcsinh(ay / np.where(ax > 0, ax, 1.0)), 0.0) \
            + np.where(ay > 0, ay * np.arcsinh(ax / np.where(ay > 0, ay, 1.0)), 0.0)
    return np.sign(x) * np.sign(y) * f


def rectangle_kernel_integral(x1, x2, y1, y2):
    """Exact II_{[x1,x2]x[y1,y2]} 1/sqrt(x^2 + y^2) dx dy (mm), vectorised; finite also around (0, 0)."""
    f = corner_antiderivative
    return f(x2, y2) - f(x1, y2) - f(x2, y1) + f(x1, y1)


@functools.lru_cache(maxsize=16)
def _kernel_table(h: float, m: int, ni: int, nj: int) -> np.ndarray:
    """(nj, ni): exact kernel integral over the cell (y centre j h, width h; x centre i h/m, width h/m) / (h/m)."""
    hx = h / m
    xc = np.arange(ni)[None, :] * hx
    yc = np.arange(nj)[:, None] * h
    table = rectangle_kernel_integral(xc - hx / 2, xc + hx / 2, yc - h / 2, yc + h / 2) / hx
    table.setflags(write=False)
    return table


def _table(h: float, m: int, ni: int, nj: int) -> np.ndarray:
    """Cached table at least (ni, nj), sizes rounded up to powers of two so that few tables are built."""
    ri = 1 << max(int(ni - 1).bit_length(), 4)
    rj = 1 << max(int(nj - 1).bit_length(), 4)
    return _kernel_table(float(h), int(m), ri, rj)


#: Largest kernel table (x cells of the longest strip x strips) built; beyond it the table would take GBs (a
#: patch under a 1e-33 MPa modulus is 1e15 cells long). 3e7 cells = 240 MB.
MAX_TABLE_CELLS = 3e7

_EDGE_CELLS = 8.0   # cells closer than this many widths to x_l use the exact antiderivative (arcsin)


@kernel()
def _weighted_sum(a, dj, table, hx):
    """sum over strips s and cells i of (II_cell sqrt(a_s^2 - x^2) dx) * table[dj_s, i], cells +-i.

    Cells ending at least _EDGE_CELLS widths inside the strip use the cell-mean expansion
    hx (f + f2 hx^2/24 + f4 hx^4/1920) of f = sqrt(a^2 - x^2) about the cell centre (f2, f4: 2nd and 4th
    derivatives; relative error below 1e-10 there since a hx / (a^2 - x^2) <= 1/16); the cells near x_l use the
    exact antiderivative G(x) = (x sqrt(a^2 - x^2) + a^2 asin(x/a)) / 2 (no arcsin in the bulk: 3x faster).
    """
    total = 0.0
    c2 = hx * hx / 24.0                               # f2 = -a^2 / q^3, f4 = -3 a^2 (a^2 + 4 x^2) / q^7
    c4 = 3.0 * hx ** 4 / 1920.0
    for s in range(a.size):
        aa = a[s]
        a2 = aa * aa
        row = dj[s]
        x_fast = aa - _EDGE_CELLS * hx
        i = 0
        x_prev = 0.0                                   # upper edge of the last expanded cell
        while (i + 0.5) * hx <= x_fast:
            xc = i * hx
            q2 = a2 - xc * xc
            q = np.sqrt(q2)
            r2 = 1.0 / (q2 * q2)
            w = hx * q * (1.0 - a2 * r2 * (c2 + c4 * (a2 + 4.0 * xc * xc) * r2))
            total += (2.0 * w if i > 0 else w) * table[row, i]
            x_prev = (i + 0.5) * hx
            i += 1
        g_prev = 0.5 * (x_prev * np.sqrt(a2 - x_prev * x_prev) + a2 * np.arcsin(x_prev / aa))
        while True:
            xe = (i + 0.5) * hx
            inside = xe < aa
            if not inside:
                xe = aa
            g = 0.5 * (xe * np.sqrt(max(a2 - xe * xe, 0.0)) + a2 * np.arcsin(min(xe / aa, 1.0)))
            w = 2.0 * (g - g_prev)                    # cell 0 = 2 * [0, hx/2]; cells i > 0 counted +-i
            total += w * table[row, i]
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
    if not a.max() > 1e-9 * hx:  # a patch of no length in x: the kernel sum would divide by zero
        raise ConvergenceError(f"contact patch of half-length x_l = {a.max():.4g} mm on an x cell of {hx:g} mm: "
                               "degenerate patch (absurd radius or load for the grid)")
    cells = a.max() / hx * (float(dj.max()) + 1.0)
    if not (np.all(np.isfinite(a)) and cells <= MAX_TABLE_CELLS):
        raise ConvergenceError(f"contact patch of half-length x_l = {a.max():.4g} mm over {int(dj.max()) + 1} "
                               f"strips needs {cells:.3g} kernel cells (at most {MAX_TABLE_CELLS:g}): absurd "
                               "load, modulus or radius for the grid")
    ni = int(np.ceil(a.max() / hx + 0.5)) + 1
    table = _table(grid_mm, x_subdivision, ni, int(dj.max()) + 1)
    return float(_weighted_sum(a, dj, table, hx))


def elliptic_patch_integral(a_mm: float, b_mm: float) -> float:
    """I2 of the ellipsoidal (Hertz) pressure factor on an elliptic patch, semi-axes a (x) and b (y), exactly:
    II a sqrt(1 - x^2/a^2 - y^2/b^2) / r dx dy = pi a b' K(e) with b' = min(a, b), e^2 = 1 - (b'/a')^2 (mm^2)."""
    from scipy.special import ellipk
    big, small = max(a_mm, b_mm), min(a_mm, b_mm)
    return float(np.pi * a_mm * small * ellipk(1.0 - (small / big) ** 2))
