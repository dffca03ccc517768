"""Rigid wheel/rail contact over a lateral sweep of the wheelset: contact points, rolling radii, contact angles and
the roll angle on both sides (units mm, rad).

Frames and placement are those of :mod:`contact.wheel_rail.track_geometry` (track frame: Y towards the right rail,
Z up; each side computed in its side frame, the rail's profile coordinate positive towards its field side, the
wheel's profile coordinate y = S). At every lateral displacement y of the wheelset (no yaw unless given):

- the roll angle phi at which both wheels touch their rails when the rigid wheelset is lowered
  (:func:`contact.wheel_rail.deformed.rigid_roll`; positive lifting the right wheel), or phi = 0 with
  ``with_roll = False`` (each wheel then lowered onto its rail on its own, as the wear loop's Delta r);
- per side, the first contact point of :func:`contact.wheel_rail.contact_search.search_contacts` (the candidate of
  smallest normal gap): rail and wheel profile coordinates, track-frame position, contact angle gamma (side frame:
  positive where the rail normal leans towards the track centre, i.e. on the gauge side; both sides alike), the
  rolling radius r = nominal_radius - z_wheel(y_wheel), and the gap of the next candidate (NaN if there is none; a
  small value warns of a near two-point contact).

Derived functions (EN 15302:2021 names them; its text was not available): Delta r(y) = r_right - r_left,
Delta tan gamma(y) = tan gamma_right - tan gamma_left, and the roll angle parameter sigma(y) = e0 phi(y) / y (the
wheelset roll coefficient of the linear theory, phi = sigma y / e0 (Wickens, Fundamentals of Rail Vehicle
Dynamics, 2003); NaN at y = 0). e0 and r0 are half the lateral distance between the two contact points and the mean
rolling radius at the centred position (y = 0, or the sweep position nearest to it).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field, fields

import numpy as np

from contact.geometry.defaults import DEFAULT_STEP_MM
from contact.wheel_rail.contact_search import SearchSettings, search_contacts
from contact.wheel_rail.deformed import rigid_roll
from contact.wheel_rail.track_geometry import PlacedRail, TrackLayout, WheelsetPose, place_rail, side_sign
from meshes.profiles import Profile
from wrlayer.errors import InputError



@dataclass(frozen=True, eq=False)
class WheelsetProfiles:
    """The profiles of a wheelset on its track: the right side's rail and wheel and, when they differ, the left
    side's (None: the right side's, a mirror-symmetric wheelset)."""

    rail: Profile
    wheel: Profile
    left_rail: Profile | None = None
    left_wheel: Profile | None = None

    def side(self, side: str) -> tuple[Profile, Profile]:
        """(rail, wheel) of ``side``."""
        if side_sign(side) > 0:
            return self.rail, self.wheel
        return self.left_rail or self.rail, self.left_wheel or self.wheel


@dataclass(frozen=True)
class SideContact:
    """First contact point of one side (mm, rad; see the module docstring)."""

    y_rail_mm: float
    y_wheel_mm: float
    Y_mm: float
    Z_mm: float
    contact_angle_rad: float
    rolling_radius_mm: float
    next_gap_mm: float


@dataclass(frozen=True)
class ContactState:
    """Both sides' first contacts of the rigid wheelset at one pose (lateral mm, yaw and roll rad)."""

    lateral_mm: float
    yaw_rad: float
    roll_rad: float
    right: SideContact
    left: SideContact


@dataclass(frozen=True, eq=False)
class SideSweep:
    """One side over the sweep: the fields of :class:`SideContact` as arrays (n,)."""

    y_rail_mm: np.ndarray
    y_wheel_mm: np.ndarray
    Y_mm: np.ndarray
    Z_mm: np.ndarray
    contact_angle_rad: np.ndarray
    rolling_radius_mm: np.ndarray
    next_gap_mm: np.ndarray

    @classmethod
    def of(cls, contacts: list[SideContact]) -> SideSweep:
        return cls(*(np.array([getattr(c, f.name) for c in contacts]) for f in fields(SideContact)))


@dataclass(frozen=True, eq=False)
class LateralSweep:
    """Rigid contact of both sides at every lateral displacement (arrays (n,), mm and rad)."""

    lateral_mm: np.ndarray
    yaw_rad: float
    roll_rad: np.ndarray
    right: SideSweep
    left: SideSweep
    e0_mm: float = field(init=False)
    r0_mm: float = field(init=False)

    def __post_init__(self):
        i = int(np.argmin(np.abs(self.lateral_mm)))
        object.__setattr__(self, "e0_mm", 0.5 * float(self.right.Y_mm[i] - self.left.Y_mm[i]))
        object.__setattr__(self, "r0_mm", 0.5 * float(self.right.rolling_radius_mm[i] + self.left.rolling_radius_mm[i]))

    @property
    def delta_r_mm(self) -> np.ndarray:
        """Rolling-radius difference r_right - r_left (mm)."""
        return self.right.rolling_radius_mm - self.left.rolling_radius_mm

    @property
    def delta_tan_gamma(self) -> np.ndarray:
        """tan gamma_right - tan gamma_left (-)."""
        return np.tan(self.right.contact_angle_rad) - np.tan(self.left.contact_angle_rad)

    @property
    def roll_parameter(self) -> np.ndarray:
        """sigma = e0 phi / y (-), NaN at y = 0."""
        y = self.lateral_mm
        with np.errstate(divide="ignore", invalid="ignore"):
            return np.where(y != 0.0, self.e0_mm * self.roll_rad / np.where(y != 0.0, y, 1.0), np.nan)


