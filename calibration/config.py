"""Calibration configuration files: a TOML file -> the validated dataclasses of :mod:`calibration.settings`.

The keys, their units and defaults are those of the dataclasses (their ``Attributes`` sections). Unknown keys,
wrong types, NaN/inf, out-of-range values, unknown profiles and positions outside a profile are InputError naming
the file and the key (:mod:`wrlayer.validate`).
"""

from __future__ import annotations

import math
from dataclasses import asdict, fields
from pathlib import Path
from typing import Any

from calibration.fit.characteristic_fit import N_SEGMENTS_RANGE
from calibration.placement import MIN_INCLINATION_RATIO, cant_rad
from calibration.settings import (FIT_MODES, LINEAR_SOLVERS, MESH_STYLES, METHODS, MODELS, REFERENCE_LOAD_N,
                                  SIMILARITY_ELASTIC, SIMILARITY_OUTSIDE, BodySettings, CalibrationConfig,
                                  FitSettings, LoadSettings, MaterialSettings, MeshSettings, RunSettings)
from meshes.profiles import PROFILE_FILE_SUFFIXES, PROFILE_UNITS, Profile, get_profile, named_profile
from wrlayer import validate
from wrlayer.errors import InputError
from wrlayer.input_files import read_toml
from wrlayer.runner import check_scheduler_address
from wrlayer.validate import Keys, top_keys

#: Largest number of positions per body (a hard size limit; the cost guard of calibration.cost refuses long runs
#: below it unless forced).
MAX_POSITIONS = 500

_TOP_KEYS = ("accept_implausible", "run", "material", "load", "mesh", "fit", "bodies")
_BODY_KEYS = ("body", "profile", "mate", "positions_mm", "positions", "semi_axes_mm", "inclination",
              "inclination_rad", "rail_cant_rad", "max_lateral_radius_mm", "wheel_radius_mm", "material",
              "accept_unusual_profile", "units", "anchor_table")


def _names(cls) -> tuple[str, ...]:
    return tuple(f.name for f in fields(cls))


def _run(k: Keys) -> RunSettings:
    k.check_known(_names(RunSettings))
    kw: dict[str, Any] = {}
    if "model" in k.table:
        kw["model"] = k.text("model", choices=MODELS)
    if "method" in k.table:
        kw["method"] = k.text("method", choices=METHODS)
    if "similarity_outside" in k.table:
        kw["similarity_outside"] = k.text("similarity_outside", choices=SIMILARITY_OUTSIDE)
    if "similarity_elastic" in k.table:
        flag = k.table["similarity_elastic"]  # the boolean form of earlier configurations
        kw["similarity_elastic"] = {True: "all", False: "none"}[flag] if isinstance(flag, bool) else \
            k.text("similarity_elastic", choices=SIMILARITY_ELASTIC)
    if "master_dir" in k.table:
        kw["master_dir"] = k.text("master_dir")
    if "workers" in k.table:
        kw["workers"] = k.integer("workers", None, ge=1, le=64)
    if "scheduler" in k.table:
        kw["scheduler"] = check_scheduler_address(k.table["scheduler"], k.what("scheduler"))  # by its form, up front
    if "plots" in k.table:
        kw["plots"] = k.boolean("plots", True)
    if "linear_solver" in k.table:
        kw["linear_solver"] = k.text("linear_solver", choices=LINEAR_SOLVERS)
    run = RunSettings(**kw)
    if run.method == "similarity" and run.model != "3d":
        raise k.error("method", "'similarity' needs model = '3d' (the master curves are 3D half-model results)")
    return run


def _material(k: Keys, base: MaterialSettings = MaterialSettings()) -> MaterialSettings:
    k.check_known(_names(MaterialSettings))
    kw = asdict(base)
    for name in ("E_MPa", "yield_MPa"):
        if name in k.table:
            kw[name] = k.plausible_number(name, name, gt=0.0)
    for name in ("H_iso_MPa", "H_kin_MPa"):
        if name in k.table:
            kw[name] = k.number(name, ge=0.0)
    if "poisson" in k.table:
        kw["poisson"] = k.number("poisson", gt=-1.0, le=0.4999)
    return MaterialSettings(**kw)


def _numbers(k: Keys, bounds: dict[str, dict[str, float]]) -> dict[str, float]:
    """The given keys of ``bounds`` as numbers within their bounds (the absent ones keep their defaults)."""
    return {name: k.number(name, **b) for name, b in bounds.items() if name in k.table}


