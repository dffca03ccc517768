"""Scenes of type "wheel_rail": wheels on rails placed in a track, one case or a sweep (units mm, N, MPa, s, rad).

Run by ``python -m contact simulate SCENE --out DIR`` (and ``simulate-all``), which calls
:func:`run_wheel_rail_scene`. Keys (every one optional unless marked; unknown keys are errors)::

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
    [passes]    max = 1, hardening = false, tolerance_mm = 1e-6
    [method]    alpha = 0.55, grid_mm = 0.1, fastsim_cells = 60, merge_mm, candidate_gap_mm, f_cap_mm,
                normal = "kik_piotrowski" | "exact" (the normal solver), exact_cells (exact solver grid: cells
                along x over the patch length, 8..1024, default 48), layer_mode ("indentation" | "rolling"),
                contact_point = "first_contact" (default) | "weighted_centre" (reported point; creepages there),
                balance = "total" (default: vertical component of normal + tangential forces = load) | "normal"
    [sweep]     per-case values of lateral_mm, yaw_rad, roll_rad, pitch_rate_rad_s, vertical_load_N, speed_mm_s:
                a list of values or {start, stop, step} (stop included) per key; mode = "zip" (default; lists
                of equal length, case k takes the k-th value of each) or "product"; or csv = "cases.csv" (columns
                named like those keys, one case per row, '#' comments; other columns ignored) with
                convention = "wrlayer" (default) | "contact" (CONTACT's roll and pitch-rate signs). File names
                starting with "reference:" are looked up in $WRLAYER_REFERENCE or <repo>/../shared/reference.
    [output]    deformed_profiles = true (with layers: write each case's deformed rail/wheel profiles as SIMPACK
                .prr/.prw and CSV and read them back)

Output: ``result.json`` and ``cases.csv`` (one row per loaded patch: pose, location, angle, N, Fx, Fy, p_max,
area, creepages, Y/Q, balance residual, run time; :data:`CSV_COLUMNS`). A progress bar over the cases goes to
stderr when it is a terminal (:mod:`wrlayer.progress`; ``WRLAYER_PROGRESS=0/1`` overrides). Conventions:
docs/wheel-rail.md.

A case that fails (bad geometry: profiles that do not meet, the flange through the rail; or a solver failure) is
recorded with its error message in ``cases[k].error`` and the other cases are still computed; the scene itself
fails only when every case fails. Validation errors name ``<file>: <section>.<key>``.
"""

from __future__ import annotations

import csv
import hashlib
import io
import itertools
import math
import os
import time
from pathlib import Path
from typing import Any

import numpy as np

from contact.layer.characteristic import Characteristic
from contact.passes.passes import PassesOptions
from contact.scenes.result_io import UNITS, code_version
from contact.scenes.scene import (
    MAX_E_MPA,
    MAX_FASTSIM_CELLS,
    MAX_PASSES,
    MAX_RADIUS_MM,
    MIN_ALPHA,
    MIN_E_MPA,
    MIN_FORCE_N,
    MIN_GRID_MM,
    MIN_RADIUS_MM,
    SceneKeys,
)
from contact.wheel_rail.contact_search import SearchSettings
from contact.wheel_rail.solve import (
    PatchSolution,
    WheelRailInputs,
    WheelRailLayers,
    WheelRailSolution,
    deformed_profile,
    residual_on_profiles,
    rigid_roll,
    solve_wheel,
)
from contact.wheel_rail.track_geometry import TrackLayout, WheelsetPose, place_rail
from meshes.profiles import get_profile
from wrlayer.errors import ConvergenceError, InputError
from wrlayer.validate import MAX_ABS

TOP_KEYS = ("title", "description", "type", "profiles", "track", "wheel", "wheelset", "load", "material",
            "tangential", "layers", "passes", "method", "sweep", "output")
#: Per-case inputs a sweep may vary (a list per key, a {start, stop, step} range, or a column of a CSV file).
SWEEP_KEYS = ("lateral_mm", "yaw_rad", "roll_rad", "pitch_rate_rad_s", "vertical_load_N", "speed_mm_s")
#: Sign conventions of a sweep CSV: factors applied to its columns ("contact": CONTACT's input files, whose roll and
#: pitch rate are measured the other way round; see docs/wheel-rail.md).
CSV_CONVENTIONS = {"wrlayer": {}, "contact": {"roll_rad": -1.0, "pitch_rate_rad_s": -1.0}}
#: Largest number of sweep cases (values per axis, rows of a sweep CSV, cases of the product): a hard size limit,
#: checked before any case is built; the cost guard (contact.scenes.cost) refuses long runs below it unless forced.
MAX_CASES = 100000


# ------------------------------------------------------------------------------------------------ parsing
def reference_dir() -> Path:
    """The shared reference folder: ``$WRLAYER_REFERENCE`` or ``<repo>/../shared/reference``."""
    env = os.environ.get("WRLAYER_REFERENCE")
    return Path(env) if env else Path(__file__).resolve().parents[2].parent / "shared" / "reference"


