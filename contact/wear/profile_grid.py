"""Profile update grid: depths deposited on a profile by arc length, smoothed, and applied along the normal
(units mm).

A profile (rail or wheel, :mod:`meshes.profiles`) is sampled at nodes equally spaced in arc length ``ds``. Node i
owns the cell [s_i - ds/2, s_i + ds/2] (half cells at the ends). A strip of a contact patch (profile coordinate y,
width h in the contact plane, taken as h of arc length) carries a depth d: it is deposited CONSERVATIVELY, i.e.
the node depth is the cell average of the piecewise-constant strip depths, so that sum(depth * cell width) equals
sum(d * h) exactly (the mass balance of the wear loop). The smoothing filter is a Gaussian of standard deviation
``smoothing_mm`` (arc length) applied to the node depths (scipy.ndimage.gaussian_filter1d, zero outside the
profile), which keeps the integral except for what spreads past the profile's ends.

The update moves node i by -depth_i along the outward normal (into the material) and builds a new
:class:`meshes.profiles.SplineProfile` through the moved nodes. A depth that makes y non-monotone (a profile that
folds over itself, e.g. at the steep flange) is refused with an InputError naming the step: a profile z(y) with
strictly increasing y cannot self-intersect, so monotonicity is the check.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy.ndimage import gaussian_filter1d

from meshes.profiles import Profile, SplineProfile
from wrlayer.errors import InputError
from wrlayer.short_repr import short_repr


@dataclass(frozen=True)
class ArcGrid:
    """Nodes of a profile at equal arc length: s (n,), y, z, outward normal (n, 2), cell widths (n,) (mm)."""

    profile: Profile
    s_mm: np.ndarray
    y_mm: np.ndarray
    z_mm: np.ndarray
    normal: np.ndarray
    cell_mm: np.ndarray

    __repr__ = short_repr  # the nodes by their shapes

    @classmethod
    def of(cls, profile: Profile, ds_mm: float) -> ArcGrid:
        n = max(4, int(np.ceil(profile.length / ds_mm)) + 1)
        s = np.linspace(0.0, profile.length, n)
        y = profile.y_at_arc_length(s)
        y[0], y[-1] = profile.y_min, profile.y_max
        edges = np.concatenate([[0.0], 0.5 * (s[1:] + s[:-1]), [profile.length]])
        return cls(profile, s, y, profile.z(y), np.asarray(profile.normal(y)), np.diff(edges))

    @property
    def edges_mm(self) -> np.ndarray:
        return np.concatenate([[0.0], np.cumsum(self.cell_mm)])

    def arc_of(self, y_mm: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Arc length of profile coordinates y (clipped into the profile) and a mask of those inside it."""
        y = np.asarray(y_mm, float)
        inside = (y >= self.profile.y_min) & (y <= self.profile.y_max)
        return np.asarray(self.profile.arc_length(np.clip(y, self.profile.y_min, self.profile.y_max))), inside

    def deposit(self, y_strip_mm: np.ndarray, depth_mm: np.ndarray, width_mm: float) -> np.ndarray:
        """Node depths (n,) of strips (profile coordinate, depth, common width) by cell averages (conservative).

        A strip with non-zero depth outside the profile's range is an InputError (its material would be lost)."""
        d = np.asarray(depth_mm, float)
        keep = d != 0
        if not np.any(keep):
            return np.zeros_like(self.s_mm)
        s, inside = self.arc_of(np.asarray(y_strip_mm, float)[keep])
        if not np.all(inside):
            bad = np.asarray(y_strip_mm, float)[keep][~inside]
            raise InputError(f"{self.profile.name}", f"wear or inelastic depth at y = {bad.min():.4g}..{bad.max():.4g}"
                             f" mm, outside the profile ({self.profile.y_min:.4g}..{self.profile.y_max:.4g} mm)")
        a = s - 0.5 * width_mm
        e = self.edges_mm
        # integral of the piecewise-constant strip depths from 0 to each edge
        F = (np.clip(e[:, None] - a[None, :], 0.0, width_mm) * d[keep][None, :]).sum(axis=1)
        return np.diff(F) / self.cell_mm

    def smooth(self, depth_mm: np.ndarray, sigma_mm: float) -> np.ndarray:
        """Gaussian filter of standard deviation ``sigma_mm`` (arc length); 0 = no smoothing."""
        if sigma_mm <= 0:
            return np.asarray(depth_mm, float).copy()
        ds = float(self.s_mm[1] - self.s_mm[0])
        return gaussian_filter1d(np.asarray(depth_mm, float), sigma_mm / ds, mode="constant", cval=0.0, truncate=5.0)

    def area_mm2(self, depth_mm: np.ndarray) -> float:
        """Integral of a node depth over the arc length (mm^2)."""
        return float(np.sum(np.asarray(depth_mm, float) * self.cell_mm))

    def moved_points(self, depth_mm: np.ndarray) -> np.ndarray:
        """Nodes moved by -depth along the outward normal (into the material), (n, 2)."""
        d = np.asarray(depth_mm, float)
        return np.column_stack([self.y_mm, self.z_mm]) - d[:, None] * self.normal

    def updated(self, depth_mm: np.ndarray, name: str, what: str) -> SplineProfile:
        """The profile after removing ``depth_mm`` (mm, along the normal); InputError ``what`` if it folds."""
        pts = self.moved_points(depth_mm)
        dy = np.diff(pts[:, 0])
        if np.any(dy <= 0):
            i = int(np.argmax(dy <= 0))
            raise InputError(what, f"the updated {self.profile.body} profile becomes non-monotone (folds over itself) "
                             f"at y = {pts[i, 0]:.4g} mm: the depth change {np.max(np.abs(depth_mm)):.4g} mm is too "
                             "large for the grid there (lower max_depth_per_step_mm or raise smoothing_mm)")
        return SplineProfile(pts[:, 0], pts[:, 1], name=name, body=self.profile.body, what=what)


__all__ = ["ArcGrid"]
