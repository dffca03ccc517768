"""A profile given by points: interpolating cubic spline z(y) (scipy ``make_interp_spline``, k=3,
not-a-knot ends), for measured or exported (SIMPACK, text) profiles. Lengths in mm."""

from __future__ import annotations

import numpy as np
from scipy.interpolate import make_interp_spline

from wrlayer.errors import InputError
from meshes.profiles.base import Profile
from meshes.profiles.pieces import SmoothPiece
from meshes.profiles.segments import Segment


class SplineProfile(Profile):
    """Smooth C2 profile through points (y, z) (mm) with strictly increasing y.

    ``body`` is "rail" (material below) or "wheel" (material above). The input points are kept
    in ``points`` (array (n, 2)). ``surface_segments()`` is one :class:`PointCurve`.
    """

    def __init__(self, y, z, name: str = "spline", body: str = "rail", what: str | None = None):
        what = what or name
        y = np.asarray(y, dtype=float).ravel()
        z = np.asarray(z, dtype=float).ravel()
        if y.shape != z.shape:
            raise InputError(what, f"y and z differ in length ({y.size} vs {z.size})")
        if y.size < 4:
            raise InputError(what, f"need at least 4 points for a cubic spline, got {y.size}")
        if not (np.all(np.isfinite(y)) and np.all(np.isfinite(z))):
            raise InputError(what, "points contain NaN or infinite values")
        dy = np.diff(y)
        if np.any(dy <= 0):
            i = int(np.argmax(dy <= 0))
            raise InputError(what, f"y must be strictly increasing, but point {i + 2} (y = {y[i + 1]:.6g} mm) "
                                   f"follows y = {y[i]:.6g} mm")
        self.points = np.column_stack([y, z])
        spl = make_interp_spline(y, z, k=3)
        d1, d2 = spl.derivative(1), spl.derivative(2)
        piece = SmoothPiece(float(y[0]), float(y[-1]), spl, d1, d2, knots=tuple(y), max_sub=1.0)
        super().__init__(name, body, [piece])
        self.spline = spl

    def surface_segments(self, tag: str = "surface") -> list[Segment]:
        """One :class:`PointCurve` through points of the spline at arc-length spacing <= 0.1 mm."""
        return super().surface_segments(tag)