def resolve_path(name: str, base: Path) -> Path:
    """A file named in a scene: ``reference:REL`` is REL inside :func:`reference_dir`, anything else is relative to
    the scene file's folder ``base``."""
    if name.startswith("reference:"):
        return reference_dir() / name[len("reference:"):]
    return base / name


def _profile(keys: SceneKeys, key: str, default: str, base: Path, body: str):
    name = keys.text(key, default)
    candidate = resolve_path(name, base)
    target = str(candidate) if candidate.suffix.lower() in (".prr", ".prw", ".txt", ".csv") else name
    if target != name and not candidate.is_file():
        raise keys.error(key, f"no such profile file {name!r} (looked at {candidate})")
    try:
        prof = get_profile(target, body=body) if Path(target).suffix.lower() in (".txt", ".csv") \
            else get_profile(target)
    except InputError as err:
        raise InputError(keys.what(key), str(err)) from None
    if prof.body != body:
        raise InputError(keys.what(key), f"{prof.name} is a {prof.body} profile, expected a {body} profile")
    return prof


def _values(keys: SceneKeys, key: str) -> np.ndarray:
    """A sweep axis: a list of numbers or {start, stop, step} (stop included within step/1e6)."""
    value = keys.table[key]
    if isinstance(value, dict):
        sub = keys.sub(key)
        sub.check_known(("start", "stop", "step"))
        start, stop, step = sub.number("start"), sub.number("stop"), sub.number("step", gt=0.0)
        if stop < start:
            raise sub.error("stop", f"must be >= start ({start:g}), got {stop:g}")
        n = math.floor((stop - start) / step + 1e-6) + 1
        if n > MAX_CASES:
            raise sub.error("step", f"gives {n:.3g} values from {start:g} to {stop:g} (at most {MAX_CASES})")
        return start + step * np.arange(n)
    return keys.array(key, min_len=1, max_len=MAX_CASES)


