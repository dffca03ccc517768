"""Result JSON of a contact scene: units, code version, JSON conversion, typed records and atomic writing.

Strict JSON is written (no NaN/Infinity: non-finite numbers become null); numpy arrays become lists. Results are
frozen dataclasses deriving from :class:`Record` (``to_dict``/``to_json``/``from_dict``), converted to JSON only
when written.
"""

from __future__ import annotations

import dataclasses
import json
import math
import types
import typing
from pathlib import Path
from typing import Any

import numpy as np

from wrlayer.atomic_write import atomic_write_text
from wrlayer.version import code_version  # noqa: F401  (re-exported: results record it)

RESULT_NAME = "result.json"
#: File-name patterns of the pictures of :mod:`contact.scenes.plots` (stale ones are removed by the command line).
PICTURE_PATTERNS = ("patch_pass*.png", "separation.png", "shakedown.png")

#: Units of the result fields (keys without a unit suffix are listed here too).
UNITS = {
    "length": "mm", "force": "N", "stress": "MPa (N/mm^2)", "time": "s", "speed": "mm/s",
    "layer_stiffness": "N/mm^3", "spin": "1/mm", "creepage": "-",
    "WT_max": "N/mm (= N mm/mm^2: frictional work per unit area over one pass, FASTSIM)",
    "PT_max_W_per_mm2": "W/mm^2 (frictional power density at speed_mm_s)",
    "Mz_Nmm": "N mm (spin moment about the patch origin, on body 1)",
    "Fx_N, Fy_N": "N (creep forces on body 1 = the wheel; Kalker's sign convention)",
    "u0_mm": "mm (layer displacement at the reference point under load, both layers)",
    "up0_mm": "mm (residual layer displacement at the reference point added by this pass)",
    "timings": "s (wall clock)",
    "dissipated_energy_max_N_per_mm": "N/mm (= N mm/mm^2: largest accumulated slider friction work of an element)",
}


def jsonable(obj: Any) -> Any:
    """Plain JSON data from numpy values, paths, dataclasses, tuples; non-finite floats -> None."""
    if isinstance(obj, dict):
        return {str(k): jsonable(v) for k, v in obj.items()}
    if isinstance(obj, (list, tuple)):
        return [jsonable(v) for v in obj]
    if isinstance(obj, np.ndarray):
        return jsonable(obj.tolist())
    if isinstance(obj, (bool, np.bool_)):
        return bool(obj)
    if isinstance(obj, (int, np.integer)):
        return int(obj)
    if isinstance(obj, (float, np.floating)):
        value = float(obj)
        return value if math.isfinite(value) else None
    if isinstance(obj, Path):
        return str(obj)
    if dataclasses.is_dataclass(obj) and not isinstance(obj, type):
        return jsonable({f.name: getattr(obj, f.name) for f in dataclasses.fields(obj)})
    if obj is None or isinstance(obj, str):
        return obj
    raise TypeError(f"cannot write {type(obj).__name__} to the result JSON")


class Record:
    """Plain-data conversion of a frozen dataclass whose field names are its JSON keys: :meth:`to_dict` (nested
    records, tuples as lists, dicts of records), :meth:`to_json`, :meth:`from_dict` (the inverse, from the field
    types). A field with ``metadata={"key": name}`` is written under that key (a key that is not a Python name);
    ``metadata={"omit_none": True}``: left out when None; fields that are not compared (``compare=False``: derived
    objects) are not written."""

    def to_dict(self) -> dict[str, Any]:
        out = {}
        for f in dataclasses.fields(self):
            value = getattr(self, f.name)
            if not f.compare or (value is None and f.metadata.get("omit_none")):
                continue
            out[f.metadata.get("key", f.name)] = plain(value)
        return out

    def to_json(self) -> str:
        """The record as strict, indented JSON text (:func:`result_text`)."""
        return result_text(self.to_dict())

    @classmethod
    def from_dict(cls, data: dict[str, Any]):
        hints = typing.get_type_hints(cls)
        kw = {}
        for f in dataclasses.fields(cls):
            key = f.metadata.get("key", f.name)
            if f.init and f.compare and key in data:
                kw[f.name] = _typed(hints[f.name], data[key])
        return cls(**kw)


def plain(value: Any) -> Any:
    """Plain data of a record field: records as dicts, tuples as lists (recursively)."""
    if isinstance(value, Record):
        return value.to_dict()
    if isinstance(value, (tuple, list)):
        return [plain(v) for v in value]
    if isinstance(value, dict):
        return {k: plain(v) for k, v in value.items()}
    return value


def _typed(tp: Any, value: Any) -> Any:
    """``value`` (plain data) as the field type ``tp``: records, tuples, unions with None, dicts of records."""
    if value is None:
        return None
    origin, args = typing.get_origin(tp), typing.get_args(tp)
    if origin in (typing.Union, types.UnionType):
        options = [a for a in args if a is not type(None)]
        return _typed(options[0], value) if len(options) == 1 else value
    if isinstance(tp, type) and issubclass(tp, Record):
        return tp.from_dict(value)
    if origin is tuple:
        if len(args) == 2 and args[1] is Ellipsis:
            return tuple(_typed(args[0], v) for v in value)
        return tuple(_typed(a, v) for a, v in zip(args, value)) if args else tuple(value)
    if origin is dict and len(args) == 2:
        return {k: _typed(args[1], v) for k, v in value.items()}
    return value


def result_text(result: dict[str, Any]) -> str:
    """The result as strict, indented JSON text (ends with a newline)."""
    return json.dumps(jsonable(result), indent=1, allow_nan=False) + "\n"


def write_result(out_dir: str | Path, result: dict[str, Any]) -> Path:
    """Write ``out_dir/result.json`` atomically; returns its path."""
    return atomic_write_text(Path(out_dir) / RESULT_NAME, result_text(result))


def read_result(path: str | Path) -> dict[str, Any]:
    """Read a result JSON written by :func:`write_result` (a file or a folder holding result.json)."""
    path = Path(path)
    if path.is_dir():
        path = path / RESULT_NAME
    return json.loads(path.read_text(encoding="utf-8"))
