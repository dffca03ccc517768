"""Result JSON of a scene: its file name, the units of the result fields, the code version, atomic writing and
reading. The records and the JSON conversion: :mod:`wrlayer.json_io`.
"""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any

from wrlayer.atomic_write import atomic_write_text
from wrlayer.json_io import Record, json_text  # noqa: F401  (Record re-exported: the scene records import it here)
from wrlayer.version import code_version  # noqa: F401  (re-exported: results record it)

RESULT_NAME = "result.json"
#: File-name patterns of the pictures of :mod:`contact.scenes.plots` (stale ones are removed by the command line).
PICTURE_PATTERNS = ("patch_pass*.png", "separation.png", "shakedown.png")

#: Units of the result fields (keys without a unit suffix are listed here too).
UNITS = {
    "length": "mm", "force": "N", "stress": "MPa (N/mm^2)", "time": "s", "speed": "mm/s",
    "layer_stiffness": "N/mm^3", "spin": "1/mm", "creepage": "-",
    "WT_max_N_per_mm": "N/mm (= N mm/mm^2: frictional work per unit area over one pass, FASTSIM)",
    "PT_max_W_per_mm2": "W/mm^2 (frictional power density at speed_mm_s)",
    "Mz_Nmm": "N mm (spin moment about the patch origin, on body 1)",
    "Fx_N, Fy_N": "N (creep forces on body 1 = the wheel; Kalker's sign convention)",
    "u0_mm": "mm (layer displacement at the reference point under load, both layers)",
    "up0_mm": "mm (residual layer displacement at the reference point added by this pass)",
    "timings": "s (wall clock)",
    "dissipated_energy_max_N_per_mm": "N/mm (= N mm/mm^2: largest accumulated slider friction work of an element)",
}


def write_result(out_dir: str | Path, result: Record | dict[str, Any]) -> Path:
    """Write ``out_dir/result.json`` atomically; returns its path."""
    return atomic_write_text(Path(out_dir) / RESULT_NAME, json_text(result))


def read_result(path: str | Path) -> dict[str, Any]:
    """Read a result JSON written by :func:`write_result` (a file or a folder holding result.json)."""
    path = Path(path)
    if path.is_dir():
        path = path / RESULT_NAME
    return json.loads(path.read_text(encoding="utf-8"))
