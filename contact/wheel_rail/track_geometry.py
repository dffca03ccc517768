"""Wheel and rail placed in the track (units mm, rad).

Frames
------
Track frame (right-handed): X forward (rolling direction), Y lateral from the track centre line, positive towards
the RIGHT rail, Z up, Z = 0 in the plane of the rail tops (highest points of the canted heads).

Side frame: the geometry of one wheel on its rail is computed in a "side frame" in which that rail lies at
positive Y with its field side towards +Y, so that rail and wheel profiles are used UNMIRRORED (their profile
frames have the field side at +y too). For the right side the side frame is the track frame; for the left side it
is the track frame mirrored Y -> -Y, and the wheelset pose (lateral displacement, yaw, roll) changes sign
(:meth:`WheelsetPose.for_side`).

Rail placement (side frame): the rail profile is rotated about its crown (0, 0) by the inclination (cant towards
the track centre, counter-clockwise, :func:`meshes.profiles.placement.rail_inclination`), shifted vertically so that its
highest point is at Z = 0 and laterally so that its gauge point lies at Y = gauge / 2. Gauge point (EN 13848-1):
the innermost point (smallest Y) of the gauge side of the head within ``gauge_depth_mm`` (14 mm) below the top.

Wheel placement: the wheelset centre is at (X, Y, Z) = (0, lateral_mm, Z_c); its axle direction (towards the
right wheel) is a = R_z(yaw) R_x(roll) e_Y = (-sin(yaw) cos(roll), cos(yaw) cos(roll), sin(roll)) (yaw positive
counter-clockwise seen from above, roll positive lifting the right wheel). A wheel profile point y (profile frame:
y = S, field side +) lies on the axle at the axial distance s(y) = back_to_back / 2 - flange_back_y + y from the
centre (S1002: flange back at y = -70 mm, so the taping line is at 680 + 70 = 750 mm) and has the rolling radius
r(y) = nominal_radius - z(y).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np
from scipy.optimize import brentq, minimize_scalar

from meshes.profiles import Profile
from meshes.profiles.placement import rail_inclination
from wrlayer.errors import require

SIDES = ("right", "left")
#: The rail inclination 1:n of a track that gives none (-).
INCLINATION = 40.0
#: Spacing (mm) of the dense rail sample used for lateral look-ups.
RAIL_SAMPLE_MM = 0.02


@dataclass(frozen=True)
class TrackLayout:
    """Track and wheelset dimensions (mm, rad).

    gauge_mm: track gauge between the gauge points; gauge_depth_mm: depth of the gauge points below the rail top;
    inclination_rad: rail cant towards the track centre (1:40 -> atan(1/40)); back_to_back_mm: distance between
    the flange backs; flange_back_y_mm: wheel profile coordinate of the flange back (S1002: -70);
    nominal_radius_mm: rolling radius at the wheel profile's y = 0 (taping line).
    """

    gauge_mm: float = 1435.0
    gauge_depth_mm: float = 14.0
    inclination_rad: float = rail_inclination(INCLINATION)
    back_to_back_mm: float = 1360.0
    flange_back_y_mm: float = -70.0
    nominal_radius_mm: float = 460.0

    def __post_init__(self):
        for key in ("gauge_mm", "gauge_depth_mm", "back_to_back_mm", "nominal_radius_mm"):
            v = getattr(self, key)
            require(bool(np.isfinite(v)) and v > 0, key, f"must be a positive number, got {v!r}")
        require(bool(np.isfinite(self.inclination_rad)) and abs(self.inclination_rad) < 0.2, "inclination",
                f"cant angle {self.inclination_rad!r} rad is not plausible (|angle| < 0.2 rad)")
        require(bool(np.isfinite(self.flange_back_y_mm)), "flange_back_y_mm", "must be a finite number")
        require(self.gauge_mm > self.back_to_back_mm, "gauge_mm",
                f"impossible gauge {self.gauge_mm:g} mm: it must exceed the back-to-back distance "
                f"{self.back_to_back_mm:g} mm (the flange backs must fit between the rails)")

    @property
    def taping_line_mm(self) -> float:
        """Axial distance of the wheel profile's y = 0 from the wheelset centre: b2b/2 - flange_back_y (mm)."""
        return 0.5 * self.back_to_back_mm - self.flange_back_y_mm


