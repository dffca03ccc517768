"""Read and write profile point files: SIMPACK ``.prr`` (rail) / ``.prw`` (wheel), plain text / CSV, and read
MiniProf measurement files ``.whl`` (wheel) / ``.ban`` (rail) (:mod:`meshes.profiles.miniprof`).

Length units: a text, CSV or MiniProf file is in mm unless read with ``units = "m"``; a SIMPACK file states its
unit in ``units.len.f`` (1000: mm, 1: m), and a ``units`` given for it must agree with that (or sets it when the
header has no ``units.len.f``).

All readers return a :class:`~meshes.profiles.spline.SplineProfile` in the project frame: lengths in
mm, z UP (SIMPACK's z points DOWN and is negated on reading), y strictly increasing.

SIMPACK processing, in the order of the numbered header comments of the format: (2) ``shift.y``,
``shift.z`` added; (3) ``rotate`` (angle units, converted with ``units.ang.f``) applied as
y' = y cos a - z sin a, z' = y sin a + z cos a in the file's (y, z-down) frame; (4) ``bound.*``
(only when min < max); (5) ``mirror.y`` / ``mirror.z`` negate y / z; (6) ``inversion`` reverses
the point order; (7) ``units.len.f`` (user length units per metre) converts to mm. Finally z is
negated (z down -> z up) and the points are put in increasing y. The rotation sign of SIMPACK
itself could not be checked (both reference files have ``rotate = 0``). ``point.dist.min`` and
``approx.smooth`` are not applied (the profile is always the interpolating spline); weights are
ignored. ``type``: 0 = rail, 1 = wheel.

Reference files (tests/meshes/test_profiles_reference.py): ``MBench_S1002_v3.prw`` read this way is
y = S, z = -F(S) (points within 1.6e-6 mm). ``MBench_UIC60_v3.prr`` is the 60E1 head rotated
counter-clockwise by atan(1/40) (z up) and shifted so that its highest point is the origin; since
the cant tilts the head towards the gauge side, the file's +y points to the FIELD side and -y to
the gauge side, as in the project's rail frame (which cannot be told from the symmetric head alone).
"""

from __future__ import annotations

import math
import re
from pathlib import Path

import numpy as np

from wrlayer import validate
from wrlayer.atomic_write import atomic_write_text
from wrlayer.errors import InputError
from wrlayer.input_files import MAX_DATA_BYTES
from wrlayer.input_files import read_text as read_text_file
from meshes.profiles.base import Profile
from meshes.profiles.lookup import PROFILE_UNITS
from meshes.profiles.miniprof import MINIPROF_SUFFIXES, parse_miniprof
from meshes.profiles.plausibility import check_profile_points
from meshes.profiles.spline import SplineProfile

_LENGTH_UNITS_MM = PROFILE_UNITS


# --------------------------------------------------------------------------------------------
# shared helpers
# --------------------------------------------------------------------------------------------
def _read_lines(path) -> tuple[Path, list[str]]:
    path = Path(path)
    return path, read_text_file(path, MAX_DATA_BYTES).splitlines()


def _floats(fields: list[str], path: Path, lineno: int) -> list[float]:
    try:
        vals = [float(f) for f in fields]
    except ValueError:
        raise InputError(str(path), f"line {lineno}: non-numeric value in {' '.join(fields)!r}") from None
    if not all(math.isfinite(v) for v in vals):
        raise InputError(str(path), f"line {lineno}: NaN or infinite value")
    return vals


