"""Elastic half-space on a uniform rectangular grid: influence coefficients and their FFT convolution.

Units: mm, MPa (N/mm^2). Two bodies of (quasi-)identical material pressed together: the normal surface
displacement of both together caused by a pressure p (Boussinesq, combined compliance)

    u(x, y) = 2 (1 - nu^2) / (pi E) * II p(s, t) / sqrt((x - s)^2 + (y - t)^2) ds dt      (paper eq. 13's kernel)

The pressure is constant on every cell (dx by dy, centres x_i = x_0 + i dx, y_j = y_0 + j dy). The influence
coefficient of cell (k, l) on the centre of cell (i, j) is Love's (1929) closed form: the exact integral of 1/r
over the rectangle, by the corner antiderivative F(x, y) = x asinh(y/x) + y asinh(x/y) (no epsilon at the
singularity; :func:`contact.normal.boussinesq.rectangle_kernel_integral`). It depends only on the offsets
(i - k, j - l), so u = K * p is a 2-D linear convolution, evaluated exactly (no periodic wrap-around) by a
zero-padded real FFT of size at least (2 ny - 1) x (2 nx - 1); the kernel's transform is cached per grid
(nx, ny, dx, dy). The 2-D transforms are done one axis at a time (:func:`padded_rfft2`, :func:`cropped_irfft2`):
the padding rows are zero on the way in and not wanted on the way out, so only ny rows go through the x transform
(the same result as ``rfft2`` / ``irfft2`` on the padded array, 25-40 % less time on the solvers' grids).
"""

from __future__ import annotations

import functools

import numpy as np

from contact.normal.boussinesq import corner_antiderivative, rectangle_kernel_integral

__all__ = ["HalfSpace", "influence_coefficients", "compliance_factor", "cropped_irfft2", "fft_module",
           "offset_integrals", "padded_rfft2", "wrapped_kernel"]


@functools.cache
def fft_module():
    """scipy.fft, imported on first use: it takes 0.2-0.4 s to import and the Kik-Piotrowski path never needs it."""
    import scipy.fft
    return scipy.fft


def padded_rfft2(a: np.ndarray, shape: tuple[int, int]) -> np.ndarray:
    """``rfft2(a, s=shape)`` over the last two axes of ``a`` (..., ny, nx), zero-padded to ``shape``: the x
    transform of the ny data rows only, then the y transform."""
    sfft = fft_module()
    return sfft.fft(sfft.rfft(a, n=shape[1], axis=-1), n=shape[0], axis=-2)


def cropped_irfft2(spec: np.ndarray, shape: tuple[int, int], ny: int, nx: int) -> np.ndarray:
    """``irfft2(spec, s=shape)[..., :ny, :nx]``: the y transform, then the x transform of the first ny rows only."""
    sfft = fft_module()
    return sfft.irfft(sfft.ifft(spec, axis=-2)[..., :ny, :], n=shape[1], axis=-1)[..., :nx]


def compliance_factor(E_MPa: float, poisson: float) -> float:
    """2 (1 - nu^2) / (pi E) (1/MPa): both bodies of modulus E and Poisson's ratio nu (the KP solver's factor)."""
    return 2.0 * (1.0 - poisson ** 2) / (np.pi * E_MPa)


def influence_coefficients(di: np.ndarray, dj: np.ndarray, dx: float, dy: float) -> np.ndarray:
    """II 1/r over a cell (dx x dy, mm) whose centre is at offset (di dx, dj dy) from the field point (mm).

    Multiply by :func:`compliance_factor` to get mm of displacement per MPa of cell pressure."""
    xc = np.asarray(di, dtype=float) * dx
    yc = np.asarray(dj, dtype=float) * dy
    return rectangle_kernel_integral(xc - 0.5 * dx, xc + 0.5 * dx, yc - 0.5 * dy, yc + 0.5 * dy)


