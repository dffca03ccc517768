"""Rolling-radius difference of the current profiles (rigid contact, units mm).

For a wheelset displaced laterally by ``a`` (towards the right rail, no yaw, no roll) each wheel is lowered onto its
rail (:func:`contact.wheel_rail.contact_search.search_contacts`) and the rolling radius of its first contact
point is taken. Delta r(a) = r_right(a) - r_left(a) (mm). The quasi-conicity Delta r(a) / (2 a) is reported beside
it; it is NOT the EN 15302 equivalent conicity (no harmonic linearisation, roll neglected), only its simplest
estimate at one amplitude, used to follow the profiles' evolution against distance.
"""

from __future__ import annotations

from dataclasses import asdict, dataclass

from contact.wheel_rail.contact_search import SearchSettings, search_contacts
from contact.wheel_rail.track_geometry import TrackLayout, WheelsetPose, place_rail
from meshes.profiles import Profile


def rolling_radius(rail: Profile, wheel: Profile, layout: TrackLayout, side: str, lateral_mm: float,
                   settings: SearchSettings | None = None) -> float:
    """Rolling radius (mm) of the first contact of one wheel at wheelset lateral displacement ``lateral_mm``."""
    pose = WheelsetPose(lateral_mm, 0.0, 0.0).for_side(side)
    found = search_contacts(place_rail(rail, layout), wheel, layout, pose, settings or SearchSettings(),
                            case=f"rolling radius at lateral {lateral_mm:g} mm, {side} wheel")
    first = min(found.candidates, key=lambda c: c.normal_gap_mm)
    return float(first.wheel_radius_mm)


@dataclass(frozen=True)
class RadiusDifference:
    """Rolling-radius difference at one lateral amplitude (result.json ``conicity``).

    Attributes
    ----------
    delta_r_mm : float
        r_right - r_left at the amplitude (mm).
    quasi_conicity : float
        delta_r / (2 amplitude) (-).
    r_right_mm : float
        Rolling radius of the right wheel (mm).
    r_left_mm : float
        Rolling radius of the left wheel (mm).
    """

    delta_r_mm: float
    quasi_conicity: float
    r_right_mm: float
    r_left_mm: float

    def to_dict(self) -> dict[str, float]:
        return asdict(self)


def radius_difference(profiles: dict, layout: TrackLayout, amplitude_mm: float,
                      settings: SearchSettings | None = None) -> RadiusDifference:
    """The rolling-radius difference at +amplitude; ``profiles[side] = {"rail": ..., "wheel": ...}``; a side not
    simulated takes the other side's profiles (mirror-symmetric wheelset)."""
    right = profiles.get("right") or profiles["left"]
    left = profiles.get("left") or profiles["right"]
    rr = rolling_radius(right["rail"], right["wheel"], layout, "right", amplitude_mm, settings)
    rl = rolling_radius(left["rail"], left["wheel"], layout, "left", amplitude_mm, settings)
    dr = rr - rl
    return RadiusDifference(dr, dr / (2.0 * amplitude_mm), rr, rl)


__all__ = ["RadiusDifference", "radius_difference", "rolling_radius"]
