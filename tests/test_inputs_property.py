"""Property test of the input contract (hypothesis): random scene and calibration-config documents, valid and
invalid (numbers in and out of range, NaN, inf, huge, strings, booleans, nested lists, missing and unknown keys),
either give a result that passes the physical invariants or the project's clear error, never anything else,
within a time bound. Scenes are parsed AND solved (coarse grid, few passes); configurations are parsed and
turned into FEM tasks (geometry, mesh checks), the FEM itself being covered by tests/calibration."""

from __future__ import annotations

import copy
import math
import time
from pathlib import Path

import numpy as np
from hypothesis import HealthCheck, event, given, settings
from hypothesis import strategies as st

from calibration.config import parse_config
from calibration.pipeline import make_tasks
from contact.scenes.cost import scene_cost
from contact.scenes.scene import parse_scene
from contact.scenes.simulation import simulate
from wrlayer.cost import guard
from wrlayer.errors import WrLayerError

#: Time bound per generated document (s): the slowest accepted scene takes well under a second alone; the bound
#: leaves room for a loaded 2-core machine.
TIME_BOUND_S = 30.0
#: Cost limit for generated scenes (s of estimated run time): larger ones must be refused by the guard.
TEST_COST_LIMIT_S = 2.0

BASE_SCENE = {
    "load": {"normal_force_N": 20000.0, "rolling_radius_mm": 460.0},
    "material": {"E_MPa": 210000.0, "poisson": 0.3},
    "separation": {"lateral_radius_mm": 100.0, "half_width_mm": 10.0},
    "layer": {"u_mm": [0.0, 0.02, 0.03, 0.06], "p_MPa": [0.0, 1190.0, 1456.0, 1900.0]},
    "tangential": {"creepage_x": 0.002, "creepage_y": 0.0, "spin_per_mm": 0.0, "friction": 0.3},
    "passes": {"max": 3, "tolerance_mm": 1e-5},
    "method": {"alpha": 0.55, "grid_mm": 0.25, "fastsim_cells": 20},
}
SCENE_KEYS = [(s, k) for s, table in BASE_SCENE.items() for k in table] + [
    ("tangential", "speed_mm_s"), ("tangential", "flexibility"), ("passes", "hardening"),
    ("separation", "step_mm"), ("method", "typo_key"), ("load", "unknown"), ("method", "normal"),
    ("method", "exact_cells"), ("method", "layer_mode")]

BASE_CONFIG = {
    "run": {"model": "2d", "workers": 1, "plots": False},
    "load": {"max_factor": 2.0, "n_levels": 4, "unload_factors": [1.5, 2.0], "max_increment_factor": 0.25},
    "mesh": {"elements_per_semi_axis": 3.0, "h_max_mm": 10.0, "order": 1},
    "fit": {"n_segments": 3, "max_relative_error": 0.2},
    "material": {"E_MPa": 210000.0, "poisson": 0.3, "yield_MPa": 500.0},
    "bodies": [{"body": "rail", "profile": "60E1", "mate": "S1002", "positions_mm": [0.0]}],
}
CONFIG_KEYS = [(s, k) for s, t in BASE_CONFIG.items() if isinstance(t, dict) for k in t] + [
    ("mesh", "depth_mm"), ("mesh", "grading"), ("load", "reference_load_N"), ("bodies", "positions_mm"),
    ("bodies", "semi_axes_mm"), ("bodies", "rail_cant_rad"), ("run", "linear_solver")]

DELETE = object()


def values(base):
    """Replacement values for a key whose valid value is ``base``: scaled valid values and every kind of bad."""
    bad = st.sampled_from([math.nan, math.inf, -math.inf, 1e300, -1e300, 0, 0.0, -1.0, True, False, "1.0", "",
                           [], [[1.0]], [[[[0.0]]], 1.0], {"a": 1}, 10 ** 30, 1e-300, DELETE])
    good = st.just(base)
    if isinstance(base, bool):
        good = st.booleans()
    elif isinstance(base, int):
        good = st.integers(min_value=-5, max_value=3 * max(base, 2))
    elif isinstance(base, float):
        good = st.floats(min_value=-2.0, max_value=4.0).map(lambda f: base * f if base else f)
    elif isinstance(base, list) and base and all(isinstance(v, (int, float)) for v in base):
        good = st.lists(st.floats(min_value=-1.0, max_value=3.0), min_size=0, max_size=6).map(
            lambda fs: sorted(b * f for b, f in zip(base * 3, fs)))
    return st.one_of(good, bad)


@st.composite
def documents(draw, base: dict, keys: list):
    doc = copy.deepcopy(base)
    for section, key in draw(st.lists(st.sampled_from(keys), min_size=0, max_size=3, unique=True)):
        target = doc.setdefault(section, {}) if section != "bodies" else doc["bodies"][0]
        value = draw(values(target.get(key, 1.0)))
        if value is DELETE:
            target.pop(key, None)
        else:
            target[key] = value
    if draw(st.booleans()) and draw(st.integers(0, 9)) == 0:
        doc[draw(st.sampled_from(list(doc)))] = draw(st.sampled_from([1, "x", [1, 2], None]))
    return doc


