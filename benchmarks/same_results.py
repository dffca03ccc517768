"""Do two output folders hold the same results? The check behind "results unchanged" for a restructure.

    python -m benchmarks.same_results BEFORE AFTER [--rtol 1e-9] [--ignore KEY ...]

Walks both folders and compares every file found under the same relative path:

- ``.json``: recursively, numbers within ``rtol`` relative (``atol`` absolute for values near zero), strings and
  keys equal; keys that record how or where a run was made (code version, run times, paths, host, dates) are
  skipped (``IGNORED_KEYS`` and ``--ignore``).
- ``.csv``, ``.prr``, ``.prw``, ``.txt``, ``.md``: line by line, each line split into number and text tokens,
  numbers within ``rtol``; lines containing an ignored key or a run time (``... s``) are skipped in text files.
- pictures and other binaries: present on both sides (their pixels depend on the matplotlib version).

Prints one line per difference (at most ``--most``) and a summary; exit 0 when the folders agree, 1 when they do
not, 2 on bad input.
"""

from __future__ import annotations

import argparse
import csv
import io
import json
import math
import re
import sys
from pathlib import Path
from typing import Iterator

#: Keys describing the run rather than its result (code revision, time, place, machine).
IGNORED_KEYS = frozenset({
    "code_version", "timings", "timing", "wall_s", "elapsed_s", "cpu_s", "seconds", "run_time_s", "revision",
    "host", "hostname", "platform", "python", "created", "created_utc", "date", "started", "finished", "scene_file", "path",
    "out", "output_dir", "versions", "package_versions", "command",
})
#: Keys and CSV columns holding a run time (s), recognised by name: ``time_s``, ``total_s``, ``timings_s``, ``*_s``
#: inside a ``timings`` record; a unit such as ``speed_mm_s`` or ``pitch_rate_rad_s`` is not a run time.
RUN_TIME_KEY = re.compile(r"^(?:time_s|total_s|timings?(?:_s)?|.*_time_s|.*seconds.*|wall.*|elapsed.*|cpu.*)$")
TEXT_SUFFIXES = (".csv", ".prr", ".prw", ".txt", ".md", ".toml", ".log")
BINARY_SUFFIXES = (".png", ".svg", ".pdf", ".vtu", ".vtk", ".vtp", ".pvd", ".npz", ".npy")
NUMBER = re.compile(r"[-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?")
RUN_TIME = re.compile(r"\d\s*(?:s|ms|min)\b|load average|git [0-9a-f]{7}|/work/|/tmp/")


def close(a: float, b: float, rtol: float, atol: float) -> bool:
    """True when a and b agree within rtol relative or atol absolute (NaN equals NaN)."""
    if math.isnan(a) or math.isnan(b):
        return math.isnan(a) and math.isnan(b)
    return abs(a - b) <= max(atol, rtol * max(abs(a), abs(b)))


def json_differences(a, b, where: str, rtol: float, atol: float, ignored: frozenset[str]) -> Iterator[str]:
    """Yield one line per difference between two parsed JSON values."""
    if isinstance(a, dict) and isinstance(b, dict):
        for key in sorted(set(a) | set(b)):
            if key in ignored or RUN_TIME_KEY.match(key):
                continue
            if key not in a or key not in b:
                yield f"{where}.{key}: only {'after' if key not in a else 'before'}"
                continue
            yield from json_differences(a[key], b[key], f"{where}.{key}", rtol, atol, ignored)
    elif isinstance(a, list) and isinstance(b, list):
        if len(a) != len(b):
            yield f"{where}: {len(a)} items before, {len(b)} after"
            return
        for i, (x, y) in enumerate(zip(a, b)):
            yield from json_differences(x, y, f"{where}[{i}]", rtol, atol, ignored)
    elif isinstance(a, bool) or isinstance(b, bool):
        if a != b:
            yield f"{where}: {a!r} before, {b!r} after"
    elif isinstance(a, (int, float)) and isinstance(b, (int, float)):
        if not close(float(a), float(b), rtol, atol):
            yield f"{where}: {a!r} before, {b!r} after"
    elif isinstance(a, str) and isinstance(b, str) and ("/" in a or "\\" in a) and ("/" in b or "\\" in b):
        return  # a path: where the run was made, not what it found
    elif a != b:
        yield f"{where}: {str(a)[:60]!r} before, {str(b)[:60]!r} after"


