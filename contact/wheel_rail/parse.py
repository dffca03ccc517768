"""Scenes of type "wheel_rail": the TOML content -> :class:`contact.wheel_rail.scene.WheelRailScene`, validated once
(units mm, N, MPa, s, rad). Keys (every one optional unless marked; unknown keys are errors)::

    type = "wheel_rail"                                   (required)
    title, description                                    free text
    [profiles]  rail = "60E1", wheel = "S1002"            a standard name or a profile file (.prr/.prw/.txt/.csv,
                                                          relative to the scene file)
    [track]     gauge_mm = 1435, gauge_depth_mm = 14, inclination = 40 (1:40; or inclination_rad),
                back_to_back_mm = 1360, flange_back_y_mm = -70 (wheel profile coordinate of the flange back)
    [wheel]     nominal_radius_mm = 460, side = "right" | "left" | "both"
    [wheelset]  lateral_mm = 0 (towards the right rail), yaw_rad = 0, roll_rad = 0 or "auto" (the rigid
                wheelset's roll at which both wheels touch), pitch_rate_rad_s (default: speed / nominal radius)
    [load]      vertical_load_N = 10000 (per wheel), speed_mm_s = 2000
    [material]  E_MPa = 210000 or G_MPa, poisson = 0.28
    [tangential] friction = 0.3 (0: no tangential solution)
    [layers]    rail = "table.json", wheel = "table.json" (calibration tables, relative to the scene file), or
                [layers.combined] u_mm, p_MPa (one characteristic for both bodies, the paper's eq. 13 layer);
                scale_to_patch = false (true: each patch's table characteristics scaled to its own solved
                semi-axes, displacements x sqrt(ab)/sqrt(a_c b_c); docs/calibration.md)
    [passes]    max = 1, hardening = false, tolerance_mm = 1e-6, memory = "rolling", traction_coefficient = 0
    [method]    alpha = 0.55, grid_mm = 0.1, fastsim_cells = 60, merge_mm, candidate_gap_mm, f_cap_mm,
                normal = "kik_piotrowski" | "exact" | "coarse_exact" (the normal solver), exact_cells (exact
                solver grid: cells
                along x over the patch length, 8..1024, default 48), layer_mode ("indentation" | "rolling"),
                contact_point = "first_contact" (default) | "weighted_centre" (reported point; creepages there),
                balance = "total" (default: vertical component of normal + tangential forces = load) | "normal"
    [sweep]     per-case values of lateral_mm, yaw_rad, roll_rad, pitch_rate_rad_s, vertical_load_N, speed_mm_s
                (:mod:`contact.wheel_rail.sweep`)
    [output]    deformed_profiles = true (with layers: write each case's deformed rail/wheel profiles as SIMPACK
                .prr/.prw and CSV and read them back), vtk = true, convention = "wrlayer" | "contact",
                contact_table = false (true: contact_table.csv for multibody codes, docs/contact-tables.md),
                frictional_csv = true (false: no frictional_cells.csv / frictional_strips.csv)
    [run]       workers = 1 (local processes solving the cases), scheduler = "" (a Dask scheduler address)

Validation errors name ``<file>: <section>.<key>``.
"""

from __future__ import annotations

import math
from pathlib import Path
from typing import Any

