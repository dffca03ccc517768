"""A contact patch on the square grid of the Kik–Piotrowski method (paper section 4, eqs. 10–12).

One connected contact region, discretised in strips of width ``h`` along the rolling direction x. Each strip
extends from the leading edge ``x_l(y)`` to the trailing edge ``-x_l(y)`` (eq. 10) and carries a semi-elliptic
pressure ``p(x, y) = p_peak(y) sqrt(1 - (x / x_l(y))^2)`` (eq. 11, with p_peak(y) = p_0 x_l(y) / x_l(0)).
Units: mm, MPa, N.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from wrlayer.errors import InputError


@dataclass(frozen=True, repr=False)
class Patch:
    """One connected contact region of strips (units mm, MPa).

    grid_mm: edge h of the square elements; y_mm: (ny,) strip centres, spacing h, increasing;
    x_lead_mm: (ny,) leading edge x_l(y) > 0 (trailing edge at -x_l); p_peak_MPa: (ny,) peak pressure p(0, y).
    """

    grid_mm: float
    y_mm: np.ndarray
    x_lead_mm: np.ndarray
    p_peak_MPa: np.ndarray

    def __post_init__(self):
        y = np.asarray(self.y_mm, dtype=float)
        xl = np.asarray(self.x_lead_mm, dtype=float)
        pk = np.asarray(self.p_peak_MPa, dtype=float)
        object.__setattr__(self, "y_mm", y)
        object.__setattr__(self, "x_lead_mm", xl)
        object.__setattr__(self, "p_peak_MPa", pk)
        if not (np.isfinite(self.grid_mm) and self.grid_mm > 0):
            raise InputError("patch.grid_mm", f"must be a positive number, got {self.grid_mm!r}")
        if y.ndim != 1 or y.size == 0 or xl.shape != y.shape or pk.shape != y.shape:
            raise InputError("patch", "y_mm, x_lead_mm and p_peak_MPa must be non-empty 1-D arrays of one length")
        # one sum per array: it is finite exactly when every value is (below 1e308; a patch is built per solve)
        if not (math.isfinite(y.sum()) and math.isfinite(xl.sum()) and math.isfinite(pk.sum())):
            raise InputError("patch", "contains NaN or infinite values")
        if xl.min() <= 0 or pk.min() < 0:
            raise InputError("patch", "strips need x_lead_mm > 0 and p_peak_MPa >= 0")
        if y.size > 1 and bool((y[1:] <= y[:-1]).any()):
            raise InputError("patch.y_mm", "strip centres must increase")

    def __repr__(self) -> str:
        return (f"Patch({self.n_strips} strips y=[{self.y_mm[0]:.4g}, {self.y_mm[-1]:.4g}] mm, "
                f"h={self.grid_mm:g} mm, length={self.length_mm():.4g} mm, "
                f"p_peak max={float(self.p_peak_MPa.max()):.6g} MPa)")

    @property
    def n_strips(self) -> int:
        return int(self.y_mm.size)

    def normal_force_N(self) -> float:
        """Integral of the semi-elliptic pressure over the strips (eq. 12): sum pi/2 p_peak x_l h (N)."""
        return float(np.sum(0.5 * np.pi * self.p_peak_MPa * self.x_lead_mm) * self.grid_mm)

    def length_mm(self) -> float:
        """Patch length in the rolling direction: 2 max x_l (mm)."""
        return float(2.0 * self.x_lead_mm.max())

    def width_mm(self) -> float:
        """Lateral extent: number of strips times h (mm)."""
        return float(self.n_strips * self.grid_mm)

    def area_mm2(self) -> float:
        """Area of the strips: sum 2 x_l h (mm^2)."""
        return float(np.sum(2.0 * self.x_lead_mm) * self.grid_mm)

    def pressure_MPa(self, x_mm: np.ndarray) -> np.ndarray:
        """Pressure at x (broadcast against the strips: x has shape (..., ny)); zero outside the strip (MPa)."""
        ratio = np.asarray(x_mm, dtype=float) / self.x_lead_mm
        return self.p_peak_MPa * np.sqrt(np.clip(1.0 - ratio * ratio, 0.0, None))

    def grid(self) -> tuple[np.ndarray, np.ndarray]:
        """Square cells for pictures: x centres (nx,) symmetric about 0 and a (ny, nx) mask of cells inside."""
        h = self.grid_mm
        n_half = int(np.ceil(self.x_lead_mm.max() / h))
        x = (np.arange(-n_half, n_half) + 0.5) * h
        mask = np.abs(x)[None, :] < self.x_lead_mm[:, None]
        return x, mask