def _to_profile(y, z, path: Path, body: str, name: str | None, accept_unusual: bool = False) -> SplineProfile:
    """Spline profile from points in the project frame, reversing a strictly decreasing order; checked for
    plausibility (:mod:`meshes.profiles.plausibility`) unless ``accept_unusual``."""
    y, z = np.asarray(y, float), np.asarray(z, float)
    big = ~(np.abs(y) <= MAX_COORD_MM) | ~(np.abs(z) <= MAX_COORD_MM)
    if np.any(big):
        i = int(np.argmax(big))
        raise InputError(str(path), f"point {i + 1}: (y, z) = ({y[i]:.6g}, {z[i]:.6g}) mm is beyond "
                                    f"{MAX_COORD_MM:g} mm (a unit mistake? profiles span less than 1 m)")
    if len(y) > validate.MAX_LIST:
        raise InputError(str(path), f"has {len(y)} profile points (at most {validate.MAX_LIST})")
    if len(y) < 4:
        raise InputError(str(path), f"need at least 4 profile points, found {len(y)}")
    if np.all(np.diff(y) < 0):
        y, z = y[::-1], z[::-1]
    bad = np.diff(y) <= 0
    if np.any(bad):
        i = int(np.argmax(bad))
        raise InputError(str(path), f"y is not strictly monotone after mirroring/inversion "
                                    f"(points {i + 1} and {i + 2}: y = {y[i]:.6g}, {y[i + 1]:.6g} mm)")
    if not accept_unusual:
        check_profile_points(y, z, body, str(path))
    return SplineProfile(y, z, name=name or path.stem, body=body, what=str(path))


def _profile_points(profile_or_points, ds: float) -> np.ndarray:
    """(n, 2) points: a SplineProfile's own points, a profile sampled at ``ds`` mm, or an array."""
    if isinstance(profile_or_points, SplineProfile):
        return profile_or_points.points
    if isinstance(profile_or_points, Profile):
        return np.column_stack(profile_or_points.sample(ds))
    pts = np.asarray(profile_or_points, dtype=float)
    if pts.ndim != 2 or pts.shape[1] != 2:
        raise InputError("points", f"need an (n, 2) array of (y, z) in mm, got shape {pts.shape}")
    return pts


# --------------------------------------------------------------------------------------------
# SIMPACK
# --------------------------------------------------------------------------------------------
_KEY_VALUE = re.compile(r"^\s*([A-Za-z][\w.]*)\s*=\s*(.*)$")


def _parse_value(text: str):
    text = text.strip()
    if text.startswith(("'", '"')):
        end = text.find(text[0], 1)
        return text[1:end] if end > 0 else text[1:]
    text = text.split("!", 1)[0].strip()
    try:
        return float(text)
    except ValueError:
        return text


def parse_simpack(path) -> tuple[dict, np.ndarray]:
    """Raw SIMPACK profile: (settings from the header and spline blocks, points (n, 2) as in the file)."""
    path, lines = _read_lines(path)
    settings: dict = {}
    block = None
    points: list[list[float]] = []
    seen_points = False
    for lineno, raw in enumerate(lines, start=1):
        line = raw.strip()
        if not line or line.startswith("!"):
            continue
        low = line.split("!", 1)[0].strip().lower()
        if low in ("header.begin", "spline.begin"):
            block = low.split(".")[0]
            continue
        if low in ("header.end", "spline.end"):
            block = None
            continue
        if low == "point.begin":
            block, seen_points = "point", True
            continue
        if low == "point.end":
            block = "spline"
            continue
        if block == "point":
            fields = line.split("!", 1)[0].replace(",", " ").split()
            if len(fields) not in (2, 3):
                raise InputError(str(path), f"line {lineno}: expected 2 or 3 numbers (y, z[, weight]), "
                                            f"got {len(fields)}")
            points.append(_floats(fields, path, lineno)[:2])
            continue
        m = _KEY_VALUE.match(line)
        if m and block in ("header", "spline"):
            settings[f"{block}.{m.group(1)}" if block == "header" else m.group(1)] = _parse_value(m.group(2))
    if not seen_points:
        raise InputError(str(path), "no point block (point.begin ... point.end) found")
    return settings, np.array(points, dtype=float).reshape(-1, 2)


