"""FaStrip: strip theory of rolling contact with Kalker-calibrated strip compliances, for any strip patch.

Units: mm, N, MPa, s; creepages vx, vy (-), spin phi (1/mm). Same sign conventions, inputs and output
(:class:`contact.tangential.fastsim.TangentialResult`) as FASTSIM (:mod:`contact.tangential.fastsim`): creepages
are body 1's rigid slip relative to body 2 over V, tractions act on body 1, the material enters each strip at its
leading edge x_c + x_l and leaves at x_c - x_l.

Idea (M. Sh. Sichani, R. Enblom, M. Berg 2016, "An alternative to FASTSIM for tangential solution of the
wheel–rail contact", *Vehicle System Dynamics* 54(6), FaStrip): Kalker's (1967) strip theory, in which every strip
along the rolling direction is a two-dimensional (Carter) rolling contact, with its stiffness calibrated by
Kalker's creep coefficients so that the linear theory is exact, extended for spin. The paper's closed forms were
not at hand here; the strip model below was derived for this project from that description, and each strip is
solved exactly on its cells rather than by closed forms.

Strip model. Along a strip (length 2 x_l, centre x_c, pressure p(x)) the displacement difference is

    u_k(x) = c_k Int K(x - x') t_k(x') dx',   K(x) = (2/pi) asinh(w / (2|x|))      (k = x, y)

the mean over a width w of the half-space's 1/r: a strip of width w = 2 b (b: lateral semi-axis of the patch's
equivalent ellipse, Kik–Piotrowski: same area and length/width ratio) loaded uniformly across. Where |x| << w the
kernel is the 2-D (plane) log kernel, so that strips of wide patches (a << b) are Carter's; where |x| >> w it decays
like w/|x|, so that long patches (a >> b) behave locally, as FASTSIM's flexibility assumes. Slip / V:
s = w_r - du/dx with the rigid slip w_r = (vx - phi y, vy + phi' (x - x_c)); Coulomb |t| <= mu p,
t = -mu p s/|s| where s != 0.

Calibration (:func:`strip_flexibilities`). The model's full-adhesion forces on the equivalent ellipse (c = 1, unit
creepage and unit spin; linear solves strip by strip; they scale with a^2 and a^3; interpolated in a/b,
:func:`model_coefficients`) give
c_x, c_y and the spin factor phi'/phi such that Fx = -G a b C11 vx, Fy = -G a b (C22 vy + sqrt(ab) C23 phi)
(Kalker's linear theory, :mod:`contact.tangential.kalker_coefficients`). The longitudinal part -phi y of the spin
acts strip by strip unscaled (the strip's own longitudinal creepage), so the result does not depend on the point
the spin is taken about (unlike FASTSIM's, :mod:`contact.tangential.spin_centre`).

Solution. The Coulomb problem of each strip is solved on its ``nx`` cells (closed-form cell integrals of K) by the
nonlinear Gauss–Seidel march on the summed slip equation of the exact solver
(:mod:`contact.tangential.exact_rolling`), strip by strip (nx^2 work per sweep and strip; the strips do not interact).
"""

from __future__ import annotations

import functools
import math

import numpy as np

from contact.normal.patch import Patch
from contact.tangential.exact_rolling import coulomb_cell
from contact.tangential.fastrip_nodes import table_node
from contact.tangential.fastsim import (
    Creepage,
    TangentialResult,
    equivalent_ellipse,
    strip_cells,
)
from wrlayer.errors import ConvergenceError
from wrlayer.jit import kernel

__all__ = ["NODES_PER_DECADE", "START_STRIPS", "STRIP_TOL", "clear_node_cache", "model_coefficients",
           "solve_fastrip", "solve_model_coefficients", "start_tractions", "strip_flexibilities"]

#: The strip solver's stop: the largest traction change of a sweep below STRIP_TOL times the strip's traction scale
#: min(mu max p, max |t|). On the A-2.2 sweep 1e-5 leaves the forces within 3.5e-7 mu F_N (exact/fastrip; 8.3e-7
#: coarse_exact/fastrip) of solves to 1e-7, with 8 sweeps per strip on average instead of 15 (1e-6: 4.5e-8 mu F_N,
#: 11 sweeps).
STRIP_TOL = 1e-5
#: A start (:func:`start_tractions`) is used while the patch's strip count differs from the earlier one's by at
#: most this many strips (a balance step changes the patch by a strip or two).
START_STRIPS = 3

