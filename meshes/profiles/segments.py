"""Exact segment primitives of a section outline, handed to the mesher (lengths in mm; frames in
:mod:`meshes.profiles.base`).

:class:`Line`, :class:`Arc` and :class:`PointCurve` each carry a ``tag`` in {"surface", "side", "fixed"};
:func:`outline_area` and :func:`check_closed` check a closed outline made of them.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
from scipy.interpolate import CubicSpline

from wrlayer.errors import InputError

__all__ = ["TAGS", "Arc", "Line", "PointCurve", "Segment", "check_closed", "outline_area", "reversed_segment",
           "with_ends"]

TAGS = ("surface", "side", "fixed")


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

