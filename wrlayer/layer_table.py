"""Per-position layer tables: the calibrated Prandtl characteristic along a profile (units mm, MPa, N/mm^3).

File format (JSON, ``format = "wrlayer-layer-table"``, ``format_version = 5`` when the rolling law has convexity
nodes, else 4 for the operating-range calibration, else 3 with a rolling law, else 2; versions 1 to 4 are read too
and give their numbers as before)::

    {"format": ..., "format_version": 4,
     "header": {"body": "rail"|"wheel", "profile": name, "material": {...}, "model": "2d"|"3d",
                "mesh": {...}, "load": {...}, "fit": {...}, "software": {...}, "code_version": ...,
                "inputs_hash": sha256 of all inputs, ...},
     "positions": [{"y_mm": y, "characteristic": {"u_mm": [...], "p_MPa": [...]}, "n_segments": N,
                    "k_N_per_mm3": [...], "T0_MPa": [...], "max_error_mm": ..., "rms_error_mm": ...,
                    "geometry": {"a_mm", "b_mm", ...}, "fem": {...}, "warnings": [...] (v2),
                    "fit_mode", "calibrated_max_MPa", "levels_over_p2", "u_pl_error", "residual_error" (v4),
                    ...}, ...],                                      # characteristic: "reverse_factor" (v4)
                                                                     # y_mm strictly increasing
     "failed": [{"y_mm": y, "error": message}, ...],
     "rolling_law": {...}}                                           # v3, optional (wrlayer.rolling_law);
                                                                     # its "convexity" nodes: v5

``positions`` are the calibrated positions (profile coordinate y in mm, frames as in :mod:`meshes.profiles`);
``failed`` lists positions whose calibration failed; they are never interpolated over: a y between the two
calibrated neighbours of a failed position (or at it) is an InputError naming the failed position and its cause.
Between positions the characteristic is interpolated linearly in y with :meth:`Characteristic.interpolate`
(p(u) blended, concave by construction); outside the calibrated range :meth:`LayerTable.characteristic_at` raises
InputError. ``rolling_law`` (version 3, :class:`~wrlayer.rolling_law.RollingLaw`): what a rolling pass leaves
relative to the static residual, calibrated by the rolling FEM (docs/rolling.md); None in older tables. A table
without it is written as version 2. This module only reads/writes tables; it does not import the FEM code.
"""

from __future__ import annotations

import csv
import io
import json
import math
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from wrlayer.characteristic import Characteristic
from wrlayer import input_files, validate
from wrlayer.atomic_write import atomic_write_text
from wrlayer.errors import InputError
from wrlayer.json_io import json_text
from wrlayer.rolling_law import RollingLaw

FORMAT = "wrlayer-layer-table"
FORMAT_VERSION = 4
#: The version of a table whose rolling law has convexity nodes (``RollingLaw.convexity``).
FORMAT_VERSION_CONVEXITY_LAW = 5
#: The version of a table of the earlier (paper) calibration with a rolling law.
FORMAT_VERSION_ROLLING_LAW = 3
#: The version of a table of the earlier calibration without a rolling law (written as before the law existed).
FORMAT_VERSION_NO_ROLLING_LAW = 2
#: The position keys that make a table version 4: the operating-range calibration's residual levels and errors,
#: its calibrated range, and the element's reverse factor (in ``characteristic``).
VERSION_4_KEYS = ("fit_mode", "calibrated_max_MPa", "levels_over_p2", "u_pl_error", "residual_error")
#: Versions this reader accepts. 2: positions may carry "warnings" (conforming contact) and the
#: characteristic can be scaled to a patch size (``characteristic_at(y, patch_mm)``, needs geometry a_mm, b_mm).
#: 3: an optional ``rolling_law``. 4: the keys of :data:`VERSION_4_KEYS` and the characteristics' reverse factors.
#: 5: the rolling law's ``convexity`` nodes.
SUPPORTED_VERSIONS = (1, 2, 3, 4, 5)
BODIES = ("rail", "wheel")
#: Relative tolerance between stored (k_i, T_0i) and those re-derived from the stored characteristic.
PARAMETER_RTOL = 1e-6
#: Most segments of a stored characteristic (the operating-range fit reaches 2 % of u_pl from 1.1 p_2 up with
#: 14-15 on the default positions).
MAX_SEGMENTS = 16
#: Bounds of a calibrated patch semi-axis ``geometry.a_mm``/``b_mm`` (mm): a wheel-rail patch is 1-10 mm; far
#: outside, a scale to the patch size (``characteristic_at(y, patch_mm)``) would be meaningless or overflow.
SEMI_AXIS_RANGE_MM = (1e-3, 1e3)


