"""Scenes of type "wheel_rail": the TOML content -> :class:`contact.wheel_rail.scene.WheelRailScene`, validated once
(units mm, N, MPa, s, rad). Keys (every one optional unless marked; unknown keys are errors)::

    type = "wheel_rail"                                   (required)
    title, description                                    free text
    [profiles]  rail = "60E1", wheel = "S1002"            a standard name or a profile file (.prr/.prw/.txt/.csv/
                                                          .whl/.ban, relative to the scene file); units ("mm"/"m",
                                                          the files' length unit), accept_unusual_profile
    [track]     gauge_mm = 1435, gauge_depth_mm = 14, inclination = 40 (1:40; or inclination_rad),
                back_to_back_mm = 1360, flange_back_y_mm = -70 (wheel profile coordinate of the flange back)
    [wheel]     nominal_radius_mm, side = "right" | "left" | "both"
    [wheelset]  lateral_mm (towards the right rail), yaw_rad, roll_rad (or "auto": the rigid wheelset's roll at
                which both wheels touch), pitch_rate_rad_s (default: speed / nominal radius)
    [load]      vertical_load_N (per wheel), speed_mm_s
    [material]  E_MPa or G_MPa, poisson
    [tangential] friction (0: no tangential solution)
    [layers]    rail = "table.json", wheel = "table.json" (calibration tables, relative to the scene file), or
                [layers.combined] u_mm, p_MPa (one characteristic for both bodies, the paper's eq. 13 layer);
                scale_to_patch = false (contact.scenes.layers)
    [passes]    max, hardening, tolerance_mm, memory, traction_coefficient (contact.scenes.sections.PassesSpec)
    [method]    alpha, grid_mm, fastsim_cells, normal, exact_cells, layer_mode, tangential, merge_mm,
                candidate_gap_mm, f_cap_mm, contact_point, balance (contact.wheel_rail.sections.WheelRailMethodSpec)
    [sweep]     per-case values of lateral_mm, yaw_rad, roll_rad, pitch_rate_rad_s, vertical_load_N, speed_mm_s
                (:mod:`contact.wheel_rail.sweep`)
    [output]    deformed_profiles, vtk, convention, contact_table, frictional_csv
    [run]       workers (local processes solving the cases), scheduler = "" (a Dask scheduler address)

Each key's unit, default and bounds are declared once on its section's field (:mod:`contact.scenes.sections`,
:mod:`contact.wheel_rail.sections`, :mod:`contact.wheel_rail.scene`). Validation errors name ``<file>: <section>.<key>``.
"""

from __future__ import annotations

import dataclasses
from pathlib import Path
from typing import Any

from contact.scenes.layers import read_layers
from contact.scenes.sections import TangentialSpec, read_material, read_method, read_passes
from contact.wheel_rail.scene import (
    ProfilesSpec,
    RunSpec,
    TrackSpec,
    WheelRailScene,
    WheelsetSpec,
    WheelSpec,
)
from contact.wheel_rail.scene_files import read_profile
from contact.wheel_rail.sections import WheelLoadSpec, WheelRailMethodSpec, WheelRailOutputSpec
from contact.wheel_rail.sweep import parse_sweep
from contact.wheel_rail.sweep_spec import CaseSpec
from contact.wheel_rail.track_geometry import INCLINATION, TrackLayout
from meshes.profiles.placement import rail_inclination
from wrlayer.errors import InputError
from wrlayer.input_files import read_toml
from wrlayer.section_keys import read_section
from wrlayer.validate import Keys, top_keys

TOP_KEYS = ("title", "description", "type", "accept_implausible", "profiles", "track", "wheel", "wheelset", "load", "material",
            "tangential", "layers", "passes", "method", "sweep", "output", "run")


def load_wheel_rail_scene(path: str | Path) -> WheelRailScene:
    """Read and validate a wheel–rail scene file (TOML; units mm, N, MPa, s, rad)."""
    path = Path(path)
    return parse_wheel_rail_scene(read_toml(path, what=str(path)), path)