def _load(k: Keys) -> tuple[LoadSettings, float]:
    k.check_known(_names(LoadSettings) + ("reference_load_N",))
    ref = k.number("reference_load_N", REFERENCE_LOAD_N, gt=0.0)
    kw: dict[str, Any] = _numbers(k, {"max_factor": dict(gt=1.0, le=10.0),
                                      "max_increment_factor": dict(gt=0.0, le=1.0)})
    if "n_levels" in k.table:
        kw["n_levels"] = k.integer("n_levels", None, ge=1, le=200)
    if "unload_factors" in k.table:
        kw["unload_factors"] = tuple(sorted(float(x) for x in k.array("unload_factors", min_len=1, gt=1.0)))
    load = LoadSettings(**kw)
    if load.unload_factors[-1] > load.max_factor + 1e-12:
        raise k.error("unload_factors", f"must not exceed load.max_factor = {load.max_factor:g}")
    return load, ref


def _mesh(k: Keys) -> MeshSettings:
    k.check_known(_names(MeshSettings))
    kw: dict[str, Any] = _numbers(k, {
        "elements_per_semi_axis": dict(gt=0.5, le=100.0), "h_max_mm": dict(gt=0.0, le=100.0),
        "depth_mm": dict(gt=0.0, le=500.0), "rail_support_below_mm": dict(gt=0.0, le=500.0),
        "length_factor": dict(gt=1.0, le=50.0), "grading": dict(gt=0.0, le=5.0),
        "yield_search_radius_factor": dict(gt=0.0, le=100.0), "reference_depth_factor": dict(ge=0.0, le=20.0),
        "refine_depth_factor": dict(gt=0.0, le=10.0), "x_elements_per_semi_axis": dict(ge=2.0, le=100.0),
        "yield_zone_refinement": dict(ge=1.0, le=4.0)})
    if "order" in k.table:
        kw["order"] = k.integer("order", None, ge=1, le=2)
    if "style" in k.table:
        kw["style"] = k.text("style", choices=MESH_STYLES)
    return MeshSettings(**kw)


def _fit(k: Keys) -> FitSettings:
    k.check_known(_names(FitSettings))
    kw: dict[str, Any] = _numbers(k, {"elastic_tolerance": dict(gt=0.0, le=1.0),
                                      "elastic_fraction": dict(gt=0.0, le=1.0),
                                      "max_relative_error": dict(gt=0.0, le=10.0),
                                      "error_floor": dict(gt=0.0, le=1.0)})
    for name in ("n_segments", "max_segments"):
        if name in k.table:
            kw[name] = k.integer(name, None, ge=N_SEGMENTS_RANGE[0], le=N_SEGMENTS_RANGE[1])
            if kw[name] < 2:
                raise k.error(name, "must be >= 2 for the calibration (p_2 is pinned to the FEM first yield)")
    if "mode" in k.table:
        kw["mode"] = k.text("mode", choices=FIT_MODES)
    if "target_error" in k.table:
        kw["target_error"] = k.number("target_error", gt=0.0, lt=1.0)
    if "weight_range" in k.table:
        low, high = k.array("weight_range", min_len=2, max_len=2, ge=1.0, le=10.0)
        if not high > low:
            raise k.error("weight_range", f"must be [low, high] with high > low, got [{low:g}, {high:g}]")
        kw["weight_range"] = (float(low), float(high))
    return FitSettings(**kw)


def resolve_profile(spec: Any, what: str, base: Path, accept_unusual: bool = False, units: str | None = None,
                    body: str | None = None) -> tuple[Any, Profile]:
    """(spec as stored, Profile) of a profile given as a name, a file path (relative to ``base``) or a Profile
    object; InputError naming ``what`` when it is none of them or cannot be read. A file read with options
    (``accept_unusual``: without the plausibility checks; ``units``: "mm" or "m", the file's length unit; ``body``
    for a text or CSV file, which does not state its body; :func:`meshes.profiles.named_profile`) is stored as the
    Profile object (so that it is not read again without them)."""
    if isinstance(spec, Profile):
        return spec, spec
    if not isinstance(spec, str) or not spec.strip():
        raise InputError(what, f"must be a profile name or file path, got {validate.show(spec)}")
    if Path(spec).suffix.lower() in PROFILE_FILE_SUFFIXES:
        path = Path(spec) if Path(spec).is_absolute() else base / spec
        if not path.is_file():
            raise InputError(what, f"profile file {str(path)!r} not found")
        spec = str(path)
    try:
        suffix = Path(spec).suffix.lower()
        text_body = body if suffix in (".txt", ".csv") else None
        if suffix in PROFILE_FILE_SUFFIXES and (accept_unusual or units is not None or text_body is not None):
            profile = named_profile(spec, text_body, units, accept_unusual)
            return profile, profile
        return spec, get_profile(spec)
    except InputError as err:
        raise InputError(what, str(err)) from None


