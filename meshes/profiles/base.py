"""Profile geometry base: exact segment primitives, curve pieces, and the piecewise :class:`Profile`.

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

Segments (:class:`Line`, :class:`Arc`, :class:`PointCurve`) are the exact primitives handed to the
mesher; each carries a ``tag`` in {"surface", "side", "fixed"}.
"""

from __future__ import annotations

import dataclasses
import itertools
from collections.abc import Callable, Sequence
from dataclasses import dataclass

import numpy as np
from scipy.interpolate import CubicSpline

from wrlayer.errors import InputError

TAGS = ("surface", "side", "fixed")

# Gauss-Legendre rule used for arc lengths of smooth pieces (exact for polynomials of degree 15).
_GL_X, _GL_W = np.polynomial.legendre.leggauss(8)
# Tolerance (mm) for accepting y slightly outside the valid range (round-off) before clipping.
_Y_TOL = 1e-9


# --------------------------------------------------------------------------------------------
# Segment primitives (for meshing)
# --------------------------------------------------------------------------------------------
def _check_tag(tag: str) -> None:
    if tag not in TAGS:
        raise InputError("tag", f"{tag!r} is not one of {TAGS}")


@dataclass(frozen=True)
class Line:
    """Straight segment from ``start`` to ``end``; points are (y, z) in mm."""

    start: tuple[float, float]
    end: tuple[float, float]
    tag: str = "surface"

    def __post_init__(self):
        _check_tag(self.tag)


@dataclass(frozen=True)
class Arc:
    """Circular arc of less than 180 degrees from ``start`` to ``end`` about ``centre`` ((y, z), mm)."""

    start: tuple[float, float]
    end: tuple[float, float]
    centre: tuple[float, float]
    tag: str = "surface"

    def __post_init__(self):
        _check_tag(self.tag)

    @property
    def radius(self) -> float:
        """Radius (mm), measured from the centre to the start point."""
        return float(np.hypot(self.start[0] - self.centre[0], self.start[1] - self.centre[1]))

    def sweep(self) -> float:
        """Signed angle (rad) from start to end, in (-pi, pi); positive = counter-clockwise."""
        a0 = np.arctan2(self.start[1] - self.centre[1], self.start[0] - self.centre[0])
        a1 = np.arctan2(self.end[1] - self.centre[1], self.end[0] - self.centre[0])
        return float((a1 - a0 + np.pi) % (2 * np.pi) - np.pi)


@dataclass(frozen=True, eq=False)
class PointCurve:
    """Smooth curve through dense points (array (n, 2) of (y, z), mm), e.g. for a spline in Gmsh."""

    points: np.ndarray
    tag: str = "surface"

    def __post_init__(self):
        _check_tag(self.tag)
        pts = np.asarray(self.points, dtype=float)
        if pts.ndim != 2 or pts.shape[1] != 2 or len(pts) < 2:
            raise InputError("points", f"need an (n >= 2, 2) array, got shape {pts.shape}")
        object.__setattr__(self, "points", pts)

    @property
    def start(self) -> tuple[float, float]:
        return (float(self.points[0, 0]), float(self.points[0, 1]))

    @property
    def end(self) -> tuple[float, float]:
        return (float(self.points[-1, 0]), float(self.points[-1, 1]))


Segment = Line | Arc | PointCurve


def with_ends(seg: Segment, start, end) -> Segment:
    """A copy of ``seg`` with its end points replaced (to make neighbouring segments share points)."""
    start = (float(start[0]), float(start[1]))
    end = (float(end[0]), float(end[1]))
    if isinstance(seg, PointCurve):
        pts = seg.points.copy()
        pts[0], pts[-1] = start, end
        return PointCurve(pts, seg.tag)
    return dataclasses.replace(seg, start=start, end=end)


def reversed_segment(seg: Segment) -> Segment:
    """The same segment traversed from end to start."""
    if isinstance(seg, PointCurve):
        return PointCurve(seg.points[::-1].copy(), seg.tag)
    return dataclasses.replace(seg, start=seg.end, end=seg.start)


