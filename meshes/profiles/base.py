"""The piecewise :class:`Profile` z(y) of a rail or wheel running surface, and the profile frames.

Frames (see the project conventions): 2D, z up, lengths in mm.

- rail: y lateral from the head centre line, positive towards the FIELD side, crown at (0, 0),
  material BELOW the curve;
- wheel: y = S (0 at the taping line, positive towards the field side, flange at negative y),
  z = -F(S), material ABOVE the curve.

A :class:`Profile` is a chain of pieces ordered by increasing y; each piece is a function
z(y) (straight line, circular arc or smooth curve) that evaluates its value, slope, second
derivative, curvature, normal and arc length exactly (arcs, lines) or to round-off by
Gauss-Legendre quadrature and Newton's method (smooth curves). Arcs handle their vertical
end points (infinite slope) analytically for everything except ``dz``/``d2z`` (which return
+-inf there).

Pieces: :mod:`meshes.profiles.pieces`. Segments (:class:`Line`, :class:`Arc`, :class:`PointCurve`, in
:mod:`meshes.profiles.segments`) are the exact primitives handed to the mesher; each carries a ``tag`` in
{"surface", "side", "fixed"}. They are re-exported here.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from meshes.profiles.pieces import ArcPiece, Piece, SmoothPiece, line_piece, poly_piece
from meshes.profiles.segments import (TAGS, Arc, Line, PointCurve, Segment, check_closed, outline_area,
                                      reversed_segment, with_ends)
from wrlayer.errors import InputError

# the segment and piece names are re-exported: profile modules and the mesher import them from here
__all__ = ["TAGS", "Arc", "ArcPiece", "Line", "Piece", "PointCurve", "Profile", "Segment", "SmoothPiece",
           "check_closed", "line_piece", "outline_area", "poly_piece", "reversed_segment", "with_ends"]

# Tolerance (mm) for accepting y slightly outside the valid range (round-off) before clipping.
_Y_TOL = 1e-9


class Profile:
    """A rail or wheel running-surface profile z(y) on [y_min, y_max] (mm), made of pieces.

    Attributes: ``name``, ``body`` ("rail" or "wheel"), ``y_min``, ``y_max``. All evaluation
    methods are vectorised (scalars in, scalars out; arrays in, arrays out) and raise
    :class:`InputError` for y outside the valid range.
    """

    def __init__(self, name: str, body: str, pieces: Sequence[Piece]):
        if body not in ("rail", "wheel"):
            raise InputError("body", f"{body!r} is neither 'rail' nor 'wheel'")
        if not pieces:
            raise InputError(name, "a profile needs at least one piece")
        self.name = name
        self.body = body
        self._pieces = list(pieces)
        self.y_min = float(self._pieces[0].ya)
        self.y_max = float(self._pieces[-1].yb)
        self._breaks = np.array([p.yb for p in self._pieces[:-1]])
        self._s_offsets = np.r_[0.0, np.cumsum([p.total_length for p in self._pieces])]

    def __repr__(self) -> str:
        return f"{type(self).__name__}(name={self.name!r}, body={self.body!r}, y=[{self.y_min:g}, {self.y_max:g}] mm)"

    # -- range ---------------------------------------------------------------------------------
    def check_y(self, y, what: str = "y"):
        """Return y as a float array clipped to [y_min, y_max]; InputError if (beyond round-off) outside."""
        y = np.asarray(y, dtype=float)
        if y.size and self.y_min - _Y_TOL <= y.min() and y.max() <= self.y_max + _Y_TOL:   # NaN fails both
            return np.clip(y, self.y_min, self.y_max)
        bad = ~((y >= self.y_min - _Y_TOL) & (y <= self.y_max + _Y_TOL))
        if np.any(bad):
            shown = np.atleast_1d(y[bad])[:3]
            vals = ", ".join(f"{v:.6g}" for v in shown)
            raise InputError(what, f"{vals} mm outside the profile's valid range "
                                   f"[{self.y_min:.6g}, {self.y_max:.6g}] mm ({self.name})")
        return np.clip(y, self.y_min, self.y_max)

    # -- evaluation ----------------------------------------------------------------------------
    def _eval(self, method: str, y, trailing: tuple = ()):
        y = np.asarray(y, dtype=float)
        # one point (a contact search's or a balance's): no array bookkeeping (the same piece and value)
        if y.size == 1:
            v = float(y.reshape(-1)[0])
            if self.y_min - _Y_TOL <= v <= self.y_max + _Y_TOL:
                v = min(max(v, self.y_min), self.y_max)
                piece = self._pieces[int(self._breaks.searchsorted(v))]
                out = getattr(piece, method)(np.array([v])).reshape(y.shape + trailing)
                return out[()] if out.ndim == 0 else out
        y = self.check_y(y)
        k = np.searchsorted(self._breaks, y, side="left")
        out = np.empty(y.shape + trailing)
        flat = k.reshape(-1)
        if flat.size and flat[0] == flat.min() == flat.max():      # all on one piece (most calls: a few points)
            out.reshape((-1,) + trailing)[:] = getattr(self._pieces[int(flat[0])], method)(y.reshape(-1))
            return out[()] if out.ndim == 0 else out
        for i in np.unique(flat):                                  # only the pieces the points fall on
            m = k == i
            out[m] = getattr(self._pieces[int(i)], method)(y[m])
        return out[()] if out.ndim == 0 else out

    def z(self, y):
        """Height z(y) (mm)."""
        return self._eval("z", y)

    def dz(self, y):
        """Slope dz/dy (-); +-inf at a vertical arc end."""
        return self._eval("dz", y)

    def d2z(self, y):
        """Second derivative d2z/dy2 (1/mm)."""
        return self._eval("d2z", y)

    def curvature(self, y):
        """Signed curvature z''/(1+z'^2)^1.5 (1/mm): negative where the curve bends down
        (rail crown: -1/300), positive where it bends up (wheel tread, flange root)."""
        return self._eval("curvature", y)

    def normal(self, y):
        """Unit normal pointing OUT of the material, array (..., 2) of (n_y, n_z)."""
        n = self._eval("up_normal", y, (2,))
        return n if self.body == "rail" else -n

    # -- arc length ----------------------------------------------------------------------------
    @property
    def length(self) -> float:
        """Arc length of the whole profile (mm)."""
        return float(self._s_offsets[-1])

    def arc_length(self, y):
        """Arc length from y_min to y (mm)."""
        y = self.check_y(y)
        k = np.searchsorted(self._breaks, y, side="left")
        out = np.empty(y.shape)
        for i, piece in enumerate(self._pieces):
            m = k == i
            if np.any(m):
                out[m] = self._s_offsets[i] + piece.length(y[m])
        return out[()] if out.ndim == 0 else out

    def y_at_arc_length(self, s):
        """Inverse of :meth:`arc_length`: lateral coordinate y (mm) at arc length s (mm)."""
        s = np.asarray(s, dtype=float)
        total = self.length
        tol = 1e-9 * max(1.0, total)
        if np.any(~((s >= -tol) & (s <= total + tol))):
            raise InputError("s", f"arc length outside [0, {total:.6g}] mm ({self.name})")
        s = np.clip(s, 0.0, total)
        k = np.clip(np.searchsorted(self._s_offsets, s, side="right") - 1, 0, len(self._pieces) - 1)
        out = np.empty(s.shape)
        for i, piece in enumerate(self._pieces):
            m = k == i
            if np.any(m):
                out[m] = piece.y_at(np.clip(s[m] - self._s_offsets[i], 0.0, piece.total_length))
        return out[()] if out.ndim == 0 else out

    def sample(self, ds: float = 0.5):
        """Points (y, z) (mm) at equal arc-length spacing <= ds (mm), both ends included."""
        if not ds > 0:
            raise InputError("ds", f"spacing must be positive, got {ds}")
        n = max(1, int(np.ceil(self.length / ds)))
        y = self.y_at_arc_length(np.linspace(0.0, self.length, n + 1))
        y[0], y[-1] = self.y_min, self.y_max
        return y, self.z(y)

    def signed_distance(self, points):
        """Distance (mm) from points (n, 2) to the profile curve and the foot points' y (mm).

        Returns ``(d, y_foot)``; d > 0 outside the material (in the direction of :meth:`normal`).
        Foot points are clipped to [y_min, y_max] (then d is the distance to the end point, signed
        by the side of the end normal). Newton's method from the nearest point at 0.05 mm spacing.
        """
        q = np.asarray(points, dtype=float).reshape(-1, 2)
        ys, zs = self.sample(0.05)
        k = np.argmin((q[:, None, 0] - ys) ** 2 + (q[:, None, 1] - zs) ** 2, axis=1)
        y = ys[k]
        active = np.ones(len(y), dtype=bool)
        for _ in range(50):
            ya = y[active]
            with np.errstate(invalid="ignore", divide="ignore"):
                z1, z2 = self.dz(ya), self.d2z(ya)
                ry, rz = ya - q[active, 0], self.z(ya) - q[active, 1]
                step = (ry + rz * z1) / (1.0 + z1 * z1 + rz * z2)
            step = np.where(np.isfinite(step), step, 0.0)   # at a vertical arc end: keep the end
            new = np.clip(ya - step, self.y_min, self.y_max)
            moved = np.abs(new - ya)
            y[active] = new
            idx = np.flatnonzero(active)
            active[idx[moved < 1e-12 * (1.0 + np.abs(new))]] = False
            if not np.any(active):
                break
        foot = np.column_stack([y, self.z(y)])
        d = np.hypot(*(q - foot).T)
        sign = np.sign(np.sum((q - foot) * self.normal(y), axis=1))
        return sign * d, y

    # -- meshing primitives --------------------------------------------------------------------
    def surface_segments(self, tag: str = "surface") -> list[Segment]:
        """The running surface from y_min to y_max as exact primitives, ordered by increasing y.

        Neighbouring segments share their end points exactly: at a joint the point of an arc
        (or else of the left piece) is used, so a polynomial or line end moves by at most the
        joint mismatch of the definition (S1002: < 1e-4 mm).
        """
        segs = [p.segment(tag) for p in self._pieces]
        for i in range(len(segs) - 1):
            a, b = segs[i], segs[i + 1]
            joint = b.start if (isinstance(b, Arc) and not isinstance(a, Arc)) else a.end
            segs[i] = with_ends(a, a.start, joint)
            segs[i + 1] = with_ends(b, joint, b.end)
        return segs

    def section_outline(self, depth_mm: float) -> list[Segment]:
        """Closed counter-clockwise loop of a block section under (rail) or over (wheel) the surface.

        The running surface ("surface"), vertical side faces at y_min and y_max ("side") and a
        horizontal cut ("fixed") at z = -depth_mm (rail) or z = +depth_mm (wheel). Subclasses with
        a real cross-section (rail heads) override this.
        """
        surf = self.surface_segments()
        p0, p1 = surf[0].start, surf[-1].end
        z_surf = self.sample(1.0)[1]
        if self.body == "wheel":
            zc, ok, bound = float(depth_mm), float(depth_mm) > np.max(z_surf), f"z = {np.max(z_surf):.4g}"
        else:
            zc, ok, bound = -float(depth_mm), -float(depth_mm) < np.min(z_surf), f"depth {-np.min(z_surf):.4g}"
        if not ok:
            raise InputError("depth_mm", f"{depth_mm} mm must lie beyond the surface's extreme point "
                                         f"({bound} mm) of {self.name}")
        q0, q1 = (p0[0], zc), (p1[0], zc)
        if self.body == "wheel":  # material above: surface left to right, then up, back, down
            return surf + [Line(p1, q1, "side"), Line(q1, q0, "fixed"), Line(q0, p0, "side")]
        top = [reversed_segment(sg) for sg in reversed(surf)]
        return [Line(q0, q1, "fixed"), Line(q1, p1, "side")] + top + [Line(p0, q0, "side")]

    def section_area(self, depth_mm: float) -> float:
        """Area (mm^2) enclosed by :meth:`section_outline` (exact for lines and arcs)."""
        return outline_area(self.section_outline(depth_mm))
