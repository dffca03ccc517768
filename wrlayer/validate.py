"""One validation layer for every file the tool reads (scenes, wheel–rail scenes, calibration configs, layer
tables, profile files). Units are those of the key names (mm, N, MPa, s, rad).

The rules, shared by all readers:

- a *number* is a finite real: an ``int`` or ``float`` (never a ``bool``, never a string), not NaN or inf, and
  within the key's bounds; :data:`MAX_ABS` bounds every number (no coordinate or load beyond 1e12 mm/N/MPa);
- an *integer* is an ``int`` (not ``bool``, not ``3.0``), within its bounds;
- a *list of numbers* is a FLAT list (no nested lists) of numbers as above, with at least ``min_len`` and at
  most ``max_len`` (default :data:`MAX_LIST`) values;
- a *table* is a mapping; unknown keys are errors (they catch typos);
- every problem is an :class:`~wrlayer.errors.InputError` whose ``what`` is ``<file>: <key path>``, e.g.
  ``scene.toml: layer.u_mm``, and whose message is one short line (long values are abbreviated).

:class:`Keys` is the typed, validating view of one table used by the TOML readers; the free functions do the
same checks for values that are not in a TOML table (JSON tables, profile file headers).
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from wrlayer.errors import InputError

#: Largest magnitude accepted for any number in an input file (mm, N, MPa, ...): larger values are absurd and
#: overflow the squares the solvers form.
MAX_ABS = 1e12
#: Longest list of numbers accepted in an input file (separation tables, characteristics, positions).
MAX_LIST = 100_000
#: Longest text shown from a bad value in a message.
SHOW_CHARS = 60

# Plausible ranges of the contact scene quantities (Kik–Piotrowski and wheel–rail scenes): outside them the solvers
# underflow or ask for absurd grids.
#: Young's modulus (MPa): from soft polymers to beyond tungsten carbide (a 1e-33 MPa modulus asks for a 1e15-cell
#: patch).
MIN_E_MPA, MAX_E_MPA = 1.0, 1e7
#: Rolling radius 1 mm .. 1 km (mm).
MIN_RADIUS_MM, MAX_RADIUS_MM = 1.0, 1e6
#: Lateral radius of a parabolic separation (mm).
MIN_LATERAL_RADIUS_MM = 1e-2
#: Normal force or vertical load (N): 1 mN.
MIN_FORCE_N = 1e-3
#: Kik–Piotrowski's alpha (-).
MIN_ALPHA = 1e-2
#: Strip grid spacing (mm): 1 um.
MIN_GRID_MM = 1e-3
#: Largest number of lateral strips (separation table width / grid_mm) a scene may ask for.
MAX_STRIPS = 20000
#: Largest number of FASTSIM cells per strip (method.fastsim_cells): beyond it the cell arrays alone take GBs.
MAX_FASTSIM_CELLS = 10000
#: Largest passes.max: every pass keeps its record (strip arrays); the paper's shakedown takes 20-50 passes.
MAX_PASSES = 100000


def kind(value: Any) -> str:
    """The TOML/JSON name of a value's type (for messages)."""
    return {bool: "boolean", int: "integer", float: "number", str: "string", list: "list",
            dict: "table"}.get(type(value), type(value).__name__)


def show(value: Any) -> str:
    """``repr(value)`` cut to :data:`SHOW_CHARS` characters (one readable line)."""
    text = repr(value).replace("\n", " ")
    return text if len(text) <= SHOW_CHARS else text[:SHOW_CHARS - 5] + " ...]"


def join(what: str, key: str) -> str:
    """``what`` + key path: ``("a.toml: load", "x")`` -> ``"a.toml: load.x"``; ``("a.toml", "x")`` ->
    ``"a.toml: x"``; list indices (``"[3]"``) are appended without a dot."""
    if not what:
        return key
    if key.startswith("["):
        return what + key
    return f"{what}.{key}" if ": " in what else f"{what}: {key}"


def is_number(value: Any) -> bool:
    """True for an int or float that is not a bool (finiteness not checked)."""
    return isinstance(value, (int, float)) and not isinstance(value, bool)


def _bounds(value: float, what: str, gt, ge, lt, le) -> None:
    checks = ((gt, ">", lambda b: value > b), (ge, ">=", lambda b: value >= b),
              (lt, "<", lambda b: value < b), (le, "<=", lambda b: value <= b))
    for bound, sign, ok in checks:
        if bound is not None and not ok(bound):
            raise InputError(what, f"must be {sign} {bound:g}, got {value:g}")