def parse_wheel_rail_scene(data: dict[str, Any], scene_path: Path) -> dict[str, Any]:
    """Validate a wheel_rail scene; returns the parsed objects (profiles, layout, cases, inputs template, layers)."""
    scene_path = Path(scene_path)
    file, base = scene_path.name, scene_path.parent
    top = SceneKeys(file, "", data)
    top.check_known(TOP_KEYS)
    known = {
        "profiles": ("rail", "wheel"),
        "track": ("gauge_mm", "gauge_depth_mm", "inclination", "inclination_rad", "back_to_back_mm",
                  "flange_back_y_mm"),
        "wheel": ("nominal_radius_mm", "side"),
        "wheelset": ("lateral_mm", "yaw_rad", "roll_rad", "pitch_rate_rad_s"),
        "load": ("vertical_load_N", "speed_mm_s"),
        "material": ("E_MPa", "G_MPa", "poisson"),
        "tangential": ("friction",),
        "layers": ("rail", "wheel", "combined", "scale_to_patch"),
        "passes": ("max", "hardening", "tolerance_mm"),
        "method": ("alpha", "grid_mm", "fastsim_cells", "merge_mm", "candidate_gap_mm", "f_cap_mm", "normal",
                   "exact_cells", "layer_mode", "contact_point", "balance"),
        "sweep": SWEEP_KEYS + ("mode", "csv", "convention"),
        "output": ("deformed_profiles",),
    }
    sec = {name: top.sub(name) for name in known if name in data}
    for name, allowed in known.items():
        if name in sec:
            sec[name].check_known(allowed)
    for key in ("title", "description"):
        top.text(key, "")

    def s(name: str) -> SceneKeys:
        return sec.get(name) or SceneKeys(file, name, {})

    rail = _profile(s("profiles"), "rail", "60E1", base, "rail")
    track = s("track")
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
    wheel_keys = s("wheel")
    r0 = wheel_keys.number("nominal_radius_mm", 460.0, ge=MIN_RADIUS_MM, le=MAX_RADIUS_MM)
    wheel = _profile(s("profiles"), "wheel", "S1002", base, "wheel")
    try:
        layout = TrackLayout(gauge_mm=track.number("gauge_mm", 1435.0), gauge_depth_mm=track.number("gauge_depth_mm",
                             14.0, gt=0.0), inclination_rad=incl, back_to_back_mm=track.number("back_to_back_mm",
                             1360.0, gt=0.0), flange_back_y_mm=track.number("flange_back_y_mm", -70.0),
                             nominal_radius_mm=r0)
    except InputError as err:
        if err.what.startswith(f"{file}: "):  # already names the file and key (a bad number)
            raise
        raise InputError(f"{file}: track.{err.what}", err.problem) from None
    side = wheel_keys.text("side", "right")
    if side not in ("right", "left", "both"):
        raise wheel_keys.error("side", f"must be 'right', 'left' or 'both', got {side!r}")
    ws = s("wheelset")
    roll_value = ws.table.get("roll_rad", 0.0)
    roll_auto = roll_value == "auto"
    base_pose = {"lateral_mm": ws.number("lateral_mm", 0.0), "yaw_rad": ws.number("yaw_rad", 0.0, ge=-0.2, le=0.2),
                 "roll_rad": 0.0 if roll_auto else ws.number("roll_rad", 0.0, ge=-0.2, le=0.2)}
    pitch = ws.number("pitch_rate_rad_s") if "pitch_rate_rad_s" in ws.table else None
    load = s("load")
    mat = s("material")
    nu = mat.number("poisson", 0.28, ge=0.0, lt=0.5)
    if "E_MPa" in mat.table and "G_MPa" in mat.table:
        raise mat.error("G_MPa", "give either E_MPa or G_MPa, not both")
    E = 2.0 * mat.number("G_MPa", ge=MIN_E_MPA / 3.0, le=MAX_E_MPA / 2.0) * (1.0 + nu) if "G_MPa" in mat.table \
        else mat.number("E_MPa", 210000.0, ge=MIN_E_MPA, le=MAX_E_MPA)
    met, pas = s("method"), s("passes")
    search = SearchSettings(merge_mm=met.number("merge_mm", 0.005, ge=0.0),
                            candidate_gap_mm=met.number("candidate_gap_mm", 1.0, gt=0.0),
                            f_cap_mm=met.number("f_cap_mm", 2.0, gt=0.0))
    inputs = {"layout": layout, "side": "right",
              "vertical_load_N": load.number("vertical_load_N", 10000.0, ge=MIN_FORCE_N),
              "speed_mm_s": load.number("speed_mm_s", 2000.0, gt=0.0), "pitch_rate_rad_s": pitch,
              "friction": s("tangential").number("friction", 0.3, ge=0.0), "E_MPa": E, "poisson": nu,
              "alpha": met.number("alpha", 0.55, ge=MIN_ALPHA, le=1.0),
              "grid_mm": met.number("grid_mm", 0.1, ge=MIN_GRID_MM),
              "fastsim_cells": met.integer("fastsim_cells", 60, ge=2, le=MAX_FASTSIM_CELLS),
              "passes": PassesOptions(max_passes=pas.integer("max", 1, ge=1, le=MAX_PASSES),
                                      tolerance_mm=pas.number("tolerance_mm", 1e-6, ge=0.0),
                                      hardening=pas.boolean("hardening", False)),
              "search": search, "normal_method": _normal_method(met),
              "contact_point": met.text("contact_point", "first_contact"),
              "balance": met.text("balance", "total")}
    for key in ("contact_point", "balance"):
        try:
            WheelRailInputs(**{k: v for k, v in inputs.items() if k in (key,)})
        except InputError as err:
            raise met.error(key, err.problem) from None
    layers, hashes = _parse_layers(sec.get("layers"), base)
    sweep = sec.get("sweep")
    base_pose.update({"pitch_rate_rad_s": pitch, "vertical_load_N": inputs["vertical_load_N"],
                      "speed_mm_s": inputs["speed_mm_s"]})
    cases, csv_info = _cases(sweep, base_pose, base)
    if roll_auto and sweep is not None and ("roll_rad" in sweep.table or "roll_rad" in csv_info.get("columns", ())):
        raise sweep.error("roll_rad", "cannot sweep the roll angle when wheelset.roll_rad = \"auto\"")
    out = s("output")
    return {"rail": rail, "wheel": wheel, "layout": layout, "sides": ["right", "left"] if side == "both" else [side],
            "roll_auto": roll_auto, "cases": cases, "inputs": inputs, "layers": layers, "table_sha256": hashes,
            "sweep_csv": csv_info,
            "deformed_profiles": out.boolean("deformed_profiles", True)}


def _parse_layers(keys: SceneKeys | None, base: Path) -> tuple[WheelRailLayers | None, dict]:
    if keys is None:
        return None, {}
    hashes: dict[str, str] = {}
    scale = keys.boolean("scale_to_patch", False)
    if "combined" in keys.table:
        if "rail" in keys.table or "wheel" in keys.table:
            raise keys.error("combined", "give either per-body tables (rail, wheel) or combined, not both")
        if scale:
            raise keys.error("scale_to_patch", "only used with calibration tables (rail, wheel), not with "
                                               "[layers.combined]")
        sub = keys.sub("combined")
        sub.check_known(("u_mm", "p_MPa"))
        return WheelRailLayers(combined=Characteristic(sub.array("u_mm"), sub.array("p_MPa"),
                                                       name=sub.what("u_mm/p_MPa"))), hashes
    from contact.layer.layer_table import LayerTable

    tables, names = {}, {}
    for body in ("rail", "wheel"):
        if body not in keys.table:
            continue
        rel = keys.text(body)
        path = (base / rel).resolve()
        if not path.is_file():
            raise keys.error(body, f"no such calibration table {rel!r} (looked at {path})")
        try:
            table = LayerTable.read(path)
        except InputError as err:
            raise keys.error(body, str(err)) from None
        if table.body != body:
            raise keys.error(body, f"{rel} is a {table.body} table, expected a {body} table")
        tables[body], names[body] = table, path.name
        hashes[body] = hashlib.sha256(path.read_bytes()).hexdigest()
    if not tables:
        raise keys.error("rail", "[layers] needs rail and/or wheel tables, or [layers.combined]")
    if scale:
        for body, table in tables.items():
            if any(table.calibrated_length_mm(y) is None for y in table.y_range_mm):
                raise keys.error("scale_to_patch", f"the {body} table {names[body]} records no calibrated "
                                                   "semi-axes (geometry a_mm, b_mm): it cannot be scaled")
    return WheelRailLayers(rail=tables.get("rail"), wheel=tables.get("wheel"), names=names,
                           scale_to_patch=scale), hashes


