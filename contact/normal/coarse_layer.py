"""The layers' loading curves on the lines of the coarse grid of :mod:`contact.normal.coarse_exact` (indentation).

Units: mm, MPa. Each line carries the element(s) of its nearest strip (wheel + rail + combined in series, as
:class:`contact.normal.layer_at_strip.LayerAtReference`), loaded monotonically from the current state; strips whose
elements are in the same state share one curve. :meth:`LineLayers.linearise` gives each cell's displacement and the
compliance of the segment its pressure lies on (paper eq. 7), the outer iteration's linearisation.
"""

from __future__ import annotations

import numpy as np

from contact.layer.prandtl_layer import LayerPair
from contact.normal.layer_at_strip import LayerAtReference, layer_points
from contact.normal.problem import NormalProblem
from wrlayer.errors import InputError
from wrlayer.jit import kernel

__all__ = ["LineLayers"]


#: The loading curves of element states met so far, by the states' numbers (a balance's solves of one patch meet
#: the same states: each solve would otherwise build them again); the oldest go first beyond this many.
MAX_CACHED_CURVES = 512
_CURVES: dict[bytes, LayerAtReference] = {}


class LineLayers:
    """The layers' loading curves (from their current state) at the strip nearest each line, linearised per cell."""

    def __init__(self, layer: LayerPair | None, prob: NormalProblem):
        self.bodies = []
        if layer is not None:
            for lay in layer.bodies().values():
                if np.any(np.abs(lay.pressure_MPa) > 1e-9 * max(1.0, float(np.abs(lay.pressure_MPa).max()))):
                    raise InputError(lay.name, "layer must be unloaded (p = 0) before a normal solve")
                self.bodies.append((lay, layer_points(lay, prob.strip_y_mm, prob.grid_mm)))
        self.ys = prob.strip_y_mm
        self.h = prob.grid_mm
        self._curves: dict[int, LayerAtReference | None] = {}

    @property
    def present(self) -> bool:
        return bool(self.bodies)

    def _curve(self, strip: int) -> LayerAtReference | None:
        """The loading curve at a strip (None where a body's layer has no point there)."""
        if strip not in self._curves:
            self._add_curves(np.array([strip]))
        return self._curves[strip]

    def _add_curves(self, strips: np.ndarray) -> None:
        """The loading curves of ``strips`` not yet known; strips whose elements are in the same state share one
        (a virgin uniform layer has one curve): the states compared as one row of numbers per strip, at once."""
        todo = np.array(sorted({int(j) for j in strips} - self._curves.keys()), dtype=int)
        if todo.size == 0:
            return
        ix = np.stack([idx[todo] for _, idx in self.bodies])           # (bodies, strips)
        covered = np.all(ix >= 0, axis=0)
        for j in todo[~covered]:
            self._curves[int(j)] = None
        todo, ix = todo[covered], ix[:, covered]
        if todo.size == 0:
            return
        rows = np.hstack([np.column_stack([lay.k_N_per_mm3[i], lay.half_width_mm[i], lay.u_mm[i], lay.slip_mm[i],
                                           lay.k_last_N_per_mm3[i], lay.reverse_factor[i]])
                          for (lay, _), i in zip(self.bodies, ix)])
        same = bool(np.all(rows == rows[0]))          # a uniform state (a virgin layer): one key for all
        head = np.array([lay.k_N_per_mm3.shape[1] for lay, _ in self.bodies], dtype=float).tobytes()
        for k, j in enumerate(todo):
            key = head + rows[0 if same else k].tobytes()    # the bodies' slider counts, then their states
            if key not in _CURVES:
                if len(_CURVES) >= MAX_CACHED_CURVES:
                    _CURVES.pop(next(iter(_CURVES)))
                _CURVES[key] = LayerAtReference([(lay, int(i[k])) for (lay, _), i in zip(self.bodies, ix)])
            self._curves[int(j)] = _CURVES[key]

    def strips(self, y: np.ndarray) -> np.ndarray:
        return np.clip(np.rint((y - self.ys[0]) / self.h).astype(int), 0, self.ys.size - 1)

    @staticmethod
    def _arrays(cur: LayerAtReference) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """(knots, displacements, compliance of the segment from each knot on; the last: beyond it) of a curve."""
        if cur.segments is None:
            dp = np.diff(cur.p)
            slope = np.append(np.where(dp > 0, np.diff(cur.u) / np.where(dp > 0, dp, 1.0), 0.0),
                              cur.final_compliance)
            cur.segments = (cur.p, cur.u, slope)
        return cur.segments

    def on_lines(self, y: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Knots (ny, K) of the loading curves at the lines y (padded with +inf), the displacement there and the
        compliance of the segment from each knot on (mm/MPa; the last: beyond the last knot); a line without a
        curve has the knot 0 only and compliance 0."""
        strips = self.strips(y)
        self._add_curves(strips)
        curves = [self._curves[int(j)] for j in strips]
        size = max((c.p.size for c in curves if c is not None), default=1)
        knots = np.full((y.size, size), np.inf)
        disp = np.zeros((y.size, size))
        slope = np.zeros((y.size, size))
        for k, cur in enumerate(curves):
            if cur is None:
                knots[k, 0] = 0.0
                continue
            m = cur.p.size
            knots[k, :m], disp[k, :m], slope[k, :m] = self._arrays(cur)
        return knots, disp, slope

    @staticmethod
    def linearise(p: np.ndarray, curves) -> tuple[np.ndarray, np.ndarray]:
        """(u_L (mm), c (mm/MPa)) of each cell (ny, nx) at the pressure p: the displacement on the line's loading
        curve (:meth:`on_lines`) and the compliance of the segment p lies on (the segment above at a knot)."""
        knots, disp, slope = curves
        return _linearised(np.ascontiguousarray(p, dtype=float), knots, disp, slope)

    def check_coverage(self, p: np.ndarray, y: np.ndarray) -> None:
        """InputError when a loaded line (p (ny, nx) at the lines y) has no layer element at its strip."""
        if not self.present:
            return
        loaded = self.strips(y)[p.max(axis=1) > 0]
        self._add_curves(loaded)
        for j in np.unique(loaded):
            if self._curves[int(j)] is None:
                raise InputError("layer", f"has no element at strip y = {self.ys[j]:.6g} mm (contact there): the "
                                 "layer does not cover the contact patch")


@kernel()
def _linearised(p, knots, disp, slope):
    """u_L and c of every cell: the segment of the cell's line whose knot is the last one <= p (paper eq. 7)."""
    ny, nx = p.shape
    u = np.empty((ny, nx))
    c = np.empty((ny, nx))
    for r in range(ny):
        for i in range(nx):
            seg = -1
            for m in range(knots.shape[1]):
                if p[r, i] >= knots[r, m]:
                    seg += 1
            c[r, i] = slope[r, seg]
            u[r, i] = disp[r, seg] + slope[r, seg] * (p[r, i] - knots[r, seg])
    return u, c
