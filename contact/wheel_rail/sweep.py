"""The cases of a wheel–rail scene: [sweep] lists, {start, stop, step} ranges or a sweep CSV -> :class:`SweepSpec`
(units mm, N, s, rad).

Per-case values of the :data:`contact.wheel_rail.scene.SWEEP_KEYS` are a list of values or {start, stop, step}
(stop included) per key; ``mode`` = "zip" (default; lists of equal length, case k takes the k-th value of each) or
"product"; or ``csv`` = "cases.csv" (columns named like those keys, one case per row, '#' comments, an optional
``case`` label column; any other column must be listed in ``ignore_columns``) with ``convention`` = "wrlayer" (default) | "contact" (CONTACT's roll and pitch-rate signs). File names
starting with "reference:" are looked up in the shared reference folder
(:func:`contact.wheel_rail.scene_files.reference_dir`).
"""

from __future__ import annotations

import dataclasses
import itertools
import math
from pathlib import Path

import numpy as np

from contact.wheel_rail.sweep_spec import SWEEP_KEYS, CaseSpec, SweepCsv, SweepSpec
from contact.wheel_rail.scene_files import resolve_path
from wrlayer.csv_input import CsvTable, read_numeric_csv
from wrlayer.validate import MIN_FORCE_N, Keys

#: Sign conventions of a sweep CSV: factors applied to its columns ("contact": CONTACT's input files, whose roll and
#: pitch rate are measured the other way round; see docs/wheel-rail.md).
CSV_CONVENTIONS = {"wrlayer": {}, "contact": {"roll_rad": -1.0, "pitch_rate_rad_s": -1.0}}
#: Largest number of sweep cases (values per axis, rows of a sweep CSV, cases of the product): a hard size limit,
#: checked before any case is built; the cost guard (contact.scenes.cost) refuses long runs below it unless forced.
MAX_CASES = 100000
#: Keys of [sweep].
KEYS = SWEEP_KEYS + ("mode", "csv", "convention", "ignore_columns")


def sweep_values(keys: Keys, key: str) -> np.ndarray:
    """A sweep axis: a list of numbers or {start, stop, step} (stop included within step/1e6)."""
    value = keys.table[key]
    if isinstance(value, dict):
        sub = keys.sub(key)
        sub.check_known(("start", "stop", "step"))
        start, stop, step = sub.number("start"), sub.number("stop"), sub.number("step", gt=0.0)
        if stop < start:
            raise sub.error("stop", f"must be >= start ({start:g}), got {stop:g}")
        n = math.floor((stop - start) / step + 1e-6) + 1
        if n > MAX_CASES:
            raise sub.error("step", f"gives {n:.3g} values from {start:g} to {stop:g} (at most {MAX_CASES})")
        return start + step * np.arange(n)
    return keys.array(key, min_len=1, max_len=MAX_CASES)


def _check_direction(sweep: Keys, rel: str, table: CsvTable, convention: str) -> None:
    """A pitch rate that, in the wrlayer convention, turns the wheel backwards is refused with the hint to check
    ``sweep.convention`` (CONTACT's input files give it negative for forward rolling)."""
    if "pitch_rate_rad_s" not in table.columns:
        return
    rates = table.column("pitch_rate_rad_s") * CSV_CONVENTIONS[convention].get("pitch_rate_rad_s", 1.0)
    backwards = np.flatnonzero(rates < 0.0)
    if backwards.size:
        k = int(backwards[0])
        raise sweep.error("convention", f"{rel}: row {k + 1}: pitch rate {rates[k]:g} rad/s in the {convention!r} "
                          "convention turns the wheel backwards; check sweep.convention (\"contact\" for CONTACT's "
                          "signs)")


