"""Physically absurd inputs are refused before any solve: one ``error:`` line naming the file, the key, the value,
the range and the unit slip that explains it, exit 2, nothing written; the top-level ``accept_implausible = true``
lets the same values through. The corpus is made here from the shipped scenes, one slip each."""

from pathlib import Path

import pytest

from contact.__main__ import main

SCENES = Path(__file__).resolve().parents[1] / "scenes"

#: (shipped scene, key line as shipped, the slip, key named, words of the message)
CORPUS = [
    ("hertz_check.toml", "E_MPa = 210000.0", "E_MPa = 210.0", "material.E_MPa", "GPa typed as MPa"),
    ("hertz_check.toml", "lateral_radius_mm = 80.0", "lateral_radius_mm = 0.08", "separation.lateral_radius_mm",
     "metres typed as millimetres"),
    ("hertz_check.toml", "normal_force_N = 50000.0", "normal_force_N = 50.0", "load.normal_force_N", "kN typed as N"),
    ("hertz_check.toml", "rolling_radius_mm = 300.0", "rolling_radius_mm = 0.3", "load.rolling_radius_mm",
     "metres typed as millimetres"),
    ("wheel_rail_sweep_elastic.toml", "G_MPa = 82000.0", "G_MPa = 82.0", "material.G_MPa", "GPa typed as MPa"),
    ("wheel_rail_sweep_elastic.toml", "nominal_radius_mm = 460.0", "nominal_radius_mm = 0.46",
     "wheel.nominal_radius_mm", "metres typed as millimetres"),
    ("wheel_rail_sweep_elastic.toml", "gauge_mm = 1435.0", "gauge_mm = 1.435", "track.gauge_mm",
     "metres typed as millimetres"),
    ("wheel_rail_sweep_elastic.toml", "vertical_load_N = 10000.0", "vertical_load_N = 10.0", "load.vertical_load_N",
     "kN typed as N"),
    ("wheel_rail_sweep_elastic.toml", "speed_mm_s = 2000.0", "speed_mm_s = 2.0", "load.speed_mm_s",
     "m/s typed as mm/s"),
]


def _slipped(tmp_path: Path, scene: str, shipped: str, slip: str, override: bool = False) -> Path:
    text = (SCENES / scene).read_text(encoding="utf-8")
    assert shipped in text, f"{scene} no longer has {shipped!r}"
    path = tmp_path / scene
    path.write_text(("accept_implausible = true\n" if override else "") + text.replace(shipped, slip, 1),
                    encoding="utf-8")
    (tmp_path / "tables").symlink_to(SCENES / "tables")
    return path


@pytest.mark.parametrize("scene, shipped, slip, key, words", CORPUS, ids=[c[3] for c in CORPUS])
def test_slip_is_one_error_line_naming_key_value_range_and_slip(tmp_path, capsys, scene, shipped, slip, key, words):
    path = _slipped(tmp_path, scene, shipped, slip)
    out = tmp_path / "out"
    assert main(["simulate", str(path), "--out", str(out), "--no-vtk"]) == 2
    err = capsys.readouterr().err
    value = slip.split(" = ")[1].rstrip("0").rstrip(".")
    assert err.startswith(f"error: {scene}: {key}: {value} ") and err.count("\n") == 1, err
    assert words in err and "engineering range" in err
    assert not out.exists()


def test_the_override_lets_the_value_through(tmp_path, capsys):
    path = _slipped(tmp_path, "hertz_check.toml", "E_MPa = 210000.0", "E_MPa = 180.0E3", override=True)
    assert main(["simulate", str(path), "--out", str(tmp_path / "ok"), "--no-vtk"]) == 0
    scene, shipped, slip = CORPUS[1][:3]
    path = _slipped(tmp_path / "x", scene, shipped, "lateral_radius_mm = 0.5", override=True) \
        if (tmp_path / "x").mkdir() is None else None
    assert main(["simulate", str(path), "--out", str(tmp_path / "o2"), "--no-vtk"]) == 0   # a needle-sharp radius
    assert "engineering range" not in capsys.readouterr().err


def test_an_accepted_implausible_input_gives_result_warnings(tmp_path, capsys):
    """E = 210 MPa (GPa typed as MPa) let through: the solve runs (p_max 16.6 MPa, approach 8.4 mm, a 106 mm long
    patch), each outside its plausible range, so result.json carries one warning per quantity after the line of
    the method's approximate p_max (hertz_check names Kik-Piotrowski) and stderr prints them; a plausible scene
    carries the method's line only."""
    import json

    path = _slipped(tmp_path, "hertz_check.toml", "E_MPa = 210000.0", "E_MPa = 210.0", override=True)
    text = path.read_text(encoding="utf-8").replace("half_width_mm = 6.0", "half_width_mm = 200.0")
    path.write_text(text, encoding="utf-8")
    out = tmp_path / "out"
    assert main(["simulate", str(path), "--out", str(out), "--no-vtk"]) == 0
    method_line, *warnings = json.loads((out / "result.json").read_text(encoding="utf-8"))["warnings"]
    err = capsys.readouterr().err
    assert method_line.startswith('warning: hertz_check.toml: method.normal = "kik_piotrowski": p_max approximate')
    assert [w.split(": ")[2].split(" = ")[0] for w in warnings] == ["p_max_MPa", "approach_mm", "semi_axis_mm"]
    assert "p_max_MPa = 16.59 MPa" in warnings[0] and "(50..6000 MPa)" in warnings[0]
    assert all(w in err for w in [method_line, *warnings]) and all(
        w.startswith("warning: hertz_check.toml, pass 1: ") for w in warnings)
    assert main(["simulate", str(SCENES / "hertz_check.toml"), "--out", str(tmp_path / "plain"), "--no-vtk"]) == 0
    plain = json.loads((tmp_path / "plain" / "result.json").read_text(encoding="utf-8"))
    assert plain["warnings"] == [method_line]


def test_calibration_material_is_checked_too(tmp_path, capsys):
    """A calibration configuration's yield stress in GPa: one error line naming the key and the slip, exit 2,
    before any FEM; accept_implausible = true lets it through to the parser's other checks."""
    from calibration.__main__ import main as calibration_main

    config = Path(__file__).resolve().parents[1] / "calibration" / "configs" / "test_coarse.toml"
    text = config.read_text(encoding="utf-8").replace("[load]", "[material]\nyield_MPa = 0.5\n\n[load]", 1)
    path = tmp_path / "gpa.toml"
    path.write_text(text, encoding="utf-8")
    assert calibration_main(["run", str(path), "--out", str(tmp_path / "out")]) == 2
    err = capsys.readouterr().err
    assert err.startswith("error: ") and "material.yield_MPa: 0.5 MPa" in err and "GPa typed as MPa" in err
    assert err.count("\n") == 1 and not (tmp_path / "out").exists()
    from calibration.config import parse_config
    from wrlayer.input_files import read_toml

    data = read_toml(path)
    accepted = parse_config({**data, "accept_implausible": True}, "gpa.toml")
    assert all(body.material.yield_MPa == 0.5 for body in accepted.bodies)