#: Largest profile coordinate accepted (mm, after unit conversion): wheel and rail profiles span < 1 m; larger
#: values are a unit mistake or garbage and overflow the spline fit.
MAX_COORD_MM = 1e5
#: Per-setting rules of a SIMPACK header (beyond "a finite number"): (check, what it must be).
_SETTING_RULES = {
    "units.ang.f": (lambda v: v > 0, "> 0 (angle units per radian)"),
    "units.len.f": (lambda v: v > 0, "> 0 (length units per metre)"),
    "header.type": (lambda v: v in (0.0, 1.0), "0 (rail) or 1 (wheel)"),
    "mirror.y": (lambda v: v in (0.0, 1.0), "0 or 1"),
    "mirror.z": (lambda v: v in (0.0, 1.0), "0 or 1"),
    "inversion": (lambda v: v in (0.0, 1.0), "0 or 1"),
}


def _setting(settings: dict, key: str, default: float, path: Path) -> float:
    """A SIMPACK header setting: a finite number (wrlayer.validate rules) obeying its rule; InputError naming the
    file and the setting otherwise."""
    val = settings.get(key, default)
    if not isinstance(val, float):
        raise InputError(f"{path}: {key}", f"must be a number, got {validate.show(val)}")
    validate.number(val, f"{path}: {key}")
    rule = _SETTING_RULES.get(key)
    if rule is not None and not rule[0](val):
        raise InputError(f"{path}: {key}", f"must be {rule[1]}, got {val:g}")
    return val


def read_simpack(path, name: str | None = None, accept_unusual: bool = False, units: str | None = None,
                 body: str | None = None) -> SplineProfile:
    """Read a SIMPACK ``.prr``/``.prw`` profile into the project frame (mm, z up); see module doc.

    ``accept_unusual``: skip the plausibility checks (units, orientation, steps; a profile unusual on purpose);
    ``units``: "mm" or "m", the file's length unit when its header does not state ``units.len.f`` (a stated one
    must agree); ``body``: "rail" or "wheel", must agree with the header's ``type``."""
    settings, pts = parse_simpack(path)
    path = Path(path)
    if units is not None:
        _check_units(units)
        per_m = 1000.0 / _LENGTH_UNITS_MM[units]
        stated = settings.setdefault("units.len.f", per_m)
        if isinstance(stated, float) and stated != per_m:  # a non-number is reported by the header check below
            raise InputError(f"{path}: units.len.f", f"the file states {stated:g} length units per metre, not "
                                                     f"{units} ({per_m:g}) as given")

    def num(key: str, default: float) -> float:
        return _setting(settings, key, default, path)

    y, z = pts[:, 0].copy(), pts[:, 1].copy()
    y += num("shift.y", 0.0)
    z += num("shift.z", 0.0)
    ang_f = num("units.ang.f", 1.0)
    angle = num("rotate", 0.0) / ang_f
    if angle != 0.0:
        c, s = math.cos(angle), math.sin(angle)
        y, z = c * y - s * z, s * y + c * z
    for axis, vals in (("y", y), ("z", z)):
        lo, hi = num(f"bound.{axis}.min", 1.0), num(f"bound.{axis}.max", 0.0)
        if lo < hi:
            keep = (vals >= lo) & (vals <= hi)
            y, z = y[keep], z[keep]
    if num("mirror.y", 0.0):
        y = -y
    if num("mirror.z", 0.0):
        z = -z
    if num("inversion", 0.0):
        y, z = y[::-1], z[::-1]
    len_f = num("units.len.f", 1000.0)
    to_mm = 1000.0 / len_f
    kind = ("rail", "wheel")[int(num("header.type", 0.0))]
    if body is not None and body != kind:
        raise InputError(f"{path}: type", f"the file holds a {kind} profile, not a {body} profile")
    return _to_profile(y * to_mm, -z * to_mm, path, kind, name, accept_unusual)


