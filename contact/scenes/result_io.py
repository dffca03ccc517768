"""Result JSON of a contact scene: units, code version, JSON conversion and atomic writing.

Strict JSON is written (no NaN/Infinity: non-finite numbers become null); numpy arrays become lists.
"""

from __future__ import annotations

import dataclasses
import json
import math
from pathlib import Path
from typing import Any

import numpy as np

from wrlayer.atomic_write import atomic_write_text
from wrlayer.version import code_version  # noqa: F401  (re-exported: results record it)

RESULT_NAME = "result.json"
#: File-name patterns of the pictures of :mod:`contact.scenes.plots` (stale ones are removed by the command line).
PICTURE_PATTERNS = ("patch_pass*.png", "separation.png", "shakedown.png")

#: Units of the result fields (keys without a unit suffix are listed here too).
UNITS = {
    "length": "mm", "force": "N", "stress": "MPa (N/mm^2)", "time": "s", "speed": "mm/s",
    "layer_stiffness": "N/mm^3", "spin": "1/mm", "creepage": "-",
    "WT_max": "N/mm (= N mm/mm^2: frictional work per unit area over one pass, FASTSIM)",
    "PT_max_W_per_mm2": "W/mm^2 (frictional power density at speed_mm_s)",
    "Mz_Nmm": "N mm (spin moment about the patch origin, on body 1)",
    "Fx_N, Fy_N": "N (creep forces on body 1 = the wheel; Kalker's sign convention)",
    "u0_mm": "mm (layer displacement at the reference point under load, both layers)",
    "up0_mm": "mm (residual layer displacement at the reference point added by this pass)",
    "timings": "s (wall clock)",
    "dissipated_energy_max_N_per_mm": "N/mm (= N mm/mm^2: largest accumulated slider friction work of an element)",
}


def jsonable(obj: Any) -> Any:
    """Plain JSON data from numpy values, paths, dataclasses, tuples; non-finite floats -> None."""
    if isinstance(obj, dict):
        return {str(k): jsonable(v) for k, v in obj.items()}
    if isinstance(obj, (list, tuple)):
        return [jsonable(v) for v in obj]
    if isinstance(obj, np.ndarray):
        return jsonable(obj.tolist())
    if isinstance(obj, (bool, np.bool_)):
        return bool(obj)
    if isinstance(obj, (int, np.integer)):
        return int(obj)
    if isinstance(obj, (float, np.floating)):
        value = float(obj)
        return value if math.isfinite(value) else None
    if isinstance(obj, Path):
        return str(obj)
    if dataclasses.is_dataclass(obj) and not isinstance(obj, type):
        return jsonable({f.name: getattr(obj, f.name) for f in dataclasses.fields(obj)})
    if obj is None or isinstance(obj, str):
        return obj
    raise TypeError(f"cannot write {type(obj).__name__} to the result JSON")


def result_text(result: dict[str, Any]) -> str:
    """The result as strict, indented JSON text (ends with a newline)."""
    return json.dumps(jsonable(result), indent=1, allow_nan=False) + "\n"


def write_result(out_dir: str | Path, result: dict[str, Any]) -> Path:
    """Write ``out_dir/result.json`` atomically; returns its path."""
    return atomic_write_text(Path(out_dir) / RESULT_NAME, result_text(result))


def read_result(path: str | Path) -> dict[str, Any]:
    """Read a result JSON written by :func:`write_result` (a file or a folder holding result.json)."""
    path = Path(path)
    if path.is_dir():
        path = path / RESULT_NAME
    return json.loads(path.read_text(encoding="utf-8"))
