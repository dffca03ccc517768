"""Cerruti influence coefficients of uniform tangential traction on rectangular cells, FFT-convolved.

Units: mm, MPa (N/mm^2). Two quasi-identical bodies (same G and nu): the tangential surface displacement
difference u = u_1 - u_2 caused by the traction t acting on body 1 (and -t on body 2) is twice one body's
(Johnson 1985, *Contact Mechanics*, eqs. 2.19 at z = 0 (Cerruti); Kalker 1990, *Three-dimensional elastic bodies
in rolling contact*, section 1.5):

    u_x = 1/(pi G) II [ ((1 - nu)/r + nu x^2/r^3) t_x + nu x y/r^3 t_y ] ds dt
    u_y = 1/(pi G) II [ nu x y/r^3 t_x + ((1 - nu)/r + nu y^2/r^3) t_y ] ds dt

with (x, y) the offset of the field point from the loaded point and r = |(x, y)|. Since (1 - nu)/r + nu x^2/r^3
= 1/r - nu y^2/r^3, the integrals over a cell need three corner antiderivatives F (dF/dx dy = kernel),
evaluated once per corner of the grid's lattice of cell edges (:func:`contact.normal.halfspace.offset_integrals`):

    y^2/r^3  -> x asinh(y/|x|)
    x^2/r^3  -> y asinh(x/|y|)
    x y/r^3  -> -r
    1/r      -> the sum of the first two (Love 1929; contact.normal.boussinesq)

so every coefficient is exact (no quadrature, no epsilon at the singularity). The normal-tangential coupling
(Cerruti's u_z ~ (1 - 2 nu) x / r^2) vanishes for quasi-identical bodies: the difference of the two bodies'
normal displacements cancels. For dissimilar materials 1/G becomes (1/G_1 + 1/G_2)/2 with the nu terms weighted
per body, and Kalker's difference parameter K = ((1 - 2 nu_1)/G_1 - (1 - 2 nu_2)/G_2)/4 couples the normal and
tangential problems (an outer Panagiotopoulos iteration would then alternate normal and tangential solves).

The coefficients depend only on the cell offsets, so u = A * t is a 2-D linear convolution evaluated exactly by a
zero-padded real FFT (both components in one call of :func:`contact.normal.halfspace.padded_rfft2` and of
:func:`contact.normal.halfspace.cropped_irfft2`); the kernels' transforms are cached per grid (ny, nx, dy, dx, nu).
"""

from __future__ import annotations

import functools

import numpy as np

from contact.normal.halfspace import cropped_irfft2, fft_module, offset_integrals, padded_rfft2, wrapped_kernel
from wrlayer.jit import kernel

__all__ = ["TractionHalfSpace", "cerruti_coefficients"]


def _asinh_x(x, y):
    """x asinh(y/|x|), 0 at x = 0 (its limit): the corner antiderivative of y^2/r^3."""
    x = np.asarray(x, dtype=float)
    y = np.asarray(y, dtype=float)
    with np.errstate(divide="ignore", invalid="ignore"):
        return np.where(x != 0.0, x * np.arcsinh(y / np.abs(x)), 0.0)


def _asinh_y(x, y):
    """y asinh(x/|y|): the corner antiderivative of x^2/r^3."""
    return _asinh_x(y, x)


def _minus_r(x, y):
    """-r: the corner antiderivative of x y/r^3."""
    return -np.hypot(x, y)


def _combine(i_yy, i_xx, i_xy, poisson):
    """(A_xx, A_xy, A_yy) * pi G from the integrals of y^2/r^3, x^2/r^3 and x y/r^3 (II 1/r = i_xx + i_yy)."""
    return i_xx + (1.0 - poisson) * i_yy, poisson * i_xy, i_yy + (1.0 - poisson) * i_xx


