"""Small wear scenes for fast tests (coarse grids, few passes)."""

import json
from pathlib import Path

import pytest

from contact.wear.scene import parse_wear_scene

REPO = Path(__file__).resolve().parents[3]
TABLES = REPO / "scenes" / "tables"


def wear_data(**over):
    """A one-side wear scene (dict) with calibrated layers; sections in ``over`` replace or extend the defaults."""
    data = {
        "type": "wear",
        "profiles": {"rail": "60E1", "wheel": "S1002"},
        "wheel": {"nominal_radius_mm": 460.0, "side": "right"},
        "wheelset": {"roll_rad": 0.0},
        "load": {"vertical_load_N": 40000.0, "speed_mm_s": 2000.0},
        "material": {"G_MPa": 82000.0, "poisson": 0.28},
        "tangential": {"friction": 0.3},
        "layers": {"rail": str(TABLES / "rail_60E1_default.json"), "wheel": str(TABLES / "wheel_S1002_default.json")},
        "passes": {"max": 8},
        "method": {"normal": "kik_piotrowski", "grid_mm": 0.2, "fastsim_cells": 16},   # the loop's logic (limitations)
        "wear": {"law": "archard", "distance_km": 100.0, "steps": 1, "max_depth_per_step_mm": 10.0,
                 "smoothing_mm": 0.0, "grid_mm": 0.2},
        "collective": {"lateral_mm": [2.0], "yaw_rad": 0.002, "weights": [1.0]},
    }
    for key, value in over.items():
        if value is None:
            data.pop(key, None)
        elif isinstance(value, dict) and isinstance(data.get(key), dict):
            data[key] = {**data[key], **value}
        else:
            data[key] = value
    return data


@pytest.fixture
def make_scene(tmp_path):
    def make(**over):
        return parse_wear_scene(wear_data(**over), tmp_path / "w.toml")

    return make


@pytest.fixture
def wear_dict():
    """The scene-dict builder :func:`wear_data`."""
    return wear_data


@pytest.fixture
def write_scene(tmp_path):
    """Write a scene dict as ``tmp_path/w.toml``; returns the path."""
    def write(data):
        path = tmp_path / "w.toml"
        path.write_text(_toml(data))
        return path

    return write


def _toml(data, prefix=""):
    """Tiny TOML writer for the test scenes (tables, numbers, strings, lists of numbers)."""
    lines, tables = [], []
    for k, v in data.items():
        if isinstance(v, dict):
            tables.append((k, v))
        else:
            lines.append(f"{k} = {_val(v)}")
    out = "\n".join(lines) + "\n"
    for k, v in tables:
        name = f"{prefix}{k}"
        scal = {kk: vv for kk, vv in v.items() if not isinstance(vv, dict)}
        out += f"\n[{name}]\n" + "".join(f"{kk} = {_val(vv)}\n" for kk, vv in scal.items())
        sub = {kk: vv for kk, vv in v.items() if isinstance(vv, dict)}
        if sub:
            out += _toml(sub, prefix=f"{name}.")
    return out


def _val(v):
    if isinstance(v, bool):
        return "true" if v else "false"
    if isinstance(v, str):
        return json.dumps(v)
    if isinstance(v, list):
        return "[" + ", ".join(_val(x) for x in v) + "]"
    return repr(float(v)) if isinstance(v, float) else str(v)
