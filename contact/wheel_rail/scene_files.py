"""The files a wheel–rail scene names: profiles and sweep CSVs, found relative to the scene file or in the shared
reference folder (``reference:`` names); calibration tables: :func:`wrlayer.layer_table.read_body_table`.

Every reader raises :class:`wrlayer.errors.InputError` naming ``what`` (``<file>: <section>.<key>``).
"""

from __future__ import annotations

from pathlib import Path

from meshes.profiles import PROFILE_FILE_SUFFIXES, Profile, named_profile
from wrlayer.errors import InputError
from wrlayer.input_files import REFERENCE_PREFIX, reference_dir, resolve_reference

#: Profile file suffixes a scene may name (anything else is a standard profile name): the readers' suffixes.
PROFILE_SUFFIXES = PROFILE_FILE_SUFFIXES


def resolve_path(name: str, base: Path, what: str) -> Path:
    """A file named in a scene: ``reference:REL`` is REL in the shared reference folder
    (:func:`wrlayer.input_files.resolve_reference`: ``$WRLAYER_REFERENCE``, else beside the repository; a missing
    file is an InputError naming both), anything else is relative to the scene file's folder ``base``."""
    if name.startswith(REFERENCE_PREFIX):
        return resolve_reference(name, what)
    return base / name


def read_profile(name: str, base: Path, body: str, what: str, accept_unusual: bool = False,
                 units: str | None = None) -> Profile:
    """The ``body`` ("rail" or "wheel") profile a scene names: a standard name or a profile file in ``units``
    ("mm", "m"; None: the reader's default), checked for plausibility unless ``accept_unusual``
    (:func:`meshes.profiles.named_profile`)."""
    candidate = resolve_path(name, base, what)
    is_file = candidate.suffix.lower() in PROFILE_SUFFIXES
    if is_file and not candidate.is_file():
        raise InputError(what, f"no such profile file {name!r} (looked at {candidate})")
    try:
        return named_profile(candidate if is_file else name, body, units, accept_unusual)
    except InputError as err:
        raise InputError(what, err.problem if err.what == "profile" else str(err)) from None


__all__ = ["PROFILE_SUFFIXES", "read_profile", "reference_dir", "resolve_path"]