def cerruti_coefficients(di, dj, dx: float, dy: float, poisson: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(A_xx, A_xy, A_yy) * pi G: displacement difference at a cell centre (mm, times pi G in MPa) under a unit
    traction (1 MPa) on a cell (dx by dy, mm) whose centre lies at offset (-di dx, -dj dy) from the field point,
    i.e. field minus source = (di dx, dj dy). Divide by pi G to get mm/MPa."""
    xc = np.asarray(di, dtype=float) * dx
    yc = np.asarray(dj, dtype=float) * dy
    x1, x2, y1, y2 = xc - 0.5 * dx, xc + 0.5 * dx, yc - 0.5 * dy, yc + 0.5 * dy
    corners = lambda f: f(x2, y2) - f(x1, y2) - f(x2, y1) + f(x1, y1)  # noqa: E731
    return _combine(corners(_asinh_x), corners(_asinh_y), corners(_minus_r), poisson)


@functools.lru_cache(maxsize=16)
def _spectra(ny: int, nx: int, dy: float, dx: float, poisson: float):
    """rfft2 of the three wrapped kernels (scaled by pi G) on the padded shape, and the kernels themselves on the
    offsets -(n-1)..(n-1) (read-only; the local solver uses them as its near field)."""
    sfft = fft_module()
    shape = (sfft.next_fast_len(2 * ny - 1, real=True), sfft.next_fast_len(2 * nx - 1, real=True))
    dense = np.stack(_combine(*offset_integrals((_asinh_x, _asinh_y, _minus_r), ny, nx, dy, dx), poisson))
    spec = tuple(sfft.rfft2(wrapped_kernel(k, shape)) for k in dense)
    for a in (*spec, dense):
        a.setflags(write=False)
    return spec, shape, dense


class TractionHalfSpace:
    """u = A * t on a grid of ny lines by nx cells (cell dx by dy, mm) for quasi-identical bodies.

    :meth:`displacement` maps tractions (tx, ty), each (ny, nx) in MPa, to the displacement difference (ux, uy) at
    the cell centres (mm). ``near``: (3, 2 ny - 1, 2 nx - 1) coefficients A_xx, A_xy, A_yy (mm/MPa) for the
    offsets (field - source) = (dj, di) stored at index (dj + ny - 1, di + nx - 1).
    """

    def __init__(self, ny: int, nx: int, dy: float, dx: float, G_MPa: float, poisson: float):
        self.ny, self.nx, self.dy, self.dx = int(ny), int(nx), float(dy), float(dx)
        spec, self.shape, dense = _spectra(self.ny, self.nx, self.dy, self.dx, float(poisson))
        scale = 1.0 / (np.pi * G_MPa)
        self._spec = tuple(np.ascontiguousarray(s * scale) for s in spec)
        self.near = dense * scale
        self.evaluations = 0

    def displacement(self, tx: np.ndarray, ty: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """(ux, uy) (mm) of the cell tractions (tx, ty) (MPa)."""
        u = self.displacement_pair(np.stack((tx, ty)))
        return u[0], u[1]

    def displacement_pair(self, t: np.ndarray) -> np.ndarray:
        """(ux, uy) (2, ny, nx) (mm) of the tractions (tx, ty) (2, ny, m) (MPa), m <= nx: the columns from m on
        carry no traction (zero-padded, as the FFT's own padding)."""
        self.evaluations += 1
        f = padded_rfft2(t, self.shape)                      # both components in one call
        _spectral_product(*self._spec, f)                     # in place: no complex temporaries
        return cropped_irfft2(f, self.shape, self.ny, self.nx)


@kernel()
def _spectral_product(sxx, sxy, syy, f):  # pragma: no cover - compiled
    """f = (sxx fx + sxy fy, sxy fx + syy fy) in place on the spectra f (2, ky, kx)."""
    for a in range(f.shape[1]):
        for b in range(f.shape[2]):
            fx = f[0, a, b]
            fy = f[1, a, b]
            f[0, a, b] = sxx[a, b] * fx + sxy[a, b] * fy
            f[1, a, b] = sxy[a, b] * fx + syy[a, b] * fy
