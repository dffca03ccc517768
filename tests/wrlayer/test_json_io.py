"""The one JSON converter and the one SHA-256 helper: strict JSON from records, numpy and paths; a record written
in a layout (other keys than its field names) and read back; file and text fingerprints."""

import dataclasses
import hashlib
import json
import math
from pathlib import Path

import numpy as np

from wrlayer.hashing import file_sha256, file_sha256_or_none, sha256_hex
from wrlayer.json_io import Record, json_text, jsonable


@dataclasses.dataclass(frozen=True, kw_only=True)
class Inner(Record):
    a_mm: float
    n: int = 0


@dataclasses.dataclass(frozen=True, kw_only=True)
class Outer(Record):
    inner: tuple[Inner, ...] = dataclasses.field(metadata={"layout": (("a", "a_mm"),)})
    note: str | None = dataclasses.field(default=None, metadata={"omit_none": True})


def test_numbers_arrays_paths_and_non_finite_values_become_strict_json():
    data = {"x": np.float64(1.5), "k": np.int32(3), "ok": np.bool_(True), "v": np.array([1.0, math.inf]),
            "p": Path("a/b"), "t": (1, 2), "nan": math.nan}
    assert jsonable(data) == {"x": 1.5, "k": 3, "ok": True, "v": [1.0, None], "p": "a/b", "t": [1, 2], "nan": None}
    assert json.loads(json_text(data))["v"] == [1.0, None]


def test_a_record_in_a_layout_is_written_under_the_layout_keys_and_read_back():
    rec = Outer(inner=(Inner(a_mm=2.0), Inner(a_mm=3.0)))
    assert rec.to_dict() == {"inner": [{"a": 2.0}, {"a": 3.0}]}              # n not in the layout, note omitted
    assert Outer.from_dict(json.loads(rec.to_json())) == rec
    assert Inner(a_mm=1.0, n=5).projected((("a", "a_mm"),)) == Inner(a_mm=1.0)


def test_sha256_of_text_bytes_and_files(tmp_path):
    path = tmp_path / "f.txt"
    path.write_bytes(b"wrlayer")
    expected = hashlib.sha256(b"wrlayer").hexdigest()
    assert sha256_hex("wrlayer") == sha256_hex(b"wrlayer") == file_sha256(path) == file_sha256_or_none(path) == expected
    assert file_sha256_or_none(tmp_path / "missing.toml") is None
