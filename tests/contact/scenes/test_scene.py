"""Scene parsing: the shipped scenes, defaults, the parabola separation, per-body layers (the [layers] shape and the
deprecated [layer]), the inputs record."""

import json
import math
from pathlib import Path

import numpy as np
import pytest

from wrlayer.json_io import json_text
from contact.scenes.scene import load_scene, parse_scene
from wrlayer.errors import InputError

SCENES = Path(__file__).resolve().parents[3] / "scenes"
KP_SCENES = sorted(p for p in SCENES.glob("*.toml") if "type = \"wheel_rail\"" not in p.read_text())

MINIMAL = {
    "load": {"normal_force_N": 20000.0, "rolling_radius_mm": 400.0},
    "material": {"E_MPa": 210000.0, "poisson": 0.28},
    "separation": {"y_mm": [-4.0, 0.0, 4.0], "f_mm": [0.16, 0.0, 0.16]},
}
LAYER = {"u_mm": [0.0, 0.0202, 0.0301, 0.06], "p_MPa": [0.0, 1190.0, 1456.0, 1800.0]}


def scene_with(**sections):
    data = {k: dict(v) for k, v in MINIMAL.items()}
    data.update(sections)
    return parse_scene(data, Path("scenes") / "test_scene.toml")


@pytest.mark.parametrize("path", KP_SCENES, ids=[p.stem for p in KP_SCENES])
def test_shipped_scenes_load(path):
    scene = load_scene(path)
    assert scene.load.normal_force_N > 0 and scene.separation.y_mm.size >= 3
    json.loads(json_text({"inputs": scene.to_dict()}))  # the inputs record is strict JSON


def test_paper_scenes_share_the_paper_inputs():
    """The three paper scenes differ only in the layer and the passes (R = 1600 mm, N = 100 kN, creepages)."""
    scenes = [load_scene(SCENES / f"paper_{n}.toml") for n in ("no_layer", "with_layer", "shakedown")]
    for s in scenes:
        assert (s.load.normal_force_N, s.load.rolling_radius_mm) == (100000.0, 1600.0)
        assert (s.tangential.creepage_x, s.tangential.creepage_y, s.tangential.spin_per_mm) == (0.002, 0.0, 0.0012)
        np.testing.assert_array_equal(s.separation.f_mm, scenes[0].separation.f_mm)
    assert scenes[0].layers is None
    assert scenes[1].layers.sources.combined.elastic_limit_MPa == 1190.0 and scenes[1].passes.max == 1
    assert scenes[2].passes.max > 19 and not scenes[2].passes.hardening


def test_defaults():
    s = scene_with()
    assert (s.method.alpha, s.method.grid_mm, s.method.fastsim_cells) == (0.55, 0.1, 60)
    assert (s.passes.max, s.passes.hardening, s.passes.tolerance_mm) == (1, False, 1e-6)
    assert s.layers is None and s.tangential is None and s.title == "test_scene"
    t = scene_with(tangential={"creepage_x": 0.001, "friction": 0.25}).tangential
    assert (t.creepage_y, t.spin_per_mm, t.speed_mm_s, t.friction) == (0.0, 0.0, 1000.0, 0.25)
    assert t.has_creepage
    assert math.isclose(s.material.G_MPa, 210000.0 / 2.56)


def test_parabola_separation_is_sampled_exactly_on_the_strip_centres():
    s = scene_with(separation={"lateral_radius_mm": 31.7, "half_width_mm": 5.0}, method={"grid_mm": 0.2})
    y, f = s.separation.y_mm, s.separation.f_mm
    assert y[0] == pytest.approx(-5.0) and y[-1] == pytest.approx(5.0)
    assert np.allclose(np.diff(y), 0.05)  # grid / 4
    np.testing.assert_allclose(f, y * y / (2 * 31.7))
    on_grid = np.isclose((y / 0.2) - np.round(y / 0.2), 0.0, atol=1e-9)
    assert on_grid.sum() == 51  # every strip centre j * h is a table point


def test_combined_and_per_body_layers():
    s = scene_with(layers={"combined": LAYER})
    assert s.layers.sources.combined.n_segments == 3 and s.layers.wheel is None
    s = scene_with(layers={"wheel": LAYER, "rail": {"u_mm": [0.0, 0.01, 0.03], "p_MPa": [0.0, 1000.0, 1400.0]}})
    assert s.layers.combined is None
    assert s.layers.sources.wheel.p_MPa[1] == 1190.0 and s.layers.sources.rail.p_MPa[1] == 1000.0
    inputs = s.to_dict()
    assert inputs["layers"]["wheel"] == {"u_mm": LAYER["u_mm"], "p_MPa": LAYER["p_MPa"]}


