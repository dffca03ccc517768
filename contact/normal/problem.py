"""The normal contact problem: separation, load, material and the fixed lateral strip grid (paper sec. 4).

The separation table f(y) (mm) is interpolated onto a FIXED lateral strip grid (centres at integer multiples of
h = ``grid_mm``; y = 0 should be the geometric contact point) and shifted so that its minimum is 0. Every normal
solver (:mod:`contact.normal.kik_piotrowski`, :mod:`contact.normal.exact`) and the passes work on that grid.
Units: mm, N, MPa.
"""

from __future__ import annotations

import copy
from dataclasses import dataclass, field

import numpy as np

from wrlayer.errors import require

__all__ = ["ALPHA", "GRID_MM", "NormalProblem", "strip_grid"]

#: Kik–Piotrowski's virtual-penetration factor delta_0 = alpha delta, the paper's value (eq. 9; ``method.alpha``).
ALPHA = 0.55
#: Strip width h of the lateral grid (mm; ``method.grid_mm``).
GRID_MM = 0.1


def strip_grid(y_min_mm: float, y_max_mm: float, grid_mm: float) -> np.ndarray:
    """Strip centres j h (integer j) inside [y_min, y_max] (mm): the fixed lateral grid."""
    j0 = int(np.ceil(y_min_mm / grid_mm - 1e-9))
    j1 = int(np.floor(y_max_mm / grid_mm + 1e-9))
    return np.arange(j0, j1 + 1) * grid_mm


def _on_grid(y: np.ndarray, f: np.ndarray, yg: np.ndarray, interpolation: str) -> np.ndarray:
    """f(y) interpolated onto the strip centres ``yg`` (mm), linearly or by a monotone cubic (PCHIP)."""
    if interpolation == "linear":
        return np.interp(yg, y, f)
    # scipy.interpolate is imported here: it is slow to import and only the "pchip" option needs it
    from scipy.interpolate import PchipInterpolator

    return PchipInterpolator(y, f)(yg)