def write_simpack(path, profile_or_points, body: str | None = None, comment: str = "", ds: float = 0.2) -> Path:
    """Write a SIMPACK profile (mm, z DOWN in the file, no shift/rotation/mirroring).

    ``profile_or_points``: a Profile (a SplineProfile writes its own points, others are sampled at
    arc-length spacing ``ds`` mm) or an array (n, 2) of (y, z) in the project frame (z up).
    ``body`` ("rail"/"wheel") defaults to the profile's.
    """
    pts = _profile_points(profile_or_points, ds)
    body = body or getattr(profile_or_points, "body", None)
    if body not in ("rail", "wheel"):
        raise InputError("body", f"{body!r} is neither 'rail' nor 'wheel'")
    comment = comment.replace("'", "")
    rows = "\n".join(f"{y:+.12e}  {-z:+.12e}" for y, z in pts)
    text = f"""! SIMPACK Rail-Wheel Profile written by wrlayer (meshes.profiles.io)
! lengths in mm (units.len.f = 1000), z positive DOWNWARDS as in SIMPACK
  header.begin
    version       =  1
    type          =  {0 if body == 'rail' else 1}                       ! 0=rail profile, 1=wheel profile
  header.end
  spline.begin
    approx.smooth  = +0.000000000000000e+00
    comment        = '{comment}'
    shift.y        = +0.000000000000000e+00
    shift.z        = +0.000000000000000e+00
    rotate         = +0.000000000000000e+00
    mirror.y       =  0
    mirror.z       =  0
    inversion      =  0
    units.len.f    = +1.000000000000000e+03   ! l[User] / l[m]
    units.ang.f    = +1.000000000000000e+00   ! a[User] / a[rad]
    point.begin
    ! y (mm)  z (mm, down)
{rows}
    point.end
  spline.end
"""
    return atomic_write_text(path, text)


# --------------------------------------------------------------------------------------------
# Plain text / CSV
# --------------------------------------------------------------------------------------------
def read_text(path, units: str = "mm", z_down: bool = False, body: str = "rail",
              name: str | None = None, accept_unusual: bool = False) -> SplineProfile:
    """Read two columns (y, z) separated by whitespace, commas or semicolons.

    ``units``: "mm" or "m" (the file's length unit); ``z_down``: the file's z points downwards;
    lines starting with ``#`` are comments; one non-numeric header line before the data is allowed.
    """
    _check_units(units)
    path, lines = _read_lines(path)
    pts: list[list[float]] = []
    header_allowed = True
    for lineno, raw in enumerate(lines, start=1):
        line = raw.split("#", 1)[0].strip()
        if not line:
            continue
        fields = re.split(r"[\s,;]+", line)
        if header_allowed and not pts:
            header_allowed = False
            try:
                [float(f) for f in fields]
            except ValueError:
                continue  # header line
        if len(fields) != 2:
            raise InputError(str(path), f"line {lineno}: expected 2 columns (y, z), got {len(fields)}")
        pts.append(_floats(fields, path, lineno))
    if not pts:
        raise InputError(str(path), "no profile points found")
    arr = np.array(pts) * _LENGTH_UNITS_MM[units]
    return _to_profile(arr[:, 0], -arr[:, 1] if z_down else arr[:, 1], path, body, name, accept_unusual)


def write_text(path, profile_or_points, units: str = "mm", z_down: bool = False, ds: float = 0.2,
               comment: str = "") -> Path:
    """Write two columns y, z (CSV if the suffix is .csv, else whitespace) with a ``#`` header."""
    _check_units(units)
    pts = _profile_points(profile_or_points, ds) / _LENGTH_UNITS_MM[units]
    sep = "," if Path(path).suffix.lower() == ".csv" else "  "
    zcol = "z_down" if z_down else "z_up"
    head = [f"# profile points written by wrlayer; lengths in {units}; z {'DOWN' if z_down else 'UP'}"]
    if comment:
        head.append("# " + comment.replace("\n", " "))
    head.append(f"# y_{units}{sep}{zcol}_{units}")
    rows = [f"{y:.12e}{sep}{(-z if z_down else z):.12e}" for y, z in pts]
    return atomic_write_text(path, "\n".join(head + rows) + "\n")


