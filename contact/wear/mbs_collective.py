"""A load collective from a multibody code's export: a CSV of per-time-step wheelset conditions, weighted by time or
distance and merged into at most ``max_conditions`` running conditions (units mm, N, s, rad; curvature in 1/m).

Column set (one header line; ``#`` comment lines allowed; read strictly by :func:`wrlayer.csv_input.read_numeric_csv`)

=========================  =========  ===========================================================================
column                     unit       meaning
=========================  =========  ===========================================================================
``time_s`` or              s          the sample's time, or its running distance (exactly one of them; strictly
``distance_m``             m          increasing)
``lateral_mm``             mm         wheelset lateral displacement from the track centre line, towards the right rail
``yaw_rad``                rad        wheelset yaw relative to the track tangent (positive turns towards the right
                                      rail), |yaw| < 0.2
``vertical_load_left_N``   N          vertical wheel-rail force of the left wheel (> 0)
``vertical_load_right_N``  N          vertical wheel-rail force of the right wheel (> 0)
``speed_mm_s``             mm/s       running speed (> 0)
``curvature_1_per_m``      1/m        optional: track curvature, positive for a curve to the left; default 0
``longitudinal_creepage``  \\-         optional: mean longitudinal creepage xi of the two wheels (Kalker's sign,
                                      negative under traction); gives the pitch rate omega = V (1 - xi) / r0;
                                      default pure rolling
``creepage_x_right``,      \\-         optional, all six or none: each wheel's creepages in wrlayer's contact
``creepage_y_right``,      \\-         frame (Kalker's sign, body 1 = wheel; x rolling direction, y in the contact
``spin_right_1_per_m``,    1/m        plane towards the right rail, spin about the normal into the wheel), |vx|,
``creepage_x_left``,       \\-         |vy| < 0.5, |spin| <= 5 1/m; used at every patch of the wheel instead of
``creepage_y_left``,       \\-         the kinematic creepages (the position, yaw and curvature then set only the
``spin_left_1_per_m``      1/m        contact geometry)
=========================  =========  ===========================================================================

Weights: sample k stands for the interval between the midpoints to its neighbours (half intervals at the ends).
``weight_by = "distance"`` (default; the collective's weights are shares of running distance) weights it by that
interval's distance (from ``time_s``: interval x speed); ``weight_by = "time"`` by its duration (from
``distance_m``: interval / speed). The weights are normalised to sum to one.

Merging (the documented rule): each sample falls into a cell of a regular grid on (lateral_mm, yaw_rad,
curvature_1_per_m) with the cell widths :data:`BIN_WIDTHS` centred on zero; while more than ``max_conditions``
cells are occupied, all widths grow by the factor :data:`GROWTH` (1.25). Each occupied cell becomes one condition:
the weight is the sum of its samples' weights, every other column the weighted mean of its samples'. Conditions
are ordered by cell (lateral, then yaw, then curvature).
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np

from contact.wear.collective import MAX_CONDITIONS, Condition
from wrlayer.csv_input import CsvTable, read_numeric_csv
from wrlayer.errors import InputError

KEY_COLUMNS = ("time_s", "distance_m")
REQUIRED_COLUMNS = ("lateral_mm", "yaw_rad", "vertical_load_left_N", "vertical_load_right_N", "speed_mm_s")
#: The per-wheel creepage columns (vx, vy, spin in 1/m), given all together or not at all.
CREEPAGE_COLUMNS = {side: (f"creepage_x_{side}", f"creepage_y_{side}", f"spin_{side}_1_per_m")
                    for side in ("right", "left")}
OPTIONAL_COLUMNS = ("curvature_1_per_m", "longitudinal_creepage") + CREEPAGE_COLUMNS["right"] + \
    CREEPAGE_COLUMNS["left"]
#: Largest |spin| (1/m) of an export: sin(gamma) / r on a flange (r >= 0.3 m) plus 1/R stays below 5 1/m.
MAX_SPIN_1_PER_M = 5.0
COLUMNS = KEY_COLUMNS + REQUIRED_COLUMNS + OPTIONAL_COLUMNS
#: Starting cell widths of the merging grid: lateral (mm), yaw (rad), curvature (1/m).
BIN_WIDTHS = (0.25, 0.5e-3, 0.1e-3)
#: Factor by which all cell widths grow while too many cells are occupied.
GROWTH = 1.25
WEIGHT_BY = ("distance", "time")
#: Largest number of samples read from one export.
MAX_SAMPLES = 1_000_000


@dataclass(frozen=True)
class MbsCollective:
    """``[collective] csv``: a multibody export merged into running conditions.

    Attributes
    ----------
    csv : str
        The export (path relative to the scene).
    weight_by : str
        ``"distance"`` (default) or ``"time"``: what a sample's weight measures.
    max_conditions : int
        Largest number of merged conditions (default 20).
    """

    csv: str
    weight_by: str = "distance"
    max_conditions: int = 20

    def __post_init__(self):
        if self.weight_by not in WEIGHT_BY:
            raise InputError("collective.weight_by", f"must be one of {', '.join(WEIGHT_BY)}, got {self.weight_by!r}")
        if not (isinstance(self.max_conditions, int) and 1 <= self.max_conditions <= MAX_CONDITIONS):
            raise InputError("collective.max_conditions", f"must be an integer in 1..{MAX_CONDITIONS}, got "
                             f"{self.max_conditions!r}")


def _check(table: CsvTable, what: str) -> str:
    """The key column's name; InputError for a missing column or a value out of range (naming the row)."""
    keys = [k for k in KEY_COLUMNS if k in table.columns]
    if len(keys) != 1:
        raise InputError(what, "needs exactly one of the columns time_s, distance_m (the weighting key), got "
                         f"{', '.join(keys) or 'none'}")
    missing = [c for c in REQUIRED_COLUMNS if c not in table.columns]
    if missing:
        raise InputError(what, f"missing column(s) {', '.join(missing)}")
    creepage_columns = CREEPAGE_COLUMNS["right"] + CREEPAGE_COLUMNS["left"]
    present = [c for c in creepage_columns if c in table.columns]
    if present and len(present) < len(creepage_columns):
        raise InputError(what, "the creepage columns come all six or none: missing "
                         f"{', '.join(c for c in creepage_columns if c not in present)}")
    key = table.column(keys[0])
    step = np.diff(key)
    if np.any(step <= 0):
        row = int(np.argmax(step <= 0)) + 2
        raise InputError(what, f"row {row}, column {keys[0]}: must increase strictly, {key[row - 1]:g} follows "
                               f"{key[row - 2]:g}")
    rules = {"vertical_load_left_N": (lambda v: v > 0, "must be > 0"),
             "vertical_load_right_N": (lambda v: v > 0, "must be > 0"), "speed_mm_s": (lambda v: v > 0, "must be > 0"),
             "yaw_rad": (lambda v: np.abs(v) < 0.2, "|yaw| must be < 0.2 rad"),
             "curvature_1_per_m": (lambda v: np.abs(v) <= 0.02, "|1/R| must be <= 0.02 1/m (R >= 50 m)"),
             "longitudinal_creepage": (lambda v: np.abs(v) < 0.5, "|creepage| must be < 0.5"),
             **{c: (lambda v: np.abs(v) < 0.5, "|creepage| must be < 0.5 (a fraction, not per cent)")
                for side in ("right", "left") for c in CREEPAGE_COLUMNS[side][:2]},
             **{CREEPAGE_COLUMNS[side][2]: (lambda v: np.abs(v) <= MAX_SPIN_1_PER_M,
                                            f"|spin| must be <= {MAX_SPIN_1_PER_M:g} 1/m (1/m, not 1/mm or rad/km)")
                for side in ("right", "left")}}
    for col, (ok, problem) in rules.items():
        if col in table.columns:
            bad = ~ok(table.column(col))
            if np.any(bad):
                row = int(np.argmax(bad)) + 1
                raise InputError(what, f"row {row}, column {col}: {problem}, got {table.column(col)[row - 1]:g}")
    return keys[0]