def outline_area(segments: Sequence[Segment]) -> float:
    """Signed area (mm^2) enclosed by a closed chain of segments (positive if counter-clockwise).

    Green's theorem A = 1/2 * loop integral of (y dz - z dy): exact for lines and arcs; a
    :class:`PointCurve` counts as the chord-length-parameterised cubic spline through its points.
    """
    area = 0.0
    for seg in segments:
        if isinstance(seg, Arc):
            (cy, cz), r = seg.centre, seg.radius
            a0 = np.arctan2(seg.start[1] - cz, seg.start[0] - cy)
            a1 = a0 + seg.sweep()
            area += 0.5 * (r * r * (a1 - a0) + cy * r * (np.sin(a1) - np.sin(a0))
                           - cz * r * (np.cos(a1) - np.cos(a0)))
        elif isinstance(seg, PointCurve):
            area += _point_curve_area_term(seg.points)
        else:
            area += 0.5 * (seg.start[0] * seg.end[1] - seg.end[0] * seg.start[1])
    return float(area)


def _point_curve_area_term(pts: np.ndarray) -> float:
    """1/2 * integral of (y dz - z dy) along the chord-length cubic spline through the points."""
    t = np.r_[0.0, np.cumsum(np.hypot(*np.diff(pts, axis=0).T))]
    spl = CubicSpline(t, pts)
    x, w = np.polynomial.legendre.leggauss(4)          # exact for the degree-5 integrand
    half, mid = 0.5 * np.diff(t), 0.5 * (t[1:] + t[:-1])
    tq = (mid[:, None] + half[:, None] * x).ravel()
    p, dp = spl(tq), spl(tq, 1)
    integrand = (p[:, 0] * dp[:, 1] - p[:, 1] * dp[:, 0]).reshape(-1, len(x))
    return float(0.5 * np.sum(half * (integrand @ w)))


def check_closed(segments: Sequence[Segment], tol: float = 1e-9) -> None:
    """Raise AssertionError unless each segment ends where the next one starts (cyclically)."""
    for a, b in zip(segments, list(segments[1:]) + [segments[0]]):
        gap = np.hypot(a.end[0] - b.start[0], a.end[1] - b.start[1])
        if gap > tol:
            raise AssertionError(f"outline not closed: gap {gap:.3g} mm at {a.end}")


# --------------------------------------------------------------------------------------------
# Pieces: z(y) on [ya, yb]
# --------------------------------------------------------------------------------------------
@dataclass(frozen=True)
class ArcPiece:
    """Circular arc z = cz + sign * sqrt(R^2 - (y - cy)^2) on [ya, yb]; ``upper`` selects sign=+1."""

    ya: float
    yb: float
    centre: tuple[float, float]
    radius: float
    upper: bool

    def _u(self, y):
        return np.clip((y - self.centre[0]) / self.radius, -1.0, 1.0)

    def z(self, y):
        u = self._u(y)
        return self.centre[1] + (1 if self.upper else -1) * self.radius * np.sqrt(1 - u * u)

    def dz(self, y):
        u = self._u(y)
        with np.errstate(divide="ignore"):
            return (-1 if self.upper else 1) * u / np.sqrt(1 - u * u)

    def d2z(self, y):
        u = self._u(y)
        with np.errstate(divide="ignore"):
            return (-1 if self.upper else 1) / (self.radius * (1 - u * u) ** 1.5)

    def curvature(self, y):
        return np.full(np.shape(y), (-1.0 if self.upper else 1.0) / self.radius)

    def up_normal(self, y):
        u = self._u(y)
        s = 1.0 if self.upper else -1.0
        return np.stack([s * u, np.sqrt(1 - u * u)], axis=-1)

    def length(self, y):
        return self.radius * (np.arccos(self._u(self.ya)) - np.arccos(self._u(y)))

    @property
    def total_length(self) -> float:
        return float(self.length(self.yb))

    def y_at(self, s):
        return self.centre[0] + self.radius * np.cos(np.arccos(self._u(self.ya)) - s / self.radius)

    def segment(self, tag: str) -> Segment:
        return Arc((self.ya, float(self.z(self.ya))), (self.yb, float(self.z(self.yb))),
                   tuple(map(float, self.centre)), tag)


