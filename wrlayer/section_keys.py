"""Input-file sections as dataclasses whose fields declare their keys once: the unit, the default and the bounds of
each key live in the field's metadata (:func:`key`), and one reader (:func:`read_section`) validates a TOML table
against them with :class:`wrlayer.validate.Keys` (messages ``<file>: <section>.<key>: ...``).

A section field is declared as::

    alpha: float = key(0.55, "-", ge=1e-2, le=1.0)

The field's annotation says what the key holds: ``float``, ``int``, ``bool``, ``str`` (with ``choices``) or one of
them ``| None`` (an optional key whose absence gives None). A key without a default is required. Fields declared
without :func:`key` are not read from the table (derived values, or values a scene reader computes itself).
:func:`key_facts` gives the unit and bounds as text for the generated key tables (:mod:`wrlayer.keydoc`).
"""

from __future__ import annotations

import dataclasses
from dataclasses import MISSING, field
from typing import Any, Callable

from wrlayer.validate import Keys, is_number

#: The metadata entry that marks a field as a key of its section.
KEY = "section_key"
#: The metadata entry that marks a field as a value a reader derives, not a key of the input (left out of the key
#: tables of :mod:`wrlayer.keydoc`).
NOT_A_KEY = "not_a_key"
_BOUNDS = (("gt", ">"), ("ge", ">="), ("lt", "<"), ("le", "<="))


@dataclasses.dataclass(frozen=True)
class KeySpec:
    """What a section's key accepts.

    Attributes
    ----------
    unit : str
        The unit of the value ("mm", "N", "MPa", "s", "rad", "-" for none).
    gt, ge, lt, le : float | None
        Bounds (exclusive/inclusive) of a number or an integer.
    choices : tuple | Callable | None
        Allowed strings, or a function returning them (for lists that live in modules slow to import).
    plausible : str | None
        The quantity of :data:`wrlayer.plausibility.INPUT_RANGES` whose engineering range the value must lie in
        (unless the file sets ``accept_implausible``).
    """

    unit: str = "-"
    gt: float | None = None
    ge: float | None = None
    lt: float | None = None
    le: float | None = None
    choices: tuple[str, ...] | Callable[[], tuple[str, ...]] | None = None
    plausible: str | None = None

    def allowed(self) -> tuple[str, ...] | None:
        return self.choices() if callable(self.choices) else self.choices

    def bounds(self) -> dict[str, float]:
        return {name: getattr(self, name) for name, _ in _BOUNDS if getattr(self, name) is not None}


def key(default: Any = MISSING, unit: str = "-", *, gt: float | None = None, ge: float | None = None,
        lt: float | None = None, le: float | None = None, choices=None, plausible: str | None = None,
        **field_options) -> Any:
    """A dataclass field that is a key of its section (see the module docstring); no default: required."""
    spec = KeySpec(unit, gt, ge, lt, le, choices, plausible)
    return field(default=default, metadata={KEY: spec}, **field_options)


def key_spec(f: dataclasses.Field) -> KeySpec | None:
    """The field's :class:`KeySpec` (None for a field that is not a key)."""
    return f.metadata.get(KEY)


def key_names(cls: type) -> tuple[str, ...]:
    """The keys of a section class, in field order."""
    return tuple(f.name for f in dataclasses.fields(cls) if key_spec(f) is not None)


def key_facts(f: dataclasses.Field) -> str:
    """The unit and bounds of a key as text (``MPa, >= 1, <= 1e+07``; ``one of: a, b``); "" for other fields."""
    spec = key_spec(f)
    if spec is None:
        return ""
    parts = [spec.unit] if spec.unit and spec.unit != "-" else []
    parts += [f"{sign} {getattr(spec, name):g}" for name, sign in _BOUNDS if getattr(spec, name) is not None]
    allowed = spec.allowed()
    if allowed:
        parts.append("one of " + ", ".join(f'"{c}"' for c in allowed))
    return ", ".join(parts)


def _annotation(f: dataclasses.Field) -> str:
    """The field's annotation as written, without spaces (``from __future__ import annotations`` keeps it a
    string)."""
    hint = f.type if isinstance(f.type, str) else getattr(f.type, "__name__", str(f.type))
    return hint.replace(" ", "")


def read_key(keys: Keys, name: str, kind: str, spec: KeySpec, default: Any) -> Any:
    """One key of ``keys`` by its annotation ``kind`` (``float``, ``int``, ``bool``, ``str``, ``X|None``);
    ``default`` MISSING: required."""
    optional = kind.endswith("|None")
    base = kind.removesuffix("|None")
    if optional and name not in keys.table:
        return None if default is MISSING else default
    required = default is MISSING or default is None
    if base == "float":
        return keys.number(name, None if required else default, **spec.bounds())
    if base == "int":
        if required and name not in keys.table:
            raise keys.error(name, "missing (required)")
        return keys.integer(name, None if required else default, ge=spec.ge, le=spec.le)
    if base == "bool":
        if required and name not in keys.table:
            raise keys.error(name, "missing (required)")
        return keys.boolean(name, default)
    if base == "str":
        return keys.text(name, None if required else default, spec.allowed())
    raise TypeError(f"{name}: a section key cannot be of type {kind}")


def read_section(cls: type, keys: Keys, *, required: tuple[str, ...] = (), given: dict[str, Any] | None = None,
                 also_known: tuple[str, ...] = ()):
    """The section ``cls`` read from ``keys``: every key field by its declaration (``required``: keys that have a
    default but must be given in this scene kind); ``given``: field values the caller has read itself (their
    keys, and ``also_known``, are accepted in the table without being read here)."""
    given = dict(given or {})
    names = key_names(cls)
    keys.check_known(names + tuple(k for k in (*given, *also_known) if k not in names))
    values = {}
    for f in dataclasses.fields(cls):
        spec = key_spec(f)
        if f.name in given:
            values[f.name] = given.pop(f.name)
        elif spec is not None:
            default = MISSING if f.name in required else f.default
            plausible = spec.plausible is not None and is_number(keys.table.get(f.name))
            if plausible:       # a unit slip first (it may break a hard bound too), then the bounds, then the range
                keys.plausible(f.name, float(keys.table[f.name]), spec.plausible, slips_only=True)
            values[f.name] = read_key(keys, f.name, _annotation(f), spec, default)
            if plausible:
                keys.plausible(f.name, values[f.name], spec.plausible)
    values.update(given)
    return cls(**values)


__all__ = ["KEY", "NOT_A_KEY", "KeySpec", "key", "key_facts", "key_names", "key_spec", "read_key", "read_section"]
