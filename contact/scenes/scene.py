"""Contact scenes: TOML files -> validated dataclasses (:mod:`contact.scenes.scene_spec`; units mm, N, MPa, s).

A scene describes one Kik–Piotrowski contact (paper section 4) with an optional Prandtl-body layer, optional
creepages for FASTSIM and optional repeated passes (section 5). Keys (all carry their unit):

    title, description                       free text (optional)
    type                                     "kik_piotrowski" (default) or "wheel_rail" (dispatched elsewhere)
    [load]       normal_force_N, rolling_radius_mm                             (both > 0, required)
    [material]   E_MPa (> 0), poisson (0 <= nu < 0.5)                          (required)
    [separation] y_mm, f_mm      table, y strictly increasing, finite           (or)
                 lateral_radius_mm, half_width_mm (default 10), step_mm (default grid_mm / 4):
                 the parabola f = y^2 / (2 R_y) sampled on [-half_width, half_width]
    [layers]     rail, wheel: a calibration table (JSON, relative to the scene file) or {u_mm, p_MPa} per body;
                 position_mm = {rail, wheel} (profile coordinate of the contact point on each body with a table),
                 scale_to_patch (tables); or [layers.combined] u_mm, p_MPa: ONE characteristic for wheel and rail
                 together (the paper's eq. 13 layer); contact.scenes.layers. The earlier [layer] is still read.
    [tangential] creepage_x, creepage_y (-), spin_per_mm (1/mm), friction (>= 0), speed_mm_s (> 0, default 1000),
                 flexibility ("three" (default), "single", "blended": FASTSIM flexibility rule, contact.tangential.fastsim);
                 creepages about the scene's origin, |creepage| <= 0.1, |spin| <= 0.01 1/mm, friction > 0 with creepages
    [passes]     max, hardening, tolerance_mm, memory, traction_coefficient
    [method]     alpha, grid_mm, fastsim_cells, normal, exact_cells, layer_mode, tangential
    [output]     vtk, convention
    [reference]  published numbers to compare with (optional; any of the Table 1 keys, see REFERENCE_KEYS)

The units, defaults and bounds of [load], [material], [tangential], [passes], [method] and [output] are declared
once on their sections' fields (:mod:`contact.scenes.sections`; docs/scene-keys.md lists them). Every problem raises :class:`wrlayer.errors.InputError` naming the file and the key, e.g.
``scene.toml: load.normal_force_N: must be > 0, got -5``. Unknown keys are errors (they catch typos).
"""

from __future__ import annotations

import math
from pathlib import Path
from typing import Any

import numpy as np

from contact.scenes.layers import read_layers, read_old_layer
from contact.scenes.scene_spec import Scene, SeparationSpec
from contact.scenes.sections import (LoadSpec, OutputSpec, read_creepages, read_material, read_method,
                                     read_passes)
from wrlayer.errors import InputError
from wrlayer.hashing import file_sha256_or_none, sha256_hex
from wrlayer.input_files import read_toml
from wrlayer.section_keys import read_section
from wrlayer.validate import MAX_STRIPS, MIN_LATERAL_RADIUS_MM, Keys, top_keys

SCENE_TYPES = ("kik_piotrowski", "wheel_rail")
#: Keys allowed in [reference]: published values of the last pass (Table 1 rows), units in the names.
REFERENCE_KEYS = ("source", "length_mm", "width_mm", "area_mm2", "delta_mm", "Fx_N", "Fy_N", "p_max_MPa",
                  "WT_max_N_per_mm", "PT_max_W_per_mm2", "passes", "u0_mm", "up0_mm")


# ---------------------------------------------------------------------------------------------------- reading
def read_scene_data(path: str | Path) -> tuple[Path, dict[str, Any]]:
    """Read a TOML scene file safely (:func:`wrlayer.input_files.read_toml`: a regular file of bounded size,
    UTF-8, nesting bounded); InputError when missing, unreadable or not valid TOML."""
    path = Path(path)
    return path, read_toml(path, what=str(path))


def load_scene(path: str | Path) -> Scene:
    """Read and validate a Kik–Piotrowski scene file."""
    path, data = read_scene_data(path)
    return parse_scene(data, path)


def scene_type(data: dict[str, Any], path: Path) -> str:
    """The scene's top-level ``type`` ("kik_piotrowski" when absent)."""
    kind = data.get("type", "kik_piotrowski")
    if kind not in SCENE_TYPES:
        raise InputError(f"{path.name}: type", f"must be one of {', '.join(SCENE_TYPES)}, got {kind!r}")
    return kind


class SceneKeys(Keys):
    """Typed, validating access to one TOML table of a scene file: :class:`wrlayer.validate.Keys` (the one
    validation layer of every reader; public: the wheel–rail scene parser uses it)."""


TOP_KEYS = ("title", "description", "type", "accept_implausible", "load", "material", "separation", "layers", "layer", "tangential",
            "passes", "method", "output", "reference")


