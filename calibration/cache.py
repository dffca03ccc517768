"""Cache entries of a calibration run (``OUT/cache/*.json``), validated against their schema before use.

An entry that is missing, unreadable, not JSON, or valid JSON of the wrong shape (``{}``, a string where a list of
numbers belongs, a NaN, a characteristic that is not concave) is reported as invalid and recomputed by the
pipeline, never used and never a traceback. Units as in the entries (mm, MPa, s).
"""

from __future__ import annotations

import json
import math
from dataclasses import MISSING, fields
from pathlib import Path
from typing import Any

from wrlayer import validate
from wrlayer.errors import InputError


def _read_json(path: Path) -> tuple[Any, str | None]:
    try:
        return json.loads(path.read_text(encoding="utf-8")), None
    except FileNotFoundError:
        return None, "missing"
    except (OSError, UnicodeDecodeError, json.JSONDecodeError) as err:
        return None, f"not readable JSON ({err})"
    except RecursionError:
        return None, "nested too deeply"


def check_indentation(data: Any, what: str) -> dict:
    """Validate a FEM cache entry (the dict of :class:`calibration.indentation.IndentationResult`): every field
    present with its type (lists flat and finite, p_MPa with >= 2 values); InputError naming the field."""
    from calibration.indentation import IndentationResult

    validate.table(data, what)
    names = [f.name for f in fields(IndentationResult)]
    validate.check_known(data, names, what)
    for f in fields(IndentationResult):
        key = validate.join(what, f.name)
        if f.name not in data:
            if f.default is not MISSING or f.default_factory is not MISSING:  # a field with a default may be absent
                continue
            raise InputError(key, "missing")
        value = data[f.name]
        kind = f.type if isinstance(f.type, str) else getattr(f.type, "__name__", str(f.type))
        if value is None and "None" in kind:
            continue
        if f.name == "files":
            if not isinstance(value, list) or not all(isinstance(v, str) for v in value):
                raise InputError(key, "must be a list of file names")
        elif kind.startswith("list"):
            validate.number_list(value, key, min_len=2 if f.name in ("p_MPa", "u_fem_mm", "u_pl_mm") else 0)
        elif kind.startswith("dict"):
            for name, item in validate.table(value, key).items():
                validate.number_list(item, f"{key}.{name}", min_len=0)
        elif kind.startswith("int"):
            validate.integer(value, key, ge=0)
        elif kind.startswith("str"):
            validate.text(value, key)
        else:
            validate.number(value, key)
    n = len(data["p_MPa"])
    for name in ("u_fem_mm", "u_pl_mm"):
        if len(data[name]) != n:
            raise InputError(validate.join(what, name), f"has {len(data[name])} values, p_MPa has {n}")
    if len(data["residual_fem_mm"]) != len(data["unload_peaks_MPa"]):
        raise InputError(validate.join(what, "residual_fem_mm"), "length differs from unload_peaks_MPa")
    if not data["halfspace_compliance_mm_per_MPa"] > 0:
        raise InputError(validate.join(what, "halfspace_compliance_mm_per_MPa"), "must be > 0")
    return data


def check_fit_entry(entry: Any, y_mm: float, what: str) -> dict:
    """Validate a fit cache entry (a layer-table position as made by ``fit_position``) for position ``y_mm``."""
    from contact.layer.layer_table import LayerTable

    validate.table(entry, what)
    for key in ("max_error_mm", "y_mm"):
        validate.number(entry.get(key), validate.join(what, key))
    if not math.isclose(float(entry["y_mm"]), float(y_mm), rel_tol=0, abs_tol=1e-9):
        raise InputError(validate.join(what, "y_mm"), f"is {entry['y_mm']!r}, expected {y_mm!r}")
    points = validate.table(entry.get("fem_points"), validate.join(what, "fem_points"))
    validate.number_list(points.get("u_mm"), validate.join(what, "fem_points.u_mm"), min_len=1)
    validate.number_list(entry.get("residual_error_mm"), validate.join(what, "residual_error_mm"), min_len=0)
    LayerTable({"body": "rail", "profile": "cache"}, [entry], [], what)  # the characteristic and its parameters
    return entry


def load_indentation(path: Path) -> tuple[dict | None, str | None]:
    """(entry, None) for a valid FEM cache entry at ``path``, else (None, why it is not usable)."""
    data, why = _read_json(path)
    if why:
        return None, why
    try:
        return check_indentation(data, path.name), None
    except InputError as err:
        return None, str(err)


def load_fit(path: Path, y_mm: float) -> tuple[dict | None, str | None]:
    """(entry, None) for a valid fit cache entry of position ``y_mm`` at ``path``, else (None, why not)."""
    data, why = _read_json(path)
    if why:
        return None, why
    try:
        return check_fit_entry(data, y_mm, path.name), None
    except InputError as err:
        return None, str(err)


__all__ = ["check_fit_entry", "check_indentation", "load_fit", "load_indentation"]
