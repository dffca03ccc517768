"""Dense constrained conjugate gradients for the small grids of the coarse-grid normal solver (compiled kernel).

Units: mm, MPa, N. The same Polonsky–Keer problem as :mod:`contact.normal.constrained_cg` (force prescribed):
cell pressures p >= 0 of a grid of ny lines (on a lattice, possibly with gaps) x nx cells flattened line by
line, gap g = f + M p + c p + b - delta, p g = 0, sum p dA = N, where M is the matrix of the half-space's
influence coefficients (both bodies), read from the table k[|dj|, di] of the cell offsets (it depends on them
only), and c p + b the linearised layer of each cell. On the few hundred cells of
:mod:`contact.normal.coarse_exact` the product restricted to the loaded cells costs less than an FFT pair, and the
whole iteration runs in one kernel (no per-step interpreter cost). Up to :data:`MATRIX_CELLS` cells the columns of M
are expanded from the table once per call into a contiguous matrix, so that each column product runs over the whole
grid in one vectorised loop instead of one short loop per line (the same sums in the same order: identical
results, about 3-4 times faster on the default 32 x 12 grid). The displacement M p is updated from the step
(M t, plus the cells that were clipped or entered the contact set) and recomputed in full every
:data:`FULL_EVERY` steps and at the end.
"""

from __future__ import annotations

import numpy as np

from wrlayer.jit import kernel

__all__ = ["FULL_EVERY", "MATRIX_CELLS", "dense_cg", "influence_columns"]

#: Steps between full recomputations of the displacement M p (the update accumulates round-off).
FULL_EVERY = 25
#: Largest grid (cells) whose influence matrix is expanded (8 MB of float64 at 1024 cells).
MATRIX_CELLS = 1024


def influence_columns(k: np.ndarray, rows: np.ndarray) -> np.ndarray:
    """The columns of M expanded from the table (``cols[j]`` = column j, mm/MPa) for :func:`dense_cg`, built once
    per grid and shared by its solves (the layer iteration's); an empty (0, 0) array above :data:`MATRIX_CELLS`
    cells (the table is read instead)."""
    nx = (k.shape[1] + 1) // 2
    if rows.size * nx > MATRIX_CELLS:
        return np.empty((0, 0))
    return _columns(k, rows, nx)


