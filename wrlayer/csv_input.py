"""Strict reading of numeric CSV inputs (sweep cases, load collectives, multibody exports).

One header line names the columns; ``#`` comment lines and blank lines are skipped; one row per case. Read
strictly, because a CSV that is read wrongly gives a silently wrong run:

- the file is opened safely (:mod:`wrlayer.input_files`: regular file, size bounded, UTF-8; a byte-order mark is
  dropped, so that the first column keeps its name);
- a column named twice, an empty column name, or a column that is neither known nor listed as ignored is refused
  (an unknown column is usually a typo or a unit in the name);
- every line is at most :data:`MAX_LINE_CHARS` characters and every field at most :data:`MAX_FIELD_CHARS`;
- every row has the header's number of fields, and every value of a used column is a finite number of magnitude at
  most :data:`wrlayer.validate.MAX_ABS` (no units in cells, no NaN or inf);
- at most ``max_rows`` rows.

Each problem is one :class:`~wrlayer.errors.InputError` naming the file, the row (1 = first data row) and column.
"""

from __future__ import annotations

import csv
import math
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from wrlayer.errors import InputError
from wrlayer.hashing import sha256_hex
from wrlayer.input_files import MAX_CSV_BYTES, decode_utf8, read_bytes
from wrlayer.validate import MAX_ABS

#: Longest line accepted in a CSV input (characters).
MAX_LINE_CHARS = 10_000
#: Longest field accepted in a CSV input (characters).
MAX_FIELD_CHARS = 100


@dataclass(frozen=True)
class CsvTable:
    """The used columns of a numeric CSV input.

    Attributes
    ----------
    file : str
        Path of the file as read.
    sha256 : str
        SHA-256 of the file's bytes (recorded with the results).
    columns : tuple of str
        Names of the used (known) columns, in file order.
    values : numpy.ndarray
        Values, shape (rows, len(columns)), in the units of the column names.
    labels : tuple of str
        The label column's text per row (empty when the file has no label column).
    ignored_columns : tuple of str
        Columns present and ignored on request.
    """

    file: str
    sha256: str
    columns: tuple[str, ...]
    values: np.ndarray
    labels: tuple[str, ...]
    ignored_columns: tuple[str, ...]

    def column(self, name: str) -> np.ndarray:
        """One used column's values (KeyError for a column the file does not have)."""
        return self.values[:, self.columns.index(name)]

    def __repr__(self) -> str:
        return f"CsvTable({Path(self.file).name!r}, columns={self.columns}, rows={self.values.shape[0]})"


def _data_lines(text: str, what: str) -> list[tuple[int, str]]:
    lines = []
    for lineno, line in enumerate(text.splitlines(), start=1):
        if len(line) > MAX_LINE_CHARS:
            raise InputError(what, f"line {lineno} has {len(line)} characters (at most {MAX_LINE_CHARS})")
        if line.strip() and not line.lstrip().startswith("#"):
            lines.append((lineno, line))
    return lines


def _header(fields: list[str], what: str, known: tuple[str, ...], label: str | None,
            ignore: tuple[str, ...], ignore_key: str) -> list[str]:
    header = [h.strip() for h in fields]
    seen: set[str] = set()
    for h in header:
        if not h:
            raise InputError(what, "the header has an empty column name")
        if h in seen:
            raise InputError(what, f"column {h!r} appears twice in the header")
        seen.add(h)
        if h not in known and h != label and h not in ignore:
            raise InputError(what, f"unknown column {h!r} (known: {', '.join(known)}"
                                   f"{f', {label}' if label else ''}); list it in {ignore_key} to skip it")
    return header


def _number(text: str, what: str, row: int, column: str) -> float:
    try:
        x = float(text)
    except ValueError:
        raise InputError(what, f"row {row}, column {column}: not a number: {text.strip()[:40]!r}") from None
    if not (math.isfinite(x) and abs(x) <= MAX_ABS):
        raise InputError(what, f"row {row}, column {column}: not a finite number of magnitude <= {MAX_ABS:g}: "
                               f"{text.strip()[:40]!r}")
    return x


def read_numeric_csv(path: str | Path, known: tuple[str, ...], *, what: str | None = None, label: str | None = None,
                     ignore: tuple[str, ...] = (), ignore_key: str = "ignore_columns", max_rows: int = 100_000,
                     max_bytes: int = MAX_CSV_BYTES) -> CsvTable:
    """Read a numeric CSV strictly (see the module docstring).

    Parameters
    ----------
    path : str or Path
        The file.
    known : tuple of str
        Column names that may be used (each with its unit in the name, e.g. ``lateral_mm``).
    what : str, optional
        How messages name the file (default: the path).
    label : str, optional
        Name of a text column kept as row labels (e.g. ``case``).
    ignore : tuple of str
        Columns that may be present and are skipped.
    ignore_key : str
        The input key that lists ignored columns (named in the unknown-column message).
    max_rows : int
        Largest number of data rows accepted.
    """
    what = str(path) if what is None else what
    raw = read_bytes(path, max_bytes, what)
    lines = _data_lines(decode_utf8(raw, what), what)
    if len(lines) < 2:
        raise InputError(what, "needs a header line and at least one data row")
    if len(lines) - 1 > max_rows:
        raise InputError(what, f"has {len(lines) - 1} data rows (at most {max_rows})")
    rows = list(csv.reader([line for _, line in lines]))
    header = _header(rows[0], what, known, label, ignore, ignore_key)
    used = [h for h in header if h in known]
    if not used:
        raise InputError(what, f"no column named like {', '.join(known)}")
    index = [header.index(h) for h in used]
    values = np.empty((len(rows) - 1, len(used)))
    labels = []
    for r, fields in enumerate(rows[1:], start=1):
        if len(fields) != len(header):
            raise InputError(what, f"row {r} has {len(fields)} fields, the header {len(header)}")
        long = next((f for f in fields if len(f) > MAX_FIELD_CHARS), None)
        if long is not None:
            raise InputError(what, f"row {r} has a field of {len(long)} characters (at most {MAX_FIELD_CHARS})")
        values[r - 1] = [_number(fields[i], what, r, h) for i, h in zip(index, used)]
        if label in header:
            labels.append(fields[header.index(label)].strip())
    return CsvTable(file=str(path), sha256=sha256_hex(raw), columns=tuple(used), values=values,
                    labels=tuple(labels), ignored_columns=tuple(h for h in header if h in ignore))


__all__ = ["CsvTable", "MAX_FIELD_CHARS", "MAX_LINE_CHARS", "read_numeric_csv"]