def sample_weights(key: np.ndarray, speed_mm_s: np.ndarray, key_name: str, weight_by: str) -> np.ndarray:
    """Normalised weights of the samples (module docstring): the midpoint intervals of ``key``, converted to
    distance or time with the speed where the key is the other one."""
    edges = np.concatenate([[key[0]], 0.5 * (key[1:] + key[:-1]), [key[-1]]]) if key.size > 1 else np.array([0., 1.])
    span = np.diff(edges)
    if key_name == "time_s" and weight_by == "distance":
        span = span * speed_mm_s
    elif key_name == "distance_m" and weight_by == "time":
        span = span / speed_mm_s
    return span / span.sum()


def merge_cells(values: dict[str, np.ndarray], weights: np.ndarray, max_conditions: int
                ) -> list[tuple[float, dict[str, float], int]]:
    """(weight, weighted means of every column, number of samples) per occupied cell (module docstring)."""
    coords = np.column_stack([values["lateral_mm"], values["yaw_rad"], values["curvature_1_per_m"]])
    widths = np.asarray(BIN_WIDTHS, dtype=float)
    while True:
        cells = np.floor(coords / widths + 0.5).astype(np.int64)
        unique, inverse = np.unique(cells, axis=0, return_inverse=True)
        if len(unique) <= max_conditions:
            break
        widths = GROWTH * widths
    inverse = inverse.ravel()
    out = []
    for k in range(len(unique)):
        members = inverse == k
        w = weights[members]
        means = {c: float(np.sum(w * v[members]) / w.sum()) for c, v in values.items()}
        out.append((float(w.sum()), means, int(members.sum())))
    return out


