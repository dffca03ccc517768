"""Rolling-radius difference of the current profiles (rigid contact, units mm).

For a wheelset displaced laterally by ``a`` (towards the right rail, no yaw, no roll) each wheel is lowered onto its
rail (:func:`contact.wheel_rail.contact_search.search_contacts`) and the rolling radius of its first contact
point is taken. Delta r(a) = r_right(a) - r_left(a) (mm). The quasi-conicity Delta r(a) / (2 a) is reported beside
it; it is NOT the EN 15302 equivalent conicity (no harmonic linearisation, roll neglected), only its simplest
estimate at one amplitude, used to follow the profiles' evolution against distance.
"""

from __future__ import annotations

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


def radius_difference(profiles: dict, layout: TrackLayout, amplitude_mm: float,
                      settings: SearchSettings | None = None) -> dict:
    """{"delta_r_mm", "quasi_conicity"} at +amplitude; ``profiles[side] = {"rail": ..., "wheel": ...}``; a side
    not simulated takes the other side's profiles (mirror-symmetric wheelset)."""
    right = profiles.get("right") or profiles["left"]
    left = profiles.get("left") or profiles["right"]
    rr = rolling_radius(right["rail"], right["wheel"], layout, "right", amplitude_mm, settings)
    rl = rolling_radius(left["rail"], left["wheel"], layout, "left", amplitude_mm, settings)
    dr = rr - rl
    return {"delta_r_mm": dr, "quasi_conicity": dr / (2.0 * amplitude_mm), "r_right_mm": rr, "r_left_mm": rl}


__all__ = ["radius_difference", "rolling_radius"]