def _check_scene_result(result: dict, scene) -> None:
    """Physical invariants of a returned result (units N, mm, MPa)."""
    n = scene.load.normal_force_N
    assert 1 <= result["n_passes"] == len(result["passes"]) <= scene.passes.max
    for rec in result["passes"]:
        assert abs(rec["normal_force_N"] - n) <= 1e-6 * n, rec["normal_force_N"]
        for key in ("length_mm", "width_mm", "area_mm2", "delta_mm", "p_max_MPa"):
            assert math.isfinite(rec[key]) and rec[key] > 0, (key, rec[key])
        if rec.get("Fx_N") is not None:
            ft = math.hypot(rec["Fx_N"], rec["Fy_N"])
            assert math.isfinite(ft) and ft <= scene.tangential.friction * n * (1 + 1e-9) + 1e-9
        assert rec["up0_mm"] is None or rec["up0_mm"] >= -1e-12


@settings(max_examples=60, deadline=None, suppress_health_check=[HealthCheck.too_slow], derandomize=True)
@given(doc=documents(BASE_SCENE, SCENE_KEYS))
def test_random_scene_documents_keep_the_contract(doc):
    t0 = time.perf_counter()
    try:
        scene = parse_scene(doc, Path("generated.toml"))
        guard(scene_cost(scene), limit_s=TEST_COST_LIMIT_S)
        result = simulate(scene).result.to_dict()
    except WrLayerError as err:
        msg = str(err)
        assert msg and "\n" not in msg and len(msg) < 400, msg
        event(f"clear error ({type(err).__name__})")
    else:
        _check_scene_result(result, scene)
        event("result")
    assert time.perf_counter() - t0 < TIME_BOUND_S


@settings(max_examples=40, deadline=None, suppress_health_check=[HealthCheck.too_slow], derandomize=True)
@given(doc=documents(BASE_CONFIG, CONFIG_KEYS))
def test_random_config_documents_keep_the_contract(doc, tmp_path_factory):
    t0 = time.perf_counter()
    try:
        cfg = parse_config(doc, "generated.toml", Path("."))
        tasks, failed, _ = make_tasks(cfg, tmp_path_factory.mktemp("cfg"), plots=False)
    except WrLayerError as err:
        msg = str(err)
        assert msg.startswith("generated.toml") and "\n" not in msg and len(msg) < 400, msg
        event("clear error")
    else:
        event("accepted")
        # a configuration accepted here can be meshed: h_max >= h_min, positions on the profile, sane numbers
        assert len(tasks) + len(failed) == sum(len(b.positions_mm) for b in cfg.bodies)
        for t in tasks:
            h_min = t.geometry.b_mm / cfg.mesh.elements_per_semi_axis
            assert cfg.mesh.h_max_mm >= h_min and np.isfinite(t.geometry.a_mm)
        assert cfg.load.unload_factors[-1] <= cfg.load.max_factor
        assert all(math.isfinite(v) for v in (cfg.bodies[0].material.E_MPa, cfg.reference_load_N))
    assert time.perf_counter() - t0 < TIME_BOUND_S


def _wheel_rail_base() -> dict:
    return {"type": "wheel_rail", "profiles": {"rail": "60E1", "wheel": "S1002"},
            "track": {"gauge_mm": 1435.0, "inclination": 40.0, "back_to_back_mm": 1360.0},
            "wheel": {"nominal_radius_mm": 460.0, "side": "right"},
            "wheelset": {"lateral_mm": 0.0, "yaw_rad": 0.0},
            "load": {"vertical_load_N": 10000.0, "speed_mm_s": 2000.0},
            "material": {"E_MPa": 210000.0, "poisson": 0.28}, "tangential": {"friction": 0.3},
            "passes": {"max": 1}, "method": {"grid_mm": 0.2, "fastsim_cells": 20},
            "sweep": {"lateral_mm": [0.0, 2.0]}}


WHEEL_RAIL_KEYS = [(s, k) for s, t in _wheel_rail_base().items() if isinstance(t, dict) for k in t] + [
    ("wheelset", "roll_rad"), ("method", "alpha"), ("method", "f_cap_mm"), ("sweep", "mode")]


@settings(max_examples=25, deadline=None, suppress_health_check=[HealthCheck.too_slow], derandomize=True)
@given(doc=documents(_wheel_rail_base(), WHEEL_RAIL_KEYS))
def test_random_wheel_rail_documents_keep_the_contract(doc, tmp_path_factory):
    from contact.scenes.cost import wheel_rail_cost
    from contact.wheel_rail.parse import parse_wheel_rail_scene
    from contact.run_files import run_wheel_rail_scene

    t0 = time.perf_counter()
    path = Path("generated.toml")
    try:
        scene = parse_wheel_rail_scene(doc, path)
        guard(wheel_rail_cost(scene), limit_s=TEST_COST_LIMIT_S)
        result = run_wheel_rail_scene(scene, tmp_path_factory.mktemp("wr"), False).to_dict()
    except WrLayerError as err:
        msg = str(err)
        assert msg and "\n" not in msg and len(msg) < 400, msg
        event("clear error")
    else:
        event("result")
        q = result["inputs"]["vertical_load_N"]
        mu = result["inputs"]["friction"]
        for case in result["cases"]:
            if "error" in case:  # a failed case is recorded with its one-line message, the others still run
                assert "\n" not in case["error"]
                continue
            for wheel in case["wheels"].values():
                assert abs(wheel["vertical_balance_rel"]) <= 1e-6 and wheel["n_patches"] >= 1
                for p in wheel["patches"]:
                    assert p["normal_force_N"] > 0 and math.isfinite(p["p_max_MPa"]) and p["p_max_MPa"] > 0
                    assert math.hypot(p["Fx_N"], p["Fy_N"]) <= mu * p["normal_force_N"] * (1 + 1e-9) + 1e-9
                assert 0 < wheel["normal_vertical_N"] <= 1.5 * q  # the balance (method.balance) sets the rest
    assert time.perf_counter() - t0 < TIME_BOUND_S
