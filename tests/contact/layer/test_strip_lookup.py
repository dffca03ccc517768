"""The per-strip table lookup shared by the scenes and the wheel–rail solver: clamping, caching, coverage."""

import numpy as np
import pytest

from wrlayer.characteristic import Characteristic
from contact.layer.strip_lookup import check_coverage, clamped_characteristics
from wrlayer.errors import InputError, LayerNotCovered


class Table:
    """A table over y in [-2, 3] mm whose characteristic stiffens with y; counts its reads."""

    y_range_mm = (-2.0, 3.0)

    def __init__(self):
        self.reads = []

    def characteristic_at(self, y_mm, patch_mm=None):
        if not -2.0 <= y_mm <= 3.0:
            raise InputError("table", f"y = {y_mm} outside")
        self.reads.append((y_mm, patch_mm))
        scale = 1.0 if patch_mm is None else patch_mm[0]
        return Characteristic(np.array([0.0, 0.01 * scale]), np.array([0.0, 100.0 + y_mm]))


def test_coordinates_outside_the_table_take_its_end_value_and_are_flagged():
    table = Table()
    chars, clamped = clamped_characteristics(table, np.array([-5.0, -2.0, 0.5, 0.5, 4.0]), "layers.rail")
    assert clamped.tolist() == [True, False, False, False, True]
    assert [float(c.p_MPa[-1]) for c in chars] == [98.0, 98.0, 100.5, 100.5, 103.0]
    assert [y for y, _ in table.reads] == [-2.0, 0.5, 3.0]   # each distinct (clamped) y read once


def test_patch_size_reaches_the_table():
    table = Table()
    chars, _ = clamped_characteristics(table, np.array([0.0]), "w", patch_mm=(2.0, 1.0))
    assert table.reads == [(0.0, (2.0, 1.0))] and float(chars[0].u_mm[-1]) == pytest.approx(0.02)


def test_a_table_error_names_the_layer():
    class Broken(Table):
        def characteristic_at(self, y_mm, patch_mm=None):
            raise InputError("positions", "a failed position")

    with pytest.raises(InputError, match=r"^layers.wheel \(t.json\): positions: a failed position"):
        clamped_characteristics(Broken(), np.array([0.0]), "layers.wheel (t.json)")


def test_coverage_of_the_strips_in_contact():
    check_coverage(Table(), np.array([-2.0, 3.0]), "layer.rail.table", "rail", "t.json")
    check_coverage(Table(), np.array([]), "layer.rail.table", "rail", "t.json")
    check_coverage(Table(), np.array([3.0 + 1e-10]), "layer.rail.table", "rail", "t.json", tolerance_mm=1e-9)
    with pytest.raises(LayerNotCovered, match=r"^layer.rail.table: does not cover the contact location: the patch "
                                              r"spans y = 1..3.5 mm on the rail, the table t.json covers -2..3 mm"):
        check_coverage(Table(), np.array([1.0, 3.5]), "layer.rail.table", "rail", "t.json")
