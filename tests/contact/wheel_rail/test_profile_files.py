"""Profile files a wheel–rail scene names: their length unit ([profiles] units), MiniProf files, and the command
line's --accept-unusual-profile (the same as the scene key accept_unusual_profile)."""

import json
from pathlib import Path

import numpy as np
import pytest

from contact.__main__ import main
from contact.run_files import run_wheel_rail_scene
from contact.wheel_rail.parse import parse_wheel_rail_scene
from contact.wheel_rail.scene_files import PROFILE_SUFFIXES
from meshes.profiles import PROFILE_FILE_SUFFIXES, get_profile
from meshes.profiles.io import write_text
from wrlayer.errors import InputError

SCENES = Path(__file__).resolve().parents[3] / "scenes"


def _scene(**profiles):
    return {"type": "wheel_rail", "wheel": {"side": "right"}, "profiles": profiles}


def _write_pair(folder, units):
    """60E1 and S1002 sampled every 0.5 mm, written in ``units`` at full precision; the file names."""
    scale = {"mm": 1.0, "m": 1e-3}[units]
    for body, name in (("rail", "60E1"), ("wheel", "S1002")):
        y, z = get_profile(name).sample(0.5)
        np.savetxt(folder / f"{body}_{units}.csv", np.column_stack([y, z]) * scale, fmt="%.17g", delimiter=",")
    return {"rail": f"rail_{units}.csv", "wheel": f"wheel_{units}.csv"}


def _numbers(record, prefix=""):
    """The numbers of a result record by their key path."""
    if isinstance(record, dict):
        return {k: v for key, item in record.items() for k, v in _numbers(item, f"{prefix}.{key}").items()}
    if isinstance(record, list):
        return {k: v for i, item in enumerate(record) for k, v in _numbers(item, f"{prefix}[{i}]").items()}
    return {prefix: record} if isinstance(record, int | float) and not isinstance(record, bool) else {}


def _cases(tmp_path, data, name):
    run = run_wheel_rail_scene(parse_wheel_rail_scene(data, tmp_path / f"{name}.toml"), tmp_path / name, False)
    return run.to_dict()["cases"]


def test_profile_files_in_metres_with_units_give_the_same_result_as_in_mm(tmp_path):
    mm = _cases(tmp_path, _scene(**_write_pair(tmp_path, "mm")), "mm")
    metres = _cases(tmp_path, _scene(**_write_pair(tmp_path, "m"), units="m"), "m")
    a, b = _numbers(mm), _numbers(metres)
    assert a.keys() == b.keys() and len(a) > 50
    assert mm[0]["wheels"]["right"]["patches"][0]["p_max_MPa"] > 100.0   # a real contact, compared number by number
    for key, value in a.items():
        if key.endswith("time_s"):   # the run's clock
            continue
        assert b[key] == pytest.approx(value, rel=1e-7, abs=1e-9), key


def test_a_file_in_metres_without_units_is_diagnosed_naming_the_key(tmp_path):
    files = _write_pair(tmp_path, "m")
    with pytest.raises(InputError, match=r"s.toml: profiles.rail: .*spans only 0.0.* mm laterally.*metres"):
        parse_wheel_rail_scene(_scene(**files), tmp_path / "s.toml")
    with pytest.raises(InputError, match=r"s.toml: profiles.units: must be one of"):
        parse_wheel_rail_scene(_scene(**files, units="cm"), tmp_path / "s.toml")
    parsed = parse_wheel_rail_scene(_scene(**files, units="m"), tmp_path / "s.toml")
    assert parsed.profiles.units == "m"
    assert parsed.rail_profile.z(10.0) == pytest.approx(get_profile("60E1").z(10.0), abs=1e-3)