@dataclass
class LayerTable:
    """A validated layer table. ``positions``: list of dicts (see module docstring) sorted by y_mm;
    ``characteristics``: the parsed Characteristic of each position; ``rolling_law``: the rolling law (None: the
    table has none)."""

    header: dict[str, Any]
    positions: list[dict[str, Any]]
    failed: list[dict[str, Any]] = field(default_factory=list)
    source: str = "layer table"
    rolling_law: RollingLaw | None = None

    def __post_init__(self):
        self.characteristics = _validate(self.header, self.positions, self.failed, self.source)

    # ------------------------------------------------------------------ reading / writing
    @classmethod
    def read(cls, path: str | Path) -> "LayerTable":
        """Read and validate a JSON table (InputError naming the file and the problem)."""
        path = Path(path)
        if not path.exists() and not path.is_symlink():  # a broken link or a loop: input_files names it
            raise InputError(str(path), "layer table file not found")
        text = input_files.read_text(path, input_files.MAX_DATA_BYTES, str(path))  # FIFO, size, UTF-8
        try:
            data = json.loads(text)
        except json.JSONDecodeError as err:
            raise InputError(str(path), f"not a readable JSON layer table: {err}") from None
        except RecursionError:
            raise InputError(str(path), "arrays or objects nested too deeply to read") from None
        return cls.from_dict(data, str(path))

    @classmethod
    def from_dict(cls, data: Any, source: str = "layer table") -> "LayerTable":
        if not isinstance(data, dict):
            raise InputError(source, "must be a JSON object")
        if data.get("format") != FORMAT:
            raise InputError(source, f"'format' must be {FORMAT!r}, got {data.get('format')!r}")
        if data.get("format_version") not in SUPPORTED_VERSIONS:
            raise InputError(source, f"unsupported format_version {data.get('format_version')!r} "
                                     f"(this reader: {', '.join(map(str, SUPPORTED_VERSIONS))})")
        for key, kind in (("header", dict), ("positions", list)):
            if not isinstance(data.get(key), kind):
                raise InputError(source, f"missing or malformed {key!r} ({kind.__name__} expected)")
        failed = data.get("failed", [])
        if not isinstance(failed, list):
            raise InputError(source, "'failed' must be a list")
        version = data["format_version"]
        if version < FORMAT_VERSION and _has_version_4_keys(data["positions"]):
            raise InputError(source, f"positions carry keys of format_version {FORMAT_VERSION} "
                                     f"({', '.join(VERSION_4_KEYS)} or reverse_factor), the file says {version}")
        law = None
        if "rolling_law" in data:
            if data["format_version"] < 3:
                raise InputError(source, f"'rolling_law' needs format_version 3, got {data['format_version']}")
            law = RollingLaw.from_dict(data["rolling_law"], f"{source}: rolling_law")
            if law.convexity is not None and data["format_version"] < FORMAT_VERSION_CONVEXITY_LAW:
                raise InputError(source, f"'rolling_law.convexity' needs format_version {FORMAT_VERSION_CONVEXITY_LAW}"
                                         f", got {data['format_version']}")
        return cls(data["header"], data["positions"], failed, source, law)

    def to_dict(self) -> dict[str, Any]:
        out = {"format": FORMAT, "format_version": FORMAT_VERSION_NO_ROLLING_LAW, "header": self.header,
               "positions": self.positions, "failed": self.failed}
        if self.rolling_law is not None:
            out.update(format_version=FORMAT_VERSION_ROLLING_LAW, rolling_law=self.rolling_law.to_dict())
        if self.is_version_4:
            out["format_version"] = FORMAT_VERSION
        if self.rolling_law is not None and self.rolling_law.convexity is not None:
            out["format_version"] = FORMAT_VERSION_CONVEXITY_LAW
        return out

    @property
    def is_version_4(self) -> bool:
        """True when a position carries a key of format version 4 (:data:`VERSION_4_KEYS`, a reverse factor)."""
        return _has_version_4_keys(self.positions)

    def to_json(self) -> str:
        return json_text(self.to_dict())

    def to_csv(self) -> str:
        """One row per calibrated position: geometry, N, S_i, k_i, T_0i, the points, fit errors (units in names),
        warnings (e.g. a conforming position calibrated at a lower load); format 4 adds the element's reverse factor
        and the calibrated range."""
        cols = (["body", "profile", "y_mm", "n_segments", "p2_MPa", "max_error_mm", "rms_error_mm", "a_mm", "b_mm"]
                + [f"S{i}_N_per_mm3" for i in range(1, MAX_SEGMENTS + 1)]
                + [f"k{i}_N_per_mm3" for i in range(1, MAX_SEGMENTS + 1)]
                + [f"T0{i}_MPa" for i in range(1, MAX_SEGMENTS)]
                + [f"u{i}_mm" for i in range(1, MAX_SEGMENTS + 2)] + [f"p{i}_MPa" for i in range(1, MAX_SEGMENTS + 2)]
                + ["warnings"] + (["reverse_factor", "calibrated_max_MPa"] if self.is_version_4 else []))
        buf = io.StringIO()
        w = csv.DictWriter(buf, fieldnames=cols, lineterminator="\n")
        w.writeheader()
        for pos, ch in zip(self.positions, self.characteristics):
            geo = pos.get("geometry", {})
            row = {"body": self.body, "profile": self.profile_name, "y_mm": pos["y_mm"],
                   "n_segments": ch.n_segments, "p2_MPa": ch.elastic_limit_MPa,
                   "max_error_mm": pos.get("max_error_mm"), "rms_error_mm": pos.get("rms_error_mm"),
                   "a_mm": geo.get("a_mm"), "b_mm": geo.get("b_mm"), "warnings": "; ".join(pos.get("warnings", []))}
            if self.is_version_4:
                row.update(reverse_factor=repr(ch.reverse_factor), calibrated_max_MPa=pos.get("calibrated_max_MPa"))
            par = ch.to_parameters()
            for i, v in enumerate(ch.slopes, 1):
                row[f"S{i}_N_per_mm3"] = repr(float(v))
            for i, v in enumerate(par.k_N_per_mm3, 1):
                row[f"k{i}_N_per_mm3"] = repr(float(v))
            for i, v in enumerate(par.T0_MPa, 1):
                row[f"T0{i}_MPa"] = repr(float(v))
            for i, (u, p) in enumerate(zip(ch.u_mm, ch.p_MPa), 1):
                row[f"u{i}_mm"], row[f"p{i}_MPa"] = repr(float(u)), repr(float(p))
            w.writerow(row)
        return buf.getvalue()

    def write(self, json_path: str | Path, csv_path: str | Path | None = None) -> list[Path]:
        """Write the JSON (and CSV) atomically; returns the paths."""
        out = [atomic_write_text(json_path, self.to_json())]
        if csv_path is not None:
            out.append(atomic_write_text(csv_path, self.to_csv()))
        return out

    # ------------------------------------------------------------------ queries
    @property
    def body(self) -> str:
        return self.header["body"]

    @property
    def profile_name(self) -> str:
        return self.header["profile"]

    @property
    def y_mm(self) -> np.ndarray:
        return np.array([float(p["y_mm"]) for p in self.positions])

    @property
    def y_range_mm(self) -> tuple[float, float]:
        y = self.y_mm
        return float(y[0]), float(y[-1])

    def calibrated_length_mm(self, y_mm: float) -> float | None:
        """The patch length sqrt(a b) (mm) the characteristic at y was calibrated on (linear in y between
        positions); None when the table does not record the semi-axes (older tables)."""
        lengths = []
        for pos in self.positions:
            geo = pos.get("geometry") or {}
            a, b = geo.get("a_mm"), geo.get("b_mm")
            if not (isinstance(a, (int, float)) and isinstance(b, (int, float)) and a > 0 and b > 0):
                return None
            lengths.append(math.sqrt(a * b))
        return float(np.interp(float(y_mm), self.y_mm, lengths))

    def lateral_curvature_at(self, y_mm):
        """The body's own lateral curvature 1/R (1/mm, convex > 0) at y (a float, or an array of them) on the
        profile the table was calibrated on (``geometry.k_y_per_mm``, linear in y between positions, the end values
        outside); 0 when a position does not record it (older tables). With the patch's lateral semi-axis b it
        gives the surface convexity b / (2 R) at which a rolling law with convexity nodes is read."""
        curvatures = []
        for pos in self.positions:
            k = (pos.get("geometry") or {}).get("k_y_per_mm")
            if isinstance(k, bool) or not isinstance(k, (int, float)) or not math.isfinite(k):
                curvatures = [0.0] * len(self.positions)
                break
            curvatures.append(float(k))
        out = np.interp(np.asarray(y_mm, dtype=float), self.y_mm, curvatures)
        return float(out) if out.ndim == 0 else out

    def calibrated_max_MPa(self, y_mm: float) -> float | None:
        """The largest pressure the characteristic at y was calibrated to (MPa, linear in y between positions): a
        position's ``calibrated_max_MPa`` (format 4), else the largest of its ``fem_points.p_MPa``; None when a
        position records neither (an assumed characteristic has no calibrated range)."""
        limits = []
        for pos in self.positions:
            value = pos.get("calibrated_max_MPa")
            if value is None:
                points = pos.get("fem_points") or {}
                p = points.get("p_MPa") if isinstance(points, dict) else None
                value = max(p) if isinstance(p, list) and p else None
            if not isinstance(value, (int, float)) or isinstance(value, bool) or not value > 0:
                return None
            limits.append(float(value))
        return float(np.interp(float(y_mm), self.y_mm, limits))

    def characteristic_at(self, y_mm: float, patch_mm: tuple[float, float] | None = None) -> Characteristic:
        """The characteristic at profile coordinate y (mm): linear in y between calibrated positions (exact at
        them); InputError outside the calibrated range.

        patch_mm = (a, b): the semi-axes (mm) of the contact patch the layer is used on. The displacements are
        then scaled by sqrt(a b) / sqrt(a_c b_c), (a_c, b_c) the calibrated patch: a half-space of J2 material
        with linear hardening under a Hertz pressure p0 sqrt(1 - (x/a)^2 - (y/b)^2) has no length of its own,
        so at fixed p0 and a/b its displacements are proportional to the patch size (docs/calibration.md;
        measured x1.26 for a x1.27 patch). InputError for a table without the calibrated semi-axes."""
        ch = self._characteristic_at(y_mm)
        if patch_mm is None:
            return ch
        a, b = (float(v) for v in patch_mm)
        if not (math.isfinite(a) and math.isfinite(b) and a > 0 and b > 0):
            raise InputError("patch_mm", f"semi-axes must be positive finite mm, got {patch_mm!r}")
        ref = self.calibrated_length_mm(y_mm)
        if ref is None:
            raise InputError(self.source, "records no calibrated semi-axes (geometry a_mm, b_mm): cannot scale the "
                                          "characteristic to the patch size")
        scale = math.sqrt(a * b) / ref  # ref >= SEMI_AXIS_RANGE_MM[0] (validated)
        if not (math.isfinite(scale) and scale > 0):
            raise InputError("patch_mm", f"semi-axes {a:g} x {b:g} mm are too small or too large to scale the "
                                         f"characteristic of the {self.body} table ({self.source}) to")
        return ch.with_points(np.asarray(ch.u_mm) * scale, np.asarray(ch.p_MPa),
                              f"{ch.name} scaled to the patch {a:.3g} x {b:.3g} mm (x{scale:.3g})")

    def _characteristic_at(self, y_mm: float) -> Characteristic:
        y = float(y_mm)
        lo, hi = self.y_range_mm
        tol = 1e-9 * max(1.0, abs(lo), abs(hi))
        if not (math.isfinite(y) and lo - tol <= y <= hi + tol):
            raise InputError(f"position y = {y_mm!r} mm",
                             f"outside the calibrated range [{lo:g}, {hi:g}] mm of the {self.body} table "
                             f"({self.profile_name}, {self.source})")
        ys = self.y_mm
        j = int(np.clip(np.searchsorted(ys, y, side="right") - 1, 0, len(ys) - 1))
        if j == len(ys) - 1 or abs(y - ys[j]) <= tol:
            return self.characteristics[j]
        gap = [f for f in self.failed if ys[j] < float(f["y_mm"]) < ys[j + 1]]
        if gap:
            raise InputError(f"position y = {y_mm!r} mm",
                             f"lies between {ys[j]:g} and {ys[j + 1]:g} mm, across the failed calibration at "
                             f"y = {float(gap[0]['y_mm']):g} mm of the {self.body} table ({self.source}): "
                             f"{gap[0].get('error', 'no cause recorded')}")
        t = (y - ys[j]) / (ys[j + 1] - ys[j])
        return Characteristic.interpolate(self.characteristics[j], self.characteristics[j + 1], float(t),
                                          name=f"{self.body} layer at y = {y:g} mm")