def _csv_columns(sweep: Keys, base: Path) -> tuple[dict[str, np.ndarray], SweepCsv]:
    """The sweep CSV (``sweep.csv``), read strictly (:func:`wrlayer.csv_input.read_numeric_csv`): columns named like
    the sweep keys, an optional ``case`` label column, other columns only when listed in ``sweep.ignore_columns``;
    one case per row; ``sweep.convention`` = "wrlayer" (default) or "contact" (sign factors)."""
    rel = sweep.text("csv")
    path = resolve_path(rel, base, sweep.what("csv"))
    convention = sweep.text("convention", "wrlayer")
    if convention not in CSV_CONVENTIONS:
        raise sweep.error("convention", f"must be one of {', '.join(CSV_CONVENTIONS)}, got {convention!r}")
    ignore = tuple(sweep.table["ignore_columns"]) if "ignore_columns" in sweep.table else ()
    if not all(isinstance(c, str) for c in ignore):
        raise sweep.error("ignore_columns", "must be a list of column names")
    table = read_numeric_csv(path, SWEEP_KEYS, what=sweep.what("csv") + f" ({rel})", label="case", ignore=ignore,
                             ignore_key="sweep.ignore_columns", max_rows=MAX_CASES)
    _check_direction(sweep, rel, table, convention)
    cols = {h: table.column(h) * CSV_CONVENTIONS[convention].get(h, 1.0) for h in table.columns}
    ignored = (("case",) if table.labels else ()) + table.ignored_columns
    info = SweepCsv(str(path), table.sha256, convention, table.columns, ignored)
    return cols, info


def _rows(sweep: Keys, axes: dict[str, np.ndarray], mode: str) -> list[tuple]:
    """The value rows of the axes: zipped (equal lengths) or their product."""
    if mode == "zip":
        sizes = {k: v.size for k, v in axes.items()}
        if len(set(sizes.values())) > 1:
            raise sweep.error("mode", f"'zip' needs sweep lists of equal length, got {sizes}")
        return list(zip(*axes.values()))
    n_cases = math.prod(v.size for v in axes.values())
    if n_cases > MAX_CASES:
        raise sweep.error("mode", f"'product' of {' x '.join(str(v.size) for v in axes.values())} values gives "
                          f"{n_cases:.3g} cases (at most {MAX_CASES})")
    return list(itertools.product(*axes.values()))


def _check_case(sweep: Keys, case: CaseSpec) -> None:
    for key in ("yaw_rad", "roll_rad"):
        if abs(getattr(case, key)) >= 0.2:
            raise sweep.error(key, f"angle {getattr(case, key):g} rad is not plausible (|angle| < 0.2 rad)")
    for key, low in (("vertical_load_N", MIN_FORCE_N), ("speed_mm_s", 0.0)):
        value = getattr(case, key)
        if not (value > 0 and value >= low):
            raise sweep.error(key, f"must be > 0 in every case{f' (at least {low:g})' if low else ''}, got "
                              f"{value:g}")


def parse_sweep(sweep: Keys | None, base_case: CaseSpec, base: Path, roll_auto: bool) -> SweepSpec:
    """The cases of [sweep] (``sweep`` None: the one case ``base_case``); ``base`` is the scene file's folder."""
    if sweep is None:
        return SweepSpec(cases=(base_case,))
    sweep.check_known(KEYS)
    axes, info = {}, None
    if "csv" in sweep.table:
        both = [k for k in SWEEP_KEYS if k in sweep.table]
        axes, info = _csv_columns(sweep, base)
        if both:
            raise sweep.error(both[0], "give the per-case values either in the CSV (sweep.csv) or as lists, not both")
    elif "convention" in sweep.table:
        raise sweep.error("convention", "applies to a sweep CSV only (sweep.csv)")
    axes.update({k: sweep_values(sweep, k) for k in SWEEP_KEYS if k in sweep.table})
    if not axes:
        raise sweep.error("lateral_mm", f"[sweep] needs at least one of {', '.join(SWEEP_KEYS)} or a csv")
    mode = sweep.text("mode", "zip")
    if mode not in ("zip", "product"):
        raise sweep.error("mode", f"must be 'zip' or 'product', got {mode!r}")
    names = list(axes)
    cases = tuple(dataclasses.replace(base_case, **{k: float(v) for k, v in zip(names, row)})
                  for row in _rows(sweep, axes, mode))
    for case in cases:
        _check_case(sweep, case)
    if roll_auto and "roll_rad" in axes:
        raise sweep.error("roll_rad", "cannot sweep the roll angle when wheelset.roll_rad = \"auto\"")
    return SweepSpec(mode, info, cases)


__all__ = ["CSV_CONVENTIONS", "KEYS", "MAX_CASES", "parse_sweep", "sweep_values"]
