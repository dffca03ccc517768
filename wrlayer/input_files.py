"""Opening input files safely: regular files only, sizes bounded before reading, UTF-8 text, TOML nesting bounded.

Every reader of a user's file (scenes, calibration configs, layer tables, profile files, CSV sweeps, load
collectives) goes through :func:`read_bytes`, :func:`read_text` or :func:`read_toml`, so that

- a FIFO, a device (``/dev/zero``), a directory or a symbolic-link loop is refused up front with the reason,
  instead of blocking for ever or filling the memory;
- a file larger than its kind's limit is refused before it is read (the limits below are far above any real
  input: a measured profile of 10 000 points is about 0.3 MB);
- text that is not UTF-8 is one clear line naming the byte offset; a UTF-8 byte-order mark is dropped;
- a TOML file whose keys or inline tables/arrays nest deeper than :data:`MAX_TOML_DEPTH` is refused before
  ``tomllib`` sees it (its cost grows with the square of a dotted key's length).

Every failure is an :class:`~wrlayer.errors.InputError` whose ``what`` is the path as the user gave it.

A file named ``reference:REL`` in a scene lies in the shared reference folder (:func:`resolve_reference`):
``$WRLAYER_REFERENCE``, else ``shared/reference`` beside the repository of a source tree; an installed package has
no such sibling, so there the variable is the only way, and a missing file names both places.
"""

from __future__ import annotations

import errno
import os
import stat
import tomllib
from pathlib import Path
from typing import Any

from wrlayer.errors import InputError
from wrlayer.version import source_tree

#: Largest TOML scene or configuration file read (bytes).
MAX_TOML_BYTES = 4 * 2**20
#: Largest profile, layer-table or JSON file read (bytes).
MAX_DATA_BYTES = 64 * 2**20
#: Largest CSV input read (bytes): a 100 000-case sweep or load collective is about 10 MB.
MAX_CSV_BYTES = 64 * 2**20
#: Prefix of a file name that lies in the shared reference folder (profiles and inputs of published benchmarks).
REFERENCE_PREFIX = "reference:"
#: Environment variable naming the shared reference folder.
REFERENCE_ENV = "WRLAYER_REFERENCE"
#: Deepest nesting of keys (dotted parts or table headers) and inline tables/arrays accepted in a TOML file.
MAX_TOML_DEPTH = 32

_KIND_NAMES = ((stat.S_ISDIR, "a folder"), (stat.S_ISFIFO, "a FIFO (named pipe)"),
               (stat.S_ISCHR, "a character device"), (stat.S_ISBLK, "a block device"),
               (stat.S_ISSOCK, "a socket"))


def _kind_of(mode: int) -> str:
    for test, name in _KIND_NAMES:
        if test(mode):
            return name
    return "not a regular file"


def _stat(path: Path, what: str) -> os.stat_result:
    try:
        return path.stat()
    except FileNotFoundError:
        if path.is_symlink():
            raise InputError(what, "a symbolic link to a file that does not exist") from None
        raise InputError(what, "no such file") from None
    except RuntimeError:  # pathlib's own symlink-loop detection on some Python versions
        raise InputError(what, "a symbolic-link loop") from None
    except OSError as err:
        if err.errno == errno.ELOOP:
            raise InputError(what, "a symbolic-link loop") from None
        raise InputError(what, f"cannot read ({err.strerror})") from None


def check_regular_file(path: str | Path, max_bytes: int, what: str | None = None) -> Path:
    """The path, after checking that it is a regular file (links followed) of at most ``max_bytes`` bytes.

    Raises
    ------
    InputError
        Missing file, dangling link, link loop, FIFO, device, folder, socket, or a file over the limit.
    """
    path = Path(path)
    what = str(path) if what is None else what
    mode = _stat(path, what)
    if not stat.S_ISREG(mode.st_mode):
        raise InputError(what, f"{_kind_of(mode.st_mode)}, not a regular file")
    if mode.st_size > max_bytes:
        raise InputError(what, f"{mode.st_size} bytes, more than the {max_bytes} accepted for this kind of file")
    return path


def read_bytes(path: str | Path, max_bytes: int = MAX_DATA_BYTES, what: str | None = None) -> bytes:
    """The contents of a regular file of at most ``max_bytes`` bytes (see :func:`check_regular_file`).

    The file is opened non-blocking and checked again on the open descriptor, so a file swapped for a FIFO
    between the check and the open cannot block the run.
    """
    path = check_regular_file(path, max_bytes, what)
    what = str(path) if what is None else what
    try:
        fd = os.open(path, os.O_RDONLY | getattr(os, "O_NONBLOCK", 0))
    except OSError as err:
        raise InputError(what, f"cannot read ({err.strerror})") from None
    with os.fdopen(fd, "rb") as fh:
        if not stat.S_ISREG(os.fstat(fh.fileno()).st_mode):
            raise InputError(what, "not a regular file")
        try:
            data = fh.read(max_bytes + 1)
        except OSError as err:
            raise InputError(what, f"cannot read ({err.strerror})") from None
    if len(data) > max_bytes:
        raise InputError(what, f"more than the {max_bytes} bytes accepted for this kind of file")
    return data