def _normal_method(met: SceneKeys):
    from contact.normal.method import NormalMethod

    name = met.text("normal", "kik_piotrowski")
    cells = met.integer("exact_cells", None, ge=1) if "exact_cells" in met.table else None
    try:
        return NormalMethod(name, exact_cells=cells, layer_mode=met.text("layer_mode", "indentation"))
    except InputError as err:
        key = err.what.removeprefix("method.")
        raise met.error(key if key in ("exact_cells", "layer_mode") else "normal", err.problem) from None


def _csv_columns(sweep: SceneKeys, base: Path) -> tuple[dict[str, np.ndarray], dict[str, Any]]:
    """The sweep CSV (``sweep.csv``): columns named like the sweep keys (others are ignored and listed), '#'
    comment lines, one case per row; ``sweep.convention`` = "wrlayer" (default) or "contact" (sign factors)."""
    rel = sweep.text("csv")
    path = resolve_path(rel, base)
    if not path.is_file():
        raise sweep.error("csv", f"no such file {rel!r} (looked at {path})")
    convention = sweep.text("convention", "wrlayer")
    if convention not in CSV_CONVENTIONS:
        raise sweep.error("convention", f"must be one of {', '.join(CSV_CONVENTIONS)}, got {convention!r}")
    text = path.read_text(encoding="utf-8", errors="replace")
    lines = [ln for ln in text.splitlines() if ln.strip() and not ln.lstrip().startswith("#")]
    rows = list(csv.reader(io.StringIO("\n".join(lines))))
    if len(rows) < 2:
        raise sweep.error("csv", f"{rel}: needs a header line and at least one case")
    if len(rows) - 1 > MAX_CASES:
        raise sweep.error("csv", f"{rel}: has {len(rows) - 1} cases (at most {MAX_CASES})")
    header = [h.strip() for h in rows[0]]
    used = [h for h in header if h in SWEEP_KEYS]
    if not used:
        raise sweep.error("csv", f"{rel}: no column named like a sweep key ({', '.join(SWEEP_KEYS)}); header: "
                          f"{', '.join(header)}")
    cols: dict[str, list[float]] = {h: [] for h in used}
    for lineno, row in enumerate(rows[1:], start=2):
        if len(row) != len(header):
            raise sweep.error("csv", f"{rel}: data row {lineno - 1} has {len(row)} fields, the header {len(header)}")
        for h, v in zip(header, row):
            if h in cols:
                try:
                    x = float(v)
                except ValueError:
                    raise sweep.error("csv", f"{rel}: data row {lineno - 1}, column {h}: not a number: {v!r}") \
                        from None
                if not (math.isfinite(x) and abs(x) <= MAX_ABS):
                    raise sweep.error("csv", f"{rel}: data row {lineno - 1}, column {h}: not a finite number of "
                                      f"magnitude <= {MAX_ABS:g}: {v!r}")
                cols[h].append(x * CSV_CONVENTIONS[convention].get(h, 1.0))
    info = {"file": str(path), "sha256": hashlib.sha256(path.read_bytes()).hexdigest(), "convention": convention,
            "columns": used, "ignored_columns": [h for h in header if h not in used]}
    return {k: np.array(v) for k, v in cols.items()}, info