from contact.normal.method import NormalMethod
from contact.scenes.scene_spec import OUTPUT_CONVENTIONS
from contact.tangential.method import TANGENTIAL_METHODS
from contact.wheel_rail.inputs import BALANCES
from contact.wheel_rail.reference_point import CONTACT_POINTS
from contact.wheel_rail.layers_spec import CombinedLayerSpec, LayersSpec, read_layers
from contact.scenes.scene_spec import PASSES_KEYS, parse_passes_memory
from contact.wheel_rail.scene import (
    LoadSpec,
    MaterialSpec,
    MethodSpec,
    OutputSpec,
    PassesSpec,
    ProfilesSpec,
    RunSpec,
    TangentialSpec,
    TrackSpec,
    WheelRailScene,
    WheelsetSpec,
    WheelSpec,
)
from contact.wheel_rail.scene_files import read_profile
from contact.wheel_rail.sweep import KEYS as SWEEP_SECTION_KEYS
from contact.wheel_rail.sweep import parse_sweep
from contact.wheel_rail.sweep_spec import CaseSpec
from contact.wheel_rail.track_geometry import TrackLayout
from wrlayer.input_files import read_toml
from wrlayer.elastic import youngs_modulus_MPa
from wrlayer.errors import InputError
from wrlayer.validate import (
    MAX_E_MPA,
    MAX_FASTSIM_CELLS,
    MAX_PASSES,
    MAX_RADIUS_MM,
    MIN_ALPHA,
    MIN_E_MPA,
    MIN_FORCE_N,
    MIN_GRID_MM,
    MIN_RADIUS_MM,
    Keys,
)

TOP_KEYS = ("title", "description", "type", "profiles", "track", "wheel", "wheelset", "load", "material",
            "tangential", "layers", "passes", "method", "sweep", "output", "run")
#: Keys of each section.
SECTION_KEYS = {
    "profiles": ("rail", "wheel", "accept_unusual_profile"),
    "track": ("gauge_mm", "gauge_depth_mm", "inclination", "inclination_rad", "back_to_back_mm", "flange_back_y_mm"),
    "wheel": ("nominal_radius_mm", "side"),
    "wheelset": ("lateral_mm", "yaw_rad", "roll_rad", "pitch_rate_rad_s"),
    "load": ("vertical_load_N", "speed_mm_s"),
    "material": ("E_MPa", "G_MPa", "poisson"),
    "tangential": ("friction",),
    "layers": ("rail", "wheel", "combined", "scale_to_patch"),
    "passes": PASSES_KEYS,
    "method": ("alpha", "grid_mm", "fastsim_cells", "merge_mm", "candidate_gap_mm", "f_cap_mm", "normal",
               "exact_cells", "layer_mode", "contact_point", "balance", "tangential"),
    "sweep": SWEEP_SECTION_KEYS,
    "output": ("deformed_profiles", "vtk", "convention", "contact_table", "frictional_csv"),
    "run": ("workers", "scheduler"),
}
#: Largest number of local worker processes of [run] (as the calibration's run.workers).
MAX_WORKERS = 64
SIDES = ("right", "left", "both")


def load_wheel_rail_scene(path: str | Path) -> WheelRailScene:
    """Read and validate a wheel–rail scene file (TOML; units mm, N, MPa, s, rad)."""
    path = Path(path)
    return parse_wheel_rail_scene(read_toml(path, what=str(path)), path)


