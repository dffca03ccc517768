"""Where a calibration's rail stands in the track: the rail inclination of a body, resolved once (units rad).

The mating position of a calibration point (:func:`calibration.hertz.geometry.mating_position`) compares the
surface slopes of the rail and the wheel in the track frame, so it needs the angle by which the track tilts the
rail profile's own frame: ``inclination`` (1:n, as the wheel-rail scenes' ``track.inclination``) or
``inclination_rad``. A builtin rail (e.g. "60E1", or its Profile object) is upright in its frame and is canted
1:40 unless told otherwise; a rail read from a file, or built from points (e.g. a worn profile), may already be
canted (e.g. the Manchester
benchmark's ``MBench_UIC60_v3.prr``, canted 1:40 in the file), so its inclination must be given: 0 for a file
already placed as in the track.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

from calibration.hertz.geometry import DEFAULT_RAIL_CANT_RAD
from calibration.settings import BodySettings
from meshes.profiles import BUILTIN_PROFILES
from meshes.profiles.placement import rail_inclination
from wrlayer.errors import InputError

#: Smallest n of an inclination 1:n (as the wheel-rail scenes' track.inclination); 0 means upright.
MIN_INCLINATION_RATIO = 5.0


def inclination_to_rad(ratio: float) -> float:
    """The cant angle (rad) of an inclination 1:ratio (0: upright, 0 rad)."""
    return 0.0 if ratio == 0 else rail_inclination(ratio)


def is_builtin(spec: Any) -> bool:
    """True for a builtin profile: its name, or a Profile object of a builtin profile's class (not one read from
    a file or built from points)."""
    if isinstance(spec, str):
        return spec.strip().upper() in BUILTIN_PROFILES
    return type(spec) in set(BUILTIN_PROFILES.values())


def rail_spec(b: BodySettings) -> Any:
    """The rail of a body's contact: its profile (rail) or its mate (wheel; None without a mate)."""
    return b.profile if b.body == "rail" else b.mate


def cant_rad(b: BodySettings, what: str) -> float:
    """The body's rail inclination (rad): ``inclination_rad``, else ``inclination`` (1:n), else 1:40 for a
    builtin rail (and 0 when there is no rail: given semi-axes). InputError naming ``<what>.inclination`` for a
    rail from a file or a Profile object without either (its placement in the file is not known)."""
    if b.inclination_rad is not None:
        return float(b.inclination_rad)
    if b.inclination is not None:
        return inclination_to_rad(float(b.inclination))
    spec = rail_spec(b)
    if spec is None or b.semi_axes_mm is not None or is_builtin(spec):  # given semi-axes: no mating position
        return DEFAULT_RAIL_CANT_RAD
    name = spec.name if hasattr(spec, "name") else Path(str(spec)).name
    raise InputError(f"{what}.inclination", f"the rail profile {name} is not builtin, so its placement is not known: "
                     "set inclination = 0 if the profile is already canted as in the track (e.g. "
                     "MBench_UIC60_v3.prr), or inclination = 40 (1:40) if it is upright in its file")


__all__ = ["MIN_INCLINATION_RATIO", "cant_rad", "inclination_to_rad", "is_builtin", "rail_spec"]