def _cases(sweep: SceneKeys | None, base_pose: dict[str, Any], base: Path) -> tuple[list[dict[str, Any]], dict]:
    if sweep is None:
        return [dict(base_pose)], {}
    axes, info = {}, {}
    if "csv" in sweep.table:
        both = [k for k in SWEEP_KEYS if k in sweep.table]
        axes, info = _csv_columns(sweep, base)
        if both:
            raise sweep.error(both[0], "give the per-case values either in the CSV (sweep.csv) or as lists, not both")
    elif "convention" in sweep.table:
        raise sweep.error("convention", "applies to a sweep CSV only (sweep.csv)")
    axes.update({k: _values(sweep, k) for k in SWEEP_KEYS if k in sweep.table})
    if not axes:
        raise sweep.error("lateral_mm", f"[sweep] needs at least one of {', '.join(SWEEP_KEYS)} or a csv")
    mode = sweep.text("mode", "zip")
    if mode not in ("zip", "product"):
        raise sweep.error("mode", f"must be 'zip' or 'product', got {mode!r}")
    names = list(axes)
    if mode == "zip":
        sizes = {k: v.size for k, v in axes.items()}
        if len(set(sizes.values())) > 1:
            raise sweep.error("mode", f"'zip' needs sweep lists of equal length, got {sizes}")
        rows = list(zip(*(axes[k] for k in names)))
    else:
        n_cases = math.prod(v.size for v in axes.values())
        if n_cases > MAX_CASES:
            raise sweep.error("mode", f"'product' of {' x '.join(str(v.size) for v in axes.values())} values gives "
                              f"{n_cases:.3g} cases (at most {MAX_CASES})")
        rows = list(itertools.product(*(axes[k] for k in names)))
    cases = []
    for row in rows:
        case = dict(base_pose)
        case.update({k: float(v) for k, v in zip(names, row)})
        cases.append(case)
    for case in cases:
        for key in ("yaw_rad", "roll_rad"):
            if abs(case[key]) >= 0.2:
                raise sweep.error(key, f"angle {case[key]:g} rad is not plausible (|angle| < 0.2 rad)")
        for key, low in (("vertical_load_N", MIN_FORCE_N), ("speed_mm_s", 0.0)):
            if not (case[key] > 0 and case[key] >= low):
                raise sweep.error(key, f"must be > 0 in every case{f' (at least {low:g})' if low else ''}, got "
                                  f"{case[key]:g}")
    return cases, info


# ------------------------------------------------------------------------------------------------ results
def patch_result(p: PatchSolution) -> dict[str, Any]:
    """JSON-serialisable numbers of one loaded patch (track-frame forces; see contact.wheel_rail.contact_search for the
    location conventions)."""
    c, ns = p.candidate, p.normal
    t = p.tangential
    ref = p.reference
    sign = p.strip_sign
    out = {
        "contact_point": ref.kind, "eta_ref_mm": ref.eta_mm,
        "y_rail_mm": ref.y_rail_mm, "y_wheel_mm": ref.y_wheel_mm,
        "Y_track_mm": float(p.point_track[1]), "Z_track_mm": float(p.point_track[2]),
        "X_lead_mm": float(p.point_track[0]),
        "first_contact": {"y_rail_mm": c.y_rail_mm, "y_wheel_mm": c.y_wheel_mm, "Y_track_mm": sign * c.Y_mm,
                          "Z_track_mm": c.Z_mm, "X_lead_mm": c.X_mm, "contact_angle_rad": c.contact_angle_rad},
        "weighted_centre": _weighted_centre_result(p),
        "contact_angle_rad": ref.angle_rad, "contact_angle_deg": math.degrees(ref.angle_rad),
        "wheel_contact_angle_rad": c.wheel_contact_angle_rad, "wheel_radius_mm": c.wheel_radius_mm,
        "rolling_radius_kp_mm": c.rolling_radius_kp_mm, "normal_gap_mm": c.normal_gap_mm,
        "normal_force_N": p.normal_force_N, "delta_mm": ns.delta_mm, "delta0_mm": ns.delta0_mm,
        "area_mm2": ns.area_mm2, "p_max_MPa": ns.p_max_MPa, "length_mm": ns.length_mm, "width_mm": ns.width_mm,
        "n_regions": len(ns.patches),
        "regions": [{"eta_min_mm": float(pt.y_mm[0]), "eta_max_mm": float(pt.y_mm[-1]), "p0_MPa": r.p0_MPa,
                     "normal_force_N": r.normal_force_N} for pt, r in zip(ns.patches, ns.regions)],
        "creepage_x": p.kinematics.vx, "creepage_y": p.kinematics.vy, "spin_per_mm": p.kinematics.phi_per_mm,
        "Fx_N": p.Fx_N, "Fy_N": p.Fy_N, "Mz_Nmm": p.Mz_Nmm,
        "WT_max": max((r.WT_max_N_per_mm for r in t), default=None),
        "PT_max_W_per_mm2": max((r.PT_max_W_per_mm2 for r in t), default=None),
        "force_on_wheel_track_N": p.force_track_N().tolist(),
        "normal_track": p.normal_track.tolist(), "lateral_track": p.lateral_track.tolist(),
        "elastic": bool(ns.elastic), "u0_mm": ns.u0_mm,
        "layer_scaled_to_patch": None if p.layer_patch_mm is None else {
            "a_mm": p.layer_patch_mm[0], "b_mm": p.layer_patch_mm[1], "balances": p.layer_scaling_solves},
    }
    y, f = p.problem.strip_y_mm, p.problem.separation_on_grid_mm
    near = f <= 2.0 * ns.delta0_mm  # the strips in contact and their neighbourhood
    out["strips"] = {"eta_mm": y[near].tolist(), "f_mm": f[near].tolist(), "p_peak_MPa": ns.p_peak_MPa[near].tolist(),
                     "y_rail_mm": p.rail_y_of_strip[near].tolist(), "y_wheel_mm": p.wheel_y_of_strip[near].tolist()}
    if p.passes:
        out["passes"] = [{**r.summary(), "max_cumulative_residual_mm":
                          {b: float(np.max(v, initial=0.0)) for b, v in r.cumulative_residual_mm.items()}}
                         for r in p.passes]
    return out


