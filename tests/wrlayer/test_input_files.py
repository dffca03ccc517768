"""Input files are opened safely: regular files only, bounded sizes, UTF-8, bounded TOML nesting."""

import os
import threading

import pytest

from wrlayer.errors import InputError
from wrlayer.input_files import (MAX_TOML_DEPTH, check_regular_file, decode_utf8, parse_toml, read_bytes,
                                 read_text, read_toml, toml_depth)


def test_regular_file_read(tmp_path):
    f = tmp_path / "a.toml"
    f.write_text('title = "x"\n[load]\nforce_N = 1.0e5\n', encoding="utf-8")
    assert read_toml(f) == {"title": "x", "load": {"force_N": 1.0e5}}


def test_missing_file(tmp_path):
    with pytest.raises(InputError, match="no such file"):
        read_bytes(tmp_path / "none.toml")


def test_folder_refused(tmp_path):
    with pytest.raises(InputError, match="a folder, not a regular file"):
        read_bytes(tmp_path)


def test_fifo_refused_without_blocking(tmp_path):
    fifo = tmp_path / "pipe.toml"
    os.mkfifo(fifo)
    result = []
    t = threading.Thread(target=lambda: result.append(pytest.raises(InputError, read_bytes, fifo)))
    t.start()
    t.join(5.0)
    assert not t.is_alive(), "reading a FIFO blocked"
    assert "FIFO" in str(result[0].value)


def test_device_refused():
    with pytest.raises(InputError, match="character device"):
        read_bytes("/dev/zero")


def test_link_to_device_refused(tmp_path):
    link = tmp_path / "zero.toml"
    link.symlink_to("/dev/zero")
    with pytest.raises(InputError, match="character device"):
        read_toml(link)


def test_symlink_loop_refused(tmp_path):
    a, b = tmp_path / "a.json", tmp_path / "b.json"
    a.symlink_to(b)
    b.symlink_to(a)
    with pytest.raises(InputError, match="symbolic-link loop"):
        read_bytes(a)


def test_dangling_link(tmp_path):
    a = tmp_path / "a.json"
    a.symlink_to(tmp_path / "gone.json")
    with pytest.raises(InputError, match="does not exist"):
        read_bytes(a)


def test_size_bounded_before_reading(tmp_path):
    f = tmp_path / "big.csv"
    f.write_bytes(b"x" * 1001)
    with pytest.raises(InputError, match="1001 bytes, more than the 1000"):
        check_regular_file(f, 1000)
    assert len(read_bytes(f, 1001)) == 1001


def test_utf8_bom_dropped_and_latin1_refused(tmp_path):
    assert decode_utf8(b"\xef\xbb\xbflateral_mm,yaw_rad", "x.csv") == "lateral_mm,yaw_rad"
    f = tmp_path / "latin.toml"
    f.write_bytes("title = 'Stra\u00dfe'".encode("latin-1"))
    with pytest.raises(InputError, match=r"not UTF-8 text \(byte 0xdf at offset 13\)"):
        read_text(f)


def test_message_names_the_input_once(tmp_path):
    with pytest.raises(InputError) as err:
        read_bytes(tmp_path / "none.toml", what="scene.toml")
    assert str(err.value) == "scene.toml: no such file"


@pytest.mark.parametrize("text, depth", [
    ("a = 1\n", 1),
    ("a.b.c = 1\n", 3),
    ("[x.y]\nz = 1.5\n", 3),
    ('"a.b.c" = 1\n', 1),           # dots inside a quoted key do not nest
    ("a = 'x.y.z' # c.d.e.f\n", 1),  # nor inside strings and comments
    ("a = [[1, 2], [3, [4]]]\n", 4),  # a, the array, its arrays, the innermost
])
def test_toml_depth(text, depth):
    assert toml_depth(text) == depth


def test_deep_dotted_key_refused_quickly():
    text = ".".join(["a"] * 100_000) + " = 1\n"
    with pytest.raises(InputError, match=f"nested too deeply \\(100000 levels, at most {MAX_TOML_DEPTH}\\)"):
        parse_toml(text, "deep.toml")


def test_deep_arrays_refused():
    with pytest.raises(InputError, match="nested"):
        parse_toml("a = " + "[" * 5000 + "]" * 5000, "deep.toml")


def test_invalid_toml(tmp_path):
    with pytest.raises(InputError, match="not valid TOML"):
        parse_toml("a = = 1", "bad.toml")
