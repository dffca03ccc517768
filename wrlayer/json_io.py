"""The one JSON converter: plain JSON data from result records, numpy values, paths and containers.

Strict JSON is written (no NaN/Infinity: non-finite numbers become null); numpy arrays become lists. Result
records are frozen dataclasses deriving from :class:`Record` (``to_dict``/``to_json``/``from_dict``), converted
to JSON only when written. Every JSON file of wrlayer (result.json of every scene kind, layer tables) goes
through :func:`jsonable` and :func:`json_text`.
"""

from __future__ import annotations

import dataclasses
import json
import math
import operator
import types
import typing
from pathlib import Path
from typing import Any

import numpy as np

__all__ = ["Layout", "Record", "json_text", "jsonable"]

#: How a record is written where its JSON keys differ from its field names (one record, several result files):
#: ``(JSON key, attribute)`` pairs in the order written, or ``(JSON key, attribute, layout of the attribute's
#: records)``. An attribute may be a property or a dotted path into a nested record (written, not read back).
Layout = tuple[tuple, ...]


def jsonable(obj: Any, layout: Layout | None = None) -> Any:
    """Plain JSON data of ``obj``: records (:class:`Record`, by their JSON keys or ``layout``) and other
    dataclasses as dicts, tuples and arrays as lists, numpy scalars as Python numbers, paths as text; non-finite
    floats -> None. TypeError for anything else."""
    kind = type(obj)
    if kind is float:           # the common leaves first: a record's numbers and names
        return obj if math.isfinite(obj) else None
    if kind is str or kind is int or obj is None:
        return obj
    if isinstance(obj, Record):
        return obj.to_dict(layout)
    if isinstance(obj, dict):
        return {str(k): jsonable(v, layout) for k, v in obj.items()}
    if isinstance(obj, (list, tuple)):
        return [jsonable(v, layout) for v in obj]
    if isinstance(obj, np.ndarray):
        # tolist() already gives Python numbers; only non-finite floats need the element walk
        if obj.dtype.kind in "biu" or (obj.dtype.kind == "f" and np.isfinite(obj).all()):
            return obj.tolist()
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
    raise TypeError(f"cannot write {type(obj).__name__} to JSON")


def json_text(data: Any) -> str:
    """``data`` as strict, indented JSON text (ends with a newline)."""
    return json.dumps(jsonable(data), indent=1, allow_nan=False) + "\n"


class Record:
    """JSON conversion of a frozen dataclass whose field names are its JSON keys: :meth:`to_dict` (the JSON data:
    nested records, tuples as lists, dicts of records), :meth:`to_json`, :meth:`from_dict` (the inverse, from the
    field types). A field with ``metadata={"key": name}`` is written under that key (a key that is not a Python
    name); ``metadata={"omit_none": True}``: left out when None; ``metadata={"layout": ...}``: the field's records
    written in that :data:`Layout`; fields that are not compared (``compare=False``: arrays and derived objects
    kept for the writers) are not written. ``to_dict(layout)``/``from_dict(data, layout)``: in a layout."""

    def to_dict(self, layout: Layout | None = None) -> dict[str, Any]:
        out = {}
        if layout is not None:
            omit = {f.name for f in dataclasses.fields(self) if f.metadata.get("omit_none")}
            for key, attr, *sub in layout:
                value = operator.attrgetter(attr)(self)
                if not (value is None and attr in omit):
                    out[key] = jsonable(value, sub[0] if sub else None)
            return out
        for f in dataclasses.fields(self):
            value = getattr(self, f.name)
            if not f.compare or (value is None and f.metadata.get("omit_none")):
                continue
            out[f.metadata.get("key", f.name)] = jsonable(value, f.metadata.get("layout"))
        return out

    def projected(self, layout: Layout):
        """The record as written in ``layout`` and read back: what a result file keeps of it."""
        return type(self).from_dict(self.to_dict(layout), layout)

    def to_json(self) -> str:
        """The record as strict, indented JSON text (:func:`json_text`)."""
        return json_text(self.to_dict())

    @classmethod
    def from_dict(cls, data: dict[str, Any], layout: Layout | None = None):
        hints = typing.get_type_hints(cls)
        fields = {f.name: f for f in dataclasses.fields(cls)}
        kw = {}
        if layout is not None:
            for key, attr, *sub in layout:
                if attr in fields and fields[attr].init and key in data:
                    kw[attr] = _typed(hints[attr], data[key], sub[0] if sub else None)
            return cls(**kw)
        for f in fields.values():
            key = f.metadata.get("key", f.name)
            if f.init and f.compare and key in data:
                kw[f.name] = _typed(hints[f.name], data[key], f.metadata.get("layout"))
        return cls(**kw)


def _typed(tp: Any, value: Any, layout: Layout | None = None) -> Any:
    """``value`` (plain data) as the field type ``tp``: records (in ``layout``), tuples, unions with None, dicts of
    records."""
    if value is None:
        return None
    origin, args = typing.get_origin(tp), typing.get_args(tp)
    if origin in (typing.Union, types.UnionType):
        options = [a for a in args if a is not type(None)]
        return _typed(options[0], value, layout) if len(options) == 1 else value
    if isinstance(tp, type) and issubclass(tp, Record):
        return tp.from_dict(value, layout)
    if origin is tuple:
        if len(args) == 2 and args[1] is Ellipsis:
            return tuple(_typed(args[0], v, layout) for v in value)
        return tuple(_typed(a, v, layout) for a, v in zip(args, value)) if args else tuple(value)
    if origin is dict and len(args) == 2:
        return {k: _typed(args[1], v, layout) for k, v in value.items()}
    return value
