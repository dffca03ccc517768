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
    [layer]      u_mm, p_MPa     ONE characteristic for wheel and rail together (the paper's eq. 13 layer)  (or)
    [layer.wheel], [layer.rail]  per body: u_mm + p_MPa, or table (calibration JSON, relative to the scene file)
                                 + position_mm (profile coordinate of the contact point on that body)
    [tangential] creepage_x, creepage_y (-), spin_per_mm (1/mm), friction (>= 0), speed_mm_s (> 0, default 1000),
                 flexibility ("three" (default), "single", "blended": FASTSIM flexibility rule, contact.tangential.fastsim);
                 creepages about the scene's origin, |creepage| <= 0.1, |spin| <= 0.01 1/mm, friction > 0 with creepages
    [passes]     max (>= 1, default 1), hardening (bool, default false), tolerance_mm (> 0, default 1e-6),
                 memory ("rolling" default | "relaxed" | "state_kept"), traction_coefficient (-1..1, default 0)
    [method]     alpha (0 < alpha <= 1, default 0.55), grid_mm (> 0, default 0.1), fastsim_cells (>= 2, default 60),
                 normal ("kik_piotrowski" (default, the paper's), "exact": FFT half-space, docs/exact-solver.md,
                 or "coarse_exact": the half-space on a coarse grid),
                 exact_cells (exact solver: cells along x over the KP patch length, 8..1024, default 48),
                 layer_mode (exact solver: "indentation" (default) or "rolling"),
                 tangential ("fastsim" (default), "fastrip" or "exact": docs/tangential.md)
    [output]     vtk (bool, default true: vtk/contact_fields.pvd for ParaView), convention ("wrlayer" (default) or
                 "contact": also contact_convention.csv in CONTACT's signs)
    [reference]  published numbers to compare with (optional; any of the Table 1 keys, see REFERENCE_KEYS)

Every problem raises :class:`wrlayer.errors.InputError` naming the file and the key, e.g.
``scene.toml: load.normal_force_N: must be > 0, got -5``. Unknown keys are errors (they catch typos).
"""

from __future__ import annotations

import math
from pathlib import Path
from typing import Any

import numpy as np

from wrlayer.characteristic import Characteristic
from wrlayer.layer_table import read_body_table
from contact.scenes.scene_spec import (
    BODIES,
    BodyLayerSpec,
    LayerSpec,
    LoadSpec,
    MaterialSpec,
    MethodSpec,
    OUTPUT_CONVENTIONS,
    OutputSpec,
    PASSES_KEYS,
    PassesSpec,
    parse_passes_memory,
    Scene,
    SeparationSpec,
    TangentialSpec,
)
from wrlayer.input_files import read_toml
from wrlayer.errors import InputError
from wrlayer.hashing import file_sha256, file_sha256_or_none, sha256_hex
from wrlayer.validate import (
    MAX_E_MPA,
    MAX_FASTSIM_CELLS,
    MAX_PASSES,
    MAX_RADIUS_MM,
    MAX_STRIPS,
    MIN_ALPHA,
    MIN_E_MPA,
    MIN_FORCE_N,
    MIN_GRID_MM,
    MIN_LATERAL_RADIUS_MM,
    MIN_RADIUS_MM,
    Keys,
)

SCENE_TYPES = ("kik_piotrowski", "wheel_rail")
#: Keys allowed in [reference]: published values of the last pass (Table 1 rows), units in the names.
REFERENCE_KEYS = ("source", "length_mm", "width_mm", "area_mm2", "delta_mm", "Fx_N", "Fy_N", "p_max_MPa",
                  "WT_max", "PT_max_W_per_mm2", "passes", "u0_mm", "up0_mm")


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


TOP_KEYS = ("title", "description", "type", "load", "material", "separation", "layer", "tangential", "passes",
            "method", "output", "reference")


def parse_scene(data: dict[str, Any], path: str | Path) -> Scene:
    """Validate the TOML content of a Kik–Piotrowski scene read from ``path`` (relative paths resolve from its
    folder). Raises InputError naming ``<file>: <section>.<key>``."""
    path = Path(path)
    file = path.name
    top = SceneKeys(file, "", data)
    top.check_known(TOP_KEYS)
    kind = scene_type(data, path)
    if kind != "kik_piotrowski":
        raise InputError(f"{file}: type", f"a {kind!r} scene is not a Kik–Piotrowski scene")
    title = top.text("title", path.stem)
    description = top.text("description", "")

    for required in ("load", "material", "separation"):
        if required not in data:
            raise InputError(f"{file}: {required}", f"missing section [{required}] (required)")

    load_keys = top.sub("load")
    load_keys.check_known(("normal_force_N", "rolling_radius_mm"))
    load = LoadSpec(load_keys.number("normal_force_N", ge=MIN_FORCE_N),
                    load_keys.number("rolling_radius_mm", ge=MIN_RADIUS_MM, le=MAX_RADIUS_MM))

    mat_keys = top.sub("material")
    mat_keys.check_known(("E_MPa", "poisson"))
    material = MaterialSpec(mat_keys.number("E_MPa", ge=MIN_E_MPA, le=MAX_E_MPA),
                            mat_keys.number("poisson", ge=0.0, lt=0.5))

    method = _parse_method(top.sub("method"), file)

    separation = _parse_separation(top.sub("separation"), method.grid_mm)
    n_strips = (separation.y_mm[-1] - separation.y_mm[0]) / method.grid_mm
    if n_strips > MAX_STRIPS:
        raise InputError(f"{file}: method.grid_mm", f"{method.grid_mm:g} mm gives {n_strips:.3g} strips over the "
                         f"separation table (at most {MAX_STRIPS}): use a coarser grid or a shorter table")
    if n_strips < 2:
        raise InputError(f"{file}: method.grid_mm", f"{method.grid_mm:g} mm is wider than the separation table "
                         f"({separation.y_mm[0]:g}..{separation.y_mm[-1]:g} mm)")
    hashes = [file_sha256_or_none(path) or ""]
    layer = None
    if (keys := top.sub("layer")) is not None:
        layer = _parse_layer(keys, path.parent, hashes)

    tangential = _parse_tangential(top.sub("tangential"))

    passes = PassesSpec()
    if (keys := top.sub("passes")) is not None:
        keys.check_known(PASSES_KEYS)
        hardening, memory, traction = parse_passes_memory(keys)
        passes = PassesSpec(max=keys.integer("max", 1, ge=1, le=MAX_PASSES), hardening=hardening,
                            tolerance_mm=keys.number("tolerance_mm", 1e-6, gt=0.0), memory=memory,
                            traction_coefficient=traction)
        if passes.max > 1 and layer is None:
            raise keys.error("max", f"repeated passes ({passes.max}) need a [layer] (without a layer every pass "
                             "is the same elastic contact)")

    output = OutputSpec()
    if (keys := top.sub("output")) is not None:
        keys.check_known(("vtk", "convention"))
        output = OutputSpec(keys.boolean("vtk", True), keys.text("convention", "wrlayer", OUTPUT_CONVENTIONS))

    reference: dict[str, Any] = {}
    if (keys := top.sub("reference")) is not None:
        keys.check_known(REFERENCE_KEYS)
        for key in keys.table:
            reference[key] = keys.text(key) if key == "source" else keys.number(key)

    return Scene(path=path, title=title, description=description, load=load, material=material,
                 separation=separation, layer=layer, tangential=tangential, passes=passes, method=method,
                 output=output, reference=reference, data=data,
                 content_hash=sha256_hex("".join(hashes)))


def _parse_method(keys: SceneKeys | None, file: str) -> MethodSpec:
    if keys is None:
        return MethodSpec()
    keys.check_known(("alpha", "grid_mm", "fastsim_cells", "normal", "exact_cells", "layer_mode", "tangential"))
    method = MethodSpec(alpha=keys.number("alpha", 0.55, ge=MIN_ALPHA, le=1.0),
                        grid_mm=keys.number("grid_mm", 0.1, ge=MIN_GRID_MM),
                        fastsim_cells=keys.integer("fastsim_cells", 60, ge=2, le=MAX_FASTSIM_CELLS),
                        normal=keys.text("normal", "kik_piotrowski"),
                        exact_cells=keys.integer("exact_cells", None, ge=1),
                        layer_mode=keys.text("layer_mode", "indentation"),
                        tangential=keys.text("tangential", MethodSpec.tangential))
    from contact.tangential.method import TANGENTIAL_METHODS  # here: the tangential solvers compile with numba

    if method.tangential not in TANGENTIAL_METHODS:
        raise keys.error("tangential", f"must be one of {', '.join(TANGENTIAL_METHODS)}, got {method.tangential!r}")
    try:
        method.normal_method()
    except InputError as err:
        raise InputError(f"{file}: {err.what}", err.problem) from None
    return method


def _parse_tangential(keys: SceneKeys | None) -> TangentialSpec | None:
    if keys is None:
        return None
    keys.check_known(("creepage_x", "creepage_y", "spin_per_mm", "friction", "speed_mm_s", "flexibility"))
    tangential = TangentialSpec(creepage_x=keys.number("creepage_x", 0.0),
                                creepage_y=keys.number("creepage_y", 0.0),
                                spin_per_mm=keys.number("spin_per_mm", 0.0),
                                friction=keys.number("friction", ge=0.0),
                                speed_mm_s=keys.number("speed_mm_s", 1000.0, gt=0.0),
                                flexibility=keys.text("flexibility", "three"))
    from contact.tangential.fastsim import FLEXIBILITY_RULES  # here: fastsim compiles with numba

    if tangential.flexibility not in FLEXIBILITY_RULES:
        raise keys.error("flexibility", f"must be one of {', '.join(FLEXIBILITY_RULES)}, "
                         f"got {tangential.flexibility!r}")
    check_creepages(keys, tangential)
    return tangential


#: Largest |creepage_x|, |creepage_y| (-) and |spin_per_mm| (1/mm) of a scene: beyond them the creepages are not
#: small (rolling contact theory's assumption) and almost surely a unit or sign slip (e.g. percent for -).
MAX_CREEPAGE = 0.1
MAX_SPIN_PER_MM = 0.01


def check_creepages(keys: SceneKeys, tangential: TangentialSpec) -> None:
    """Creepages within range and, when any is given, a friction coefficient > 0 (InputError naming the key)."""
    for key, limit in (("creepage_x", MAX_CREEPAGE), ("creepage_y", MAX_CREEPAGE), ("spin_per_mm", MAX_SPIN_PER_MM)):
        value = getattr(tangential, key)
        if not abs(value) <= limit:
            raise keys.error(key, f"must be within +-{limit:g}, got {value!r}")
    if tangential.has_creepage and not tangential.friction > 0:
        raise keys.error("friction", f"must be > 0 with creepages (a tangential solution), got {tangential.friction!r}")


def _parse_separation(keys: SceneKeys, grid_mm: float) -> SeparationSpec:
    if "lateral_radius_mm" in keys.table:
        keys.check_known(("lateral_radius_mm", "half_width_mm", "step_mm"))
        radius = keys.number("lateral_radius_mm", ge=MIN_LATERAL_RADIUS_MM)
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


def _parse_layer(keys: SceneKeys, base: Path, hashes: list[str]) -> LayerSpec:
    has_bodies = any(b in keys.table for b in BODIES)
    has_points = any(k in keys.table for k in ("u_mm", "p_MPa"))
    if has_bodies and has_points:
        raise keys.error("u_mm", "give either one combined characteristic (layer.u_mm, layer.p_MPa) or per body "
                         "layers ([layer.wheel], [layer.rail]), not both")
    if has_points:
        keys.check_known(("u_mm", "p_MPa"))
        return LayerSpec(combined=_characteristic(keys))
    keys.check_known(BODIES)
    if not has_bodies:
        raise InputError(keys.what("u_mm"), "missing: [layer] needs u_mm and p_MPa, or [layer.wheel]/[layer.rail]")
    bodies = {body: _parse_body(keys.sub(body), body, base, hashes) for body in BODIES if body in keys.table}
    return LayerSpec(wheel=bodies.get("wheel"), rail=bodies.get("rail"))


def _characteristic(keys: SceneKeys) -> Characteristic:
    u = keys.array("u_mm")
    p = keys.array("p_MPa")
    return Characteristic(u, p, name=f"{keys.what('u_mm')}/p_MPa")


def _parse_body(keys: SceneKeys, body: str, base: Path, hashes: list[str]) -> BodyLayerSpec:
    if "table" in keys.table:
        keys.check_known(("table", "position_mm", "scale_to_patch"))
        table_path, table = read_body_table(keys.text("table"), base, body, keys.what("table"))
        position = keys.number("position_mm")
        hashes.append(file_sha256(table_path))
        spec = BodyLayerSpec(body, table_path=table_path, position_mm=position, table=table,
                             scale_to_patch=keys.boolean("scale_to_patch", False))
        spec.characteristic_at(0.0, f"{keys.file}: {keys.prefix}")  # the table must cover the contact point
        return spec
    keys.check_known(("u_mm", "p_MPa", "table", "position_mm", "scale_to_patch"))
    if "scale_to_patch" in keys.table:
        raise keys.error("scale_to_patch", "only used with a calibration table (layer.<body>.table)")
    if "position_mm" in keys.table:
        raise keys.error("position_mm", "only used with a calibration table (layer.<body>.table)")
    return BodyLayerSpec(body, characteristic=_characteristic(keys))


def scene_inputs(scene: Scene) -> dict[str, Any]:
    """The parsed scene as JSON-serialisable data: resolved values (defaults filled in), resolved paths, hashes."""
    layer: dict[str, Any] | None = None
    if scene.layer is not None:
        layer = {}
        if scene.layer.combined is not None:
            layer["combined"] = scene.layer.combined.to_dict()
        for body in BODIES:
            spec = getattr(scene.layer, body)
            if spec is None:
                continue
            if spec.table_path is not None:
                layer[body] = {"table": str(spec.table_path), "position_mm": spec.position_mm,
                               "scale_to_patch": spec.scale_to_patch,
                               "characteristic_at_position": spec.characteristic_at(0.0).to_dict()}
            else:
                layer[body] = spec.characteristic.to_dict()
    sep = scene.separation
    return {
        "scene_file": str(scene.path.resolve()),
        "content_sha256": scene.content_hash,
        "title": scene.title,
        "description": scene.description,
        "load": vars(scene.load).copy(),
        "material": {**vars(scene.material), "G_MPa": scene.material.G_MPa},
        "separation": {"kind": sep.kind, "lateral_radius_mm": sep.lateral_radius_mm,
                       "y_mm": sep.y_mm.tolist(), "f_mm": sep.f_mm.tolist()},
        "layer": layer,
        "tangential": None if scene.tangential is None else vars(scene.tangential).copy(),
        "passes": vars(scene.passes).copy(),
        "method": vars(scene.method).copy(),
        "output": vars(scene.output).copy(),
        "reference": dict(scene.reference),
        "scene_toml": scene.data,
    }