def parse_wheel_rail_scene(data: dict[str, Any], scene_path: str | Path) -> WheelRailScene:
    """Validate the TOML content of a wheel_rail scene read from ``scene_path`` (relative file names resolve from
    its folder); reads the profiles and tables it names. Raises InputError naming ``<file>: <section>.<key>``."""
    path = Path(scene_path)
    file, base = path.name, path.parent
    top = Keys(file, "", data)
    top.check_known(TOP_KEYS)
    sec = {name: top.sub(name) for name in SECTION_KEYS if name in data}
    for name, allowed in SECTION_KEYS.items():
        if name in sec:
            sec[name].check_known(allowed)
    title, description = top.text("title", ""), top.text("description", "")

    def s(name: str) -> Keys:
        return sec.get(name) or Keys(file, name, {})

    profiles = ProfilesSpec(s("profiles").text("rail", "60E1"), s("profiles").text("wheel", "S1002"),
                            s("profiles").boolean("accept_unusual_profile", False))
    unusual = profiles.accept_unusual_profile
    rail = read_profile(profiles.rail, base, "rail", s("profiles").what("rail"), unusual)
    track = _track(s("track"))
    wheel = WheelSpec(s("wheel").number("nominal_radius_mm", 460.0, ge=MIN_RADIUS_MM, le=MAX_RADIUS_MM),
                      s("wheel").text("side", "right"))
    wheel_profile = read_profile(profiles.wheel, base, "wheel", s("profiles").what("wheel"), unusual)
    _check_layout(s("track"), track, wheel)
    if wheel.side not in SIDES:
        raise s("wheel").error("side", f"must be 'right', 'left' or 'both', got {wheel.side!r}")
    wheelset = _wheelset(s("wheelset"))
    load = s("load")
    material = _material(s("material"))
    method = _method(s("method"))
    hardening, memory, traction = parse_passes_memory(s("passes"))
    passes = PassesSpec(s("passes").integer("max", 1, ge=1, le=MAX_PASSES), hardening,
                        s("passes").number("tolerance_mm", 1e-6, ge=0.0), memory, traction)
    load_spec = LoadSpec(load.number("vertical_load_N", 10000.0, ge=MIN_FORCE_N),
                         load.number("speed_mm_s", 2000.0, gt=0.0))
    tangential = TangentialSpec(s("tangential").number("friction", 0.3, ge=0.0))
    if tangential.friction == 0 and "tangential" in s("method").table:
        raise s("tangential").error("friction", f"must be > 0 with method.tangential = {method.tangential!r} "
                                    "(0: no tangential solution)")
    layers = _layers(sec.get("layers"), base)
    base_case = CaseSpec(wheelset.lateral_mm, wheelset.yaw_rad, 0.0 if wheelset.roll_auto else wheelset.roll_rad,
                         wheelset.pitch_rate_rad_s, load_spec.vertical_load_N, load_spec.speed_mm_s)
    sweep = parse_sweep(sec.get("sweep"), base_case, base, wheelset.roll_auto)
    output = OutputSpec(s("output").boolean("deformed_profiles", True), s("output").boolean("vtk", True),
                        s("output").text("convention", OutputSpec.convention, OUTPUT_CONVENTIONS),
                        s("output").boolean("contact_table", OutputSpec.contact_table),
                        s("output").boolean("frictional_csv", OutputSpec.frictional_csv))
    run = _run(s("run"))
    return WheelRailScene(path, title, description, profiles, track, wheel, wheelset, load_spec, material, tangential,
                          layers, passes, method, sweep, output, run, data, rail, wheel_profile)


def _track(track: Keys) -> TrackSpec:
    """[track]; ``inclination`` (n of 1:n) becomes ``inclination_rad``."""
    if "inclination" in track.table and "inclination_rad" in track.table:
        raise track.error("inclination", "give either inclination (1:n) or inclination_rad, not both")
    if "inclination_rad" in track.table:
        incl = track.number("inclination_rad", ge=-0.2, le=0.2)
    else:
        ratio = track.number("inclination", 40.0)
        if ratio == 0:
            incl = 0.0
        elif ratio < 5:
            raise track.error("inclination", f"1:n needs n >= 5 (or 0 for an upright rail), got {ratio:g}")
        else:
            incl = math.atan(1.0 / ratio)
    return TrackSpec(gauge_mm=track.number("gauge_mm", 1435.0), gauge_depth_mm=track.number("gauge_depth_mm", 14.0,
                     gt=0.0), inclination_rad=incl, back_to_back_mm=track.number("back_to_back_mm", 1360.0, gt=0.0),
                     flange_back_y_mm=track.number("flange_back_y_mm", -70.0))


def _check_layout(track: Keys, spec: TrackSpec, wheel: WheelSpec) -> None:
    """The track's consistency checks (:class:`TrackLayout`), naming the [track] key."""
    try:
        TrackLayout(spec.gauge_mm, spec.gauge_depth_mm, spec.inclination_rad, spec.back_to_back_mm,
                    spec.flange_back_y_mm, wheel.nominal_radius_mm)
    except InputError as err:
        raise InputError(track.what(err.what), err.problem) from None


def _run(run: Keys) -> RunSpec:
    """[run]; the scheduler address checked by its form, before any case is solved (no connection)."""
    workers = run.integer("workers", RunSpec.workers, ge=1, le=MAX_WORKERS)
    if "scheduler" not in run.table:
        return RunSpec(workers)
    from wrlayer.runner import check_scheduler_address  # only with a scheduler: the runner imports multiprocessing

    return RunSpec(workers, check_scheduler_address(run.table["scheduler"], run.what("scheduler")))


