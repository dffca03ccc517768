"""Creepages and spin of a wheelset at its contact points (rigid kinematics; units mm, s, rad).

Track frame (right-handed, see :mod:`contact.wheel_rail.track_geometry`): X forward, Y towards the right rail, Z up. The
wheelset centre C moves forward with speed V (mm/s) along X; the wheelset spins about its axle a (unit vector,
yawed and rolled) with the pitch rate omega (rad/s, positive for forward rolling: omega = V / r0 is pure rolling
at the nominal radius). The lateral velocity is zero (a steady, quasi-static wheelset position); the yaw rate
``yaw_rate_rad_s`` about Z is zero on straight track and psi' = -V kappa in a steady curve of signed curvature kappa
(1/mm, positive for a curve to the left, the heading turning from X towards -Y; yaw positive turns towards +Y, see
:func:`contact.wheel_rail.track_geometry.axle_direction`). The rails are at rest.

Contact frame of a patch (Kalker's convention, body 1 = wheel, body 2 = rail): x = e_X (rolling direction; it lies
in the contact plane because the contact-locus normal has no X component), y = t (contact-plane lateral axis with
a POSITIVE track-Y component, for both wheels), z = n = x cross y (the normal from the rail into the wheel).

Creepages (Kalker): the rigid slip velocity of the wheel relative to the rail at the contact point P, divided by
the rolling speed V:

    Omega = omega a + psi' e_Z,   v_slip = V e_X + Omega x (P - C)
    vx = v_slip . e_X / V,   vy = v_slip . t / V,   phi = Omega . n / V   (1/mm)

(the spin is the relative angular velocity about the normal over V; the rail does not rotate). For a centred
right wheel without yaw this gives vx = 1 - omega r / V and phi = -sin(gamma) / r0 at omega = V / r0; for a yaw
angle psi, vy ~ -psi cos(gamma) ... exactly as in Kalker's wheelset kinematics. In a curve the yaw rate adds
-psi' (P - C)_Y / V = kappa Y_P to vx (the outer wheel's centre runs faster: +e0 / R with e0 the half distance of
the contact points, the inner's slower) and psi' n_Z / V = -kappa cos(gamma) to the spin: the linear curving
creepages of a wheelset (Iwnicki, Handbook of Railway Vehicle Dynamics, 2006, ch. 9; Wickens, Fundamentals of
Rail Vehicle Dynamics, 2003, ch. 7): vx = +-(e0 / R - y gamma / r0), vy = -psi, phi = -+gamma / r0 - 1 / R.
FASTSIM's forces on body 1 are then the forces exerted by the rail on the wheel, in this contact frame.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from wrlayer.errors import require


@dataclass(frozen=True)
class PatchKinematics:
    """Creepages at one contact point: vx, vy (-), spin phi_per_mm (1/mm); slip velocity vector (mm/s, track)."""

    vx: float
    vy: float
    phi_per_mm: float
    slip_velocity_mm_s: tuple[float, float, float]


def contact_frame(normal: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(x, y, z) unit axes of the contact frame for a normal n with n_X = 0: x = e_X, y = (0, n_Z, -n_Y), z = n."""
    n = np.asarray(normal, dtype=float)
    require(abs(n[0]) < 1e-9, "contact normal", f"must be normal to the rolling direction X, got n_X = {n[0]:g}")
    n = n / np.linalg.norm(n)
    return np.array([1.0, 0.0, 0.0]), np.array([0.0, n[2], -n[1]]), n


def creepages(point_mm: np.ndarray, normal: np.ndarray, centre_mm: np.ndarray, axle: np.ndarray, speed_mm_s: float,
              pitch_rate_rad_s: float, yaw_rate_rad_s: float = 0.0) -> PatchKinematics:
    """Kalker creepages (vx, vy, spin) of the wheel relative to the rail at ``point_mm`` (track frame, see module);
    ``yaw_rate_rad_s``: the wheelset's yaw rate psi' (rad/s; -V kappa in a steady curve, 0 on straight track)."""
    require(bool(np.isfinite(speed_mm_s)) and speed_mm_s > 0, "speed_mm_s", f"must be > 0, got {speed_mm_s!r}")
    require(bool(np.isfinite(pitch_rate_rad_s)), "pitch_rate_rad_s", f"must be finite, got {pitch_rate_rad_s!r}")
    require(bool(np.isfinite(yaw_rate_rad_s)), "yaw_rate_rad_s", f"must be finite, got {yaw_rate_rad_s!r}")
    ex, t, n = contact_frame(normal)
    a = np.asarray(axle, dtype=float)
    arm = np.asarray(point_mm, dtype=float) - np.asarray(centre_mm)
    # the yaw-rate terms are added separately, so that straight track (psi' = 0) keeps its numbers bit for bit
    v = speed_mm_s * ex + pitch_rate_rad_s * np.cross(a, arm) + yaw_rate_rad_s * np.array([-arm[1], arm[0], 0.0])
    spin = (pitch_rate_rad_s * (a @ n) + yaw_rate_rad_s * n[2]) / speed_mm_s
    return PatchKinematics(float(v @ ex / speed_mm_s), float(v @ t / speed_mm_s), float(spin),
                           tuple(float(c) for c in v))


def given_creepages(creepages_given: tuple[float, float, float], normal: np.ndarray, speed_mm_s: float
                    ) -> PatchKinematics:
    """Creepages (vx, vy, phi (1/mm)) given from outside (a multibody export) in the contact frame of ``normal``,
    with the rigid slip velocity V (vx e_X + vy t) they stand for (mm/s, track)."""
    ex, t, _ = contact_frame(normal)
    vx, vy, phi = (float(c) for c in creepages_given)
    v = speed_mm_s * (vx * ex + vy * t)
    return PatchKinematics(vx, vy, phi, tuple(float(c) for c in v))


__all__ = ["PatchKinematics", "contact_frame", "creepages", "given_creepages"]
