"""Read MiniProf (Greenwood Engineering) profile measurement files: ``.whl`` (wheel) and ``.ban`` (rail).

What is publicly described, and implemented here: the manuals of the GENSYS converters CONV_MINIPROF2KPF_WHEEL
and CONV_MINIPROF2KPF_RAIL (gensys.se, "Users Manual for Program ...") state that a MiniProf file of a wheel
measurement has the suffix ``.whl`` and of a rail measurement ``.ban``; that the file begins with the MiniProf
header lines and the measured data start after the first empty line; and that lines beginning with ``#`` are
comments. The same manuals orient the data with two options: TURN (reverse the lateral direction; their default
"yes" for wheels, "no" for rails) and a lateral shift from the wheel's inner face (DIST_TO_ORIGO, default 70 mm)
or the rail's gauge face (GAUGE_TO_ORIGO, default 32.5 mm) to the profile origin.

What is not publicly described (Greenwood's MiniProf for Windows Technical Reference / Advanced Guide exist but
their text was not available): the header's keys, the data columns, the length unit, and the origin and
directions of the coordinates. The reader therefore assumes two numeric columns per data line (lateral,
vertical; separated by blanks, commas or semicolons), in mm unless ``units = "m"``, and takes the orientation
from its options, named after the converters': ``mirror_y`` (TURN), ``y_offset_mm`` (added to the lateral
coordinate after mirroring) and ``z_down``. The result must then lie in the project's profile frame
(:mod:`meshes.profiles.base`); the plausibility checks (:mod:`meshes.profiles.plausibility`) name what looks wrong
(flange on the wrong side, upside down, lengths in metres) when it does not. Header lines are kept as text
(:func:`parse_miniprof`); ``key = value`` / ``key: value`` lines among them are offered as a mapping, unused.
The conversion to a profile (units, orientation, checks) is :func:`meshes.profiles.io.read_miniprof`.
"""

from __future__ import annotations

import re
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from wrlayer.errors import InputError
from wrlayer.input_files import MAX_DATA_BYTES
from wrlayer.input_files import read_text as read_text_file

#: Body measured, by suffix.
MINIPROF_SUFFIXES = {".whl": "wheel", ".ban": "rail"}
_HEADER_ITEM = re.compile(r"^\s*([^=:]+?)\s*[=:]\s*(.*?)\s*$")


@dataclass(frozen=True, eq=False)
class MiniProfFile:
    """A MiniProf file as read: ``header`` lines (text, without comments), ``items`` (the header's key/value lines),
    ``points`` (n, 2) as in the file (first two columns, file units), ``body`` from the suffix."""

    path: Path
    body: str
    header: tuple[str, ...]
    items: dict = field(repr=False)
    points: np.ndarray = field(repr=False)


def miniprof_body(path) -> str:
    """"wheel" for ``.whl``, "rail" for ``.ban`` (InputError otherwise)."""
    suffix = Path(path).suffix.lower()
    if suffix not in MINIPROF_SUFFIXES:
        raise InputError(str(path), f"not a MiniProf file (suffix {', '.join(MINIPROF_SUFFIXES)})")
    return MINIPROF_SUFFIXES[suffix]


def parse_miniprof(path) -> MiniProfFile:
    """Header (up to the first empty line) and data points of a MiniProf file; ``#`` lines are comments."""
    path = Path(path)
    body = miniprof_body(path)
    lines = read_text_file(path, MAX_DATA_BYTES).splitlines()
    blank = next((i for i, ln in enumerate(lines) if not ln.strip()), None)
    if blank is None:
        raise InputError(str(path), "no empty line: a MiniProf file's measured data start after the first empty "
                                    "line that ends its header")
    header = tuple(ln.rstrip() for ln in lines[:blank] if not ln.lstrip().startswith("#"))
    items = {m.group(1): m.group(2) for m in map(_HEADER_ITEM.match, header) if m}
    pts: list[tuple[float, float]] = []
    for lineno, raw in enumerate(lines[blank + 1:], start=blank + 2):
        line = raw.strip()
        if not line or line.startswith("#"):
            continue
        fields = [f for f in re.split(r"[\s,;]+", line) if f]
        if len(fields) != 2:
            raise InputError(str(path), f"line {lineno}: expected 2 columns (lateral, vertical), got {len(fields)}")
        try:
            y, z = float(fields[0]), float(fields[1])
        except ValueError:
            raise InputError(str(path), f"line {lineno}: non-numeric value in {line!r}") from None
        if not (np.isfinite(y) and np.isfinite(z)):
            raise InputError(str(path), f"line {lineno}: NaN or infinite value")
        pts.append((y, z))
    if not pts:
        raise InputError(str(path), "no measured points after the header")
    return MiniProfFile(path, body, header, items, np.array(pts))


__all__ = ["MINIPROF_SUFFIXES", "MiniProfFile", "miniprof_body", "parse_miniprof"]
