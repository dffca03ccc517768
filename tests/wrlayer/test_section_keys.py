"""One reader for every section: defaults, required keys, bounds, choices, optional keys and values the caller reads
itself, with messages naming <file>: <section>.<key>."""

from __future__ import annotations

from dataclasses import dataclass

import pytest

from wrlayer.errors import InputError
from wrlayer.section_keys import key, key_facts, key_names, read_section
from wrlayer.validate import Keys


@dataclass(frozen=True)
class Section:
    force_N: float = key(unit="N", gt=0.0)
    cells: int = key(60, ge=2, le=100)
    exact_cells: int | None = key(None, ge=1)
    radius_mm: float | None = key(None, "mm")
    vtk: bool = key(True)
    mode: str = key("a", choices=lambda: ("a", "b"))
    derived: float = 0.0


def read(table: dict, **options) -> Section:
    return read_section(Section, Keys("s.toml", "sec", table), **options)


def test_defaults_optional_keys_and_given_values():
    s = read({"force_N": 5.0})
    assert s == Section(5.0, 60, None, None, True, "a", 0.0)
    assert read({"force_N": 1, "exact_cells": 8, "radius_mm": 2, "mode": "b"}).exact_cells == 8
    assert read({"force_N": 1.0, "derived": 3.0}, given={"derived": 3.0}).derived == 3.0
    assert key_names(Section) == ("force_N", "cells", "exact_cells", "radius_mm", "vtk", "mode")


@pytest.mark.parametrize("table, options, message", [
    ({}, {}, "s.toml: sec.force_N: missing (required)"),
    ({"force_N": 1.0}, {"required": ("cells",)}, "s.toml: sec.cells: missing (required)"),
    ({"force_N": 0.0}, {}, "s.toml: sec.force_N: must be > 0, got 0"),
    ({"force_N": 1.0, "cells": 1}, {}, "s.toml: sec.cells: must be >= 2, got 1"),
    ({"force_N": 1.0, "cells": 2.0}, {}, "s.toml: sec.cells: must be an integer"),
    ({"force_N": 1.0, "mode": "c"}, {}, "s.toml: sec.mode: must be one of a, b, got 'c'"),
    ({"force_N": 1.0, "vtk": 1}, {}, "s.toml: sec.vtk: must be true or false"),
    ({"force_N": 1.0, "derived": 1.0}, {}, "s.toml: sec.derived: unknown key"),
    ({"force_N": 1.0, "typo": 1.0}, {"also_known": ("other",)}, "s.toml: sec.typo: unknown key"),
])
def test_problems_name_the_key(table, options, message):
    with pytest.raises(InputError) as err:
        read(table, **options)
    assert str(err.value).startswith(message)


def test_facts_give_unit_bounds_and_choices():
    facts = {f.name: key_facts(f) for f in Section.__dataclass_fields__.values()}
    assert facts["force_N"] == "N, > 0" and facts["cells"] == ">= 2, <= 100"
    assert facts["mode"] == 'one of "a", "b"' and facts["derived"] == ""