def csv_differences(a: str, b: str, name: str, rtol: float, atol: float) -> Iterator[str]:
    """Yield one line per differing cell of two CSV tables, run-time columns left out, numbers within rtol."""
    rows_a, rows_b = list(csv.reader(io.StringIO(a))), list(csv.reader(io.StringIO(b)))
    if not rows_a or not rows_b or rows_a[0] != rows_b[0]:
        yield f"{name}: header differs"
        return
    if len(rows_a) != len(rows_b):
        yield f"{name}: {len(rows_a)} rows before, {len(rows_b)} after"
    keep = [i for i, column in enumerate(rows_a[0]) if not RUN_TIME_KEY.match(column.strip())]
    for r, (x, y) in enumerate(zip(rows_a[1:], rows_b[1:]), start=2):
        for i in keep:
            u, v = (x[i] if i < len(x) else ""), (y[i] if i < len(y) else "")
            if u == v:
                continue
            try:
                same = close(float(u), float(v), rtol, atol)
            except ValueError:
                same = False
            if not same:
                yield f"{name}:{r}: {rows_a[0][i]} {u!r} before, {v!r} after"


def text_differences(a: str, b: str, name: str, rtol: float, atol: float, ignored: frozenset[str]) -> Iterator[str]:
    """Yield one line per differing line of two text files, numbers compared within rtol."""
    if name.endswith(".csv") and not a.startswith("#"):
        yield from csv_differences(a, b, name, rtol, atol)
        return
    lines_a = [line for line in a.splitlines() if not _run_line(line, ignored)]
    lines_b = [line for line in b.splitlines() if not _run_line(line, ignored)]
    if len(lines_a) != len(lines_b):
        yield f"{name}: {len(lines_a)} lines before, {len(lines_b)} after"
    for i, (x, y) in enumerate(zip(lines_a, lines_b)):
        if NUMBER.sub("#", x) != NUMBER.sub("#", y):
            yield f"{name}:{i + 1}: text differs: {x[:50]!r} / {y[:50]!r}"
            continue
        for u, v in zip(NUMBER.findall(x), NUMBER.findall(y)):
            if not close(float(u), float(v), rtol, atol):
                yield f"{name}:{i + 1}: {u} before, {v} after"
                break


def _run_line(line: str, ignored: frozenset[str]) -> bool:
    return bool(RUN_TIME.search(line)) or any(key in line for key in ignored if len(key) > 6)


def folder_differences(before: Path, after: Path, rtol: float, atol: float,
                       ignored: frozenset[str]) -> Iterator[str]:
    """Yield the differences between every pair of files under the same relative path."""
    files_a = {p.relative_to(before) for p in before.rglob("*") if p.is_file()}
    files_b = {p.relative_to(after) for p in after.rglob("*") if p.is_file()}
    for rel in sorted(files_a ^ files_b):
        yield f"{rel}: only {'before' if rel in files_a else 'after'}"
    for rel in sorted(files_a & files_b):
        pa, pb = before / rel, after / rel
        if rel.suffix == ".json":
            yield from json_differences(json.loads(pa.read_text()), json.loads(pb.read_text()), str(rel),
                                        rtol, atol, ignored)
        elif rel.suffix in TEXT_SUFFIXES:
            yield from text_differences(pa.read_text(errors="replace"), pb.read_text(errors="replace"), str(rel),
                                        rtol, atol, ignored)
        elif rel.suffix not in BINARY_SUFFIXES and pa.read_bytes() != pb.read_bytes():
            yield f"{rel}: bytes differ"


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(prog="python -m benchmarks.same_results", description=__doc__.split("\n")[0])
    parser.add_argument("before", type=Path)
    parser.add_argument("after", type=Path)
    parser.add_argument("--rtol", type=float, default=1e-9, help="relative tolerance on numbers (default 1e-9)")
    parser.add_argument("--atol", type=float, default=1e-12, help="absolute tolerance near zero (default 1e-12)")
    parser.add_argument("--ignore", nargs="*", default=(), help="further JSON keys to skip")
    parser.add_argument("--most", type=int, default=40, help="differences printed at most (default 40)")
    args = parser.parse_args(argv)
    for folder in (args.before, args.after):
        if not folder.is_dir():
            print(f"error: {folder}: not a folder", file=sys.stderr)
            return 2
    ignored = IGNORED_KEYS | frozenset(args.ignore)
    n = 0
    for line in folder_differences(args.before, args.after, args.rtol, args.atol, ignored):
        if n < args.most:
            print(line)
        n += 1
    print(f"{n} difference(s) between {args.before} and {args.after} (rtol {args.rtol:g})")
    return 1 if n else 0


if __name__ == "__main__":
    sys.exit(main())
