"""Placing 2D profile points (y, z) (mm) in a section frame: mirror, rotate, shift.

``place(points, p)`` applies, in this order: mirror y -> -y (if ``p.mirror``), rotation about the
origin by ``p.angle_rad`` (positive = counter-clockwise in the (y, z) plane, z up), shift by
(``p.dy``, ``p.dz``).

Rail cant sign convention: a profile in the project frame has its gauge side at NEGATIVE y. Canting
it towards the track centre tilts its top towards the gauge side, i.e. towards -y, which is a
counter-clockwise rotation: ``rail_inclination(40) = +atan(1/40)`` (+0.0249948 rad). This is the
rotation found by fitting the 60E1 head to the canted Manchester-benchmark file
``MBench_UIC60_v3.prr`` (see tests/meshes/test_profiles_reference.py). For the other rail use
:func:`mirror` on the whole placement.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from wrlayer.errors import InputError


@dataclass(frozen=True)
class Placement:
    """Mirror (y -> -y) first, then rotate by ``angle_rad`` (CCW positive), then shift (mm)."""

    angle_rad: float = 0.0
    dy: float = 0.0
    dz: float = 0.0
    mirror: bool = False


def place(points, placement: Placement) -> np.ndarray:
    """Placed copy of points (n, 2) of (y, z) in mm."""
    pts = np.asarray(points, dtype=float)
    if pts.ndim != 2 or pts.shape[1] != 2:
        raise InputError("points", f"need an (n, 2) array of (y, z), got shape {pts.shape}")
    y = -pts[:, 0] if placement.mirror else pts[:, 0]
    c, s = math.cos(placement.angle_rad), math.sin(placement.angle_rad)
    return np.column_stack([c * y - s * pts[:, 1] + placement.dy, s * y + c * pts[:, 1] + placement.dz])


def unplace(points, placement: Placement) -> np.ndarray:
    """Inverse of :func:`place`: points from the section frame back into the profile frame."""
    pts = np.asarray(points, dtype=float)
    c, s = math.cos(placement.angle_rad), math.sin(placement.angle_rad)
    dy, dz = pts[:, 0] - placement.dy, pts[:, 1] - placement.dz
    y, z = c * dy + s * dz, -s * dy + c * dz
    return np.column_stack([-y if placement.mirror else y, z])


def rail_inclination(ratio: float = 40.0) -> float:
    """Cant angle (rad) 1:ratio towards the track centre for a rail profile whose gauge side is at
    negative y: +atan(1/ratio) (counter-clockwise)."""
    if not ratio > 0:
        raise InputError("ratio", f"inclination ratio must be positive, got {ratio}")
    return math.atan(1.0 / ratio)


def wheel_at_radius(r0: float = 460.0, y_taping: float = 0.0) -> Placement:
    """Wheel profile (z = -F) placed in a frame with the axle centre line at z = 0: the taping line
    point (0, 0) goes to (y_taping, -r0), so z + r0 is the height above the lowest tread point."""
    if not r0 > 0:
        raise InputError("r0", f"rolling radius must be positive, got {r0} mm")
    return Placement(0.0, float(y_taping), -float(r0), False)


def mirror(placement: Placement) -> Placement:
    """The placement seen in the mirror y -> -y (left/right swap): place(p, mirror(P)) equals
    place(p, P) with y negated."""
    return Placement(-placement.angle_rad, -placement.dy, placement.dz, not placement.mirror)
