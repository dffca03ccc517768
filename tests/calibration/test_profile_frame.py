"""Profiles in their own frame: 3D is the default model; the rail inclination is a per-body key with the
wheel-rail scenes' meaning (1:n, 0 = already placed as in the track); a rail file of unknown placement is refused;
the benchmark's canted files pair rail and wheel as the Manchester A-2.2 contact does; the default configuration
covers the field side."""

import math
from dataclasses import replace
from pathlib import Path

import pytest

from calibration.config import parse_config, profile_of
from calibration.placement import cant_rad
from calibration.settings import RunSettings
from calibration.tasks import position_geometry
from wrlayer.errors import InputError

ROOT = Path(__file__).resolve().parents[2]
PROFILES = ROOT.parent / "shared" / "reference" / "profiles"  # the reference material beside the worktree
RAIL_FILE = PROFILES / "MBench_UIC60_v3.prr"
WHEEL_FILE = PROFILES / "MBench_S1002_v3.prw"
needs_files = pytest.mark.skipif(not RAIL_FILE.is_file(), reason="Manchester benchmark profiles not available")


def _cfg(body: dict, run: dict | None = None):
    data = {"bodies": [dict({"body": "rail", "profile": "60E1", "mate": "S1002", "positions_mm": [0.0]}, **body)]}
    if run is not None:
        data["run"] = run
    return parse_config(data, "test.toml")


def test_3d_is_the_default_model():
    assert RunSettings().model == "3d"
    assert _cfg({}).run.model == "3d"  # no [run] table at all
    assert _cfg({}, {"workers": 1}).run.model == "3d"


def test_builtin_rail_is_canted_1_to_40_by_default():
    b = _cfg({}).bodies[0]
    assert cant_rad(b, "b") == pytest.approx(math.atan(1 / 40))
    assert cant_rad(_cfg({"inclination": 0}).bodies[0], "b") == 0.0
    assert cant_rad(_cfg({"inclination": 20}).bodies[0], "b") == pytest.approx(math.atan(1 / 20))
    assert cant_rad(_cfg({"rail_cant_rad": 0.01}).bodies[0], "b") == 0.01  # the former key, an alias


@pytest.mark.parametrize("body, match", [({"inclination": 2}, "inclination: 1:n needs n >= 5"),
                                         ({"inclination": 40, "inclination_rad": 0.02}, "inclination_rad: give one"),
                                         ({"inclination_rad": 0.5}, "inclination_rad: must be <= 0.2")])
def test_bad_inclination_is_refused(body, match):
    with pytest.raises(InputError, match=match):
        _cfg(body)


@needs_files
def test_rail_file_without_inclination_is_refused_naming_the_key():
    with pytest.raises(InputError, match=r"bodies\[0\]\.inclination: the rail profile MBench_UIC60_v3.prr"):
        _cfg({"profile": str(RAIL_FILE), "mate": str(WHEEL_FILE), "wheel_radius_mm": 460.0})
    with pytest.raises(InputError, match=r"bodies\[0\]\.inclination"):  # a wheel whose mate is the rail file
        parse_config({"bodies": [{"body": "wheel", "profile": "S1002", "mate": str(RAIL_FILE),
                                  "positions_mm": [0.0]}]}, "test.toml")


def _pair(body: str, y: float):
    other = "wheel" if body == "rail" else "rail"
    files = {"rail": str(RAIL_FILE), "wheel": str(WHEEL_FILE)}
    cfg = parse_config({"bodies": [{"body": body, "profile": files[body], "mate": files[other], "inclination": 0,
                                    "wheel_radius_mm": 460.0, "positions_mm": [y]}]}, "test.toml")
    b = cfg.bodies[0]
    geo, _ = position_geometry(b, profile_of(b.profile), profile_of(b.mate), y, cfg.reference_load_N)
    return geo


@needs_files
def test_benchmark_files_pair_as_the_a22_contact():
    """A-2.2 sweep: rail y = -20.05 mm is in contact with wheel y = -12.09 mm (canted rail file, inclination 0)."""
    geo = _pair("rail", -20.0)
    assert geo.y_mate_mm == pytest.approx(-12.0, abs=0.3)
    assert geo.b_mm == pytest.approx(3.76, abs=0.05)
    assert _pair("wheel", -12.09).y_mate_mm == pytest.approx(-20.05, abs=0.3)
    assert _pair("rail", -35.0).b_mm == pytest.approx(1.83, abs=0.05)


def test_default_configuration_covers_the_field_side():
    from calibration.config import load_config

    cfg = load_config(ROOT / "calibration" / "configs" / "default.toml")
    bodies = {b.body: b for b in cfg.bodies}
    assert max(bodies["rail"].positions_mm) >= 30.0 and min(bodies["rail"].positions_mm) <= -35.9
    assert max(bodies["wheel"].positions_mm) >= 40.0 and min(bodies["wheel"].positions_mm) <= -45.0
    assert replace(cfg.run).model == "3d"
