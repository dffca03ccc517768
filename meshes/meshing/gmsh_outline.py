"""Build a profile section outline as exact Gmsh geometry (built-in "geo" kernel).

The outline is a closed counter-clockwise loop of segments in the (y, z) profile frame (mm), each with a
boundary ``tag`` ("surface", "side", "fixed"); see ``meshes.profiles``. Segment kinds are recognised by their
fields: ``centre`` -> circle arc (< 180 deg), ``points`` -> smooth interpolating spline through the points,
otherwise a straight line from ``start`` to ``end``. Gmsh's (x, y) plane holds the profile's (y, z).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import gmsh
import numpy as np

from wrlayer.errors import InputError

#: Largest gap (mm) accepted between the end of one segment and the start of the next.
JOIN_TOLERANCE_MM = 1e-6


@dataclass
class SectionGeometry:
    """Gmsh tags of one section: the plane surface and its boundary curves grouped by outline tag."""

    surface: int
    curves: list[int] = field(default_factory=list)
    curve_names: list[str] = field(default_factory=list)
    curve_radii: list[float] = field(default_factory=list)  # smallest radius of curvature per curve, mm

    def curves_named(self, name: str) -> list[int]:
        return [c for c, n in zip(self.curves, self.curve_names) if n == name]


def segment_points(segment) -> np.ndarray:
    """The defining points (n, 2) of a segment, first = start and last = end (mm)."""
    if hasattr(segment, "points"):
        return np.asarray(segment.points, dtype=float).reshape(-1, 2)
    return np.array([segment.start, segment.end], dtype=float).reshape(2, 2)


def min_radius(segment) -> float:
    """Smallest radius of curvature (mm) of a segment: the arc radius, for a point curve the smallest
    circumradius of three consecutive points, infinite for a line."""
    if hasattr(segment, "centre"):
        return float(np.hypot(*(np.asarray(segment.start, float) - np.asarray(segment.centre, float))))
    pts = segment_points(segment)
    if len(pts) < 3:
        return math.inf
    a, b, c = pts[:-2], pts[1:-1], pts[2:]
    cross = np.abs((b - a)[:, 0] * (c - a)[:, 1] - (b - a)[:, 1] * (c - a)[:, 0])  # twice the area
    lengths = np.linalg.norm(b - a, axis=1) * np.linalg.norm(c - b, axis=1) * np.linalg.norm(c - a, axis=1)
    with np.errstate(divide="ignore"):
        return float(np.min(np.where(cross > 0, lengths / (2.0 * cross), math.inf)))


def check_outline(outline, what: str = "section_outline") -> None:
    """Raise InputError unless ``outline`` is a closed chain of at least 3 segments with known tags."""
    if len(outline) < 2:
        raise InputError(what, f"needs at least 2 segments, got {len(outline)}")
    for i, seg in enumerate(outline):
        if seg.tag not in ("surface", "side", "fixed"):
            raise InputError(what, f"segment {i} has unknown tag {seg.tag!r}")
        nxt = outline[(i + 1) % len(outline)]
        gap = np.linalg.norm(segment_points(seg)[-1] - segment_points(nxt)[0])
        if gap > JOIN_TOLERANCE_MM:
            raise InputError(what, f"segment {i} ends {gap:.3g} mm away from the start of segment "
                                   f"{(i + 1) % len(outline)} (the loop must be closed)")


def add_section(outline) -> SectionGeometry:
    """Add the outline as curves, a curve loop and a plane surface to the current model (geo kernel)."""
    check_outline(outline)
    geo = gmsh.model.geo
    corners = [geo.addPoint(*segment_points(seg)[0], 0.0) for seg in outline]
    curves, names = [], []
    for i, seg in enumerate(outline):
        start, end = corners[i], corners[(i + 1) % len(outline)]
        if hasattr(seg, "centre"):
            centre = geo.addPoint(*np.asarray(seg.centre, dtype=float), 0.0)
            curve = geo.addCircleArc(start, centre, end)
        elif hasattr(seg, "points"):
            inner = [geo.addPoint(y, z, 0.0) for y, z in segment_points(seg)[1:-1]]
            curve = geo.addSpline([start, *inner, end])
        else:
            curve = geo.addLine(start, end)
        curves.append(curve)
        names.append(seg.tag)
    loop = geo.addCurveLoop(curves)
    surface = geo.addPlaneSurface([loop])
    return SectionGeometry(surface=surface, curves=curves, curve_names=names,
                           curve_radii=[min_radius(seg) for seg in outline])
