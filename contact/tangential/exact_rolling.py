"""Kalker's exact steady-state rolling contact (full theory, tangential part) on a grid of rectangular cells.

Units: mm, N, MPa, s; creepages vx, vy (-), spin phi (1/mm). Sign convention as FASTSIM's
(:mod:`contact.tangential.fastsim`): creepages are the rigid slip velocity of body 1 relative to body 2 divided by
the rolling speed V; the traction t acts on body 1; the material enters the contact at the leading edge (+x) and
leaves at the trailing edge (-x).

Problem (Kalker 1990, *Three-dimensional elastic bodies in rolling contact*, ch. 2; CONTACT's steady state). On
cells (j, i) of the normal solution's grid with pressure p (lines y_j, cells x_i increasing, spacing dx, dy):

    slip / V:   s = w + (u_I - u_I+) / dx,    w = (vx - phi y, vy + phi x)            (rigid slip, x/y about the
                                                                                         reference point)
    u = A * t   (Cerruti, :mod:`contact.tangential.exact_influence`),  I+ = the leading neighbour (j, i + 1)

The backward difference (u_I - u_I+)/dx = -du/dx is the change of the displacement difference of a material
particle over the time dx/V it needs to travel from I+ to I (CONTACT's discretisation of the steady-state slip).
Coulomb's law on every cell with p > 0: |t| <= mu p; adhesion |t| < mu p => s = 0; slip s != 0 => t = -mu p s/|s|.
Cells with p = 0 carry no traction. The grid is extended by one traction-free column on the leading side, so the
leading cells see the displacement of the free surface ahead of them.

Normal and tangential problems are decoupled for quasi-identical bodies (same G and nu: Kalker's difference
parameter vanishes), so the normal pressure is input. For dissimilar materials the tangential traction changes the
pressure (and the reverse): the normal solve and this solve would be alternated (Panagiotopoulos) with the coupled
coefficients. With the Prandtl surface layer of this project the layer is normal only (it acts in series with the
half-space in the normal direction); the tangential problem sees the same elastic half-space, so this solver applies
unchanged to the pressure of a layered exact normal solution.

Solver: nonlinear Gauss–Seidel over the cells (the idea of Kalker's and CONTACT's steady-state solvers, written
here from the equations): each line marched from the leading edge to the trailing edge (the direction of the
material flow). Each cell is solved in the summed form of its line's slip equations,

    u_I = u_pad + sum_{K >= I} (s_K - w_K) dx      (K from I up to the leading edge; u_pad: the free cell ahead)

with the slips s_K of the cells ahead of it from the current sweep: its own traction enters with the coefficient
A(0) / dx of the (symmetric, positive definite) half-space operator, and its 2 x 2 Coulomb problem is solved
exactly (:func:`coulomb_cell`). (The plain difference form, own coefficient (A(0) - A(1)) / dx, diverges: marching
inverts the difference and amplifies the influence of the cells behind by the line's cell count.)

A sweep takes the lines in blocks of ``block_lines``: the exact displacement is evaluated once by FFT at the start
of the sweep, and a traction change updates the displacement of its own block cell by cell (Gauss–Seidel within a
block, Jacobi between blocks: one FFT pair per sweep). Alone this iteration diverges (the blocks' changes add up),
but it is a fixed-point map t -> G(t) whose error is dominated by a few smooth modes, which Anderson acceleration
(:mod:`contact.tangential.anderson`, the last ``memory`` sweeps) removes; the mixed tractions are projected onto the
friction discs |t| <= mu p. Every sweep ends with the Gauss–Seidel update itself, so the stop test is the same
as for plain Gauss–Seidel: the largest traction change of a sweep below ``tol`` times min(mu max(p), max |t|).
On a flange patch of 159 x 61 cells from rest this takes 35 sweeps of one FFT pair each to the tolerance 1e-5
(about 55 to 1e-8), where the exact block Gauss–Seidel (the displacement recomputed by FFT before every block of
max(8, lines / 8) lines) takes 51 sweeps of 8 FFT pairs to 1e-5. ``memory = 0``, or an accelerated iteration not
converged after half of ``max_sweeps``, runs that exact block Gauss–Seidel (from the current tractions);
ConvergenceError after ``max_sweeps`` in all.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from contact.tangential.anderson import Anderson
from contact.tangential.exact_influence import TractionHalfSpace
from wrlayer.errors import ConvergenceError
from wrlayer.jit import kernel

__all__ = ["BLOCK_NEAR_COLUMNS", "RollingOptions", "RollingField", "coulomb_cell", "solve_rolling"]

#: A traction change in the accelerated sweep updates the displacement within this many columns of it only (on its
#: own line the cells behind it, on its block's other lines both sides): the farther, weaker influence waits for the
#: next sweep's FFT. The fixed point is the same; on the benchmark patches (bench_tangential) the sweeps are the
#: same as with the whole lines updated, at 25-40 % less kernel time per sweep (the block's other lines) and 0-8 %
#: less time per solve (its own line).
BLOCK_NEAR_COLUMNS = 4


@dataclass(frozen=True)
class RollingOptions:
    """Options of the exact rolling solver.

    tol: stop when the largest traction change of a sweep is below tol times the traction scale
    min(mu max(p), max |t|) (-): 1e-4 leaves a traction error max |dq| of 1e-5 to 6e-5 of mu max(p), below the
    exact normal solve's pressure error at its default (1e-4 to 2e-4 of max(p)), and a force error below 1e-6 of
    mu F_N, three to four orders below the grid's discretisation error (benchmarks.bench_tangential_cost);
    max_sweeps: limit; block_lines: lines per Gauss–Seidel block of the accelerated sweep (Jacobi between blocks;
    with the near-column updates (:data:`BLOCK_NEAR_COLUMNS`) 8 took 10-20 % fewer sweeps than 4 on the
    bench_tangential patches, 16 no fewer than 8); memory: Anderson depth (sweeps mixed; to 1e-4 depths 10, 20 and
    40 took the same sweeps there, 5 up to 5 % more; 10 halves 20's mixing work); 0: exact block Gauss–Seidel
    without acceleration.
    """

    tol: float = 1e-4
    max_sweeps: int = 500
    block_lines: int = 8
    memory: int = 10


@dataclass(frozen=True)
class RollingField:
    """Exact rolling solution on the grid (ny, nx) (x_i increasing).

    tx_MPa, ty_MPa: traction on body 1; sx, sy: slip / V (-) (zero in adhesion); slip: cells in slip (bool);
    iterations: Gauss–Seidel sweeps; residual: the largest traction change of the last sweep over
    min(mu max p, max |t|) (-);
    fft_evaluations: exact displacement evaluations.
    """

    tx_MPa: np.ndarray
    ty_MPa: np.ndarray
    sx: np.ndarray
    sy: np.ndarray
    slip: np.ndarray
    iterations: int
    residual: float
    fft_evaluations: int


#: Newton on sigma stops after a step below this fraction of sigma + mu p min(b); from a step of that size the
#: next one (the error left) is of the order of its square: round-off (checked against Newton on the plain residual
#: to 1e-12 of mu p on random anisotropic cells, tests/contact/tangential/test_coulomb_cell.py).
NEWTON_STEP = 1e-8


@kernel()
def coulomb_slip(ssx, ssy, bx, by, bound, start):  # pragma: no cover - compiled
    """The traction (tx, ty) of one cell and sigma = |s| (0 in adhesion), given s* (the cell's slip without its own
    traction): s = s* + diag(bx, by) t. Adhesion when t = -s*/b fits the bound; otherwise t = -bound s/|s| with
    s_k = s*_k sigma/(sigma + c_k), c_k = bound b_k, sigma the root of phi(sigma) = 1 with
    phi = (sum s*_k^2/(sigma + c_k)^2)^(-1/2), a weighted power mean (exponent -2) of the sigma + c_k over |s*|:
    increasing, concave and linear when bx = by, so Newton from any start lands left of the root (exactly on it
    when bx = by) and then climbs to it monotonically, in about two steps on any anisotropy. ``start``: a guess of
    sigma (the cell's sigma of the previous sweep; <= 0: none, then the isotropic closed form |s*| - c with c
    weighted by the slip's direction); the first step's result is kept if right of the cold start |s*| - max(c)
    (left of the root)."""
    ax = -ssx / bx
    ay = -ssy / by
    if ax * ax + ay * ay <= bound * bound:
        return ax, ay, 0.0
    cx = bound * bx
    cy = bound * by
    s2 = ssx * ssx + ssy * ssy
    sig = max(math.sqrt(s2) - max(cx, cy), 0.0)
    if start <= 0.0:       # the isotropic closed form |s*| - bound b with b weighted by the slip's direction
        start = math.sqrt(s2) - (ssx * ssx * cx + ssy * ssy * cy) / s2
    warm = start > sig
    if warm:
        sig, sig_cold = start, sig
    for k in range(60):
        rx = 1.0 / (sig + cx)
        ry = 1.0 / (sig + cy)
        qx = ssx * ssx * rx * rx
        qy = ssy * ssy * ry * ry
        q = qx + qy
        step = q * (math.sqrt(q) - 1.0) / (qx * rx + qy * ry)
        sig += step
        if k == 0 and warm:
            sig = max(sig, sig_cold)    # left of the root from here (a cold start left of it is no worse)
        if abs(step) <= NEWTON_STEP * (sig + min(cx, cy)):
            break
    return -ssx * bound / (sig + cx), -ssy * bound / (sig + cy), sig


@kernel()
def coulomb_cell(ssx, ssy, bx, by, bound):  # pragma: no cover - compiled
    """The traction (tx, ty) of one cell and its slip flag from s* (:func:`coulomb_slip` without a start)."""
    tx, ty, sig = coulomb_slip(ssx, ssy, bx, by, bound, 0.0)
    ax = -ssx / bx
    ay = -ssy / by
    return tx, ty, not ax * ax + ay * ay <= bound * bound


@kernel(fastmath=True)  # vectorised updates: 2x faster, forces unchanged to 1e-10
def _sweep(tx, ty, ux, uy, wx, wy, bound, near, inv_dx, blocks, cols, sigma):  # pragma: no cover - compiled
    """A Gauss–Seidel sweep over the blocks of lines (j0, j1) in ``blocks``; ux, uy (ny, nx + 1): exact
    displacement at the start, the leading pad column included; returns max |dt|.

    Each cell solves the summed slip equation u_I = u_pad + sum_{K >= I} (s_K - w_K) dx for its own traction
    (coefficient A(0): the symmetric half-space operator's diagonal), with the slips s_K of the cells ahead of it
    from this sweep. A traction change updates the displacement where this sweep still reads it, within
    :data:`BLOCK_NEAR_COLUMNS` of it: on its own line behind the cell at once, on the block's lines not yet swept
    when its line is done (:func:`_update_lines`), each line's columns cols[j, 0] <= i < cols[j, 1] (its loaded
    cells and the free cell or pad ahead of them)."""
    ny, nx = tx.shape
    cy = near.shape[1] // 2
    cx = near.shape[2] // 2
    bx = near[0, cy, cx] * inv_dx
    by = near[2, cy, cx] * inv_dx
    dx = 1.0 / inv_dx
    biggest = 0.0
    dline = np.zeros((2, nx))              # the traction changes of the line being swept
    for b in range(blocks.shape[0]):
        j0 = blocks[b, 0]
        j1 = blocks[b, 1]
        for j in range(j0, j1):
            dline[:, :] = 0.0
            acc_x = ux[j, nx]
            acc_y = uy[j, nx]
            for i in range(nx - 1, -1, -1):
                g = bound[j, i]
                if g <= 0.0:
                    acc_x = ux[j, i]       # a free cell: the summation restarts from its displacement
                    acc_y = uy[j, i]
                    continue
                ssx = wx[j, i] + (ux[j, i] - acc_x) * inv_dx - bx * tx[j, i]
                ssy = wy[j, i] + (uy[j, i] - acc_y) * inv_dx - by * ty[j, i]
                nxv, nyv, sg = coulomb_slip(ssx, ssy, bx, by, g, sigma[j, i])
                sigma[j, i] = sg
                sl = sg > 0.0
                sx = ssx + bx * nxv if sl else 0.0
                sy = ssy + by * nyv if sl else 0.0
                acc_x += (sx - wx[j, i]) * dx
                acc_y += (sy - wy[j, i]) * dx
                dtx = nxv - tx[j, i]
                dty = nyv - ty[j, i]
                if dtx == 0.0 and dty == 0.0:
                    continue
                biggest = max(biggest, math.sqrt(dtx * dtx + dty * dty))
                tx[j, i] = nxv
                ty[j, i] = nyv
                dline[0, i] = dtx
                dline[1, i] = dty
                for ii in range(max(cols[j, 0], i - BLOCK_NEAR_COLUMNS), i):  # its own line: the cells behind it
                    ox = ii - i + cx
                    ux[j, ii] += near[0, cy, ox] * dtx      # A_xy vanishes on a cell's own line
                    uy[j, ii] += near[2, cy, ox] * dty
            _update_lines(ux, uy, near, dline, j, j1, cols)
    return biggest


@kernel(fastmath=True)
def _update_lines(ux, uy, near, dline, j, j1, cols):  # pragma: no cover - compiled
    """Add the influence of line j's traction changes dline (2, nx) on the displacement of the block's lines
    j + 1 .. j1 - 1 (not read before line j is swept, so after it in one pass), within
    :data:`BLOCK_NEAR_COLUMNS` of each change, in each line's columns cols[jj, 0] <= ii < cols[jj, 1]: per column
    offset k one long loop over the line (the sums of the cell-by-cell updates, in another order)."""
    cy = near.shape[1] // 2
    cx = near.shape[2] // 2
    s_lo = cols[j, 0]
    s_hi = min(cols[j, 1], dline.shape[1])
    for jj in range(j + 1, j1):
        oy = jj - j + cy
        for k in range(-BLOCK_NEAR_COLUMNS, BLOCK_NEAR_COLUMNS + 1):     # field minus source column
            axx = near[0, oy, cx + k]
            axy = near[1, oy, cx + k]
            ayy = near[2, oy, cx + k]
            for ii in range(max(cols[jj, 0], s_lo + k), min(cols[jj, 1], s_hi + k)):
                dtx = dline[0, ii - k]
                dty = dline[1, ii - k]
                ux[jj, ii] += axx * dtx + axy * dty
                uy[jj, ii] += axy * dtx + ayy * dty


def _line_columns(on: np.ndarray) -> np.ndarray:
    """(ny, 2): per line the columns [first loaded, last loaded + 2) of the displacement (the free cell or the
    pad ahead of the line's leading loaded cell included); (0, 0) for a line without load."""
    ny, nx = on.shape
    out = np.zeros((ny, 2), dtype=np.int64)
    rows = np.flatnonzero(on.any(axis=1))
    out[rows, 0] = np.argmax(on[rows], axis=1)
    out[rows, 1] = np.minimum(nx - np.argmax(on[rows, ::-1], axis=1) + 1, nx + 1)
    return out


def _blocks(loaded: np.ndarray, step: int) -> np.ndarray:
    """(j0, j1) of the blocks of ``step`` lines from the first to the last loaded line."""
    lo, hi = int(loaded[0]), int(loaded[-1]) + 1
    return np.array([(j, min(j + step, hi)) for j in range(lo, hi, step)], dtype=np.int64)


class _Iteration:
    """The state of one solve: tractions, slip flags and the sweeps (accelerated or exact)."""

    def __init__(self, hs, p_MPa, wx, wy, friction, dx, options, initial_MPa):
        ny, nx = p_MPa.shape
        self.hs, self.dx, self.options = hs, dx, options
        self.near = np.ascontiguousarray(hs.near)
        self.bound = np.ascontiguousarray(friction * np.maximum(p_MPa, 0.0))
        self.on = self.bound > 0
        self.cells = np.flatnonzero(self.on)      # the loaded cells (flat indices), the mixed vector's order
        self.cell_bound = self.bound.ravel()[self.cells]
        self.wx, self.wy = np.ascontiguousarray(wx, dtype=float), np.ascontiguousarray(wy, dtype=float)
        self.t = np.zeros((2, ny, nx))            # (tx, ty): one array, so the FFT takes both without a copy
        self.tx, self.ty = self.t[0], self.t[1]   # views, updated in place
        if initial_MPa is not None and np.shape(initial_MPa[0]) == (ny, nx) == np.shape(initial_MPa[1]):
            self.tx[...] = np.where(self.on, np.asarray(initial_MPa[0], dtype=float), 0.0)
            self.ty[...] = np.where(self.on, np.asarray(initial_MPa[1], dtype=float), 0.0)
        self.sigma = np.zeros((ny, nx))          # |s| per cell (0: adhesion), the next sweep's Newton start
        loaded = np.flatnonzero(self.on.any(axis=1))
        self.cols = _line_columns(self.on)
        self.fast_blocks = _blocks(loaded, max(1, int(options.block_lines)))
        self.exact_blocks = _blocks(loaded, max(8, int(math.ceil(ny / 8))))

    def displacement(self) -> tuple[np.ndarray, np.ndarray]:
        """Exact (ux, uy) of the current tractions with the traction-free pad column (ny, nx + 1)."""
        u = self.hs.displacement_pair(self.t)     # the pad column: zero-padded by the FFT
        return np.ascontiguousarray(u[0]), np.ascontiguousarray(u[1])

    @property
    def slip(self) -> np.ndarray:
        """Cells in slip (ny, nx) after the last sweep."""
        return self.sigma > 0.0

    def sweep(self, exact: bool) -> float:
        """One sweep (exact block Gauss–Seidel or the accelerated one's Gauss–Seidel step); max |dt| (MPa)."""
        args = (self.wx, self.wy, self.bound, self.near, 1.0 / self.dx)
        if not exact:
            ux, uy = self.displacement()
            return _sweep(self.tx, self.ty, ux, uy, *args, self.fast_blocks, self.cols, self.sigma)
        change = 0.0
        for k in range(self.exact_blocks.shape[0]):
            ux, uy = self.displacement()
            change = max(change, _sweep(self.tx, self.ty, ux, uy, *args, self.exact_blocks[k:k + 1], self.cols,
                                        self.sigma))
        return change

    def packed(self) -> np.ndarray:
        """The loaded cells' tractions (tx..., ty...) (the mixed vector)."""
        return _pack(self.t.reshape(2, -1), self.cells)

    def set_projected(self, v: np.ndarray) -> None:
        """Tractions from a packed vector, each cell's projected onto its friction disc |t| <= mu p."""
        _unpack_projected(v, self.cells, self.cell_bound, self.t.reshape(2, -1))


@kernel()
def _pack(t, cells):  # pragma: no cover - compiled
    """(t[0, cells], t[1, cells]) as one vector of length 2 len(cells)."""
    n = cells.size
    out = np.empty(2 * n)
    for k in range(n):
        out[k] = t[0, cells[k]]
        out[n + k] = t[1, cells[k]]
    return out


@kernel()
def _unpack_projected(v, cells, bound, t):  # pragma: no cover - compiled
    """t[:, cells] = the packed v's (tx, ty) of each cell, scaled onto the disc of radius ``bound`` if beyond it."""
    n = cells.size
    for k in range(n):
        vx = v[k]
        vy = v[n + k]
        mag = math.sqrt(vx * vx + vy * vy)
        fac = bound[k] / mag if mag > bound[k] else 1.0
        t[0, cells[k]] = vx * fac
        t[1, cells[k]] = vy * fac


def _loaded_box(on: np.ndarray) -> tuple[slice, slice]:
    """(rows, columns) of the loaded cells' bounding box, at least 2 x 2 where the grid has them (the cell size
    is read from neighbouring centres)."""
    out = []
    for axis in (1, 0):
        idx = np.flatnonzero(on.any(axis=axis))
        n = on.shape[1 - axis]
        lo, hi = int(idx[0]), int(idx[-1]) + 1
        if hi - lo < 2 <= n:
            lo, hi = (lo, lo + 2) if lo + 2 <= n else (n - 2, n)
        out.append(slice(lo, hi))
    return out[0], out[1]


def solve_rolling(x_mm: np.ndarray, y_mm: np.ndarray, p_MPa: np.ndarray, wx: np.ndarray, wy: np.ndarray,
                  friction: float, G_MPa: float, poisson: float,
                  options: RollingOptions = RollingOptions(),
                  initial_MPa: tuple[np.ndarray, np.ndarray] | None = None) -> RollingField:
    """Solve the steady rolling problem of the module docstring.

    x_mm (nx,), y_mm (ny,): cell centres (uniform, x increasing: +x is the leading side); p_MPa (ny, nx) >= 0;
    wx, wy (ny, nx): rigid slip / V at the cell centres (-); friction mu; G_MPa, poisson: the (common) material;
    initial_MPa: (tx, ty) (ny, nx) to start the iteration from (e.g. the previous solve of an iteration over the
    load; ignored when the shape differs): the same solution to the tolerance in fewer sweeps.
    """
    ny, nx = p_MPa.shape
    dx = float(x_mm[1] - x_mm[0]) if nx > 1 else 1.0
    dy = float(y_mm[1] - y_mm[0]) if ny > 1 else 1.0
    on = p_MPa > 0
    scale = float(friction * np.max(p_MPa, initial=0.0))
    if scale <= 0.0:
        z = np.zeros((ny, nx))
        return RollingField(z, z.copy(), np.where(on, wx, 0.0), np.where(on, wy, 0.0), on, 0, 0.0, 0)
    box = _loaded_box(on)
    if (box[0].stop - box[0].start, box[1].stop - box[1].start) != (ny, nx):
        # the loaded cells' bounding box only (the free cells around carry no traction and need no slip)
        start = None if initial_MPa is None else tuple(np.asarray(v)[box] if np.shape(v) == (ny, nx) else v
                                                     for v in initial_MPa)
        sub = solve_rolling(x_mm[box[1]], y_mm[box[0]], p_MPa[box], wx[box], wy[box], friction, G_MPa, poisson,
                            options, start)
        out = [np.zeros((ny, nx)) for _ in range(4)] + [np.zeros((ny, nx), dtype=bool)]
        for full, part in zip(out, (sub.tx_MPa, sub.ty_MPa, sub.sx, sub.sy, sub.slip)):
            full[box] = part
        return RollingField(*out, sub.iterations, sub.residual, sub.fft_evaluations)
    hs = TractionHalfSpace(ny, nx + 1, dy, dx, G_MPa, poisson)
    it = _Iteration(hs, p_MPa, wx, wy, friction, dx, options, initial_MPa)
    mixer = Anderson(2 * int(it.on.sum()), options.memory)
    exact = options.memory <= 0
    change, best = 0.0, np.inf
    for sweep in range(1, options.max_sweeps + 1):
        if not exact and sweep > options.max_sweeps // 2:
            exact = True                  # the accelerated iteration stalled: plain Gauss-Seidel from here
        before = None if exact else it.packed()
        change = it.sweep(exact)
        change /= min(scale, max(float(np.abs(it.t).max()), 1e-300))
        if change < options.tol:
            break
        if before is not None:
            if change > 100.0 * best:     # a mixing step that made things worse: start the history afresh
                mixer.restart()
            best = min(best, change)
            it.set_projected(mixer.mix(before, it.packed()))
    else:
        raise ConvergenceError(f"exact tangential solver: Gauss-Seidel did not converge in {options.max_sweeps} "
                               f"sweeps (traction change {change:.3g} of the traction scale, tolerance "
                               f"{options.tol:g})")
    ux, uy = it.displacement()
    wxc, wyc = it.wx, it.wy
    sx = np.where(on, wxc + (ux[:, :-1] - ux[:, 1:]) / dx, 0.0)
    sy = np.where(on, wyc + (uy[:, :-1] - uy[:, 1:]) / dx, 0.0)
    sx[on & ~it.slip] = 0.0
    sy[on & ~it.slip] = 0.0
    return RollingField(it.tx, it.ty, sx, sy, it.slip & on, sweep, float(change), hs.evaluations)
