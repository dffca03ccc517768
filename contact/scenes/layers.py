"""[layers] of every scene kind: the Prandtl-body layers as typed data, read once, and the one builder of a patch's
layers on its strip grid (units mm, MPa).

One TOML shape for the contact and the wheel–rail scenes::

    [layers]
    rail = "tables/rail_60E1_default.json"   # a calibration table (relative to the scene file), or in a contact
    wheel = {u_mm = [...], p_MPa = [...]}    #   scene a characteristic of that body
    scale_to_patch = true                    # tables scaled to the solved patch size (docs/calibration.md)
    position_mm = {rail = 0.0, wheel = 0.0}  # contact scene: the contact point's profile coordinate on each body
    [layers.combined]                        # or ONE characteristic for wheel and rail together (paper eq. 13)
    u_mm = [...]
    p_MPa = [...]

A contact scene's earlier ``[layer]`` (``u_mm``/``p_MPa``, ``[layer.wheel]``/``[layer.rail]`` with ``table``,
``position_mm``, ``scale_to_patch``) is still read, with one deprecation line on stderr (:func:`read_old_layer`).
"""

from __future__ import annotations

import sys
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Callable

import numpy as np

from contact.layer.prandtl_layer import LayerPair, PrandtlLayer
from contact.layer.strip_lookup import LayerLookup, clamped_characteristics
from contact.scenes.result_io import Record
from wrlayer.characteristic import Characteristic
from wrlayer.errors import InputError, require
from wrlayer.hashing import file_sha256
from wrlayer.layer_table import read_body_table
from wrlayer.validate import Keys

#: The bodies of a layer, in the order their tables are hashed and checked.
BODIES = ("wheel", "rail")
LAYERS_KEYS = ("rail", "wheel", "combined", "scale_to_patch", "position_mm")


@dataclass(frozen=True)
class CharacteristicSpec(Record):
    """A characteristic p(u) given in the scene (``[layers.combined]``, or a body's ``{u_mm, p_MPa}``).

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
class LayerSources:
    """The layers as read, for the solvers: per body a calibration table (a :class:`LayerLookup`) or a
    characteristic, or one ``combined`` characteristic of both bodies. ``names``: body -> table name for messages;
    ``position_mm``: body -> the contact point's profile coordinate (contact scenes); ``scale_to_patch``: scale the
    tables' characteristics to each patch's solved semi-axes."""

    rail: LayerLookup | Characteristic | None = None
    wheel: LayerLookup | Characteristic | None = None
    combined: Characteristic | None = None
    names: dict = field(default_factory=dict)
    scale_to_patch: bool = False
    position_mm: dict = field(default_factory=dict)

    def __post_init__(self):
        require(self.combined is None or (self.rail is None and self.wheel is None), "layers",
                "give either per-body layers (rail, wheel) or one combined characteristic, not both")
        require(not (self.scale_to_patch and self.combined is not None), "layers.scale_to_patch",
                "only used with calibration tables (rail, wheel), not with a combined characteristic")

    @property
    def empty(self) -> bool:
        return self.rail is None and self.wheel is None and self.combined is None

    def name(self, body: str) -> str:
        """The table name of ``body`` (for messages)."""
        return self.names.get(body, body)

    def at_contact(self) -> list[Characteristic]:
        """The characteristics at the contact point: the combined one, or each body's (a table's at its
        ``position_mm``)."""
        if self.combined is not None:
            return [self.combined]
        return [s if isinstance(s, Characteristic) else s.characteristic_at(self.position_mm[b])
                for b in BODIES if (s := getattr(self, b)) is not None]

    def tables(self) -> dict[str, LayerLookup]:
        """The bodies' calibration tables (body -> table), in :data:`BODIES` order."""
        return {b: t for b in BODIES if (t := getattr(self, b)) is not None and not isinstance(t, Characteristic)}


