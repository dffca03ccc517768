"""Calibration configuration: a TOML file -> validated dataclasses (units mm, N, MPa).

Layout (every key optional except ``[[bodies]]`` with ``body``, ``profile`` and positions)::

    [run]       model = "2d" | "3d", workers = 2, scheduler = "" (Dask address), plots = true,
                linear_solver = "scipy" | "pardiso" | "auto" (SuperLU is the faster for 2D sections)
    [material]  E_MPa, poisson, yield_MPa, H_iso_MPa, H_kin_MPa            (J2 with linear hardening)
    [load]      reference_load_N, max_factor, n_levels, unload_factors, max_increment_factor
    [mesh]      elements_per_semi_axis, h_max_mm, order, depth_mm, rail_support_below_mm, length_factor, grading,
                yield_search_radius_factor, reference_depth_factor, refine_depth_factor,
                style = "isotropic" | "stretched" | "extruded" | "structured" | "auto" (3D: stretched: the
                isotropic mesh of a patch of a/b = 1.4 stretched along x to the patch's own a/b; extruded:
                structured layers along x; structured: a core structured along the surface, the normal and x;
                auto: extruded for a/b >= 4; see docs/calibration.md),
                x_elements_per_semi_axis (extruded: layers of a / this; default elements_per_semi_axis),
                yield_zone_refinement (1..4; isotropic, stretched: h_min / this around the first-yield point; 1: off)
    [fit]       n_segments (1..8), elastic_tolerance, elastic_fraction (former S_1 rule), max_relative_error
    [[bodies]]  body = "rail" | "wheel", profile = name or file (relative to the config), mate = name or file,
                positions_mm = [...] or positions = {start_mm, stop_mm, step_mm}, semi_axes_mm = [a, b],
                rail_cant_rad, max_lateral_radius_mm, wheel_radius_mm, [bodies.material] (overrides)

Unknown keys, wrong types, NaN/inf, out-of-range values, unknown profiles and positions outside a profile are
InputError naming the file and the key.
"""

from __future__ import annotations

import math
import tomllib
from dataclasses import asdict, dataclass, fields
from pathlib import Path
from typing import Any

from calibration.fit.characteristic_fit import N_SEGMENTS_RANGE
from calibration.hertz.geometry import DEFAULT_MAX_LATERAL_RADIUS_MM, DEFAULT_RAIL_CANT_RAD
from calibration.indentation import MESH_STYLES, LoadSettings, MeshSettings
from wrlayer import validate
from wrlayer.errors import InputError

MODELS = ("2d", "3d")
#: Largest number of positions per body (a hard size limit; the cost guard of calibration.cost refuses long runs
#: below it unless forced).
MAX_POSITIONS = 500


@dataclass(frozen=True)
class RunSettings:
    model: str = "2d"
    workers: int = 2
    scheduler: str = ""
    plots: bool = True
    linear_solver: str = "scipy"


@dataclass(frozen=True)
class MaterialSettings:
    """J2 material (MPa). Defaults: rail/wheel steel, E = 210 GPa, nu = 0.3, initial yield 500 MPa (R260 0.2 %
    proof stress range), linear isotropic and kinematic hardening 10 GPa each (stated assumption)."""

    E_MPa: float = 210000.0
    poisson: float = 0.3
    yield_MPa: float = 500.0
    H_iso_MPa: float = 10000.0
    H_kin_MPa: float = 10000.0


@dataclass(frozen=True)
class FitSettings:
    """n_segments N; elastic_tolerance t: S_1 = p_max / (t u_pl(p_max)), the layer's elastic displacement at the
    largest calibrated pressure being t times its inelastic one (docs/calibration.md: the layer has no elasticity
    of its own, the half-space carries it; t = the 1 % accuracy of the FEM layer displacement);
    elastic_fraction f: the former rule S_1 = 1 / (f c_hs) (c_hs: half-space centre compliance), used only when
    given; max_relative_error: largest accepted fit error relative to max u."""

    n_segments: int = 5
    elastic_tolerance: float = 0.01
    elastic_fraction: float | None = None
    max_relative_error: float = 0.1


@dataclass(frozen=True)
class BodySettings:
    body: str
    profile: str
    mate: str | None
    positions_mm: tuple[float, ...]
    semi_axes_mm: tuple[float, float] | None = None
    rail_cant_rad: float = DEFAULT_RAIL_CANT_RAD
    max_lateral_radius_mm: float = DEFAULT_MAX_LATERAL_RADIUS_MM
    wheel_radius_mm: float | None = None
    material: MaterialSettings = MaterialSettings()


