"""The files a wheel–rail scene names: profiles, calibration tables and sweep CSVs, found relative to the scene file
or in the shared reference folder (``reference:`` names).

Every reader raises :class:`wrlayer.errors.InputError` naming ``what`` (``<file>: <section>.<key>``).
"""

from __future__ import annotations

import hashlib
import os
from pathlib import Path

from contact.layer.layer_table import LayerTable
from meshes.profiles import Profile, get_profile
from wrlayer.errors import InputError

#: Profile file suffixes a scene may name (anything else is a standard profile name).
PROFILE_SUFFIXES = (".prr", ".prw", ".txt", ".csv")


def reference_dir() -> Path:
    """The shared reference folder: ``$WRLAYER_REFERENCE`` or ``<repo>/../shared/reference``."""
    env = os.environ.get("WRLAYER_REFERENCE")
    return Path(env) if env else Path(__file__).resolve().parents[2].parent / "shared" / "reference"


def resolve_path(name: str, base: Path) -> Path:
    """A file named in a scene: ``reference:REL`` is REL inside :func:`reference_dir`, anything else is relative to
    the scene file's folder ``base``."""
    if name.startswith("reference:"):
        return reference_dir() / name[len("reference:"):]
    return base / name


def file_sha256(path: Path) -> str:
    """sha256 of a file's bytes (hex)."""
    return hashlib.sha256(Path(path).read_bytes()).hexdigest()


def read_profile(name: str, base: Path, body: str, what: str) -> Profile:
    """The ``body`` ("rail" or "wheel") profile a scene names: a standard name or a profile file."""
    candidate = resolve_path(name, base)
    target = str(candidate) if candidate.suffix.lower() in PROFILE_SUFFIXES else name
    if target != name and not candidate.is_file():
        raise InputError(what, f"no such profile file {name!r} (looked at {candidate})")
    try:
        prof = get_profile(target, body=body) if Path(target).suffix.lower() in (".txt", ".csv") \
            else get_profile(target)
    except InputError as err:
        raise InputError(what, str(err)) from None
    if prof.body != body:
        raise InputError(what, f"{prof.name} is a {prof.body} profile, expected a {body} profile")
    return prof


def read_layer_table(rel: str, base: Path, body: str, what: str) -> tuple[Path, LayerTable]:
    """The ``body`` calibration table a scene names (relative to the scene's folder): (resolved path, table)."""
    path = (base / rel).resolve()
    if not path.is_file():
        raise InputError(what, f"no such calibration table {rel!r} (looked at {path})")
    try:
        table = LayerTable.read(path)
    except InputError as err:
        raise InputError(what, str(err)) from None
    if table.body != body:
        raise InputError(what, f"{rel} is a {table.body} table, expected a {body} table")
    return path, table


__all__ = ["PROFILE_SUFFIXES", "file_sha256", "read_layer_table", "read_profile", "reference_dir", "resolve_path"]
