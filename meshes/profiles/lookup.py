"""A profile by standard name or from a file: :func:`load_profile` (lengths in mm, frames in
:mod:`meshes.profiles.base`)."""

from __future__ import annotations

import inspect
from pathlib import Path

from meshes.profiles.base import Profile
from meshes.profiles.rail_heads import Rail54E1, Rail60E1
from meshes.profiles.s1002 import S1002
from wrlayer.errors import InputError

__all__ = ["BUILTIN_PROFILES", "PROFILE_FILE_SUFFIXES", "PROFILE_UNITS", "get_profile", "load_profile", "named_profile"]

#: Standard profiles by upper-case name.
BUILTIN_PROFILES = {
    "S1002": S1002,
    "60E1": Rail60E1,
    "UIC60": Rail60E1,
    "54E1": Rail54E1,
    "UIC54": Rail54E1,
}
#: Suffixes of the profile files :func:`load_profile` reads (SIMPACK .prr/.prw, two-column .txt/.csv, MiniProf
#: .whl/.ban).
PROFILE_FILE_SUFFIXES = (".prr", ".prw", ".txt", ".csv", ".whl", ".ban")
#: Length units of a profile file, in mm per unit (the readers' ``units`` option; the ``units`` key of every input
#: that names a profile file).
PROFILE_UNITS = {"mm": 1.0, "m": 1000.0}


def load_profile(name: str | Path, **kw) -> Profile:
    """A profile by standard name or from a file.

    Parameters
    ----------
    name : str or pathlib.Path
        "S1002" (EN 13715 wheel), "60E1"/"UIC60" or "54E1"/"UIC54" (EN 13674-1 rail), case-insensitive; or the
        path of a profile file ending in .prr/.prw (SIMPACK), .txt/.csv (two columns y, z) or .whl/.ban (MiniProf).
    **kw
        Options of the standard profile's constructor (e.g. ``r0`` of S1002, the nominal wheel radius in mm) or of
        the file reader (:func:`meshes.profiles.io.read_profile`: ``units`` ("mm" default, or "m"), ``body``,
        ``name``, ``accept_unusual``; text: ``z_down``; MiniProf: ``mirror_y``, ``y_offset_mm``, ``z_down``).

    Returns
    -------
    Profile
        z(y) in mm (rail: material below, crown at (0, 0); wheel: y = S, z = -F(S), material above).

    Raises
    ------
    InputError
        For an unknown name or suffix, an option the profile does not take, or a bad file.
    """
    key = str(name).strip().upper()
    if key in BUILTIN_PROFILES:
        allowed = set(inspect.signature(BUILTIN_PROFILES[key]).parameters)
        if set(kw) - allowed:
            raise InputError("profile", f"{name} does not take option(s) {sorted(set(kw) - allowed)}; "
                                        f"it takes {sorted(allowed) or 'none'}")
        return BUILTIN_PROFILES[key](**kw)
    path = Path(str(name))
    if path.suffix.lower() in PROFILE_FILE_SUFFIXES:
        # the file readers are imported here: the standard profiles do not need them
        from meshes.profiles.io import read_profile

        return read_profile(path, **kw)
    raise InputError("profile", f"unknown profile {name!r}; valid names: {', '.join(BUILTIN_PROFILES)}, "
                                f"or a file path ending in {', '.join(PROFILE_FILE_SUFFIXES)}")


#: The same as :func:`load_profile` (the name used by the scene and configuration readers).
get_profile = load_profile


def named_profile(name: str | Path, body: str | None = None, units: str | None = None,
                  accept_unusual: bool = False) -> Profile:
    """The profile an input names: a standard name, or a profile file read with ``units`` ("mm" or "m"; None: mm
    for text, CSV and MiniProf files, the header's ``units.len.f`` for SIMPACK files) and without the plausibility
    checks when ``accept_unusual``. The file options do not apply to a standard profile (it has no file unit).
    ``body`` ("rail" or "wheel"), when given, must be the profile's. Raises InputError."""
    if str(name).strip().upper() in BUILTIN_PROFILES:
        prof = load_profile(name)
    else:
        options = {"body": body, "units": units, "accept_unusual": accept_unusual or None}
        prof = load_profile(name, **{k: v for k, v in options.items() if v is not None})
    if body is not None and prof.body != body:
        raise InputError("profile", f"{prof.name} is a {prof.body} profile, expected a {body} profile")
    return prof