@kernel()
def _columns(k, rows, nx):
    """The matrix C (n, n) with C[j] = column j of M (:func:`_add_column`'s values, exactly; written, not added to
    zeros: 40 % less time on the default grid)."""
    ny = rows.size
    n = ny * nx
    cols = np.empty((n, n))
    for j in range(n):
        jr = rows[j // nx]
        shift = nx - 1 - j % nx
        cj = cols[j]
        for ir in range(ny):
            dr = rows[ir] - jr if rows[ir] >= jr else jr - rows[ir]
            base = ir * nx
            for ic in range(nx):
                cj[base + ic] = k[dr, shift + ic]
    return cols


@kernel()
def _add(cols, k, rows, nx, j, qj, out):
    """out += M[:, j] qj, from the expanded columns when there are any (cols.shape[0] > 0), else the table."""
    if cols.shape[0] > 0:
        cj = cols[j]
        for i in range(out.size):
            out[i] += cj[i] * qj
    else:
        _add_column(k, rows, nx, j, qj, out)


@kernel()
def _add_column(k, rows, nx, j, qj, out):
    """out += M[:, j] qj: the displacement of pressure qj on cell j (k: offset table (lattice rows, 2 nx - 1) with
    the x offset d at column nx - 1 + d, mm/MPa; rows: the lattice row of each line)."""
    ny = rows.size
    jr, jc = rows[j // nx], j % nx
    shift = nx - 1 - jc
    for ir in range(ny):
        dr = rows[ir] - jr if rows[ir] >= jr else jr - rows[ir]
        base = ir * nx
        for ic in range(nx):
            out[base + ic] += k[dr, shift + ic] * qj


@kernel()
def _product(cols, k, rows, nx, q, out):
    """out = M q over the cells where q != 0."""
    n = q.size
    for i in range(n):
        out[i] = 0.0
    for j in range(n):
        if q[j] != 0.0:
            _add(cols, k, rows, nx, j, q[j], out)


@kernel()
def dense_cg(cols, k, rows, f, c, b, cell_area, p, force, tol, max_iter):
    """Polonsky–Keer CG with the force prescribed on the flattened grid (module docstring).

    cols: :func:`influence_columns` of k and rows; k influence coefficients of the cell offsets (|dj|, di)
    (mm/MPa) on the lattice (:func:`_add_column`);
    rows (ny,) the lattice row of each line; f, c, b (n = ny nx,) separation (mm), layer compliance (mm/MPa) and
    offset (mm); cell_area (mm^2); p (n,) starting pressure (MPa, positive somewhere; modified in place and returned);
    force (N); tol: relative change of the pressure sum that stops; max_iter. Returns (p, delta (mm), iterations,
    last relative change); the caller checks the change against ``tol`` (not converged when above it).
    """
    n = f.size
    nx = (k.shape[1] + 1) // 2
    total = 0.0
    for i in range(n):
        if p[i] < 0.0:
            p[i] = 0.0
        total += p[i]
    for i in range(n):
        p[i] *= force / (cell_area * total)
    u = np.empty(n)
    ut = np.empty(n)
    g = np.empty(n)
    t = np.zeros(n)
    p_old = np.empty(n)
    _product(cols, k, rows, nx, p, u)
    g_old = 1.0
    conj = False
    change = np.inf
    since_full = 0
    it = 0
    while it < max_iter:
        it += 1
        ns = 0
        gsum = 0.0
        for i in range(n):
            g[i] = f[i] + u[i] + c[i] * p[i] + b[i]
            if p[i] > 0.0:
                ns += 1
                gsum += g[i]
        gm = gsum / ns
        g_norm = 0.0
        for i in range(n):
            g[i] -= gm
            if p[i] > 0.0:
                g_norm += g[i] * g[i]
        ratio = g_norm / g_old if conj else 0.0
        for i in range(n):
            t[i] = g[i] + ratio * t[i] if p[i] > 0.0 else 0.0
        g_old = g_norm
        _product(cols, k, rows, nx, t, ut)
        rsum = 0.0
        for i in range(n):
            if p[i] > 0.0:
                rsum += ut[i] + c[i] * t[i]
        rm = rsum / ns
        rt = 0.0
        gt = 0.0
        for i in range(n):
            if p[i] > 0.0:
                rt += (ut[i] + c[i] * t[i] - rm) * t[i]
                gt += g[i] * t[i]
        tau = gt / rt if rt > 0.0 else 0.0
        overlap = False
        total = 0.0
        for i in range(n):
            p_old[i] = p[i]
            if p[i] > 0.0:
                p[i] = max(p[i] - tau * t[i], 0.0)
            if p[i] == 0.0 and g[i] < 0.0:
                p[i] = -tau * g[i]
                overlap = True
            total += p[i]
        conj = not overlap
        scale = force / (cell_area * total)
        since_full += 1
        if since_full >= FULL_EVERY:
            for i in range(n):
                p[i] *= scale
            _product(cols, k, rows, nx, p, u)
            since_full = 0
        else:
            for i in range(n):
                u[i] -= tau * ut[i]
            for j in range(n):                  # cells whose pressure is not p_old - tau t (clipped, entered)
                d = p[j] - (p_old[j] - tau * t[j])
                if d != 0.0:
                    _add(cols, k, rows, nx, j, d, u)
            for i in range(n):
                p[i] *= scale
                u[i] *= scale
        change = 0.0
        for i in range(n):
            change += abs(p[i] - p_old[i])
        change /= force / cell_area
        if change < tol and ns > 0:
            break
    _product(cols, k, rows, nx, p, u)
    ns = 0
    gsum = 0.0
    for i in range(n):
        if p[i] > 0.0:
            ns += 1
            gsum += f[i] + u[i] + c[i] * p[i] + b[i]
    return p, gsum / max(ns, 1), it, change
