"""A short ``repr`` for dataclasses that hold arrays: the scalar fields with their values, every array, long
sequence or mapping of arrays by its shape or length, so that ``print(run.first)`` fits a few lines.

Used as ``__repr__ = short_repr`` in the class body (a dataclass keeps a ``__repr__`` defined there).
"""

from __future__ import annotations

import dataclasses
from typing import Any

import numpy as np

__all__ = ["short_repr", "short_value"]

#: Sequences up to this length are shown element by element (each shortened); longer ones by their length.
SHOWN_ITEMS = 3


def short_value(value: Any) -> str:
    """``value`` in a few characters: numbers to 6 significant digits, arrays as ``array(shape, dtype)``, long
    sequences as ``<n items>``, mappings key by key (values shortened), other objects by their own repr."""
    if isinstance(value, np.ndarray):
        return f"array({value.shape}, {value.dtype})" if value.ndim else short_value(value.item())
    if isinstance(value, (bool, np.bool_)) or value is None:
        return repr(bool(value) if isinstance(value, np.bool_) else value)
    if isinstance(value, (float, np.floating)):
        return f"{float(value):.6g}"
    if isinstance(value, (int, np.integer, str)):
        return repr(value if isinstance(value, str) else int(value))
    if isinstance(value, dict):
        return "{" + ", ".join(f"{k!r}: {short_value(v)}" for k, v in value.items()) + "}"
    if isinstance(value, (list, tuple)):
        if len(value) > SHOWN_ITEMS:
            kinds = sorted({type(v).__name__ for v in value})
            return f"<{len(value)} {'/'.join(kinds)}>"
        inner = ", ".join(short_value(v) for v in value)
        return f"[{inner}]" if isinstance(value, list) else f"({inner}{',' if len(value) == 1 else ''})"
    return repr(value)


def short_repr(obj: Any) -> str:
    """``Type(field=value, ...)`` of a dataclass instance with every value shortened (:func:`short_value`)."""
    fields = ", ".join(f"{f.name}={short_value(getattr(obj, f.name))}"
                       for f in dataclasses.fields(obj) if f.repr)
    return f"{type(obj).__name__}({fields})"