def _cell_integrals(c: np.ndarray, m: np.ndarray) -> np.ndarray:
    """(2/pi) Int_{m-1/2}^{m+1/2} asinh(c/|z|) dz for half-widths c (ny, 1) and offsets m (in cell widths)."""
    def prim(z):                                    # odd antiderivative: z asinh(c/|z|) + c asinh(z/c)
        az = np.abs(z)
        return np.where(az > 0, z * np.arcsinh(c / np.where(az > 0, az, 1.0)), 0.0) + c * np.arcsinh(z / c)

    return 2.0 / np.pi * (prim(m + 0.5) - prim(m - 0.5))


def strip_kernel(width_mm: float, dx_mm: np.ndarray, nx: int) -> np.ndarray:
    """kappa[j, m + nx + 1], m = -(nx+1)..(nx+1): the strip kernel's influence (in units of dx_j) of a cell of
    strip j at an offset of m cells: K(x) = (1/pi) Int_{-w/2}^{w/2} dy / sqrt(x^2 + y^2) = (2/pi) asinh(w/(2|x|))
    integrated over the cell (w = width_mm)."""
    m = np.arange(-(nx + 1), nx + 2, dtype=float)[None, :]
    return np.ascontiguousarray(_cell_integrals((0.5 * width_mm / np.asarray(dx_mm, float))[:, None], m))


#: The model's coefficients are solved at a/b = 10^(k / NODES_PER_DECADE) (integer k) and interpolated between
#: these nodes (:func:`model_coefficients`): cubic in log(a/b) on log k, within 1e-7 of the direct solve (1.5e-6
#: with 16 nodes per decade, 2.4e-5 with 8; tests/contact/tangential/test_fastrip_and_methods.py).
NODES_PER_DECADE = 32


def model_coefficients(a_over_b: float, nx: int) -> tuple[float, float]:
    """(k_x, k_phi) of :func:`solve_model_coefficients` at ``a_over_b``, interpolated from its values at the four
    nearest nodes a/b = 10^(k / :data:`NODES_PER_DECADE`) (Lagrange cubic in log(a/b), on the logarithms of k_x,
    k_phi). The nodes are read from the shipped table or solved, and cached, so the patches of a sweep (a/b changing
    in every balance step) share a few dozen of them; a given a/b gives the same values whatever was solved before."""
    s = math.log(a_over_b) * NODES_PER_DECADE / math.log(10.0)
    k0 = math.floor(s) - 1
    out = np.zeros(2)
    for i in range(4):
        w = 1.0
        for j in range(4):
            if j != i:
                w *= (s - (k0 + j)) / (i - j)
        out += w * np.log(_node_coefficients(k0 + i, int(nx)))
    k_x, k_phi = np.exp(out)
    return float(k_x), float(k_phi)


@functools.lru_cache(maxsize=512)
def _node_coefficients(k: int, nx: int) -> tuple[float, float]:
    """:func:`solve_model_coefficients` at the node a/b = 10^(k / :data:`NODES_PER_DECADE`): from the shipped table
    (:mod:`contact.tangential.fastrip_nodes`) where it holds the node, else solved."""
    return table_node(k, nx, NODES_PER_DECADE) or solve_model_coefficients(10.0 ** (k / NODES_PER_DECADE), nx)


def clear_node_cache() -> None:
    """Forget the nodes solved or read so far (:func:`model_coefficients`; a benchmark's sweeps each start as a new
    process would, from the shipped table)."""
    _node_coefficients.cache_clear()


def solve_model_coefficients(a_over_b: float, nx: int, ny: int = 41) -> tuple[float, float]:
    """(k_x, k_phi): -Fx per unit vx and -Fy per unit spin phi' of the strip model with c = 1 in full adhesion on
    the ellipse a = 1 mm, b = 1/a_over_b (strip width w = 2 b; linear solves, strip by strip). On an ellipse of
    semi-axis a they scale as a^2 and a^3."""
    b = 1.0 / a_over_b
    h = 2.0 * b / ny
    y = -b + (np.arange(ny) + 0.5) * h
    xl = np.sqrt(1.0 - (y / b) ** 2)
    dx = 2.0 * xl / nx
    kap = strip_kernel(2.0 * b, dx, nx)
    idx = np.arange(nx + 1)
    K = kap[:, (idx[:, None] - idx[None, :]) + nx + 1] * dx[:, None, None]     # (ny, nx+1, nx+1); index 0: the pad
    M = K[:, 1:, 1:] - K[:, 0:1, 1:]
    xm = xl[:, None] - (np.arange(nx) + 0.5)[None, :] * dx[:, None]
    rhs = -np.cumsum(np.stack([np.ones((ny, nx)), xm], axis=2) * dx[:, None, None], axis=1)
    t = np.linalg.solve(M, rhs)                                  # every strip's two full-adhesion solves at once
    forces = -(t.sum(axis=1) * (dx * h)[:, None]).sum(axis=0)
    return float(forces[0]), float(forces[1])


