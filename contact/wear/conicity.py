"""Rolling-radius difference and equivalent conicity of the current profiles (rigid contact, units mm, rad).

For a wheelset displaced laterally by ``y`` (towards the right rail, no yaw, no roll) each wheel is lowered onto
its rail and the rolling radius of its first contact point is taken
(:func:`contact.wheel_rail.contact_search.first_contact_radius`: the search's first contact without the
candidates' separation functions), with the track gauge and rail inclination of the scene's layout.
Delta r(y) = r_right(y) - r_left(y) (mm); roll is neglected (it changes the rolling radii in second order only).

Reported per profile state, at the amplitude ``A`` (``wear.conicity_amplitude_mm``, default 3 mm):

- ``delta_r_mm`` = Delta r(A) and the quasi-conicity Delta r(A) / (2 A): the simplest estimate at one point;
- ``equivalent_conicity``: EN 15302's harmonic linearisation of the whole function Delta r on [-A, A]
  (:func:`contact.geometry.conicity.harmonic_conicity`, ``N_PHI`` = 64 points per period), which is
  the quantity wheel-wear studies follow. The nodes y = A sin(phi_k) come in +- pairs, so one period needs
  32 distinct displacements; with one simulated side the left wheel is the mirrored right one,
  r_left(y) = r_right(-y), and each displacement costs one contact search.
"""

from __future__ import annotations

from dataclasses import asdict, dataclass

import numpy as np

from contact.wheel_rail.contact_search import SearchSettings, first_contact_radius
from contact.geometry.conicity import harmonic_conicity
from contact.wheel_rail.track_geometry import PlacedRail, TrackLayout, WheelsetPose, place_rail
from meshes.profiles import Profile


def rolling_radius(rail: Profile, wheel: Profile, layout: TrackLayout, side: str, lateral_mm: float,
                   settings: SearchSettings | None = None) -> float:
    """Rolling radius (mm) of the first contact of one wheel at wheelset lateral displacement ``lateral_mm``."""
    return _placed_rolling_radius(place_rail(rail, layout), wheel, layout, side, lateral_mm, settings)


def _placed_rolling_radius(rail: PlacedRail, wheel: Profile, layout: TrackLayout, side: str, lateral_mm: float,
                           settings: SearchSettings | None) -> float:
    """:func:`rolling_radius` on a rail already placed in the track."""
    pose = WheelsetPose(lateral_mm, 0.0, 0.0).for_side(side)
    return first_contact_radius(rail, wheel, layout, pose, settings or SearchSettings(),
                                case=f"rolling radius at lateral {lateral_mm:g} mm, {side} wheel")


@dataclass(frozen=True)
class RadiusDifference:
    """Rolling-radius difference and equivalent conicity at one lateral amplitude (result.json ``conicity``).

    Attributes
    ----------
    delta_r_mm : float
        r_right - r_left at the amplitude (mm).
    quasi_conicity : float
        delta_r / (2 amplitude) (-).
    r_right_mm : float
        Rolling radius of the right wheel at the amplitude (mm).
    r_left_mm : float
        Rolling radius of the left wheel at the amplitude (mm).
    equivalent_conicity : float
        Equivalent conicity after EN 15302, harmonic linearisation of Delta r(y) on [-amplitude, amplitude] (-).
    amplitude_mm : float
        Lateral amplitude of both (mm), ``wear.conicity_amplitude_mm``.
    """

    delta_r_mm: float
    quasi_conicity: float
    r_right_mm: float
    r_left_mm: float
    equivalent_conicity: float = float("nan")
    amplitude_mm: float = float("nan")

    def to_dict(self) -> dict[str, float]:
        return asdict(self)


class RadiusFunction:
    """Delta r(y) (mm) of one profile state, each wheel's rolling radius searched once per displacement."""

    def __init__(self, profiles: dict, layout: TrackLayout, settings: SearchSettings | None = None):
        """``profiles[side] = {"rail": ..., "wheel": ...}``; a side not simulated takes the other side's profiles
        (mirror-symmetric wheelset)."""
        right = profiles.get("right") or profiles["left"]
        left = profiles.get("left") or profiles["right"]
        self.sides = {"right": right, "left": left}
        self.layout, self.settings = layout, settings
        self._cache: dict[tuple[int, float], float] = {}
        self._placed: dict[int, PlacedRail] = {}  # each side's rail placed once (32 searches per state)

    def radius(self, side: str, lateral_mm: float) -> float:
        """Rolling radius (mm) of ``side`` at the wheelset displacement ``lateral_mm``."""
        pair = self.sides[side]
        # the same profiles on both sides: the left wheel at y is the right wheel at -y (cached once)
        y = round(float(lateral_mm), 9)  # A sin(phi) and A sin(pi - phi) may differ in the last bit
        key = (id(pair), y if side == "right" else -y)
        if key not in self._cache:
            if id(pair) not in self._placed:
                self._placed[id(pair)] = place_rail(pair["rail"], self.layout)
            self._cache[key] = _placed_rolling_radius(self._placed[id(pair)], pair["wheel"], self.layout, side,
                                                      lateral_mm, self.settings)
        return self._cache[key]

    def __call__(self, y_mm: np.ndarray) -> np.ndarray:
        return np.array([self.radius("right", y) - self.radius("left", y) for y in np.asarray(y_mm, float)])


def radius_difference(profiles: dict, layout: TrackLayout, amplitude_mm: float,
                      settings: SearchSettings | None = None) -> RadiusDifference:
    """Delta r at +amplitude and the equivalent conicity on [-amplitude, amplitude]; ``profiles[side] =
    {"rail": ..., "wheel": ...}``; a side not simulated takes the other side's profiles."""
    delta_r = RadiusFunction(profiles, layout, settings)
    rr, rl = delta_r.radius("right", amplitude_mm), delta_r.radius("left", amplitude_mm)
    dr = rr - rl
    return RadiusDifference(dr, dr / (2.0 * amplitude_mm), rr, rl, harmonic_conicity(delta_r, amplitude_mm),
                            float(amplitude_mm))


__all__ = ["RadiusDifference", "RadiusFunction", "radius_difference", "rolling_radius"]