RAIL_TABLE = str(SCENES / "tables" / "rail_60E1_default.json")
WHEEL_TABLE = str(SCENES / "tables" / "wheel_S1002_default.json")
#: The same layers in the deprecated [layer] shape and in [layers].
SAME_LAYERS = [
    ({"u_mm": LAYER["u_mm"], "p_MPa": LAYER["p_MPa"]}, {"combined": LAYER}),
    ({"wheel": LAYER, "rail": {"table": RAIL_TABLE, "position_mm": 0.5}},
     {"wheel": LAYER, "rail": RAIL_TABLE, "position_mm": {"rail": 0.5}}),
    ({"rail": {"table": RAIL_TABLE, "position_mm": 0.0, "scale_to_patch": True},
      "wheel": {"table": WHEEL_TABLE, "position_mm": 1.0, "scale_to_patch": True}},
     {"rail": RAIL_TABLE, "wheel": WHEEL_TABLE, "position_mm": {"rail": 0.0, "wheel": 1.0}, "scale_to_patch": True}),
]


@pytest.mark.parametrize("old, new", SAME_LAYERS, ids=["combined", "characteristic_and_table", "tables_scaled"])
def test_old_layer_shape_gives_the_same_scene(old, new, capsys):
    """The deprecated [layer] is read as [layers], with one deprecation line on stderr; both give the same scene
    (sections, echo and the layers built on the strips)."""
    before = scene_with(layer=old)
    assert capsys.readouterr().err == ("warning: test_scene.toml: [layer] is deprecated, write [layers] "
                                       "(docs/scene-keys.md)\n")
    after = scene_with(layers=new)
    assert capsys.readouterr().err == ""
    assert before.layers == after.layers and before.content_hash == after.content_hash
    assert {k: v for k, v in before.to_dict().items() if k != "scene_toml"} == \
        {k: v for k, v in after.to_dict().items() if k != "scene_toml"}
    from contact.scenes.scene_layers import build_layers

    y = before.normal_problem().strip_y_mm
    pairs = [build_layers(s, y, (6.0, 5.0)).bodies() for s in (before, after)]
    assert pairs[0].keys() == pairs[1].keys()
    for name, layer in pairs[0].items():
        np.testing.assert_array_equal(layer.k_N_per_mm3, pairs[1][name].k_N_per_mm3)
        np.testing.assert_array_equal(layer.half_width_mm, pairs[1][name].half_width_mm)


def test_layers_shape_errors():
    with pytest.raises(InputError, match=r"^test_scene.toml: layer: give \[layers\] only"):
        scene_with(layer={"combined": LAYER}, layers={"combined": LAYER})
    with pytest.raises(InputError, match=r"^test_scene.toml: layers.position_mm.rail: missing \(required\)"):
        scene_with(layers={"rail": RAIL_TABLE})
    with pytest.raises(InputError, match=r"^test_scene.toml: layers.combined: give either"):
        scene_with(layers={"combined": LAYER, "wheel": LAYER})
    with pytest.raises(InputError, match=r"^test_scene.toml: layer.rail.scale_to_patch: must be the same"):
        scene_with(layer={"rail": {"table": RAIL_TABLE, "position_mm": 0.0, "scale_to_patch": True},
                          "wheel": {"table": WHEEL_TABLE, "position_mm": 0.0}})


def test_messages_name_file_and_key():
    with pytest.raises(InputError, match=r"^test_scene.toml: load.normal_force_N: must be >= 0.001, got -5$"):
        scene_with(load={"normal_force_N": -5, "rolling_radius_mm": 400.0})
    with pytest.raises(InputError, match=r"test_scene.toml: layers.rail.u_mm/p_MPa: .*concave"):
        scene_with(layers={"rail": {"u_mm": [0.0, 0.01, 0.02], "p_MPa": [0.0, 100.0, 1000.0]}})
    with pytest.raises(InputError, match=r"method.fastsim_cells: must be >= 2"):
        scene_with(method={"fastsim_cells": 1})
    with pytest.raises(InputError, match=r"reference.p_max: unknown key"):
        scene_with(reference={"p_max": 1.0})


def test_content_hash_follows_the_file(tmp_path):
    a = tmp_path / "a.toml"
    text = (SCENES / "hertz_check.toml").read_text()
    a.write_text(text)
    h1 = load_scene(a).content_hash
    a.write_text(text.replace("50000.0", "50001.0"))
    h2 = load_scene(a).content_hash
    assert h1 != h2 and len(h1) == 64
