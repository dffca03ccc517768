"""Markdown key tables generated from dataclasses, and the docs' generated blocks.

A scene, configuration or result dataclass documents its keys in a numpydoc ``Attributes`` section::

    Attributes
    ----------
    normal_force_N : float
        Normal force on the contact (N), paper eq. (9).

:func:`key_table` renders one markdown row per field: the key (a caller's section prefix such as ``load.`` plus
the field name), its type, its default (``required`` when it has none) and the description from that section
(empty where the class has no entry; a subclass inherits its bases' entries). Fields that are dataclasses themselves
are expanded with a dotted prefix; fields with ``metadata={NOT_A_KEY: True}`` (values a reader derives) are left
out. A section whose fields declare their keys (:func:`wrlayer.section_keys.key`)
gets a column with each key's unit and bounds.

In a markdown page, a block::

    <!-- keys: contact.scenes.sections.LoadSpec load. -->
    ...
    <!-- /keys -->

is replaced by the table of ``contact.scenes.sections.LoadSpec`` with the prefix ``load.`` (the prefix is optional).
``python -m wrlayer.keydoc docs/`` rewrites every such block in the pages under the given folders or files;
``--check`` rewrites nothing and exits 1 when a block is out of date. An unknown class or a malformed block is an
:class:`~wrlayer.errors.InputError` (exit 2).
"""

from __future__ import annotations

import argparse
import dataclasses
import importlib
import inspect
import math
import re
import sys
import types
import typing
from pathlib import Path

from wrlayer.errors import InputError, cli_guard
from wrlayer.section_keys import NOT_A_KEY, key_facts, key_spec

#: A generated block: the opening comment with the class path and an optional prefix, the body, the closing comment.
BLOCK = re.compile(r"(<!-- keys: *(?P<target>[A-Za-z_][\w.]*)(?: +(?P<prefix>\S+))? *-->\n)(?P<body>.*?)(<!-- /keys -->)",
                   re.S)
#: A numpydoc section underline (a line of dashes under the section title).
_UNDERLINE = re.compile(r"^\s*-{3,}\s*$")
#: A numpydoc entry line: ``name : type`` (the type is optional).
_ENTRY = re.compile(r"^(?P<name>[A-Za-z_]\w*)\s*(?::\s*(?P<type>.*))?$")
HEADER = "| key | type | default | description |\n|---|---|---|---|\n"
#: The header of a section whose fields declare their unit and bounds.
SECTION_HEADER = "| key | type | default | unit, bounds | description |\n|---|---|---|---|---|\n"


def attribute_descriptions(cls: type) -> dict[str, str]:
    """``{field name: one-line description}`` from the ``Attributes`` section of ``cls``'s docstring.

    An entry is a ``name : type`` line at the section's indentation followed by indented description lines, which
    are joined with single spaces. A class without the section gives ``{}``.
    """
    doc = inspect.cleandoc(cls.__doc__ or "")
    lines = doc.splitlines()
    start = None
    for i in range(len(lines) - 1):
        if lines[i].strip() == "Attributes" and _UNDERLINE.match(lines[i + 1]):
            start = i + 2
            break
    if start is None:
        return {}
    out: dict[str, str] = {}
    name, base = None, None
    for i in range(start, len(lines)):
        line = lines[i]
        if i + 1 < len(lines) and line.strip() and _UNDERLINE.match(lines[i + 1]):
            break  # the next section's title
        if not line.strip():
            continue
        indent = len(line) - len(line.lstrip())
        if base is None:
            base = indent
        entry = _ENTRY.match(line.strip()) if indent == base else None
        if entry:
            name = entry.group("name")
            out[name] = ""
        elif name is not None and indent > base:
            out[name] = (out[name] + " " + line.strip()).strip()
    return out


def _type_text(f: dataclasses.Field) -> str:
    """The field's annotation as written (``from __future__ import annotations`` keeps it a string)."""
    if isinstance(f.type, str):
        return f.type
    return getattr(f.type, "__name__", str(f.type)).replace("typing.", "")


def _default_text(f: dataclasses.Field) -> str:
    if f.default is not dataclasses.MISSING:
        return format_value(f.default)
    if f.default_factory is not dataclasses.MISSING:
        return format_value(f.default_factory())
    return "required"


def format_value(value) -> str:
    """A default as it is written in a TOML file (``true``, ``"three"``, ``[1.5, 2.0]``); None as ``unset``."""
    if value is None:
        return "unset"
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, str):
        return f'"{value}"'
    if isinstance(value, float):
        if math.isinf(value) or math.isnan(value):
            return str(value)
        return re.sub(r"e([+-])0*(\d)", r"e\1\2", repr(value)).replace("e+", "e")
    if isinstance(value, (tuple, list)):
        return "[" + ", ".join(format_value(v) for v in value) + "]"
    if isinstance(value, dict):
        return "{" + ", ".join(f"{k} = {format_value(v)}" for k, v in value.items()) + "}"
    if dataclasses.is_dataclass(value):
        return "(table)"
    return str(value)


def _nested_dataclass(cls: type, f: dataclasses.Field) -> type | None:
    """The dataclass a field holds (also ``X | None``), or None. Unresolvable annotations count as not nested."""
    try:
        hint = typing.get_type_hints(cls).get(f.name)
    except Exception:  # a forward reference only a type checker resolves: render the field as a plain key
        hint = None
    if hint is None:
        return None
    candidates = typing.get_args(hint) if isinstance(hint, types.UnionType) or typing.get_origin(hint) is typing.Union \
        else (hint,)
    found = [c for c in candidates if isinstance(c, type) and dataclasses.is_dataclass(c)]
    return found[0] if len(found) == 1 else None