def _weighted_centre_result(p: PatchSolution) -> dict[str, float]:
    from contact.wheel_rail.reference_point import weighted_centre_eta

    c = p.candidate
    eta = weighted_centre_eta(c, p.normal.delta_mm)
    return {"eta_mm": eta, "y_rail_mm": float(c.rail_coordinate(eta)), "y_wheel_mm": float(c.wheel_coordinate(eta)),
            "Y_track_mm": p.strip_sign * float(c.Y_mm + eta * c.lateral[1]), "Z_track_mm": float(c.Z_mm + eta
                                                                                                  * c.lateral[2])}


def wheel_result(sol: WheelRailSolution) -> dict[str, Any]:
    Q = sol.inputs.vertical_load_N
    force = sum((p.force_track_N() for p in sol.patches), np.zeros(3))
    return {
        "side": sol.inputs.side, "wheel_height_mm": sol.search.wheel_height_mm, "approach_mm": sol.approach_mm,
        "vertical_balance_rel": sol.vertical_balance_rel, "balance": sol.inputs.balance,
        "balance_iterations": sol.balance_iterations, "vertical_force_N": float(force[2]),
        "merge_mm": sol.merge_mm,
        "normal_vertical_N": float(sum(p.normal_force_N * p.normal_track[2] for p in sol.patches)),
        "force_on_wheel_track_N": force.tolist(), "Y_over_Q": float(force[1] / Q), "n_patches": len(sol.patches),
        "patches": [{**patch_result(p), "load_share": p.vertical_N / float(force[2])} for p in sol.patches],
        "unloaded_candidates": [{"y_rail_mm": c.y_rail_mm, "y_wheel_mm": c.y_wheel_mm, "normal_gap_mm": c.normal_gap_mm,
                                 "contact_angle_rad": c.contact_angle_rad} for c in sol.unloaded],
        "flange_tip": {"y_wheel_mm": sol.search.flange_tip[0], "Y_side_mm": sol.search.flange_tip[1]},
    }


# ------------------------------------------------------------------------------------------------ run
def solve_case(parsed: dict[str, Any], case: dict[str, float], placed_rail=None) -> tuple[dict, dict]:
    """One case of the scene: (result entry, {side: WheelRailSolution}); raises InputError/ConvergenceError."""
    layout, rail, wheel = parsed["layout"], parsed["rail"], parsed["wheel"]
    placed_rail = placed_rail or place_rail(rail, layout)
    roll = case["roll_rad"]
    pose = WheelsetPose(case["lateral_mm"], case["yaw_rad"], 0.0 if parsed["roll_auto"] else roll)
    if parsed["roll_auto"]:
        roll = rigid_roll(placed_rail, wheel, layout, pose, parsed["inputs"]["search"])
        pose = WheelsetPose(pose.lateral_mm, pose.yaw_rad, roll)
    sols = {}
    per_case = {k: case[k] for k in ("pitch_rate_rad_s", "vertical_load_N", "speed_mm_s") if k in case}
    for side in parsed["sides"]:
        inputs = WheelRailInputs(**{**parsed["inputs"], **per_case, "side": side, "pose": pose})
        sols[side] = solve_wheel(rail, wheel, inputs, parsed["layers"], placed_rail,
                                 case=f"case lateral {pose.lateral_mm:g} mm, yaw {pose.yaw_rad:g} rad, {side} wheel")
    any_inputs = next(iter(sols.values())).inputs
    entry = {"lateral_mm": pose.lateral_mm, "yaw_rad": pose.yaw_rad, "roll_rad": pose.roll_rad,
             "pitch_rate_rad_s": any_inputs.omega_rad_s, "vertical_load_N": any_inputs.vertical_load_N,
             "speed_mm_s": any_inputs.speed_mm_s,
             "wheels": {side: wheel_result(s) for side, s in sols.items()}}
    if len(sols) == 2:  # rolling radius difference of the main (largest normal force) patches, left - right
        r = {side: max(s.patches, key=lambda p: p.normal_force_N).candidate.wheel_radius_mm for side, s in sols.items()}
        entry["rolling_radius_difference_mm"] = r["left"] - r["right"]
    return entry, sols


def write_deformed_profiles(parsed: dict[str, Any], sols: dict[str, WheelRailSolution], out_dir: Path,
                            stem: str) -> list[dict[str, Any]]:
    """Deformed rail and wheel profiles of one case (every side), written as SIMPACK and CSV and read back."""
    from meshes.profiles.io import write_profile_files

    written = []
    for side, sol in sols.items():
        for body, (ys, up) in residual_on_profiles(sol.patches).items():
            if not np.any(up > 1e-9):
                continue
            prof = parsed[body]
            pts = deformed_profile(prof, ys, up)
            paths, err = write_profile_files(out_dir / "deformed_profiles" / f"{stem}_{side}_{body}", pts, body,
                                             f"{prof.name} with residual displacements ({stem}, {side})")
            for path in paths:
                written.append({"file": str(path.relative_to(out_dir)), "body": body, "side": side,
                                "max_residual_mm": float(up.max()), "read_back_max_error_mm": err})
    return written