def strip_flexibilities(a_mm: float, b_mm: float, C11: float, C22: float, C23: float, G_MPa: float, nx: int
                        ) -> tuple[float, float, float]:
    """(c_x, c_y, phi'/phi) of the strip model (module docstring): the kernel compliances c_x, c_y (1/MPa) and
    the spin factor (-) that give Kalker's linear theory on the ellipse (a, b in mm) with nx cells per strip."""
    k_x, k_phi = model_coefficients(a_mm / b_mm, int(nx))
    cx = k_x * a_mm ** 2 / (G_MPa * a_mm * b_mm * C11)
    cy = k_x * a_mm ** 2 / (G_MPa * a_mm * b_mm * C22)
    spin = G_MPa * (a_mm * b_mm) ** 1.5 * C23 * cy / (k_phi * a_mm ** 3)
    return float(cx), float(cy), float(spin)


@kernel()
def _warm_start(tx, ty, ux, uy, j, src_x, src_y, ratio, bound, kappa, cx, cy, h):  # pragma: no cover - compiled
    """Strip j's traction := the traction src (nx,) cell by cell, times ``ratio``, within the bound; ux, uy its
    displacement (index 0: the pad)."""
    nx = tx.shape[1]
    c0 = nx + 1
    for k in range(nx):
        tx[j, k] = src_x[k] * ratio
        ty[j, k] = src_y[k] * ratio
        mag = math.sqrt(tx[j, k] ** 2 + ty[j, k] ** 2)
        if mag > bound[j, k]:
            tx[j, k] *= bound[j, k] / mag
            ty[j, k] *= bound[j, k] / mag
    for q in range(nx + 1):
        for k in range(nx):
            kq = kappa[j, q - (k + 1) + c0] * h
            ux[q] += cx * kq * tx[j, k]
            uy[q] += cy * kq * ty[j, k]


@kernel(fastmath=True)  # the updates vectorised: the strip solves 5 % faster on, forces within 1e-11 N
def _strips(dx, wx, wy, bound, kappa, cx, cy, tol, max_sweeps, start_x, start_y, start_scale
            ):  # pragma: no cover - compiled
    """Every strip's rolling problem (kernel table kappa (ny, 2 nx + 3), :func:`strip_kernel`); cells k = 0
    (leading) .. nx-1, the free pad ahead of cell 0. Strip j starts from start_x[j], start_y[j] (an earlier
    solution's traction at the bound start_scale[j] (its largest mu p), scaled to this strip's) when
    start_scale[j] > 0, else from the last solved strip's traction.

    Returns tx, ty, sx, sy (ny, nx), slip flags and the largest sweep count (-1 when a strip did not converge)."""
    ny, nx = wx.shape
    tx = np.zeros((ny, nx))
    ty = np.zeros((ny, nx))
    sx = np.zeros((ny, nx))
    sy = np.zeros((ny, nx))
    slip = np.zeros((ny, nx), dtype=np.bool_)
    c0 = nx + 1                                  # kappa index of offset 0
    worst = 0
    prev, prev_scale = -1, 1.0
    gx = np.empty(kappa.shape[1])                # the strip's kernel times dx and c_x, c_y (the update's factors)
    gy = np.empty(kappa.shape[1])
    for j in range(ny):
        h = dx[j]
        ux = np.zeros(nx + 1)                    # index 0: the pad; cell k at index k + 1
        uy = np.zeros(nx + 1)
        bx = cx * kappa[j, c0]                   # d s_k / d t_k: the cell's own kernel coefficient / dx
        by = cy * kappa[j, c0]
        for m in range(kappa.shape[1]):
            kq = kappa[j, m] * h
            gx[m] = cx * kq
            gy[m] = cy * kq
        scale = 0.0
        for k in range(nx):
            scale = max(scale, bound[j, k])
        if scale <= 0.0:
            continue
        if start_scale[j] > 0.0:                 # an earlier solution of this strip (a balance's last step)
            _warm_start(tx, ty, ux, uy, j, start_x[j], start_y[j], scale / start_scale[j], bound, kappa, cx, cy, h)
        elif prev >= 0:                          # start from the last solved strip's traction (35 % faster)
            _warm_start(tx, ty, ux, uy, j, tx[prev], ty[prev], scale / prev_scale, bound, kappa, cx, cy, h)
        prev, prev_scale = j, scale
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
                off = c0 - (k + 1)
                for q in range(nx + 1):          # displacement at index q (cell q - 1) from cell k (index k + 1)
                    ux[q] += gx[q + off] * dtx
                    uy[q] += gy[q + off] * dty
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