def parse_scene(data: dict[str, Any], path: str | Path) -> Scene:
    """Validate the TOML content of a Kik–Piotrowski scene read from ``path`` (relative paths resolve from its
    folder). Raises InputError naming ``<file>: <section>.<key>``."""
    path = Path(path)
    file = path.name
    top = top_keys(file, data, SceneKeys)
    top.check_known(TOP_KEYS)
    kind = scene_type(data, path)
    if kind != "kik_piotrowski":
        raise InputError(f"{file}: type", f"a {kind!r} scene is not a Kik–Piotrowski scene")
    title = top.text("title", path.stem)
    description = top.text("description", "")

    for required in ("load", "material", "separation"):
        if required not in data:
            raise InputError(f"{file}: {required}", f"missing section [{required}] (required)")

    def section(name: str) -> SceneKeys:
        return top.sub(name) if name in data else SceneKeys(file, name, {})

    load = read_section(LoadSpec, section("load"))
    material = read_material(section("material"), required=True)
    method = read_method(section("method"))

    separation = _parse_separation(top.sub("separation"), method.grid_mm)
    n_strips = (separation.y_mm[-1] - separation.y_mm[0]) / method.grid_mm
    if n_strips > MAX_STRIPS:
        raise InputError(f"{file}: method.grid_mm", f"{method.grid_mm:g} mm gives {n_strips:.3g} strips over the "
                         f"separation table (at most {MAX_STRIPS}): use a coarser grid or a shorter table")
    if n_strips < 2:
        raise InputError(f"{file}: method.grid_mm", f"{method.grid_mm:g} mm is wider than the separation table "
                         f"({separation.y_mm[0]:g}..{separation.y_mm[-1]:g} mm)")
    layers = _layers(top, path.parent)
    tangential = read_creepages(top.sub("tangential")) if "tangential" in data else None
    passes = read_passes(section("passes"))
    if passes.max > 1 and layers is None:
        raise top.sub("passes").error("max", f"repeated passes ({passes.max}) need [layers] (without a layer every "
                                             "pass is the same elastic contact)")
    output = read_section(OutputSpec, section("output"))

    reference: dict[str, Any] = {}
    if (keys := top.sub("reference")) is not None:
        keys.check_known(REFERENCE_KEYS)
        for key in keys.table:
            reference[key] = keys.text(key) if key == "source" else keys.number(key)

    hashes = [file_sha256_or_none(path) or ""]
    hashes += [] if layers is None else layers.table_hashes()
    return Scene(path=path, title=title, description=description, load=load, material=material,
                 separation=separation, layers=layers, tangential=tangential, passes=passes, method=method,
                 output=output, reference=reference, data=data,
                 content_hash=sha256_hex("".join(hashes)))


def _layers(top: SceneKeys, base: Path):
    """[layers] (None: elastic bodies); the deprecated [layer] read as [layers]."""
    if "layer" in top.table and "layers" in top.table:
        raise top.error("layer", "give [layers] only ([layer] is its deprecated form)")
    if "layer" in top.table:
        return read_old_layer(top.sub("layer"), base)
    if "layers" in top.table:
        return read_layers(top.sub("layers"), base, per_body=True)
    return None


def _parse_separation(keys: SceneKeys, grid_mm: float) -> SeparationSpec:
    if "lateral_radius_mm" in keys.table:
        keys.check_known(("lateral_radius_mm", "half_width_mm", "step_mm"))
        radius = keys.plausible_number("lateral_radius_mm", "profile_radius_mm", ge=MIN_LATERAL_RADIUS_MM)
        half = keys.number("half_width_mm", 10.0, gt=0.0)
        step = keys.number("step_mm", grid_mm / 4.0, gt=0.0)
        if half / step > 2 * MAX_STRIPS:
            what = keys.what("step_mm") if "step_mm" in keys.table else f"{keys.file}: method.grid_mm"
            raise InputError(what, f"gives {2 * half / step:.3g} separation points over +-{half:g} mm "
                             f"(at most {4 * MAX_STRIPS}): use a coarser grid")
        n = math.ceil(half / step)
        y = np.linspace(-n * step, n * step, 2 * n + 1)
        return SeparationSpec(y, y * y / (2.0 * radius), kind="parabola", lateral_radius_mm=radius)
    keys.check_known(("y_mm", "f_mm"))
    y = keys.array("y_mm", min_len=3)
    f = keys.array("f_mm", min_len=3)
    if y.size != f.size:
        raise keys.error("f_mm", f"has {f.size} values but y_mm has {y.size}")
    steps = np.diff(y)
    if np.any(steps <= 0):
        i = int(np.argmax(steps <= 0))
        raise keys.error("y_mm", f"must be strictly increasing (f must be a function of y): y[{i}] = {y[i]:g} "
                         f">= y[{i + 1}] = {y[i + 1]:g}")
    return SeparationSpec(y, f)


__all__ = ["REFERENCE_KEYS", "SCENE_TYPES", "SceneKeys", "TOP_KEYS", "load_scene", "parse_scene", "read_scene_data",
           "scene_type"]
