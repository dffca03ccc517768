"""A calibration position of a shipped layer table: the profile, the Hertz semi-axes and the material (mm, MPa).

``table_position(path, y_mm)`` reads a layer table (``scenes/tables/*_default.json``, :mod:`wrlayer.layer_table`)
and returns its position at y_mm: the profile named in the table's header, the patch semi-axes a (rolling
direction x) and b (lateral) of the position's Hertz geometry and the table's material. Used by the rolling
section (``[contact] body = "section"``) and the gap cases.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

from calibration.settings import MaterialSettings
from wrlayer.errors import InputError
from wrlayer.layer_table import LayerTable
from wrlayer.shipped import scenes_dir



@dataclass(frozen=True)
class TablePosition:
    """A table's position: the table's path, the profile's name (or file) and body ("rail" or "wheel"), the
    profile coordinate y_mm, the semi-axes a_mm (rolling direction) and b_mm (mm) and the table's material."""

    table: str
    profile: str
    body: str
    y_mm: float
    a_mm: float
    b_mm: float
    material: MaterialSettings


def table_path(table: str | Path) -> Path:
    """A table given absolute, relative to the working folder, or as a shipped one, ``scenes/tables/NAME.json``
    (the shipped scenes folder of the source tree or the installed package, :func:`wrlayer.shipped.scenes_dir`)."""
    path = Path(table)
    if path.is_absolute() or path.is_file() or not path.parts or path.parts[0] != "scenes":
        return path
    return scenes_dir().joinpath(*path.parts[1:])


def table_position(table: str | Path, y_mm: float) -> TablePosition:
    """The position ``y_mm`` (mm) of the layer table ``table`` (:func:`table_path`).
    InputError naming "table" when there is no such file, "y_mm" when the table has no position there."""
    path = table_path(table)
    if not path.is_file():
        raise InputError("table", f"no such layer table: {path}")
    tab = LayerTable.read(path)
    pos = next((p for p in tab.positions if abs(float(p["y_mm"]) - float(y_mm)) < 1e-9), None)
    if pos is None:
        have = ", ".join(f"{float(p['y_mm']):g}" for p in tab.positions)
        raise InputError("y_mm", f"{y_mm:g} mm is not a position of {path.name} (positions: {have} mm)")
    m = tab.header["material"]
    mat = MaterialSettings(E_MPa=float(m["E_MPa"]), poisson=float(m["poisson"]), yield_MPa=float(m["yield_MPa"]),
                           H_iso_MPa=float(m["H_iso_MPa"]), H_kin_MPa=float(m["H_kin_MPa"]))
    return TablePosition(str(table), str(tab.header["profile"]), str(tab.header["body"]), float(y_mm),
                         float(pos["geometry"]["a_mm"]), float(pos["geometry"]["b_mm"]), mat)


__all__ = ["TablePosition", "table_path", "table_position"]