@dataclass(frozen=True)
class LayersSpec(Record):
    """[layers]: calibration tables or characteristics per body, or one combined characteristic.

    Attributes
    ----------
    rail : str | CharacteristicSpec | None
        Rail calibration table (resolved path of the JSON table) or, in a contact scene, the rail's characteristic.
    wheel : str | CharacteristicSpec | None
        Wheel calibration table or characteristic, as ``rail``.
    combined : CharacteristicSpec | None
        One characteristic for both bodies instead (``[layers.combined]``; the paper's eq. 13 layer).
    scale_to_patch : bool
        Scale each patch's table characteristics to its own solved semi-axes (displacements x sqrt(ab) /
        sqrt(a_c b_c); docs/calibration.md) (-).
    sha256 : dict
        sha256 of each table file (body -> hex).
    position_mm : dict | None
        Contact scene: the contact point's profile coordinate on each body with a table (body -> mm); the
        wheel–rail scene finds it by the contact search.
    sources : LayerSources
        The layers as read (not compared, not written).
    """

    rail: str | CharacteristicSpec | None = None
    wheel: str | CharacteristicSpec | None = None
    combined: CharacteristicSpec | None = None
    scale_to_patch: bool = False
    sha256: dict = field(default_factory=dict)
    position_mm: dict | None = field(default=None, metadata={"omit_none": True})
    sources: LayerSources = field(default_factory=LayerSources, compare=False, repr=False)

    @classmethod
    def from_dict(cls, data: dict[str, Any]) -> LayersSpec:
        """The spec of :meth:`to_dict` (the tables read again)."""
        table = {k: v for k, v in data.items() if k in LAYERS_KEYS and v is not None}
        return read_layers(Keys("layers", "", table), Path("/"), per_body=data.get("position_mm") is not None)

    def table_hashes(self) -> list[str]:
        """The tables' sha256 in :data:`BODIES` order (a contact scene's content hash)."""
        return [self.sha256[b] for b in BODIES if b in self.sha256]


def _characteristic(keys: Keys) -> CharacteristicSpec:
    keys.check_known(("u_mm", "p_MPa"))
    return CharacteristicSpec(tuple(keys.array("u_mm").tolist()), tuple(keys.array("p_MPa").tolist()))


def _char(spec: CharacteristicSpec, what: str) -> Characteristic:
    return Characteristic(spec.u_mm, spec.p_MPa, name=f"{what}.u_mm/p_MPa")


def read_layers(keys: Keys, base: Path, per_body: bool = False) -> LayersSpec:
    """[layers] of ``keys`` with its tables read (relative to ``base``). ``per_body``: the contact scene's form
    (a body may be a characteristic; every table needs its ``position_mm``, which it must cover)."""
    keys.check_known(LAYERS_KEYS if per_body else tuple(k for k in LAYERS_KEYS if k != "position_mm"))
    scale = keys.boolean("scale_to_patch", False)
    if "combined" in keys.table:
        if "rail" in keys.table or "wheel" in keys.table:
            raise keys.error("combined", "give either per-body layers (rail, wheel) or combined, not both")
        if scale:
            raise keys.error("scale_to_patch", "only used with calibration tables (rail, wheel), not with "
                                               "[layers.combined]")
        combined = _characteristic(keys.sub("combined"))
        return LayersSpec(combined=combined, sources=LayerSources(combined=_char(combined, keys.what("combined"))))
    if not any(b in keys.table for b in BODIES):
        raise keys.error("rail", "[layers] needs rail and/or wheel tables, or [layers.combined]")
    positions = keys.sub("position_mm") or Keys(keys.file, f"{keys.prefix}.position_mm", {})
    spec, sources, names, hashes, given = {}, {}, {}, {}, {}
    for body in BODIES:
        if body not in keys.table:
            continue
        if isinstance(keys.table[body], dict):
            if not per_body:
                raise keys.error(body, "must be a calibration table file (a string): a wheel–rail scene reads each "
                                       "body's table at the contact search's profile coordinates")
            spec[body] = _characteristic(keys.sub(body))
            sources[body] = _char(spec[body], keys.what(body))
            continue
        path, sources[body] = read_body_table(keys.text(body), base, body, keys.what(body))
        spec[body], names[body] = str(path), path.name
        hashes[body] = file_sha256(path)
        if per_body:
            given[body] = positions.number(body)
            _check_covers(sources[body], given[body], path, body, keys.what(body))
        if scale and any(sources[body].calibrated_length_mm(y) is None for y in sources[body].y_range_mm):
            raise keys.error("scale_to_patch", f"the {body} table {path.name} records no calibrated semi-axes "
                             "(geometry a_mm, b_mm): it cannot be scaled")
    if scale and not names:
        raise keys.error("scale_to_patch", "only used with a calibration table (rail, wheel)")
    for body in positions.table:
        if body not in names:
            raise positions.error(body, "only used with a calibration table (layers.<body> = \"table.json\")"
                                  if body in BODIES else f"unknown key (allowed: {', '.join(names)})")
    return LayersSpec(rail=spec.get("rail"), wheel=spec.get("wheel"), scale_to_patch=scale, sha256=hashes,
                      position_mm=given if per_body else None,
                      sources=LayerSources(rail=sources.get("rail"), wheel=sources.get("wheel"), names=names,
                                           scale_to_patch=scale, position_mm=given))


