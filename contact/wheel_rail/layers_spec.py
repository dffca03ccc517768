"""[layers] of a wheel–rail scene as typed data: calibration tables per body or one combined characteristic, read
once (units mm, MPa).
"""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from wrlayer.characteristic import Characteristic
from wrlayer.layer_table import read_body_table
from contact.scenes.result_io import Record
from contact.wheel_rail.inputs import WheelRailLayers
from wrlayer.hashing import file_sha256
from wrlayer.errors import InputError


@dataclass(frozen=True)
class CombinedLayerSpec(Record):
    """[layers.combined]: one characteristic for both bodies (the paper's eq. 13 layer).

    Attributes
    ----------
    u_mm : tuple[float, ...]
        Layer displacements of the characteristic's points (mm, paper eq. 13).
    p_MPa : tuple[float, ...]
        Pressures of the characteristic's points (MPa, paper eq. 13).
    """

    u_mm: tuple[float, ...]
    p_MPa: tuple[float, ...]


@dataclass(frozen=True)
class LayersSpec(Record):
    """[layers]: calibration tables per body or one combined characteristic.

    Attributes
    ----------
    rail : str | None
        Rail calibration table (resolved path of the JSON table).
    wheel : str | None
        Wheel calibration table (resolved path of the JSON table).
    combined : CombinedLayerSpec | None
        One characteristic for both bodies instead of tables.
    scale_to_patch : bool
        Scale each patch's table characteristics to its own solved semi-axes (displacements x sqrt(ab) /
        sqrt(a_c b_c); docs/calibration.md) (-).
    sha256 : dict
        sha256 of each table file (body -> hex).
    solver : WheelRailLayers
        The tables as read (not compared, not written).
    """

    rail: str | None = None
    wheel: str | None = None
    combined: CombinedLayerSpec | None = None
    scale_to_patch: bool = False
    sha256: dict = field(default_factory=dict)
    solver: WheelRailLayers = field(default_factory=WheelRailLayers, compare=False, repr=False)

    @classmethod
    def from_dict(cls, data: dict[str, Any]) -> LayersSpec:
        combined = data.get("combined")
        return read_layers(CombinedLayerSpec.from_dict(combined) if combined is not None else None,
                           {b: data[b] for b in ("rail", "wheel") if data.get(b) is not None},
                           bool(data.get("scale_to_patch", False)), Path("/"), "layers")


def read_layers(combined: CombinedLayerSpec | None, tables: dict[str, str], scale_to_patch: bool, base: Path,
                what: str) -> LayersSpec:
    """The layers spec with its tables read (``tables``: body -> table file, relative to ``base``); ``what``
    names the [layers] table in messages (``<file>: layers``)."""
    if combined is not None:
        char = Characteristic(combined.u_mm, combined.p_MPa, name=f"{what}.combined.u_mm/p_MPa")
        return LayersSpec(combined=combined, solver=WheelRailLayers(combined=char))
    read, paths = {}, {}
    for body, rel in tables.items():
        paths[body], read[body] = read_body_table(rel, base, body, f"{what}.{body}")
    if scale_to_patch:
        for body, table in read.items():
            if any(table.calibrated_length_mm(y) is None for y in table.y_range_mm):
                raise InputError(f"{what}.scale_to_patch", f"the {body} table {paths[body].name} records no "
                                 "calibrated semi-axes (geometry a_mm, b_mm): it cannot be scaled")
    solver = WheelRailLayers(rail=read.get("rail"), wheel=read.get("wheel"),
                             names={b: p.name for b, p in paths.items()}, scale_to_patch=scale_to_patch)
    return LayersSpec(rail=str(paths["rail"]) if "rail" in paths else None,
                      wheel=str(paths["wheel"]) if "wheel" in paths else None, scale_to_patch=scale_to_patch,
                      sha256={b: file_sha256(p) for b, p in paths.items()}, solver=solver)


__all__ = ["CombinedLayerSpec", "LayersSpec", "read_layers"]