@dataclass(frozen=True)
class CalibrationConfig:
    source: str
    run: RunSettings
    load: LoadSettings
    reference_load_N: float
    mesh: MeshSettings
    fit: FitSettings
    bodies: tuple[BodySettings, ...]

    def to_dict(self) -> dict[str, Any]:
        d = asdict(self)
        d.pop("source")
        return d


_TOP_KEYS = {"run", "material", "load", "mesh", "fit", "bodies"}
_BODY_KEYS = {"body", "profile", "mate", "positions_mm", "positions", "semi_axes_mm", "rail_cant_rad",
              "max_lateral_radius_mm", "wheel_radius_mm", "material"}


class _Reader:
    def __init__(self, source: str):
        self.source = source

    def fail(self, key: str, problem: str):
        raise InputError(f"{self.source}: {key}", problem)

    def table(self, data: dict, key: str) -> dict:
        value = data.get(key, {})
        if not isinstance(value, dict):
            self.fail(key, f"must be a table, got {type(value).__name__}")
        return value

    def known(self, data: dict, allowed: set[str], where: str) -> None:
        extra = sorted(set(data) - allowed)
        if extra:
            self.fail(f"{where}{extra[0]}", f"unknown key; allowed: {', '.join(sorted(allowed))}")

    def number(self, value, key: str, lo: float | None = None, hi: float | None = None, lo_open: bool = True,
               integer: bool = False) -> float:
        if integer:
            validate.integer(value, f"{self.source}: {key}")
        validate.number(value, f"{self.source}: {key}")  # a finite real, not a bool or a string (shared rules)
        if lo is not None and (value <= lo if lo_open else value < lo):
            self.fail(key, f"must be {'>' if lo_open else '>='} {lo:g}, got {value!r}")
        if hi is not None and value > hi:
            self.fail(key, f"must be <= {hi:g}, got {value!r}")
        return int(value) if integer else float(value)

    def dataclass_from(self, cls, data: dict, where: str, checks: dict):
        """Build dataclass ``cls`` from ``data`` (defaults for missing keys), validating with ``checks``."""
        self.known(data, {f.name for f in fields(cls)}, f"{where}.")
        kw = {}
        for name, check in checks.items():
            if name in data:
                kw[name] = check(data[name], f"{where}.{name}")
        return cls(**kw)


def _material(r: _Reader, data: dict, where: str, base: MaterialSettings = MaterialSettings()) -> MaterialSettings:
    r.known(data, {f.name for f in fields(MaterialSettings)}, f"{where}.")
    kw = asdict(base)
    kw.update({k: r.number(data[k], f"{where}.{k}", 0.0, lo_open=k in ("E_MPa", "yield_MPa"))
               for k in ("E_MPa", "yield_MPa", "H_iso_MPa", "H_kin_MPa") if k in data})
    if "poisson" in data:
        kw["poisson"] = r.number(data["poisson"], f"{where}.poisson", -1.0, 0.4999)
    return MaterialSettings(**kw)


def _resolve_profile(r: _Reader, name, key: str, base: Path):
    from meshes.profiles import PROFILE_FILE_SUFFIXES, get_profile

    if not isinstance(name, str) or not name.strip():
        r.fail(key, f"must be a profile name or file path, got {name!r}")
    spec = name
    if Path(name).suffix.lower() in PROFILE_FILE_SUFFIXES:
        path = Path(name) if Path(name).is_absolute() else base / name
        if not path.is_file():
            r.fail(key, f"profile file {str(path)!r} not found")
        spec = str(path)
    try:
        return spec, get_profile(spec)
    except InputError as err:
        r.fail(key, str(err))


def _positions(r: _Reader, data: dict, where: str) -> tuple[float, ...]:
    if ("positions_mm" in data) == ("positions" in data):
        r.fail(f"{where}.positions_mm", "give exactly one of positions_mm = [...] or positions = {start_mm, "
                                        "stop_mm, step_mm}")
    if "positions_mm" in data:
        values = data["positions_mm"]
        if not isinstance(values, list) or not values:
            r.fail(f"{where}.positions_mm", "must be a non-empty list of numbers (mm)")
        if len(values) > MAX_POSITIONS:
            r.fail(f"{where}.positions_mm", f"has {len(values)} positions (at most {MAX_POSITIONS})")
        ys = [r.number(v, f"{where}.positions_mm[{i}]") for i, v in enumerate(values)]
    else:
        spec = data["positions"]
        if not isinstance(spec, dict):
            r.fail(f"{where}.positions", "must be a table {start_mm, stop_mm, step_mm}")
        r.known(spec, {"start_mm", "stop_mm", "step_mm"}, f"{where}.positions.")
        for k in ("start_mm", "stop_mm", "step_mm"):
            if k not in spec:
                r.fail(f"{where}.positions.{k}", "missing")
        a = r.number(spec["start_mm"], f"{where}.positions.start_mm")
        b = r.number(spec["stop_mm"], f"{where}.positions.stop_mm")
        step = r.number(spec["step_mm"], f"{where}.positions.step_mm", 0.0)
        if b < a:
            r.fail(f"{where}.positions.stop_mm", f"must be >= start_mm ({b:g} < {a:g})")
        n = int(math.floor((b - a) / step + 1e-9)) + 1
        if n > MAX_POSITIONS:
            r.fail(f"{where}.positions.step_mm", f"gives {n} positions (at most {MAX_POSITIONS})")
        ys = [round(a + i * step, 9) for i in range(n)]
    if len(set(ys)) != len(ys):
        r.fail(f"{where}.positions_mm", "contains duplicate positions")
    return tuple(sorted(ys))