def decode_utf8(data: bytes, what: str) -> str:
    """``data`` decoded as UTF-8 without a leading byte-order mark; InputError naming the first bad byte."""
    if data.startswith(b"\xef\xbb\xbf"):
        data = data[3:]
    try:
        return data.decode("utf-8")
    except UnicodeDecodeError as err:
        raise InputError(what, f"not UTF-8 text (byte 0x{data[err.start]:02x} at offset {err.start}); "
                               "save the file as UTF-8") from None


def read_text(path: str | Path, max_bytes: int = MAX_DATA_BYTES, what: str | None = None) -> str:
    """A regular UTF-8 text file of at most ``max_bytes`` bytes, byte-order mark dropped."""
    what = str(path) if what is None else what
    return decode_utf8(read_bytes(path, max_bytes, what), what)


def toml_depth(text: str) -> int:
    """The deepest nesting in a TOML text: dotted key parts (in a key or a table header) plus open inline
    tables and arrays, ignoring anything inside strings and comments. A cheap, linear pre-scan."""
    deepest = 0
    brackets = 0  # open inline tables/arrays, across lines (arrays may span lines)
    for line in text.splitlines():
        parts = 1
        in_key = brackets == 0
        quote = ""
        i = 0
        while i < len(line):
            c = line[i]
            if quote:
                if c == "\\" and quote == '"':
                    i += 2
                    continue
                if line.startswith(quote, i):
                    i += len(quote)
                    quote = ""
                    continue
            elif c == "#":
                break
            elif line.startswith(('"""', "'''"), i):
                quote = line[i:i + 3]
                i += 3
                continue
            elif c in "\"'":
                quote = c
            elif c in "[{":
                brackets += 1
            elif c in "]}":
                brackets = max(brackets - 1, 0)
            elif c == "=" and in_key:
                in_key = False
            elif c == "." and in_key:
                parts += 1
            elif c == "," and brackets:
                parts = 1
            deepest = max(deepest, brackets + (parts if in_key or brackets else 0))
            i += 1
        deepest = max(deepest, parts)
    return deepest


def parse_toml(text: str, what: str, max_depth: int = MAX_TOML_DEPTH) -> dict[str, Any]:
    """Parse TOML text whose nesting is at most ``max_depth`` (InputError otherwise or when invalid)."""
    depth = toml_depth(text)
    if depth > max_depth:
        raise InputError(what, f"keys or arrays nested too deeply ({depth} levels, at most {max_depth})")
    try:
        return tomllib.loads(text)
    except tomllib.TOMLDecodeError as err:
        raise InputError(what, f"not valid TOML ({err})") from None
    except RecursionError:
        raise InputError(what, "arrays or tables nested too deeply to read") from None


def read_toml(path: str | Path, max_bytes: int = MAX_TOML_BYTES, what: str | None = None) -> dict[str, Any]:
    """A TOML file read safely: regular file, at most ``max_bytes``, UTF-8, nesting bounded."""
    what = str(path) if what is None else what
    return parse_toml(read_text(path, max_bytes, what), what)


def sibling_reference_dir() -> Path | None:
    """``shared/reference`` beside the repository this code runs from, or None for an installed package."""
    root = source_tree()
    return None if root is None else root.parent / "shared" / "reference"


def reference_dir() -> Path | None:
    """The shared reference folder: ``$WRLAYER_REFERENCE``, else :func:`sibling_reference_dir` (None: neither)."""
    env = os.environ.get(REFERENCE_ENV)
    return Path(env) if env else sibling_reference_dir()


def reference_places() -> str:
    """Where reference files are looked for, for messages: the variable (set or not) and the sibling folder."""
    env = os.environ.get(REFERENCE_ENV)
    sibling = sibling_reference_dir()
    first = f"${REFERENCE_ENV} = {env}" if env else f"${REFERENCE_ENV} (not set)"
    if sibling is None:
        second = "no folder beside the repository (an installed package)"
    else:
        second = f"the folder beside the repository, {sibling}" + (" (used when the variable is not set)" if env
                                                                     else "")
    return f"{first}; {second}; set ${REFERENCE_ENV} to the reference folder"


def resolve_reference(name: str, what: str) -> Path:
    """The file ``reference:REL`` stands for: REL inside :func:`reference_dir`.

    Raises
    ------
    InputError
        ``what``: the file is not there (or no reference folder is known); the message names both places.
    """
    rel = name[len(REFERENCE_PREFIX):] if name.startswith(REFERENCE_PREFIX) else name
    folder = reference_dir()
    if folder is None or not (folder / rel).exists():
        raise InputError(what, f"{name!r}: not found in the reference folder {reference_places()}")
    return folder / rel
