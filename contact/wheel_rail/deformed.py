"""Residual displacements mapped back onto the profiles, and the rigid wheelset's roll (units mm, rad).

Each body's accumulated residual displacement u_p(eta) (along the patch normal, into the body) is mapped back onto
the body's profile at the strip positions and the profile points are moved by -u_p along the profile's outward
normal (:func:`deformed_profile`).
"""

from __future__ import annotations

import numpy as np
from scipy.optimize import brentq

from contact.wheel_rail.contact_search import SearchSettings, raw_min_gap
from contact.wheel_rail.solution import PatchSolution
from contact.wheel_rail.track_geometry import PlacedRail, TrackLayout, WheelsetPose
from meshes.profiles import Profile
from wrlayer.errors import ConvergenceError


def deformed_profile(profile: Profile, y_strip_mm: np.ndarray, residual_mm: np.ndarray, spacing_mm: float = 0.1
                     ) -> np.ndarray:
    """Points (n, 2) of ``profile`` with the residual displacement u_p(y) (mm, into the body, given at the profile
    coordinates ``y_strip_mm`` of the strips; zero elsewhere) applied along the inward normal.

    The points are at ``spacing_mm`` in y over the profile's range plus the strip positions (so a dent narrower than
    the spacing is still resolved); u_p is interpolated linearly between strips.
    """
    ys = np.asarray(y_strip_mm, dtype=float)
    up = np.asarray(residual_mm, dtype=float)
    order = np.argsort(ys)
    ys, up = ys[order], up[order]
    y = np.linspace(profile.y_min, profile.y_max, int(np.ceil((profile.y_max - profile.y_min) / spacing_mm)) + 1)
    inside = ys[(ys > profile.y_min) & (ys < profile.y_max)]
    y = np.unique(np.concatenate([y, inside]))
    u = np.interp(y, ys, up, left=0.0, right=0.0) if ys.size else np.zeros_like(y)
    n = profile.normal(y)
    pts = np.column_stack([y, profile.z(y)]) - u[:, None] * n
    keep = np.concatenate([[True], np.diff(pts[:, 0]) > 1e-9])
    return pts[keep]


def residual_on_profiles(patches: list[PatchSolution]) -> dict[str, tuple[np.ndarray, np.ndarray]]:
    """Per body ("rail", "wheel"): (profile coordinates, residual displacement) of all loaded strips of all patches.

    A ``combined`` layer's residual is split equally between the two bodies (it stands for both together).
    """
    out: dict[str, list] = {"rail": [[], []], "wheel": [[], []]}
    for p in patches:
        if not p.residual_mm:
            continue
        coords = {"rail": p.rail_y_of_strip, "wheel": p.wheel_y_of_strip}
        for body in ("rail", "wheel"):
            if body in p.residual_mm:
                u = p.residual_mm[body]
            elif "combined" in p.residual_mm:
                u = 0.5 * p.residual_mm["combined"]
            else:
                continue
            out[body][0].append(coords[body])
            out[body][1].append(u)
    return {b: (np.concatenate(v[0]), np.concatenate(v[1])) for b, v in out.items() if v[0]}


def rigid_roll(rail: PlacedRail, wheel: Profile, layout: TrackLayout, pose: WheelsetPose,
               settings: SearchSettings | None = None, bracket_rad: float = 0.05,
               left: tuple[PlacedRail, Profile] | None = None) -> float:
    """Roll angle (rad) of a rigid wheelset at which both wheels touch their rails when it is lowered: the minimum
    vertical gaps of the two sides are equal (Brent, 1e-12 rad). ``rail``/``wheel``: the right side's placed rail
    and wheel profile, also the left side's unless ``left`` = (placed rail, wheel profile) of the left side (e.g.
    worn differently). ``pose.roll_rad`` is ignored."""
    settings = settings or SearchSettings()
    left_rail, left_wheel = left if left is not None else (rail, wheel)

    def difference(roll: float) -> float:
        p = WheelsetPose(pose.lateral_mm, pose.yaw_rad, roll)
        return (raw_min_gap(rail, wheel, layout, p.for_side("right"), settings)
                - raw_min_gap(left_rail, left_wheel, layout, p.for_side("left"), settings))

    lo, hi = -bracket_rad, bracket_rad
    d_lo, d_hi = difference(lo), difference(hi)
    if d_lo * d_hi > 0:
        raise ConvergenceError(f"rigid wheelset roll: no root in [{lo:g}, {hi:g}] rad (both wheels cannot touch)")
    return float(brentq(difference, lo, hi, xtol=1e-12, rtol=1e-12, maxiter=100))


__all__ = ["deformed_profile", "residual_on_profiles", "rigid_roll"]