def profile_of(spec: Any) -> Profile:
    """The Profile of a BodySettings.profile or .mate as stored (a name, a resolved file path or a Profile)."""
    return spec if isinstance(spec, Profile) else get_profile(spec)


def _position_range(k: Keys) -> list[float]:
    k.check_known(("start_mm", "stop_mm", "step_mm"))
    a = k.number("start_mm")
    b = k.number("stop_mm")
    step = k.number("step_mm", gt=0.0)
    if b < a:
        raise k.error("stop_mm", f"must be >= start_mm ({b:g} < {a:g})")
    n = int(math.floor((b - a) / step + 1e-9)) + 1
    if n > MAX_POSITIONS:
        raise k.error("step_mm", f"gives {n} positions (at most {MAX_POSITIONS})")
    return [round(a + i * step, 9) for i in range(n)]


def _positions(k: Keys) -> tuple[float, ...]:
    if ("positions_mm" in k.table) == ("positions" in k.table):
        raise k.error("positions_mm", "give exactly one of positions_mm = [...] or positions = {start_mm, "
                                      "stop_mm, step_mm}")
    if "positions_mm" in k.table:
        ys = [float(y) for y in k.array("positions_mm", min_len=1, max_len=MAX_POSITIONS)]
    else:
        ys = _position_range(k.sub("positions"))
    if len(set(ys)) != len(ys):
        raise k.error("positions_mm", "contains duplicate positions")
    return tuple(sorted(ys))


def _mate(k: Keys, body: str, base: Path, accept_unusual: bool = False, units: str | None = None):
    mate, profile = resolve_profile(k.table["mate"], k.what("mate"), base, accept_unusual, units,
                                    "wheel" if body == "rail" else "rail")
    if profile.body == body:
        raise k.error("mate", f"{profile.name} is a {profile.body} profile; the mate of a {body} must be a "
                              f"{'wheel' if body == 'rail' else 'rail'}")
    return mate


def _body(k: Keys, base: Path, material: MaterialSettings, accept_unusual_profile: bool = False) -> BodySettings:
    k.check_known(_BODY_KEYS)
    if "body" not in k.table:
        raise k.error("body", "missing (required)")
    body = k.table["body"]
    if body not in ("rail", "wheel"):
        raise k.error("body", f"must be 'rail' or 'wheel', got {validate.show(body)}")
    if "profile" not in k.table:
        raise k.error("profile", "missing (required)")
    unusual = accept_unusual_profile or k.boolean("accept_unusual_profile", False)
    units = k.text("units", None, tuple(PROFILE_UNITS)) if "units" in k.table else None
    spec, profile = resolve_profile(k.table["profile"], k.what("profile"), base, unusual, units, body)
    if profile.body != body:
        raise k.error("profile", f"{profile.name} is a {profile.body} profile, not a {body} profile")
    ys = _positions(k)
    for y in ys:
        try:
            profile.check_y(y, f"position y = {y:g} mm")
        except InputError as err:
            raise k.error("positions_mm", str(err)) from None
    semi = None
    if "semi_axes_mm" in k.table:
        v = k.table["semi_axes_mm"]
        if not isinstance(v, list) or len(v) != 2:
            raise k.error("semi_axes_mm", "must be [a_mm, b_mm] (rolling, lateral)")
        semi = tuple(float(x) for x in k.array("semi_axes_mm", gt=0.0))
    if "mate" not in k.table and semi is None:
        raise k.error("mate", "missing (needed for the Hertz semi-axes unless semi_axes_mm is given)")
    mate = _mate(k, body, base, unusual, units) if "mate" in k.table else None
    kw = _numbers(k, {"max_lateral_radius_mm": dict(gt=0.0), "wheel_radius_mm": dict(gt=0.0)})
    kw.update(_inclination(k))
    mat = _material(k.sub("material"), material) if "material" in k.table else material
    anchor = _anchor_table(k, base, body) if "anchor_table" in k.table else None
    settings = BodySettings(body, spec, mate, ys, semi, material=mat, accept_unusual_profile=unusual, units=units,
                            anchor_table=anchor, **kw)
    cant_rad(settings, f"{k.file}: {k.prefix}")  # a rail of unknown placement: refused here
    return settings