def number(value: Any, what: str, *, gt: float | None = None, ge: float | None = None, lt: float | None = None,
           le: float | None = None) -> float:
    """A finite real number (int or float, not bool or string, |x| <= MAX_ABS) within the bounds, as float."""
    if not is_number(value):
        raise InputError(what, f"must be a number, got {kind(value)} {show(value)}")
    try:
        value = float(value)
    except OverflowError:  # a huge TOML integer
        raise InputError(what, f"must be a finite number of magnitude <= {MAX_ABS:g}, got a huge integer") from None
    if not math.isfinite(value):
        raise InputError(what, f"must be a finite number, got {value!r}")
    if abs(value) > MAX_ABS:
        raise InputError(what, f"must be of magnitude <= {MAX_ABS:g}, got {value:g}")
    _bounds(value, what, gt, ge, lt, le)
    return value


def integer(value: Any, what: str, *, ge: int | None = None, le: int | None = None) -> int:
    """An integer (not bool, not 3.0) within the bounds."""
    if isinstance(value, bool) or not isinstance(value, int):
        raise InputError(what, f"must be an integer, got {kind(value)} {show(value)}")
    if ge is not None and value < ge:
        raise InputError(what, f"must be >= {ge}, got {value}")
    if le is not None and value > le:
        raise InputError(what, f"must be <= {le}, got {show(value)}")
    return int(value)


def boolean(value: Any, what: str) -> bool:
    """true or false (not 0/1, not a string)."""
    if not isinstance(value, bool):
        raise InputError(what, f"must be true or false, got {kind(value)} {show(value)}")
    return value


def text(value: Any, what: str, choices: tuple[str, ...] | None = None) -> str:
    """A string (one of ``choices`` when given)."""
    if not isinstance(value, str):
        raise InputError(what, f"must be a string, got {kind(value)} {show(value)}")
    if choices is not None and value not in choices:
        raise InputError(what, f"must be one of {', '.join(choices)}, got {show(value)}")
    return value


def number_list(value: Any, what: str, *, min_len: int = 1, max_len: int = MAX_LIST, gt: float | None = None,
                ge: float | None = None, lt: float | None = None, le: float | None = None) -> np.ndarray:
    """A flat list of finite real numbers (see :func:`number`) of length min_len..max_len, as a float array.

    The first offending entry is named by its index, e.g. ``layer.u_mm[3]: must be a number, got list [...]``.
    """
    if not isinstance(value, (list, tuple)):
        raise InputError(what, f"must be a list of numbers, got {kind(value)} {show(value)}")
    if len(value) > max_len:
        raise InputError(what, f"has {len(value)} values (at most {max_len})")
    for i, item in enumerate(value):
        if isinstance(item, (list, tuple, dict)):
            raise InputError(f"{what}[{i}]", f"must be a number (a flat list is expected), got {kind(item)} "
                             f"{show(item)}")
        number(item, f"{what}[{i}]", gt=gt, ge=ge, lt=lt, le=le)
    if len(value) < min_len:
        raise InputError(what, f"needs at least {min_len} values, got {len(value)}")
    return np.asarray(value, dtype=float)


def table(value: Any, what: str) -> dict:
    """A mapping (TOML table / JSON object)."""
    if not isinstance(value, dict):
        raise InputError(what, f"must be a table, got {kind(value)} {show(value)}")
    return value


def check_known(mapping: dict, allowed, what: str) -> None:
    """InputError for the first key of ``mapping`` not in ``allowed``."""
    for key in mapping:
        if key not in allowed:
            raise InputError(join(what, str(key)), f"unknown key (allowed: {', '.join(sorted(allowed))})")


def rewrap(err: InputError, what: str) -> InputError:
    """``err`` re-attributed to ``what`` without naming an input twice (``a.toml: a.toml: ...``): when the
    inner error already names a path that ``what`` ends with or starts with, the inner location is kept."""
    inner = err.what
    if inner == what or inner.startswith((what + ":", what + ".")):
        return InputError(inner, err.problem)
    file = what.split(": ", 1)[0]
    if inner.startswith(file + ": "):
        inner = inner[len(file) + 2:]
    return InputError(what, f"{inner}: {err.problem}" if inner else err.problem)