def _side_contact(rail: PlacedRail, wheel: Profile, layout: TrackLayout, pose: WheelsetPose, side: str,
                  settings: SearchSettings) -> SideContact:
    found = search_contacts(rail, wheel, layout, pose.for_side(side), settings,
                            case=f"geometry at lateral {pose.lateral_mm:g} mm, {side} wheel")
    order = sorted(found.candidates, key=lambda c: c.normal_gap_mm)
    first = order[0]
    next_gap = order[1].normal_gap_mm - first.normal_gap_mm if len(order) > 1 else math.nan
    s = side_sign(side)
    return SideContact(first.y_rail_mm, first.y_wheel_mm, s * first.Y_mm, first.Z_mm, first.contact_angle_rad,
                       first.wheel_radius_mm, next_gap)


def contact_state(rails: tuple[PlacedRail, PlacedRail], profiles: WheelsetProfiles, layout: TrackLayout,
                  lateral_mm: float, yaw_rad: float = 0.0, with_roll: bool = True,
                  settings: SearchSettings | None = None) -> ContactState:
    """Both sides' first contacts at one lateral displacement; ``rails``: the placed (right, left) rails."""
    settings = settings or SearchSettings()
    pose = WheelsetPose(float(lateral_mm), float(yaw_rad), 0.0)
    if with_roll:
        roll = rigid_roll(rails[0], profiles.wheel, layout, pose, settings,
                          left=(rails[1], profiles.side("left")[1]))
        pose = WheelsetPose(pose.lateral_mm, pose.yaw_rad, roll)
    right = _side_contact(rails[0], profiles.wheel, layout, pose, "right", settings)
    left = _side_contact(rails[1], profiles.side("left")[1], layout, pose, "left", settings)
    return ContactState(pose.lateral_mm, pose.yaw_rad, pose.roll_rad, right, left)


def place_rails(profiles: WheelsetProfiles, layout: TrackLayout) -> tuple[PlacedRail, PlacedRail]:
    """The (right, left) rails placed in their side frames."""
    right = place_rail(profiles.rail, layout)
    return right, (right if profiles.left_rail is None else place_rail(profiles.left_rail, layout))


def lateral_positions(lateral_min_mm: float, lateral_max_mm: float, step_mm: float = DEFAULT_STEP_MM) -> np.ndarray:
    """Lateral displacements lateral_min..lateral_max (mm) at ``step_mm``, always including 0 when inside."""
    for key, v in (("lateral_min_mm", lateral_min_mm), ("lateral_max_mm", lateral_max_mm), ("step_mm", step_mm)):
        if not math.isfinite(v):
            raise InputError(key, f"must be a finite number of mm, got {v!r}")
    if not step_mm > 0.0:
        raise InputError("step_mm", f"must be > 0 mm, got {step_mm:g}")
    if not lateral_max_mm > lateral_min_mm:
        raise InputError("lateral_max_mm", f"{lateral_max_mm:g} mm must exceed lateral_min_mm {lateral_min_mm:g} mm")
    n = int(round((lateral_max_mm - lateral_min_mm) / step_mm))
    if n > 20000:
        raise InputError("step_mm", f"{n + 1} lateral positions (at most 20001): use a larger step")
    y = np.linspace(lateral_min_mm, lateral_max_mm, n + 1)
    return np.unique(np.r_[y, 0.0]) if lateral_min_mm < 0.0 < lateral_max_mm else y


def lateral_sweep(profiles: WheelsetProfiles, layout: TrackLayout, lateral_mm: np.ndarray, yaw_rad: float = 0.0,
                  with_roll: bool = True, settings: SearchSettings | None = None) -> LateralSweep:
    """:func:`contact_state` at every lateral displacement (mm, strictly increasing)."""
    y = np.asarray(lateral_mm, dtype=float)
    if y.ndim != 1 or y.size < 2 or np.any(np.diff(y) <= 0.0):
        raise InputError("lateral_mm", "needs at least two strictly increasing lateral displacements")
    rails = place_rails(profiles, layout)
    states = [contact_state(rails, profiles, layout, v, yaw_rad, with_roll, settings) for v in y]
    return LateralSweep(y, float(yaw_rad), np.array([s.roll_rad for s in states]),
                        SideSweep.of([s.right for s in states]), SideSweep.of([s.left for s in states]))


__all__ = ["DEFAULT_STEP_MM", "ContactState", "LateralSweep", "SideContact", "SideSweep", "WheelsetProfiles",
           "contact_state", "lateral_positions", "lateral_sweep", "place_rails"]