def _anchor_table(k: Keys, base: Path, body: str) -> str:
    """``anchor_table``: the resolved path of a readable layer table of ``body`` whose reference profile can be
    read (InputError naming the key otherwise)."""
    from calibration.similarity.anchor import table_profile  # the similarity package reads configurations
    from wrlayer.layer_table import LayerTable

    rel = k.text("anchor_table")
    path = Path(rel) if Path(rel).is_absolute() else base / rel
    try:
        table = LayerTable.read(path)
        if table.body != body:
            raise InputError(str(path), f"is a {table.body} table, not a {body} table")
        table_profile(table)
    except InputError as err:
        raise k.error("anchor_table", str(err)) from None
    return str(path.resolve())


def _inclination(k: Keys) -> dict[str, float]:
    """``inclination`` (1:n) or ``inclination_rad`` (alias ``rail_cant_rad``), at most one of them."""
    given = [name for name in ("inclination", "inclination_rad", "rail_cant_rad") if name in k.table]
    if len(given) > 1:
        raise k.error(given[1], f"give one of inclination (1:n) or inclination_rad, not also {given[0]}")
    if not given:
        return {}
    if given[0] == "inclination":
        ratio = k.number("inclination", ge=0.0)
        if 0 < ratio < MIN_INCLINATION_RATIO:
            raise k.error("inclination", f"1:n needs n >= {MIN_INCLINATION_RATIO:g} (or 0 for a rail already "
                                         f"placed as in the track), got {ratio:g}")
        return {"inclination": ratio}
    return {"inclination_rad": k.number(given[0], ge=-0.2, le=0.2)}


def _table(k: Keys, key: str) -> Keys:
    return k.sub(key) or Keys(k.file, key, {})


def parse_config(data: dict, source: str = "config", base: Path = Path("."), accept_unusual_profile: bool = False
                 ) -> CalibrationConfig:
    """Validate a parsed TOML mapping (InputError naming ``source`` and the key); profile files are relative to
    ``base``. ``accept_unusual_profile``: as ``accept_unusual_profile = true`` in every body (the command line's
    ``--accept-unusual-profile``)."""
    top = top_keys(source, data)
    top.check_known(_TOP_KEYS)
    run = _run(_table(top, "run"))
    material = _material(_table(top, "material"))
    load, ref = _load(_table(top, "load"))
    mesh = _mesh(_table(top, "mesh"))
    fit = _fit(_table(top, "fit"))
    bodies = data.get("bodies")
    if not isinstance(bodies, list) or not bodies:
        raise top.error("bodies", "missing: give at least one [[bodies]] table")
    parsed = tuple(_body(Keys(source, f"bodies[{i}]", b), base, material, accept_unusual_profile)
                   for i, b in enumerate(bodies))
    names = [b.body for b in parsed]
    if len(set(names)) != len(names):
        raise top.error("bodies", f"each body may appear once, got {names}")
    return CalibrationConfig(source, run, load, ref, mesh, fit, parsed)


def load_config(path: str | Path, accept_unusual_profile: bool = False) -> CalibrationConfig:
    """Read and validate a TOML configuration file (``accept_unusual_profile``: as :func:`parse_config`)."""
    path = Path(path)
    return parse_config(read_toml(path, what=str(path)), str(path), path.parent, accept_unusual_profile)


def material_of(body: BodySettings):
    """The J2Material of a body."""
    from calibration.fem.material import J2Material  # the FEM engine only where a material is built

    return J2Material(**asdict(body.material))


__all__ = ["BodySettings", "CalibrationConfig", "FitSettings", "LoadSettings", "MAX_POSITIONS", "MaterialSettings",
           "MeshSettings", "RunSettings", "load_config", "material_of", "parse_config", "profile_of", "resolve_profile"]
