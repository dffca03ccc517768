"""A Hertzian pressure on the cells of a uniform grid (shared by the tangential tests and the benchmark)."""

import numpy as np

from contact.tangential.method import PressureGrid


def hertz_grid(a_mm: float, b_mm: float, n: int, p0_MPa: float = 1000.0, margin: int = 2,
               ny: int | None = None) -> PressureGrid:
    """p0 sqrt(1 - x^2/a^2 - y^2/b^2) at the centres of n (x) by ny (y, default n) cells over the ellipse's
    bounding box (cell edges on the axes; n, ny even), plus ``margin`` free cells each side."""
    ny = n if ny is None else ny
    dx, dy = 2.0 * a_mm / n, 2.0 * b_mm / ny
    x = (np.arange(-(n // 2 + margin), n // 2 + margin) + 0.5) * dx
    y = (np.arange(-(ny // 2 + margin), ny // 2 + margin) + 0.5) * dy
    X, Y = np.meshgrid(x, y)
    return PressureGrid(x, y, p0_MPa * np.sqrt(np.clip(1.0 - (X / a_mm) ** 2 - (Y / b_mm) ** 2, 0.0, None)))


def effective_axes(grid: PressureGrid, a_mm: float, b_mm: float) -> tuple[float, float]:
    """Semi-axes of the ellipse of the loaded cells' area and the ratio a/b (mm)."""
    ratio = np.count_nonzero(grid.p_MPa > 0) * grid.dx_mm * grid.dy_mm / (np.pi * a_mm * b_mm)
    return a_mm * np.sqrt(ratio), b_mm * np.sqrt(ratio)
