"""The residual groove on a profile section (:mod:`calibration.rolling.section_track`): the displacement along the
inward normal left by the load, relative to the clamped support (units mm).

Depths are positive INTO the body, d = -u . n(y) (n the profile's outward normal at the point), at surface points
(x, y) (the engine's load-centre probes, :func:`calibration.rolling.section_track.point_probes`). The reference
is the support (the section's clamped far cut and, for a rail, the clamped sides below z = -35 mm; u = 0 there),
as the calibration's dents are. ``groove_mm``: the mean of d along the track centreline (y = y0, at the x grid
lines) over |x| <= a/2; across the track: d at mid-track x = 0, y0 - 1.5 b .. y0 + 1.5 b (21 points along y);
``shift_mm``: the mean u_x at the centreline points over |x| <= a/2; ``max_eq_plastic_strain``: below |x| <= a.
The same :class:`~calibration.rolling.groove.GrooveProfile` as the block's, its ``y_mm`` the profile coordinates.
"""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp

from calibration.fem.assembly import Discretisation
from calibration.fem.solver_state import SolverState
from calibration.rolling.groove import GrooveProfile
from calibration.rolling.section_track import normal_probe, point_probes

#: Points across the track at mid-track, over y0 +- ACROSS_HALF_WIDTH b.
ACROSS_POINTS = 21
ACROSS_HALF_WIDTH = 1.5


class SectionProbe:
    """The groove probes of a section track mesh: ``x_mm`` its x grid lines, the profile and y0 (mm), the
    semi-axes a and b (mm); the same interface as :class:`calibration.rolling.groove.SurfaceProbe`."""

    def __init__(self, disc: Discretisation, profile, y0_mm: float, a_mm: float, b_mm: float, x_mm: np.ndarray):
        self.a = a_mm
        tol = 1e-9 * float(np.ptp(x_mm))
        self.x = np.asarray(x_mm, dtype=float)
        self.along = normal_probe(disc, profile, self.x, np.full(self.x.size, float(y0_mm)))
        y = float(y0_mm) + ACROSS_HALF_WIDTH * b_mm * np.linspace(-1.0, 1.0, ACROSS_POINTS)
        self.y = y[(y >= profile.y_min) & (y <= profile.y_max)]
        self.across = normal_probe(disc, profile, np.zeros(self.y.size), self.y)
        self.window = np.nonzero(np.abs(self.x) <= 0.5 * a_mm + tol)[0]
        self.shift = sp.vstack([P[0] for P in point_probes(disc, profile, self.x[self.window],
                                                           np.full(self.window.size, float(y0_mm)))]).tocsr()
        self.below = np.abs(disc.qp_coordinates()[0]) <= a_mm + tol

    def far_field(self, u: np.ndarray) -> float:
        """The reference's displacement: 0 (the clamped support)."""
        return 0.0

    def depth_at(self, u: np.ndarray, x_mm: float) -> float:
        """Depth (mm) at the centreline point nearest x (mm)."""
        k = int(np.argmin(np.abs(self.x - x_mm)))
        return float((self.along[k] @ u)[0])

    def profile(self, state: SolverState) -> GrooveProfile:
        """The :class:`GrooveProfile` of a residual state."""
        u = state.u_mm
        along = self.along @ u
        eq = state.eq_plastic_strain[self.below]
        return GrooveProfile(self.x.tolist(), along.tolist(), self.y.tolist(), (self.across @ u).tolist(),
                             float(np.mean(along[self.window])), float(np.mean(self.shift @ u)),
                             float(eq.max()) if eq.size else 0.0)


__all__ = ["ACROSS_HALF_WIDTH", "ACROSS_POINTS", "SectionProbe"]