@dataclass(frozen=True)
class NormalProblem:
    """Input of the normal problem (units mm, N, MPa).

    Attributes
    ----------
    y_mm : numpy.ndarray
        Lateral positions of the separation table (mm), strictly increasing.
    f_mm : numpy.ndarray
        Separation of the undeformed profiles at ``y_mm`` (mm); only its shape matters (shifted to min 0).
    normal_force_N : float
        Normal force N (N), eq. 12.
    rolling_radius_mm : float
        Radius R in the rolling direction (mm): the virtual penetration's x_l = sqrt(2 R g), eq. 10.
    E_MPa : float
        Young's modulus of both bodies (MPa).
    poisson : float
        Poisson's ratio of both bodies (1).
    alpha : float
        Virtual-penetration factor delta_0 = alpha delta (1), eq. 9; the paper's 0.55.
    grid_mm : float
        Strip width h of the lateral grid (mm).
    interpolation : str
        "linear" or "pchip" (monotone cubic) interpolation of the table onto the strip grid.
    x_subdivision : int
        Sub-cells per strip along x in the Boussinesq integral I2 (1), eq. 13.
    f_offset_mm : numpy.ndarray or None
        Added to the separation on the strip grid (mm), one value per strip (dents from earlier passes).
    region_interaction : bool
        Separate contact regions interact elastically and each region's virtual penetration comes from its own
        local approach (:mod:`contact.normal.regions`); False: the independent regions of the earlier solver.
    """

    y_mm: np.ndarray
    f_mm: np.ndarray
    normal_force_N: float
    rolling_radius_mm: float
    E_MPa: float
    poisson: float
    alpha: float = ALPHA
    grid_mm: float = GRID_MM
    interpolation: str = "linear"
    x_subdivision: int = 1
    f_offset_mm: np.ndarray | None = None
    region_interaction: bool = True
    _grid: tuple = field(default=None, init=False, repr=False, compare=False)

    def __post_init__(self):
        y = np.asarray(self.y_mm, dtype=float).ravel()
        f = np.asarray(self.f_mm, dtype=float).ravel()
        object.__setattr__(self, "y_mm", y)
        object.__setattr__(self, "f_mm", f)
        require(y.size == f.size and y.size >= 2, "separation", "y_mm and f_mm need the same length (>= 2)")
        require(bool(np.all(np.isfinite(y)) and np.all(np.isfinite(f))), "separation", "contains NaN/inf")
        require(bool(np.all(np.diff(y) > 0)), "separation.y_mm", "must be strictly increasing")
        for name in ("normal_force_N", "rolling_radius_mm", "E_MPa", "grid_mm"):
            v = getattr(self, name)
            require(bool(np.isfinite(v) and v > 0), name, f"must be a positive number, got {v!r}")
        require(bool(-1.0 < self.poisson < 0.5), "poisson", f"must lie in (-1, 0.5), got {self.poisson!r}")
        require(bool(0.0 < self.alpha <= 1.0), "alpha", f"must lie in (0, 1], got {self.alpha!r}")
        require(self.interpolation in ("linear", "pchip"), "interpolation",
                f"must be 'linear' or 'pchip', got {self.interpolation!r}")
        require(int(self.x_subdivision) >= 1, "x_subdivision", "must be a positive integer")
        yg = strip_grid(y[0], y[-1], self.grid_mm)
        require(yg.size >= 1, "separation.y_mm", f"range shorter than one grid step {self.grid_mm} mm")
        object.__setattr__(self, "_grid", (yg, _on_grid(y, f, yg, self.interpolation)))
        self._set_offset(self.f_offset_mm)

    def __repr__(self) -> str:
        return (f"NormalProblem(N={self.normal_force_N:g} N, R={self.rolling_radius_mm:g} mm, "
                f"E={self.E_MPa:g} MPa, nu={self.poisson:g}, y=[{self.y_mm[0]:g}, {self.y_mm[-1]:g}] mm "
                f"({self.y_mm.size} points), grid={self.grid_mm:g} mm, alpha={self.alpha:g}"
                f"{', with offset' if self.f_offset_mm is not None else ''})")

    def _set_offset(self, f_offset_mm) -> None:
        yg, fg = self._grid[:2]
        if f_offset_mm is not None:
            off = np.asarray(f_offset_mm, dtype=float).ravel()
            require(off.shape == yg.shape and bool(np.all(np.isfinite(off))), "f_offset_mm",
                    f"needs {yg.size} finite values (one per strip)")
            object.__setattr__(self, "f_offset_mm", off)
            fg = fg + off
        object.__setattr__(self, "_grid", (yg, self._grid[1], fg))

    @property
    def strip_y_mm(self) -> np.ndarray:
        """Centres of the fixed strip grid (mm)."""
        return self._grid[0]

    @property
    def separation_on_grid_mm(self) -> np.ndarray:
        """f on the strip grid, shifted so that its minimum is 0 (mm)."""
        return self._grid[2] - self._grid[2].min()

    @property
    def separation_unshifted_on_grid_mm(self) -> np.ndarray:
        """f interpolated onto the strip grid plus ``f_offset_mm``, not shifted (mm)."""
        return self._grid[2]

    def with_offset(self, f_offset_mm: np.ndarray) -> "NormalProblem":
        """The same problem with the separation raised by ``f_offset_mm`` on the strip grid (dents)."""
        out = copy.copy(self)                      # the interpolated table is shared, only the offset changes
        out._set_offset(f_offset_mm)
        return out

    def with_force(self, normal_force_N: float) -> "NormalProblem":
        """The same problem at another normal force (N); the interpolated table is shared, not rebuilt."""
        require(bool(np.isfinite(normal_force_N) and normal_force_N > 0), "normal_force_N",
                f"must be a positive number, got {normal_force_N!r}")
        out = copy.copy(self)
        object.__setattr__(out, "normal_force_N", normal_force_N)
        return out

    @property
    def elastic_compliance_factor(self) -> float:
        """2 (1 - nu^2) / (pi E) (1/MPa): elastic part of delta = factor * p_0 * I2 / x_l(0) (mm), eq. 13."""
        return 2.0 * (1.0 - self.poisson ** 2) / (np.pi * self.E_MPa)