def read_mbs_collective(spec: MbsCollective, base: Path, what: str, nominal_radius_mm: float
                        ) -> tuple[list[Condition], CsvTable]:
    """The merged conditions of the export ``base / spec.csv`` and the table as read (its SHA-256 goes into the
    result); ``nominal_radius_mm``: r0 (mm) converting ``longitudinal_creepage`` into a pitch rate. Every problem
    is an InputError naming ``what`` (the file) and the row."""
    table = read_numeric_csv(base / spec.csv, COLUMNS, what=what, max_rows=MAX_SAMPLES)
    key_name = _check(table, what)
    values = {c: table.column(c) for c in REQUIRED_COLUMNS}
    for c in OPTIONAL_COLUMNS:
        values[c] = table.column(c) if c in table.columns else np.zeros(table.values.shape[0])
    weights = sample_weights(table.column(key_name), values["speed_mm_s"], key_name, spec.weight_by)
    conditions = []
    for k, (w, m, n) in enumerate(merge_cells(values, weights, spec.max_conditions)):
        load = 0.5 * (m["vertical_load_left_N"] + m["vertical_load_right_N"])
        pitch = None if "longitudinal_creepage" not in table.columns else \
            m["speed_mm_s"] * (1.0 - m["longitudinal_creepage"]) / nominal_radius_mm
        given = {} if CREEPAGE_COLUMNS["right"][0] not in table.columns else \
            {f"creepages_{side}": (m[vx], m[vy], m[spin] * 1e-3) for side, (vx, vy, spin) in CREEPAGE_COLUMNS.items()}
        conditions.append(Condition(m["lateral_mm"], m["yaw_rad"], load, m["speed_mm_s"], w,
                                    f"{Path(spec.csv).name} cell {k} ({n} samples)", pitch,
                                    vertical_load_right_N=m["vertical_load_right_N"],
                                    vertical_load_left_N=m["vertical_load_left_N"],
                                    curvature_1_per_m=m["curvature_1_per_m"], **given))
    total = sum(c.weight for c in conditions)
    return [Condition(**{**vars(c), "weight": c.weight / total}) for c in conditions], table


__all__ = ["BIN_WIDTHS", "COLUMNS", "CREEPAGE_COLUMNS", "MbsCollective", "merge_cells", "read_mbs_collective", "sample_weights"]
