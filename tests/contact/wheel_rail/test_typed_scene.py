"""The typed wheel–rail scene: parsed once, plain-data round trip, the solver inputs it gives."""

import json
from pathlib import Path

import pytest

from contact.scenes.cost import wheel_rail_cost
from contact.scenes.scene import read_scene_data
from contact.wheel_rail.parse import parse_wheel_rail_scene
from contact.wheel_rail.scene import WheelRailScene
from wrlayer.elastic import shear_modulus_MPa

SCENES = Path(__file__).resolve().parents[3] / "scenes"


@pytest.mark.parametrize("name", ["wheel_rail_sweep_layers", "wheel_rail_sweep_elastic", "manchester_a22"])
def test_round_trip_through_plain_data(name):
    path, data = read_scene_data(SCENES / f"{name}.toml")
    scene = parse_wheel_rail_scene(data, path)
    again = WheelRailScene.from_dict(json.loads(json.dumps(scene.to_dict())))
    assert again == scene
    assert again.rail_profile.name == scene.rail_profile.name
    assert (again.layers is None) == (scene.layers is None)
    assert wheel_rail_cost(again).seconds == wheel_rail_cost(scene).seconds


def test_g_is_converted_to_e_and_defaults_are_filled(tmp_path):
    scene = parse_wheel_rail_scene({"type": "wheel_rail", "material": {"G_MPa": 80000.0, "poisson": 0.3},
                                    "track": {"inclination": 20}}, tmp_path / "s.toml")
    assert scene.material.E_MPa == pytest.approx(2 * 80000.0 * 1.3)
    assert scene.material.G_MPa == pytest.approx(80000.0)
    assert scene.track.inclination_rad == pytest.approx(0.049958395721942765)
    assert scene.sides == ["right"] and len(scene.cases) == 1 and scene.layers is None
    inputs = scene.inputs("left")
    assert inputs.side == "left" and inputs.G_MPa == pytest.approx(shear_modulus_MPa(inputs.E_MPa, 0.3))
    assert inputs.search == scene.method.search and inputs.passes.max == 1


def test_case_values_reach_the_inputs(tmp_path):
    scene = parse_wheel_rail_scene({"type": "wheel_rail", "wheel": {"side": "both"},
                                    "sweep": {"vertical_load_N": [5000.0, 7000.0], "speed_mm_s": [1000.0, 3000.0]}},
                                   tmp_path / "s.toml")
    assert scene.sides == ["right", "left"]
    inputs = scene.inputs("right", case=scene.cases[1])
    assert (inputs.vertical_load_N, inputs.speed_mm_s) == (7000.0, 3000.0)


def test_result_records_round_trip_and_stay_short(tmp_path):
    from contact.wheel_rail.results import SweepResult
    from contact.run_files import run_wheel_rail_scene

    data = {"type": "wheel_rail", "wheel": {"side": "both"}, "sweep": {"lateral_mm": [0.0, 3.0]},
            "layers": {"combined": {"u_mm": [0.0, 0.01, 0.05], "p_MPa": [0.0, 300.0, 900.0]}},
            "passes": {"max": 2}}
    result = run_wheel_rail_scene(parse_wheel_rail_scene(data, tmp_path / "s.toml"), tmp_path, plots=False)
    assert SweepResult.from_dict(result.to_dict()) == result
    assert SweepResult.from_dict(json.loads(result.to_json())) == result
    case = result.cases[1]
    patch = case.wheels["right"].patches[0]
    assert len(patch.passes) == 2 and case.deformed_profiles is not None
    for record in (result, case, case.wheels["left"], patch):
        assert len(repr(record)) < 400
    assert "error" not in case.to_dict() and "pictures" not in result.to_dict()
