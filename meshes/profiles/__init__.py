"""Public API for rail and wheel profiles (lengths in mm, frames in :mod:`meshes.profiles.base`).

    from meshes.profiles import load_profile, S1002, Rail60E1, Rail54E1, SplineProfile, Profile

- :func:`load_profile` (alias ``get_profile``): by name ("S1002", "60E1"/"UIC60", "54E1"/"UIC54") or file path;
  :func:`named_profile`: the profile an input names, with the file's ``units`` and ``accept_unusual``.
- :class:`S1002`: EN 13715 wheel (sections A..H), y = S, z = -F(S).
- :class:`Rail60E1`, :class:`Rail54E1`: EN 13674-1 rail heads from arcs (crown at (0, 0)).
- :class:`SplineProfile`: a C2 spline through points, e.g. read from a SIMPACK or text file.
- :class:`Profile`: the piecewise z(y) they all are (:mod:`~meshes.profiles.base`), built from curve pieces
  (:mod:`~meshes.profiles.pieces`); :class:`Line`, :class:`Arc`, :class:`PointCurve`: the exact outline segments
  handed to the mesher (:mod:`~meshes.profiles.segments`).
- :mod:`~meshes.profiles.io`: SIMPACK, text and MiniProf (:mod:`~meshes.profiles.miniprof`) profile files, each with
  a ``units`` argument (mm or m); :mod:`~meshes.profiles.placement`: rails and wheels
  placed in the track frame.

Depends on: wrlayer.
"""

from __future__ import annotations

from meshes.profiles.base import Profile
from meshes.profiles.lookup import (
    BUILTIN_PROFILES,
    PROFILE_FILE_SUFFIXES,
    PROFILE_UNITS,
    get_profile,
    load_profile,
    named_profile,
)
from meshes.profiles.rail_heads import Rail54E1, Rail60E1, RailHead, RailHeadDimensions
from meshes.profiles.s1002 import S1002
from meshes.profiles.segments import Arc, Line, PointCurve, Segment, check_closed, outline_area
from meshes.profiles.spline import SplineProfile

__all__ = [
    "BUILTIN_PROFILES",
    "PROFILE_FILE_SUFFIXES",
    "PROFILE_UNITS",
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
    "load_profile",
    "named_profile",
    "outline_area",
]