def described_attributes(cls: type) -> dict[str, str]:
    """:func:`attribute_descriptions` of ``cls`` and its bases (the class's own entry wins)."""
    out: dict[str, str] = {}
    for klass in reversed(cls.__mro__):
        out.update({k: v for k, v in attribute_descriptions(klass).items() if v or k not in out})
    return out


def key_rows(cls: type, prefix: str = "") -> list[tuple[str, str, str, str]]:
    """``(key, type, default, description)`` per field of dataclass ``cls``, nested dataclasses expanded."""
    return [row[:4] for row in _rows(cls, prefix)]


def _rows(cls: type, prefix: str = "") -> list[tuple[str, str, str, str, str]]:
    """:func:`key_rows` with each key's unit and bounds (:func:`wrlayer.section_keys.key_facts`) appended."""
    if not (isinstance(cls, type) and dataclasses.is_dataclass(cls)):
        raise InputError(getattr(cls, "__qualname__", repr(cls)), "is not a dataclass")
    described = described_attributes(cls)
    rows = []
    for f in dataclasses.fields(cls):
        if f.name.startswith("_") or f.metadata.get(NOT_A_KEY):
            continue
        nested = _nested_dataclass(cls, f)
        if nested is not None:
            rows.extend(_rows(nested, f"{prefix}{f.name}."))
            continue
        rows.append((f"{prefix}{f.name}", _type_text(f), _default_text(f), described.get(f.name, ""), key_facts(f)))
    return rows


def _cell(text: str) -> str:
    return text.replace("|", "\\|").replace("\n", " ")


def _default_cell(default: str) -> str:
    """A default as code, except the words ``required`` and ``unset``."""
    return default if default in ("required", "unset") else f"`{_cell(default)}`"


def key_table(cls: type, prefix: str = "") -> str:
    """The markdown table of ``cls``'s keys (header, separator and one row per key, each line ending in a newline)."""
    rows = _rows(cls, prefix)
    if not any(any(key_spec(f) for f in dataclasses.fields(c)) for c in _classes(cls)):
        return HEADER + "".join(f"| `{_cell(key)}` | `{_cell(kind)}` | {_default_cell(default)} | {_cell(text)} |\n"
                                for key, kind, default, text, _ in rows)
    return SECTION_HEADER + "".join(
        f"| `{_cell(key)}` | `{_cell(kind)}` | {_default_cell(default)} | {_cell(facts)} | {_cell(text)} |\n"
        for key, kind, default, text, facts in rows)


def _classes(cls: type) -> list[type]:
    """``cls`` and the dataclasses nested in its fields."""
    nested = [n for f in dataclasses.fields(cls) if (n := _nested_dataclass(cls, f)) is not None]
    return [cls] + [c for n in nested for c in _classes(n)]


def resolve(target: str) -> type:
    """``package.module.ClassName`` -> the class (InputError when it cannot be imported)."""
    module_name, _, class_name = target.rpartition(".")
    if not module_name:
        raise InputError(target, "expected package.module.ClassName")
    try:
        module = importlib.import_module(module_name)
    except ImportError as err:
        raise InputError(target, f"cannot import {module_name}: {err}") from None
    cls = getattr(module, class_name, None)
    if cls is None:
        raise InputError(target, f"{module_name} has no {class_name}")
    return cls


def render_blocks(text: str, where: str = "<text>") -> str:
    """``text`` with every keys block's body replaced by its generated table."""

    def replace(match: re.Match) -> str:
        try:
            table = key_table(resolve(match.group("target")), match.group("prefix") or "")
        except InputError as err:
            raise InputError(f"{where}: keys block {match.group('target')}", err.problem) from None
        return match.group(1) + table + match.group(5)

    rendered = BLOCK.sub(replace, text)
    if rendered.count("<!-- keys:") != rendered.count("<!-- /keys -->"):
        raise InputError(where, "a '<!-- keys: ... -->' block without its '<!-- /keys -->' (or the reverse)")
    return rendered


def markdown_files(paths: list[str]) -> list[Path]:
    """The ``*.md`` files among ``paths`` (folders searched recursively), sorted."""
    found: list[Path] = []
    for name in paths:
        path = Path(name)
        if path.is_dir():
            found.extend(sorted(path.rglob("*.md")))
        elif path.is_file():
            found.append(path)
        else:
            raise InputError(name, "no such file or folder")
    return found


def update(paths: list[str], check: bool = False) -> list[Path]:
    """Regenerate the blocks in the pages under ``paths``; returns the pages that were (``check``: would be)
    changed. With ``check`` nothing is written."""
    changed = []
    for page in markdown_files(paths):
        text = page.read_text(encoding="utf-8")
        rendered = render_blocks(text, str(page))
        if rendered != text:
            changed.append(page)
            if not check:
                page.write_text(rendered, encoding="utf-8")
    return changed


@cli_guard
def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(
        prog="python -m wrlayer.keydoc",
        description="Regenerate the key tables between '<!-- keys: package.module.Class prefix -->' and "
                    "'<!-- /keys -->' in markdown pages from the dataclasses' Attributes docstrings.",
        epilog="example: python -m wrlayer.keydoc docs/ --check. Exit codes: 0 up to date (or rewritten), "
               "1 --check found a block out of date, 2 bad input (unknown class, malformed block).")
    parser.add_argument("paths", nargs="+", help="markdown files or folders (searched for *.md)")
    parser.add_argument("--check", action="store_true", help="write nothing; exit 1 if a block is out of date")
    args = parser.parse_args(argv)
    changed = update(args.paths, check=args.check)
    for page in changed:
        print(f"{'out of date' if args.check else 'rewritten'}: {page}")
    return 1 if (args.check and changed) else 0


if __name__ == "__main__":
    sys.exit(main())