def offset_integrals(antiderivatives, ny: int, nx: int, dy: float, dx: float) -> list[np.ndarray]:
    """The integrals over every cell offset of a grid of ny lines by nx cells: for each corner antiderivative F
    (dF/dx dy = kernel), the (2 ny - 1, 2 nx - 1) array of F(x2, y2) - F(x1, y2) - F(x2, y1) + F(x1, y1) over the
    cell centred at (di dx, dj dy), stored at (dj + ny - 1, di + nx - 1). F is evaluated once per corner of the
    lattice of cell edges (4 times fewer evaluations than cell by cell)."""
    xe = (np.arange(2 * nx) - nx + 0.5) * dx
    ye = (np.arange(2 * ny) - ny + 0.5) * dy
    out = []
    for fun in antiderivatives:
        f = fun(xe[None, :], ye[:, None])
        out.append(f[1:, 1:] - f[:-1, 1:] - f[1:, :-1] + f[:-1, :-1])
    return out


def wrapped_kernel(dense: np.ndarray, shape: tuple[int, int]) -> np.ndarray:
    """A (2 ny - 1, 2 nx - 1) offset table (:func:`offset_integrals`) wrapped onto the periodic FFT array ``shape``
    (offset d at index d mod shape); the other entries are never read by a zero-padded convolution and stay 0."""
    ny, nx = (dense.shape[0] + 1) // 2, (dense.shape[1] + 1) // 2
    rows = np.arange(-(ny - 1), ny) % shape[0]
    cols = np.arange(-(nx - 1), nx) % shape[1]
    out = np.zeros(shape)
    out[np.ix_(rows, cols)] = dense
    return out


@functools.lru_cache(maxsize=32)
def _kernel_spectrum(ny: int, nx: int, dy: float, dx: float) -> tuple[np.ndarray, tuple[int, int], np.ndarray]:
    """rfft2 of the wrapped kernel on the padded shape (>= 2n - 1 each way, fast FFT length), and the kernel on the
    offsets -(n-1)..(n-1) (:func:`offset_integrals`)."""
    sfft = fft_module()
    shape = (sfft.next_fast_len(2 * ny - 1, real=True), sfft.next_fast_len(2 * nx - 1, real=True))
    (k,) = offset_integrals((corner_antiderivative,), ny, nx, dy, dx)
    spec = sfft.rfft2(wrapped_kernel(k, shape))
    for a in (spec, k):
        a.setflags(write=False)
    return spec, shape, k


class HalfSpace:
    """The convolution u = C * p on a grid of ny lines (y) by nx cells (x), cell dx by dy (mm).

    ``C``: :func:`compliance_factor` (1/MPa). :meth:`displacement` maps a (ny, nx) pressure (MPa) to the
    (ny, nx) displacement of both bodies together at the cell centres (mm)."""

    def __init__(self, ny: int, nx: int, dy: float, dx: float, factor: float):
        self.ny, self.nx, self.dy, self.dx, self.factor = int(ny), int(nx), float(dy), float(dx), float(factor)
        spec, self.shape, self._dense = _kernel_spectrum(self.ny, self.nx, self.dy, self.dx)
        self._spec = spec * self.factor
        self.evaluations = 0

    def displacement(self, p: np.ndarray) -> np.ndarray:
        """u = C * p (mm) for the cell pressures p (ny, nx) (MPa)."""
        self.evaluations += 1
        return cropped_irfft2(padded_rfft2(p, self.shape) * self._spec, self.shape, self.ny, self.nx)

    def cells_displacement(self, rows: np.ndarray, cols: np.ndarray, values: np.ndarray) -> np.ndarray:
        """u = C * p (mm) of a pressure on a few cells only (p[rows, cols] = values, MPa), summed directly from the
        influence coefficients: cheaper than a convolution for a handful of cells."""
        u = np.zeros((self.ny, self.nx))
        for r, c, v in zip(rows, cols, values):
            u += v * self._dense[self.ny - 1 - r:2 * self.ny - 1 - r, self.nx - 1 - c:2 * self.nx - 1 - c]
        return self.factor * u

    def self_influence(self) -> float:
        """Displacement of a cell centre under a unit pressure on that cell alone (mm/MPa)."""
        return float(self.factor * influence_coefficients(0, 0, self.dx, self.dy))
