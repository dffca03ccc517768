"""The cache of a calibration run (``OUT/cache/*.json``): FEM results (:class:`IndentationResult`, file
``<key>.json``) and fits (:class:`PositionFit`, file ``fit-<key>.json``), read back through their typed
``from_dict``.

Entries are read through the safe reader of inputs (:func:`wrlayer.input_files.read_text`): an entry that is
missing, not a regular file (a folder, a FIFO, a device such as a link to ``/dev/zero``, a socket), a
symbolic-link loop or a dangling link, larger than :data:`wrlayer.input_files.MAX_DATA_BYTES`, unreadable
(permissions), not UTF-8 JSON, or valid JSON of the wrong shape (``{}``, a string where a list of numbers
belongs, a NaN, a characteristic that is not concave) is reported as unusable and recomputed by the pipeline,
never used, never a hang, an ``out of memory`` or a traceback; writing the new entry replaces whatever was there
(the link itself, not its target). Units as in the entries (mm, MPa, s).
"""

from __future__ import annotations

import json
import shutil
from pathlib import Path
from typing import Any

from calibration.results import IndentationResult, PositionFit
from wrlayer.atomic_write import atomic_write_text
from wrlayer.errors import InputError
from wrlayer.input_files import MAX_DATA_BYTES, read_text
from wrlayer.layer_table import LayerTable


def fem_entry(cache: Path, key: str) -> Path:
    """The cache file of the FEM result with cache key ``key``."""
    return cache / f"{key}.json"


def fit_entry(cache: Path, key: str) -> Path:
    """The cache file of the fit with cache key ``key``."""
    return cache / f"fit-{key}.json"


def entry_exists(path: Path) -> bool:
    """True when something is at ``path`` (also a FIFO, a device, a dangling link or a link loop, which
    :meth:`pathlib.Path.exists` calls absent): the entry is then read and, if unusable, reported."""
    return path.exists() or path.is_symlink()


def read_json_entry(path: Path) -> tuple[Any, str | None]:
    """(the JSON of the cache entry at ``path``, None), or (None, why it is not usable) through the safe reader."""
    if not entry_exists(path):
        return None, "missing"
    try:
        text = read_text(path, MAX_DATA_BYTES, path.name)  # no FIFO, device, link loop or oversize file
    except InputError as err:
        return None, err.problem
    try:
        return json.loads(text), None
    except json.JSONDecodeError as err:
        return None, f"not readable JSON ({err})"
    except RecursionError:
        return None, "nested too deeply"


def load_indentation(path: Path) -> tuple[IndentationResult | None, str | None]:
    """(result, None) for a usable FEM cache entry at ``path``, else (None, why it is not usable)."""
    data, why = read_json_entry(path)
    if why:
        return None, why
    try:
        return IndentationResult.from_dict(data, path.name), None
    except InputError as err:
        return None, str(err)


def load_fit(path: Path, y_mm: float) -> tuple[PositionFit | None, str | None]:
    """(fit, None) for a usable fit cache entry of position ``y_mm`` at ``path``, else (None, why not). The
    characteristic and its parameters are checked as a layer table checks them."""
    data, why = read_json_entry(path)
    if why:
        return None, why
    try:
        fit = PositionFit.from_dict(data, path.name)
        fit.check_position(y_mm, path.name)
        LayerTable({"body": "rail", "profile": "cache"}, [data], [], path.name)
        return fit, None
    except InputError as err:
        return None, str(err)


def save_entry(path: Path, record) -> Path:
    """Write ``record`` (a typed record with ``to_dict``: :class:`IndentationResult`, :class:`PositionFit`, a
    section's elastic solution) as the cache entry ``path`` (atomically), replacing a folder or file of the wrong
    kind."""
    if path.is_dir() and not path.is_symlink():
        shutil.rmtree(path)
    return atomic_write_text(path, json.dumps(record.to_dict()))


__all__ = ["entry_exists", "fem_entry", "fit_entry", "load_fit", "load_indentation", "read_json_entry", "save_entry"]