def read_body_table(rel: str, base: Path, body: str, what: str) -> tuple[Path, LayerTable]:
    """The ``body`` ("rail" or "wheel") table a scene names, ``rel`` relative to the scene's folder ``base``:
    (resolved path, table). InputError naming ``what`` when it is missing, unreadable or of the other body."""
    try:
        path = (Path(base) / rel).resolve()
    except (RuntimeError, OSError):  # a symbolic-link loop (RuntimeError before Python 3.13)
        raise InputError(what, f"{rel!r}: a symbolic-link loop") from None
    if not path.exists() and not path.is_symlink():
        raise InputError(what, f"no such calibration table {rel!r} (looked at {path})")
    try:
        table = LayerTable.read(path)
    except InputError as err:
        raise InputError(what, str(err)) from None
    if table.body != body:
        raise InputError(what, f"is a {table.body} table, expected a {body} table")
    return path, table


def _has_version_4_keys(positions: list) -> bool:
    """True when a position (a dict) carries a key of :data:`VERSION_4_KEYS` or a characteristic reverse factor."""
    return any(isinstance(pos, dict) and (any(k in pos for k in VERSION_4_KEYS) or (
        isinstance(pos.get("characteristic"), dict) and "reverse_factor" in pos["characteristic"]))
        for pos in positions)