def test_a_scene_names_miniprof_files(tmp_path):
    assert {".whl", ".ban"} <= set(PROFILE_SUFFIXES) and set(PROFILE_SUFFIXES) == set(PROFILE_FILE_SUFFIXES)
    for suffix, name in ((".ban", "60E1"), (".whl", "S1002")):
        y, z = get_profile(name).sample(0.5)
        rows = "\n".join(f"{a:.6f} {b:.6f}" for a, b in zip(y, z))
        (tmp_path / f"measured{suffix}").write_text(f"MiniProf export (made for the test)\n\n{rows}\n")
    parsed = parse_wheel_rail_scene(_scene(rail="measured.ban", wheel="measured.whl"), tmp_path / "s.toml")
    assert parsed.rail_profile.body == "rail" and parsed.wheel_profile.body == "wheel"
    assert parsed.wheel_profile.z(0.0) == pytest.approx(get_profile("S1002").z(0.0), abs=1e-3)
    with pytest.raises(InputError, match=r"s.toml: profiles.rail: .*wheel profile.*rail profile"):
        parse_wheel_rail_scene(_scene(rail="measured.whl"), tmp_path / "s.toml")


def _spiked_rail(folder):
    """60E1 with a one-point spike on the field side (30 mm from the crown): refused by the plausibility checks,
    harmless for a wheel at the crown."""
    y, z = get_profile("60E1").sample(0.5)
    z = np.asarray(z, float).copy()
    i = int(np.argmin(np.abs(np.asarray(y) - 30.0)))
    z[i] += 2.0
    write_text(folder / "spiked.csv", np.column_stack([y, z]))
    return "spiked.csv"


def test_simulate_accepts_unusual_profiles_with_the_option(tmp_path, capsys):
    scene = tmp_path / "s.toml"
    scene.write_text(f'type = "wheel_rail"\n[wheel]\nside = "right"\n[profiles]\nrail = "{_spiked_rail(tmp_path)}"\n'
                     '[output]\nvtk = false\n')
    assert main(["simulate", str(scene), "--out", str(tmp_path / "refused")]) == 2
    assert "--accept-unusual-profile" in capsys.readouterr().err
    assert not (tmp_path / "refused").exists()
    assert main(["simulate", str(scene), "--out", str(tmp_path / "one"), "--accept-unusual-profile"]) == 0
    result = json.loads((tmp_path / "one" / "result.json").read_text())
    assert result["cases"][0]["wheels"]["right"]["vertical_force_N"] > 0


@pytest.mark.parametrize("command, runner", [
    ("simulate-all", "run_scene_folder"),
    ("wear", "run_wear_into"),
])
def test_every_scene_command_passes_the_option_on(tmp_path, monkeypatch, command, runner):
    """simulate-all and wear hand --accept-unusual-profile to the run as simulate does (the run itself: above)."""
    import contact.run_files as run_files

    seen = {}

    def fake(*args, **kw):
        seen.update(kw)
        raise InputError("stop", "here")

    monkeypatch.setattr(run_files, runner, fake)
    (tmp_path / "scenes").mkdir()
    (tmp_path / "scenes" / "s.toml").write_text('type = "wheel_rail"\n')
    target = str(tmp_path / "scenes") if command == "simulate-all" else str(tmp_path / "scenes" / "s.toml")
    assert main([command, target, "--out", str(tmp_path / "out"), "--accept-unusual-profile"]) == 2
    assert seen["accept_unusual_profile"] is True


def test_wear_scene_takes_units_and_the_option(tmp_path):
    from contact.wear.scene import parse_wear_scene
    from wrlayer.input_files import read_toml

    shipped = read_toml(SCENES / "wear" / "s1002_60e1.toml")
    shipped["layers"] = {k: str(SCENES / "wear" / v) for k, v in shipped["layers"].items() if k != "scale_to_patch"}
    data = {**shipped, "profiles": {**_write_pair(tmp_path, "m"), "units": "m"}}
    scene = parse_wear_scene(data, tmp_path / "w.toml")
    assert scene.wheel_rail.profiles.units == "m"
    spiked = {**shipped, "profiles": {"rail": _spiked_rail(tmp_path)}}
    with pytest.raises(InputError, match="accept_unusual_profile"):
        parse_wear_scene(spiked, tmp_path / "w.toml")
    assert parse_wear_scene(spiked, tmp_path / "w.toml", accept_unusual_profile=True
                            ).wheel_rail.profiles.accept_unusual_profile
