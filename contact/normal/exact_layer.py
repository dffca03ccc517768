"""The Prandtl surface layer in series with the half-space, cell by cell, for the exact normal solver.

Units: mm, MPa, N/mm^3. Every cell (line j, cell i) of the exact grid carries the element(s) of its lateral strip
j (wheel + rail + combined layers in series, as in the Kik–Piotrowski solver: displacements add at the same
pressure). The layer displacement u_L counts from the element's current state (its displacement at rest, which
after earlier passes with kept state is already part of the separation). Two modes:

``indentation``  every cell is on its monotonic loading branch from the current state to its own pressure:
                 u_L(i, j) = u_j(p_ij) - u_j(0), u_j the element's loading curve (paper eq. 7 per segment).
``rolling``      steady rolling: material enters a line at the leading edge (largest x) and moves to -x, so a
                 cell's element has met the pressures of the cells ahead of it. It is moved monotonically from
                 cell to cell, p_{j,nx-1} -> ... -> p_{j,i} (exact element law with its sliders: loading along the
                 characteristic, unloading with the element's own law, Masing reverse slip included), and
                 u_L(i, j) is its displacement there. Past the peak the element unloads on its steeper branch,
                 so the pressure is not symmetric in x; behind the patch it keeps its residual displacement,
                 eq. (8) for a single peak p_0 <= 2 p_2.

The contact problem is nonlinear in p through u_L; :meth:`CellLayer.linearise` returns, at a pressure field p,
u_L(p) and the tangent compliance c = du_L/dp of each cell's current segment (in the direction of its move), so
that u_L ~ b + c p with b = u_L(p) - c p: the outer iteration of :func:`contact.normal.exact.solve_exact`.
"""

from __future__ import annotations

import numpy as np

from contact.layer.prandtl_layer import LayerPair, PrandtlLayer, move_elements
from contact.normal.layer_at_strip import layer_points
from wrlayer.errors import InputError
from wrlayer.jit import kernel

__all__ = ["LAYER_MODES", "CellLayer"]

LAYER_MODES = ("indentation", "rolling")
_DP = 1e-4            # pressure step of the tangent compliance (MPa): u is piecewise linear, so exact on a segment


class _Body:
    """One layer's elements on the lines of the grid (state copied at construction)."""

    def __init__(self, layer: PrandtlLayer, index: np.ndarray):
        self.name = layer.name
        self.index = index
        self.covered = index >= 0
        ix = np.where(self.covered, index, 0)
        self.u = np.ascontiguousarray(layer.u_mm[ix])
        self.slip = np.ascontiguousarray(layer.slip_mm[ix])
        self.k = np.ascontiguousarray(layer.k_N_per_mm3[ix])
        self.e = np.ascontiguousarray(layer.half_width_mm[ix])
        self.kl = np.ascontiguousarray(layer.k_last_N_per_mm3[ix])
        self.rho = np.ascontiguousarray(layer.reverse_factor[ix])

    def indentation(self, p: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        ny, nx = p.shape
        m = self.k.shape[1]
        rep = (lambda a: np.ascontiguousarray(np.repeat(a, nx, axis=0)))
        u0, kl, rho = rep(self.u), rep(self.kl), rep(self.rho)
        s0, k, e = (rep(a).reshape(ny * nx, m) for a in (self.slip, self.k, self.e))
        flat = np.ascontiguousarray(p.reshape(-1))
        u1 = move_elements(u0, s0, k, e, kl, flat, rho)[0]
        u2 = move_elements(u0, s0, k, e, kl, flat + _DP, rho)[0]
        return (u1 - u0).reshape(ny, nx), ((u2 - u1) / _DP).reshape(ny, nx)

    def rolling(self, p: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        u, c = _rolling_march(np.ascontiguousarray(p), self.u, self.slip, self.k, self.e, self.kl, self.rho)
        return u, c


@kernel()
def _rolling_march(p, u0, slip0, k, e, kl, rho):
    """Steady rolling: move each line's element from the leading edge (last column) to the trailing edge through
    the cell pressures p (ny, nx); returns the displacement from the initial state and the tangent compliance in
    the direction of each move (a move to an equal pressure counts as loading)."""
    ny, nx = p.shape
    u_out = np.empty((ny, nx))
    c_out = np.empty((ny, nx))
    u = u0.copy()
    s = slip0.copy()
    p_prev = np.zeros(ny)
    step = np.empty(ny)
    for i in range(nx - 1, -1, -1):
        col = np.ascontiguousarray(p[:, i])
        u_new, s_new, _ = move_elements(u, s, k, e, kl, col, rho)
        for j in range(ny):
            step[j] = _DP if col[j] >= p_prev[j] else -_DP
        u_pert = move_elements(u, s, k, e, kl, col + step, rho)[0]
        for j in range(ny):
            u_out[j, i] = u_new[j] - u0[j]
            c_out[j, i] = (u_pert[j] - u_new[j]) / step[j]
        u = u_new
        s = s_new
        p_prev = col
    return u_out, c_out


class CellLayer:
    """The layers of a :class:`LayerPair` on the exact grid's lines ``lines`` (indices into the strip grid)."""

    def __init__(self, layer: LayerPair | None, strip_y_mm: np.ndarray, grid_mm: float, lines: np.ndarray,
                 mode: str):
        if mode not in LAYER_MODES:
            raise InputError("method.layer_mode", f"must be one of {', '.join(LAYER_MODES)}, got {mode!r}")
        self.mode = mode
        self.bodies: list[_Body] = []
        if layer is not None:
            for lay in layer.bodies().values():
                if np.any(np.abs(lay.pressure_MPa) > 1e-9 * max(1.0, float(np.abs(lay.pressure_MPa).max()))):
                    raise InputError(lay.name, "layer must be unloaded (p = 0) before a normal solve")
                ix = layer_points(lay, strip_y_mm, grid_mm)[lines]
                self.bodies.append(_Body(lay, ix))

    @property
    def present(self) -> bool:
        return bool(self.bodies)

    def linearise(self, p: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """(u_L, c): layer displacement (mm) and tangent compliance (mm/MPa) per cell at the pressure p (MPa)."""
        u = np.zeros_like(p)
        c = np.zeros_like(p)
        for body in self.bodies:
            ub, cb = body.rolling(p) if self.mode == "rolling" else body.indentation(p)
            ub[~body.covered] = 0.0
            cb[~body.covered] = 0.0
            u += ub
            c += cb
        return u, c

    def check_coverage(self, p: np.ndarray, y_lines: np.ndarray) -> None:
        """InputError when a line in contact has no element of some layer."""
        loaded = np.any(p > 0, axis=1)
        for body in self.bodies:
            bad = loaded & ~body.covered
            if np.any(bad):
                raise InputError(body.name, f"has no element at strip y = {y_lines[np.argmax(bad)]:.6g} mm "
                                 "(contact there): the layer does not cover the contact patch")