@dataclass(frozen=True)
class WheelsetPose:
    """Lateral displacement (mm, towards +Y = the right rail), yaw and roll angles (rad) of the wheelset."""

    lateral_mm: float = 0.0
    yaw_rad: float = 0.0
    roll_rad: float = 0.0

    def __post_init__(self):
        for key in ("lateral_mm", "yaw_rad", "roll_rad"):
            require(bool(np.isfinite(getattr(self, key))), key, f"must be a finite number, got {getattr(self, key)!r}")
        require(abs(self.yaw_rad) < 0.2 and abs(self.roll_rad) < 0.2, "yaw/roll",
                "angles must be small (|angle| < 0.2 rad) for a wheelset on track")

    def for_side(self, side: str) -> WheelsetPose:
        """The pose seen in the side frame of ``side`` (left: mirrored, all three change sign)."""
        s = side_sign(side)
        return WheelsetPose(s * self.lateral_mm, s * self.yaw_rad, s * self.roll_rad)


def side_sign(side: str) -> int:
    """+1 for the right side, -1 for the left side (InputError otherwise)."""
    require(side in SIDES, "side", f"must be 'right' or 'left', got {side!r}")
    return 1 if side == "right" else -1


def axle_direction(pose: WheelsetPose) -> np.ndarray:
    """Unit axle vector a = R_z(yaw) R_x(roll) e_Y (3,)."""
    cy, sy, cr, sr = math.cos(pose.yaw_rad), math.sin(pose.yaw_rad), math.cos(pose.roll_rad), math.sin(pose.roll_rad)
    return np.array([-sy * cr, cy * cr, sr])


# ------------------------------------------------------------------------------------------------- rail
@dataclass(frozen=True, eq=False)
class PlacedRail:
    """A rail profile placed in the side frame: point (Y, Z) = rotate(angle) (y, z(y)) + (dy, dz).

    ``q_mm``/``Y_mm``/``Z_mm``: dense sample (spacing ~0.02 mm) of the profile coordinate q and the placed points;
    ``gauge_point``: (Y, Z) of the gauge point; ``top_q_mm``: profile coordinate of the highest point.
    """

    profile: Profile
    angle_rad: float
    dy_mm: float
    dz_mm: float
    top_q_mm: float
    gauge_point: tuple[float, float]
    q_mm: np.ndarray = field(repr=False)
    Y_mm: np.ndarray = field(repr=False)
    Z_mm: np.ndarray = field(repr=False)

    def point(self, q) -> np.ndarray:
        """Placed points (..., 2) (Y, Z) of profile coordinates q (mm)."""
        q = np.asarray(q, dtype=float)
        c, s = math.cos(self.angle_rad), math.sin(self.angle_rad)
        z = self.profile.z(q)
        return np.stack([c * q - s * z + self.dy_mm, s * q + c * z + self.dz_mm], axis=-1)

    def normal(self, q) -> np.ndarray:
        """Placed outward unit normals (..., 2) (pointing out of the rail, into the wheel)."""
        n = self.profile.normal(q)
        c, s = math.cos(self.angle_rad), math.sin(self.angle_rad)
        return np.stack([c * n[..., 0] - s * n[..., 1], s * n[..., 0] + c * n[..., 1]], axis=-1)

    def q_at(self, Y) -> np.ndarray:
        """Profile coordinate q (mm) of the placed rail point at lateral position Y (mm): Newton from the sample.

        Y outside the placed running surface gives NaN.
        """
        Y = np.asarray(Y, dtype=float)
        q = np.interp(Y, self.Y_mm, self.q_mm, left=np.nan, right=np.nan)
        ok = np.isfinite(q)
        c, s = math.cos(self.angle_rad), math.sin(self.angle_rad)
        prof = self.profile
        for _ in range(2):  # the 0.02 mm sample start is within ~1e-6 mm: two Newton steps reach round-off
            if not np.any(ok):
                break
            qq = np.clip(q[ok], prof.y_min, prof.y_max)
            resid = c * qq - s * prof.z(qq) + self.dy_mm - Y[ok]
            q[ok] = np.clip(qq - resid / (c - s * prof.dz(qq)), prof.y_min, prof.y_max)
        return q

    def Z_at(self, Y) -> np.ndarray:
        """Height Z (mm) of the placed rail at lateral position Y (NaN outside)."""
        q = self.q_at(Y)
        out = np.full(np.shape(q), np.nan)
        ok = np.isfinite(q)
        if np.any(ok):
            out[ok] = self.point(q[ok])[..., 1]
        return out


