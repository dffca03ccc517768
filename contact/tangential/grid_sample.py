"""The fields of a tangential result (FASTSIM, FaStrip or Kalker's exact theory) on the patch's square picture
grid, for pictures and VTK output (units mm, MPa, W/mm^2, N/mm, mm/s)."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from contact.normal.patch import Patch
from contact.tangential.fastsim import TangentialResult
from wrlayer.errors import require
from wrlayer.short_repr import short_repr


@dataclass(frozen=True)
class GridSample:
    """Fields of a TangentialResult on the patch's square picture grid (:meth:`Patch.grid`).

    x_mm (ng,), mask (ny, ng) of cells inside; tx_MPa, ty_MPa, PT_W_per_mm2, WT_field_N_per_mm,
    slip_velocity_mm_s (ny, ng), NaN outside; slip (ny, ng) bool, False outside.
    """

    x_mm: np.ndarray
    mask: np.ndarray
    tx_MPa: np.ndarray
    ty_MPa: np.ndarray
    slip: np.ndarray
    PT_W_per_mm2: np.ndarray
    WT_field_N_per_mm: np.ndarray
    slip_velocity_mm_s: np.ndarray

    __repr__ = short_repr  # the arrays by their shapes


def sample_on_grid(patch: Patch, result: TangentialResult) -> GridSample:
    """Interpolate the result's fields (linear between its cell centres ``x_mm`` along each row, constant beyond
    the end cells) onto ``patch.grid()``: the strips of FASTSIM and FaStrip and the grid cells of the exact theory
    alike (rows: the patch's strips; columns from the leading edge).

    The slip flag is taken from the nearest cell; use it for the adhesion/slip map.
    """
    require(result.x_mm.shape[0] == patch.n_strips, "result", "does not belong to this patch (strip count differs)")
    xg, mask = patch.grid()
    x = np.asarray(result.x_mm, dtype=float)[:, ::-1]        # increasing along each row
    ny = x.shape[0]

    def lerp(field):
        f = np.asarray(field, dtype=float)[:, ::-1]
        out = np.array([np.interp(xg, x[j], f[j]) for j in range(ny)]).reshape(ny, xg.size)
        return np.where(mask, out, np.nan)

    nearest = np.array([np.abs(x[j][:, None] - xg[None, :]).argmin(axis=0) for j in range(ny)]).reshape(ny, xg.size)
    slip = np.take_along_axis(np.asarray(result.slip)[:, ::-1], nearest, axis=1)
    return GridSample(x_mm=xg, mask=mask, tx_MPa=lerp(result.tx_MPa), ty_MPa=lerp(result.ty_MPa),
                      slip=mask & slip, PT_W_per_mm2=lerp(result.PT_W_per_mm2),
                      WT_field_N_per_mm=lerp(result.WT_field_N_per_mm),
                      slip_velocity_mm_s=lerp(result.slip_velocity_mm_s))


__all__ = ["GridSample", "sample_on_grid"]