@dataclass(frozen=True, eq=False)
class SmoothPiece:
    """A smooth curve z = f(y) on [ya, yb] given by callables for f, f', f''.

    Arc length by 8-point Gauss-Legendre on sub-intervals no longer than ``max_sub`` mm (plus the
    given ``knots``); its inverse by safeguarded Newton iteration. ``line`` marks a straight piece
    (exported as a :class:`Line`); otherwise the segment is a :class:`PointCurve` with points at
    arc-length spacing <= ``point_ds`` mm (default 0.1 mm: then even Gmsh's Catmull-Rom "Spline"
    through the points stays within 1e-4 mm of the S1002 polynomials; a cubic spline within 1e-5).
    """

    ya: float
    yb: float
    f: Callable
    df: Callable
    d2f: Callable
    knots: tuple = ()
    max_sub: float = 1.0
    point_ds: float = 0.1
    line: bool = False

    def __post_init__(self):
        inner = [k for k in self.knots if self.ya < k < self.yb]
        brk = np.unique(np.r_[self.ya, inner, self.yb])
        fine = [np.linspace(a, b, int(np.ceil((b - a) / self.max_sub)) + 1)[:-1] for a, b in itertools.pairwise(brk)]
        sub = np.r_[np.concatenate(fine), self.yb]
        cum = np.r_[0.0, np.cumsum(self._gl(sub[:-1], sub[1:]))]
        object.__setattr__(self, "_sub", sub)
        object.__setattr__(self, "_cum", cum)

    def _speed(self, y):
        return np.sqrt(1.0 + self.df(y) ** 2)

    def _gl(self, a, b):
        a, b = np.asarray(a, float), np.asarray(b, float)
        half, mid = 0.5 * (b - a), 0.5 * (b + a)
        pts = mid[..., None] + half[..., None] * _GL_X
        return half * np.sum(_GL_W * self._speed(pts), axis=-1)

    def z(self, y):
        return self.f(y)

    def dz(self, y):
        return self.df(y)

    def d2z(self, y):
        return self.d2f(y)

    def curvature(self, y):
        return self.d2f(y) / (1.0 + self.df(y) ** 2) ** 1.5

    def up_normal(self, y):
        d = self.df(y)
        n = np.sqrt(1.0 + d * d)
        return np.stack([-d / n, 1.0 / n], axis=-1)

    def length(self, y):
        y = np.asarray(y, float)
        k = np.clip(np.searchsorted(self._sub, y, side="right") - 1, 0, len(self._sub) - 2)
        return self._cum[k] + self._gl(self._sub[k], y)

    @property
    def total_length(self) -> float:
        return float(self._cum[-1])

    def y_at(self, s):
        s = np.asarray(s, float)
        y = np.interp(s, self._cum, self._sub)  # chord-wise initial guess
        for _ in range(30):
            step = (self.length(y) - s) / self._speed(y)
            y = np.clip(y - step, self.ya, self.yb)
            if np.all(np.abs(step) < 1e-13 * (1.0 + np.abs(y))):
                break
        return y

    def segment(self, tag: str) -> Segment:
        start, end = (self.ya, float(self.f(self.ya))), (self.yb, float(self.f(self.yb)))
        if self.line:
            return Line(start, end, tag)
        n = max(2, int(np.ceil(self.total_length / self.point_ds)))
        y = self.y_at(np.linspace(0.0, self.total_length, n + 1))
        y[0], y[-1] = self.ya, self.yb
        return PointCurve(np.column_stack([y, self.f(y)]), tag)


def line_piece(ya: float, yb: float, za: float, slope: float) -> SmoothPiece:
    """Straight piece z = za + slope * (y - ya) on [ya, yb]."""
    p = np.polynomial.Polynomial([za - slope * ya, slope])
    return SmoothPiece(ya, yb, p, p.deriv(), p.deriv(2), line=True)


def poly_piece(ya: float, yb: float, coef_increasing: Sequence[float], **kw) -> SmoothPiece:
    """Polynomial piece z = sum c_k y^k on [ya, yb] (coefficients in increasing powers)."""
    p = np.polynomial.Polynomial(coef_increasing)
    dp, d2p = p.deriv(), p.deriv(2)
    return SmoothPiece(ya, yb, p, dp, d2p, **kw)


Piece = ArcPiece | SmoothPiece


# --------------------------------------------------------------------------------------------
# Profile
# --------------------------------------------------------------------------------------------
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
        bad = ~((y >= self.y_min - _Y_TOL) & (y <= self.y_max + _Y_TOL))
        if np.any(bad):
            shown = np.atleast_1d(y[bad])[:3]
            vals = ", ".join(f"{v:.6g}" for v in shown)
            raise InputError(what, f"{vals} mm outside the profile's valid range "
                                   f"[{self.y_min:.6g}, {self.y_max:.6g}] mm ({self.name})")
        return np.clip(y, self.y_min, self.y_max)

    # -- evaluation ----------------------------------------------------------------------------
    def _eval(self, method: str, y, trailing: tuple = ()):
        y = self.check_y(y)
        k = np.searchsorted(self._breaks, y, side="left")
        out = np.empty(y.shape + trailing)
        for i, piece in enumerate(self._pieces):
            m = k == i
            if np.any(m):
                out[m] = getattr(piece, method)(y[m])
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
