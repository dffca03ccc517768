"""Numeric CSV inputs are read strictly: BOM, duplicate and unknown columns, field sizes, numbers."""

import numpy as np
import pytest

from wrlayer.csv_input import MAX_FIELD_CHARS, MAX_LINE_CHARS, read_numeric_csv
from wrlayer.errors import InputError

KNOWN = ("lateral_mm", "yaw_rad", "vertical_load_N")


def write(tmp_path, text: str, encoding="utf-8", bom=False):
    f = tmp_path / "cases.csv"
    f.write_bytes((b"\xef\xbb\xbf" if bom else b"") + text.encode(encoding))
    return f


def test_reads_columns_labels_and_comments(tmp_path):
    f = write(tmp_path, "# units: mm, rad\ncase,lateral_mm,yaw_rad\n\na,1.5,0.001\nb,-2,0\n")
    t = read_numeric_csv(f, KNOWN, label="case")
    assert t.columns == ("lateral_mm", "yaw_rad")
    np.testing.assert_array_equal(t.column("lateral_mm"), [1.5, -2.0])
    assert t.labels == ("a", "b")
    assert len(t.sha256) == 64
    assert "rows=2" in repr(t)


def test_bom_does_not_hide_the_first_column(tmp_path):
    t = read_numeric_csv(write(tmp_path, "lateral_mm,yaw_rad\n3,0\n", bom=True), KNOWN)
    assert t.columns[0] == "lateral_mm"
    assert t.column("lateral_mm")[0] == 3.0


def test_duplicate_column_refused(tmp_path):
    with pytest.raises(InputError, match="column 'lateral_mm' appears twice"):
        read_numeric_csv(write(tmp_path, "lateral_mm,lateral_mm\n1,2\n"), KNOWN)


def test_unknown_column_refused_unless_ignored(tmp_path):
    f = write(tmp_path, "lateral_mm,radius_mm\n1,460\n")
    with pytest.raises(InputError, match="unknown column 'radius_mm'.*list it in sweep.ignore_columns"):
        read_numeric_csv(f, KNOWN, ignore_key="sweep.ignore_columns")
    t = read_numeric_csv(f, KNOWN, ignore=("radius_mm",))
    assert t.ignored_columns == ("radius_mm",)


def test_empty_column_name_refused(tmp_path):
    with pytest.raises(InputError, match="empty column name"):
        read_numeric_csv(write(tmp_path, "lateral_mm,\n1,2\n"), KNOWN)


@pytest.mark.parametrize("cell, problem", [("nan", "finite"), ("inf", "finite"), ("1e300", "finite"),
                                           ("3 mm", "not a number"), ("0,", "not a number")])
def test_bad_cells(tmp_path, cell, problem):
    with pytest.raises(InputError, match=f"row 1, column lateral_mm: .*{problem}"):
        read_numeric_csv(write(tmp_path, f"yaw_rad,lateral_mm\n{cell if ',' in cell else '0,' + cell}\n"), KNOWN)


def test_ragged_row(tmp_path):
    with pytest.raises(InputError, match="row 2 has 1 fields, the header 2"):
        read_numeric_csv(write(tmp_path, "lateral_mm,yaw_rad\n1,0\n2\n"), KNOWN)


def test_huge_field_is_a_clear_error(tmp_path):
    with pytest.raises(InputError, match=f"at most {MAX_FIELD_CHARS}"):
        read_numeric_csv(write(tmp_path, "lateral_mm\n" + "1" * 5000 + "\n"), KNOWN)
    with pytest.raises(InputError, match=f"at most {MAX_LINE_CHARS}"):
        read_numeric_csv(write(tmp_path, "lateral_mm\n" + "1" * 200_000 + "\n"), KNOWN)


def test_row_bound_and_empty(tmp_path):
    with pytest.raises(InputError, match="has 3 data rows"):
        read_numeric_csv(write(tmp_path, "lateral_mm\n1\n2\n3\n"), KNOWN, max_rows=2)
    with pytest.raises(InputError, match="header line and at least one data row"):
        read_numeric_csv(write(tmp_path, "lateral_mm\n"), KNOWN)


def test_latin1_refused(tmp_path):
    with pytest.raises(InputError, match="not UTF-8"):
        read_numeric_csv(write(tmp_path, "lateral_mm,yaw_rad # \u00e9\n1,0\n", encoding="latin-1"), KNOWN)