def _wheelset(ws: Keys) -> WheelsetSpec:
    roll = "auto" if ws.table.get("roll_rad", 0.0) == "auto" else ws.number("roll_rad", 0.0, ge=-0.2, le=0.2)
    return WheelsetSpec(ws.number("lateral_mm", 0.0), ws.number("yaw_rad", 0.0, ge=-0.2, le=0.2), roll,
                        ws.number("pitch_rate_rad_s") if "pitch_rate_rad_s" in ws.table else None)


def _material(mat: Keys) -> MaterialSpec:
    """[material]; ``G_MPa`` becomes ``E_MPa`` = 2 G (1 + nu)."""
    nu = mat.number("poisson", 0.28, ge=0.0, lt=0.5)
    if "E_MPa" in mat.table and "G_MPa" in mat.table:
        raise mat.error("G_MPa", "give either E_MPa or G_MPa, not both")
    if "G_MPa" in mat.table:
        return MaterialSpec(youngs_modulus_MPa(mat.number("G_MPa", ge=MIN_E_MPA / 3.0, le=MAX_E_MPA / 2.0), nu), nu)
    return MaterialSpec(mat.number("E_MPa", 210000.0, ge=MIN_E_MPA, le=MAX_E_MPA), nu)


def _method(met: Keys) -> MethodSpec:
    spec = MethodSpec(alpha=met.number("alpha", 0.55, ge=MIN_ALPHA, le=1.0),
                      grid_mm=met.number("grid_mm", 0.1, ge=MIN_GRID_MM),
                      fastsim_cells=met.integer("fastsim_cells", 60, ge=2, le=MAX_FASTSIM_CELLS),
                      merge_mm=met.number("merge_mm", 0.005, ge=0.0),
                      candidate_gap_mm=met.number("candidate_gap_mm", 1.0, gt=0.0),
                      f_cap_mm=met.number("f_cap_mm", 2.0, gt=0.0),
                      normal=met.text("normal", "kik_piotrowski"),
                      exact_cells=met.integer("exact_cells", None, ge=1),
                      layer_mode=met.text("layer_mode", "indentation"),
                      contact_point=met.text("contact_point", "first_contact", CONTACT_POINTS),
                      balance=met.text("balance", "total", BALANCES),
                      tangential=met.text("tangential", MethodSpec.tangential, TANGENTIAL_METHODS))
    try:
        NormalMethod(spec.normal, exact_cells=spec.exact_cells, layer_mode=spec.layer_mode)
    except InputError as err:
        key = err.what.removeprefix("method.")
        raise met.error(key if key in ("exact_cells", "layer_mode") else "normal", err.problem) from None
    return spec


def _layers(keys: Keys | None, base: Path) -> LayersSpec | None:
    if keys is None:
        return None
    scale = keys.boolean("scale_to_patch", False)
    combined = None
    if "combined" in keys.table:
        if "rail" in keys.table or "wheel" in keys.table:
            raise keys.error("combined", "give either per-body tables (rail, wheel) or combined, not both")
        if scale:
            raise keys.error("scale_to_patch", "only used with calibration tables (rail, wheel), not with "
                                               "[layers.combined]")
        sub = keys.sub("combined")
        sub.check_known(("u_mm", "p_MPa"))
        combined = CombinedLayerSpec(tuple(sub.array("u_mm").tolist()), tuple(sub.array("p_MPa").tolist()))
    tables = {body: keys.text(body) for body in ("rail", "wheel") if body in keys.table}
    if combined is None and not tables:
        raise keys.error("rail", "[layers] needs rail and/or wheel tables, or [layers.combined]")
    return read_layers(combined, tables, scale, base, f"{keys.file}: layers")


__all__ = ["MAX_WORKERS", "SECTION_KEYS", "TOP_KEYS", "parse_wheel_rail_scene"]