def _check_extras(pos: dict, what: str) -> None:
    """The optional entries of a position: ``geometry`` an object whose semi-axes ``a_mm``, ``b_mm`` are numbers
    (not booleans: true is not 1) within :data:`SEMI_AXIS_RANGE_MM`; ``warnings`` a list of strings."""
    if "geometry" in pos:
        geo = validate.table(pos["geometry"], f"{what}: geometry")
        lo, hi = SEMI_AXIS_RANGE_MM
        for key in ("a_mm", "b_mm"):
            if key in geo:
                validate.number(geo[key], f"{what}: geometry.{key}", ge=lo, le=hi)
    if pos.get("calibrated_max_MPa") is not None:
        validate.number(pos["calibrated_max_MPa"], f"{what}: calibrated_max_MPa", gt=0.0)
    for key in ("levels_over_p2", "u_pl_error", "residual_error"):
        if key in pos:
            validate.number_list(pos[key], f"{what}: {key}", min_len=0)
    if "warnings" in pos:
        items = pos["warnings"]
        if not isinstance(items, list):
            raise InputError(f"{what}: warnings", f"must be a list of strings, got {validate.kind(items)}")
        for i, item in enumerate(items):
            validate.text(item, f"{what}: warnings[{i}]")


def _validate(header, positions, failed, source) -> list[Characteristic]:
    for key in ("body", "profile"):
        if key not in header:
            raise InputError(source, f"header has no {key!r}")
    validate.text(header["body"], f"{source}: header.body", BODIES)
    validate.text(header["profile"], f"{source}: header.profile")
    if not positions:
        raise InputError(source, "has no calibrated positions")
    if len(positions) > validate.MAX_LIST:
        raise InputError(f"{source}: positions", f"has {len(positions)} entries (at most {validate.MAX_LIST})")
    for i, f in enumerate(failed):
        y = f.get("y_mm") if isinstance(f, dict) else None
        if not (isinstance(y, (int, float)) and not isinstance(y, bool) and math.isfinite(y)):
            raise InputError(f"{source}: failed[{i}]", "must be an object with a finite number 'y_mm'")
    chars, ys = [], []
    for i, pos in enumerate(positions):
        what = f"{source}: positions[{i}]"
        if not isinstance(pos, dict):
            raise InputError(what, "must be an object")
        if "y_mm" not in pos:
            raise InputError(what, "missing 'y_mm'")
        y = validate.number(pos["y_mm"], f"{what}.y_mm")  # a finite real: not a string, not a boolean
        what = f"{source}: position y = {y:g} mm"
        if not isinstance(pos.get("characteristic"), dict):
            raise InputError(what, "missing 'characteristic' {u_mm, p_MPa}")
        ch = Characteristic.from_dict(pos["characteristic"], what)
        if ch.n_segments > MAX_SEGMENTS:
            raise InputError(what, f"has {ch.n_segments} segments (at most {MAX_SEGMENTS})")
        par = ch.to_parameters()
        for key, derived in (("k_N_per_mm3", par.k_N_per_mm3), ("T0_MPa", par.T0_MPa)):
            if key in pos:
                stored = validate.number_list(pos[key], f"{what}: {key}", min_len=0)
                if stored.shape != derived.shape or not np.allclose(stored, derived, rtol=PARAMETER_RTOL, atol=0):
                    raise InputError(what, f"{key!r} disagrees with the characteristic (eqs. 4-6)")
        _check_extras(pos, what)
        chars.append(ch)
        ys.append(y)
    if np.any(np.diff(ys) <= 0):
        raise InputError(source, "positions' y_mm must be strictly increasing")
    for i, f in enumerate(failed):
        if not (isinstance(f, dict) and "y_mm" in f and "error" in f):
            raise InputError(source, f"failed[{i}] must have 'y_mm' and 'error'")
        validate.text(f["error"], f"{source}: failed[{i}].error")
    return chars