def parse_wheel_rail_scene(data: dict[str, Any], scene_path: str | Path, accept_unusual_profile: bool = False
                           ) -> WheelRailScene:
    """Validate the TOML content of a wheel_rail scene read from ``scene_path`` (relative file names resolve from
    its folder); reads the profiles and tables it names. ``accept_unusual_profile``: as the scene key
    ``profiles.accept_unusual_profile`` = true (the command line's ``--accept-unusual-profile``). Raises InputError
    naming ``<file>: <section>.<key>``."""
    path = Path(scene_path)
    file, base = path.name, path.parent
    top = top_keys(file, data)
    top.check_known(TOP_KEYS)
    title, description = top.text("title", ""), top.text("description", "")

    def s(name: str) -> Keys:
        return top.sub(name) if name in data else Keys(file, name, {})

    profiles = read_section(ProfilesSpec, s("profiles"))
    if accept_unusual_profile:
        profiles = dataclasses.replace(profiles, accept_unusual_profile=True)
    unusual, units = profiles.accept_unusual_profile, profiles.units
    rail = read_profile(profiles.rail, base, "rail", s("profiles").what("rail"), unusual, units)
    track = _track(s("track"))
    wheel = read_section(WheelSpec, s("wheel"))
    wheel_profile = read_profile(profiles.wheel, base, "wheel", s("profiles").what("wheel"), unusual, units)
    _check_layout(s("track"), track, wheel)
    wheelset = _wheelset(s("wheelset"))
    material = read_material(s("material"))
    method = read_method(s("method"), WheelRailMethodSpec)
    passes = read_passes(s("passes"))
    load = read_section(WheelLoadSpec, s("load"))
    tangential = read_section(TangentialSpec, s("tangential"))
    if tangential.friction == 0 and "tangential" in s("method").table:
        raise s("tangential").error("friction", f"must be > 0 with method.tangential = {method.tangential!r} "
                                    "(0: no tangential solution)")
    layers = read_layers(top.sub("layers"), base) if "layers" in data else None
    base_case = CaseSpec(wheelset.lateral_mm, wheelset.yaw_rad, 0.0 if wheelset.roll_auto else wheelset.roll_rad,
                         wheelset.pitch_rate_rad_s, load.vertical_load_N, load.speed_mm_s)
    sweep = parse_sweep(top.sub("sweep"), base_case, base, wheelset.roll_auto)
    output = read_section(WheelRailOutputSpec, s("output"))
    run = _run(s("run"))
    return WheelRailScene(path, title, description, profiles, track, wheel, wheelset, load, material, tangential,
                          layers, passes, method, sweep, output, run, data, rail, wheel_profile)


def _track(track: Keys) -> TrackSpec:
    """[track]; ``inclination`` (n of 1:n) becomes ``inclination_rad``."""
    if "inclination" in track.table and "inclination_rad" in track.table:
        raise track.error("inclination", "give either inclination (1:n) or inclination_rad, not both")
    if "inclination_rad" in track.table:
        return read_section(TrackSpec, track)
    ratio = track.number("inclination", INCLINATION)
    if ratio == 0:
        incl = 0.0
    elif ratio < 5:
        raise track.error("inclination", f"1:n needs n >= 5 (or 0 for an upright rail), got {ratio:g}")
    else:
        incl = rail_inclination(ratio)
    return read_section(TrackSpec, track, given={"inclination_rad": incl}, also_known=("inclination",))


def _check_layout(track: Keys, spec: TrackSpec, wheel: WheelSpec) -> None:
    """The track's consistency checks (:class:`TrackLayout`), naming the [track] key."""
    try:
        TrackLayout(spec.gauge_mm, spec.gauge_depth_mm, spec.inclination_rad, spec.back_to_back_mm,
                    spec.flange_back_y_mm, wheel.nominal_radius_mm)
    except InputError as err:
        raise InputError(track.what(err.what), err.problem) from None


def _run(run: Keys) -> RunSpec:
    """[run]; the scheduler address checked by its form, before any case is solved (no connection)."""
    if "scheduler" not in run.table:
        return read_section(RunSpec, run)
    from wrlayer.runner import check_scheduler_address  # only with a scheduler: the runner imports multiprocessing

    return read_section(RunSpec, run, given={"scheduler": check_scheduler_address(run.table["scheduler"],
                                                                                   run.what("scheduler"))})


def _wheelset(ws: Keys) -> WheelsetSpec:
    """[wheelset]; ``roll_rad`` may be "auto"."""
    roll = "auto" if ws.table.get("roll_rad", 0.0) == "auto" else ws.number("roll_rad", 0.0, ge=-0.2, le=0.2)
    return read_section(WheelsetSpec, ws, given={"roll_rad": roll})


__all__ = ["TOP_KEYS", "load_wheel_rail_scene", "parse_wheel_rail_scene"]
