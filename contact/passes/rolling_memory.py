"""The "rolling" memory rule of the passes: residual increments from the layer table's rolling law (mm, MPa).

A pass loads a virgin element to its strip's peak pressure p and unloads it; its static (Masing) residual r(p)
(paper eq. 8) is what the "relaxed" rule adds every pass. Under the rolling rule each element carries its
accumulated rolling residual U and the pass adds ``law.next_residual(U, r, p / p_2, c) - U``
(:class:`wrlayer.rolling_law.RollingLaw`: the first-pass groove over the static dent and the per-pass increment
law calibrated by the rolling FEM, docs/rolling.md), p_2 being the element's elastic limit (its first slider
threshold), c the traction coefficient of the passes and, for a law with patch-shape nodes, a/b the shape of the
pass's contact region that loads the element (:func:`patch_shape`), for a law with convexity nodes also the
surface convexity b / (2 R) there (b the region's lateral semi-axis, 1/R the layer's lateral curvature at the
element: the table's, :meth:`wrlayer.layer_table.LayerTable.lateral_curvature_at`). The layer itself is relaxed before
each pass (the residual is moved into the profile, as in the "relaxed" rule), so the normal solve sees the virgin
element.
"""

from __future__ import annotations

import numpy as np

from contact.layer.prandtl_layer import PrandtlLayer

__all__ = ["MEMORY_RULES", "RollingMemory", "patch_aspect_ratios", "patch_semi_axes", "patch_shape"]

#: The memory rules of the passes (``PassesOptions.memory``): "rolling" (the rolling law; a layer without one
#: falls back to "relaxed"), "relaxed" (the paper's model: a virgin element each pass) and "state_kept" (the
#: sliders keep their slip between passes).
MEMORY_RULES = ("rolling", "relaxed", "state_kept")


class RollingMemory:
    """The accumulated rolling residual of one body's layer points (mm). ``layer``: the body's layer (its rolling
    law and elastic limits are read; it is not modified); ``traction_coefficient``: c of the law (-)."""

    def __init__(self, layer: PrandtlLayer, traction_coefficient: float):
        if layer.rolling_law is None:
            raise ValueError(f"{layer.name} has no rolling law")
        self.law = layer.rolling_law
        self.p2_MPa = layer.relaxed().yield_pressure_MPa()
        self.curvature_per_mm = layer.lateral_curvature_per_mm
        self.c = float(traction_coefficient)
        self.accumulated_mm = np.zeros(layer.n_points)

    def advance(self, p_peak_MPa: np.ndarray, static_residual_mm: np.ndarray,
                aspect_ratio: np.ndarray | None = None, half_width_mm: np.ndarray | None = None) -> np.ndarray:
        """One pass at the points' peak pressures (MPa) with their static residuals r(p) (mm) on contact regions
        of shape a/b ``aspect_ratio`` (-, per point; used by a law with patch-shape nodes) and lateral semi-axis
        ``half_width_mm`` b (mm, per point; with the layer's curvature the convexity b / (2 R) of a law with
        convexity nodes; None: a flat surface): the residual added by the pass (mm, per point)."""
        x = np.divide(p_peak_MPa, self.p2_MPa, out=np.zeros(self.p2_MPa.shape), where=np.isfinite(self.p2_MPa))
        aspect = np.ones_like(x) if aspect_ratio is None else aspect_ratio
        convexity = (np.zeros_like(x) if half_width_mm is None
                     else 0.5 * np.asarray(half_width_mm, dtype=float) * self.curvature_per_mm)
        new = self.law.next_residual(self.accumulated_mm, np.maximum(static_residual_mm, 0.0), x, self.c, aspect,
                                     convexity)
        added = new - self.accumulated_mm
        self.accumulated_mm = new
        return added


def patch_semi_axes(sol, strip_width_mm: float) -> tuple[np.ndarray, np.ndarray]:
    """(a, b) of the contact region each strip of ``sol`` (a :class:`contact.normal.solution.NormalSolution`)
    belongs to (mm, per strip of the problem's grid; 0 on the strips out of contact): a the region's largest
    half-length along the rolling direction (its strips' leading edges), b half its lateral extent (its strips
    times ``strip_width_mm``)."""
    a = np.zeros(np.asarray(sol.p_peak_MPa).size)
    b = np.zeros_like(a)
    for region in sol.regions:
        strips = np.asarray(region.strips)
        if strips.size:
            a[strips] = float(np.max(region.x_lead_mm))
            b[strips] = 0.5 * strips.size * strip_width_mm
    return a, b


def patch_shape(sol, strip_width_mm: float) -> tuple[np.ndarray, np.ndarray]:
    """(a/b, b) of the contact region each strip of ``sol`` belongs to (-, mm; per strip; a/b = 1 and b = 0 on the
    strips out of contact; :func:`patch_semi_axes`): what a rolling law with patch-shape and convexity nodes reads."""
    a, b = patch_semi_axes(sol, strip_width_mm)
    return np.divide(a, b, out=np.ones_like(a), where=b > 0), b


def patch_aspect_ratios(sol, strip_width_mm: float) -> np.ndarray:
    """a/b of the contact region each strip of ``sol`` belongs to (-, per strip; 1 on the strips out of contact;
    :func:`patch_shape`)."""
    return patch_shape(sol, strip_width_mm)[0]
