"""The layers at one strip of the normal problem's grid: which layer point sits there and its loading curve u(p).

u_layer(p_0) of eq. 13 is the displacement of the layer element(s) at the reference point loaded from their
current state to p_0: wheel + rail (+ combined) in series. It is piecewise linear in p_0, so the contact condition
delta = u_layer(p_0) + c p_0 is solved EXACTLY by locating its segment (the paper's "iteration on the layer
stiffness", done in one step; the secant stiffness k = p_0/u_layer of eqs. 13/14 follows). Units: mm, MPa.
"""

from __future__ import annotations

import numpy as np

from contact.layer.prandtl_layer import PrandtlLayer

__all__ = ["LayerAtReference", "layer_points"]


def layer_points(layer: PrandtlLayer, y_grid: np.ndarray, h: float) -> np.ndarray:
    """Index of the layer point at each strip centre y_grid (mm), -1 where the layer has no point there."""
    idx = np.searchsorted(layer.y_mm, y_grid - 0.25 * h)
    ok = (idx < layer.n_points)
    ok[ok] = np.abs(layer.y_mm[idx[ok]] - y_grid[ok]) < 0.25 * h
    return np.where(ok, idx, -1)


class LayerAtReference:
    """Piecewise-linear loading curve u(p) of all layers at one strip, from their current state (p = 0)."""

    def __init__(self, layers: list[tuple[PrandtlLayer, int]]):
        curves = [lay.loading_curve(i) for lay, i in layers]
        knots = np.unique(np.concatenate([c[0] for c in curves] + [[0.0]]))
        self.p = knots[knots >= 0.0]
        self.u = np.zeros_like(self.p)
        self.final_compliance = 0.0
        self.segments = None   # the coarse solver's (knots, u, compliance per segment), built on first use
        for pk, uk, kl in curves:
            u = np.interp(self.p, pk, uk)                   # the curve is piecewise linear through its knots
            beyond = self.p > pk[-1]
            u[beyond] = uk[-1] + (self.p[beyond] - pk[-1]) / kl
            self.u += u - uk[0]
            self.final_compliance += 1.0 / kl

    def solve(self, delta: float, c: float) -> tuple[float, float, int]:
        """p_0 with u(p_0) + c p_0 = delta (exact): (p_0, u(p_0), segment number 1..)."""
        h = self.u + c * self.p - delta
        j = int(np.searchsorted(h, 0.0))                    # first knot with h >= 0 (h strictly increasing)
        if j == 0:
            return 0.0, 0.0, 1
        if j >= self.p.size:
            p0 = self.p[-1] - h[-1] / (self.final_compliance + c)
            return float(p0), float(self.u[-1] + (p0 - self.p[-1]) * self.final_compliance), int(self.p.size)
        t = -h[j - 1] / (h[j] - h[j - 1])
        p0 = self.p[j - 1] + t * (self.p[j] - self.p[j - 1])
        return float(p0), float(self.u[j - 1] + t * (self.u[j] - self.u[j - 1])), j