# --------------------------------------------------------------------------------------------
# MiniProf
# --------------------------------------------------------------------------------------------
def read_miniprof(path, units: str = "mm", mirror_y: bool = False, y_offset_mm: float = 0.0, z_down: bool = False,
                  body: str | None = None, name: str | None = None, accept_unusual: bool = False) -> SplineProfile:
    """Read a MiniProf ``.whl`` (wheel) / ``.ban`` (rail) file (:mod:`meshes.profiles.miniprof`) into the project
    frame: the two columns scaled by ``units`` ("mm" or "m"), the lateral one negated when ``mirror_y`` and then
    shifted by ``y_offset_mm`` (mm), the vertical one negated when ``z_down``; checked for plausibility unless
    ``accept_unusual``. ``body``, when given, must agree with the suffix."""
    _check_units(units)
    if not (isinstance(y_offset_mm, int | float) and math.isfinite(y_offset_mm)):
        raise InputError("y_offset_mm", f"must be a finite number of mm, got {y_offset_mm!r}")
    parsed = parse_miniprof(path)
    if body is not None and body != parsed.body:
        raise InputError(str(path), f"a {Path(path).suffix} file holds a {parsed.body} profile, not a {body} profile")
    pts = parsed.points * _LENGTH_UNITS_MM[units]
    y = (-pts[:, 0] if mirror_y else pts[:, 0]) + y_offset_mm
    z = -pts[:, 1] if z_down else pts[:, 1]
    return _to_profile(y, z, parsed.path, parsed.body, name, accept_unusual)


def _check_units(units) -> None:
    if units not in _LENGTH_UNITS_MM:
        raise InputError("units", f"{units!r} is not one of {tuple(_LENGTH_UNITS_MM)} (the file's length unit)")


def read_profile(path, **kw) -> SplineProfile:
    """Read a profile file by suffix: .prr/.prw (SIMPACK, :func:`read_simpack`), .txt/.csv (two columns,
    :func:`read_text`) or .whl/.ban (MiniProf, :func:`read_miniprof`). Every reader takes ``units`` ("mm" or "m",
    the file's length unit), ``body``, ``name`` and ``accept_unusual``."""
    suffix = Path(path).suffix.lower()
    if suffix in (".prr", ".prw"):
        unknown = set(kw) - {"name", "accept_unusual", "units", "body"}
        if unknown:
            raise InputError(str(path), f"options {sorted(unknown)} do not apply to SIMPACK files")
        return read_simpack(path, **kw)
    if suffix in (".txt", ".csv"):
        return read_text(path, **kw)
    if suffix in MINIPROF_SUFFIXES:
        return read_miniprof(path, **kw)
    raise InputError(str(path), "unknown profile file type (expected .prr, .prw, .txt, .csv, .whl or .ban)")


def write_profile_files(stem_path, points: np.ndarray, body: str, comment: str = "") -> tuple[list[Path], float]:
    """Write the points (n, 2) of a profile (mm, z up) as SIMPACK (``<stem>.prr`` rail / ``.prw`` wheel) and as CSV
    (``<stem>.csv``), read both back and return the paths and the largest read-back error in z (mm).

    The read-back check makes a written profile trustworthy for the next tool (a wear step, a multibody code)."""
    stem_path = Path(stem_path)
    stem_path.parent.mkdir(parents=True, exist_ok=True)
    simpack = stem_path.with_name(stem_path.name + (".prr" if body == "rail" else ".prw"))
    text = stem_path.with_name(stem_path.name + ".csv")
    write_simpack(simpack, points, body=body, comment=comment)
    write_text(text, points, comment=comment)
    err = 0.0
    for back in (read_profile(simpack), read_profile(text, body=body)):
        err = max(err, float(np.max(np.abs(back.z(points[:, 0]) - points[:, 1]))))
    return [simpack, text], err
