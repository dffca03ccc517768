"""Plausibility of a profile read from a file: units, orientation, spikes and steps (lengths in mm, z up).

A profile that is subtly wrong (written in metres, upside down, mirrored, with a spike or a near-vertical step)
meshes and solves without complaint and ends in a message about something else (conforming contact, degenerate
elements, ``depth_mm``, a flange through the rail). These checks run on the points of every profile file in the
project frame (:mod:`meshes.profiles.base`: rail material below the curve, crown near y = 0, field side +y;
wheel material above, flange at -y) and name the file and what looks wrong. A profile that is unusual on purpose
is accepted with ``check = False`` in the reader (the scene and configuration key ``accept_unusual_profile``).

The rules (stated limits, far from any standard or worn section):

- lateral extent: a rail head profile spans :data:`RAIL_SPAN_MM`, a wheel profile :data:`WHEEL_SPAN_MM`
  (a rail head is about 70 mm wide, a wheel about 130 mm); outside, the lengths are most likely in m or µm;
- height: the profile's vertical extent is at most :data:`MAX_HEIGHT_RATIO` times its lateral extent
  (a spike of a metre is not a rail head);
- orientation: a rail's crown is its highest region, so both ends lie at least :data:`MIN_END_DROP_MM` below
  the highest point; a wheel's flange is its lowest point, on the -y side, at least :data:`MIN_FLANGE_MM`
  below the tread at the middle of the profile;
- corners: consecutive point-to-point segments turn by at most :data:`MAX_TURN_RAD` (a step of 0.5 mm over
  0.001 mm, or a one-point spike, turns by nearly 90 or 180 degrees; a 13 mm gauge-corner radius sampled every
  0.5 mm turns by 0.04 rad; the vertical flange back of a wheel turns smoothly).
"""

from __future__ import annotations

import numpy as np

from wrlayer.errors import InputError

#: Accepted lateral extent (mm) of a rail head profile.
RAIL_SPAN_MM = (20.0, 300.0)
#: Accepted lateral extent (mm) of a wheel profile.
WHEEL_SPAN_MM = (40.0, 400.0)
#: Largest vertical extent of a profile relative to its lateral extent.
MAX_HEIGHT_RATIO = 1.5
#: Smallest drop (mm) of a rail profile's ends below its highest point.
MIN_END_DROP_MM = 0.5
#: Smallest depth (mm) of a wheel's flange below the tread at the middle of the profile.
MIN_FLANGE_MM = 10.0
#: Largest turning angle (rad) between consecutive segments of the profile's points (60 degrees).
MAX_TURN_RAD = np.pi / 3.0

_HINT = ("; set accept_unusual_profile = true (command line: --accept-unusual-profile; Python: accept_unusual=True) "
         "if this is intended")


class ImplausibleProfile(InputError):
    """A profile file whose points do not look like the rail head or wheel it is read as."""

    def __init__(self, what: str, problem: str):
        super().__init__(what, problem + _HINT)


def _check_span(y: np.ndarray, z: np.ndarray, body: str, what: str) -> None:
    span = float(y[-1] - y[0])
    lo, hi = RAIL_SPAN_MM if body == "rail" else WHEEL_SPAN_MM
    width = "a rail head is about 70 mm wide" if body == "rail" else "a wheel profile is about 130 mm wide"
    if span < lo:
        raise ImplausibleProfile(what, f"spans only {span:.4g} mm laterally ({width}): lengths in metres? "
                                       "(set the file's units)")
    if span > hi:
        raise ImplausibleProfile(what, f"spans {span:.4g} mm laterally ({width}): lengths in micrometres or "
                                       "a whole section?")
    height = float(z.max() - z.min())
    if height > MAX_HEIGHT_RATIO * span:
        i = int(np.argmax(np.abs(z - np.median(z))))
        raise ImplausibleProfile(what, f"is {height:.4g} mm high over a {span:.4g} mm width (a spike at "
                                       f"y = {y[i]:.4g} mm, z = {z[i]:.4g} mm?)")


def _check_orientation(y: np.ndarray, z: np.ndarray, body: str, what: str) -> None:
    top = float(z.max())
    if body == "rail":
        drop = top - max(float(z[0]), float(z[-1]))
        if drop < MIN_END_DROP_MM:
            raise ImplausibleProfile(what, f"an end of the rail profile is within {drop:.3g} mm of its highest "
                                           "point: upside down (z down in the file?) or not a rail head")
        return
    i_low = int(np.argmin(z))
    middle = float(np.interp(0.5 * (y[0] + y[-1]), y, z))
    if middle - float(z[i_low]) < MIN_FLANGE_MM:
        raise ImplausibleProfile(what, f"the lowest point is only {middle - float(z[i_low]):.3g} mm below the "
                                       "tread: no flange, or upside down (z down in the file?)")
    if y[i_low] > 0.5 * (y[0] + y[-1]):
        raise ImplausibleProfile(what, f"the flange (lowest point, y = {y[i_low]:.4g} mm) is on the +y side; "
                                       "the wheel frame has the flange at -y (mirror the file's y)")


def _check_corners(y: np.ndarray, z: np.ndarray, what: str) -> None:
    d = np.column_stack([np.diff(y), np.diff(z)])
    heading = np.arctan2(d[:, 1], d[:, 0])
    turn = np.abs(np.angle(np.exp(1j * np.diff(heading))))
    if turn.size and float(turn.max()) > MAX_TURN_RAD:
        i = int(np.argmax(turn)) + 1
        raise ImplausibleProfile(what, f"turns by {np.degrees(turn[i - 1]):.0f} degrees at point {i + 1} "
                                       f"(y = {y[i]:.6g} mm, z = {z[i]:.6g} mm): a step or a spike")


def check_profile_points(y, z, body: str, what: str) -> None:
    """Raise :class:`ImplausibleProfile` when the points (mm, z up, y increasing) do not look like a ``body``
    ("rail" or "wheel") profile in the project frame."""
    y = np.asarray(y, dtype=float)
    z = np.asarray(z, dtype=float)
    if body not in ("rail", "wheel"):
        raise InputError(what, f"body must be 'rail' or 'wheel', got {body!r}")
    _check_span(y, z, body, what)
    _check_orientation(y, z, body, what)
    _check_corners(y, z, what)


__all__ = ["ImplausibleProfile", "check_profile_points"]