def start_tractions(start: TangentialResult | None, ny: int, nx: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(t_x, t_y (ny, nx), mu p_max per strip (ny,)) to start ``ny`` strips of ``nx`` cells from an earlier FaStrip
    solution of nearly the same patch (the previous step of a balance iteration): strip j from the earlier strip
    at the same relative position across the patch (the same strip when the count is unchanged), cell by cell;
    zeros (no start) without one, for another cell count or for a strip count changed by more than
    :data:`START_STRIPS`."""
    tx, ty, scale = np.zeros((ny, nx)), np.zeros((ny, nx)), np.zeros(ny)
    if start is None or start.method != "fastrip" or start.tx_MPa.shape[1] != nx \
            or abs(start.tx_MPa.shape[0] - ny) > START_STRIPS:
        return tx, ty, scale
    m = start.tx_MPa.shape[0]
    src = np.rint(np.arange(ny) * ((m - 1) / max(ny - 1, 1))).astype(int) if m != ny else np.arange(ny)
    return (np.ascontiguousarray(start.tx_MPa[src]), np.ascontiguousarray(start.ty_MPa[src]),
            start.friction * start.pn_MPa[src].max(axis=1))


def solve_fastrip(patch: Patch, creepage: Creepage, G_MPa: float, poisson: float, friction: float,
                  speed_mm_s: float = 1000.0, nx: int = 60, pressure_cells_MPa: np.ndarray | None = None,
                  strip_centre_mm: np.ndarray | None = None, tol: float = STRIP_TOL, max_sweeps: int = 1000,
                  start: TangentialResult | None = None) -> TangentialResult:
    """FaStrip on the patch's strips; arguments as :func:`contact.tangential.fastsim.solve_tangential` (without
    ``flexibility``); tol, max_sweeps: the strip solver's stop (relative traction change) and limit; ``start``: an
    earlier FaStrip solution of nearly the same patch to start the strips from (:func:`start_tractions`; the
    same solution to the tolerance, in fewer sweeps). The result's ``iterations``: the most sweeps a strip took.
    ConvergenceError when a strip does not converge."""
    cells = strip_cells(patch, creepage, G_MPa, poisson, friction, speed_mm_s, nx, pressure_cells_MPa,
                        strip_centre_mm)
    ell = equivalent_ellipse(patch, G_MPa, poisson)
    k = ell.coefficients
    cx, cy, spin_factor = strip_flexibilities(ell.a_mm, ell.b_mm, k.C11, k.C22, k.C23, G_MPa, nx)
    y, x, xc, pn, dx = patch.y_mm, cells.x_mm, cells.centre_mm, cells.pn_MPa, cells.dx_mm
    wx = np.ascontiguousarray(np.broadcast_to((creepage.vx - creepage.phi_per_mm * y)[:, None], x.shape))
    wy = np.ascontiguousarray(creepage.vy + creepage.phi_per_mm * spin_factor * (x - xc[:, None]))
    tx, ty, sx, sy, slip, sweeps = _strips(dx, wx, wy, np.ascontiguousarray(friction * pn),
                                           strip_kernel(2.0 * ell.b_mm, dx, int(nx)), cx, cy, float(tol),
                                           int(max_sweeps), *start_tractions(start, y.size, int(nx)))
    if sweeps < 0:
        raise ConvergenceError(f"FaStrip: a strip did not converge in {max_sweeps} sweeps (tolerance {tol:g})")
    # spin-scaled lateral slip is the strip model's; the reported slip is the model's slip
    speed = np.hypot(sx, sy)
    work = np.hypot(tx, ty) * speed * dx[:, None]                 # N/mm per cell and pass
    return cells.result(patch, tx, ty, slip, speed * speed_mm_s, work, ell, "fastrip", (cx, cy, spin_factor),
                        sweeps, 0.0)