def _rail_sample(profile: Profile, angle: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    n = int(np.ceil((profile.y_max - profile.y_min) / RAIL_SAMPLE_MM)) + 1
    q = np.linspace(profile.y_min, profile.y_max, n)
    z = profile.z(q)
    c, s = math.cos(angle), math.sin(angle)
    return q, c * q - s * z, s * q + c * z


def place_rail(profile: Profile, layout: TrackLayout) -> PlacedRail:
    """Place a rail profile in the side frame (see the module docstring); InputError naming the case if the
    profile has no top inside its range or does not reach ``gauge_depth_mm`` below the top on the gauge side."""
    require(profile.body == "rail", "rail profile", f"{profile.name} is a {profile.body} profile, not a rail")
    a = layout.inclination_rad
    q, Y, Z = _rail_sample(profile, a)
    require(bool(np.all(np.diff(Y) > 0)), "rail profile",
            f"{profile.name} is not a graph over the lateral coordinate after the cant of {a:g} rad")
    i_top = int(np.argmax(Z))
    require(0 < i_top < q.size - 1, "rail profile", f"{profile.name}: the highest point of the canted rail is at an "
            "end of the profile (no rail top)")
    # exact top: rotated slope zero, dz/dq = -tan(a)
    slope = lambda v: float(profile.dz(v)) + math.tan(a)
    q_top = brentq(slope, q[i_top - 1], q[i_top + 1], xtol=1e-12) if slope(q[i_top - 1]) * slope(q[i_top + 1]) < 0 \
        else float(q[i_top])
    c, s = math.cos(a), math.sin(a)
    z_top = s * q_top + c * float(profile.z(q_top))
    Z = Z - z_top
    depth = layout.gauge_depth_mm
    gauge_side = slice(0, i_top + 1)
    Zg, Yg, qg = Z[gauge_side], Y[gauge_side], q[gauge_side]
    require(bool(Zg[0] < -depth), "gauge_depth_mm",
            f"the rail profile {profile.name} reaches only {-Zg[0]:.3f} mm below the top on the gauge side, "
            f"less than the gauge depth {depth:g} mm")
    # crossing of Z = -depth on the gauge side (last sample below, from the top downwards)
    k = int(np.flatnonzero(Zg < -depth)[-1])
    height = lambda v: s * v + c * float(profile.z(v)) - z_top + depth
    q_cross = brentq(height, qg[k], qg[k + 1], xtol=1e-12)
    Y_cross = c * q_cross - s * float(profile.z(q_cross))
    # innermost point within the band (an interior minimum of Y if the gauge face undercuts)
    band = Zg >= -depth
    j = int(np.argmin(np.where(band, Yg, np.inf)))
    Y_gauge, q_gauge = Y_cross, q_cross
    if Yg[j] < Y_cross - 1e-9:
        lo, hi = qg[max(j - 1, 0)], qg[min(j + 1, qg.size - 1)]
        res = minimize_scalar(lambda v: c * v - s * float(profile.z(v)), bounds=(lo, hi), method="bounded",
                              options={"xatol": 1e-10})
        q_gauge, Y_gauge = float(res.x), float(res.fun)
    dy = 0.5 * layout.gauge_mm - Y_gauge
    Z_gauge = s * q_gauge + c * float(profile.z(q_gauge)) - z_top
    return PlacedRail(profile, a, dy, -z_top, float(q_top), (0.5 * layout.gauge_mm, float(Z_gauge)),
                      q, Y + dy, Z)


# ------------------------------------------------------------------------------------------------- wheel
@dataclass(frozen=True)
class WheelLocus:
    """Points of a wheel's contact locus in the side frame, one per wheel profile coordinate y (mm).

    For a yawed wheelset the wheel surface touches a straight (prismatic) rail where its outward normal is
    perpendicular to X; for every profile circle y that point is (X, Y, Z) below the axle (X = the longitudinal
    lead). ``normal`` (n, 3): outward unit normal of the wheel (pointing away from the wheel material, i.e.
    down towards the rail) with n_X = 0; ``radius_mm``: r(y); ``circumferential`` (n, 3): unit circumferential
    direction; ``Z`` relative to the wheelset centre at Z = 0.
    """

    y_mm: np.ndarray
    X_mm: np.ndarray
    Y_mm: np.ndarray
    Z_mm: np.ndarray
    normal: np.ndarray
    radius_mm: np.ndarray
    dr_dy: np.ndarray
    circumferential: np.ndarray


def cross3(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """a x b of 3-vectors (..., 3), broadcast: numpy.cross's products and differences (the same values) without its
    axis handling, which costs more than the products on the few vectors of a contact search."""
    a, b = np.asarray(a, dtype=float), np.asarray(b, dtype=float)
    return np.stack([a[..., 1] * b[..., 2] - a[..., 2] * b[..., 1], a[..., 2] * b[..., 0] - a[..., 0] * b[..., 2],
                     a[..., 0] * b[..., 1] - a[..., 1] * b[..., 0]], axis=-1)


def wheel_locus(wheel: Profile, layout: TrackLayout, pose: WheelsetPose, y_mm, z_mm=None, dz=None) -> WheelLocus:
    """The contact locus of the wheel at profile coordinates ``y_mm`` (side frame, wheelset centre at height 0).

    Closed form: with r' = dr/dy = -z'(y), u = unit projection of e_X on the plane normal to a, w = a x u, the
    radial direction at angle theta is e = cos(theta) u + sin(theta) w; the surface normal e - r' a has zero X
    component when cos(theta) = r' a_X / sqrt(1 - a_X^2); the lower of the two solutions is taken.
    """
    y = np.asarray(y_mm, dtype=float)
    a = axle_direction(pose)
    ex = np.array([1.0, 0.0, 0.0])
    norm_u = math.sqrt(max(1.0 - a[0] ** 2, 1e-300))
    u = (ex - a[0] * a) / norm_u
    w = cross3(a, u)
    r = layout.nominal_radius_mm - (wheel.z(y) if z_mm is None else np.asarray(z_mm, dtype=float))
    with np.errstate(invalid="ignore"):
        dr = -(wheel.dz(y) if dz is None else np.asarray(dz, dtype=float))
    dr = np.where(np.isfinite(dr), dr, np.sign(dr) * 1e6)
    cos_t = np.clip(dr * a[0] / norm_u, -1.0, 1.0)
    sin_t = -math.copysign(1.0, w[2]) * np.sqrt(1.0 - cos_t ** 2)
    e_rad = cos_t[..., None] * u + sin_t[..., None] * w
    centre = np.array([0.0, pose.lateral_mm, 0.0])
    s = layout.taping_line_mm + y
    p = centre + s[..., None] * a + r[..., None] * e_rad
    n = e_rad - dr[..., None] * a
    n /= np.linalg.norm(n, axis=-1, keepdims=True)
    circ = cross3(a, e_rad)
    return WheelLocus(y, p[..., 0], p[..., 1], p[..., 2], n, r, dr, circ)


def wheel_sample_y(wheel: Profile, spacing_mm: float = 0.02, margin_mm: float = 1e-3) -> np.ndarray:
    """Dense profile coordinates of the wheel (avoiding a vertical flange-back end by ``margin_mm``)."""
    lo, hi = wheel.y_min + margin_mm, wheel.y_max
    return np.linspace(lo, hi, int(np.ceil((hi - lo) / spacing_mm)) + 1)


__all__ = [
    "SIDES",
    "PlacedRail",
    "TrackLayout",
    "WheelLocus",
    "WheelsetPose",
    "axle_direction",
    "cross3",
    "place_rail",
    "side_sign",
    "wheel_locus",
    "wheel_sample_y",
]