class Keys:
    """Typed, validating access to one table of an input file.

    ``Keys(file, prefix, table)``: ``file`` is the input file's name, ``prefix`` the key path of the table
    ("" for the top level, e.g. "load" or "layer.rail"). The getters (:meth:`number`, :meth:`integer`,
    :meth:`boolean`, :meth:`text`, :meth:`array`, :meth:`sub`) apply the module's rules and raise
    :class:`~wrlayer.errors.InputError` naming ``<file>: <prefix>.<key>``; :meth:`check_known` rejects unknown
    keys. Raises InputError when ``table`` is not a table. ``accept_implausible`` (the scene's top-level override
    key, carried to every sub-table): :meth:`plausible` lets values outside the engineering ranges pass.
    """

    def __init__(self, file: str, prefix: str, table: Any, accept_implausible: bool = False):
        self.file, self.prefix = file, prefix
        self.accept_implausible = accept_implausible
        if not isinstance(table, dict):
            raise InputError(f"{file}: {prefix}" if prefix else file,
                             f"must be a table ([{prefix}]), got {kind(table)} {show(table)}")
        self.table = table

    def what(self, key: str) -> str:
        """The error location of ``key``: ``<file>: <prefix>.<key>``."""
        return f"{self.file}: {self.prefix}.{key}" if self.prefix else f"{self.file}: {key}"

    def error(self, key: str, problem: str) -> InputError:
        """An InputError for ``key`` (to raise)."""
        return InputError(self.what(key), problem)

    def check_known(self, allowed: tuple[str, ...]) -> None:
        """Raise InputError for the first key of the table not in ``allowed``."""
        for key in self.table:
            if key not in allowed:
                raise self.error(key, f"unknown key (allowed: {', '.join(allowed)})")

    def number(self, key: str, default: float | None = None, *, gt: float | None = None, ge: float | None = None,
               lt: float | None = None, le: float | None = None) -> float:
        """A finite number within the bounds, ``default`` when absent (None: required)."""
        if key not in self.table:
            if default is None:
                raise self.error(key, "missing (required)")
            return default
        return number(self.table[key], self.what(key), gt=gt, ge=ge, lt=lt, le=le)

    def integer(self, key: str, default: int | None, *, ge: int | None = None, le: int | None = None) -> int | None:
        """An integer within the bounds, ``default`` when absent (which may be None: an optional key)."""
        if key not in self.table:
            return default
        return integer(self.table[key], self.what(key), ge=ge, le=le)

    def boolean(self, key: str, default: bool) -> bool:
        """true/false, ``default`` when absent."""
        return boolean(self.table.get(key, default), self.what(key))

    def text(self, key: str, default: str | None = None, choices: tuple[str, ...] | None = None) -> str:
        """A string, ``default`` when absent (None: required); one of ``choices`` when given."""
        if key not in self.table:
            if default is None:
                raise self.error(key, "missing (required)")
            return default
        return text(self.table[key], self.what(key), choices)

    def array(self, key: str, min_len: int = 2, max_len: int = MAX_LIST, **bounds) -> np.ndarray:
        """A required flat list of min_len..max_len finite numbers, as a float array."""
        if key not in self.table:
            raise self.error(key, "missing (required)")
        return number_list(self.table[key], self.what(key), min_len=min_len, max_len=max_len, **bounds)

    def sub(self, key: str) -> Keys | None:
        """The sub-table ``key`` (prefix extended), None when absent."""
        if key not in self.table:
            return None
        return type(self)(self.file, f"{self.prefix}.{key}" if self.prefix else key, self.table[key],
                          self.accept_implausible)

    def plausible_number(self, key: str, quantity: str, default: float | None = None, **bounds) -> float:
        """:meth:`number` checked against the engineering range of ``quantity`` too: a unit slip first (it may
        break a bound: 0.46 m as a radius), then the bounds (clearer for a negative or zero value), then the
        range."""
        if is_number(self.table.get(key)):
            self.plausible(key, float(self.table[key]), quantity, slips_only=True)
        return self.plausible(key, self.number(key, default, **bounds), quantity)

    def plausible(self, key: str, value: float, quantity: str, slips_only: bool = False) -> float:
        """``value`` of ``key`` when it lies in the engineering range of ``quantity``
        (:data:`wrlayer.plausibility.INPUT_RANGES`) or the override is set; else
        :class:`~wrlayer.plausibility.ImplausibleInput` naming the key, the value, the range and the likely slip
        (``slips_only``: only when a unit slip explains the value)."""
        from wrlayer.plausibility import check_input  # here: validate is imported by every reader, first

        return check_input(self.what(key), value, quantity, self.accept_implausible, slips_only)


def top_keys(file: str, data: Any, cls: type[Keys] = Keys) -> Keys:
    """The top-level table of an input file, carrying its ``accept_implausible`` override (a boolean key)."""
    accept = boolean(data.get("accept_implausible", False), f"{file}: accept_implausible") \
        if isinstance(data, dict) else False
    return cls(file, "", data, accept)


__all__ = ["top_keys", "MAX_ABS", "MAX_E_MPA", "MAX_FASTSIM_CELLS", "MAX_LIST", "MAX_PASSES", "MAX_RADIUS_MM", "MAX_STRIPS",
           "MIN_ALPHA", "MIN_E_MPA", "MIN_FORCE_N", "MIN_GRID_MM", "MIN_LATERAL_RADIUS_MM", "MIN_RADIUS_MM", "Keys",
           "boolean", "check_known", "integer", "is_number", "join", "kind", "number", "number_list", "rewrap", "show",
           "table", "text"]