def _body(r: _Reader, data, i: int, base: Path, material: MaterialSettings) -> BodySettings:
    where = f"bodies[{i}]"
    if not isinstance(data, dict):
        r.fail(where, "must be a table")
    r.known(data, _BODY_KEYS, f"{where}.")
    for k in ("body", "profile"):
        if k not in data:
            r.fail(f"{where}.{k}", "missing")
    body = data["body"]
    if body not in ("rail", "wheel"):
        r.fail(f"{where}.body", f"must be 'rail' or 'wheel', got {body!r}")
    spec, profile = _resolve_profile(r, data["profile"], f"{where}.profile", base)
    if profile.body != body:
        r.fail(f"{where}.profile", f"{profile.name} is a {profile.body} profile, not a {body} profile")
    ys = _positions(r, data, where)
    for y in ys:
        try:
            profile.check_y(y, f"position y = {y:g} mm")
        except InputError as err:
            r.fail(f"{where}.positions_mm", str(err))
    semi = None
    if "semi_axes_mm" in data:
        v = data["semi_axes_mm"]
        if not isinstance(v, list) or len(v) != 2:
            r.fail(f"{where}.semi_axes_mm", "must be [a_mm, b_mm] (rolling, lateral)")
        semi = tuple(r.number(x, f"{where}.semi_axes_mm[{i}]", 0.0) for i, x in enumerate(v))
    mate = None
    if "mate" in data:
        mate, mate_profile = _resolve_profile(r, data["mate"], f"{where}.mate", base)
        if mate_profile.body == body:
            r.fail(f"{where}.mate", f"{mate_profile.name} is a {mate_profile.body} profile; the mate of a {body} "
                                    f"must be a {'wheel' if body == 'rail' else 'rail'}")
    elif semi is None:
        r.fail(f"{where}.mate", "missing (needed for the Hertz semi-axes unless semi_axes_mm is given)")
    kw = {}
    if "rail_cant_rad" in data:
        kw["rail_cant_rad"] = r.number(data["rail_cant_rad"], f"{where}.rail_cant_rad", -0.2, 0.2, lo_open=False)
    if "max_lateral_radius_mm" in data:
        kw["max_lateral_radius_mm"] = r.number(data["max_lateral_radius_mm"], f"{where}.max_lateral_radius_mm", 0.0)
    if "wheel_radius_mm" in data:
        kw["wheel_radius_mm"] = r.number(data["wheel_radius_mm"], f"{where}.wheel_radius_mm", 0.0)
    mat = _material(r, r.table(data, "material"), f"{where}.material", material)
    return BodySettings(body, spec, mate, ys, semi, material=mat, **kw)


