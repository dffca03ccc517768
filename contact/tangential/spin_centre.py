"""The point the spin acts about: creepages, moments and FASTSIM's spin centre for patches off a frame's origin.

Units: mm, N, MPa. Creepages of a scene are given about the scene's origin (x = 0, y = 0): the rigid slip / V is
w(x, y) = (vx - phi y, vy + phi x) there, so a patch whose frame has its origin at (x_P, y_P) sees the creepages
(vx - phi y_P, vy + phi x_P) and the same spin (:meth:`contact.tangential.fastsim.Creepage.about`). Moments of
several patches add only about one point (:func:`moment_about`). FASTSIM's result depends on the spin centre (see
:func:`solve_about_centroid`); FaStrip's and the exact theory's do not.
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np

from contact.normal.patch import Patch
from contact.tangential.fastsim import Creepage, TangentialResult, solve_tangential

__all__ = ["force_centroid_mm", "moment_about", "solve_about_centroid"]


def moment_about(Mz_Nmm: float, Fx_N: float, Fy_N: float, x_mm: float = 0.0, y_mm: float = 0.0) -> float:
    """Mz (N mm) about the origin of the frame in which the point (x_mm, y_mm) lies, from the moment Mz_Nmm about
    that point and the forces Fx_N, Fy_N applied there: Mz + x Fy - y Fx. Sum patches' moments only after this."""
    return float(Mz_Nmm + x_mm * Fy_N - y_mm * Fx_N)


def force_centroid_mm(patch: Patch, pressure_cells_MPa: np.ndarray | None = None) -> float:
    """y (mm) of the patch's normal-force centroid: strip forces (semi-elliptic, eq. 12, or the sums of the given
    cell pressures) weighting the strip centres. A centroid within 1e-9 h of the origin is the origin (a symmetric
    patch keeps its numbers to the bit)."""
    if pressure_cells_MPa is None:
        force = patch.p_peak_MPa * patch.x_lead_mm
    else:
        force = np.asarray(pressure_cells_MPa, dtype=float).sum(axis=1) * patch.x_lead_mm
    yc = float(np.sum(force * patch.y_mm) / np.sum(force))
    return 0.0 if abs(yc) <= 1e-9 * patch.grid_mm else yc


def solve_about_centroid(patch: Patch, creepage: Creepage, G_MPa: float, poisson: float, friction: float,
                         speed_mm_s: float = 1000.0, nx: int = 60, **options) -> TangentialResult:
    """FASTSIM with the spin about the patch's force centroid, for a patch and creepages given in one frame
    (strip y and creepages about that frame's origin, e.g. a scene's).

    FASTSIM's three flexibilities scale the spin's longitudinal slip -phi y by 1/L3 but a longitudinal creepage by
    1/L1, so its forces depend on the point the spin is taken about; Kalker's theory takes it about the contact's
    centre. This solves on the patch shifted to its centroid y_c (:func:`force_centroid_mm`) with the creepages
    moved there (:meth:`Creepage.about`) and returns the result in the given frame: strip y unchanged, Mz about
    the frame's origin (:func:`moment_about`). ``options``: as :func:`solve_tangential` (flexibility,
    pressure_cells_MPa, strip_centre_mm).
    """
    yc = force_centroid_mm(patch, options.get("pressure_cells_MPa"))
    local = patch if yc == 0.0 else Patch(patch.grid_mm, patch.y_mm - yc, patch.x_lead_mm, patch.p_peak_MPa)
    r = solve_tangential(local, creepage.about(0.0, yc), G_MPa, poisson, friction, speed_mm_s, nx, **options)
    if yc == 0.0:
        return r
    return replace(r, y_mm=patch.y_mm, Mz_Nmm=moment_about(r.Mz_Nmm, r.Fx_N, r.Fy_N, 0.0, yc))
