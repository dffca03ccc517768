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

__all__ = ["LineLayers"]


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
        self._states: dict[tuple, LayerAtReference] = {}
        self._segments: dict[int, tuple] = {}

    @property
    def present(self) -> bool:
        return bool(self.bodies)

    def _curve(self, strip: int) -> LayerAtReference | None:
        """The loading curve at a strip; strips whose elements are in the same state share it (a virgin uniform
        layer has one curve)."""
        if strip not in self._curves:
            pts = [(lay, int(ix[strip])) for lay, ix in self.bodies]
            if any(i < 0 for _, i in pts):
                self._curves[strip] = None
            else:
                key = tuple(a[i].tobytes() for lay, i in pts for a in (lay.k_N_per_mm3, lay.half_width_mm, lay.u_mm,
                                                                        lay.slip_mm, lay.k_last_N_per_mm3))
                if key not in self._states:
                    self._states[key] = LayerAtReference(pts)
                self._curves[strip] = self._states[key]
        return self._curves[strip]

    def strips(self, y: np.ndarray) -> np.ndarray:
        return np.clip(np.rint((y - self.ys[0]) / self.h).astype(int), 0, self.ys.size - 1)

    def _arrays(self, cur: LayerAtReference) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """(knots, displacements, compliance of the segment from each knot on; the last: beyond it) of a curve."""
        if id(cur) not in self._segments:
            dp = np.diff(cur.p)
            slope = np.append(np.where(dp > 0, np.diff(cur.u) / np.where(dp > 0, dp, 1.0), 0.0),
                              cur.final_compliance)
            self._segments[id(cur)] = (cur.p, cur.u, slope)
        return self._segments[id(cur)]

    def on_lines(self, y: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Knots (ny, K) of the loading curves at the lines y (padded with +inf), the displacement there and the
        compliance of the segment from each knot on (mm/MPa; the last: beyond the last knot); a line without a
        curve has the knot 0 only and compliance 0."""
        curves = [self._curve(int(j)) for j in self.strips(y)]
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
        seg = np.sum(p[:, :, None] >= knots[:, None, :], axis=2) - 1           # 0..K-1
        rows = np.arange(p.shape[0])[:, None]
        c = slope[rows, seg]
        return disp[rows, seg] + c * (p - knots[rows, seg]), c

    def check_coverage(self, p: np.ndarray, y: np.ndarray) -> None:
        """InputError when a loaded line (p (ny, nx) at the lines y) has no layer element at its strip."""
        if not self.present:
            return
        for k, j in enumerate(self.strips(y)):
            if np.any(p[k] > 0) and self._curve(int(j)) is None:
                raise InputError("layer", f"has no element at strip y = {self.ys[j]:.6g} mm (contact there): the "
                                 "layer does not cover the contact patch")