def run_wheel_rail_scene(data: dict[str, Any], scene_path: Path, out_dir: Path, plots: bool) -> dict[str, Any]:
    """Run a wheel_rail scene (see the module docstring); pictures and deformed profiles go into ``out_dir``."""
    t0 = time.perf_counter()
    scene_path, out_dir = Path(scene_path), Path(out_dir)
    parsed = parse_wheel_rail_scene(data, scene_path)
    placed = place_rail(parsed["rail"], parsed["layout"])
    entries, all_sols = [], []
    from wrlayer.progress import progress

    for k, case in enumerate(progress(parsed["cases"], desc=scene_path.stem, total=len(parsed["cases"]), unit="case",
                                      leave=False)):
        t_case = time.perf_counter()
        try:
            entry, sols = solve_case(parsed, case, placed)
            if parsed["layers"] is not None and parsed["deformed_profiles"]:
                entry["deformed_profiles"] = write_deformed_profiles(parsed, sols, out_dir, f"case{k:03d}")
        except (InputError, ConvergenceError) as err:
            entry, sols = {**{key: case.get(key) for key in SWEEP_KEYS}, "error": str(err)}, None
        entry["case"] = k
        entry["time_s"] = time.perf_counter() - t_case
        entries.append(entry)
        all_sols.append(sols)
    if all(s is None for s in all_sols):
        raise InputError(scene_path.name, f"every case failed; first: {entries[0]['error']}")
    result = {
        "type": "wheel_rail",
        "inputs": _inputs_echo(parsed, scene_path, data),
        "code_version": code_version(),
        "units": {**UNITS, "angles": "rad (contact_angle_deg in degrees)",
                  "Fx_N, Fy_N": "N (creep forces of the rail on the wheel, contact frame x = rolling direction, "
                                "y = contact-plane lateral axis with positive track-Y component)"},
        "conventions": CONVENTIONS,
        "rail_placement": {"dy_mm": placed.dy_mm, "dz_mm": placed.dz_mm, "angle_rad": placed.angle_rad,
                           "gauge_point_Y_mm": placed.gauge_point[0], "gauge_point_Z_mm": placed.gauge_point[1],
                           "top_y_rail_mm": placed.top_q_mm},
        "cases": entries,
        "n_failed": sum(1 for e in entries if "error" in e),
        "timings_s": {"total": time.perf_counter() - t0},
    }
    from contact.tangential.frictional_outputs import write_wheel_rail  # wear-ready CSVs beside result.json

    result["frictional_outputs"] = write_wheel_rail(all_sols, out_dir)
    text = cases_csv(result)
    out_dir.mkdir(parents=True, exist_ok=True)
    (out_dir / "cases.csv").write_text(text, encoding="utf-8")
    result["cases_csv"] = "cases.csv"
    if plots:
        from contact.wheel_rail.plots import write_wheel_rail_plots

        result["pictures"] = [p.name for p in write_wheel_rail_plots(result, all_sols, out_dir)]
    return result


#: Columns of cases.csv (one row per loaded patch; a failed case gets one row with its error).
CSV_COLUMNS = ("case", "lateral_mm", "yaw_rad", "roll_rad", "pitch_rate_rad_s", "vertical_load_N", "speed_mm_s",
               "side", "patch", "contact_point", "y_rail_mm", "y_wheel_mm", "Y_track_mm", "Z_track_mm",
               "y_rail_first_contact_mm", "y_rail_weighted_centre_mm",
               "contact_angle_deg", "normal_force_N", "load_share", "Fx_N", "Fy_N", "Mz_Nmm", "p_max_MPa",
               "area_mm2", "creepage_x", "creepage_y", "spin_per_mm", "delta_mm", "approach_mm", "Y_over_Q",
               "vertical_force_N", "vertical_balance_rel", "time_s", "error")


def cases_csv(result: dict[str, Any]) -> str:
    """The per-case table of a wheel_rail result as CSV text (columns :data:`CSV_COLUMNS`; units in the names)."""
    buf = io.StringIO()
    w = csv.writer(buf, lineterminator="\n")
    w.writerow(CSV_COLUMNS)
    for e in result["cases"]:
        head = {k: e.get(k) for k in CSV_COLUMNS[:7]}
        head["case"] = e["case"]
        if "error" in e:
            w.writerow([head.get(k, "") if k in head else (e["error"] if k == "error" else "") for k in CSV_COLUMNS])
            continue
        for side, wr in e["wheels"].items():
            for j, pr in enumerate(wr["patches"]):
                row = {**head, **{k: pr.get(k) for k in CSV_COLUMNS if k in pr}, "side": side, "patch": j,
                       "y_rail_first_contact_mm": pr["first_contact"]["y_rail_mm"],
                       "y_rail_weighted_centre_mm": pr["weighted_centre"]["y_rail_mm"],
                       "approach_mm": wr["approach_mm"], "Y_over_Q": wr["Y_over_Q"],
                       "vertical_force_N": wr["vertical_force_N"], "vertical_balance_rel": wr["vertical_balance_rel"],
                       "time_s": e.get("time_s"), "error": ""}
                w.writerow(["" if row.get(k) is None else (f"{row[k]:.10g}" if isinstance(row[k], float) else row[k])
                            for k in CSV_COLUMNS])
    return buf.getvalue()


