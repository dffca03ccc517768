"""Curve pieces of a profile: each a function z(y) on [ya, yb] (mm) with exact derivatives and arc length.

:class:`ArcPiece` (circular arc, exact, vertical end points handled analytically except for ``dz``/``d2z``, which
return +-inf there) and :class:`SmoothPiece` (straight line or smooth curve; arc length by Gauss-Legendre
quadrature and its inverse by Newton's method, to round-off). A :class:`~meshes.profiles.base.Profile` chains them
by increasing y. Lengths in mm, curvatures in 1/mm.
"""

from __future__ import annotations

import itertools
from collections.abc import Callable, Sequence
from dataclasses import dataclass

import numpy as np

from meshes.profiles.segments import Arc, Line, PointCurve, Segment

__all__ = ["ArcPiece", "Piece", "SmoothPiece", "line_piece", "poly_piece"]

# Gauss-Legendre rule used for arc lengths of smooth pieces (exact for polynomials of degree 15).
_GL_X, _GL_W = np.polynomial.legendre.leggauss(8)


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
