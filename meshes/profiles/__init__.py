"""Public API for rail and wheel profiles (lengths in mm, frames in :mod:`meshes.profiles.base`).

    from meshes.profiles import (Profile, S1002, Rail60E1, Rail54E1, SplineProfile, get_profile,
                                 Line, Arc, PointCurve)

- :class:`S1002`: EN 13715 wheel (sections A..H), y = S, z = -F(S).
- :class:`Rail60E1`, :class:`Rail54E1`: EN 13674-1 rail heads from arcs (crown at (0, 0)).
- :class:`SplineProfile`: a C2 spline through points, e.g. read from a SIMPACK or text file.
- :func:`get_profile`: by name ("S1002", "60E1"/"UIC60", "54E1"/"UIC54") or by file path.
"""

from __future__ import annotations

import inspect
from pathlib import Path

from wrlayer.errors import InputError
from meshes.profiles.base import (
    Arc,
    Line,
    PointCurve,
    Profile,
    Segment,
    check_closed,
    outline_area,
)
from meshes.profiles.rail_heads import Rail54E1, Rail60E1, RailHead, RailHeadDimensions
from meshes.profiles.s1002 import S1002
from meshes.profiles.spline import SplineProfile

_BUILTIN = {
    "S1002": S1002,
    "60E1": Rail60E1,
    "UIC60": Rail60E1,
    "54E1": Rail54E1,
    "UIC54": Rail54E1,
}
PROFILE_FILE_SUFFIXES = (".prr", ".prw", ".txt", ".csv")


def get_profile(name: str, **kw) -> Profile:
    """A profile by standard name (case-insensitive) or from a file (.prr/.prw/.txt/.csv).

    Keyword arguments go to the constructor (e.g. ``r0`` for S1002) or to the reader
    (:func:`meshes.profiles.io.read_profile`, e.g. ``units``, ``z_down``, ``body``).
    """
    key = str(name).strip().upper()
    if key in _BUILTIN:
        allowed = set(inspect.signature(_BUILTIN[key]).parameters)
        if set(kw) - allowed:
            raise InputError("profile", f"{name} does not take option(s) {sorted(set(kw) - allowed)}; "
                                        f"it takes {sorted(allowed) or 'none'}")
        return _BUILTIN[key](**kw)
    path = Path(str(name))
    if path.suffix.lower() in PROFILE_FILE_SUFFIXES:
        from meshes.profiles.io import read_profile

        return read_profile(path, **kw)
    raise InputError("profile", f"unknown profile {name!r}; valid names: {', '.join(_BUILTIN)}, "
                                f"or a file path ending in {', '.join(PROFILE_FILE_SUFFIXES)}")


__all__ = [
    "S1002",
    "Arc",
    "Line",
    "PointCurve",
    "Profile",
    "Rail54E1",
    "Rail60E1",
    "RailHead",
    "RailHeadDimensions",
    "Segment",
    "SplineProfile",
    "check_closed",
    "get_profile",
    "outline_area",
]
