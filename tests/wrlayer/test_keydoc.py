"""wrlayer.keydoc: key tables from dataclasses and their numpydoc Attributes sections; the docs' blocks."""

from __future__ import annotations

import sys
from dataclasses import dataclass, field

import pytest

from wrlayer import keydoc
from wrlayer.errors import InputError


@dataclass(frozen=True)
class Inner:
    """Inner settings.

    Attributes
    ----------
    depth_mm : float
        Depth below the surface (mm).
    """

    depth_mm: float = 1.5
    label: str = "a"


@dataclass(frozen=True)
class Outer:
    """Outer settings, with a nested table and a second section after the attributes.

    Attributes
    ----------
    force_N : float
        Normal force (N),
        paper eq. (9).
    steps : tuple of float
        Load steps | as multiples of p_y (-).
    inner : Inner
        Nested table.

    Notes
    -----
    force_N : not an attribute
        This belongs to the Notes section.
    """

    force_N: float
    steps: tuple[float, ...] = (1.5, 2.0)
    flag: bool = True
    tolerance_mm: float = 1e-6
    cells: int | None = None
    inner: Inner = Inner()
    maybe: Inner | None = None
    names: list[str] = field(default_factory=lambda: ["x"])
    _private: int = 0


def test_attribute_descriptions_joins_the_indented_lines_and_stops_at_the_next_section():
    described = keydoc.attribute_descriptions(Outer)
    assert described == {"force_N": "Normal force (N), paper eq. (9).",
                         "steps": "Load steps | as multiples of p_y (-).", "inner": "Nested table."}


def test_a_class_without_attributes_section_has_no_descriptions():
    @dataclass
    class Bare:
        """Only a summary."""

        x: int = 1

    assert keydoc.attribute_descriptions(Bare) == {}
    assert keydoc.key_rows(Bare) == [("x", "int", "1", "")]


def test_rows_give_key_type_default_and_description_with_nested_dataclasses_expanded():
    rows = keydoc.key_rows(Outer, "load.")
    assert rows == [
        ("load.force_N", "float", "required", "Normal force (N), paper eq. (9)."),
        ("load.steps", "tuple[float, ...]", "[1.5, 2.0]", "Load steps | as multiples of p_y (-)."),
        ("load.flag", "bool", "true", ""),
        ("load.tolerance_mm", "float", "1e-6", ""),
        ("load.cells", "int | None", "unset", ""),
        ("load.inner.depth_mm", "float", "1.5", "Depth below the surface (mm)."),
        ("load.inner.label", "str", '"a"', ""),
        ("load.maybe.depth_mm", "float", "1.5", "Depth below the surface (mm)."),
        ("load.maybe.label", "str", '"a"', ""),
        ("load.names", "list[str]", '["x"]', ""),
    ]


def test_table_escapes_pipes_and_has_a_header():
    table = keydoc.key_table(Inner)
    assert table.splitlines()[:2] == ["| key | type | default | description |", "|---|---|---|---|"]
    assert "| `depth_mm` | `float` | `1.5` | Depth below the surface (mm). |" in table
    assert "| `label` | `str` | `\"a\"` |  |" in table
    outer = keydoc.key_table(Outer)
    assert "| `cells` | `int \\| None` | unset |" in outer and "| required |" in outer and "Load steps \\| as multiples" in outer
    assert all(line.count("|") - line.count("\\|") == 5 for line in outer.splitlines())


def test_render_blocks_replaces_only_the_block_body():
    module = sys.modules[__name__].__name__
    text = (f"# Page\n\nintro\n<!-- keys: {module}.Inner mesh. -->\nstale\n<!-- /keys -->\nafter\n"
            f"<!-- keys: {module}.Inner -->\n<!-- /keys -->\n")
    out = keydoc.render_blocks(text)
    assert out.startswith("# Page\n\nintro\n<!-- keys: ")
    assert "stale" not in out and out.endswith("<!-- /keys -->\n")
    assert "| `mesh.depth_mm` |" in out and "| `depth_mm` |" in out
    assert keydoc.render_blocks(out) == out


@pytest.mark.parametrize("target", ["nosuchmodule_xyz.Thing", "wrlayer.keydoc.NoSuchClass", "Bare"])
def test_unknown_classes_are_input_errors(target):
    with pytest.raises(InputError, match="keys block"):
        keydoc.render_blocks(f"<!-- keys: {target} -->\n<!-- /keys -->\n", "page.md")


def test_not_a_dataclass_and_unclosed_blocks_are_input_errors():
    with pytest.raises(InputError, match="not a dataclass"):
        keydoc.render_blocks("<!-- keys: wrlayer.errors.InputError -->\n<!-- /keys -->\n")
    with pytest.raises(InputError, match="without"):
        keydoc.render_blocks("<!-- keys: wrlayer.keydoc.X -->\nno end\n")


def test_cli_check_and_rewrite(tmp_path, capsys):
    module = sys.modules[__name__].__name__
    page = tmp_path / "sub" / "page.md"
    page.parent.mkdir()
    page.write_text(f"<!-- keys: {module}.Inner x. -->\nold\n<!-- /keys -->\n", encoding="utf-8")
    (tmp_path / "other.txt").write_text("<!-- keys: nosuch.X -->\n", encoding="utf-8")  # not markdown: ignored
    assert keydoc.main([str(tmp_path), "--check"]) == 1
    assert "out of date" in capsys.readouterr().out
    assert "old" in page.read_text(encoding="utf-8")
    assert keydoc.main([str(tmp_path)]) == 0
    assert "| `x.depth_mm` |" in page.read_text(encoding="utf-8")
    assert keydoc.main([str(tmp_path), "--check"]) == 0
    assert keydoc.main([str(tmp_path / "missing")]) == 2


def test_a_section_table_shows_each_keys_unit_and_bounds():
    """Fields declared with wrlayer.section_keys.key get a column with their unit and bounds; a subclass inherits
    its bases' descriptions."""
    from wrlayer.section_keys import key

    @dataclass(frozen=True)
    class Section:
        """A section.

        Attributes
        ----------
        force_N : float
            Normal force (N).
        """

        force_N: float = key(10.0, "N", gt=0.0, le=1e6)
        mode: str = key("a", choices=("a", "b"))

    @dataclass(frozen=True)
    class Extended(Section):
        """More keys."""

        cells: int = key(60, ge=2)

    table = keydoc.key_table(Extended, "load.")
    assert table.splitlines()[0] == "| key | type | default | unit, bounds | description |"
    assert "| `load.force_N` | `float` | `10.0` | N, > 0, <= 1e+06 | Normal force (N). |" in table
    assert '| `load.mode` | `str` | `"a"` | one of "a", "b" |  |' in table
    assert "| `load.cells` | `int` | `60` | >= 2 |  |" in table


@dataclass(frozen=True)
class WithDerived:
    """A section with a value its reader derives.

    Attributes
    ----------
    radius_mm : float
        A key (mm).
    derived : float
        Computed by the reader, not a key.
    """

    radius_mm: float = 1.0
    derived: float | None = field(default=None, metadata={keydoc.NOT_A_KEY: True})


def test_derived_fields_are_not_keys():
    table = keydoc.key_table(WithDerived, "s.")
    assert "`s.radius_mm`" in table and "derived" not in table
