"""Rail and wheel surfaces and the contact patches placed on them, in track coordinates (units mm, rad).

For ParaView overlays of the contact fields on the bodies (:mod:`contact.wheel_rail.track_vtk`). Frames as in
:mod:`contact.wheel_rail.track_geometry`: track frame X forward, Y lateral towards the right rail, Z up; a side's
geometry is computed in its side frame and mirrored Y -> -Y for the left side (``sign`` = -1).

- Rail surface: the placed rail profile (:class:`~contact.wheel_rail.track_geometry.PlacedRail`) extruded along X
  (a straight rail), points (X, sign Y(q), Z(q)) on a grid of X and the profile coordinate q.
- Wheel surface: the wheel profile revolved about the axle a of the pose: for profile coordinate y the circle of
  radius r(y) = nominal radius - z(y) about the axle point c + s(y) a (s(y) the axial distance of
  :func:`~contact.wheel_rail.track_geometry.wheel_locus`, c the wheelset centre at the rigid-contact height), over
  the angles phi within +-``length / r0`` of the lowest point.
- A patch on the rail: its cell corners (x along X from the contact point, eta along the contact plane's lateral
  axis) are put on the rail surface at q = ``ContactCandidate.rail_coordinate(eta)``; on the wheel at the wheel
  profile coordinate ``wheel_coordinate(eta)`` on the circle through the contact point, phi = x / r. A normal
  displacement field (mm, into the body) moves the points along the surface normal (the deformed surface).
"""

from __future__ import annotations

import math

import numpy as np

from contact.wheel_rail.contact_search import ContactCandidate
from contact.wheel_rail.track_geometry import PlacedRail, TrackLayout, WheelsetPose, axle_direction
from meshes.profiles import Profile


def quads(n_i: int, n_j: int) -> np.ndarray:
    """Connectivity (n_i - 1) (n_j - 1) x 4 of the quads of an n_i x n_j point grid flattened row by row."""
    i, j = np.meshgrid(np.arange(n_i - 1), np.arange(n_j - 1), indexing="ij")
    k = (i * n_j + j).ravel()
    return np.stack([k, k + n_j, k + n_j + 1, k + 1], axis=1)


def _mirrored(points: np.ndarray, sign: int) -> np.ndarray:
    out = np.array(points, dtype=float)
    out[..., 1] *= sign
    return out


def rail_points(rail: PlacedRail, sign: int, X_mm: np.ndarray, q_mm: np.ndarray,
                depth_mm: np.ndarray | None = None) -> np.ndarray:
    """Track-frame points (nX, nq, 3) of the rail surface at X (nX,) and profile coordinates q (nq,); ``depth_mm``
    (nX, nq): displacement into the rail along its surface normal (the deformed surface)."""
    X = np.asarray(X_mm, dtype=float)
    yz = rail.point(np.asarray(q_mm, dtype=float))                  # (nq, 2)
    pts = np.empty((X.size, yz.shape[0], 3))
    pts[..., 0] = X[:, None]
    pts[..., 1:] = yz[None, :, :]
    if depth_mm is not None:
        n = rail.normal(np.asarray(q_mm, dtype=float))              # outward (into the wheel)
        pts[..., 1:] -= np.asarray(depth_mm)[..., None] * n[None, :, :]
    return _mirrored(pts, sign)


def _wheel_frame(layout: TrackLayout, pose: WheelsetPose, height_mm: float):
    """(centre (3,), axle a (3,), down d (3,), forward e (3,)) of the wheelset in the side frame."""
    a = axle_direction(pose)
    down = np.array([0.0, 0.0, -1.0]) - (-a[2]) * a
    down /= np.linalg.norm(down)
    forward = np.cross(down, a)
    forward *= math.copysign(1.0, forward[0])
    return np.array([0.0, pose.lateral_mm, height_mm]), a, down, forward


def wheel_points(wheel: Profile, layout: TrackLayout, pose: WheelsetPose, height_mm: float, sign: int,
                 phi_rad: np.ndarray, y_mm: np.ndarray, depth_mm: np.ndarray | None = None) -> np.ndarray:
    """Track-frame points (nphi, ny, 3) of the wheel surface at angles phi from the lowest point (positive
    forward) and profile coordinates y; ``pose`` and ``height_mm`` (wheelset-centre height Z) in the side frame;
    ``depth_mm`` (nphi, ny): displacement into the wheel along its outward normal."""
    c, a, down, forward = _wheel_frame(layout, pose, height_mm)
    y = np.asarray(y_mm, dtype=float)
    phi = np.asarray(phi_rad, dtype=float)
    r = layout.nominal_radius_mm - wheel.z(y)
    s = layout.taping_line_mm + y
    radial = np.cos(phi)[:, None, None] * down + np.sin(phi)[:, None, None] * forward     # (nphi, 1, 3)
    pts = c + s[None, :, None] * a + r[None, :, None] * radial
    if depth_mm is not None:
        dr = -wheel.dz(y)
        n = radial - dr[None, :, None] * a
        n /= np.linalg.norm(n, axis=-1, keepdims=True)
        pts = pts - np.asarray(depth_mm)[..., None] * n
    return _mirrored(pts, sign)


def patch_on_rail(rail: PlacedRail, cand: ContactCandidate, sign: int, x_mm: np.ndarray, eta_mm: np.ndarray,
                  depth_mm: np.ndarray | None = None) -> np.ndarray:
    """Track-frame points (nx, neta, 3) of a patch grid (x along the rolling direction from the contact point,
    eta the contact plane's lateral coordinate) on the rail surface; ``depth_mm`` (nx, neta) as in
    :func:`rail_points`."""
    q = cand.rail_coordinate(np.asarray(eta_mm, dtype=float))
    return rail_points(rail, sign, cand.X_mm + np.asarray(x_mm, dtype=float), q, depth_mm)


def patch_on_wheel(wheel: Profile, layout: TrackLayout, pose: WheelsetPose, height_mm: float,
                   cand: ContactCandidate, sign: int, x_mm: np.ndarray, eta_mm: np.ndarray,
                   depth_mm: np.ndarray | None = None) -> np.ndarray:
    """Track-frame points (nx, neta, 3) of a patch grid on the wheel surface (the circle of each strip's wheel
    profile coordinate, at phi = x / r from the lowest point plus the contact's longitudinal lead)."""
    y = cand.wheel_coordinate(np.asarray(eta_mm, dtype=float))
    centre, a, down, forward = _wheel_frame(layout, pose, height_mm)
    y0 = float(cand.wheel_coordinate(0.0))
    r0 = layout.nominal_radius_mm - float(wheel.z(y0))
    # the contact point's angle phi_c on its circle: circle_X + r0 (cos phi d_X + sin phi e_X) = X_c (the circle's
    # centre leads by s a_X on a yawed axle; d_X != 0 with roll), the root nearer the lowest point
    circle_X = centre[0] + (layout.taping_line_mm + y0) * a[0]
    A, B = r0 * down[0], r0 * forward[0]
    base, half = math.atan2(B, A), math.acos(max(-1.0, min(1.0, (cand.X_mm - circle_X) / math.hypot(A, B))))
    lead = min((base - half, base + half), key=lambda v: abs(math.remainder(v, 2.0 * math.pi)))
    phi = math.remainder(lead, 2.0 * math.pi) + np.asarray(x_mm, dtype=float) / r0
    return wheel_points(wheel, layout, pose, height_mm, sign, phi, y, depth_mm)