def _check_covers(table, position_mm: float, path: Path, body: str, what: str) -> None:
    """The table must cover the contact point (InputError naming ``what``)."""
    lo, hi = (float(v) for v in table.y_range_mm)
    if not lo <= position_mm <= hi:
        raise InputError(what, f"does not cover the contact location y = {position_mm:.4g} mm on the {body} (table "
                         f"{path.name} covers {lo:.4g}..{hi:.4g} mm)")


def read_old_layer(keys: Keys, base: Path) -> LayersSpec:
    """A contact scene's deprecated ``[layer]`` table read as [layers] (one deprecation line on stderr):
    ``u_mm``/``p_MPa`` are ``[layers.combined]``; ``[layer.<body>]`` ``u_mm``/``p_MPa`` the body's characteristic,
    ``table`` the body's table with its ``position_mm`` and ``scale_to_patch`` (the same for every table)."""
    print(f"warning: {keys.file}: [layer] is deprecated, write [layers] (docs/scene-keys.md)", file=sys.stderr)
    old = keys.table
    if any(k in old for k in ("u_mm", "p_MPa")):
        if any(b in old for b in BODIES):
            raise keys.error("u_mm", "give either one combined characteristic (layer.u_mm, layer.p_MPa) or per "
                                     "body layers ([layer.wheel], [layer.rail]), not both")
        combined = _characteristic(keys)  # messages name layer.u_mm, as written
        return LayersSpec(combined=combined, sources=LayerSources(combined=_char(combined, keys.what("combined"))))
    keys.check_known(BODIES)
    new: dict[str, Any] = {}
    scales = set()
    for body in BODIES:
        if body not in old:
            continue
        sub = keys.sub(body)
        if "table" in sub.table:
            sub.check_known(("table", "position_mm", "scale_to_patch"))
            new[body] = sub.table["table"]
            new.setdefault("position_mm", {})[body] = sub.table.get("position_mm")
            scales.add(sub.boolean("scale_to_patch", False))
            if new["position_mm"][body] is None:
                raise sub.error("position_mm", "missing (required)")
        else:
            sub.check_known(("u_mm", "p_MPa"))
            new[body] = old[body]
    if not new:
        raise InputError(keys.what("u_mm"), "missing: [layer] needs u_mm and p_MPa, or [layer.wheel]/[layer.rail]")
    if len(scales) > 1:
        raise keys.error("rail.scale_to_patch", "must be the same for both tables (write [layers] scale_to_patch)")
    if scales == {True}:
        new["scale_to_patch"] = True
    return read_layers(Keys(keys.file, "layer", new), base, per_body=True)


def build_layer_pair(sources: LayerSources | None, strips_mm: np.ndarray, coords_mm: Callable[[str], np.ndarray],
                     patch_mm: tuple[float, float] | None, what: str) -> LayerPair | None:
    """A patch's layers on its strips (mm): per body a uniform layer of its characteristic or the body's table read
    at the strips' profile coordinates ``coords_mm(body)`` (clamped to the table's range,
    :func:`contact.layer.strip_lookup.clamped_characteristics`; with ``scale_to_patch`` scaled to ``patch_mm`` =
    (a, b) in mm), or one combined layer; the layers carry the table's rolling law (and, for a law with convexity
    nodes, the table's lateral curvature at the strips). ``what`` names [layers] in
    messages (``<file>: layers``). None without layers."""
    if sources is None or sources.empty:
        return None
    if sources.combined is not None:
        return LayerPair(combined=PrandtlLayer.uniform(sources.combined, strips_mm, name=f"{what}.combined"))
    built = {}
    for body in BODIES:
        source = getattr(sources, body)
        if isinstance(source, Characteristic):
            built[body] = PrandtlLayer.uniform(source, strips_mm, name=f"{what}.{body}")
        elif source is not None:
            name = f"{what}.{body} ({sources.name(body)})"
            coords = coords_mm(body)
            chars, _ = clamped_characteristics(source, coords, name, patch_mm if sources.scale_to_patch else None)
            law = source.rolling_law
            curvature = (source.lateral_curvature_at(np.asarray(coords, dtype=float))
                         if law is not None and law.convexity is not None else None)  # the law reads b / (2 R)
            built[body] = PrandtlLayer.from_characteristics(chars, strips_mm, name=name, rolling_law=law,
                                                            lateral_curvature_per_mm=curvature)
    return LayerPair(**built)


__all__ = ["BODIES", "CharacteristicSpec", "LayerSources", "LayersSpec", "build_layer_pair", "read_layers",
           "read_old_layer"]