def parse_config(data: dict, source: str = "config", base: Path = Path(".")) -> CalibrationConfig:
    """Validate a parsed TOML mapping (InputError naming ``source`` and the key)."""
    r = _Reader(source)
    r.known(data, _TOP_KEYS, "")
    run_d = r.table(data, "run")

    def model(v, k):
        if v not in MODELS:
            r.fail(k, f"must be one of {MODELS}, got {v!r}")
        return v

    def string(v, k):
        if not isinstance(v, str):
            r.fail(k, f"must be a string, got {v!r}")
        return v

    def solver(v, k):
        if v not in ("auto", "pardiso", "scipy"):
            r.fail(k, f"must be 'auto', 'pardiso' or 'scipy', got {v!r}")
        return v

    def boolean(v, k):
        if not isinstance(v, bool):
            r.fail(k, f"must be true or false, got {v!r}")
        return v

    run = r.dataclass_from(RunSettings, run_d, "run", {
        "model": model, "workers": lambda v, k: r.number(v, k, 1, 64, lo_open=False, integer=True),
        "scheduler": string, "plots": boolean, "linear_solver": solver})
    material = _material(r, r.table(data, "material"), "material")
    load_d = dict(r.table(data, "load"))
    ref = r.number(load_d.pop("reference_load_N", 100000.0), "load.reference_load_N", 0.0)

    def factors(v, k):
        if not isinstance(v, list) or not v:
            r.fail(k, "must be a non-empty list of numbers")
        return tuple(sorted(r.number(x, f"{k}[{i}]", 1.0) for i, x in enumerate(v)))

    load = r.dataclass_from(LoadSettings, load_d, "load", {
        "max_factor": lambda v, k: r.number(v, k, 1.0, 10.0),
        "n_levels": lambda v, k: r.number(v, k, 1, 200, lo_open=False, integer=True),
        "unload_factors": factors,
        "max_increment_factor": lambda v, k: r.number(v, k, 0.0, 1.0)})
    if load.unload_factors[-1] > load.max_factor + 1e-12:
        r.fail("load.unload_factors", f"must not exceed load.max_factor = {load.max_factor:g}")
    def style(v, k):
        if v not in MESH_STYLES:
            r.fail(k, f"must be one of {', '.join(repr(m) for m in MESH_STYLES)}, got {v!r}")
        return v

    mesh = r.dataclass_from(MeshSettings, r.table(data, "mesh"), "mesh", {
        "elements_per_semi_axis": lambda v, k: r.number(v, k, 0.5, 100.0),
        "h_max_mm": lambda v, k: r.number(v, k, 0.0, 100.0),
        "order": lambda v, k: int(r.number(v, k, 1, 2, lo_open=False, integer=True)),
        "depth_mm": lambda v, k: r.number(v, k, 0.0, 500.0),
        "rail_support_below_mm": lambda v, k: r.number(v, k, 0.0, 500.0),
        "length_factor": lambda v, k: r.number(v, k, 1.0, 50.0),
        "grading": lambda v, k: r.number(v, k, 0.0, 5.0),
        "yield_search_radius_factor": lambda v, k: r.number(v, k, 0.0, 100.0),
        "reference_depth_factor": lambda v, k: r.number(v, k, 0.0, 20.0, lo_open=False),
        "refine_depth_factor": lambda v, k: r.number(v, k, 0.0, 10.0),
        "style": style,
        "x_elements_per_semi_axis": lambda v, k: r.number(v, k, 2.0, 100.0, lo_open=False),
        "yield_zone_refinement": lambda v, k: r.number(v, k, 1.0, 4.0, lo_open=False)})
    fit = r.dataclass_from(FitSettings, r.table(data, "fit"), "fit", {
        "n_segments": lambda v, k: int(r.number(v, k, N_SEGMENTS_RANGE[0], N_SEGMENTS_RANGE[1], lo_open=False,
                                                integer=True)),
        "elastic_tolerance": lambda v, k: r.number(v, k, 0.0, 1.0),
        "elastic_fraction": lambda v, k: r.number(v, k, 0.0, 1.0),
        "max_relative_error": lambda v, k: r.number(v, k, 0.0, 10.0)})
    if fit.n_segments < 2:
        r.fail("fit.n_segments", "must be >= 2 for the calibration (p_2 is pinned to the FEM first yield)")
    bodies = data.get("bodies")
    if not isinstance(bodies, list) or not bodies:
        r.fail("bodies", "missing: give at least one [[bodies]] table")
    parsed = tuple(_body(r, b, i, base, material) for i, b in enumerate(bodies))
    names = [b.body for b in parsed]
    if len(set(names)) != len(names):
        r.fail("bodies", f"each body may appear once, got {names}")
    return CalibrationConfig(source, run, load, ref, mesh, fit, parsed)


def load_config(path: str | Path) -> CalibrationConfig:
    """Read and validate a TOML configuration file."""
    path = Path(path)
    try:
        raw = path.read_bytes()
    except FileNotFoundError:
        raise InputError(str(path), "configuration file not found") from None
    except OSError as err:
        raise InputError(str(path), f"cannot read: {err.strerror}") from None
    try:
        data = tomllib.loads(raw.decode("utf-8"))
    except (UnicodeDecodeError, tomllib.TOMLDecodeError) as err:
        raise InputError(str(path), f"not valid TOML: {err}") from None
    except RecursionError:
        raise InputError(str(path), "arrays or tables nested too deeply to read") from None
    return parse_config(data, str(path), path.parent)


def material_of(body: BodySettings):
    """The J2Material of a body."""
    from calibration.fem.material import J2Material

    return J2Material(**asdict(body.material))


__all__ = ["CalibrationConfig", "BodySettings", "RunSettings", "MaterialSettings", "FitSettings",
           "LoadSettings", "MeshSettings", "load_config", "parse_config", "material_of"]