CONVENTIONS = {
    "y_rail_mm": "rail profile coordinate of the contact point: from the head centre line, + towards the field side "
                 "(gauge side negative); same for both rails",
    "y_wheel_mm": "wheel profile coordinate (S1002: S, 0 at the taping line, + towards the field side, flange "
                  "negative); same for both wheels",
    "Y_track_mm": "lateral track coordinate of the wheel contact point (from the track centre, + towards the right "
                  "rail)",
    "contact_point": "y_rail_mm, y_wheel_mm, Y_track_mm, Z_track_mm, X_lead_mm of a patch are its reference point "
                     "(method.contact_point: first_contact = rigid first contact, weighted_centre = centre of the "
                     "interpenetration region weighted by the depth), in the contact plane; creepages, spin, FASTSIM "
                     "and Mz refer to it; first_contact and weighted_centre are both reported; see docs/wheel-rail.md",
    "vertical_force_N": "Z component of the total contact force on the wheel (normal + tangential); the balance "
                        "(method.balance = total) makes it equal the vertical load",
    "load_share": "a patch's share of the wheel's vertical force",
    "contact_angle_rad": "angle of the contact normal at the reference point (weighted centre: the weighted mean "
                         "angle; first_contact.contact_angle_rad: the candidate's) from the vertical, positive when "
                         "it tilts towards the track centre (flange contact ~ +1.2 rad), same sign for both wheels",
    "rolling_radius_kp_mm": "Kik-Piotrowski radius in the rolling direction: 1/(k_c cos^2 b + k_m sin^2 b); without "
                            "yaw r / cos(wheel contact angle)",
    "strips": "per strip of a patch (track orientation, eta = 0 at the contact point): separation f in the contact "
              "plane (shifted to min 0), peak pressure p(0, eta), and the strip's profile coordinates on rail and wheel",
    "lateral_mm/yaw_rad/roll_rad": "wheelset displacement towards the right rail; yaw counter-clockwise seen from "
                                   "above; roll lifting the right wheel",
}


def _inputs_echo(parsed: dict[str, Any], scene_path: Path, data: dict[str, Any]) -> dict[str, Any]:
    lay = parsed["layout"]
    inp = parsed["inputs"]
    layers = parsed["layers"]
    return {
        "scene_file": str(scene_path.resolve()),
        "content_sha256": hashlib.sha256(scene_path.read_bytes()).hexdigest() if scene_path.is_file() else None,
        "title": data.get("title", ""), "description": data.get("description", ""),
        "rail_profile": parsed["rail"].name, "wheel_profile": parsed["wheel"].name,
        "track": {"gauge_mm": lay.gauge_mm, "gauge_depth_mm": lay.gauge_depth_mm,
                  "inclination_rad": lay.inclination_rad, "back_to_back_mm": lay.back_to_back_mm,
                  "flange_back_y_mm": lay.flange_back_y_mm, "nominal_radius_mm": lay.nominal_radius_mm},
        "sides": parsed["sides"], "roll": "auto" if parsed["roll_auto"] else "given",
        "vertical_load_N": inp["vertical_load_N"], "speed_mm_s": inp["speed_mm_s"],
        "pitch_rate_rad_s": inp["pitch_rate_rad_s"] if inp["pitch_rate_rad_s"] is not None
        else inp["speed_mm_s"] / lay.nominal_radius_mm,
        "friction": inp["friction"], "E_MPa": inp["E_MPa"], "poisson": inp["poisson"],
        "G_MPa": inp["E_MPa"] / (2.0 * (1.0 + inp["poisson"])),
        "method": {"alpha": inp["alpha"], "grid_mm": inp["grid_mm"], "fastsim_cells": inp["fastsim_cells"],
                   "normal": inp["normal_method"].name, "exact_cells": inp["normal_method"].exact_cells,
                   "layer_mode": inp["normal_method"].layer_mode, "contact_point": inp["contact_point"],
                   "balance": inp["balance"], **vars(inp["search"])},
        "sweep_csv": parsed["sweep_csv"] or None,
        "passes": vars(inp["passes"]),
        "layers": None if layers is None else (
            {"combined": layers.combined.to_dict()} if layers.combined is not None else
            {**{b: n for b, n in layers.names.items()}, "sha256": parsed["table_sha256"]}),
        "scene_toml": data,
    }


__all__ = [
    "CONVENTIONS",
    "CSV_COLUMNS",
    "cases_csv",
    "parse_wheel_rail_scene",
    "patch_result",
    "reference_dir",
    "resolve_path",
    "run_wheel_rail_scene",
    "solve_case",
    "wheel_result",
    "write_deformed_profiles",
]
